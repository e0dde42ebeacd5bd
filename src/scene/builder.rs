//! `Builder`: the mutable scene that scene commands change: the camera,
//! geometry pools (vertices, normals), primitives, lights and the current
//! material (state that applies to the objects that follow, as in OpenGL).
//! Every input is checked here, so a frozen `Scene` is always valid.

use std::sync::Arc;

use glam::{DAffine3, DVec3, Vec3};
use rayon::prelude::*;

use super::camera::Camera;
use super::light::Light;
use super::material::{Bump, Highlight, Material};
use super::objects::{BlobFrame, CsgFrame, CsgLeafDef, Group, ObjDef, Saved};
use super::sampling::Sampling;
use super::texture::Texture;
use crate::geometry::{Cone, Prefetch, Shape, Triangle};

/// The largest image, in pixels (64 Mpixel: 768 MiB of f32 RGB, and 192 MiB
/// more in bytes while the file is written).
pub const MAX_PIXELS: u64 = 1 << 26;
/// The deepest recursion `trace_depth` accepts.
pub const MAX_TRACE_DEPTH: u32 = 64;

#[derive(Debug, Clone, PartialEq)]
pub enum SceneError {
    IndexOutOfRange {
        pool: &'static str,
        index: i64,
        size: usize,
    },
    NotFinite,
    Capacity {
        what: &'static str,
    },
    ZeroVector {
        what: &'static str,
    },
    /// `camera_up` (the vector) along the view direction (the other).
    UpParallel(Vec3, Vec3),
    Invalid(String),
    Memory(crate::mem::OverBudget),
}

impl From<crate::mem::OverBudget> for SceneError {
    fn from(e: crate::mem::OverBudget) -> SceneError {
        SceneError::Memory(e)
    }
}

impl std::fmt::Display for SceneError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SceneError::IndexOutOfRange { pool, index, size } => {
                write!(f, "{pool} index {index} out of range: the {pool} pool has {size} entries")
            }
            SceneError::NotFinite => write!(f, "numbers must be finite (not NaN or infinite)"),
            SceneError::Capacity { what } => write!(f, "too many {what}: the limit is 2^32"),
            SceneError::ZeroVector { what } => write!(f, "{what} must not be the zero vector"),
            SceneError::UpParallel(up, forward) => {
                let v = |v: &Vec3| format!("{} {} {}", v.x, v.y, v.z);
                write!(
                    f,
                    "camera up vector is parallel to the view direction (camera_up {}, looking along {})",
                    v(up),
                    v(forward)
                )
            }
            SceneError::Invalid(s) => f.write_str(s),
            SceneError::Memory(e) => write!(f, "{e}"),
        }
    }
}

/// A triangle mesh as read from a file (indices count from 0).
#[derive(Clone, Debug, Default)]
pub struct MeshData {
    pub positions: Vec<Vec3>,
    pub normals: Vec<Vec3>,
    pub tris: Vec<[u32; 3]>,
    /// Per-corner normal indices, when the file gives normals.
    pub normal_tris: Option<Vec<[u32; 3]>>,
    /// Texture coordinates (OBJ `vt`: u right, v up).
    pub uvs: Vec<[f32; 2]>,
    /// Per-corner texture coordinate indices, when every face has them.
    pub uv_tris: Option<Vec<[u32; 3]>>,
}

/// The vertex pools relative to a build's origin, in single precision:
/// each corner as `Builder::shape_of` makes it, made once per vertex
/// instead of once per triangle and build pass (`Builder::corners`).
pub struct Corners {
    vertices: Vec<Vec3>,
    mesh: Vec<Vec3>,
}

/// A primitive as the script gave it. Triangles keep pool indices (checked
/// when added) and are resolved to inline vertices by `shape` at render, so adding
/// one is a bounds check and a 32-byte push, whatever the pool's size.
/// Spheres and cones keep theirs in pools too (`Builder::spheres`,
/// `cones`): a cone inline made every primitive 72 bytes, which a render's
/// build read twice, the second time in the tree's order (a 100k-triangle
/// mesh's leaves took 4 ms to make on two threads, mostly waiting for
/// memory).
#[derive(Clone, Copy, Debug)]
pub enum Prim {
    /// Vertex indices into `Builder::vertices`.
    Tri { v: [u32; 3], n: [u32; 3], material: u32 },
    /// Vertex indices into `Builder::mesh_vertices` (meshes keep their
    /// positions out of the script's pool, so `vertex` numbering is theirs).
    MeshTri { v: [u32; 3], n: [u32; 3], material: u32 },
    /// `Builder::spheres[at]`.
    Sphere { at: u32, material: u32 },
    /// `Builder::cones[at]`.
    Cone { at: u32, material: u32 },
}

// (Kept so: see `Prim`.)
const _: () = assert!(std::mem::size_of::<Prim>() == 32);

/// A sphere of `Prim::Sphere`: centre and radius.
#[derive(Clone, Copy, Debug)]
pub struct SphereDef {
    pub center: DVec3,
    pub radius: f64,
}

