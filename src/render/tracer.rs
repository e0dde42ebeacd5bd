//! The Whitted tracer. Shading (per the COS 426 rayshell):
//!
//! ```text
//!   Ka·ambient·colour
//! + Σ lights a shadow ray reaches: [Kd·colour·light·max(0, N·L) + Ks·light·max(0, R·V)^n_s]
//! + Ks·(reflected ray) + T·(transmitted ray, Snell's law, total internal reflection)
//! ```
//!
//! Shadow rays pass through transmitting surfaces, tinted by T·colour at
//! each surface crossed. Secondary rays start from a point offset along the
//! geometric normal by an amount relative to the point's magnitude.

use glam::Vec3;
use std::sync::Mutex;

use super::job::{Job, per_pixel};
use crate::geometry::{Hit, Ray, Shape, intersect_brute};
use crate::image::Image;
use crate::scene::Scene;

/// A ray whose contribution to its pixel is below this is not traced.
const MIN_WEIGHT: f32 = 1.0 / 1024.0;

#[derive(Clone, Copy, Debug, Default)]
pub struct RayStats {
    pub primary: u64,
    pub shadow: u64,
    pub reflected: u64,
    pub refracted: u64,
    pub bvh_steps: u64,
}

impl RayStats {
    pub(crate) fn add(self, o: RayStats) -> RayStats {
        RayStats {
            primary: self.primary + o.primary,
            shadow: self.shadow + o.shadow,
            reflected: self.reflected + o.reflected,
            refracted: self.refracted + o.refracted,
            bvh_steps: self.bvh_steps + o.bvh_steps,
        }
    }

    pub fn total(&self) -> u64 {
        self.primary + self.shadow + self.reflected + self.refracted
    }
}

/// Mirror `d` about `n`.
pub fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - 2.0 * d.dot(n) * n
}

/// Refract unit `d` through a surface with unit normal `n` facing against
/// `d`, with `eta` = n_from / n_to; `None` on total internal reflection.
pub fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = -d.dot(n);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    if k < 0.0 {
        return None;
    }
    Some(eta * d + (eta * cos_i - k.sqrt()) * n)
}

/// How far to move a secondary ray's origin off the surface at `p`.
fn offset(p: Vec3) -> f32 {
    1e-4 * p.abs().max_element().max(1.0)
}

/// Renders the job's part of the picture; also returns the ray counts.
/// `None` if the job was cancelled.
pub fn render(scene: &Scene, job: &Job) -> Option<(Image, RayStats)> {
    let cam = &scene.camera;
    let r = job.rect(cam.width, cam.height);
    let own;
    let out = match job.canvas {
        Some(c) => c,
        None => {
            own = Mutex::new(vec![Vec3::ZERO; r.pixels() as usize]);
            &own
        }
    };
    let stats = per_pixel(cam.width, cam.height, job, out, |x, y, st| {
        st.primary += 1;
        trace(scene, &cam.ray(x, y), 0, 1.0, st)
    })?;
    let pixels = out.lock().unwrap_or_else(|e| e.into_inner()).clone();
    Some((Image { width: r.width(), height: r.height(), pixels }, stats))
}

/// The cost picture: each pixel coloured by the BVH traversal steps of its
/// primary ray (nodes entered and leaf blocks tested), from black through
/// blue, red and yellow to white at the most.
pub fn render_heatmap(scene: &Scene, job: &Job) -> Option<(Image, RayStats)> {
    let cam = &scene.camera;
    let r = job.rect(cam.width, cam.height);
    let out = Mutex::new(vec![0u32; r.pixels() as usize]);
    let stats = per_pixel(cam.width, cam.height, job, &out, |x, y, st| {
        st.primary += 1;
        let (_, steps) = scene.bvh.intersect(&cam.ray(x, y), 0.0, f32::INFINITY);
        st.bvh_steps += steps as u64;
        steps
    })?;
    let counts = out.into_inner().unwrap_or_else(|e| e.into_inner());
    let max = counts.iter().copied().max().unwrap_or(1).max(1) as f32;
    let ramp = [
        Vec3::ZERO,
        Vec3::new(0.1, 0.2, 0.9),
        Vec3::new(0.9, 0.1, 0.1),
        Vec3::new(1.0, 0.9, 0.1),
        Vec3::ONE,
    ];
    let pixels = counts
        .iter()
        .map(|&c| {
            let t = c as f32 / max * (ramp.len() - 1) as f32;
            let i = (t as usize).min(ramp.len() - 2);
            ramp[i].lerp(ramp[i + 1], t - i as f32)
        })
        .collect();
    Some((Image { width: r.width(), height: r.height(), pixels }, stats))
}

