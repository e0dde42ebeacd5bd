//! Lights: parallel (infinitely far), point (1/r² falloff) and spot.
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
    },
    /// Full strength within `inner` of the axis, fading linearly to zero at
    /// `outer` (both as cosines).
    Spot {
        color: Vec3,
        pos: DVec3,
        dir: Vec3,
        cos_inner: f32,
        cos_outer: f32,
    },
}

impl Light {
    pub fn parallel(color: Vec3, dir: Vec3) -> Result<Light, SceneError> {
        Ok(Light::Parallel {
            color: check_color(color)?,
            dir: check_nonzero(dir, "light direction")?.normalize(),
        })
    }

    pub fn point(color: Vec3, pos: DVec3) -> Result<Light, SceneError> {
        Ok(Light::Point { color: check_color(color)?, pos })
    }

    pub fn spot(
        color: Vec3,
        pos: DVec3,
        dir: Vec3,
        inner_deg: f32,
        outer_deg: f32,
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
        })
    }

    pub(crate) fn check(&self) -> Result<(), SceneError> {
        let ok = match self {
            Light::Parallel { color, dir } => color.is_finite() && dir.is_finite(),
            Light::Point { color, pos } => color.is_finite() && in_range(*pos),
            Light::Spot { color, pos, dir, .. } => {
                color.is_finite() && in_range(*pos) && dir.is_finite()
            }
        };
        if ok { Ok(()) } else { Err(SceneError::NotFinite) }
    }

    /// The light with its position moved to be relative to `origin`.
    pub fn relative_to(self, origin: DVec3) -> Light {
        match self {
            Light::Parallel { .. } => self,
            Light::Point { color, pos } => Light::Point { color, pos: pos - origin },
            Light::Spot { color, pos, dir, cos_inner, cos_outer } => {
                Light::Spot { color, pos: pos - origin, dir, cos_inner, cos_outer }
            }
        }
    }

    /// For a point `p`: the unit direction towards the light, the distance
    /// to it (infinite for parallel lights) and the light arriving there.
    pub fn at(&self, p: Vec3) -> (Vec3, f32, Vec3) {
        match *self {
            Light::Parallel { color, dir } => (-dir, f32::INFINITY, color),
            Light::Point { color, pos } => {
                let d = pos.as_vec3() - p;
                let r2 = d.length_squared();
                let r = r2.sqrt();
                (d / r, r, color / r2)
            }
            Light::Spot { color, pos, dir, cos_inner, cos_outer } => {
                let d = pos.as_vec3() - p;
                let r2 = d.length_squared();
                let r = r2.sqrt();
                let l = d / r;
                let cos = (-l).dot(dir);
                let f = spot_factor(cos, cos_inner, cos_outer);
                (l, r, color * (f / r2))
            }
        }
    }
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
