//! Leaf geometry in blocks of four: the BVH's leaves store their triangles
//! (or spheres) four to a block, coordinates in SIMD lanes, so one pass of
//! the watertight (or sphere) test covers four primitives. Each lane does
//! exactly the arithmetic of the scalar test in `shapes`, so the hits are
//! the same to the bit. What shading needs besides positions lives in one `Rec` per
//! lane, at the lane's own index (block * 4 + lane), which is also the
//! primitive's number in `Hit::prim`: a block holds only coordinates.

use glam::{Vec3, Vec4};

use super::shapes::{Cone, RayPre, intersect_sphere};
use super::{Ray, Shape, Triangle};

/// No primitive (in a list of lanes some of which are left out). A lane
/// with no primitive has an `Empty` record and coordinates no test
/// accepts: NaN, or in an object block an inverted box.
pub(super) const NONE: u32 = u32::MAX;

/// Four triangles (or spheres, or cones) of one leaf.
#[derive(Clone, Copy, Debug)]
#[repr(C, align(16))]
pub(super) struct Block {
    /// Triangles: x, y, z of vertex 0, then of vertex 1, then of vertex 2.
    /// Spheres: centre x, y, z and radius; the rest unused.
    /// Cones: base x, y, z; unit axis x, y, z; length (negated when
    /// capped); radius at the base; slope.
    pub v: [Vec4; 9],
}

/// What a lane holds.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Kind {
    Triangle = 0,
    Sphere = 1,
    /// An object, whose index is `Rec::normals[0]`.
    Object = 2,
    /// Nothing: the padding of a leaf's last block.
    Empty = 3,
    Cone = 4,
}

/// One lane's primitive: its vertex normals and material, its kind, and
/// its number in the scene (the order it was added in, whatever the
/// tree). 20 bytes: the kind takes the top three bits of the number.
#[derive(Clone, Copy, Debug, bytemuck::Pod, bytemuck::Zeroable)]
#[repr(C)]
pub(super) struct Rec {
    pub normals: [u32; 3],
    pub material: u32,
    tag: u32,
}

/// The bits of `Rec::tag` below the kind.
const ID_BITS: u32 = 29;
/// The largest number a record keeps: the primitives past it (in a scene
/// of over 2^29) all keep it, so their ties (`Closest`) go to the one the
/// walk meets first, still the same for any thread count.
const ID_MAX: u32 = (1 << ID_BITS) - 1;

impl Default for Rec {
    /// An empty lane.
    fn default() -> Rec {
        Rec::new(Kind::Empty, [0; 3], 0, 0)
    }
}

impl Rec {
    /// The record of lane `lane` of the block of `shapes` (`Block::of`):
    /// an empty lane's past the last.
    pub fn of_lane(shapes: &[(u32, Shape)], lane: usize) -> Rec {
        let Some(&(id, ref s)) = shapes.get(lane) else { return Rec::default() };
        match s {
            Shape::Triangle(t) => Rec::new(Kind::Triangle, t.normals, t.material, id),
            Shape::Sphere { material, .. } => Rec::new(Kind::Sphere, [0; 3], *material, id),
            Shape::Cone(c) => Rec::new(Kind::Cone, [0; 3], c.material, id),
            Shape::Object { index, .. } => Rec::new(Kind::Object, [*index, 0, 0], u32::MAX, id),
        }
    }

    pub fn new(kind: Kind, normals: [u32; 3], material: u32, id: u32) -> Rec {
        Rec { normals, material, tag: (kind as u32) << ID_BITS | id.min(ID_MAX) }
    }

    #[inline(always)]
    pub fn kind(&self) -> Kind {
        match self.tag >> ID_BITS {
            0 => Kind::Triangle,
            1 => Kind::Sphere,
            2 => Kind::Object,
            4 => Kind::Cone,
            _ => Kind::Empty,
        }
    }

    /// The number in the scene (at most `ID_MAX`).
    #[inline(always)]
    pub fn id(&self) -> u32 {
        self.tag & ID_MAX
    }

    pub fn set_id(&mut self, id: u32) {
        *self = Rec::new(self.kind(), self.normals, self.material, id);
    }
}

