//! The shell: everything that touches the outside world. It parses the
//! command line, owns the interpreter and its I/O (`StdHost`), runs scripts,
//! stdin or the REPL, and turns outcomes into exit codes.
//!
//! Exit codes (for farm managers: retry only 74 and 130):
//! 0 success; 1 a script error (or `exit 1`): retrying will not help;
//! 2 a usage error; 74 an I/O error writing an image (disk full, a path
//! that vanished): worth a retry; 130 interrupted (Ctrl-C, SIGTERM);
//! 70 an internal error; `exit N` in a script exits with N.

/// `eprintln!` that never panics: a closed or full stderr (`2>&1 | head
/// -1`, `2>/dev/full`) loses the message, not the run.
macro_rules! say {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stderr(), $($arg)*);
    }};
}

/// `println!` that never panics (a closed stdout ends nothing by itself).
macro_rules! show_line {
    ($($arg:tt)*) => {{
        use std::io::Write as _;
        let _ = writeln!(std::io::stdout(), $($arg)*);
    }};
}

mod args;
mod budget;
mod commands;
pub mod docs;
mod feedback;
mod frames;
mod nff;
pub mod obj;
mod preview;
pub mod repl;
pub mod safe;
mod stats;
mod structure;
mod surface;
mod term;

use std::cell::RefCell;
use std::io::{IsTerminal, Write};
use std::process::ExitCode;
use std::rc::Rc;

use crate::interp::{Code, Exception, Host, INTERRUPT_CODE, Interp, Value};

pub use args::Cli;
pub use args::options as args_list;
pub use feedback::{INTERRUPTED, ProgressMode};

/// `errorCode` of a failure to write an image; the exit status is `EXIT_IO`.
pub const IO_ERROR_CODE: &str = "RAYSHELL IO";
pub const EXIT_SCRIPT: i32 = 1;
pub const EXIT_USAGE: i32 = 2;
pub const EXIT_INTERNAL: i32 = 70;
pub const EXIT_IO: i32 = 74;
pub const EXIT_INTERRUPTED: i32 = 130;
/// `--time-limit` ran out (as timeout(1) says it).
pub const EXIT_TIMED_OUT: i32 = 124;
/// Standard output was closed by its reader: 128 + SIGPIPE, as a shell
/// reports a tool that died of it.
pub const EXIT_BROKEN_PIPE: i32 = 141;

/// The error a cancelled render or script ends with.
pub fn interrupted() -> Exception {
    Exception::error("interrupted").with_error_code(INTERRUPT_CODE)
}

/// Stack for the interpreter thread: deep (but bounded) Tcl recursion must
/// hit the interpreter's own limit long before the native stack runs out.
pub const INTERP_STACK_BYTES: usize = 512 << 20;

/// Runs `f` on a thread with the interpreter's large stack and waits for it.
pub fn on_big_stack<T: Send + 'static>(
    f: impl FnOnce() -> T + Send + 'static,
) -> std::thread::Result<T> {
    std::thread::Builder::new()
        .name("interp".into())
        .stack_size(INTERP_STACK_BYTES)
        .spawn(f)
        .map_err(|e| Box::new(e) as Box<dyn std::any::Any + Send>)?
        .join()
}

/// Real stdout (buffered: `feedback::STDOUT`) and stderr.
pub struct StdHost {
    out: &'static std::sync::Mutex<std::io::BufWriter<std::io::Stdout>>,
}

impl StdHost {
    pub fn new() -> StdHost {
        StdHost { out: &feedback::STDOUT }
    }

    fn out(&self) -> std::sync::MutexGuard<'_, std::io::BufWriter<std::io::Stdout>> {
        self.out.lock().unwrap_or_else(|e| e.into_inner())
    }
}

impl Default for StdHost {
    fn default() -> Self {
        StdHost::new()
    }
}

impl Host for StdHost {
    fn stdout(&mut self, s: &str) -> std::io::Result<()> {
        self.out().write_all(s.as_bytes())
    }
    /// Messages on stderr never fail the script: a closed or full stderr
    /// (`2>&1 | head -1`, `2>/dev/full`) only loses them.
    fn stderr(&mut self, s: &str) -> std::io::Result<()> {
        let _ = self.out().flush();
        let _ = std::io::stderr().write_all(s.as_bytes());
        Ok(())
    }
    fn read_file(&mut self, path: &str) -> std::io::Result<String> {
        read_text(path)
    }
    fn flush(&mut self) -> std::io::Result<()> {
        self.out().flush()
    }
}