/// A cone of `Prim::Cone`, from `a` (radius `r0`) to `b` (radius `r1`):
/// placed by a similarity, so still a cone (`Builder::cone`).
#[derive(Clone, Copy, Debug)]
pub struct ConeDef {
    pub a: DVec3,
    pub b: DVec3,
    pub r0: f64,
    pub r1: f64,
    pub capped: bool,
}

/// The look state objects take with their material.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Look {
    pub texture: Option<Texture>,
    pub highlight: Highlight,
    pub bump: Option<Bump>,
    /// `emission`: the radiance the objects that follow emit.
    pub emission: Vec3,
}

/// Where the camera looks: at a point, or along a direction.
#[derive(Clone, Copy, Debug)]
pub enum Aim {
    Target(DVec3),
    Forward(DVec3),
}

/// Positions are kept in double precision, as the script gave them; the
/// frozen scene is in single precision relative to the eye, so a scene far
/// from the origin renders as it would at the origin.
#[derive(Clone, Debug)]
pub struct Builder {
    pub from: DVec3,
    pub aim: Aim,
    pub up: Vec3,
    /// Horizontal field of view in degrees.
    pub angle: f32,
    pub width: u32,
    pub height: u32,
    pub vertices: Vec<DVec3>,
    /// Placed positions of `mesh` files.
    pub mesh_vertices: Vec<DVec3>,
    /// Shared with the frozen scenes (changed copy-on-write: a render's
    /// scene is gone by the next change), so freezing a scene of smooth
    /// meshes copies no normals (10 MB of each render of a 1.6M-triangle
    /// mesh).
    pub normals: Arc<Vec<Vec3>>,
    /// Texture coordinates beside `normals`: a smooth corner's normal index
    /// is also its uv's. Shorter than `normals` (or NaN) where no mesh gave
    /// any. Shared as `normals` is.
    pub uvs: Arc<Vec<[f32; 2]>>,
    pub prims: Vec<Prim>,
    /// The spheres and cones of `Prim::Sphere` and `Prim::Cone` (of
    /// groups and CSGs too; they only grow until `clear`).
    pub spheres: Vec<SphereDef>,
    pub cones: Vec<ConeDef>,
    /// Where `motion` changed: from primitive `.0` on, primitives move at
    /// velocity `.1` (scene units per unit of time); none before the first.
    pub motion: Vec<(u32, DVec3)>,
    /// Shapes that are not triangles or spheres, and instances.
    pub objects: Vec<ObjDef>,
    /// The current transform (what follows, to the world) and `push`'s
    /// stack.
    pub transform: DAffine3,
    pub stack: Vec<DAffine3>,
    /// The CSGs being made (innermost last) and their leaves so far.
    pub csg: Vec<CsgFrame>,
    pub csg_leaves: Vec<CsgLeafDef>,
    /// Named groups, and what the groups being made set aside.
    pub groups: Vec<Group>,
    pub building: Vec<Saved>,
    /// The blob being made.
    pub blob: Option<BlobFrame>,
    /// The last `material` command's entry, and the state of `texture`,
    /// `highlight` and `bump` that objects made now take with it.
    pub base_material: usize,
    pub look: Look,
    /// `displace`: how the meshes that follow are displaced.
    pub displace: Option<super::displace::Displace>,
    /// The images textures use (`texture image`).
    pub images: Vec<std::sync::Arc<super::texture::Image>>,
    pub materials: Vec<Material>,
    pub lights: Vec<Light>,
    /// `environment`: the light from every direction nothing blocks
    /// (`None`: the background colour's).
    pub environment: Option<std::sync::Arc<super::emitters::Sky>>,
    pub ambient: Vec3,
    pub background: Vec3,
    pub trace_depth: u32,
    /// Samples per pixel, filter, seed, exposure, tone map.
    pub sampling: Sampling,
    /// The thin lens's radius (0: a pinhole) and the distance in focus
    /// along the view direction (`None`: the distance to `camera_target`,
    /// or the length of the `camera_forw` vector).
    pub aperture: f64,
    pub focus: Option<f64>,
    /// The largest `camera_resolution` accepted (`MAX_PIXELS` unless an
    /// embedder lowers it; `clear` keeps it).
    pub max_pixels: u64,
    /// Counts changes (the shell bumps it after every scene command), so
    /// a render can tell that nothing changed since the last one.
    pub generation: u64,
    /// The `generation` at which something a BVH is built from last
    /// changed: primitives, vertices, objects, groups, transforms, motion,
    /// the shutter. A render whose geometry and eye are the last render's
    /// reuses its tree (see `Scene::freeze_reusing`).
    pub geometry: u64,
}

/// The index the next entry of a pool of `len` gets, if a `u32` holds it.
pub(super) fn next_in_pool(len: usize) -> Result<u32, SceneError> {
    u32::try_from(len)
        .ok()
        .filter(|&i| i < u32::MAX)
        .ok_or_else(|| SceneError::Invalid("too many spheres or cones: at most 4294967294".into()))
}

