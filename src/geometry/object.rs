//! Objects: what a BVH holds besides its triangles and spheres, each a
//! leaf of its own kind. An object has a place (a transform from its
//! parent's coordinates into its own, and a velocity) and a kind: an
//! analytic solid, a whole tree of its own (an instance of a group, or
//! primitives moving together), or a CSG of solids. Rays go into the
//! object's coordinates (the same `t`: the direction is transformed, not
//! made unit), normals come out by the inverse transpose.

use std::sync::Arc;

use glam::{Affine3A, Vec3};

use super::blob::Blob;
use super::csg::Csg;
use super::fractal::{Flake, Menger};
use super::solid::Solid;
use super::{Aabb, Bvh, Ray, Triangle};

/// Where an object is in its parent's coordinates at time t: moved by
/// `velocity`·t, then placed by the inverse of `to_local`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Place {
    /// Parent to local coordinates; `None`: the same.
    pub to_local: Option<Affine3A>,
    pub velocity: Vec3,
}

impl Place {
    pub const IDENTITY: Place = Place { to_local: None, velocity: Vec3::ZERO };

    /// Parent to local coordinates at `time` (`None`: the identity).
    #[inline]
    pub fn at(&self, time: f32) -> Option<Affine3A> {
        let shift = self.velocity * time;
        match (self.to_local, shift == Vec3::ZERO) {
            (None, true) => None,
            (None, false) => Some(Affine3A::from_translation(-shift)),
            (Some(m), true) => Some(m),
            (Some(m), false) => Some(m * Affine3A::from_translation(-shift)),
        }
    }

    /// The ray in local coordinates.
    #[inline]
    pub fn local(&self, ray: &Ray) -> Ray {
        match self.at(ray.time) {
            None => *ray,
            Some(m) => Ray {
                origin: m.transform_point3(ray.origin),
                dir: m.transform_vector3(ray.dir),
                time: ray.time,
            },
        }
    }

    /// The parent-space bounds of local `b` over the shutter `[t0, t1]`.
    pub fn bounds(&self, b: Aabb, [t0, t1]: [f32; 2]) -> Aabb {
        if b.is_empty() {
            return b;
        }
        let placed = match self.to_local {
            None => b,
            Some(m) => {
                let to_parent = m.inverse();
                (0..8).fold(Aabb::EMPTY, |acc, k| {
                    let c = Vec3::new(
                        if k & 1 == 0 { b.min.x } else { b.max.x },
                        if k & 2 == 0 { b.min.y } else { b.max.y },
                        if k & 4 == 0 { b.min.z } else { b.max.z },
                    );
                    acc.grow(to_parent.transform_point3(c))
                })
            }
        };
        let at = |t: f32| {
            let s = self.velocity * t;
            let s = glam::Vec3A::from(s);
            Aabb { min: placed.min + s, max: placed.max + s }
        };
        at(t0).union(at(t1))
    }
}

/// What an object is.
#[derive(Debug)]
pub enum Kind {
    /// An analytic solid of one material.
    Solid { solid: Solid, material: u32 },
    /// A tree of its own: an instance of a group, or primitives that move
    /// together.
    Tree(Arc<Bvh>),
    /// Constructive solid geometry.
    Csg(Box<Csg>),
    /// Metaballs of one material.
    Blob { blob: Box<Blob>, material: u32 },
    /// A sphereflake, generated as rays reach it.
    Flake { flake: Box<Flake>, material: u32 },
    /// A Menger sponge, generated as rays reach it.
    Menger { sponge: Box<Menger>, material: u32 },
}

#[derive(Debug)]
pub struct Object {
    pub place: Place,
    pub kind: Kind,
}

/// A surface a shadow ray crosses, as `transmittance`'s `pass` sees it:
/// its material and distance, and for textures (as `Located` has them) a
/// triangle's corners (indices of its normals and texture coordinates,
/// `Triangle::FLAT` if none) with the barycentric weights, and the level
/// the surface was written in.
#[derive(Clone, Copy, Debug)]
pub struct ShadowHit {
    pub material: u32,
    pub t: f32,
    pub corners: [u32; 3],
    pub uv: [f32; 2],
    pub level: Option<Affine3A>,
    pub moved: Vec3,
}

