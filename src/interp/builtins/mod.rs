//! The built-in Tcl commands, registered in one table (`register_all`), with
//! the usage line each one reports in `wrong # args` and in `help`.

mod binary;
mod chan;
mod control;
pub(crate) mod coro;
mod dict;
mod exec;
mod file;
mod lists;
mod mathop;
mod misc;
mod namespace;
mod package;
pub(crate) mod regexp;
mod scan;
mod strings;
pub(crate) mod trace;
mod vars;

/// The subcommands of the built-in ensembles (`string`, `info`, `array`),
/// as their commands accept them: for completion.
pub fn subcommands(command: &str) -> Option<&'static [&'static str]> {
    match command {
        "string" => Some(strings::SUBCOMMANDS),
        "info" => Some(control::INFO_SUBCOMMANDS),
        "array" => Some(vars::ARRAY_SUBCOMMANDS),
        "file" => Some(file::SUBCOMMANDS),
        _ => None,
    }
}

pub(crate) use chan::Channels;
pub(crate) use control::{check_if, with_body_line};
pub(crate) use coro::Coroutines;
pub use coro::making_a_stack;
pub use exec::waited_children;
pub(crate) use lists::{append_element, append_elements};
pub(crate) use misc::{PARRAY, UNKNOWN};
pub use package::{Packages, TCL_PATCHLEVEL, TCL_VERSION};
pub(crate) use strings::{string_index, string_length, string_range};
pub(crate) use trace::{CmdTraces, VarTraceTable};
pub(crate) use vars::append_strings;

use super::error::Exception;
use super::eval::{Interp, NativeFn};
use super::value::Value;

type Entry = (&'static str, NativeFn, &'static str, &'static str);

pub(crate) fn register_all(interp: &mut Interp) {
    let tables: [&[Entry]; 16] = [
        binary::COMMANDS,
        chan::COMMANDS,
        control::COMMANDS,
        dict::COMMANDS,
        file::COMMANDS,
        vars::COMMANDS,
        lists::COMMANDS,
        misc::COMMANDS,
        strings::COMMANDS,
        package::COMMANDS,
        regexp::COMMANDS,
        scan::COMMANDS,
        namespace::COMMANDS,
        trace::COMMANDS,
        exec::COMMANDS,
        coro::COMMANDS,
    ];
    for table in tables {
        for (name, f, usage, summary) in table {
            interp.register(name, *f, usage, summary);
        }
    }
    mathop::register(interp);
}

/// Tcl's string hash (`TclHashObjKey`): `h = h*9 + byte`.
fn tcl_hash(key: &str) -> u32 {
    let b = key.as_bytes();
    let Some((&first, rest)) = b.split_first() else { return 0 };
    rest.iter().fold(first as u32, |h, &c| h.wrapping_add(h << 3).wrapping_add(c as u32))
}

/// Keys in the order Tcl's hash table lists them, given the order they
/// were inserted: the table starts with 4 buckets, grows fourfold when it
/// holds 3 entries per bucket (re-inserting chain by chain), puts a new
/// entry at the head of its bucket's chain, and is walked bucket by
/// bucket. `array names` and `array get` print in this order, as tclsh
/// does (exactly so while nothing was deleted: deletions here are
/// forgotten, where Tcl's table keeps the size they left).
pub(crate) fn tcl_hash_order<'a, T>(items: impl IntoIterator<Item = (&'a str, T)>) -> Vec<T> {
    let mut buckets: Vec<Vec<(u32, T)>> = (0..4).map(|_| Vec::new()).collect();
    let (mut mask, mut rebuild_at, mut n) = (3u32, 12usize, 0usize);
    for (key, item) in items {
        let h = tcl_hash(key);
        // A chain is kept with its head last.
        buckets[(h & mask) as usize].push((h, item));
        n += 1;
        if n >= rebuild_at {
            let old = std::mem::take(&mut buckets);
            buckets = (0..old.len() * 4).map(|_| Vec::new()).collect();
            mask = (mask << 2) | 3;
            rebuild_at *= 4;
            for chain in old {
                for (h, item) in chain.into_iter().rev() {
                    buckets[(h & mask) as usize].push((h, item));
                }
            }
        }
    }
    buckets.into_iter().flat_map(|chain| chain.into_iter().rev().map(|(_, item)| item)).collect()
}

