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

/// The sample passes of a progressive render of pixels with several
/// samples: every pixel up to 1 camera ray, then up to 4, 16, 64... (each
/// pass this many times the last), then on until every pixel is finished.
pub const SAMPLE_PASS_GROWTH: u32 = 4;

/// Whether pixel (x, y) is traced in the pass of stride `s` (`first`:
/// the first pass's stride; later passes leave out what earlier ones did).
/// The strides are powers of two, so this is all masks, no division.
fn in_pass(x: u32, y: u32, s: u32, first: u32) -> bool {
    debug_assert!(s.is_power_of_two());
    let (on, on2) = (s - 1, 2 * s - 1);
    (x | y) & on == 0 && (s == first || x & on2 != 0 || y & on2 != 0)
}

/// The tiles of a rectangle: their top-left corners, row by row.
fn tiles(r: Rect) -> Vec<(u32, u32)> {
    (r.y0..r.y1)
        .step_by(TILE as usize)
        .flat_map(|ty| (r.x0..r.x1).step_by(TILE as usize).map(move |tx| (tx, ty)))
        .collect()
}

/// Where `per_pixel` puts the pixels' values (rectangle-sized, row-major).
pub(crate) enum Out<'a, T> {
    /// The caller's own buffer: written in place, each thread on its own
    /// band of rows, with no lock and no copy.
    Own(&'a mut [T]),
    /// `Own`, and each band, once its last pass is traced, given to
    /// `Finish` while it is in cache.
    Finished(&'a mut [T], Finish<'a, T>),
    /// A buffer another thread looks at while the render runs (the
    /// preview): each tile is written under its lock when it finishes.
    Shared(&'a Mutex<Vec<T>>),
}

/// What an `Out::Finished` render makes of its pixels (a picture's bytes
/// for its file): `f(pixels, bytes)` for each band of rows once it is
/// traced, with its share of `bytes`, `per` bytes to a pixel. (Made after
/// the render instead, a 1024² picture's bytes took 1.6–1.9 ms on two
/// threads, reading its 12 MB of floats back from memory.)
pub(crate) struct Finish<'a, T> {
    bytes: &'a mut [u8],
    per: usize,
    f: &'a (dyn Fn(&mut [T], &mut [u8]) + Sync),
}

impl<'a, T: Send> Finish<'a, T> {
    /// `f` for a picture of `pixels` whose bytes go into `bytes` (made
    /// `per` times as long as the picture).
    pub fn new(
        bytes: &'a mut Vec<u8>,
        pixels: usize,
        per: usize,
        f: &'a (dyn Fn(&mut [T], &mut [u8]) + Sync),
    ) -> Finish<'a, T> {
        crate::image::resize_bytes(bytes, pixels * per);
        Finish { bytes, per, f }
    }

    /// `f` over all of `buf` at once, in bands on all threads (for renders
    /// whose bands are not finished one by one).
    fn all(self, buf: &mut [T]) {
        const BAND: usize = 16 * 1024;
        let f = self.f;
        let bytes = self.bytes.par_chunks_mut(BAND * self.per);
        buf.par_chunks_mut(BAND).zip(bytes).for_each(|(px, bytes)| f(px, bytes));
    }
}

/// Rows per band of an `Out::Own` render: a tile's height, or fewer when
/// the picture is short, so that every thread gets several bands.
fn band_rows(height: u32) -> u32 {
    let threads = rayon::current_num_threads().max(1) as u32;
    (height / (4 * threads)).clamp(1, TILE)
}

/// Runs `f` for every pixel of the job's rectangle, in parallel, writing
/// into `out`. `None` if cancelled. The result does not depend on the
/// number of threads, the order tiles finish in, or the passes.
pub(crate) fn per_pixel<T: Send + Copy>(
    width: u32,
    height: u32,
    job: &Job,
    out: Out<T>,
    f: impl Fn(u32, u32, &mut RayStats) -> T + Sync,
) -> Option<RayStats> {
    per_block(width, height, job, out, |px, st, values| {
        values.extend(px.iter().map(|&(x, y)| f(x, y, st)));
    })
}

/// Pixels go in blocks of at most this many on a side (within a tile),
/// so that their camera rays can be traced together.
pub(crate) const BLOCK: u32 = 8;

