//! Streaming evaluation of whole scripts: a file is read in windows that
//! end at an unescaped newline, commands run as soon as they are parsed, and
//! memory stays bounded by the longest command, not the file.
//!
//! Long generated scripts (a mesh is a million `vertex`/`tri` lines) take a
//! fast path: a scanner thread splits the next window into plain commands
//! (no quoting or substitution) and reads their numbers while this thread
//! runs the previous window. A command that is not plain is parsed and run
//! here in full, in order; the scanner never evaluates anything.

use std::io::Read;
use std::rc::Rc;
use std::sync::Arc;
use std::sync::mpsc::{Receiver, RecvTimeoutError, SyncSender, sync_channel};

use smallvec::SmallVec;

use super::cmdframe::{At, Text, Unit};
use super::error::{Code, Exception, TclResult};
use super::eval::{CommandKind, INTERRUPT_CODE, Interp, NumericFn};
use super::number::{self, Num};
use super::parser::{Parser, Plain, PlainScanner, PlainWord};
use super::value::Value;

/// Bytes read per window (a window grows to hold a longer command).
const WINDOW: usize = 1 << 16;

/// What the streaming evaluator carries from one window to the next.
#[derive(Default)]
struct StreamState {
    result: Value,
    /// The result of a trailing numeric command, not yet made a value.
    last_num: Option<Option<Num>>,
    spans: SmallVec<[PlainWord; 8]>,
    argv: SmallVec<[Value; 8]>,
    /// Values whose allocations the fast path reuses.
    pool: Vec<Value>,
    cache: [Option<CachedNumeric>; 2],
}

/// A numeric command found by name, valid while `Interp::cmd_epoch` holds.
struct CachedNumeric {
    epoch: u64,
    name: Box<str>,
    arity: usize,
    f: NumericFn,
}

impl StreamState {
    fn into_result(self) -> Value {
        match self.last_num {
            Some(Some(n)) => Value::from_num(n),
            Some(None) => Value::empty(),
            None => self.result,
        }
    }
}

/// The end of the last line in `buf` whose newline is not escaped by a
/// backslash (an odd run of backslashes before it).
fn safe_cut(buf: &[u8]) -> Option<usize> {
    let mut end = buf.len();
    while let Some(nl) = buf[..end].iter().rposition(|&c| c == b'\n') {
        let backslashes = buf[..nl].iter().rev().take_while(|&&c| c == b'\\').count();
        if backslashes % 2 == 0 {
            return Some(nl + 1);
        }
        end = nl;
    }
    None
}

fn window_room(bytes: usize) -> std::io::Result<()> {
    if bytes > super::eval::MAX_VALUE_LEN {
        return Err(std::io::Error::other(format!(
            "a command longer than {} bytes",
            super::eval::MAX_VALUE_LEN
        )));
    }
    crate::mem::reserve(bytes).map_err(std::io::Error::other)
}

/// What the scanner sends: a window, or why reading stopped (with the line
/// the unread text starts on).
type Scanned = Result<Batch, (u32, std::io::Error)>;

/// One window of source with its plain commands already scanned.
struct Batch {
    window: Arc<str>,
    /// (line, start, end, first word, word count) per plain command.
    cmds: Vec<(u32, u32, u32, u32, u32)>,
    words: Vec<PlainWord>,
    /// Where the first command that is not plain starts, and its line.
    stop: Option<(usize, u32)>,
    last: bool,
}

/// The scanner thread: reads windows, scans their plain commands.
/// The UTF-8 byte order mark.
pub const BOM: &[u8] = b"\xef\xbb\xbf";

/// Tcl's `-translation auto` on input: `\r\n` and a lone `\r` end a line
/// as `\n` does. Translates `buf[from..]` in place; `after_cr` carries a
/// `\r` at the end of one read over to the next.
pub(crate) fn translate_eol(buf: &mut Vec<u8>, from: usize, after_cr: &mut bool) {
    if !*after_cr && !buf[from..].contains(&b'\r') {
        return;
    }
    let mut w = from;
    for r in from..buf.len() {
        let c = buf[r];
        if c == b'\n' && std::mem::take(after_cr) {
            continue;
        }
        *after_cr = c == b'\r';
        buf[w] = if c == b'\r' { b'\n' } else { c };
        w += 1;
    }
    buf.truncate(w);
}