/// Checks the argument count: `min..=max` words including the command name.
pub(crate) fn check_args(
    argv: &[Value],
    min: usize,
    max: usize,
    usage: &str,
) -> Result<(), Exception> {
    if argv.len() < min || argv.len() > max {
        let name = argv[0].as_str();
        return Err(Exception::wrong_args(&if usage.is_empty() {
            name.to_string()
        } else {
            format!("{name} {usage}")
        }));
    }
    Ok(())
}

/// Parses a Tcl index (`3`, `end`, `end-1`, `2+1`) against a length.
/// Returns an index that may be out of range (negative or >= len).
pub(crate) fn parse_index(v: &Value, len: usize) -> Result<i64, Exception> {
    if let Some(i) = v.cached_int() {
        return Ok(i);
    }
    let raw = v.as_str();
    if raw == "end" {
        return Ok(len as i64 - 1);
    }
    // A plain decimal integer: kept as the value's number, so the next
    // use of this (literal) index reads it straight.
    if !raw.is_empty()
        && raw.len() < 19
        && raw.bytes().all(|b| b.is_ascii_digit())
        && (raw.len() == 1 || !raw.starts_with('0'))
        && let Some(super::number::Num::Int(i)) = v.as_num()
    {
        return Ok(i);
    }
    let s = raw.trim();
    let bad = || {
        Exception::error(format!(
            "bad index \"{}\": must be integer?[+-]integer? or end?[+-]integer?",
            v.as_str()
        ))
        .with_error_code("TCL VALUE INDEX")
    };
    let int = |t: &str| super::number::parse_int(t).filter(|_| !t.trim().is_empty());
    if let Some(rest) = s.strip_prefix("end") {
        let end = len as i64 - 1;
        if rest.is_empty() {
            return Ok(end);
        }
        let n = rest.get(1..).and_then(int).ok_or_else(bad)?;
        return match rest.as_bytes()[0] {
            b'-' => Ok(end.saturating_sub(n)),
            b'+' => Ok(end.saturating_add(n)),
            _ => Err(bad()),
        };
    }
    if let Some(i) = int(s) {
        return Ok(i);
    }
    // a+b or a-b
    let op = s.bytes().enumerate().skip(1).find(|(_, c)| *c == b'+' || *c == b'-');
    if let Some((pos, c)) = op {
        let (a, b) = (int(&s[..pos]).ok_or_else(bad)?, int(&s[pos + 1..]).ok_or_else(bad)?);
        return Ok(if c == b'+' { a.saturating_add(b) } else { a.saturating_sub(b) });
    }
    Err(bad())
}

/// Tcl's `string match` glob: `*`, `?`, `[a-z]`, `\x`.
pub(crate) fn glob_match(pattern: &str, s: &str, nocase: bool) -> bool {
    if pattern.is_ascii() && s.is_ascii() {
        if !nocase {
            return glob_rec(pattern.as_bytes(), s.as_bytes());
        }
        let p = pattern.to_ascii_lowercase();
        let t = s.to_ascii_lowercase();
        return glob_rec(p.as_bytes(), t.as_bytes());
    }
    let fold = |c: char| if nocase { c.to_lowercase().next().unwrap_or(c) } else { c };
    let p: Vec<char> = pattern.chars().map(fold).collect();
    let t: Vec<char> = s.chars().map(fold).collect();
    glob_rec(&p, &t)
}

/// A character of a glob match: a byte of ASCII text, or a `char`.
trait GlobChar: Copy + Ord {
    /// The ASCII character this is, if it is one.
    fn kind(self) -> Option<u8>;
}

impl GlobChar for u8 {
    #[inline]
    fn kind(self) -> Option<u8> {
        Some(self)
    }
}

impl GlobChar for char {
    #[inline]
    fn kind(self) -> Option<u8> {
        self.is_ascii().then_some(self as u8)
    }
}

