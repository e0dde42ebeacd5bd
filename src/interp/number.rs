//! Numbers as Tcl 8.6 reads and prints them: integer syntaxes (`0x`, `0o`,
//! `0b`, leading-zero octal), doubles, booleans, and the shortest round-trip
//! printing of doubles (`1.0`, `0.30000000000000004`, `1e+20`).

use std::rc::Rc;

use num_bigint::BigInt;
use num_traits::{ToPrimitive, Zero};

use super::error::Exception;

/// A Tcl number. Integers are 64-bit until they overflow, then bignums
/// (invariant: a `Big` never fits an `i64`, so `Int` is the only form of
/// a small integer and the fast paths need look no further).
#[derive(Clone, Debug, PartialEq)]
pub enum Num {
    Int(i64),
    Double(f64),
    Big(Rc<BigInt>),
}

impl Num {
    /// An integer of any size, in its canonical form.
    pub fn from_big(b: BigInt) -> Num {
        match b.to_i64() {
            Some(i) => Num::Int(i),
            None => Num::Big(Rc::new(b)),
        }
    }

    pub fn to_f64(&self) -> f64 {
        match self {
            Num::Int(i) => *i as f64,
            Num::Double(d) => *d,
            Num::Big(b) => big_to_f64(b),
        }
    }

    pub fn truthy(&self) -> bool {
        match self {
            Num::Int(i) => *i != 0,
            Num::Double(d) => *d != 0.0,
            Num::Big(b) => !b.is_zero(),
        }
    }

    /// The integer as a bignum, or `None` for a double.
    pub fn to_bigint(&self) -> Option<BigInt> {
        match self {
            Num::Int(i) => Some(BigInt::from(*i)),
            Num::Double(_) => None,
            Num::Big(b) => Some((**b).clone()),
        }
    }

    /// An integer cut to its low 64 bits, as `wide()` and `%d` do.
    pub fn wrap_i64(&self) -> Option<i64> {
        match self {
            Num::Int(i) => Some(*i),
            Num::Double(_) => None,
            Num::Big(b) => Some(wrap_big(b)),
        }
    }
}

/// The sum of two integers of any size.
pub fn int_add(a: &Num, b: &Num) -> Num {
    if let (Num::Int(x), Num::Int(y)) = (a, b)
        && let Some(s) = x.checked_add(*y)
    {
        return Num::Int(s);
    }
    match (a.to_bigint(), b.to_bigint()) {
        (Some(x), Some(y)) => Num::from_big(x + y),
        _ => Num::Double(a.to_f64() + b.to_f64()),
    }
}

/// The low 64 bits of a bignum, two's complement.
pub fn wrap_big(b: &BigInt) -> i64 {
    let digits = b.iter_u64_digits().next().unwrap_or(0);
    let v = digits as i64;
    if b.sign() == num_bigint::Sign::Minus { v.wrapping_neg() } else { v }
}

/// A bignum as the nearest double (infinite when out of range).
pub fn big_to_f64(b: &BigInt) -> f64 {
    b.to_f64().unwrap_or(if b.sign() == num_bigint::Sign::Minus {
        f64::NEG_INFINITY
    } else {
        f64::INFINITY
    })
}

fn trim_tcl(s: &str) -> &str {
    let b = s.as_bytes();
    let space = |c: u8| matches!(c, b' ' | b'\t' | b'\n' | b'\r' | 0x0b | 0x0c);
    if let (Some(&f), Some(&l)) = (b.first(), b.last())
        && !space(f)
        && !space(l)
    {
        return s;
    }
    s.trim_matches(|c: char| matches!(c, ' ' | '\t' | '\n' | '\r' | '\x0b' | '\x0c'))
}

/// An integer's parts: its sign, radix and digits (checked to be digits
/// of that radix), in any Tcl syntax (surrounding white space allowed).
pub(crate) fn int_parts(s: &str) -> Option<(bool, u32, &str)> {
    let t = trim_tcl(s);
    let (neg, body) = match t.as_bytes().first()? {
        b'-' => (true, &t[1..]),
        b'+' => (false, &t[1..]),
        _ => (false, t),
    };
    let b = body.as_bytes();
    if b.is_empty() {
        return None;
    }
    let (radix, digits) = if b.len() > 1 && b[0] == b'0' {
        match b[1] {
            b'x' | b'X' => (16, &body[2..]),
            b'o' | b'O' => (8, &body[2..]),
            b'b' | b'B' => (2, &body[2..]),
            b'0'..=b'9' => (8, &body[1..]),
            _ => return None,
        }
    } else {
        (10, body)
    };
    if digits.is_empty() || !digits.bytes().all(|c| (c as char).is_digit(radix)) {
        return None;
    }
    Some((neg, radix, digits))
}

