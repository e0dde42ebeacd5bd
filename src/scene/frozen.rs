//! `Scene`: the frozen, render-ready scene (Send + Sync). `freeze` builds
//! the BVH over every primitive; rendering only reads it. Its coordinates
//! are single precision with the eye at the origin.

use std::sync::Arc;
use std::time::Instant;

use glam::{Affine3A, DAffine3, DVec3, Vec3};

use super::builder::{Builder, Prim, SceneError};
use super::camera::Camera;
use super::emitters::{LightSet, Sky};
use super::light::Light;
use super::material::Material;
use super::objects::{CsgTree, LeafDef, ObjDef, ObjKind};
use super::texture::Image;
use crate::geometry::{
    Blob, Bvh, Csg, CsgLeaf, CsgNode, CsgShape, Flake, Hit, Kind, Located, Menger, Object,
    Occluder, Place, Ray, ShadowHit, Shape,
};

pub struct Scene {
    pub camera: Camera,
    /// Everything: the still triangles and spheres, and objects (analytic
    /// shapes, CSG, instances of groups, primitives moving together);
    /// shared with the next render of the same geometry from the same eye.
    pub bvh: Arc<Bvh>,
    /// Whether `bvh` is an earlier render's (`freeze_reusing`).
    pub reused: bool,
    pub materials: Vec<Material>,
    pub normals: Arc<Vec<Vec3>>,
    /// Texture coordinates beside `normals` (see `Builder::uvs`).
    pub uvs: Arc<Vec<[f32; 2]>>,
    pub lights: Vec<Light>,
    /// The lights camera and reflected rays can see (those with a size).
    pub emitters: Vec<Light>,
    pub ambient: Vec3,
    pub background: Vec3,
    pub trace_depth: u32,
    pub sampling: super::Sampling,
    pub build_seconds: f64,
    /// Where the eye is in the script's coordinates (the frozen scene's
    /// origin), for textures.
    pub origin: Vec3,
    /// The images textures use.
    pub images: Vec<Arc<Image>>,
    /// Triangles skipped because they have no area.
    pub degenerate: usize,
    /// The light from where nothing is hit: the environment, or the
    /// background as a constant one; whether an environment was given.
    pub sky: Arc<Sky>,
    pub has_environment: bool,
    /// What the path tracer samples light from (empty for Whitted).
    pub emitters_set: LightSet,
}

impl Scene {
    /// Freezes the builder's current state (the builder is left as it is,
    /// so a script can change it and render again).
    pub fn freeze(b: &Builder) -> Result<Scene, SceneError> {
        Scene::freeze_reusing(b, None)
    }

    /// `freeze` with `tree` as the BVH when given: an earlier freeze's, of
    /// the same `Builder::geometry` and eye (`Builder::from`), which the
    /// caller checks. The tree depends on nothing else of the builder.
    pub fn freeze_reusing(b: &Builder, tree: Option<Arc<Bvh>>) -> Result<Scene, SceneError> {
        let camera = b.camera()?;
        let start = Instant::now();
        let reused = tree.is_some();
        let bvh = tree.unwrap_or_else(|| {
            let mut groups = vec![None; b.groups.len()];
            // On one of the pool's threads, not the caller's: the build's
            // serial steps then run there, and its parallel ones start
            // from within the pool instead of each being handed over to
            // it and waited for (a 69k-triangle build 11-12 -> 9 ms).
            Arc::new(rayon::scope(|_| {
                freeze_level(b, &b.prims, &b.motion, &b.objects, b.from, &mut groups)
            }))
        });
        let degenerate = bvh.degenerate;
        let sky = match &b.environment {
            Some(s) => s.clone(),
            None => Arc::new(Sky::constant(b.background)),
        };
        let emitters_set = if b.sampling.integrator == super::Integrator::Path {
            let bounds = bvh.bounds();
            let radius = if bounds.min.x <= bounds.max.x {
                let d: Vec3 = (Vec3::from(bounds.max) - Vec3::from(bounds.min)) * 0.5;
                d.length().min(1e18)
            } else {
                1.0
            };
            LightSet::build(b, &sky, radius)
        } else {
            LightSet::default()
        };
        let build_seconds = start.elapsed().as_secs_f64();
        Ok(Scene {
            camera,
            bvh,
            reused,
            materials: b.materials.clone(),
            normals: b.normals.clone(),
            uvs: b.uvs.clone(),
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
            origin: b.from.as_vec3(),
            images: b.images.clone(),
            sky,
            has_environment: b.environment.is_some(),
            emitters_set,
        })
    }

