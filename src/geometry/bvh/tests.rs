use super::*;
use crate::geometry::{Cone, Solid, Triangle};

fn lcg(seed: &mut u64) -> f32 {
    *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    (*seed >> 40) as f32 / (1u64 << 24) as f32
}

fn random_scene(n: usize, seed: &mut u64) -> Vec<Shape> {
    (0..n)
        .map(|i| {
            let c = Vec3::new(lcg(seed), lcg(seed), lcg(seed)) * 10.0;
            if i % 5 == 0 {
                Shape::Sphere { center: c, radius: 0.05 + lcg(seed) * 0.3, material: 0 }
            } else if i % 5 == 1 {
                random_cone(c, i % 2 == 0, seed)
            } else {
                let d = |s: &mut u64| Vec3::new(lcg(s), lcg(s), lcg(s)) - 0.5;
                Shape::Triangle(Triangle {
                    p: [c, c + d(seed), c + d(seed)],
                    normals: [Triangle::FLAT; 3],
                    material: 0,
                })
            }
        })
        .collect()
}

/// A cone (or, one time in three, a cylinder) at `c` in a random
/// direction.
fn random_cone(c: Vec3, capped: bool, seed: &mut u64) -> Shape {
    let axis = (Vec3::new(lcg(seed), lcg(seed), lcg(seed)) - 0.5).normalize();
    let (h, r0) = (0.2 + lcg(seed), 0.02 + lcg(seed) * 0.2);
    let r1 = if lcg(seed) < 0.33 { r0 } else { lcg(seed) * 0.3 };
    Shape::Cone(Cone { base: c, axis, h, r0, slope: (r1 - r0) / h, capped, material: 0 })
}

/// The closest hit's distance by testing every shape (with the same rule
/// for ties).
fn brute(shapes: &[Shape], ray: &Ray) -> Option<f32> {
    crate::geometry::intersect_brute(shapes, ray, 0.0, f32::INFINITY).map(|h| h.t)
}

#[test]
fn same_hits_as_brute_force() {
    let mut seed = 7;
    let shapes = random_scene(3000, &mut seed);
    let bvh = Bvh::build(&shapes);
    assert_eq!(bvh.len(), shapes.len());
    for _ in 0..3000 {
        let o = Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 14.0 - 2.0;
        let d = Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) - 0.5;
        let ray = Ray::new(o, d);
        let hit = bvh.intersect(&ray, 0.0, f32::INFINITY).0;
        let got = hit.map(|h| h.t);
        assert_eq!(got, brute(&shapes, &ray), "ray {o} {d}");
        // The hit names the primitive that is there, with its barycentrics.
        if let Some(h) = hit {
            let alone = bvh.shape(h.prim).intersect(&ray, &RayPre::new(d), 0.0, f32::INFINITY);
            assert_eq!(alone, Some((h.t, h.uv)));
        }
        // Any-hit agrees with closest-hit about occlusion.
        let blocked = bvh.transmittance(&ray, 0.0, f32::INFINITY, |_| Vec3::ZERO) == Vec3::ZERO;
        assert_eq!(blocked, got.is_some());
    }
}

#[test]
fn every_primitive_is_reachable() {
    let mut seed = 99;
    let shapes = random_scene(500, &mut seed);
    let bvh = Bvh::build(&shapes);
    for (i, s) in bvh.shapes().iter().enumerate() {
        // A ray from just outside each primitive's centre towards it hits it
        // or something in front of it, never nothing.
        let c = Vec3::from(s.bounds().centroid());
        let target = match s {
            Shape::Object { .. } => unreachable!(),
            Shape::Triangle(t) => (t.p[0] + t.p[1] + t.p[2]) / 3.0,
            Shape::Sphere { center, .. } => *center,
            // A point of the side, halfway up.
            Shape::Cone(k) => {
                let mid = k.base + k.axis * (k.h / 2.0);
                mid + k.axis.any_orthonormal_vector() * (k.r0 + k.slope * k.h / 2.0)
            }
        };
        let o = c + Vec3::new(0.0, 0.0, 20.0);
        let ray = Ray::new(o, target - o);
        let (hit, _) = bvh.intersect(&ray, 0.0, f32::INFINITY);
        let hit = hit.unwrap_or_else(|| panic!("primitive {i} unreachable"));
        assert!(hit.t <= 1.0 + 1e-4);
    }
    let st = bvh.stats();
    assert!(st.leaves >= shapes.len() / MAX_LEAF && st.depth < 64);
    // The blocks hold every primitive exactly once: the same shapes, reordered.
    let key = |s: &Shape| format!("{s:?}");
    let mut want: Vec<String> = shapes.iter().map(key).collect();
    let mut got: Vec<String> = bvh.shapes().iter().map(key).collect();
    want.sort();
    got.sort();
    assert_eq!(got, want);
    // A record per lane: the full ones are the primitives, and empty
    // lanes are NaN.
    assert_eq!(bvh.recs.len(), bvh.blocks.len() * 4);
    let full = bvh.recs.iter().filter(|r| r.kind() != blocks::Kind::Empty).count();
    assert_eq!((full, bvh.len()), (shapes.len(), shapes.len()));
    for (i, r) in bvh.recs.iter().enumerate() {
        let corner = bvh.blocks[i / 4].v[0][i % 4];
        assert_eq!(r.kind() == blocks::Kind::Empty, corner.is_nan(), "lane {i}");
    }
}

#[test]
fn degenerate_inputs() {
    assert!(Bvh::build(&[]).intersect(&Ray::new(Vec3::ZERO, Vec3::X), 0.0, 1.0).0.is_none());
    // Many identical spheres: no infinite recursion, all found.
    let same = vec![Shape::Sphere { center: Vec3::ZERO, radius: 1.0, material: 0 }; 1000];
    let bvh = Bvh::build(&same);
    let r = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
    assert_eq!(bvh.intersect(&r, 0.0, f32::INFINITY).0.map(|h| h.t), Some(4.0));
}

