//! Rendering: a recursive (Whitted) ray tracer, or a path tracer
//! (`integrator path`), over a frozen `Scene`, run
//! in parallel over tiles with rayon (`job`: crops, progressive passes,
//! progress and cancellation). Random numbers are hashes of (seed, frame,
//! pixel, sample, dimension) (`sample`), so the picture is the same for any
//! thread count, tile order or pass order.

mod job;
mod path;
pub mod sample;
mod tracer;

pub use job::{Job, PASSES, Rect};
pub use tracer::{
    RayStats, apply_look, raybench, raybench_brute, reflect, refract, render, render_finished,
    render_heatmap, render_into, trace,
};
