//! Ctrl-C and kill -9 against the real binary: a cancelled render leaves
//! no file behind, the REPL keeps its session, and an image under its
//! final name is never truncated.

use std::path::Path;
use std::process::{Child, Command, Stdio};
use std::time::{Duration, Instant};

use crate::util::{listing, raytrace, scratch, text};

/// A render that takes seconds: many mirror spheres, a large picture.
const SLOW: &str = "set keep 42
camera_resolution 3000 3000
point_light 1 1 1 0 5 0
material 1 1 1 0.1 0.5 0.5 10 0 1
for {set i 0} {$i < 400} {incr i} { sphere [expr {$i % 20 - 10}] [expr {$i / 20 - 10}] -20 0.7 }
";

fn signal(child: &Child, sig: &str) {
    let ok = Command::new("kill").args([sig, &child.id().to_string()]).status().unwrap();
    assert!(ok.success());
}

/// Waits until a temporary image file shows up in `dir` (the render has
/// started: the output is opened before tracing).
fn wait_for_tmp(dir: &Path, child: &mut Child) {
    let start = Instant::now();
    while !listing(dir).iter().any(|n| n.ends_with(".tmp")) {
        assert!(child.try_wait().unwrap().is_none(), "raytrace ended before rendering");
        assert!(start.elapsed() < Duration::from_secs(60), "the render never started");
        std::thread::sleep(Duration::from_millis(10));
    }
}

pub fn ctrl_c_in_a_batch_exits_130_and_leaves_no_file() {
    let dir = scratch("sigint");
    std::fs::write(dir.join("slow.tsd"), format!("{SLOW}render slow.png\n")).unwrap();
    let mut child =
        raytrace().arg("slow.tsd").current_dir(&dir).stderr(Stdio::piped()).spawn().unwrap();
    wait_for_tmp(&dir, &mut child);
    let sent = Instant::now();
    signal(&child, "-INT");
    let out = child.wait_with_output().unwrap();
    let took = sent.elapsed();
    assert_eq!(out.status.code(), Some(130), "{}", text(&out.stderr));
    assert!(text(&out.stderr).starts_with("slow.tsd:6: interrupted"), "{}", text(&out.stderr));
    assert!(took < Duration::from_secs(5), "cancelling took {took:?}");
    assert_eq!(listing(&dir), ["slow.tsd"], "no image, no temporary file");
    let _ = std::fs::remove_dir_all(&dir);
}

pub fn ctrl_c_in_the_repl_cancels_the_render_and_keeps_the_session() {
    // The REPL needs a terminal: util-linux `script` gives it one, and a
    // ^C typed there reaches raytrace as SIGINT, as from a keyboard.
    let dir = scratch("repl-sigint");
    let mut child = crate::util::spawn_repl(&dir);
    let mut input = child.stdin.take().unwrap();
    // Everything the terminal shows, collected as it comes.
    let shown = std::sync::Arc::new(std::sync::Mutex::new(String::new()));
    let mut stdout = child.stdout.take().unwrap();
    let sink = shown.clone();
    let reader = std::thread::spawn(move || {
        use std::io::Read;
        let mut buf = [0u8; 4096];
        while let Ok(n) = stdout.read(&mut buf) {
            if n == 0 {
                break;
            }
            sink.lock().unwrap().push_str(&String::from_utf8_lossy(&buf[..n]));
        }
    });
    use std::io::Write;
    let type_line = |input: &mut std::process::ChildStdin, line: &str| {
        writeln!(input, "{line}").unwrap();
        input.flush().unwrap();
    };
    for line in SLOW.lines().chain(["render big.png"]) {
        type_line(&mut input, line);
    }
    wait_for_tmp(&dir, &mut child);
    std::thread::sleep(Duration::from_millis(200));
    let sent = Instant::now();
    input.write_all(b"\x03").unwrap();
    input.flush().unwrap();
    while listing(&dir).iter().any(|n| n.ends_with(".tmp")) {
        assert!(sent.elapsed() < Duration::from_secs(5), "the render was not cancelled");
        std::thread::sleep(Duration::from_millis(10));
    }
    type_line(&mut input, "puts \"alive $keep [file exists big.png]\"");
    type_line(&mut input, "exit 3");
    let status = child.wait().unwrap();
    reader.join().unwrap();
    let mut stderr = String::new();
    use std::io::Read;
    child.stderr.take().unwrap().read_to_string(&mut stderr).unwrap();
    let all = shown.lock().unwrap().clone() + &stderr;
    assert_eq!(status.code(), Some(3), "{all}");
    assert!(all.contains("interrupted"), "{all}");
    assert!(all.contains("alive 42 0"), "the session survives, with no image: {all}");
    drop(input);
    let _ = std::fs::remove_dir_all(&dir);
}

