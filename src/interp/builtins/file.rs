//! `file`, `glob`, `pwd` and `cd`: the file system as Tcl 8.6 shows it.
//! Every path a script reads, writes or changes passes the host's policy
//! (`Interp::check_access`), which `--safe` fences.

use std::path::{Path, PathBuf};

use super::chan::{file_error, posix_code};
use super::{check_args, glob_match, pick_subcommand};
use crate::interp::error::{Exception, TclResult};
use crate::interp::eval::{Access, Interp};
use crate::interp::value::Value;

pub(super) const COMMANDS: &[super::Entry] = &[
    ("file", cmd_file, "subcommand name ?arg ...?", "file names and the file system"),
    ("glob", cmd_glob, "?-option ...? pattern ?pattern ...?", "file names matching patterns"),
    ("pwd", cmd_pwd, "", "the current directory"),
    ("pid", cmd_pid, "?channelId?", "this process's id"),
    ("cd", cmd_cd, "?dirName?", "change the current directory"),
];

/// The `file` subcommands, for completion.
pub(crate) const SUBCOMMANDS: &[&str] = &[
    "atime",
    "attributes",
    "channels",
    "copy",
    "delete",
    "dirname",
    "executable",
    "exists",
    "extension",
    "isdirectory",
    "isfile",
    "join",
    "link",
    "lstat",
    "mkdir",
    "mtime",
    "nativename",
    "normalize",
    "owned",
    "pathtype",
    "readable",
    "readlink",
    "rename",
    "rootname",
    "separator",
    "size",
    "split",
    "stat",
    "system",
    "tail",
    "tempfile",
    "type",
    "volumes",
    "writable",
];

fn dirname(name: &str) -> String {
    let trimmed = name.trim_end_matches('/');
    if trimmed.is_empty() {
        return if name.starts_with('/') { "/".into() } else { ".".into() };
    }
    match trimmed.rfind('/') {
        Some(i) => {
            let d = trimmed[..i].trim_end_matches('/');
            if d.is_empty() { "/".into() } else { d.to_string() }
        }
        None => ".".into(),
    }
}

fn tail(name: &str) -> String {
    let trimmed = name.trim_end_matches('/');
    trimmed.rsplit('/').next().unwrap_or("").to_string()
}

/// The extension of the last component (`.gz` of `a.tar.gz`), or "".
fn extension(name: &str) -> &str {
    let last_start = name.rfind('/').map_or(0, |i| i + 1);
    match name[last_start..].rfind('.') {
        None => "",
        Some(i) => &name[last_start + i..],
    }
}

fn split(name: &str) -> Vec<String> {
    let mut out = Vec::new();
    if name.starts_with('/') {
        out.push("/".to_string());
    }
    out.extend(name.split('/').filter(|p| !p.is_empty()).enumerate().map(|(k, p)| {
        // A later component that looks like `~user` is kept as `./~user`
        // (a leading one is a home directory, as in Tcl 8.6).
        if k > 0 && p.starts_with('~') { format!("./{p}") } else { p.to_string() }
    }));
    out
}

fn join(parts: &[Value]) -> String {
    let mut out = String::new();
    for p in parts {
        let p = p.as_str();
        if p.starts_with('/') {
            out = p.trim_end_matches('/').to_string();
            if out.is_empty() {
                out.push('/');
            }
            continue;
        }
        let p = p.trim_end_matches('/');
        if p.is_empty() {
            continue;
        }
        if !out.is_empty() && !out.ends_with('/') {
            out.push('/');
        }
        out.push_str(p);
    }
    out
}

/// An absolute path with `.` and `..` resolved (symbolic links are
/// followed where the path exists).
fn normalize(name: &str) -> String {
    let abs = if name.starts_with('/') {
        PathBuf::from(name)
    } else {
        std::env::current_dir().unwrap_or_default().join(name)
    };
    if let Ok(c) = abs.canonicalize() {
        return c.to_string_lossy().into_owned();
    }
    let mut parts: Vec<String> = Vec::new();
    for c in abs.to_string_lossy().split('/') {
        match c {
            "" | "." => {}
            ".." => {
                parts.pop();
            }
            c => parts.push(c.to_string()),
        }
    }
    format!("/{}", parts.join("/"))
}

fn metadata(path: &str, follow: bool) -> Result<std::fs::Metadata, Exception> {
    let m = if follow { std::fs::metadata(path) } else { std::fs::symlink_metadata(path) };
    m.map_err(|e| {
        Exception::error(format!("could not read \"{path}\": {}", posix_msg(&e)))
            .with_error_code(&posix_code(&e))
    })
}