/// Output captured in memory, for tests and embedding.
#[derive(Clone, Default)]
pub struct CaptureHost {
    pub out: Rc<RefCell<String>>,
    pub err: Rc<RefCell<String>>,
}

impl Host for CaptureHost {
    fn stdout(&mut self, s: &str) -> std::io::Result<()> {
        self.out.borrow_mut().push_str(s);
        Ok(())
    }
    fn stderr(&mut self, s: &str) -> std::io::Result<()> {
        self.err.borrow_mut().push_str(s);
        Ok(())
    }
    fn read_file(&mut self, path: &str) -> std::io::Result<String> {
        read_text(path)
    }
}

/// Reads a file as text; bytes that are not UTF-8 become U+FFFD rather
/// than an error, as a binary-garbage scene should give a Tcl error.
pub fn read_text(path: &str) -> std::io::Result<String> {
    let p = path.to_string();
    let mut bytes = feedback::blocking(path, move || read_bounded(&p))
        .map_err(|_| std::io::Error::other("interrupted"))??;
    // A UTF-8 byte order mark is not text (tclsh's `source` skips it).
    if bytes.starts_with(b"\xef\xbb\xbf") {
        bytes.drain(..3);
    }
    Ok(match String::from_utf8(bytes) {
        Ok(s) => s,
        Err(e) => String::from_utf8_lossy(e.as_bytes()).into_owned(),
    })
}

/// Reads a whole file, refusing one past the value cap or the memory
/// budget (`/dev/zero` has no end) and stopping at Ctrl-C.
fn read_bounded(path: &str) -> std::io::Result<Vec<u8>> {
    let f = safe::open_read(path).map_err(|e| match e {
        safe::ReadError::Io(e) => e,
        refused => std::io::Error::other(refused.message(path)),
    })?;
    read_all(f)
}

fn read_all(mut f: std::fs::File) -> std::io::Result<Vec<u8>> {
    use std::io::Read;
    const CHUNK: usize = 1 << 20;
    let mut bytes = Vec::new();
    loop {
        if bytes.len() > crate::interp::MAX_VALUE_LEN {
            return Err(std::io::Error::other(format!(
                "file longer than {} bytes",
                crate::interp::MAX_VALUE_LEN
            )));
        }
        crate::mem::room(&bytes, CHUNK).map_err(std::io::Error::other)?;
        if feedback::INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed) {
            return Err(std::io::Error::other("interrupted"));
        }
        if (&mut f).take(CHUNK as u64).read_to_end(&mut bytes)? == 0 {
            return Ok(bytes);
        }
    }
}

/// A whole file a scene command reads (an image, the sky), opened through
/// the `--safe` gate, within the memory budget, stopping at Ctrl-C: the
/// errors are Tcl's (`couldn't read "F": why`).
pub fn read_scene_file(path: &str) -> Result<Vec<u8>, Exception> {
    let p = path.to_string();
    feedback::blocking(path, move || {
        safe::open_read(&p).and_then(|f| read_all(f).map_err(safe::ReadError::Io))
    })
    .map_err(|_| interrupted())?
    .map_err(|e| {
        if feedback::INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed) {
            interrupted()
        } else {
            e.into_exception(path)
        }
    })
}

/// An interpreter with the rayshell commands, and the scene they change.
pub struct Session {
    pub interp: Interp,
    pub scene: Rc<RefCell<crate::scene::Builder>>,
    pub state: Rc<RefCell<stats::ShellState>>,
}

impl Session {
    pub fn new(host: Box<dyn Host>) -> Session {
        let mut interp = Interp::new(host);
        if safe::active() {
            interp.set_fs_policy(Box::new(safe::check));
        }
        register_shell_commands(&mut interp);
        let scene = Rc::new(RefCell::new(crate::scene::Builder::new()));
        let state = Rc::new(RefCell::new(stats::ShellState::default()));
        commands::register(&mut interp, scene.clone(), state.clone());
        Session { interp, scene, state }
    }
}

/// A new interpreter with the rayshell commands registered.
pub fn new_interp(host: Box<dyn Host>) -> Interp {
    Session::new(host).interp
}

