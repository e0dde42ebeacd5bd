//! Fractals generated lazily, as rays reach them: no sphere or cube is
//! stored, so any depth renders in the memory of one.
//!
//! - `Flake`: Haines' sphereflake with the layout of the SPD `balls`
//!   generator: each sphere carries nine of a third its radius, six around
//!   its equator and three above, pointing away from its parent.
//! - `Menger`: the Menger sponge: a cube split into 27, of which the
//!   centre and the six face centres are removed, recursively.

use glam::{DMat3, DVec3, Vec3};

use super::solid::Solid;
use super::{Aabb, Ray, intersect_sphere};

/// The nine directions of a sphere's children around +z (the SPD `balls`
/// generator's `objset`): three unit vectors at 45° tipped up by
/// asin(2/√6) about (1, −1, 0), then turned by 0°, 120° and 240° about z.
fn child_directions() -> [DVec3; 9] {
    let d = 1.0 / 2f64.sqrt();
    let trio = [DVec3::new(d, d, 0.0), DVec3::new(d, 0.0, -d), DVec3::new(0.0, d, -d)];
    let tip =
        DMat3::from_axis_angle(DVec3::new(1.0, -1.0, 0.0).normalize(), (2.0 / 6f64.sqrt()).asin());
    let mut out = [DVec3::ZERO; 9];
    for set in 0..3 {
        let turn = DMat3::from_rotation_z(set as f64 * 2.0 * std::f64::consts::PI / 3.0);
        for k in 0..3 {
            out[set * 3 + k] = turn * (tip * trio[k]);
        }
    }
    out
}

/// The rotation taking +z to `dir` (a unit vector).
fn from_z(dir: DVec3) -> DMat3 {
    if dir.z >= 1.0 {
        DMat3::IDENTITY
    } else if dir.z <= -1.0 {
        DMat3::from_rotation_y(std::f64::consts::PI)
    } else {
        let axis = DVec3::Z.cross(dir).normalize();
        DMat3::from_axis_angle(axis, dir.z.clamp(-1.0, 1.0).acos())
    }
}

/// The deepest sphereflake or sponge accepted.
pub const MAX_DEPTH: u32 = 10;

#[derive(Clone, Debug)]
pub struct Flake {
    center: DVec3,
    radius: f64,
    depth: u32,
    dirs: [DVec3; 9],
}

/// A sphere of a flake.
#[derive(Clone, Copy, Debug)]
struct Ball {
    center: DVec3,
    radius: f64,
    dir: DVec3,
    depth: u32,
}

impl Flake {
    /// The root sphere, pointing up +z, with `depth` generations of
    /// children (at most `MAX_DEPTH`).
    pub fn new(center: Vec3, radius: f32, depth: u32) -> Flake {
        Flake {
            center: center.as_dvec3(),
            radius: radius as f64,
            depth: depth.min(MAX_DEPTH),
            dirs: child_directions(),
        }
    }

    /// How many spheres: Σ 9^k for k = 0..=depth.
    pub fn count(&self) -> u64 {
        (0..=self.depth).map(|k| 9u64.pow(k)).sum()
    }

    /// The radius of a sphere's whole subtree, `depth` generations deep:
    /// its children's centres are 4r/3 away.
    fn reach(radius: f64, depth: u32) -> f64 {
        if depth == 0 { radius } else { 4.0 * radius / 3.0 + Flake::reach(radius / 3.0, depth - 1) }
    }

    pub fn bounds(&self) -> Aabb {
        let r = Flake::reach(self.radius, self.depth);
        let (lo, hi) = (self.center - r, self.center + r);
        Aabb { min: lo.as_vec3().into(), max: hi.as_vec3().into() }
    }