/// What `file type` calls a file's kind.
fn kind_of(m: &std::fs::Metadata) -> &'static str {
    let t = m.file_type();
    if t.is_symlink() {
        "link"
    } else if t.is_dir() {
        "directory"
    } else if t.is_file() {
        "file"
    } else {
        "characterSpecial"
    }
}

fn posix_msg(e: &std::io::Error) -> String {
    let code = posix_code(e);
    code.split_once('{').map_or(String::new(), |(_, m)| m.trim_end_matches('}').to_string())
}

fn unix_time(t: std::io::Result<std::time::SystemTime>) -> i64 {
    t.ok()
        .and_then(|t| t.duration_since(std::time::UNIX_EPOCH).ok())
        .map_or(0, |d| d.as_secs() as i64)
}

/// Asks the host's policy (`--safe`) about every path a `file` subcommand
/// names, in one place, so no subcommand can forget it: reads for those
/// that look at the file system, changes for those that change it. Those
/// that only work on the name's text ask nothing; `exists` and its kin
/// answer 0 for a refused path (as Tcl's safe interpreters do), and
/// `copy`, `rename` and `tempfile` ask for each of their names themselves.
fn gate(interp: &Interp, sub: &str, a: &[Value]) -> Result<(), Exception> {
    let names =
        |a: &'_ [Value]| -> Vec<String> { a.iter().map(|v| v.as_str().to_string()).collect() };
    let (access, paths) = match sub {
        "readlink" | "owned" | "normalize" | "system" | "size" | "type" | "stat" | "lstat" => {
            (Access::Read, names(&a[..a.len().min(1)]))
        }
        "atime" | "mtime" if a.len() > 1 => (Access::Modify, names(&a[..1])),
        "atime" | "mtime" => (Access::Read, names(a)),
        "attributes" if a.len() > 2 => (Access::Modify, names(&a[..1])),
        "attributes" => (Access::Read, names(&a[..a.len().min(1)])),
        "link" => {
            let rest = match a.first().map(|v| v.as_str()) {
                Some("-hard" | "-symbolic") => &a[1..],
                _ => a,
            };
            match rest.len() {
                2 => (Access::Modify, names(&rest[..1])),
                _ => (Access::Read, names(rest)),
            }
        }
        "mkdir" => (Access::Modify, names(a)),
        "delete" => (Access::Modify, names(options(a, "-force").1)),
        _ => return Ok(()),
    };
    for p in &paths {
        interp.check_access(p, access)?;
    }
    Ok(())
}