impl Default for Builder {
    fn default() -> Builder {
        Builder {
            from: DVec3::ZERO,
            aim: Aim::Target(DVec3::new(0.0, 0.0, -1.0)),
            up: Vec3::Y,
            angle: 45.0,
            width: 256,
            height: 256,
            vertices: Vec::new(),
            mesh_vertices: Vec::new(),
            normals: Default::default(),
            uvs: Default::default(),
            environment: None,
            prims: Vec::new(),
            spheres: Vec::new(),
            cones: Vec::new(),
            motion: Vec::new(),
            objects: Vec::new(),
            transform: DAffine3::IDENTITY,
            stack: Vec::new(),
            csg: Vec::new(),
            csg_leaves: Vec::new(),
            groups: Vec::new(),
            building: Vec::new(),
            blob: None,
            base_material: 0,
            look: Look::default(),
            images: Vec::new(),
            displace: None,
            materials: vec![Material::default()],
            lights: Vec::new(),
            ambient: Vec3::ZERO,
            background: Vec3::ZERO,
            trace_depth: 5,
            sampling: Sampling::default(),
            aperture: 0.0,
            focus: None,
            max_pixels: MAX_PIXELS,
            generation: 0,
            geometry: 0,
        }
    }
}

/// `i` as an index into a pool of `size` entries.
fn pool_index(pool: &'static str, i: i64, size: usize) -> Result<u32, SceneError> {
    if i < 0 || i as usize >= size {
        return Err(SceneError::IndexOutOfRange { pool, index: i, size });
    }
    Ok(i as u32)
}

/// False for triangles with no area (or a non-finite normal): they are
/// skipped, with a warning, rather than rendered as slivers.
fn finite(v: Vec3) -> Result<Vec3, SceneError> {
    if v.is_finite() { Ok(v) } else { Err(SceneError::NotFinite) }
}

/// A position: finite, and within single precision's range.
pub(crate) fn position(p: DVec3) -> Result<DVec3, SceneError> {
    if p.is_finite() && p.abs().max_element() <= f32::MAX as f64 {
        Ok(p)
    } else {
        Err(SceneError::NotFinite)
    }
}

pub(crate) fn check_nonzero(v: Vec3, what: &'static str) -> Result<Vec3, SceneError> {
    let v = finite(v)?;
    if v.length_squared() == 0.0 || !v.length_squared().is_normal() {
        return Err(SceneError::ZeroVector { what });
    }
    Ok(v)
}

pub(crate) fn check_color(c: Vec3) -> Result<Vec3, SceneError> {
    let c = finite(c)?;
    if c.min_element() < 0.0 {
        return Err(SceneError::Invalid("colour components must not be negative".into()));
    }
    Ok(c)
}

impl Builder {
    pub fn new() -> Builder {
        Builder::default()
    }

    /// The material of an object made now: the last `material`, with the
    /// current `texture`, `highlight` and `bump`, and (for textures and
    /// bumps) the inverse of the current transform, so the pattern moves
    /// with the object. A new entry only when that differs from the last.
    pub(super) fn material_index(&mut self) -> Result<u32, SceneError> {
        let last = self.materials.len() - 1;
        if self.base_material == last && self.look == Look::default() {
            // The common case: no texture, highlight or bump since `material`.
            return Ok(last as u32);
        }
        let base = self.materials[self.base_material];
        let look = self.look;
        let patterned = look.texture.is_some() || look.bump.is_some();
        let to_texture = if patterned {
            self.placed().map(|m| {
                let m = m.inverse();
                glam::Affine3A::from_mat3_translation(m.matrix3.as_mat3(), m.translation.as_vec3())
            })
        } else {
            None
        };
        let want = Material {
            texture: look.texture,
            to_texture,
            highlight: look.highlight,
            bump: look.bump,
            emission: look.emission,
            ..base
        };
        if self.materials[last] == want {
            return Ok(last as u32);
        }
        if self.materials.len() >= u32::MAX as usize {
            return Err(SceneError::Capacity { what: "materials" });
        }
        crate::mem::room(&self.materials, 1)?;
        self.materials.push(want);
        Ok(last as u32 + 1)
    }

    // -- Camera ---------------------------------------------------------------

    pub fn camera_from(&mut self, p: DVec3) -> Result<(), SceneError> {
        self.from = position(p)?;
        Ok(())
    }

    pub fn camera_target(&mut self, p: DVec3) -> Result<(), SceneError> {
        self.aim = Aim::Target(position(p)?);
        Ok(())
    }

    pub fn camera_forward(&mut self, d: DVec3) -> Result<(), SceneError> {
        check_nonzero(d.as_vec3(), "camera_forw direction")?;
        self.aim = Aim::Forward(d);
        Ok(())
    }

    pub fn camera_up(&mut self, u: Vec3) -> Result<(), SceneError> {
        self.up = check_nonzero(u, "camera_up vector")?;
        Ok(())
    }

    pub fn camera_angle(&mut self, degrees: f32) -> Result<(), SceneError> {
        if !(degrees > 0.0 && degrees < 180.0) {
            return Err(SceneError::Invalid(format!(
                "camera angle must be between 0 and 180 degrees, got {degrees}"
            )));
        }
        self.angle = degrees;
        Ok(())
    }

