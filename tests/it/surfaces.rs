//! Surfaces (issue "surfaces"): textures at known points, a bumped plane's
//! shading against its perturbed normal, and Blinn's and Ward's highlights
//! against their closed forms, pixel by pixel.

use crate::util::{raytrace, scratch, text};

fn render(dir: &std::path::Path, script: &str) -> rayshell::image::Rgb8 {
    let r = raytrace().args(["-q", "-c", script]).current_dir(dir).output().unwrap();
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let out = script.rsplit(' ').next().unwrap();
    rayshell::image::read_rgb8(&std::fs::read(dir.join(out)).unwrap()).unwrap()
}

/// A camera straight above the floor (y = 0) at height `h`, looking down
/// with +x to the right and −z up the picture, `w` pixels across `2·half`
/// units: the floor point under pixel (i, j)'s centre.
fn under(i: u32, j: u32, w: u32, half: f64) -> (f64, f64) {
    let x = ((i as f64 + 0.5) / w as f64 * 2.0 - 1.0) * half;
    let z = ((j as f64 + 0.5) / w as f64 * 2.0 - 1.0) * half;
    (x, z)
}

fn top_view(w: u32, h: f64, half: f64) -> String {
    let angle = 2.0 * (half / h).atan().to_degrees();
    format!(
        "camera_resolution {w} {w}; camera_angle {angle}; camera_from 0 {h} 0; camera_target 0 0 0; camera_up 0 0 -1\n"
    )
}

