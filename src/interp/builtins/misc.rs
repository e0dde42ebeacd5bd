//! Small commands of Tcl 8.6: `clock` (seconds, milliseconds,
//! microseconds, clicks, format), `after ms`, `tailcall`, `parray`, and
//! `encoding` (utf-8, iso8859-1, ascii, binary).

use std::time::{SystemTime, UNIX_EPOCH};

use super::{check_args, pick_subcommand};
use crate::interp::error::{Code, Exception, TclResult};
use crate::interp::eval::Interp;
use crate::interp::value::Value;

pub(super) const COMMANDS: &[super::Entry] = &[
    ("clock", cmd_clock, "subcommand ?arg ...?", "the time: seconds, milliseconds, format..."),
    ("after", cmd_after, "ms", "wait ms milliseconds"),
    ("tailcall", cmd_tailcall, "command ?arg ...?", "replace this proc's call by a command's"),
    ("parray", cmd_parray, "arrayName ?pattern?", "print an array's elements"),
    ("encoding", cmd_encoding, "subcommand ?arg ...?", "convert between strings and bytes"),
];

fn since_epoch() -> std::time::Duration {
    SystemTime::now().duration_since(UNIX_EPOCH).unwrap_or_default()
}

const DAYS: [&str; 7] =
    ["Sunday", "Monday", "Tuesday", "Wednesday", "Thursday", "Friday", "Saturday"];
const MONTHS: [&str; 12] = [
    "January",
    "February",
    "March",
    "April",
    "May",
    "June",
    "July",
    "August",
    "September",
    "October",
    "November",
    "December",
];

/// (year, month 1-12, day 1-31) of a day count since 1970-01-01
/// (Howard Hinnant's civil-from-days).
fn civil(days: i64) -> (i64, u32, u32) {
    let z = days + 719_468;
    let era = z.div_euclid(146_097);
    let doe = z.rem_euclid(146_097);
    let yoe = (doe - doe / 1460 + doe / 36_524 - doe / 146_096) / 365;
    let doy = doe - (365 * yoe + yoe / 4 - yoe / 100);
    let mp = (5 * doy + 2) / 153;
    let d = (doy - (153 * mp + 2) / 5 + 1) as u32;
    let m = if mp < 10 { mp + 3 } else { mp - 9 } as u32;
    (yoe + era * 400 + (m <= 2) as i64, m, d)
}

/// `clock format` in UTC with the common `%` codes (the zone is called
/// GMT with `-gmt 1`, as Tcl calls it, else UTC).
fn format_time(secs: i64, fmt: &str, gmt: bool) -> String {
    let days = secs.div_euclid(86_400);
    let rem = secs.rem_euclid(86_400);
    let (y, mo, d) = civil(days);
    let (h, mi, s) = (rem / 3600, rem / 60 % 60, rem % 60);
    let wday = (days + 4).rem_euclid(7) as usize;
    let yday = days - {
        let mut k = days;
        while civil(k - 1).0 == y {
            k -= 1;
        }
        k
    } + 1;
    let mut out = String::new();
    let mut it = fmt.chars();
    while let Some(c) = it.next() {
        if c != '%' {
            out.push(c);
            continue;
        }
        let Some(k) = it.next() else {
            out.push('%');
            break;
        };
        let piece = match k {
            'Y' => y.to_string(),
            'C' => format!("{:02}", y / 100),
            'y' => format!("{:02}", y.rem_euclid(100)),
            'm' => format!("{mo:02}"),
            'd' => format!("{d:02}"),
            'e' => format!("{d:2}"),
            'H' => format!("{h:02}"),
            'I' => format!("{:02}", if h % 12 == 0 { 12 } else { h % 12 }),
            'M' => format!("{mi:02}"),
            'S' => format!("{s:02}"),
            'p' => (if h < 12 { "AM" } else { "PM" }).to_string(),
            'j' => format!("{yday:03}"),
            'a' => DAYS[wday][..3].to_string(),
            'A' => DAYS[wday].to_string(),
            'b' | 'h' => MONTHS[mo as usize - 1][..3].to_string(),
            'B' => MONTHS[mo as usize - 1].to_string(),
            'u' => (if wday == 0 { 7 } else { wday }).to_string(),
            'w' => wday.to_string(),
            's' => secs.to_string(),
            'Z' => (if gmt { "GMT" } else { "UTC" }).to_string(),
            'z' => "+0000".to_string(),
            'T' => format!("{h:02}:{mi:02}:{s:02}"),
            'R' => format!("{h:02}:{mi:02}"),
            'D' => format!("{mo:02}/{d:02}/{y}"),
            'n' => "\n".to_string(),
            't' => "\t".to_string(),
            '%' => "%".to_string(),
            other => format!("%{other}"),
        };
        out.push_str(&piece);
    }
    out
}

