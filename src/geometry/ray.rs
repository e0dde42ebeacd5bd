//! A ray: origin, direction (not necessarily unit length) and the moment
//! in the shutter interval it samples (what moving objects are seen at).

use glam::Vec3;

#[derive(Clone, Copy, Debug)]
pub struct Ray {
    pub origin: Vec3,
    pub dir: Vec3,
    /// The time the ray samples; 0 unless the camera's shutter is open.
    pub time: f32,
}

impl Ray {
    /// A ray at time 0.
    pub fn new(origin: Vec3, dir: Vec3) -> Ray {
        Ray { origin, dir, time: 0.0 }
    }

    /// The same ray at `time`.
    pub fn at_time(self, time: f32) -> Ray {
        Ray { time, ..self }
    }

    /// A ray leaving from where this one went (a reflection, a refraction,
    /// a shadow ray): at the same moment.
    pub fn spawn(&self, origin: Vec3, dir: Vec3) -> Ray {
        Ray { origin, dir, time: self.time }
    }

    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + self.dir * t
    }
}

/// `Vec3::is_finite` without a branch per coordinate (no exponent all
/// ones): asked of every camera ray.
#[inline]
pub fn finite(v: Vec3) -> bool {
    const EXP: u32 = 0x7f80_0000;
    let e = |x: f32| x.to_bits() & EXP != EXP;
    e(v.x) & e(v.y) & e(v.z)
}
