//! Analytic shapes in their own coordinates (an `Object` places them):
//! the unit sphere (ellipsoids are transformed ones), boxes, cones and
//! cylinders along a canonical axis, disks, tori and planes. Each gives
//! every crossing of a ray's whole line, in order, with which part of its
//! surface was crossed: the closest hit, a shadow ray's crossings and CSG's
//! intervals all come from that one list. Computed in double precision.

use glam::{DVec3, Vec3};

use super::poly;
use super::{Aabb, Cone, Ray};

/// An analytic shape in its own coordinates.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Solid {
    /// The unit sphere at the origin.
    Sphere,
    /// The box between two corners.
    Box { min: Vec3, max: Vec3 },
    /// Along z from 0 to 1, of radius `r0` at z = 0 and `r1` at z = 1 (a
    /// cylinder when they are equal); `capped` closes both ends.
    Cone { r0: f32, r1: f32, capped: bool },
    /// The unit disk in the plane z = 0, less the disk of radius `inner`.
    Disk { inner: f32 },
    /// Around the y axis: the circle of radius `major` in the xz-plane,
    /// swept by a circle of radius `minor`.
    Torus { major: f32, minor: f32 },
    /// The plane n·p = d (n a unit vector): infinite, so never in a tree.
    Plane { n: Vec3, d: f32 },
}

/// A crossing of a solid's surface: where along the ray, and which part
/// of the surface (`Solid::normal` takes it back).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Crossing {
    pub t: f32,
    pub part: u32,
}

/// At most this many crossings of one solid along a line (the torus's).
pub const MAX_CROSSINGS: usize = 4;

/// A solid's crossings, in order.
#[derive(Clone, Copy, Debug)]
pub struct Crossings {
    pub n: usize,
    pub at: [Crossing; MAX_CROSSINGS],
}

impl Crossings {
    const NONE: Crossings = Crossings { n: 0, at: [Crossing { t: 0.0, part: 0 }; MAX_CROSSINGS] };

    fn push(&mut self, t: f64, part: u32) {
        if self.n < MAX_CROSSINGS && t.is_finite() {
            self.at[self.n] = Crossing { t: t as f32, part };
            self.n += 1;
        }
    }

    fn sort(&mut self) {
        self.at[..self.n].sort_by(|a, b| a.t.total_cmp(&b.t));
    }

    pub fn as_slice(&self) -> &[Crossing] {
        &self.at[..self.n]
    }

    /// The first crossing in `(t_min, t_max)`.
    #[inline]
    pub fn first_in(&self, t_min: f32, t_max: f32) -> Option<Crossing> {
        self.as_slice().iter().copied().find(|c| c.t > t_min && c.t < t_max)
    }
}

/// The parts of a cone: its side and its two caps (numbered as the BVH's
/// own cones number them).
const SIDE: u32 = Cone::SIDE;
const CAP0: u32 = Cone::CAP0;
const CAP1: u32 = Cone::CAP1;

impl Solid {
    /// Whether it encloses a volume (CSG needs that).
    pub fn is_closed(&self) -> bool {
        match self {
            Solid::Sphere | Solid::Box { .. } | Solid::Torus { .. } => true,
            Solid::Cone { capped, .. } => *capped,
            Solid::Disk { .. } | Solid::Plane { .. } => false,
        }
    }

    /// The bounds, in its own coordinates (empty for a plane, which has
    /// none).
    pub fn bounds(&self) -> Aabb {
        let b = |lo: Vec3, hi: Vec3| Aabb { min: lo.into(), max: hi.into() };
        match *self {
            Solid::Sphere => b(Vec3::splat(-1.0), Vec3::ONE),
            Solid::Box { min, max } => b(min, max),
            Solid::Cone { r0, r1, .. } => {
                let r = r0.max(r1);
                b(Vec3::new(-r, -r, 0.0), Vec3::new(r, r, 1.0))
            }
            Solid::Disk { .. } => b(Vec3::new(-1.0, -1.0, 0.0), Vec3::new(1.0, 1.0, 0.0)),
            Solid::Torus { major, minor } => {
                let o = major + minor;
                b(Vec3::new(-o, -minor, -o), Vec3::new(o, minor, o))
            }
            Solid::Plane { .. } => Aabb::EMPTY,
        }
    }

