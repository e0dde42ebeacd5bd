//! Tcl lists: splitting a string into elements (TclFindElement) and joining
//! elements back with Tcl 8.6's quoting rules (TclScanElement and
//! TclConvertElement), so `list` prints exactly what tclsh prints.

use super::error::Exception;
use super::parser::backslash;
use super::value::Value;

fn is_space(c: u8) -> bool {
    matches!(c, b' ' | b'\t' | b'\n' | b'\r' | 0x0b | 0x0c)
}

/// Whether `s` is surely a list of one element that is `s` itself: not
/// empty, and no space, brace, quote or backslash anywhere in it (a
/// quick test that needs no parse; `lindex $l 3` reads its index so).
pub(crate) fn is_bare_element(s: &str) -> bool {
    !s.is_empty() && !s.bytes().any(|b| is_space(b) || matches!(b, b'{' | b'}' | b'"' | b'\\'))
}

fn context(b: &[u8], from: usize) -> String {
    let mut end = from;
    while end < b.len() && !is_space(b[end]) && end < from + 20 {
        end += 1;
    }
    String::from_utf8_lossy(&b[from..end]).into_owned()
}

/// Splits a string into list elements.
pub fn parse_list(s: &str) -> Result<Vec<Value>, Exception> {
    let b = s.as_bytes();
    let mut out = Vec::new();
    let mut i = 0;
    loop {
        while i < b.len() && is_space(b[i]) {
            i += 1;
        }
        if i >= b.len() {
            return Ok(out);
        }
        // Every 4096 elements: the cap, and room for the next 4096.
        if out.len() % 4096 == 0 && !out.is_empty() {
            super::eval::check_list_len(out.len() + 1)?;
            crate::mem::reserve_n(4096, Value::BYTES)?;
        }
        match b[i] {
            b'{' => {
                let start = i + 1;
                let mut depth = 1;
                i += 1;
                while i < b.len() {
                    match b[i] {
                        b'\\' => i += 1,
                        b'{' => depth += 1,
                        b'}' => {
                            depth -= 1;
                            if depth == 0 {
                                break;
                            }
                        }
                        _ => {}
                    }
                    i += 1;
                }
                if i >= b.len() {
                    return Err(Exception::error("unmatched open brace in list")
                        .with_error_code("TCL VALUE LIST BRACE"));
                }
                out.push(Value::from(&s[start..i]));
                i += 1;
                if i < b.len() && !is_space(b[i]) {
                    return Err(Exception::error(format!(
                        "list element in braces followed by \"{}\" instead of space",
                        context(b, i)
                    )));
                }
            }
            b'"' => {
                i += 1;
                let mut elem = String::new();
                let mut run = i;
                loop {
                    if i >= b.len() {
                        return Err(Exception::error("unmatched open quote in list"));
                    }
                    match b[i] {
                        b'"' => break,
                        b'\\' => {
                            elem.push_str(&s[run..i]);
                            let (text, n) = backslash(s, i);
                            elem.push(text);
                            i += n;
                            run = i;
                        }
                        _ => i += 1,
                    }
                }
                elem.push_str(&s[run..i]);
                out.push(Value::from_string(elem));
                i += 1;
                if i < b.len() && !is_space(b[i]) {
                    return Err(Exception::error(format!(
                        "list element in quotes followed by \"{}\" instead of space",
                        context(b, i)
                    )));
                }
            }
            _ => {
                let start = i;
                let mut elem: Option<String> = None;
                let mut run = i;
                while i < b.len() && !is_space(b[i]) {
                    if b[i] == b'\\' {
                        let e = elem.get_or_insert_with(String::new);
                        e.push_str(&s[run..i]);
                        let (text, n) = backslash(s, i);
                        e.push(text);
                        i += n;
                        run = i;
                    } else {
                        i += 1;
                    }
                }
                out.push(match elem {
                    Some(mut e) => {
                        e.push_str(&s[run..i]);
                        Value::from_string(e)
                    }
                    None => Value::from(&s[start..i]),
                });
            }
        }
    }
}

#[derive(PartialEq, Clone, Copy)]
enum Quoting {
    None,
    Brace,
    /// Backslash every special character, braces included.
    Escape,
    /// Backslash every special character except braces.
    Mask,
}

fn scan_element(s: &str, quote_hash: bool) -> Quoting {
    let b = s.as_bytes();
    if b.is_empty() {
        return Quoting::Brace;
    }
    let mut forbid_none = false;
    let mut prefer_brace = false;
    let mut prefer_escape = false;
    let mut require_escape = false;
    let mut nesting: i64 = 0;
    if b[0] == b'{' || b[0] == b'"' {
        forbid_none = true;
        prefer_brace = true;
    }
    let mut i = 0;
    while i < b.len() {
        match b[i] {
            b'{' => nesting += 1,
            b'}' => {
                nesting -= 1;
                if nesting < 0 {
                    require_escape = true;
                }
            }
            b']' | b'"' => {
                forbid_none = true;
                prefer_escape = true;
            }
            b'[' | b'$' | b';' | b' ' | b'\x0c' | b'\n' | b'\r' | b'\t' | b'\x0b' => {
                forbid_none = true;
                prefer_brace = true;
            }
            b'\\' => {
                if i + 1 == b.len() {
                    require_escape = true;
                } else if b[i + 1] == b'\n' {
                    require_escape = true;
                    i += 1;
                } else {
                    if matches!(b[i + 1], b'{' | b'}' | b'\\') {
                        i += 1;
                    }
                    forbid_none = true;
                    prefer_brace = true;
                }
            }
            _ => {}
        }
        i += 1;
    }
    if nesting != 0 {
        require_escape = true;
    }
    if require_escape {
        return Quoting::Escape;
    }
    if forbid_none {
        if prefer_escape && !prefer_brace {
            // Tcl's history: a leading # turns this case into braces.
            return if quote_hash && b[0] == b'#' { Quoting::Brace } else { Quoting::Mask };
        }
        return Quoting::Brace;
    }
    if quote_hash && b[0] == b'#' {
        return Quoting::Brace;
    }
    Quoting::None
}

