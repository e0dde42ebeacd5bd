//! `--safe`: each fence holds (issues "Tcl 8.6" and "untrusted scenes").

use crate::util::{listing, raytrace, scratch, text};

/// A scene dir, an output dir and a private dir beside them; the scene
/// tries every way out and prints what each attempt gave.
pub fn every_fence_holds() {
    let dir = scratch("safe");
    let (scene, out, private) = (dir.join("scene"), dir.join("out"), dir.join("private"));
    for d in [&scene, &out, &private] {
        std::fs::create_dir_all(d).unwrap();
    }
    std::fs::write(scene.join("data.txt"), "scene data\n").unwrap();
    std::fs::write(private.join("secret.txt"), "secret\n").unwrap();
    let p = private.to_string_lossy();
    let o = out.to_string_lossy();
    let attempts = [
        (
            "read own",
            "set f [open [file join [file dirname [info script]] data.txt]]; gets $f".to_string(),
        ),
        ("read private", format!("open {p}/secret.txt")),
        ("read up and over", "open [file dirname [info script]]/../private/secret.txt".to_string()),
        ("read /etc", "open /etc/passwd".to_string()),
        ("source private", format!("source {p}/secret.txt")),
        ("write", "open [file dirname [info script]]/new.txt w".to_string()),
        ("append", format!("open {o}/log.txt a")),
        ("delete", "file delete [file dirname [info script]]/data.txt".to_string()),
        ("rename", format!("file rename {p}/secret.txt {o}/s.txt")),
        ("mkdir", format!("file mkdir {o}/made")),
        ("cd", "cd /".to_string()),
        ("pipe", "open |ls".to_string()),
        ("exec", "exec ls".to_string()),
        ("exec touch", format!("exec touch {o}/touched")),
        ("pipe touch", format!("close [open \"|touch {o}/piped\" w]")),
        ("glob private", format!("llength [glob -nocomplain {p}/*]")),
        ("render elsewhere", format!("render {p}/x.ppm")),
        ("mesh private", format!("mesh {p}/secret.txt")),
    ];
    let mut src = String::from("camera_resolution 4 4\nsphere 0 0 -3 1\n");
    for (what, cmd) in &attempts {
        src.push_str(&format!("puts \"{what}|[catch {{{cmd}}} m]|$m\"\n"));
    }
    src.push_str(&format!("render {o}/inside.ppm\n"));
    std::fs::write(scene.join("s.tsd"), src).unwrap();
    let run = |extra: &[&str]| {
        let r = raytrace()
            .arg("--safe")
            .args(extra)
            .arg(scene.join("s.tsd"))
            .arg(out.join("main.ppm"))
            .output()
            .unwrap();
        assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
        text(&r.stdout)
    };
    let got = run(&[]);
    let line = |what: &str| -> String {
        got.lines().find(|l| l.starts_with(&format!("{what}|"))).unwrap_or("").to_string()
    };
    assert_eq!(line("read own"), "read own|0|scene data", "{got}");
    for what in [
        "read private",
        "read up and over",
        "read /etc",
        "source private",
        "write",
        "append",
        "delete",
        "rename",
        "mkdir",
        "cd",
        "render elsewhere",
        "mesh private",
    ] {
        assert!(line(what).contains("|1|--safe: a scene may not"), "{what}: {got}");
    }
    assert!(line("pipe").contains("|1|--safe: a scene may not run programs"), "{got}");
    assert!(line("exec").contains("|1|--safe: a scene may not run programs"), "{got}");
    assert!(line("exec touch").contains("|1|--safe: a scene may not run programs"), "{got}");
    assert!(line("pipe touch").contains("|1|--safe: a scene may not run programs"), "{got}");
    assert!(!out.join("touched").exists() && !out.join("piped").exists());
    assert_eq!(line("glob private"), "glob private|0|0", "{got}");
    // Nothing was changed or made outside; the images inside were written.
    assert!(scene.join("data.txt").exists() && private.join("secret.txt").exists());
    assert!(!scene.join("new.txt").exists() && !out.join("made").exists());
    assert!(out.join("inside.ppm").exists() && out.join("main.ppm").exists());
    assert!(!private.join("x.ppm").exists() && !out.join("log.txt").exists());
    // A second run may not replace what the first made (only the named
    // output may be replaced).
    std::fs::remove_file(out.join("inside.ppm")).unwrap();
    // --allow-read opens the private directory for reading only.
    let got = run(&["--allow-read", &p]);
    let read = got.lines().find(|l| l.starts_with("read private|")).unwrap_or("");
    assert!(read.starts_with("read private|0|file"), "{got}");
    let rename = got.lines().find(|l| l.starts_with("rename|")).unwrap_or("");
    assert!(rename.starts_with("rename|1|--safe"), "{got}");
    // Without --safe the same scene may read and write.
    let r = raytrace().arg(scene.join("s.tsd")).output().unwrap();
    assert!(text(&r.stdout).contains("read private|0|file"));
    assert!(out.join("touched").exists() && out.join("piped").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

/// Every command the interpreter knows, by whether it can name a file.
/// Those that can are each tried under `--safe` on a path outside the
/// fence and must be refused by it; a command in neither list (a new one)
/// fails the test until it is placed, so none bypasses the gate unseen.
/// `{P}` is a file outside, `{D}` a directory outside.
const PATH_COMMANDS: &[(&str, &str)] = &[
    ("source", "source {P}"),
    ("open", "open {P}"),
    ("cd", "cd {D}"),
    ("exec", "exec {P}"),
    ("glob", "glob -directory {D} *"),
    ("mesh", "mesh {P}"),
    ("nff", "nff {P}"),
    ("texture", "texture image {P} planar"),
    ("bump", "bump image {P} 1 planar"),
    ("displace", "displace image {P} 1"),
    ("environment", "environment {P}"),
    ("show", "show {P}"),
    ("render", "render {D}/x.ppm"),
    ("file", "file size {P}"),
];

/// Each `file` subcommand that looks at or changes the file system.
const FILE_SUBCOMMANDS: &[&str] = &[
    "file atime {P}",
    "file atime {P} 0",
    "file attributes {P}",
    "file attributes {P} -permissions 0777",
    "file copy {P} {D}/copy",
    "file delete {P}",
    "file link {P}",
    "file link {D}/l {P}",
    "file lstat {P} v",
    "file mkdir {D}/made",
    "file mtime {P}",
    "file normalize {P}",
    "file owned {P}",
    "file readlink {P}",
    "file rename {P} {D}/moved",
    "file size {P}",
    "file stat {P} v",
    "file system {P}",
    "file type {P}",
    "open {P} {RDONLY CREAT APPEND}",
    "open {D}/new w",
    "open {D}/new {RDONLY CREAT}",
    "open {D}/new {RDONLY TRUNC}",
];

const NO_PATH: &[&str] = &[
    "adaptive",
    "after",
    "ambient_light",
    "append",
    "apply",
    "area_light",
    "array",
    "auto_load",
    "background",
    "binary",
    "blob",
    "blob_sphere",
    "box",
    "break",
    "camera_angle",
    "camera_aperture",
    "camera_focus",
    "camera_forw",
    "camera_from",
    "camera_resolution",
    "camera_target",
    "camera_up",
    "catch",
    "chan",
    "clear_scene",
    "clock",
    "close",
    "concat",
    "cone",
    "continue",
    "coroutine",
    "csg",
    "cylinder",
    "dict",
    "disk",
    "emission",
    "encoding",
    "eof",
    "error",
    "eval",
    "exit",
    "exposure",
    "expr",
    "fconfigure",
    "filter",
    "flush",
    "for",
    "foreach",
    "format",
    "gets",
    "global",
    "group",
    "help",
    "highlight",
    "if",
    "incr",
    "info",
    "instance",
    "integrator",
    "interp",
    "join",
    "lappend",
    "lassign",
    "lindex",
    "linsert",
    "list",
    "llength",
    "lmap",
    "lrange",
    "lrepeat",
    "lreplace",
    "lreverse",
    "lsearch",
    "lset",
    "lsort",
    "material",
    "max_normals",
    "max_vertices",
    "menger",
    "motion",
    "namespace",
    "normal",
    "ntri",
    "package",
    "parallel_light",
    "parray",
    "pid",
    "plane",
    "point_light",
    "pop",
    "preview",
    "proc",
    "push",
    "puts",
    "pwd",
    "raybench",
    "read",
    "regexp",
    "regsub",
    "rename",
    "return",
    "rotate",
    "rotate_axis",
    "samples",
    "scale",
    "scan",
    "scene_bounds",
    "seed",
    "seek",
    "set",
    "shutter",
    "sphere",
    "sphere_light",
    "sphereflake",
    "split",
    "spot_light",
    "stats",
    "string",
    "subst",
    "switch",
    "tailcall",
    "tell",
    "throw",
    "time",
    "tonemap",
    "torus",
    "trace",
    "trace_depth",
    "transform",
    "translate",
    "tri",
    "try",
    "unknown",
    "unset",
    "uplevel",
    "upvar",
    "variable",
    "vertex",
    "while",
    "yield",
    "yieldto",
];

/// Runs `script` as `scene/s.tsd` under `--safe` with `out/main.ppm` as
/// the output: (exit code, stdout, stderr).
fn run_safe(dir: &std::path::Path, script: &str, extra: &[&str]) -> (Option<i32>, String, String) {
    std::fs::write(dir.join("scene/s.tsd"), script).unwrap();
    let r = raytrace()
        .arg("--safe")
        .args(extra)
        .arg(dir.join("scene/s.tsd"))
        .arg(dir.join("out/main.ppm"))
        .current_dir(dir.join("scene"))
        .output()
        .unwrap();
    (r.status.code(), text(&r.stdout), text(&r.stderr))
}

fn fence_dirs(tag: &str) -> std::path::PathBuf {
    let dir = scratch(tag);
    for d in ["scene/sub/deep", "out", "private/inner"] {
        std::fs::create_dir_all(dir.join(d)).unwrap();
    }
    std::fs::write(dir.join("scene/sub/data.txt"), "inside\n").unwrap();
    std::fs::write(dir.join("private/secret.txt"), "secret\n").unwrap();
    std::fs::write(dir.join("out/old.ppm"), "P3 1 1 255 0 0 0\n").unwrap();
    dir
}

pub fn every_path_command_asks_the_gate() {
    let dir = fence_dirs("safe-table");
    let known = raytrace().args(["-c", "puts [lsort [info commands]]"]).output().unwrap();
    let known = text(&known.stdout);
    let listed: Vec<&str> =
        PATH_COMMANDS.iter().map(|(c, _)| *c).chain(NO_PATH.iter().copied()).collect();
    for c in known.split_whitespace() {
        assert!(
            listed.contains(&c),
            "command \"{c}\" is in neither list: say whether it names files"
        );
    }
    let p = dir.join("private/secret.txt");
    let d = dir.join("private/inner");
    let fill =
        |t: &str| t.replace("{P}", &p.to_string_lossy()).replace("{D}", &d.to_string_lossy());
    let tries: Vec<String> = PATH_COMMANDS
        .iter()
        .map(|(_, t)| fill(t))
        .chain(FILE_SUBCOMMANDS.iter().map(|t| fill(t)))
        .collect();
    let mut src = String::new();
    for (k, t) in tries.iter().enumerate() {
        src.push_str(&format!("puts \"{k}|[catch {{{t}}} m]|[string range $m 0 22]\"\n"));
    }
    let (code, out, err) = run_safe(&dir, &src, &[]);
    assert_eq!(code, Some(0), "{err}");
    for (k, t) in tries.iter().enumerate() {
        let line = out.lines().find(|l| l.starts_with(&format!("{k}|"))).unwrap_or("");
        assert!(line.ends_with("|1|--safe: a scene may not"), "{t}: {line}");
    }
    // Nothing outside changed or appeared.
    assert_eq!(listing(&dir.join("private")), ["inner", "secret.txt"]);
    assert!(listing(&d).is_empty(), "{:?}", listing(&d));
    let _ = std::fs::remove_dir_all(&dir);
}

/// Links are followed by the kernel beneath the scene's directory: `..`
/// after a link means what it means to `open`, and no link leads out.
pub fn links_lead_nowhere_outside() {
    use std::os::unix::fs::symlink;
    let dir = fence_dirs("safe-links");
    let scene = dir.join("scene");
    symlink("../../private", scene.join("sub/out")).unwrap();
    symlink("/", scene.join("root")).unwrap();
    symlink("sub/deep", scene.join("in")).unwrap();
    symlink("../../private/inner", scene.join("sub/inner")).unwrap();
    symlink(dir.join("scene/sub"), scene.join("abs")).unwrap();
    let attempts = [
        ("relative link out", "sub/out/secret.txt"),
        // Read as text, `sub/inner/..` is `sub`; to the kernel it is `private`.
        ("dot-dot after a link out", "sub/inner/../secret.txt"),
        ("link to root", "root/etc/passwd"),
        ("dot-dot after a link, out", "in/../../../private/secret.txt"),
        ("dot-dot through a link to root", "root/tmp/../etc/passwd"),
        ("absolute link", "abs/data.txt"),
        ("dot-dot beneath, out", "sub/../../private/secret.txt"),
    ];
    let mut src = String::new();
    for (what, path) in &attempts {
        src.push_str(&format!("puts \"{what}|[catch {{gets [open {path}]}} m]|$m\"\n"));
    }
    // Inside, `in/../data.txt` is the parent of the link's target: sub.
    src.push_str("puts \"inside|[catch {gets [open in/../data.txt]} m]|$m\"\n");
    src.push_str("puts \"plain|[catch {gets [open sub/deep/../data.txt]} m]|$m\"\n");
    let (code, out, err) = run_safe(&dir, &src, &[]);
    assert_eq!(code, Some(0), "{err}");
    for (what, _) in &attempts {
        let line = out.lines().find(|l| l.starts_with(&format!("{what}|"))).unwrap_or("");
        assert!(line.contains("|1|--safe: a scene may not read"), "{what}: {out}");
    }
    assert!(out.contains("inside|0|inside"), "{out}");
    assert!(out.contains("plain|0|inside"), "{out}");
    // The refusal is the same whether or not the outside file exists.
    let (_, out, _) = run_safe(
        &dir,
        "catch {open /nonexistent/x} a; catch {open /etc/passwd} b\nputs [string map {/nonexistent/x P /etc/passwd P} $a]\nputs [string map {/nonexistent/x P /etc/passwd P} $b]",
        &[],
    );
    let lines: Vec<&str> = out.lines().collect();
    assert_eq!(lines.len(), 2, "{out}");
    assert_eq!(lines[0], lines[1]);
    let _ = std::fs::remove_dir_all(&dir);
}

/// What a scene may not see or make: its user's environment, the output
/// directory's files, files through a link, a FIFO's endless wait, or a
/// picture over a file it did not make.
pub fn outputs_environment_and_fifos_are_fenced() {
    use std::os::unix::fs::symlink;
    let dir = fence_dirs("safe-outputs");
    let out_dir = dir.join("out");
    symlink(dir.join("private/evil.sh"), out_dir.join("evil.ppm")).unwrap();
    let fifo = dir.join("scene/fifo");
    assert!(std::process::Command::new("mkfifo").arg(&fifo).status().unwrap().success());
    let o = out_dir.to_string_lossy();
    let src = format!(
        "camera_resolution 4 4\n\
         puts \"env|[array size env]|[info exists env(HOME)]\"\n\
         puts \"out dir|[catch {{open {o}/old.ppm}} m]|$m\"\n\
         puts \"fifo|[catch {{open fifo}} m]|$m\"\n\
         puts \"fifo sky|[catch {{environment fifo}} m]|$m\"\n\
         puts \"dangling|[catch {{render {o}/evil.ppm}} m]|$m\"\n\
         puts \"replace|[catch {{render {o}/old.ppm}} m]|$m\"\n\
         puts \"new|[catch {{render {o}/new.ppm}} m]|$m\"\n\
         puts \"named|[catch {{render {o}/main.ppm}} m]|$m\"\n\
         puts \"not an image|[catch {{render {o}/x.sh}} m]|$m\"\n"
    );
    let start = std::time::Instant::now();
    let (code, out, err) = run_safe(&dir, &src, &[]);
    assert!(start.elapsed().as_secs() < 20, "a FIFO was waited on");
    assert_eq!(code, Some(0), "{err}");
    let line =
        |w: &str| out.lines().find(|l| l.starts_with(&format!("{w}|"))).unwrap_or("").to_string();
    assert_eq!(line("env"), "env|0|0", "{out}");
    for w in ["out dir", "fifo", "fifo sky", "dangling", "replace"] {
        assert!(line(w).contains("|1|--safe: a scene may not"), "{w}: {out}");
    }
    assert!(line("new").starts_with("new|0|"), "{out}");
    assert!(line("named").starts_with("named|0|"), "{out}");
    assert!(line("not an image").starts_with("not an image|1|"), "{out}");
    assert!(!dir.join("private/evil.sh").exists(), "a picture went through the link");
    assert_eq!(std::fs::read(out_dir.join("old.ppm")).unwrap(), b"P3 1 1 255 0 0 0\n");
    // The current directory is not readable when no output is named.
    let r = raytrace()
        .args(["--safe", "-"])
        .current_dir(&dir)
        .stdin(std::process::Stdio::piped())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .and_then(|mut c| {
            use std::io::Write;
            c.stdin.take().unwrap().write_all(b"puts [catch {open private/secret.txt} m]|$m\n")?;
            c.wait_with_output()
        })
        .unwrap();
    assert!(text(&r.stdout).starts_with("1|--safe: a scene may not read"), "{}", text(&r.stdout));
    let _ = std::fs::remove_dir_all(&dir);
}
