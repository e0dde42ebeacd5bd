//! The builder's structure: the current transform and its stack (OpenGL's
//! convention: each command post-multiplies, so the last one applies
//! first), analytic shapes, CSG, and named groups placed by instances.
//!
//! Triangles, meshes and spheres under a transform are placed at once
//! (their vertices moved, their normals by the inverse transpose; a
//! sphere under a non-uniform scale becomes an ellipsoid, an object).
//! Other shapes are objects: a solid in its canonical coordinates and the
//! transform that places it.

use std::sync::Arc;

use glam::{DAffine3, DMat3, DVec3, Vec3};

use super::builder::{Builder, Prim, SceneError, position};
use crate::geometry::{BlobComponent, CsgOp, Solid};

/// The deepest `push` nesting, CSG nesting and group nesting accepted.
pub const MAX_NESTING: usize = 1000;

/// An object as the script made it: what it is, where (its coordinates to
/// the world's, or the group's), how fast it moves, its material.
#[derive(Clone, Debug)]
pub struct ObjDef {
    pub kind: ObjKind,
    pub to_world: DAffine3,
    pub velocity: DVec3,
}

#[derive(Clone, Debug)]
pub enum ObjKind {
    Solid {
        solid: Solid,
        material: u32,
    },
    /// Leaves placed in world coordinates, and the tree of operations.
    Csg {
        leaves: Vec<CsgLeafDef>,
        root: CsgTree,
    },
    /// Group number `.0` (`Builder::groups`).
    Instance(u32),
    Blob {
        comps: Vec<BlobComponent>,
        threshold: f32,
        material: u32,
    },
    Flake {
        center: Vec3,
        radius: f32,
        depth: u32,
        material: u32,
    },
    Menger {
        center: Vec3,
        size: f32,
        depth: u32,
        material: u32,
    },
}

/// A blob being made: its threshold, the transform it was started under,
/// and its components so far (in its own coordinates).
#[derive(Clone, Debug)]
pub struct BlobFrame {
    threshold: f64,
    to_world: DAffine3,
    comps: Vec<BlobComponent>,
}

#[derive(Clone, Debug)]
pub struct CsgLeafDef {
    pub shape: LeafDef,
    pub to_world: DAffine3,
    pub material: u32,
}

/// A CSG solid as the script made it.
#[derive(Clone, Debug)]
pub enum LeafDef {
    Solid(Solid),
    Blob {
        comps: Vec<BlobComponent>,
        threshold: f32,
    },
    /// A mesh's triangles (placed in world coordinates already).
    Mesh(Vec<Prim>),
}

#[derive(Clone, Debug)]
pub enum CsgTree {
    Leaf(u32),
    Op(CsgOp, Vec<CsgTree>),
}

/// A named group: its own primitives and objects, in its own coordinates.
#[derive(Clone, Debug, Default)]
pub struct Group {
    pub name: String,
    pub prims: Vec<Prim>,
    pub objects: Vec<ObjDef>,
    /// How deep its instances nest (1: none inside).
    pub depth: u32,
}

/// The deepest nesting of instances in instances (a ray goes down them
/// recursively).
pub const MAX_INSTANCE_DEPTH: u32 = 32;

/// What a `group` script sets aside while it runs.
#[derive(Clone, Debug)]
pub struct Saved {
    name: String,
    prims: Vec<Prim>,
    objects: Vec<ObjDef>,
    motion: Vec<(u32, DVec3)>,
    transform: DAffine3,
    stack: Vec<DAffine3>,
}

/// A CSG being built: its operation and the items made so far.
#[derive(Clone, Debug)]
pub struct CsgFrame {
    op: CsgOp,
    items: Vec<CsgTree>,
}

fn invalid(s: String) -> SceneError {
    SceneError::Invalid(s)
}

/// Whether `m`'s linear part is a rotation (or mirror) times a uniform
/// scale: spheres stay spheres. Returns the scale.
fn similarity(m: &DMat3) -> Option<f64> {
    let g = m.transpose() * *m;
    let s2 = g.x_axis.x;
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-9 * s2;
    (close(g.y_axis.y, s2)
        && close(g.z_axis.z, s2)
        && close(g.x_axis.y, 0.0)
        && close(g.x_axis.z, 0.0)
        && close(g.y_axis.z, 0.0))
    .then(|| s2.sqrt())
}

