//! Each mistake in a mechanism's generalized coordinates is a compile error that names the
//! coordinate (`coordinate_errors/*.stderr`): the coordinates are resolved to value references
//! by constant evaluation where the equations are compiled (`cargo build`, as `mechfmu build`
//! runs it), and a declaration without mistakes compiles (`coordinates_right/`).

#[test]
fn coordinate_mistakes_are_reported_at_compile_time() {
    let cases = trybuild::TestCases::new();
    cases.pass("tests/coordinates_right/*.rs");
    cases.compile_fail("tests/coordinate_errors/*.rs");
}