/// What Tcl takes from the process's environment: the `env` array,
/// `tcl_platform(user)` and `(osVersion)`, `info nameofexecutable`, and
/// `auto_path` (`$TCLLIBPATH`, then where Debian keeps Tcl packages, so
/// `package require` finds script packages as tclsh does).
///
/// Under `--safe` a scene sees none of it: the environment holds tokens,
/// paths and names that are the user's, not the scene's (`docs/safe.md`).
fn set_environment(interp: &mut Interp) {
    if safe::active() {
        let _ = interp.eval(&Value::from("array set ::env {}"));
        let _ = interp.set_var("tcl_platform(user)", Value::from(""));
        return;
    }
    for (k, v) in std::env::vars_os() {
        if let (Some(k), Some(v)) = (k.to_str(), v.to_str()) {
            let _ = interp.set_var(&format!("env({k})"), Value::from(v));
        }
    }
    let user = std::env::var("USER").or_else(|_| std::env::var("LOGNAME")).unwrap_or_default();
    let _ = interp.set_var("tcl_platform(user)", Value::from(user.as_str()));
    if let Ok(release) = std::fs::read_to_string("/proc/sys/kernel/osrelease") {
        let _ = interp.set_var("tcl_platform(osVersion)", Value::from(release.trim()));
    }
    if let Ok(exe) = std::env::current_exe() {
        interp.executable = exe.to_string_lossy().into_owned();
    }
    let mut path: Vec<Value> = std::env::var("TCLLIBPATH")
        .map(|p| p.split_whitespace().map(Value::from).collect())
        .unwrap_or_default();
    for dir in
        ["/usr/share/tcltk/tcl8.6", "/usr/share/tcltk", "/usr/lib/tcltk", "/usr/local/lib/tcltk"]
    {
        path.push(Value::from(dir));
    }
    let _ = interp.set_var("auto_path", Value::from_list(path));
}

fn register_shell_commands(interp: &mut Interp) {
    set_environment(interp);
    interp.register_host(
        "help",
        "?topic|command?",
        "the commands by topic, a topic's commands, or one command whole",
        |interp, argv| {
            crate::interp::check_args(argv, 1, 2, "?command?")?;
            Ok(Value::from_string(help_text(interp, argv.get(1).map(|v| v.as_str()))?))
        },
    );
}

pub fn help_text(interp: &Interp, name: Option<&str>) -> Result<String, Exception> {
    if let Some(text) = name.and_then(|n| help_topic(interp, n)) {
        return Ok(text);
    }
    match name {
        Some(n) => match (interp.help(n), docs::find(n)) {
            (Some((usage, _)), Some(doc)) => {
                let mut out = format!("{n} {usage}\n    {}", doc.meaning);
                if !doc.default.is_empty() {
                    out.push_str(&format!("\n    default: {}", doc.default));
                }
                out.push_str(&format!("\n    example: {}", doc.example));
                Ok(out)
            }
            (Some((usage, summary)), None) => Ok(format!("{n} {usage}\n    {summary}")),
            (None, _) if interp.has_command(n) => Ok(format!("{n}: a procedure")),
            (None, _) => Err(Exception::error(format!("no help for \"{n}\": no such command"))),
        },
        None => Ok(help_overview(interp)),
    }
}

/// `help` alone: the scene commands by topic, each topic with what it is
/// for and its commands' names, then Tcl's.
fn help_overview(interp: &Interp) -> String {
    let mut out = vec![
        "Scene commands by topic (help TOPIC: each with a line; help NAME: one command whole):"
            .to_string(),
    ];
    for (topic, what, names) in docs::TOPICS {
        out.push(format!("  {topic:<10} {what}"));
        let indent = " ".repeat(13);
        let mut line = indent.clone();
        for n in names.iter() {
            if line.len() + n.len() > 78 {
                out.push(std::mem::replace(&mut line, indent.clone()).trim_end().to_string());
            }
            line.push_str(n);
            line.push(' ');
        }
        out.push(line.trim_end().to_string());
    }
    let tcl = tcl_commands(interp);
    out.push(format!("  {:<10} the language's own commands ({}): help tcl", "tcl", tcl.len()));
    out.join("\n")
}

/// The commands that are not scene commands: Tcl's, and the procs the
/// script defined.
fn tcl_commands(interp: &Interp) -> Vec<String> {
    interp.help_names().into_iter().filter(|n| docs::topic_of(n).is_none()).collect()
}

/// `help TOPIC`: each command of the topic with its usage and a line.
fn help_topic(interp: &Interp, topic: &str) -> Option<String> {
    let (what, names): (&str, Vec<String>) = match topic {
        "tcl" => ("the language's own commands", tcl_commands(interp)),
        t => {
            let (_, what, names) = docs::TOPICS.iter().find(|x| x.0 == t)?;
            (what, names.iter().map(|n| n.to_string()).collect())
        }
    };
    let rows: Vec<(String, &str)> = names
        .iter()
        .map(|n| {
            let (usage, short) = interp.help(n).unwrap_or(("", ""));
            (format!("{n} {usage}").trim_end().to_string(), short)
        })
        .collect();
    let width = rows.iter().map(|r| r.0.chars().count()).filter(|&w| w <= 40).max().unwrap_or(0);
    let mut out = vec![format!("{topic}: {what}")];
    for (usage, short) in rows {
        out.push(format!("  {usage:width$}  {short}").trim_end().to_string());
    }
    Some(out.join("\n"))
}