/// `texture checker` on a plane seen from above: each pixel has the colour
/// of its centre's parity, ⌊x/s⌋ + ⌊y/s⌋ + ⌊z/s⌋, and moving the plane
/// with `translate` moves the pattern with it.
pub fn checkers_follow_their_parity_and_their_object() {
    let dir = scratch("surfaces-checker");
    let (w, h, half, s) = (64u32, 100.0, 2.0, 0.37);
    let head = format!("{}ambient_light 1 1 1\n", top_view(w, h, half));
    let flat = "material 1 1 1 1 0 0 1 0 1";
    let img = render(
        &dir,
        &format!("{head}texture checker 1 0 0 0 0 1 {s}; {flat}; plane 0 1 0 -0.1; render a.ppm"),
    );
    let moved = render(
        &dir,
        &format!(
            "{head}texture checker 1 0 0 0 0 1 {s}; {flat}; transform {{translate 0.2 0 0; plane 0 1 0 -0.1}}; render b.ppm"
        ),
    );
    let parity = |x: f64, y: f64, z: f64| {
        ((x / s).floor() + (y / s).floor() + (z / s).floor()) as i64 % 2 == 0
    };
    let mut checked = 0;
    for j in 0..w {
        for i in 0..w {
            let (x, z) = under(i, j, w, half);
            // Skip pixel centres right at a cell's edge.
            let near = |v: f64| ((v / s) - (v / s).round()).abs() * s < 0.01;
            if near(x) || near(z) || near(x - 0.2) {
                continue;
            }
            let at = ((j * w + i) * 3) as usize;
            let red = |img: &rayshell::image::Rgb8| img.rgb[at] > 128;
            // (The camera sees the plane y = -0.1 at floor point (x, z).)
            let (x, z) = (x * (h + 0.1) / h, z * (h + 0.1) / h);
            assert_eq!(red(&img), parity(x, -0.1, z), "pixel {i},{j}");
            assert_eq!(red(&moved), parity(x - 0.2, -0.1, z), "moved: pixel {i},{j}");
            checked += 1;
        }
    }
    assert!(checked > 1500, "{checked}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A bumped plane lit head-on: each pixel is Kd·I·(n′·l) with n′ the
/// normal tilted by the height's gradient, here amount·noise(p/size):
/// n′ ∝ (−∂h/∂x, 1, −∂h/∂z) for the floor, so the pixel is 1/√(1 + |∇h|²).
pub fn bumps_shade_by_the_perturbed_normal() {
    let dir = scratch("surfaces-bump");
    let (w, h, half, amount, size) = (64u32, 100.0, 2.0, 0.3f32, 0.5f32);
    let img = render(
        &dir,
        &format!(
            "{}parallel_light 1 1 1 0 -1 0; bump noise {amount} {size}; material 1 1 1 0 1 0 1 0 1\n\
             plane 0 1 0 0; render a.ppm",
            top_view(w, h, half)
        ),
    );
    let mut worst = 0.0f64;
    let mut tilted = 0;
    for j in 0..w {
        for i in 0..w {
            let (x, z) = under(i, j, w, half);
            let q = glam::Vec3::new(x as f32, 0.0, z as f32);
            let g = rayshell::scene::noise_gradient(q / size) * (amount / size);
            let want = 1.0 / (1.0 + (g.x * g.x + g.z * g.z) as f64).sqrt();
            let got = img.rgb[((j * w + i) * 3) as usize] as f64 / 255.0;
            worst = worst.max((got - want).abs());
            tilted += (want < 0.97) as usize;
        }
    }
    assert!(tilted > 200, "the bumps barely tilt: {tilted}");
    assert!(worst <= 2.0 / 255.0, "a pixel is {worst} off");
    let _ = std::fs::remove_dir_all(&dir);
}

/// Highlights on the floor under a point light, seen from above, against
/// their closed forms (Ks·I/d²·term, Kd = 0): Blinn's (N·H)^n, and Ward's
/// cosθi·exp(−((H·u/ax)² + (H·v/ay)²)/(H·N)²)/(4·ax·ay·√(cosθi·cosθo)),
/// u = +x (the plane's own x axis), v = N × u; isotropic when ax = ay.
pub fn blinn_and_ward_highlights_follow_their_formulas() {
    let dir = scratch("surfaces-highlight");
    let (w, h, half) = (64u32, 100.0f64, 2.0f64);
    let (lx, ly, lz, li) = (0.4f64, 1.5f64, -0.3f64, 0.6f64);
    let cases: [(&str, f64, f64, f64); 3] = [
        ("blinn", 40.0, 0.0, 0.0),
        ("ward 0.25 0.25", 1.0, 0.25, 0.25),
        ("ward 0.1 0.4", 1.0, 0.1, 0.4),
    ];
    for (model, ns, ax, ay) in cases {
        let img = render(
            &dir,
            &format!(
                "{}point_light {li} {li} {li} {lx} {ly} {lz}; highlight {model}\n\
                 material 1 1 1 0 0 0.5 {ns} 0 1; plane 0 1 0 0; render a.ppm",
                top_view(w, h, half)
            ),
        );
        let mut worst = 0.0f64;
        let mut lit = 0;
        for j in 0..w {
            for i in 0..w {
                let (x, z) = under(i, j, w, half);
                let p = [x, 0.0, z];
                let norm = |v: [f64; 3]| {
                    let l = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                    [v[0] / l, v[1] / l, v[2] / l]
                };
                let to_light = [lx - p[0], ly, lz - p[2]];
                let d2 = to_light.iter().map(|c| c * c).sum::<f64>();
                let l = norm(to_light);
                let v = norm([-p[0], h, -p[2]]);
                let hv = norm([l[0] + v[0], l[1] + v[1], l[2] + v[2]]);
                let term = if model == "blinn" {
                    hv[1].powf(ns)
                } else {
                    // u = +x, v = N × u = (0, 0, −1).
                    let (hu, hw) = (hv[0] / ax, -hv[2] / ay);
                    let e = (-(hu * hu + hw * hw) / (hv[1] * hv[1])).exp();
                    l[1] * e / (4.0 * ax * ay * (l[1] * v[1]).sqrt())
                };
                let want = (0.5 * li / d2 * term).min(1.0);
                let got = img.rgb[((j * w + i) * 3) as usize] as f64 / 255.0;
                worst = worst.max((got - want).abs());
                lit += (want > 0.1) as usize;
            }
        }
        assert!(lit > 20, "{model}: the highlight is too small to test ({lit} pixels)");
        assert!(worst <= 2.0 / 255.0, "{model}: a pixel is {worst} off");
    }
    // Ward with ax = ay is round: the same across x as across z.
    let img = render(
        &dir,
        &format!(
            "{}point_light 0.6 0.6 0.6 0 1.5 0; highlight ward 0.3 0.3\n\
             material 1 1 1 0 0 0.5 1 0 1; plane 0 1 0 0; render b.ppm",
            top_view(w, h, half)
        ),
    );
    let px = |i: u32, j: u32| img.rgb[((j * w + i) * 3) as usize] as i32;
    for k in 0..20 {
        let (a, b) = (px(32 + k, 32), px(32, 32 + k));
        assert!((a - b).abs() <= 1, "offset {k}: {a} across x, {b} across z");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Bad surface commands are located errors.
pub fn bad_surfaces_are_located_errors() {
    for (script, msg) in [
        (
            "texture plaid",
            "bad texture \"plaid\": must be checker, noise, marble, wood, granite or none",
        ),
        ("texture checker 1 0 0 0 0 1 0", "texture size must be above 0"),
        ("texture marble 1 2", "wrong # args"),
        ("texture image a.png planar", "couldn't read \"a.png\""),
        (
            "texture image a.png polar",
            "bad mapping \"polar\": must be planar, cylindrical, spherical or uv",
        ),
        ("highlight ward 0 1", "ward roughness must be above 0"),
        ("highlight toon", "bad highlight \"toon\": must be phong, blinn or ward"),
        ("bump noise 1 0", "bump needs a finite amount and a size above 0"),
        ("bump ripple 1", "bad bump \"ripple\": must be noise or none"),
    ] {
        let r = raytrace().args(["-c", script]).output().unwrap();
        assert_eq!(r.status.code(), Some(1), "{script}");
        let err = text(&r.stderr);
        assert!(err.starts_with("-c:1: ") && err.contains(msg), "{script}: {err}");
    }
}

/// An 8×8 test image whose texel (i, j) (j from the top) is
/// (i/7, j/7, 0.5): bilinear filtering of it is linear inside.
fn ramp_ppm(path: &std::path::Path) {
    let mut data = b"P6\n8 8\n255\n".to_vec();
    for j in 0..8u32 {
        for i in 0..8u32 {
            data.extend([(i * 255 / 7) as u8, (j * 255 / 7) as u8, 128]);
        }
    }
    std::fs::write(path, data).unwrap();
}

/// The ramp's colour at image point (u, v): red (8u − 1/2)/7, green
/// (8(1 − v) − 1/2)/7, both inside [0, 1] away from the borders.
fn ramp_at(u: f64, v: f64) -> (f64, f64) {
    ((8.0 * u - 0.5) / 7.0, (8.0 * (1.0 - v) - 0.5) / 7.0)
}

/// Each projection puts the image's known texels at the known points:
/// planar on the plane z = 0 ((u, v) = (x, y)), spherical on a unit ball
/// (u around y from +x towards +z, as POV-Ray, v the latitude), cylindrical on a
/// unit cylinder (v the height). Ambient-lit white, so each pixel is the
/// texture's linear colour.
pub fn image_textures_put_texels_where_their_projection_says() {
    let dir = scratch("surfaces-image");
    ramp_ppm(&dir.join("ramp.ppm"));
    let (w, depth) = (64u32, 100.0f64);
    let view = |cx: f64, cy: f64, half: f64| {
        let angle = 2.0 * (half / depth).atan().to_degrees();
        format!(
            "camera_resolution {w} {w}; camera_angle {angle}; camera_from {cx} {cy} {depth}; camera_target {cx} {cy} 0\n\
             ambient_light 1 1 1; material 1 1 1 1 0 0 1 0 1\n"
        )
    };
    // The point of the picture each pixel centre looks at, on z = 0.
    let aim = |i: u32, j: u32, cx: f64, cy: f64, half: f64| {
        let x = cx + ((i as f64 + 0.5) / w as f64 * 2.0 - 1.0) * half;
        let y = cy + (1.0 - (j as f64 + 0.5) / w as f64 * 2.0) * half;
        (x, y)
    };
    type Case<'a> = (&'a str, (f64, f64, f64), &'a dyn Fn(f64, f64) -> Option<(f64, f64)>);
    let tau = std::f64::consts::TAU;
    let around = |x: f64, z: f64| {
        let a = z.atan2(x) / tau;
        if a < 0.0 { a + 1.0 } else { a }
    };
    let cases: [Case; 4] = [
        ("texture image ramp.ppm planar; plane 0 0 1 0", (0.5, 0.5, 0.5), &|x, y| Some((x, y))),
        // A surface without texture coordinates: `uv` falls back to planar.
        ("texture image ramp.ppm uv; plane 0 0 1 0", (0.5, 0.5, 0.5), &|x, y| Some((x, y))),
        ("texture image ramp.ppm spherical; sphere 0 0 0 1", (0.0, 0.0, 1.1), &|x, y| {
            let z2 = 1.0 - x * x - y * y;
            // Seen from +z: the front of the ball.
            (z2 > 0.05).then(|| {
                let z = z2.sqrt();
                (around(x, z), 0.5 + y.asin() / std::f64::consts::PI)
            })
        }),
        ("texture image ramp.ppm cylindrical; cylinder 0 0 0 0 1 0 1", (0.0, 0.5, 1.1), &|x, y| {
            // The near side of the cylinder, between its caps.
            (x.abs() < 0.95 && (0.02..0.98).contains(&y)).then(|| {
                let z = (1.0 - x * x).sqrt();
                (around(x, z), y)
            })
        }),
    ];
    for (scene, (cx, cy, half), uv) in cases {
        let img = render(&dir, &format!("{}{scene}; render t.ppm", view(cx, cy, half)));
        let (mut checked, mut worst) = (0, 0.0f64);
        for j in 0..w {
            for i in 0..w {
                let (x, y) = aim(i, j, cx, cy, half);
                let Some((u, v)) = uv(x, y) else { continue };
                // Away from the borders, where the image wraps.
                if !(0.08..0.92).contains(&u) || !(0.08..0.92).contains(&v) {
                    continue;
                }
                let (r, g) = ramp_at(u, v);
                let at = ((j * w + i) * 3) as usize;
                let (gr, gg) = (img.rgb[at] as f64 / 255.0, img.rgb[at + 1] as f64 / 255.0);
                worst = worst.max((gr - r).abs()).max((gg - g).abs());
                checked += 1;
            }
        }
        assert!(checked > 300, "{scene}: {checked} pixels checked");
        // The camera is 100 away, not at infinity: its rays meet a curved
        // surface a little off the point straight below (here ≤ 0.01).
        assert!(worst <= 4.0 / 255.0, "{scene}: a pixel is {worst} off");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// `texture image FILE uv` lays the image by a mesh's own `vt`
/// coordinates: a square whose corners carry a turned and shrunk copy of
/// the unit square shows the texel each point's interpolated (u, v)
/// names, placed by `-scale` and `-translate`, split by `-subdivide`, or
/// flat-shaded alike.
pub fn uv_textures_follow_the_mesh_coordinates() {
    let dir = scratch("surfaces-uv");
    ramp_ppm(&dir.join("ramp.ppm"));
    // u = 0.1 + 0.4(y + 1), v = 0.1 + 0.4(1 − x) on the square [−1, 1]².
    let uv_of = |x: f64, y: f64| (0.1 + 0.4 * (y + 1.0), 0.1 + 0.4 * (1.0 - x));
    let mut obj = String::new();
    for (x, y) in [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)] {
        let (u, v) = uv_of(x, y);
        obj += &format!("v {x} {y} 0\nvt {u} {v}\n");
    }
    obj += "f 1/1 2/2 3/3 4/4\n";
    std::fs::write(dir.join("quad.obj"), obj).unwrap();
    let (w, depth, half) = (64u32, 100.0f64, 1.8);
    let angle = 2.0 * (half / depth).atan().to_degrees();
    let view = format!(
        "camera_resolution {w} {w}; camera_angle {angle}; camera_from 3 0 {depth}; camera_target 3 0 0\n\
         ambient_light 1 1 1; material 1 1 1 1 0 0 1 0 1; texture image ramp.ppm uv\n"
    );
    for options in ["", "-flat", "-subdivide 2"] {
        let script =
            format!("{view}mesh quad.obj -scale 2 -translate 3 0 0 {options}; render t.ppm");
        let img = render(&dir, &script);
        let (mut checked, mut worst) = (0, 0.0f64);
        for j in 0..w {
            for i in 0..w {
                let sx = 3.0 + ((i as f64 + 0.5) / w as f64 * 2.0 - 1.0) * half;
                let sy = (1.0 - (j as f64 + 0.5) / w as f64 * 2.0) * half;
                // The mesh's own coordinates: scaled by 2, then moved by 3.
                let (x, y) = ((sx - 3.0) / 2.0, sy / 2.0);
                if x.abs() > 0.95 || y.abs() > 0.95 {
                    continue;
                }
                let (u, v) = uv_of(x, y);
                let (r, g) = ramp_at(u, v);
                let at = ((j * w + i) * 3) as usize;
                let (gr, gg) = (img.rgb[at] as f64 / 255.0, img.rgb[at + 1] as f64 / 255.0);
                worst = worst.max((gr - r).abs()).max((gg - g).abs());
                checked += 1;
            }
        }
        assert!(checked > 2000, "{options}: {checked} pixels checked");
        assert!(worst <= 3.0 / 255.0, "mesh {options}: a pixel is {worst} off");
    }
    // `bump image ramp.ppm A uv` lit head-on: the height A·luminance has
    // the gradient A·(0.2126·(8/7)·∇u − 0.7152·(8/7)·∇v) (red rises with u,
    // green falls with v), with ∇u = (0, 0.2, 0) and ∇v = (−0.2, 0, 0) in
    // the world, so every pixel is 1/√(1 + |∇h|²).
    let a = 5.0f64;
    let g = [a * 0.7152 * 8.0 / 7.0 * 0.2, a * 0.2126 * 8.0 / 7.0 * 0.2];
    let want = 1.0 / (1.0 + g[0] * g[0] + g[1] * g[1]).sqrt();
    let script = view.replace("texture image ramp.ppm uv", &format!("bump image ramp.ppm {a} uv"))
        + "parallel_light 1 1 1 0 0 -1; ambient_light 0 0 0; material 1 1 1 0 1 0 1 0 1\n\
           mesh quad.obj -scale 2 -translate 3 0 0; render t.ppm";
    let img = render(&dir, &script);
    let worst = img.rgb.iter().map(|&c| (c as f64 / 255.0 - want).abs()).fold(0.0, f64::max);
    assert!(worst <= 3.0 / 255.0, "bump uv: {worst} off {want}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A texture tints the light through glass as it tints the glass: a
/// clear textured pane (T = 1, ior 1) above a white floor, lit and seen
/// straight from above, filters each floor point twice by the checker's
/// colour at the same (x, z), once on the shadow ray down and once on the
/// view ray up: the pixel is the colour squared, pane moved by `translate`
/// or not.
pub fn textures_tint_light_through_glass() {
    let dir = scratch("surfaces-glass");
    let (w, h, half, s) = (64u32, 50.0, 2.0, 0.37);
    let (a, b) = ([1.0, 0.5, 0.25], [0.25, 0.5, 1.0]);
    for shift in [0.0, 0.3] {
        let script = format!(
            "{}parallel_light 1 1 1 0 -1 0\n\
             material 1 1 1 0 1 0 1 0 1; plane 0 1 0 0\n\
             material 1 1 1 0 0 0 1 1 1; texture checker {} {} {} {} {} {} {s}\n\
             translate {shift} 0 0; plane 0 1 0 1; render t.ppm",
            top_view(w, h, half),
            a[0],
            a[1],
            a[2],
            b[0],
            b[1],
            b[2]
        );
        let img = render(&dir, &script);
        let mut worst = 0.0f64;
        for j in 0..w {
            for i in 0..w {
                let (x, z) = under(i, j, w, half);
                // Keep off the cells' edges (the camera is 50 away).
                let c = [(x - shift) / s, 1.0 / s, z / s];
                if c.iter().any(|c| (c - c.round()).abs() < 0.05) {
                    continue;
                }
                let parity = c.iter().map(|c| c.floor() as i64).sum::<i64>().rem_euclid(2);
                let want = if parity == 0 { a } else { b };
                let at = ((j * w + i) * 3) as usize;
                for (got, want) in img.rgb[at..at + 3].iter().zip(want) {
                    worst = worst.max((*got as f64 / 255.0 - want * want).abs());
                }
            }
        }
        assert!(worst <= 2.0 / 255.0, "shift {shift}: a pixel is {worst} off");
    }
    let _ = std::fs::remove_dir_all(&dir);
}

/// Far away, a fine image texture is mip-mapped: one sample per pixel
/// comes near the average of 256 (each of which samples its own, sharper,
/// level), where plain point sampling would alias.
pub fn mip_maps_keep_far_textures_close_to_supersampled() {
    let dir = scratch("surfaces-mip");
    // A 256×256 checker of single texels.
    let mut data = b"P6\n256 256\n255\n".to_vec();
    for j in 0..256u32 {
        for i in 0..256u32 {
            let v = if (i + j) % 2 == 0 { 255 } else { 0 };
            data.extend([v, v, v]);
        }
    }
    std::fs::write(dir.join("fine.ppm"), data).unwrap();
    let scene = "camera_resolution 64 48; camera_from 0 1 0; camera_target 0 0.3 -20\n\
                 ambient_light 1 1 1; material 1 1 1 1 0 0 1 0 1\n\
                 texture image fine.ppm planar; transform { rotate -90 0 0; scale 0.5; plane 0 0 1 0 }\n";
    let one = render(&dir, &format!("{scene}render a.ppm"));
    let many = render(&dir, &format!("{scene}samples 256; render b.ppm"));
    let n = one.rgb.len() as f64;
    let err =
        one.rgb.iter().zip(&many.rgb).map(|(a, b)| (*a as f64 - *b as f64).abs()).sum::<f64>()
            / n
            / 255.0;
    assert!(err < 0.04, "mean |one sample − 256 samples| = {err}");
    let _ = std::fs::remove_dir_all(&dir);
}

/// A ball of triangles: an octahedron subdivided `n` times and pushed out
/// onto the unit sphere, as OBJ text.
fn ball_obj(n: u32) -> String {
    let mut p: Vec<[f64; 3]> =
        vec![[1., 0., 0.], [-1., 0., 0.], [0., 1., 0.], [0., -1., 0.], [0., 0., 1.], [0., 0., -1.]];
    let mut t: Vec<[usize; 3]> = vec![
        [0, 2, 4],
        [2, 1, 4],
        [1, 3, 4],
        [3, 0, 4],
        [2, 0, 5],
        [1, 2, 5],
        [3, 1, 5],
        [0, 3, 5],
    ];
    for _ in 0..n {
        let mut mid = std::collections::HashMap::new();
        let mut next = Vec::new();
        for &[a, b, c] in &t {
            let mut m = |i: usize, j: usize| {
                *mid.entry((i.min(j), i.max(j))).or_insert_with(|| {
                    let q = [
                        (p[i][0] + p[j][0]) / 2.0,
                        (p[i][1] + p[j][1]) / 2.0,
                        (p[i][2] + p[j][2]) / 2.0,
                    ];
                    let l = (q[0] * q[0] + q[1] * q[1] + q[2] * q[2]).sqrt();
                    p.push([q[0] / l, q[1] / l, q[2] / l]);
                    p.len() - 1
                })
            };
            let (ab, bc, ca) = (m(a, b), m(b, c), m(c, a));
            next.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
        }
        t = next;
    }
    let mut s: String = p.iter().map(|v| format!("v {} {} {}\n", v[0], v[1], v[2])).collect();
    s.extend(t.iter().map(|f| format!("f {} {} {}\n", f[0] + 1, f[1] + 1, f[2] + 1)));
    s
}

/// `displace` moves a mesh's vertices along their normals: the ball's
/// bounds grow by at most the amount, and its silhouette, round before,
/// is no longer round (its radius, measured along 90 directions, varies).
pub fn displacement_changes_bounds_and_silhouettes() {
    let dir = scratch("surfaces-displace");
    std::fs::write(dir.join("ball.obj"), ball_obj(4)).unwrap();
    let amount = 0.12;
    let bounds = |setup: &str| -> Vec<f64> {
        let r = raytrace()
            .args(["-c", &format!("{setup}; mesh ball.obj; puts [scene_bounds]")])
            .current_dir(&dir)
            .output()
            .unwrap();
        assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
        text(&r.stdout).split_whitespace().map(|w| w.parse().unwrap()).collect()
    };
    let plain = bounds("displace none");
    let moved = bounds(&format!("displace noise {amount} 0.3"));
    let grew: Vec<f64> =
        (0..6).map(|k| if k < 3 { plain[k] - moved[k] } else { moved[k] - plain[k] }).collect();
    assert!(grew.iter().all(|&g| g <= amount + 1e-6), "grew by {grew:?}");
    assert!(grew.iter().any(|&g| g > 0.01), "did not grow: {grew:?}");
    // Silhouettes: radius from the centre along 90 directions.
    let w = 101u32;
    let view = "camera_resolution 101 101; camera_angle 40; camera_from 0 0 6; camera_target 0 0 0\n\
                ambient_light 1 1 1; material 1 1 1 1 0 0 1 0 1";
    let spread = |setup: &str, out: &str| {
        let img =
            render(&dir, &format!("{view}; {setup}; mesh ball.obj -subdivide 2; render {out}"));
        let lit = |x: i64, y: i64| {
            (0..w as i64).contains(&x)
                && (0..w as i64).contains(&y)
                && img.rgb[((y * w as i64 + x) * 3) as usize] > 128
        };
        let radii: Vec<f64> = (0..90)
            .map(|k| {
                let a = k as f64 * std::f64::consts::TAU / 90.0;
                (0..70)
                    .map(|r| r as f64 * 0.5)
                    .take_while(|&r| lit((50.5 + r * a.cos()) as i64, (50.5 + r * a.sin()) as i64))
                    .last()
                    .unwrap_or(0.0)
            })
            .collect();
        let mean = radii.iter().sum::<f64>() / radii.len() as f64;
        (radii.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / radii.len() as f64).sqrt()
    };
    let round = spread("displace none", "a.ppm");
    let bumpy = spread("displace noise 0.4 0.3", "b.ppm");
    assert!(round < 0.8, "the plain ball's radius varies by {round} pixels");
    assert!(
        bumpy > 2.0 * round.max(0.5),
        "the displaced ball's radius varies by {bumpy} pixels only"
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// `bump image` and `displace image` take their height from the image's
/// luminance: on the ramp image, whose luminance rises linearly in x and
/// falls in y, a bumped plane lit head-on has the one tilt the slopes
/// give, 1/√(1 + (a·0.2126·8/7)² + (a·0.7152·8/7)²); a displaced square's
/// top is the amount times the brightest texel's luminance (a vertex of
/// the subdivided square sits on its centre).
pub fn image_bumps_and_displacements_follow_the_image() {
    let dir = scratch("surfaces-image-bump");
    ramp_ppm(&dir.join("ramp.ppm"));
    let (w, depth, half, a) = (64u32, 100.0f64, 0.5f64, 0.5f64);
    let angle = 2.0 * (half / depth).atan().to_degrees();
    let img = render(
        &dir,
        &format!(
            "camera_resolution {w} {w}; camera_angle {angle}; camera_from 0.5 0.5 {depth}; camera_target 0.5 0.5 0\n\
             parallel_light 1 1 1 0 0 -1; material 1 1 1 0 1 0 1 0 1\n\
             bump image ramp.ppm {a} planar; plane 0 0 1 0; render a.ppm"
        ),
    );
    let k = 8.0 / 7.0;
    let want = 1.0 / (1.0 + (a * 0.2126 * k).powi(2) + (a * 0.7152 * k).powi(2)).sqrt();
    let mut checked = 0;
    for j in 8..56u32 {
        for i in 8..56u32 {
            let got = img.rgb[((j * w + i) * 3) as usize] as f64 / 255.0;
            assert!((got - want).abs() <= 2.0 / 255.0, "pixel {i},{j}: {got} vs {want}");
            checked += 1;
        }
    }
    assert!(checked > 2000);
    let square = "v 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nf 1 2 3\nf 1 3 4\n";
    std::fs::write(dir.join("square.obj"), square).unwrap();
    let r = raytrace()
        .args([
            "-c",
            "displace image ramp.ppm 0.2; mesh square.obj -subdivide 4; puts [scene_bounds]",
        ])
        .current_dir(&dir)
        .output()
        .unwrap();
    assert_eq!(r.status.code(), Some(0), "{}", text(&r.stderr));
    let b: Vec<f64> = text(&r.stdout).split_whitespace().map(|w| w.parse().unwrap()).collect();
    // The highest vertex sits on the centre of the brightest texel, the
    // bottom right (7, 7): (1, 1, 128/255).
    let top = 0.2 * (0.2126 + 0.7152 + 0.0722 * 128.0 / 255.0);
    assert!((b[5] - top).abs() < 1e-4, "top {} (want {top})", b[5]);
    assert!(b[2] >= 0.0, "nothing goes below the plane: {}", b[2]);
    let _ = std::fs::remove_dir_all(&dir);
}
