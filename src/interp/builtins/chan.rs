//! Channels, as Tcl 8.6 has them for files: `open`, `close`, `gets`,
//! `read`, `puts`, `flush`, `eof`, `seek`, `tell`, `fconfigure` and the
//! `chan` ensemble, with `stdin`, `stdout` and `stderr` as channels (the
//! last two go through the host, so captured output stays captured).
//! Text is UTF-8 with `auto` end-of-line translation on input, as Tcl's
//! defaults on Unix; `-translation binary` gives bytes as U+0000..U+00FF.

use std::collections::BTreeMap;
use std::fs::File;
use std::io::{Read, Seek, SeekFrom, Write};

use super::{check_args, pick_subcommand};
use crate::interp::error::{Exception, TclResult};
use crate::interp::eval::{Access, Interp};
use crate::interp::value::Value;

pub(super) const COMMANDS: &[super::Entry] = &[
    ("open", cmd_open, "fileName ?access? ?permissions?", "open a file as a channel"),
    ("close", cmd_close, "channelId", "close a channel"),
    ("gets", cmd_gets, "channelId ?varName?", "read a line from a channel"),
    ("read", cmd_read, "?-nonewline? channelId ?numChars?", "read from a channel"),
    ("flush", cmd_flush, "channelId", "write out a channel's buffered output"),
    ("eof", cmd_eof, "channelId", "whether the last read reached the end"),
    ("seek", cmd_seek, "channelId offset ?origin?", "move a channel's position"),
    ("tell", cmd_tell, "channelId", "a channel's position"),
    (
        "fconfigure",
        cmd_fconfigure,
        "channelId ?-option value ...?",
        "a channel's options: -translation -encoding -buffering -blocking",
    ),
    ("chan", cmd_chan, "subcommand ?arg ...?", "channel operations by subcommand"),
];

/// An open file.
pub(crate) struct FileChan {
    file: File,
    readable: bool,
    writable: bool,
    /// Bytes read ahead and not yet consumed.
    rbuf: Vec<u8>,
    rpos: usize,
    wbuf: Vec<u8>,
    eof: bool,
    binary: bool,
    /// A `\r` ended the last read: a `\n` right after it belongs to it.
    pending_cr: bool,
    /// For a command pipeline (`open |cmd`): its processes.
    children: Vec<std::process::Child>,
}

/// The channels an interpreter has open, by name.
#[derive(Default)]
pub(crate) struct Channels {
    files: BTreeMap<String, FileChan>,
    stdin_eof: bool,
}

fn io_error(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file or directory".into(),
        std::io::ErrorKind::PermissionDenied => "permission denied".into(),
        std::io::ErrorKind::AlreadyExists => "file already exists".into(),
        std::io::ErrorKind::IsADirectory => "illegal operation on a directory".into(),
        _ => {
            let s = e.to_string();
            let s = s.split(" (os error").next().unwrap_or(&s);
            let mut c = s.chars();
            match c.next() {
                Some(f) => f.to_lowercase().chain(c).collect(),
                None => s.to_string(),
            }
        }
    }
}

/// The POSIX errorCode of an I/O error, as Tcl gives it.
pub(crate) fn posix_code(e: &std::io::Error) -> String {
    let name = match e.kind() {
        std::io::ErrorKind::NotFound => "ENOENT",
        std::io::ErrorKind::PermissionDenied => "EACCES",
        std::io::ErrorKind::AlreadyExists => "EEXIST",
        std::io::ErrorKind::IsADirectory => "EISDIR",
        _ => "EIO",
    };
    format!("POSIX {name} {{{}}}", io_error(e))
}

pub(crate) fn file_error(what: &str, path: &str, e: &std::io::Error) -> Exception {
    Exception::error(format!("couldn't {what} \"{path}\": {}", io_error(e)))
        .with_error_code(&posix_code(e))
}

fn no_channel(name: &str) -> Exception {
    Exception::error(format!("can not find channel named \"{name}\""))
        .with_error_code(&format!("TCL LOOKUP CHANNEL {name}"))
}

