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