impl Block {
    const EMPTY: Block = Block { v: [Vec4::NAN; 9] };

    /// Packs `shapes` (all of one kind, each with its number in the scene)
    /// into blocks appended to `blocks`, and their lanes' records to
    /// `recs` (which holds four per block). (The build makes the same
    /// blocks on all threads, with `of` and `Rec::of_lane`.)
    #[cfg(test)]
    pub fn pack(shapes: &[(u32, Shape)], blocks: &mut Vec<Block>, recs: &mut Vec<Rec>) {
        debug_assert_eq!(recs.len(), blocks.len() * 4);
        for chunk in shapes.chunks(4) {
            blocks.push(Block::of(chunk));
            recs.extend((0..4).map(|lane| Rec::of_lane(chunk, lane)));
        }
    }

    /// The block of up to four `shapes` of one kind (`pack`'s step).
    pub fn of(shapes: &[(u32, Shape)]) -> Block {
        let mut b = Block::EMPTY;
        for (lane, (_, s)) in shapes.iter().enumerate().take(4) {
            match s {
                Shape::Triangle(t) => {
                    for (k, p) in t.p.iter().enumerate() {
                        for axis in 0..3 {
                            b.v[3 * k + axis][lane] = p[axis];
                        }
                    }
                }
                Shape::Sphere { center, radius, .. } => {
                    for axis in 0..3 {
                        b.v[axis][lane] = center[axis];
                    }
                    b.v[3][lane] = *radius;
                }
                Shape::Cone(c) => b.set_cone(lane, c),
                Shape::Object { bounds, .. } => {
                    for axis in 0..3 {
                        b.v[axis][lane] = bounds.min[axis];
                        b.v[3 + axis][lane] = bounds.max[axis];
                    }
                }
            }
        }
        // An object block's empty lanes: inverted boxes, which the slab
        // test never enters (a NaN box may pass it).
        if let Some((_, Shape::Object { .. })) = shapes.first() {
            for lane in shapes.len()..4 {
                for axis in 0..3 {
                    b.v[axis][lane] = f32::INFINITY;
                    b.v[3 + axis][lane] = f32::NEG_INFINITY;
                }
            }
        }
        b
    }

    /// The primitive in `lane`, as a shape. (Marked inline: mount-s4's
    /// 256² render 394 -> 385 M instructions.)
    #[inline]
    pub fn shape(&self, lane: usize, rec: &Rec) -> Shape {
        let v = |i: usize| self.v[i][lane];
        match rec.kind() {
            Kind::Object => Shape::Object {
                index: rec.normals[0],
                bounds: crate::geometry::Aabb {
                    min: glam::Vec3A::new(v(0), v(1), v(2)),
                    max: glam::Vec3A::new(v(3), v(4), v(5)),
                },
            },
            Kind::Sphere => Shape::Sphere {
                center: Vec3::new(v(0), v(1), v(2)),
                radius: v(3),
                material: rec.material,
            },
            Kind::Cone => Shape::Cone(Cone {
                base: Vec3::new(v(0), v(1), v(2)),
                axis: Vec3::new(v(3), v(4), v(5)),
                h: v(6).abs(),
                r0: v(7),
                slope: v(8),
                capped: v(6) < 0.0,
                material: rec.material,
            }),
            // (An empty lane: a triangle with NaN corners, never hit.)
            Kind::Triangle | Kind::Empty => Shape::Triangle(Triangle {
                p: [0, 3, 6].map(|k| Vec3::new(v(k), v(k + 1), v(k + 2))),
                normals: rec.normals,
                material: rec.material,
            }),
        }
    }