impl Channels {
    /// The process ids behind a pipeline channel (empty for a file).
    pub(crate) fn pids(&self, name: &str) -> Result<Vec<u32>, Exception> {
        match name {
            "stdin" | "stdout" | "stderr" => Ok(Vec::new()),
            _ => Ok(self
                .files
                .get(name)
                .ok_or_else(|| no_channel(name))?
                .children
                .iter()
                .map(|c| c.id())
                .collect()),
        }
    }

    fn get(&mut self, name: &str) -> Result<&mut FileChan, Exception> {
        self.files.get_mut(name).ok_or_else(|| no_channel(name))
    }

    /// Writes any buffered output of every open file (at exit).
    pub(crate) fn flush_all(&mut self) {
        for c in self.files.values_mut() {
            let _ = c.flush();
        }
    }
}

impl FileChan {
    /// A channel on a pipe to or from a pipeline's processes.
    pub(super) fn pipe(
        file: File,
        readable: bool,
        writable: bool,
        children: Vec<std::process::Child>,
    ) -> FileChan {
        FileChan {
            file,
            readable,
            writable,
            rbuf: Vec::new(),
            rpos: 0,
            wbuf: Vec::new(),
            eof: false,
            binary: false,
            pending_cr: false,
            children,
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        if !self.wbuf.is_empty() {
            self.file.write_all(&self.wbuf)?;
            self.wbuf.clear();
        }
        Ok(())
    }

    /// Reads more bytes into the buffer; false at the end of the file.
    fn fill(&mut self) -> std::io::Result<bool> {
        // A line or a read without end (`/dev/zero`) stops at the value cap.
        if self.rbuf.len() - self.rpos > crate::interp::MAX_VALUE_LEN {
            return Err(std::io::Error::other("string too long"));
        }
        crate::interp::eval::check_len(self.rbuf.len() + 8192)
            .map_err(|e| std::io::Error::other(e.message().to_string()))?;
        if self.rpos > 0 {
            self.rbuf.drain(..self.rpos);
            self.rpos = 0;
        }
        let mut chunk = [0u8; 8192];
        let n = self.file.read(&mut chunk)?;
        self.rbuf.extend_from_slice(&chunk[..n]);
        Ok(n > 0)
    }

    fn decode(&self, bytes: &[u8]) -> String {
        if self.binary {
            return bytes.iter().map(|&b| b as char).collect();
        }
        String::from_utf8_lossy(bytes).into_owned()
    }

    /// Input translation: `\r\n` and a lone `\r` become `\n`.
    fn translate(&mut self, bytes: &[u8]) -> Vec<u8> {
        if self.binary {
            return bytes.to_vec();
        }
        let mut out = Vec::with_capacity(bytes.len());
        for &b in bytes {
            if self.pending_cr {
                self.pending_cr = false;
                if b == b'\n' {
                    continue;
                }
            }
            if b == b'\r' {
                out.push(b'\n');
                self.pending_cr = true;
            } else {
                out.push(b);
            }
        }
        out
    }

    /// One line without its end, or None at the end of the file.
    fn gets(&mut self) -> std::io::Result<Option<String>> {
        self.flush()?;
        loop {
            let avail = &self.rbuf[self.rpos..];
            let end = avail.iter().position(|&b| b == b'\n' || (!self.binary && b == b'\r'));
            if let Some(i) = end {
                let line = avail[..i].to_vec();
                let term = avail[i];
                self.rpos += i + 1;
                if term == b'\r' {
                    // `\r\n` is one line end.
                    if self.rpos >= self.rbuf.len() {
                        self.fill()?;
                    }
                    if self.rbuf.get(self.rpos) == Some(&b'\n') {
                        self.rpos += 1;
                    }
                }
                let line = self.translate(&line);
                return Ok(Some(self.decode(&line)));
            }
            if !self.fill()? {
                self.eof = true;
                let rest = self.rbuf[self.rpos..].to_vec();
                self.rpos = self.rbuf.len();
                if rest.is_empty() {
                    return Ok(None);
                }
                let rest = self.translate(&rest);
                return Ok(Some(self.decode(&rest)));
            }
        }
    }

    /// Everything to the end, or at most `n` characters.
    fn read(&mut self, n: Option<usize>) -> std::io::Result<String> {
        self.flush()?;
        loop {
            if let Some(n) = n {
                let avail = &self.rbuf[self.rpos..];
                // Enough bytes for n characters (UTF-8 is at most 4 per character).
                let enough = if self.binary { n } else { n.saturating_mul(4) };
                if avail.len() >= enough {
                    break;
                }
            }
            if !self.fill()? {
                self.eof = true;
                break;
            }
        }
        let raw = &self.rbuf[self.rpos..];
        // The bytes of the first n characters (a `\r\n` is one; a byte
        // that is not UTF-8 is one character, as the decoding makes it).
        let mut take = raw.len();
        if let Some(n) = n {
            let (mut bytes, mut chars) = (0, 0);
            while chars < n && bytes < raw.len() {
                let b = raw[bytes];
                let len = if self.binary {
                    1
                } else if b == b'\r' && raw.get(bytes + 1) == Some(&b'\n') {
                    2
                } else {
                    let want = match b {
                        0xc0..=0xdf => 2,
                        0xe0..=0xef => 3,
                        0xf0..=0xf7 => 4,
                        _ => 1,
                    };
                    let ok = raw[bytes + 1..]
                        .iter()
                        .take(want - 1)
                        .take_while(|&&c| c & 0xc0 == 0x80)
                        .count();
                    if ok == want - 1 { want } else { 1 }
                };
                bytes += len;
                chars += 1;
            }
            take = bytes.min(raw.len());
        }
        let raw = raw[..take].to_vec();
        self.rpos += take;
        if self.rpos < self.rbuf.len() {
            self.eof = false;
        }
        let text = self.translate(&raw);
        Ok(self.decode(&text))
    }

    fn write(&mut self, s: &str) {
        if self.binary {
            self.wbuf.extend(s.chars().map(|c| c as u32 as u8));
        } else {
            self.wbuf.extend_from_slice(s.as_bytes());
        }
    }

    fn tell(&mut self) -> std::io::Result<u64> {
        let pos = self.file.stream_position()?;
        let unread = self.rbuf.len().saturating_sub(self.rpos) as u64;
        Ok((pos + self.wbuf.len() as u64).saturating_sub(unread))
    }

    fn seek(&mut self, to: SeekFrom) -> std::io::Result<()> {
        let to = match to {
            SeekFrom::Current(d) => SeekFrom::Start((self.tell()? as i64 + d).max(0) as u64),
            other => other,
        };
        self.flush()?;
        self.rbuf.clear();
        self.rpos = 0;
        self.pending_cr = false;
        self.eof = false;
        self.file.seek(to)?;
        Ok(())
    }
}

/// Parses an access mode: `r w a` with `+` and `b`, or a list of POSIX
/// flags. Returns (read, write, append, create, truncate, exclusive, binary).
fn parse_access(mode: &str) -> Result<[bool; 7], Exception> {
    let bad = || Exception::error(format!("illegal access mode \"{mode}\"",));
    let m = mode.trim();
    if m.chars().next().is_some_and(|c| c.is_ascii_uppercase()) {
        let mut f = [false; 7];
        let items = Value::from(m).as_list()?;
        for it in items.iter() {
            match it.as_str() {
                "RDONLY" => f[0] = true,
                "WRONLY" => f[1] = true,
                "RDWR" => {
                    f[0] = true;
                    f[1] = true;
                }
                "APPEND" => f[2] = true,
                "CREAT" => f[3] = true,
                "TRUNC" => f[4] = true,
                "EXCL" => f[5] = true,
                "BINARY" => f[6] = true,
                "NOCTTY" | "NONBLOCK" => {}
                other => {
                    return Err(Exception::error(format!(
                        "invalid access mode \"{other}\": must be APPEND, BINARY, CREAT, EXCL, NOCTTY, NONBLOCK, RDONLY, RDWR, TRUNC, or WRONLY"
                    )));
                }
            }
        }
        if !f[0] && !f[1] {
            f[0] = true;
        }
        return Ok(f);
    }
    let binary = m.contains('b');
    let core: String = m.chars().filter(|&c| c != 'b').collect();
    Ok(match core.as_str() {
        "r" => [true, false, false, false, false, false, binary],
        "r+" => [true, true, false, false, false, false, binary],
        "w" => [false, true, false, true, true, false, binary],
        "w+" => [true, true, false, true, true, false, binary],
        "a" => [false, true, true, true, false, false, binary],
        "a+" => [true, true, true, true, false, false, binary],
        _ => return Err(bad()),
    })
}

fn cmd_open(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 4, "fileName ?access? ?permissions?")?;
    let path = argv[1].as_str();
    let [read, write, append, create, truncate, exclusive, binary] =
        parse_access(argv.get(2).map_or("r", |v| v.as_str()))?;
    if let Some(spec) = path.strip_prefix('|') {
        if read && write {
            return Err(Exception::error(
                "rayshell opens a command pipeline for reading or for writing, not both",
            ));
        }
        let chan = super::exec::open_pipeline(interp, spec, write)?;
        let name = {
            use std::os::unix::io::AsRawFd;
            format!("file{}", chan.file.as_raw_fd())
        };
        interp.channels.files.insert(name.clone(), chan);
        return Ok(Value::from_string(name));
    }
    // Any flag that can create or change a file is a write, whatever the
    // read/write flags say (`{RDONLY CREAT APPEND}` creates the file).
    let changes = write || append || create || truncate;
    interp.check_access(path, if changes { Access::Write } else { Access::Read })?;
    let mut opts = std::fs::OpenOptions::new();
    opts.read(read).write(write && !append).append(append);
    if exclusive && create {
        opts.create_new(true);
    } else {
        opts.create(create);
    }
    opts.truncate(truncate);
    if let Some(perm) = argv.get(3) {
        use std::os::unix::fs::OpenOptionsExt;
        let p = perm.as_int()?;
        opts.mode(u32::try_from(p).map_err(|_| Exception::error("bad permissions"))?);
    }
    let file = opts.open(path).map_err(|e| file_error("open", path, &e))?;
    if file.metadata().is_ok_and(|m| m.is_dir()) && write {
        return Err(Exception::error(format!(
            "couldn't open \"{path}\": illegal operation on a directory"
        )));
    }
    // Named by the descriptor, as Tcl names them (so names are reused).
    let name = {
        use std::os::unix::io::AsRawFd;
        format!("file{}", file.as_raw_fd())
    };
    interp.channels.files.insert(
        name.clone(),
        FileChan {
            file,
            readable: read,
            writable: write,
            rbuf: Vec::new(),
            rpos: 0,
            wbuf: Vec::new(),
            eof: false,
            binary,
            pending_cr: false,
            children: Vec::new(),
        },
    );
    Ok(Value::from_string(name))
}