fn scan_windows(reader: Box<dyn Read + Send>, tx: SyncSender<Scanned>) {
    // Closed as soon as it is read to the end, before the last window goes
    // out: the script's file descriptor is free by the time its commands
    // run (`open` names channels by descriptor, as Tcl does).
    let mut reader = Some(reader);
    let mut buf: Vec<u8> = Vec::new();
    let mut after_cr = false;
    let mut eof = false;
    let mut line = 1u32;
    let mut spans = SmallVec::new();
    let mut first = true;
    loop {
        if !eof {
            let want = WINDOW.max(buf.len());
            // A command with no end in sight (`/dev/zero`): stop before it
            // passes the value cap or the memory budget.
            if let Err(e) = window_room(buf.len() + want) {
                let _ = tx.send(Err((line, e)));
                return;
            }
            let n0 = buf.len();
            let read = match reader.as_mut() {
                Some(r) => r.take(want as u64).read_to_end(&mut buf),
                None => Ok(0),
            };
            match read {
                Ok(_) => {
                    eof = buf.len() == n0;
                    // Fewer bytes than asked for: the reader is at its end
                    // (the next round reads nothing and ends).
                    if buf.len() - n0 < want {
                        reader = None;
                    }
                    translate_eol(&mut buf, n0, &mut after_cr);
                }
                Err(e) => {
                    let _ = tx.send(Err((line, e)));
                    return;
                }
            }
            // A UTF-8 byte order mark opening the file is not script text
            // (tclsh skips it too).
            if first && buf.starts_with(BOM) {
                buf.drain(..BOM.len());
            }
            first = false;
        }
        let cut = if eof {
            buf.len()
        } else {
            match safe_cut(&buf) {
                Some(c) => c,
                None => continue,
            }
        };
        if std::str::from_utf8(&buf[..cut]).is_err() {
            // Replace bad bytes (binary garbage) so the window is text.
            let fixed = String::from_utf8_lossy(&buf[..cut]).into_owned();
            buf.splice(..cut, fixed.into_bytes());
            continue;
        }
        let window: Arc<str> = Arc::from(std::str::from_utf8(&buf[..cut]).expect("checked above"));
        let mut batch = Batch {
            window: window.clone(),
            cmds: Vec::new(),
            words: Vec::new(),
            stop: None,
            last: eof,
        };
        let mut sc = PlainScanner::new(window.as_bytes(), line);
        loop {
            match sc.next(&mut spans) {
                Plain::End => break,
                Plain::Complex => {
                    let pos = sc.pos;
                    batch.stop = Some((pos, sc.line_at(pos)));
                    break;
                }
                Plain::Cmd { line, start, end } => {
                    if spans.is_empty() {
                        continue;
                    }
                    let first = batch.words.len() as u32;
                    batch.words.extend_from_slice(&spans);
                    batch.cmds.push((line, start, end, first, spans.len() as u32));
                }
            }
        }
        line = sc.line_at(cut);
        buf.drain(..cut);
        if tx.send(Ok(batch)).is_err() || eof {
            return;
        }
    }
}

impl Interp {
    /// Runs a whole script held in a string (the REPL, `-c`, `source`).
    pub fn eval_source(&mut self, src: &str, file: Option<&str>) -> TclResult {
        self.run_source(src, file, true)
    }

    /// `source`: a file's commands run as Tcl runs a sourced file, one
    /// compiled unit (the commands Tcl compiles inline, `if`, `while`,
    /// `catch`..., add no unit of their own), where the main script and
    /// the REPL evaluate each command directly.
    pub(crate) fn source_script(&mut self, src: &str, file: &str) -> TclResult {
        self.run_source(src, Some(file), false)
    }

    fn run_source(&mut self, src: &str, file: Option<&str>, direct: bool) -> TclResult {
        self.with_script_file(file, direct, |interp, file| {
            let mut st = StreamState::default();
            let mut p = Parser::new(Rc::from(src), file.clone(), 1);
            interp.run_window(&mut p, &mut st, file, false)?;
            Ok(st.into_result())
        })
    }

    /// Runs a script read from `reader` (a file, stdin), streaming. The
    /// reading thread is not waited for: on an interrupt it may be blocked
    /// in a read for ever (a pipe nobody writes to); it ends at its next
    /// window otherwise, finding the receiver gone.
    pub fn eval_reader(&mut self, file: Option<&str>, reader: Box<dyn Read + Send>) -> TclResult {
        self.with_script_file(file, true, |interp, file| {
            let (tx, rx) = sync_channel(2);
            std::thread::Builder::new()
                .name("scanner".into())
                .spawn(move || scan_windows(reader, tx))
                .map_err(|e| Exception::error(format!("couldn't start reading: {e}")))?;
            interp.run_batches(&rx, file)
        })
    }

