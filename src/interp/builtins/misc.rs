//! Small commands of Tcl 8.6: `clock` (seconds, milliseconds,
//! microseconds, clicks, format, scan, add; in UTC), `after ms`, `tailcall`, `parray`, and
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

/// Days since 1970-01-01 of a (year, month 1-12, day) (Hinnant's
/// days-from-civil).
fn days_from_civil(y: i64, m: u32, d: u32) -> i64 {
    let y = if m <= 2 { y - 1 } else { y };
    let era = y.div_euclid(400);
    let yoe = y.rem_euclid(400);
    let mp = (m as i64 + 9) % 12;
    let doy = (153 * mp + 2) / 5 + d as i64 - 1;
    let doe = yoe * 365 + yoe / 4 - yoe / 100 + doy;
    era * 146_097 + doe - 719_468
}

fn month_len(y: i64, m: u32) -> u32 {
    match m {
        2 if (y % 4 == 0 && y % 100 != 0) || y % 400 == 0 => 29,
        2 => 28,
        4 | 6 | 9 | 11 => 30,
        _ => 31,
    }
}

/// The fields a scan found; what it did not find comes from the base time.
#[derive(Default)]
struct Scanned {
    year: Option<i64>,
    month: Option<u32>,
    day: Option<u32>,
    yday: Option<i64>,
    hour: Option<i64>,
    minute: i64,
    second: i64,
    pm: Option<bool>,
    epoch: Option<i64>,
}

impl Scanned {
    fn seconds(&self, base: i64) -> Result<i64, Exception> {
        if let Some(e) = self.epoch {
            return Ok(e);
        }
        let base_days = base.div_euclid(86_400);
        let (by, bm, bd) = civil(base_days);
        let has_date = self.year.is_some() || self.month.is_some() || self.day.is_some();
        let year = self.year.unwrap_or(by);
        let days = if let Some(j) = self.yday {
            days_from_civil(year, 1, 1) + j - 1
        } else if has_date || self.hour.is_some() {
            let (m, d) = (self.month.unwrap_or(if has_date { 1 } else { bm }), self.day);
            let d = d.unwrap_or(if has_date && self.month.is_some() { 1 } else { bd });
            if !(1..=12).contains(&m) || d < 1 || d > month_len(year, m) {
                return Err(Exception::error("unable to convert input string: invalid date"));
            }
            days_from_civil(year, m, d)
        } else {
            base_days
        };
        let mut h = self.hour.unwrap_or(0);
        match self.pm {
            Some(true) if h < 12 => h += 12,
            Some(false) if h == 12 => h = 0,
            _ => {}
        }
        Ok(days * 86_400 + h * 3600 + self.minute * 60 + self.second)
    }
}

/// Reads up to `max` digits (an optional sign with `signed`).
fn scan_num(s: &[u8], i: &mut usize, max: usize, signed: bool) -> Option<i64> {
    let start = *i;
    if signed && *i < s.len() && (s[*i] == b'-' || s[*i] == b'+') {
        *i += 1;
    }
    let digits = *i;
    while *i < s.len() && *i - digits < max && s[*i].is_ascii_digit() {
        *i += 1;
    }
    if *i == digits {
        *i = start;
        return None;
    }
    std::str::from_utf8(&s[start..*i]).ok()?.parse().ok()
}

/// A month or day name, full or in three letters, any case.
fn scan_name(s: &[u8], i: &mut usize, names: &[&str]) -> Option<usize> {
    let rest = std::str::from_utf8(&s[*i..]).ok()?.to_ascii_lowercase();
    for (k, n) in names.iter().enumerate() {
        let n = n.to_ascii_lowercase();
        for cand in [n.as_str(), &n[..3]] {
            if rest.starts_with(cand) {
                *i += cand.len();
                return Some(k);
            }
        }
    }
    None
}

