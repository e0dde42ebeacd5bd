//! The bad-input corpus: every scene command with missing, extra,
//! non-numeric, NaN and infinite arguments, impossible values, bad paths,
//! broken syntax, runaway growth and recursion, binary garbage, huge input.
//! Each must end with its documented exit status and a `file:line:` message,
//! never a panic, never a partial file; and the REPL must survive each one
//! with its variables, procs and scene intact.

use rayshell::shell::repl::{Reply, eval_line};
use rayshell::shell::{CaptureHost, Session};

use crate::util::{listing, raytrace, scratch, text};

/// (what, script, exit status, message). Scripts run after a first line
/// `puts ok`, so the message starts with `bad.tsd:LINE:` where LINE is the
/// script's last line plus one, unless the message gives its own `@LINE `.
const CORPUS: &[(&str, &str, i32, &str)] = &[
    ("camera_from missing", "camera_from 1 2", 1, "wrong # args: should be \"camera_from x y z\""),
    (
        "raybench no threads",
        "raybench -threads 0",
        1,
        "expected a thread count from 1 to 256 but got \"0\"",
    ),
    (
        "raybench threads word",
        "raybench -threads",
        1,
        "expected a thread count from 1 to 256 but got \"\"",
    ),
    (
        "raybench option",
        "raybench -fast",
        1,
        "bad option \"-fast\": must be -shadow, -brute or -threads",
    ),
    (
        "camera_from extra",
        "camera_from 1 2 3 4",
        1,
        "wrong # args: should be \"camera_from x y z\"",
    ),
    ("camera_from word", "camera_from x 0 0", 1, "camera_from: x: expected number but got \"x\""),
    (
        "camera_from nan",
        "camera_from nan 0 0",
        1,
        "camera_from: x: expected a finite number but got \"NaN\"",
    ),
    (
        "camera_target inf",
        "camera_target 0 0 inf",
        1,
        "camera_target: z: expected a finite number but got \"Inf\"",
    ),
    (
        "camera_target missing",
        "camera_target 0 0",
        1,
        "wrong # args: should be \"camera_target x y z\"",
    ),
    ("camera_up zero", "camera_up 0 0 0", 1, "camera_up vector must not be the zero vector"),
    (
        "camera_up parallel",
        "camera_up 0 0 1\nrender x.ppm",
        1,
        "camera up vector is parallel to the view direction",
    ),
    (
        "camera_forw zero",
        "camera_forw 0 0 0",
        1,
        "camera_forw direction must not be the zero vector",
    ),
    ("camera_angle missing", "camera_angle", 1, "wrong # args: should be \"camera_angle theta\""),
    (
        "camera_angle zero",
        "camera_angle 0",
        1,
        "camera angle must be between 0 and 180 degrees, got 0",
    ),
    (
        "camera_angle negative",
        "camera_angle -10",
        1,
        "camera angle must be between 0 and 180 degrees, got -10",
    ),
    (
        "camera_angle 180",
        "camera_angle 180",
        1,
        "camera angle must be between 0 and 180 degrees, got 180",
    ),
    (
        "camera_angle nan",
        "camera_angle nan",
        1,
        "camera_angle: theta: expected a finite number but got \"NaN\"",
    ),
    (
        "camera_resolution zero",
        "camera_resolution 0 10",
        1,
        "resolution must be at least 1x1, got 0x10",
    ),
    (
        "camera_resolution missing",
        "camera_resolution 10",
        1,
        "wrong # args: should be \"camera_resolution width height\"",
    ),
    (
        "camera_resolution absurd",
        "camera_resolution 1000000 1000000",
        1,
        "resolution 1000000x1000000 would need 11444091 MiB for the image; the limit is 64 Mpixel",
    ),
    (
        "camera_resolution fraction",
        "camera_resolution 10.5 10",
        1,
        "camera_resolution: width: expected integer but got \"10.5\"",
    ),
    (
        "camera_resolution negative",
        "camera_resolution -5 5",
        1,
        "resolution must be at least 1x1, got -5x5",
    ),
    ("vertex missing", "vertex 1 2", 1, "wrong # args: should be \"vertex x y z\""),
    ("vertex extra", "vertex 1 2 3 4", 1, "wrong # args: should be \"vertex x y z\""),
    ("vertex words", "vertex a b c", 1, "vertex: x: expected number but got \"a\""),
    ("vertex nan", "vertex nan 0 0", 1, "vertex: x: expected a finite number but got \"NaN\""),
    ("vertex inf", "vertex 0 inf 0", 1, "vertex: y: expected a finite number but got \"Inf\""),
    (
        "vertex overflow",
        "vertex 0 0 1e400",
        1,
        "vertex: z: expected a finite number but got \"Inf\"",
    ),
    ("normal zero", "normal 0 0 0", 1, "a normal must not be the zero vector"),
    ("normal missing", "normal 1 2", 1, "wrong # args: should be \"normal x y z\""),
    ("normal -inf", "normal -inf 0 0", 1, "normal: x: expected a finite number but got \"-Inf\""),
    (
        "tri empty pool",
        "tri 0 1 2",
        1,
        "vertex index 0 out of range: the vertex pool has 0 entries",
    ),
    (
        "tri index past end",
        "vertex 0 0 0\ntri 0 0 1",
        1,
        "vertex index 1 out of range: the vertex pool has 1 entries",
    ),
    (
        "tri negative index",
        "vertex 0 0 0\ntri 0 0 -1",
        1,
        "vertex index -1 out of range: the vertex pool has 1 entries",
    ),
    ("tri fraction", "tri 0.5 1 2", 1, "tri: v1: expected integer but got \"0.5\""),
    ("tri missing", "tri 1 2", 1, "wrong # args: should be \"tri v1 v2 v3\""),
    (
        "tri huge index",
        "vertex 0 0 0\ntri 0 0 99999999999999999999",
        1,
        "tri: v3: integer 99999999999999999999 is too large",
    ),
    ("ntri missing", "ntri 0 0 0 0 0", 1, "wrong # args: should be \"ntri v1 n1 v2 n2 v3 n3\""),
    (
        "ntri normal out of range",
        "vertex 0 0 0\nntri 0 0 0 0 0 0",
        1,
        "normal index 0 out of range: the normal pool has 0 entries",
    ),
    ("sphere missing", "sphere 1 2 3", 1, "wrong # args: should be \"sphere x y z radius\""),
    ("sphere extra", "sphere 1 2 3 4 5", 1, "wrong # args: should be \"sphere x y z radius\""),
    ("sphere word", "sphere a 0 0 1", 1, "sphere: x: expected number but got \"a\""),
    ("sphere negative radius", "sphere 0 0 0 -1", 1, "sphere radius must be positive, got -1"),
    ("sphere zero radius", "sphere 0 0 0 0", 1, "sphere radius must be positive, got 0"),
    (
        "sphere nan radius",
        "sphere 0 0 0 nan",
        1,
        "sphere: radius: expected a finite number but got \"NaN\"",
    ),
    (
        "sphere inf radius",
        "sphere 0 0 0 inf",
        1,
        "sphere: radius: expected a finite number but got \"Inf\"",
    ),
    ("background negative", "background -1 0 0", 1, "colour components must not be negative"),
    ("background missing", "background 1 1", 1, "wrong # args: should be \"background r g b\""),
    (
        "background nan",
        "background nan 0 0",
        1,
        "background: r: expected a finite number but got \"NaN\"",
    ),
    (
        "ambient_light word",
        "ambient_light 1 1 x",
        1,
        "ambient_light: b: expected number but got \"x\"",
    ),
    (
        "parallel_light zero direction",
        "parallel_light 1 1 1 0 0 0",
        1,
        "light direction must not be the zero vector",
    ),
    (
        "parallel_light missing",
        "parallel_light 1 1 1 0 -1",
        1,
        "wrong # args: should be \"parallel_light r g b x y z\"",
    ),
    (
        "point_light nan",
        "point_light 1 1 1 0 0 nan",
        1,
        "point_light: z: expected a finite number but got \"NaN\"",
    ),
    (
        "point_light two falloff coefficients",
        "point_light 1 1 1 0 0 0 1 0",
        1,
        "wrong # args: should be \"point_light r g b x y z ?constant linear quadratic?\"",
    ),
    (
        "point_light negative falloff",
        "point_light 1 1 1 0 0 0 -1 0 0",
        1,
        "light falloff coefficients must be finite, not negative and not all zero, got -1 0 0",
    ),
    (
        "point_light no falloff at all",
        "point_light 1 1 1 0 0 0 0 0 0",
        1,
        "light falloff coefficients must be finite, not negative and not all zero, got 0 0 0",
    ),
    (
        "spot_light falloff not a number",
        "spot_light 1 1 1 0 0 0 0 -1 0 10 20 1 x 0",
        1,
        "spot_light: linear: expected number but got \"x\"",
    ),
    (
        "spot_light angles reversed",
        "spot_light 1 1 1 0 0 0 0 -1 0 30 20",
        1,
        "spot light angles must satisfy 0 <= angle1 <= angle2 <= 180, got 30 and 20",
    ),
    (
        "spot_light zero axis",
        "spot_light 1 1 1 0 0 0 0 0 0 10 20",
        1,
        "spot light direction must not be the zero vector",
    ),
    (
        "spot_light negative angle",
        "spot_light 1 1 1 0 0 0 0 -1 0 -5 20",
        1,
        "spot light angles must satisfy 0 <= angle1 <= angle2 <= 180, got -5 and 20",
    ),
    (
        "material glass zero ior",
        "material 1 1 1 0 1 0 1 0.5 0",
        1,
        "index of refraction must be positive (or 0 when T is 0), got 0",
    ),
    ("exit -1 is 255", "exit -1", 255, ""),
    ("exit past an int", "exit 9223372036854775807", 1, "integer value too large to represent"),
    ("return -code error at the top", "return -code error boom", 1, ""),
    (
        "lrepeat nothing for ever",
        "lrepeat 9223372036854775807",
        1,
        "integer value too large to represent",
    ),
    (
        "lsort with an inconsistent order",
        "proc r {a b} {expr {int(rand()*3)-1}}; lsort -command r [lrepeat 300 a b c d e f g]",
        0,
        "",
    ),
    (
        "material huge ior",
        "material 1 1 1 0.2 0.8 0 1 0.9 1e38",
        1,
        "index of refraction must be between 0.01 and 100, got 1e38",
    ),
    (
        "material negative ior",
        "material 1 1 1 0 1 0 1 0 -1",
        1,
        "index of refraction must be positive (or 0 when T is 0), got -1",
    ),
    (
        "camera_resolution fraction as decimal",
        "camera_resolution 64.0 2.5",
        1,
        "camera_resolution: height: expected integer but got \"2.5\"",
    ),
    (
        "material negative Kd",
        "material 1 1 1 0 -1 0 1 0 1",
        1,
        "material Kd must not be negative, got -1",
    ),
    (
        "material negative T",
        "material 1 1 1 0 1 0 1 -0.5 1",
        1,
        "material T must not be negative, got -0.5",
    ),
    (
        "material negative n_s",
        "material 1 1 1 0 1 0 -1 0 1",
        1,
        "material n_s must not be negative, got -1",
    ),
    (
        "material missing",
        "material 1 1 1",
        1,
        "wrong # args: should be \"material r g b Ka Kd Ks n_s T index_of_refraction\"",
    ),
    (
        "material extra",
        "material 1 1 1 0 1 0 1 0 1 9",
        1,
        "wrong # args: should be \"material r g b Ka Kd Ks n_s T index_of_refraction\"",
    ),
    ("trace_depth huge", "trace_depth 1000", 1, "trace depth must be between 0 and 64, got 1000"),
    ("trace_depth negative", "trace_depth -1", 1, "trace depth must be between 0 and 64, got -1"),
    (
        "trace_depth fraction",
        "trace_depth 2.5",
        1,
        "trace_depth: n: expected integer but got \"2.5\"",
    ),
    (
        "render unknown format",
        "render x.jpg",
        1,
        "unknown image format for \"x.jpg\": the name must end in .ppm, .png or .pfm",
    ),
    (
        "render missing dir",
        "render /nonexistent-dir/x.ppm",
        1,
        "couldn't write \"/nonexistent-dir/x.ppm\": no such file or directory",
    ),
    ("render into a file", "render bad.tsd/x.png", 74, "couldn't write \"bad.tsd/x.png\": "),
    (
        "render no file",
        "render",
        1,
        "wrong # args: should be \"render ?-srgb? ?-heatmap? ?-progressive? fileName\"",
    ),
    (
        "render bad option",
        "render -bogus x.ppm",
        1,
        "bad option \"-bogus\": must be -heatmap, -progressive, or -srgb",
    ),
    (
        "mesh missing file",
        "mesh missing.obj",
        1,
        "couldn't read \"missing.obj\": no such file or directory",
    ),
    ("mesh garbage file", "mesh garbage.obj", 1, "garbage.obj:"),
    ("mesh bad face", "mesh badface.obj", 1, "badface.obj:4: bad OBJ line \"f 1 2 7\""),
    ("mesh NaN vertex", "mesh nanvertex.obj", 1, "nanvertex.obj:2: bad OBJ line \"v nan 0 0\""),
    ("mesh zero scale", "mesh badface.obj -scale 0", 1, "mesh -scale must not be zero"),
    (
        "mesh bad option",
        "mesh badface.obj -rotate 9",
        1,
        "bad option \"-rotate\": must be -flat, -scale, -subdivide, or -translate",
    ),
    (
        "source missing",
        "source missing.tsd",
        1,
        "couldn't read file \"missing.tsd\": no such file or directory",
    ),
    ("source itself", "source bad.tsd", 1, "@1 too many nested evaluations (infinite loop?)"),
    ("unknown command", "sphre 0 0 0 1", 1, "invalid command name \"sphre\""),
    ("unterminated quote", "puts \"abc", 1, "missing \""),
    ("unterminated bracket", "puts [expr 1", 1, "missing close-bracket"),
    ("unterminated brace", "proc f {} {", 1, "missing close-brace"),
    ("chars after brace", "set x {a}b", 1, "extra characters after close-brace"),
    ("divide by zero", "expr {1/0}", 1, "divide by zero"),
    ("domain error", "expr {sqrt(-1)}", 1, "domain error: argument not in valid range"),
    (
        "infinite recursion",
        "proc f {} {f}\nf",
        1,
        "@2 too many nested evaluations (infinite loop?)",
    ),
    (
        "runaway string",
        "string repeat x 2000000000",
        1,
        "string too long: rayshell values are limited to 1073741824 bytes",
    ),
    (
        "runaway list",
        "lrepeat 200000000 x",
        1,
        "list too long: rayshell lists are limited to 67108864 elements",
    ),
    (
        "runaway split",
        "split [string repeat x 100000000] {}",
        1,
        "list too long: rayshell lists are limited to 67108864 elements",
    ),
    // Memory: the corpus runs with --max-memory 512M under a 4 GB
    // address-space cap; each growth below once aborted or ran the machine
    // out of memory. Issue "hostile input, second round".
    (
        "a 2 GB string from small lists",
        "puts [string length [lrepeat 1000 [lrepeat 1000 [lrepeat 1000 x]]]]",
        1,
        "string too long: rayshell values are limited to 1073741824 bytes",
    ),
    (
        "caught, the long list stays a list",
        "set l [lrepeat 1000 [lrepeat 1000 [lrepeat 1000 x]]]\n\
         if {[catch {string length $l} m] && [llength $l] == 1000} { error \"kept: $m\" }",
        1,
        "kept: string too long",
    ),
    (
        "string map on 400 MB",
        "set s [string repeat x 400000000]; string map {x yy} $s",
        1,
        "not enough memory: ",
    ),
    ("split of 10 M characters", "split [string repeat x 10000000] {}", 1, "not enough memory: "),
    ("concat doubling", "set l {a b c}; while 1 {set l [concat $l $l]}", 1, "not enough memory: "),
    ("append doubling", "set s x; while 1 {append s $s}", 1, "not enough memory: "),
    ("word doubling", "set s x; while 1 {set s $s$s}", 1, "not enough memory: "),
    ("lappend for ever", "while 1 {lappend l [incr i]}", 1, "not enough memory: "),
    ("array for ever", "while 1 {set a([incr i]) [incr i]}", 1, "not enough memory: "),
    ("lights for ever", "while 1 {point_light 1 1 1 0 0 0}", 1, "not enough memory: "),
    ("materials for ever", "while 1 {material 1 1 1 0 1 0 1 0 1}", 1, "not enough memory: "),
    ("spheres for ever", "while 1 {sphere 0 0 0 1}", 1, "not enough memory: "),
    (
        "triangles for ever",
        "vertex 0 0 0; vertex 1 0 0; vertex 0 1 0; while 1 {tri 0 1 2}",
        1,
        "not enough memory: ",
    ),
    (
        "a picture past the budget",
        "camera_resolution 8192 8192; point_light 1 1 1 0 5 0; sphere 0 0 -5 1; render big.png",
        1,
        "not enough memory: 960 MiB more would pass the budget of 512 MiB",
    ),
    (
        "source /dev/zero",
        "source /dev/zero",
        1,
        "couldn't read file \"/dev/zero\": not enough memory",
    ),
    ("mesh /dev/zero", "mesh /dev/zero", 1, "/dev/zero:1: line longer than 16 MiB"),
    ("nff /dev/zero", "nff /dev/zero", 1, "/dev/zero:1: line longer than 1 MiB"),
    // Nesting: a list a million deep prints and frees without recursion
    // (it once overflowed the stack); Tcl's level count is tclsh's.
    (
        "a list nested a million deep",
        "set l x; for {set i 0} {$i<1000000} {incr i} {set l [list $l]}\n\
         if {[string length $l] != 1} { error wrong }",
        0,
        "",
    ),
    (
        "a list of lists a thousand deep",
        "set l x; for {set i 0} {$i<1000} {incr i} {set l [list $l y]}\n\
         if {[string length $l] != 3999} { error [string length $l] }",
        0,
        "",
    ),
    ("recursion to level 1000", "proc f {n} {if {$n>0} {f [expr {$n-1}]}}; f 999", 0, ""),
    (
        "recursion past level 1000",
        "proc f {n} {if {$n>0} {f [expr {$n-1}]}}; f 1000",
        1,
        "too many nested evaluations (infinite loop?)",
    ),
    (
        "eval recursion counts two levels",
        "proc g {n} {if {$n>0} {eval g [expr {$n-1}]}}; g 500",
        1,
        "too many nested evaluations (infinite loop?)",
    ),
    (
        "a resolution written as a double",
        "camera_resolution 1e9 1e9",
        1,
        "resolution 1000000000x1000000000 would need",
    ),
    ("array as scalar", "set a(1) 1\nset a 2", 1, "can't set \"a\": variable is array"),
    ("break outside loop", "break", 1, "invoked \"break\" outside of a loop"),
    ("exit code", "exit 3", 3, ""),
];

