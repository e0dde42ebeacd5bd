use super::*;
use crate::shell::CaptureHost;

fn ev(src: &str) -> String {
    let mut interp = Interp::new(Box::new(CaptureHost::default()));
    match interp.eval_expr(&Value::from(src)) {
        Ok(v) => v.as_str().to_string(),
        Err(e) => format!("error: {}", e.message()),
    }
}

#[test]
fn precedence_and_associativity() {
    assert_eq!(ev("1 + 2 * 3"), "7");
    assert_eq!(ev("2 ** 3 ** 2"), "512");
    assert_eq!(ev("-2 ** 2"), "4");
    assert_eq!(ev("(1 + 2) * 3"), "9");
    assert_eq!(ev("1 < 2 == 1"), "1");
    assert_eq!(ev("1 ? 2 : 0 ? 3 : 4"), "2");
    assert_eq!(ev("6 & 3 | 8 ^ 1"), "11");
}

#[test]
fn tcl_arithmetic() {
    assert_eq!(ev("-7 / 2"), "-4");
    assert_eq!(ev("-7 % 2"), "1");
    assert_eq!(ev("7 % -2"), "-1");
    assert_eq!(ev("5 / 2."), "2.5");
    assert_eq!(ev("1.0 / 0"), "Inf");
    assert_eq!(ev("1 / 0"), "error: divide by zero");
    assert_eq!(ev("2 ** -1"), "0");
    assert_eq!(ev("0x10 + 010 + 0b11"), "27");
    assert_eq!(ev("int(-3.7)"), "-3");
    assert_eq!(ev("round(-2.5)"), "-3");
    assert_eq!(ev("sqrt(-1)"), "error: domain error: argument not in valid range");
}

#[test]
fn strings_and_laziness() {
    assert_eq!(ev("\"abc\" < \"abd\""), "1");
    assert_eq!(ev("\"1\" == 1.0"), "1");
    assert_eq!(ev("\"3\" eq \"3.0\""), "0");
    assert_eq!(ev("\"a\" in {a b}"), "1");
    assert_eq!(ev("0 && [error boom]"), "0");
    assert_eq!(ev("1 || [error boom]"), "1");
    assert_eq!(ev("\"abc\" + 1"), "error: can't use non-numeric string as operand of \"+\"");
}

#[test]
fn syntax_errors() {
    assert_eq!(ev("1 +"), "error: missing operand at _@_\nin expression \"1 +_@_\"");
    assert_eq!(ev("(1"), "error: unbalanced open paren\nin expression \"(1\"");
    assert_eq!(ev("1 2"), "error: missing operator at _@_\nin expression \"1 _@_2\"");
    assert_eq!(ev("foo(1)"), "error: invalid command name \"tcl::mathfunc::foo\"");
    assert!(ev("abc").starts_with("error: invalid bareword \"abc\""));
}