    pub fn camera_resolution(&mut self, w: i64, h: i64) -> Result<(), SceneError> {
        if w < 1 || h < 1 {
            return Err(SceneError::Invalid(format!(
                "resolution must be at least 1x1, got {w}x{h}"
            )));
        }
        let pixels = (w as u64).saturating_mul(h as u64);
        if pixels > self.max_pixels || w > u32::MAX as i64 || h > u32::MAX as i64 {
            let mib = pixels.saturating_mul(12) >> 20;
            let limit = match self.max_pixels {
                m if m >= 1 << 20 => format!("{} Mpixel", m >> 20),
                m => format!("{m} pixels"),
            };
            return Err(SceneError::Invalid(format!(
                "resolution {w}x{h} would need {mib} MiB for the image; the limit is {limit}"
            )));
        }
        self.width = w as u32;
        self.height = h as u32;
        Ok(())
    }

    /// The camera as it would render now (checks `camera_up`).
    pub fn camera(&self) -> Result<Camera, SceneError> {
        self.camera_at(self.width, self.height)
    }

    /// The camera at another resolution (a preview's).
    pub fn camera_at(&self, width: u32, height: u32) -> Result<Camera, SceneError> {
        let forward = match self.aim {
            Aim::Target(t) => t - self.from,
            Aim::Forward(d) => d,
        };
        if forward.length_squared() == 0.0 {
            return Err(SceneError::Invalid(
                "camera_target is the same point as camera_from".into(),
            ));
        }
        let focus = self.focus.unwrap_or(forward.length());
        // In the frozen scene the eye is the origin (see `shape`).
        let forward = (forward / forward.abs().max_element()).as_vec3();
        let camera = Camera::new(Vec3::ZERO, forward, self.up, self.angle, width, height)
            .ok_or(SceneError::UpParallel(self.up, forward.normalize()))?;
        Ok(camera.with_lens(self.aperture as f32, focus as f32))
    }

    pub fn set_aperture(&mut self, r: f64) -> Result<(), SceneError> {
        if !(r >= 0.0 && r.is_finite()) {
            return Err(SceneError::Invalid(format!(
                "camera aperture must be 0 (a pinhole) or more, got {r}"
            )));
        }
        self.aperture = r;
        Ok(())
    }

    pub fn set_focus(&mut self, d: f64) -> Result<(), SceneError> {
        if !(d > 0.0 && d.is_finite()) {
            return Err(SceneError::Invalid(format!(
                "camera focus distance must be above 0, got {d}"
            )));
        }
        self.focus = Some(d);
        Ok(())
    }

    /// `motion dx dy dz`: primitives created from now on move by this much
    /// per unit of time (0 0 0 stops).
    pub fn set_motion(&mut self, v: DVec3) -> Result<(), SceneError> {
        let v = position(v)?;
        let next = self.prims.len() as u32;
        if self.motion.last().is_some_and(|&(first, _)| first == next) {
            // Nothing was created at the last velocity.
            self.motion.pop();
        }
        if self.velocity_from_here() != v {
            crate::mem::room(&self.motion, 1)?;
            self.motion.push((next, v));
        }
        Ok(())
    }

    /// The velocity of the next primitive.
    fn velocity_from_here(&self) -> DVec3 {
        self.motion.last().map_or(DVec3::ZERO, |m| m.1)
    }

    /// The velocity of primitive `i`.
    pub fn velocity(&self, i: usize) -> DVec3 {
        match self.motion.partition_point(|&(first, _)| first as usize <= i) {
            0 => DVec3::ZERO,
            k => self.motion[k - 1].1,
        }
    }

    // -- Geometry -------------------------------------------------------------

    pub fn reserve_vertices(&mut self, n: i64) {
        self.vertices.reserve(n.clamp(0, 1 << 24) as usize);
    }

    pub fn reserve_normals(&mut self, n: i64) {
        Arc::make_mut(&mut self.normals).reserve(n.clamp(0, 1 << 24) as usize);
    }

    /// Adds a vertex; returns its index.
    pub fn vertex(&mut self, p: DVec3) -> Result<usize, SceneError> {
        if self.vertices.len() >= u32::MAX as usize - 1 {
            return Err(SceneError::Capacity { what: "vertices" });
        }
        crate::mem::room(&self.vertices, 1)?;
        self.vertices.push(position(p)?);
        Ok(self.vertices.len() - 1)
    }

    /// Adds a normal; returns its index.
    pub fn normal(&mut self, n: Vec3) -> Result<usize, SceneError> {
        if self.normals.len() >= u32::MAX as usize - 1 {
            return Err(SceneError::Capacity { what: "normals" });
        }
        crate::mem::room(&self.normals, 1)?;
        let n = check_nonzero(n, "a normal")?.normalize();
        Arc::make_mut(&mut self.normals).push(n);
        Ok(self.normals.len() - 1)
    }

    fn vertex_index(&self, i: i64) -> Result<u32, SceneError> {
        pool_index("vertex", i, self.vertices.len())
    }

    fn normal_index(&self, i: i64) -> Result<u32, SceneError> {
        pool_index("normal", i, self.normals.len())
    }

