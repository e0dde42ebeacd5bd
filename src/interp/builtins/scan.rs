//! `scan`: C's sscanf as Tcl 8.6 does it (after generic/tclScan.c): `%d i
//! o x X b u c s f e g [...] n`, widths, `*` to skip, XPG `%n$` positions,
//! `ll` for integers of any size; with no variables the values come back
//! as a list.

use num_bigint::BigInt;

use super::check_args;
use crate::interp::error::{Exception, TclResult};
use crate::interp::eval::Interp;
use crate::interp::number::Num;
use crate::interp::value::Value;

pub(super) const COMMANDS: &[super::Entry] = &[(
    "scan",
    cmd_scan,
    "string format ?varName ...?",
    "parse a string by conversions, as C's sscanf",
)];

/// The size modifier of a conversion.
#[derive(Clone, Copy, PartialEq)]
enum Size {
    Plain,
    /// `l` or `L`: 64 bits.
    Long,
    /// `ll`: any size.
    Big,
}

/// One `%` conversion, as written.
struct Conv {
    /// Variable slot (None when suppressed with `*`).
    slot: Option<usize>,
    width: usize,
    size: Size,
    ch: char,
    /// The characters of a `[...]` set, after the `[`.
    set: Option<CharSet>,
}

struct CharSet {
    negate: bool,
    chars: Vec<char>,
    ranges: Vec<(char, char)>,
}

impl CharSet {
    fn contains(&self, c: char) -> bool {
        let inside =
            self.chars.contains(&c) || self.ranges.iter().any(|&(a, b)| (a..=b).contains(&c));
        inside != self.negate
    }
}

enum Item {
    /// White space in the format: skips any in the input.
    Space,
    Literal(char),
    Conv(Conv),
}

fn err(msg: &str, code: &str) -> Exception {
    Exception::error(msg).with_error_code(&format!("TCL FORMAT {code}"))
}

