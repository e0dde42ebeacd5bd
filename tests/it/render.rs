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
        let mut img = render(&scene, &Job::default()).expect("not cancelled").0;
        rayshell::render::apply_look(&scene.sampling, &mut img);
        img
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

pub fn lambert_pixel_under_parallel_light() {
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

pub fn point_light_falls_off_as_inverse_square() {
    for d in [1.5f32, 3.0] {
        let img = render_script(&format!("{PLANE}point_light 2 2 2  0 0 {d}\n"));
        let want = 0.5 * Vec3::new(0.8, 0.6, 0.4) * 2.0 / (d * d);
        assert!(close(img.get(4, 4), want, 1e-5), "d={d}: {} != {want}", img.get(4, 4));
        // With falloff coefficients: 1/(c + l·d + q·d²); (1 0 0) does not
        // fall off at all (NFF's and POV-Ray's lights).
        for (c, l, q) in [(1.0f32, 0.0, 0.0), (0.5, 0.25, 0.125), (0.0, 0.0, 1.0)] {
            let img = render_script(&format!("{PLANE}point_light 2 2 2  0 0 {d}  {c} {l} {q}\n"));
            let want = 0.5 * Vec3::new(0.8, 0.6, 0.4) * 2.0 / (c + l * d + q * d * d);
            let got = img.get(4, 4);
            assert!(close(got, want, 1e-5), "d={d} falloff {c} {l} {q}: {got} != {want}");
        }
    }
}

pub fn spot_light_falloff_matches_formula() {
    for falloff in ["", "0.5 0.5 0.5"] {
        spot_light_with(falloff);
    }
}

fn spot_light_with(falloff: &str) {
    let (inner, outer) = (10f32, 30f32);
    let h = 2.0f32;
    let script = format!(
        "{PLANE}camera_resolution 41 41\nspot_light 3 3 3  0 0 {h}  0 0 -1  {inner} {outer} {falloff}\n"
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
            let att = if falloff.is_empty() { r2 } else { 0.5 * (1.0 + r2.sqrt() + r2) };
            let want = 0.5 * Vec3::new(0.8, 0.6, 0.4) * 3.0 * f * l.z / att;
            assert!(
                close(img.get(x, y), want, 1e-4),
                "({x},{y}) f={f}: {} != {want}",
                img.get(x, y)
            );
        }
    }
    assert!(checked_partial > 0, "no pixel fell in the fading band");
}

