use super::*;

fn tri(a: [f32; 3], b: [f32; 3], c: [f32; 3]) -> Triangle {
    Triangle {
        p: [Vec3::from(a), Vec3::from(b), Vec3::from(c)],
        normals: [Triangle::FLAT; 3],
        material: 0,
    }
}

#[test]
fn sphere_hits_front_and_back() {
    let r = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
    assert_eq!(intersect_sphere(&r, Vec3::ZERO, 1.0, 0.0, f32::INFINITY), Some(4.0));
    assert_eq!(intersect_sphere(&r, Vec3::ZERO, 1.0, 4.5, f32::INFINITY), Some(6.0));
    let inside = Ray::new(Vec3::ZERO, Vec3::new(0.0, 2.0, 0.0));
    assert_eq!(intersect_sphere(&inside, Vec3::ZERO, 1.0, 0.0, f32::INFINITY), Some(0.5));
    let miss = Ray::new(Vec3::new(0.0, 1.5, 5.0), Vec3::new(0.0, 0.0, -1.0));
    assert_eq!(intersect_sphere(&miss, Vec3::ZERO, 1.0, 0.0, f32::INFINITY), None);
    // Far away and tiny: no catastrophic cancellation.
    let far = Ray::new(Vec3::new(0.0, 0.0, 1.0e4), Vec3::new(0.0, 0.0, -1.0));
    let t = intersect_sphere(&far, Vec3::ZERO, 0.01, 0.0, f32::INFINITY).unwrap();
    assert!((t - (1.0e4 - 0.01)).abs() < 1e-3, "{t}");
}

#[test]
fn triangle_hits_and_barycentrics() {
    let t = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]);
    let r = Ray::new(Vec3::new(0.25, 0.5, 1.0), Vec3::new(0.0, 0.0, -1.0));
    let (d, uv) = intersect_triangle(&r, &t, 0.0, f32::INFINITY).unwrap();
    assert!((d - 1.0).abs() < 1e-6);
    assert!((uv[0] - 0.25).abs() < 1e-6 && (uv[1] - 0.5).abs() < 1e-6, "{uv:?}");
    // Both sides are hit; t range is respected.
    let back = Ray::new(Vec3::new(0.25, 0.25, -1.0), Vec3::new(0.0, 0.0, 1.0));
    assert!(intersect_triangle(&back, &t, 0.0, f32::INFINITY).is_some());
    assert!(intersect_triangle(&r, &t, 0.0, 0.5).is_none());
    let outside = Ray::new(Vec3::new(0.8, 0.8, 1.0), Vec3::new(0.0, 0.0, -1.0));
    assert!(intersect_triangle(&outside, &t, 0.0, f32::INFINITY).is_none());
}

#[test]
fn shared_edges_are_watertight() {
    // A quad split along its diagonal: rays aimed exactly at the diagonal
    // (and everywhere else) must hit at least one of the two triangles.
    let a = tri([0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [1.0, 1.0, 0.0]);
    let b = tri([0.0, 0.0, 0.0], [1.0, 1.0, 0.0], [0.0, 1.0, 0.0]);
    let mut seed = 12345u32;
    let mut rnd = || {
        seed ^= seed << 13;
        seed ^= seed >> 17;
        seed ^= seed << 5;
        seed as f32 / u32::MAX as f32
    };
    for i in 0..20_000 {
        let s = if i % 2 == 0 { rnd() } else { (i as f32 / 20_000.0).min(0.999) };
        let target = Vec3::new(s, s, 0.0);
        let origin = Vec3::new(rnd() * 4.0 - 2.0, rnd() * 4.0 - 2.0, 1.0 + rnd() * 3.0);
        let r = Ray::new(origin, target - origin);
        let hit = intersect_triangle(&r, &a, 0.0, f32::INFINITY).is_some()
            || intersect_triangle(&r, &b, 0.0, f32::INFINITY).is_some();
        assert!(hit, "ray {i} slipped through the shared edge at {target}");
    }
}

#[test]
fn agrees_with_double_precision_reference() {
    let t = tri([-1.0, -1.0, -3.0], [2.0, -0.5, -4.0], [0.0, 2.0, -3.5]);
    let mut disagreements = 0;
    for i in 0..200 {
        let x = (i % 20) as f32 / 10.0 - 1.0;
        let y = (i / 20) as f32 / 5.0 - 1.0;
        let r = Ray::new(Vec3::ZERO, Vec3::new(x, y, -1.0));
        let got = intersect_triangle(&r, &t, 0.0, f32::INFINITY).map(|(t, _)| t as f64);
        let want = intersect_triangle_f64(&r, &t);
        match (got, want) {
            (Some(g), Some(w)) => assert!((g - w).abs() < 1e-4 * w.abs(), "{g} vs {w}"),
            (None, None) => {}
            // Only rays within rounding of an edge may disagree.
            _ => disagreements += 1,
        }
    }
    assert!(disagreements <= 2, "{disagreements} rays disagree with the reference");
}