fn cmd_close(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 3, "channelId ?direction?")?;
    let name = argv[1].as_str();
    if matches!(name, "stdin" | "stdout" | "stderr") {
        interp.flush();
        return Ok(Value::empty());
    }
    let mut c = interp.channels.files.remove(name).ok_or_else(|| no_channel(name))?;
    let flushed = c.flush();
    let children = std::mem::take(&mut c.children);
    // The pipe closes before the processes are waited for.
    drop(c);
    if !children.is_empty() {
        super::exec::close_pipeline(children)?;
    }
    flushed
        .map_err(|e| Exception::error(format!("error flushing \"{name}\": {}", io_error(&e))))?;
    Ok(Value::empty())
}

/// Reads a line from stdin (None at its end).
fn stdin_line(interp: &mut Interp) -> Option<String> {
    interp.flush();
    let mut line = String::new();
    match std::io::stdin().read_line(&mut line) {
        Ok(0) | Err(_) => {
            interp.channels.stdin_eof = true;
            None
        }
        Ok(_) => {
            if line.ends_with('\n') {
                line.pop();
                if line.ends_with('\r') {
                    line.pop();
                }
            }
            Some(line)
        }
    }
}

fn readable<'a>(interp: &'a mut Interp, name: &str) -> Result<&'a mut FileChan, Exception> {
    if matches!(name, "stdout" | "stderr") {
        return Err(Exception::error(format!("channel \"{name}\" wasn't opened for reading")));
    }
    let c = interp.channels.get(name)?;
    if !c.readable {
        return Err(Exception::error(format!("channel \"{name}\" wasn't opened for reading")));
    }
    Ok(c)
}