fn cmd_file(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "subcommand ?arg ...?")?;
    let sub = pick_subcommand(argv[1].as_str(), SUBCOMMANDS)?;
    let a = &argv[2..];
    let one = |usage: &str| -> Result<&str, Exception> {
        match a {
            [n] => Ok(n.as_str()),
            _ => Err(Exception::wrong_args(&format!("file {sub} {usage}"))),
        }
    };
    gate(interp, sub, a)?;
    Ok(match sub {
        "dirname" => Value::from_string(dirname(one("name")?)),
        "tail" => Value::from_string(tail(one("name")?)),
        "extension" => Value::from(extension(one("name")?)),
        "rootname" => {
            let n = one("name")?;
            Value::from(&n[..n.len() - extension(n).len()])
        }
        "split" => {
            Value::from_list(split(one("name")?).into_iter().map(Value::from_string).collect())
        }
        "join" => {
            if a.is_empty() {
                return Err(Exception::wrong_args("file join name ?name ...?"));
            }
            Value::from_string(join(a))
        }
        "normalize" => Value::from_string(normalize(one("filename")?)),
        "nativename" => Value::from(one("name")?),
        "pathtype" => {
            let n = one("name")?;
            Value::from(if n.starts_with(['/', '~']) { "absolute" } else { "relative" })
        }
        "system" => Value::from_string(normalize(one("name")?)),
        "volumes" => {
            if !a.is_empty() {
                return Err(Exception::wrong_args("file volumes"));
            }
            Value::from("/")
        }
        "channels" => {
            if a.len() > 1 {
                return Err(Exception::wrong_args("file channels ?pattern?"));
            }
            let mut argv = vec![Value::from("chan"), Value::from("names")];
            argv.extend(a.iter().cloned());
            interp.invoke(&argv)?
        }
        "readlink" => {
            let n = one("name")?;
            let t = std::fs::read_link(n).map_err(|e| {
                Exception::error(format!("could not read link \"{n}\": {}", posix_msg(&e)))
                    .with_error_code(&posix_code(&e))
            })?;
            Value::from(t.to_string_lossy().as_ref())
        }
        "owned" => {
            use std::os::unix::fs::MetadataExt;
            let n = one("name")?;
            let me = std::fs::metadata("/proc/self").map(|m| m.uid()).ok();
            Value::from_bool(std::fs::metadata(n).is_ok_and(|m| Some(m.uid()) == me))
        }
        "stat" | "lstat" => {
            use std::os::unix::fs::MetadataExt;
            let [n, var] = a else {
                return Err(Exception::wrong_args(&format!("file {sub} name varName")));
            };
            let m = metadata(n.as_str(), sub == "stat")?;
            let kind = kind_of(&m);
            let fields: [(&str, Value); 12] = [
                ("atime", Value::from_int(m.atime())),
                ("ctime", Value::from_int(m.ctime())),
                ("dev", Value::from_int(m.dev() as i64)),
                ("gid", Value::from_int(m.gid() as i64)),
                ("ino", Value::from_int(m.ino() as i64)),
                ("mode", Value::from_int(m.mode() as i64)),
                ("mtime", Value::from_int(m.mtime())),
                ("nlink", Value::from_int(m.nlink() as i64)),
                ("size", Value::from_int(m.size() as i64)),
                ("type", Value::from(kind)),
                ("uid", Value::from_int(m.uid() as i64)),
                ("blksize", Value::from_int(m.blksize() as i64)),
            ];
            for (k, v) in fields {
                interp.set_var(&format!("{}({k})", var.as_str()), v)?;
            }
            Value::empty()
        }
        "link" => {
            let (hard, rest) = match a {
                [o, rest @ ..] if o.as_str() == "-hard" => (true, rest),
                [o, rest @ ..] if o.as_str() == "-symbolic" => (false, rest),
                rest => (false, rest),
            };
            match rest {
                [l] => {
                    let t = std::fs::read_link(l.as_str())
                        .map_err(|e| file_error("read link", l.as_str(), &e))?;
                    Value::from(t.to_string_lossy().as_ref())
                }
                [l, t] => {
                    let r = if hard {
                        std::fs::hard_link(t.as_str(), l.as_str())
                    } else {
                        std::os::unix::fs::symlink(t.as_str(), l.as_str())
                    };
                    r.map_err(|e| file_error("create link", l.as_str(), &e))?;
                    t.clone()
                }
                _ => return Err(Exception::wrong_args("file link ?-linktype? linkname ?target?")),
            }
        }
        "attributes" => {
            use std::os::unix::fs::PermissionsExt;
            let Some((n, rest)) = a.split_first() else {
                return Err(Exception::wrong_args(
                    "file attributes name ?-option? ?value? ?-option value ...?",
                ));
            };
            let m = metadata(n.as_str(), true)?;
            let perms = Value::from(format!("{:05o}", m.permissions().mode() & 0o7777));
            match rest {
                [] => Value::from_list(vec![Value::from("-permissions"), perms]),
                [o] if o.as_str() == "-permissions" => perms,
                [o, v] if o.as_str() == "-permissions" => {
                    let mode = crate::interp::number::parse_int(v.as_str())
                        .ok_or_else(|| crate::interp::number::int_error(v.as_str()))?;
                    std::fs::set_permissions(
                        n.as_str(),
                        std::fs::Permissions::from_mode(mode as u32),
                    )
                    .map_err(|e| file_error("set permissions of", n.as_str(), &e))?;
                    Value::empty()
                }
                [o, ..] => {
                    return Err(Exception::error(format!(
                        "bad option \"{}\": must be -group, -owner, or -permissions",
                        o.as_str()
                    )));
                }
            }
        }
        "separator" => {
            if a.len() > 1 {
                return Err(Exception::wrong_args("file separator ?name?"));
            }
            Value::from("/")
        }
        "exists" | "isfile" | "isdirectory" | "readable" | "writable" | "executable" => {
            let n = one("name")?;
            if interp.check_access(n, Access::Read).is_err() {
                return Ok(Value::from_bool(false));
            }
            let p = Path::new(n);
            Value::from_bool(match sub {
                "exists" => p.exists(),
                "isfile" => p.is_file(),
                "isdirectory" => p.is_dir(),
                _ => may(p, sub),
            })
        }
        "size" | "mtime" | "atime" | "type" => {
            let n = one("name")?;
            let m = metadata(n, sub != "type")?;
            match sub {
                "size" => Value::from_int(m.len() as i64),
                "mtime" => Value::from_int(unix_time(m.modified())),
                "atime" => Value::from_int(unix_time(m.accessed())),
                _ => Value::from(kind_of(&m)),
            }
        }
        "mkdir" => {
            for d in a {
                std::fs::create_dir_all(d.as_str()).map_err(|e| {
                    Exception::error(format!(
                        "can't create directory \"{}\": {}",
                        d.as_str(),
                        posix_msg(&e)
                    ))
                    .with_error_code(&posix_code(&e))
                })?;
            }
            Value::empty()
        }
        "delete" => {
            let (force, names) = options(a, "-force");
            for n in names {
                let n = n.as_str();
                let p = Path::new(n);
                let r = match std::fs::symlink_metadata(p) {
                    Err(_) => Ok(()),
                    Ok(m) if m.is_dir() && force => std::fs::remove_dir_all(p),
                    Ok(m) if m.is_dir() => std::fs::remove_dir(p),
                    Ok(_) => std::fs::remove_file(p),
                };
                r.map_err(|e| {
                    let why = if p.is_dir() && !force {
                        "directory not empty".to_string()
                    } else {
                        posix_msg(&e)
                    };
                    Exception::error(format!("error deleting \"{n}\": {why}"))
                        .with_error_code(&posix_code(&e))
                })?;
            }
            Value::empty()
        }
        "rename" | "copy" => {
            let (force, names) = options(a, "-force");
            let [from @ .., to] = names else {
                return Err(Exception::wrong_args(&format!(
                    "file {sub} ?-option value ...? source ?source ...? target"
                )));
            };
            if from.is_empty() {
                return Err(Exception::wrong_args(&format!(
                    "file {sub} ?-option value ...? source ?source ...? target"
                )));
            }
            let to = to.as_str();
            interp.check_access(to, Access::Modify)?;
            for f in from {
                let f = f.as_str();
                interp
                    .check_access(f, if sub == "copy" { Access::Read } else { Access::Modify })?;
                let target = if Path::new(to).is_dir() {
                    Path::new(to).join(tail(f))
                } else {
                    PathBuf::from(to)
                };
                if target.exists() && !force {
                    return Err(Exception::error(format!(
                        "error {}ing \"{f}\" to \"{}\": file already exists",
                        if sub == "copy" { "copy" } else { "renam" },
                        target.to_string_lossy()
                    ))
                    .with_error_code("POSIX EEXIST {file already exists}"));
                }
                let r = if sub == "copy" {
                    std::fs::copy(f, &target).map(|_| ())
                } else {
                    std::fs::rename(f, &target)
                };
                r.map_err(|e| file_error(if sub == "copy" { "copy" } else { "rename" }, f, &e))?;
            }
            Value::empty()
        }
        _ => {
            // tempfile
            if a.len() > 2 {
                return Err(Exception::wrong_args("file tempfile ?nameVar? ?template?"));
            }
            let dir = std::env::temp_dir();
            let base = a.get(1).map_or("tcl".to_string(), |t| t.as_str().to_string());
            let mut k = std::process::id() as u64;
            loop {
                let p = dir.join(format!("{base}_{k:06x}"));
                let ps = p.to_string_lossy().into_owned();
                if !p.exists() {
                    interp.check_access(&ps, Access::Write)?;
                    let chan = interp.invoke(&[
                        Value::from("open"),
                        Value::from(ps.as_str()),
                        Value::from("RDWR CREAT EXCL"),
                    ])?;
                    if let Some(var) = a.first() {
                        interp.set_var(var.as_str(), Value::from_string(ps))?;
                    }
                    return Ok(chan);
                }
                k = k.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407) >> 8;
            }
        }
    })
}

