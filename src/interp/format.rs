//! `format`: C's printf as Tcl 8.6 does it (flags `-+ 0#`, width and
//! precision with `*`, XPG `%n$` positions, `d i u o x X b c s f e g a %`).

use num_bigint::{BigUint, Sign};
use num_traits::Zero;

use super::error::Exception;
use super::number::{self, Num};
use super::value::Value;

struct Spec {
    minus: bool,
    plus: bool,
    space: bool,
    zero: bool,
    alt: bool,
    width: usize,
    precision: Option<usize>,
    size: Size,
}

/// C's size modifier: how many bits of an integer are printed.
#[derive(Clone, Copy, PartialEq)]
enum Size {
    /// `h`: 16 bits.
    Short,
    /// None or `l`: 64 bits, as Tcl 8.6 on a 64-bit machine.
    Wide,
    /// `ll`: the whole integer, bignums included, with a sign.
    Big,
}

fn pad(spec: &Spec, body: String, numeric: bool) -> String {
    let len = body.chars().count();
    if len >= spec.width {
        return body;
    }
    let fill = spec.width - len;
    if spec.minus {
        return body + &" ".repeat(fill);
    }
    if spec.zero && numeric {
        // Zeros go after the sign and any 0x prefix.
        let prefix_len = if body.starts_with(['-', '+', ' ']) { 1 } else { 0 };
        let prefix_len =
            if body[prefix_len..].starts_with("0x") || body[prefix_len..].starts_with("0X") {
                prefix_len + 2
            } else {
                prefix_len
            };
        let (p, rest) = body.split_at(prefix_len);
        return format!("{p}{}{rest}", "0".repeat(fill));
    }
    " ".repeat(fill) + &body
}

/// `%s` and `%c`: Tcl pads with zeros too when asked, on the side the
/// text is not (`%05s` of ab is 000ab, `%-05s` is ab000).
fn pad_text(spec: &Spec, body: String) -> String {
    let len = body.chars().count();
    if !spec.zero || len >= spec.width {
        return pad(spec, body, false);
    }
    let zeros = "0".repeat(spec.width - len);
    if spec.minus { body + &zeros } else { zeros + &body }
}

fn sign(spec: &Spec, neg: bool) -> &'static str {
    if neg {
        "-"
    } else if spec.plus {
        "+"
    } else if spec.space {
        " "
    } else {
        ""
    }
}

fn get_int(v: &Value) -> Result<i64, Exception> {
    match v.as_num() {
        Some(Num::Int(i)) => Ok(i),
        _ => Err(number::int_error(v.as_str())),
    }
}

/// An integer argument cut to the spec's size: (negative, magnitude).
/// An integer's magnitude: 64 bits (no allocation) or a bignum (`%ll`).
enum Mag {
    Small(u64),
    Big(BigUint),
}

impl Mag {
    fn is_zero(&self) -> bool {
        match self {
            Mag::Small(m) => *m == 0,
            Mag::Big(b) => b.is_zero(),
        }
    }

    /// The digits in the conversion's base (`o`, `x`, `X`, `b`; else 10).
    fn digits(&self, conv: char) -> String {
        match (self, conv) {
            (Mag::Small(m), 'o') => radix(*m, 3, b"01234567"),
            (Mag::Small(m), 'x') => radix(*m, 4, b"0123456789abcdef"),
            (Mag::Small(m), 'X') => radix(*m, 4, b"0123456789ABCDEF"),
            (Mag::Small(m), 'b') => radix(*m, 1, b"01"),
            (Mag::Small(m), _) => itoa::Buffer::new().format(*m).to_string(),
            (Mag::Big(b), 'o') => b.to_str_radix(8),
            (Mag::Big(b), 'x') => b.to_str_radix(16),
            (Mag::Big(b), 'X') => b.to_str_radix(16).to_ascii_uppercase(),
            (Mag::Big(b), 'b') => b.to_str_radix(2),
            (Mag::Big(b), _) => b.to_string(),
        }
    }
}

