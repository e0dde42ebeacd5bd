//! String commands: string (all subcommands listed in the README), format
//! and puts. String indices count characters, not bytes.

use super::super::error::{Exception, TclResult};
use super::super::eval::{Interp, check_len};
use super::super::format;
use super::super::number::{self, Num};
use super::super::value::Value;
use super::{Entry, check_args, glob_match, parse_index, pick_option};

pub(super) const COMMANDS: &[Entry] = &[
    (
        "string",
        cmd_string,
        "subcommand ?arg ...?",
        "length, index, range, compare, equal, match, map, trim, is, ...",
    ),
    ("format", cmd_format, "formatString ?arg ...?", "printf-style formatting"),
    ("puts", cmd_puts, "?-nonewline? ?channelId? string", "print a line to stdout or stderr"),
];

pub(crate) const SUBCOMMANDS: &[&str] = &[
    "bytelength",
    "cat",
    "compare",
    "equal",
    "first",
    "index",
    "is",
    "last",
    "length",
    "map",
    "match",
    "range",
    "repeat",
    "replace",
    "reverse",
    "tolower",
    "totitle",
    "toupper",
    "trim",
    "trimleft",
    "trimright",
    "wordend",
    "wordstart",
];

const TRIM_DEFAULT: &str = " \t\n\r\x0b\x0c\0";

/// Tcl's one-to-one lower case (for -nocase): one char for one char.
fn lower(c: char) -> char {
    let mut l = c.to_lowercase();
    match (l.next(), l.next()) {
        (Some(x), None) => x,
        _ => c,
    }
}

/// Tcl's one-to-one upper case: `ß` stays `ß` (tclsh's `STRAßE`).
fn upper(c: char) -> char {
    let mut u = c.to_uppercase();
    match (u.next(), u.next()) {
        (Some(x), None) => x,
        _ => c,
    }
}

/// Title case for one character: the few with a title form of their own
/// (`ǆ` is `ǅ`), else upper case.
fn title(c: char) -> char {
    match c {
        'Ǆ' | 'ǅ' | 'ǆ' => 'ǅ',
        'Ǉ' | 'ǈ' | 'ǉ' => 'ǈ',
        'Ǌ' | 'ǋ' | 'ǌ' => 'ǋ',
        'Ǳ' | 'ǲ' | 'ǳ' => 'ǲ',
        c => upper(c),
    }
}

/// A `-nocase` flag, which Tcl takes abbreviated (`-no`); anything else in
/// its place is a bad option.
fn nocase_flag(v: &Value) -> Result<(), Exception> {
    let s = v.as_str();
    if s.len() > 1 && "-nocase".starts_with(s) {
        return Ok(());
    }
    Err(Exception::error(format!("bad option \"{s}\": must be -nocase")))
}

fn fold(s: &str, nocase: bool) -> String {
    if nocase { s.chars().map(lower).collect() } else { s.to_string() }
}

/// If `s` starts with `key` (already folded), the bytes of `s` it covers.
fn match_at(s: &str, key: &str, nocase: bool) -> Option<usize> {
    if !nocase {
        return s.starts_with(key).then_some(key.len());
    }
    let mut it = s.char_indices();
    for k in key.chars() {
        let (_, c) = it.next()?;
        if lower(c) != k {
            return None;
        }
    }
    Some(it.next().map_or(s.len(), |(i, _)| i))
}

fn chars(s: &str) -> Vec<char> {
    s.chars().collect()
}

fn char_len(s: &str) -> usize {
    if s.is_ascii() { s.len() } else { s.chars().count() }
}

/// The byte offset of character `i` of `s` (its length past the end).
fn byte_offset(s: &str, i: usize) -> usize {
    if s.is_ascii() {
        return i.min(s.len());
    }
    s.char_indices().nth(i).map_or(s.len(), |(b, _)| b)
}

/// Characters `first..=last` (clamped) of `v` as a value.
fn char_range(v: &Value, first: i64, last: i64) -> Value {
    let table = v.char_table();
    let s = v.as_str();
    let len = table.as_ref().map_or(s.len(), |t| t.len()) as i64;
    let f = first.max(0);
    let l = last.min(len - 1);
    if f > l {
        return Value::empty();
    }
    match table {
        None => Value::from(&s[f as usize..=l as usize]),
        Some(t) => Value::from_string(t[f as usize..=l as usize].iter().collect()),
    }
}

