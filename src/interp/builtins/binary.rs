//! `binary format`, `binary scan`, `binary encode` and `binary decode`, as
//! Tcl 8.6 has them (after generic/tclBinary.c). A byte string is a string
//! whose characters are U+0000..U+00FF, one per byte; any other string
//! gives each character's low byte, as Tcl's byte arrays do.

use num_bigint::BigInt;

use super::{check_args, pick_subcommand};
use crate::interp::error::{Exception, TclResult};
use crate::interp::eval::Interp;
use crate::interp::number::Num;
use crate::interp::value::Value;

pub(super) const COMMANDS: &[super::Entry] = &[(
    "binary",
    cmd_binary,
    "subcommand ?arg ...?",
    "pack and unpack bytes: format, scan, encode, decode",
)];

/// A field's count: absent, `*`, or a number.
#[derive(Clone, Copy, PartialEq)]
enum Count {
    None,
    All,
    N(usize),
}

/// One field specifier: its letter, count and `u` (unsigned) flag.
struct Field {
    cmd: char,
    /// What a bad field is reported as: the first character after the
    /// previous field (a blank, if blanks came between), as Tcl does.
    shown: char,
    count: Count,
    unsigned: bool,
}

/// Splits a format string into fields as GetFormatSpec does: blanks
/// between fields, then a letter, an optional `u`, and `*` or digits.
fn fields(fmt: &str) -> Vec<Field> {
    let b: Vec<char> = fmt.chars().collect();
    let mut i = 0;
    let mut out = Vec::new();
    loop {
        let shown = b.get(i).copied().unwrap_or(' ');
        while i < b.len() && b[i] == ' ' {
            i += 1;
        }
        if i >= b.len() {
            return out;
        }
        let cmd = b[i];
        i += 1;
        let unsigned = b.get(i) == Some(&'u');
        if unsigned {
            i += 1;
        }
        let count = if b.get(i) == Some(&'*') {
            i += 1;
            Count::All
        } else if b.get(i).is_some_and(char::is_ascii_digit) {
            let s = i;
            while i < b.len() && b[i].is_ascii_digit() {
                i += 1;
            }
            let n: String = b[s..i].iter().collect();
            Count::N(n.parse().unwrap_or(i32::MAX as usize).min(i32::MAX as usize))
        } else {
            Count::None
        };
        out.push(Field { cmd, shown, count, unsigned });
    }
}

/// Where digit `k` of a `b B h H` field sits in its byte: binary digits
/// low bit first (`b`) or high first (`B`), hex digits low nibble first
/// (`h`) or high first (`H`).
fn digit_shift(cmd: char, k: usize) -> usize {
    match cmd {
        'b' => k % 8,
        'B' => 7 - k % 8,
        'h' => (k % 2) * 4,
        _ => (1 - k % 2) * 4,
    }
}

/// The byte size of a numeric field letter.
fn number_size(cmd: char) -> Option<usize> {
    Some(match cmd {
        'c' => 1,
        't' | 's' | 'S' => 2,
        'n' | 'i' | 'I' | 'r' | 'R' | 'f' => 4,
        'm' | 'w' | 'W' | 'q' | 'Q' | 'd' => 8,
        _ => return None,
    })
}

/// Whether a numeric field is little-endian (this machine's order for the
/// native ones, as on x86 and ARM).
fn little_endian(cmd: char) -> bool {
    !matches!(cmd, 'S' | 'I' | 'W' | 'R' | 'Q')
}

/// The bytes of a value: each character's low byte.
pub(crate) fn bytes_of(v: &Value) -> Vec<u8> {
    let s = v.as_str();
    if s.is_ascii() {
        return s.as_bytes().to_vec();
    }
    s.chars().map(|c| c as u32 as u8).collect()
}

/// A byte string as a value: one character per byte.
pub(crate) fn value_of(bytes: &[u8]) -> Value {
    Value::from_string(bytes.iter().map(|&b| b as char).collect())
}

fn bad_field(c: char) -> Exception {
    Exception::error(format!("bad field specifier \"{c}\""))
}

fn not_enough() -> Exception {
    Exception::error("not enough arguments for all format specifiers")
}

fn missing_at_count() -> Exception {
    Exception::error("missing count for \"@\" field specifier")
}

