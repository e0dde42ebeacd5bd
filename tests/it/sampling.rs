//! Sampling by numbers (issue "sampling"): antialiased edges against their
//! covered fractions, the same bytes for any thread count, crop or pass,
//! seeds that change the noise only, and tone maps against their formulas.

use crate::util::{raytrace, scratch, text};

/// Renders `script` (with the output named in it) and returns the linear
/// 8-bit picture.
fn render(dir: &std::path::Path, args: &[&str], script: &str) -> rayshell::image::Rgb8 {
    let r = raytrace().args(args).args(["-q", "-c", script]).current_dir(dir).output().unwrap();
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let out = script.rsplit(' ').next().unwrap();
    rayshell::image::read_rgb8(&std::fs::read(dir.join(out)).unwrap()).unwrap()
}

/// The area of the unit pixel square at (i, j) on the side a·x + b·y < c.
fn covered(i: u32, j: u32, (a, b, c): (f64, f64, f64)) -> f64 {
    let (x0, y0) = (i as f64, j as f64);
    let square = [(x0, y0), (x0 + 1.0, y0), (x0 + 1.0, y0 + 1.0), (x0, y0 + 1.0)];
    // Sutherland–Hodgman against one half-plane, then the shoelace area.
    let inside = |p: (f64, f64)| c - a * p.0 - b * p.1;
    let mut poly = Vec::new();
    for k in 0..4 {
        let (p, q) = (square[k], square[(k + 1) % 4]);
        let (dp, dq) = (inside(p), inside(q));
        if dp >= 0.0 {
            poly.push(p);
        }
        if (dp >= 0.0) != (dq >= 0.0) {
            let t = dp / (dp - dq);
            poly.push((p.0 + t * (q.0 - p.0), p.1 + t * (q.1 - p.1)));
        }
    }
    let n = poly.len();
    (0..n)
        .map(|k| poly[k].0 * poly[(k + 1) % n].1 - poly[(k + 1) % n].0 * poly[k].1)
        .sum::<f64>()
        .abs()
        / 2.0
}

/// A white half-plane a·x + b·y < c in pixel coordinates on black: a huge
/// triangle in the plane z = -1 seen by a 90° camera at the origin, where
/// pixel (px, py) of a W×H picture is the point (2px/W - 1, 1 - 2py/H).
fn half_plane_scene(w: u32, h: u32, (a, b, c): (f64, f64, f64)) -> String {
    let to_plane = |px: f64, py: f64| (2.0 * px / w as f64 - 1.0, 1.0 - 2.0 * py / h as f64);
    // A point on the line, its direction, and the white side's normal.
    let n = (a * a + b * b).sqrt();
    let p = (a * c / (n * n), b * c / (n * n));
    let d = (-b / n, a / n);
    let far = 1.0e4;
    let corners = [
        (p.0 + far * d.0, p.1 + far * d.1),
        (p.0 - far * d.0, p.1 - far * d.1),
        (p.0 - far * a / n, p.1 - far * b / n),
    ];
    let mut s = format!(
        "camera_resolution {w} {h}; camera_angle 90; camera_from 0 0 0; camera_target 0 0 -1\n\
         ambient_light 1 1 1; material 1 1 1 1 0 0 1 0 1\n"
    );
    let mut ids = Vec::new();
    for (k, (px, py)) in corners.iter().enumerate() {
        let (x, y) = to_plane(*px, *py);
        s.push_str(&format!("set v{k} [vertex {x} {y} -1]\n"));
        ids.push(format!("$v{k}"));
    }
    s.push_str(&format!("tri {}\n", ids.join(" ")));
    s
}

