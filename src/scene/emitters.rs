//! What a path tracer samples light from (issue "global illumination"):
//! the scene's lights, its emitting triangles and spheres, and the
//! environment, each chosen in proportion to its power; and the
//! environment itself, a constant or an equirectangular map sampled by
//! its luminance (a constant is a 1×1 map: uniform over the sphere).
//!
//! Every sample comes with its probability density per unit solid angle,
//! and each kind can give the density of a direction found otherwise (a
//! BSDF sample that hit it), for multiple importance sampling.

use std::f32::consts::{PI, TAU};

use glam::{DVec3, Vec3};

use super::builder::{Builder, Prim};
use super::light::Light;
pub use super::light::orthonormal;
use super::objects::{LeafDef, ObjKind};

/// The light arriving at a point from one sample of an emitter.
#[derive(Clone, Copy, Debug)]
pub struct LightSample {
    /// The unit direction towards it, and how far (infinite: the sky).
    pub dir: Vec3,
    pub dist: f32,
    /// Radiance, or for point, spot and parallel lights the COS 426
    /// number (1/π of the radiometric quantity: see the README's units).
    pub li: Vec3,
    /// The density per unit solid angle (with the choice of this emitter
    /// among all); 0 for the lights that are points or directions.
    pub pdf: f32,
}

#[derive(Clone, Debug)]
pub enum Emitter {
    Light(Light),
    /// An emitting triangle (eye-relative), emitting from the side `normal`
    /// (unit) points to.
    Triangle {
        p: [Vec3; 3],
        normal: Vec3,
        emission: Vec3,
    },
    Sphere {
        center: Vec3,
        radius: f32,
        emission: Vec3,
    },
    Sky,
}

/// The emitters and the distribution they are chosen by.
#[derive(Clone, Debug, Default)]
pub struct LightSet {
    pub items: Vec<Emitter>,
    /// Running sums of the items' powers, normalized to end at 1.
    cdf: Vec<f32>,
    total: f32,
    /// Per material: whether every surface of it that emits is among
    /// `items` (so that a hit on one has a light density).
    pub sampled: Vec<bool>,
    /// Per light of the scene: the chance it is chosen.
    pub light_prob: Vec<f32>,
    /// The chance the sky is chosen.
    pub sky_prob: f32,
}

/// The mean of a colour's channels: the power measure lights are chosen by
/// (never zero for a colour that is not black).
fn mean(c: Vec3) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