fn cmd_gets(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 3, "channelId ?varName?")?;
    let name = argv[1].as_str();
    let line = if name == "stdin" {
        stdin_line(interp)
    } else {
        let c = readable(interp, name)?;
        c.gets()
            .map_err(|e| Exception::error(format!("error reading \"{name}\": {}", io_error(&e))))?
    };
    match argv.get(2) {
        Some(var) => {
            let n = line.as_ref().map_or(-1, |l| l.chars().count() as i64);
            interp.set_var(var.as_str(), Value::from_string(line.unwrap_or_default()))?;
            Ok(Value::from_int(n))
        }
        None => Ok(Value::from_string(line.unwrap_or_default())),
    }
}

fn cmd_read(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 3, "?-nonewline? channelId ?numChars?")?;
    let (nonewline, name, count) = match argv {
        [_, f, c] if f.as_str() == "-nonewline" => (true, c, None),
        [_, c, n] => {
            let k = n.as_int().map_err(|_| {
                Exception::error(format!(
                    "expected non-negative integer but got \"{}\"",
                    n.as_str()
                ))
            })?;
            (
                false,
                c,
                Some(usize::try_from(k).map_err(|_| {
                    Exception::error(format!(
                        "expected non-negative integer but got \"{}\"",
                        n.as_str()
                    ))
                })?),
            )
        }
        [_, c] => (false, c, None),
        _ => unreachable!("checked"),
    };
    let name = name.as_str();
    let mut s = if name == "stdin" {
        interp.flush();
        let mut buf = String::new();
        let _ = std::io::stdin().read_to_string(&mut buf);
        interp.channels.stdin_eof = true;
        buf
    } else {
        let c = readable(interp, name)?;
        c.read(count)
            .map_err(|e| Exception::error(format!("error reading \"{name}\": {}", io_error(&e))))?
    };
    if nonewline && s.ends_with('\n') {
        s.pop();
    }
    crate::interp::eval::check_len(s.len())?;
    Ok(Value::from_string(s))
}