    /// A flat triangle from three vertex indices (counter-clockwise).
    /// Triangles with no area are skipped when the scene is rendered.
    pub fn tri(&mut self, v: [i64; 3]) -> Result<(), SceneError> {
        let v = [self.vertex_index(v[0])?, self.vertex_index(v[1])?, self.vertex_index(v[2])?];
        self.add_tri(v, None)
    }

    /// A triangle of the script's vertices (and normals), placed by the
    /// current transform.
    fn add_tri(&mut self, v: [u32; 3], n: Option<[u32; 3]>) -> Result<(), SceneError> {
        if self.in_csg() {
            return Err(SceneError::Invalid("csg takes closed solids only, not triangles".into()));
        }
        let material = self.material_index()?;
        let prim = match self.placed() {
            None => Prim::Tri { v, n: n.unwrap_or([Triangle::FLAT; 3]), material },
            Some(_) => self.placed_tri(v, n, material)?,
        };
        crate::mem::room(&self.prims, 1)?;
        self.prims.push(prim);
        Ok(())
    }

    /// A smooth triangle: (vertex, normal) index pairs.
    pub fn ntri(&mut self, vn: [(i64, i64); 3]) -> Result<(), SceneError> {
        let mut v = [0u32; 3];
        let mut n = [0u32; 3];
        for k in 0..3 {
            v[k] = self.vertex_index(vn[k].0)?;
            n[k] = self.normal_index(vn[k].1)?;
        }
        self.add_tri(v, Some(n))
    }

    /// The primitive `i` as a renderable shape in single precision, placed
    /// relative to `origin` (the eye): the subtraction is done in double
    /// precision, so only the geometry's distance from the eye limits its
    /// precision, never its distance from the world's origin.
    pub fn shape(&self, i: usize, origin: DVec3) -> Shape {
        self.shape_of(&self.prims[i], origin)
    }

    /// `shape` for any primitive (a group's too).
    pub fn shape_of(&self, prim: &Prim, origin: DVec3) -> Shape {
        let rel = |p: DVec3| (p - origin).as_vec3();
        // (Corner by corner: `[T; 3]::map` was not inlined, 8% of a large
        // mesh's build.)
        let corners = |pool: &[DVec3], v: [u32; 3]| {
            [rel(pool[v[0] as usize]), rel(pool[v[1] as usize]), rel(pool[v[2] as usize])]
        };
        match *prim {
            Prim::Tri { v, n, material } => {
                let p = corners(&self.vertices, v);
                Shape::Triangle(Triangle { p, normals: n, material })
            }
            Prim::MeshTri { v, n, material } => {
                let p = corners(&self.mesh_vertices, v);
                Shape::Triangle(Triangle { p, normals: n, material })
            }
            Prim::Sphere { at, material } => {
                let SphereDef { center, radius } = self.spheres[at as usize];
                Shape::Sphere { center: rel(center), radius: radius as f32, material }
            }
            Prim::Cone { at, material } => {
                let ConeDef { a, b, r0, r1, capped } = self.cones[at as usize];
                let (axis, h) = ((b - a).normalize(), (b - a).length());
                Shape::Cone(Cone {
                    base: rel(a),
                    axis: axis.as_vec3(),
                    h: h as f32,
                    r0: r0 as f32,
                    slope: ((r1 - r0) / h) as f32,
                    capped,
                    material,
                })
            }
        }
    }

    /// The vertex pools relative to `origin`, for a build that makes `n`
    /// shapes: each is made twice (its entry, then its leaf, the second
    /// time in the tree's order) and each vertex of a mesh is a corner of
    /// about six triangles, so reading corners half the size, converted
    /// already, repays converting the pools (a 100k-triangle build 5 %
    /// faster on one thread). `None` when `n` is small beside the pools
    /// (a group's few triangles in a large scene).
    pub fn corners(&self, origin: DVec3, n: usize) -> Option<Corners> {
        if n < (self.vertices.len() + self.mesh_vertices.len()) / 2 {
            return None;
        }
        let rel = |pool: &[DVec3]| pool.par_iter().map(|&p| (p - origin).as_vec3()).collect();
        Some(Corners { vertices: rel(&self.vertices), mesh: rel(&self.mesh_vertices) })
    }

    /// `shape_of`, a triangle's corners read from `corners` (made for
    /// the same origin) when there are any: the same shape to the bit.
    /// (Its triangle arms are `shape_of`'s again: `shape_of` written as
    /// `shape_in(.., None)`, one closure choosing the pool, made the
    /// 100k dragon's build 5-12 % slower, `#[inline(always)]` or not.)
    #[inline]
    pub fn shape_in(&self, prim: &Prim, origin: DVec3, corners: Option<&Corners>) -> Shape {
        let Some(c) = corners else { return self.shape_of(prim, origin) };
        let of = |pool: &[Vec3], v: [u32; 3]| {
            [pool[v[0] as usize], pool[v[1] as usize], pool[v[2] as usize]]
        };
        match *prim {
            Prim::Tri { v, n, material } => {
                Shape::Triangle(Triangle { p: of(&c.vertices, v), normals: n, material })
            }
            Prim::MeshTri { v, n, material } => {
                Shape::Triangle(Triangle { p: of(&c.mesh, v), normals: n, material })
            }
            _ => self.shape_of(prim, origin),
        }
    }

