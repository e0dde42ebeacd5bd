//! Animation batches, shards, crops and merges, progress output, and the
//! promise that none of them changes a single byte of a picture.

use std::path::Path;

use crate::util::{listing, raytrace, root, scratch, text};

/// A small animation: a sphere moving with `$frame`, a floor, a mirror.
const ANIM: &str = "
camera_from 0 1 6
camera_target 0 0 0
camera_resolution 40 30
point_light 1 1 1 3 4 5
ambient_light 0.1 0.1 0.1
material 0.9 0.3 0.2  0.2 0.7 0.3 20 0 1
sphere [expr {-1.5 + $frame * 0.25}] 0 0 0.8
material 0.5 0.5 0.5  0.2 0.6 0.5 10 0 1
set a [vertex -5 -1 -5]; set b [vertex 5 -1 -5]; set c [vertex 5 -1 5]; set d [vertex -5 -1 5]
tri $a $c $b; tri $a $d $c
";

fn batch(dir: &Path, args: &[&str]) -> std::process::Output {
    raytrace().args(["anim.tsd"]).args(args).current_dir(dir).output().expect("run raytrace")
}

pub fn frames_are_selected_named_and_rendered_once() {
    let dir = scratch("frames");
    std::fs::write(dir.join("anim.tsd"), ANIM).unwrap();
    let r = batch(&dir, &["out/f####.png", "--frames", "3..11", "--step", "4"]);
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    assert_eq!(listing(&dir.join("out")), ["f0003.png", "f0007.png", "f0011.png"]);
    // Not a terminal: one plain line per frame, then a summary.
    let err = text(&r.stderr);
    let lines: Vec<&str> = err.lines().collect();
    assert_eq!(lines.len(), 4, "{err}");
    assert!(lines[0].starts_with("frame 3 (1/3): wrote out/f0003.png 40×30 in "), "{err}");
    assert!(lines[2].starts_with("frame 11 (3/3): wrote out/f0011.png"), "{err}");
    assert!(lines[3].starts_with("3 frame(s) rendered, 0 skipped"), "{err}");
    // Each frame differs (the sphere moves), and the default name pattern.
    let a = std::fs::read(dir.join("out/f0003.png")).unwrap();
    assert_ne!(a, std::fs::read(dir.join("out/f0007.png")).unwrap());
    let r = batch(&dir, &["--frames", "2", "-q"]);
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    assert!(r.stderr.is_empty(), "--quiet: {}", text(&r.stderr));
    assert!(dir.join("anim-0002.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

pub fn shards_cover_every_frame_once_with_the_same_bytes() {
    let dir = scratch("shards");
    std::fs::write(dir.join("anim.tsd"), ANIM).unwrap();
    let r = batch(&dir, &["all/f####.ppm", "--frames", "0..9", "-q"]);
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let mut seen = Vec::new();
    for i in 0..4 {
        let shard = format!("{i}/4");
        let r = batch(&dir, &["sharded/f####.ppm", "--frames", "0..9", "--shard", &shard]);
        assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
        for line in text(&r.stderr).lines().filter(|l| l.starts_with("frame ")) {
            seen.push(line.split_whitespace().nth(1).unwrap().parse::<i64>().unwrap());
        }
    }
    seen.sort();
    assert_eq!(seen, (0..10).collect::<Vec<i64>>(), "every frame exactly once");
    let names = listing(&dir.join("all"));
    assert_eq!(names.len(), 10);
    assert_eq!(names, listing(&dir.join("sharded")));
    for n in &names {
        let a = std::fs::read(dir.join("all").join(n)).unwrap();
        assert_eq!(a, std::fs::read(dir.join("sharded").join(n)).unwrap(), "{n}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

pub fn skip_existing_leaves_finished_frames_alone() {
    let dir = scratch("skip");
    std::fs::write(dir.join("anim.tsd"), ANIM).unwrap();
    std::fs::create_dir_all(dir.join("out")).unwrap();
    std::fs::write(dir.join("out/f0001.png"), "kept").unwrap();
    let r = batch(
        &dir,
        &["out/f####.png", "--frames", "0..2", "--skip-existing", "--progress", "json"],
    );
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    assert_eq!(std::fs::read_to_string(dir.join("out/f0001.png")).unwrap(), "kept");
    assert_eq!(listing(&dir.join("out")), ["f0000.png", "f0001.png", "f0002.png"]);
    let err = text(&r.stderr);
    let events: Vec<&str> = err.lines().collect();
    assert!(events.iter().all(|l| l.starts_with("{\"event\":") && l.ends_with('}')), "{err}");
    assert!(events[0].starts_with("{\"event\":\"render\",\"file\":\"out/f0000.png\",\"frame\":0,"));
    assert_eq!(
        events[1],
        "{\"event\":\"skip\",\"file\":\"out/f0001.png\",\"frame\":1,\"index\":2,\"count\":3,\"reason\":\"exists\"}"
    );
    assert!(events[3].starts_with("{\"event\":\"batch\",\"rendered\":2,\"skipped\":1,"), "{err}");
    // A second run renders nothing.
    let r = batch(&dir, &["out/f####.png", "--frames", "0..2", "--skip-existing"]);
    assert!(text(&r.stderr).contains("0 frame(s) rendered, 3 skipped"), "{}", text(&r.stderr));
    let _ = std::fs::remove_dir_all(&dir);
}

pub fn exit_codes_tell_a_farm_what_to_retry() {
    let dir = scratch("codes");
    std::fs::write(dir.join("anim.tsd"), ANIM).unwrap();
    std::fs::write(
        dir.join("bad.tsd"),
        "point_light 1 1 1 0 5 0; sphere 0 0 -5 [expr {2 + 1 / (1 - $frame)}]\n",
    )
    .unwrap();
    // A script error: 1, and the frames before it are kept.
    let r = raytrace()
        .args(["bad.tsd", "b####.ppm", "--frames", "0..3", "-q"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_eq!(r.status.code(), Some(1));
    assert!(text(&r.stderr).starts_with("bad.tsd:1: divide by zero"), "{}", text(&r.stderr));
    assert!(text(&r.stderr).contains("frame 1 failed; 1 frame(s) rendered before it"));
    // Cannot write: 74 (worth a retry elsewhere).
    std::fs::write(dir.join("file"), "").unwrap();
    let r = batch(&dir, &["file/f####.png", "--frames", "0..1"]);
    assert_eq!(r.status.code(), Some(74), "{}", text(&r.stderr));
    let r = raytrace()
        .args(["-c", "camera_resolution 4 4; render file/x.png"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_eq!(r.status.code(), Some(74), "{}", text(&r.stderr));
    // Usage errors: 2.
    for args in
        [&["--frames", "9..1"][..], &["--frames", "0..3", "--shard", "4/4"], &["--shard", "0/2"]]
    {
        let r = batch(&dir, args);
        assert_eq!(r.status.code(), Some(2), "{args:?}: {}", text(&r.stderr));
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The animation at frame 3, 640x480 but cheap to trace (debug builds).
fn still(dir: &Path) -> &'static str {
    let src = format!("set frame 3\n{ANIM}\ncamera_resolution 640 480\ntrace_depth 1\n");
    std::fs::write(dir.join("still.tsd"), src).unwrap();
    "still.tsd"
}

pub fn crops_merge_into_the_full_picture() {
    let dir = scratch("crop");
    let scene = still(&dir);
    let run = |args: &[&str]| {
        let r = raytrace().args(args).current_dir(&dir).output().unwrap();
        assert_eq!(r.status.code(), Some(0), "{args:?}: {}", text(&r.stderr));
    };
    run(&["--threads", "1", scene, "full.ppm"]);
    // Three regions, PNG and PPM mixed, uneven edges.
    run(&["--crop", "0", "0", "301", "203", scene, "a.png"]);
    run(&["--crop", "301", "0", "640", "480", "--progressive", scene, "b.ppm"]);
    run(&["--crop", "0", "203", "301", "480", scene, "c.png"]);
    run(&["--merge", "merged.ppm", "a.png", "b.ppm", "c.png"]);
    let full = std::fs::read(dir.join("full.ppm")).unwrap();
    assert_eq!(full, std::fs::read(dir.join("merged.ppm")).unwrap());
    // A region is its own small picture.
    let (w, h, _) = rayshell::image::read_ppm(&std::fs::read(dir.join("b.ppm")).unwrap()).unwrap();
    assert_eq!((w, h), (339, 480));
    let fails = |args: &[&str], want: &str| {
        let r = raytrace().args(args).current_dir(&dir).output().unwrap();
        assert_eq!(r.status.code(), Some(1), "{args:?}");
        assert!(text(&r.stderr).contains(want), "{args:?}: {}", text(&r.stderr));
    };
    fails(
        &["--merge", "m.ppm", "a.png", "b.ppm"],
        "leave 83377 of 307200 pixels uncovered (the first at 0 203)",
    );
    fails(&["--merge", "m.ppm", "full.ppm"], "is not a cropped render");
    fails(
        &["--crop", "0", "0", "700", "10", scene, "x.png"],
        "crop region 0 0 700 10 is outside the 640x480 picture",
    );
    assert!(!dir.join("m.ppm").exists() && !dir.join("x.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

pub fn progressive_and_thread_count_change_no_pixel() {
    let dir = scratch("progressive");
    let scene = still(&dir);
    let mut outs = Vec::new();
    for (k, args) in [
        &["--threads", "1"][..],
        &["--threads", "2", "--progressive"],
        &["--threads", "1", "--progressive"],
    ]
    .iter()
    .enumerate()
    {
        let out = format!("o{k}.ppm");
        let r = raytrace().args(*args).args([scene, &out]).current_dir(&dir).output().unwrap();
        assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
        outs.push(std::fs::read(dir.join(&out)).unwrap());
    }
    assert!(outs.iter().all(|o| *o == outs[0]));
    // In-process, in floats: every pass order gives the same values.
    let src = std::fs::read_to_string(root().join("tsd/spheres.tsd")).unwrap()
        + "camera_resolution 97 61\n";
    let images: Vec<Vec<glam::Vec3>> = rayshell::shell::on_big_stack(move || {
        let mut s =
            rayshell::shell::Session::new(Box::new(rayshell::shell::CaptureHost::default()));
        s.interp.eval_source(&src, Some("spheres.tsd")).expect("scene runs");
        let scene = rayshell::scene::Scene::freeze(&s.scene.borrow()).unwrap();
        [false, true]
            .iter()
            .map(|&progressive| {
                let job = rayshell::render::Job { progressive, ..Default::default() };
                rayshell::render::render(&scene, &job).unwrap().0.pixels
            })
            .collect()
    })
    .unwrap();
    assert_eq!(images[0], images[1]);
    let _ = std::fs::remove_dir_all(&dir);
}

pub fn movie_is_an_animated_png_of_the_frames() {
    let dir = scratch("movie");
    std::fs::write(dir.join("anim.tsd"), ANIM).unwrap();
    let r = batch(&dir, &["f/f####.png", "--frames", "0..2", "-q"]);
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let frames: Vec<String> = listing(&dir.join("f")).iter().map(|n| format!("f/{n}")).collect();
    let r = raytrace()
        .args(["--movie", "m.png"])
        .args(&frames)
        .args(["--fps", "12"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let data = std::fs::read(dir.join("m.png")).unwrap();
    let mut reader = png::Decoder::new(std::io::Cursor::new(&data)).read_info().unwrap();
    let actl = reader.info().animation_control.expect("an APNG");
    assert_eq!((actl.num_frames, actl.num_plays), (3, 0));
    // Each movie frame is the rendered frame, pixel for pixel.
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    for f in &frames {
        reader.next_frame(&mut buf).unwrap();
        let fc = reader.info().frame_control.expect("a frame");
        assert_eq!((fc.delay_num, fc.delay_den), (1, 12));
        let want = rayshell::image::read_rgb8(&std::fs::read(dir.join(f)).unwrap()).unwrap();
        assert_eq!(&buf[..want.rgb.len()], &want.rgb[..], "{f}");
    }
    // Frames of different sizes are refused.
    std::fs::write(dir.join("small.tsd"), "camera_resolution 4 4\nambient_light 1 1 1\n").unwrap();
    let r = raytrace().args(["small.tsd", "s.png"]).current_dir(&dir).output().unwrap();
    assert_eq!(r.status.code(), Some(0));
    let r = raytrace()
        .args(["--movie", "bad.png", &frames[0], "s.png"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_eq!(r.status.code(), Some(1));
    assert!(
        text(&r.stderr).contains("\"s.png\" is 4x4, the first frame 40x30"),
        "{}",
        text(&r.stderr)
    );
    assert!(!dir.join("bad.png").exists());
    let _ = std::fs::remove_dir_all(&dir);
}

pub fn gnu_parallel_shards_match_a_single_run() {
    if std::process::Command::new("parallel").arg("--version").output().is_err() {
        crate::util::skip("GNU parallel is not installed (apt-get install parallel)");
    }
    let dir = scratch("parallel");
    std::fs::write(dir.join("anim.tsd"), ANIM).unwrap();
    let bin = env!("CARGO_BIN_EXE_raytrace");
    // The README's command, as a farm of one machine would run it.
    let r = std::process::Command::new("parallel")
        .args(["--will-cite", "--halt", "now,fail=1", "-j2"])
        .arg(format!("{bin} anim.tsd par/f####.png --frames 0..7 --shard {{}}/4 -q"))
        .args([":::", "0", "1", "2", "3"])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let r = batch(&dir, &["one/f####.png", "--frames", "0..7", "-q"]);
    assert_eq!(r.status.code(), Some(0));
    let names = listing(&dir.join("one"));
    assert_eq!(names.len(), 8);
    assert_eq!(names, listing(&dir.join("par")));
    for n in &names {
        assert_eq!(
            std::fs::read(dir.join("one").join(n)).unwrap(),
            std::fs::read(dir.join("par").join(n)).unwrap(),
            "{n}"
        );
    }
    let _ = std::fs::remove_dir_all(&dir);
}

pub fn a_self_rendering_script_is_not_traced_twice() {
    // Issue "the first ten minutes": without an output pattern, --frames
    // writes only what the script writes; with one, the same pictures are
    // copied, not traced again.
    let dir = scratch("selfrender");
    std::fs::write(
        dir.join("anim.tsd"),
        "camera_resolution 16 12; sphere [expr {$frame * 0.1}] 0 -3 1; ambient_light 1 1 1\n\
         render [format self%02d.png $frame]\n",
    )
    .unwrap();
    let r = batch(&dir, &["--frames", "0..2"]);
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    assert_eq!(listing(&dir), ["anim.tsd", "self00.png", "self01.png", "self02.png"]);
    let r = batch(&dir, &["out/f####.png", "--frames", "0..1"]);
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let err = text(&r.stderr);
    assert_eq!(err.matches("(the scene had not changed since it was traced)").count(), 2, "{err}");
    assert_eq!(
        std::fs::read(dir.join("self01.png")).unwrap(),
        std::fs::read(dir.join("out/f0001.png")).unwrap()
    );
}