    /// Every crossing of the ray's line (any t), in order.
    pub fn crossings(&self, ray: &Ray) -> Crossings {
        let o = ray.origin.as_dvec3();
        let d = ray.dir.as_dvec3();
        let mut out = Crossings::NONE;
        match *self {
            Solid::Sphere => {
                // |o + t·d|² = 1, from the point nearest the centre.
                let a = d.length_squared();
                let b = -o.dot(d);
                let l = o + d * (b / a);
                let disc = a * (1.0 - l.length_squared());
                if disc > 0.0 {
                    let q = b + b.signum() * disc.sqrt();
                    let c = o.length_squared() - 1.0;
                    let (t0, t1) = (c / q, q / a);
                    out.push(t0.min(t1), 0);
                    out.push(t0.max(t1), 0);
                }
            }
            Solid::Box { min, max } => {
                let (lo, hi) = (min.as_dvec3(), max.as_dvec3());
                let (mut near, mut far) = (f64::NEG_INFINITY, f64::INFINITY);
                let (mut near_face, mut far_face) = (0, 0);
                for axis in 0..3 {
                    if d[axis] == 0.0 {
                        if o[axis] < lo[axis] || o[axis] > hi[axis] {
                            return out;
                        }
                        continue;
                    }
                    let inv = 1.0 / d[axis];
                    let (mut t0, mut t1) = ((lo[axis] - o[axis]) * inv, (hi[axis] - o[axis]) * inv);
                    // Faces: 2·axis for the low side, 2·axis + 1 for the high.
                    let (mut f0, mut f1) = (2 * axis as u32, 2 * axis as u32 + 1);
                    if t0 > t1 {
                        std::mem::swap(&mut t0, &mut t1);
                        std::mem::swap(&mut f0, &mut f1);
                    }
                    if t0 > near {
                        (near, near_face) = (t0, f0);
                    }
                    if t1 < far {
                        (far, far_face) = (t1, f1);
                    }
                }
                if near < far {
                    out.push(near, near_face);
                    out.push(far, far_face);
                }
            }
            Solid::Cone { r0, r1, capped } => {
                let (r0, r1) = (r0 as f64, r1 as f64);
                let k = r1 - r0;
                // x² + y² = (r0 + k·z)², for 0 ≤ z ≤ 1.
                let rz = r0 + k * o.z;
                let a = d.x * d.x + d.y * d.y - k * k * d.z * d.z;
                let b = 2.0 * (o.x * d.x + o.y * d.y - rz * k * d.z);
                let c = o.x * o.x + o.y * o.y - rz * rz;
                let mut roots = [0.0; poly::MAX_DEGREE];
                let (lo, hi) = (f64::NEG_INFINITY, f64::INFINITY);
                // What `roots` does with a quadratic, without its general
                // case around it (a ray along a cylinder's axis has a = 0).
                let n = if a != 0.0 {
                    poly::quadratic(a, b, c, lo, hi, &mut roots)
                } else {
                    poly::roots(&[c, b, a], lo, hi, &mut roots)
                };
                for &t in &roots[..n] {
                    let z = o.z + t * d.z;
                    if (0.0..=1.0).contains(&z) {
                        out.push(t, SIDE);
                    }
                }
                // The side's crossings come in order; the caps' need sorting.
                if capped && d.z != 0.0 {
                    for (z, r, part) in [(0.0, r0, CAP0), (1.0, r1, CAP1)] {
                        let t = (z - o.z) / d.z;
                        let p = o + d * t;
                        if p.x * p.x + p.y * p.y <= r * r && r > 0.0 {
                            out.push(t, part);
                        }
                    }
                    out.sort();
                }
            }
            Solid::Disk { inner } => {
                if d.z != 0.0 {
                    let t = -o.z / d.z;
                    let p = o + d * t;
                    let r2 = p.x * p.x + p.y * p.y;
                    let inner = inner as f64;
                    if r2 <= 1.0 && r2 >= inner * inner {
                        out.push(t, 0);
                    }
                }
            }
            Solid::Torus { major, minor } => torus(o, d, major as f64, minor as f64, &mut out),
            Solid::Plane { n, d: dist } => {
                let n = n.as_dvec3();
                let den = n.dot(d);
                if den != 0.0 {
                    out.push((dist as f64 - n.dot(o)) / den, 0);
                }
            }
        }
        out
    }

    /// The outward normal (not unit length) at `p` on `part`.
    pub fn normal(&self, p: Vec3, part: u32) -> Vec3 {
        match *self {
            Solid::Sphere => p,
            Solid::Box { .. } => {
                let axis = (part / 2) as usize;
                let mut n = Vec3::ZERO;
                n[axis] = if part.is_multiple_of(2) { -1.0 } else { 1.0 };
                n
            }
            Solid::Cone { r0, r1, .. } => match part {
                CAP0 => Vec3::NEG_Z,
                CAP1 => Vec3::Z,
                _ => {
                    let k = r1 - r0;
                    Vec3::new(p.x, p.y, -(r0 + k * p.z) * k)
                }
            },
            Solid::Disk { .. } => Vec3::Z,
            Solid::Torus { major, minor } => {
                // ∇[(|p|² + R² − r²)² − 4R²(x² + z²)] / 4.
                let (r2, m) = (major * major, p.length_squared() + major * major - minor * minor);
                Vec3::new(p.x * (m - 2.0 * r2), p.y * m, p.z * (m - 2.0 * r2))
            }
            Solid::Plane { n, .. } => n,
        }
    }
}

/// The torus's quartic (|p|² + R² − r²)² = 4R²(x² + z²), solved for the
/// ray's parameter measured from its point nearest the centre, with the
/// direction made unit: the coefficients stay of the torus's size, not
/// the ray's distance, so far rays lose no precision.
fn torus(o: DVec3, d: DVec3, major: f64, minor: f64, out: &mut Crossings) {
    let len = d.length();
    if len == 0.0 {
        return;
    }
    let u = d / len;
    // The bounding sphere first: most rays stop here.
    let t_mid = -o.dot(u);
    let p = o + u * t_mid;
    let reach = major + minor;
    let miss = p.length_squared();
    if miss >= reach * reach {
        return;
    }
    let half = (reach * reach - miss).sqrt();
    // In s = t − t_mid: p(s) = p + s·u, |p(s)|² = s² + |p|² (p ⊥ u).
    let k = miss + major * major - minor * minor;
    let (pu_xz, p_xz, u_xz) = (p.x * u.x + p.z * u.z, p.x * p.x + p.z * p.z, u.x * u.x + u.z * u.z);
    let r4 = 4.0 * major * major;
    // (s² + k)² − 4R²(u_xz·s² + 2·pu_xz·s + p_xz).
    let c = [k * k - r4 * p_xz, -2.0 * r4 * pu_xz, 2.0 * k - r4 * u_xz, 0.0, 1.0];
    let mut roots = [0.0; poly::MAX_DEGREE];
    // A little beyond the sphere, so roots at its surface are not lost.
    let n = poly::roots(&c, -half * 1.001 - 1e-9, half * 1.001 + 1e-9, &mut roots);
    for &s in &roots[..n] {
        out.push((s + t_mid) / len, 0);
    }
}

#[cfg(test)]
mod tests;