/// The number of characters of `v`.
fn value_len(v: &Value) -> usize {
    v.char_table().map_or(v.as_str().len(), |t| t.len())
}

/// `string length s` (`argv` has both words of the command's name; the
/// compiler calls it straight, `cmd_string` too).
pub(crate) fn string_length(_: &mut Interp, argv: &[Value]) -> TclResult {
    if argv.len() != 3 {
        return Err(Exception::wrong_args("string length string"));
    }
    Ok(Value::from_int(value_len(&argv[2]) as i64))
}

/// `string index s i`.
pub(crate) fn string_index(_: &mut Interp, argv: &[Value]) -> TclResult {
    if argv.len() != 4 {
        return Err(Exception::wrong_args("string index string charIndex"));
    }
    let i = parse_index(&argv[3], value_len(&argv[2]))?;
    Ok(char_range(&argv[2], i, i))
}

/// `string range s first last`.
pub(crate) fn string_range(_: &mut Interp, argv: &[Value]) -> TclResult {
    if argv.len() != 5 {
        return Err(Exception::wrong_args("string range string first last"));
    }
    let n = value_len(&argv[2]);
    Ok(char_range(&argv[2], parse_index(&argv[3], n)?, parse_index(&argv[4], n)?))
}

fn cmd_string(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "subcommand ?arg ...?")?;
    let sub = super::pick_subcommand(argv[1].as_str(), SUBCOMMANDS)?;

    let a = &argv[2..];
    let usage = |u: &str| Exception::wrong_args(&format!("string {sub} {u}"));
    let _ = interp;
    match sub {
        "length" => string_length(interp, argv),
        "index" => string_index(interp, argv),
        "range" => string_range(interp, argv),
        "replace" => {
            if a.len() < 3 || a.len() > 4 {
                return Err(usage("string first last ?string?"));
            }
            let s = a[0].as_str();
            let len = char_len(s);
            let n = len as i64;
            let f = parse_index(&a[1], len)?;
            let l = parse_index(&a[2], len)?;
            if l < f || l < 0 || f >= n {
                return Ok(a[0].clone());
            }
            let (f, l) = (f.max(0) as usize, l.min(n - 1) as usize);
            let (bf, bl) = (byte_offset(s, f), byte_offset(s, l + 1));
            let with = if a.len() == 4 { a[3].as_str() } else { "" };
            let mut out = String::with_capacity(s.len() - (bl - bf) + with.len());
            out.push_str(&s[..bf]);
            out.push_str(with);
            out.push_str(&s[bl..]);
            Ok(Value::from_string(out))
        }
        "toupper" | "tolower" | "totitle" => {
            if a.is_empty() || a.len() > 3 {
                return Err(usage("string ?first? ?last?"));
            }
            // Character by character, one for one, as Tcl maps case; only
            // the range first..last (inclusive) changes.
            let s = a[0].as_str();
            if a.len() == 1 && sub != "totitle" {
                return Ok(Value::from_string(match (sub, s.is_ascii()) {
                    ("toupper", true) => s.to_ascii_uppercase(),
                    ("toupper", false) => s.chars().map(upper).collect(),
                    (_, true) => s.to_ascii_lowercase(),
                    _ => s.chars().map(lower).collect(),
                }));
            }
            let chars: Vec<char> = a[0].as_str().chars().collect();
            let n = chars.len();
            let first = match a.get(1) {
                Some(v) => parse_index(v, n)?,
                None => 0,
            };
            let last = match a.get(2) {
                Some(v) => parse_index(v, n)?,
                None if a.len() == 2 => first,
                None => n as i64 - 1,
            };
            let (lo, hi) = (first.max(0), last.min(n as i64 - 1));
            let out: String = chars
                .iter()
                .enumerate()
                .map(|(i, &c)| {
                    let i = i as i64;
                    if i < lo || i > hi {
                        return c;
                    }
                    match sub {
                        "toupper" => upper(c),
                        "tolower" => lower(c),
                        _ if i == lo => title(c),
                        _ => lower(c),
                    }
                })
                .collect();
            Ok(Value::from_string(out))
        }
        "equal" | "compare" => {
            let u = "?-nocase? ?-length int? string1 string2";
            if a.len() < 2 {
                return Err(usage(u));
            }
            let mut nocase = false;
            let mut length: Option<i64> = None;
            let mut i = 0;
            while i < a.len() - 2 {
                let o = a[i].as_str();
                let is = |full: &str| o.len() > 1 && full.starts_with(o);
                if is("-nocase") {
                    nocase = true;
                } else if is("-length") {
                    if i + 1 >= a.len() - 2 {
                        return Err(usage(u));
                    }
                    i += 1;
                    length = Some(a[i].as_int()?);
                } else {
                    return Err(Exception::error(format!(
                        "bad option \"{o}\": must be -nocase or -length"
                    )));
                }
                i += 1;
            }
            let prep = |v: &Value| -> String {
                let s = if nocase { v.as_str().to_lowercase() } else { v.as_str().to_string() };
                match length {
                    Some(n) if n >= 0 => s.chars().take(n as usize).collect(),
                    _ => s,
                }
            };
            let (x, y) = (prep(&a[a.len() - 2]), prep(&a[a.len() - 1]));
            Ok(Value::from_int(if sub == "equal" {
                (x == y) as i64
            } else {
                match x.cmp(&y) {
                    std::cmp::Ordering::Less => -1,
                    std::cmp::Ordering::Equal => 0,
                    std::cmp::Ordering::Greater => 1,
                }
            }))
        }
        "match" => {
            let (nocase, rest) = match a {
                [o, p, s] => {
                    nocase_flag(o)?;
                    (true, [p, s])
                }
                [p, s] => (false, [p, s]),
                _ => return Err(usage("?-nocase? pattern string")),
            };
            Ok(Value::from_bool(glob_match(rest[0].as_str(), rest[1].as_str(), nocase)))
        }
        "first" | "last" => {
            if a.len() < 2 || a.len() > 3 {
                return Err(usage("needleString haystackString ?startIndex?"));
            }
            let (needle, hay) = (a[0].as_str(), a[1].as_str());
            let (nn, n) = (char_len(needle), char_len(hay));
            if nn == 0 || nn > n {
                return Ok(Value::from_int(-1));
            }
            // Searched as UTF-8 (a match starts on a character), then the
            // byte offset counted back into characters.
            let found = if sub == "first" {
                let start = if a.len() == 3 { parse_index(&a[2], n)?.max(0) as usize } else { 0 };
                if start > n - nn {
                    None
                } else {
                    let b = byte_offset(hay, start);
                    hay[b..].find(needle).map(|i| start + char_len(&hay[b..b + i]))
                }
            } else {
                let last = if a.len() == 3 { parse_index(&a[2], n)? } else { n as i64 - 1 };
                // The whole match must lie at or before `last`.
                if last < 0 {
                    None
                } else {
                    let end = byte_offset(hay, (last as usize + 1).min(n));
                    hay[..end].rfind(needle).map(|i| char_len(&hay[..i]))
                }
            };
            Ok(Value::from_int(found.map(|i| i as i64).unwrap_or(-1)))
        }
        "trim" | "trimleft" | "trimright" => {
            if a.is_empty() || a.len() > 2 {
                return Err(usage("string ?chars?"));
            }
            let set: Vec<char> =
                if a.len() == 2 { chars(a[1].as_str()) } else { chars(TRIM_DEFAULT) };
            let s = a[0].as_str();
            let t = match sub {
                "trim" => s.trim_matches(|c| set.contains(&c)),
                "trimleft" => s.trim_start_matches(|c| set.contains(&c)),
                _ => s.trim_end_matches(|c| set.contains(&c)),
            };
            Ok(Value::from(t))
        }
        "map" => {
            let (nocase, map, s) = match a {
                [o, m, s] => {
                    nocase_flag(o)?;
                    (true, m, s)
                }
                [m, s] => (false, m, s),
                _ => return Err(usage("?-nocase? charMap string")),
            };
            let pairs = map.as_list()?;
            if pairs.len() % 2 != 0 {
                return Err(Exception::error("char map list unbalanced"));
            }
            // Works on the string in place: a copy as chars would take four
            // times its bytes.
            let keys: Vec<(String, &str)> = pairs
                .chunks(2)
                .filter(|kv| !kv[0].as_str().is_empty())
                .map(|kv| (fold(kv[0].as_str(), nocase), kv[1].as_str()))
                .collect();
            let src = s.as_str();
            let mut out = String::new();
            let mut i = 0;
            'outer: while i < src.len() {
                for (k, v) in &keys {
                    if let Some(n) = match_at(&src[i..], k, nocase) {
                        check_len(out.len() + v.len())?;
                        out.push_str(v);
                        i += n;
                        continue 'outer;
                    }
                }
                let c = src[i..].chars().next().unwrap_or(' ');
                check_len(out.len() + 4)?;
                out.push(c);
                i += c.len_utf8();
            }
            Ok(Value::from_string(out))
        }
        "repeat" => {
            if a.len() != 2 {
                return Err(usage("string count"));
            }
            let n = a[1].as_int()?.max(0) as usize;
            check_len(n.saturating_mul(a[0].as_str().len()))?;
            Ok(Value::from_string(a[0].as_str().repeat(n)))
        }
        "reverse" => {
            if a.len() != 1 {
                return Err(usage("string"));
            }
            Ok(Value::from_string(a[0].as_str().chars().rev().collect()))
        }
        "cat" => {
            check_len(a.iter().map(|v| v.as_str().len()).sum())?;
            Ok(Value::from_string(a.iter().map(|v| v.as_str()).collect()))
        }
        "is" => string_is(interp, a),
        "bytelength" => {
            if a.len() != 1 {
                return Err(usage("string"));
            }
            Ok(Value::from_int(a[0].as_str().len() as i64))
        }
        "wordend" | "wordstart" => {
            if a.len() != 2 {
                return Err(usage("string index"));
            }
            let s = chars(a[0].as_str());
            let n = s.len();
            let i = parse_index(&a[1], n)?.clamp(0, n.saturating_sub(1) as i64) as usize;
            let word = |c: char| c.is_alphanumeric() || c == '_';
            if n == 0 {
                return Ok(Value::from_int(if sub == "wordend" { 1 } else { 0 }));
            }
            let r = if sub == "wordend" {
                let mut j = i;
                if word(s[i]) {
                    while j < n && word(s[j]) {
                        j += 1;
                    }
                } else {
                    j += 1;
                }
                j
            } else {
                let mut j = i;
                if word(s[i]) {
                    while j > 0 && word(s[j - 1]) {
                        j -= 1;
                    }
                }
                j
            };
            Ok(Value::from_int(r as i64))
        }
        _ => unreachable!("pick_option only returns listed names"),
    }
}