impl LightSet {
    /// The lights, the emitting still triangles and spheres at the scene's
    /// top level (relative to the eye), and the sky. Emitting surfaces
    /// elsewhere (moving, in objects or instances) are found by paths
    /// alone; their materials are marked unsampled.
    pub fn build(b: &Builder, sky: &Sky, radius: f32) -> LightSet {
        let origin = b.from;
        let emits = |m: u32| b.materials[m as usize].emission != Vec3::ZERO;
        let mut sampled: Vec<bool> = b.materials.iter().map(|m| m.emission != Vec3::ZERO).collect();
        let mut unsample = |m: u32| {
            if let Some(s) = sampled.get_mut(m as usize) {
                *s = false;
            }
        };
        // Moving primitives.
        let mut still = vec![true; b.prims.len()];
        for (k, &(first, v)) in b.motion.iter().enumerate() {
            let end = b.motion.get(k + 1).map_or(b.prims.len(), |m| m.0 as usize);
            if v != DVec3::ZERO {
                still[first as usize..end].iter_mut().for_each(|s| *s = false);
            }
        }
        let prim_material = |p: &Prim| match *p {
            Prim::Tri { material, .. }
            | Prim::MeshTri { material, .. }
            | Prim::Sphere { material, .. }
            | Prim::Cone { material, .. } => material,
        };
        for (p, _) in b.prims.iter().zip(&still).filter(|(_, s)| !**s) {
            unsample(prim_material(p));
        }
        let mut objects: Vec<&ObjKind> = b.objects.iter().map(|o| &o.kind).collect();
        for g in &b.groups {
            g.prims.iter().for_each(|p| unsample(prim_material(p)));
            objects.extend(g.objects.iter().map(|o| &o.kind));
        }
        for kind in objects {
            match kind {
                ObjKind::Solid { material, .. }
                | ObjKind::Blob { material, .. }
                | ObjKind::Flake { material, .. }
                | ObjKind::Menger { material, .. } => unsample(*material),
                ObjKind::Csg { leaves, .. } => {
                    for leaf in leaves {
                        unsample(leaf.material);
                        if let LeafDef::Mesh(prims) = &leaf.shape {
                            prims.iter().for_each(|p| unsample(prim_material(p)));
                        }
                    }
                }
                ObjKind::Instance(_) => {}
            }
        }
        let mut items = Vec::new();
        let mut power = Vec::new();
        let scene_area = PI * radius * radius;
        for l in &b.lights {
            let l = l.relative_to(origin);
            power.push(match l {
                Light::Parallel { color, .. } => mean(color) * PI * scene_area,
                // A light that does not fall off as 1/r² weighs as much as
                // it lights the scene's edge.
                Light::Point { color, falloff, .. } | Light::Spot { color, falloff, .. } => {
                    let edge = radius * radius / falloff.at(radius, radius * radius);
                    let edge = if edge > 0.0 && edge.is_finite() { edge } else { 1.0 };
                    mean(color) * PI * 4.0 * PI * edge
                }
                Light::Area { radiance, u, v, .. } => mean(radiance) * PI * u.cross(v).length(),
                Light::Sphere { radiance, radius, .. } => {
                    mean(radiance) * PI * 4.0 * PI * radius * radius
                }
            });
            items.push(Emitter::Light(l));
        }
        let lights = items.len();
        for (i, p) in b.prims.iter().enumerate() {
            let m = prim_material(p);
            if !still[i] || !emits(m) || !sampled[m as usize] {
                continue;
            }
            let emission = b.materials[m as usize].emission;
            match b.shape_of(p, origin) {
                crate::geometry::Shape::Triangle(t) if t.has_area() => {
                    let cross = t.cross();
                    let mut normal = cross.normalize();
                    if t.normals[0] != crate::geometry::Triangle::FLAT {
                        let n: Vec3 = t.normals.iter().map(|&i| b.normals[i as usize]).sum();
                        if normal.dot(n) < 0.0 {
                            normal = -normal;
                        }
                    }
                    power.push(mean(emission) * PI * 0.5 * cross.length());
                    items.push(Emitter::Triangle { p: t.p, normal, emission });
                }
                crate::geometry::Shape::Sphere { center, radius, .. } if radius > 0.0 => {
                    power.push(mean(emission) * PI * 4.0 * PI * radius * radius);
                    items.push(Emitter::Sphere { center, radius, emission });
                }
                _ => {}
            }
        }
        let sky_power = mean(sky.mean) * PI * scene_area;
        if sky_power > 0.0 {
            power.push(sky_power);
            items.push(Emitter::Sky);
        }
        let mut cdf = Vec::with_capacity(power.len());
        let mut total = 0.0f64;
        for p in &power {
            total += (*p).max(0.0) as f64;
            cdf.push(total as f32);
        }
        let total = total as f32;
        if total > 0.0 && total.is_finite() {
            cdf.iter_mut().for_each(|c| *c /= total);
        } else {
            // Nothing with power (or too much to add up): evenly.
            let n = cdf.len() as f32;
            cdf.iter_mut().enumerate().for_each(|(i, c)| *c = (i + 1) as f32 / n);
        }
        let prob = |i: usize| cdf[i] - if i == 0 { 0.0 } else { cdf[i - 1] };
        let light_prob = (0..lights).map(prob).collect();
        let sky_prob = if sky_power > 0.0 { prob(items.len() - 1) } else { 0.0 };
        LightSet { items, cdf, total, sampled, light_prob, sky_prob }
    }

    pub fn is_empty(&self) -> bool {
        self.items.is_empty()
    }