    /// The watertight test on all four triangles: the lanes hit within
    /// `(t_min, t_max)` as a bit mask, and per lane `t` and the edge
    /// functions (u, v, w) whose sum is the determinant.
    ///
    /// With `EARLY`, a block whose four lines all pass beside their
    /// triangles returns before the division (its `t` then all zero):
    /// closest-hit rays, where it saves waiting for the division (the
    /// 100k dragon's camera rays 2-3 % faster). Shadow rays test without
    /// the branch: it made them 5 % slower.
    #[inline(always)]
    pub fn triangles<const EARLY: bool>(
        &self,
        r: &Pre4,
        t_min: f32,
        t_max: f32,
    ) -> (u32, Vec4, [Vec4; 3]) {
        let [kx, ky, kz] = r.k;
        let v = &self.v;
        let rel = |k: usize| (v[k + kx] - r.o[0], v[k + ky] - r.o[1], v[k + kz] - r.o[2]);
        let (a, b, c) = (rel(0), rel(3), rel(6));
        let (ax, ay) = (a.0 - r.s[0] * a.2, a.1 - r.s[1] * a.2);
        let (bx, by) = (b.0 - r.s[0] * b.2, b.1 - r.s[1] * b.2);
        let (cx, cy) = (c.0 - r.s[0] * c.2, c.1 - r.s[1] * c.2);
        let mut u = cx * by - cy * bx;
        let mut vv = ax * cy - ay * cx;
        let mut w = bx * ay - by * ax;
        let zero = u.cmpeq(Vec4::ZERO) | vv.cmpeq(Vec4::ZERO) | w.cmpeq(Vec4::ZERO);
        if zero.any() {
            // On an edge in single precision: decide it in double precision,
            // lane by lane, as the scalar test does.
            let d = |x1: Vec4, y1: Vec4, x2: Vec4, y2: Vec4, l: usize| {
                (x1[l] as f64 * y2[l] as f64 - y1[l] as f64 * x2[l] as f64) as f32
            };
            for l in (0..4).filter(|&l| zero.bitmask() & (1 << l) != 0) {
                u[l] = d(cx, cy, bx, by, l);
                vv[l] = d(ax, ay, cx, cy, l);
                w[l] = d(bx, by, ax, ay, l);
            }
        }
        let zero = Vec4::ZERO;
        let neg = u.cmplt(zero) | vv.cmplt(zero) | w.cmplt(zero);
        let pos = u.cmpgt(zero) | vv.cmpgt(zero) | w.cmpgt(zero);
        let det = u + vv + w;
        if EARLY && !(!(neg & pos) & det.cmpne(zero)).any() {
            return (0, Vec4::ZERO, [u, vv, w]);
        }
        let (az, bz, cz) = (r.s[2] * a.2, r.s[2] * b.2, r.s[2] * c.2);
        let t = (u * az + vv * bz + w * cz) / det;
        let ok = !(neg & pos)
            & det.cmpne(zero)
            & t.cmpgt(Vec4::splat(t_min))
            & t.cmplt(Vec4::splat(t_max));
        (ok.bitmask(), t, [u, vv, w])
    }

    /// Calls `each(lane, t, uv)` for each lane `triangles::<EARLY>` finds
    /// hit, in lane order (`uv`: the weights of vertices 1 and 2); stops,
    /// and returns true, as soon as `each` returns true.
    #[inline(always)]
    pub fn each_triangle_hit<const EARLY: bool>(
        &self,
        r: &Pre4,
        t_min: f32,
        t_max: f32,
        mut each: impl FnMut(usize, f32, [f32; 2]) -> bool,
    ) -> bool {
        let (mut mask, t, [u, v, w]) = self.triangles::<EARLY>(r, t_min, t_max);
        while mask != 0 {
            let l = mask.trailing_zeros() as usize;
            mask &= mask - 1;
            let det = u[l] + v[l] + w[l];
            if each(l, t[l], [v[l] / det, w[l] / det]) {
                return true;
            }
        }
        false
    }