#[test]
fn parallel_build_finds_the_same_hits() {
    // Large enough that the top of the tree is built on two threads.
    let mut seed = 3;
    let shapes = random_scene(3 * PARALLEL_BUILD, &mut seed);
    let bvh = Bvh::build(&shapes);
    assert_eq!(bvh.len(), shapes.len());
    for _ in 0..300 {
        let o = Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 14.0 - 2.0;
        let d = Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) - 0.5;
        let ray = Ray::new(o, d);
        assert_eq!(bvh.intersect(&ray, 0.0, f32::INFINITY).0.map(|h| h.t), brute(&shapes, &ray));
    }
}

/// The parallel build lays its parts out as the one-thread recursion
/// would, node for node and primitive for primitive.
#[test]
fn parallel_build_lays_out_the_sequential_tree() {
    let mut seed = 9;
    let shapes = random_scene(5 * PARALLEL_BUILD, &mut seed);
    let prims: Vec<BuildPrim> = (0..shapes.len())
        .map(|i| BuildPrim::new(shapes[i].bounds(), i as u32, block_kind(&shapes[i])))
        .collect();
    let both = bounds_of(&prims);
    let at = Level { level: 1, mixed: true };
    let (mut a, mut b) = (prims.clone(), prims);
    let parallel = build_par(&mut a, both, 0, at).into_nodes();
    let mut one = Vec::new();
    build_rec(&mut b, both, 0, &mut one, at);
    assert!(one.len() > 1000);
    let bytes = |n: &[Node]| bytemuck::cast_slice::<Node, u8>(n).to_vec();
    assert!(bytes(&parallel) == bytes(&one));
    assert!(a.iter().map(|p| p.index()).eq(b.iter().map(|p| p.index())));
}

/// The root's children's boxes, and theirs, hold every primitive (what
/// passing over a block of camera rays relies on).
#[test]
fn top_boxes_hold_every_primitive() {
    let mut seed = 13;
    let shapes = random_scene(3000, &mut seed);
    for width in [Width::Four, Width::Eight] {
        let bvh = Bvh::build_wide(shapes.len(), |i| shapes[i], Vec::new(), width);
        let top = bvh.top_boxes();
        assert!(top.len() >= 2 && top.iter().any(|(_, inner)| inner.len() >= 2));
        let holds = |o: &Aabb, b: &Aabb| o.min.cmple(b.min).all() && b.max.cmple(o.max).all();
        for s in &shapes {
            let b = s.bounds();
            let held = top.iter().any(|(o, inner)| {
                holds(o, &b) && (inner.is_empty() || inner.iter().any(|i| holds(i, &b)))
            });
            assert!(held, "{width:?}: {s:?}");
        }
    }
}

/// `inv4` is `inv` lane for lane, to the bit: zeros of either sign,
/// values either side of the cut-off, subnormals, large values.
#[test]
fn four_reciprocals_are_the_single_ones() {
    let xs = [
        0.0,
        -0.0,
        1e-30,
        -1e-30,
        1.0001e-30,
        9.999e-31,
        1e-40,
        -1e-40,
        3.0,
        -7.5,
        1e30,
        -3e38,
        0.1,
        f32::MIN_POSITIVE,
    ];
    for q in xs.chunks(4) {
        let mut four = [1.0; 4];
        four[..q.len()].copy_from_slice(q);
        let got = wide::inv4(Vec4::from_array(four)).to_array();
        for (x, g) in four.iter().zip(got) {
            assert_eq!(g.to_bits(), wide::inv(*x).to_bits(), "{x:e}");
        }
    }
}

#[test]
fn blocks_are_watertight_and_match_the_scalar_test() {
    // A 6x6 grid of quads in the plane z = 0, two triangles each, with
    // vertices on integers: rays aimed at its vertices and edge midpoints
    // make the edge functions exactly zero, the blocks' double-precision
    // path. Every ray must hit, and with the scalar test's t and barycentrics.
    let v = |x: i32, y: i32| Vec3::new(x as f32, y as f32, 0.0);
    let tri = |a, b, c| {
        Shape::Triangle(Triangle { p: [a, b, c], normals: [Triangle::FLAT; 3], material: 0 })
    };
    let mut shapes = Vec::new();
    for y in 0..6 {
        for x in 0..6 {
            shapes.push(tri(v(x, y), v(x + 1, y), v(x + 1, y + 1)));
            shapes.push(tri(v(x, y), v(x + 1, y + 1), v(x, y + 1)));
        }
    }
    let bvh = Bvh::build(&shapes);
    let mut seed = 11;
    let mut origins = vec![Vec3::new(3.0, 3.0, 5.0), Vec3::new(-1.5, 2.0, 4.0)];
    origins.extend((0..30).map(|_| {
        Vec3::new(
            lcg(&mut seed) * 8.0 - 1.0,
            lcg(&mut seed) * 8.0 - 1.0,
            lcg(&mut seed) * 6.0 + 0.5,
        )
    }));
    let mut checked = 0;
    for &o in &origins {
        for y2 in 1..12 {
            for x2 in 1..12 {
                let target = Vec3::new(x2 as f32 / 2.0, y2 as f32 / 2.0, 0.0);
                let ray = Ray::new(o, target - o);
                let (hit, _) = bvh.intersect(&ray, 0.0, f32::INFINITY);
                let hit = hit.unwrap_or_else(|| panic!("slipped through at {target} from {o}"));
                let scalar =
                    bvh.shape(hit.prim).intersect(&ray, &RayPre::new(ray.dir), 0.0, f32::INFINITY);
                assert_eq!(scalar, Some((hit.t, hit.uv)));
                assert_eq!(hit.t, brute(&shapes, &ray).unwrap());
                // A shadow ray there is blocked too.
                assert_eq!(bvh.transmittance(&ray, 0.0, f32::INFINITY, |_| Vec3::ZERO), Vec3::ZERO);
                checked += 1;
            }
        }
    }
    assert_eq!(checked, origins.len() * 121);
}