/// Leading `-force` (and `--`) before the names.
fn options<'a>(a: &'a [Value], flag: &str) -> (bool, &'a [Value]) {
    let mut force = false;
    let mut i = 0;
    while i < a.len() && a[i].as_str().starts_with('-') {
        match a[i].as_str() {
            f if f == flag => force = true,
            "--" => {
                i += 1;
                break;
            }
            _ => break,
        }
        i += 1;
    }
    (force, &a[i..])
}

/// `file readable/writable/executable`: what this process may do.
fn may(p: &Path, sub: &str) -> bool {
    use std::os::unix::fs::PermissionsExt;
    let Ok(m) = std::fs::metadata(p) else { return false };
    match sub {
        "readable" if m.is_dir() => std::fs::read_dir(p).is_ok(),
        "readable" => std::fs::File::open(p).is_ok(),
        "writable" if m.is_dir() => !m.permissions().readonly(),
        "writable" => std::fs::OpenOptions::new().append(true).open(p).is_ok(),
        _ => m.permissions().mode() & 0o111 != 0,
    }
}

/// The names in `dir` matching one glob component.
fn matches_in(dir: &Path, pattern: &str) -> Vec<String> {
    let Ok(rd) = std::fs::read_dir(if dir.as_os_str().is_empty() { Path::new(".") } else { dir })
    else {
        return Vec::new();
    };
    // `.*` finds `.` and `..` too, as in Tcl.
    let dots = [".", ".."].map(String::from);
    let mut out: Vec<String> = rd
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().into_owned())
        .chain(dots)
        .filter(|n| {
            (!n.starts_with('.') || pattern.starts_with('.')) && glob_match(pattern, n, false)
        })
        .collect();
    out.sort();
    out
}

