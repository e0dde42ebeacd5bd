//! The command line: options, stdin, -c, argv, help and version.

use crate::util::{run, text};

pub fn dash_c_and_stdin() {
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

pub fn argv_like_tclsh() {
    let out = run(&["-c", "puts \"$argc [lindex $argv 1]\"", "--", "a", "b c"], "");
    assert_eq!(text(&out.stdout), "2 b c\n");
}

pub fn options() {
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

pub fn help_lists_commands() {
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

pub fn no_panic_on_garbage() {
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
pub fn regressions_do_not_crash() {
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

pub fn source_returns_the_last_result() {
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

pub fn numbers_as_old_converters_write_them() {
    // Issue "pictures that hold up": C printf and converters write integers
    // as integral decimals, and opaque SPD-style materials an ior of 0.
    let dir = crate::util::scratch("decimals");
    let out = dir.join("d.ppm");
    let script = format!(
        "camera_resolution 16.0 12.0; trace_depth 5.0; max_vertices 1e3; max_normals 3.0
         vertex 0 0 -3; vertex 1 0 -3; vertex 0 1 -3
         material 1 1 1 0.2 0.8 0 1 0 0
         tri 0.0 1e0 2.0; ambient_light 1 1 1
         render {{{}}}",
        out.display()
    );
    let r = run(&["-c", &script], "");
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let img = rayshell::image::read_rgb8(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!((img.width, img.height), (16, 12));
    assert!(img.rgb.iter().any(|&b| b > 0), "the triangle is there");
}

pub fn errors_at_the_final_render_name_the_script() {
    // The render after a script (`raytrace scene.tsd out.ppm`) is placed at
    // the script's last line; its message says what the camera was told.
    let dir = crate::util::scratch("final-render");
    let scene = dir.join("up.tsd");
    std::fs::write(&scene, "camera_up 0 0 1\nsphere 0 0 -5 1\n").unwrap();
    let out = dir.join("x.ppm");
    let r = run(&[scene.to_str().unwrap(), out.to_str().unwrap()], "");
    assert_eq!(r.status.code(), Some(1));
    let want = format!(
        "{}:2: camera up vector is parallel to the view direction (camera_up 0 0 1, looking along 0 0 -1)",
        scene.display()
    );
    assert!(text(&r.stderr).starts_with(&want), "{}", text(&r.stderr));
    assert!(!out.exists());
}

pub fn the_first_run_says_what_happened() {
    // Issue "the first ten minutes": each render prints one line; an
    // unchanged scene is never traced twice; a script that builds a scene
    // but renders nothing says so.
    let dir = crate::util::scratch("said");
    let scene = dir.join("s.tsd");
    let a = dir.join("a.ppm");
    std::fs::write(
        &scene,
        format!(
            "camera_resolution 20 10; sphere 0 0 -3 1; point_light 1 1 1 0 2 0\nrender {{{}}}\n",
            a.display()
        ),
    )
    .unwrap();
    let out = dir.join("out.ppm");
    let r = run(&[scene.to_str().unwrap(), out.to_str().unwrap()], "");
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let err = text(&r.stderr);
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 2, "{err}");
    assert!(lines[0].starts_with(&format!("wrote {} 20×10 in ", a.display())), "{err}");
    assert!(lines[0].ends_with("Mrays/s)"), "{err}");
    assert_eq!(
        lines[1],
        format!("wrote {} 20×10 (the scene had not changed since it was traced)", out.display())
    );
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&out).unwrap());
    // --quiet says nothing.
    let r = run(&["-q", scene.to_str().unwrap(), out.to_str().unwrap()], "");
    assert_eq!(text(&r.stderr), "");
    // A scene and no render: exit 0, and how to get a picture.
    let r = run(&["-c", "sphere 0 0 -3 1"], "");
    assert_eq!(r.status.code(), Some(0));
    assert!(text(&r.stderr).contains("rendered nothing"), "{}", text(&r.stderr));
    // Pure Tcl is not a scene: nothing to say.
    let r = run(&["-c", "puts hi"], "");
    assert_eq!(text(&r.stderr), "");
}

pub fn stdin_dash_and_dash_c_with_an_output() {
    let dir = crate::util::scratch("dash");
    let scene = "camera_resolution 8 6; sphere 0 0 -3 1; ambient_light 1 1 1\n";
    let (a, b) = (dir.join("a.png"), dir.join("b.png"));
    let r = run(&["-", a.to_str().unwrap()], scene);
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let r = run(&["-c", scene, b.to_str().unwrap()], "");
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    assert_eq!(std::fs::read(&a).unwrap(), std::fs::read(&b).unwrap());
    let r = run(&["-c", scene, b.to_str().unwrap(), "extra.png"], "");
    assert_eq!(r.status.code(), Some(2));
}

pub fn the_output_is_checked_before_the_script_runs() {
    // A mistyped output fails at once with exit 2, before the script's
    // first line runs; a missing directory is a usage error, not an I/O
    // failure worth retrying (74).
    let dir = crate::util::scratch("outcheck");
    let scene = dir.join("s.tsd");
    std::fs::write(&scene, "puts started\nsphere 0 0 -3 1\n").unwrap();
    for (out, want) in [
        (dir.join("out.jpg"), "unknown image format"),
        (dir.join("no/such/dir/out.png"), "no directory"),
    ] {
        let r = run(&[scene.to_str().unwrap(), out.to_str().unwrap()], "");
        assert_eq!(r.status.code(), Some(2), "{}", text(&r.stderr));
        assert_eq!(text(&r.stdout), "", "the script ran");
        assert!(text(&r.stderr).contains(want), "{}", text(&r.stderr));
    }
    // An unknown option names the valid ones, and not clap's `-- --x` tip.
    let r = run(&["--thread", "2"], "");
    assert_eq!(r.status.code(), Some(2));
    let err = text(&r.stderr);
    assert!(err.contains("unknown option \"--thread\" (did you mean --threads?)"), "{err}");
    assert!(err.contains("--frames") && err.contains("--quiet"), "{err}");
    assert!(!err.contains("-- --thread"), "{err}");
}