/// For an error from an unknown command, the closest known name, as a
/// hint (` (did you mean "sphere"?)`); Tcl's message itself, which
/// `catch` sees, is left as tclsh words it.
pub fn did_you_mean(interp: &Interp, e: &Exception) -> Option<String> {
    let code = e.error_code();
    let name = code.as_str().strip_prefix("TCL LOOKUP COMMAND ")?;
    let name = name.trim_start_matches(':');
    // Nearest first; of those as near, one with the same letters (a
    // transposition: `camera_form` is `camera_from`, not `camera_forw`).
    let letters = |s: &str| {
        let mut v: Vec<char> = s.chars().collect();
        v.sort_unstable();
        v
    };
    let mine = letters(name);
    let best = interp
        .command_names()
        .into_iter()
        .map(|c| (strsim::osa_distance(name, c.trim_start_matches(':')), letters(&c) != mine, c))
        .filter(|(d, _, c)| *d > 0 && *d <= (name.len() / 3).clamp(1, 3) && !c.contains("::"))
        .min()?;
    Some(format!("did you mean \"{}\"?", best.2))
}

/// Prints an uncaught error as `file:line: message` plus the Tcl trace.
pub fn report_error(interp: &mut Interp, e: &Exception) {
    interp.flush();
    let info = e.error_info();
    let mut text = e.located_message();
    if let Some(hint) = did_you_mean(interp, e) {
        text.push_str(&format!(" ({hint})"));
    }
    match info.strip_prefix(e.message()) {
        Some(trace) => text.push_str(trace),
        // An -errorinfo of the script's own, not led by the message.
        None => {
            text.push('\n');
            text.push_str(info);
        }
    }
    text.push('\n');
    let _ = interp.write_stderr(&text);
}

/// The number of the last line of a script (where the render that follows
/// it is said to happen).
pub(crate) fn last_line(src: &[u8]) -> u32 {
    let newlines = src.iter().filter(|&&b| b == b'\n').count();
    let ends_open = !src.is_empty() && !src.ends_with(b"\n");
    (newlines + ends_open as usize).max(1) as u32
}

/// An error of the render that follows a script, placed at the script's
/// last line when it has no place of its own.
pub(crate) fn at_end_of(mut e: Exception, file: &str, line: u32) -> Exception {
    if e.loc.is_none() {
        e.loc = Some(crate::interp::Loc { file: Some(file.into()), line });
    }
    e
}

/// Turns the outcome of a top-level script into an exit code.
pub fn finish(interp: &mut Interp, r: Result<Value, Exception>) -> i32 {
    // Output still buffered must reach stdout, or the run failed.
    let r = match (r, interp.flush_checked()) {
        (Ok(_), Err(e)) => Err(e),
        (r, _) => r,
    };
    // `return -code error` at the top level is an error, as in tclsh.
    let r = match r {
        Err(e) if e.code == Code::Return && e.return_code == Some(Code::Error) => {
            let mut err = Exception::error(e.value.as_str().to_string());
            err.error_code = e.error_code.clone();
            err.loc = e.loc.clone();
            Err(err)
        }
        r => r,
    };
    let code = match r {
        // A Ctrl-C that came during the last command, which finished
        // without looking: the run did not end as asked, so it is not 0.
        Ok(_) if feedback::INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed) => {
            let why = if feedback::TIMED_OUT.load(std::sync::atomic::Ordering::Relaxed) {
                "time limit reached (--time-limit)"
            } else {
                "interrupted"
            };
            let _ = interp.write_stderr(&format!("raytrace: {why}\n"));
            exit_code_of(&interrupted())
        }
        Ok(_) => 0,
        Err(e) => match e.code {
            // As a process's status: the low byte (`exit -1` is 255).
            Code::Exit(n) => n & 0xff,
            Code::Return => 0,
            Code::Other(n) => {
                let mut err = Exception::error(format!("command returned bad code: {n}"));
                err.loc = e.loc.clone();
                report_error(interp, &err);
                1
            }
            Code::Break | Code::Continue => {
                let word = if e.code == Code::Break { "break" } else { "continue" };
                let mut err = Exception::error(format!("invoked \"{word}\" outside of a loop"));
                err.loc = e.loc.clone();
                report_error(interp, &err);
                1
            }
            // Whoever read standard output has stopped (`| head`): end
            // quietly, as a Unix tool killed by SIGPIPE does.
            Code::Error if e.error_code().as_str().starts_with("POSIX EPIPE") => EXIT_BROKEN_PIPE,
            Code::Error => {
                report_error(interp, &e);
                if feedback::TIMED_OUT.load(std::sync::atomic::Ordering::Relaxed) {
                    let _ = interp.write_stderr("raytrace: time limit reached (--time-limit)\n");
                }
                exit_code_of(&e)
            }
        },
    };
    interp.flush();
    code
}