/// The length in characters of the longest prefix of `s` that is an
/// integer in Tcl's syntax (what `int_parts` takes), in one pass: where
/// `string is integer -failindex` puts the failure. 0 when none is.
pub fn integer_prefix(s: &str) -> usize {
    #[derive(Clone, Copy, PartialEq)]
    enum St {
        Lead,
        Sign,
        Zero,
        Mark(u32),
        Digits(u32),
        Trail,
    }
    let space = |c: char| matches!(c, ' ' | '\t' | '\n' | '\r' | '\x0b' | '\x0c');
    let mut st = St::Lead;
    let mut best = 0;
    for (k, c) in s.chars().enumerate() {
        st = match (st, c) {
            (St::Lead, c) if space(c) => St::Lead,
            (St::Lead, '+' | '-') => St::Sign,
            (St::Lead | St::Sign, '0') => St::Zero,
            (St::Lead | St::Sign, '1'..='9') => St::Digits(10),
            (St::Zero, 'x' | 'X') => St::Mark(16),
            (St::Zero, 'o' | 'O') => St::Mark(8),
            (St::Zero, 'b' | 'B') => St::Mark(2),
            // A leading zero makes the rest octal: 012 is ten, 08 nothing.
            (St::Zero, c) if c.is_digit(8) => St::Digits(8),
            (St::Mark(r) | St::Digits(r), c) if c.is_digit(r) => St::Digits(r),
            (St::Zero | St::Digits(_) | St::Trail, c) if space(c) => St::Trail,
            _ => break,
        };
        if matches!(st, St::Zero | St::Digits(_) | St::Trail) {
            best = k + 1;
        }
    }
    best
}

/// Parses a 64-bit integer in any Tcl syntax (surrounding white space allowed).
pub fn parse_int(s: &str) -> Option<i64> {
    let (neg, radix, digits) = int_parts(s)?;
    let mag = u64::from_str_radix(digits, radix).ok()?;
    if neg {
        if mag <= i64::MAX as u64 + 1 { Some((mag as i64).wrapping_neg()) } else { None }
    } else {
        i64::try_from(mag).ok()
    }
}

/// Parses an integer of any size in any Tcl syntax.
pub fn parse_integer(s: &str) -> Option<Num> {
    if let Some(i) = parse_int(s) {
        return Some(Num::Int(i));
    }
    let (neg, radix, digits) = int_parts(s)?;
    let mag = BigInt::parse_bytes(digits.as_bytes(), radix)?;
    Some(Num::from_big(if neg { -mag } else { mag }))
}

/// Parses a double in Tcl syntax; integers are accepted too.
pub fn parse_double(s: &str) -> Option<f64> {
    if let Some(i) = parse_int(s) {
        return Some(i as f64);
    }
    parse_float(s).or_else(|| parse_integer(s).map(|n| n.to_f64()))
}

/// A double that is not written as an integer.
fn parse_float(s: &str) -> Option<f64> {
    let t = trim_tcl(s);
    let b = t.as_bytes();
    let body = t.strip_prefix(['+', '-']).unwrap_or(t);
    if body.len() > 1 && body.starts_with('0') && body.bytes().all(|c| c.is_ascii_digit()) {
        return None; // An invalid octal integer such as 08 is not a double either.
    }
    if body.as_bytes().first().is_some_and(|c| c.is_ascii_alphabetic()) {
        let lower = body.to_ascii_lowercase();
        if matches!(lower.as_str(), "inf" | "infinity" | "nan") {
            return t.parse().ok();
        }
        return None;
    }
    // Rust accepts a few spellings Tcl does not; check the shape first.
    if b.is_empty()
        || !b.iter().all(|c| c.is_ascii_digit() || matches!(c, b'.' | b'e' | b'E' | b'+' | b'-'))
        || !body.bytes().next().is_some_and(|c| c.is_ascii_digit() || c == b'.')
    {
        return None;
    }
    t.parse().ok()
}

/// A number of either kind: integers stay integers.
/// Powers of ten that are exact in an f64.
pub(crate) const POW10: [f64; 23] = [
    1e0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9, 1e10, 1e11, 1e12, 1e13, 1e14, 1e15, 1e16,
    1e17, 1e18, 1e19, 1e20, 1e21, 1e22,
];

