use super::*;

fn words(src: &str) -> Vec<Vec<String>> {
    let s = Script::parse(Rc::from(src), None, 1);
    assert!(s.error.is_none(), "unexpected error {:?}", s.error);
    s.cmds
        .iter()
        .map(|c| {
            c.words
                .iter()
                .map(|w| match w {
                    Word::Lit(v) => format!("L:{}", v.as_str()),
                    Word::Var(VarName::Scalar(n)) => format!("V:{n}"),
                    Word::Var(VarName::Elem(n, _)) => format!("A:{n}"),
                    Word::Cmd(s) => format!("C:{}", s.cmds.len()),
                    Word::Concat(p) => format!("P:{}", p.len()),
                    Word::Expand(_) => "X".to_string(),
                    Word::Local(..) | Word::LocalElem(..) | Word::Compiled(_) => {
                        unreachable!("the parser makes neither")
                    }
                })
                .collect()
        })
        .collect()
}

fn error(src: &str) -> ParseError {
    Script::parse(Rc::from(src), None, 1).error.expect("a syntax error")
}

#[test]
fn separators_and_comments() {
    assert_eq!(words("a b;c\n# x\n d"), vec![vec!["L:a", "L:b"], vec!["L:c"], vec!["L:d"]]);
    assert_eq!(words("a # not a comment"), vec![vec!["L:a", "L:#", "L:not", "L:a", "L:comment"]]);
    assert_eq!(words("# c \\\n still comment\nx"), vec![vec!["L:x"]]);
}

#[test]
fn braces_quotes_and_substitutions() {
    assert_eq!(words("set x {a {b} c}"), vec![vec!["L:set", "L:x", "L:a {b} c"]]);
    assert_eq!(words("p {a\\\n   b}"), vec![vec!["L:p", "L:a b"]]);
    assert_eq!(words("p \"a $b [c]\""), vec![vec!["L:p", "P:4"]]);
    assert_eq!(words("p $x ${a b} $a(i) [x]"), vec![vec!["L:p", "V:x", "V:a b", "A:a", "C:1"]]);
    assert_eq!(words("p \\x41\\u00e9\\101\\q"), vec![vec!["L:p", "L:AéAq"]]);
    assert_eq!(words("p {*}$x $ a$"), vec![vec!["L:p", "X", "L:$", "L:a$"]]);
    assert_eq!(words("p [a [b] \"]\"]"), vec![vec!["L:p", "C:1"]]);
}

#[test]
fn lines_are_tracked() {
    let s = Script::parse(Rc::from("a\n\nb {\n}\nc"), None, 10);
    let lines: Vec<u32> = s.cmds.iter().map(|c| c.line).collect();
    assert_eq!(lines, vec![10, 12, 14]);
}

#[test]
fn syntax_errors_name_the_opening_line() {
    let e = error("a\nb {\n\n");
    assert_eq!((e.msg.as_str(), e.line, e.incomplete), ("missing close-brace", 2, true));
    assert_eq!(error("x [y\n").msg, "missing close-bracket");
    assert_eq!(error("x \"y").msg, "missing \"");
    let e = error("x {a}b");
    assert_eq!((e.msg.as_str(), e.incomplete), ("extra characters after close-brace", false));
    assert_eq!(error("x \"a\"b").msg, "extra characters after close-quote");
}

#[test]
fn completeness() {
    assert!(is_complete("set a {b}"));
    assert!(!is_complete("proc f {} {"));
    assert!(!is_complete("puts [x"));
    assert!(!is_complete("puts \"x"));
    assert!(is_complete("puts {a}b"));
}

#[test]
fn deep_nesting_is_an_error_not_a_crash() {
    let msg = crate::shell::on_big_stack(|| {
        let src = "[".repeat(100_000);
        Script::parse(Rc::from(src.as_str()), None, 1).error.map(|e| e.msg)
    });
    assert_eq!(msg.unwrap().as_deref(), Some("too many nested brackets"));
    let src = "{".repeat(100_000);
    assert_eq!(error(&src).msg, "missing close-brace");
}