/// The exit status for an uncaught error, by its `errorCode`.
pub fn exit_code_of(e: &Exception) -> i32 {
    match e.error_code().as_str() {
        c if c.starts_with("POSIX EPIPE") => EXIT_BROKEN_PIPE,
        _ if feedback::TIMED_OUT.load(std::sync::atomic::Ordering::Relaxed) => EXIT_TIMED_OUT,
        INTERRUPT_CODE => EXIT_INTERRUPTED,
        // Whatever failed on the way out of an interrupt (a read, a write).
        _ if feedback::INTERRUPTED.load(std::sync::atomic::Ordering::Relaxed) => EXIT_INTERRUPTED,
        IO_ERROR_CODE => EXIT_IO,
        _ => EXIT_SCRIPT,
    }
}

fn set_argv(interp: &mut Interp, argv0: &str, args: &[String]) {
    let list: Vec<Value> = args.iter().map(|a| Value::from(a.as_str())).collect();
    let _ = interp.set_var("argv0", Value::from(argv0));
    let _ = interp.set_var("argc", Value::from_int(args.len() as i64));
    let _ = interp.set_var("argv", Value::from_list(list));
}

/// The program: parse arguments, then run a script, `-c`, stdin or the REPL.
pub fn main() -> ExitCode {
    budget::fit_address_space();
    // A coroutine's stack that cannot be mapped is a Tcl error, not a
    // message from the crate that maps it.
    let default_hook = std::panic::take_hook();
    std::panic::set_hook(Box::new(move |info| {
        if !crate::interp::making_a_stack() {
            default_hook(info);
        }
    }));
    let cli = match args::parse() {
        Ok(c) => c,
        Err(code) => return ExitCode::from(code),
    };
    if let Some(shell) = cli.completions {
        use clap::CommandFactory;
        clap_complete::generate(shell, &mut Cli::command(), "raytrace", &mut std::io::stdout());
        return ExitCode::SUCCESS;
    }
    if let Some(n) = cli.threads
        && let Err(e) = rayon::ThreadPoolBuilder::new().num_threads(n as usize).build_global()
    {
        say!("raytrace: cannot set up {n} threads: {e}");
        return ExitCode::from(2);
    }
    if let Err(msg) = budget::apply(cli.max_memory) {
        say!("raytrace: {msg}");
        return ExitCode::from(EXIT_USAGE as u8);
    }
    feedback::catch_interrupts();
    if let Some(t) = cli.time_limit {
        feedback::limit_time(t);
    }
    // The interpreter runs on a thread with a large stack (see above).
    let code = match on_big_stack(move || run(cli)) {
        Ok(code) => code,
        _ => {
            say!("raytrace: internal error (please report it)");
            EXIT_INTERNAL
        }
    };
    ExitCode::from(code.clamp(0, 255) as u8)
}

/// A session set up as the command line asks (stats, progress, crop...).
fn new_session(cli: &Cli) -> Result<Session, String> {
    let mut session = Session::new(Box::new(StdHost::new()));
    session.interp.interrupt = Some(&feedback::INTERRUPTED);
    session.scene.borrow_mut().sampling.base_seed = cli.seed;
    session.scene.borrow_mut().sampling.noise_target = cli.noise_target;
    let mut st = session.state.borrow_mut();
    st.print_stats = cli.stats;
    st.feedback =
        feedback::Feedback::new(if cli.quiet { ProgressMode::None } else { cli.progress });
    st.feedback.progressive = cli.progressive;
    if let Some(c) = &cli.crop {
        let r = crate::render::Rect { x0: c[0], y0: c[1], x1: c[2], y1: c[3] };
        if r.x1 <= r.x0 || r.y1 <= r.y0 {
            return Err(format!(
                "--crop {} {} {} {}: the region is empty (X1 must exceed X0, Y1 Y0)",
                c[0], c[1], c[2], c[3]
            ));
        }
        st.feedback.crop = Some(r);
    }
    if cli.preview {
        st.feedback.preview = Some(preview::Preview::open()?);
    }
    drop(st);
    Ok(session)
}

