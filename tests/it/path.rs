//! Path tracing (issue "global illumination"): furnace tests whose answer
//! is known exactly in expectation, Mitsuba 3's picture of the same Cornell
//! box, and the same bytes for any thread count, pass order or crop.

use crate::util::{raytrace, root, scratch, text};

fn render(dir: &std::path::Path, args: &[&str], script: &str) -> rayshell::image::Rgb8 {
    let r = raytrace().args(args).args(["-q", "-c", script]).current_dir(dir).output().unwrap();
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let out = script.rsplit(' ').next().unwrap();
    rayshell::image::read_rgb8(&std::fs::read(dir.join(out)).unwrap()).unwrap()
}

fn value(img: &rayshell::image::Rgb8, i: usize) -> f64 {
    img.rgb[i] as f64 / 255.0
}

/// A convex diffuse ball of albedo a under a uniform environment of
/// radiance L shows a·L everywhere (every bounce leaves to the sky, which
/// light sampling and BSDF sampling both find); around it, L. Measured
/// (64 paths per pixel): mean 0.4798 for 0.48, the worst pixel 0.041 off.
pub fn a_diffuse_ball_in_a_white_furnace_shows_its_albedo() {
    let dir = scratch("path-furnace-ball");
    let (a, l) = (0.6, 0.8);
    let (w, r, dist) = (32u32, 1.0f64, 4.0f64);
    let angle = 2.0 * (1.3 * r / dist).atan().to_degrees();
    let img = render(
        &dir,
        &[],
        &format!(
            "camera_resolution {w} {w}; camera_angle {angle}; camera_from 0 0 {dist}; camera_target 0 0 0\n\
             integrator path; samples 64; trace_depth 6; environment {l} {l} {l}\n\
             material 1 1 1 0 {a} 0 1 0 1; sphere 0 0 0 {r}; render f.ppm"
        ),
    );
    let half = (angle / 2.0).to_radians().tan() * dist;
    let (mut sum, mut n, mut worst) = (0.0, 0, 0.0f64);
    for j in 0..w {
        for i in 0..w {
            let x = ((i as f64 + 0.5) / w as f64 * 2.0 - 1.0) * half;
            let y = (1.0 - (j as f64 + 0.5) / w as f64 * 2.0) * half;
            // The ball's silhouette from 4 away is a little smaller than r.
            let rho = (x * x + y * y).sqrt();
            let k = ((j * w + i) * 3) as usize;
            if rho < 0.9 * r {
                for c in 0..3 {
                    sum += value(&img, k + c);
                    worst = worst.max((value(&img, k + c) - a * l).abs());
                    n += 1;
                }
            } else if rho > 1.1 * r {
                assert!((value(&img, k) - l).abs() <= 1.0 / 255.0, "sky at {i},{j}");
            }
        }
    }
    let mean = sum / n as f64;
    assert!(n > 1000, "{n} values");
    assert!((mean - a * l).abs() < 0.004, "mean {mean}, want {}", a * l);
    assert!(worst < 0.06, "a pixel is {worst} off");
    let _ = std::fs::remove_dir_all(&dir);
}