    /// Item `i` of the distribution for `u` in [0, 1), with its chance.
    pub fn pick(&self, u: f32) -> Option<(usize, f32)> {
        if self.items.is_empty() {
            return None;
        }
        let i = self.cdf.partition_point(|&c| c <= u).min(self.items.len() - 1);
        Some((i, self.cdf[i] - if i == 0 { 0.0 } else { self.cdf[i - 1] }))
    }

    /// The chance of choosing an emitting surface of `area` and `emission`
    /// (among `items` by the rule `build` used).
    pub fn surface_prob(&self, emission: Vec3, area: f32) -> f32 {
        if self.total > 0.0 && self.total.is_finite() {
            mean(emission) * PI * area / self.total
        } else {
            1.0 / self.items.len().max(1) as f32
        }
    }
}

/// Samples emitter `e` (chosen with chance `prob`) from point `p` with
/// the unit-square point `(a, b)`; `None` if it sends nothing there.
pub fn sample(
    e: &Emitter,
    sky: &Sky,
    p: Vec3,
    prob: f32,
    (a, b): (f32, f32),
) -> Option<LightSample> {
    match *e {
        Emitter::Light(Light::Area { radiance, corner, u, v, .. }) => {
            let q = corner.as_vec3() + u * a + v * b;
            let normal = u.cross(v);
            let area = normal.length();
            toward_area(p, q, normal / area, area, radiance, prob)
        }
        Emitter::Light(Light::Sphere { radiance, center, radius, .. }) => {
            toward_sphere(p, center.as_vec3(), radius, radiance, prob, (a, b))
        }
        Emitter::Light(l) => {
            let (dir, dist, li) = l.at(p);
            (li != Vec3::ZERO).then_some(LightSample { dir, dist, li: li / prob, pdf: 0.0 })
        }
        Emitter::Triangle { p: v, normal, emission } => {
            let s = a.sqrt();
            let (b0, b1) = (1.0 - s, b * s);
            let q = v[0] * b0 + v[1] * b1 + v[2] * (1.0 - b0 - b1);
            let area = 0.5 * (v[1] - v[0]).cross(v[2] - v[0]).length();
            toward_area(p, q, normal, area, emission, prob)
        }
        Emitter::Sphere { center, radius, emission } => {
            toward_sphere(p, center, radius, emission, prob, (a, b))
        }
        Emitter::Sky => {
            let (dir, li, pdf) = sky.sample((a, b))?;
            Some(LightSample { dir, dist: f32::INFINITY, li, pdf: pdf * prob })
        }
    }
}

/// Towards point `q` of a flat emitter of `area` facing `normal`.
fn toward_area(
    p: Vec3,
    q: Vec3,
    normal: Vec3,
    area: f32,
    radiance: Vec3,
    prob: f32,
) -> Option<LightSample> {
    let d = q - p;
    let r2 = d.length_squared();
    let dist = r2.sqrt();
    let dir = d / dist;
    let cos_l = -dir.dot(normal);
    if !(cos_l > 0.0 && r2 > 0.0 && area > 0.0) {
        return None;
    }
    let pdf = prob * r2 / (area * cos_l);
    pdf.is_finite().then_some(LightSample { dir, dist, li: radiance, pdf })
}

/// Towards a sphere, uniformly over the cone it fills seen from `p`.
fn toward_sphere(
    p: Vec3,
    center: Vec3,
    radius: f32,
    radiance: Vec3,
    prob: f32,
    (a, b): (f32, f32),
) -> Option<LightSample> {
    let dc = center - p;
    let dist_c = dc.length();
    if dist_c <= radius {
        return None;
    }
    let w = dc / dist_c;
    let cos_max = (1.0 - (radius / dist_c).powi(2)).max(0.0).sqrt();
    let cos_t = 1.0 - a * (1.0 - cos_max);
    let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
    let phi = TAU * b;
    let (t1, t2) = orthonormal(w);
    let dir = (t1 * (sin_t * phi.cos()) + t2 * (sin_t * phi.sin()) + w * cos_t).normalize();
    let along = dist_c * cos_t;
    let dist = along - (radius * radius - dist_c * dist_c * sin_t * sin_t).max(0.0).sqrt();
    let pdf = prob * cone_pdf(cos_max);
    pdf.is_finite().then_some(LightSample { dir, dist, li: radiance, pdf })
}