/// What `--safe` lets a scene reach (`docs/safe.md`): reads beneath its
/// own directory and the `--allow-read` ones (a scene from standard input
/// or `-c` has no directory of its own); new pictures in the output
/// directory (the output file's, else the current one), and the output
/// file itself; nothing else.
fn safe_policy(cli: &Cli) -> safe::Policy {
    let dir_of = |p: &std::path::Path| match p.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => std::path::PathBuf::from("."),
    };
    let output = match (&cli.command, &cli.script, &cli.output) {
        (Some(_), Some(out), None) => Some(out),
        (_, _, out) => out.as_ref(),
    };
    let out_dir = output.map_or_else(|| std::path::PathBuf::from("."), |o| dir_of(o));
    let mut read: Vec<std::path::PathBuf> = cli.allow_read.clone();
    if let (None, Some(s)) = (&cli.command, &cli.script)
        && s.as_os_str() != "-"
    {
        read.push(dir_of(s));
    }
    safe::Policy {
        read,
        images: vec![out_dir],
        outputs: output.into_iter().cloned().collect(),
        ..Default::default()
    }
}

fn run(cli: Cli) -> i32 {
    let done = |r: Result<(), (i32, String)>| match r {
        Ok(()) => 0,
        Err((code, msg)) => {
            say!("raytrace: {msg}");
            code
        }
    };
    if let Some(paths) = &cli.merge {
        return done(frames::merge(&paths[0], &paths[1..]));
    }
    if let Some(paths) = &cli.movie {
        return done(frames::movie(&paths[0], &paths[1..], cli.fps));
    }
    if cli.safe
        && let Err(msg) = safe::install(safe_policy(&cli))
    {
        say!("raytrace: {msg}");
        return EXIT_USAGE;
    }
    if cli.frames.is_some() {
        return frames::run_batch(&cli);
    }
    let session = match new_session(&cli) {
        Ok(s) => s,
        Err(msg) => {
            say!("raytrace: {msg}");
            return EXIT_USAGE;
        }
    };
    // With -c, a first positional argument is the output file.
    let output = match (&cli.command, &cli.script, &cli.output) {
        (Some(_), Some(_), Some(extra)) => {
            say!(
                "raytrace: with -c, only an output file may follow, not also \"{}\"",
                extra.display()
            );
            return EXIT_USAGE;
        }
        (Some(_), Some(out), None) => Some(out.clone()),
        (_, _, out) => out.clone(),
    };
    // A mistyped output name fails now, not after a long script.
    if let Some(out) = &output
        && let Err(msg) = check_output(out)
    {
        say!("raytrace: {msg}");
        return EXIT_USAGE;
    }
    let state = session.state.clone();
    let scene = session.scene.clone();
    let mut interp = session.interp;
    let (r, file, end) = if let Some(cmd) = &cli.command {
        set_argv(&mut interp, "raytrace", &cli.args);
        // Errors are placed as `-c:LINE:`.
        (interp.eval_source(cmd, Some("-c")), None, None)
    } else {
        match &cli.script {
            Some(path) if path.as_os_str() != "-" => {
                let path_str = path.to_string_lossy().into_owned();
                set_argv(&mut interp, &path_str, &cli.args);
                if path.is_dir() {
                    say!(
                        "raytrace: couldn't read file \"{path_str}\": illegal operation on a directory"
                    );
                    return EXIT_SCRIPT;
                }
                let p = path.clone();
                let opened = match feedback::blocking(&path_str, move || std::fs::File::open(p)) {
                    Ok(r) => r,
                    Err(_) => return exit_code_of(&interrupted()),
                };
                let f = match opened {
                    Ok(f) => f,
                    Err(e) => {
                        say!("raytrace: couldn't read file \"{path_str}\": {}", io_reason(&e));
                        return EXIT_SCRIPT;
                    }
                };
                let r = interp.eval_reader(Some(&path_str), Box::new(f));
                (r, Some(path_str), None)
            }
            None if std::io::stdin().is_terminal() => return repl::run(&mut interp, &state),
            // No script, or `-`: the script is standard input.
            _ => {
                set_argv(&mut interp, "raytrace", &cli.args);
                let r = interp.eval_reader(Some("stdin"), Box::new(std::io::stdin()));
                (r, Some("stdin".to_string()), Some(1))
            }
        }
    };
    // An error of what follows the script (the render of the output, the
    // last flush of stdout) is placed at the script's last line (read
    // again only for the message).
    let at_end = |e: Exception| match (&file, &cli.command) {
        (Some(f), _) => {
            let line = end.unwrap_or_else(|| std::fs::read(f).map(|b| last_line(&b)).unwrap_or(1));
            at_end_of(e, f, line)
        }
        (None, Some(cmd)) => at_end_of(e, "-c", last_line(cmd.as_bytes())),
        (None, None) => e,
    };
    let r = match (r, &output) {
        (Ok(_), Some(out)) => {
            let argv = [Value::from("render"), Value::from(out.to_string_lossy().as_ref())];
            interp.invoke(&argv).map_err(at_end)
        }
        (r, _) => r,
    };
    // What is still buffered for stdout is written now, so a failure (a
    // full disk) is placed like any other error.
    let r = r.and_then(|v| interp.flush_checked().map(|_| v).map_err(at_end));
    let quiet = cli.quiet || cli.progress == ProgressMode::None;
    if r.is_ok() && output.is_none() && state.borrow().renders == 0 && !quiet {
        let b = scene.borrow();
        if !b.prims.is_empty() || !b.lights.is_empty() {
            let (name, how) = match file.as_deref() {
                Some("stdin") if cli.script.as_ref().is_none_or(|s| s.as_os_str() == "-") => {
                    ("the script".to_string(), "raytrace - out.png".to_string())
                }
                Some(f) => (f.to_string(), format!("raytrace {f} out.png")),
                None => ("the script".to_string(), "raytrace -c SCRIPT out.png".to_string()),
            };
            say!(
                "raytrace: {name} built a scene but rendered nothing; name an output file \
                 ({how}) or call `render out.png` in the script"
            );
        }
    }
    finish(&mut interp, r)
}

