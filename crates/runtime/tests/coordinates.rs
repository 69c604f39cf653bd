//! Each mistake in a mechanism's generalized coordinates is a compile error that names the
//! coordinate (`coordinates/mistakes.stderr`): the coordinates are resolved to value references
//! by constant evaluation where the equations are compiled (`cargo build`, as `mechfmu build`
//! runs it), and a declaration without mistakes compiles (`coordinates/right.rs`).

#[test]
fn coordinate_mistakes_are_reported_at_compile_time() {
    let cases = trybuild::TestCases::new();
    cases.pass("tests/coordinates/right.rs");
    cases.compile_fail("tests/coordinates/mistakes.rs");
}
