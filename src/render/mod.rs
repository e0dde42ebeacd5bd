//! Rendering: a recursive (Whitted) ray tracer over a frozen `Scene`, run
//! in parallel over image rows with rayon. There is no randomness, so the
//! picture is the same for any thread count and row order.

mod tracer;

pub use tracer::{
    RayStats, raybench, raybench_brute, reflect, refract, render, render_heatmap, trace,
};
