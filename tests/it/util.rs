//! Helpers shared by the integration tests.

use std::path::PathBuf;
use std::process::{Command, Output, Stdio};

pub fn root() -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR"))
}

pub fn raytrace() -> Command {
    Command::new(env!("CARGO_BIN_EXE_raytrace"))
}

/// Runs the binary with the given args and stdin text.
pub fn run(args: &[&str], stdin: &str) -> Output {
    use std::io::Write;
    let mut child = raytrace()
        .args(args)
        .current_dir(root())
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("spawn raytrace");
    child.stdin.take().expect("stdin").write_all(stdin.as_bytes()).expect("write stdin");
    child.wait_with_output().expect("wait for raytrace")
}

pub fn tclsh_available() -> bool {
    Command::new("tclsh").stdin(Stdio::piped()).stdout(Stdio::null()).spawn().is_ok()
}

pub fn text(b: &[u8]) -> String {
    String::from_utf8_lossy(b).into_owned()
}

/// A fresh scratch directory for one test: its own even when two tests
/// running at once ask with the same tag (the REPL sessions do).
pub fn scratch(tag: &str) -> PathBuf {
    static NEXT: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let n = NEXT.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
    let d = std::env::temp_dir().join(format!("rayshell-{tag}-{}-{n}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).expect("create scratch dir");
    d
}

/// The names in `dir`, sorted.
pub fn listing(dir: &std::path::Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .map(|r| {
            r.filter_map(|e| Some(e.ok()?.file_name().to_string_lossy().into_owned())).collect()
        })
        .unwrap_or_default();
    v.sort();
    v
}

/// Why a test did not run: the payload of the panic `skip` raises, which
/// the harness (`main.rs`) reports as an ignored test with this reason.
pub struct Skip(pub String);

/// Ends the current test as skipped (ignored, with `reason`, in the
/// summary): for tests whose outside tool or data is absent.
pub fn skip(reason: impl Into<String>) -> ! {
    std::panic::panic_any(Skip(reason.into()))
}

/// Starts the REPL in `dir` on a terminal that util-linux `script` gives
/// it, with its stdin, stdout and stderr piped. Skips the test when
/// `script` is absent.
pub fn spawn_repl(dir: &std::path::Path) -> std::process::Child {
    spawn_repl_with(dir, &[])
}

/// `spawn_repl` with options for raytrace.
pub fn spawn_repl_with(dir: &std::path::Path, args: &[&str]) -> std::process::Child {
    if Command::new("script").arg("--version").output().is_err() {
        skip("`script` (util-linux) is not installed");
    }
    // `exec`: raytrace is the only process on the terminal, or dash (CI's
    // /bin/sh, which `script` runs the command with) would also get a ^C,
    // die of it, and `script` would report that status instead of ours.
    // TERM=dumb: rustyline's line mode keeps lines typed ahead (a raw-mode
    // switch would flush them).
    let mut bin = format!("exec '{}'", env!("CARGO_BIN_EXE_raytrace"));
    for a in args {
        bin.push_str(&format!(" '{a}'"));
    }
    Command::new("script")
        .args(["-qfec", &bin, "/dev/null"])
        .current_dir(dir)
        .env("XDG_DATA_HOME", dir)
        .env("TERM", "dumb")
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("run script")
}

/// Runs the REPL on a terminal (`spawn_repl`), types
/// `lines` (a line `#pause MS` waits instead), and returns its exit status and everything the terminal and
/// stderr showed. Skips the test when `script` is absent.
pub fn repl_session(lines: &[&str]) -> (Option<i32>, String) {
    repl_session_with(&[], lines)
}

/// `repl_session` with options for raytrace.
pub fn repl_session_with(args: &[&str], lines: &[&str]) -> (Option<i32>, String) {
    use std::io::{Read, Write};
    let dir = scratch("repl-session");
    let mut child = spawn_repl_with(&dir, args);
    let mut input = child.stdin.take().expect("stdin");
    for line in lines {
        // `#pause MS`: wait before typing on, as a person would.
        if let Some(ms) = line.strip_prefix("#pause ") {
            input.flush().expect("flush");
            std::thread::sleep(std::time::Duration::from_millis(ms.parse().expect("ms")));
            continue;
        }
        writeln!(input, "{line}").expect("type a line");
    }
    input.flush().expect("flush");
    let mut shown = String::new();
    child.stdout.take().expect("stdout").read_to_string(&mut shown).expect("read the terminal");
    let status = child.wait().expect("wait");
    let mut err = String::new();
    child.stderr.take().expect("stderr").read_to_string(&mut err).expect("read stderr");
    drop(input);
    let _ = std::fs::remove_dir_all(&dir);
    (status.code(), shown + &err)
}