/// Appends one element, quoted as Tcl would quote it.
pub fn append_element(out: &mut String, s: &str, quote_hash: bool) {
    match scan_element(s, quote_hash) {
        Quoting::None => out.push_str(s),
        Quoting::Brace => {
            out.push('{');
            out.push_str(s);
            out.push('}');
        }
        mode => {
            let mut chars = s.chars().peekable();
            if quote_hash && s.starts_with('#') {
                out.push_str("\\#");
                chars.next();
            }
            for c in chars {
                match c {
                    ']' | '[' | '$' | ';' | ' ' | '\\' | '"' => {
                        out.push('\\');
                        out.push(c);
                    }
                    '{' | '}' if mode == Quoting::Escape => {
                        out.push('\\');
                        out.push(c);
                    }
                    '\x0c' => out.push_str("\\f"),
                    '\n' => out.push_str("\\n"),
                    '\r' => out.push_str("\\r"),
                    '\t' => out.push_str("\\t"),
                    '\x0b' => out.push_str("\\v"),
                    _ => out.push(c),
                }
            }
        }
    }
}

/// The string form of a list, refusing a string past the value cap or the
/// memory budget before building it. Nested lists get their string forms bottom
/// up, without recursion: a list nested a million deep prints too.
pub(crate) fn format_list_checked(items: &[Value]) -> Result<String, Exception> {
    format_nested(items);
    let mut raw = items.len();
    for v in items {
        raw = raw.saturating_add(v.as_str().len());
        if v.is_unformatted_list() {
            // An element too long to print: so is this list.
            return Err(super::value::take_pending().unwrap_or_else(super::eval::too_long));
        }
    }
    super::eval::check_len(raw)?;
    let mut out = String::with_capacity(raw + 2);
    for (i, v) in items.iter().enumerate() {
        if i > 0 {
            out.push(' ');
        }
        append_element(&mut out, v.as_str(), i == 0);
    }
    super::eval::check_len(out.len())?;
    Ok(out)
}

/// Makes the string forms of the unformatted lists nested in `items`,
/// innermost first, with an explicit stack.
fn format_nested(items: &[Value]) {
    let mut stack: Vec<(Value, bool)> =
        items.iter().filter(|v| v.is_unformatted_list()).map(|v| (v.clone(), false)).collect();
    while let Some((v, children_done)) = stack.pop() {
        if children_done {
            v.as_str();
        } else if v.is_unformatted_list() {
            stack.push((v.clone(), true));
            if let super::value::Rep::List(l) = &*v.rep() {
                stack.extend(
                    l.iter().filter(|c| c.is_unformatted_list()).map(|c| (c.clone(), false)),
                );
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn fmt(items: &[&str]) -> String {
        let v: Vec<Value> = items.iter().map(|s| Value::from(*s)).collect();
        format_list_checked(&v).unwrap()
    }

    #[test]
    fn quoting_matches_tcl() {
        assert_eq!(fmt(&["a\"b", "a b", "", "{", "}", "a\\"]), "a\\\"b {a b} {} \\{ \\} a\\\\");
        assert_eq!(fmt(&["$x", "#a", "b", "#c"]), "{$x} #a b #c");
        assert_eq!(fmt(&["#a", "#b"]), "{#a} #b");
        assert_eq!(fmt(&["#]", "#]"]), "{#]} #\\]");
        assert_eq!(fmt(&["[x]", "{a}b", "x\\y", "a}", "\"a"]), "{[x]} {{a}b} {x\\y} a\\} {\"a}");
    }

    #[test]
    fn round_trip() {
        for s in ["a b c", "{a b} c", "\"x y\" z", "a\\ b", "{}", "  lead  trail  "] {
            let items = parse_list(s).unwrap();
            let again = parse_list(&format_list_checked(&items).unwrap()).unwrap();
            let a: Vec<&str> = items.iter().map(|v| v.as_str()).collect();
            let b: Vec<&str> = again.iter().map(|v| v.as_str()).collect();
            assert_eq!(a, b);
        }
    }

    #[test]
    fn list_errors() {
        assert!(parse_list("{a").is_err());
        assert!(parse_list("\"a").is_err());
        let e = parse_list("{a}b c").unwrap_err();
        assert_eq!(e.message(), "list element in braces followed by \"b\" instead of space");
    }
}