/// Clinger's fast path: `[-]digits[.digits]` with at most 15 significant
/// digits is exactly `mantissa / 10^k`, correctly rounded. Anything else
/// (exponents, long mantissas, other syntaxes) returns `None`.
pub(crate) fn parse_simple_decimal(b: &[u8]) -> Option<Num> {
    let neg = b.first() == Some(&b'-');
    let start = if neg || b.first() == Some(&b'+') { 1 } else { 0 };
    let mut i = start;
    let mut m: u64 = 0;
    while i < b.len() && b[i].is_ascii_digit() {
        m = m.wrapping_mul(10).wrapping_add((b[i] - b'0') as u64);
        i += 1;
    }
    let int_end = i;
    let mut frac = None;
    if i < b.len() && b[i] == b'.' {
        i += 1;
        let f = i;
        while i < b.len() && b[i].is_ascii_digit() {
            m = m.wrapping_mul(10).wrapping_add((b[i] - b'0') as u64);
            i += 1;
        }
        frac = Some(i - f);
    }
    let n_digits = i - start - frac.is_some() as usize;
    if i != b.len() || !(1..=15).contains(&n_digits) {
        return None;
    }
    match frac {
        // Leading zeros mean octal in Tcl: not this path.
        None if int_end - start > 1 && b[start] == b'0' => None,
        None => Some(Num::Int(if neg { -(m as i64) } else { m as i64 })),
        Some(k) => {
            let v = m as f64 / POW10[k];
            Some(Num::Double(if neg { -v } else { v }))
        }
    }
}

pub fn parse_num(s: &str) -> Option<Num> {
    if s.is_empty() {
        return None;
    }
    if let Some(n) = parse_simple_decimal(s.as_bytes()) {
        return Some(n);
    }
    // Fast path: a plain decimal integer or decimal fraction.
    let b = s.as_bytes();
    let body = match b.first() {
        Some(b'-' | b'+') => &b[1..],
        _ => b,
    };
    let decimal = matches!(body, [b'1'..=b'9', ..] | [b'0', b'.', ..] | [b'0']);
    if decimal {
        if body.iter().all(u8::is_ascii_digit) {
            return match s.parse::<i64>() {
                Ok(i) => Some(Num::Int(i)),
                Err(_) => parse_integer(s),
            };
        }
        if body.iter().all(|c| c.is_ascii_digit() || matches!(c, b'.' | b'e' | b'E' | b'+' | b'-'))
        {
            return s.parse::<f64>().ok().map(Num::Double);
        }
    }
    if let Some(n) = parse_integer(s) {
        return Some(n);
    }
    parse_float(s).map(Num::Double)
}

pub fn parse_bool(s: &str) -> Option<bool> {
    let l = s.to_ascii_lowercase();
    let l = l.as_str();
    if l.is_empty() {
        return None;
    }
    let prefix_of = |w: &str, min: usize| l.len() >= min && w.starts_with(l);
    if prefix_of("true", 1) || prefix_of("yes", 1) || prefix_of("on", 2) {
        Some(true)
    } else if prefix_of("false", 1) || prefix_of("no", 1) || prefix_of("off", 2) {
        Some(false)
    } else {
        None
    }
}

pub fn int_error(s: &str) -> Exception {
    let t = trim_tcl(s);
    let octal_like = t.len() > 1
        && t.trim_start_matches(['+', '-']).starts_with('0')
        && t.trim_start_matches(['+', '-']).bytes().all(|c| c.is_ascii_digit());
    let e = if octal_like {
        Exception::error(format!(
            "expected integer but got \"{s}\" (looks like invalid octal number)"
        ))
    } else {
        Exception::error(format!("expected integer but got \"{s}\""))
    };
    e.with_error_code("TCL VALUE NUMBER")
}

/// Prints a double exactly as Tcl 8.6 does: the shortest digits that read
/// back to the same double, in `%g`-like layout with a 17-digit threshold,
/// and always with a `.` or exponent so it stays a double.
pub fn format_double(d: f64) -> String {
    format_double_digits(d, PRECISION.get())
}

thread_local! {
    /// `tcl_precision`: significant digits for doubles (0: the shortest
    /// that read back).
    static PRECISION: std::cell::Cell<usize> = const { std::cell::Cell::new(0) };
}

/// Sets `tcl_precision` for this thread's interpreter (0 to 17).
pub fn set_precision(digits: usize) {
    PRECISION.set(digits.min(17));
}