/// Two unit vectors perpendicular to `n` and to each other, right-handed
/// with it (Duff et al. 2017).
fn basis(n: DVec3) -> (DVec3, DVec3) {
    let s = 1.0f64.copysign(n.z);
    let a = -1.0 / (s + n.z);
    let b = n.x * n.y * a;
    (DVec3::new(1.0 + s * n.x * n.x * a, s * b, -s * n.x), DVec3::new(b, s + n.y * n.y * a, -n.y))
}

impl Builder {
    // -- The current transform --------------------------------------------

    fn post(&mut self, m: DAffine3) -> Result<(), SceneError> {
        let t = self.transform * m;
        if !(t.matrix3.is_finite() && t.translation.is_finite()) {
            return Err(SceneError::NotFinite);
        }
        self.transform = t;
        Ok(())
    }

    pub fn translate(&mut self, d: DVec3) -> Result<(), SceneError> {
        self.post(DAffine3::from_translation(d))
    }

    /// Degrees about x, then y, then z (so the matrix is Rz·Ry·Rx).
    pub fn rotate(&mut self, deg: DVec3) -> Result<(), SceneError> {
        let r = deg * (std::f64::consts::PI / 180.0);
        self.post(
            DAffine3::from_rotation_z(r.z)
                * DAffine3::from_rotation_y(r.y)
                * DAffine3::from_rotation_x(r.x),
        )
    }

    pub fn rotate_axis(&mut self, deg: f64, axis: DVec3) -> Result<(), SceneError> {
        let a = axis.try_normalize().ok_or(SceneError::ZeroVector { what: "a rotation axis" })?;
        self.post(DAffine3::from_axis_angle(a, deg.to_radians()))
    }

    pub fn scale(&mut self, s: DVec3) -> Result<(), SceneError> {
        if s.x == 0.0 || s.y == 0.0 || s.z == 0.0 {
            return Err(invalid(format!(
                "scale must not be 0 on any axis (it would flatten what follows), got {} {} {}",
                s.x, s.y, s.z
            )));
        }
        self.post(DAffine3::from_scale(s))
    }

    pub fn push(&mut self) -> Result<(), SceneError> {
        if self.stack.len() >= MAX_NESTING {
            return Err(invalid(format!("too many nested pushes (the limit is {MAX_NESTING})")));
        }
        self.stack.push(self.transform);
        Ok(())
    }

    pub fn pop(&mut self) -> Result<(), SceneError> {
        self.transform =
            self.stack.pop().ok_or_else(|| invalid("pop without a matching push".into()))?;
        Ok(())
    }

    /// The current transform, if it is not the identity.
    pub(crate) fn placed(&self) -> Option<DAffine3> {
        (self.transform != DAffine3::IDENTITY).then_some(self.transform)
    }

    /// The current transform composed with `local` (a shape's canonical
    /// coordinates to the script's), checked invertible.
    fn placement(&self, local: DAffine3) -> Result<DAffine3, SceneError> {
        let m = self.transform * local;
        let det = m.matrix3.determinant();
        if !(det.is_finite() && det.abs() > 1e-300 && m.translation.is_finite()) {
            return Err(invalid("the shape's transform cannot be inverted".into()));
        }
        Ok(m)
    }

    // -- Objects ----------------------------------------------------------

    /// Adds a solid in its canonical coordinates (placed by `local`, then
    /// the current transform).
    fn add_solid(&mut self, solid: Solid, local: DAffine3) -> Result<(), SceneError> {
        let to_world = self.placement(local)?;
        let material = self.material_index()?;
        if self.in_csg() {
            if !solid.is_closed() {
                return Err(invalid(
                    "csg takes closed solids only: spheres, boxes, capped cylinders and cones, tori, blobs, closed meshes and other csg"
                        .into(),
                ));
            }
            return self.add_csg_leaf(LeafDef::Solid(solid), to_world, material);
        }
        self.add_object(ObjKind::Solid { solid, material }, to_world)
    }