fn glob_rec<T: GlobChar>(p: &[T], t: &[T]) -> bool {
    let (mut pi, mut ti) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    loop {
        if pi < p.len() {
            match p[pi].kind() {
                Some(b'*') => {
                    while pi < p.len() && p[pi].kind() == Some(b'*') {
                        pi += 1;
                    }
                    if pi == p.len() {
                        return true;
                    }
                    star = Some((pi, ti));
                    continue;
                }
                Some(b'?') if ti < t.len() => {
                    pi += 1;
                    ti += 1;
                    continue;
                }
                Some(b'[') if ti < t.len() => {
                    let mut j = pi + 1;
                    let mut matched = false;
                    while j < p.len() && p[j].kind() != Some(b']') {
                        let lo = p[j];
                        let mut hi = lo;
                        if j + 2 < p.len()
                            && p[j + 1].kind() == Some(b'-')
                            && p[j + 2].kind() != Some(b']')
                        {
                            hi = p[j + 2];
                            j += 2;
                        }
                        let (a, b) = if lo <= hi { (lo, hi) } else { (hi, lo) };
                        if a <= t[ti] && t[ti] <= b {
                            matched = true;
                        }
                        j += 1;
                    }
                    if matched {
                        pi = (j + 1).min(p.len());
                        ti += 1;
                        continue;
                    }
                }
                Some(b'\\') if pi + 1 < p.len() && ti < t.len() && p[pi + 1] == t[ti] => {
                    pi += 2;
                    ti += 1;
                    continue;
                }
                k if k != Some(b'\\') && ti < t.len() && p[pi] == t[ti] => {
                    pi += 1;
                    ti += 1;
                    continue;
                }
                _ => {}
            }
        } else if ti == t.len() {
            return true;
        }
        match star {
            Some((sp, st)) if st < t.len() => {
                star = Some((sp, st + 1));
                pi = sp;
                ti = st + 1;
            }
            _ => return false,
        }
    }
}

/// Matches a unique prefix of one of `options` (Tcl's `Tcl_GetIndexFromObj`).
pub(crate) fn pick_option<'a>(
    given: &str,
    options: &[&'a str],
    what: &str,
) -> Result<&'a str, Exception> {
    if let Some(o) = options.iter().find(|o| **o == given) {
        return Ok(o);
    }
    let matches: Vec<&&str> = options.iter().filter(|o| o.starts_with(given)).collect();
    if matches.len() == 1 && !given.is_empty() {
        return Ok(matches[0]);
    }
    let kind = if matches.len() > 1 { "ambiguous" } else { "bad" };
    let list = match options.len() {
        1 => options[0].to_string(),
        n => format!("{}, or {}", options[..n - 1].join(", "), options[n - 1]),
    };
    Err(Exception::error(format!("{kind} {what} \"{given}\": must be {list}")))
}

/// An ensemble's subcommand by a unique prefix, refused with Tcl's
/// `unknown or ambiguous subcommand "x": must be ...` listing them all.
pub(crate) fn pick_subcommand<'a>(given: &str, subs: &[&'a str]) -> Result<&'a str, Exception> {
    pick_option(given, subs, "subcommand").map_err(|_| {
        let n = subs.len();
        Exception::error(format!(
            "unknown or ambiguous subcommand \"{given}\": must be {}, or {}",
            subs[..n - 1].join(", "),
            subs[n - 1]
        ))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn globs() {
        assert!(glob_match("a*c", "abbbc", false));
        assert!(glob_match("a?c", "abc", false));
        assert!(!glob_match("a?c", "ac", false));
        assert!(glob_match("[a-c]x", "bx", false));
        assert!(glob_match("*.tsd", "teapot.tsd", false));
        assert!(glob_match("A*", "abc", true));
        assert!(glob_match("a\\*", "a*", false));
        assert!(!glob_match("a\\*", "ab", false));
    }

    #[test]
    fn indices() {
        let v = |s: &str| Value::from(s);
        assert_eq!(parse_index(&v("end"), 5).unwrap(), 4);
        assert_eq!(parse_index(&v("end-1"), 5).unwrap(), 3);
        assert_eq!(parse_index(&v("1+2"), 5).unwrap(), 3);
        assert!(parse_index(&v("x"), 5).is_err());
        // Regressions found by fuzzing: no panics on odd input.
        assert!(parse_index(&v("\u{e9}+1"), 5).is_err());
        assert!(parse_index(&v(""), 5).is_err());
        assert!(parse_index(&v("end\u{e9}"), 5).is_err());
        assert_eq!(parse_index(&v("end--9223372036854775808"), 5).unwrap(), i64::MAX);
        assert_eq!(parse_index(&v("9223372036854775807+1"), 5).unwrap(), i64::MAX);
    }
}