/// An integer for a field: any integer that fits 64 bits unsigned, cut to
/// the field's width as C's casts do.
fn field_int(v: &Value) -> Result<i64, Exception> {
    match v.as_num() {
        Some(Num::Int(i)) => Ok(i),
        Some(Num::Big(b)) if b.bits() <= 64 => Ok(crate::interp::number::wrap_big(&b)),
        Some(Num::Big(_)) => Err(Exception::error("integer value too large to represent")),
        _ => Err(crate::interp::number::int_error(v.as_str())),
    }
}

fn field_double(v: &Value) -> Result<f64, Exception> {
    v.as_f64()
}

fn put_number(out: &mut Vec<u8>, at: &mut usize, cmd: char, v: &Value) -> Result<(), Exception> {
    let size = number_size(cmd).expect("a numeric field");
    let mut bytes: Vec<u8> = match cmd {
        'd' | 'q' | 'Q' => field_double(v)?.to_le_bytes().to_vec(),
        'f' | 'r' | 'R' => {
            let d = field_double(v)?;
            let f = if d.abs() > f32::MAX as f64 && d.is_finite() {
                f32::MAX.copysign(d as f32)
            } else {
                d as f32
            };
            f.to_le_bytes().to_vec()
        }
        _ => field_int(v)?.to_le_bytes()[..size].to_vec(),
    };
    if !little_endian(cmd) {
        bytes.reverse();
    }
    write_at(out, *at, &bytes);
    *at += size;
    Ok(())
}

fn write_at(out: &mut Vec<u8>, at: usize, bytes: &[u8]) {
    if out.len() < at + bytes.len() {
        out.resize(at + bytes.len(), 0);
    }
    out[at..at + bytes.len()].copy_from_slice(bytes);
}

/// The most bytes `binary format` may make.
const MAX_BYTES: usize = crate::interp::MAX_VALUE_LEN;

fn format(args: &[Value]) -> TclResult {
    let mut out: Vec<u8> = Vec::new();
    let mut at = 0usize;
    let mut arg = 0;
    let next = |arg: &mut usize| -> Result<Value, Exception> {
        let v = args.get(*arg).cloned().ok_or_else(not_enough);
        *arg += 1;
        v
    };
    let fmt = next(&mut arg)?;
    for f in fields(fmt.as_str()) {
        // The result may reach `n` bytes: within the cap, and within the
        // memory budget for the piece, the buffer and the string made of
        // it (checked before any of them is made).
        let grow = |n: usize| {
            if n > MAX_BYTES {
                Err(Exception::error("binary format result too long"))
            } else {
                crate::mem::reserve_n(n.saturating_sub(out.len()), 3)?;
                Ok(n)
            }
        };
        match f.cmd {
            'a' | 'A' => {
                let v = bytes_of(&next(&mut arg)?);
                let n = match f.count {
                    Count::All => v.len(),
                    Count::None => 1,
                    Count::N(n) => grow(at + n)? - at,
                };
                let pad = if f.cmd == 'a' { 0 } else { b' ' };
                let mut piece = vec![pad; n];
                let k = v.len().min(n);
                piece[..k].copy_from_slice(&v[..k]);
                write_at(&mut out, at, &piece);
                at += n;
            }
            'b' | 'B' | 'h' | 'H' => {
                let v = next(&mut arg)?;
                let s: Vec<char> = v.as_str().chars().collect();
                let n = match f.count {
                    Count::All => s.len(),
                    Count::None => 1,
                    Count::N(n) => n,
                };
                let per = if matches!(f.cmd, 'b' | 'B') { 8 } else { 2 };
                let len = grow(n.div_ceil(per))?;
                let mut piece = vec![0u8; len];
                let (kind, base) = if per == 8 { ("binary", 2) } else { ("hexadecimal", 16) };
                for (k, c) in s.iter().take(n).enumerate() {
                    let d = c.to_digit(base).ok_or_else(|| {
                        Exception::error(format!(
                            "expected {kind} string but got \"{}\" instead",
                            v.as_str()
                        ))
                    })? as u8;
                    let shift = digit_shift(f.cmd, k);
                    piece[k / per] |= d << shift;
                }
                write_at(&mut out, at, &piece);
                at += len;
            }
            'x' => {
                let n = match f.count {
                    Count::All => {
                        return Err(Exception::error(
                            "cannot use \"*\" in format string with \"x\"",
                        ));
                    }
                    Count::None => 1,
                    Count::N(n) => grow(at + n)? - at,
                };
                write_at(&mut out, at, &vec![0; n]);
                at += n;
            }
            'X' => {
                // Back, never before the start (`binary format X` is "").
                let n = match f.count {
                    Count::None => 1.min(at),
                    Count::All => at,
                    Count::N(n) => n.min(at),
                };
                at -= n;
            }
            '@' => {
                at = match f.count {
                    Count::None => return Err(missing_at_count()),
                    Count::All => out.len(),
                    Count::N(n) => grow(n)?,
                };
                if out.len() < at {
                    out.resize(at, 0);
                }
            }
            c if number_size(c).is_some() => {
                let v = next(&mut arg)?;
                match f.count {
                    Count::None => put_number(&mut out, &mut at, c, &v)?,
                    count => {
                        let items = v.as_list()?;
                        let n = match count {
                            Count::N(n) if n > items.len() => {
                                return Err(Exception::error(
                                    "number of elements in list does not match count",
                                ));
                            }
                            Count::N(n) => n,
                            _ => items.len(),
                        };
                        for item in &items[..n] {
                            put_number(&mut out, &mut at, c, item)?;
                        }
                    }
                }
            }
            _ => return Err(bad_field(f.shown)),
        }
    }
    Ok(value_of(&out))
}