    /// The closest hit along `ray` (at its time) in `(0, ∞)`, and the
    /// traversal steps taken.
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray) -> (Option<Hit>, u32) {
        self.bvh.intersect(ray, 0.0, f32::INFINITY)
    }

    /// `intersect` for each ray of `rays` (at most `PACKET`), into `out`:
    /// the same hits, found together when the rays can go as one packet.
    #[inline]
    pub fn intersect_packet(&self, rays: &[Ray], out: &mut [(Option<Hit>, u32)]) {
        self.bvh.intersect_packet(rays, 0.0, f32::INFINITY, out)
    }

    /// The surface `hit` is on.
    #[inline]
    pub fn locate(&self, ray: &Ray, hit: &Hit) -> Located {
        self.bvh.locate(ray, hit)
    }

    /// What reaches the end of the shadow segment `(0, t_max)` along `ray`
    /// (at its time): the product of `pass` over every surface crossed.
    #[inline(always)]
    pub fn transmittance(
        &self,
        ray: &Ray,
        t_max: f32,
        pass: impl FnMut(ShadowHit) -> Vec3,
    ) -> Vec3 {
        self.bvh.transmittance(ray, 0.0, t_max, pass)
    }

    /// `transmittance`, testing first the block of primitives that blocked
    /// the last shadow ray `last` was given (see
    /// `Bvh::transmittance_hinted`): the same value, to the bit.
    #[inline]
    pub fn transmittance_hinted(
        &self,
        ray: &Ray,
        t_max: f32,
        last: &mut Occluder,
        pass: impl FnMut(ShadowHit) -> Vec3,
    ) -> Vec3 {
        self.bvh.transmittance_hinted(ray, 0.0, t_max, last, pass)
    }

    /// Warnings worth printing before a render.
    pub fn warnings(&self) -> Vec<String> {
        let mut w = Vec::new();
        let emits = self.materials.iter().any(|m| m.emission != Vec3::ZERO);
        if self.sampling.integrator == super::Integrator::Path {
            if self.lights.is_empty() && !emits && self.sky.mean == Vec3::ZERO {
                w.push("the scene has no lights, nothing emits and the environment is black: the picture will be black".into());
            }
        } else if self.lights.is_empty() && self.ambient == Vec3::ZERO && !emits {
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

/// The tree of one level (the scene, relative to `origin`, or a group,
/// in its own coordinates): its still triangles and spheres, one object
/// per velocity of its moving ones, and its objects. Each primitive keeps
/// its number in the level (primitives first, then objects) for the tie
/// rule. Groups are frozen once each, when first placed.
fn freeze_level(
    b: &Builder,
    prims: &[Prim],
    motion: &[(u32, DVec3)],
    defs: &[ObjDef],
    origin: DVec3,
    groups: &mut Vec<Option<Arc<Bvh>>>,
) -> Bvh {
    let n = prims.len();
    let shutter = b.sampling.shutter;
    let mut objects: Vec<Object> = Vec::new();
    // Each object's number in the level.
    let mut ids: Vec<u32> = Vec::new();
    // The still primitives (all of them unless `motion` was used).
    let still: Vec<u32> = if motion.is_empty() {
        Vec::new()
    } else {
        let mut groups_by_v: Vec<(DVec3, Vec<u32>)> = vec![(DVec3::ZERO, Vec::new())];
        let mut index =
            std::collections::HashMap::from([(DVec3::ZERO.to_array().map(f64::to_bits), 0)]);
        let runs = std::iter::once((0, DVec3::ZERO)).chain(motion.iter().copied());
        let ends = motion.iter().map(|m| m.0).chain(std::iter::once(n as u32));
        for ((first, v), end) in runs.zip(ends) {
            let g = *index.entry(v.to_array().map(f64::to_bits)).or_insert_with(|| {
                groups_by_v.push((v, Vec::new()));
                groups_by_v.len() - 1
            });
            groups_by_v[g].1.extend(first..end);
        }
        for (v, members) in groups_by_v.iter().skip(1).filter(|g| !g.1.is_empty()) {
            let mut t =
                Bvh::build_from(members.len(), |k| b.shape_of(&prims[members[k] as usize], origin));
            t.renumber(members);
            ids.push(members[0]);
            objects.push(Object {
                place: Place { to_local: None, velocity: v.as_vec3() },
                kind: Kind::Tree(Arc::new(t)),
            });
        }
        std::mem::take(&mut groups_by_v[0].1)
    };
    for (k, d) in defs.iter().enumerate() {
        let kind = match &d.kind {
            ObjKind::Solid { solid, material } => {
                Kind::Solid { solid: *solid, material: *material }
            }
            ObjKind::Csg { leaves, root } => {
                let leaves = leaves
                    .iter()
                    .map(|l| {
                        let (shape, to_local) = match &l.shape {
                            LeafDef::Solid(s) => {
                                (CsgShape::Solid(*s), to_local(l.to_world, origin))
                            }
                            LeafDef::Blob { comps, threshold } => (
                                CsgShape::Blob(Arc::new(Blob::new(comps.clone(), *threshold))),
                                to_local(l.to_world, origin),
                            ),
                            // Built from the eye, as the scene's triangles.
                            LeafDef::Mesh(prims) => (
                                CsgShape::Mesh(Arc::new(Bvh::build_from(prims.len(), |k| {
                                    b.shape_of(&prims[k], origin)
                                }))),
                                None,
                            ),
                        };
                        CsgLeaf {
                            place: Place { to_local, velocity: Vec3::ZERO },
                            shape,
                            material: l.material,
                        }
                    })
                    .collect();
                Kind::Csg(Box::new(Csg::new(leaves, csg_node(root))))
            }
            ObjKind::Instance(g) => {
                let tree = group_tree(b, *g as usize, groups);
                Kind::Tree(tree)
            }
            ObjKind::Flake { center, radius, depth, material } => Kind::Flake {
                flake: Box::new(Flake::new(*center, *radius, *depth)),
                material: *material,
            },
            ObjKind::Menger { center, size, depth, material } => Kind::Menger {
                sponge: Box::new(Menger::new(*center, *size, *depth)),
                material: *material,
            },
            ObjKind::Blob { comps, threshold, material } => Kind::Blob {
                blob: Box::new(Blob::new(comps.clone(), *threshold)),
                material: *material,
            },
        };
        // CSG leaves carry their own placement (from the eye).
        let placement =
            if matches!(d.kind, ObjKind::Csg { .. }) { None } else { to_local(d.to_world, origin) };
        ids.push((n + k) as u32);
        objects.push(Object {
            place: Place { to_local: placement, velocity: d.velocity.as_vec3() },
            kind,
        });
    }
    let n_still = if motion.is_empty() { n } else { still.len() };
    let total = n_still + objects.len();
    let bounds: Vec<_> = objects.iter().map(|o| o.bounds(shutter)).collect();
    // The tree's shape `i < n_still`: the primitive it is.
    let prim_of = |i: usize| if motion.is_empty() { i as u32 } else { still[i] };
    let pools = b.corners(origin, n_still);
    let shape = |i: usize| {
        if i < n_still {
            b.shape_in(&prims[prim_of(i) as usize], origin, pools.as_ref())
        } else {
            Shape::Object { index: (i - n_still) as u32, bounds: bounds[i - n_still] }
        }
    };
    let fetch = crate::geometry::Prefetch::new();
    let ahead = |i: usize, corners: bool| {
        if i < n_still {
            b.shape_ahead(fetch, &prims[prim_of(i) as usize], corners, pools.as_ref());
        }
    };
    let mut tree = Bvh::build_with(total, shape, ahead, objects);
    if !motion.is_empty() || !ids.is_empty() {
        let numbers: Vec<u32> = (0..n_still).map(prim_of).chain(ids).collect();
        tree.renumber(&numbers);
    }
    tree
}

/// World (or group) to local coordinates, with the eye at `origin`: the
/// inverse of `to_world`, after moving the origin back (in double
/// precision, then single).
fn to_local(to_world: DAffine3, origin: DVec3) -> Option<Affine3A> {
    let m = to_world.inverse() * DAffine3::from_translation(origin);
    (m != DAffine3::IDENTITY).then(|| affine(m))
}

fn affine(m: DAffine3) -> Affine3A {
    Affine3A::from_mat3_translation(m.matrix3.as_mat3(), m.translation.as_vec3())
}

fn csg_node(t: &CsgTree) -> CsgNode {
    match t {
        CsgTree::Leaf(i) => CsgNode::Leaf(*i),
        CsgTree::Op(op, kids) => CsgNode::Op(*op, kids.iter().map(csg_node).collect()),
    }
}

/// Group `g`'s tree, frozen the first time it is asked for.
fn group_tree(b: &Builder, g: usize, groups: &mut Vec<Option<Arc<Bvh>>>) -> Arc<Bvh> {
    if let Some(t) = &groups[g] {
        return t.clone();
    }
    let def = &b.groups[g];
    let t = Arc::new(freeze_level(b, &def.prims, &[], &def.objects, DVec3::ZERO, groups));
    groups[g] = Some(t.clone());
    t
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
        // Two still spheres, and one object per velocity.
        assert_eq!((s.bvh.len(), s.bvh.objects()), (4, 2));
        // Scene numbers survive: the still spheres are primitives 0 and 2,
        // the objects take their first primitive's (1 and 3).
        let mut ids: Vec<u32> = (0..4)
            .filter(|&p| matches!(s.bvh.shape(p), Shape::Sphere { .. }))
            .map(|p| s.bvh.id(p))
            .collect();
        ids.sort();
        assert_eq!(ids, [0, 2]);
    }
}