/// Checks an output file's name alone: a known extension, not a
/// directory, a last name of at most 255 bytes (mistakes that no retry
/// mends: usage errors, said before the script runs).
pub(super) fn check_output_name(path: &std::path::Path) -> Result<(), String> {
    let name = path.to_string_lossy();
    if crate::image::Format::from_path(&name).is_none() {
        return Err(format!(
            "unknown image format for \"{name}\": the name must end in .ppm, .png or .pfm"
        ));
    }
    if path.is_dir() {
        return Err(format!("can't write \"{name}\": it is a directory"));
    }
    if path.file_name().is_some_and(|n| n.len() > 255) {
        return Err(format!(
            "can't write \"{}...\": a file name holds at most 255 bytes",
            name.chars().take(40).collect::<String>()
        ));
    }
    Ok(())
}

/// Checks an output file's name before any work: a known extension, and a
/// directory that exists and takes new files.
fn check_output(path: &std::path::Path) -> Result<(), String> {
    check_output_name(path)?;
    let name = path.to_string_lossy();
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => std::path::Path::new("."),
    };
    if !dir.is_dir() {
        return Err(format!("can't write \"{name}\": no directory \"{}\"", dir.display()));
    }
    // Try the directory as the render will: a new file beside the output.
    let probe = dir.join(format!(".rayshell-probe.{}", std::process::id()));
    match std::fs::OpenOptions::new().write(true).create_new(true).open(&probe) {
        Ok(_) => {
            let _ = std::fs::remove_file(&probe);
            Ok(())
        }
        Err(e) => Err(format!("can't write \"{name}\": {}", io_reason(&e))),
    }
}

/// A file written atomically: into a temporary name in the same directory,
/// put in place of the final name by `commit`, so no reader ever sees half
/// a file, whatever stops the program. Dropped without `commit`, it removes
/// the temporary file. It is not synced to the disk (an `fsync` took 6 to
/// 10 ms of a 1024x1024 frame's 80 here): a power cut may lose the latest
/// pictures, as with other renderers, but never shows a program's crash.
///
/// On Linux a file that replaces an existing one swaps names with it in
/// one step (`renameat2` with `RENAME_EXCHANGE`) and the old one is then
/// removed: at every moment the name holds one whole picture, as with a
/// rename over it, without the write-out that ext4 starts (and waits to
/// submit) when a file is renamed over another (its `auto_da_alloc`: 1.7
/// to 2.6 ms for a 3 MB picture here, a tenth of a quick re-render).
pub struct AtomicFile {
    tmp: std::path::PathBuf,
    path: std::path::PathBuf,
    file: Option<std::io::BufWriter<feedback::Cancellable<std::fs::File>>>,
}

