//! Spheres, triangles and cones: intersection tests and the `Shape` the BVH
//! holds. Triangles use the watertight test of Woop, Benthin and Wald
//! (2013), so a ray never slips through the shared edge of two triangles of
//! a mesh.

use glam::{DVec3, Vec3};

use super::{Aabb, Ray};

/// A triangle with its vertices inline (fast to test) and the indices of
/// its vertex normals in the scene's normal pool (`u32::MAX`: flat).
#[derive(Clone, Copy, Debug)]
pub struct Triangle {
    pub p: [Vec3; 3],
    pub normals: [u32; 3],
    pub material: u32,
}

impl Triangle {
    pub const FLAT: u32 = u32::MAX;

    /// The counter-clockwise geometric normal (not normalized).
    pub fn cross(&self) -> Vec3 {
        (self.p[1] - self.p[0]).cross(self.p[2] - self.p[0])
    }

    /// Whether it has an area (and so a normal) in single precision. One
    /// without could still be "hit" through rounding, with no normal to
    /// shade by, so the BVH leaves such triangles out.
    pub fn has_area(&self) -> bool {
        let n = self.cross();
        n.length_squared() > 0.0 && n.is_finite()
    }
}

/// A cone or cylinder: from `base` (radius `r0`) along the unit vector
/// `axis` for `h`, its radius growing by `slope` per unit of length (0: a
/// cylinder), open or `capped` at both ends.
/// Tested in the BVH's leaves four at once like spheres (the general
/// solid, `Solid::Cone`, is what CSG and skewed placements use).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    pub base: Vec3,
    pub axis: Vec3,
    pub h: f32,
    pub r0: f32,
    pub slope: f32,
    pub capped: bool,
    pub material: u32,
}

impl Cone {
    /// The parts `intersect_cone` names: the side and the two caps (also
    /// `Solid::Cone`'s).
    pub const SIDE: u32 = 0;
    pub const CAP0: u32 = 1;
    pub const CAP1: u32 = 2;

    /// The radius at the top.
    pub fn r1(&self) -> f32 {
        self.r0 + self.slope * self.h
    }

    /// The bounds of its two end disks (a little widened: the test rounds).
    pub fn bounds(&self) -> Aabb {
        let top = self.base + self.axis * self.h;
        // A disk of radius r normal to the axis reaches r·sqrt(1 - w_i²)
        // along axis i.
        let reach = (Vec3::ONE - self.axis * self.axis).max(Vec3::ZERO).powf(0.5);
        let (d0, d1) = (reach * self.r0, reach * self.r1());
        let lo = (self.base - d0).min(top - d1);
        let hi = (self.base + d0).max(top + d1);
        let pad = Vec3::splat(lo.abs().max(hi.abs()).max_element() * 4.0 * f32::EPSILON);
        Aabb { min: (lo - pad).into(), max: (hi + pad).into() }
    }

    /// The outward normal (not unit length) at `p` on `part`.
    pub fn normal(&self, p: Vec3, part: u32) -> Vec3 {
        match part {
            Cone::CAP0 => -self.axis,
            Cone::CAP1 => self.axis,
            _ => {
                // Out from the axis, tilted by the slope (r1 - r0) / h.
                let x = p - self.base;
                let radial = (x - self.axis * x.dot(self.axis)).normalize_or_zero();
                radial - self.axis * self.slope
            }
        }
    }
}

#[derive(Clone, Copy, Debug)]
pub enum Shape {
    Triangle(Triangle),
    Sphere {
        center: Vec3,
        radius: f32,
        material: u32,
    },
    Cone(Cone),
    /// Entry `index` of the tree's objects, with its bounds (empty: it
    /// has none, as a plane, and is tested by every ray).
    Object {
        index: u32,
        bounds: Aabb,
    },
}

impl Shape {
    pub fn bounds(&self) -> Aabb {
        match self {
            Shape::Triangle(t) => Aabb::EMPTY.grow(t.p[0]).grow(t.p[1]).grow(t.p[2]),
            Shape::Sphere { center, radius, .. } => {
                let r = Vec3::splat(*radius);
                Aabb { min: (*center - r).into(), max: (*center + r).into() }
            }
            Shape::Cone(c) => c.bounds(),
            Shape::Object { bounds, .. } => *bounds,
        }
    }