/// `clock scan -format`: the fields of `input` as `fmt` lays them out.
fn scan_format(input: &str, fmt: &str) -> Result<Scanned, Exception> {
    let bad = || Exception::error("input string does not match supplied format");
    let s = input.as_bytes();
    let mut i = 0;
    let mut out = Scanned::default();
    let mut f = fmt.chars().peekable();
    while let Some(c) = f.next() {
        if c.is_whitespace() {
            while i < s.len() && s[i].is_ascii_whitespace() {
                i += 1;
            }
            continue;
        }
        if c != '%' {
            let mut buf = [0u8; 4];
            let lit = c.encode_utf8(&mut buf).as_bytes();
            if !s[i..].starts_with(lit) {
                return Err(bad());
            }
            i += lit.len();
            continue;
        }
        let k = f.next().ok_or_else(bad)?;
        let num = |i: &mut usize, max: usize| scan_num(s, i, max, false).ok_or_else(bad);
        match k {
            'Y' => out.year = Some(num(&mut i, 4)?),
            'y' => {
                let y = num(&mut i, 2)?;
                out.year = Some(if y < 38 { 2000 + y } else { 1900 + y });
            }
            'C' => {
                let c = num(&mut i, 2)?;
                out.year = Some(c * 100 + out.year.unwrap_or(0) % 100);
            }
            'm' => out.month = Some(num(&mut i, 2)? as u32),
            'd' | 'e' => {
                while i < s.len() && s[i] == b' ' {
                    i += 1;
                }
                out.day = Some(num(&mut i, 2)? as u32);
            }
            'j' => out.yday = Some(num(&mut i, 3)?),
            'H' | 'k' => out.hour = Some(num(&mut i, 2)?),
            'I' | 'l' => out.hour = Some(num(&mut i, 2)? % 12),
            'M' => out.minute = num(&mut i, 2)?,
            'S' => out.second = num(&mut i, 2)?,
            's' => out.epoch = Some(scan_num(s, &mut i, 20, true).ok_or_else(bad)?),
            'p' | 'P' => {
                let rest = input[i..].to_ascii_lowercase();
                if rest.starts_with("am") {
                    out.pm = Some(false);
                } else if rest.starts_with("pm") {
                    out.pm = Some(true);
                } else {
                    return Err(bad());
                }
                i += 2;
            }
            'b' | 'B' | 'h' => {
                out.month = Some(scan_name(s, &mut i, &MONTHS).ok_or_else(bad)? as u32 + 1)
            }
            'a' | 'A' => {
                scan_name(s, &mut i, &DAYS).ok_or_else(bad)?;
            }
            'T' => return scan_format_rest(input, i, "%H:%M:%S", f.collect(), out),
            'R' => return scan_format_rest(input, i, "%H:%M", f.collect(), out),
            'D' => return scan_format_rest(input, i, "%m/%d/%y", f.collect(), out),
            'Z' => {
                let rest = &input[i..];
                let n = rest.find(|c: char| !c.is_ascii_alphanumeric()).unwrap_or(rest.len());
                if !matches!(&rest[..n], "UTC" | "GMT" | "Z" | "UCT") {
                    return Err(Exception::error(format!(
                        "rayshell's clock knows only UTC, not time zone \"{}\"",
                        &rest[..n]
                    )));
                }
                i += n;
            }
            '%' => {
                if s.get(i) != Some(&b'%') {
                    return Err(bad());
                }
                i += 1;
            }
            _ => return Err(bad()),
        }
    }
    while i < s.len() && s[i].is_ascii_whitespace() {
        i += 1;
    }
    if i != s.len() {
        return Err(bad());
    }
    Ok(out)
}

/// A compound group (`%T`): its expansion, then the rest of the format.
fn scan_format_rest(
    input: &str,
    at: usize,
    group: &str,
    rest: String,
    before: Scanned,
) -> Result<Scanned, Exception> {
    let mut got = scan_format(&input[at..], &format!("{group}{rest}"))?;
    got.year = got.year.or(before.year);
    got.month = got.month.or(before.month);
    got.day = got.day.or(before.day);
    got.yday = got.yday.or(before.yday);
    got.hour = got.hour.or(before.hour);
    got.pm = got.pm.or(before.pm);
    Ok(got)
}

/// `clock scan` without `-format`: ISO 8601 dates and times (`2024-03-01`,
/// `20240301`, `2024-03-01T12:30:00`, `2024-03-01 12:30`), US dates
/// (`03/01/2024`), `1 March 2024`, `March 1, 2024`, a time alone (today),
/// each optionally ending in `UTC`/`GMT`/`Z`.
fn scan_free(input: &str) -> Result<Scanned, Exception> {
    let t = input.trim();
    let t = ["UTC", "GMT", "Z"]
        .iter()
        .find_map(|z| t.strip_suffix(z).filter(|r| r.ends_with(' ') || *z == "Z"))
        .unwrap_or(t)
        .trim();
    let formats = [
        "%Y-%m-%dT%H:%M:%S",
        "%Y-%m-%d %H:%M:%S",
        "%Y-%m-%d %H:%M",
        "%Y-%m-%d",
        "%Y%m%dT%H%M%S",
        "%Y%m%d",
        "%m/%d/%Y %H:%M:%S",
        "%m/%d/%Y %H:%M",
        "%m/%d/%Y",
        "%d %B %Y %H:%M:%S",
        "%d %B %Y",
        "%B %d, %Y %H:%M:%S",
        "%B %d, %Y",
        "%H:%M:%S",
        "%H:%M",
        "%I:%M:%S %p",
        "%I:%M %p",
    ];
    for f in formats {
        if let Ok(s) = scan_format(t, f) {
            return Ok(s);
        }
    }
    Err(Exception::error(format!("unable to convert date-time string \"{input}\": syntax error")))
}