impl AtomicFile {
    /// Creates the temporary file now, so an unwritable path fails early.
    /// A symlink is written through (the link stays, its target is
    /// replaced); an existing file must be writable, as for a plain write,
    /// and keeps its permissions.
    pub fn create(path: &str) -> std::io::Result<AtomicFile> {
        let p = resolve_links(std::path::Path::new(path));
        let name = p.file_name().ok_or_else(|| std::io::Error::other("not a file name"))?;
        let dir = match p.parent() {
            Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
            _ => std::path::PathBuf::from("."),
        };
        let existing = std::fs::metadata(&p).ok();
        if existing.as_ref().is_some_and(|m| m.is_file()) {
            // The permission a plain write would need.
            std::fs::OpenOptions::new().write(true).open(&p)?;
        }
        let name = name.to_string_lossy();
        let pid = std::process::id();
        // The temporary name must fit in a name's 255 bytes too.
        // Created exclusively (`O_EXCL`): a file or link already at the
        // name, left by a crash or planted, is never written through.
        let (tmp, file) = {
            let mut k = 0u32;
            loop {
                let tag = if k == 0 { pid.to_string() } else { format!("{pid}-{k}") };
                let tmp_name = format!(".{name}.{tag}.tmp");
                let tmp_name =
                    if tmp_name.len() <= 255 { tmp_name } else { format!(".rayshell.{tag}.tmp") };
                let tmp = dir.join(tmp_name);
                match std::fs::OpenOptions::new().write(true).create_new(true).open(&tmp) {
                    Ok(f) => break (tmp, f),
                    Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists && k < 100 => k += 1,
                    Err(e) => return Err(e),
                }
            }
        };
        feedback::add_temp(&tmp);
        let file = std::io::BufWriter::new(feedback::Cancellable(file));
        let mut out = AtomicFile { tmp, path: p, file: Some(file) };
        if let Some(m) = existing.filter(|m| m.is_file()) {
            std::fs::set_permissions(&out.tmp, m.permissions())?;
        }
        out.file.as_mut().expect("just made").flush()?;
        Ok(out)
    }

    /// Where the picture goes; writes fail once Ctrl-C has come.
    pub fn writer(&mut self) -> &mut impl Write {
        self.file.as_mut().expect("not committed yet")
    }

    /// Flushes and renames the file into place.
    pub fn commit(mut self) -> std::io::Result<()> {
        let w = self.file.take().expect("committed once");
        // Flushed and closed (no sync: see above).
        w.into_inner().map_err(|e| e.into_error())?;
        if !exchange(&self.tmp, &self.path) {
            std::fs::rename(&self.tmp, &self.path)?;
        }
        feedback::remove_temp(&self.tmp);
        Ok(())
    }
}

/// Swaps the names of `tmp` and an existing regular file `path`, then
/// removes `tmp` (now the old file); false, with nothing changed, where
/// `path` is no regular file or the file system cannot swap names.
#[cfg(target_os = "linux")]
fn exchange(tmp: &std::path::Path, path: &std::path::Path) -> bool {
    use rustix::fs::{CWD, RenameFlags, renameat_with};
    if !std::fs::symlink_metadata(path).is_ok_and(|m| m.is_file()) {
        return false;
    }
    if renameat_with(CWD, tmp, CWD, path, RenameFlags::EXCHANGE).is_err() {
        return false;
    }
    let _ = std::fs::remove_file(tmp);
    true
}

#[cfg(not(target_os = "linux"))]
fn exchange(_: &std::path::Path, _: &std::path::Path) -> bool {
    false
}

/// `path` with symlinks in its last component followed (up to 40, as the
/// kernel does), so writing replaces the file a link points to.
fn resolve_links(path: &std::path::Path) -> std::path::PathBuf {
    let mut p = path.to_path_buf();
    for _ in 0..40 {
        match std::fs::read_link(&p) {
            Ok(target) if target.is_absolute() => p = target,
            Ok(target) => p = p.parent().map_or(target.clone(), |d| d.join(&target)),
            Err(_) => break,
        }
    }
    p
}

impl Drop for AtomicFile {
    fn drop(&mut self) {
        if self.file.is_some() || self.tmp.exists() {
            self.file = None;
            let _ = std::fs::remove_file(&self.tmp);
            feedback::remove_temp(&self.tmp);
        }
    }
}

pub fn io_reason(e: &std::io::Error) -> String {
    match e.kind() {
        std::io::ErrorKind::NotFound => "no such file or directory".into(),
        std::io::ErrorKind::PermissionDenied => "permission denied".into(),
        _ => e.to_string().to_lowercase(),
    }
}
