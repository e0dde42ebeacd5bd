//! Each solid's crossings against brute force: marching along the ray in
//! small steps and watching an inside test (an independent formula per
//! shape) change, on random rays from outside and inside, and on rays
//! chosen to graze.

use super::*;

/// A tiny deterministic generator (SplitMix64) for the random rays.
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> f64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 53) as f64
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.next()
    }
    fn dir(&mut self) -> DVec3 {
        loop {
            let v = DVec3::new(self.range(-1.0, 1.0), self.range(-1.0, 1.0), self.range(-1.0, 1.0));
            if v.length_squared() > 0.01 && v.length_squared() <= 1.0 {
                return v;
            }
        }
    }
}

/// Inside tests written from each shape's definition.
fn inside(s: &Solid, p: DVec3) -> bool {
    match *s {
        Solid::Sphere => p.length_squared() < 1.0,
        Solid::Box { min, max } => (0..3).all(|a| p[a] > min[a] as f64 && p[a] < max[a] as f64),
        Solid::Cone { r0, r1, .. } => {
            let r = r0 as f64 + (r1 - r0) as f64 * p.z;
            p.z > 0.0 && p.z < 1.0 && p.x * p.x + p.y * p.y < r * r
        }
        Solid::Torus { major, minor } => {
            let ring = (p.x * p.x + p.z * p.z).sqrt() - major as f64;
            ring * ring + p.y * p.y < (minor * minor) as f64
        }
        Solid::Disk { .. } | Solid::Plane { .. } => unreachable!(),
    }
}

/// Where marching from `t0` to `t1` in `steps` sees the inside test flip.
fn marched(s: &Solid, o: DVec3, d: DVec3, (t0, t1): (f64, f64), steps: usize) -> Vec<f64> {
    let h = (t1 - t0) / steps as f64;
    let mut flips = Vec::new();
    let mut was = inside(s, o + d * t0);
    for i in 1..=steps {
        let t = t0 + h * i as f64;
        let now = inside(s, o + d * t);
        if now != was {
            flips.push(t - h / 2.0);
        }
        was = now;
    }
    flips
}

/// Compares `crossings` with marching on `rays` random rays through the
/// solid's bounds (origins up to 3 sizes away, a share of them inside).
fn agrees_with_marching(s: Solid, rays: usize, seed: u64) {
    let b = s.bounds();
    let (lo, hi) = (b.min.as_dvec3(), b.max.as_dvec3());
    let size = (hi - lo).max_element();
    let mut rng = Rng(seed);
    let steps = 40_000;
    let (mut hits, mut from_inside) = (0, 0);
    for k in 0..rays {
        let target =
            DVec3::new(rng.range(lo.x, hi.x), rng.range(lo.y, hi.y), rng.range(lo.z, hi.z));
        let o = if k % 4 == 0 { target } else { target + rng.dir() * (3.0 * size) };
        // Towards the target (any direction from inside), of any length.
        let d = if k % 4 == 0 { rng.dir() } else { (target - o).normalize() };
        let d = d * rng.range(0.2, 5.0);
        let ray = Ray::new(o.as_vec3(), d.as_vec3());
        let (o, d) = (ray.origin.as_dvec3(), ray.dir.as_dvec3());
        let span = 8.0 * size / d.length();
        let flips = marched(&s, o, d, (-span, span), steps);
        let got = s.crossings(&ray);
        let h = 2.0 * span / steps as f64;
        // A graze (two flips within a step or two) may be seen or not.
        let grazing = flips.windows(2).any(|w| w[1] - w[0] < 3.0 * h)
            || got.as_slice().windows(2).any(|w| ((w[1].t - w[0].t) as f64) < 3.0 * h);
        if grazing {
            continue;
        }
        assert_eq!(
            got.n,
            flips.len(),
            "{s:?}: ray {o} {d}: {:?} vs marched {flips:?}",
            got.as_slice()
        );
        for (c, f) in got.as_slice().iter().zip(&flips) {
            assert!(((c.t as f64) - f).abs() <= h, "{s:?}: ray {o} {d}: {} vs {f}", c.t);
            // The normal points out: inside a little before, outside after
            // (or the reverse), as the normal says.
            let p = (o + d * c.t as f64).as_vec3();
            let n = s.normal(p, c.part).as_dvec3().normalize();
            let eps = 1e-4 * size;
            let (pin, pout) = (o + d * c.t as f64 - n * eps, o + d * c.t as f64 + n * eps);
            assert!(
                inside(&s, pin) && !inside(&s, pout),
                "{s:?}: normal {n} at {p} (part {})",
                c.part
            );
        }
        hits += (got.n > 0) as usize;
        from_inside += (k % 4 == 0 && got.n > 0) as usize;
    }
    assert!(hits > rays / 4 && from_inside > 0, "{s:?}: too few rays hit ({hits})");
}