#[test]
fn sphere_blocks_match_the_scalar_test() {
    // Random spheres four to a block (one lane empty in every third block),
    // random rays from outside, inside and on the surface, random windows:
    // the four-lane test must give the scalar test's answers to the bit.
    let mut seed = 5;
    for round in 0..2000 {
        let n = if round % 3 == 0 { 3 } else { 4 };
        let shapes: Vec<Shape> = (0..n)
            .map(|_| Shape::Sphere {
                center: Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 4.0,
                radius: 0.1 + lcg(&mut seed) * 2.0,
                material: 0,
            })
            .collect();
        let mut packed = Vec::new();
        let mut recs = Vec::new();
        let tagged: Vec<(u32, Shape)> = (0..n as u32).zip(shapes.iter().copied()).collect();
        Block::pack(&tagged, &mut packed, &mut recs);
        let o = match round % 4 {
            0 => match shapes[0] {
                Shape::Sphere { center, radius, .. } => center + Vec3::X * radius,
                _ => unreachable!(),
            },
            _ => Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 8.0 - 2.0,
        };
        let d = Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) - 0.5;
        let ray = Ray::new(o, d);
        let (t_min, t_max) = (lcg(&mut seed) * 0.5, 1.0 + lcg(&mut seed) * 20.0);
        let (mask, t) = packed[0].spheres(&ray, t_min, t_max);
        for (l, s) in shapes.iter().enumerate() {
            let scalar = s.intersect(&ray, &RayPre::new(d), t_min, t_max).map(|h| h.0);
            let simd = (mask & 1 << l != 0).then(|| t[l]);
            assert_eq!(simd, scalar, "round {round} lane {l}");
        }
        assert_eq!(mask >> n, 0, "an empty lane was hit");
    }
}

/// The nearest crossing of cone `k` past `t_min` and its part, solved in
/// double precision from the same numbers: the reference for the blocks.
fn cone_f64(k: &Cone, ray: &Ray, t_min: f32) -> Option<(f64, u32)> {
    let (w, q, d) = (k.axis.as_dvec3(), (ray.origin - k.base).as_dvec3(), ray.dir.as_dvec3());
    let (h, r0, slope) = (k.h as f64, k.r0 as f64, k.slope as f64);
    let (qs, ds) = (q.dot(w), d.dot(w));
    let (u, p) = (q - w * qs, d - w * ds);
    let rq = r0 + slope * qs;
    let a = p.dot(p) - (slope * ds).powi(2);
    let b = u.dot(p) - slope * ds * rq;
    let c = u.dot(u) - rq * rq;
    let disc = b * b - a * c;
    let mut found: Vec<(f64, u32)> = Vec::new();
    if disc >= 0.0 && a != 0.0 {
        for t in [(-b - disc.sqrt()) / a, (-b + disc.sqrt()) / a] {
            let s = qs + ds * t;
            if (0.0..=h).contains(&s) {
                found.push((t, Cone::SIDE));
            }
        }
    }
    if k.capped {
        for (end, part) in [(0.0, Cone::CAP0), (h, Cone::CAP1)] {
            let t = (end - qs) / ds;
            let r = r0 + slope * end;
            if (u + p * t).length_squared() <= r * r {
                found.push((t, part));
            }
        }
    }
    found.into_iter().filter(|&(t, _)| t > t_min as f64).min_by(|x, y| x.0.total_cmp(&y.0))
}

/// Cone blocks against a double-precision solution of the same cone: the
/// same crossings, to a few millionths of the cone's size, for rays from
/// outside, from the surface and along the axis, with caps and without;
/// the four lanes give the scalar test's answer to the bit; and the
/// normal is the general solid's (`Solid::Cone` placed by an object).
#[test]
fn cone_blocks_agree_with_double_precision() {
    use crate::geometry::{Kind as ObjKind, Local, Object, Place, intersect_cone};
    let mut seed = 23;
    let (mut hits, mut misses, mut grazing) = (0, 0, 0);
    for round in 0..4000 {
        let lanes: Vec<Shape> = (0..4)
            .map(|l| {
                let c = Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 4.0;
                random_cone(c, (round + l) % 2 == 0, &mut seed)
            })
            .collect();
        let mut packed = Vec::new();
        let mut recs = Vec::new();
        let tagged: Vec<(u32, Shape)> = (0..4).zip(lanes.iter().copied()).collect();
        Block::pack(&tagged, &mut packed, &mut recs);
        let Shape::Cone(k) = lanes[0] else { unreachable!() };
        let u = k.axis.any_orthonormal_vector();
        let v = k.axis.cross(u);
        let target = k.base + k.axis * (lcg(&mut seed) * 1.2 - 0.1) * k.h;
        let target = target + u * (lcg(&mut seed) - 0.5) * 3.0 * k.r0.max(k.r1());
        let (o, t_min) = match round % 4 {
            // From the side surface (a shadow ray's start).
            0 => {
                let s = lcg(&mut seed) * k.h;
                (k.base + k.axis * s + v * (k.r0 + k.slope * s), 1e-4)
            }
            // Along the axis.
            1 => (k.base - k.axis * (1.0 + lcg(&mut seed) * 5.0), 0.0),
            _ => (Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 20.0 - 8.0, 0.0),
        };
        let d = if round % 4 == 1 { k.axis * 2.0 } else { target - o };
        let ray = Ray::new(o, d);
        let want = cone_f64(&k, &ray, t_min);
        let got = intersect_cone(&ray, &k, t_min, f32::INFINITY);
        let (mask, t, part) = packed[0].cones(&ray, t_min, f32::INFINITY);
        assert_eq!((mask & 1 != 0).then(|| (t[0], part[0])), got, "round {round}: lanes");
        let size = (k.h + k.r0.max(k.r1()) + (o - k.base).length()) / d.length();
        match (want, got) {
            (Some((tw, pw)), Some((tg, pg))) => {
                let err = (tw - tg as f64).abs() as f32;
                assert!(err <= 1e-5 * size, "round {round}: t {tw} vs {tg}");
                assert_eq!(pw, pg, "round {round}: part");
                // The general solid's normal there.
                let to_world = glam::Affine3A::from_cols(
                    u.into(),
                    v.into(),
                    (k.axis * k.h).into(),
                    k.base.into(),
                );
                let solid = Object {
                    place: Place { to_local: Some(to_world.inverse()), velocity: Vec3::ZERO },
                    kind: ObjKind::Solid {
                        solid: Solid::Cone { r0: k.r0, r1: k.r1(), capped: k.capped },
                        material: 0,
                    },
                };
                let at = solid.locate(&ray, tg, [0.0; 2], pg);
                let Local::Solid { normal } = at.local else { unreachable!() };
                let m = at.to_local.unwrap();
                let nw = Vec3::from(m.matrix3.transpose() * glam::Vec3A::from(normal)).normalize();
                let n = k.normal(ray.at(tg), pg).normalize();
                assert!(n.dot(nw) > 0.999, "round {round}: normal {n} vs {nw}");
                hits += 1;
            }
            (None, None) => misses += 1,
            // A grazing ray may fall either way.
            (w, g) => {
                grazing += 1;
                assert!(grazing < 20, "round {round}: double {w:?}, block {g:?}");
            }
        }
    }
    assert!(hits > 1000 && misses > 500, "{hits} hits, {misses} misses");
}

