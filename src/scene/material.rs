//! Materials: `material r g b Ka Kd Ks n_s T index_of_refraction`, and
//! the look that `texture`, `highlight` and `bump` add to them.

use glam::{Affine3A, Vec3};

use super::builder::{SceneError, check_color};
use super::texture::Texture;

/// The specular model (`highlight`).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Highlight {
    /// Ks·(R·V)^n_s, as COS 426 (the default).
    #[default]
    Phong,
    /// Ks·(N·H)^n_s, H halfway between the light and the eye.
    Blinn,
    /// Ward's anisotropic model: roughness `ax` along the surface's u
    /// direction, `ay` across it; Ks is its ρs.
    Ward { ax: f32, ay: f32 },
}

/// A bump map: the shading normal tilted by the gradient of a height,
/// amount·noise(p/size), or amount times the luminance of image `id`
/// laid by its mapping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Bump {
    pub amount: f32,
    pub size: f32,
    pub image: Option<(u32, super::texture::Mapping)>,
}

/// The range `material` accepts for an index of refraction (0 aside).
pub const MIN_IOR: f32 = 0.01;
pub const MAX_IOR: f32 = 100.0;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    pub color: Vec3,
    pub ka: f32,
    pub kd: f32,
    pub ks: f32,
    pub ns: f32,
    pub t: f32,
    pub ior: f32,
    /// The colour's texture, if any, and the map from the coordinates the
    /// object was written in to the texture's (the inverse of the
    /// transform current when the object was made).
    pub texture: Option<Texture>,
    pub to_texture: Option<Affine3A>,
    pub highlight: Highlight,
    pub bump: Option<Bump>,
    /// Radiance emitted from the front side (`emission`).
    pub emission: Vec3,
}

impl Default for Material {
    /// Matte white: ambient 0.2, diffuse 0.8, no specular, opaque.
    fn default() -> Material {
        Material {
            color: Vec3::ONE,
            ka: 0.2,
            kd: 0.8,
            ks: 0.0,
            ns: 1.0,
            t: 0.0,
            ior: 1.0,
            texture: None,
            to_texture: None,
            highlight: Highlight::Phong,
            bump: None,
            emission: Vec3::ZERO,
        }
    }
}

impl Material {
    /// Plain colour only: no texture, bump, anisotropic highlight,
    /// reflection, transmission or emission (so without lights it shades
    /// to `ka * ambient * color`).
    #[inline]
    pub(crate) fn is_flat(&self) -> bool {
        self.texture.is_none()
            && self.bump.is_none()
            && !matches!(self.highlight, Highlight::Ward { .. })
            && self.ks == 0.0
            && self.t == 0.0
            && self.emission == Vec3::ZERO
    }

    pub(crate) fn check(&self) -> Result<(), SceneError> {
        check_color(self.color)?;
        for (name, v) in
            [("Ka", self.ka), ("Kd", self.kd), ("Ks", self.ks), ("n_s", self.ns), ("T", self.t)]
        {
            if !v.is_finite() {
                return Err(SceneError::NotFinite);
            }
            if v < 0.0 {
                return Err(SceneError::Invalid(format!(
                    "material {name} must not be negative, got {v}"
                )));
            }
        }
        // Opaque scenes (SPD conversions) write an ior of 0: it is never
        // used when nothing is transmitted, so only glass must have one.
        if !self.ior.is_finite() || self.ior < 0.0 || (self.t > 0.0 && self.ior == 0.0) {
            return Err(SceneError::Invalid(format!(
                "index of refraction must be positive (or 0 when T is 0), got {}",
                self.ior
            )));
        }
        // Real materials lie between about 1 and 4; far outside, refraction
        // only makes degenerate rays.
        if self.ior != 0.0 && !(MIN_IOR..=MAX_IOR).contains(&self.ior) {
            return Err(SceneError::Invalid(format!(
                "index of refraction must be between {MIN_IOR} and {MAX_IOR}, got {:?}",
                self.ior
            )));
        }
        Ok(())
    }
}