    /// Asks for what `shape_in(prim)` reads ahead of its reading (a hint;
    /// see `Bvh::build_with`): `prim`'s record, or (`corners`, once the
    /// record has come) a triangle's corners, from `pools` when there are
    /// any.
    #[inline]
    pub fn shape_ahead(
        &self,
        fetch: Prefetch,
        prim: &Prim,
        corners: bool,
        pools: Option<&Corners>,
    ) {
        if !corners {
            return fetch.fetch(prim);
        }
        fn ask<T>(fetch: Prefetch, pool: &[T], v: [u32; 3]) {
            for i in v {
                if let Some(p) = pool.get(i as usize) {
                    fetch.fetch(p);
                }
            }
        }
        match (*prim, pools) {
            (Prim::Tri { v, .. }, Some(c)) => ask(fetch, &c.vertices, v),
            (Prim::MeshTri { v, .. }, Some(c)) => ask(fetch, &c.mesh, v),
            (Prim::Tri { v, .. }, None) => ask(fetch, &self.vertices, v),
            (Prim::MeshTri { v, .. }, None) => ask(fetch, &self.mesh_vertices, v),
            _ => {}
        }
    }

    /// The bounding box of every primitive, in world coordinates, as
    /// (min, max); `None` when there are none.
    pub fn bounds(&self) -> Option<(DVec3, DVec3)> {
        let mut b = (DVec3::INFINITY, DVec3::NEG_INFINITY);
        let mut grow = |lo: DVec3, hi: DVec3| b = (b.0.min(lo), b.1.max(hi));
        for prim in &self.prims {
            match *prim {
                Prim::Tri { v, .. } => v
                    .iter()
                    .for_each(|&i| grow(self.vertices[i as usize], self.vertices[i as usize])),
                Prim::MeshTri { v, .. } => v.iter().for_each(|&i| {
                    grow(self.mesh_vertices[i as usize], self.mesh_vertices[i as usize])
                }),
                Prim::Sphere { at, .. } => {
                    let SphereDef { center, radius } = self.spheres[at as usize];
                    grow(center - DVec3::splat(radius), center + DVec3::splat(radius))
                }
                Prim::Cone { at, .. } => {
                    let ConeDef { a, b, r0, r1, .. } = self.cones[at as usize];
                    let r = DVec3::splat(r0.max(r1));
                    grow(a.min(b) - r, a.max(b) + r)
                }
            }
        }
        (b.0.x <= b.1.x).then_some(b)
    }

    pub fn sphere(&mut self, center: DVec3, radius: f64) -> Result<(), SceneError> {
        let center = position(center)?;
        if !(radius > 0.0 && radius <= f32::MAX as f64) {
            return Err(SceneError::Invalid(format!(
                "sphere radius must be positive, got {radius}"
            )));
        }
        let Some((center, radius)) = self.placed_sphere(center, radius)? else {
            return Ok(());
        };
        let (center, radius) = (position(center)?, radius.min(f32::MAX as f64));
        crate::mem::room(&self.prims, 1)?;
        crate::mem::room(&self.spheres, 1)?;
        let material = self.material_index()?;
        let at = next_in_pool(self.spheres.len())?;
        self.spheres.push(SphereDef { center, radius });
        self.prims.push(Prim::Sphere { at, material });
        Ok(())
    }