/// `per_pixel` a block at a time: `f(pixels, stats, values)` traces the
/// pixels of one block (at most `BLOCK`×`BLOCK` of one tile, those of the
/// pass, row by row) and pushes their values onto `values`, in order.
pub(crate) fn per_block<T: Send + Copy>(
    width: u32,
    height: u32,
    job: &Job,
    out: Out<T>,
    f: impl Fn(&[(u32, u32)], &mut RayStats, &mut Vec<T>) + Sync,
) -> Option<RayStats> {
    let r = job.rect(width, height);
    let passes: &[u32] = if job.progressive { &PASSES } else { &[1] };
    let (buf, finish) = match out {
        Out::Own(buf) => (buf, None),
        Out::Finished(buf, finish) => (buf, Some(finish)),
        Out::Shared(m) => return per_tile(r, passes, job, m, f),
    };
    debug_assert_eq!(buf.len() as u64, r.pixels());
    let w = r.width() as usize;
    let rows = band_rows(r.height());
    let band = (w * rows as usize).max(1);
    // Each band's share of the bytes (without `finish`, a placeholder
    // byte per band, so the bands are zipped with something alike).
    let mut none = vec![0u8; buf.len().div_ceil(band)];
    let (bytes, per_band, finish) = match finish {
        Some(Finish { bytes, per, f }) => (bytes, band * per, Some(f)),
        None => (&mut none[..], 1, None),
    };
    let last = passes[passes.len() - 1];
    in_passes(job, passes, |s| {
        buf.par_chunks_mut(band)
            .zip(bytes.par_chunks_mut(per_band))
            .enumerate()
            .map(|(band, (px, bytes))| {
                let mut st = RayStats::default();
                let y0 = r.y0 + band as u32 * rows;
                let y1 = (y0 + rows).min(r.y1);
                let (mut pixels, mut values) = (Vec::new(), Vec::new());
                // Tile by tile along the band, for coherent rays.
                for tx in (r.x0..r.x1).step_by(TILE as usize) {
                    let tile = (tx, (tx + TILE).min(r.x1), y0, y1);
                    let mut n = 0;
                    let whole = blocks(job, tile, (s, passes[0]), &mut pixels, |block| {
                        values.clear();
                        f(block, &mut st, &mut values);
                        // Run by run along the rows (a block's row, or in a
                        // later pass single pixels).
                        let mut done = 0;
                        for run in block.chunk_by(|a, b| a.1 == b.1 && b.0 == a.0 + 1) {
                            let (x, y) = run[0];
                            let at = (y - y0) as usize * w + (x - r.x0) as usize;
                            let end = (done + run.len()).min(values.len());
                            px[at..at + (end - done)].copy_from_slice(&values[done..end]);
                            done = end;
                        }
                        n += block.len() as u64;
                    });
                    if !whole {
                        return st;
                    }
                    job.done.fetch_add(n, Ordering::Relaxed);
                }
                if let Some(finish) = finish.filter(|_| s == last) {
                    finish(px, bytes);
                }
                st
            })
            .reduce(RayStats::default, RayStats::add)
    })
}

/// Runs `pass(stride)` for each pass of `passes` in turn, adding up their
/// ray counts; `None` when the job is cancelled.
fn in_passes(job: &Job, passes: &[u32], mut pass: impl FnMut(u32) -> RayStats) -> Option<RayStats> {
    let mut stats = RayStats::default();
    for &s in passes {
        stats = stats.add(pass(s));
        if job.cancelled() {
            return None;
        }
        job.pass_done.store(s as u64, Ordering::Relaxed);
    }
    Some(stats)
}

/// `per_block` into a shared buffer, a tile at a time.
fn per_tile<T: Send + Copy>(
    r: Rect,
    passes: &[u32],
    job: &Job,
    out: &Mutex<Vec<T>>,
    f: impl Fn(&[(u32, u32)], &mut RayStats, &mut Vec<T>) + Sync,
) -> Option<RayStats> {
    let tiles = tiles(r);
    in_passes(job, passes, |s| {
        tiles
            .par_iter()
            .map(|&(x0, y0)| {
                let mut st = RayStats::default();
                let tile = (x0, (x0 + TILE).min(r.x1), y0, (y0 + TILE).min(r.y1));
                let mut done = Vec::with_capacity((TILE * TILE) as usize);
                let (mut pixels, mut values) = (Vec::new(), Vec::new());
                let whole = blocks(job, tile, (s, passes[0]), &mut pixels, |block| {
                    values.clear();
                    f(block, &mut st, &mut values);
                    done.extend(block.iter().zip(&values).map(|(&(x, y), &v)| (x, y, v)));
                });
                if !whole {
                    return st;
                }
                put(out, r, &done);
                job.done.fetch_add(done.len() as u64, Ordering::Relaxed);
                st
            })
            .reduce(RayStats::default, RayStats::add)
    })
}

