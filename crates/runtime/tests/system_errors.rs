//! Each mistake `system!` rejects is a compile error at the line it is about, naming the
//! connection, value or component and what is wrong with it (`system_errors/mistakes.stderr`).

#[test]
fn system_mistakes_are_reported_at_their_line() {
    trybuild::TestCases::new().compile_fail("tests/system_errors/mistakes.rs");
}