/// Parses and checks a format as ValidateFormat does; returns its items
/// and the number of variable slots.
fn parse_format(fmt: &str, num_vars: usize) -> Result<(Vec<Item>, usize), Exception> {
    let f: Vec<char> = fmt.chars().collect();
    let mut i = 0;
    let mut items = Vec::new();
    let (mut got_xpg, mut got_seq) = (false, false);
    let mut next_slot = 0usize;
    let mut xpg_size = 0usize;
    let mut assigned: Vec<usize> = Vec::new();
    let bad_index = |xpg: bool| {
        if xpg {
            err("\"%n$\" argument index out of range", "INDEXRANGE")
        } else {
            err("different numbers of variable names and field specifiers", "FIELDVARMISMATCH")
        }
    };
    let digits = |i: &mut usize| -> usize {
        let s = *i;
        while *i < f.len() && f[*i].is_ascii_digit() {
            *i += 1;
        }
        f[s..*i].iter().collect::<String>().parse().unwrap_or(usize::MAX)
    };
    while i < f.len() {
        let c = f[i];
        i += 1;
        if c.is_whitespace() {
            items.push(Item::Space);
            continue;
        }
        if c != '%' {
            items.push(Item::Literal(c));
            continue;
        }
        if f.get(i) == Some(&'%') {
            i += 1;
            items.push(Item::Literal('%'));
            continue;
        }
        let mut suppress = false;
        if f.get(i) == Some(&'*') {
            suppress = true;
            i += 1;
        } else if f.get(i).is_some_and(char::is_ascii_digit) {
            let mut j = i;
            let n = digits(&mut j);
            if f.get(j) == Some(&'$') {
                got_xpg = true;
                if got_seq {
                    return Err(err(
                        "cannot mix \"%\" and \"%n$\" conversion specifiers",
                        "MIXEDSPECTYPES",
                    ));
                }
                if n == 0 || (num_vars > 0 && n > num_vars) {
                    return Err(bad_index(true));
                }
                if num_vars == 0 {
                    xpg_size = xpg_size.max(n);
                }
                next_slot = n - 1;
                i = j + 1;
            } else {
                got_seq = true;
            }
        } else {
            got_seq = true;
        }
        if got_seq && got_xpg {
            return Err(err(
                "cannot mix \"%\" and \"%n$\" conversion specifiers",
                "MIXEDSPECTYPES",
            ));
        }
        let mut width = 0;
        let has_width = f.get(i).is_some_and(char::is_ascii_digit);
        if has_width {
            width = digits(&mut i);
        }
        let mut size = Size::Plain;
        match f.get(i) {
            Some('l') if f.get(i + 1) == Some(&'l') => {
                size = Size::Big;
                i += 2;
            }
            Some('l' | 'L') => {
                size = Size::Long;
                i += 1;
            }
            Some('h') => i += 1,
            _ => {}
        }
        if !suppress && num_vars > 0 && next_slot >= num_vars {
            return Err(bad_index(got_xpg));
        }
        let Some(&ch) = f.get(i) else {
            return Err(err("bad scan conversion character \"\"", "BADTYPE"));
        };
        i += 1;
        let mut set = None;
        match ch {
            'c' if has_width => {
                return Err(err("field width may not be specified in %c conversion", "BADWIDTH"));
            }
            'c' | 'n' | 's' | '[' if size != Size::Plain => {
                return Err(err(
                    &format!("field size modifier may not be specified in %{ch} conversion"),
                    "BADSIZE",
                ));
            }
            'u' if size == Size::Big => {
                return Err(err("unsigned bignum scans are invalid", "BADUNSIGNED"));
            }
            '[' => {
                let unmatched = || err("unmatched [ in format string", "BRACKET");
                let mut cs = CharSet { negate: false, chars: Vec::new(), ranges: Vec::new() };
                if f.get(i) == Some(&'^') {
                    cs.negate = true;
                    i += 1;
                }
                if f.get(i) == Some(&']') {
                    cs.chars.push(']');
                    i += 1;
                }
                loop {
                    let Some(&c) = f.get(i) else { return Err(unmatched()) };
                    i += 1;
                    if c == ']' {
                        break;
                    }
                    if f.get(i) == Some(&'-') && f.get(i + 1).is_some_and(|&e| e != ']') {
                        let e = f[i + 1];
                        cs.ranges.push(if c <= e { (c, e) } else { (e, c) });
                        i += 2;
                    } else {
                        cs.chars.push(c);
                    }
                }
                set = Some(cs);
            }
            'c' | 'n' | 's' | 'd' | 'e' | 'E' | 'f' | 'g' | 'G' | 'i' | 'o' | 'x' | 'X' | 'b'
            | 'u' => {}
            other => {
                return Err(err(&format!("bad scan conversion character \"{other}\""), "BADTYPE"));
            }
        }
        let slot = if suppress {
            None
        } else {
            if assigned.len() <= next_slot {
                assigned.resize(next_slot + 1, 0);
            }
            assigned[next_slot] += 1;
            next_slot += 1;
            Some(next_slot - 1)
        };
        items.push(Item::Conv(Conv { slot, width, size, ch, set }));
    }
    let total = if num_vars > 0 {
        num_vars
    } else if xpg_size > 0 {
        xpg_size
    } else {
        assigned.len()
    };
    assigned.resize(total.max(assigned.len()), 0);
    for &n in &assigned[..total] {
        if n > 1 {
            return Err(err(
                "variable is assigned by multiple \"%n$\" conversion specifiers",
                "POLYASSIGNED",
            ));
        }
        if n == 0 && xpg_size == 0 {
            return Err(err("variable is not assigned by any conversion specifiers", "UNASSIGNED"));
        }
    }
    Ok((items, total))
}

