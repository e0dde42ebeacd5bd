//! The path tracer (`integrator path`): Monte Carlo light transport over
//! the same scene, BVH and samples as the Whitted tracer.
//!
//! Along each camera ray's path, at every surface:
//! - its **emission** (front side only) is added, weighted against light
//!   sampling when a diffuse bounce found it;
//! - **next-event estimation**: one emitter, chosen by power (`LightSet`),
//!   is sampled and a shadow ray cast. Point, spot and parallel lights add
//!   the Lambert term and the material's highlight (standing in for the
//!   mirror image of a light no path can hit); area and sphere lights,
//!   emitting triangles and spheres and the sky are weighted by multiple
//!   importance sampling (the power heuristic, Veach 1997) against the
//!   BSDF's density;
//! - the **BSDF** is sampled: one lobe chosen by weight, Kd·colour a
//!   Lambertian lobe (cosine-weighted), Ks a perfect mirror, T a smooth
//!   dielectric (Fresnel's equations choose reflection or refraction;
//!   radiance is not rescaled by η², exact for closed objects seen from
//!   outside);
//! - after three bounces, **Russian roulette** ends the path with chance
//!   1 − min(0.95, max throughput), and a surviving path is weighted up.
//!
//! `trace_depth d` bounds paths to d bounces after the camera's hit
//! (Mitsuba's `max_depth` d + 1). Ambient light is not used: the light
//! between surfaces is computed. Random numbers come from the camera
//! ray's key, a fresh dimension each (`RayStats::next_dim`), so pictures
//! do not depend on threads, tiles or passes.

use std::f32::consts::PI;

use glam::Vec3;

use super::sample;
use super::tracer::{
    Look, Media, OCCLUDERS, OFFSET, RayStats, Surface, highlight, offset, reflect, refract, surface,
};
use crate::geometry::{Hit, Local, Ray};
use crate::scene::Scene;
use crate::scene::emitters::{self, Emitter};

/// Bounces before Russian roulette may end a path.
const ROULETTE_AFTER: u32 = 3;

/// The power heuristic's weight of a sample of density `a` against a
/// second strategy's density `b`.
fn mis(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 && (a2 + b2).is_finite() { a2 / (a2 + b2) } else { 1.0 }
}

/// Fresnel reflectance of a smooth dielectric for unpolarized light, from
/// the cosine of incidence and η = n_from / n_to (1 on total internal
/// reflection).
pub fn fresnel(cos_i: f32, eta: f32) -> f32 {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return 1.0;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (eta * cos_i - cos_t) / (eta * cos_i + cos_t);
    let rp = (cos_i - eta * cos_t) / (cos_i + eta * cos_t);
    0.5 * (rs * rs + rp * rp)
}

/// A cosine-weighted direction about unit `n` for a unit-square point.
fn cosine_dir(n: Vec3, (a, b): (f32, f32)) -> Vec3 {
    let r = a.sqrt();
    let phi = 2.0 * PI * b;
    let (t1, t2) = emitters::orthonormal(n);
    (t1 * (r * phi.cos()) + t2 * (r * phi.sin()) + n * (1.0 - a).max(0.0).sqrt()).normalize()
}

/// The radiance arriving along the camera ray `ray`.
pub fn radiance(scene: &Scene, camera_ray: &Ray, st: &mut RayStats) -> Vec3 {
    radiance_from(scene, camera_ray, None, st)
}