/// Expands `{a,b}` alternatives in a glob pattern.
/// The patterns a pattern's `{a,b}` alternatives stand for, in order.
/// Their number multiplies with each brace (seven braces of ten are ten
/// million patterns): each is asked of the memory budget as it is made.
fn braces(pattern: &str) -> Result<Vec<String>, Exception> {
    let mut out = Vec::new();
    expand_braces(pattern, &mut out)?;
    Ok(out)
}

fn expand_braces(pattern: &str, out: &mut Vec<String>) -> Result<(), Exception> {
    let leaf = |out: &mut Vec<String>| -> Result<(), Exception> {
        crate::mem::room(out, 1)?;
        crate::mem::reserve(pattern.len())?;
        out.push(pattern.to_string());
        Ok(())
    };
    let Some(open) = pattern.find('{') else { return leaf(out) };
    let mut depth = 0;
    let mut close = None;
    for (i, c) in pattern[open..].char_indices() {
        match c {
            '{' => depth += 1,
            '}' => {
                depth -= 1;
                if depth == 0 {
                    close = Some(open + i);
                    break;
                }
            }
            _ => {}
        }
    }
    let Some(close) = close else { return leaf(out) };
    let (pre, body, post) = (&pattern[..open], &pattern[open + 1..close], &pattern[close + 1..]);
    let mut alts = Vec::new();
    let (mut depth, mut start) = (0, 0);
    for (i, c) in body.char_indices() {
        match c {
            '{' => depth += 1,
            '}' => depth -= 1,
            ',' if depth == 0 => {
                alts.push(&body[start..i]);
                start = i + 1;
            }
            _ => {}
        }
    }
    alts.push(&body[start..]);
    for a in alts {
        expand_braces(&format!("{pre}{a}{post}"), out)?;
    }
    Ok(())
}

fn glob_one(base: &Path, pattern: &str) -> Vec<String> {
    let (root, rest) = match pattern.strip_prefix('/') {
        Some(r) => (PathBuf::from("/"), r),
        None => (base.to_path_buf(), pattern),
    };
    let mut found: Vec<(PathBuf, String)> = vec![(root, String::new())];
    let parts: Vec<&str> = rest.split('/').filter(|p| !p.is_empty()).collect();
    for (k, part) in parts.iter().enumerate() {
        let last = k + 1 == parts.len();
        let mut next = Vec::new();
        for (dir, shown) in &found {
            let names = if part.contains(['*', '?', '[', '\\']) {
                matches_in(dir, part)
            } else if dir.join(part).exists() || (last && dir.join(part).symlink_metadata().is_ok())
            {
                vec![part.to_string()]
            } else {
                Vec::new()
            };
            for n in names {
                let p = dir.join(&n);
                if !last && !p.is_dir() {
                    continue;
                }
                let s = if shown.is_empty() {
                    if pattern.starts_with('/') { format!("/{n}") } else { n }
                } else if shown == "/" {
                    format!("/{n}")
                } else {
                    format!("{shown}/{n}")
                };
                next.push((p, s));
            }
        }
        found = next;
    }
    if parts.is_empty() {
        return if pattern.starts_with('/') { vec!["/".into()] } else { Vec::new() };
    }
    found.into_iter().map(|(_, s)| s).collect()
}