impl ShadowHit {
    pub fn new(material: u32, t: f32) -> ShadowHit {
        ShadowHit {
            material,
            t,
            corners: [super::Triangle::FLAT; 3],
            uv: [0.0; 2],
            level: None,
            moved: Vec3::ZERO,
        }
    }
}

/// A level and motion seen from one level up, through `place` at `time`.
fn lift(level: &mut Option<Affine3A>, moved: &mut Vec3, place: &Place, time: f32) {
    match (place.at(time), level.as_mut()) {
        (Some(m), Some(l)) => *l *= m,
        (_, None) => *moved += place.velocity * time,
        (None, Some(_)) => {}
    }
}

/// What passes the crossings of a surface of one material: the product of
/// `pass` over each crossing `cross` reports (in order) inside
/// `(t_min, t_max)`, stopping at the first past `t_max` or once nothing
/// passes.
fn through(
    material: u32,
    pass: &mut dyn FnMut(ShadowHit) -> Vec3,
    (t_min, t_max): (f32, f32),
    cross: impl FnOnce(&mut dyn FnMut(f32) -> bool),
) -> Vec3 {
    let mut through = Vec3::ONE;
    cross(&mut |t| {
        if t >= t_max {
            return true;
        }
        if t > t_min {
            through *= pass(ShadowHit::new(material, t));
        }
        through == Vec3::ZERO
    });
    through
}

/// A hit's surface, resolved down to a primitive in its own coordinates:
/// what shading needs, whatever the nesting.
#[derive(Clone, Copy, Debug)]
pub struct Located {
    pub local: Local,
    pub material: u32,
    /// Barycentric weights of vertices 1 and 2, for triangles.
    pub uv: [f32; 2],
    /// World to the primitive's coordinates at the ray's time (composed
    /// over every level); `None`: the same.
    pub to_local: Option<Affine3A>,
    /// World to the coordinates of the group the primitive was written in
    /// (where its texture is evaluated); `None`: it is in no instance.
    pub level: Option<Affine3A>,
    /// For a primitive in no instance: how far its motion has carried it
    /// at the ray's time (its texture goes with it).
    pub moved: Vec3,
}

/// The primitive a hit resolves to, in its own coordinates.
#[derive(Clone, Copy, Debug)]
pub enum Local {
    Triangle(Triangle),
    Sphere {
        center: Vec3,
        radius: f32,
    },
    /// A solid's outward normal there (not unit length).
    Solid {
        normal: Vec3,
    },
}

impl Located {
    /// `self` as seen from one level up, through `place` at `time`.
    fn within(mut self, place: &Place, time: f32) -> Located {
        if let Some(m) = place.at(time) {
            self.to_local = Some(self.to_local.map_or(m, |i| i * m));
        }
        lift(&mut self.level, &mut self.moved, place, time);
        self
    }
}

impl Object {
    /// Bounds in the parent's coordinates over the shutter (empty for
    /// something infinite: a plane).
    pub fn bounds(&self, shutter: [f32; 2]) -> Aabb {
        let local = match &self.kind {
            Kind::Solid { solid, .. } => solid.bounds(),
            Kind::Tree(t) => t.bounds(),
            Kind::Csg(c) => c.bounds(),
            Kind::Blob { blob, .. } => blob.bounds(),
            Kind::Flake { flake, .. } => flake.bounds(),
            Kind::Menger { sponge, .. } => sponge.bounds(),
        };
        self.place.bounds(local, shutter)
    }

