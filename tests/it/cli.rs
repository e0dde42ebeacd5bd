//! The command line: options, stdin, -c, argv, help and version.

use crate::util::{run, text};

#[test]
fn dash_c_and_stdin() {
    let out = run(&["-c", "puts [expr {6 * 7}]"], "");
    assert_eq!(text(&out.stdout), "42\n");
    let out = run(&[], "puts hi\nputs [llength {a b}]\n");
    assert_eq!(text(&out.stdout), "hi\n2\n");
    assert_eq!(out.status.code(), Some(0));
    let out = run(&[], "puts a\nnope\nputs b\n");
    assert_eq!(text(&out.stdout), "a\n");
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).starts_with("stdin:2: invalid command name \"nope\""));
}

#[test]
fn argv_like_tclsh() {
    let out = run(&["-c", "puts \"$argc [lindex $argv 1]\"", "--", "a", "b c"], "");
    assert_eq!(text(&out.stdout), "2 b c\n");
}

#[test]
fn options() {
    let out = run(&["--version"], "");
    assert!(text(&out.stdout).starts_with("raytrace "));
    let out = run(&["--help"], "");
    assert!(text(&out.stdout).contains("Usage"));
    let out = run(&["--bogus"], "");
    assert_eq!(out.status.code(), Some(2));
    assert!(text(&out.stderr).contains("--bogus"));
    let out = run(&["no/such/file.tsd"], "");
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("couldn't read file"));
    let out = run(&["tests"], "");
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("illegal operation on a directory"));
}

#[test]
fn help_lists_commands() {
    let out = run(&["-c", "puts [help]; puts [help lsort]"], "");
    let s = text(&out.stdout);
    assert!(
        s.lines()
            .any(|l| l.starts_with("foreach ")
                && l.ends_with("varList list ?varList list ...? command")),
        "{s}"
    );
    assert!(s.contains("lsort ?-option value ...? list"), "{s}");
}

#[test]
fn no_panic_on_garbage() {
    let garbage: String =
        (0..2000u32).map(|i| char::from_u32((i * 7919) % 0x2FF + 1).unwrap_or('x')).collect();
    let out = run(&[], &garbage);
    assert_ne!(out.status.code(), Some(101));
    let deep = "[".repeat(100_000);
    let out = run(&["-c", &deep], "");
    assert_eq!(out.status.code(), Some(1));
    let braces = format!("puts {}", "{".repeat(100_000));
    let out = run(&["-c", &braces], "");
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).contains("missing close-brace"));
}

/// Every input that once crashed (found by fuzzing, kept in tests/regress)
/// now ends with a Tcl error or success, never a panic.
#[test]
fn regressions_do_not_crash() {
    let dir = crate::util::root().join("tests/regress");
    let mut n = 0;
    for entry in std::fs::read_dir(&dir).expect("tests/regress") {
        let path = entry.unwrap().path();
        // Scripts run as scripts; OBJ files (fuzz finds in the loader) go
        // through `mesh` and must be refused with a located error.
        let out = match path.extension().and_then(|e| e.to_str()) {
            Some("obj") => {
                let out = crate::util::raytrace()
                    .arg("-c")
                    .arg("mesh $argv")
                    .arg("--")
                    .arg(&path)
                    .output()
                    .unwrap();
                let want = format!("{}:", path.display());
                assert!(text(&out.stderr).starts_with(&want), "{}", text(&out.stderr));
                out
            }
            _ => crate::util::raytrace().arg(&path).output().unwrap(),
        };
        assert!(
            matches!(out.status.code(), Some(0 | 1)),
            "{}: exit {:?}\n{}",
            path.display(),
            out.status.code(),
            text(&out.stderr)
        );
        n += 1;
    }
    assert!(n > 0);
}

#[test]
fn source_returns_the_last_result() {
    let dir = std::env::temp_dir().join(format!("rayshell-src-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("a.tcl"), "set x 1\nexpr {40 + 2}\n").unwrap();
    std::fs::write(dir.join("b.tcl"), "vertex 1 2 3\nvertex 4 5 6\n").unwrap();
    let out = crate::util::raytrace()
        .args(["-c", "puts [source a.tcl]; puts [source b.tcl]"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_eq!(text(&out.stdout), "42\n1\n");
    let _ = std::fs::remove_dir_all(&dir);
}