    /// The next window from the scanner; waiting for it can be interrupted.
    fn next_batch(&self, rx: &Receiver<Scanned>) -> Result<Option<Scanned>, Exception> {
        let Some(flag) = self.interrupt else { return Ok(rx.recv().ok()) };
        loop {
            match rx.recv_timeout(std::time::Duration::from_millis(50)) {
                Ok(b) => return Ok(Some(b)),
                Err(RecvTimeoutError::Disconnected) => return Ok(None),
                Err(RecvTimeoutError::Timeout) => {
                    if flag.load(std::sync::atomic::Ordering::Relaxed) {
                        return Err(Exception::error("interrupted").with_error_code(INTERRUPT_CODE));
                    }
                }
            }
        }
    }

    fn with_script_file(
        &mut self,
        file: Option<&str>,
        direct: bool,
        f: impl FnOnce(&mut Interp, &Option<Rc<str>>) -> TclResult,
    ) -> TclResult {
        let file: Option<Rc<str>> = file.map(Rc::from);
        let saved_file = std::mem::replace(&mut self.script_file, file.clone());
        let outer_direct = std::mem::replace(&mut self.direct, direct);
        self.begin_unit(Unit::top(&file));
        if direct {
            self.unit_is_direct();
        }
        let r = f(self, &file);
        self.end_unit_frame();
        self.direct = outer_direct;
        self.script_file = saved_file;
        match r {
            Err(mut e) if e.code == Code::Error => {
                if let (Some(f), true) = (&file, e.script_line > 0) {
                    let t = format!("\n    (file \"{f}\" line {})", e.script_line);
                    e.trace.push_str(&t);
                }
                // The unit that ran the file logs its own command.
                e.logged = false;
                e.abs_line = 0;
                Err(e)
            }
            // `return` ends the file, as it ends a proc (`-code error` is an error).
            Err(e) if e.code == Code::Return => super::eval::finish_return(e),
            r => r,
        }
    }

    fn run_batches(&mut self, rx: &Receiver<Scanned>, file: &Option<Rc<str>>) -> TclResult {
        let mut st = StreamState::default();
        // A command that continues past its window: its text and line.
        let mut carry: Option<(String, u32)> = None;
        while let Some(batch) = self.next_batch(rx)? {
            let batch = batch.map_err(|(line, e)| {
                let name = file.as_deref().unwrap_or("stdin");
                let mut err = Exception::error(format!("error reading \"{name}\": {e}"));
                // Where the command that could not be read starts.
                let line = carry.as_ref().map_or(line, |c| c.1);
                err.loc = Some(super::error::Loc { file: file.clone(), line });
                err
            })?;
            let (text, line): (Rc<str>, u32) = match carry.take() {
                Some((mut rest, line)) => {
                    // One command longer than any value may be.
                    super::eval::check_len(rest.len() + batch.window.len())?;
                    rest.push_str(&batch.window);
                    (Rc::from(rest), line)
                }
                None => {
                    let w = &batch.window;
                    let text = Text::Shared(w.clone());
                    for &(line, start, end, first, n) in &batch.cmds {
                        let spans = &batch.words[first as usize..(first + n) as usize];
                        self.exec_plain(&text, line, start, end, spans, &mut st, file)?;
                    }
                    match batch.stop {
                        Some((pos, line)) => (Rc::from(&w[pos..]), line),
                        None => continue,
                    }
                }
            };
            let mut p = Parser::new(text.clone(), file.clone(), line);
            let used = self.run_window(&mut p, &mut st, file, !batch.last)?;
            if used < text.len() {
                let line = line + text[..used].bytes().filter(|&c| c == b'\n').count() as u32;
                carry = Some((text[used..].to_string(), line));
            }
        }
        Ok(st.into_result())
    }

    /// Runs one plain command: straight from its numbers when it is a
    /// numeric command, else with values made from its words.
    #[allow(clippy::too_many_arguments)]
    fn exec_plain(
        &mut self,
        source: &Text,
        line: u32,
        start: u32,
        end: u32,
        spans: &[PlainWord],
        st: &mut StreamState,
        file: &Option<Rc<str>>,
    ) -> Result<(), Exception> {
        let text = source.as_str();
        match self.try_numeric(text, spans, &mut st.cache) {
            Some(Ok(n)) => {
                st.last_num = Some(n);
                return Ok(());
            }
            Some(Err(mut e)) => {
                self.add_trace(
                    &mut e,
                    &text[start as usize..end as usize],
                    line,
                    1,
                    file,
                    self.direct,
                );
                return Err(e);
            }
            None => {}
        }
        for w in spans {
            let word = &text[w.start as usize..w.end as usize];
            let v = match st.pool.pop() {
                Some(mut v) => {
                    if !v.recycle(word) {
                        v = Value::from(word);
                    }
                    v
                }
                None => Value::from(word),
            };
            st.argv.push(v);
        }
        st.last_num = None;
        // Drop the previous result first so `lappend` can grow in place.
        drop(std::mem::take(&mut st.result));
        self.note_at(At::Plain(source.clone(), start, end, line));
        let r = self.invoke(&st.argv);
        st.pool.extend(st.argv.drain(..));
        st.pool.truncate(16);
        match r {
            Ok(v) => {
                st.result = v;
                Ok(())
            }
            Err(mut e) => {
                self.add_trace(
                    &mut e,
                    &text[start as usize..end as usize],
                    line,
                    1,
                    file,
                    self.direct,
                );
                Err(e)
            }
        }
    }