/// The mean absolute error of the edge pixels against their covered
/// fractions, and the mean signed error (bias).
fn edge_error(img: &rayshell::image::Rgb8, line: (f64, f64, f64)) -> (f64, f64, usize) {
    let (mut abs, mut signed, mut n) = (0.0, 0.0, 0);
    for j in 0..img.height {
        for i in 0..img.width {
            let want = covered(i, j, line);
            if want > 1e-9 && want < 1.0 - 1e-9 {
                let got = img.rgb[((j * img.width + i) * 3) as usize] as f64 / 255.0;
                abs += (got - want).abs();
                signed += got - want;
                n += 1;
            }
        }
    }
    (abs / n as f64, signed / n as f64, n)
}

pub fn edges_converge_to_their_covered_fractions() {
    let dir = scratch("sampling-edges");
    let (w, h) = (48, 48);
    // An edge at about 27° through the picture, off the pixel grid.
    let line = (0.45, -0.89, 0.45 * 24.3 - 0.89 * 23.7);
    let scene = half_plane_scene(w, h, line);
    let mut errors = Vec::new();
    for n in [1, 4, 16, 64] {
        let img = render(&dir, &[], &format!("{scene}samples {n}; render e{n}.ppm"));
        let (abs, bias, edge_pixels) = edge_error(&img, line);
        assert!(edge_pixels > 40, "{edge_pixels}");
        assert!(n == 1 || bias.abs() < 0.02, "samples {n}: bias {bias}");
        errors.push(abs);
    }
    // One ray per pixel: all or nothing (an error near 1/4 on average).
    assert!(errors[0] > 0.15, "{errors:?}");
    // Stratified: the error falls faster than 1/sqrt(n) (16x the samples,
    // at least 4x less error), to the 8-bit floor.
    assert!(errors[1] < 0.12, "{errors:?}");
    assert!(errors[3] < errors[1] / 4.0, "{errors:?}");
    assert!(errors[3] < 0.012, "{errors:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The same bytes for 1 and 2 threads, progressive passes, and a crop
/// (its pixels are the whole picture's), with every filter, adaptive
/// sampling and a moving ball.
pub fn sampled_pictures_do_not_depend_on_threads_passes_or_crops() {
    let dir = scratch("sampling-same");
    let scene = "camera_resolution 40 30; camera_from 0 0 5; camera_target 0 0 0\n\
                 point_light 1 1 1 3 4 5; ambient_light 0.1 0.1 0.1\n\
                 material 0.9 0.3 0.2 0.2 0.8 0.5 30 0 1; sphere 0 0 0 1.2\n\
                 material 0.3 0.9 0.5 0.2 0.8 0 1 0.5 1.5; sphere 1.2 0.8 1 0.5\n\
                 motion 0.4 0 0; sphere -1.3 -0.6 1 0.4; shutter 0 1\n\
                 samples 9\n";
    for filter in ["box", "tent 1.2", "gaussian", "mitchell", "tent; adaptive 0.01 40"] {
        let s = format!("{scene}filter {filter}; render a.ppm");
        let one = render(&dir, &["--threads", "1"], &s);
        let two = render(&dir, &["--threads", "2"], &s);
        let prog = render(&dir, &["--progressive"], &s);
        assert!(one.rgb == two.rgb, "{filter}: 1 vs 2 threads");
        assert!(one.rgb == prog.rgb, "{filter}: progressive");
        let crop = render(&dir, &["--crop", "7", "5", "29", "21"], &s);
        for y in 0..16u32 {
            for x in 0..22u32 {
                let (c, f) = (((y * 22 + x) * 3) as usize, (((y + 5) * 40 + x + 7) * 3) as usize);
                assert_eq!(crop.rgb[c..c + 3], one.rgb[f..f + 3], "{filter}: crop at {x},{y}");
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `seed` and `--seed` move the noise and nothing else: edge pixels change,
/// their mean does not (much), flat areas not at all; one sample per pixel
/// has no noise to move.
pub fn seeds_change_the_noise_only() {
    let dir = scratch("sampling-seed");
    let line = (0.3, 0.95, 0.3 * 20.2 + 0.95 * 19.6);
    let scene = half_plane_scene(40, 40, line);
    let base = render(&dir, &[], &format!("{scene}samples 4; render a.ppm"));
    let seeded = render(&dir, &[], &format!("{scene}samples 4; seed 7; render b.ppm"));
    let flag = render(&dir, &["--seed", "7"], &format!("{scene}samples 4; render c.ppm"));
    for other in [&seeded, &flag] {
        let differ = base.rgb.iter().zip(&other.rgb).filter(|(a, b)| a != b).count();
        assert!(differ > 20, "{differ}");
        let (e0, e1) = (edge_error(&base, line), edge_error(other, line));
        assert!((e0.1 - e1.1).abs() < 0.03, "{e0:?} {e1:?}");
    }
    assert!(seeded.rgb != flag.rgb, "the script's seed and --seed are different noise");
    let one = render(&dir, &[], &format!("{scene}render d.ppm"));
    let one_seeded = render(&dir, &["--seed", "3"], &format!("{scene}seed 5; render e.ppm"));
    assert!(one.rgb == one_seeded.rgb);
    let _ = std::fs::remove_dir_all(&dir);
}

/// `exposure` and `tonemap` on a flat surface of linear value 3.
pub fn exposure_and_tone_maps_follow_their_formulas() {
    let dir = scratch("sampling-look");
    let scene = "camera_resolution 4 4; camera_from 0 0 5; camera_target 0 0 0\n\
                 ambient_light 3 3 3; material 1 0.5 0.25 1 0 0 1 0 1; sphere 0 0 0 10\n";
    let aces = |x: f64| (x * (2.51 * x + 0.03)) / (x * (2.43 * x + 0.59) + 0.14);
    let cases: [(&str, [f64; 3]); 5] = [
        ("", [3.0, 1.5, 0.75]),
        ("exposure -1", [1.5, 0.75, 0.375]),
        ("exposure -2", [0.75, 0.375, 0.1875]),
        ("tonemap reinhard", [0.75, 0.375, 0.1875]),
        ("tonemap aces", [aces(3.0), aces(3.0) / 2.0, aces(3.0) / 4.0]),
    ];
    for (look, want) in cases {
        let img = render(&dir, &[], &format!("{scene}{look}\nrender l.ppm"));
        for (k, w) in want.iter().enumerate() {
            let want = (w.min(1.0) * 255.0).round() as i32;
            let got = img.rgb[k] as i32;
            assert!((got - want).abs() <= 1, "{look}: channel {k}: {got} vs {want}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Bad values are located errors that name the choices.
pub fn sampling_commands_refuse_bad_values() {
    for (script, msg) in [
        ("samples 0", "samples must be between 1 and 65536, got 0"),
        ("samples 1.5", "samples: n: expected integer but got \"1.5\""),
        ("filter lanczos", "bad filter \"lanczos\": must be box, tent, gaussian or mitchell"),
        ("filter box 0", "filter radius must be above 0 and at most 16 pixels, got 0"),
        ("filter tent x", "filter: radius: expected a finite number but got \"x\""),
        ("tonemap filmic", "bad tone map \"filmic\": must be clamp, reinhard or aces"),
        ("exposure 100", "exposure must be between -64 and 64 stops, got 100"),
        ("shutter 1 0", "shutter must open before it closes, at finite times, got 1 0"),
        ("motion 1 x 0", "motion: dy: expected number but got \"x\""),
        ("motion 1 0 1e300", "motion: dz: number 1e+300 is too large"),
    ] {
        let r = raytrace().args(["-c", script]).output().unwrap();
        assert_eq!(r.status.code(), Some(1), "{script}");
        let err = text(&r.stderr);
        assert!(err.starts_with(&format!("-c:1: {msg}")), "{script}: {err}");
    }
}

/// Depth of field: an out-of-focus bright ball blurs into the thin lens's
/// circle of confusion. A 90° camera of W pixels images a point at depth z,
/// seen through a lens of radius A focused at depth f, as a disc of radius
/// R = (W/2)·A·|1/f − 1/z| pixels; a uniform disc has E[r²] = R²/2, to
/// which the ball's own disc (radius s: s²/2) and the pixel (1/6) add.
pub fn depth_of_field_blurs_into_the_circle_of_confusion() {
    let dir = scratch("sampling-dof");
    let (w, a, z, ball) = (101.0f64, 0.5, 4.0, 0.1);
    let s = (w / 2.0) * ball / (z * z - ball * ball).sqrt();
    // As bright as keeps every pixel below 1 (no clipping).
    for (focus, light) in [(2.0f64, 20), (4.0, 1), (8.0, 5)] {
        let script = format!(
            "camera_resolution 101 101; camera_angle 90; camera_from 0 0 0; camera_target 0 0 -1\n\
             ambient_light {light} {light} {light}; material 1 1 1 1 0 0 1 0 1; sphere 0 0 -{z} {ball}\n\
             camera_aperture {a}; camera_focus {focus}; samples 400; render d.ppm"
        );
        let img = render(&dir, &[], &script);
        let (mut m0, mut m2) = (0.0f64, 0.0f64);
        for j in 0..101u32 {
            for i in 0..101u32 {
                let v = img.rgb[((j * 101 + i) * 3) as usize] as f64 / 255.0;
                let (dx, dy) = (i as f64 + 0.5 - 50.5, j as f64 + 0.5 - 50.5);
                m0 += v;
                m2 += v * (dx * dx + dy * dy);
            }
        }
        let r = (w / 2.0) * a * (1.0 / focus - 1.0 / z).abs();
        let want = r * r / 2.0 + s * s / 2.0 + 1.0 / 6.0;
        let got = m2 / m0;
        assert!((got / want - 1.0).abs() < 0.08, "focus {focus}: E[r²] {got} vs {want} (R = {r})");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Adaptive sampling: on the half-plane, where only edge pixels vary, it
/// reaches uniform sampling's error with far fewer samples, and `--stats`
/// says how many it spent. The measure is the standard error of the
/// pixel's mean luminance.
pub fn adaptive_sampling_spends_fewer_samples_for_the_same_error() {
    let dir = scratch("sampling-adaptive");
    let (w, h) = (48, 48);
    let line = (0.45, -0.89, 0.45 * 24.3 - 0.89 * 23.7);
    let scene = half_plane_scene(w, h, line);
    let spent = |args: &[&str], script: &str| -> (rayshell::image::Rgb8, f64) {
        let r = raytrace()
            .args(args)
            .args(["-q", "--stats", "-c", script])
            .current_dir(&dir)
            .output()
            .unwrap();
        assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
        let err = text(&r.stderr);
        let line = err.lines().find(|l| l.starts_with("samples ")).expect("a samples line");
        let per_pixel: f64 = line.split_whitespace().nth(1).unwrap().parse().unwrap();
        let img = rayshell::image::read_rgb8(&std::fs::read(dir.join("a.ppm")).unwrap()).unwrap();
        (img, per_pixel)
    };
    let (uniform, u_spent) = spent(&[], &format!("{scene}samples 64; render a.ppm"));
    let (adaptive, a_spent) =
        spent(&[], &format!("{scene}samples 8; adaptive 0.01 256; render a.ppm"));
    let (eu, ea) = (edge_error(&uniform, line).0, edge_error(&adaptive, line).0);
    assert_eq!(u_spent, 64.0);
    assert!(ea <= eu * 1.1, "adaptive error {ea} vs uniform {eu}");
    assert!(a_spent < u_spent / 3.0, "adaptive spent {a_spent} per pixel");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The outside oracle: Mitsuba 3's `direct` integrator on the same scenes
/// (`tests/mitsuba/NAME.py` made `NAME.pfm` from the scene in `NAME.tsd`:
/// diffuse reflectance Kd·colour, point intensity π·I, area emitters of the
/// same radiance, 1024 samples per pixel, box filter). Ours at 64 samples
/// agrees within the noise of both and 8-bit rounding. Measured: `lambert`
/// (three balls, two point lights) mean |difference| 0.0026, 99th
/// percentile 0.017 (edge pixels); `area` (an area light's soft shadows and
/// a point light) 0.0012 and 0.0086; means equal to 1e-4.
pub fn agrees_with_mitsuba_on_lambert_scenes() {
    for name in ["lambert", "area"] {
        compare_with_mitsuba(name);
    }
}

fn compare_with_mitsuba(name: &str) {
    let dir = crate::util::root().join("tests/mitsuba");
    let pfm = std::fs::read(dir.join(format!("{name}.pfm"))).unwrap();
    // PFM: "PF", width height, scale (negative: little-endian), then rows
    // of RGB floats from the bottom up.
    let mut header = pfm.splitn(4, |&b| b == b'\n');
    assert_eq!(header.next(), Some(&b"PF"[..]));
    let size = text(header.next().unwrap());
    let (w, h): (usize, usize) = {
        let mut it = size.split_whitespace().map(|x| x.parse().unwrap());
        (it.next().unwrap(), it.next().unwrap())
    };
    assert!(text(header.next().unwrap()).starts_with('-'), "little-endian PFM");
    let floats: Vec<f32> = header
        .next()
        .unwrap()
        .chunks_exact(4)
        .map(|b| f32::from_le_bytes([b[0], b[1], b[2], b[3]]))
        .collect();
    assert_eq!(floats.len(), w * h * 3);
    let out = scratch(&format!("mitsuba-{name}"));
    let r = raytrace()
        .args(["-q", dir.join(format!("{name}.tsd")).to_str().unwrap(), "ours.ppm"])
        .current_dir(&out)
        .output()
        .unwrap();
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let ours = rayshell::image::read_rgb8(&std::fs::read(out.join("ours.ppm")).unwrap()).unwrap();
    assert_eq!((ours.width as usize, ours.height as usize), (w, h));
    let mut diffs = Vec::with_capacity(w * h * 3);
    let (mut sum_ours, mut sum_ref) = (0.0f64, 0.0f64);
    for y in 0..h {
        for x in 0..w {
            for k in 0..3 {
                let reference = floats[((h - 1 - y) * w + x) * 3 + k].clamp(0.0, 1.0) as f64;
                let got = ours.rgb[(y * w + x) * 3 + k] as f64 / 255.0;
                diffs.push((got - reference).abs());
                sum_ours += got;
                sum_ref += reference;
            }
        }
    }
    let n = diffs.len() as f64;
    let mean = diffs.iter().sum::<f64>() / n;
    diffs.sort_by(|a, b| a.total_cmp(b));
    let p99 = diffs[(0.99 * n) as usize];
    assert!(sum_ref / n > 0.05, "{name}: the reference is not dark");
    assert!(mean < 0.005, "{name}: mean |difference| {mean}");
    assert!(p99 < 0.03, "{name}: 99th percentile {p99}");
    assert!(
        (sum_ours - sum_ref).abs() / n < 0.001,
        "{name}: means {} vs {}",
        sum_ours / n,
        sum_ref / n
    );
    let _ = std::fs::remove_dir_all(&out);
}

/// The light a point receives from a lit rectangle or sphere, against the
/// closed forms: a white Lambert floor point under a corner of an a×b
/// rectangle of radiance L at height h reflects L·F, F the form factor
/// (1/2π)(X/√(1+X²)·atan(Y/√(1+X²)) + Y/√(1+Y²)·atan(X/√(1+Y²))), X = a/h,
/// Y = b/h; under its centre, four such quarters. Under a sphere of radius
/// R at height d: L·(R/d)².
pub fn area_and_sphere_lights_match_their_form_factors() {
    let dir = scratch("sampling-area");
    let corner_ff = |a: f64, b: f64, h: f64| {
        let (x, y) = (a / h, b / h);
        let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
        (x / sx * (y / sx).atan() + y / sy * (x / sy).atan()) / (2.0 * std::f64::consts::PI)
    };
    let (a, b, h, l) = (2.0, 1.0, 1.5, 2.0);
    // The camera looks down at the origin, past the sphere and through the
    // rectangles' backs (seen from the front only): its centre pixel.
    let floor = "camera_resolution 33 33; camera_from 3 4 0; camera_target 0 0 0\n\
                 material 1 1 1 0 1 0 1 0 1\n\
                 tri [vertex -9 0 -9] [vertex -9 0 9] [vertex 9 0 9]\n\
                 tri [vertex -9 0 -9] [vertex 9 0 9] [vertex 9 0 -9]\n";
    let cases = [
        (
            "under the centre",
            format!("area_light {l} {l} {l}  {} {h} {}  {a} 0 0  0 0 {b}  32", -a / 2.0, -b / 2.0),
            l * 4.0 * corner_ff(a / 2.0, b / 2.0, h),
        ),
        (
            "under a corner",
            format!("area_light {l} {l} {l}  0 {h} 0  {a} 0 0  0 0 {b}  32"),
            l * corner_ff(a, b, h),
        ),
        ("under a sphere", "sphere_light 3 3 3  0 2 0  0.6 32".to_string(), 3.0 * 0.09),
    ];
    for (what, light, want) in cases {
        let img = render(&dir, &[], &format!("{floor}{light}\nrender a.ppm"));
        let got = img.rgb[(16 * 33 + 16) * 3] as f64 / 255.0;
        assert!((got - want).abs() <= 1.5 / 255.0, "{what}: {got} vs {want}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Motion blur: a ball (or a square of two triangles) of half-width r
/// moving at v across a shutter of length T leaves a streak 2r + v·T long;
/// a point x on its path is covered for the part of the shutter when
/// |x − c − v·t| < r. Each pixel of the middle row is that fraction
/// averaged over the pixel (an ambient-lit white shape on black).
pub fn motion_blur_streaks_by_velocity_times_shutter() {
    let dir = scratch("sampling-motion");
    // 201 pixels across 5 units at depth 100: 1/40.2 unit per pixel.
    let (w, depth, half) = (201u32, 100.0f64, 2.5f64);
    let angle = 2.0 * (half / depth).atan().to_degrees();
    let (c0, r, v, t0, t1) = (-1.5f64, 0.5f64, 3.0f64, 0.25f64, 0.75f64);
    let shapes = [
        ("a sphere", format!("sphere {c0} 0 0 {r}")),
        (
            "a square",
            format!(
                "set a [vertex {} -5 0]; set b [vertex {} -5 0]; set c [vertex {} 5 0]; set d [vertex {} 5 0]\n\
                 tri $a $b $c; tri $a $c $d",
                c0 - r,
                c0 + r,
                c0 + r,
                c0 - r
            ),
        ),
    ];
    // The covered fraction of the shutter at x, averaged over [xa, xb].
    let covered = |xa: f64, xb: f64| {
        let steps = 200;
        (0..steps)
            .map(|k| {
                let x = xa + (xb - xa) * (k as f64 + 0.5) / steps as f64;
                // c0 + v·t within (x − r, x + r).
                let (lo, hi) = (((x - r - c0) / v).max(t0), ((x + r - c0) / v).min(t1));
                (hi - lo).max(0.0) / (t1 - t0)
            })
            .sum::<f64>()
            / steps as f64
    };
    for (what, shape) in shapes {
        let script = format!(
            "camera_resolution {w} 21; camera_angle {angle}; camera_from 0 0 {depth}; camera_target 0 0 0\n\
             ambient_light 1 1 1; material 1 1 1 1 0 0 1 0 1\n\
             motion {v} 0 0; {shape}; motion 0 0 0\n\
             shutter {t0} {t1}; samples 256; render m.ppm"
        );
        let img = render(&dir, &[], &script);
        let px = 2.0 * half / w as f64;
        let (mut worst, mut first, mut last) = (0.0f64, None, 0);
        for i in 0..w {
            let got = img.rgb[((10 * w + i) * 3) as usize] as f64 / 255.0;
            let xa = -half + i as f64 * px;
            let want = covered(xa, xa + px);
            worst = worst.max((got - want).abs());
            if got > 0.0 {
                first.get_or_insert(i);
                last = i;
            }
        }
        assert!(worst < 0.03, "{what}: a pixel is {worst} from its covered fraction");
        // The streak: from c0 + v·t0 − r to c0 + v·t1 + r.
        let streak = (last - first.unwrap() + 1) as f64 * px;
        let want = 2.0 * r + v * (t1 - t0);
        assert!((streak - want).abs() <= 2.0 * px, "{what}: streak {streak} vs {want}");
        // The plateau where the shape covers a point for 2r/v of the time.
        let mid = img.rgb[((10 * w + w / 2 - 10) * 3) as usize] as f64 / 255.0;
        let plateau = 2.0 * r / (v * (t1 - t0));
        assert!((mid - plateau).abs() < 0.02, "{what}: plateau {mid} vs {plateau}");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// With the shutter closed at an instant, a moving object is exactly where
/// its velocity puts it, shadow included: the picture of a still object
/// placed there (up to the rounding of the moved ray's origin). Spheres,
/// triangles, boxes and instances alike, their textures carried along.
pub fn moving_objects_are_where_the_shutter_says() {
    let dir = scratch("sampling-moved");
    let base = "camera_resolution 60 40; camera_from 0 3 6; camera_target 0 0.5 0\n\
                point_light 1 1 1 2 5 3; ambient_light 0.1 0.1 0.1\n\
                material 0.8 0.8 0.8 0.2 0.8 0 1 0 1\n\
                tri [vertex -5 0 -5] [vertex -5 0 5] [vertex 5 0 5]\n\
                tri [vertex -5 0 -5] [vertex 5 0 5] [vertex 5 0 -5]\n\
                material 0.9 0.3 0.2 0.2 0.8 0.4 20 0 1\n";
    let moving = format!(
        "{base}motion 0.5 0.25 0; sphere -1 0.7 0 0.6; tri [vertex 0 1 0] [vertex 1 1 0] [vertex 0 2 -1]\n\
         box 1 0 -2 1.5 0.5 -1.5; group g {{torus 0.3 0.1}}; transform {{translate -2 0.3 -1; instance g}}\n"
    );
    for (time, dx, dy) in [(0.0, 0.0, 0.0), (2.0, 1.0, 0.5)] {
        let seen = render(&dir, &[], &format!("{moving}shutter {time} {time}; render a.ppm"));
        let still = render(
            &dir,
            &[],
            &format!(
                "{base}sphere {} {} 0 0.6; tri [vertex {dx} {} 0] [vertex {} {} 0] [vertex {dx} {} -1]\n\
                 box {} {dy} -2 {} {} -1.5; group g {{torus 0.3 0.1}}; transform {{translate {} {} -1; instance g}}; render b.ppm",
                -1.0 + dx,
                0.7 + dy,
                1.0 + dy,
                1.0 + dx,
                1.0 + dy,
                2.0 + dy,
                1.0 + dx,
                1.5 + dx,
                0.5 + dy,
                -2.0 + dx,
                0.3 + dy
            ),
        );
        let differ = seen.rgb.iter().zip(&still.rgb).filter(|(a, b)| a.abs_diff(**b) > 2).count();
        assert!(differ <= 3, "at time {time}: {differ} channels differ");
        // Textured: the pattern rides along, as under `translate`.
        let objects =
            "texture checker 1 0.4 0.3 0.3 0.4 1 0.2; sphere -1 0.7 0 0.6; box 1 0 -2 1.5 0.5 -1.5";
        let seen = render(
            &dir,
            &[],
            &format!("{base}motion 0.5 0.25 0; {objects}; shutter {time} {time}; render c.ppm"),
        );
        let still = render(
            &dir,
            &[],
            &format!("{base}transform {{translate {dx} {dy} 0; {objects}}}; render d.ppm"),
        );
        let differ = seen.rgb.iter().zip(&still.rgb).filter(|(a, b)| a.abs_diff(**b) > 2).count();
        assert!(differ <= 3, "textured, at time {time}: {differ} channels differ");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The penumbra of a straight edge under a square area light: a floor point
/// at x sees the part of the light beyond the line through the edge, so the
/// shadow is total for x < −a·h/(2(H − h)) and absent beyond +a·h/(2(H − h))
/// (similar triangles: light of width a at height H, edge at height h), and
/// in between it lets through the visible part of ∫ cos·cos/d² over the
/// light. Checked pixel by pixel against the unoccluded floor.
pub fn penumbrae_match_similar_triangles() {
    let dir = scratch("sampling-penumbra");
    let (a, big_h, h) = (1.0f64, 4.0f64, 2.0f64);
    // The floor's z = 0 line across the middle row; x = 0 at the centre.
    let (w, eye_y, eye_z, half) = (201u32, 1.0f64, 10.0f64, 2.0f64);
    let depth = (eye_y * eye_y + eye_z * eye_z).sqrt();
    let angle = 2.0 * (half / depth).atan().to_degrees();
    let floor = format!(
        "camera_resolution {w} 5; camera_angle {angle}; camera_from 0 {eye_y} {eye_z}; camera_target 0 0 0\n\
         material 1 1 1 0 1 0 1 0 1\n\
         tri [vertex -20 0 -20] [vertex -20 0 20] [vertex 20 0 20]\n\
         tri [vertex -20 0 -20] [vertex 20 0 20] [vertex 20 0 -20]\n\
         area_light 45 45 45  {} {big_h} {}  {a} 0 0  0 0 {a}  32\n",
        -a / 2.0,
        -a / 2.0
    );
    let edge = format!(
        "material 0 0 0 0 0 0 1 0 1\n\
         tri [vertex -20 {h} -20] [vertex 0 {h} 20] [vertex -20 {h} 20]\n\
         tri [vertex -20 {h} -20] [vertex 0 {h} -20] [vertex 0 {h} 20]\n"
    );
    let open = render(&dir, &[], &format!("{floor}render o.ppm"));
    let shaded = render(&dir, &[], &format!("{floor}{edge}render s.ppm"));
    // The visible share of the light from (x, 0, 0): light points with
    // x_l > s = x·(1 − H/h), weighted by cos·cos/d² = H²/d⁴.
    let share = |x: f64| {
        let s = x * (1.0 - big_h / h);
        let n = 300;
        let (mut seen, mut all) = (0.0, 0.0);
        for i in 0..n {
            let xl = -a / 2.0 + a * (i as f64 + 0.5) / n as f64;
            for k in 0..n {
                let zl = -a / 2.0 + a * (k as f64 + 0.5) / n as f64;
                let d2 = (xl - x).powi(2) + big_h * big_h + zl * zl;
                let g = 1.0 / (d2 * d2);
                all += g;
                if xl > s {
                    seen += g;
                }
            }
        }
        seen / all
    };
    let px = 2.0 * half / w as f64;
    let width = a * h / (big_h - h);
    let mut worst = 0.0f64;
    for i in 0..w {
        let x = -half + (i as f64 + 0.5) * px;
        let at = ((2 * w + i) * 3) as usize;
        let (lit, got) = (open.rgb[at] as f64, shaded.rgb[at] as f64);
        assert!(lit > 100.0, "the open floor is lit at {x}: {lit}");
        if x < -width / 2.0 - px {
            assert_eq!(got, 0.0, "full shadow at x = {x}");
        } else if x > width / 2.0 + px {
            assert!((got - lit).abs() <= 1.0, "no shadow at x = {x}: {got} vs {lit}");
        } else {
            worst = worst.max((got / lit - share(x)).abs());
        }
    }
    assert!(worst < 0.02, "the penumbra is {worst} off the visible share");
    let _ = std::fs::remove_dir_all(&dir);
}