/// The number ASCII digits spell (0 for none; saturating, so a huge
/// width fails the size check rather than wrapping).
fn digits_value(d: &[char]) -> usize {
    d.iter().fold(0usize, |n, c| {
        n.saturating_mul(10).saturating_add(c.to_digit(10).unwrap_or(0) as usize)
    })
}

/// `m` in base 2^`bits` with these digits (no formatter machinery).
fn radix(mut m: u64, bits: u32, digits: &[u8]) -> String {
    let mut buf = [0u8; 64];
    let mut i = buf.len();
    loop {
        i -= 1;
        buf[i] = digits[(m & ((1 << bits) - 1)) as usize];
        m >>= bits;
        if m == 0 {
            break;
        }
    }
    String::from_utf8_lossy(&buf[i..]).into_owned()
}

fn sized_int(v: &Value, size: Size, signed: bool) -> Result<(bool, Mag), Exception> {
    let n = match v.as_num() {
        Some(n @ (Num::Int(_) | Num::Big(_))) => n,
        _ => return Err(number::int_error(v.as_str())),
    };
    let wide = n.wrap_i64().expect("an integer");
    Ok(match size {
        Size::Big => match n {
            Num::Int(i) => (i < 0, Mag::Small(i.unsigned_abs())),
            _ => {
                let b = n.to_bigint().expect("an integer");
                (b.sign() == Sign::Minus, Mag::Big(b.magnitude().clone()))
            }
        },
        Size::Wide if signed => (wide < 0, Mag::Small(wide.unsigned_abs())),
        Size::Wide => (false, Mag::Small(wide as u64)),
        Size::Short if signed => {
            ((wide as i16) < 0, Mag::Small((wide as i16).unsigned_abs() as u64))
        }
        Size::Short => (false, Mag::Small(wide as u16 as u64)),
    })
}

fn get_double(v: &Value) -> Result<f64, Exception> {
    v.as_f64()
}

/// `%e` with at least two exponent digits, as C prints it.
fn exp_form(x: f64, prec: usize, upper: bool) -> String {
    let s = format!("{:.*e}", prec, x);
    let (m, e) = s.split_once('e').expect("LowerExp writes an exponent");
    let e: i32 = e.parse().expect("decimal exponent");
    let out = format!("{m}e{}{:02}", if e < 0 { '-' } else { '+' }, e.abs());
    if upper { out.to_uppercase() } else { out }
}

fn g_form(x: f64, prec: usize, alt: bool, upper: bool) -> String {
    let p = if prec == 0 { 1 } else { prec };
    if x == 0.0 {
        return if alt { format!("{:.*}", p - 1, 0.0) } else { "0".into() };
    }
    let e_str = format!("{:.*e}", p - 1, x);
    let exp: i32 = e_str.split_once('e').map(|(_, e)| e.parse().unwrap_or(0)).unwrap_or(0);
    let mut s = if exp < -4 || exp >= p as i32 {
        exp_form(x, p - 1, upper)
    } else {
        format!("{:.*}", (p as i32 - 1 - exp).max(0) as usize, x)
    };
    if alt && !s.contains(['.', 'e', 'E']) {
        s.push('.');
    }
    if !alt {
        // Strip trailing zeros of the fraction.
        let (mant, tail) = match s.find(['e', 'E']) {
            Some(i) => (s[..i].to_string(), s[i..].to_string()),
            None => (s.clone(), String::new()),
        };
        let mant = if mant.contains('.') {
            mant.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            mant
        };
        s = mant + &tail;
    }
    s
}