    /// The closest hit in `(t_min, t_max)`: its distance, the barycentric
    /// weights or nothing, and `sub` (a solid's part, a tree's primitive,
    /// a CSG's leaf and part) for `locate`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_min: f32, t_max: f32) -> Option<(f32, [f32; 2], u32)> {
        let local = self.place.local(ray);
        match &self.kind {
            Kind::Solid { solid, .. } => {
                solid.crossings(&local).first_in(t_min, t_max).map(|c| (c.t, [0.0; 2], c.part))
            }
            Kind::Tree(t) => {
                let (hit, _) = t.intersect(&local, t_min, t_max);
                hit.map(|h| (h.t, h.uv, h.prim))
            }
            Kind::Csg(c) => c.intersect(&local, t_min, t_max).map(|(t, sub)| (t, [0.0; 2], sub)),
            Kind::Blob { blob, .. } => {
                let mut found = None;
                // The first crossing past t_min, if before t_max.
                blob.crossings(&local, |t| {
                    if t > t_min && t < t_max {
                        found = Some((t, [0.0; 2], 0));
                    }
                    t > t_min
                });
                found
            }
            Kind::Flake { flake, .. } => {
                flake.intersect(&local, t_min, t_max).map(|h| (h.0, [0.0; 2], 0))
            }
            Kind::Menger { sponge, .. } => {
                sponge.intersect(&local, t_min, t_max).map(|(t, part)| (t, [0.0; 2], part))
            }
        }
    }

    /// What passes through the object between `t_min` and `t_max`: the
    /// product of `pass` over the surfaces crossed.
    pub fn transmittance(
        &self,
        ray: &Ray,
        t_min: f32,
        t_max: f32,
        pass: &mut dyn FnMut(ShadowHit) -> Vec3,
    ) -> Vec3 {
        let local = self.place.local(ray);
        // Crossings come back to this level as `locate`'s hits do.
        let instance = matches!(self.kind, Kind::Tree(_)) && self.place.to_local.is_some();
        let mut pass = |mut h: ShadowHit| {
            if instance {
                h.level = Some(h.level.unwrap_or(Affine3A::IDENTITY));
            }
            lift(&mut h.level, &mut h.moved, &self.place, ray.time);
            pass(h)
        };
        let pass = &mut pass;
        match &self.kind {
            Kind::Tree(t) => t.transmittance(&local, t_min, t_max, pass),
            Kind::Csg(c) => c.transmittance(&local, t_min, t_max, pass),
            Kind::Solid { solid, material } => through(*material, pass, (t_min, t_max), |each| {
                for c in solid.crossings(&local).as_slice() {
                    if each(c.t) {
                        break;
                    }
                }
            }),
            Kind::Blob { blob, material } => {
                through(*material, pass, (t_min, t_max), |each| blob.crossings(&local, each))
            }
            Kind::Flake { flake, material } => through(*material, pass, (t_min, t_max), |each| {
                flake.crossings(&local, t_min, t_max, each)
            }),
            Kind::Menger { sponge, material } => through(*material, pass, (t_min, t_max), |each| {
                sponge.crossings(&local, t_min, t_max, each)
            }),
        }
    }

    /// The surface of a hit `intersect` found (`t`, `uv` and `sub` as it
    /// gave them), resolved to its primitive.
    pub fn locate(&self, ray: &Ray, t: f32, uv: [f32; 2], sub: u32) -> Located {
        let local = self.place.local(ray);
        let found = match &self.kind {
            Kind::Solid { solid, material } => {
                let p = local.at(t);
                Located {
                    local: Local::Solid { normal: solid.normal(p, sub) },
                    material: *material,
                    uv,
                    to_local: None,
                    level: None,
                    moved: Vec3::ZERO,
                }
            }
            Kind::Tree(tree) => {
                // An instance's group is a level of its own (a moving
                // group of primitives stays in its parent's).
                let mut found = tree.locate_again(&local, t, sub, uv);
                if self.place.to_local.is_some() {
                    found.level = Some(found.level.unwrap_or(Affine3A::IDENTITY));
                }
                found
            }
            Kind::Csg(c) => c.locate(&local, t, sub),
            Kind::Blob { blob, material } => Located {
                local: Local::Solid { normal: blob.normal(local.at(t)) },
                material: *material,
                uv,
                to_local: None,
                level: None,
                moved: Vec3::ZERO,
            },
            Kind::Flake { flake, material } => {
                // The sphere hit: asked again around t.
                let band = t.abs() * 1e-6 + f32::MIN_POSITIVE;
                let center =
                    flake.intersect(&local, t - band, t + band).map_or(Vec3::ZERO, |h| h.1);
                let radius = (local.at(t) - center).length();
                Located {
                    local: Local::Sphere { center, radius },
                    material: *material,
                    uv,
                    to_local: None,
                    level: None,
                    moved: Vec3::ZERO,
                }
            }
            Kind::Menger { material, .. } => {
                let cube = Solid::Box { min: Vec3::NEG_ONE, max: Vec3::ONE };
                Located {
                    local: Local::Solid { normal: cube.normal(Vec3::ZERO, sub) },
                    material: *material,
                    uv,
                    to_local: None,
                    level: None,
                    moved: Vec3::ZERO,
                }
            }
        };
        found.within(&self.place, ray.time)
    }
}
