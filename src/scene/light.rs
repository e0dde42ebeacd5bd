//! Lights: parallel (infinitely far), point (1/r² falloff unless told
//! otherwise, see `Falloff`), spot, and the
//! lights with a size: a parallelogram (`area_light`) and a sphere
//! (`sphere_light`), of a given radiance, sampled at each shading point and
//! seen by camera and reflected rays.
//! Positions are double precision in the builder (world coordinates) and
//! relative to the eye once frozen (`relative_to`).

use glam::{DVec3, Vec3};

use super::builder::{SceneError, check_color, check_nonzero};

#[derive(Clone, Copy, Debug)]
pub enum Light {
    /// `dir` is the direction the light travels (unit length).
    Parallel {
        color: Vec3,
        dir: Vec3,
    },
    Point {
        color: Vec3,
        pos: DVec3,
        falloff: Falloff,
    },
    /// Full strength within `inner` of the axis, fading linearly to zero at
    /// `outer` (both as cosines).
    Spot {
        color: Vec3,
        pos: DVec3,
        dir: Vec3,
        cos_inner: f32,
        cos_outer: f32,
        falloff: Falloff,
    },
    /// A parallelogram from `corner` along edges `u` and `v`, emitting
    /// `radiance` from the side `u × v` points to; `n`×`n` stratified
    /// samples per shading point.
    Area {
        radiance: Vec3,
        corner: DVec3,
        u: Vec3,
        v: Vec3,
        n: u32,
    },
    /// A sphere of `radiance`, sampled by solid angle, `n`×`n` samples.
    Sphere {
        radiance: Vec3,
        center: DVec3,
        radius: f32,
        n: u32,
    },
}

/// How a point or spot light's strength falls with the distance r: the
/// light arriving is its colour over `constant + linear·r + quadratic·r²`
/// (OpenGL's and VRML's attenuation). `INVERSE_SQUARE` (0, 0, 1) is the
/// physical light and the default; NFF's lights and POV-Ray's
/// `light_source` do not fall off: `NONE` (1, 0, 0).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Falloff {
    pub constant: f32,
    pub linear: f32,
    pub quadratic: f32,
}

impl Falloff {
    pub const INVERSE_SQUARE: Falloff = Falloff { constant: 0.0, linear: 0.0, quadratic: 1.0 };
    pub const NONE: Falloff = Falloff { constant: 1.0, linear: 0.0, quadratic: 0.0 };

    /// Checks the coefficients: finite, not negative, not all zero.
    pub fn new(constant: f32, linear: f32, quadratic: f32) -> Result<Falloff, SceneError> {
        let all = [constant, linear, quadratic];
        if all.iter().any(|c| !(c.is_finite() && *c >= 0.0)) || all.iter().all(|&c| c == 0.0) {
            return Err(SceneError::Invalid(format!(
                "light falloff coefficients must be finite, not negative and not all zero, got {constant} {linear} {quadratic}"
            )));
        }
        Ok(Falloff { constant, linear, quadratic })
    }

    /// The divisor at distance `r` (`r2` = r², already at hand). The
    /// default gives exactly r².
    #[inline]
    pub fn at(self, r: f32, r2: f32) -> f32 {
        if self == Falloff::INVERSE_SQUARE {
            r2
        } else {
            self.constant + self.linear * r + self.quadratic * r2
        }
    }
}

/// The most samples per side an area or sphere light takes.
pub const MAX_LIGHT_SAMPLES: u32 = 32;

impl Light {
    pub fn parallel(color: Vec3, dir: Vec3) -> Result<Light, SceneError> {
        Ok(Light::Parallel {
            color: check_color(color)?,
            dir: check_nonzero(dir, "light direction")?.normalize(),
        })
    }

    pub fn point(color: Vec3, pos: DVec3, falloff: Falloff) -> Result<Light, SceneError> {
        Ok(Light::Point { color: check_color(color)?, pos, falloff })
    }