    /// A solid of the CSG being made.
    pub(crate) fn add_csg_leaf(
        &mut self,
        shape: LeafDef,
        to_world: DAffine3,
        material: u32,
    ) -> Result<(), SceneError> {
        if self.csg_leaves.len() >= crate::geometry::CSG_MAX_LEAVES {
            return Err(invalid(format!(
                "too many solids in one csg (the limit is {})",
                crate::geometry::CSG_MAX_LEAVES
            )));
        }
        crate::mem::room(&self.csg_leaves, 1)?;
        let frame = self.csg.last_mut().expect("called inside a csg");
        frame.items.push(CsgTree::Leaf(self.csg_leaves.len() as u32));
        self.csg_leaves.push(CsgLeafDef { shape, to_world, material });
        Ok(())
    }

    fn add_object(&mut self, kind: ObjKind, to_world: DAffine3) -> Result<(), SceneError> {
        crate::mem::room(&self.objects, 1)?;
        let velocity = self.motion.last().map_or(DVec3::ZERO, |m| m.1);
        self.objects.push(ObjDef { kind, to_world, velocity });
        Ok(())
    }

    /// Whether shapes now go into a CSG (where only closed solids may).
    pub(crate) fn in_csg(&self) -> bool {
        !self.csg.is_empty()
    }

    /// Where a shape keeps its kind (a sphere stays a sphere, a cone a
    /// cone) outside a CSG: the current transform as a map of points and
    /// its scale, when it is a similarity (or none); `None` otherwise.
    fn similar(&self) -> Option<(impl Fn(DVec3) -> DVec3 + use<>, f64)> {
        if self.in_csg() {
            return None;
        }
        let m = self.placed();
        let s = match m {
            None => 1.0,
            Some(m) => similarity(&m.matrix3)?,
        };
        Some((move |p| m.map_or(p, |m| m.transform_point3(p)), s))
    }

    /// A sphere under the current transform: a sphere still under a
    /// similarity, an ellipsoid (an object) otherwise; a CSG leaf in a CSG.
    pub(crate) fn placed_sphere(
        &mut self,
        c: DVec3,
        r: f64,
    ) -> Result<Option<(DVec3, f64)>, SceneError> {
        if let Some((place, s)) = self.similar() {
            return Ok(Some((place(c), r * s)));
        }
        let local =
            DAffine3::from_scale_rotation_translation(DVec3::splat(r), glam::DQuat::IDENTITY, c);
        self.add_solid(Solid::Sphere, local)?;
        Ok(None)
    }

    pub fn plane(&mut self, n: DVec3, d: f64) -> Result<(), SceneError> {
        let n = n.try_normalize().ok_or(SceneError::ZeroVector { what: "a plane's normal" })?;
        if !d.is_finite() {
            return Err(SceneError::NotFinite);
        }
        if self.in_csg() {
            return Err(invalid("csg takes closed solids only, not planes".into()));
        }
        self.add_solid(Solid::Plane { n: n.as_vec3(), d: d as f32 }, DAffine3::IDENTITY)
    }

    pub fn add_box(&mut self, a: DVec3, b: DVec3) -> Result<(), SceneError> {
        let (lo, hi) = (a.min(b), a.max(b));
        if lo.cmpge(hi).any() {
            return Err(invalid(format!(
                "a box needs a size on every axis, got corners {} {} {} and {} {} {}",
                a.x, a.y, a.z, b.x, b.y, b.z
            )));
        }
        // Centred, so the solid's numbers stay small.
        let c = (lo + hi) / 2.0;
        let h = ((hi - lo) / 2.0).as_vec3();
        self.add_solid(Solid::Box { min: -h, max: h }, DAffine3::from_translation(c))
    }