    fn children(&self, b: &Ball) -> impl Iterator<Item = Ball> + '_ {
        let turn = from_z(b.dir);
        let scale = b.radius * (1.0 + 1.0 / 3.0);
        let (center, radius, depth) = (b.center, b.radius / 3.0, b.depth - 1);
        self.dirs.iter().map(move |&d| {
            let dir = turn * d;
            Ball { center: center + dir * scale, radius, dir, depth }
        })
    }

    fn root(&self) -> Ball {
        Ball { center: self.center, radius: self.radius, dir: DVec3::Z, depth: self.depth }
    }

    /// The nearest sphere hit in `(t_min, t_max)`: its distance and centre.
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, Vec3)> {
        let mut best = None;
        let mut t_max = t_max;
        self.visit(ray, &self.root(), t_min, &mut t_max, &mut best);
        best
    }

    fn visit(
        &self,
        ray: &Ray,
        b: &Ball,
        t_min: f32,
        t_max: &mut f32,
        best: &mut Option<(f32, Vec3)>,
    ) {
        // The subtree's bound first.
        let reach = Flake::reach(b.radius, b.depth) as f32;
        let c = b.center.as_vec3();
        if b.depth > 0 && !reaches(ray, c, reach, t_min, *t_max) {
            return;
        }
        if let Some(t) = intersect_sphere(ray, c, b.radius as f32, t_min, *t_max) {
            *t_max = t;
            *best = Some((t, c));
        }
        if b.depth > 0 {
            for child in self.children(b) {
                self.visit(ray, &child, t_min, t_max, best);
            }
        }
    }

    /// Calls `each(t)` for every crossing of a sphere's surface in
    /// `(t_min, t_max)` (for shadow rays through glass flakes), until it
    /// returns true.
    pub fn crossings(&self, ray: &Ray, t_min: f32, t_max: f32, each: &mut dyn FnMut(f32) -> bool) {
        self.cross(ray, &self.root(), t_min, t_max, each);
    }

    fn cross(
        &self,
        ray: &Ray,
        b: &Ball,
        t_min: f32,
        t_max: f32,
        each: &mut dyn FnMut(f32) -> bool,
    ) -> bool {
        let c = b.center.as_vec3();
        if !reaches(ray, c, Flake::reach(b.radius, b.depth) as f32, t_min, t_max) {
            return false;
        }
        let mut from = t_min;
        while let Some(t) = intersect_sphere(ray, c, b.radius as f32, from, t_max) {
            if each(t) {
                return true;
            }
            from = t;
        }
        b.depth > 0 && self.children(b).any(|child| self.cross(ray, &child, t_min, t_max, each))
    }
}

/// Whether the ray passes within `r` of `c` somewhere in `(t_min, t_max)`.
fn reaches(ray: &Ray, c: Vec3, r: f32, t_min: f32, t_max: f32) -> bool {
    let f = ray.origin - c;
    let a = ray.dir.length_squared();
    let b = f.dot(ray.dir);
    let cc = f.length_squared() - r * r;
    if cc <= 0.0 {
        return true; // starts inside
    }
    let disc = b * b - a * cc;
    if disc < 0.0 {
        return false;
    }
    let s = disc.sqrt();
    let (t0, t1) = ((-b - s) / a, (-b + s) / a);
    t1 > t_min && t0 < t_max
}

#[derive(Clone, Debug)]
pub struct Menger {
    center: Vec3,
    half: f32,
    depth: u32,
}

/// The 20 cells of 27 that a sponge keeps: those with at most one
/// coordinate in the middle.
fn kept() -> impl Iterator<Item = [i32; 3]> {
    (0..27)
        .map(|k| [k % 3 - 1, k / 3 % 3 - 1, k / 9 - 1])
        .filter(|c| c.iter().filter(|&&x| x == 0).count() <= 1)
}

impl Menger {
    /// The sponge filling the cube of edge `size` centred at `center`.
    pub fn new(center: Vec3, size: f32, depth: u32) -> Menger {
        Menger { center, half: size / 2.0, depth: depth.min(MAX_DEPTH) }
    }

