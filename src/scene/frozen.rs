//! `Scene`: the frozen, render-ready scene (Send + Sync). `freeze` builds
//! the BVH over every primitive; rendering only reads it. Its coordinates
//! are single precision with the eye at the origin.

use std::time::Instant;

use glam::{DVec3, Vec3};

use super::builder::{Builder, SceneError};
use super::camera::Camera;
use super::light::Light;
use super::material::Material;
use crate::geometry::{Bvh, Hit, Ray, Shape, TIE};

/// Primitives that move together (`motion`): a tree built where they are
/// at time 0, walked by rays moved back by `velocity · time` (a
/// translated object hit by a ray is the object hit by the translated
/// ray: the same distance, the same surface point).
pub struct Moving {
    pub velocity: Vec3,
    pub bvh: Bvh,
}

impl Moving {
    /// `ray` relative to where these primitives are at its time.
    fn relative(&self, ray: &Ray) -> Ray {
        Ray { origin: ray.origin - self.velocity * ray.time, ..*ray }
    }
}

/// A hit in one of the scene's trees.
#[derive(Clone, Copy, Debug)]
pub struct Found {
    pub hit: Hit,
    /// 0: the still primitives (`Scene::bvh`); k: `Scene::moving[k - 1]`.
    pub layer: u32,
}

pub struct Scene {
    pub camera: Camera,
    /// The primitives that do not move (all of them, unless `motion` was
    /// used).
    pub bvh: Bvh,
    /// The moving ones, one tree per velocity.
    pub moving: Vec<Moving>,
    pub materials: Vec<Material>,
    pub normals: Vec<Vec3>,
    pub lights: Vec<Light>,
    /// The lights camera and reflected rays can see (those with a size).
    pub emitters: Vec<Light>,
    pub ambient: Vec3,
    pub background: Vec3,
    pub trace_depth: u32,
    pub sampling: super::Sampling,
    pub build_seconds: f64,
    /// Triangles skipped because they have no area.
    pub degenerate: usize,
}

impl Scene {
    /// Freezes the builder's current state (the builder is left as it is,
    /// so a script can change it and render again).
    pub fn freeze(b: &Builder) -> Result<Scene, SceneError> {
        let camera = b.camera()?;
        let start = Instant::now();
        let (bvh, moving) = build(b);
        let degenerate = bvh.degenerate + moving.iter().map(|m| m.bvh.degenerate).sum::<usize>();
        let build_seconds = start.elapsed().as_secs_f64();
        Ok(Scene {
            camera,
            bvh,
            moving,
            materials: b.materials.clone(),
            normals: b.normals.clone(),
            lights: b.lights.iter().map(|l| l.relative_to(b.from)).collect(),
            emitters: b
                .lights
                .iter()
                .filter(|l| l.is_visible())
                .map(|l| l.relative_to(b.from))
                .collect(),
            ambient: b.ambient,
            background: b.background,
            trace_depth: b.trace_depth,
            sampling: b.sampling,
            build_seconds,
            degenerate,
        })
    }

    /// The closest hit along `ray` (at its time) in `(0, ∞)`, and the
    /// traversal steps taken. Between trees, the tie rule is the one within
    /// a tree: of hits within `TIE`, the primitive added first wins.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray) -> (Option<Found>, u32) {
        let (hit, steps) = self.bvh.intersect(ray, 0.0, f32::INFINITY);
        let best = hit.map(|hit| Found { hit, layer: 0 });
        if self.moving.is_empty() {
            return (best, steps);
        }
        self.intersect_moving(ray, best, steps)
    }

    /// `intersect`'s search of the moving trees, given the still one's.
    #[inline(never)]
    fn intersect_moving(
        &self,
        ray: &Ray,
        mut best: Option<Found>,
        mut steps: u32,
    ) -> (Option<Found>, u32) {
        for (k, m) in self.moving.iter().enumerate() {
            let t_max = best.map_or(f32::INFINITY, |b| b.hit.t * (1.0 + TIE));
            let (hit, s) = m.bvh.intersect(&m.relative(ray), 0.0, t_max);
            steps += s;
            let Some(hit) = hit else { continue };
            let better = match best {
                None => true,
                Some(b) => {
                    hit.t < b.hit.t * (1.0 - TIE)
                        || m.bvh.id(hit.prim) < self.tree(b.layer).id(b.hit.prim)
                }
            };
            if better {
                best = Some(Found { hit, layer: k as u32 + 1 });
            }
        }
        (best, steps)
    }

    fn tree(&self, layer: u32) -> &Bvh {
        match layer {
            0 => &self.bvh,
            k => &self.moving[k as usize - 1].bvh,
        }
    }

    /// The primitive hit, where it is at `time`.
    #[inline]
    pub fn shape(&self, f: &Found, time: f32) -> Shape {
        match f.layer {
            0 => self.bvh.shape(f.hit.prim),
            k => {
                let m = &self.moving[k as usize - 1];
                m.bvh.shape(f.hit.prim).moved(m.velocity * time)
            }
        }
    }

    /// What reaches the end of the shadow segment `(0, t_max)` along `ray`
    /// (at its time): the product of `pass(material)` over every surface
    /// crossed.
    #[inline(always)]
    pub fn transmittance(&self, ray: &Ray, t_max: f32, mut pass: impl FnMut(u32) -> Vec3) -> Vec3 {
        let mut through =
            self.bvh.transmittance(ray, 0.0, t_max, |prim| pass(self.bvh.material(prim)));
        for m in &self.moving {
            if through == Vec3::ZERO {
                break;
            }
            through *= m
                .bvh
                .transmittance(&m.relative(ray), 0.0, t_max, |prim| pass(m.bvh.material(prim)));
        }
        through
    }

    /// The still tree, then the moving ones.
    pub fn trees(&self) -> impl Iterator<Item = &Bvh> {
        std::iter::once(&self.bvh).chain(self.moving.iter().map(|m| &m.bvh))
    }

    /// Warnings worth printing before a render.
    pub fn warnings(&self) -> Vec<String> {
        let mut w = Vec::new();
        if self.lights.is_empty() && self.ambient == Vec3::ZERO {
            w.push("the scene has no lights and no ambient light: the picture will show only the background".into());
        } else if self.lights.is_empty() {
            w.push("the scene has no lights: only ambient light will show".into());
        }
        if self.degenerate > 0 {
            w.push(format!("skipped {} degenerate triangle(s) with no area", self.degenerate));
        }
        w
    }
}

