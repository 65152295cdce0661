//! A stage cannot be run with unchecked parameters: the programs in
//! `tests/compile_fail/` must fail to compile with exactly the errors pinned
//! beside them (trybuild compares the compiler's output).

#[test]
fn unchecked_parameters_do_not_compile() {
    let cases = trybuild::TestCases::new();
    cases.compile_fail("tests/compile_fail/*.rs");
}
