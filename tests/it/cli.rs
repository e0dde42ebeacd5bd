//! The command line: options, stdin, -c, argv, help and version.

use std::process::Command;

use crate::util::{raytrace, run, scratch, text};

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

/// `help` groups the scene commands by topic (issue "the first hour"):
/// every scene command is in exactly one topic, `help TOPIC` gives each
/// of its commands a line, `help tcl` lists the language's own.
pub fn help_lists_commands() {
    let out = run(&["-c", "puts [help]"], "");
    let overview = text(&out.stdout);
    for (topic, _, names) in rayshell::shell::docs::TOPICS {
        assert!(overview.contains(&format!("  {topic:<10} ")), "{topic}: {overview}");
        for n in names.iter() {
            let homes = rayshell::shell::docs::TOPICS.iter().filter(|t| t.2.contains(n)).count();
            assert_eq!(homes, 1, "{n} is in {homes} topics");
        }
    }
    for doc in rayshell::shell::docs::SCENE {
        assert!(rayshell::shell::docs::topic_of(doc.name).is_some(), "{} has no topic", doc.name);
    }
    let out = run(&["-c", "puts [help lights]"], "");
    let lights = text(&out.stdout);
    assert!(lights.starts_with("lights: "), "{lights}");
    assert!(
        lights.lines().any(|l| l.trim_start().starts_with("point_light r g b x y z")),
        "{lights}"
    );
    assert!(!lights.contains("foreach"), "{lights}");
    let out = run(&["-c", "puts [help tcl]; puts [help lsort]"], "");
    let s = text(&out.stdout);
    assert!(!s.contains("camera_from"), "{s}");
    assert!(
        s.lines()
            .any(|l| l.trim_start().starts_with("foreach varList list ?varList list ...? command")),
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
                // `-c:1: file.obj:LINE: bad OBJ line ...`
                let want = format!("-c:1: {}:", path.display());
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
    let r = run(&["-q", "-c", "sphere 0 0 -3 1"], "");
    assert_eq!(text(&r.stderr), "", "--quiet is quiet");
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

pub fn the_repl_leaves_error_info_as_tclsh_does() {
    // After an uncaught error, `errorInfo` holds the trace and `errorCode`
    // the code, as tclsh sets them; the session goes on.
    let (status, shown) = crate::util::repl_session(&[
        "proc f {} { error boom {} {MY CODE} }",
        "f",
        "puts \"code=$errorCode\"",
        "puts \"info=[lindex [split $errorInfo \\n] 0]\"",
        "exit 4",
    ]);
    assert_eq!(status, Some(4), "{shown}");
    assert!(shown.contains("code=MY CODE"), "{shown}");
    assert!(shown.contains("info=boom"), "{shown}");
}

/// Pixels back from viuer's half-block drawing: each cell is `▄` (lower
/// pixel in the foreground colour, upper in the background) or `▀` (upper
/// in the foreground), colours as 24-bit SGR codes; rows end in CR LF.
fn decode_half_blocks(out: &str) -> Vec<Vec<[u8; 3]>> {
    let mut rows: Vec<Vec<[u8; 3]>> = Vec::new();
    for line in out.split('\n').filter(|l| l.contains('▄') || l.contains('▀')) {
        let (mut upper, mut lower) = (Vec::new(), Vec::new());
        let (mut fg, mut bg) = ([0u8; 3], [0u8; 3]);
        let mut rest = line;
        while !rest.is_empty() {
            if let Some(r) = rest.strip_prefix("\x1b[") {
                let end = r.find('m').expect("an SGR code");
                let codes: Vec<u8> = r[..end].split(';').filter_map(|c| c.parse().ok()).collect();
                match codes[..] {
                    [38, 2, r, g, b] => fg = [r, g, b],
                    [48, 2, r, g, b] => bg = [r, g, b],
                    _ => {}
                }
                rest = &r[end + 1..];
            } else if let Some(r) = rest.strip_prefix('▄') {
                upper.push(bg);
                lower.push(fg);
                rest = r;
            } else if let Some(r) = rest.strip_prefix('▀') {
                upper.push(fg);
                lower.push(bg);
                rest = r;
            } else {
                rest = &rest[rest.chars().next().unwrap().len_utf8()..];
            }
        }
        rows.push(upper);
        rows.push(lower);
    }
    rows
}

pub fn show_draws_the_last_render_in_half_blocks() {
    // Issue "the first ten minutes": `show` draws the last render in the
    // terminal; in half-block mode every cell's two colours are the two
    // pixels (sRGB, as a viewer shows the linear file), checked by decoding
    // the output back.
    let dir = crate::util::scratch("show");
    let png = dir.join("s.png");
    let script = format!(
        "camera_resolution 12 8; background 0.2 0.5 0.9; ambient_light 1 1 1
         material 1 0.3 0.1 1 0 0 1 0 1; sphere 0 0 -3 0.8
         render -srgb {{{}}}; show -blocks -width 12",
        png.display()
    );
    let r = crate::util::raytrace()
        .args(["-q", "-c", &script])
        .env("COLORTERM", "truecolor")
        .output()
        .unwrap();
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let shown = decode_half_blocks(&text(&r.stdout));
    let want = rayshell::image::read_rgb8(&std::fs::read(&png).unwrap()).unwrap();
    assert_eq!(shown.len(), 8, "two pixel rows a line");
    for (y, row) in shown.iter().enumerate() {
        assert_eq!(row.len(), 12, "row {y}");
        for (x, px) in row.iter().enumerate() {
            let i = (y * 12 + x) * 3;
            assert_eq!(px[..], want.rgb[i..i + 3], "pixel {x},{y}");
        }
    }
    // The sphere and the background both show.
    assert!(
        shown.iter().flatten().any(|p| p[0] > p[2]) && shown.iter().flatten().any(|p| p[2] > p[0])
    );
    // A file, and a preview before any render, draw too; bad options do not.
    let r = run(&["-c", &format!("show -blocks -width 6 {{{}}}", png.display())], "");
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    assert_eq!(decode_half_blocks(&text(&r.stdout)).first().map(|r| r.len()), Some(6));
    let r = run(&["-c", "sphere 0 0 -3 1; ambient_light 1 1 1; show -blocks -width 10"], "");
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    assert_eq!(decode_half_blocks(&text(&r.stdout)).first().map(|r| r.len()), Some(10));
    // The preview is a look at the scene: no "rendered nothing" hint.
    assert!(!text(&r.stderr).contains("rendered nothing"), "{}", text(&r.stderr));
    let r = run(&["-c", "show -bogus"], "");
    assert_eq!(r.status.code(), Some(1));
}

pub fn a_bar_asked_for_is_drawn_into_a_pipe() {
    // `--progress bar` draws the bar even when stderr is not a terminal
    // (the default, `auto`, draws none there), with an ETA from the
    // recent rate.
    let dir = crate::util::scratch("bar");
    let script = format!(
        "source {{{}}}; camera_resolution 900 700; render -progressive out.png",
        crate::util::root().join("tsd/spheres.tsd").display()
    );
    let r = crate::util::raytrace()
        .args(["--progress", "bar", "-c", &script])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let err = text(&r.stderr);
    assert!(err.contains("out.png [") && err.contains("%"), "no bar: {err}");
    assert!(err.contains("ETA"), "{err}");
    let r = crate::util::raytrace().args(["-c", &script]).current_dir(&dir).output().unwrap();
    assert!(!text(&r.stderr).contains("out.png ["), "auto mode drew a bar into a pipe");
}

/// The parse time `stats` gave, from a REPL session that printed
/// `parse=[lindex [split [stats] \n] 0]`.
fn parse_time(shown: &str) -> f64 {
    let line = shown
        .lines()
        .find_map(|l| l.split_once("parse=parse").map(|(_, r)| r))
        .unwrap_or_else(|| panic!("{shown}"));
    line.split_whitespace().next().and_then(|s| s.parse().ok()).expect(line)
}

pub fn repl_stats_leave_out_the_time_spent_typing() {
    // `stats` reports "parse" time: running the script up to the render,
    // not the 1.5 s the user took to type the next line.
    let (status, shown) = crate::util::repl_session(&[
        "camera_resolution 8 8; sphere 0 0 -3 1",
        "#pause 1500",
        "render x.png",
        "puts \"parse=[lindex [split [stats] \\n] 0]\"",
        "exit 5",
    ]);
    assert_eq!(status, Some(5), "{shown}");
    let secs = parse_time(&shown);
    assert!(secs < 1.0, "parse time {secs} s includes the pause: {shown}");
}

/// A render stopped by Ctrl-C is not the next render's parse time
/// (issue "the first hour": `stats` counted the stopped render's seconds),
/// and a Ctrl-C at the prompt leaves the session and its next line alone.
pub fn repl_stats_after_an_interrupt_leave_out_the_stopped_render() {
    let (status, shown) = crate::util::repl_session(&[
        "camera_resolution 3000 3000; samples 16; sphere 0 0 -3 1; point_light 1 1 1 0 5 0",
        "render slow.png",
        "#pause 1500",
        "\u{3}",
        "#pause 300",
        "camera_resolution 8 8; samples 1",
        "render x.png",
        "puts \"parse=[lindex [split [stats] \\n] 0]\"",
        // A ^C at the prompt (this terminal is in line mode: a signal)
        // neither ends the session nor stops the next line.
        "#pause 300",
        "\u{3}",
        "#pause 900",
        "puts [string toupper alive]",
        "exit 5",
    ]);
    assert_eq!(status, Some(5), "{shown}");
    assert!(shown.contains("interrupted"), "{shown}");
    assert!(shown.contains("ALIVE"), "{shown}");
    let secs = parse_time(&shown);
    assert!(secs < 1.0, "parse time {secs} s includes the stopped render: {shown}");
}

pub fn closed_streams_and_byte_order_marks() {
    // Issue "hostile input": a closed or full stderr never stops a run (it
    // once panicked, exit 101); a reader that stops reading stdout ends the
    // run quietly (141, as a tool killed by SIGPIPE); output lost to a full
    // disk is an error; a UTF-8 byte order mark opening a script or an OBJ
    // file is skipped, as tclsh skips it.
    let dir = crate::util::scratch("streams");
    std::fs::write(dir.join("s.tsd"), "camera_resolution 8 8; sphere 0 0 -3 1\n").unwrap();
    let full = std::fs::File::options().write(true).open("/dev/full").unwrap();
    let r = crate::util::raytrace()
        .args(["s.tsd", "f####.png", "--frames", "0..3"])
        .current_dir(&dir)
        .stderr(full)
        .output()
        .unwrap();
    assert_eq!(r.status.code(), Some(0));
    assert_eq!(crate::util::listing(&dir).len(), 5, "every frame written");
    let mut child = crate::util::raytrace()
        .args(["-c", "while 1 {puts [string repeat x 100]}"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    drop(child.stdout.take());
    let out = child.wait_with_output().unwrap();
    assert_eq!(out.status.code(), Some(141));
    assert_eq!(text(&out.stderr), "", "quietly");
    let full = std::fs::File::options().write(true).open("/dev/full").unwrap();
    let r = crate::util::raytrace().args(["-c", "puts hi"]).stdout(full).output().unwrap();
    assert_eq!(r.status.code(), Some(1));
    assert!(text(&r.stderr).contains("error writing \"stdout\""), "{}", text(&r.stderr));
    std::fs::write(dir.join("bom.tsd"), b"\xef\xbb\xbfputs [mesh bom.obj]\n").unwrap();
    std::fs::write(dir.join("bom.obj"), b"\xef\xbb\xbfv 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n")
        .unwrap();
    let r = crate::util::raytrace().args(["-q", "bom.tsd"]).current_dir(&dir).output().unwrap();
    assert_eq!(text(&r.stdout), "1\n", "{}", text(&r.stderr));
}

pub fn output_files_keep_links_modes_and_long_names() {
    // Issue "hostile input": a symlink is written through (not replaced by
    // a file), an existing file keeps its permissions, and a 250-byte name
    // works (the temporary name must fit in 255 bytes too).
    use std::os::unix::fs::PermissionsExt;
    let dir = crate::util::scratch("outfiles");
    std::fs::write(dir.join("real.png"), "old").unwrap();
    std::fs::set_permissions(dir.join("real.png"), std::fs::Permissions::from_mode(0o600)).unwrap();
    std::os::unix::fs::symlink("real.png", dir.join("link.png")).unwrap();
    let long = format!("{}.png", "a".repeat(250));
    for name in ["link.png", long.as_str()] {
        let r = crate::util::raytrace()
            .args([
                "-q",
                "-c",
                &format!("camera_resolution 4 4; ambient_light 1 1 1; render {name}"),
            ])
            .current_dir(&dir)
            .output()
            .unwrap();
        assert_eq!(r.status.code(), Some(0), "{name}: {}", text(&r.stderr));
    }
    let link = std::fs::symlink_metadata(dir.join("link.png")).unwrap();
    assert!(link.file_type().is_symlink(), "the link was replaced");
    let real = std::fs::metadata(dir.join("real.png")).unwrap();
    assert_eq!(real.permissions().mode() & 0o777, 0o600);
    assert!(std::fs::read(dir.join("real.png")).unwrap().starts_with(b"\x89PNG"));
    assert!(dir.join(&long).exists());
    let mut names = crate::util::listing(&dir);
    names.retain(|n| n.ends_with(".tmp"));
    assert!(names.is_empty(), "{names:?}");
}

/// The memory budget from the command line: its sizes, and its default
/// under an address-space cap (`prlimit --as`), where growth past it is a
/// located error (it once aborted, exit 134). Issue "hostile input, second
/// round".
pub fn the_memory_budget_from_the_command_line() {
    for bad in ["lots", "12", "0%", "-1G", "5X"] {
        let out = run(&["--max-memory", bad, "-c", "puts hi"], "");
        assert_eq!(out.status.code(), Some(2), "{bad}");
        assert!(text(&out.stderr).contains("--max-memory"), "{bad}: {}", text(&out.stderr));
    }
    let out = run(&["--max-memory", "1.5GiB", "-c", "puts hi"], "");
    assert_eq!(text(&out.stdout), "hi\n");
    let out = run(&["--max-memory", "32M", "-c", "set s [string repeat x 40000000]"], "");
    assert_eq!(out.status.code(), Some(1));
    assert!(
        text(&out.stderr)
            .starts_with("-c:1: not enough memory: 38.1 MiB more would pass the budget of 32 MiB"),
        "{}",
        text(&out.stderr)
    );
    if std::process::Command::new("prlimit").arg("--version").output().is_err() {
        crate::util::skip("prlimit (util-linux) is not installed");
    }
    for script in [
        "set s [string repeat x 500000000]; string map {x yy} $s",
        "set l {a b c}; while 1 {set l [concat $l $l]}",
        "while 1 {lappend l [incr i]}",
    ] {
        let out = std::process::Command::new("prlimit")
            .args(["--as=4000000000", "--", env!("CARGO_BIN_EXE_raytrace"), "-c", script])
            .output()
            .unwrap();
        assert_eq!(out.status.code(), Some(1), "{script}: {}", text(&out.stderr));
        let err = text(&out.stderr);
        assert!(
            err.starts_with("-c:1: not enough memory: ")
                || err.starts_with("-c:1: string too long"),
            "{script}: {err}"
        );
    }
}

/// Input without end: `/dev/zero` as the script or on stdin stops at the
/// value cap with a located error, in bounded memory.
pub fn endless_input_is_refused() {
    let out = run(&["--max-memory", "256M", "/dev/zero"], "");
    assert_eq!(out.status.code(), Some(1));
    assert!(text(&out.stderr).starts_with("/dev/zero:1: error reading"), "{}", text(&out.stderr));
    let child = std::process::Command::new("sh")
        .args([
            "-c",
            &format!("head -c 600000000 /dev/zero | '{}' -", env!("CARGO_BIN_EXE_raytrace")),
        ])
        .output()
        .unwrap();
    let err = text(&child.stderr);
    assert!(err.starts_with("stdin:1: error reading \"stdin\": "), "{err}");
    assert!(err.contains("not enough memory") || err.contains("longer than"), "{err}");
}

/// `ulimit -f`: a write past it is an error (status 74, as for any write
/// error) that leaves no temporary file; SIGXFSZ no longer kills the run.
pub fn a_file_size_limit_is_a_write_error() {
    let dir = crate::util::scratch("ulimit-f");
    let script = "camera_resolution 512 512; sphere 0 0 -5 1; point_light 1 1 1 0 5 0";
    let out = std::process::Command::new("sh")
        .args([
            "-c",
            &format!(
                "ulimit -f 100; exec '{}' -q -c '{script}' out.ppm",
                env!("CARGO_BIN_EXE_raytrace")
            ),
        ])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(74), "{}", text(&out.stderr));
    assert!(text(&out.stderr).starts_with("-c:1: couldn't write \"out.ppm\": file too large"));
    assert!(crate::util::listing(&dir).is_empty(), "{:?}", crate::util::listing(&dir));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Bytes that are not UTF-8 typed into the REPL drop that line, not the
/// session (it once ended, losing the variables).
pub fn the_repl_survives_bytes_that_are_not_utf8() {
    use std::io::{Read, Write};
    let dir = crate::util::scratch("repl-latin1");
    let mut child = crate::util::spawn_repl(&dir);
    let mut input = child.stdin.take().unwrap();
    input.write_all(b"set keep 42\n").unwrap();
    input.flush().unwrap();
    std::thread::sleep(std::time::Duration::from_millis(300));
    input.write_all(b"puts caf\xe9\n").unwrap();
    input.flush().unwrap();
    std::thread::sleep(std::time::Duration::from_millis(300));
    input.write_all(b"puts \"keep=$keep\"\nexit 5\n").unwrap();
    input.flush().unwrap();
    let mut bytes = Vec::new();
    child.stdout.take().unwrap().read_to_end(&mut bytes).unwrap();
    let status = child.wait().unwrap();
    child.stderr.take().unwrap().read_to_end(&mut bytes).unwrap();
    drop(input);
    let shown = String::from_utf8_lossy(&bytes);
    assert_eq!(status.code(), Some(5), "{shown}");
    assert!(shown.contains("that line was not UTF-8 text"), "{shown}");
    assert!(shown.contains("keep=42"), "{shown}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue "untrusted scenes", findings 10 and 14: an output name that can
/// never be written (a directory, a name over 255 bytes, a frame pattern
/// 65,536 digits wide) is a usage error before the script runs, not a
/// panic or an I/O error worth a retry; inside a script such a `render`
/// is a script error (1), not 74.
pub fn unwritable_output_names_are_usage_errors() {
    let dir = scratch("bad-names");
    std::fs::create_dir(dir.join("d.png")).unwrap();
    std::fs::write(dir.join("s.tsd"), "puts ran\n").unwrap();
    let long = format!("{}.png", "x".repeat(300));
    let cases: [&[&str]; 5] = [
        &["s.tsd", "d.png"],
        &["s.tsd", &long],
        &["--frames", "1..2", "s.tsd", "f%065536d.png"],
        &["--frames", "1..2", "s.tsd", "f%0300d.png"],
        &["-c", "puts ran", &long],
    ];
    for args in cases {
        let r = raytrace().args(args).current_dir(&dir).output().unwrap();
        assert_eq!(r.status.code(), Some(2), "{args:?}: {}", text(&r.stderr));
        assert!(!text(&r.stdout).contains("ran"), "{args:?}: the script ran");
        assert!(text(&r.stderr).starts_with("raytrace: can't write"), "{}", text(&r.stderr));
    }
    for name in ["d.png", long.as_str()] {
        let script = format!("camera_resolution 4 4\nrender {name}\n");
        let r = raytrace().args(["-c", &script]).current_dir(&dir).output().unwrap();
        assert_eq!(r.status.code(), Some(1), "{name}: {}", text(&r.stderr));
        assert!(text(&r.stderr).contains("-c:2: couldn't write"), "{}", text(&r.stderr));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue "untrusted scenes", finding 10: under any address-space limit
/// (`ulimit -v`) the program either runs, with a budget that makes growth
/// a located error, or says at once that the limit is too small: never a
/// panic (101), an abort (134) or an internal error (70).
pub fn any_address_space_limit_runs_or_says_why() {
    let exe = env!("CARGO_BIN_EXE_raytrace");
    let script = "puts hi; camera_resolution 64 64; sphere 0 0 -3 1; render x.ppm\n\
                  set l {}; while 1 {lappend l [string repeat x 1000]}";
    let dir = scratch("ulimit");
    for mib in [256, 600, 900, 1024, 1200, 1600, 2048] {
        let r = Command::new("bash")
            .args([
                "-c",
                &format!("ulimit -v {}; exec \"$0\" -q -c \"$1\"", mib * 1024),
                exe,
                script,
            ])
            .current_dir(&dir)
            .output()
            .unwrap();
        let err = text(&r.stderr);
        match r.status.code() {
            Some(2) => {
                assert!(err.contains("ulimit -v") && err.contains("too small"), "{mib}: {err}")
            }
            Some(1) => {
                assert_eq!(text(&r.stdout), "hi\n", "{mib} MiB");
                assert!(err.contains("-c:2: not enough memory"), "{mib}: {err}");
            }
            c => panic!("ulimit -v of {mib} MiB: status {c:?}: {err}"),
        }
        // From 1 GiB on, the run goes as far as the budget.
        assert_eq!(r.status.code() == Some(1), mib >= 1024, "{mib} MiB: {err}");
    }
    // Coroutines' stacks past the address space: a located error (each
    // stack counted whole against the budget under a limit), never an
    // abort when the space runs out.
    let many = "for {set i 0} {$i < 100} {incr i} {coroutine c$i apply {{} {yield}}}";
    let r = Command::new("bash")
        .args(["-c", "ulimit -v 1400000; exec \"$0\" -c \"$1\"", exe, many])
        .output()
        .unwrap();
    let err = text(&r.stderr);
    assert_eq!(r.status.code(), Some(1), "{err}");
    assert!(err.starts_with("-c:1: not enough memory"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue "untrusted scenes", finding 13: every error names `file:line`,
/// however it ends the script: a bad return code, an `-errorinfo` of the
/// script's own, output that cannot be written.
pub fn errors_name_their_line_however_they_end() {
    let dir = scratch("located");
    let cases = [
        ("puts a\nreturn -code 5\n", "f.tcl:2: command returned bad code: 5"),
        ("puts a\nreturn -code error -errorinfo {my own} boom\n", "f.tcl:2: boom\nmy own"),
        ("puts a\n\nbreak\n", "f.tcl:3: invoked \"break\" outside of a loop"),
    ];
    for (script, want) in cases {
        std::fs::write(dir.join("f.tcl"), script).unwrap();
        let r = raytrace().arg("f.tcl").current_dir(&dir).output().unwrap();
        assert_eq!(r.status.code(), Some(1), "{script}");
        assert!(text(&r.stderr).starts_with(want), "{script}: {}", text(&r.stderr));
    }
    if std::path::Path::new("/dev/full").exists() {
        std::fs::write(dir.join("f.tcl"), "puts a\nputs b\n").unwrap();
        let full = std::fs::File::create("/dev/full").unwrap();
        let r = raytrace().arg("f.tcl").current_dir(&dir).stdout(full).output().unwrap();
        assert_eq!(r.status.code(), Some(1));
        let err = text(&r.stderr);
        assert!(
            err.starts_with("f.tcl:2: error writing \"stdout\": no space left on device"),
            "{err}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Shell completions come from the command line's own definition (issue
/// "the first hour"): bash completes an option from its start, and the
/// zsh and fish scripts name every long option.
pub fn shell_completions_know_every_option() {
    let options = rayshell::shell::args_list();
    for shell in ["bash", "zsh", "fish"] {
        let r = raytrace().args(["--completions", shell]).output().unwrap();
        assert_eq!(r.status.code(), Some(0), "{shell}");
        let script = text(&r.stdout);
        for o in &options {
            let long = o.rsplit('/').next().unwrap().trim_start_matches('-');
            if matches!(long, "help" | "version") {
                continue;
            }
            assert!(script.contains(long), "{shell}: no {long}");
        }
    }
    let exe = env!("CARGO_BIN_EXE_raytrace");
    let r = Command::new("bash")
        .args([
            "-c",
            "source <(\"$0\" --completions bash); COMP_WORDS=(raytrace --thr); COMP_CWORD=1; \
             _raytrace raytrace --thr raytrace; echo \"${COMPREPLY[@]}\"",
            exe,
        ])
        .output()
        .unwrap();
    assert_eq!(text(&r.stdout).trim(), "--threads", "{}", text(&r.stderr));
}