/// The trees of a scene: one over the primitives that do not move, and
/// one per velocity over those that do (built where they are at time 0).
/// Each primitive keeps its number in the scene, for the tie rule.
fn build(b: &Builder) -> (Bvh, Vec<Moving>) {
    let n = b.prims.len();
    if b.motion.is_empty() {
        return (Bvh::build_from(n, |i| b.shape(i, b.from)), Vec::new());
    }
    // The primitives of each velocity, still ones first, in scene order.
    let mut groups: Vec<(DVec3, Vec<u32>)> = vec![(DVec3::ZERO, Vec::new())];
    let mut index =
        std::collections::HashMap::from([(DVec3::ZERO.to_array().map(f64::to_bits), 0)]);
    let runs = std::iter::once((0, DVec3::ZERO)).chain(b.motion.iter().copied());
    let ends = b.motion.iter().map(|m| m.0).chain(std::iter::once(n as u32));
    for ((first, v), end) in runs.zip(ends) {
        let g = *index.entry(v.to_array().map(f64::to_bits)).or_insert_with(|| {
            groups.push((v, Vec::new()));
            groups.len() - 1
        });
        groups[g].1.extend(first..end);
    }
    let tree = |ids: &[u32]| {
        let mut t = Bvh::build_from(ids.len(), |k| b.shape(ids[k] as usize, b.from));
        t.renumber(ids);
        t
    };
    let still = tree(&groups[0].1);
    let moving = groups[1..]
        .iter()
        .filter(|g| !g.1.is_empty())
        .map(|(v, ids)| Moving { velocity: v.as_vec3(), bvh: tree(ids) })
        .collect();
    (still, moving)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `motion` runs: a velocity set and changed before anything is made
    /// leaves no run; the still primitives share one tree; each velocity
    /// gets one, whatever order its primitives came in.
    #[test]
    fn primitives_are_grouped_by_velocity() {
        let mut b = Builder::default();
        let v = |x: f64| DVec3::new(x, 0.0, 0.0);
        b.sphere(v(0.0), 1.0).unwrap();
        b.set_motion(v(5.0)).unwrap();
        b.set_motion(v(1.0)).unwrap();
        b.sphere(v(1.0), 1.0).unwrap();
        b.set_motion(v(0.0)).unwrap();
        b.sphere(v(2.0), 1.0).unwrap();
        b.set_motion(v(2.0)).unwrap();
        b.sphere(v(3.0), 1.0).unwrap();
        b.set_motion(v(1.0)).unwrap();
        b.sphere(v(4.0), 1.0).unwrap();
        assert_eq!(b.motion.len(), 4);
        assert_eq!([0, 1, 2, 3, 4].map(|i| b.velocity(i).x), [0.0, 1.0, 0.0, 2.0, 1.0]);
        let s = Scene::freeze(&b).unwrap();
        assert_eq!(s.bvh.len(), 2);
        let speeds: Vec<(f32, usize)> =
            s.moving.iter().map(|m| (m.velocity.x, m.bvh.len())).collect();
        assert_eq!(speeds, [(1.0, 2), (2.0, 1)]);
        // Scene numbers survive: the still tree holds primitives 0 and 2.
        let mut ids: Vec<u32> = (0..2).map(|p| s.bvh.id(p)).collect();
        ids.sort();
        assert_eq!(ids, [0, 2]);
    }
}