    /// Adds a triangle mesh with the current material, placed by `scale`
    /// then `translate`. Smooth normals come from the mesh's own normals,
    /// or are computed (area-weighted) when it has none; `flat` turns
    /// smoothing off. Returns the number of triangles added.
    pub fn add_mesh(
        &mut self,
        mesh: &MeshData,
        scale: f64,
        translate: DVec3,
        flat: bool,
    ) -> Result<usize, SceneError> {
        // In a CSG, the mesh is a solid of it (it must be closed).
        let csg_start = self.in_csg().then_some(self.prims.len());
        let xf = self.transform;
        let place = |p: Vec3| xf.transform_point3(p.as_dvec3() * scale + translate);
        // Normals by the inverse transpose (and a mirroring scale's sign).
        let normal_xf = (xf.matrix3 * scale).inverse().transpose();
        let turn = |n: Vec3| (normal_xf * n.as_dvec3()).as_vec3();
        let n_v = mesh.positions.len();
        if let Some(bad) = mesh.tris.iter().flatten().find(|&&i| i as usize >= n_v) {
            return Err(SceneError::IndexOutOfRange {
                pool: "mesh vertex",
                index: *bad as i64,
                size: n_v,
            });
        }
        if self.mesh_vertices.len() + n_v >= u32::MAX as usize {
            return Err(SceneError::Capacity { what: "mesh vertices" });
        }
        // The placed positions, and the normals to be summed.
        crate::mem::reserve_n(n_v, 2 * size_of::<DVec3>() + size_of::<Vec3>())?;
        let positions: Vec<DVec3> = mesh.positions.iter().map(|&p| place(p)).collect();
        if positions.iter().any(|&p| position(p).is_err()) {
            return Err(SceneError::NotFinite);
        }
        let face_normal = |t: &[u32; 3]| {
            (positions[t[1] as usize] - positions[t[0] as usize])
                .cross(positions[t[2] as usize] - positions[t[0] as usize])
        };
        let uv_tris = match &mesh.uv_tris {
            Some(ut) if ut.len() == mesh.tris.len() => {
                if let Some(bad) = ut.iter().flatten().find(|&&i| i as usize >= mesh.uvs.len()) {
                    return Err(SceneError::IndexOutOfRange {
                        pool: "mesh texture coordinate",
                        index: *bad as i64,
                        size: mesh.uvs.len(),
                    });
                }
                Some(ut)
            }
            _ => None,
        };
        // This mesh's normals, and each corner's index among them.
        let (normals, corners): (Vec<Vec3>, Option<Vec<[u32; 3]>>) = if flat {
            match uv_tris {
                // Texture coordinates need corners: the face's own normal
                // at each is flat shading still.
                Some(_) => {
                    let normals = mesh
                        .tris
                        .iter()
                        .flat_map(|t| [face_normal(t).normalize_or(DVec3::Y).as_vec3(); 3])
                        .collect();
                    let corners =
                        (0..mesh.tris.len() as u32).map(|k| [3 * k, 3 * k + 1, 3 * k + 2]);
                    (normals, Some(corners.collect()))
                }
                None => (Vec::new(), None),
            }
        } else if let (Some(nt), false) = (&mesh.normal_tris, mesh.normals.is_empty()) {
            if let Some(bad) = nt.iter().flatten().find(|&&i| i as usize >= mesh.normals.len()) {
                return Err(SceneError::IndexOutOfRange {
                    pool: "mesh normal",
                    index: *bad as i64,
                    size: mesh.normals.len(),
                });
            }
            let normals =
                mesh.normals.iter().map(|n| turn(*n).try_normalize().unwrap_or(Vec3::Y)).collect();
            (normals, Some(nt.clone()))
        } else {
            let mut acc = vec![DVec3::ZERO; n_v];
            for t in &mesh.tris {
                let n = face_normal(t);
                for &i in t {
                    acc[i as usize] += n;
                }
            }
            let normals = acc
                .iter()
                .map(|n| n.try_normalize().map(DVec3::as_vec3).unwrap_or(Vec3::Y))
                .collect();
            (normals, Some(mesh.tris.clone()))
        };
        // With texture coordinates, one entry per (normal, uv) pair used.
        let (normals, uvs, corners) = match (uv_tris, corners) {
            (Some(ut), Some(corners)) => {
                let mut pairs: std::collections::HashMap<(u32, u32), u32> = Default::default();
                let (mut ns, mut uvs) = (Vec::new(), Vec::new());
                let corners = corners
                    .iter()
                    .zip(ut)
                    .map(|(c, t)| {
                        std::array::from_fn(|k| {
                            *pairs.entry((c[k], t[k])).or_insert_with(|| {
                                ns.push(normals[c[k] as usize]);
                                uvs.push(mesh.uvs[t[k] as usize]);
                                ns.len() as u32 - 1
                            })
                        })
                    })
                    .collect();
                (ns, uvs, Some(corners))
            }
            (_, corners) => (normals, Vec::new(), corners),
        };
        if self.normals.len() + normals.len() >= u32::MAX as usize {
            return Err(SceneError::Capacity { what: "normals" });
        }
        crate::mem::room(&self.normals, normals.len())?;
        let base = self.normals.len() as u32;
        if !uvs.is_empty() {
            crate::mem::room(&self.uvs, normals.len() + self.normals.len() - self.uvs.len())?;
            let own = Arc::make_mut(&mut self.uvs);
            own.resize(self.normals.len(), [f32::NAN; 2]);
            own.extend(uvs);
        }
        Arc::make_mut(&mut self.normals).extend(normals);
        let corner_normals: Option<Vec<[u32; 3]>> =
            corners.map(|c| c.iter().map(|t| [base + t[0], base + t[1], base + t[2]]).collect());
        let vbase = self.mesh_vertices.len() as u32;
        let material = self.material_index()?;
        crate::mem::room(&self.prims, mesh.tris.len())?;
        crate::mem::room(&self.mesh_vertices, positions.len())?;
        self.prims.reserve(mesh.tris.len());
        let mut added = 0;
        // (Corner by corner, not `[T; 3]::map`: whether that is inlined
        // depends on how the crate is cut into codegen units, and a change
        // elsewhere once made it a call per corner, the mesh's load 18 %
        // slower.)
        for (k, t) in mesh.tris.iter().enumerate() {
            let n = corner_normals.as_ref().map(|c| c[k]).unwrap_or([Triangle::FLAT; 3]);
            let at = |i: u32| (positions[i as usize] - positions[t[0] as usize]).as_vec3();
            let p = [at(t[0]), at(t[1]), at(t[2])];
            if (Triangle { p, normals: n, material }).has_area() {
                added += 1;
            }
            let v = [vbase + t[0], vbase + t[1], vbase + t[2]];
            self.prims.push(Prim::MeshTri { v, n, material });
        }
        self.mesh_vertices.extend(positions);
        if let Some(start) = csg_start {
            let prims: Vec<Prim> = self.prims.drain(start..).collect();
            let leaf = super::objects::LeafDef::Mesh(prims);
            self.add_csg_leaf(leaf, DAffine3::IDENTITY, material)?;
        }
        Ok(added)
    }