/// `puts` to a channel other than stdout and stderr.
pub(crate) fn write_to(interp: &mut Interp, name: &str, s: &str) -> Result<(), Exception> {
    if name == "stdin" {
        return Err(Exception::error("channel \"stdin\" wasn't opened for writing"));
    }
    let c = interp.channels.get(name)?;
    if !c.writable {
        return Err(Exception::error(format!("channel \"{name}\" wasn't opened for writing")));
    }
    c.write(s);
    if c.wbuf.len() >= 1 << 16 {
        c.flush()
            .map_err(|e| Exception::error(format!("error writing \"{name}\": {}", io_error(&e))))?;
    }
    Ok(())
}

fn cmd_flush(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 2, "channelId")?;
    let name = argv[1].as_str();
    match name {
        "stdout" | "stderr" => interp.flush_checked()?,
        "stdin" => return Err(Exception::error("channel \"stdin\" wasn't opened for writing")),
        _ => {
            let c = interp.channels.get(name)?;
            c.flush().map_err(|e| {
                Exception::error(format!("error flushing \"{name}\": {}", io_error(&e)))
            })?;
        }
    }
    Ok(Value::empty())
}

fn cmd_eof(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 2, "channelId")?;
    let name = argv[1].as_str();
    Ok(Value::from_bool(match name {
        "stdin" => interp.channels.stdin_eof,
        "stdout" | "stderr" => false,
        _ => interp.channels.get(name)?.eof,
    }))
}

fn cmd_seek(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 3, 4, "channelId offset ?origin?")?;
    let name = argv[1].as_str();
    let off = argv[2].as_int()?;
    let to = match argv.get(3).map_or("start", |v| v.as_str()) {
        "start" => SeekFrom::Start(u64::try_from(off).unwrap_or(0)),
        "current" => SeekFrom::Current(off),
        "end" => SeekFrom::End(off),
        other => {
            return Err(Exception::error(format!(
                "bad origin \"{other}\": must be start, current, or end"
            ))
            .with_error_code(&format!("TCL LOOKUP INDEX origin {other}")));
        }
    };
    let c = interp.channels.get(name)?;
    c.seek(to).map_err(|e| {
        Exception::error(format!("error during seek on \"{name}\": {}", io_error(&e)))
    })?;
    Ok(Value::empty())
}

