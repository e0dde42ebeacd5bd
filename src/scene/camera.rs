//! The pinhole camera: rays through pixel centres, row 0 at the top.

use glam::Vec3;

use crate::geometry::Ray;

#[derive(Clone, Copy, Debug)]
pub struct Camera {
    pub from: Vec3,
    pub width: u32,
    pub height: u32,
    /// The direction to the top-left image corner and the steps from one
    /// pixel to the next, so a ray costs no division but its normalizing.
    corner: Vec3,
    dx: Vec3,
    dy: Vec3,
}

impl Camera {
    /// `None` when `up` is parallel to `forward`.
    pub fn new(
        from: Vec3,
        forward: Vec3,
        up: Vec3,
        angle_deg: f32,
        width: u32,
        height: u32,
    ) -> Option<Camera> {
        let forward = forward.normalize();
        let right = forward.cross(up);
        if right.length_squared() < 1e-12 * up.length_squared() {
            return None;
        }
        let right = right.normalize();
        let up = right.cross(forward);
        let th = (angle_deg.to_radians() * 0.5).tan();
        let tv = th * height as f32 / width as f32;
        let corner = forward - right * th + up * tv;
        let dx = right * (2.0 * th / width as f32);
        let dy = up * (-2.0 * tv / height as f32);
        Some(Camera { from, width, height, corner, dx, dy })
    }

    /// The primary ray through the centre of pixel (x, y).
    pub fn ray(&self, x: u32, y: u32) -> Ray {
        self.ray_at(x as f32 + 0.5, y as f32 + 0.5)
    }

    /// The primary ray through the image point (px, py), in pixels from
    /// the top-left corner (pixel centres are at half-integers).
    pub fn ray_at(&self, px: f32, py: f32) -> Ray {
        let dir = self.corner + self.dx * px + self.dy * py;
        Ray::new(self.from, dir.normalize())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn centre_pixel_looks_forward() {
        let c = Camera::new(
            Vec3::new(1.0, 2.0, 3.0),
            Vec3::new(0.0, 0.0, -2.0),
            Vec3::Y,
            60.0,
            101,
            51,
        )
        .unwrap();
        let r = c.ray(50, 25);
        assert!((r.dir - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
        assert_eq!(r.origin, Vec3::new(1.0, 2.0, 3.0));
        // Row 0 is the top; the left edge is at -angle/2.
        assert!(c.ray(50, 0).dir.y > 0.0);
        let left = Camera::new(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y, 90.0, 1000, 10).unwrap().ray(0, 5);
        let angle = left.dir.x.atan2(-left.dir.z).to_degrees();
        assert!((angle + 45.0).abs() < 0.1, "{angle}");
    }

    #[test]
    fn up_parallel_is_refused() {
        assert!(Camera::new(Vec3::ZERO, Vec3::Y, Vec3::Y, 45.0, 10, 10).is_none());
    }
}
