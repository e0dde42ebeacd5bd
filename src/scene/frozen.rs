//! `Scene`: the frozen, render-ready scene (Send + Sync). `freeze` builds
//! the BVH over every primitive; rendering only reads it. Its coordinates
//! are single precision with the eye at the origin.

use std::time::Instant;

use glam::Vec3;

use super::builder::{Builder, SceneError};
use super::camera::Camera;
use super::light::Light;
use super::material::Material;
use crate::geometry::Bvh;

pub struct Scene {
    pub camera: Camera,
    pub bvh: Bvh,
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
        let bvh = Bvh::build_from(b.prims.len(), |i| b.shape(i, b.from));
        let degenerate = bvh.degenerate;
        let build_seconds = start.elapsed().as_secs_f64();
        Ok(Scene {
            camera,
            bvh,
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