    pub fn spot(
        color: Vec3,
        pos: DVec3,
        dir: Vec3,
        inner_deg: f32,
        outer_deg: f32,
        falloff: Falloff,
    ) -> Result<Light, SceneError> {
        if !(0.0..=180.0).contains(&inner_deg)
            || !(0.0..=180.0).contains(&outer_deg)
            || inner_deg > outer_deg
        {
            return Err(SceneError::Invalid(format!(
                "spot light angles must satisfy 0 <= angle1 <= angle2 <= 180, got {inner_deg} and {outer_deg}"
            )));
        }
        Ok(Light::Spot {
            color: check_color(color)?,
            pos,
            dir: check_nonzero(dir, "spot light direction")?.normalize(),
            cos_inner: inner_deg.to_radians().cos(),
            cos_outer: outer_deg.to_radians().cos(),
            falloff,
        })
    }

    pub fn area(
        radiance: Vec3,
        corner: DVec3,
        u: Vec3,
        v: Vec3,
        n: i64,
    ) -> Result<Light, SceneError> {
        if robust_length(u.cross(v)) == 0.0 || !u.cross(v).is_finite() {
            return Err(SceneError::Invalid(
                "area light edges u and v must not be parallel or zero".into(),
            ));
        }
        Ok(Light::Area { radiance: check_color(radiance)?, corner, u, v, n: light_samples(n)? })
    }

    pub fn sphere(radiance: Vec3, center: DVec3, radius: f32, n: i64) -> Result<Light, SceneError> {
        if !(radius > 0.0 && radius.is_finite()) {
            return Err(SceneError::Invalid(format!(
                "sphere light radius must be positive, got {radius}"
            )));
        }
        Ok(Light::Sphere { radiance: check_color(radiance)?, center, radius, n: light_samples(n)? })
    }

    /// Shading samples per point (n² for the lights with a size).
    pub fn samples(&self) -> u32 {
        match self {
            Light::Area { n, .. } | Light::Sphere { n, .. } => n * n,
            _ => 1,
        }
    }

    /// For a point `p` and sample `k` of `samples()`, jittered by `(a, b)`
    /// in its stratum: the unit direction towards the light, the distance,
    /// and the light arriving, already divided among the samples and
    /// expressed as a point light's number (radiance L over area A at
    /// distance r and angle θ to the light's normal arrives as
    /// L·A·cos θ/(π·r²)); the other lights ignore `k` and the jitter.
    #[inline]
    pub fn sample_at(&self, p: Vec3, k: u32, jitter: (f32, f32)) -> (Vec3, f32, Vec3) {
        match *self {
            Light::Area { .. } | Light::Sphere { .. } => self.sample_sized(p, k, jitter),
            _ => self.at(p),
        }
    }

    /// `sample_at` out of line, for the lights with a size (the point
    /// lights' path is inlined into the shaders).
    fn sample_sized(&self, p: Vec3, k: u32, (a, b): (f32, f32)) -> (Vec3, f32, Vec3) {
        match *self {
            Light::Area { radiance, corner, u, v, n } => {
                let (i, j) = ((k % n) as f32, (k / n) as f32);
                let q = corner.as_vec3() + u * ((i + a) / n as f32) + v * ((j + b) / n as f32);
                let d = q - p;
                let r2 = d.length_squared();
                let r = r2.sqrt();
                let l = d / r;
                let normal = u.cross(v);
                let area = robust_length(normal);
                let cos_l = -l.dot(normal / area);
                if !(cos_l > 0.0 && r2 > 0.0) {
                    return (l, r, Vec3::ZERO);
                }
                let share = area * cos_l / (std::f32::consts::PI * r2 * (n * n) as f32);
                (l, r, radiance * share)
            }
            Light::Sphere { radiance, center, radius, n } => {
                let dc = center.as_vec3() - p;
                let dist = dc.length();
                if dist <= radius {
                    return (Vec3::Y, 0.0, Vec3::ZERO);
                }
                let w = dc / dist;
                let sin2_max = (radius / dist).powi(2);
                let cos_max = (1.0 - sin2_max).max(0.0).sqrt();
                let (i, j) = ((k % n) as f32, (k / n) as f32);
                let (a, b) = ((i + a) / n as f32, (j + b) / n as f32);
                let cos_t = 1.0 - a * (1.0 - cos_max);
                let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
                let phi = 2.0 * std::f32::consts::PI * b;
                let (t1, t2) = orthonormal(w);
                let l =
                    (t1 * (sin_t * phi.cos()) + t2 * (sin_t * phi.sin()) + w * cos_t).normalize();
                // Where the direction meets the sphere (the near side).
                let along = dist * cos_t;
                let r = along - (radius * radius - dist * dist * sin_t * sin_t).max(0.0).sqrt();
                // L · solid angle / π, shared among the samples.
                let share = 2.0 * (1.0 - cos_max) / (n * n) as f32;
                (l, r, radiance * share)
            }
            _ => self.at(p),
        }
    }