fn cmd_glob(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "?-option ...? pattern ?pattern ...?")?;
    let opts = ["--", "-directory", "-join", "-nocomplain", "-path", "-tails", "-types"];
    let (mut nocomplain, mut tails, mut join_all) = (false, false, false);
    let mut dir: Option<String> = None;
    let mut types: Vec<String> = Vec::new();
    let mut i = 1;
    while i < argv.len() && argv[i].as_str().starts_with('-') {
        let o = super::pick_option(argv[i].as_str(), &opts, "option")?;
        i += 1;
        match o {
            "--" => break,
            "-nocomplain" => nocomplain = true,
            "-tails" => tails = true,
            "-join" => join_all = true,
            _ => {
                let Some(v) = argv.get(i) else {
                    return Err(Exception::error(format!("missing argument to \"{o}\"")));
                };
                i += 1;
                if o == "-types" {
                    types = v.as_list()?.iter().map(|t| t.as_str().to_string()).collect();
                } else {
                    dir = Some(v.as_str().to_string());
                }
            }
        }
    }
    let patterns: Vec<String> = if join_all {
        vec![join(&argv[i..])]
    } else {
        argv[i..].iter().map(|p| p.as_str().to_string()).collect()
    };
    if patterns.is_empty() {
        return Err(Exception::wrong_args("glob ?-option ...? pattern ?pattern ...?"));
    }
    let base = dir.clone().unwrap_or_default();
    if !base.is_empty() {
        interp.check_access(&base, Access::Read)?;
    }
    let mut out = Vec::new();
    for pat in &patterns {
        for p in braces(pat)? {
            for m in glob_one(Path::new(&base), &p) {
                let full = if base.is_empty() || m.starts_with('/') {
                    m.clone()
                } else {
                    format!("{}/{m}", base.trim_end_matches('/'))
                };
                let ok = interp.check_access(&full, Access::Read).is_ok()
                    && (types.is_empty()
                        || types.iter().any(|t| match t.as_str() {
                            "d" => Path::new(&full).is_dir(),
                            "f" => Path::new(&full).is_file(),
                            "l" => Path::new(&full).is_symlink(),
                            _ => false,
                        }));
                if ok {
                    out.push(Value::from_string(if tails { m } else { full }));
                }
            }
        }
    }
    if out.is_empty() && !nocomplain {
        let shown = patterns.join(" ");
        let msg = if patterns.len() > 1 {
            format!("no files matched glob patterns \"{shown}\"")
        } else {
            format!("no files matched glob pattern \"{shown}\"")
        };
        return Err(Exception::error(msg).with_error_code("TCL OPERATION GLOB NOMATCH"));
    }
    Ok(Value::from_list(out))
}

fn cmd_pid(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 1, 2, "?channelId?")?;
    if argv.len() == 2 {
        // A pipeline's processes; a file has none.
        let pids = interp.channels.pids(argv[1].as_str())?;
        return Ok(Value::from_list(pids.into_iter().map(|p| Value::from_int(p.into())).collect()));
    }
    Ok(Value::from_int(std::process::id() as i64))
}

fn cmd_pwd(_: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 1, 1, "")?;
    let d = std::env::current_dir().map_err(|e| {
        Exception::error(format!("error getting working directory name: {}", posix_msg(&e)))
    })?;
    Ok(Value::from(d.to_string_lossy().as_ref()))
}

fn cmd_cd(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 1, 2, "?dirName?")?;
    let dir = match argv.get(1) {
        Some(d) => d.as_str().to_string(),
        None => std::env::var("HOME").unwrap_or_else(|_| "/".into()),
    };
    interp.check_access(&dir, Access::Modify)?;
    std::env::set_current_dir(&dir).map_err(|e| {
        Exception::error(format!(
            "couldn't change working directory to \"{dir}\": {}",
            posix_msg(&e)
        ))
        .with_error_code(&posix_code(&e))
    })?;
    Ok(Value::empty())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_split_as_tcl_splits_them() {
        assert_eq!(dirname("/a/b/c"), "/a/b");
        assert_eq!(dirname("c"), ".");
        assert_eq!(dirname("/c"), "/");
        assert_eq!(tail("/a/b/"), "b");
        assert_eq!(extension("a/b.tar.gz"), ".gz");
        assert_eq!(extension("a.b/c"), "");
        assert_eq!(extension(".bashrc"), ".bashrc");
        assert_eq!(split("/a//b"), ["/", "a", "b"]);
        let v = |s: &str| Value::from(s);
        assert_eq!(join(&[v("a"), v("b/"), v("/c"), v("d")]), "/c/d");
        assert_eq!(braces("x{a,b{c,d}}y").unwrap(), ["xay", "xbcy", "xbdy"]);
    }
}