/// The density of uniform directions in a cone of half-angle acos(cos_max).
pub fn cone_pdf(cos_max: f32) -> f32 {
    1.0 / (TAU * (1.0 - cos_max)).max(f32::MIN_POSITIVE)
}

/// The density `toward_sphere` gives a direction to a sphere seen from
/// `p` (0 from inside it).
pub fn sphere_pdf(p: Vec3, center: Vec3, radius: f32) -> f32 {
    let dist_c = (center - p).length();
    if dist_c <= radius {
        return 0.0;
    }
    cone_pdf((1.0 - (radius / dist_c).powi(2)).max(0.0).sqrt())
}

/// The light from every direction nothing blocks: an equirectangular map
/// of radiance, u = atan2(−z, x)/2π around the y axis (as the `spherical`
/// texture mapping), v the latitude from the bottom; piecewise constant
/// per texel, each texel chosen by its luminance times its solid angle,
/// then a direction uniformly within it.
#[derive(Clone, Debug)]
pub struct Sky {
    w: u32,
    h: u32,
    px: Vec<Vec3>,
    /// The rows' running sums, and each row's columns', normalized.
    rows: Vec<f32>,
    cols: Vec<f32>,
    /// Each texel's chance.
    prob: Vec<f32>,
    /// The mean radiance over the sphere.
    pub mean: Vec3,
}

impl Sky {
    /// A constant radiance from everywhere.
    pub fn constant(c: Vec3) -> Sky {
        Sky::map(1, 1, vec![c])
    }

    /// cos θ at the top of row `j` (θ from +y).
    fn cos_top(&self, j: usize) -> f32 {
        (PI * j as f32 / self.h as f32).cos()
    }

    /// The solid angle of a texel of row `j`.
    fn texel_solid_angle(&self, j: usize) -> f32 {
        TAU / self.w as f32 * (self.cos_top(j) - self.cos_top(j + 1))
    }

    /// A map of `w`×`h` texels, row by row from the top.
    pub fn map(w: u32, h: u32, px: Vec<Vec3>) -> Sky {
        let mut sky = Sky {
            w,
            h,
            px,
            rows: Vec::new(),
            cols: Vec::new(),
            prob: Vec::new(),
            mean: Vec3::ZERO,
        };
        let (wu, hu) = (w as usize, h as usize);
        let mut cols = vec![0.0f32; wu * hu];
        let mut weights = vec![0.0f64; wu * hu];
        let mut row_sums = vec![0.0f64; hu];
        let mut mean_c = glam::DVec3::ZERO;
        for j in 0..hu {
            let omega = sky.texel_solid_angle(j) as f64;
            let mut acc = 0.0f64;
            for i in 0..wu {
                let c = sky.px[j * wu + i];
                mean_c += c.as_dvec3() * omega;
                let wgt = mean(c).max(0.0) as f64 * omega;
                weights[j * wu + i] = wgt;
                acc += wgt;
                cols[j * wu + i] = acc as f32;
            }
            row_sums[j] = acc;
            if acc > 0.0 {
                cols[j * wu..(j + 1) * wu].iter_mut().for_each(|c| *c /= acc as f32);
            }
        }
        let total: f64 = row_sums.iter().sum();
        let mut acc = 0.0f64;
        for s in &row_sums {
            acc += s;
            sky.rows.push(if total > 0.0 { (acc / total) as f32 } else { 0.0 });
        }
        sky.prob =
            weights.iter().map(|w| if total > 0.0 { (w / total) as f32 } else { 0.0 }).collect();
        sky.cols = cols;
        sky.mean = (mean_c / (4.0 * std::f64::consts::PI)).as_vec3();
        sky
    }

    /// The texel a unit direction falls in.
    fn texel(&self, d: Vec3) -> (usize, usize) {
        let u = {
            let a = (-d.z).atan2(d.x) / TAU;
            if a < 0.0 { a + 1.0 } else { a }
        };
        let theta = d.y.clamp(-1.0, 1.0).acos();
        let i = ((u * self.w as f32) as usize).min(self.w as usize - 1);
        let j = ((theta / PI * self.h as f32) as usize).min(self.h as usize - 1);
        (i, j)
    }