fn string_is(interp: &mut Interp, a: &[Value]) -> TclResult {
    const CLASSES: &[&str] = &[
        "alnum",
        "alpha",
        "ascii",
        "boolean",
        "control",
        "digit",
        "double",
        "entier",
        "false",
        "graph",
        "integer",
        "list",
        "lower",
        "print",
        "punct",
        "space",
        "true",
        "upper",
        "wideinteger",
        "wordchar",
        "xdigit",
    ];
    if a.len() < 2 {
        return Err(Exception::wrong_args("string is class ?-strict? ?-failindex var? str"));
    }
    let class = pick_option(a[0].as_str(), CLASSES, "class")?;
    let (mut strict, mut fail_var) = (false, None);
    let mut i = 1;
    while i < a.len() - 1 {
        match pick_option(a[i].as_str(), &["-failindex", "-strict"], "option") {
            Ok("-strict") => strict = true,
            Ok(_) if i + 1 < a.len() - 1 => {
                fail_var = Some(a[i + 1].clone());
                i += 1;
            }
            _ => {
                return Err(Exception::error(format!(
                    "bad option \"{}\": must be -strict or -failindex",
                    a[i].as_str()
                )));
            }
        }
        i += 1;
    }
    let v = &a[a.len() - 1];
    let s = v.as_str();
    // Where the string stops being of the class (for -failindex).
    let fail_at = |at: i64, interp: &mut Interp| -> TclResult {
        if let Some(var) = &fail_var {
            interp.set_var(var.as_str(), Value::from_int(at))?;
        }
        Ok(Value::from_bool(false))
    };
    if s.is_empty() {
        if strict && class != "list" {
            return fail_at(0, interp);
        }
        return Ok(Value::from_bool(true));
    }
    // The character classes fail at their first character outside.
    let char_class: Option<fn(char) -> bool> = match class {
        "alnum" => Some(char::is_alphanumeric),
        "alpha" => Some(char::is_alphabetic),
        "ascii" => Some(|c: char| c.is_ascii()),
        "control" => Some(char::is_control),
        "digit" => Some(|c: char| c.is_ascii_digit()),
        "graph" => Some(|c: char| !c.is_whitespace() && !c.is_control()),
        "print" => Some(|c: char| !c.is_control()),
        "punct" => Some(|c: char| c.is_ascii_punctuation()),
        "lower" => Some(char::is_lowercase),
        "upper" => Some(char::is_uppercase),
        "space" => Some(char::is_whitespace),
        "wordchar" => Some(|c: char| c.is_alphanumeric() || c == '_'),
        "xdigit" => Some(|c: char| c.is_ascii_hexdigit()),
        _ => None,
    };
    if let Some(f) = char_class {
        return match s.chars().position(|c| !f(c)) {
            Some(at) => fail_at(at as i64, interp),
            None => Ok(Value::from_bool(true)),
        };
    }
    let r = match class {
        "boolean" => number::parse_bool(s).is_some() || matches!(number::parse_int(s), Some(0 | 1)),
        "true" => number::parse_bool(s) == Some(true) || number::parse_int(s) == Some(1),
        "false" => number::parse_bool(s) == Some(false) || number::parse_int(s) == Some(0),
        "double" => number::parse_double(s).is_some(),
        "integer" | "wideinteger" | "entier" => int_class_fits(class, s),
        _ => v.as_list().is_ok(),
    };
    if r {
        return Ok(Value::from_bool(true));
    }
    // A number fails where its longest readable prefix ends; an integer
    // that is readable whole but too big fails at -1, as in Tcl.
    let at = match class {
        "integer" | "wideinteger" | "entier" => {
            let at = number::integer_prefix(s);
            if at == s.chars().count() { -1 } else { at as i64 }
        }
        "double" => {
            let ends: Vec<usize> =
                s.char_indices().map(|(b, _)| b).skip(1).chain([s.len()]).collect();
            ends.iter()
                .rev()
                .find(|&&e| number::parse_double(&s[..e]).is_some())
                .map_or(0, |&e| s[..e].chars().count() as i64)
        }
        _ => 0,
    };
    fail_at(at, interp)
}

