//! `regexp` and `regsub` over fancy-regex, with Tcl's regular expression
//! syntax translated where the two differ: `\m \M \y \Y` (word start, end,
//! boundary), `\Z`, embedded options (`(?i)`, `***=`), and Tcl's default
//! that `.` matches a newline (`-line` and `-linestop` turn that off).
//! Backreferences work (fancy-regex's backtracking). Known difference:
//! Tcl's engine prefers the longest match of an alternation (`a|ab` on
//! "ab" matches "ab"), this one the first that matches.
//! Indices are in characters, as Tcl's.

use std::cell::RefCell;
use std::rc::Rc;

use fancy_regex::Regex;

use super::{check_args, parse_index, pick_option};
use crate::interp::error::{Exception, TclResult};
use crate::interp::eval::Interp;
use crate::interp::value::Value;

pub(super) const COMMANDS: &[super::Entry] = &[
    (
        "regexp",
        cmd_regexp,
        "?-option ...? exp string ?matchVar? ?subMatchVar ...?",
        "match a regular expression",
    ),
    (
        "regsub",
        cmd_regsub,
        "?-option ...? exp string subSpec ?varName?",
        "substitute the matches of a regular expression",
    ),
];

/// How a pattern is compiled.
#[derive(Clone, Copy, Default, PartialEq, Eq, Hash)]
pub(crate) struct Flags {
    pub nocase: bool,
    pub expanded: bool,
    /// `.` and `[^...]` stop at newlines.
    pub linestop: bool,
    /// `^` and `$` match at line ends.
    pub lineanchor: bool,
}

/// A compiled pattern, by its text and flags.
type Cached = ((String, Flags), Rc<Regex>);

thread_local! {
    /// Recently compiled patterns.
    static CACHE: RefCell<Vec<Cached>> = const { RefCell::new(Vec::new()) };
}

/// Tcl's pattern syntax in fancy-regex's.
fn translate(pattern: &str, flags: &mut Flags) -> String {
    let mut p = pattern;
    // `***=`: the rest is a literal string; `***:` an ARE.
    if let Some(rest) = p.strip_prefix("***=") {
        return fancy_regex::escape(rest).into_owned();
    }
    if let Some(rest) = p.strip_prefix("***:") {
        p = rest;
    }
    // Embedded options at the start: (?ixn...).
    if let Some(rest) = p.strip_prefix("(?")
        && let Some(end) = rest.find(')')
        && rest[..end].chars().all(|c| "bceimnpqstwx".contains(c))
    {
        for c in rest[..end].chars() {
            match c {
                'i' => flags.nocase = true,
                'c' => flags.nocase = false,
                'x' => flags.expanded = true,
                't' => flags.expanded = false,
                'n' | 'm' => {
                    flags.linestop = true;
                    flags.lineanchor = true;
                }
                'p' => flags.linestop = true,
                'w' => flags.lineanchor = true,
                's' => {
                    flags.linestop = false;
                    flags.lineanchor = false;
                }
                'q' => return fancy_regex::escape(&rest[end + 1..]).into_owned(),
                _ => {}
            }
        }
        p = &rest[end + 1..];
    }
    let mut out = String::with_capacity(p.len() + 8);
    let mut chars = p.chars().peekable();
    let mut in_class = false;
    while let Some(c) = chars.next() {
        match c {
            '\\' => match chars.next() {
                Some('m') if !in_class => out.push_str(r"\b(?=\w)"),
                Some('M') if !in_class => out.push_str(r"\b(?<=\w)"),
                Some('y') if !in_class => out.push_str(r"\b"),
                Some('Y') if !in_class => out.push_str(r"\B"),
                Some('Z') if !in_class => out.push_str(r"\z"),
                Some('e') => out.push_str(r"\x1b"),
                Some(d) => {
                    out.push('\\');
                    out.push(d);
                }
                None => out.push_str(r"\\"),
            },
            '[' if !in_class => {
                in_class = true;
                out.push('[');
                // A leading ^ and a leading ] belong to the class.
                if chars.peek() == Some(&'^') {
                    out.push('^');
                    chars.next();
                }
                if chars.peek() == Some(&']') {
                    out.push_str(r"\]");
                    chars.next();
                }
            }
            '[' if in_class => {
                // [:alpha:] and friends pass through; a lone [ is literal.
                if chars.peek() == Some(&':') {
                    out.push('[');
                } else {
                    out.push_str(r"\[");
                }
            }
            ']' if in_class => {
                in_class = false;
                out.push(']');
            }
            _ => out.push(c),
        }
    }
    out
}