    // -- Lights and materials -------------------------------------------------

    pub fn set_background(&mut self, c: Vec3) -> Result<(), SceneError> {
        self.background = check_color(c)?;
        Ok(())
    }

    pub fn set_ambient(&mut self, c: Vec3) -> Result<(), SceneError> {
        self.ambient = check_color(c)?;
        Ok(())
    }

    pub fn add_light(&mut self, light: Light) -> Result<(), SceneError> {
        light.check()?;
        crate::mem::room(&self.lights, 1)?;
        self.lights.push(light);
        Ok(())
    }

    pub fn set_material(&mut self, m: Material) -> Result<(), SceneError> {
        m.check()?;
        if self.materials.len() >= u32::MAX as usize {
            return Err(SceneError::Capacity { what: "materials" });
        }
        crate::mem::room(&self.materials, 1)?;
        self.materials.push(m);
        self.base_material = self.materials.len() - 1;
        Ok(())
    }

    pub fn set_texture(&mut self, t: Option<Texture>) -> Result<(), SceneError> {
        if let Some(t) = &t {
            t.check()?;
        }
        self.look.texture = t;
        Ok(())
    }

    pub fn set_highlight(&mut self, h: Highlight) -> Result<(), SceneError> {
        if let Highlight::Ward { ax, ay } = h
            && !(ax > 0.0 && ay > 0.0 && ax.is_finite() && ay.is_finite())
        {
            return Err(SceneError::Invalid(format!(
                "ward roughness must be above 0, got {ax} and {ay}"
            )));
        }
        self.look.highlight = h;
        Ok(())
    }

    pub fn set_bump(&mut self, b: Option<Bump>) -> Result<(), SceneError> {
        if let Some(b) = b
            && !(b.amount.is_finite() && b.size > 0.0 && b.size.is_finite())
        {
            return Err(SceneError::Invalid(format!(
                "bump needs a finite amount and a size above 0, got {} and {}",
                b.amount, b.size
            )));
        }
        self.look.bump = b;
        Ok(())
    }

    pub fn set_trace_depth(&mut self, d: i64) -> Result<(), SceneError> {
        if !(0..=MAX_TRACE_DEPTH as i64).contains(&d) {
            return Err(SceneError::Invalid(format!(
                "trace depth must be between 0 and {MAX_TRACE_DEPTH}, got {d}"
            )));
        }
        self.trace_depth = d as u32;
        Ok(())
    }

    /// Back to the defaults, but for the picture size limit, the animation
    /// frame and `--seed` (the run's, not the script's).
    pub fn clear(&mut self) {
        let (max_pixels, generation) = (self.max_pixels, self.generation + 1);
        let s = self.sampling;
        *self = Builder { max_pixels, generation, geometry: generation, ..Builder::default() };
        self.sampling.frame = s.frame;
        self.sampling.base_seed = s.base_seed;
        self.sampling.noise_target = s.noise_target;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A level's corners converted once make `shape_of`'s triangles to the
    /// bit, of the script's pool and a mesh's alike, far from the origin
    /// too; a level of few shapes beside the pools reads them as before.
    #[test]
    fn converted_corners_make_the_same_shapes() {
        let mut b = Builder::new();
        let at = [(1.0e6 + 0.1, 2.3, -4.7), (0.3, 1e-3, 5.5), (-7.25, 3.3, 0.1), (2.0, -2.0, 9.9)];
        for (x, y, z) in at {
            b.vertex(DVec3::new(x, y, z)).unwrap();
        }
        b.tri([0, 1, 2]).unwrap();
        b.tri([1, 2, 3]).unwrap();
        let mesh = MeshData {
            positions: vec![
                Vec3::new(0.1, 0.2, 0.3),
                Vec3::new(3.7, -1.1, 2.2),
                Vec3::new(-5.0, 4.4, 1.3),
            ],
            normals: Vec::new(),
            tris: vec![[0, 1, 2], [2, 1, 0]],
            normal_tris: None,
            uvs: Vec::new(),
            uv_tris: None,
        };
        b.add_mesh(&mesh, 1.7, DVec3::new(123.456, -7.0, 0.25), false).unwrap();
        let origin = DVec3::new(0.7, -1.3, 2.9);
        let corners = b.corners(origin, b.prims.len()).expect("four shapes, seven vertices");
        let bits = |s: Shape| match s {
            Shape::Triangle(t) => t.p.map(|p| p.to_array().map(f32::to_bits)),
            _ => panic!("a triangle"),
        };
        assert_eq!(b.prims.len(), 4);
        for p in &b.prims {
            assert_eq!(bits(b.shape_in(p, origin, Some(&corners))), bits(b.shape_of(p, origin)));
        }
        assert!(b.corners(origin, 2).is_none());
    }
}
