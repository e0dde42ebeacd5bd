//! `exec` and command pipelines (`open |cmd`), as Tcl 8.6's tclPipe.c
//! reads them: commands joined by `|` (or `|&`, which pipes standard error
//! too), redirections `< file`, `<< value`, `<@ chan`, `> file`, `>> file`,
//! `2> file`, `2>> file`, `>& file`, `>>& file`, `>@ chan`, `2>@ chan`,
//! `2>@1`, the operator joined to its word or not, and a final `&` to run
//! in the background. `exec` returns what the last command wrote, less
//! one final newline; anything on standard error, or a non-zero exit,
//! makes it an error, worded and coded (`CHILDSTATUS pid code`) as Tcl's.
//!
//! Running a program is fenced by the host's policy (`Access::Run`):
//! `--safe` refuses it.

use std::fs::File;
use std::io::Read;
use std::process::{Child, Command, Stdio};

use super::chan::{FileChan, file_error};
use super::check_args;
use crate::interp::error::{Exception, TclResult};
use crate::interp::eval::{Access, Interp};
use crate::interp::value::Value;

pub(super) const COMMANDS: &[super::Entry] = &[(
    "exec",
    cmd_exec,
    "?-option ...? arg ?arg ...?",
    "run programs (a pipeline, with redirections) and return their output",
)];

/// Where a pipeline's input comes from.
enum Input {
    Inherit,
    File(String),
    Value(String),
}

/// Where a pipeline's standard output or error goes.
#[derive(Clone, PartialEq)]
enum Output {
    /// To the caller (`exec`'s result, or the channel `open` returns).
    Capture,
    Inherit,
    /// Standard error only: wherever standard output goes (`2>@1`).
    ToStdout,
    File(String, bool),
}

struct Pipeline {
    stages: Vec<(Vec<String>, bool)>,
    input: Input,
    stdout: Output,
    stderr: Output,
    background: bool,
}

/// The file or channel a redirection names: the rest of its word, or the
/// next word.
fn target(words: &[String], i: &mut usize, rest: &str, op: &str) -> Result<String, Exception> {
    if !rest.is_empty() {
        return Ok(rest.to_string());
    }
    *i += 1;
    words
        .get(*i)
        .cloned()
        .ok_or_else(|| Exception::error(format!("can't specify \"{op}\" as last word in command")))
}

/// `>@ chan` and friends: only the standard channels are real descriptors
/// a child can share here.
fn chan_output(name: &str) -> Result<Output, Exception> {
    match name {
        "stdout" | "stderr" => Ok(Output::Inherit),
        _ => Err(Exception::error(format!(
            "rayshell cannot redirect a program to channel \"{name}\" (only stdout and stderr)"
        ))),
    }
}

fn parse(words: &[String], capture_err: bool) -> Result<Pipeline, Exception> {
    let mut p = Pipeline {
        stages: vec![(Vec::new(), false)],
        input: Input::Inherit,
        stdout: Output::Capture,
        stderr: if capture_err { Output::Capture } else { Output::Inherit },
        background: false,
    };
    let mut words = words.to_vec();
    if words.last().is_some_and(|w| w == "&") {
        p.background = true;
        words.pop();
    }
    let mut i = 0;
    while i < words.len() {
        let w = words[i].clone();
        if w == "|" || w == "|&" {
            if p.stages.last().is_none_or(|s| s.0.is_empty()) || i + 1 == words.len() {
                return Err(Exception::error("illegal use of | or |& in command"));
            }
            p.stages.last_mut().expect("a stage").1 = w == "|&";
            p.stages.push((Vec::new(), false));
        } else if let Some(rest) = w.strip_prefix("<<") {
            p.input = Input::Value(target(&words, &mut i, rest, "<<")?);
        } else if let Some(rest) = w.strip_prefix("<@") {
            let name = target(&words, &mut i, rest, "<@")?;
            if name != "stdin" {
                return Err(Exception::error(format!(
                    "rayshell cannot redirect a program from channel \"{name}\" (only stdin)"
                )));
            }
            p.input = Input::Inherit;
        } else if let Some(rest) = w.strip_prefix('<') {
            p.input = Input::File(target(&words, &mut i, rest, "<")?);
        } else if let Some(rest) = w.strip_prefix("2>@") {
            p.stderr = if rest == "1" {
                Output::ToStdout
            } else {
                chan_output(&target(&words, &mut i, rest, "2>@")?)?
            };
        } else if let Some(rest) = w.strip_prefix("2>>") {
            p.stderr = Output::File(target(&words, &mut i, rest, "2>>")?, true);
        } else if let Some(rest) = w.strip_prefix("2>") {
            p.stderr = Output::File(target(&words, &mut i, rest, "2>")?, false);
        } else if let Some(after) = w.strip_prefix('>') {
            let mut rest = after;
            let append = rest.starts_with('>');
            if append {
                rest = &rest[1..];
            }
            let both = rest.starts_with('&');
            if both {
                rest = &rest[1..];
            }
            let to_chan = rest.starts_with('@');
            if to_chan {
                rest = &rest[1..];
            }
            let op = &w[..w.len() - rest.len()];
            let name = target(&words, &mut i, rest, op)?;
            p.stdout = if to_chan { chan_output(&name)? } else { Output::File(name, append) };
            if both {
                p.stderr = Output::ToStdout;
            }
        } else {
            p.stages.last_mut().expect("a stage").0.push(w);
        }
        i += 1;
    }
    if p.stages.iter().any(|s| s.0.is_empty()) {
        return Err(Exception::error(if p.stages.len() > 1 {
            "illegal use of | or |& in command"
        } else {
            "didn't specify command to execute"
        }));
    }
    Ok(p)
}