    /// The sphere test on all four lanes, each lane doing exactly the
    /// arithmetic of `intersect_sphere`: the lanes hit within
    /// `(t_min, t_max)` as a bit mask, and per lane the nearest root there.
    #[inline(always)]
    pub fn spheres(&self, ray: &Ray, t_min: f32, t_max: f32) -> (u32, Vec4) {
        let v = &self.v;
        let (d, o) = (ray.dir, ray.origin);
        let (dx, dy, dz) = (Vec4::splat(d.x), Vec4::splat(d.y), Vec4::splat(d.z));
        let (fx, fy, fz) =
            (Vec4::splat(o.x) - v[0], Vec4::splat(o.y) - v[1], Vec4::splat(o.z) - v[2]);
        let r2 = v[3] * v[3];
        let a = Vec4::splat(d.length_squared());
        let b = -(fx * dx + fy * dy + fz * dz);
        let ba = b / a;
        let (lx, ly, lz) = (fx + dx * ba, fy + dy * ba, fz + dz * ba);
        let disc = a * (r2 - (lx * lx + ly * ly + lz * lz));
        if !disc.cmpge(Vec4::ZERO).any() {
            // No lane's line meets its sphere (most blocks a ray meets;
            // a NaN lane, an empty one, meets nothing either): no roots
            // to take.
            return (0, Vec4::ZERO);
        }
        let c = (fx * fx + fy * fy + fz * fz) - r2;
        let q = b + b.signum() * disc.sqrt();
        let (t0, t1) = (c / q, q / a);
        let order = t0.cmplt(t1);
        let (lo, hi) = (Vec4::select(order, t0, t1), Vec4::select(order, t1, t0));
        let (t_min, t_max) = (Vec4::splat(t_min), Vec4::splat(t_max));
        let in_lo = lo.cmpgt(t_min) & lo.cmplt(t_max);
        let in_hi = hi.cmpgt(t_min) & hi.cmplt(t_max);
        let ok = !disc.cmplt(Vec4::ZERO) & q.cmpne(Vec4::ZERO) & (in_lo | in_hi);
        (ok.bitmask(), Vec4::select(in_lo, lo, hi))
    }

    /// Cone `c` in `lane`.
    fn set_cone(&mut self, lane: usize, c: &Cone) {
        let h = if c.capped { -c.h } else { c.h };
        let v = [c.base.x, c.base.y, c.base.z, c.axis.x, c.axis.y, c.axis.z, h, c.r0, c.slope];
        for (k, x) in v.into_iter().enumerate() {
            self.v[k][lane] = x;
        }
    }

    /// A block of cone `c` alone, in lane 0 (the scalar test).
    pub fn lone_cone(c: &Cone) -> Block {
        let mut b = Block::EMPTY;
        b.set_cone(0, c);
        b
    }