/// Inputs too big or too odd to write inline: (what, script, status, message).
fn generated() -> Vec<(&'static str, String, i32, String)> {
    let garbage: String = (0u8..=255).map(|b| b as char).cycle().take(4000).collect();
    vec![
        ("binary garbage", garbage, 1, "@2 invalid command name".into()),
        (
            "100,000 nested braces (balanced: fine)",
            format!("set x {}{}", "{".repeat(100_000), "}".repeat(100_000)),
            0,
            String::new(),
        ),
        (
            "100,000 open braces",
            format!("set x {}", "{".repeat(100_000)),
            1,
            "missing close-brace".into(),
        ),
        (
            "100,000 nested brackets",
            format!("set x {}{}", "[".repeat(100_000), "]".repeat(100_000)),
            1,
            "too many nested brackets".into(),
        ),
        (
            "a 100 MB line",
            format!("vertex 1 2 3 {}", "7".repeat(100 << 20)),
            1,
            "wrong # args: should be \"vertex x y z\"".into(),
        ),
    ]
}

fn all_cases() -> Vec<(String, String, i32, String)> {
    let mut v: Vec<_> = CORPUS
        .iter()
        .map(|(w, s, c, m)| (w.to_string(), s.to_string(), *c, m.to_string()))
        .collect();
    v.extend(generated().into_iter().map(|(w, s, c, m)| (w.to_string(), s, c, m)));
    v
}

