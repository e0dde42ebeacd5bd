//! Pictures checked against numbers: analytic pixels, golden images with a
//! tolerance (UPDATE_EXPECT=1 rewrites them), an outside validator
//! (netpbm), bad input, and determinism across thread counts.

use std::path::Path;

use glam::Vec3;
use rayshell::image::{Encoding, Image, read_ppm, write_ppm};
use rayshell::render::{Job, render};
use rayshell::scene::{Scene, spot_factor};
use rayshell::shell::{CaptureHost, Session};

use crate::util::{raytrace, root, text};

/// Runs a script in-process and renders its scene (floats, not bytes).
fn render_script(src: &str) -> Image {
    let src = src.to_string();
    rayshell::shell::on_big_stack(move || {
        let mut s = Session::new(Box::new(CaptureHost::default()));
        // Scenes find their files relative to `info script`: run from tsd/.
        if let Err(e) = s.interp.eval_source(&src, Some("tsd/test.tsd")) {
            panic!("script failed: {}", e.located_message());
        }
        let scene = Scene::freeze(&s.scene.borrow()).expect("freeze");
        render(&scene, &Job::default()).expect("not cancelled").0
    })
    .expect("render thread")
}

/// A camera looking down -z at a big triangle in the plane z = 0.
const PLANE: &str = "
camera_from 0 0 5
camera_target 0 0 0
camera_angle 40
camera_resolution 9 9
background 0 0 0
ambient_light 0 0 0
material 0.8 0.6 0.4  0 0.5 0 1 0 1
set a [vertex -50 -50 0]; set b [vertex 50 -50 0]; set c [vertex 0 50 0]
tri $a $b $c
";

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).abs().max_element() <= tol
}

#[test]
fn lambert_pixel_under_parallel_light() {
    let angle = 30f32.to_radians();
    let img = render_script(&format!(
        "{PLANE}parallel_light 1 1 1  0 {} {}\n",
        -angle.sin(),
        -angle.cos()
    ));
    let want = 0.5 * Vec3::new(0.8, 0.6, 0.4) * angle.cos();
    // Every pixel sees the lit plane: all equal, no shadow acne anywhere.
    for (i, p) in img.pixels.iter().enumerate() {
        assert!(close(*p, want, 1e-5), "pixel {i}: {p} != {want}");
    }
}

#[test]
fn point_light_falls_off_as_inverse_square() {
    for d in [1.5f32, 3.0] {
        let img = render_script(&format!("{PLANE}point_light 2 2 2  0 0 {d}\n"));
        let want = 0.5 * Vec3::new(0.8, 0.6, 0.4) * 2.0 / (d * d);
        assert!(close(img.get(4, 4), want, 1e-5), "d={d}: {} != {want}", img.get(4, 4));
    }
}

#[test]
fn spot_light_falloff_matches_formula() {
    let (inner, outer) = (10f32, 30f32);
    let h = 2.0f32;
    let script = format!(
        "{PLANE}camera_resolution 41 41\nspot_light 3 3 3  0 0 {h}  0 0 -1  {inner} {outer}\n"
    );
    let img = render_script(&script);
    let cam =
        rayshell::scene::Camera::new(Vec3::new(0.0, 0.0, 5.0), Vec3::NEG_Z, Vec3::Y, 40.0, 41, 41)
            .unwrap();
    let mut checked_partial = 0;
    for y in (0..41).step_by(4) {
        for x in (0..41).step_by(4) {
            let ray = cam.ray(x, y);
            let t = -ray.origin.z / ray.dir.z;
            let p = ray.at(t);
            let to_light = Vec3::new(0.0, 0.0, h) - p;
            let r2 = to_light.length_squared();
            let l = to_light / r2.sqrt();
            let cos_axis = (-l).dot(Vec3::NEG_Z);
            let f = spot_factor(cos_axis, inner.to_radians().cos(), outer.to_radians().cos());
            if f > 0.0 && f < 1.0 {
                checked_partial += 1;
            }
            let want = 0.5 * Vec3::new(0.8, 0.6, 0.4) * 3.0 * f * l.z / r2;
            assert!(
                close(img.get(x, y), want, 1e-4),
                "({x},{y}) f={f}: {} != {want}",
                img.get(x, y)
            );
        }
    }
    assert!(checked_partial > 0, "no pixel fell in the fading band");
}

