//! How a render runs: which pixels (a crop rectangle), in what order (plain
//! tiles, or progressive coarse-to-fine passes), and what another thread
//! may watch or steer while it runs (pixels done, the picture so far,
//! cancellation). Each pixel's value depends on its own samples only, so
//! the order never changes the result.

use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicU64, Ordering};

use rayon::prelude::*;

use super::tracer::RayStats;

/// Tiles are squares of this many pixels on a side.
const TILE: u32 = 16;

/// The pixel strides of the progressive passes: every 8th pixel in x and y
/// first, then every 4th, 2nd, and the rest.
pub const PASSES: [u32; 4] = [8, 4, 2, 1];

/// A rectangle of pixels, `x0..x1` by `y0..y1`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Rect {
    pub x0: u32,
    pub y0: u32,
    pub x1: u32,
    pub y1: u32,
}

impl Rect {
    pub fn full(width: u32, height: u32) -> Rect {
        Rect { x0: 0, y0: 0, x1: width, y1: height }
    }
    pub fn width(&self) -> u32 {
        self.x1 - self.x0
    }
    pub fn height(&self) -> u32 {
        self.y1 - self.y0
    }
    pub fn pixels(&self) -> u64 {
        self.width() as u64 * self.height() as u64
    }
}

/// A render's settings and its live state, shared with a watching thread.
#[derive(Default)]
pub struct Job<'a> {
    /// Trace only this part of the picture (the image is its size).
    pub crop: Option<Rect>,
    /// Trace in coarse-to-fine passes (`PASSES`).
    pub progressive: bool,
    /// Set from anywhere to stop the render soon (it then returns `None`).
    pub cancel: Option<&'a AtomicBool>,
    /// Pixels finished so far.
    pub done: AtomicU64,
    /// The stride of the last finished pass (0 before the first).
    pub pass_done: AtomicU64,
    /// Where `render` puts colours as tiles finish, when someone wants to
    /// look at the picture while it grows (crop-sized, row-major).
    pub canvas: Option<&'a Mutex<Vec<glam::Vec3>>>,
}

impl Job<'_> {
    pub fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }

    /// The rectangle traced for a `width`×`height` camera.
    pub fn rect(&self, width: u32, height: u32) -> Rect {
        self.crop.unwrap_or(Rect::full(width, height))
    }
}

/// Whether pixel (x, y) is traced in the pass of stride `s` (`first`:
/// the first pass's stride; later passes leave out what earlier ones did).
/// The strides are powers of two, so this is all masks, no division.
fn in_pass(x: u32, y: u32, s: u32, first: u32) -> bool {
    debug_assert!(s.is_power_of_two());
    let (on, on2) = (s - 1, 2 * s - 1);
    (x | y) & on == 0 && (s == first || x & on2 != 0 || y & on2 != 0)
}

/// Runs `f` for every pixel of the job's rectangle, in parallel over tiles,
/// writing into `out` (rectangle-sized, row-major). `None` if cancelled.
/// The result does not depend on the number of threads, the order tiles
/// finish in, or the passes.
pub(crate) fn per_pixel<T: Send + Copy>(
    width: u32,
    height: u32,
    job: &Job,
    out: &Mutex<Vec<T>>,
    f: impl Fn(u32, u32, &mut RayStats) -> T + Sync,
) -> Option<RayStats> {
    let r = job.rect(width, height);
    let tiles: Vec<(u32, u32)> = (r.y0..r.y1)
        .step_by(TILE as usize)
        .flat_map(|ty| (r.x0..r.x1).step_by(TILE as usize).map(move |tx| (tx, ty)))
        .collect();
    let passes: &[u32] = if job.progressive { &PASSES } else { &[1] };
    let mut stats = RayStats::default();
    for &s in passes {
        let pass_stats = tiles
            .par_iter()
            .map(|&(x0, y0)| {
                let mut st = RayStats::default();
                let (x1, y1) = ((x0 + TILE).min(r.x1), (y0 + TILE).min(r.y1));
                let mut done = Vec::with_capacity(((x1 - x0) * (y1 - y0)) as usize);
                for y in y0..y1 {
                    if job.cancelled() {
                        return st;
                    }
                    for x in x0..x1 {
                        if in_pass(x, y, s, passes[0]) {
                            done.push((x, y, f(x, y, &mut st)));
                        }
                    }
                }
                let mut o = out.lock().unwrap_or_else(|e| e.into_inner());
                for &(x, y, v) in &done {
                    o[((y - r.y0) * r.width() + (x - r.x0)) as usize] = v;
                }
                drop(o);
                job.done.fetch_add(done.len() as u64, Ordering::Relaxed);
                st
            })
            .reduce(RayStats::default, RayStats::add);
        stats = stats.add(pass_stats);
        if job.cancelled() {
            return None;
        }
        job.pass_done.store(s as u64, Ordering::Relaxed);
    }
    Some(stats)
}
