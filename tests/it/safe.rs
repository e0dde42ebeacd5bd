//! `--safe`: each fence holds (issue "Tcl 8.6", untrusted scenes).

use crate::util::{raytrace, scratch, text};

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