#[test]
fn non_finite_rays_find_nothing_and_end() {
    // Issue "hostile input": a NaN direction made every slab test pass,
    // empty slots (child 0) led back to the root, and the walk's stack grew
    // until the allocation failed.
    let mut seed = 11;
    let shapes = random_scene(2000, &mut seed);
    let bvh = Bvh::build(&shapes);
    let o = Vec3::new(5.0, 5.0, 20.0);
    for d in [Vec3::NAN, Vec3::new(0.0, f32::INFINITY, -1.0), Vec3::new(f32::NAN, 0.0, -1.0)] {
        let ray = Ray::new(o, d);
        assert!(bvh.intersect(&ray, 0.0, f32::INFINITY).0.is_none());
        assert_eq!(bvh.transmittance(&ray, 0.0, f32::INFINITY, |_| Vec3::ZERO), Vec3::ONE);
    }
    let ray = Ray::new(Vec3::splat(f32::INFINITY), Vec3::NEG_Z);
    assert!(bvh.intersect(&ray, 0.0, f32::INFINITY).0.is_none());
}

#[test]
fn crossings_cover_the_whole_line() {
    // A closed cube of 12 triangles, and a ray from inside it.
    let v = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    let c = [
        v(-1., -1., -1.),
        v(1., -1., -1.),
        v(1., 1., -1.),
        v(-1., 1., -1.),
        v(-1., -1., 1.),
        v(1., -1., 1.),
        v(1., 1., 1.),
        v(-1., 1., 1.),
    ];
    let quads =
        [[0, 3, 2, 1], [4, 5, 6, 7], [0, 1, 5, 4], [3, 7, 6, 2], [0, 4, 7, 3], [1, 2, 6, 5]];
    let mut shapes = Vec::new();
    for q in quads {
        for (a, b, d) in [(q[0], q[1], q[2]), (q[0], q[2], q[3])] {
            shapes.push(Shape::Triangle(Triangle {
                p: [c[a], c[b], c[d]],
                normals: [Triangle::FLAT; 3],
                material: 0,
            }));
        }
    }
    let bvh = Bvh::build(&shapes);
    for dir in [v(1., 0.3, 0.2), v(-0.2, 1., 0.1), v(0.3, -0.4, -1.)] {
        let mut ts = Vec::new();
        bvh.crossings(&Ray::new(Vec3::ZERO, dir), &mut |t, _| ts.push(t));
        ts.sort_by(f32::total_cmp);
        assert_eq!(ts.len(), 2, "{dir}: {ts:?}");
        assert!(ts[0] < 0.0 && ts[1] > 0.0, "{dir}: {ts:?}");
    }
}

/// Trees of 8-wide nodes (where this CPU has AVX2) and of 4-wide ones
/// find the same surfaces at the same distances, and let the same light
/// through: the width changes the walk, never the answer.
#[test]
fn widths_agree() {
    let mut seed = 17;
    let shapes = random_scene(4000, &mut seed);
    let build = |w| Bvh::build_wide(shapes.len(), |i| shapes[i], Vec::new(), w);
    let (four, eight) = (build(Width::Four), build(Width::Eight));
    assert_eq!(four.stats().width, Width::Four);
    #[cfg(target_arch = "x86_64")]
    if wide::Avx2::new().is_some() {
        assert_eq!(eight.stats().width, Width::Eight);
        assert!(eight.stats().nodes < four.stats().nodes);
    }
    assert_eq!(four.bounds(), eight.bounds());
    let half = |_: ShadowHit| Vec3::splat(0.5);
    for _ in 0..4000 {
        let o = Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 14.0 - 2.0;
        let d = Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) - 0.5;
        let ray = Ray::new(o, d);
        let hit = |b: &Bvh| b.intersect(&ray, 0.0, f32::INFINITY).0.map(|h| (h.t, b.id(h.prim)));
        assert_eq!(hit(&four), hit(&eight), "ray {o} {d}");
        let through = |b: &Bvh| b.transmittance(&ray, 0.0, 20.0, half);
        assert_eq!(through(&four), through(&eight), "ray {o} {d}");
        let crossed = |b: &Bvh| {
            let mut ts = Vec::new();
            b.crossings(&ray, &mut |t, prim| ts.push((t.to_bits(), b.id(prim))));
            ts.sort();
            ts
        };
        assert_eq!(crossed(&four), crossed(&eight), "ray {o} {d}");
    }
}

/// The eight-lane leaf-box test of a packet (`Rays::entering8`) gives
/// the four-lane test's mask to the bit: packets of 2 to 64 rays (odd
/// groups of four included), boxes around, beside, behind and on the
/// origin, segments cut short for some rays.
#[cfg(target_arch = "x86_64")]
#[test]
fn eight_lane_entering_is_four_lane_entering() {
    let Some(v3) = pulp::x86::V3::try_new() else { return };
    let (mut seed, mut some, mut partial) = (5, 0, 0);
    for k in 0..2000 {
        let n = [64, 37, 2, 9, 63, 4][k % 6];
        let o = Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 4.0 - 2.0;
        let dir = Vec3::new(lcg(&mut seed) + 0.1, lcg(&mut seed) + 0.1, lcg(&mut seed) + 0.1);
        let spread = [0.001, 0.05, 0.3][k % 3];
        let rays: Vec<Ray> = (0..n)
            .map(|i| {
                let (x, y) = ((i % 8) as f32 * spread, (i / 8) as f32 * spread);
                Ray::new(o, dir + Vec3::new(x, y, x * 0.5))
            })
            .collect();
        let Some(p) = packet::Rays::new(&rays) else { continue };
        let c = Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 8.0 - 3.0;
        let h = Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * [0.1, 1.0, 4.0][k % 3];
        let b = Aabb { min: (c - h).into(), max: (c + h).into() };
        let mut t_max = [f32::NEG_INFINITY; packet::PACKET];
        for (i, t) in t_max.iter_mut().enumerate().take(n) {
            *t = if i % 5 == 0 { lcg(&mut seed) * 6.0 } else { f32::INFINITY };
        }
        let t_min = [0.0, 0.5][k % 2];
        let four = p.entering(&b, t_min, &t_max);
        assert_eq!(p.entering8(v3, &b, t_min, &t_max), four, "packet {k}");
        some += (four != 0) as u32;
        partial += (four != 0 && four.count_ones() < n as u32) as u32;
    }
    // Boxes entered by all, some and none of a packet's rays.
    assert!(some > 200 && partial > 50, "{some} {partial}");
}