/// Files the cases refer to.
fn setup(dir: &std::path::Path) {
    std::fs::write(dir.join("garbage.obj"), (0u8..=255).cycle().take(1024).collect::<Vec<u8>>())
        .unwrap();
    std::fs::write(dir.join("badface.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 7\n").unwrap();
    std::fs::write(dir.join("nanvertex.obj"), "v 0 0 0\nv nan 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
}

pub fn the_corpus_is_big_enough() {
    assert!(all_cases().len() >= 60, "{} cases", all_cases().len());
}

/// The binary under a 4 GB address-space cap (`prlimit --as`, when
/// util-linux has it) with a 512 MiB memory budget.
fn capped() -> std::process::Command {
    let mut c = if std::process::Command::new("prlimit").arg("--version").output().is_ok() {
        let mut c = std::process::Command::new("prlimit");
        c.args(["--as=4000000000", "--", env!("CARGO_BIN_EXE_raytrace")]);
        c
    } else {
        raytrace()
    };
    c.args(["--max-memory", "512M"]);
    c
}

pub fn every_bad_input_exits_with_a_located_message() {
    let dir = scratch("bad-corpus");
    setup(&dir);
    for (what, script, code, msg) in all_cases() {
        std::fs::write(dir.join("bad.tsd"), format!("puts ok\n{script}\n")).unwrap();
        let r = capped().arg("bad.tsd").current_dir(&dir).output().unwrap();
        let err = text(&r.stderr);
        let head: String = err.chars().take(300).collect();
        assert_eq!(r.status.code(), Some(code), "{what}: {head}");
        if code == 0 {
            continue;
        }
        assert!(text(&r.stdout).starts_with("ok\n"), "{what}: output before the error stays");
        if !msg.is_empty() {
            let (line, msg) = match msg.strip_prefix('@') {
                Some(rest) => rest.split_once(' ').unwrap(),
                None => ("", msg.as_str()),
            };
            let line = if line.is_empty() {
                (2 + script.lines().count() - 1).to_string()
            } else {
                line.into()
            };
            let want = format!("bad.tsd:{line}: {msg}");
            assert!(err.starts_with(&want), "{what}: want {want:?}\n got {head}");
        }
        // Nothing left behind: no partial image, no temporary file.
        assert_eq!(
            listing(&dir),
            ["bad.tsd", "badface.obj", "garbage.obj", "nanvertex.obj"],
            "{what}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

pub fn the_repl_survives_every_bad_input() {
    let dir = scratch("bad-repl");
    setup(&dir);
    let d = dir.clone();
    rayshell::shell::on_big_stack(move || {
        let mut s = Session::new(Box::new(CaptureHost::default()));
        let i = &mut s.interp;
        let p = |f: &str| d.join(f).to_string_lossy().into_owned();
        for line in [
            "set keep 42",
            "proc twice {x} {expr {2 * $x}}",
            "sphere 0 0 -5 1",
            "point_light 1 1 1 0 5 0",
        ] {
            assert!(!matches!(eval_line(i, line), Reply::Error(_)), "{line}");
        }
        std::fs::write(d.join("bad.tsd"), format!("source {}\n", p("bad.tsd"))).unwrap();
        for (what, script, code, msg) in all_cases() {
            // This process has no memory budget (see
            // `the_repl_keeps_its_session_past_the_memory_budget`).
            if msg.starts_with("not enough memory") {
                continue;
            }
            // The REPL runs in another directory: name files in full.
            let full = |text: String| {
                [
                    "bad.tsd",
                    "garbage.obj",
                    "badface.obj",
                    "nanvertex.obj",
                    "missing.obj",
                    "missing.tsd",
                    "x.ppm",
                ]
                .iter()
                .fold(text, |s, f| s.replace(f, &p(f)))
            };
            let (script, msg) = (full(script), full(msg));
            let reply = eval_line(i, &script);
            match (code, &reply) {
                (0, Reply::Nothing | Reply::Result(_)) => {}
                (c, Reply::Exit(n)) if n & 0xff == c => {}
                (_, Reply::Error(e)) => {
                    let msg = msg
                        .split_once(' ')
                        .filter(|_| msg.starts_with('@'))
                        .map_or(msg.as_str(), |m| m.1);
                    let first = msg.split(['"', ':']).next().unwrap();
                    assert!(e.starts_with(first), "{what}: {e}");
                }
                _ => panic!("{what}: {reply:?}"),
            }
            // (`camera_up 0 0 1` is accepted and stays: only `render` objects.)
            eval_line(i, "camera_up 0 1 0");
            // Variables, procs and the scene are still there.
            assert_eq!(eval_line(i, "set keep"), Reply::Result("42".into()), "after {what}");
            assert_eq!(eval_line(i, "twice 21"), Reply::Result("42".into()), "after {what}");
            let (lo, hi) = s.scene.borrow().bounds().expect("the sphere is gone");
            assert!(lo.z <= -6.0 && hi.z >= -4.0, "after {what}: the sphere is gone");
        }
        // And it still renders.
        let out = p("after.ppm");
        assert_eq!(eval_line(i, "clear_scene"), Reply::Nothing);
        for line in [
            "camera_resolution 4 4",
            "ambient_light 1 1 1",
            "sphere 0 0 -5 1",
            &format!("render {out}"),
        ] {
            assert_eq!(eval_line(i, line), Reply::Nothing, "{line}");
        }
    })
    .unwrap();
    assert!(dir.join("after.ppm").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Renders that once aborted or ran for ever, run through the binary under
/// a 4 GB address-space cap (`prlimit --as`): each must finish, exit 0 and
/// write its picture. Issue "hostile input, second round".
pub fn hostile_renders_finish_under_a_memory_cap() {
    if std::process::Command::new("prlimit").arg("--version").output().is_err() {
        crate::util::skip("prlimit (util-linux) is not installed");
    }
    // (what, scene, whether something shows at the centre)
    let cases = [
        // A mirror sphere too small for single precision: NaN normals and
        // directions, which once sent the BVH walk round its root for ever.
        ("degenerate mirror sphere", "material 1 1 1 0 0 1 1 0 1; sphere 0 0 -1e-30 1e-31", false),
        // Ks + T = 1.5 at trace_depth 64 through 50 glass balls: the ray tree
        // doubles at every bounce (over 10 minutes before the per-pixel cap).
        (
            "ray tree that doubles",
            "trace_depth 64; material 1 1 1 0 0 0.5 1 1 1.5\n\
             for {set i 0} {$i < 50} {incr i} { sphere 0 0 [expr {-$i * 2.5}] 1 }",
            false,
        ),
        // Far from the origin: once "up vector is parallel" and "degenerate".
        (
            "camera at 1e30",
            "ambient_light 1 1 1; camera_from 1e30 0 5; camera_target 1e30 0 0; sphere 1e30 0 0 1",
            true,
        ),
        (
            "triangle near 1e20",
            "ambient_light 1 1 1; camera_from 1e20 1e20 5; camera_target 1e20 1e20 0\n\
             tri [vertex -1e5 -1e5 0] [vertex 1e5 -1e5 0] [vertex 0 1e5 0]\n\
             tri [vertex [expr {1e20-1e5}] [expr {1e20-1e5}] 0] [vertex [expr {1e20+1e5}] \
             [expr {1e20-1e5}] 0] [vertex 1e20 [expr {1e20+1e5}] 0]",
            true,
        ),
    ];
    let dir = scratch("hostile-renders");
    for (what, scene, visible) in cases {
        let script = format!(
            "camera_resolution 32 32; camera_from 0 0 5; camera_target 0 0 0\n\
             point_light 10 10 10 0 5 5\n{scene}\nrender out.png\n"
        );
        std::fs::write(dir.join("s.tsd"), script).unwrap();
        let start = std::time::Instant::now();
        let r = std::process::Command::new("prlimit")
            .args(["--as=4000000000", "--", env!("CARGO_BIN_EXE_raytrace"), "-q", "s.tsd"])
            .current_dir(&dir)
            .output()
            .unwrap();
        assert_eq!(r.status.code(), Some(0), "{what}: {}", text(&r.stderr));
        let png = std::fs::read(dir.join("out.png")).expect("a picture");
        // Generous: an unbounded tree takes hours, the bounded one < 1 s.
        assert!(start.elapsed().as_secs() < 60, "{what}: {:?}", start.elapsed());
        if visible {
            let img = rayshell::image::read_rgb8(&png).unwrap();
            let centre = (16 * 32 + 16) * 3;
            assert!(img.rgb[centre..centre + 3].iter().all(|&c| c > 40), "{what}: not seen");
        }
        std::fs::remove_file(dir.join("out.png")).unwrap();
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The REPL (on a terminal, through the binary) with a 64 MiB budget: growth
/// past it is an error; what is held stays readable, and freeing it makes
/// room again.
pub fn the_repl_keeps_its_session_past_the_memory_budget() {
    let (code, shown) = crate::util::repl_session_with(
        &["--max-memory", "64M"],
        &[
            "set keep 42",
            "while 1 {lappend l [incr i]}",
            "puts \"held [expr {[llength $l] > 1000}] keep $keep\"",
            "while 1 {point_light 1 1 1 0 0 0}",
            "puts \"alive $keep\"",
            "unset l; clear_scene",
            "puts \"room [llength [lrepeat 100000 x]]\"",
            "exit 7",
        ],
    );
    assert_eq!(code, Some(7), "{shown}");
    assert_eq!(shown.matches("not enough memory: ").count(), 2, "{shown}");
    for want in ["held 1 keep 42", "alive 42", "room 100000"] {
        assert!(shown.contains(want), "{want}: {shown}");
    }
}

/// A PNG of `width` x `height` RGB pixels whose data is one row of zeros:
/// a few dozen bytes whatever size its header claims.
fn png_claiming(width: u32, height: u32) -> Vec<u8> {
    use std::io::Write;
    let chunk = |kind: &[u8], data: &[u8]| {
        let mut crc = flate2::Crc::new();
        crc.update(kind);
        crc.update(data);
        let mut c = (data.len() as u32).to_be_bytes().to_vec();
        c.extend_from_slice(kind);
        c.extend_from_slice(data);
        c.extend_from_slice(&crc.sum().to_be_bytes());
        c
    };
    let mut ihdr = width.to_be_bytes().to_vec();
    ihdr.extend_from_slice(&height.to_be_bytes());
    ihdr.extend_from_slice(&[8, 2, 0, 0, 0]);
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::best());
    z.write_all(&vec![0u8; 1 + 3 * width.min(1 << 16) as usize]).unwrap();
    let mut png = b"\x89PNG\r\n\x1a\n".to_vec();
    png.extend(chunk(b"IHDR", &ihdr));
    png.extend(chunk(b"IDAT", &z.finish().unwrap()));
    png.extend(chunk(b"IEND", b""));
    png
}

/// Issue "untrusted scenes", finding 8: a picture's header is checked
/// against a size cap and the memory budget before any buffer is made, by
/// every command that reads pictures and by `--merge` and `--movie`.
pub fn picture_headers_are_checked_before_decoding() {
    let dir = scratch("png-bomb");
    let bomb = dir.join("bomb.png");
    std::fs::write(&bomb, png_claiming(1_000_000, 1_000_000)).unwrap();
    // 12,000 squared: under the pixel cap, over a 256 MB budget.
    let big = dir.join("big.png");
    std::fs::write(&big, png_claiming(12_000, 12_000)).unwrap();
    assert!(std::fs::metadata(&bomb).unwrap().len() < 1000);
    for file in [&bomb, &big] {
        let f = file.to_string_lossy();
        for cmd in [
            format!("texture image {f} planar"),
            format!("bump image {f} 1 planar"),
            format!("displace image {f} 1"),
            format!("environment {f}"),
            format!("show {f}"),
        ] {
            let r = raytrace().args(["--max-memory", "256M", "-c", &cmd]).output().unwrap();
            let err = text(&r.stderr);
            assert_eq!(r.status.code(), Some(1), "{cmd}: {err}");
            assert!(err.starts_with("-c:1: "), "{cmd}: {err}");
            assert!(err.contains("pixels") || err.contains("memory"), "{cmd}: {err}");
        }
        for mode in ["--merge", "--movie"] {
            let out = dir.join("out.png");
            let r = raytrace()
                .args(["--max-memory", "256M", mode])
                .arg(&out)
                .arg(file)
                .output()
                .unwrap();
            assert_eq!(r.status.code(), Some(1), "{mode}: {}", text(&r.stderr));
            assert!(!out.exists());
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Issue "untrusted scenes", findings 9 and 11: growth a script causes in
/// one command, or below many nested ones, is refused at the budget: the
/// peak resident size (`VmHWM`, read by the script itself after the
/// refusal) stays within the budget and a stated slack, and the refusal is
/// a located error that `catch` sees.
pub fn the_budget_is_a_ceiling_for_peak_memory() {
    if !std::path::Path::new("/proc/self/status").exists() {
        crate::util::skip("no /proc/self/status to read the peak resident size from");
    }
    // 64 MiB of budget; 96 MiB for the program, its threads and stacks.
    const BUDGET_MIB: u64 = 64;
    const SLACK_MIB: u64 = 96;
    let nested = format!("{}incr x{}", "if 1 {".repeat(20_000), "}".repeat(20_000));
    let coroutines = "proc deep {n} {if {$n > 0} {deep [expr {$n - 1}]} else {yield}}
        for {set i 0} {$i < 200} {incr i} {coroutine c$i deep 300}";
    let cases: Vec<(&str, String)> = vec![
        ("binary format a", "binary format a200000000 x".into()),
        ("binary format x", "binary format x200000000".into()),
        ("binary format @", "binary format @200000000".into()),
        ("hex", "binary encode hex [string repeat x 30000000]".into()),
        ("base64", "binary encode base64 -maxlen 2 [string repeat x 30000000]".into()),
        ("regsub", "regsub -all x [string repeat x 8000000] yyyyyyyyyyyyyyyy".into()),
        ("glob braces", "glob -nocomplain [string repeat \\{a,b,c,d,e,f,g,h,i,j\\} 7]".into()),
        // From a file of its own: its text and every parse of its bodies
        // are let go with the error (as a literal in the script, they
        // would stay cached there, and `catch` would find the heap still
        // past the budget).
        ("nested bodies", "source nested.tcl".into()),
        ("coroutines", coroutines.into()),
    ];
    let dir = scratch("ceiling");
    std::fs::write(dir.join("nested.tcl"), nested).unwrap();
    for (what, cmd) in cases {
        let script = format!(
            "set x 0\ncatch {{{cmd}}} m\nset f [open /proc/[pid]/status]\n\
             regexp {{VmHWM:\\s+(\\d+)}} [read $f] -> kb\nputs \"$kb|$m\""
        );
        let file = dir.join("s.tcl");
        std::fs::write(&file, script).unwrap();
        let r = raytrace()
            .args(["--max-memory", &format!("{BUDGET_MIB}M")])
            .arg(&file)
            .current_dir(&dir)
            .output()
            .unwrap();
        let out = text(&r.stdout);
        assert_eq!(r.status.code(), Some(0), "{what}: {}", text(&r.stderr));
        let (kb, msg) = out.trim().split_once('|').unwrap_or_else(|| panic!("{what}: {out}"));
        let peak_mib = kb.parse::<u64>().unwrap() / 1024;
        assert!(peak_mib <= BUDGET_MIB + SLACK_MIB, "{what}: peak {peak_mib} MiB; {msg}");
        assert!(msg.contains("memory"), "{what}: not refused: {}", &msg[..msg.len().min(200)]);
    }
    let _ = std::fs::remove_dir_all(&dir);
}