    /// Where `ray` meets the emitting side of a light with a size, if it
    /// does before `t_max`: the distance and the radiance seen.
    pub fn hit(&self, ray: &crate::geometry::Ray, t_max: f32) -> Option<(f32, Vec3)> {
        match *self {
            Light::Area { radiance, corner, u, v, .. } => {
                let normal = u.cross(v);
                let denom = ray.dir.dot(normal);
                // Seen from the front only: the back is not there.
                if denom.is_nan() || denom >= 0.0 {
                    return None;
                }
                let t = (corner.as_vec3() - ray.origin).dot(normal) / denom;
                if !(t > 0.0 && t < t_max) {
                    return None;
                }
                let q = ray.origin + ray.dir * t - corner.as_vec3();
                // Coordinates along u and v (the dual basis in the plane).
                let (uu, uv, vv) = (u.dot(u), u.dot(v), v.dot(v));
                let det = uu * vv - uv * uv;
                let (qu, qv) = (q.dot(u), q.dot(v));
                let a = (qu * vv - qv * uv) / det;
                let b = (qv * uu - qu * uv) / det;
                ((0.0..=1.0).contains(&a) && (0.0..=1.0).contains(&b)).then_some((t, radiance))
            }
            Light::Sphere { radiance, center, radius, .. } => {
                let oc = ray.origin - center.as_vec3();
                let b = oc.dot(ray.dir);
                let c = oc.length_squared() - radius * radius;
                let disc = b * b - c;
                if disc.is_nan() || disc < 0.0 {
                    return None;
                }
                let s = disc.sqrt();
                let t = if -b - s > 0.0 { -b - s } else { -b + s };
                (t > 0.0 && t < t_max).then_some((t, radiance))
            }
            _ => None,
        }
    }

    /// Whether camera and reflected rays can see this light.
    pub fn is_visible(&self) -> bool {
        matches!(self, Light::Area { .. } | Light::Sphere { .. })
    }

    pub(crate) fn check(&self) -> Result<(), SceneError> {
        let ok = match self {
            Light::Parallel { color, dir } => color.is_finite() && dir.is_finite(),
            Light::Point { color, pos, .. } => color.is_finite() && in_range(*pos),
            Light::Spot { color, pos, dir, .. } => {
                color.is_finite() && in_range(*pos) && dir.is_finite()
            }
            Light::Area { radiance, corner, u, v, .. } => {
                radiance.is_finite() && in_range(*corner) && u.is_finite() && v.is_finite()
            }
            Light::Sphere { radiance, center, radius, .. } => {
                radiance.is_finite() && in_range(*center) && radius.is_finite()
            }
        };
        if ok { Ok(()) } else { Err(SceneError::NotFinite) }
    }

    /// The light with its position moved to be relative to `origin`.
    pub fn relative_to(self, origin: DVec3) -> Light {
        match self {
            Light::Parallel { .. } => self,
            Light::Point { color, pos, falloff } => {
                Light::Point { color, pos: pos - origin, falloff }
            }
            Light::Spot { color, pos, dir, cos_inner, cos_outer, falloff } => {
                Light::Spot { color, pos: pos - origin, dir, cos_inner, cos_outer, falloff }
            }
            Light::Area { radiance, corner, u, v, n } => {
                Light::Area { radiance, corner: corner - origin, u, v, n }
            }
            Light::Sphere { radiance, center, radius, n } => {
                Light::Sphere { radiance, center: center - origin, radius, n }
            }
        }
    }

