//! The camera: a pinhole, or a thin lens (`camera_aperture`,
//! `camera_focus`); rays through points of the image, row 0 at the top.

use glam::{Vec3, Vec3A, Vec4};

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
    /// The thin lens, if the aperture is open.
    lens: Option<Lens>,
}

/// A thin lens: rays leave from a disc of `radius` around the eye (across
/// `right` and `up`) and meet where the pinhole ray meets the plane in
/// focus, `focus` along `forward`.
#[derive(Clone, Copy, Debug)]
struct Lens {
    radius: f32,
    focus: f32,
    right: Vec3,
    up: Vec3,
    forward: Vec3,
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
        Some(Camera { from, width, height, corner, dx, dy, lens: None })
    }

    /// This camera with a thin lens of `radius` focused at `focus` along
    /// the view direction (a radius of 0 keeps the pinhole).
    pub fn with_lens(mut self, radius: f32, focus: f32) -> Camera {
        if radius > 0.0 {
            let forward = (self.corner
                + self.dx * (self.width as f32 * 0.5)
                + self.dy * (self.height as f32 * 0.5))
                .normalize();
            let right = self.dx.normalize();
            let up = -self.dy.normalize();
            self.lens = Some(Lens { radius, focus, right, up, forward });
        }
        self
    }

    /// The angle one pixel spans, in radians (near the centre): the
    /// spread of a camera ray's cone, for texture filtering.
    pub fn pixel_spread(&self) -> f32 {
        self.dx.length()
    }

    /// Whether rays leave from a lens (and need a lens sample).
    pub fn has_lens(&self) -> bool {
        self.lens.is_some()
    }

    /// The ray through image point (px, py) from lens point (lu, lv) in
    /// the unit square (mapped to the disc by Shirley and Chiu's concentric
    /// map); a pinhole ignores (lu, lv).
    pub fn lens_ray(&self, px: f32, py: f32, lu: f32, lv: f32) -> Ray {
        let pinhole = self.ray_at(px, py);
        let Some(l) = self.lens else { return pinhole };
        let d = pinhole.dir;
        let in_focus = self.from + d * (l.focus / d.dot(l.forward));
        let (x, y) = concentric_disc(lu, lv);
        let origin = self.from + l.right * (x * l.radius) + l.up * (y * l.radius);
        Ray::new(origin, (in_focus - origin).normalize())
    }

    /// The primary ray through the centre of pixel (x, y).
    pub fn ray(&self, x: u32, y: u32) -> Ray {
        self.ray_at(x as f32 + 0.5, y as f32 + 0.5)
    }

    /// `ray` for each pixel of `px`, at `time`, into `out`: the same rays
    /// to the bit, four at a time (each lane does `ray_at`'s arithmetic in
    /// its order; one ray at a time, the division and square root of the
    /// normalizing took a fifth of a primary-only render).
    pub fn rays_into(&self, px: &[(u32, u32)], time: f32, out: &mut [Ray]) {
        let n = px.len().min(out.len());
        let rest = n - n % 4;
        // One axis of `corner + dx * px + dy * py`, for four pixels.
        let axis = |c: usize| {
            let (a, b, d) = (self.corner[c], self.dx[c], self.dy[c]);
            move |fx: Vec4, fy: Vec4| (Vec4::splat(a) + Vec4::splat(b) * fx) + Vec4::splat(d) * fy
        };
        let (x_of, y_of, z_of) = (axis(0), axis(1), axis(2));
        for (q, out) in px[..rest].chunks_exact(4).zip(out.chunks_exact_mut(4)) {
            let centre = |f: fn(&(u32, u32)) -> u32| {
                Vec4::new(f(&q[0]) as f32, f(&q[1]) as f32, f(&q[2]) as f32, f(&q[3]) as f32)
                    + Vec4::splat(0.5)
            };
            let (fx, fy) = (centre(|p| p.0), centre(|p| p.1));
            let (x, y, z) = (x_of(fx, fy), y_of(fx, fy), z_of(fx, fy));
            // `normalize`: times 1 / sqrt((x·x + y·y) + z·z).
            let r = Vec4::ONE / ((x * x + y * y) + z * z).sqrt();
            let (x, y, z) = (x * r, y * r, z * r);
            for (k, o) in out.iter_mut().enumerate() {
                *o = Ray::new(self.from, Vec3::new(x[k], y[k], z[k])).at_time(time);
            }
        }
        for (o, &(x, y)) in out[rest..n].iter_mut().zip(&px[rest..n]) {
            *o = self.ray(x, y).at_time(time);
        }
    }

    /// The pyramid of the camera rays through the image rectangle
    /// `x0..x1` by `y0..y1` (in pixels from the top-left corner): a box it
    /// `misses` no such ray can meet. Given the pixels' whole squares, it
    /// holds for the rays through their centres, half a pixel inside.
    /// `None` with a lens, whose rays leave from elsewhere than the eye.
    pub fn pyramid(&self, (x0, y0, x1, y1): (f32, f32, f32, f32)) -> Option<Pyramid> {
        if self.lens.is_some() {
            return None;
        }
        // (In `Vec3A`, whose fourth lane is a copy of z: packed `Vec3`
        // arithmetic left garbage there, whose denormals took a microcode
        // assist each, a third of this test's time.)
        let (corner, dx, dy) =
            (Vec3A::from(self.corner), Vec3A::from(self.dx), Vec3A::from(self.dy));
        let dir = |x: f32, y: f32| corner + dx * x + dy * y;
        let edges = [dir(x0, y0), dir(x1, y0), dir(x1, y1), dir(x0, y1)];
        let centre = dir(0.5 * (x0 + x1), 0.5 * (y0 + y1));
        let planes = std::array::from_fn(|k| {
            let n = edges[k].cross(edges[(k + 1) % 4]);
            if n.dot(centre) < 0.0 { -n } else { n }
        });
        Some(Pyramid { planes, from: self.from.into() })
    }

    /// The primary ray through the image point (px, py), in pixels from
    /// the top-left corner (pixel centres are at half-integers).
    pub fn ray_at(&self, px: f32, py: f32) -> Ray {
        let dir = self.corner + self.dx * px + self.dy * py;
        Ray::new(self.from, dir.normalize())
    }
}