/// The longest integer at the start of `s` (at most `width` characters)
/// in the syntax a conversion allows: (value, characters used).
fn scan_int(s: &[char], width: usize, ch: char) -> Option<(BigInt, usize)> {
    let s = &s[..s.len().min(width)];
    let mut i = 0;
    let neg = match s.first() {
        Some('-') => {
            i += 1;
            true
        }
        Some('+') => {
            i += 1;
            false
        }
        _ => false,
    };
    let digits_from = |start: usize, radix: u32| {
        let n = s[start..].iter().take_while(|c| c.is_digit(radix)).count();
        (n > 0).then_some((start, start + n, radix))
    };
    let prefixed = |i: usize, letters: [char; 2], radix: u32| {
        if s.get(i) == Some(&'0') && s.get(i + 1).is_some_and(|c| letters.contains(c)) {
            digits_from(i + 2, radix)
        } else {
            None
        }
    };
    let (start, end, radix) = match ch {
        'd' | 'u' => digits_from(i, 10)?,
        'x' | 'X' => prefixed(i, ['x', 'X'], 16).or_else(|| digits_from(i, 16))?,
        'b' => prefixed(i, ['b', 'B'], 2).or_else(|| digits_from(i, 2))?,
        'o' => digits_from(i, 8)?,
        // As C's strtol: `0x` for hex, a leading 0 for octal.
        _ => prefixed(i, ['x', 'X'], 16)
            .or_else(|| if s.get(i) == Some(&'0') { digits_from(i, 8) } else { None })
            .or_else(|| digits_from(i, 10))?,
    };
    let text: String = s[start..end].iter().collect();
    let mag = BigInt::parse_bytes(text.as_bytes(), radix)?;
    Some((if neg { -mag } else { mag }, end))
}

/// The longest decimal floating-point number at the start of `s`.
fn scan_float(s: &[char], width: usize) -> Option<(f64, usize)> {
    let s = &s[..s.len().min(width)];
    let mut i = 0;
    if matches!(s.first(), Some('-' | '+')) {
        i += 1;
    }
    let word: String = s[i..].iter().take(8).collect::<String>().to_ascii_lowercase();
    for (w, v) in [("infinity", f64::INFINITY), ("inf", f64::INFINITY)] {
        if word.starts_with(w) {
            let v = if s.first() == Some(&'-') { -v } else { v };
            return Some((v, i + w.len()));
        }
    }
    let int = s[i..].iter().take_while(|c| c.is_ascii_digit()).count();
    let mut end = i + int;
    let mut frac = 0;
    if s.get(end) == Some(&'.') {
        frac = s[end + 1..].iter().take_while(|c| c.is_ascii_digit()).count();
        if int + frac > 0 {
            end += 1 + frac;
        }
    }
    if int + frac == 0 {
        return None;
    }
    if matches!(s.get(end), Some('e' | 'E')) {
        let mut j = end + 1;
        if matches!(s.get(j), Some('-' | '+')) {
            j += 1;
        }
        let n = s[j..].iter().take_while(|c| c.is_ascii_digit()).count();
        if n > 0 {
            end = j + n;
        }
    }
    let text: String = s[..end].iter().collect();
    text.parse().ok().map(|v| (v, end))
}

/// An integer as a plain conversion gives it: 64 bits, clamped when
/// larger (a `%u` of a negative number reads it as unsigned).
fn sized(v: BigInt, size: Size, unsigned: bool) -> Value {
    if size == Size::Big {
        return Value::from_num(Num::from_big(v));
    }
    let n = match Num::from_big(v.clone()) {
        Num::Int(i) => i,
        Num::Big(b) if b.bits() <= 64 => crate::interp::number::wrap_big(&b),
        _ if v.sign() == num_bigint::Sign::Minus => i64::MIN,
        _ => i64::MAX,
    };
    if unsigned && n < 0 {
        return Value::from_num(Num::from_big(BigInt::from(n as u64)));
    }
    Value::from_int(n)
}