    /// For a point `p`: the unit direction towards the light, the distance
    /// to it (infinite for parallel lights) and the light arriving there.
    /// (Inlined for parallel and point lights: the three values come back
    /// in registers, where a call returned them through memory, written
    /// in narrower pieces than they were read back in, a store-forwarding
    /// stall per shadow ray.)
    #[inline(always)]
    pub fn at(&self, p: Vec3) -> (Vec3, f32, Vec3) {
        match *self {
            Light::Parallel { color, dir } => (-dir, f32::INFINITY, color),
            Light::Point { color, pos, falloff } => {
                let d = pos.as_vec3() - p;
                let r2 = d.length_squared();
                let r = r2.sqrt();
                (d / r, r, color / falloff.at(r, r2))
            }
            _ => self.at_other(p),
        }
    }

    /// `at` for spot lights and lights with a size.
    #[inline(never)]
    fn at_other(&self, p: Vec3) -> (Vec3, f32, Vec3) {
        match *self {
            Light::Parallel { .. } | Light::Point { .. } => self.at(p),
            Light::Spot { color, pos, dir, cos_inner, cos_outer, falloff } => {
                let d = pos.as_vec3() - p;
                let r2 = d.length_squared();
                let r = r2.sqrt();
                let l = d / r;
                let cos = (-l).dot(dir);
                let f = spot_factor(cos, cos_inner, cos_outer);
                (l, r, color * (f / falloff.at(r, r2)))
            }
            // The middle of the light, all of it (raybench's shadow rays).
            Light::Area { .. } | Light::Sphere { .. } => {
                let mut total = Vec3::ZERO;
                let (l, r, _) = self.sample_at(p, 0, (0.5, 0.5));
                for k in 0..self.samples() {
                    total += self.sample_at(p, k, (0.5, 0.5)).2;
                }
                (l, r, total)
            }
        }
    }
}

fn light_samples(n: i64) -> Result<u32, SceneError> {
    if !(1..=MAX_LIGHT_SAMPLES as i64).contains(&n) {
        return Err(SceneError::Invalid(format!(
            "light samples per side must be between 1 and {MAX_LIGHT_SAMPLES}, got {n}"
        )));
    }
    Ok(n as u32)
}

/// |v| without underflow for tiny vectors (a light 1e-20 across).
fn robust_length(v: Vec3) -> f32 {
    let m = v.abs().max_element();
    if m == 0.0 || !m.is_finite() { m } else { m * (v / m).length() }
}

/// Two unit vectors that make an orthonormal basis with `w` (Duff et al.).
pub fn orthonormal(w: Vec3) -> (Vec3, Vec3) {
    let sign = 1.0f32.copysign(w.z);
    let a = -1.0 / (sign + w.z);
    let b = w.x * w.y * a;
    (
        Vec3::new(1.0 + sign * w.x * w.x * a, sign * b, -sign * w.x),
        Vec3::new(b, sign + w.y * w.y * a, -w.y),
    )
}

/// Finite and within single precision's range.
fn in_range(p: DVec3) -> bool {
    p.is_finite() && p.abs().max_element() <= f32::MAX as f64
}

/// 1 inside the inner cone, 0 outside the outer cone, linear in angle between.
pub fn spot_factor(cos: f32, cos_inner: f32, cos_outer: f32) -> f32 {
    if cos >= cos_inner {
        1.0
    } else if cos <= cos_outer {
        0.0
    } else {
        let a = cos.clamp(-1.0, 1.0).acos();
        let (ai, ao) = (cos_inner.acos(), cos_outer.acos());
        ((ao - a) / (ao - ai)).clamp(0.0, 1.0)
    }
}