pub fn shadows_are_black_or_tinted() {
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

pub fn mirror_shows_what_it_faces() {
    // A mirror (Ks = 1) facing the camera reflects the background only.
    let img = render_script(
        "camera_from 0 0 5\ncamera_target 0 0 0\ncamera_resolution 5 5\nbackground 0.2 0.4 0.6\n\
         material 1 1 1 0 0 1 1 0 1\nsphere 0 0 0 1\n",
    );
    assert!(close(img.get(2, 2), Vec3::new(0.2, 0.4, 0.6), 1e-6), "{}", img.get(2, 2));
}

pub fn same_picture_for_any_thread_count() {
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
pub fn sample_scenes_match_goldens() {
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

pub fn output_files_pass_netpbm() {
    if !netpbm() {
        crate::util::skip("netpbm is not installed (.ci/run installs it)");
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

pub fn cli_renders_the_final_scene() {
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

pub fn no_light_warns() {
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

pub fn stats_and_heatmap() {
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

/// A render keeps its BVH for the next: reused after changes to the view,
/// the lights or the materials, built again after any change to the
/// geometry or the eye, and the pictures are those a fresh run makes.
pub fn renders_reuse_the_tree_only_while_its_geometry_and_eye_stay() {
    let dir = std::env::temp_dir().join(format!("rayshell-reuse-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let steps = [
        ("a", "camera_resolution 32 24; point_light 1 1 1 0 3 3; sphere 0 0 -5 1", "built"),
        (
            "b",
            "point_light 0.5 0.5 0.5 3 3 3; material 1 0 0 0.2 0.8 0 1 0 1; camera_angle 50",
            "reused",
        ),
        ("c", "sphere 1 1 -6 0.5", "built"),
        ("d", "camera_from 0 0 0.5", "built"),
        ("e", "samples 2; background 0 0 0.2", "reused"),
        ("f", "translate 0.5 0 0; sphere -1 0 -5 0.4", "built"),
        (
            "g",
            "clear_scene; camera_resolution 32 24; point_light 1 1 1 0 3 3; sphere 0 0 -5 1",
            "built",
        ),
    ];
    let tree =
        "[expr {[string match *reused* [lindex [split [stats] \\n] 1]] ? \"reused\" : \"built\"}]";
    let mut script = String::new();
    for (name, cmds, _) in steps {
        script += &format!("{cmds}\nrender {name}.ppm\nputs \"{name} {tree}\"\n");
    }
    let r = raytrace().arg("-c").arg(&script).current_dir(&dir).output().unwrap();
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let want: String = steps.iter().map(|(n, _, w)| format!("{n} {w}\n")).collect();
    assert_eq!(text(&r.stdout), want);
    // Each picture against a run that builds the same scene and renders once.
    let mut so_far = String::new();
    for (name, cmds, _) in steps {
        so_far += &format!("{cmds}\n");
        let fresh = format!("{so_far}render fresh-{name}.ppm\n");
        let r = raytrace().arg("-c").arg(&fresh).current_dir(&dir).output().unwrap();
        assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
        let (a, b) = (dir.join(format!("{name}.ppm")), dir.join(format!("fresh-{name}.ppm")));
        assert!(std::fs::read(a).unwrap() == std::fs::read(b).unwrap(), "{name} differs");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

pub fn degenerate_triangles_are_skipped_with_one_warning() {
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

/// A scene with shadows, a mirror and glass, placed by a uniform scale `s`
/// and a translation (camera, geometry and lights alike; point lights
/// brighter by s² so the light arriving is the same).
fn placed_scene(s: f64, t: [f64; 3]) -> String {
    format!(
        "
set s {s}; lassign {{{} {} {}}} tx ty tz
proc P {{x y z}} {{ global s tx ty tz; list [expr {{$x*$s+$tx}}] [expr {{$y*$s+$ty}}] [expr {{$z*$s+$tz}}] }}
proc V {{x y z}} {{ vertex {{*}}[P $x $y $z] }}
camera_from {{*}}[P 0 2 6]; camera_target {{*}}[P 0 0.5 0]; camera_resolution 96 72; camera_angle 50
ambient_light 0.1 0.1 0.1; background 0.2 0.3 0.5
set i [expr {{20*$s*$s}}]; point_light $i $i $i {{*}}[P -3 6 4]
parallel_light 0.3 0.3 0.3 1 -2 -1
material 0.8 0.8 0.8 0.2 0.6 0.3 10 0 1
set a [V -5 0 -5]; set b [V -5 0 5]; set c [V 5 0 5]; set d [V 5 0 -5]
tri $a $b $c; tri $a $c $d
material 0.9 0.9 0.9 0 0.1 0.9 50 0 1
sphere {{*}}[P -1.3 0.7 0] [expr {{0.7*$s}}]
material 1 1 1 0 0 0.1 50 0.9 1.5
sphere {{*}}[P 0.3 0.5 1.2] [expr {{0.5*$s}}]
material 0.9 0.3 0.2 0.2 0.7 0.3 30 0 1
sphere {{*}}[P 1.4 0.6 -0.5] [expr {{0.6*$s}}]
",
        t[0], t[1], t[2]
    )
}

pub fn pictures_do_not_depend_on_where_the_scene_sits_or_its_scale() {
    // Issue "pictures that hold up": moved by 10^4 the old offset lost
    // shadows and reflections (19 % of pixels), scaled to 10^-4 every shadow.
    let base = render_script(&placed_scene(1.0, [0.0; 3])).to_rgb8(Encoding::Linear);
    let cases = [
        (1.0, [1e4, 0.0, 1e4]),
        (1.0, [1e5, 0.0, 1e5]),
        (1.0, [-3e4, 7e4, 1e5]),
        (1e-4, [0.0; 3]),
        (1e-3, [0.0; 3]),
        (1e3, [0.0; 3]),
        (1e6, [0.0; 3]),
        (1e-4, [1.0, 2.0, 3.0]),
    ];
    for (s, t) in cases {
        let got = render_script(&placed_scene(s, t)).to_rgb8(Encoding::Linear);
        let off = base
            .chunks(3)
            .zip(got.chunks(3))
            .filter(|(a, b)| a.iter().zip(b.iter()).any(|(x, y)| x.abs_diff(*y) > 2))
            .count();
        // Under 0.1 % of the pixels may be off by more than 2/255.
        assert!(off * 1000 < base.len() / 3, "scale {s}, moved by {t:?}: {off} pixels differ");
    }
}

/// Two overlapping coplanar quads, `first` added before `second` (if any).
fn coplanar(first: &str, second: Option<&str>) -> String {
    format!(
        "
camera_from 0.37 0.21 4.3; camera_target 0.2 0.1 0; camera_angle 40; camera_resolution 64 64
ambient_light 0.2 0.2 0.2; parallel_light 1 1 1 0.3 -0.2 -1
# In a tilted plane, so the two quads' distances round differently.
proc V {{x y}} {{ vertex [expr {{$x + 0.0137}}] $y [expr {{-0.31*$x - 0.17*$y + 0.123}}] }}
# Each quad is a grid of 3x3 cells, so the two land in different leaves of
# the tree, in an order that has nothing to do with which came first.
proc quad {{x0 y0 x1 y1}} {{
    set n 3.0
    for {{set i 0}} {{$i < $n}} {{incr i}} {{
        for {{set j 0}} {{$j < $n}} {{incr j}} {{
            set xa [expr {{$x0 + ($x1 - $x0) * $i / $n}}]; set xb [expr {{$x0 + ($x1 - $x0) * ($i + 1) / $n}}]
            set ya [expr {{$y0 + ($y1 - $y0) * $j / $n}}]; set yb [expr {{$y0 + ($y1 - $y0) * ($j + 1) / $n}}]
            set a [V $xa $ya]; set b [V $xb $ya]; set c [V $xb $yb]; set d [V $xa $yb]
            tri $a $b $c; tri $a $c $d
        }}
    }}
}}
material {first} 0.5 0.5 0 1 0 1
quad -1 -1 1 1
{}
",
        match second {
            Some(c) => format!("material {c} 0.5 0.5 0 1 0 1; quad -0.7 -0.6 1.3 1.2"),
            None => String::new(),
        }
    )
}

pub fn coplanar_triangles_show_the_one_added_first() {
    // Issue "pictures that hold up": equal-distance hits went to whichever
    // the walk met first, a speckled mix of both colours.
    let (blue, yellow) = ("0.1 0.2 0.9", "0.9 0.8 0.1");
    for (first, second, want_blue) in [(blue, yellow, true), (yellow, blue, false)] {
        let img = render_script(&coplanar(first, Some(second)));
        let (mut overlap, mut wrong) = (0, 0);
        for p in &img.pixels {
            if *p == Vec3::ZERO {
                continue;
            }
            let is_blue = p.z > p.x;
            overlap += 1;
            wrong += (is_blue != want_blue) as usize;
        }
        // The first quad covers the overlap; the second shows only where the
        // first is not (a band on two sides).
        assert!(overlap > 1000, "{overlap}");
        let alone = render_script(&coplanar(first, None));
        let band = alone
            .pixels
            .iter()
            .zip(&img.pixels)
            .filter(|(a, p)| **a == Vec3::ZERO && **p != Vec3::ZERO)
            .count();
        assert_eq!(
            wrong, band,
            "first {first}: {wrong} pixels show the second quad inside the first"
        );
    }
}

/// A 6x12 sphere of smooth (counter-clockwise) triangles lit by a parallel
/// light travelling along `dir`, over a faint ambient that marks its disk.
fn coarse_sphere(dir: &str) -> String {
    coarse_sphere_with(dir, "1 1 1 1 1 0 1 0 1", false)
}

/// The coarse sphere with a material, wound clockwise if `cw`.
fn coarse_sphere_with(dir: &str, material: &str, cw: bool) -> String {
    let corners = if cw {
        "$v($p) $nn($p) $v($r) $nn($r) $v($q) $nn($q)"
    } else {
        "$v($p) $nn($p) $v($q) $nn($q) $v($r) $nn($r)"
    };
    format!(
        "
camera_from 0 0 4; camera_target 0 0 0; camera_angle 40; camera_resolution 128 128
parallel_light 1 1 1 {dir}; ambient_light 0.02 0.02 0.02
material {material}
set pi [expr {{acos(-1)}}]
set rows 6; set cols 12
for {{set i 0}} {{$i <= $rows}} {{incr i}} {{
    for {{set j 0}} {{$j < $cols}} {{incr j}} {{
        set th [expr {{$pi * $i / $rows}}]; set ph [expr {{2 * $pi * $j / $cols}}]
        set n [list [expr {{sin($th)*cos($ph)}}] [expr {{cos($th)}}] [expr {{sin($th)*sin($ph)}}]]
        set v($i,$j) [vertex {{*}}$n]; set nn($i,$j) [normal {{*}}$n]
    }}
}}
for {{set i 0}} {{$i < $rows}} {{incr i}} {{
    for {{set j 0}} {{$j < $cols}} {{incr j}} {{
        set k [expr {{($j + 1) % $cols}}]; set i1 [expr {{$i + 1}}]
        foreach {{p q r}} [list $i,$j $i,$k $i1,$k  $i,$j $i1,$k $i1,$j] {{
            ntri {corners}
        }}
    }}
}}
"
    )
}

pub fn coarse_smooth_meshes_have_no_shadow_terminator_notches() {
    // Issue "pictures that hold up": near the terminator the facets shadowed
    // their neighbours, cutting dark facet-shaped notches into the lit side
    // (jumps of 0.2-0.28 between neighbouring pixels). Shadow rays now start
    // from Hanika's point on the smooth surface: away from the silhouette,
    // no pixel differs from a neighbour by more than 0.08 (measured: 0.043).
    for dir in ["-1 -0.3 0.4", "-1 0.5 0.8", "-0.5 -1 0.3"] {
        let img = render_script(&coarse_sphere(dir));
        let (w, h) = (img.width as i32, img.height as i32);
        let g = |x: i32, y: i32| img.get(x as u32, y as u32).x;
        let mut worst = 0f32;
        for y in 3..h - 3 {
            for x in 3..w - 3 {
                // Only where the disk (ambient > 0) surrounds the pixel.
                let inner = (-3..=3).all(|j| (-3..=3).all(|i| g(x + i, y + j) > 0.01));
                if !inner {
                    continue;
                }
                for (i, j) in [(-1, 0), (1, 0), (0, -1), (0, 1)] {
                    worst = worst.max((g(x, y) - g(x + i, y + j)).abs());
                }
            }
        }
        assert!(worst <= 0.08, "light {dir}: neighbouring pixels differ by {worst}");
    }
}

/// The chunks of a PNG file: (type, data).
fn png_chunks(data: &[u8]) -> Vec<(String, Vec<u8>)> {
    assert_eq!(&data[..8], b"\x89PNG\r\n\x1a\n");
    let mut out = Vec::new();
    let mut i = 8;
    while i + 8 <= data.len() {
        let n = u32::from_be_bytes(data[i..i + 4].try_into().unwrap()) as usize;
        let kind = String::from_utf8_lossy(&data[i + 4..i + 8]).into_owned();
        out.push((kind, data[i + 8..i + 8 + n].to_vec()));
        i += 12 + n;
    }
    out
}

pub fn pngs_say_how_their_values_are_encoded() {
    // Issue "pictures that hold up": untagged linear PNGs were shown as sRGB,
    // too dark. Linear output carries gAMA 1.0 (100000); `-srgb` the sRGB
    // chunk, with the gAMA it implies (45455) for older decoders.
    let dir = crate::util::scratch("png-tags");
    let (lin, srgb) = (dir.join("lin.png"), dir.join("srgb.png"));
    let r = raytrace()
        .args(["-c", &format!(
            "camera_resolution 8 8; sphere 0 0 -3 1; ambient_light 1 1 1; render {{{}}}; render -srgb {{{}}}",
            lin.display(),
            srgb.display()
        )])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", text(&r.stderr));
    let find = |path: &Path, kind: &str| {
        png_chunks(&std::fs::read(path).unwrap()).into_iter().find(|c| c.0 == kind).map(|c| c.1)
    };
    assert_eq!(find(&lin, "gAMA"), Some(100_000u32.to_be_bytes().to_vec()));
    assert_eq!(find(&lin, "sRGB"), None);
    assert_eq!(find(&srgb, "sRGB"), Some(vec![0]));
    assert_eq!(find(&srgb, "gAMA"), Some(45_455u32.to_be_bytes().to_vec()));
    // Merging crops keeps the parts' encoding.
    let part = dir.join("part.png");
    let r = raytrace()
        .args([
            "-c",
            &format!("camera_resolution 8 8; sphere 0 0 -3 1; render -srgb {{{}}}", part.display()),
        ])
        .args(["--crop", "0", "0", "8", "8"])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", text(&r.stderr));
    let merged = dir.join("merged.png");
    let r = raytrace()
        .args(["--merge", merged.to_str().unwrap(), part.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(r.status.success(), "{}", text(&r.stderr));
    assert_eq!(find(&merged, "sRGB"), Some(vec![0]));
}

pub fn smooth_meshes_shade_the_same_whichever_way_they_are_wound() {
    // Issue "pictures that hold up": a clockwise `ntri` mesh lost its vertex
    // normals (`ns = ng` when they disagreed) and was flat-shaded with a
    // square highlight. The shading normal is now turned to the ray's side.
    let m = "0.8 0.3 0.2 0.1 0.7 0.5 30 0 1";
    let ccw = render_script(&coarse_sphere_with("-1 -0.5 -1", m, false));
    let cw = render_script(&coarse_sphere_with("-1 -0.5 -1", m, true));
    assert!(ccw.pixels.iter().any(|p| p.x > 0.5), "the highlight is there");
    let (a, b) = (ccw.to_rgb8(Encoding::Linear), cw.to_rgb8(Encoding::Linear));
    let differ = a.iter().zip(&b).filter(|(x, y)| x != y).count();
    assert_eq!(differ, 0, "{differ} bytes differ between the two windings");
}