/// The compiled pattern (cached).
pub(crate) fn compile(pattern: &str, flags: Flags) -> Result<Rc<Regex>, Exception> {
    let key = (pattern.to_string(), flags);
    if let Some(r) =
        CACHE.with(|c| c.borrow().iter().find(|(k, _)| *k == key).map(|(_, r)| r.clone()))
    {
        return Ok(r);
    }
    let mut f = flags;
    let body = translate(pattern, &mut f);
    let mut prefix = String::from("(?");
    if f.nocase {
        prefix.push('i');
    }
    if f.expanded {
        prefix.push('x');
    }
    if !f.linestop {
        prefix.push('s');
    }
    if f.lineanchor {
        prefix.push('m');
    }
    let full = if prefix.len() > 2 { format!("{prefix}){body}") } else { body };
    let re =
        fancy_regex::RegexBuilder::new(&full).backtrack_limit(10_000_000).build().map_err(|e| {
            Exception::error(format!("couldn't compile regular expression pattern: {e}"))
                .with_error_code("REGEXP COMPILE")
        })?;
    let re = Rc::new(re);
    CACHE.with(|c| {
        let mut c = c.borrow_mut();
        if c.len() >= 64 {
            c.remove(0);
        }
        c.push((key, re.clone()));
    });
    Ok(re)
}

fn match_error(e: fancy_regex::Error) -> Exception {
    Exception::error(format!("error while matching regular expression: {e}"))
}

/// The character index of each byte offset's char boundary.
fn char_index(s: &str, byte: usize) -> usize {
    s[..byte].chars().count()
}

/// The byte offset of character index `i` (clamped to the end).
fn byte_offset(s: &str, i: usize) -> usize {
    s.char_indices().nth(i).map_or(s.len(), |(b, _)| b)
}