    /// The cone test on all four lanes: the lanes hit within `(t_min,
    /// t_max)` as a bit mask, and per lane the nearest crossing there and
    /// its part (`Cone::SIDE`, `CAP0`, `CAP1`).
    ///
    /// The side is |x⊥|² = (r0 + k·s)² for the axial coordinate s in
    /// [0, h] (k the slope), with x⊥ the part of the ray's point across
    /// the axis: a quadratic a·t² + 2b·t + c in t. With u and p the parts
    /// of the origin (from the base) and the direction across the axis,
    /// and r the radius at the origin's s, its discriminant b² - a·c is
    /// |r·p - k·(d·w)·u|² - |u × p|²: two squares of vectors, computed
    /// as such, so it does not cancel for a ray from far away (for a
    /// cylinder it is the sphere's form of Ray Tracing Gems, chapter 7);
    /// the roots come in the form that keeps both accurate (and give the
    /// one root of a line along the side of a cone). A line along a
    /// cylinder's axis meets no side.
    #[inline(always)]
    pub fn cones(&self, ray: &Ray, t_min: f32, t_max: f32) -> (u32, Vec4, [u32; 4]) {
        let v = &self.v;
        let (d, o) = (ray.dir, ray.origin);
        let (wx, wy, wz) = (v[3], v[4], v[5]);
        let (r0, k) = (v[7], v[8]);
        let dot = |x: Vec4, y: Vec4, z: Vec4| x * wx + y * wy + z * wz;
        let (dx, dy, dz) = (Vec4::splat(d.x), Vec4::splat(d.y), Vec4::splat(d.z));
        let ds = dot(dx, dy, dz);
        let (px, py, pz) = (dx - wx * ds, dy - wy * ds, dz - wz * ds);
        let (qx, qy, qz) =
            (Vec4::splat(o.x) - v[0], Vec4::splat(o.y) - v[1], Vec4::splat(o.z) - v[2]);
        let qs = dot(qx, qy, qz);
        let (ux, uy, uz) = (qx - wx * qs, qy - wy * qs, qz - wz * qs);
        let (rq, kds) = (r0 + k * qs, k * ds);
        let (ex, ey, ez) = (rq * px - kds * ux, rq * py - kds * uy, rq * pz - kds * uz);
        let (cx, cy, cz) = (uy * pz - uz * py, uz * px - ux * pz, ux * py - uy * px);
        let disc = (ex * ex + ey * ey + ez * ez) - (cx * cx + cy * cy + cz * cz);
        let sides = disc.cmpge(Vec4::ZERO);
        let capped = v[6].cmplt(Vec4::ZERO);
        if !(sides | capped).any() {
            // No lane's line meets its side, and none has caps (a NaN
            // lane, an empty one, meets nothing).
            return (0, Vec4::ZERO, [0; 4]);
        }
        let a = px * px + py * py + pz * pz - kds * kds;
        let b = ux * px + uy * py + uz * pz - kds * rq;
        let c = ux * ux + uy * uy + uz * uz - rq * rq;
        let q = -(b + disc.max(Vec4::ZERO).sqrt().copysign(b));
        let (t0, t1) = (q / a, c / q);
        let (t_min, t_max) = (Vec4::splat(t_min), Vec4::splat(t_max));
        let mut best = Vec4::INFINITY;
        let mut part = Vec4::ZERO;
        let mut take = |t: Vec4, ok: glam::BVec4A, which: u32| {
            let closer = ok & t.cmpgt(t_min) & t.cmplt(t_max) & t.cmplt(best);
            best = Vec4::select(closer, t, best);
            part = Vec4::select(closer, Vec4::splat(which as f32), part);
        };
        let h = v[6].abs();
        for t in [t0, t1] {
            let s = qs + ds * t;
            take(t, sides & s.cmpge(Vec4::ZERO) & s.cmple(h), Cone::SIDE);
        }
        if capped.any() {
            // The end disks, where the axial coordinate is 0 and h.
            for (end, which) in [(Vec4::ZERO, Cone::CAP0), (h, Cone::CAP1)] {
                let t = (end - qs) / ds;
                let r = r0 + k * end;
                let (fx, fy, fz) = (ux + px * t, uy + py * t, uz + pz * t);
                let within = (fx * fx + fy * fy + fz * fz).cmple(r * r) & r.cmpgt(Vec4::ZERO);
                take(t, capped & within, which);
            }
        }
        let hit = best.cmplt(Vec4::INFINITY);
        (hit.bitmask(), best, part.to_array().map(|p| p as u32))
    }

    /// The nearest crossing of the cone in `lane` within `(t_min,
    /// t_max)`, and its part.
    #[inline]
    pub fn cone(&self, lane: usize, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, u32)> {
        let (mask, t, part) = self.cones(ray, t_min, t_max);
        (mask & (1 << lane) != 0).then(|| (t[lane], part[lane]))
    }

    /// The nearest hit on the sphere in `lane` within `(t_min, t_max)`.
    #[inline]
    pub fn sphere(&self, lane: usize, ray: &Ray, t_min: f32, t_max: f32) -> Option<f32> {
        let v = |i: usize| self.v[i][lane];
        intersect_sphere(ray, Vec3::new(v(0), v(1), v(2)), v(3), t_min, t_max)
    }
}

/// Per-ray constants of the four-wide triangle test: the watertight
/// test's axis permutation and shear, and the permuted origin, splatted.
pub(super) struct Pre4 {
    pub(super) k: [usize; 3],
    pub(super) o: [Vec4; 3],
    pub(super) s: [Vec4; 3],
}

impl Pre4 {
    pub fn new(ray: &Ray, pre: &RayPre) -> Pre4 {
        let [kx, ky, kz] = pre.k;
        Pre4 {
            k: pre.k,
            o: [kx, ky, kz].map(|k| Vec4::splat(ray.origin[k])),
            s: [pre.s.x, pre.s.y, pre.s.z].map(Vec4::splat),
        }
    }
}