    /// How many cubes: 20^depth.
    pub fn count(&self) -> u64 {
        20u64.pow(self.depth)
    }

    pub fn bounds(&self) -> Aabb {
        let h = Vec3::splat(self.half);
        Aabb { min: (self.center - h).into(), max: (self.center + h).into() }
    }

    /// The nearest cube face hit in `(t_min, t_max)`: its distance and the
    /// face (`Solid::Box` parts: 2·axis, +1 on the high side).
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, u32)> {
        let mut best = None;
        let mut t_max = t_max;
        self.visit(ray, self.center, self.half, self.depth, t_min, &mut t_max, &mut best);
        best
    }

    #[allow(clippy::too_many_arguments)]
    fn visit(
        &self,
        ray: &Ray,
        c: Vec3,
        half: f32,
        depth: u32,
        t_min: f32,
        t_max: &mut f32,
        best: &mut Option<(f32, u32)>,
    ) {
        let cube = Solid::Box { min: Vec3::splat(-half), max: Vec3::splat(half) };
        let local = Ray { origin: ray.origin - c, ..*ray };
        let cr = cube.crossings(&local);
        let (Some(enter), Some(leave)) = (cr.as_slice().first(), cr.as_slice().get(1)) else {
            return;
        };
        if leave.t <= t_min || enter.t >= *t_max {
            return;
        }
        if depth == 0 {
            if enter.t > t_min {
                *t_max = enter.t;
                *best = Some((enter.t, enter.part));
            } else if leave.t < *t_max {
                // From inside a cube (only a ray starting in one): its exit.
                *t_max = leave.t;
                *best = Some((leave.t, leave.part));
            }
            return;
        }
        // The kept cells, nearest entry first; stop past the best hit.
        let third = half / 3.0;
        let mut cells: Vec<(f32, Vec3)> = kept()
            .map(|k| c + Vec3::new(k[0] as f32, k[1] as f32, k[2] as f32) * (2.0 * third))
            .filter_map(|cc| {
                let b = Solid::Box { min: Vec3::splat(-third), max: Vec3::splat(third) };
                let x = b.crossings(&Ray { origin: ray.origin - cc, ..*ray });
                let s = x.as_slice();
                (s.len() == 2 && s[1].t > t_min).then(|| (s[0].t, cc))
            })
            .collect();
        cells.sort_by(|a, b| a.0.total_cmp(&b.0));
        for (t, cc) in cells {
            if t >= *t_max {
                break;
            }
            self.visit(ray, cc, third, depth - 1, t_min, t_max, best);
        }
    }

    /// Calls `each(t)` for every crossing of a cube's surface in
    /// `(t_min, t_max)`, until it returns true.
    pub fn crossings(&self, ray: &Ray, t_min: f32, t_max: f32, each: &mut dyn FnMut(f32) -> bool) {
        self.cross(ray, self.center, self.half, self.depth, (t_min, t_max), each);
    }

    fn cross(
        &self,
        ray: &Ray,
        c: Vec3,
        half: f32,
        depth: u32,
        (t_min, t_max): (f32, f32),
        each: &mut dyn FnMut(f32) -> bool,
    ) -> bool {
        let cube = Solid::Box { min: Vec3::splat(-half), max: Vec3::splat(half) };
        let x = cube.crossings(&Ray { origin: ray.origin - c, ..*ray });
        let s = x.as_slice();
        if s.len() < 2 || s[1].t <= t_min || s[0].t >= t_max {
            return false;
        }
        if depth == 0 {
            return s.iter().any(|x| x.t > t_min && x.t < t_max && each(x.t));
        }
        let third = half / 3.0;
        kept().any(|k| {
            let cc = c + Vec3::new(k[0] as f32, k[1] as f32, k[2] as f32) * (2.0 * third);
            self.cross(ray, cc, third, depth - 1, (t_min, t_max), each)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first two generations sit where the SPD `balls` generator puts
    /// them (its balls-s3.nff: "s 0.272166 0.272166 0.544331 0.166667",
    /// then that sphere's first child at 0.420314 0.420314 0.618405).
    #[test]
    fn flakes_follow_the_spd_layout() {
        let f = Flake::new(Vec3::ZERO, 0.5, 3);
        assert_eq!(f.count(), 820);
        let kids: Vec<Ball> = f.children(&f.root()).collect();
        let first = kids[0];
        assert!((first.center - DVec3::new(0.272166, 0.272166, 0.544331)).length() < 1e-6);
        assert!((first.radius - 0.166667).abs() < 1e-6);
        let grand = f.children(&first).next().unwrap();
        assert!((grand.center - DVec3::new(0.420314, 0.420314, 0.618405)).length() < 1e-6);
        // Every child touches its parent.
        for k in &kids {
            assert!(((k.center - f.center).length() - 0.5 * 4.0 / 3.0).abs() < 1e-12);
        }
    }

    /// The lazy walk finds what testing every sphere finds.
    #[test]
    fn flakes_hit_what_brute_force_hits() {
        let f = Flake::new(Vec3::new(0.1, -0.2, 0.3), 0.5, 3);
        let mut all = Vec::new();
        let mut stack = vec![f.root()];
        while let Some(b) = stack.pop() {
            all.push(b);
            if b.depth > 0 {
                stack.extend(f.children(&b));
            }
        }
        assert_eq!(all.len(), 820);
        for k in 0..500 {
            let a = k as f32 * 0.37;
            let o = Vec3::new(3.0 * a.cos(), 3.0 * a.sin(), 1.5 * (a * 0.3).sin());
            let target = Vec3::new(0.1 + 0.6 * (a * 1.7).sin(), -0.2 + 0.6 * (a * 2.3).cos(), 0.5);
            let ray = Ray::new(o, target - o);
            let brute = all
                .iter()
                .filter_map(|b| {
                    intersect_sphere(&ray, b.center.as_vec3(), b.radius as f32, 0.0, f32::INFINITY)
                })
                .fold(f32::INFINITY, f32::min);
            let lazy = f.intersect(&ray, 0.0, f32::INFINITY).map_or(f32::INFINITY, |h| h.0);
            assert_eq!(lazy, brute, "ray {k}");
        }
    }

    /// A sponge of depth 1 is its 20 cubes.
    #[test]
    fn sponges_hit_what_their_cubes_hit() {
        let m = Menger::new(Vec3::ZERO, 3.0, 1);
        assert_eq!(m.count(), 20);
        let cubes: Vec<Vec3> =
            kept().map(|k| Vec3::new(k[0] as f32, k[1] as f32, k[2] as f32)).collect();
        assert_eq!(cubes.len(), 20);
        for k in 0..500 {
            let a = k as f32 * 0.41;
            let o = Vec3::new(5.0 * a.cos(), 4.0 * (a * 0.7).sin(), 5.0 * a.sin());
            let target =
                Vec3::new(1.4 * (a * 1.3).sin(), 1.4 * (a * 2.9).cos(), 1.4 * (a * 0.5).sin());
            let ray = Ray::new(o, target - o);
            let brute = cubes
                .iter()
                .filter_map(|&c| {
                    let b = Solid::Box { min: c - 0.5, max: c + 0.5 };
                    b.crossings(&ray).first_in(0.0, f32::INFINITY).map(|x| x.t)
                })
                .fold(f32::INFINITY, f32::min);
            let lazy = m.intersect(&ray, 0.0, f32::INFINITY).map_or(f32::INFINITY, |h| h.0);
            assert!(
                (lazy - brute).abs() <= 1e-5 * brute.abs().max(1.0) || lazy == brute,
                "ray {k}: {lazy} vs {brute}"
            );
        }
        // Down the middle of a face's centre: the hole goes through.
        let through = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
        assert!(m.intersect(&through, 0.0, f32::INFINITY).is_none());
    }
}