/// Times the primary rays alone (closest hit, no shading) and then, if
/// asked, one shadow ray per hit towards the first light (any hit).
/// Returns (primary seconds, shadow seconds, counts).
pub fn raybench(scene: &Scene, shadow: bool) -> (f64, f64, RayStats) {
    let cam = &scene.camera;
    let job = Job::default();
    // The buffers are made (and their pages touched) before the clock
    // starts, as scripts/embree_bench.c does: only tracing is timed.
    let hits = Mutex::new(vec![Vec3::NAN; cam.width as usize * cam.height as usize]);
    let blocked = Mutex::new(vec![0u8; cam.width as usize * cam.height as usize]);
    let start = std::time::Instant::now();
    let mut stats = per_pixel(cam.width, cam.height, &job, &hits, |x, y, st| {
        st.primary += 1;
        let ray = cam.ray(x, y);
        let (hit, steps) = scene.bvh.intersect(&ray, 0.0, f32::INFINITY);
        st.bvh_steps += steps as u64;
        hit.map(|h| ray.at(h.t)).unwrap_or(Vec3::NAN)
    })
    .unwrap_or_default();
    let hits = hits.into_inner().unwrap_or_else(|e| e.into_inner());
    let primary_s = start.elapsed().as_secs_f64();
    let Some(light) = scene.lights.first().filter(|_| shadow) else {
        return (primary_s, 0.0, stats);
    };
    let start = std::time::Instant::now();
    let w = cam.width;
    let st2 = per_pixel(cam.width, cam.height, &job, &blocked, |x, y, st| {
        let p = hits[(y * w + x) as usize];
        if p.is_nan() {
            return 0u8;
        }
        let (l, dist, _) = light.at(p);
        let eps = offset(p);
        st.shadow += 1;
        let t_max = if dist.is_finite() { dist - 2.0 * eps } else { f32::INFINITY };
        // Start on the light's side of the surface.
        let origin = p + l * eps;
        (scene.bvh.transmittance(&Ray::new(origin, l), 0.0, t_max, |_| Vec3::ZERO) == Vec3::ZERO)
            as u8
    })
    .unwrap_or_default();
    stats.shadow = st2.shadow;
    (primary_s, start.elapsed().as_secs_f64(), stats)
}

/// Primary rays by brute force (every primitive tested per ray), over an
/// evenly spread subset of the pixels sized to about `budget` ray-primitive
/// tests: the baseline for `raybench -brute`. Returns (rays, seconds).
pub fn raybench_brute(scene: &Scene, budget: u64) -> (u64, f64) {
    use rayon::prelude::*;
    let cam = &scene.camera;
    let pixels = cam.width as u64 * cam.height as u64;
    let shapes = scene.bvh.shapes();
    let prims = shapes.len().max(1) as u64;
    let rays = (budget / prims).clamp(1, pixels);
    let stride = pixels / rays;
    let start = std::time::Instant::now();
    let hits: u64 = (0..rays)
        .into_par_iter()
        .map(|k| {
            let i = k * stride;
            let ray = cam.ray((i % cam.width as u64) as u32, (i / cam.width as u64) as u32);
            intersect_brute(&shapes, &ray, 0.0, f32::INFINITY).is_some() as u64
        })
        .sum();
    std::hint::black_box(hits);
    (rays, start.elapsed().as_secs_f64())
}

/// The colour seen along `ray`, `depth` bounces deep.
pub fn trace(scene: &Scene, ray: &Ray, depth: u32, weight: f32, st: &mut RayStats) -> Vec3 {
    let (hit, steps) = scene.bvh.intersect(ray, 0.0, f32::INFINITY);
    st.bvh_steps += steps as u64;
    match hit {
        Some(h) => shade(scene, ray, &h, depth, weight, st),
        None => scene.background,
    }
}