    /// A cone (or cylinder) from `a` (radius `r0`) to `b` (radius `r1`).
    pub fn cone(
        &mut self,
        a: DVec3,
        r0: f64,
        b: DVec3,
        r1: f64,
        capped: bool,
    ) -> Result<(), SceneError> {
        let axis = b - a;
        let len = axis.length();
        if !(len > 0.0 && len.is_finite()) {
            return Err(invalid("a cone or cylinder needs two different end points".into()));
        }
        if !(r0 >= 0.0 && r1 >= 0.0 && r0.max(r1) > 0.0 && r0.is_finite() && r1.is_finite()) {
            return Err(invalid(format!(
                "a cone's radii must be 0 or more, and not both 0, got {r0} and {r1}"
            )));
        }
        // Placed by a similarity (or not at all), it stays a cone: one
        // the BVH tests natively, four at once.
        if let Some((place, s)) = self.similar()
            && let (Ok(a), Ok(b)) = (position(place(a)), position(place(b)))
        {
            // (One single precision cannot hold goes the general way.)
            let (r0, r1) = (r0 * s, r1 * s);
            let h = (b - a).length();
            if h.is_finite() && (h as f32) > 0.0 && r0.max(r1) <= f32::MAX as f64 {
                crate::mem::room(&self.prims, 1)?;
                crate::mem::room(&self.cones, 1)?;
                let material = self.material_index()?;
                let at = super::builder::next_in_pool(self.cones.len())?;
                self.cones.push(super::builder::ConeDef { a, b, r0, r1, capped });
                self.prims.push(Prim::Cone { at, material });
                return Ok(());
            }
        }
        let (u, v) = basis(axis / len);
        let frame = DAffine3::from_cols(u, v, axis, a);
        self.add_solid(Solid::Cone { r0: r0 as f32, r1: r1 as f32, capped }, frame)
    }

    pub fn disk(&mut self, c: DVec3, n: DVec3, r: f64, inner: f64) -> Result<(), SceneError> {
        let n = n.try_normalize().ok_or(SceneError::ZeroVector { what: "a disk's normal" })?;
        if !(r > 0.0 && r.is_finite() && inner >= 0.0 && inner < r) {
            return Err(invalid(format!(
                "a disk needs a radius above 0 and an inner radius from 0 up to it, got {r} and {inner}"
            )));
        }
        let (u, v) = basis(n);
        let frame = DAffine3::from_cols(u * r, v * r, n, c);
        self.add_solid(Solid::Disk { inner: (inner / r) as f32 }, frame)
    }

    pub fn torus(&mut self, major: f64, minor: f64) -> Result<(), SceneError> {
        if !(major > 0.0 && minor > 0.0 && major.is_finite() && minor.is_finite()) {
            return Err(invalid(format!("a torus needs radii above 0, got {major} and {minor}")));
        }
        self.add_solid(
            Solid::Torus { major: major as f32, minor: minor as f32 },
            DAffine3::IDENTITY,
        )
    }

    // -- CSG --------------------------------------------------------------

    /// Starts a CSG: solids made until `end_csg` are its children.
    pub fn begin_csg(&mut self, op: CsgOp) -> Result<(), SceneError> {
        if self.csg.len() >= MAX_NESTING {
            return Err(invalid(format!("csg nested too deep (the limit is {MAX_NESTING})")));
        }
        self.csg.push(CsgFrame { op, items: Vec::new() });
        Ok(())
    }

    /// Ends the innermost CSG (`ok`: its script ran to the end; otherwise
    /// it is dropped). The outermost becomes an object.
    pub fn end_csg(&mut self, ok: bool) -> Result<(), SceneError> {
        let Some(frame) = self.csg.pop() else { return Ok(()) };
        if !ok {
            if self.csg.is_empty() {
                self.csg_leaves.clear();
            }
            return Ok(());
        }
        if frame.items.is_empty() {
            return Err(invalid("csg made no solids".into()));
        }
        let tree = CsgTree::Op(frame.op, frame.items);
        match self.csg.last_mut() {
            Some(outer) => outer.items.push(tree),
            None => {
                let leaves = std::mem::take(&mut self.csg_leaves);
                self.add_object(ObjKind::Csg { leaves, root: tree }, DAffine3::IDENTITY)?;
            }
        }
        Ok(())
    }

    // -- Fractals ---------------------------------------------------------

    fn fractal_depth(depth: i64) -> Result<u32, SceneError> {
        let max = crate::geometry::FRACTAL_MAX_DEPTH;
        if !(0..=max as i64).contains(&depth) {
            return Err(invalid(format!("fractal depth must be between 0 and {max}, got {depth}")));
        }
        Ok(depth as u32)
    }