/// The two-block triangle test (`Avx2::triangles2`) gives each block's
/// own four-lane test's answers to the bit, with and without the early
/// return: the lanes hit, their t and their weights (from edge functions
/// whose zeros go to double precision). Triangles of a grid with integer corners
/// (rays at its corners and edges make the edge functions exactly zero)
/// and random ones, blocks with empty lanes, segments cut short.
#[cfg(target_arch = "x86_64")]
#[test]
fn two_blocks_at_once_are_each_block_alone() {
    let Some(avx) = wide::Avx2::new() else { return };
    let v = |x: i32, y: i32| Vec3::new(x as f32, y as f32, 0.0);
    let tri = |p| Shape::Triangle(Triangle { p, normals: [Triangle::FLAT; 3], material: 0 });
    let mut grid = Vec::new();
    for y in 0..2 {
        for x in 0..2 {
            grid.push(tri([v(x, y), v(x + 1, y), v(x + 1, y + 1)]));
            grid.push(tri([v(x, y), v(x + 1, y + 1), v(x, y + 1)]));
        }
    }
    let mut seed = 17;
    let (mut hits, mut edges) = (0, 0);
    for k in 0..3000 {
        let shapes: Vec<(u32, Shape)> = if k % 2 == 0 {
            grid.iter().copied().enumerate().map(|(i, s)| (i as u32, s)).collect()
        } else {
            let n = [8, 7, 5][k % 3];
            let mut p = || Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 2.0;
            (0..n).map(|i| (i, tri([p(), p(), p()]))).collect()
        };
        let (b0, b1) = (Block::of(&shapes[..4]), Block::of(&shapes[4..]));
        let o =
            Vec3::new(lcg(&mut seed) * 4.0 - 1.0, lcg(&mut seed) * 4.0 - 1.0, 2.0 + lcg(&mut seed));
        // At a corner or an edge's middle of the grid, or anywhere.
        let target = if k % 4 < 2 {
            Vec3::new((k % 5) as f32 / 2.0, (k / 5 % 5) as f32 / 2.0, 0.0)
        } else {
            Vec3::new(lcg(&mut seed) * 2.0, lcg(&mut seed) * 2.0, lcg(&mut seed))
        };
        let ray = Ray::new(o, target - o);
        let pre = Pre4::new(&ray, &RayPre::new(ray.dir));
        let (t_min, t_max) = ([0.0, 1.5][k % 2], [f32::INFINITY, 2.5, 3.0][k % 3]);
        for early in [false, true] {
            let h = if early {
                avx.triangles2::<true>([&b0, &b1], &pre, t_min, t_max)
            } else {
                avx.triangles2::<false>([&b0, &b1], &pre, t_min, t_max)
            };
            let mut mask = 0;
            for (j, b) in [&b0, &b1].into_iter().enumerate() {
                let (m, t, [u, vv, w]) = if early {
                    b.triangles::<true>(&pre, t_min, t_max)
                } else {
                    b.triangles::<false>(&pre, t_min, t_max)
                };
                mask |= m << (4 * j);
                for l in 0..4 {
                    let i = 4 * j + l;
                    edges += (u[l] == 0.0 || vv[l] == 0.0 || w[l] == 0.0) as u32;
                    if m & (1 << l) != 0 {
                        // `each_triangle_hit`'s weights.
                        let det = u[l] + vv[l] + w[l];
                        let want = [t[l], vv[l] / det, w[l] / det].map(f32::to_bits);
                        let got = [h.t[i], h.u[i], h.v[i]].map(f32::to_bits);
                        assert_eq!(got, want, "{k} lane {i}");
                    }
                }
            }
            assert_eq!(h.mask, mask, "{k} early {early}");
            hits += mask.count_ones();
        }
    }
    assert!(hits > 1000 && edges > 100, "{hits} {edges}");
}

/// The two-block sphere test (`Avx2::spheres2`) gives each block's own
/// four-lane test's lanes and roots to the bit: random spheres, blocks
/// with empty lanes, rays from outside, inside and on a surface, and
/// random windows.
#[cfg(target_arch = "x86_64")]
#[test]
fn two_sphere_blocks_at_once_are_each_block_alone() {
    let Some(avx) = wide::Avx2::new() else { return };
    let mut seed = 23;
    let mut hits = 0;
    for round in 0..3000 {
        let n = [8, 7, 5][round % 3];
        let shapes: Vec<(u32, Shape)> = (0..n)
            .map(|i| {
                let center = Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 4.0;
                (i, Shape::Sphere { center, radius: 0.1 + lcg(&mut seed) * 2.0, material: 0 })
            })
            .collect();
        let (b0, b1) = (Block::of(&shapes[..4]), Block::of(&shapes[4..]));
        let o = match (round % 4, shapes[round % 8 % n as usize].1) {
            (0, Shape::Sphere { center, radius, .. }) => center + Vec3::X * radius,
            _ => Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 8.0 - 2.0,
        };
        let d = Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) - 0.5;
        let ray = Ray::new(o, d);
        let (t_min, t_max) = (lcg(&mut seed) * 0.5, 1.0 + lcg(&mut seed) * 20.0);
        let (mask, t) = avx.spheres2([&b0, &b1], &ray, t_min, t_max);
        for (j, b) in [&b0, &b1].into_iter().enumerate() {
            let (m, tb) = b.spheres(&ray, t_min, t_max);
            assert_eq!(mask >> (4 * j) & 15, m, "round {round} block {j}");
            for l in (0..4).filter(|l| m & 1 << l != 0) {
                assert_eq!(t[4 * j + l].to_bits(), tb[l].to_bits(), "round {round} lane {l}");
            }
        }
        hits += mask.count_ones();
    }
    assert!(hits > 1000, "{hits}");
}

