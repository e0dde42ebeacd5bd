//! The scene: a mutable `Builder` that scene commands change, frozen into an
//! immutable `Scene` (with its BVH) for each render. It knows nothing of the
//! interpreter; commands convert words to numbers first.

mod builder;
mod camera;
mod displace;
pub mod emitters;
mod frozen;
mod light;
mod material;
mod objects;
mod sampling;
pub mod texture;

pub use builder::{Aim, Builder, MAX_PIXELS, MAX_TRACE_DEPTH, MeshData, SceneError};
pub use camera::Camera;
pub use displace::{Displace, MAX_SUBDIVIDE, luminance, subdivide};
pub use frozen::Scene;
pub use light::{Falloff, Light, spot_factor};
pub use material::{Bump, Highlight, Material};
pub use sampling::{Filter, FilterKind, Integrator, Sampling, Tonemap};
pub use texture::{Image, Mapping, Pattern, Texture, noise, noise_gradient, pattern, turbulence};