    /// The shape moved by `by` (where a moving one is at some time).
    pub fn moved(self, by: Vec3) -> Shape {
        match self {
            Shape::Triangle(t) => Shape::Triangle(Triangle { p: t.p.map(|p| p + by), ..t }),
            Shape::Sphere { center, radius, material } => {
                Shape::Sphere { center: center + by, radius, material }
            }
            Shape::Cone(c) => Shape::Cone(Cone { base: c.base + by, ..c }),
            o @ Shape::Object { .. } => o,
        }
    }

    pub fn material(&self) -> u32 {
        match self {
            Shape::Triangle(t) => t.material,
            Shape::Sphere { material, .. } => *material,
            Shape::Cone(c) => c.material,
            Shape::Object { .. } => u32::MAX,
        }
    }

    #[inline]
    pub fn intersect(
        &self,
        ray: &Ray,
        pre: &RayPre,
        t_min: f32,
        t_max: f32,
    ) -> Option<(f32, [f32; 2])> {
        match self {
            Shape::Triangle(t) => intersect_triangle_pre(t, ray, pre, t_min, t_max),
            Shape::Sphere { center, radius, .. } => {
                intersect_sphere(ray, *center, *radius, t_min, t_max).map(|t| (t, [0.0, 0.0]))
            }
            Shape::Cone(c) => intersect_cone(ray, c, t_min, t_max).map(|(t, _)| (t, [0.0, 0.0])),
            // Objects live in their tree's table: only the tree tests them.
            Shape::Object { .. } => None,
        }
    }
}

/// A hit: distance, the primitive (index into the BVH's shapes), the
/// barycentric weights of vertices 1 and 2 for triangles, and for an
/// object what it says of the hit (`Object::intersect`).
#[derive(Clone, Copy, Debug)]
pub struct Hit {
    pub t: f32,
    pub prim: u32,
    pub uv: [f32; 2],
    pub sub: u32,
}

/// Per-ray constants of the watertight triangle test.
#[derive(Clone, Copy, Debug)]
pub struct RayPre {
    /// The axes permuted so the ray's largest direction component is z.
    pub(crate) k: [usize; 3],
    pub(crate) s: Vec3,
}