    /// Runs the commands of one window; returns how many bytes it used up
    /// (less than the window when the last command continues past it).
    fn run_window(
        &mut self,
        p: &mut Parser,
        st: &mut StreamState,
        file: &Option<Rc<str>>,
        more_coming: bool,
    ) -> Result<usize, Exception> {
        loop {
            // Fast path: plain words become recycled values, no parse tree.
            match p.next_plain(&mut st.spans) {
                Plain::End => return Ok(p.src().len()),
                Plain::Cmd { line, start, end } => {
                    let text = Text::Local(p.src().clone());
                    let spans = std::mem::take(&mut st.spans);
                    let r = self.exec_plain(&text, line, start, end, &spans, st, file);
                    st.spans = spans;
                    r?;
                    continue;
                }
                Plain::Complex => {}
            }
            let cmd_pos = p.pos();
            match p.next_command() {
                None => return Ok(p.src().len()),
                Some(Ok(cmd)) => {
                    st.last_num = None;
                    // Drop the previous result first so `lappend` can grow in place.
                    drop(std::mem::take(&mut st.result));
                    let cmd = Rc::new(cmd);
                    let at = || At::Loose(p.src().clone(), cmd.clone());
                    match self.eval_command(&cmd, at) {
                        Ok(v) => st.result = v,
                        Err(mut e) => {
                            let text = &p.src()[cmd.start as usize..cmd.end as usize];
                            self.add_trace(&mut e, text, cmd.line, 1, file, self.direct);
                            return Err(e);
                        }
                    }
                }
                Some(Err(pe)) if pe.incomplete && more_coming => return Ok(cmd_pos),
                Some(Err(pe)) => {
                    let src = p.src();
                    let text = &src[pe.cmd_start as usize..(pe.pos as usize).min(src.len())];
                    let mut e = Exception::error(pe.msg.clone());
                    self.add_trace(&mut e, text, pe.line, 1, file, self.direct);
                    return Err(e);
                }
            }
        }
    }

    /// Calls a numeric command straight from source spans when every
    /// argument is a plain number; `None` means "take the general path".
    fn try_numeric(
        &mut self,
        text: &str,
        spans: &[PlainWord],
        cache: &mut [Option<CachedNumeric>; 2],
    ) -> Option<Result<Option<Num>, Exception>> {
        let bytes = text.as_bytes();
        let name_bytes = &bytes[spans[0].start as usize..spans[0].end as usize];
        // Meshes alternate a few names: remember the last two lookups.
        let epoch = self.cmd_epoch;
        let hit =
            cache.iter().flatten().find(|c| c.epoch == epoch && c.name.as_bytes() == name_bytes);
        let (arity, f) = match hit {
            Some(c) => (c.arity, c.f.clone()),
            None => {
                let name = &text[spans[0].start as usize..spans[0].end as usize];
                let Some(CommandKind::Numeric(arity, _, f)) = self.commands.get(name) else {
                    return None;
                };
                let entry =
                    CachedNumeric { epoch, name: Box::from(name), arity: *arity, f: f.clone() };
                cache.swap(0, 1);
                cache[0] = Some(entry);
                (*arity, f.clone())
            }
        };
        if arity != spans.len() - 1 {
            return None;
        }
        let mut nums: SmallVec<[Num; 12]> = SmallVec::new();
        for w in &spans[1..] {
            match number::parse_simple_decimal(&bytes[w.start as usize..w.end as usize]) {
                Some(n) => nums.push(n),
                None => nums.push(number::parse_num(&text[w.start as usize..w.end as usize])?),
            }
        }
        if let Err(e) = self.enter() {
            return Some(Err(e));
        }
        let r = f(self, &nums);
        self.depth -= 1;
        Some(r)
    }
}