/// The processes of the `exec` pipeline being waited for (not those sent
/// to the background): a host that must end at once, past its grace after
/// Ctrl-C, hands them the signal first, as a terminal would have.
static WAITED: std::sync::Mutex<Vec<u32>> = std::sync::Mutex::new(Vec::new());

/// The processes `exec` is waiting for now.
pub fn waited_children() -> Vec<u32> {
    WAITED.lock().unwrap_or_else(|e| e.into_inner()).clone()
}

fn set_waited(pids: Vec<u32>) {
    *WAITED.lock().unwrap_or_else(|e| e.into_inner()) = pids;
}

/// Clears `WAITED` however the wait ends (an error on the way returns early).
struct Waiting;

impl Drop for Waiting {
    fn drop(&mut self) {
        set_waited(Vec::new());
    }
}

/// A started pipeline: its children, and the ends the caller keeps.
struct Running {
    children: Vec<Child>,
    stdin: Option<std::process::ChildStdin>,
    stdout: Option<std::io::PipeReader>,
    stderr: Option<std::io::PipeReader>,
}

fn open_out(interp: &Interp, path: &str, append: bool) -> Result<File, Exception> {
    interp.check_access(path, Access::Write)?;
    std::fs::OpenOptions::new()
        .write(true)
        .create(true)
        .append(append)
        .truncate(!append)
        .open(path)
        .map_err(|e| file_error("write file", path, &e))
}

fn spawn(interp: &mut Interp, p: &Pipeline, stdin_piped: bool) -> Result<Running, Exception> {
    for (argv, _) in &p.stages {
        interp.check_access(&argv[0], Access::Run)?;
    }
    // What the children write to our own streams comes after ours.
    interp.flush();
    let (err_reader, err_writer) = if p.stderr == Output::Capture {
        let (r, w) = std::io::pipe().map_err(|e| Exception::error(e.to_string()))?;
        (Some(r), Some(w))
    } else {
        (None, None)
    };
    let mut out_file = match &p.stdout {
        Output::File(path, append) => Some(open_out(interp, path, *append)?),
        _ => None,
    };
    let err_file = match &p.stderr {
        Output::File(path, append) => Some(open_out(interp, path, *append)?),
        _ => None,
    };
    let io = |e: std::io::Error| Exception::error(e.to_string());
    let mut children: Vec<Child> = Vec::new();
    let mut prev_out: Option<std::io::PipeReader> = None;
    let mut captured: Option<std::io::PipeReader> = None;
    let mut value_in = None;
    let n = p.stages.len();
    for (k, (argv, pipe_err)) in p.stages.iter().enumerate() {
        let last = k + 1 == n;
        let mut cmd = Command::new(&argv[0]);
        cmd.args(&argv[1..]);
        if let Some(prev) = prev_out.take() {
            cmd.stdin(Stdio::from(prev));
        } else if stdin_piped {
            cmd.stdin(Stdio::piped());
        } else {
            match &p.input {
                Input::Inherit => {}
                Input::File(path) => {
                    interp.check_access(path, Access::Read)?;
                    let f = File::open(path).map_err(|e| file_error("read file", path, &e))?;
                    cmd.stdin(Stdio::from(f));
                }
                Input::Value(v) => {
                    cmd.stdin(Stdio::piped());
                    value_in = Some(v.clone());
                }
            }
        }
        // Standard output: a pipe to the next command or to us, a file,
        // or ours. Standard error may share it (`|&`, `2>@1`, `>&`).
        let (out, out_twin): (Stdio, Option<Stdio>) = if !last || p.stdout == Output::Capture {
            let (r, w) = std::io::pipe().map_err(io)?;
            if last {
                captured = Some(r);
            } else {
                prev_out = Some(r);
            }
            let twin = w.try_clone().map_err(io)?;
            (Stdio::from(w), Some(Stdio::from(twin)))
        } else if let Some(f) = &out_file {
            let twin = f.try_clone().map_err(io)?;
            (Stdio::from(f.try_clone().map_err(io)?), Some(Stdio::from(twin)))
        } else {
            (Stdio::inherit(), Some(Stdio::inherit()))
        };
        cmd.stdout(out);
        let err: Stdio = if (*pipe_err && !last) || (last && p.stderr == Output::ToStdout) {
            out_twin.unwrap_or_else(Stdio::inherit)
        } else {
            match &p.stderr {
                Output::Capture => {
                    Stdio::from(err_writer.as_ref().expect("made above").try_clone().map_err(io)?)
                }
                Output::File(..) => {
                    Stdio::from(err_file.as_ref().expect("opened above").try_clone().map_err(io)?)
                }
                _ => Stdio::inherit(),
            }
        };
        cmd.stderr(err);
        let child = match cmd.spawn() {
            Ok(c) => c,
            Err(e) => {
                for mut c in children {
                    let _ = c.kill();
                    let _ = c.wait();
                }
                return Err(file_error("execute", &argv[0], &e));
            }
        };
        children.push(child);
    }
    let _ = out_file.take();
    drop(err_writer);
    let first = children.first_mut().expect("one stage at least");
    let mut stdin = first.stdin.take();
    if let Some(v) = value_in
        && let Some(pipe) = stdin.take()
    {
        // Fed from a thread, so a child that writes before it reads
        // cannot deadlock against us.
        std::thread::spawn(move || {
            use std::io::Write;
            let mut pipe = pipe;
            let _ = pipe.write_all(v.as_bytes());
        });
    }
    Ok(Running { children, stdin, stdout: captured, stderr: err_reader })
}