/// The same for shadow packets (`Segments::entering8`): segments from
/// points spread on a surface toward a light, some of them no longer
/// live.
#[cfg(target_arch = "x86_64")]
#[test]
fn eight_lane_segments_entering_is_four_lane() {
    let Some(v3) = pulp::x86::V3::try_new() else { return };
    let (mut seed, mut some) = (11, 0);
    for k in 0..2000 {
        let n = [64, 37, 2, 9, 63, 4][k % 6];
        let light = Vec3::new(20.0, 30.0, 25.0);
        let spread = [0.01, 0.1, 1.0][k % 3];
        let base = Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 4.0;
        let (rays, ends): (Vec<Ray>, Vec<f32>) = (0..n)
            .map(|i| {
                let o = base + Vec3::new((i % 8) as f32, 0.0, (i / 8) as f32) * spread;
                let d = light - o;
                (Ray::new(o, d.normalize()), d.length())
            })
            .unzip();
        let Some(p) = shadow::Segments::new(&rays, &ends) else { continue };
        let mut t_max = [f32::NEG_INFINITY; packet::PACKET];
        t_max[..n].copy_from_slice(&ends);
        let live = (0..n).fold(0u64, |m, i| m | ((lcg(&mut seed) < 0.8) as u64) << i);
        let c = base + Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 12.0;
        let h = Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * [0.2, 1.0, 5.0][k % 3];
        let b = Aabb { min: (c - h).into(), max: (c + h).into() };
        let four = p.entering(&b, &t_max, live);
        assert_eq!(p.entering8(v3, &b, &t_max, live), four, "packet {k}");
        some += (four != 0) as u32;
    }
    assert!(some > 100, "{some}");
}

/// A packet finds each of its rays' hits as the ray alone does, to the
/// bit (distance, primitive, barycentrics), in trees of either width:
/// packets narrow and wide, whole and partial, some with directions of
/// mixed signs (which go one by one).
#[test]
fn packets_agree_with_single_rays() {
    let mut seed = 23;
    let mut shapes = random_scene(4000, &mut seed);
    // Coplanar twins: ties the packet must settle as single rays do.
    for i in (0..4000).step_by(7) {
        if let Shape::Triangle(t) = shapes[i] {
            shapes.push(Shape::Triangle(Triangle { p: [t.p[1], t.p[2], t.p[0]], ..t }));
        }
    }
    for width in [Width::Four, Width::Eight] {
        let bvh = Bvh::build_wide(shapes.len(), |i| shapes[i], Vec::new(), width);
        let mut packets = 0;
        for k in 0..300 {
            let o = Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed)) * 14.0 - 2.0;
            let centre = Vec3::new(5.0, 5.0, 5.0) + (Vec3::splat(lcg(&mut seed)) - 0.5) * 6.0;
            let spread = [0.002, 0.02, 0.2, 1.0][k % 4];
            let n = [64, 64, 37, 2][k % 4];
            let (du, dv) = (Vec3::new(spread, 0.0, 0.0), Vec3::new(0.0, spread, spread * 0.3));
            let rays: Vec<Ray> = (0..n)
                .map(|i| {
                    let (x, y) = ((i % 8) as f32 - 3.5, (i / 8) as f32 - 3.5);
                    Ray::new(o, (centre - o).normalize() + du * x + dv * y)
                })
                .collect();
            packets += Rays::new(&rays).is_some() as u32;
            let mut out = vec![(None, 0); n];
            bvh.intersect_packet(&rays, 0.0, f32::INFINITY, &mut out);
            for (r, (hit, _)) in rays.iter().zip(&out) {
                let alone = bvh.intersect(r, 0.0, f32::INFINITY).0;
                let key =
                    |h: &Option<Hit>| h.map(|h| (h.t.to_bits(), h.prim, h.uv.map(f32::to_bits)));
                assert_eq!(key(hit), key(&alone), "{width:?} packet {k}: ray {r:?}");
            }
        }
        // Most packets went together.
        assert!(packets > 200, "{packets}");
    }
}

/// A shadow ray that first tests the block that blocked an earlier one
/// finds what the plain walk finds, to the bit: with opaque and partly
/// transparent surfaces, hints from rays anywhere, and a hint from
/// another tree (which names none of this one's blocks).
#[test]
fn occluder_hints_change_no_shadow() {
    let mut seed = 17;
    let shapes = random_scene(2000, &mut seed);
    let bvh = Bvh::build(&shapes);
    let other = Bvh::build(&random_scene(300, &mut seed));
    // Some surfaces stop light, others let half through (by where they
    // are hit, so the same surface answers the same each time).
    let half = |h: ShadowHit| {
        if ((h.t * 64.0) as u32).is_multiple_of(3) { Vec3::ZERO } else { Vec3::splat(0.5) }
    };
    let bits = |v: Vec3| v.to_array().map(f32::to_bits);
    let (mut last, mut foreign, mut reused, mut early) = (Occluder::NONE, Occluder::NONE, 0, 0);
    // Shadow segments as a renderer makes them: runs of 20 from points
    // close together toward one light.
    let (mut base, mut light) = (Vec3::ZERO, Vec3::ZERO);
    for i in 0..4000 {
        let mut p = || Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed));
        if i % 20 == 0 {
            (base, light) = (p() * 10.0, p() * 14.0 - 2.0);
        }
        let o = base + (p() - 0.5) * 0.2;
        let ray = Ray::new(o, light - o);
        let t_max = 1.0;
        let before = last;
        for pass in [&(|_: ShadowHit| Vec3::ZERO) as &dyn Fn(ShadowHit) -> Vec3, &half] {
            let plain = bvh.transmittance(&ray, 0.0, t_max, pass);
            // Whether the hinted block alone settles it (the fast path).
            if let Some((kind, b)) = before.block(&bvh) {
                let mut opaque = |h| pass(h) == Vec3::ZERO;
                early += bvh.block_hits(b, kind, &ray, (0.0, t_max), &mut None, &mut opaque) as u32;
            }
            let mut hint = before;
            let hinted = bvh.transmittance_hinted(&ray, 0.0, t_max, &mut hint, pass);
            assert_eq!(bits(hinted), bits(plain), "ray {i}");
            if hint != before {
                last = hint;
            }
            let mut f = foreign;
            assert_eq!(bits(bvh.transmittance_hinted(&ray, 0.0, t_max, &mut f, pass)), bits(plain));
        }
        reused += (before.kind.is_some()) as u32;
        // Now and then, a hint from the other tree.
        if i % 7 == 0 {
            let mut f = foreign;
            other.transmittance_hinted(&ray, 0.0, t_max, &mut f, |_| Vec3::ZERO);
            if f.kind.is_some() {
                foreign = f;
            }
        }
    }
    assert!(reused > 1000, "hints were rarely there to use: {reused}");
    assert!(early > 50, "the hinted block alone blocked only {early} rays");
    assert!(foreign.kind.is_some() && foreign.block(&bvh).is_none());
}