/// Calls `each(pixels)` for each block of the tile `x0..x1` by `y0..y1`
/// that has pixels in the pass of stride `s` (`first`: the first pass's),
/// with those pixels row by row (gathered in `pixels`). False if the job
/// was cancelled.
fn blocks(
    job: &Job,
    (x0, x1, y0, y1): (u32, u32, u32, u32),
    (s, first): (u32, u32),
    pixels: &mut Vec<(u32, u32)>,
    mut each: impl FnMut(&[(u32, u32)]),
) -> bool {
    for by in (y0..y1).step_by(BLOCK as usize) {
        for bx in (x0..x1).step_by(BLOCK as usize) {
            if job.cancelled() {
                return false;
            }
            pixels.clear();
            for y in by..(by + BLOCK).min(y1) {
                let xs = bx..(bx + BLOCK).min(x1);
                if s == 1 && first == 1 {
                    // One pass: every pixel.
                    pixels.extend(xs.map(|x| (x, y)));
                    continue;
                }
                pixels.extend(xs.filter(|&x| in_pass(x, y, s, first)).map(|x| (x, y)));
            }
            if !pixels.is_empty() {
                each(pixels);
            }
        }
    }
    true
}

/// Where a finished tile's pixels go: (x, y, value) each.
type Sink<'a, T> = &'a (dyn Fn(&[(u32, u32, T)]) + Sync);

/// Writes a finished tile's pixels into a shared buffer.
fn put<T: Copy, V: std::ops::DerefMut<Target = [T]>>(
    out: &Mutex<V>,
    r: Rect,
    done: &[(u32, u32, T)],
) {
    let mut o = out.lock().unwrap_or_else(|e| e.into_inner());
    for &(x, y, v) in done {
        o[((y - r.y0) * r.width() + (x - r.x0)) as usize] = v;
    }
}

/// A pixel of a sample-progressive render: its state between passes, and
/// whether it is finished.
struct Kept<S> {
    state: S,
    finished: bool,
}

