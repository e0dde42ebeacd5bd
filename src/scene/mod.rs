//! The scene: a mutable `Builder` that scene commands change. It knows
//! nothing of the interpreter; commands convert words to numbers first.
//! (The frozen, render-ready scene arrives with the renderer.)

mod builder;

pub use builder::{Builder, SceneError};