#[test]
fn shadows_are_black_or_tinted() {
    // Seen from the side so the sphere does not hide the shadowed point.
    let base = "
camera_from 0 -5 5
camera_target 0 0 0
camera_resolution 9 9
background 0 0 0
material 1 1 1  0 1 0 1 0 1
set a [vertex -50 -50 0]; set b [vertex 50 -50 0]; set c [vertex 0 50 0]
tri $a $b $c
parallel_light 1 1 1  0 0 -1
";
    let opaque = render_script(&format!("{base}material 1 1 1 0 1 0 1 0 1\nsphere 0 0 2 0.5\n"));
    assert_eq!(opaque.get(4, 4), Vec3::ZERO);
    let glass =
        render_script(&format!("{base}material 1 0.5 0.25 0 0 0 1 0.5 1\nsphere 0 0 2 0.5\n"));
    // Two surfaces crossed, each passing T·colour.
    let tint = Vec3::new(0.5, 0.25, 0.125);
    assert!(close(glass.get(4, 4), tint * tint, 1e-5), "{}", glass.get(4, 4));
    let lit = render_script(base);
    assert!(close(lit.get(4, 4), Vec3::ONE, 1e-5));
}

#[test]
fn mirror_shows_what_it_faces() {
    // A mirror (Ks = 1) facing the camera reflects the background only.
    let img = render_script(
        "camera_from 0 0 5\ncamera_target 0 0 0\ncamera_resolution 5 5\nbackground 0.2 0.4 0.6\n\
         material 1 1 1 0 0 1 1 0 1\nsphere 0 0 0 1\n",
    );
    assert!(close(img.get(2, 2), Vec3::new(0.2, 0.4, 0.6), 1e-6), "{}", img.get(2, 2));
}

#[test]
fn same_picture_for_any_thread_count() {
    let src = std::fs::read_to_string(root().join("tsd/spheres.tsd")).unwrap();
    let src = format!("{src}\ncamera_resolution 80 60\n");
    let one = rayon::ThreadPoolBuilder::new().num_threads(1).build().unwrap();
    let two = rayon::ThreadPoolBuilder::new().num_threads(2).build().unwrap();
    let a = one.install(|| render_script(&src)).to_rgb8(Encoding::Linear);
    let b = two.install(|| render_script(&src)).to_rgb8(Encoding::Linear);
    assert!(a == b, "pictures differ between 1 and 2 threads");
}

/// Every sample scene renders at thumbnail size and matches its golden
/// image within 2/255 per channel (so no example can rot).
#[test]
fn sample_scenes_match_goldens() {
    let update = std::env::var_os("UPDATE_EXPECT").is_some();
    let golden_dir = root().join("tests/golden");
    let diff_dir = root().join("target/golden-diff");
    let mut names: Vec<_> = std::fs::read_dir(root().join("tsd"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "tsd"))
        .collect();
    names.sort();
    assert!(names.len() >= 5);
    let mut failures = Vec::new();
    for path in names {
        let stem = path.file_stem().unwrap().to_string_lossy().into_owned();
        let src = std::fs::read_to_string(&path).unwrap();
        if src.contains("shared models") && !root().join("../shared/models").is_dir() {
            println!("SKIPPED golden {stem}: ../shared/models is absent");
            continue;
        }
        let img = render_script(&format!("{src}\ncamera_resolution 64 48\n"));
        let got = img.to_rgb8(Encoding::Linear);
        let golden = golden_dir.join(format!("{stem}.ppm"));
        if update {
            std::fs::create_dir_all(&golden_dir).unwrap();
            let mut buf = Vec::new();
            write_ppm(&mut buf, 64, 48, &got).unwrap();
            std::fs::write(&golden, buf).unwrap();
            continue;
        }
        let data = std::fs::read(&golden).unwrap_or_else(|_| {
            panic!("missing golden {} (UPDATE_EXPECT=1 makes it)", golden.display())
        });
        let (w, h, want) = read_ppm(&data).expect("golden is a P6 PPM");
        assert_eq!((w, h), (64, 48));
        let worst = got.iter().zip(&want).map(|(a, b)| a.abs_diff(*b)).max().unwrap_or(0);
        if worst > 2 {
            std::fs::create_dir_all(&diff_dir).unwrap();
            let diff: Vec<u8> =
                got.iter().zip(&want).map(|(a, b)| a.abs_diff(*b).saturating_mul(16)).collect();
            let mut buf = Vec::new();
            write_ppm(&mut buf, 64, 48, &diff).unwrap();
            std::fs::write(diff_dir.join(format!("{stem}-diff.ppm")), buf).unwrap();
            let mut buf = Vec::new();
            write_ppm(&mut buf, 64, 48, &got).unwrap();
            std::fs::write(diff_dir.join(format!("{stem}-got.ppm")), buf).unwrap();
            failures
                .push(format!("{stem}: max channel difference {worst} (see target/golden-diff)"));
        }
    }
    assert!(failures.is_empty(), "{}", failures.join("\n"));
}

fn netpbm() -> bool {
    std::process::Command::new("pamfile").arg("--version").output().is_ok()
}