/// Whether `s` is an integer `string is CLASS` accepts: Tcl takes a
/// magnitude of up to 32 bits for `integer` (either sign), up to 64 for
/// `wideinteger`, any for `entier`. Linear in the length: the digits are
/// counted before any big number is made of them.
fn int_class_fits(class: &str, s: &str) -> bool {
    let Some((_, radix, digits)) = number::int_parts(s) else { return false };
    if class == "entier" {
        return true;
    }
    // 64 bits take at most 22 octal digits (fewer in other bases).
    if digits.trim_start_matches('0').len() > 22 && radix != 2 {
        return false;
    }
    if digits.trim_start_matches('0').len() > 64 {
        return false;
    }
    let Some(n) = number::parse_integer(s) else { return false };
    let bits = match &n {
        Num::Int(i) => 64 - i.unsigned_abs().leading_zeros() as u64,
        Num::Big(b) => b.bits(),
        Num::Double(_) => return false,
    };
    match class {
        "integer" => bits <= 32,
        "wideinteger" => bits <= 64,
        _ => true,
    }
}

fn cmd_format(_: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "formatString ?arg ...?")?;
    Ok(Value::from_string(format::format(argv[1].as_str(), &argv[2..])?))
}

fn cmd_puts(interp: &mut Interp, argv: &[Value]) -> TclResult {
    let usage = "?-nonewline? ?channelId? string";
    check_args(argv, 2, 4, usage)?;
    let mut args = &argv[1..];
    let mut newline = true;
    if args.len() > 1 && args[0].as_str() == "-nonewline" {
        newline = false;
        args = &args[1..];
    }
    let (chan, text) = match args {
        [t] => ("stdout", t),
        [c, t] => (c.as_str(), t),
        _ => return Err(Exception::wrong_args(&format!("puts {usage}"))),
    };
    let mut s = String::with_capacity(text.as_str().len() + 1);
    s.push_str(text.as_str());
    // A list too long to print prints nothing (the error is on its way).
    if let Some(e) = crate::interp::value::take_pending() {
        return Err(e);
    }
    if newline {
        s.push('\n');
    }
    match chan {
        "stdout" => interp.write_stdout(&s)?,
        "stderr" => interp.write_stderr(&s)?,
        other => super::chan::write_to(interp, other, &s)?,
    }
    Ok(Value::empty())
}