/// Shadow rays in packets learn what each ray's own walk finds, to the
/// bit: blocked where `transmittance` gives zero, clear where it gives one,
/// unknown only where a surface that lets light through is crossed; in
/// trees of either width, with packets narrow and wide, whole and
/// partial, toward lights near and far, some with directions of mixed
/// signs or without an end (which go one by one), and hints kept from
/// packet to packet.
#[test]
fn shadow_packets_agree_with_transmittance() {
    let mut seed = 29;
    let mut shapes = random_scene(4000, &mut seed);
    // Material 2 lets half the light through; 0 and 1 stop it.
    for (i, s) in shapes.iter_mut().enumerate() {
        let m = (i % 3) as u32;
        match s {
            Shape::Triangle(t) => t.material = m,
            Shape::Sphere { material, .. } => *material = m,
            Shape::Cone(c) => c.material = m,
            _ => {}
        }
    }
    let opaque = |m: u32| m != 2;
    let pass = |h: ShadowHit| if opaque(h.material) { Vec3::ZERO } else { Vec3::splat(0.5) };
    for width in [Width::Four, Width::Eight] {
        let bvh = Bvh::build_wide(shapes.len(), |i| shapes[i], Vec::new(), width);
        let (mut packets, mut seen) = (0, [0u32; 3]);
        let mut last = Occluder::NONE;
        for k in 0..400 {
            let mut p = || Vec3::new(lcg(&mut seed), lcg(&mut seed), lcg(&mut seed));
            let base = p() * 10.0;
            let light = [p() * 14.0 - 2.0, p() * 200.0 - 100.0, base + p() * 0.5][k % 3];
            let spread = [0.01, 0.1, 1.0, 4.0][k % 4];
            let n = [64, 64, 37, 5][k % 4];
            let rays: Vec<Ray> = (0..n)
                .map(|_| {
                    let o = base + (p() - 0.5) * spread;
                    Ray::new(o, (light - o).normalize())
                })
                .collect();
            let far = k % 10 == 9;
            let t_max: Vec<f32> = rays
                .iter()
                .map(|r| if far { f32::INFINITY } else { (light - r.origin).length() * 0.999 })
                .collect();
            packets += Segments::new(&rays, &t_max).is_some() as u32;
            let mut out = vec![Shadow::Unknown; n];
            bvh.shadows(&rays, &t_max, &mut last, &opaque, &mut out, true);
            for ((r, &t), &s) in rays.iter().zip(&t_max).zip(&out) {
                let alone = bvh.transmittance(r, 0.0, t, pass);
                let bits = alone.to_array().map(f32::to_bits);
                match s {
                    Shadow::Blocked => assert_eq!(bits, [0; 3], "{width:?} packet {k}: {r:?}"),
                    Shadow::Clear => assert_eq!(bits, [1f32.to_bits(); 3], "{width:?} {k}: {r:?}"),
                    Shadow::Unknown => assert_ne!(alone, Vec3::ONE, "{width:?} {k}: {r:?}"),
                }
                seen[s as usize] += 1;
            }
        }
        // Most packets went together, and every answer came up.
        assert!(packets > 200, "{packets}");
        assert!(seen.iter().all(|&c| c > 500), "{seen:?}");
    }
}