/// `radiance`, given the camera ray's closest hit (and steps) when it was
/// found already, in a packet.
pub(super) fn radiance_from(
    scene: &Scene,
    camera_ray: &Ray,
    mut first: Option<(Option<Hit>, u32)>,
    st: &mut RayStats,
) -> Vec3 {
    let set = &scene.emitters_set;
    let (mut total, mut beta) = (Vec3::ZERO, Vec3::ONE);
    let mut ray = *camera_ray;
    let mut media = Media::default();
    // The density with which the last bounce chose `ray` (0: the camera's
    // or a specular bounce's, whose emitters count whole).
    let mut bsdf_pdf = 0.0f32;
    for depth in 0..=scene.trace_depth {
        if !(ray.origin.is_finite() && ray.dir.is_finite() && ray.dir != Vec3::ZERO) {
            break;
        }
        let (hit, steps) = first.take().unwrap_or_else(|| scene.intersect(&ray));
        st.bvh_steps += steps as u64;
        let scale = ray.dir.length();
        let d = ray.dir / scale;
        // Lights with a size, where nothing nearer is.
        let nearest = hit.as_ref().map_or(f32::INFINITY, |h| h.t);
        let seen = scene
            .lights
            .iter()
            .enumerate()
            .filter_map(|(k, l)| l.hit(&ray, nearest).map(|(t, c)| (k, t, c)))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        if let Some((k, t, radiance)) = seen {
            let w = if bsdf_pdf > 0.0 {
                let prob = set.light_prob.get(k).copied().unwrap_or(0.0);
                mis(bsdf_pdf, prob * light_pdf(&scene.lights[k], &ray, t * scale))
            } else {
                1.0
            };
            total += beta * radiance * w;
            break;
        }
        let Some(h) = hit else {
            let w = if bsdf_pdf > 0.0 && set.sky_prob > 0.0 {
                mis(bsdf_pdf, set.sky_prob * scene.sky.pdf(d))
            } else {
                1.0
            };
            total += beta * scene.sky.radiance(d) * w;
            break;
        };
        let at = scene.locate(&ray, &h);
        let material = at.material;
        let m = &scene.materials[material as usize];
        let p = ray.at(h.t);
        let Surface { ng, ns, front, shadow_from } = surface(scene, &at, p, d);
        if front && m.emission != Vec3::ZERO {
            let sampled = set.sampled.get(material as usize).copied().unwrap_or(false);
            let w = if bsdf_pdf > 0.0 && sampled {
                mis(bsdf_pdf, surface_pdf(scene, &at, ray.origin, p, m.emission))
            } else {
                1.0
            };
            total += beta * m.emission * w;
        }
        if depth == scene.trace_depth {
            break;
        }
        let look = Look::at(scene, m, &at, (p, ray.origin), ns, front);
        let ns = look.normal;
        let diffuse = m.kd * look.colour;
        let eps = offset(p, ray.origin);
        let above = p + ng * eps;
        let weights = [mean(diffuse), m.ks, m.t];
        let sum: f32 = weights.iter().sum();
        if !(sum > 0.0 && sum.is_finite()) {
            break;
        }
        let p_diffuse = weights[0] / sum;

        // Next-event estimation.
        let (u_pick, u_lobe) = sample::jitter(st.key(), st.next_dim(), 0);
        let u_light = sample::jitter(st.key(), st.next_dim(), 0);
        if let Some((i, prob)) = set.pick(u_pick).filter(|_| m.kd > 0.0 || m.ks > 0.0) {
            let item = &set.items[i];
            if let Some(ls) = emitters::sample(item, &scene.sky, p, prob, u_light) {
                let cos = ns.dot(ls.dir);
                // Without a diffuse lobe only the highlight of a point,
                // spot or parallel light is left to gather.
                let useful = m.kd > 0.0 || ls.pdf == 0.0;
                if useful && cos > 0.0 && ls.dir.dot(ng) > 0.0 {
                    let origin = if shadow_from != p {
                        shadow_from + ng * offset(shadow_from, ray.origin)
                    } else {
                        above
                    };
                    // Towards the same point of the light from there.
                    let (dir, dist) = if ls.dist.is_finite() {
                        let v = p + ls.dir * ls.dist - origin;
                        let len = v.length();
                        (v / len, len)
                    } else {
                        (ls.dir, f32::INFINITY)
                    };
                    let t_max =
                        if dist.is_finite() { dist * (1.0 - 2.0 * OFFSET) } else { f32::INFINITY };
                    st.shadow += 1;
                    let last = &mut st.occluders[i % OCCLUDERS];
                    let shadow = ray.spawn(origin, dir);
                    let open = scene.transmittance_hinted(&shadow, t_max, last, |_| Vec3::ZERO)
                        != Vec3::ZERO;
                    if open && ls.pdf == 0.0 {
                        // A point, spot or parallel light (its number,
                        // already divided by its chance).
                        let mut c = diffuse * ls.li * cos;
                        if m.ks > 0.0 && matches!(item, Emitter::Light(_)) {
                            c += m.ks * ls.li * highlight(m, &look, ls.dir, -d, cos);
                        }
                        total += beta * c;
                    } else if open {
                        let w = mis(ls.pdf, p_diffuse * cos / PI);
                        total += beta * diffuse / PI * ls.li * (cos * w / ls.pdf);
                    }
                }
            }
        }

        // The next direction, by the BSDF.
        let (u_rr, u_fresnel) = sample::jitter(st.key(), st.next_dim(), 0);
        let u_dir = sample::jitter(st.key(), st.next_dim(), 0);
        let x = u_lobe * sum;
        if x < weights[0] {
            let dir = cosine_dir(ns, u_dir);
            let cos = dir.dot(ns);
            if dir.dot(ng) <= 0.0 || cos <= 0.0 {
                break;
            }
            beta *= diffuse / p_diffuse;
            bsdf_pdf = p_diffuse * cos / PI;
            st.reflected += 1;
            ray = ray.spawn(above, dir);
        } else if x < weights[0] + weights[1] {
            beta *= m.ks * sum / weights[1];
            bsdf_pdf = 0.0;
            st.reflected += 1;
            ray = ray.spawn(above, reflect(d, ns));
        } else {
            let (n_from, beyond) = if front {
                (media.ior(), media.enter(material, m.ior))
            } else {
                (m.ior, media.leave(material))
            };
            let eta = n_from / beyond.ior();
            let f = fresnel(-d.dot(ns), eta);
            beta *= m.t * sum / weights[2];
            bsdf_pdf = 0.0;
            st.refracted += 1;
            match refract(d, ns, eta).filter(|_| u_fresnel >= f) {
                Some(dir) => {
                    beta *= look.colour;
                    media = beyond;
                    ray = ray.spawn(p - ng * eps, dir);
                }
                None => ray = ray.spawn(above, reflect(d, ns)),
            }
        }
        if depth + 1 >= ROULETTE_AFTER {
            let q = beta.max_element().min(0.95);
            if u_rr >= q {
                break;
            }
            beta /= q;
        }
    }
    total
}

