//! The differential suite: every script in tests/tcl runs through tclsh 8.6
//! (the oracle) and through raytrace; stdout must match byte for byte and
//! the exit status must match.

use std::process::{Command, Stdio};

use crate::util::{raytrace, root, tclsh_available, text};

#[test]
fn scripts_match_tclsh() {
    if !tclsh_available() {
        println!("SKIPPED scripts_match_tclsh: tclsh is not installed (.ci/run installs it)");
        return;
    }
    let dir = root().join("tests/tcl");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("tests/tcl")
        .map(|e| e.expect("dir entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "tcl"))
        .collect();
    files.sort();
    assert!(files.len() >= 20, "the suite lost its scripts");
    let mut failures = Vec::new();
    for f in &files {
        let name = f.file_name().unwrap().to_string_lossy().into_owned();
        let args = ["x y", "z"];
        let want = Command::new("tclsh")
            .arg(&name)
            .args(args)
            .current_dir(&dir)
            .stdin(Stdio::null())
            .output()
            .expect("run tclsh");
        let got = raytrace()
            .arg(&name)
            .arg("--")
            .args(args)
            .current_dir(&dir)
            .stdin(Stdio::null())
            .output()
            .expect("run raytrace");
        if want.stdout != got.stdout || want.status.code() != got.status.code() {
            failures.push(format!(
                "{name}: exit tclsh={:?} raytrace={:?}\n--- tclsh stdout\n{}\n--- raytrace stdout\n{}\n--- raytrace stderr\n{}",
                want.status.code(),
                got.status.code(),
                text(&want.stdout),
                text(&got.stdout),
                text(&got.stderr)
            ));
        }
        // Neither may crash.
        assert_ne!(got.status.code(), Some(101), "{name} panicked");
    }
    assert!(failures.is_empty(), "{} of {} scripts differ:\n{}", failures.len(), files.len(), failures.join("\n\n"));
}

#[test]
fn errors_name_file_and_line() {
    let out = raytrace().arg("tests/tcl/err_unknown.tcl").current_dir(root()).output().unwrap();
    assert_eq!(out.status.code(), Some(1));
    let err = text(&out.stderr);
    assert!(
        err.starts_with("tests/tcl/err_unknown.tcl:3: invalid command name \"sphre\"\n"),
        "{err}"
    );
    assert!(err.contains("(procedure \"helper\" line 2)"), "{err}");
    assert!(err.contains("(file \"tests/tcl/err_unknown.tcl\" line 5)"), "{err}");
    assert_eq!(text(&out.stdout), "before\n");

    let out = raytrace().arg("tests/tcl/err_brace.tcl").current_dir(root()).output().unwrap();
    assert!(text(&out.stderr).starts_with("tests/tcl/err_brace.tcl:2: missing close-brace"));
}
