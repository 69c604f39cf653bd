//! Each mistake `mechanism!` rejects is one compile error, at the line of the variable it is
//! about, that names the variable and the offending text (`declaration_errors/*.stderr`).

#[test]
fn declaration_mistakes_are_reported_once_at_their_line() {
    trybuild::TestCases::new().compile_fail("tests/declaration_errors/*.rs");
}