fn cmd_tell(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, 2, "channelId")?;
    let name = argv[1].as_str();
    if matches!(name, "stdin" | "stdout" | "stderr") {
        return Ok(Value::from_int(-1));
    }
    let c = interp.channels.get(name)?;
    let pos = c.tell().map_err(|e| Exception::error(io_error(&e)))?;
    Ok(Value::from_int(pos as i64))
}

const OPTIONS: &[&str] =
    &["-blocking", "-buffering", "-buffersize", "-encoding", "-eofchar", "-translation"];

fn cmd_fconfigure(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "channelId ?-option value ...?")?;
    let name = argv[1].as_str();
    let std = matches!(name, "stdin" | "stdout" | "stderr");
    let binary = if std { false } else { interp.channels.get(name)?.binary };
    let value_of = |opt: &str| -> Value {
        Value::from(match opt {
            "-blocking" => "1",
            "-buffering" if name == "stderr" => "none",
            "-buffering" if name == "stdout" => "line",
            "-buffering" => "full",
            "-buffersize" => "4096",
            "-encoding" if binary => "binary",
            "-encoding" => "utf-8",
            "-eofchar" => "{}",
            "-translation" if binary => "lf",
            "-translation" => "auto",
            _ => "",
        })
    };
    match &argv[2..] {
        [] => {
            let mut out = Vec::new();
            for o in OPTIONS {
                out.push(Value::from(*o));
                out.push(value_of(o));
            }
            Ok(Value::from_list(out))
        }
        [opt] => {
            let o = super::pick_option(opt.as_str(), OPTIONS, "option")?;
            Ok(value_of(o))
        }
        pairs if pairs.len() % 2 == 0 => {
            for kv in pairs.chunks(2) {
                let o = super::pick_option(kv[0].as_str(), OPTIONS, "option")?;
                let v = kv[1].as_str();
                let to_binary = match o {
                    "-translation" => Some(v == "binary"),
                    "-encoding" => Some(v == "binary" || v == "iso8859-1"),
                    _ => None,
                };
                if let (Some(b), false) = (to_binary, std) {
                    interp.channels.get(name)?.binary = b;
                }
            }
            Ok(Value::empty())
        }
        _ => Err(Exception::wrong_args("fconfigure channelId ?-option value ...?")),
    }
}

fn cmd_chan(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "subcommand ?arg ...?")?;
    let subs =
        ["close", "configure", "eof", "flush", "gets", "names", "puts", "read", "seek", "tell"];
    let sub = pick_subcommand(argv[1].as_str(), &subs)?;
    let mut rest = vec![Value::from(sub)];
    rest.extend_from_slice(&argv[2..]);
    match sub {
        "close" => cmd_close(interp, &rest),
        "configure" => cmd_fconfigure(interp, &rest),
        "eof" => cmd_eof(interp, &rest),
        "flush" => cmd_flush(interp, &rest),
        "gets" => cmd_gets(interp, &rest),
        "read" => cmd_read(interp, &rest),
        "seek" => cmd_seek(interp, &rest),
        "tell" => cmd_tell(interp, &rest),
        "puts" => interp.invoke(&[&[Value::from("puts")], &argv[2..]].concat()),
        _ => {
            let mut names: Vec<Value> =
                ["stderr", "stdin", "stdout"].iter().map(|s| Value::from(*s)).collect();
            names.extend(interp.channels.files.keys().map(|k| Value::from(k.as_str())));
            let pattern = argv.get(2).map(|p| p.as_str().to_string());
            names.retain(|n| {
                pattern.as_deref().is_none_or(|p| super::glob_match(p, n.as_str(), false))
            });
            Ok(Value::from_list(names))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn access_modes_read_like_tcl() {
        assert_eq!(parse_access("r").unwrap(), [true, false, false, false, false, false, false]);
        assert_eq!(parse_access("w+").unwrap(), [true, true, false, true, true, false, false]);
        assert_eq!(parse_access("ab").unwrap(), [false, true, true, true, false, false, true]);
        assert!(parse_access("WRONLY CREAT").is_ok());
        assert!(parse_access("x").is_err());
    }
}