fn cmd_clock(_: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "subcommand ?arg ...?")?;
    let subs = ["clicks", "format", "microseconds", "milliseconds", "seconds"];
    let sub = pick_subcommand(argv[1].as_str(), &subs)?;
    let t = since_epoch();
    Ok(match sub {
        "seconds" => Value::from_int(t.as_secs() as i64),
        "milliseconds" => Value::from_int(t.as_millis() as i64),
        "microseconds" => Value::from_int(t.as_micros() as i64),
        "clicks" => match argv.get(2).map(|v| v.as_str()) {
            Some("-milliseconds") => Value::from_int(t.as_millis() as i64),
            None | Some("-microseconds") => Value::from_int(t.as_micros() as i64),
            Some(o) => {
                return Err(Exception::error(format!(
                    "bad option \"{o}\": must be -milliseconds or -microseconds"
                )));
            }
        },
        _ => {
            let Some(secs) = argv.get(2) else {
                return Err(Exception::wrong_args(
                    "clock format clockval ?-format string? ?-gmt boolean?",
                ));
            };
            let secs = secs.as_int()?;
            let mut fmt = "%a %b %d %H:%M:%S %Z %Y".to_string();
            let mut gmt = false;
            for kv in argv[3..].chunks(2) {
                match (kv[0].as_str(), kv.get(1)) {
                    ("-format", Some(f)) => fmt = f.as_str().to_string(),
                    ("-gmt", Some(g)) => gmt = g.as_bool()?,
                    ("-timezone", Some(_)) | ("-locale", Some(_)) => {}
                    (o, _) => {
                        return Err(Exception::error(format!(
                            "bad option \"{o}\": must be -format, -gmt, -locale, or -timezone"
                        )));
                    }
                }
            }
            Value::from_string(format_time(secs, &fmt, gmt))
        }
    })
}

fn cmd_after(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 2, "ms")?;
    let ms = argv[1].as_int()?;
    interp.flush();
    // Waits in slices, so Ctrl-C stops a long wait.
    let end = std::time::Instant::now() + std::time::Duration::from_millis(ms.max(0) as u64);
    while std::time::Instant::now() < end {
        interp.enter()?;
        interp.leave();
        let left = end.saturating_duration_since(std::time::Instant::now());
        std::thread::sleep(left.min(std::time::Duration::from_millis(50)));
    }
    Ok(Value::empty())
}

fn cmd_tailcall(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "command ?arg ...?")?;
    if interp.level() == 0 {
        return Err(Exception::error("tailcall can only be called from a proc, lambda or method"));
    }
    interp.tailcall = Some(argv[1..].to_vec());
    let mut e = Exception::flow(Code::Return, Value::empty());
    e.level = 1;
    Err(e)
}

fn cmd_parray(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 3, "arrayName ?pattern?")?;
    let name = argv[1].as_str();
    let mut words = vec![Value::from("array"), Value::from("names"), argv[1].clone()];
    words.extend(argv.get(2).cloned());
    let names = interp.invoke(&[Value::from("array"), Value::from("exists"), argv[1].clone()])?;
    if !names.as_bool()? {
        return Err(Exception::error(format!("\"{name}\" isn't an array")));
    }
    let mut keys: Vec<String> =
        interp.invoke(&words)?.as_list()?.iter().map(|k| k.as_str().to_string()).collect();
    keys.sort();
    let width = keys.iter().map(|k| name.chars().count() + k.chars().count() + 2).max();
    let mut out = String::new();
    for k in &keys {
        let label = format!("{name}({k})");
        let v = interp.get_var(&label)?;
        out.push_str(&format!("{label:<w$} = {}\n", v.as_str(), w = width.unwrap_or(0)));
    }
    interp.write_stdout(&out)?;
    Ok(Value::empty())
}

fn cmd_encoding(_: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "subcommand ?arg ...?")?;
    let sub = pick_subcommand(argv[1].as_str(), &["convertfrom", "convertto", "names", "system"])?;
    let known = ["ascii", "binary", "identity", "iso8859-1", "utf-8"];
    match sub {
        "names" => Ok(Value::from_list(known.iter().map(|n| Value::from(*n)).collect())),
        "system" => Ok(Value::from("utf-8")),
        _ => {
            let (enc, data) = match &argv[2..] {
                [d] => ("utf-8", d),
                [e, d] => (e.as_str(), d),
                _ => {
                    return Err(Exception::wrong_args(&format!("encoding {sub} ?encoding? data")));
                }
            };
            let enc = match enc.to_ascii_lowercase().as_str() {
                "utf-8" | "utf8" => "utf-8",
                "iso8859-1" | "binary" | "identity" | "latin1" => "iso8859-1",
                "ascii" => "ascii",
                _ => return Err(Exception::error(format!("unknown encoding \"{enc}\""))),
            };
            let s = data.as_str();
            Ok(Value::from_string(match (sub, enc) {
                ("convertto", "utf-8") => s.bytes().map(|b| b as char).collect(),
                ("convertto", "ascii") => {
                    s.chars().map(|c| if c.is_ascii() { c } else { '?' }).collect()
                }
                ("convertto", _) => {
                    s.chars().map(|c| if (c as u32) < 256 { c } else { '?' }).collect()
                }
                ("convertfrom", "utf-8") => {
                    let bytes: Vec<u8> = s.chars().map(|c| c as u32 as u8).collect();
                    String::from_utf8_lossy(&bytes).into_owned()
                }
                _ => s.chars().map(|c| (c as u32 as u8) as char).collect(),
            }))
        }
    }
}