/// The rays of a pinhole camera through a rectangle of the image: the
/// four planes through the eye and the rectangle's edges, their normals
/// turned inward (`Camera::pyramid`).
pub struct Pyramid {
    planes: [Vec3A; 4],
    from: Vec3A,
}

impl Pyramid {
    /// Whether the box `lo..hi` lies wholly outside one of the planes,
    /// with a margin of 10⁻⁵ radians, a hundred times the rounding of a
    /// ray's own direction.
    #[inline]
    pub fn misses(&self, lo: Vec3A, hi: Vec3A) -> bool {
        self.planes.iter().any(|&n| {
            // The box's corner farthest along n, from the eye.
            let far = Vec3A::select(n.cmpgt(Vec3A::ZERO), hi, lo) - self.from;
            // (Squared: d < -10⁻⁵·|n|·|far|, without the roots.)
            let d = n.dot(far);
            d < 0.0 && d * d > 1e-10 * n.length_squared() * far.length_squared()
        })
    }
}

/// Shirley and Chiu's concentric map of the unit square onto the unit
/// disc (areas kept, strata kept compact).
fn concentric_disc(u: f32, v: f32) -> (f32, f32) {
    let (a, b) = (2.0 * u - 1.0, 2.0 * v - 1.0);
    if a == 0.0 && b == 0.0 {
        return (0.0, 0.0);
    }
    let q = std::f32::consts::FRAC_PI_4;
    let (r, phi) = if a.abs() > b.abs() { (a, q * (b / a)) } else { (b, 2.0 * q - q * (a / b)) };
    (r * phi.cos(), r * phi.sin())
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

    /// A block whose pyramid misses a box has no pixel whose ray enters the
    /// box (an exact slab test in double precision); boxes in front, to
    /// the side, behind and around the eye, blocks of one pixel to 8×8;
    /// and it does pass over most blocks that miss.
    #[test]
    fn blocks_passed_over_miss_the_box() {
        let mut seed = 7u64;
        let mut rnd = || {
            seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            (seed >> 40) as f32 / (1u64 << 24) as f32
        };
        let enters = |r: &Ray, lo: Vec3, hi: Vec3| {
            let (mut t0, mut t1) = (0.0f64, f64::INFINITY);
            for a in 0..3 {
                let (o, d) = (r.origin[a] as f64, r.dir[a] as f64);
                let (l, h) = ((lo[a] as f64 - o) / d, (hi[a] as f64 - o) / d);
                t0 = t0.max(l.min(h));
                t1 = t1.min(l.max(h));
            }
            t0 <= t1
        };
        let (mut passed, mut missing) = (0, 0);
        for k in 0..400 {
            let from = Vec3::new(rnd(), rnd(), rnd()) * 4.0 - 2.0;
            let to = from + Vec3::new(rnd() - 0.5, rnd() - 0.5, -1.0);
            let cam = Camera::new(from, to - from, Vec3::Y, 20.0 + 60.0 * rnd(), 64, 48).unwrap();
            let c = Vec3::new(rnd() - 0.5, rnd() - 0.5, rnd() - 0.5) * 6.0 + (to - from) * 3.0;
            let h = Vec3::new(rnd(), rnd(), rnd()) * [0.05, 0.5, 3.0][k % 3];
            let (lo, hi) = (from + c - h, from + c + h);
            for by in (0..48u32).step_by(8) {
                for bx in (0..64u32).step_by(8) {
                    let size = [1, 3, 8][((bx / 8 + by / 8) % 3) as usize];
                    let mut pixels =
                        (by..by + size).flat_map(|y| (bx..bx + size).map(move |x| (x, y)));
                    let hit = pixels.any(|(x, y)| enters(&cam.ray(x, y), lo, hi));
                    let rect = (bx as f32, by as f32, (bx + size) as f32, (by + size) as f32);
                    let over = cam.pyramid(rect).is_some_and(|p| p.misses(lo.into(), hi.into()));
                    assert!(!(over && hit), "camera {k}, block at ({bx}, {by})");
                    missing += !hit as u32;
                    passed += over as u32;
                }
            }
        }
        assert!(passed * 10 > missing * 8, "{passed} of {missing}");
    }

    #[test]
    fn rays_four_at_a_time_are_single_rays_to_the_bit() {
        let bits = |r: &Ray| {
            (r.origin.to_array().map(f32::to_bits), r.dir.to_array().map(f32::to_bits), r.time)
        };
        let cams = [
            Camera::new(
                Vec3::new(1.0, 2.0, 3.0),
                Vec3::new(-4.0, 0.5, -2.0),
                Vec3::Y,
                60.0,
                101,
                51,
            ),
            Camera::new(
                Vec3::new(-7.3, 1e3, 0.1),
                Vec3::new(3.0, -2.0, 9.0),
                Vec3::Z,
                13.0,
                1920,
                1080,
            ),
        ];
        for c in cams.into_iter().map(Option::unwrap) {
            // Pixels spread over the picture, in lists of every length
            // from 0 to 9 (whole quads and leftovers).
            let px: Vec<(u32, u32)> =
                (0..9u32).map(|k| ((k * 97 + 13) % c.width, (k * 61 + 7) % c.height)).collect();
            for n in 0..=px.len() {
                let mut out = vec![Ray::new(Vec3::NAN, Vec3::NAN); n];
                c.rays_into(&px[..n], 0.25, &mut out);
                for (o, &(x, y)) in out.iter().zip(&px[..n]) {
                    assert_eq!(bits(o), bits(&c.ray(x, y).at_time(0.25)), "pixel {x} {y}");
                }
            }
        }
    }

    #[test]
    fn up_parallel_is_refused() {
        assert!(Camera::new(Vec3::ZERO, Vec3::Y, Vec3::Y, 45.0, 10, 10).is_none());
    }

    #[test]
    fn a_lens_focuses_on_its_plane() {
        let c = Camera::new(Vec3::ZERO, Vec3::NEG_Z, Vec3::Y, 90.0, 100, 100).unwrap();
        let c = c.with_lens(0.5, 4.0);
        // Every lens point's ray through pixel (30, 60) meets the pinhole
        // ray at depth 4.
        let p = c.ray_at(30.5, 60.5);
        let want = p.dir * (4.0 / -p.dir.z);
        for (u, v) in [(0.1, 0.9), (0.5, 0.5), (0.99, 0.2), (0.3, 0.3)] {
            let r = c.lens_ray(30.5, 60.5, u, v);
            assert!(r.origin.length() <= 0.5 + 1e-6 && r.origin.z == 0.0);
            let t = (want.z - r.origin.z) / r.dir.z;
            assert!((r.origin + r.dir * t - want).length() < 1e-4);
        }
        let (x, y) = concentric_disc(1.0, 0.5);
        assert!((x - 1.0).abs() < 1e-6 && y.abs() < 1e-6);
    }
}