fn scan_number(bytes: &[u8], cmd: char, unsigned: bool) -> Value {
    // The field's bytes, little-endian, in the low end of a word (no
    // allocation: `binary scan $s c*` makes one value per byte).
    let n = bytes.len().min(8);
    let mut wide = [0u8; 8];
    wide[..n].copy_from_slice(&bytes[..n]);
    if !little_endian(cmd) {
        wide[..n].reverse();
    }
    match cmd {
        'd' | 'q' | 'Q' => Value::from_f64(f64::from_le_bytes(wide)),
        'f' | 'r' | 'R' => {
            let [a, b, c, d, ..] = wide;
            Value::from_f64(f32::from_le_bytes([a, b, c, d]) as f64)
        }
        _ => {
            let raw = u64::from_le_bytes(wide);
            let bits = 8 * n as u32;
            if unsigned {
                if bits == 64 && raw > i64::MAX as u64 {
                    Value::from_num(Num::from_big(BigInt::from(raw)))
                } else {
                    Value::from_int(raw as i64)
                }
            } else {
                // Sign-extend from the field's width.
                let shift = 64 - bits;
                Value::from_int(((raw << shift) as i64) >> shift)
            }
        }
    }
}

fn scan(interp: &mut Interp, args: &[Value]) -> TclResult {
    let data = bytes_of(&args[0]);
    let len = data.len();
    let mut at = 0usize;
    let mut arg = 2;
    for f in fields(args[1].as_str()) {
        let need_var =
            matches!(f.cmd, 'a' | 'A' | 'b' | 'B' | 'h' | 'H') || number_size(f.cmd).is_some();
        if need_var && arg >= args.len() {
            return Err(not_enough());
        }
        let left = len.saturating_sub(at);
        let value = match f.cmd {
            'a' | 'A' => {
                let n = match f.count {
                    Count::All => left,
                    Count::None => 1,
                    Count::N(n) => n,
                };
                if n > left {
                    break;
                }
                let mut piece = &data[at..at + n];
                if f.cmd == 'A' {
                    while let [rest @ .., 0 | b' '] = piece {
                        piece = rest;
                    }
                }
                at += n;
                value_of(piece)
            }
            'b' | 'B' | 'h' | 'H' => {
                let per = if matches!(f.cmd, 'b' | 'B') { 8 } else { 2 };
                let n = match f.count {
                    Count::All => left * per,
                    Count::None => 1,
                    Count::N(n) => n,
                };
                if n > left * per {
                    break;
                }
                let bits = 8 / per;
                let s: String = (0..n)
                    .map(|k| {
                        let byte = data[at + k / per];
                        let shift = digit_shift(f.cmd, k);
                        let d = (byte >> shift) & ((1u8 << bits) - 1);
                        char::from_digit(d as u32, 16).expect("a digit")
                    })
                    .collect();
                at += n.div_ceil(per);
                Value::from_string(s)
            }
            'x' => {
                at = match f.count {
                    Count::None => (at + 1).min(len),
                    Count::All => len,
                    Count::N(n) => at.saturating_add(n).min(len),
                };
                continue;
            }
            'X' => {
                at = match f.count {
                    Count::None => at.saturating_sub(1),
                    Count::All => 0,
                    Count::N(n) => at.saturating_sub(n),
                };
                continue;
            }
            '@' => {
                at = match f.count {
                    Count::None => return Err(missing_at_count()),
                    Count::All => len,
                    Count::N(n) => n.min(len),
                };
                continue;
            }
            c if number_size(c).is_some() => {
                let size = number_size(c).expect("numeric");
                match f.count {
                    Count::None => {
                        if left < size {
                            break;
                        }
                        let v = scan_number(&data[at..at + size], c, f.unsigned);
                        at += size;
                        v
                    }
                    count => {
                        let n = match count {
                            Count::All => left / size,
                            Count::N(n) => n,
                            Count::None => unreachable!("handled above"),
                        };
                        if n.checked_mul(size).is_none_or(|b| b > left) {
                            break;
                        }
                        let items = (0..n)
                            .map(|k| {
                                let s = at + k * size;
                                scan_number(&data[s..s + size], c, f.unsigned)
                            })
                            .collect();
                        at += n * size;
                        Value::from_list(items)
                    }
                }
            }
            _ => return Err(bad_field(f.shown)),
        };
        interp.set_var(args[arg].as_str(), value)?;
        arg += 1;
    }
    Ok(Value::from_int(arg as i64 - 2))
}