fn mean(c: Vec3) -> f32 {
    (c.x + c.y + c.z) / 3.0
}

/// The density light sampling gives the direction of `ray` to light `l`
/// (with size) met `dist` away, per unit solid angle, before the choice
/// of the light.
fn light_pdf(l: &crate::scene::Light, ray: &Ray, dist: f32) -> f32 {
    use crate::scene::Light;
    match *l {
        Light::Area { u, v, .. } => {
            let normal = u.cross(v);
            let area = normal.length();
            let cos = ray.dir.normalize().dot(normal / area).abs();
            if cos > 0.0 { dist * dist / (area * cos) } else { 0.0 }
        }
        Light::Sphere { center, radius, .. } => {
            emitters::sphere_pdf(ray.origin, center.as_vec3(), radius)
        }
        _ => 0.0,
    }
}

/// The density light sampling gives an emitting surface's point `p`, seen
/// from `from`, per unit solid angle (with its choice): for the top
/// level's triangles and spheres, which `LightSet` holds.
fn surface_pdf(scene: &Scene, at: &crate::geometry::Located, from: Vec3, p: Vec3, e: Vec3) -> f32 {
    if at.to_local.is_some() {
        return 0.0;
    }
    let set = &scene.emitters_set;
    match at.local {
        Local::Triangle(t) => {
            let cross = t.cross();
            let area = 0.5 * cross.length();
            let v = p - from;
            let r2 = v.length_squared();
            let cos = (v / r2.sqrt()).dot(cross / (2.0 * area)).abs();
            if cos > 0.0 && area > 0.0 {
                set.surface_prob(e, area) * r2 / (area * cos)
            } else {
                0.0
            }
        }
        Local::Sphere { center, radius } => {
            let area = 4.0 * PI * radius * radius;
            set.surface_prob(e, area) * emitters::sphere_pdf(from, center, radius)
        }
        Local::Solid { .. } => 0.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fresnel_at_normal_incidence_and_beyond_the_critical_angle() {
        // ((n1 − n2)/(n1 + n2))² head-on.
        assert!((fresnel(1.0, 1.0 / 1.5) - 0.04).abs() < 1e-6);
        assert!((fresnel(1.0, 1.5) - 0.04).abs() < 1e-6);
        // From glass past asin(1/1.5) ≈ 41.8°: all reflected.
        assert_eq!(fresnel(45f32.to_radians().cos(), 1.5), 1.0);
        // Grazing: all reflected.
        assert!(fresnel(1e-4, 1.0 / 1.5) > 0.99);
    }

    #[test]
    fn cosine_directions_have_the_cosine_mean() {
        // E[cos θ] = 2/3 for a cosine-weighted hemisphere.
        let n = Vec3::new(0.3, -0.5, 0.8).normalize();
        let k = 64;
        let mut sum = 0.0;
        for i in 0..k {
            for j in 0..k {
                let u = ((i as f32 + 0.5) / k as f32, (j as f32 + 0.5) / k as f32);
                let d = cosine_dir(n, u);
                assert!((d.length() - 1.0).abs() < 1e-4);
                sum += d.dot(n);
            }
        }
        assert!((sum / (k * k) as f32 - 2.0 / 3.0).abs() < 1e-3);
    }
}