fn signal_names(sig: i32) -> (&'static str, &'static str) {
    match sig {
        1 => ("SIGHUP", "hangup"),
        2 => ("SIGINT", "interrupt"),
        3 => ("SIGQUIT", "quit signal"),
        4 => ("SIGILL", "illegal instruction"),
        6 => ("SIGABRT", "SIGABRT"),
        8 => ("SIGFPE", "floating-point exception"),
        9 => ("SIGKILL", "kill signal"),
        11 => ("SIGSEGV", "segmentation violation"),
        13 => ("SIGPIPE", "write on pipe with no readers"),
        14 => ("SIGALRM", "alarm clock"),
        15 => ("SIGTERM", "software termination signal"),
        _ => ("unknown signal", "unknown signal"),
    }
}

/// Waits for the children: `Err((message, errorCode))` for the first that
/// did not exit with 0 (Tcl reports the last such one's code).
fn wait_all(children: Vec<Child>) -> Result<(), (String, Option<String>)> {
    use std::os::unix::process::ExitStatusExt;
    let mut failure: Option<(String, Option<String>)> = None;
    for mut c in children {
        let pid = c.id();
        match c.wait() {
            Ok(st) => {
                if let Some(code) = st.code() {
                    if code != 0 {
                        failure = Some((String::new(), Some(format!("CHILDSTATUS {pid} {code}"))));
                    }
                } else if let Some(sig) = st.signal() {
                    let (id, msg) = signal_names(sig);
                    failure = Some((
                        format!("child killed: {msg}\n"),
                        Some(format!("CHILDKILLED {pid} {id} {{{msg}}}")),
                    ));
                }
            }
            Err(e) => failure = Some((format!("error waiting for process to exit: {e}"), None)),
        }
    }
    failure.map_or(Ok(()), Err)
}

fn decode(bytes: &[u8]) -> String {
    String::from_utf8_lossy(bytes).replace("\r\n", "\n")
}