/// The wide nodes made from the binary tree have the least sum of areas of
/// every way of covering it (checked against all the covers, listed one by
/// one), and never more than opening the largest child first, the rule the
/// plan replaced.
#[test]
fn wide_nodes_have_the_least_area() {
    fn area(bin: &[Node], i: usize) -> f32 {
        bin[i].bounds().surface_area()
    }
    fn children(bin: &[Node], i: usize) -> (usize, usize) {
        (i + 1, bin[i].offset as usize)
    }
    fn prims(bin: &[Node], i: usize) -> u32 {
        let (l, r) = children(bin, i);
        if bin[i].count > 0 { bin[i].count } else { prims(bin, l) + prims(bin, r) }
    }
    /// One past the last node of subtree `i` (laid out depth-first).
    fn end(bin: &[Node], i: usize) -> usize {
        if bin[i].count > 0 { i + 1 } else { end(bin, children(bin, i).1) }
    }
    /// The area sum of the wide nodes that `plan` makes of subtree `i`.
    fn emitted(bin: &[Node], plan: &Plan, i: usize, width: usize) -> f32 {
        let kids = plan.kids(bin, i, width);
        assert!((2..=width).contains(&kids.len()));
        // Descendants of `i` that hold all of its primitives: a cover.
        assert!(kids.iter().all(|&k| k > i && k < end(bin, i)));
        assert_eq!(kids.iter().map(|&k| prims(bin, k)).sum::<u32>(), prims(bin, i));
        let below = kids.iter().filter(|&&k| bin[k].count == 0);
        area(bin, i) + below.map(|&k| emitted(bin, plan, k, width)).sum::<f32>()
    }
    /// Every cover of subtree `i` by at most `k` slots.
    fn covers(bin: &[Node], i: usize, k: usize) -> Vec<Vec<usize>> {
        let mut all = vec![vec![i]];
        if bin[i].count == 0 && k >= 2 {
            let (l, r) = children(bin, i);
            for a in covers(bin, l, k - 1) {
                for b in covers(bin, r, k - a.len()) {
                    all.push([a.clone(), b].concat());
                }
            }
        }
        all
    }
    /// The least area sum of subtree `i` as a wide node, by listing covers.
    fn least(bin: &[Node], i: usize, width: usize, memo: &mut Vec<Option<f32>>) -> f32 {
        if let Some(c) = memo[i] {
            return c;
        }
        let (l, r) = children(bin, i);
        let mut best = f32::INFINITY;
        for a in covers(bin, l, width - 1) {
            for b in covers(bin, r, width - a.len()) {
                let mut c = 0.0;
                for &s in a.iter().chain(&b).filter(|&&s| bin[s].count == 0) {
                    c += least(bin, s, width, memo);
                }
                best = best.min(c);
            }
        }
        memo[i] = Some(area(bin, i) + best);
        memo[i].unwrap()
    }
    /// The area sum when each wide node opens its largest child first.
    fn greedy(bin: &[Node], i: usize, width: usize) -> f32 {
        let (l, r) = children(bin, i);
        let mut kids = vec![l, r];
        while kids.len() < width {
            let open = (0..kids.len())
                .filter(|&j| bin[kids[j]].count == 0)
                .max_by(|&a, &b| area(bin, kids[a]).total_cmp(&area(bin, kids[b])));
            let Some(j) = open else { break };
            let (l, r) = children(bin, kids[j]);
            kids[j] = l;
            kids.push(r);
        }
        let below = kids.iter().filter(|&&k| bin[k].count == 0);
        area(bin, i) + below.map(|&k| greedy(bin, k, width)).sum::<f32>()
    }

    let mut seed = 41;
    let shapes = random_scene(2000, &mut seed);
    let mut prims: Vec<BuildPrim> = shapes
        .iter()
        .enumerate()
        .map(|(i, s)| BuildPrim::new(s.bounds(), i as u32, block_kind(s)))
        .collect();
    let both = bounds_of(&prims);
    let bin = build_par(&mut prims, both, 0, Level { level: 1, mixed: true }).into_nodes();
    assert_eq!(bin[0].count, 0);
    let near = |a: f32, b: f32| (a - b).abs() <= 1e-5 * a.max(b);
    for width in [4, 8] {
        let plan = Plan::new(&bin, width);
        let made = emitted(&bin, &plan, 0, width);
        assert!(near(made, plan.cost[0][0]), "{made} {}", plan.cost[0][0]);
        let listed = least(&bin, 0, width, &mut vec![None; bin.len()]);
        assert!(near(made, listed), "width {width}: {made} made, {listed} least");
        let old = greedy(&bin, 0, width);
        assert!(made < old, "width {width}: {made} made, {old} by the largest child");
    }
}

/// A record keeps its kind and number side by side in 20 bytes; numbers
/// past 2^29 - 1 are kept as that, and renumbering keeps the kind.
#[test]
fn records_keep_kind_and_number() {
    use blocks::Kind;
    assert_eq!(std::mem::size_of::<Rec>(), 20);
    for kind in [Kind::Triangle, Kind::Sphere, Kind::Object, Kind::Empty, Kind::Cone] {
        for id in [0, 1, 12345, (1 << 29) - 1] {
            let mut r = Rec::new(kind, [7, 8, 9], 3, id);
            assert_eq!((r.kind(), r.id(), r.normals, r.material), (kind, id, [7, 8, 9], 3));
            r.set_id(id / 2);
            assert_eq!((r.kind(), r.id()), (kind, id / 2));
        }
        assert_eq!(Rec::new(kind, [0; 3], 0, u32::MAX).id(), (1 << 29) - 1);
        assert_eq!(Rec::new(kind, [0; 3], 0, u32::MAX).kind(), kind);
    }
    assert_eq!(Rec::default().kind(), Kind::Empty);
}

/// A ground quad under a small tree trunk (a cone and a sphere: the SPD
/// tree's ground and trunk, whose centroids bin together): the ground's
/// triangles get a leaf of their own, as flat as the ground, so a ray
/// leaving the ground far from the trunk enters no leaf. In one leaf with
/// the trunk, its box as wide as the ground and as high as the trunk, the
/// ray tested three blocks.
#[test]
fn a_ground_quad_is_not_kept_with_the_trunk() {
    let tri =
        |p: [Vec3; 3]| Shape::Triangle(Triangle { p, normals: [Triangle::FLAT; 3], material: 0 });
    let (a, b, c, d) = (
        Vec3::new(-50.0, -50.0, 0.0),
        Vec3::new(50.0, -50.0, 0.0),
        Vec3::new(50.0, 50.0, 0.0),
        Vec3::new(-50.0, 50.0, 0.0),
    );
    let trunk = Shape::Cone(Cone {
        base: Vec3::ZERO,
        axis: Vec3::Z,
        h: 1.0,
        r0: 0.2,
        slope: -0.1,
        capped: false,
        material: 0,
    });
    let top = Shape::Sphere { center: Vec3::new(0.0, 0.0, 1.0), radius: 0.1, material: 0 };
    let tree = Bvh::build(&[tri([a, b, c]), tri([a, c, d]), trunk, top]);
    // Up from just above the ground, far from the trunk.
    let ray = Ray::new(Vec3::new(30.0, -20.0, 1e-3), Vec3::new(0.1, 0.2, 1.0).normalize());
    let (hit, steps) = tree.intersect(&ray, 0.0, f32::INFINITY);
    assert!(hit.is_none());
    assert_eq!(steps, 1, "only the root: no leaf entered");
    // The ground is still there from above, the trunk from the side.
    let down = Ray::new(Vec3::new(30.0, -20.0, 5.0), Vec3::NEG_Z);
    assert_eq!(tree.intersect(&down, 0.0, f32::INFINITY).0.map(|h| h.t), Some(5.0));
    let side = Ray::new(Vec3::new(5.0, 0.0, 0.5), Vec3::NEG_X);
    assert!(tree.intersect(&side, 0.0, f32::INFINITY).0.is_some());
}