/// The same ball under a sky map that is white above the horizon and
/// black below (a 16×8 PPM: top four rows white): a point of normal n
/// receives π(1 + n_y)/2, so it shows a(1 + n_y)/2. This checks the map's
/// orientation, its importance sampling and the weights against BSDF
/// sampling. Measured (256 paths per pixel), pixels binned by n_y in 8
/// bands: each band's mean within 0.0036 of the formula's (0.0012 to
/// 0.0045 with other seeds).
pub fn a_diffuse_ball_under_half_a_sky_shows_its_tilt() {
    let dir = scratch("path-half-sky");
    let mut ppm = b"P6\n16 8\n255\n".to_vec();
    for j in 0..8 {
        ppm.extend(std::iter::repeat_n(if j < 4 { 255u8 } else { 0 }, 16 * 3));
    }
    std::fs::write(dir.join("half.ppm"), ppm).unwrap();
    let a = 0.7;
    let (w, dist) = (40u32, 4.0f64);
    let half = 1.2;
    let angle = 2.0 * (half / dist).atan().to_degrees();
    let img = render(
        &dir,
        &[],
        &format!(
            "camera_resolution {w} {w}; camera_angle {angle}; camera_from 0 0 {dist}; camera_target 0 0 0\n\
             integrator path; samples 256; trace_depth 4; environment half.ppm\n\
             material 1 1 1 0 {a} 0 1 0 1; sphere 0 0 0 1; render h.ppm"
        ),
    );
    // Pixels binned by n_y: each bin's mean against the formula's.
    let mut bins = [(0.0f64, 0.0f64, 0u32); 8];
    for j in 0..w {
        for i in 0..w {
            // The camera ray through the pixel centre, and where it meets
            // the unit ball.
            let x = ((i as f64 + 0.5) / w as f64 * 2.0 - 1.0) * half / dist;
            let y = (1.0 - (j as f64 + 0.5) / w as f64 * 2.0) * half / dist;
            let d = {
                let l = (x * x + y * y + 1.0f64).sqrt();
                [x / l, y / l, -1.0 / l]
            };
            let b = dist * d[2];
            let disc = b * b - (dist * dist - 1.0);
            if disc < 0.05 {
                continue;
            }
            let ny = (-b - disc.sqrt()) * d[1];
            let bin = &mut bins[(((ny + 1.0) / 2.0 * 8.0) as usize).min(7)];
            bin.0 += value(&img, ((j * w + i) * 3) as usize);
            bin.1 += a * (1.0 + ny) / 2.0;
            bin.2 += 1;
        }
    }
    let mut worst = 0.0f64;
    for (got, want, n) in bins.iter().filter(|b| b.2 >= 20) {
        worst = worst.max((got - want).abs() / *n as f64);
    }
    assert!(bins.iter().filter(|b| b.2 >= 20).count() >= 6, "{bins:?}");
    assert!(worst < 0.006, "a band of n_y is {worst} off: {bins:?}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Inside a closed box whose walls have albedo a and emit E, a path of at
/// most d bounces gathers E(1 + a + … + a^d) = E(1 − a^(d+1))/(1 − a):
/// nothing is lost before the cut, nothing counted twice between light
/// sampling and BSDF sampling, and Russian roulette (after 3 bounces)
/// stays unbiased. Measured at 256 paths per pixel: depths 0, 1, 2, 6
/// give means 0.3020, 0.4501, 0.5250, 0.5948 for 0.3, 0.45, 0.525,
/// 0.5953 (8-bit values), the worst pixel 0.044 off.
pub fn a_glowing_closed_box_sums_its_bounces() {
    let dir = scratch("path-furnace-box");
    let (a, e) = (0.5, 0.3);
    // A cube around the camera, its faces wound to face in.
    let box_ = "proc quad {p q r s} { tri [vertex {*}$p] [vertex {*}$q] [vertex {*}$r]; tri [vertex {*}$p] [vertex {*}$r] [vertex {*}$s] }\n\
                quad {-1 -1 -1} {-1 -1 1} {1 -1 1} {1 -1 -1}\n\
                quad {-1 1 -1} {1 1 -1} {1 1 1} {-1 1 1}\n\
                quad {-1 -1 -1} {1 -1 -1} {1 1 -1} {-1 1 -1}\n\
                quad {-1 -1 1} {-1 1 1} {1 1 1} {1 -1 1}\n\
                quad {-1 -1 -1} {-1 1 -1} {-1 1 1} {-1 -1 1}\n\
                quad {1 -1 -1} {1 -1 1} {1 1 1} {1 1 -1}\n";
    for d in [0u32, 1, 2, 6] {
        let img = render(
            &dir,
            &[],
            &format!(
                "camera_resolution 24 24; camera_angle 100; camera_from 0.1 0.2 0.3; camera_target 1 -0.5 -2\n\
                 integrator path; samples 256; trace_depth {d}\n\
                 material 1 1 1 0 {a} 0 1 0 1; emission {e} {e} {e}\n{box_}render b.ppm"
            ),
        );
        let want = e * (1.0 - f64::powi(a, d as i32 + 1)) / (1.0 - a);
        let n = img.rgb.len();
        let mean = (0..n).map(|i| value(&img, i)).sum::<f64>() / n as f64;
        let worst = (0..n).map(|i| (value(&img, i) - want).abs()).fold(0.0, f64::max);
        assert!((mean - want).abs() < 0.004 * want.max(0.5), "depth {d}: mean {mean}, want {want}");
        assert!(worst < 0.1, "depth {d}: a pixel is {worst} off {want}");
        if d == 0 {
            assert!(worst <= 1.0 / 255.0, "no bounce: the emission alone");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// The Cornell box of `tsd/cornell.tsd` against Mitsuba 3's `path`
/// integrator on the same box (`tests/mitsuba/cornell.py`, 4096 samples
/// per pixel): ours at 256 agrees within the noise of both, overall and
/// region by region: the three walls, the ceiling, the floor and the
/// caustic the glass ball focuses. Measured: mean |difference| 0.0038 on
/// values averaging 0.049 (means equal to 1e-4), walls within 0.8%,
/// ceiling 2.6% (5e-4), floor 1.8%, caustic 3.4% (0.2% to 1.8% with
/// other seeds).
pub fn agrees_with_mitsuba_on_the_cornell_box() {
    let dir = root().join("tests/mitsuba");
    let reference = read_pfm(&dir.join("cornell.pfm"));
    let out = scratch("path-cornell");
    let scene = root().join("tsd/cornell.tsd");
    let ours = render(
        &out,
        &[],
        &format!(
            "source {{{}}}; camera_resolution 128 128; samples 256; exposure -2; render ours.ppm",
            scene.display()
        ),
    );
    let (w, h) = (128usize, 128usize);
    assert_eq!((ours.width as usize, ours.height as usize), (w, h));
    let at = |img: &dyn Fn(usize) -> f64, (x0, y0, x1, y1): (usize, usize, usize, usize)| {
        let mut s = [0.0f64; 3];
        for y in y0..y1 {
            for x in x0..x1 {
                for (c, s) in s.iter_mut().enumerate() {
                    *s += img((y * w + x) * 3 + c);
                }
            }
        }
        s.map(|v| v / ((x1 - x0) * (y1 - y0)) as f64)
    };
    let ours_at = |i: usize| value(&ours, i);
    // Both a quarter as bright (`exposure -2`), so the caustic (up to
    // about 2) is not clipped.
    let ref_at = |i: usize| (reference[i] * 0.25).clamp(0.0, 1.0) as f64;
    let n = w * h * 3;
    let mad = (0..n).map(|i| (ours_at(i) - ref_at(i)).abs()).sum::<f64>() / n as f64;
    let (mo, mr) =
        ((0..n).map(ours_at).sum::<f64>() / n as f64, (0..n).map(ref_at).sum::<f64>() / n as f64);
    assert!(mr > 0.03, "the reference is not dark: {mr}");
    assert!((mo - mr).abs() < 0.01 * mr, "means: ours {mo}, Mitsuba {mr}");
    assert!(mad < 0.03, "mean |difference| {mad}");
    // Regions (x0, y0, x1, y1) of the 128² picture.
    for (name, region) in [
        ("left wall", (4, 40, 14, 80)),
        ("right wall", (114, 40, 124, 80)),
        ("back wall", (50, 45, 78, 75)),
        ("ceiling", (20, 3, 40, 10)),
        ("floor", (55, 100, 70, 112)),
        ("caustic", (CAUSTIC.0, CAUSTIC.1, CAUSTIC.2, CAUSTIC.3)),
    ] {
        let (o, r) = (at(&ours_at, region), at(&ref_at, region));
        for c in 0..3 {
            let tol = 0.04 * r[c] + 0.002;
            assert!((o[c] - r[c]).abs() < tol, "{name}, channel {c}: ours {o:?}, Mitsuba {r:?}");
        }
    }
    let _ = std::fs::remove_dir_all(&out);
}

/// Where the glass ball's caustic lies on the floor in the 128² picture.
const CAUSTIC: (usize, usize, usize, usize) = (89, 120, 101, 124);

/// A colour PFM as values row by row from the top.
fn read_pfm(path: &std::path::Path) -> Vec<f32> {
    let data = std::fs::read(path).unwrap();
    let (w, h, px) = rayshell::image::read_pfm(&data).expect("a colour PFM");
    assert_eq!((w, h), (128, 128));
    px.iter().flat_map(|p| p.to_array()).collect()
}

/// The same bytes for 1 and 2 threads, progressive passes and a crop.
pub fn path_traced_pictures_do_not_depend_on_threads_passes_or_crops() {
    let dir = scratch("path-same");
    let scene = format!(
        "source {{{}}}; camera_resolution 40 30; samples 4; render a.ppm",
        root().join("tsd/cornell.tsd").display()
    );
    let one = render(&dir, &["--threads", "1"], &scene);
    let two = render(&dir, &["--threads", "2"], &scene);
    let prog = render(&dir, &["--progressive"], &scene);
    assert!(one.rgb == two.rgb, "1 vs 2 threads");
    assert!(one.rgb == prog.rgb, "progressive");
    let crop = render(&dir, &["--crop", "7", "5", "29", "21"], &scene);
    for y in 0..16u32 {
        for x in 0..22u32 {
            let (c, f) = (((y * 22 + x) * 3) as usize, (((y + 5) * 40 + x + 7) * 3) as usize);
            assert_eq!(crop.rgb[c..c + 3], one.rgb[f..f + 3], "crop at {x},{y}");
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `--noise-target X` adds samples until each pixel's relative standard
/// error is below X: a tighter target costs more rays and lands nearer the
/// converged picture.
pub fn noise_targets_trade_rays_for_error() {
    let dir = scratch("path-noise");
    let scene = format!(
        "source {{{}}}; camera_resolution 32 32; samples 8; render n.ppm",
        root().join("tsd/cornell.tsd").display()
    );
    let rays = |target: &str| {
        let r = raytrace()
            .args(["-q", "--stats", "--noise-target", target, "-c", &scene])
            .current_dir(&dir)
            .output()
            .unwrap();
        assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
        let err = text(&r.stderr);
        let line = err.lines().find(|l| l.starts_with("samples")).unwrap().to_string();
        line.split_whitespace().nth(1).unwrap().parse::<f64>().unwrap()
    };
    let (loose, tight) = (rays("0.2"), rays("0.05"));
    assert!(loose >= 8.0 && tight > 2.0 * loose, "samples per pixel: {loose} vs {tight}");
    let r = raytrace().args(["--noise-target", "0", "-c", "puts hi"]).output().unwrap();
    assert_eq!(r.status.code(), Some(2), "a target of 0 is refused");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Bad path-tracing commands are located errors.
pub fn bad_path_commands_are_located_errors() {
    for (script, msg) in [
        ("integrator bidir", "bad integrator \"bidir\": must be whitted or path"),
        ("emission 1 -1 1", "emission must not be negative"),
        ("emission 1 1", "wrong # args"),
        ("environment 1 x 1", "expected"),
        ("environment nosuch.hdr", "couldn't read \"nosuch.hdr\""),
        ("environment 0 0 -1", "environment radiance must not be negative"),
    ] {
        let r = raytrace().args(["-c", script]).output().unwrap();
        assert_eq!(r.status.code(), Some(1), "{script}");
        let err = text(&r.stderr);
        assert!(err.starts_with("-c:1: ") && err.contains(msg), "{script}: {err}");
    }
}
