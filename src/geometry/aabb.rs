//! Axis-aligned bounding boxes, corners in SIMD lanes (the BVH build's
//! inner loops are unions of these), and the slab test's error bound.

use glam::Vec3A;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Aabb {
    pub min: Vec3A,
    pub max: Vec3A,
}

impl Aabb {
    pub const EMPTY: Aabb = Aabb { min: Vec3A::INFINITY, max: Vec3A::NEG_INFINITY };

    #[inline(always)]
    pub fn union(self, o: Aabb) -> Aabb {
        Aabb { min: self.min.min(o.min), max: self.max.max(o.max) }
    }

    #[inline(always)]
    pub fn grow(self, p: impl Into<Vec3A>) -> Aabb {
        let p = p.into();
        Aabb { min: self.min.min(p), max: self.max.max(p) }
    }

    pub fn centroid(&self) -> Vec3A {
        (self.min + self.max) * 0.5
    }

    pub fn extent(&self) -> Vec3A {
        (self.max - self.min).max(Vec3A::ZERO)
    }

    pub fn surface_area(&self) -> f32 {
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    pub fn is_empty(&self) -> bool {
        self.min.x > self.max.x
    }
}

/// 1 + 2·gamma(3): how much a slab exit distance is widened.
pub(crate) const ROBUST: f32 =
    1.0 + 2.0 * (3.0 * f32::EPSILON * 0.5) / (1.0 - 3.0 * f32::EPSILON * 0.5);