fn cmd_scan(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 3, usize::MAX, "string format ?varName ...?")?;
    let vars = &argv[3..];
    let (items, total) = parse_format(argv[2].as_str(), vars.len())?;
    let input: Vec<char> = argv[1].as_str().chars().collect();
    let mut values: Vec<Option<Value>> = vec![None; total];
    let mut at = 0;
    let mut conversions = 0;
    let mut underflow = false;
    'items: for item in &items {
        let conv = match item {
            Item::Space => {
                while at < input.len() && input[at].is_whitespace() {
                    at += 1;
                }
                continue;
            }
            Item::Literal(c) => {
                if at >= input.len() {
                    underflow = true;
                    break;
                }
                if input[at] != *c {
                    break;
                }
                at += 1;
                continue;
            }
            Item::Conv(c) => c,
        };
        if conv.ch == 'n' {
            if let Some(slot) = conv.slot {
                values[slot] = Some(Value::from_int(at as i64));
            }
            conversions += 1;
            continue;
        }
        if at >= input.len() {
            underflow = true;
            break;
        }
        if !matches!(conv.ch, 'c' | '[') {
            while at < input.len() && input[at].is_whitespace() {
                at += 1;
            }
            if at >= input.len() {
                underflow = true;
                break;
            }
        }
        let width = if conv.width == 0 { usize::MAX } else { conv.width };
        let rest = &input[at..];
        let (value, used) = match conv.ch {
            's' => {
                let n = rest.iter().take(width).take_while(|c| !c.is_whitespace()).count();
                (Value::from_string(rest[..n].iter().collect()), n)
            }
            '[' => {
                let set = conv.set.as_ref().expect("a [ conversion has a set");
                let n = rest.iter().take(width).take_while(|&&c| set.contains(c)).count();
                if n == 0 {
                    break 'items;
                }
                (Value::from_string(rest[..n].iter().collect()), n)
            }
            'c' => (Value::from_int(rest[0] as i64), 1),
            'f' | 'e' | 'E' | 'g' | 'G' => match scan_float(rest, width) {
                Some((v, n)) => (Value::from_f64(v), n),
                None => {
                    underflow = rest.len() <= width.min(1);
                    break;
                }
            },
            ch => match scan_int(rest, width, ch) {
                Some((v, n)) => (sized(v, conv.size, ch == 'u'), n),
                None => {
                    // Input that ends inside a number counts as running out.
                    underflow = rest.iter().take(width).all(|c| matches!(c, '+' | '-'));
                    break;
                }
            },
        };
        at += used;
        if let Some(slot) = conv.slot {
            values[slot] = Some(value);
        }
        conversions += 1;
    }
    if vars.is_empty() {
        if underflow && conversions == 0 {
            return Ok(Value::empty());
        }
        return Ok(Value::from_list(
            values.into_iter().map(|v| v.unwrap_or_else(Value::empty)).collect(),
        ));
    }
    if underflow && conversions == 0 {
        return Ok(Value::from_int(-1));
    }
    let mut assigned = 0;
    for (v, name) in values.into_iter().zip(vars) {
        if let Some(v) = v {
            interp.set_var(name.as_str(), v)?;
            assigned += 1;
        }
    }
    Ok(Value::from_int(assigned))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn chars(s: &str) -> Vec<char> {
        s.chars().collect()
    }

    #[test]
    fn integers_by_conversion() {
        let v = |s: &str, ch| scan_int(&chars(s), usize::MAX, ch).map(|(v, n)| (v.to_string(), n));
        assert_eq!(v("123abc", 'd'), Some(("123".into(), 3)));
        assert_eq!(v("-0x1f", 'i'), Some(("-31".into(), 5)));
        assert_eq!(v("017", 'i'), Some(("15".into(), 3)));
        assert_eq!(v("ff", 'x'), Some(("255".into(), 2)));
        assert_eq!(v("x", 'd'), None);
        assert_eq!(
            scan_int(&chars("12345"), 2, 'd').map(|(v, n)| (v.to_string(), n)),
            Some(("12".into(), 2))
        );
    }

    #[test]
    fn floats_take_the_longest_prefix() {
        assert_eq!(scan_float(&chars("1.5e3x"), usize::MAX), Some((1500.0, 5)));
        assert_eq!(scan_float(&chars("2.e"), usize::MAX), Some((2.0, 2)));
        assert_eq!(scan_float(&chars(".x"), usize::MAX), None);
    }
}