fn float_body(conv: char, x: f64, spec: &Spec) -> String {
    if !x.is_finite() {
        let s = if x.is_nan() { "nan" } else { "inf" };
        let s = if conv.is_ascii_uppercase() { s.to_uppercase() } else { s.to_string() };
        return format!("{}{}", sign(spec, x.is_sign_negative() && !x.is_nan()), s);
    }
    let prec = spec.precision.unwrap_or(6);
    let neg = x.is_sign_negative() && x != 0.0 || (x == 0.0 && x.is_sign_negative());
    let a = x.abs();
    let body = match conv {
        'f' | 'F' => {
            let s = format!("{:.*}", prec, a);
            if spec.alt && prec == 0 { s + "." } else { s }
        }
        'e' | 'E' => {
            let s = exp_form(a, prec, conv == 'E');
            // `#` keeps the point even with no digits after it: `5.e+00`.
            match s.find(['e', 'E']) {
                Some(at) if spec.alt && prec == 0 => format!("{}.{}", &s[..at], &s[at..]),
                _ => s,
            }
        }
        'a' | 'A' => format!("{a:e}"),
        _ => g_form(a, prec, spec.alt, conv == 'G'),
    };
    format!("{}{}", sign(spec, neg), body)
}

pub fn format(fmt: &str, args: &[Value]) -> Result<String, Exception> {
    let mut out = String::new();
    let chars: Vec<char> = fmt.chars().collect();
    let mut i = 0;
    let mut next_arg = 0;
    let mut used_xpg = false;
    let mut used_plain = false;
    let not_enough = || Exception::error("not enough arguments for all format specifiers");
    while i < chars.len() {
        let c = chars[i];
        i += 1;
        if c != '%' {
            out.push(c);
            continue;
        }
        if i < chars.len() && chars[i] == '%' {
            out.push('%');
            i += 1;
            continue;
        }
        // XPG position: digits followed by '$'.
        let mut j = i;
        while j < chars.len() && chars[j].is_ascii_digit() {
            j += 1;
        }
        if j > i && j < chars.len() && chars[j] == '$' {
            let n: usize = digits_value(&chars[i..j]);
            if n == 0 || n > args.len() {
                return Err(Exception::error("\"%n$\" argument index out of range"));
            }
            next_arg = n - 1;
            used_xpg = true;
            i = j + 1;
        } else {
            used_plain = true;
        }
        if used_xpg && used_plain {
            return Err(Exception::error("cannot mix \"%\" and \"%n$\" conversion specifiers"));
        }
        let mut spec = Spec {
            minus: false,
            plus: false,
            space: false,
            zero: false,
            alt: false,
            width: 0,
            precision: None,
            size: Size::Wide,
        };
        while i < chars.len() {
            match chars[i] {
                '-' => spec.minus = true,
                '+' => spec.plus = true,
                ' ' => spec.space = true,
                '0' => spec.zero = true,
                '#' => spec.alt = true,
                _ => break,
            }
            i += 1;
        }
        let take_arg = |next_arg: &mut usize| -> Result<Value, Exception> {
            let v = args.get(*next_arg).cloned().ok_or_else(not_enough)?;
            *next_arg += 1;
            Ok(v)
        };
        if i < chars.len() && chars[i] == '*' {
            let w = get_int(&take_arg(&mut next_arg)?)?;
            if w < 0 {
                spec.minus = true;
            }
            spec.width = w.unsigned_abs() as usize;
            i += 1;
        } else {
            let s = i;
            while i < chars.len() && chars[i].is_ascii_digit() {
                i += 1;
            }
            spec.width = digits_value(&chars[s..i]);
        }
        if i < chars.len() && chars[i] == '.' {
            i += 1;
            if i < chars.len() && chars[i] == '*' {
                spec.precision = Some(get_int(&take_arg(&mut next_arg)?)?.max(0) as usize);
                i += 1;
            } else {
                let s = i;
                while i < chars.len() && chars[i].is_ascii_digit() {
                    i += 1;
                }
                spec.precision = Some(digits_value(&chars[s..i]));
            }
        }
        // Rust's formatter takes precisions up to 65535; more is no use.
        if spec.width > 1 << 20 || spec.precision.is_some_and(|p| p > u16::MAX as usize) {
            return Err(Exception::error("format width or precision too large"));
        }
        // Size modifiers.
        if i + 1 < chars.len() && chars[i] == 'l' && chars[i + 1] == 'l' {
            spec.size = Size::Big;
            i += 2;
        } else if i < chars.len() && matches!(chars[i], 'h' | 'l') {
            if chars[i] == 'h' {
                spec.size = Size::Short;
            }
            i += 1;
        }
        let Some(&conv) = chars.get(i) else {
            return Err(Exception::error("format string ended in middle of field specifier"));
        };
        i += 1;
        let piece = match conv {
            'd' | 'i' | 'u' | 'o' | 'x' | 'X' | 'b' => {
                let signed = matches!(conv, 'd' | 'i') || spec.size == Size::Big;
                let (neg, mag) = sized_int(&take_arg(&mut next_arg)?, spec.size, signed)?;
                let mut digits = mag.digits(conv);
                if let Some(p) = spec.precision {
                    while digits.len() < p {
                        digits.insert(0, '0');
                    }
                }
                // Tcl writes the prefix for zero too (`0x0`), except `0` for octal.
                let prefix = match (spec.alt && (!mag.is_zero() || conv != 'o'), conv) {
                    (true, 'o') => "0",
                    (true, 'x') => "0x",
                    (true, 'X') => "0X",
                    (true, 'b') => "0b",
                    _ => "",
                };
                let sign = if matches!(conv, 'd' | 'i') {
                    sign(&spec, neg)
                } else if neg {
                    "-"
                } else {
                    ""
                };
                // Tcl zero-pads an integer on the left even with `-`.
                let zero_left = spec.zero && spec.precision.is_none();
                let spec = Spec { minus: spec.minus && !zero_left, ..spec };
                let mut body = String::with_capacity(sign.len() + prefix.len() + digits.len());
                body.push_str(sign);
                body.push_str(prefix);
                body.push_str(&digits);
                pad(&spec, body, zero_left)
            }
            'c' => {
                let v = get_int(&take_arg(&mut next_arg)?)?;
                let ch = u32::try_from(v).ok().and_then(char::from_u32).unwrap_or('\u{fffd}');
                pad_text(&spec, ch.to_string())
            }
            's' => {
                let v = take_arg(&mut next_arg)?;
                let s: String = match spec.precision {
                    Some(p) => v.as_str().chars().take(p).collect(),
                    None => v.as_str().to_string(),
                };
                pad_text(&spec, s)
            }
            'f' | 'F' | 'e' | 'E' | 'g' | 'G' | 'a' | 'A' => {
                let x = get_double(&take_arg(&mut next_arg)?)?;
                pad(&spec, float_body(conv, x, &spec), x.is_finite())
            }
            other => return Err(Exception::error(format!("bad field specifier \"{other}\""))),
        };
        out.push_str(&piece);
        if out.len() > super::eval::MAX_VALUE_LEN {
            return Err(Exception::error("format result too long"));
        }
    }
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn f(fmt: &str, args: &[&str]) -> String {
        let v: Vec<Value> = args.iter().map(|s| Value::from(*s)).collect();
        format(fmt, &v).unwrap()
    }

    #[test]
    fn printf_like_c() {
        assert_eq!(
            f("%5.2f|%-5d|%05d|%x|%e|%c", &["3.14159", "42", "42", "255", "1234.5", "65"]),
            " 3.14|42   |00042|ff|1.234500e+03|A"
        );
        assert_eq!(f("%g %g %g", &["0.0001", "123456789", "100000"]), "0.0001 1.23457e+08 100000");
        assert_eq!(f("%#x %#o %+d % d", &["255", "8", "5", "5"]), "0xff 010 +5  5");
        assert_eq!(f("%2$s %1$s", &["a", "b"]), "b a");
        assert_eq!(f("%.3g|%G", &["1234.5", "1e-10"]), "1.23e+03|1E-10");
        assert_eq!(f("%x", &["-1"]), "ffffffffffffffff");
    }

    #[test]
    fn huge_precision_is_an_error_not_a_panic() {
        // Found by fuzzing: Rust's formatter panics past 65535 digits.
        let v = [Value::from("1.5")];
        assert!(format("%.70000f", &v).is_err());
        assert!(format("%.70000e", &v).is_err());
        assert_eq!(format("%.3f", &v).unwrap(), "1.500");
    }
}