pub fn kill_9_never_leaves_a_truncated_image() {
    let dir = scratch("kill9");
    // Cheap to trace, slow to write: 48 MB of PPM.
    std::fs::write(
        dir.join("big.tsd"),
        "camera_resolution 4000 4000\nbackground 0.2 0.4 0.6\nrender big.ppm\n",
    )
    .unwrap();
    let want = 4000 * 4000 * 3 + "P6\n4000 4000\n255\n".len() as u64;
    for delay_ms in [0u64, 50, 150, 400] {
        let _ = std::fs::remove_file(dir.join("big.ppm"));
        let mut child =
            raytrace().arg("big.tsd").current_dir(&dir).stderr(Stdio::null()).spawn().unwrap();
        wait_for_tmp(&dir, &mut child);
        std::thread::sleep(Duration::from_millis(delay_ms));
        signal(&child, "-KILL");
        let _ = child.wait();
        if let Ok(m) = std::fs::metadata(dir.join("big.ppm")) {
            assert_eq!(m.len(), want, "killed after {delay_ms} ms: a truncated image");
        }
    }
    // Only leftovers are hidden temporary files (kill -9 cannot be caught).
    assert!(listing(&dir).iter().all(|n| n == "big.tsd" || n == "big.ppm" || n.ends_with(".tmp")));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Waits for `child` at most `secs` seconds (killing it after), and returns
/// its output.
fn wait_at_most(mut child: Child, secs: u64) -> std::process::Output {
    let start = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(secs) {
            let _ = child.kill();
            panic!("still running after {secs} s");
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    child.wait_with_output().unwrap()
}

/// Runs raytrace with `args` in `dir` (its stdin a pipe nobody writes),
/// sends it SIGINT after `ms`; its output, and how long it took to end
/// after the signal.
fn interrupted_after(dir: &Path, args: &[&str], ms: u64) -> (std::process::Output, Duration) {
    let child = raytrace()
        .args(args)
        .current_dir(dir)
        .stdin(Stdio::piped())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(Duration::from_millis(ms));
    let sent = Instant::now();
    signal(&child, "-INT");
    let out = wait_at_most(child, 10);
    (out, sent.elapsed())
}

/// Waits that once ignored Ctrl-C: a FIFO nobody writes to, as the script,
/// to `source` and to `mesh`, and standard input that never comes. Each
/// ends at the first SIGINT with status 130. Issue "hostile input, second
/// round".
pub fn waits_for_input_give_way_to_ctrl_c() {
    if Command::new("mkfifo").arg("--version").output().is_err() {
        crate::util::skip("mkfifo (coreutils) is not installed");
    }
    let dir = scratch("fifo-sigint");
    assert!(Command::new("mkfifo").arg(dir.join("pipe")).status().unwrap().success());
    let cases: [(&str, &[&str]); 4] = [
        ("the script", &["pipe"]),
        ("source", &["-c", "puts hello; source pipe"]),
        ("mesh", &["-c", "puts hello; mesh pipe"]),
        ("stdin", &["-"]),
    ];
    for (what, args) in cases {
        let (out, _) = interrupted_after(&dir, args, 300);
        assert_eq!(out.status.code(), Some(130), "{what}: {}", text(&out.stderr));
        if args.len() == 2 {
            assert_eq!(text(&out.stdout), "hello\n", "{what}: output before the wait is kept");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// SIGTERM, SIGHUP and two quick SIGINTs during a render: status 130, the
/// buffered output is flushed, no temporary file stays.
pub fn every_interrupt_exits_130_flushed_and_clean() {
    for sigs in [&["-TERM"][..], &["-HUP"], &["-INT", "-INT"]] {
        let dir = scratch("signals");
        std::fs::write(dir.join("slow.tsd"), format!("puts before\n{SLOW}render slow.png\n"))
            .unwrap();
        let mut child = raytrace()
            .arg("slow.tsd")
            .current_dir(&dir)
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        wait_for_tmp(&dir, &mut child);
        for s in sigs {
            signal(&child, s);
        }
        let out = wait_at_most(child, 10);
        assert_eq!(out.status.code(), Some(130), "{sigs:?}: {}", text(&out.stderr));
        assert_eq!(text(&out.stdout), "before\n", "{sigs:?}");
        assert_eq!(listing(&dir), ["slow.tsd"], "{sigs:?}: no image, no temporary file");
        let _ = std::fs::remove_dir_all(&dir);
    }
}

/// Ctrl-C while a large PNG is being encoded (it was once ignored until
/// the file was whole): status 130, no image, no temporary file.
pub fn ctrl_c_during_a_png_encode() {
    let dir = scratch("sigint-encode");
    // Quick to trace, a second or more to encode: 64 Mpixel of sky.
    let scene = "camera_resolution 8192 8192; background 0.2 0.3 0.4";
    let mut child = raytrace()
        .args(["-q", "-c", scene, "big.png"])
        .current_dir(&dir)
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // The encode has begun when the temporary file has bytes.
    let start = Instant::now();
    loop {
        let tmp = listing(&dir).into_iter().find(|n| n.ends_with(".tmp"));
        if let Some(t) = tmp
            && std::fs::metadata(dir.join(t)).is_ok_and(|m| m.len() > 0)
        {
            break;
        }
        assert!(child.try_wait().unwrap().is_none(), "the encode ended before it was seen");
        assert!(start.elapsed() < Duration::from_secs(120), "the encode never started");
        std::thread::sleep(Duration::from_millis(5));
    }
    signal(&child, "-INT");
    let out = wait_at_most(child, 10);
    assert_eq!(out.status.code(), Some(130), "{}", text(&out.stderr));
    assert!(listing(&dir).is_empty(), "{:?}", listing(&dir));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue "untrusted scenes", finding 12: one SIGINT ends the run within
/// half a second wherever it waits (a FIFO opened by Tcl's `open`, `gets`
/// on input that never comes, a program run by `exec` that ignores it,
/// expensive pixels), and a signal during the script's last command is
/// not lost: never status 0.
pub fn one_ctrl_c_ends_every_wait_within_half_a_second() {
    if Command::new("mkfifo").arg("--version").output().is_err() {
        crate::util::skip("mkfifo (coreutils) is not installed");
    }
    let dir = scratch("sigint-waits");
    assert!(Command::new("mkfifo").arg(dir.join("pipe")).status().unwrap().success());
    let cases: [(&str, &[&str]); 6] = [
        ("open", &["-c", "puts hello; open pipe"]),
        ("gets", &["-c", "puts hello; gets stdin"]),
        ("exec", &["-c", "puts hello; exec sleep 31.25"]),
        ("texture", &["-c", "puts hello; texture image pipe planar"]),
        ("nff", &["-c", "puts hello; nff pipe"]),
        (
            "expensive pixels",
            &[
                "-c",
                "puts hello; camera_resolution 2 2; samples 65536; sphere 0 0 -3 1
                 area_light 1 1 1 0 3 0 1 0 0 0 0 1 32; render x.ppm",
            ],
        ),
    ];
    for (what, args) in cases {
        let (out, took) = interrupted_after(&dir, args, 400);
        assert_eq!(out.status.code(), Some(130), "{what}: {}", text(&out.stderr));
        assert_eq!(text(&out.stdout), "hello\n", "{what}: output before the wait is kept");
        // Half a second, and the time a loaded machine takes to reap.
        assert!(took < Duration::from_millis(900), "{what}: {took:?}");
    }
    assert_eq!(listing(&dir), ["pipe"], "no picture, no temporary file");
    // The program `exec` waited for got the signal too.
    std::thread::sleep(Duration::from_millis(200));
    if let Ok(p) = Command::new("pgrep").args(["-f", "sleep 31.25"]).output() {
        assert!(p.stdout.is_empty(), "exec's child outlived raytrace: {}", text(&p.stdout));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--time-limit`: a script that would run for ever ends with status 124
/// and no picture, at about the limit.
pub fn a_time_limit_ends_the_run_with_124() {
    let dir = scratch("time-limit");
    for script in [
        "while 1 {}",
        "camera_resolution 3000 3000; samples 64; sphere 0 0 -3 1; point_light 1 1 1 0 5 0",
    ] {
        let start = Instant::now();
        let out = raytrace()
            .args(["--time-limit", "0.5", "-c", script, "out.png"])
            .current_dir(&dir)
            .output()
            .unwrap();
        let took = start.elapsed();
        assert_eq!(out.status.code(), Some(124), "{script}: {}", text(&out.stderr));
        assert!(text(&out.stderr).contains("time limit"), "{}", text(&out.stderr));
        assert!(took < Duration::from_millis(1500), "{script}: {took:?}");
        assert!(listing(&dir).is_empty(), "{:?}", listing(&dir));
    }
    let _ = std::fs::remove_dir_all(&dir);
}