const B64: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";

fn encode(kind: &str, args: &[Value]) -> TclResult {
    let usage = format!("binary encode {kind} ?-maxlen len? ?-wrapchar char? data");
    let Some((data, opts)) = args.split_last() else {
        return Err(Exception::wrong_args(&usage));
    };
    let data = bytes_of(data);
    let mut maxlen = 0usize;
    let mut wrap = "\n".to_string();
    if kind == "hex" && !opts.is_empty() {
        return Err(Exception::wrong_args("binary encode hex data"));
    }
    if opts.len() % 2 != 0 {
        return Err(Exception::wrong_args(&usage));
    }
    for pair in opts.chunks(2) {
        let opt = super::pick_option(pair[0].as_str(), &["-maxlen", "-wrapchar"], "option")?;
        if opt == "-maxlen" {
            let n = pair[1].as_int()?;
            if n < 0 {
                return Err(Exception::error("line length out of range"));
            }
            maxlen = n as usize;
        } else {
            wrap = pair[1].as_str().to_string();
        }
    }
    // The text, and (wrapped) its lines and their join: asked of the
    // budget before they are made.
    let len = if kind == "hex" { data.len() * 2 } else { data.len().div_ceil(3) * 4 };
    let wraps = len.checked_div(maxlen).unwrap_or(0) * wrap.len();
    crate::mem::reserve_n(len + wraps, if maxlen == 0 { 1 } else { 7 })?;
    let body: String = match kind {
        "hex" => {
            const DIGITS: &[u8; 16] = b"0123456789abcdef";
            let mut s = String::with_capacity(len);
            for &b in data.iter() {
                s.push(DIGITS[(b >> 4) as usize] as char);
                s.push(DIGITS[(b & 15) as usize] as char);
            }
            s
        }
        _ => {
            let mut s = String::with_capacity(data.len().div_ceil(3) * 4);
            for chunk in data.chunks(3) {
                let n = chunk
                    .iter()
                    .enumerate()
                    .fold(0u32, |n, (k, &b)| n | (b as u32) << (16 - 8 * k));
                for k in 0..4 {
                    if k <= chunk.len() {
                        s.push(B64[(n >> (18 - 6 * k) & 63) as usize] as char);
                    } else {
                        s.push('=');
                    }
                }
            }
            s
        }
    };
    if maxlen == 0 || wrap.is_empty() {
        return Ok(Value::from_string(body));
    }
    // The text is ASCII: lines are byte ranges.
    let mut out = String::with_capacity(len + wraps);
    for (k, line) in body.as_bytes().chunks(maxlen).enumerate() {
        if k > 0 {
            out.push_str(&wrap);
        }
        out.push_str(std::str::from_utf8(line).unwrap_or_default());
    }
    Ok(Value::from_string(out))
}