    /// Haines' sphereflake: a sphere and `depth` generations of children.
    pub fn sphereflake(&mut self, c: DVec3, r: f64, depth: i64) -> Result<(), SceneError> {
        let depth = Builder::fractal_depth(depth)?;
        if !(r > 0.0 && r.is_finite()) {
            return Err(invalid(format!("sphereflake radius must be above 0, got {r}")));
        }
        if self.in_csg() {
            return Err(invalid("csg takes closed solids only, not sphereflakes".into()));
        }
        let to_world = self.placement(DAffine3::IDENTITY)?;
        let material = self.material_index()?;
        let kind = ObjKind::Flake { center: c.as_vec3(), radius: r as f32, depth, material };
        self.add_object(kind, to_world)
    }

    /// A Menger sponge filling the cube of edge `size` centred at `c`.
    pub fn menger(&mut self, c: DVec3, size: f64, depth: i64) -> Result<(), SceneError> {
        let depth = Builder::fractal_depth(depth)?;
        if !(size > 0.0 && size.is_finite()) {
            return Err(invalid(format!("menger size must be above 0, got {size}")));
        }
        if self.in_csg() {
            return Err(invalid("csg takes closed solids only, not sponges".into()));
        }
        let to_world = self.placement(DAffine3::IDENTITY)?;
        let material = self.material_index()?;
        let kind = ObjKind::Menger { center: c.as_vec3(), size: size as f32, depth, material };
        self.add_object(kind, to_world)
    }

    // -- Blobs ------------------------------------------------------------

    /// Starts a blob: `blob_sphere` adds components until `end_blob`.
    pub fn begin_blob(&mut self, threshold: f64) -> Result<(), SceneError> {
        if !(threshold > 0.0 && threshold.is_finite()) {
            return Err(invalid(format!("a blob's threshold must be above 0, got {threshold}")));
        }
        if self.blob.is_some() {
            return Err(invalid("a blob cannot be made inside another".into()));
        }
        let to_world = self.placement(DAffine3::IDENTITY)?;
        self.blob = Some(BlobFrame { threshold, to_world, comps: Vec::new() });
        Ok(())
    }

    /// A component of the blob being made, placed by the transform current
    /// now (relative to the blob's, which must be a similarity for it).
    pub fn blob_sphere(&mut self, c: DVec3, r: f64, s: f64) -> Result<(), SceneError> {
        let Some(frame) = &self.blob else {
            return Err(invalid("blob_sphere belongs inside blob threshold {...}".into()));
        };
        if !(r > 0.0 && r.is_finite() && s.is_finite()) {
            return Err(invalid(format!(
                "blob_sphere needs a radius above 0 and a finite strength, got {r} and {s}"
            )));
        }
        let rel = frame.to_world.inverse() * self.transform;
        let k = similarity(&rel.matrix3).ok_or_else(|| {
            invalid("blob_sphere under a non-uniform scale: scale the whole blob instead".into())
        })?;
        let center = rel.transform_point3(c);
        crate::mem::room(&frame.comps, 1)?;
        let comp =
            BlobComponent { center: center.as_vec3(), radius: (r * k) as f32, strength: s as f32 };
        self.blob.as_mut().expect("checked above").comps.push(comp);
        Ok(())
    }

    /// Ends the blob (`ok`: its script ran to the end; else it is dropped).
    pub fn end_blob(&mut self, ok: bool) -> Result<(), SceneError> {
        let Some(frame) = self.blob.take() else { return Ok(()) };
        if !ok {
            return Ok(());
        }
        if !frame.comps.iter().any(|c| c.strength > 0.0) {
            return Err(invalid("a blob needs a blob_sphere of positive strength".into()));
        }
        let material = self.material_index()?;
        let threshold = frame.threshold as f32;
        if self.in_csg() {
            let leaf = LeafDef::Blob { comps: frame.comps, threshold };
            return self.add_csg_leaf(leaf, frame.to_world, material);
        }
        let kind = ObjKind::Blob { comps: frame.comps, threshold, material };
        self.add_object(kind, frame.to_world)
    }

    // -- Groups and instances ---------------------------------------------