#[test]
fn output_files_pass_netpbm() {
    if !netpbm() {
        println!("SKIPPED output_files_pass_netpbm: netpbm is not installed (.ci/run installs it)");
        return;
    }
    let dir = std::env::temp_dir().join(format!("rayshell-netpbm-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let script = "camera_resolution 37 23\npoint_light 1 1 1 0 2 2\nsphere 0 0 -3 1\n";
    for ext in ["ppm", "png"] {
        let out = dir.join(format!("img.{ext}"));
        let r = raytrace()
            .arg("-c")
            .arg(format!("{script}render {{{}}}", out.display()))
            .output()
            .unwrap();
        assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
        let pam = if ext == "png" {
            let conv = std::process::Command::new("pngtopam").arg(&out).output().unwrap();
            assert!(conv.status.success(), "pngtopam rejected the PNG");
            let p = dir.join("from-png.pam");
            std::fs::write(&p, conv.stdout).unwrap();
            p
        } else {
            out.clone()
        };
        let info = std::process::Command::new("pamfile").arg(&pam).output().unwrap();
        let info = text(&info.stdout);
        assert!(info.contains("37 by 23") && info.contains("maxval 255"), "pamfile says: {info}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn cli_renders_the_final_scene() {
    let dir = std::env::temp_dir().join(format!("rayshell-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let scene = dir.join("s.tsd");
    std::fs::write(
        &scene,
        "camera_resolution 8 6\nambient_light 1 1 1\nmaterial 1 0 0 1 0 0 1 0 1\nsphere 0 0 -3 1\n",
    )
    .unwrap();
    let out = dir.join("s.ppm");
    let r = raytrace().arg(&scene).arg(&out).output().unwrap();
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let (w, h, rgb) = read_ppm(&std::fs::read(&out).unwrap()).unwrap();
    assert_eq!((w, h), (8, 6));
    // Centre pixel: Ka·ambient·colour = pure red; corner: background black.
    let px = |x: usize, y: usize| &rgb[(y * 8 + x) * 3..(y * 8 + x) * 3 + 3];
    assert_eq!(px(4, 3), &[255, 0, 0]);
    assert_eq!(px(0, 0), &[0, 0, 0]);
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn no_light_warns() {
    let dir = std::env::temp_dir().join(format!("rayshell-warn-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let r = raytrace()
        .arg("-c")
        .arg("camera_resolution 2 2\nrender dark.ppm")
        .current_dir(&dir)
        .output()
        .unwrap();
    assert!(text(&r.stderr).contains("warning: the scene has no lights"), "{}", text(&r.stderr));
    assert!(Path::new(&dir.join("dark.ppm")).exists());
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn stats_and_heatmap() {
    let dir = std::env::temp_dir().join(format!("rayshell-stats-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let script = "camera_resolution 32 24\npoint_light 1 1 1 0 3 3\n\
        for {set i 0} {$i < 50} {incr i} { sphere [expr {$i % 10 - 5}] [expr {$i / 10 - 2}] -8 0.4 }\n\
        render -heatmap heat.ppm\nputs [stats]\n";
    let r = raytrace().arg("--stats").arg("-c").arg(script).current_dir(&dir).output().unwrap();
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let (err, out) = (text(&r.stderr), text(&r.stdout));
    for want in ["bvh build", "50 primitives", "768 primary", "Mrays/s", "peak RSS"] {
        assert!(err.contains(want) && out.contains(want), "missing {want:?} in:\n{err}");
    }
    let (_, _, rgb) = read_ppm(&std::fs::read(dir.join("heat.ppm")).unwrap()).unwrap();
    // Rays towards the spheres visit more nodes than rays past them.
    let mut distinct: Vec<&[u8]> = rgb.chunks(3).collect();
    distinct.sort();
    distinct.dedup();
    assert!(distinct.len() > 3, "the heatmap is flat");
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn degenerate_triangles_are_skipped_with_one_warning() {
    let dir = std::env::temp_dir().join(format!("rayshell-degen-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let script = "camera_resolution 4 4\npoint_light 1 1 1 0 0 1\n\
        set a [vertex 0 0 -3]; set b [vertex 1 0 -3]; set c [vertex 2 0 -3]\n\
        tri $a $b $c; tri $a $a $b; tri $a $b [vertex 0 1 -3]\nrender d.ppm\n";
    let r = raytrace().arg("-c").arg(script).current_dir(&dir).output().unwrap();
    assert_eq!(r.status.code(), Some(0));
    let err = text(&r.stderr);
    assert_eq!(err.matches("warning:").count(), 1, "{err}");
    assert!(err.contains("skipped 2 degenerate triangle(s)"), "{err}");
    let _ = std::fs::remove_dir_all(&dir);
}