fn cmd_exec(interp: &mut Interp, argv: &[Value]) -> TclResult {
    check_args(argv, 2, usize::MAX, "?-option ...? arg ?arg ...?")?;
    let (mut ignore_stderr, mut keep_newline) = (false, false);
    let mut i = 1;
    while i < argv.len() && argv[i].as_str().starts_with('-') {
        match argv[i].as_str() {
            "-ignorestderr" => ignore_stderr = true,
            "-keepnewline" => keep_newline = true,
            "--" => {
                i += 1;
                break;
            }
            o => {
                return Err(Exception::error(format!(
                    "bad option \"{o}\": must be -ignorestderr, -keepnewline, or --"
                ))
                .with_error_code(&format!("TCL LOOKUP INDEX option {o}")));
            }
        }
        i += 1;
    }
    if i == argv.len() {
        return Err(Exception::wrong_args("exec ?-option ...? arg ?arg ...?"));
    }
    let words: Vec<String> = argv[i..].iter().map(|v| v.as_str().to_string()).collect();
    let mut p = parse(&words, !ignore_stderr)?;
    if p.background {
        if p.stdout == Output::Capture {
            p.stdout = Output::Inherit;
        }
        if p.stderr == Output::Capture {
            p.stderr = Output::Inherit;
        }
        let run = spawn(interp, &p, false)?;
        let pids: Vec<Value> =
            run.children.iter().map(|c| Value::from_int(i64::from(c.id()))).collect();
        // Reaped by a thread, so no zombie outlives its parent's interest.
        std::thread::spawn(move || {
            let _ = wait_all(run.children);
        });
        return Ok(Value::from_list(pids));
    }
    let mut run = spawn(interp, &p, false)?;
    set_waited(run.children.iter().map(|c| c.id()).collect());
    let _waiting = Waiting;
    let err_thread = run.stderr.take().map(|mut r| {
        std::thread::spawn(move || {
            let mut buf = Vec::new();
            let _ = r.read_to_end(&mut buf);
            buf
        })
    });
    let mut out = Vec::new();
    if let Some(mut o) = run.stdout.take() {
        let mut chunk = [0u8; 65536];
        loop {
            match o.read(&mut chunk) {
                Ok(0) => break,
                Ok(n) => {
                    crate::interp::eval::check_len(out.len() + n)?;
                    out.extend_from_slice(&chunk[..n]);
                }
                Err(e) if e.kind() == std::io::ErrorKind::Interrupted => {}
                Err(e) => {
                    return Err(Exception::error(format!(
                        "error reading output from command: {e}"
                    )));
                }
            }
        }
    }
    drop(run.stdin.take());
    let waited = wait_all(std::mem::take(&mut run.children));
    let err_text = err_thread.and_then(|t| t.join().ok()).unwrap_or_default();
    let mut result = decode(&out);
    let mut error_code = None;
    let mut failed = false;
    let mut close_msg = String::new();
    if let Err((msg, code)) = waited {
        failed = true;
        close_msg = msg;
        error_code = code;
    }
    if !err_text.is_empty() {
        failed = true;
        close_msg = decode(&err_text);
    } else if failed && close_msg.is_empty() {
        close_msg = "child process exited abnormally".into();
    }
    result.push_str(&close_msg);
    if !keep_newline && result.ends_with('\n') {
        result.pop();
    }
    if failed {
        let mut e = Exception::error(result);
        if let Some(code) = error_code {
            e = e.with_error_code(&code);
        }
        return Err(e);
    }
    Ok(Value::from_string(result))
}

/// `open |cmd ?access?`: a channel on a pipeline, reading what its last
/// command writes (`r`) or writing what its first reads (`w`). Closing it
/// waits for the commands; a failure is `close`'s error.
pub(super) fn open_pipeline(
    interp: &mut Interp,
    spec: &str,
    write: bool,
) -> Result<FileChan, Exception> {
    let words: Vec<String> =
        Value::from(spec).as_list()?.iter().map(|v| v.as_str().to_string()).collect();
    let mut p = parse(&words, false)?;
    if write {
        if p.stdout == Output::Capture {
            p.stdout = Output::Inherit;
        }
        if !matches!(p.input, Input::Inherit) {
            return Err(Exception::error(
                "can't read input from both a file and a channel written to",
            ));
        }
    }
    let mut run = spawn(interp, &p, write)?;
    let file: File = if write {
        let pipe = run.stdin.take().ok_or_else(|| Exception::error("no pipe to write to"))?;
        File::from(std::os::fd::OwnedFd::from(pipe))
    } else {
        let pipe = run.stdout.take().ok_or_else(|| {
            Exception::error("the pipeline's output is redirected: nothing to read")
        })?;
        File::from(std::os::fd::OwnedFd::from(pipe))
    };
    Ok(FileChan::pipe(file, !write, write, std::mem::take(&mut run.children)))
}

/// Waits for a pipeline channel's commands when it is closed.
pub(super) fn close_pipeline(children: Vec<Child>) -> Result<(), Exception> {
    match wait_all(children) {
        Ok(()) => Ok(()),
        Err((msg, code)) => {
            let msg = if msg.is_empty() { "child process exited abnormally".into() } else { msg };
            let mut e = Exception::error(msg.trim_end_matches('\n').to_string());
            if let Some(code) = code {
                e = e.with_error_code(&code);
            }
            Err(e)
        }
    }
}