fn decode(kind: &str, args: &[Value]) -> TclResult {
    let usage = format!("binary decode {kind} ?-strict? data");
    let (data, opts) = match args {
        [d] => (d, false),
        [o, d] => {
            super::pick_option(o.as_str(), &["-strict"], "option")?;
            (d, true)
        }
        _ => return Err(Exception::wrong_args(&usage)),
    };
    let strict = opts;
    let s: Vec<char> = data.as_str().chars().collect();
    let invalid = |c: char, at: usize| {
        let what = if kind == "hex" { "hexadecimal digit" } else { "base64 character" };
        Exception::error(format!("invalid {what} \"{c}\" at position {at}"))
            .with_error_code("TCL BINARY DECODE INVALID")
    };
    let mut out = Vec::new();
    if kind == "hex" {
        let mut digits = Vec::new();
        for (at, &c) in s.iter().enumerate() {
            match c.to_digit(16) {
                Some(d) => digits.push(d as u8),
                None if !strict && c.is_whitespace() => {}
                None => return Err(invalid(c, at)),
            }
        }
        if digits.len() % 2 == 1 {
            if strict {
                return Err(Exception::error("incomplete hexadecimal string")
                    .with_error_code("TCL BINARY DECODE INVALID"));
            }
            digits.push(0);
            for pair in digits.chunks(2) {
                out.push(pair[0] << 4 | pair[1]);
            }
            out.pop();
            return Ok(value_of(&out));
        }
        for pair in digits.chunks(2) {
            out.push(pair[0] << 4 | pair[1]);
        }
        return Ok(value_of(&out));
    }
    let mut acc = 0u32;
    let mut n = 0;
    let mut pad = 0;
    for (at, &c) in s.iter().enumerate() {
        let d = match c {
            'A'..='Z' => c as u32 - 'A' as u32,
            'a'..='z' => c as u32 - 'a' as u32 + 26,
            '0'..='9' => c as u32 - '0' as u32 + 52,
            '+' => 62,
            '/' => 63,
            '=' => {
                pad += 1;
                continue;
            }
            c if !strict && c.is_whitespace() => continue,
            c => return Err(invalid(c, at)),
        };
        if pad > 0 {
            return Err(invalid(c, at));
        }
        acc = acc << 6 | d;
        n += 1;
        if n == 4 {
            out.extend_from_slice(&[(acc >> 16) as u8, (acc >> 8) as u8, acc as u8]);
            acc = 0;
            n = 0;
        }
    }
    match n {
        0 => {}
        2 => out.push((acc >> 4) as u8),
        3 => out.extend_from_slice(&[(acc >> 10) as u8, (acc >> 2) as u8]),
        _ if strict => {
            return Err(Exception::error("invalid base64 character \"\" at position 0")
                .with_error_code("TCL BINARY DECODE INVALID"));
        }
        _ => {}
    }
    Ok(value_of(&out))
}

fn cmd_binary(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "subcommand ?arg ...?")?;
    let sub = pick_subcommand(argv[1].as_str(), &["decode", "encode", "format", "scan"])?;
    let a = &argv[2..];
    match sub {
        "format" => {
            if a.is_empty() {
                return Err(Exception::wrong_args("binary format formatString ?arg ...?"));
            }
            format(a)
        }
        "scan" => {
            if a.len() < 2 {
                return Err(Exception::wrong_args("binary scan value formatString ?varName ...?"));
            }
            scan(interp, a)
        }
        _ => {
            let Some(kind) = a.first() else {
                return Err(Exception::wrong_args(&format!("binary {sub} subcommand ?arg ...?")));
            };
            let kind = pick_subcommand(kind.as_str(), &["base64", "hex"])?;
            if sub == "encode" { encode(kind, &a[1..]) } else { decode(kind, &a[1..]) }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fields_parse_like_tcl() {
        let f = fields("a* c3 Su x @5");
        let got: Vec<(char, bool)> = f.iter().map(|f| (f.cmd, f.unsigned)).collect();
        assert_eq!(got, [('a', false), ('c', false), ('S', true), ('x', false), ('@', false)]);
        assert!(f[0].count == Count::All && f[1].count == Count::N(3));
        assert!(f[3].count == Count::None);
    }

    #[test]
    fn numbers_round_trip() {
        let v = scan_number(&[0xff, 0xff], 's', false);
        assert_eq!(v.as_str(), "-1");
        let v = scan_number(&[0xff, 0xff], 's', true);
        assert_eq!(v.as_str(), "65535");
        let v = scan_number(&[0, 0, 0, 1], 'I', false);
        assert_eq!(v.as_str(), "1");
    }
}