impl RayPre {
    pub fn new(dir: Vec3) -> RayPre {
        let a = dir.abs();
        let kz = if a.x > a.y {
            if a.x > a.z { 0 } else { 2 }
        } else if a.y > a.z {
            1
        } else {
            2
        };
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        if dir[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        RayPre {
            k: [kx, ky, kz],
            s: Vec3::new(dir[kx] / dir[kz], dir[ky] / dir[kz], 1.0 / dir[kz]),
        }
    }
}

/// The closest hit found by testing every primitive in turn: the baseline
/// the hierarchy is measured (and checked) against, with its tie rule.
/// `Hit::prim` indexes `shapes`.
pub fn intersect_brute(shapes: &[Shape], ray: &Ray, t_min: f32, t_max: f32) -> Option<Hit> {
    let pre = RayPre::new(ray.dir);
    let mut best: Option<Hit> = None;
    let mut t_max = t_max;
    // In index order, so of hits within `TIE` of each other the first
    // stays, as in the hierarchy.
    for (k, s) in shapes.iter().enumerate() {
        if let Some((t, uv)) = s.intersect(ray, &pre, t_min, t_max)
            && best.is_none_or(|b| t < b.t * (1.0 - super::bvh::TIE))
        {
            t_max = t_max.min(t * (1.0 + super::bvh::TIE));
            best = Some(Hit { t, prim: k as u32, uv, sub: 0 });
        }
    }
    best
}

/// Ray-sphere: the nearest root in `(t_min, t_max)`, computed in the
/// cancellation-free form of Ray Tracing Gems, chapter 7.
pub fn intersect_sphere(
    ray: &Ray,
    center: Vec3,
    radius: f32,
    t_min: f32,
    t_max: f32,
) -> Option<f32> {
    let f = ray.origin - center;
    let a = ray.dir.length_squared();
    let b = -f.dot(ray.dir);
    let l = f + ray.dir * (b / a);
    let disc = a * (radius * radius - l.length_squared());
    if disc < 0.0 {
        return None;
    }
    let c = f.length_squared() - radius * radius;
    let q = b + b.signum() * disc.sqrt();
    if q == 0.0 {
        return None;
    }
    let (t0, t1) = (c / q, q / a);
    let (t0, t1) = if t0 < t1 { (t0, t1) } else { (t1, t0) };
    if t0 > t_min && t0 < t_max {
        Some(t0)
    } else if t1 > t_min && t1 < t_max {
        Some(t1)
    } else {
        None
    }
}

/// Ray-cone: the nearest crossing in `(t_min, t_max)` and its part
/// (`Cone::SIDE`, `CAP0`, `CAP1`). The four-wide test of the BVH's cone
/// blocks on one lane, so the two agree to the bit.
pub fn intersect_cone(ray: &Ray, cone: &Cone, t_min: f32, t_max: f32) -> Option<(f32, u32)> {
    let b = super::blocks::Block::lone_cone(cone);
    let (mask, t, part) = b.cones(ray, t_min, t_max);
    (mask & 1 != 0).then_some((t[0], part[0]))
}

/// Watertight ray-triangle test; returns `t` and the barycentric weights
/// of vertices 1 and 2.
pub fn intersect_triangle(
    ray: &Ray,
    tri: &Triangle,
    t_min: f32,
    t_max: f32,
) -> Option<(f32, [f32; 2])> {
    intersect_triangle_pre(tri, ray, &RayPre::new(ray.dir), t_min, t_max)
}

#[inline]
fn intersect_triangle_pre(
    tri: &Triangle,
    ray: &Ray,
    pre: &RayPre,
    t_min: f32,
    t_max: f32,
) -> Option<(f32, [f32; 2])> {
    let [kx, ky, kz] = pre.k;
    let a = tri.p[0] - ray.origin;
    let b = tri.p[1] - ray.origin;
    let c = tri.p[2] - ray.origin;
    let (ax, ay) = (a[kx] - pre.s.x * a[kz], a[ky] - pre.s.y * a[kz]);
    let (bx, by) = (b[kx] - pre.s.x * b[kz], b[ky] - pre.s.y * b[kz]);
    let (cx, cy) = (c[kx] - pre.s.x * c[kz], c[ky] - pre.s.y * c[kz]);
    let mut u = cx * by - cy * bx;
    let mut v = ax * cy - ay * cx;
    let mut w = bx * ay - by * ax;
    if u == 0.0 || v == 0.0 || w == 0.0 {
        // On an edge in single precision: decide it in double precision.
        let d = |x1: f32, y1: f32, x2: f32, y2: f32| {
            (x1 as f64 * y2 as f64 - y1 as f64 * x2 as f64) as f32
        };
        u = d(cx, cy, bx, by);
        v = d(ax, ay, cx, cy);
        w = d(bx, by, ax, ay);
    }
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None;
    }
    let (az, bz, cz) = (pre.s.z * a[kz], pre.s.z * b[kz], pre.s.z * c[kz]);
    let t_scaled = u * az + v * bz + w * cz;
    let t = t_scaled / det;
    if !(t > t_min && t < t_max) {
        return None;
    }
    Some((t, [v / det, w / det]))
}

/// Exact-ish reference used by tests: Möller-Trumbore in double precision.
pub fn intersect_triangle_f64(ray: &Ray, tri: &Triangle) -> Option<f64> {
    let o = ray.origin.as_dvec3();
    let d = ray.dir.as_dvec3();
    let p: [DVec3; 3] = [tri.p[0].as_dvec3(), tri.p[1].as_dvec3(), tri.p[2].as_dvec3()];
    let e1 = p[1] - p[0];
    let e2 = p[2] - p[0];
    let h = d.cross(e2);
    let det = e1.dot(h);
    if det.abs() < 1e-300 {
        return None;
    }
    let s = o - p[0];
    let u = s.dot(h) / det;
    let q = s.cross(e1);
    let v = d.dot(q) / det;
    if u < 0.0 || v < 0.0 || u + v > 1.0 {
        return None;
    }
    Some(e2.dot(q) / det)
}

#[cfg(test)]
mod tests;