#[test]
fn spheres_boxes_cones_and_tori_agree_with_marching() {
    let shapes = [
        Solid::Sphere,
        Solid::Box { min: Vec3::new(-1.0, -0.5, 0.0), max: Vec3::new(2.0, 0.5, 0.25) },
        Solid::Cone { r0: 0.5, r1: 0.5, capped: true },
        Solid::Cone { r0: 1.0, r1: 0.25, capped: true },
        Solid::Cone { r0: 0.0, r1: 0.8, capped: true },
        Solid::Torus { major: 1.0, minor: 0.25 },
        Solid::Torus { major: 2.0, minor: 1.5 },
    ];
    for (i, s) in shapes.into_iter().enumerate() {
        agrees_with_marching(s, 300, 17 + i as u64);
    }
}

/// The torus on the rays that trouble quartic solvers: along the axis
/// (through the hole), in the equatorial plane (four crossings), and
/// from far away.
#[test]
fn tori_on_axis_equator_and_far() {
    let t = Solid::Torus { major: 1.0, minor: 0.25 };
    let cross = |o: [f32; 3], d: [f32; 3]| {
        let c = t.crossings(&Ray::new(Vec3::from(o), Vec3::from(d)));
        c.as_slice().iter().map(|c| c.t).collect::<Vec<f32>>()
    };
    // Down the axis: through the hole, nothing.
    assert!(cross([0.0, 5.0, 0.0], [0.0, -1.0, 0.0]).is_empty());
    // Along the equator through the centre: −1.25, −0.75, 0.75, 1.25.
    let c = cross([-5.0, 0.0, 0.0], [1.0, 0.0, 0.0]);
    let want = [3.75, 4.25, 5.75, 6.25];
    assert_eq!(c.len(), 4, "{c:?}");
    for (a, b) in c.iter().zip(want) {
        assert!((a - b).abs() < 1e-5, "{c:?}");
    }
    // From 10⁴ away along the equator, scaled direction: the same points.
    let c = cross([-1.0e4, 0.0, 0.0], [2.0, 0.0, 0.0]);
    assert_eq!(c.len(), 4, "{c:?}");
    for (a, b) in c.iter().zip([1.0e4 - 1.25, 1.0e4 - 0.75, 1.0e4 + 0.75, 1.0e4 + 1.25]) {
        assert!((a * 2.0 - b).abs() < 2e-3, "{c:?}");
    }
    // Parallel to the axis through the tube's middle: in and out once.
    let c = cross([1.0, 3.0, 0.0], [0.0, -1.0, 0.0]);
    assert_eq!(c.len(), 2);
    assert!((c[0] - 2.75).abs() < 1e-5 && (c[1] - 3.25).abs() < 1e-5, "{c:?}");
    // Equatorial rays at many offsets agree with marching.
    let mut rng = Rng(5);
    for _ in 0..200 {
        let z = rng.range(-1.4, 1.4);
        let o = DVec3::new(-4.0, 0.0, z);
        let d = DVec3::new(1.0, 0.0, rng.range(-0.05, 0.05));
        let flips = marched(&t, o, d, (0.0, 8.0), 80_000);
        let got = t.crossings(&Ray::new(o.as_vec3(), d.as_vec3()));
        if flips.windows(2).any(|w| w[1] - w[0] < 3e-4) {
            continue;
        }
        assert_eq!(got.n, flips.len(), "z {z}: {:?} vs {flips:?}", got.as_slice());
    }
}

#[test]
fn disks_and_planes_follow_their_formulas() {
    let disk = Solid::Disk { inner: 0.5 };
    let down = |x: f32, y: f32| Ray::new(Vec3::new(x, y, 3.0), Vec3::new(0.0, 0.0, -2.0));
    assert_eq!(disk.crossings(&down(0.7, 0.0)).as_slice(), [Crossing { t: 1.5, part: 0 }]);
    assert_eq!(disk.crossings(&down(0.3, 0.0)).n, 0, "the hole");
    assert_eq!(disk.crossings(&down(0.8, 0.8)).n, 0, "outside");
    assert_eq!(disk.normal(Vec3::ZERO, 0), Vec3::Z);
    let plane = Solid::Plane { n: Vec3::new(0.0, 1.0, 0.0), d: -1.0 };
    let r = Ray::new(Vec3::new(3.0, 4.0, -2.0), Vec3::new(0.0, -2.0, 0.0));
    assert_eq!(plane.crossings(&r).as_slice(), [Crossing { t: 2.5, part: 0 }]);
    let parallel = Ray::new(Vec3::new(3.0, 4.0, -2.0), Vec3::new(1.0, 0.0, 0.0));
    assert_eq!(plane.crossings(&parallel).n, 0);
}