fn shade(scene: &Scene, ray: &Ray, hit: &Hit, depth: u32, weight: f32, st: &mut RayStats) -> Vec3 {
    let shape = scene.bvh.shape(hit.prim);
    let m = &scene.materials[shape.material() as usize];
    let p = ray.at(hit.t);
    let d = ray.dir.normalize();
    // Geometric and shading normals, outward (counter-clockwise) first.
    let (mut ng, mut ns) = match shape {
        Shape::Sphere { center, .. } => {
            let n = (p - center).normalize();
            (n, n)
        }
        Shape::Triangle(t) => {
            let ng = t.cross().normalize();
            if t.normals[0] == crate::geometry::Triangle::FLAT {
                (ng, ng)
            } else {
                let [u, v] = hit.uv;
                let n = &scene.normals;
                let ns = n[t.normals[0] as usize] * (1.0 - u - v)
                    + n[t.normals[1] as usize] * u
                    + n[t.normals[2] as usize] * v;
                (ng, ns.try_normalize().unwrap_or(ng))
            }
        }
    };
    let entering = d.dot(ng) < 0.0;
    if !entering {
        ng = -ng;
        ns = -ns;
    }
    if ns.dot(ng) < 0.0 {
        ns = ng;
    }
    let eps = offset(p);
    let above = p + ng * eps;
    let view = -d;

    let mut color = m.ka * scene.ambient * m.color;
    for light in &scene.lights {
        let (l, dist, li) = light.at(p);
        if li == Vec3::ZERO || l.dot(ng) <= 0.0 {
            continue;
        }
        let n_dot_l = ns.dot(l);
        if n_dot_l <= 0.0 {
            continue;
        }
        st.shadow += 1;
        let t_max = if dist.is_finite() { dist - 2.0 * eps } else { f32::INFINITY };
        let through = scene.bvh.transmittance(&Ray::new(above, l), 0.0, t_max, |prim| {
            let om = &scene.materials[scene.bvh.material(prim) as usize];
            if om.t > 0.0 { om.t * om.color } else { Vec3::ZERO }
        });
        if through == Vec3::ZERO {
            continue;
        }
        let mut c = m.kd * m.color * li * n_dot_l;
        if m.ks > 0.0 {
            let r = reflect(-l, ns);
            let r_dot_v = r.dot(view).max(0.0);
            if r_dot_v > 0.0 {
                c += m.ks * li * r_dot_v.powf(m.ns);
            }
        }
        color += through * c;
    }

    if depth < scene.trace_depth {
        if m.ks > 0.0 && weight * m.ks >= MIN_WEIGHT {
            st.reflected += 1;
            let r = Ray::new(above, reflect(d, ns));
            color += m.ks * trace(scene, &r, depth + 1, weight * m.ks, st);
        }
        if m.t > 0.0 && weight * m.t >= MIN_WEIGHT {
            let eta = if entering { 1.0 / m.ior } else { m.ior };
            let r = match refract(d, ns, eta) {
                Some(dir) => Ray::new(p - ng * eps, dir),
                // Total internal reflection: the light stays inside.
                None => Ray::new(above, reflect(d, ns)),
            };
            st.refracted += 1;
            color += m.t * trace(scene, &r, depth + 1, weight * m.t, st);
        }
    }
    color
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mirror_and_snell() {
        let d = Vec3::new(1.0, -1.0, 0.0).normalize();
        assert!((reflect(d, Vec3::Y) - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-6);
        // 45 degrees into glass (1.5): sin(t) = sin(45)/1.5.
        let t = refract(d, Vec3::Y, 1.0 / 1.5).unwrap();
        let sin_t = t.x / t.length();
        assert!((sin_t - (45f32.to_radians().sin() / 1.5)).abs() < 1e-6, "{sin_t}");
        assert!((t.length() - 1.0).abs() < 1e-6);
        // Leaving glass at 60 degrees: total internal reflection.
        let d = Vec3::new(60f32.to_radians().sin(), -60f32.to_radians().cos(), 0.0);
        assert!(refract(d, Vec3::Y, 1.5).is_none());
        // Head-on passes straight through.
        assert!((refract(Vec3::NEG_Y, Vec3::Y, 0.7).unwrap() - Vec3::NEG_Y).length() < 1e-6);
    }
}