    /// The radiance arriving from direction `d` (unit).
    pub fn radiance(&self, d: Vec3) -> Vec3 {
        let (i, j) = self.texel(d);
        self.px[j * self.w as usize + i]
    }

    /// The density `sample` gives direction `d`, per unit solid angle.
    pub fn pdf(&self, d: Vec3) -> f32 {
        let (i, j) = self.texel(d);
        self.prob[j * self.w as usize + i] / self.texel_solid_angle(j)
    }

    /// A direction by the map's luminance: (direction, radiance, density).
    pub fn sample(&self, (a, b): (f32, f32)) -> Option<(Vec3, Vec3, f32)> {
        let (w, h) = (self.w as usize, self.h as usize);
        if self.rows.last().is_none_or(|&t| t <= 0.0) {
            return None;
        }
        let j = self.rows.partition_point(|&c| c <= b).min(h - 1);
        let lo = if j == 0 { 0.0 } else { self.rows[j - 1] };
        let fb = ((b - lo) / (self.rows[j] - lo)).clamp(0.0, 1.0);
        let row = &self.cols[j * w..(j + 1) * w];
        let i = row.partition_point(|&c| c <= a).min(w - 1);
        let lo = if i == 0 { 0.0 } else { row[i - 1] };
        let fa = ((a - lo) / (row[i] - lo)).clamp(0.0, 1.0);
        let phi = TAU * (i as f32 + fa) / w as f32;
        // Uniform in cos θ across the row: uniform in solid angle.
        let (c0, c1) = (self.cos_top(j), self.cos_top(j + 1));
        let cos = c0 + (c1 - c0) * fb;
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let d = Vec3::new(sin * phi.cos(), cos, -sin * phi.sin());
        let pdf = self.prob[j * w + i] / self.texel_solid_angle(j);
        (pdf > 0.0 && pdf.is_finite()).then(|| (d, self.px[j * w + i], pdf))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A map's density integrates to 1 over the sphere and agrees with
    /// its samples; a constant sky samples the sphere uniformly.
    #[test]
    fn sky_densities_integrate_to_one_and_match_samples() {
        let px: Vec<Vec3> = (0..8 * 4).map(|k| Vec3::splat(1.0 + (k % 5) as f32)).collect();
        let sky = Sky::map(8, 4, px);
        // ∫ pdf dω by a fine grid over (θ, φ).
        let n = 400;
        let mut total = 0.0f64;
        for j in 0..n {
            let theta = PI * (j as f32 + 0.5) / n as f32;
            for i in 0..n {
                let phi = TAU * (i as f32 + 0.5) / n as f32;
                let d = Vec3::new(theta.sin() * phi.cos(), theta.cos(), -theta.sin() * phi.sin());
                let dw = (PI / n as f32) * (TAU / n as f32) * theta.sin();
                total += (sky.pdf(d) * dw) as f64;
            }
        }
        assert!((total - 1.0).abs() < 0.01, "∫pdf = {total}");
        for k in 0..200 {
            let u = ((k as f32 + 0.5) / 200.0, ((k * 7919) % 200) as f32 / 200.0 + 0.0025);
            let (d, c, pdf) = sky.sample(u).unwrap();
            assert!((d.length() - 1.0).abs() < 1e-4);
            assert!((sky.pdf(d) - pdf).abs() <= 1e-3 * pdf, "{} vs {pdf}", sky.pdf(d));
            assert_eq!(sky.radiance(d), c);
        }
        let flat = Sky::constant(Vec3::ONE);
        let uniform = 1.0 / (4.0 * PI);
        for d in [Vec3::X, Vec3::new(0.3, 0.9, 0.1).normalize(), Vec3::new(0.0, -0.6, 0.8)] {
            assert!((flat.pdf(d) - uniform).abs() < 1e-4 * uniform, "{}", flat.pdf(d));
        }
    }
}