    /// Starts group `name`: until `end_group`, what is made goes into it,
    /// from the identity transform.
    pub fn begin_group(&mut self, name: &str) -> Result<(), SceneError> {
        if self.in_csg() {
            return Err(invalid("a group cannot be made inside csg".into()));
        }
        if self.building.len() >= MAX_NESTING {
            return Err(invalid(format!("groups nested too deep (the limit is {MAX_NESTING})")));
        }
        let saved = Saved {
            name: name.to_string(),
            prims: std::mem::take(&mut self.prims),
            objects: std::mem::take(&mut self.objects),
            motion: std::mem::take(&mut self.motion),
            transform: std::mem::replace(&mut self.transform, DAffine3::IDENTITY),
            stack: std::mem::take(&mut self.stack),
        };
        self.building.push(saved);
        Ok(())
    }

    /// Ends the innermost group (`ok`: its script ran to the end; else it
    /// is dropped) and puts back what was set aside.
    pub fn end_group(&mut self, ok: bool) -> Result<(), SceneError> {
        let Some(saved) = self.building.pop() else { return Ok(()) };
        self.csg.clear();
        self.csg_leaves.clear();
        let prims = std::mem::replace(&mut self.prims, saved.prims);
        let objects = std::mem::replace(&mut self.objects, saved.objects);
        let motion = std::mem::replace(&mut self.motion, saved.motion);
        self.transform = saved.transform;
        self.stack = saved.stack;
        if ok {
            if !motion.is_empty() && motion.iter().any(|m| m.1 != DVec3::ZERO) {
                return Err(invalid(
                    "motion inside a group is not supported: give the instance its motion".into(),
                ));
            }
            let depth = 1 + objects
                .iter()
                .filter_map(|o| match o.kind {
                    ObjKind::Instance(g) => Some(self.groups[g as usize].depth),
                    _ => None,
                })
                .max()
                .unwrap_or(0);
            crate::mem::room(&self.groups, 1)?;
            self.groups.push(Group { name: saved.name, prims, objects, depth });
        }
        Ok(())
    }

    /// Places the last group named `name` under the current transform.
    pub fn instance(&mut self, name: &str) -> Result<(), SceneError> {
        if self.in_csg() {
            return Err(invalid("csg takes closed solids only, not instances".into()));
        }
        let Some(g) = self.groups.iter().rposition(|g| g.name == name) else {
            let known: Vec<&str> = self.groups.iter().map(|g| g.name.as_str()).collect();
            return Err(invalid(if known.is_empty() {
                format!("no group named \"{name}\": make one with group {name} {{...}}")
            } else {
                format!("no group named \"{name}\" (groups: {})", known.join(", "))
            }));
        };
        if self.groups[g].depth >= MAX_INSTANCE_DEPTH {
            return Err(invalid(format!(
                "instances nested too deep: \"{name}\" holds instances {} deep (the limit is {MAX_INSTANCE_DEPTH})",
                self.groups[g].depth
            )));
        }
        let to_world = self.placement(DAffine3::IDENTITY)?;
        self.add_object(ObjKind::Instance(g as u32), to_world)
    }

    /// Places a triangle's corners (and normals) made under the current
    /// transform, as a mesh triangle of its own.
    pub(crate) fn placed_tri(
        &mut self,
        v: [u32; 3],
        n: Option<[u32; 3]>,
        material: u32,
    ) -> Result<Prim, SceneError> {
        let m = self.placement(DAffine3::IDENTITY)?;
        let normal = m.matrix3.inverse().transpose();
        crate::mem::room(&self.mesh_vertices, 3)?;
        crate::mem::room(&self.normals, 3)?;
        let base = self.mesh_vertices.len() as u32;
        for k in v {
            let p = m.transform_point3(self.vertices[k as usize]);
            if !p.is_finite() {
                return Err(SceneError::NotFinite);
            }
            self.mesh_vertices.push(p);
        }
        let n = match n {
            None => [crate::geometry::Triangle::FLAT; 3],
            Some(n) => {
                let nb = self.normals.len() as u32;
                for k in n {
                    let w = (normal * self.normals[k as usize].as_dvec3()).normalize_or_zero();
                    let w = if w == DVec3::ZERO { Vec3::Y } else { w.as_vec3() };
                    Arc::make_mut(&mut self.normals).push(w);
                }
                [nb, nb + 1, nb + 2]
            }
        };
        Ok(Prim::MeshTri { v: [base, base + 1, base + 2], n, material })
    }
}