/// `per_pixel` for pixels traced in several camera rays:
/// `f(x, y, state, until, stats)` advances a pixel's `state` up to `until`
/// camera rays in all (`u32::MAX`: to the end) and returns its value so far
/// and whether it is finished. With `progressive`, every pixel's state is
/// kept between passes of `SAMPLE_PASS_GROWTH`-fold more rays, and each
/// pass writes every pixel's value so far: a coarse picture of the whole
/// first, converging pass by pass. `expected` (camera rays per pixel)
/// paces the progress count. Each pixel runs the same steps either way, so
/// the final picture is the non-progressive one, to the bit. Without
/// `progressive`, `per_pixel` with a fresh state per pixel.
pub(crate) fn per_pixel_passes<S: Default + Send, T: Send + Copy>(
    width: u32,
    height: u32,
    job: &Job,
    out: Out<T>,
    (progressive, expected): (bool, u32),
    f: impl Fn(u32, u32, &mut S, u32, &mut RayStats) -> (T, bool) + Sync,
) -> Option<RayStats> {
    if !progressive {
        return per_pixel(width, height, job, out, |x, y, st| {
            f(x, y, &mut S::default(), u32::MAX, st).0
        });
    }
    let r = job.rect(width, height);
    // Tiles finish in any order and pass by pass: each writes under a lock.
    let (own, shared, finish) = match out {
        Out::Own(buf) => (Some(Mutex::new(buf)), None, None),
        Out::Finished(buf, finish) => (Some(Mutex::new(buf)), None, Some(finish)),
        Out::Shared(m) => (None, Some(m), None),
    };
    let sink = |done: &[(u32, u32, T)]| match (&own, shared) {
        (Some(own), _) => put(own, r, done),
        (None, Some(m)) => put(m, r, done),
        (None, None) => {}
    };
    let out: Sink<T> = &sink;
    // Each tile's corner and its pixels' states.
    type Tile<S> = ((u32, u32), Vec<Kept<S>>);
    let mut tiles: Vec<Tile<S>> = tiles(r)
        .into_iter()
        .map(|(x0, y0)| {
            let n = (TILE.min(r.x1 - x0) * TILE.min(r.y1 - y0)) as usize;
            ((x0, y0), (0..n).map(|_| Kept { state: S::default(), finished: false }).collect())
        })
        .collect();
    let mut stats = RayStats::default();
    let (mut before, mut until) = (0u32, 1u32);
    loop {
        // Progress: this pass's share of the expected rays (telescoping,
        // so a tile's shares add up to its pixels).
        let share = |pixels: usize| {
            let part = |k: u32| pixels as u64 * k.min(expected) as u64 / expected.max(1) as u64;
            part(until) - part(before)
        };
        let (pass_stats, unfinished) = tiles
            .par_iter_mut()
            .map(|((x0, y0), kept)| {
                let mut st = RayStats::default();
                let (x0, y0) = (*x0, *y0);
                let (x1, y1) = ((x0 + TILE).min(r.x1), (y0 + TILE).min(r.y1));
                let mut done = Vec::with_capacity(kept.len());
                let mut left = 0usize;
                for y in y0..y1 {
                    if job.cancelled() {
                        return (st, 0);
                    }
                    for x in x0..x1 {
                        let k = &mut kept[((y - y0) * (x1 - x0) + (x - x0)) as usize];
                        if k.finished {
                            continue;
                        }
                        let (v, finished) = f(x, y, &mut k.state, until, &mut st);
                        k.finished = finished;
                        left += !finished as usize;
                        done.push((x, y, v));
                    }
                }
                out(&done);
                job.done.fetch_add(share(kept.len()), Ordering::Relaxed);
                (st, left)
            })
            .reduce(|| (RayStats::default(), 0), |a, b| (a.0.add(b.0), a.1 + b.1));
        stats = stats.add(pass_stats);
        if job.cancelled() {
            return None;
        }
        // Every pixel has a value from the first pass on.
        job.pass_done.store(1, Ordering::Relaxed);
        if unfinished == 0 {
            if let (Some(finish), Some(own)) = (finish, own) {
                finish.all(own.into_inner().unwrap_or_else(|e| e.into_inner()));
            }
            return Some(stats);
        }
        (before, until) = (until, until.saturating_mul(SAMPLE_PASS_GROWTH));
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Bands in place and tiles under a lock give the same buffer: every
    /// pixel of the rectangle written once, with its own value, cropped or
    /// not, in passes or not, on a picture short enough for 1-row bands.
    #[test]
    fn bands_and_tiles_write_the_same_pixels() {
        let (w, h) = (53u32, 37u32);
        let crop = Rect { x0: 5, y0: 3, x1: 50, y1: 36 };
        for (progressive, crop, height) in [
            (false, None, h),
            (true, None, h),
            (false, Some(crop), h),
            (true, Some(crop), h),
            (false, None, 3),
        ] {
            let job = |progressive| Job { progressive, crop, ..Job::default() };
            let r = job(progressive).rect(w, height);
            let f = |x: u32, y: u32, st: &mut RayStats| {
                st.primary += 1;
                x * 1000 + y
            };
            let own_job = job(progressive);
            let mut own = vec![0u32; r.pixels() as usize];
            let a = per_pixel(w, height, &own_job, Out::Own(&mut own), f).unwrap();
            let shared = Mutex::new(vec![0u32; r.pixels() as usize]);
            let b = per_pixel(w, height, &job(progressive), Out::Shared(&shared), f).unwrap();
            let want: Vec<u32> =
                (r.y0..r.y1).flat_map(|y| (r.x0..r.x1).map(move |x| x * 1000 + y)).collect();
            assert_eq!(own, want);
            assert_eq!(shared.into_inner().unwrap(), want);
            assert_eq!((a.primary, b.primary), (r.pixels(), r.pixels()));
            assert_eq!(own_job.done.load(Ordering::Relaxed), r.pixels());
        }
    }

    /// Progressive sample passes: every pixel gets its first ray before any
    /// gets a second pass, then 4, 16... rays in all, until each says it is
    /// finished (never asked again after); the values written are the last.
    #[test]
    fn sample_passes_advance_every_pixel_in_turn() {
        let (w, h) = (37u32, 21u32);
        let job = Job { progressive: true, ..Job::default() };
        let mut out = vec![0u32; (w * h) as usize];
        let calls = Mutex::new(Vec::new());
        // Pixel x finishes at 16 rays, or at 4 for odd x.
        let stats = per_pixel_passes(
            w,
            h,
            &job,
            Out::Own(&mut out),
            (true, 16),
            |x, y, rays: &mut u32, until, _| {
                let end = if x % 2 == 1 { 4 } else { 16 };
                *rays = until.min(end);
                calls.lock().unwrap().push((until, x, y));
                (*rays, *rays == end)
            },
        );
        assert!(stats.is_some());
        let calls = calls.into_inner().unwrap();
        let untils: Vec<u32> = calls.iter().map(|c| c.0).collect();
        assert!(untils.windows(2).all(|p| p[0] <= p[1]), "passes in order");
        let count = |u: u32| untils.iter().filter(|&&v| v == u).count() as u32;
        assert_eq!([count(1), count(4), count(16), count(64)], [w * h, w * h, 19 * h, 0]);
        assert!((0..w * h).all(|i| out[i as usize] == if i % w % 2 == 1 { 4 } else { 16 }));
        assert_eq!(job.done.load(Ordering::Relaxed), (w * h) as u64);
        assert_eq!(job.pass_done.load(Ordering::Relaxed), 1);
    }
}