/// `format_double` with `precision` significant digits (trailing zeros
/// trimmed), or the shortest that read back for 0, as Tcl_PrintDouble.
pub fn format_double_digits(d: f64, precision: usize) -> String {
    if d.is_nan() {
        return "NaN".into();
    }
    if d.is_infinite() {
        return if d > 0.0 { "Inf".into() } else { "-Inf".into() };
    }
    if d == 0.0 {
        return if d.is_sign_negative() { "-0.0".into() } else { "0.0".into() };
    }
    // The shortest digits that read back; then the same number of digits
    // correctly rounded (ties to even), which is what Tcl (David Gay's
    // dtoa) prints when two candidates are equally close.
    let n_digits = if precision > 0 {
        precision
    } else {
        let shortest = format!("{d:e}");
        shortest
            .split_once('e')
            .map(|(m, _)| m.bytes().filter(u8::is_ascii_digit).count())
            .unwrap_or(1)
    };
    let e = format!("{:.*e}", n_digits.saturating_sub(1), d);
    let (mant, exp) = e.split_once('e').expect("LowerExp always writes an exponent");
    let exp: i32 = exp.parse().expect("LowerExp writes a decimal exponent");
    let (neg, mant) = match mant.strip_prefix('-') {
        Some(m) => (true, m),
        None => (false, mant),
    };
    let mut digits: String = mant.chars().filter(|c| *c != '.').collect();
    while digits.len() > 1 && digits.ends_with('0') {
        digits.pop();
    }
    let mut out = String::with_capacity(24);
    if neg {
        out.push('-');
    }
    if !(-4..17).contains(&exp) {
        out.push_str(&digits[..1]);
        if digits.len() > 1 {
            out.push('.');
            out.push_str(&digits[1..]);
        }
        out.push('e');
        out.push(if exp < 0 { '-' } else { '+' });
        // Two exponent digits at least under tcl_precision, as Tcl 8.4.
        if precision > 0 && exp.abs() < 10 {
            out.push('0');
        }
        out.push_str(&exp.abs().to_string());
    } else if exp < 0 {
        out.push_str("0.");
        for _ in 0..(-exp - 1) {
            out.push('0');
        }
        out.push_str(&digits);
    } else {
        let int_len = exp as usize + 1;
        if digits.len() <= int_len {
            out.push_str(&digits);
            for _ in digits.len()..int_len {
                out.push('0');
            }
            out.push_str(".0");
        } else {
            out.push_str(&digits[..int_len]);
            out.push('.');
            out.push_str(&digits[int_len..]);
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn doubles_print_like_tcl() {
        let cases = [
            (1.0, "1.0"),
            (0.1 + 0.2, "0.30000000000000004"),
            (1e20, "1e+20"),
            (1e-5, "1e-5"),
            (1e-4, "0.0001"),
            (1e16, "10000000000000000.0"),
            (123456789012345678.0, "1.2345678901234568e+17"),
            (-2.5, "-2.5"),
            (7.826369259425611e-6, "7.826369259425611e-6"),
            // A tie between two shortest candidates: Tcl picks the even one.
            (164657298785009.12, "164657298785009.12"),
            (f64::INFINITY, "Inf"),
        ];
        for (d, want) in cases {
            assert_eq!(format_double(d), want, "{d:e}");
        }
    }

    #[test]
    fn integers_in_every_syntax() {
        assert_eq!(parse_int(" 42 "), Some(42));
        assert_eq!(parse_int("0x1F"), Some(31));
        assert_eq!(parse_int("010"), Some(8));
        assert_eq!(parse_int("0b101"), Some(5));
        assert_eq!(parse_int("-0o17"), Some(-15));
        assert_eq!(parse_int("08"), None);
        assert_eq!(parse_int("-9223372036854775808"), Some(i64::MIN));
        assert_eq!(parse_int("1.0"), None);
        assert_eq!(parse_double("1e3"), Some(1000.0));
        assert_eq!(parse_double(".5"), Some(0.5));
        assert_eq!(parse_double("abc"), None);
        assert_eq!(parse_double("1_0"), None);
        assert_eq!(parse_num("0.1"), Some(Num::Double(0.1)));
        assert_eq!(parse_num("-12.5"), Some(Num::Double(-12.5)));
        assert_eq!(parse_num("123"), Some(Num::Int(123)));
        assert_eq!(parse_num("5."), Some(Num::Double(5.0)));
        assert_eq!(parse_num(".5"), Some(Num::Double(0.5)));
        assert_eq!(parse_num("010"), Some(Num::Int(8)));
        assert_eq!(parse_num("."), None);
        assert_eq!(parse_num("0.30000000000000004"), Some(Num::Double(0.30000000000000004)));
    }
}