/// `clock add`: each `count unit` in turn; months and years move the
/// calendar date (a day past the month's end becomes its last day).
fn clock_add(mut t: i64, pairs: &[Value]) -> TclResult {
    for pair in pairs.chunks(2) {
        let n = pair[0].as_int()?;
        let unit = pair[1].as_str();
        let units = ["seconds", "minutes", "hours", "days", "weeks", "months", "years"];
        let full = units
            .iter()
            .find(|u| **u == unit || u.strip_suffix('s') == Some(unit))
            .ok_or_else(|| {
                Exception::error(format!(
                    "unknown unit \"{unit}\", must be  years, months, weeks, days, hours, minutes or seconds"
                ))
            })?;
        let step = |k: i64| n.checked_mul(k).and_then(|d| t.checked_add(d));
        let overflow = || Exception::error("integer value too large to represent");
        t = match *full {
            "seconds" => step(1).ok_or_else(overflow)?,
            "minutes" => step(60).ok_or_else(overflow)?,
            "hours" => step(3600).ok_or_else(overflow)?,
            "days" => step(86_400).ok_or_else(overflow)?,
            "weeks" => step(7 * 86_400).ok_or_else(overflow)?,
            _ => {
                let months = if *full == "years" { n.checked_mul(12) } else { Some(n) };
                let months = months.ok_or_else(overflow)?;
                let days = t.div_euclid(86_400);
                let (y, m, d) = civil(days);
                let total = (y * 12 + m as i64 - 1).checked_add(months).ok_or_else(overflow)?;
                let (ny, nm) = (total.div_euclid(12), total.rem_euclid(12) as u32 + 1);
                let nd = d.min(month_len(ny, nm));
                days_from_civil(ny, nm, nd) * 86_400 + t.rem_euclid(86_400)
            }
        };
    }
    Ok(Value::from_int(t))
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
    let subs = ["add", "clicks", "format", "microseconds", "milliseconds", "scan", "seconds"];
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
        "scan" => {
            let Some(input) = argv.get(2) else {
                return Err(Exception::wrong_args(
                    "clock scan string ?-base seconds? ?-format string? ?-gmt boolean? ?-locale LOCALE? ?-timezone ZONE?",
                ));
            };
            let (mut fmt, mut base) = (None, t.as_secs() as i64);
            for kv in argv[3..].chunks(2) {
                match (kv[0].as_str(), kv.get(1)) {
                    ("-format", Some(f)) => fmt = Some(f.as_str().to_string()),
                    ("-base", Some(b)) => base = b.as_int()?,
                    ("-gmt", Some(g)) => {
                        g.as_bool()?;
                    }
                    ("-timezone", Some(_)) | ("-locale", Some(_)) => {}
                    (o, _) => {
                        return Err(Exception::error(format!(
                            "bad option \"{o}\", must be -base, -format, -gmt, -locale or -timezone"
                        )));
                    }
                }
            }
            let scanned = match fmt {
                Some(f) => scan_format(input.as_str(), &f)?,
                None => scan_free(input.as_str())?,
            };
            Value::from_int(scanned.seconds(base)?)
        }
        "add" => {
            let Some(start) = argv.get(2) else {
                return Err(Exception::wrong_args(
                    "clock add clockval ?number units?... ?-gmt boolean? ?-locale LOCALE? ?-timezone ZONE?",
                ));
            };
            let mut pairs: &[Value] = &argv[3..];
            while pairs.len() >= 2
                && matches!(pairs[pairs.len() - 2].as_str(), "-gmt" | "-timezone" | "-locale")
            {
                pairs = &pairs[..pairs.len() - 2];
            }
            if !pairs.len().is_multiple_of(2) {
                return Err(Exception::wrong_args(
                    "clock add clockval ?number units?... ?-gmt boolean? ?-locale LOCALE? ?-timezone ZONE?",
                ));
            }
            clock_add(start.as_int()?, pairs)?
        }
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

/// `parray`, a proc as in Tcl (whose library defines it in Tcl, so
/// scripts may read `info body parray`, as tcltest does).
/// Tcl's default `unknown` handler, as its library defines it for a
/// script (rayshell auto-loads nothing and runs no programs for unknown
/// commands): the error Tcl gives.
pub(crate) const UNKNOWN: &str = r#"proc unknown args {
    set cmd [lindex $args 0]
    return -code error -errorcode [list TCL LOOKUP COMMAND $cmd] "invalid command name \"$cmd\""
}"#;

pub(crate) const PARRAY: &str = r#"proc parray {a {pattern *}} {
    upvar 1 $a array
    if {![array exists array]} {
        return -code error "\"$a\" isn't an array"
    }
    set names [lsort [array names array $pattern]]
    set width 0
    foreach name $names {
        set width [expr {max($width, [string length $name])}]
    }
    set width [expr {$width + [string length $a] + 2}]
    foreach name $names {
        puts stdout [format "%-*s = %s" $width [format %s(%s) $a $name] $array($name)]
    }
}"#;

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