/// The switches of both commands: those that shape the pattern and
/// `-start` are handled here, the command's own by `own` (which says
/// whether it knew the name). Returns the index of the pattern, the
/// pattern's flags, and the byte offset to start from in `text_at`'s word.
fn switches(
    argv: &[Value],
    names: &[&'static str],
    text_at: usize,
    mut own: impl FnMut(&'static str),
) -> Result<(usize, Flags, usize), Exception> {
    let (mut flags, mut start) = (Flags::default(), None);
    let mut i = 1;
    while i < argv.len() {
        let w = argv[i].as_str();
        if !w.starts_with('-') {
            break;
        }
        if w == "--" {
            i += 1;
            break;
        }
        let name = pick_option(w, names, "option").map_err(|_| {
            Exception::error(format!("bad option \"{w}\": must be {}, or --", names.join(", ")))
        })?;
        match name {
            "-nocase" => flags.nocase = true,
            "-expanded" => flags.expanded = true,
            "-line" => {
                flags.linestop = true;
                flags.lineanchor = true;
            }
            "-linestop" => flags.linestop = true,
            "-lineanchor" => flags.lineanchor = true,
            "-start" => {
                i += 1;
                let v = argv
                    .get(i)
                    .ok_or_else(|| Exception::error("missing argument to \"-start\""))?;
                start = Some(v.clone());
            }
            other => own(other),
        }
        i += 1;
    }
    let from = match (&start, argv.get(i + text_at)) {
        (Some(s), Some(text)) => {
            let text = text.as_str();
            let n = text.chars().count();
            byte_offset(text, parse_index(s, n)?.clamp(0, n as i64) as usize)
        }
        _ => 0,
    };
    Ok((i, flags, from))
}

fn cmd_regexp(interp: &mut Interp, argv: &[Value]) -> TclResult {
    let usage = "?-option ...? exp string ?matchVar? ?subMatchVar ...?";
    let (mut all, mut inline, mut indices) = (false, false, false);
    let names = [
        "-all",
        "-about",
        "-indices",
        "-inline",
        "-expanded",
        "-line",
        "-linestop",
        "-lineanchor",
        "-nocase",
        "-start",
    ];
    let (i, flags, mut from) = switches(argv, &names, 1, |name| match name {
        "-all" => all = true,
        "-inline" => inline = true,
        "-indices" => indices = true,
        _ => {}
    })?;
    if argv.len() < i + 2 {
        return Err(Exception::wrong_args(&format!("regexp {usage}")));
    }
    let vars = &argv[i + 2..];
    if inline && !vars.is_empty() {
        return Err(Exception::error("regexp match variables not allowed when using -inline"));
    }
    let re = compile(argv[i].as_str(), flags)?;
    let text = argv[i + 1].as_str();
    let groups = re.captures_len();
    let mut count = 0i64;
    let mut inline_out = Vec::new();
    let mut last: Option<Vec<Option<(usize, usize)>>> = None;
    loop {
        if count > 0 && from >= text.len() {
            break;
        }
        let caps = match re.captures_from_pos(text, from).map_err(match_error)? {
            Some(c) => c,
            None => break,
        };
        let spans: Vec<Option<(usize, usize)>> =
            (0..groups).map(|g| caps.get(g).map(|m| (m.start(), m.end()))).collect();
        count += 1;
        let (s, e) = spans[0].expect("group 0 is the match");
        if inline {
            for sp in &spans {
                inline_out.push(span_value(text, *sp, indices));
            }
        }
        last = Some(spans);
        if !all {
            break;
        }
        // Past an empty match, one character on.
        from = if e > s { e } else { e + text[e..].chars().next().map_or(1, char::len_utf8) };
        if from > text.len() {
            break;
        }
    }
    if inline {
        return Ok(Value::from_list(inline_out));
    }
    for (g, var) in vars.iter().enumerate() {
        let v = match &last {
            Some(spans) => span_value(text, spans.get(g).copied().flatten(), indices),
            None if indices => Value::from("-1 -1"),
            None => Value::empty(),
        };
        interp.set_var(var.as_str(), v).map_err(|_| {
            Exception::error(format!("can't set \"{}\": variable is array", var.as_str()))
        })?;
    }
    Ok(Value::from_int(count))
}

/// A match or submatch: its text, or with `-indices` its first and last
/// character indices ("-1 -1" when it did not take part).
fn span_value(text: &str, span: Option<(usize, usize)>, indices: bool) -> Value {
    match (span, indices) {
        (Some((s, e)), false) => Value::from(&text[s..e]),
        (Some((s, e)), true) => {
            let (a, b) = (char_index(text, s) as i64, char_index(text, e) as i64 - 1);
            Value::from_list(vec![Value::from_int(a), Value::from_int(b)])
        }
        (None, false) => Value::empty(),
        (None, true) => Value::from_list(vec![Value::from_int(-1), Value::from_int(-1)]),
    }
}

fn cmd_regsub(interp: &mut Interp, argv: &[Value]) -> TclResult {
    let usage = "?-option ...? exp string subSpec ?varName?";
    let (mut all, mut command) = (false, false);
    let names =
        ["-all", "-command", "-expanded", "-line", "-linestop", "-lineanchor", "-nocase", "-start"];
    let (i, flags, mut from) = switches(argv, &names, 1, |name| match name {
        "-all" => all = true,
        "-command" => command = true,
        _ => {}
    })?;
    check_args(&argv[i - 1..], 4, 5, "")
        .map_err(|_| Exception::wrong_args(&format!("regsub {usage}")))?;
    let re = compile(argv[i].as_str(), flags)?;
    let text = argv[i + 1].as_str();
    let spec = argv[i + 2].as_str();
    let mut out = String::from(&text[..from]);
    let mut count = 0i64;
    let mut copied = from;
    loop {
        // As Tcl: no further match is tried at the very end.
        if count > 0 && from >= text.len() {
            break;
        }
        let caps = match re.captures_from_pos(text, from).map_err(match_error)? {
            Some(c) => c,
            None => break,
        };
        let m = caps.get(0).expect("group 0 is the match");
        count += 1;
        // The result grows by steps the budget is asked for as it goes
        // (`regsub -all` of one character by ten can make ten times the
        // text), and Ctrl-C is looked at now and then.
        if count % 4096 == 0 {
            if out.capacity() - out.len() < out.len() / 2 {
                crate::mem::reserve(out.capacity())?;
            }
            interp.poll()?;
        }
        out.push_str(&text[copied..m.start()]);
        if command {
            let mut words = spec_words(spec)?;
            for g in 0..caps.len() {
                words.push(Value::from(caps.get(g).map_or("", |c| c.as_str())));
            }
            out.push_str(interp.invoke(&words)?.as_str());
        } else {
            substitute(&mut out, spec, &caps);
        }
        copied = m.end();
        if !all {
            break;
        }
        from = if m.end() > m.start() {
            m.end()
        } else {
            // An empty match: copy one character and go on past it.
            match text[m.end()..].chars().next() {
                Some(c) => {
                    out.push(c);
                    copied = m.end() + c.len_utf8();
                    copied
                }
                None => break,
            }
        };
        if from > text.len() {
            break;
        }
    }
    out.push_str(&text[copied.min(text.len())..]);
    match argv.get(i + 3) {
        Some(var) => {
            interp.set_var(var.as_str(), Value::from_string(out))?;
            Ok(Value::from_int(count))
        }
        None => Ok(Value::from_string(out)),
    }
}

fn spec_words(spec: &str) -> Result<Vec<Value>, Exception> {
    let words = Value::from(spec).as_list()?.to_vec();
    if words.is_empty() {
        return Err(Exception::error("command prefix must be a list of at least one element"));
    }
    Ok(words)
}

/// `subSpec` for one match: `&` and `\0` the match, `\1`…`\9` its groups,
/// `\&` and `\\` the characters.
fn substitute(out: &mut String, spec: &str, caps: &fancy_regex::Captures<str>) {
    let group = |g: usize| caps.get(g).map_or("", |m| m.as_str());
    let mut chars = spec.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '&' => out.push_str(group(0)),
            '\\' => match chars.peek().copied() {
                Some(d @ '0'..='9') => {
                    chars.next();
                    out.push_str(group(d as usize - '0' as usize));
                }
                Some(d @ ('&' | '\\')) => {
                    chars.next();
                    out.push(d);
                }
                _ => out.push('\\'),
            },
            _ => out.push(c),
        }
    }
}
