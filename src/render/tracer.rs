//! The Whitted tracer. Shading (per the COS 426 rayshell):
//!
//! ```text
//!   Ka·ambient·colour
//! + Σ lights a shadow ray reaches: [Kd·colour·light·max(0, N·L) + Ks·light·max(0, R·V)^n_s]
//! + Ks·(reflected ray) + T·colour·(transmitted ray, Snell's law)
//! ```
//!
//! Glass filters by T·colour (the texture's where it has one) at each
//! surface crossed, for the view through it and for the shadows it casts
//! alike. Total internal reflection sends
//! everything that would have been transmitted back in, undimmed.
//! Refraction follows the media a ray is inside (`Media`), so an air
//! bubble in glass bends light from 1.5 to 1, not from 1 to 1.
//!
//! Robustness: the scene is relative to the eye, and secondary rays start
//! off the surface by a fixed fraction of the coordinates' magnitude
//! (`offset`), so the picture is the same at any translation or scale.
//! Shadow rays of smooth triangles start from Hanika's point on the
//! smooth surface ("Hacking the shadow terminator", Ray Tracing Gems II,
//! ch. 4), so coarse meshes show no facet-shaped notches.

use glam::Vec3;

use super::job::{BLOCK, Finish, Job, Out, per_block, per_pixel, per_pixel_passes};
use super::sample::{self, FilterTable};
use crate::geometry::{
    Aabb, Hit, Local, Located, Occluder, PACKET, Ray, Shadow, ShadowHit, Triangle, finite,
    intersect_brute,
};
use crate::image::{Encoding, Image};
use crate::scene::{Highlight, Integrator, Material, Scene, texture};

/// Mixed into a batch's key for its pattern of times.
const TIME: u64 = 0x7469_6d65;

// A block of pixels' camera rays fit in one packet.
const _: () = assert!((BLOCK * BLOCK) as usize <= PACKET);

/// A ray whose contribution to its pixel is below this is not traced.
const MIN_WEIGHT: f32 = 1.0 / 1024.0;

/// The most rays one pixel's ray tree may cast (shadow rays included):
/// a scene whose surfaces both reflect and transmit everything (`Ks + T`
/// ≥ 1) doubles its rays at every bounce, 2⁶⁴ at `trace_depth 64`. Past
/// the limit, branches add nothing more. A Whitted pixel of a sane scene
/// casts tens of rays.
pub const MAX_RAYS_PER_PIXEL: u64 = 10_000;

#[derive(Clone, Copy, Debug, Default)]
pub struct RayStats {
    pub primary: u64,
    pub shadow: u64,
    pub reflected: u64,
    pub refracted: u64,
    pub bvh_steps: u64,
    /// The ray count (`total`) at which the current pixel's tree stops
    /// branching; 0: no limit.
    pub limit: u64,
    /// The current camera ray's random key before its mix (`key`), and
    /// how many shading points have drawn from it (`next_dim`). (Mixed
    /// where it is used: most camera rays draw nothing, and mixing each
    /// pixel's key was 15 % of an ambient-only render's own work.)
    pub seed: u64,
    pub dim: u32,
    /// What blocked the last shadow ray toward each light (by its number,
    /// modulo `OCCLUDERS`) that this thread traced in this band or tile:
    /// where the next one looks first. Speed only: no value depends on it.
    pub occluders: [Occluder; OCCLUDERS],
}

/// How many lights' last occluders `RayStats` keeps (eight: the SPD
/// scenes have up to seven lights; with four, lattice-s8's six shared
/// slots and its render took 4–8 % longer).
pub const OCCLUDERS: usize = 8;

impl RayStats {
    pub(crate) fn add(self, o: RayStats) -> RayStats {
        RayStats {
            primary: self.primary + o.primary,
            shadow: self.shadow + o.shadow,
            reflected: self.reflected + o.reflected,
            refracted: self.refracted + o.refracted,
            bvh_steps: self.bvh_steps + o.bvh_steps,
            limit: 0,
            seed: 0,
            dim: 0,
            occluders: self.occluders,
        }
    }

    /// A fresh dimension of the camera ray's random numbers.
    pub(crate) fn next_dim(&mut self) -> u32 {
        self.dim += 1;
        self.dim
    }

    /// Starts a camera ray: its ray budget and its random numbers, whose
    /// key is `sample::mix(seed)`.
    pub(super) fn start(&mut self, seed: u64) {
        self.primary += 1;
        self.limit = self.total() + MAX_RAYS_PER_PIXEL;
        self.seed = seed;
        self.dim = 0;
    }

    /// The current camera ray's random key.
    #[inline]
    pub(crate) fn key(&self) -> u64 {
        sample::mix(self.seed)
    }

    pub fn total(&self) -> u64 {
        self.primary + self.shadow + self.reflected + self.refracted
    }
}

/// Mirror `d` about `n`.
pub fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - 2.0 * d.dot(n) * n
}

/// Refract unit `d` through a surface with unit normal `n` facing against
/// `d`, with `eta` = n_from / n_to; `None` on total internal reflection.
pub fn refract(d: Vec3, n: Vec3, eta: f32) -> Option<Vec3> {
    let cos_i = -d.dot(n);
    let k = 1.0 - eta * eta * (1.0 - cos_i * cos_i);
    if k < 0.0 {
        return None;
    }
    Some(eta * d + (eta * cos_i - k.sqrt()) * n)
}

/// A secondary ray starts this fraction of the coordinates' magnitude off
/// the surface (2⁻¹³, about 10⁻⁴: some 1,000 units in the last place of
/// single precision, well above the error of a hit point).
pub(super) const OFFSET: f32 = 1.0 / 8192.0;

/// How far to move a secondary ray's origin off the surface at `p`, hit by
/// a ray from `o`. Coordinates are relative to the eye, so this scales
/// with the scene and does not change when the scene (with its camera)
/// moves.
pub(super) fn offset(p: Vec3, o: Vec3) -> f32 {
    (OFFSET * p.abs().max(o.abs()).max_element()).max(f32::MIN_POSITIVE)
}

/// The most nested media a ray keeps track of; deeper, the outermost is
/// forgotten.
const MAX_MEDIA: usize = 6;

/// The media a ray travels in, innermost last: for each enclosure entered
/// and not left, its material and index of refraction. Outside them all is
/// air (index 1). An enclosure is known by its material: entering a surface
/// pushes its material, leaving one removes the innermost entry with that
/// material (so overlapping objects of one glass behave as their union).
#[derive(Clone, Copy, Debug, Default)]
pub struct Media {
    len: u8,
    items: [(u32, f32); MAX_MEDIA],
}

impl Media {
    /// The index of refraction the ray travels in.
    pub fn ior(&self) -> f32 {
        match self.len {
            0 => 1.0,
            n => self.items[n as usize - 1].1,
        }
    }

    /// Inside the enclosure of `material` as well.
    pub fn enter(mut self, material: u32, ior: f32) -> Media {
        if self.len as usize == MAX_MEDIA {
            self.items.copy_within(1.., 0);
            self.len -= 1;
        }
        self.items[self.len as usize] = (material, ior);
        self.len += 1;
        self
    }

    /// Out of the innermost enclosure of `material` (unchanged if the ray
    /// was not known to be inside one: a camera inside glass, an open mesh).
    pub fn leave(mut self, material: u32) -> Media {
        let n = self.len as usize;
        if let Some(i) = self.items[..n].iter().rposition(|&(m, _)| m == material) {
            self.items.copy_within(i + 1..n, i);
            self.len -= 1;
        }
        self
    }
}

/// Renders the job's part of the picture; also returns the ray counts.
/// `None` if the job was cancelled.
pub fn render(scene: &Scene, job: &Job) -> Option<(Image, RayStats)> {
    render_into(scene, job, Vec::new())
}

/// `render` into `buf` when it has the picture's size (an earlier picture
/// of the same size: its pages are in place, and every pixel is written
/// again before the picture is returned); else into a fresh buffer.
pub fn render_into(scene: &Scene, job: &Job, buf: Vec<Vec3>) -> Option<(Image, RayStats)> {
    render_bands(scene, job, buf, None).map(|(img, st, _)| (img, st))
}

/// `render_into`, finishing the picture for a file as it is traced: each
/// band of rows, once traced, gets the look (`apply_look`) and is made
/// into bytes in `enc` (into `bytes`, as `Image::to_rgb8_into` makes
/// them) while it is in cache. The flag says whether it was done: not
/// while another thread watches the picture grow (`job.canvas`); then the
/// picture is as `render_into` makes it.
pub fn render_finished(
    scene: &Scene,
    job: &Job,
    buf: Vec<Vec3>,
    bytes: &mut Vec<u8>,
    enc: Encoding,
) -> Option<(Image, RayStats, bool)> {
    render_bands(scene, job, buf, Some((bytes, enc)))
}

fn render_bands(
    scene: &Scene,
    job: &Job,
    buf: Vec<Vec3>,
    bytes: Option<(&mut Vec<u8>, Encoding)>,
) -> Option<(Image, RayStats, bool)> {
    let cam = &scene.camera;
    let r = job.rect(cam.width, cam.height);
    let n = r.pixels() as usize;
    let mut own = match job.canvas {
        Some(_) => Vec::new(),
        None if buf.len() == n => buf,
        None => {
            drop(buf);
            crate::image::filled(n, Vec3::ZERO)
        }
    };
    let sampling = &scene.sampling;
    let enc = bytes.as_ref().map_or(Encoding::Linear, |b| b.1);
    let finish = |px: &mut [Vec3], out: &mut [u8]| {
        look_pixels(sampling, px);
        crate::image::rgb8_of(px, enc, out);
    };
    let finished = job.canvas.is_none() && bytes.is_some();
    let out = match (job.canvas, bytes) {
        (Some(c), _) => Out::Shared(c),
        (None, Some((bytes, _))) => Out::Finished(&mut own, Finish::new(bytes, n, 3, &finish)),
        (None, None) => Out::Own(&mut own),
    };
    let table = FilterTable::new(sampling.filter);
    let sampled = sampling.samples > 1
        || sampling.integrator == Integrator::Path
        || sampling.noise_target.is_some()
        || cam.has_lens()
        || sampling.adaptive.is_some()
        || sampling.has_shutter();
    let stats = if sampled {
        // Sample passes when asked for, if the pixels' states fit.
        let progressive = job.progressive
            && crate::mem::reserve_n(r.pixels() as usize, std::mem::size_of::<Pixel>() + 8).is_ok();
        let pace = (progressive, sampling.samples);
        per_pixel_passes(
            cam.width,
            cam.height,
            job,
            out,
            pace,
            |x, y, p: &mut Pixel, until, st| {
                p.advance(scene, &table, (x, y), until, st, &|| job.cancelled())
            },
        )?
    } else {
        let frame = sample::frame_key(sampling);
        let whitted = sampling.integrator == Integrator::Whitted;
        // Whether a miss sees the background alone (`seen`): no light with
        // a size to see, no environment. (A block whose rays all miss is
        // then coloured without the tracer's set-up per ray: a render whose
        // rays all miss 9 -> 8.4 ms at 1024².)
        let plain = scene.emitters.is_empty() && !scene.has_environment;
        // The box around everything a camera ray can hit, and the boxes
        // of the tree's top two levels, when a miss sees the background
        // alone and there is a box (no plane).
        let bounds = scene.bvh.bounds();
        let cull = plain && !bounds.is_empty();
        let top = if cull { scene.bvh.top_boxes() } else { Vec::new() };
        per_block(cam.width, cam.height, job, out, |px, st, values| {
            // The pixel centres, as COS 426 traces them.
            let ray = |&(x, y): &(u32, u32)| cam.ray(x, y).at_time(sampling.shutter[0]);
            let start = |st: &mut RayStats, (x, y): (u32, u32)| {
                st.start(sample::seed_of_pixel(frame, y as u64 * cam.width as u64 + x as u64));
            };
            if !whitted {
                for p in px {
                    start(st, *p);
                    values.push(camera_ray(scene, &ray(p), st));
                }
                return;
            }
            let n = px.len().min(PACKET);
            if cull && n > 0 {
                // A block whose rays all pass beside the scene's box, or
                // beside each box of the root's children (or of theirs),
                // sees the background alone: no ray is made (its rays are
                // sound, and count no steps).
                let (x0, y0, x1, y1) =
                    px[..n].iter().fold((u32::MAX, u32::MAX, 0, 0), |(a, b, c, d), &(x, y)| {
                        (a.min(x), b.min(y), c.max(x), d.max(y))
                    });
                let rect = (x0 as f32, y0 as f32, (x1 + 1) as f32, (y1 + 1) as f32);
                let beside = cam.pyramid(rect).is_some_and(|p| {
                    let out = |b: &Aabb| p.misses(b.min, b.max);
                    out(&bounds)
                        || top.iter().all(|(b, inner)| {
                            out(b) || (!inner.is_empty() && inner.iter().all(out))
                        })
                });
                if beside {
                    st.primary += n as u64;
                    values.extend(std::iter::repeat_n(scene.background, n));
                    return;
                }
            }
            // The block's camera rays found together, then each shaded.
            let mut rays = [Ray::new(Vec3::ZERO, Vec3::ZERO); PACKET];
            let mut hits = [(None, 0); PACKET];
            cam.rays_into(&px[..n], sampling.shutter[0], &mut rays[..n]);
            scene.intersect_packet(&rays[..n], &mut hits[..n]);
            if plain && hits[..n].iter().all(|h| h.0.is_none()) {
                // Every ray missed: each sees the background (`seen`), and
                // is counted as `trace_from` counts it. None needs starting:
                // a miss draws no random numbers and traces no ray.
                st.primary += n as u64;
                for (r, &(_, steps)) in rays[..n].iter().zip(&hits[..n]) {
                    let ok = sound(r);
                    st.bvh_steps += if ok { steps as u64 } else { 0 };
                    values.push(if ok { scene.background } else { Vec3::ZERO });
                }
                return;
            }
            let begin = |i: usize, st: &mut RayStats| start(st, px[i]);
            shade_packet(scene, (&rays[..n], &hits[..n]), st, begin, |_, c| values.push(c));
        })?
    };
    // The picture itself, not a copy of it (64 Mpixel are 768 MiB).
    let pixels = match job.canvas {
        None => own,
        Some(c) => c.lock().unwrap_or_else(|e| e.into_inner()).clone(),
    };
    Some((Image { width: r.width(), height: r.height(), pixels }, stats, finished))
}

/// The colours seen along camera rays `rays`, whose closest hits (and
/// steps) `hits` were found together (`Scene::intersect_packet`), by the
/// Whitted tracer: `begin(i, st)` starts ray `i`'s count and random numbers,
/// then `done(i, colour)` takes its colour, in order. Where the shadow
/// rays of the hits go in packets (`packet_shadows`), every hit's shading
/// point is worked out first, then the shadow rays toward each light of
/// one point together (`block_shadows`), then the rest of the shading:
/// the same colours as shading each ray alone, to the bit.
#[inline(always)]
fn shade_packet(
    scene: &Scene,
    (rays, hits): (&[Ray], &[(Option<Hit>, u32)]),
    st: &mut RayStats,
    mut begin: impl FnMut(usize, &mut RayStats),
    mut done: impl FnMut(usize, Vec3),
) {
    let n = rays.len().min(hits.len()).min(PACKET);
    if !packet_shadows(scene) {
        for (i, (r, &found)) in rays.iter().zip(hits).enumerate().take(n) {
            begin(i, st);
            done(i, trace_from(scene, r, found, st));
        }
        return;
    }
    let mut points = [const { None::<Shading> }; PACKET];
    for ((s, r), (hit, _)) in points.iter_mut().zip(&rays[..n]).zip(hits) {
        if let Some(h) = hit
            && r.origin.is_finite()
            && r.dir.is_finite()
        {
            *s = Some(Shading::new(scene, r, h));
        }
    }
    let known = block_shadows(scene, &rays[..n], &points[..n], st);
    for (i, r) in rays.iter().enumerate().take(n) {
        begin(i, st);
        let (hit, steps) = hits[i];
        let c = match &points[i] {
            Some(s) if traceable(r, st) => {
                st.bvh_steps += steps as u64;
                lit(scene, r, s, (0, 1.0, Media::default()), &known[i], st)
            }
            _ => trace_from(scene, r, (hit, steps), st),
        };
        done(i, c);
    }
}

/// A pixel traced in several camera rays, in batches: the first of
/// `samples`, then (adaptive sampling) batches of at least 4 while the
/// mean's standard error is above the threshold, up to its maximum. Kept
/// between the passes of a progressive render; each batch is stratified on
/// its own pattern.
#[derive(Default)]
struct Pixel {
    acc: PixelSum,
    /// The current batch, its size (0: not started) and its next sample.
    batch: u64,
    n: u32,
    s: u32,
}

impl Pixel {
    /// Traces camera rays until the pixel has `until` of them or is
    /// finished; returns its value so far and whether it is finished. A
    /// cancelled job stops it between packets of camera rays (a pixel of
    /// 65,536 samples is minutes of work; a packet, milliseconds at most);
    /// its value is then thrown away with the rest of the picture.
    fn advance(
        &mut self,
        scene: &Scene,
        table: &FilterTable,
        (x, y): (u32, u32),
        until: u32,
        st: &mut RayStats,
        cancelled: &dyn Fn() -> bool,
    ) -> (Vec3, bool) {
        let (cam, sampling) = (&scene.camera, &scene.sampling);
        let [t0, t1] = sampling.shutter;
        let first = sample::pixel_key(sampling, y as u64 * cam.width as u64 + x as u64);
        if self.n == 0 {
            self.n = sampling.samples;
        }
        // Without a lens, a batch's camera rays leave one point: their
        // hits are found as one packet (the same hits).
        let together = !cam.has_lens();
        loop {
            if self.acc.count >= until {
                return (self.acc.value(), false);
            }
            if cancelled() {
                return (self.acc.value(), true);
            }
            let (s, n) = (self.s, self.n);
            let key = if self.batch == 0 { first } else { sample::mix(first ^ self.batch) };
            // Image points, lens points and times from three patterns,
            // stratified each.
            let (pattern, lens_pattern) = (key as u32, (key >> 32) as u32);
            // The rest of the batch, as far as this pass goes.
            let todo = (n - s).min(until - self.acc.count).min(PACKET as u32) as usize;
            let mut rays = [Ray::new(Vec3::ZERO, Vec3::ZERO); PACKET];
            let mut weights = [0.0; PACKET];
            for (j, (ray, w)) in rays.iter_mut().zip(&mut weights).take(todo).enumerate() {
                let s = s + j as u32;
                let (u, v) = sample::cmj(s, n, pattern);
                let ((dx, wx), (dy, wy)) = (table.sample(u), table.sample(v));
                let (lu, lv) =
                    if cam.has_lens() { sample::cmj(s, n, lens_pattern) } else { (0.5, 0.5) };
                let time = if sampling.has_shutter() {
                    t0 + (t1 - t0) * sample::cmj(s, n, sample::mix(key ^ TIME) as u32).0
                } else {
                    t0
                };
                *ray = cam.lens_ray(x as f32 + 0.5 + dx, y as f32 + 0.5 + dy, lu, lv).at_time(time);
                *w = wx * wy;
            }
            // The cap on rays is per camera ray.
            let begin = |j: usize, st: &mut RayStats| {
                st.start(key ^ ((s + j as u32) as u64) << 32);
            };
            if together && todo >= 2 {
                let mut hits = [(None, 0); PACKET];
                scene.intersect_packet(&rays[..todo], &mut hits[..todo]);
                if sampling.integrator == Integrator::Whitted {
                    let done = |j: usize, c| self.acc.add(c, weights[j]);
                    shade_packet(scene, (&rays[..todo], &hits[..todo]), st, begin, done);
                } else {
                    for (j, ray) in rays.iter().enumerate().take(todo) {
                        begin(j, st);
                        let c = super::path::radiance_from(scene, ray, Some(hits[j]), st);
                        self.acc.add(c, weights[j]);
                    }
                }
            } else {
                for (j, ray) in rays.iter().enumerate().take(todo) {
                    begin(j, st);
                    self.acc.add(camera_ray(scene, ray, st), weights[j]);
                }
            }
            self.s += todo as u32;
            if self.s == n {
                if sampling.adaptive.is_none() && sampling.noise_target.is_none() {
                    return (self.acc.value(), true);
                }
                // Done when the absolute (`adaptive`) or the relative
                // (`--noise-target`) standard error is low enough.
                let max =
                    sampling.adaptive.map_or(crate::scene::Sampling::DEFAULT_ADAPTIVE_MAX, |a| a.1);
                let se = self.acc.standard_error();
                let mean = (self.acc.lum / self.acc.count as f64) as f32;
                let done = sampling.adaptive.is_some_and(|(threshold, _)| se <= threshold)
                    || sampling.noise_target.is_some_and(|x| se <= x * mean);
                let n = sampling.samples.max(4);
                if self.acc.count + n > max || done {
                    return (self.acc.value(), true);
                }
                (self.batch, self.s, self.n) = (self.batch + 1, 0, n);
            }
        }
    }
}

/// A pixel's samples so far: the filter-weighted sum, and the plain sums
/// of colour and of luminance (and its square) for adaptive sampling.
#[derive(Default)]
struct PixelSum {
    sum: Vec3,
    weights: f32,
    plain: Vec3,
    count: u32,
    lum: f64,
    lum2: f64,
}

impl PixelSum {
    fn add(&mut self, c: Vec3, w: f32) {
        self.sum += w * c;
        self.weights += w;
        self.plain += c;
        self.count += 1;
        let l = c.dot(Vec3::new(0.2126, 0.7152, 0.0722)) as f64;
        self.lum += l;
        self.lum2 += l * l;
    }

    /// The standard error of the mean luminance (infinite with one sample).
    fn standard_error(&self) -> f32 {
        if self.count < 2 {
            return f32::INFINITY;
        }
        let n = self.count as f64;
        let var = ((self.lum2 - self.lum * self.lum / n) / (n - 1.0)).max(0.0);
        (var / n).sqrt() as f32
    }

    /// The filter-weighted mean. Negative lobes (Mitchell) can leave too
    /// little weight with few samples: the plain mean then.
    fn value(&self) -> Vec3 {
        if self.weights > 0.25 * self.count as f32 {
            self.sum / self.weights
        } else {
            self.plain / self.count as f32
        }
    }
}

/// Applies the scene's exposure and tone map to a rendered picture (the
/// last step before it is written).
pub fn apply_look(sampling: &crate::scene::Sampling, img: &mut Image) {
    look_pixels(sampling, &mut img.pixels);
}

/// `Sampling::look` on each of `px`, unless it changes no colour.
fn look_pixels(sampling: &crate::scene::Sampling, px: &mut [Vec3]) {
    if sampling.exposure != 0.0 || sampling.tonemap != crate::scene::Tonemap::Clamp {
        px.iter_mut().for_each(|p| *p = sampling.look(*p));
    }
}

/// The cost picture: each pixel coloured by the BVH traversal steps of its
/// primary ray (nodes entered and leaf blocks tested), from black through
/// blue, red and yellow to white at the most.
pub fn render_heatmap(scene: &Scene, job: &Job) -> Option<(Image, RayStats)> {
    let cam = &scene.camera;
    let r = job.rect(cam.width, cam.height);
    let mut counts = vec![0u32; r.pixels() as usize];
    let stats = per_pixel(cam.width, cam.height, job, Out::Own(&mut counts), |x, y, st| {
        st.primary += 1;
        let ray = cam.ray(x, y).at_time(scene.sampling.shutter[0]);
        let (_, steps) = scene.intersect(&ray);
        st.bvh_steps += steps as u64;
        steps
    })?;
    let max = counts.iter().copied().max().unwrap_or(1).max(1) as f32;
    let ramp = [
        Vec3::ZERO,
        Vec3::new(0.1, 0.2, 0.9),
        Vec3::new(0.9, 0.1, 0.1),
        Vec3::new(1.0, 0.9, 0.1),
        Vec3::ONE,
    ];
    let pixels = counts
        .iter()
        .map(|&c| {
            let t = c as f32 / max * (ramp.len() - 1) as f32;
            let i = (t as usize).min(ramp.len() - 2);
            ramp[i].lerp(ramp[i + 1], t - i as f32)
        })
        .collect();
    Some((Image { width: r.width(), height: r.height(), pixels }, stats))
}

/// Times the primary rays alone (closest hit, no shading) and then, if
/// asked, one shadow ray per hit towards the first light (any hit).
/// Returns (primary seconds, shadow seconds, counts).
pub fn raybench(scene: &Scene, shadow: bool) -> (f64, f64, RayStats) {
    let cam = &scene.camera;
    let job = Job::default();
    // The buffers are made (and their pages touched) before the clock
    // starts, as scripts/embree_bench.c does: only tracing is timed.
    let mut hits = vec![Vec3::NAN; cam.width as usize * cam.height as usize];
    let mut blocked = vec![0u8; cam.width as usize * cam.height as usize];
    let start = std::time::Instant::now();
    let mut stats = per_pixel(cam.width, cam.height, &job, Out::Own(&mut hits), |x, y, st| {
        st.primary += 1;
        let ray = cam.ray(x, y).at_time(scene.sampling.shutter[0]);
        let (hit, steps) = scene.intersect(&ray);
        st.bvh_steps += steps as u64;
        hit.map(|h| ray.at(h.t)).unwrap_or(Vec3::NAN)
    })
    .unwrap_or_default();
    let primary_s = start.elapsed().as_secs_f64();
    let Some(light) = scene.lights.first().filter(|_| shadow) else {
        return (primary_s, 0.0, stats);
    };
    let start = std::time::Instant::now();
    let w = cam.width;
    let time = scene.sampling.shutter[0];
    // The forward shadow ray of the hit at `p`: from just off the surface
    // to just short of the light.
    let forward = |p: Vec3| {
        let (l, dist, _) = light.at(p);
        let eps = offset(p, Vec3::ZERO);
        let t_max = if dist.is_finite() { dist - 2.0 * eps } else { f32::INFINITY };
        (Ray::new(p + l * eps, l).at_time(time), t_max)
    };
    // A block's shadow rays together, as `render` casts them.
    let st2 = per_block(cam.width, cam.height, &job, Out::Own(&mut blocked), |px, st, values| {
        let mut rays = [Ray::new(Vec3::ZERO, Vec3::ZERO); PACKET];
        let (mut t_max, mut m) = ([0.0; PACKET], 0);
        for &(x, y) in px {
            let p = hits[(y * w + x) as usize];
            if !p.is_nan() {
                (rays[m], t_max[m]) = forward(p);
                m += 1;
            }
        }
        st.shadow += m as u64;
        let mut found = [Shadow::Unknown; PACKET];
        let last = &mut st.occluders[0];
        scene.bvh.shadow_packet(&rays[..m], &t_max[..m], last, |_| true, &mut found[..m]);
        let mut k = 0;
        for &(x, y) in px {
            let hit = !hits[(y * w + x) as usize].is_nan();
            values.push((hit && found[k] == Shadow::Blocked) as u8);
            k += hit as usize;
        }
    })
    .unwrap_or_default();
    stats.shadow = st2.shadow;
    (primary_s, start.elapsed().as_secs_f64(), stats)
}

/// Primary rays by brute force (every primitive tested per ray), over an
/// evenly spread subset of the pixels sized to about `budget` ray-primitive
/// tests: the baseline for `raybench -brute`. Returns (rays, seconds).
pub fn raybench_brute(scene: &Scene, budget: u64) -> (u64, f64) {
    use rayon::prelude::*;
    let cam = &scene.camera;
    let pixels = cam.width as u64 * cam.height as u64;
    let shapes = scene.bvh.shapes();
    let prims = shapes.len().max(1) as u64;
    let rays = (budget / prims).clamp(1, pixels);
    let stride = pixels / rays;
    let start = std::time::Instant::now();
    let hits: u64 = (0..rays)
        .into_par_iter()
        .map(|k| {
            let i = k * stride;
            let ray = cam.ray((i % cam.width as u64) as u32, (i / cam.width as u64) as u32);
            intersect_brute(&shapes, &ray, 0.0, f32::INFINITY).is_some() as u64
        })
        .sum();
    std::hint::black_box(hits);
    (rays, start.elapsed().as_secs_f64())
}

/// The colour seen along a camera ray, by the scene's integrator.
fn camera_ray(scene: &Scene, ray: &Ray, st: &mut RayStats) -> Vec3 {
    match scene.sampling.integrator {
        Integrator::Whitted => trace(scene, ray, 0, 1.0, Media::default(), st),
        Integrator::Path => super::path::radiance(scene, ray, st),
    }
}

/// The colour seen along `ray`, `depth` bounces deep, travelling in
/// `media`.
pub fn trace(
    scene: &Scene,
    ray: &Ray,
    depth: u32,
    weight: f32,
    media: Media,
    st: &mut RayStats,
) -> Vec3 {
    // A ray with a non-finite origin or direction (a degenerate surface,
    // an extreme index of refraction) sees nothing; so does one past the
    // pixel's budget.
    if !traceable(ray, st) {
        return Vec3::ZERO;
    }
    let (hit, steps) = scene.intersect(ray);
    seen(scene, ray, (hit, steps), depth, weight, media, st)
}

/// Whether `ray` is traced: a ray with a non-finite origin or direction (a
/// degenerate surface, an extreme index of refraction) sees nothing;
/// neither does one past the pixel's budget.
fn traceable(ray: &Ray, st: &RayStats) -> bool {
    sound(ray) && (st.limit == 0 || st.total() < st.limit)
}

/// Whether `ray` has a finite origin and a finite, non-zero direction (the
/// six coordinates tested without a branch each).
#[inline(always)]
fn sound(ray: &Ray) -> bool {
    finite(ray.origin) & finite(ray.dir) & (ray.dir != Vec3::ZERO)
}

/// `trace` of a camera ray whose closest hit (and steps) was found
/// already, in a packet. (Inlined into the loop over a packet's pixels:
/// a call per pixel cost a primary-only render 15 %.)
#[inline(always)]
fn trace_from(scene: &Scene, ray: &Ray, found: (Option<Hit>, u32), st: &mut RayStats) -> Vec3 {
    if !traceable(ray, st) {
        return Vec3::ZERO;
    }
    seen(scene, ray, found, 0, 1.0, Media::default(), st)
}

/// What `ray` sees, given its closest hit and the steps to it.
#[inline(always)]
fn seen(
    scene: &Scene,
    ray: &Ray,
    (hit, steps): (Option<Hit>, u32),
    depth: u32,
    weight: f32,
    media: Media,
    st: &mut RayStats,
) -> Vec3 {
    st.bvh_steps += steps as u64;
    // Lights with a size are seen where nothing nearer is.
    if !scene.emitters.is_empty() {
        let nearest = hit.as_ref().map_or(f32::INFINITY, |h| h.t);
        let seen = scene
            .emitters
            .iter()
            .filter_map(|l| l.hit(ray, nearest))
            .min_by(|a, b| a.0.total_cmp(&b.0));
        if let Some((_, radiance)) = seen {
            return radiance;
        }
    }
    match hit {
        Some(h) => shade(scene, ray, &h, depth, weight, media, st),
        None if scene.has_environment => scene.sky.radiance(ray.dir.normalize()),
        None => scene.background,
    }
}

/// The local geometry of a hit, every normal turned to the side the ray
/// came from.
pub(super) struct Surface {
    /// The geometric normal (unit).
    pub(super) ng: Vec3,
    /// The shading normal (unit): interpolated for smooth triangles.
    pub(super) ns: Vec3,
    /// Whether the ray arrives from the outside: the side the shading
    /// normals point to for smooth triangles, the counter-clockwise side
    /// for flat ones, the outside of a sphere.
    pub(super) front: bool,
    /// Where shadow rays start: the hit point, or for smooth triangles the
    /// point Hanika's method lifts it to.
    pub(super) shadow_from: Vec3,
}

/// The surface at `p` (reached along `d`), from where `locate` found it:
/// worked out in the primitive's own coordinates, then turned to the
/// world's (normals by the inverse transpose; the side a ray arrives from
/// is the same in both).
/// (Inlined, as `surface_local` is: returned through memory, the surface
/// was written in narrower pieces than it was read back in, a
/// store-forwarding stall per shading point.)
#[inline(always)]
pub(super) fn surface(scene: &Scene, at: &Located, p: Vec3, d: Vec3) -> Surface {
    let (p_l, d_l) = match at.to_local {
        None => (p, d),
        Some(m) => (m.transform_point3(p), m.transform_vector3(d)),
    };
    let local = surface_local(scene, at, p_l, d_l);
    let Some(m) = at.to_local else { return local };
    let turn = |n: Vec3| (m.matrix3.transpose() * glam::Vec3A::from(n)).normalize().into();
    let shadow_from =
        if local.shadow_from == p_l { p } else { m.inverse().transform_point3(local.shadow_from) };
    Surface { ng: turn(local.ng), ns: turn(local.ns), front: local.front, shadow_from }
}

#[inline(always)]
fn surface_local(scene: &Scene, at: &Located, p: Vec3, d: Vec3) -> Surface {
    let (ng_out, ns_out, vertex_normals) = match &at.local {
        Local::Sphere { center, .. } => {
            let n = (p - *center).normalize();
            (n, n, None)
        }
        Local::Solid { normal } => {
            let n = normal.try_normalize().unwrap_or(Vec3::Z);
            (n, n, None)
        }
        Local::Triangle(t) => {
            let ng = t.cross().normalize();
            if t.normals[0] == Triangle::FLAT {
                (ng, ng, None)
            } else {
                let n = t.normals.map(|i| scene.normals[i as usize]);
                // The vertex normals say which side is outside, whichever
                // way the triangle is wound.
                let ng = if ng.dot(n[0] + n[1] + n[2]) < 0.0 { -ng } else { ng };
                let [u, v] = at.uv;
                let ns = (n[0] * (1.0 - u - v) + n[1] * u + n[2] * v).try_normalize().unwrap_or(ng);
                (ng, ns, Some((t.p, n, [1.0 - u - v, u, v])))
            }
        }
    };
    let front = d.dot(ng_out) < 0.0;
    let side = if front { 1.0 } else { -1.0 };
    let shadow_from = match vertex_normals {
        Some((v, n, b)) => terminator(p, v, n.map(|n| n * side), b),
        None => p,
    };
    Surface { ng: ng_out * side, ns: ns_out * side, front, shadow_from }
}

/// Hanika's shadow-terminator fix: the barycentric mean of `p` lifted onto
/// each vertex's tangent plane (only where it lies below it), a point on
/// the smooth surface the normals describe rather than on the flat facet.
fn terminator(p: Vec3, v: [Vec3; 3], n: [Vec3; 3], b: [f32; 3]) -> Vec3 {
    let mut lifted = p;
    for k in 0..3 {
        let below = (p - v[k]).dot(n[k]).min(0.0);
        lifted -= b[k] * below * n[k];
    }
    lifted
}

fn shade(
    scene: &Scene,
    ray: &Ray,
    hit: &Hit,
    depth: u32,
    weight: f32,
    media: Media,
    st: &mut RayStats,
) -> Vec3 {
    // Lit by the ambient light alone, with nothing to reflect, refract,
    // texture or emit: the colour needs no geometry (a primary-only
    // render; the same value the full path below gives).
    if scene.lights.is_empty()
        && let Some(k) = scene.bvh.own_material(hit.prim)
        && let m = &scene.materials[k as usize]
        && m.is_flat()
    {
        return m.ka * scene.ambient * m.color;
    }
    lit(scene, ray, &Shading::new(scene, ray, hit), (depth, weight, media), &[], st)
}

/// The most lights whose shadow rays go in packets (the first of the
/// scene's).
const PACKET_LIGHTS: usize = 8;

/// Whether a block's camera rays are shaded with the shadow rays of their
/// hits in packets (`block_shadows`): when the tree is large enough for
/// packets to pay (`Bvh::packs_shadows`), the scene has a light at one
/// point (a light with a size casts several rays per point, each its own
/// way) and no light camera rays can see (`seen` looks for those before
/// shading). The picture is the same either way.
fn packet_shadows(scene: &Scene) -> bool {
    scene.bvh.packs_shadows()
        && scene.emitters.is_empty()
        && scene.lights.iter().take(PACKET_LIGHTS).any(packs)
}

/// Whether the shadow rays toward `light` go in packets: one ray per
/// point, unjittered.
fn packs(light: &crate::scene::Light) -> bool {
    light.samples() == 1 && !light.is_visible()
}

/// For each of `points` (a block's shading points, of camera rays `rays`)
/// and each of the first `PACKET_LIGHTS` lights, what the shadow ray `lit`
/// would cast toward it meets, learned with those of the other points in
/// one packet per light (`Bvh::shadow_packet`): the same answer as its
/// own walk. `Unknown` where `lit` casts none, and where a surface that
/// lets light through is met.
fn block_shadows(
    scene: &Scene,
    rays: &[Ray],
    points: &[Option<Shading>],
    st: &mut RayStats,
) -> [[Shadow; PACKET_LIGHTS]; PACKET] {
    let mut known = [[Shadow::Unknown; PACKET_LIGHTS]; PACKET];
    let opaque = |material: u32| scene.materials[material as usize].t <= 0.0;
    for (j, light) in scene.lights.iter().enumerate().take(PACKET_LIGHTS) {
        if !packs(light) {
            continue;
        }
        let mut shadows = [Ray::new(Vec3::ZERO, Vec3::ZERO); PACKET];
        let (mut t_max, mut which, mut m) = ([0.0; PACKET], [0u8; PACKET], 0);
        for (i, (s, r)) in points.iter().zip(rays).enumerate().take(PACKET) {
            let Some(s) = s else { continue };
            let Some(sr) = shadow_ray(light, s, r, 0, (0.5, 0.5)) else { continue };
            (shadows[m], t_max[m], which[m]) = (sr.ray, sr.t_max, i as u8);
            m += 1;
        }
        let mut found = [Shadow::Unknown; PACKET];
        let last = &mut st.occluders[j % OCCLUDERS];
        scene.bvh.shadow_packet(&shadows[..m], &t_max[..m], last, opaque, &mut found[..m]);
        for (&i, &f) in which[..m].iter().zip(&found) {
            known[i as usize][j] = f;
        }
    }
    known
}

/// The shadow ray `lit` casts from shading point `s` (hit by `ray`)
/// toward sample `k` of `light` (jittered by `jitter`), and what it
/// carries.
struct ShadowRay {
    /// The direction to the light from the hit point, the light arriving
    /// there, and its cosine to the shading normal.
    l: Vec3,
    li: Vec3,
    n_dot_l: f32,
    /// The ray, over `(0, t_max)`.
    ray: Ray,
    t_max: f32,
}

/// `lit`'s shadow ray toward sample `k` of `light`, if it casts one (a
/// light that gives nothing there, or is below the shading normal, needs
/// none). A light below the facet but above the smooth surface is left to
/// the shadow ray from the lifted point, not cut off here.
#[inline(always)]
fn shadow_ray(
    light: &crate::scene::Light,
    s: &Shading,
    ray: &Ray,
    k: u32,
    jitter: (f32, f32),
) -> Option<ShadowRay> {
    let (l, dist, li) = light.sample_at(s.p, k, jitter);
    let n_dot_l = s.look.normal.dot(l);
    if li == Vec3::ZERO || n_dot_l <= 0.0 {
        return None;
    }
    let (l_s, dist_s) = if s.lifted {
        let (l_s, dist_s, _) = light.sample_at(s.shadow_origin, k, jitter);
        (l_s, dist_s)
    } else {
        (l, dist)
    };
    // Stop short of the light by the same margin as the start.
    let t_max = if dist_s.is_finite() { dist_s * (1.0 - 2.0 * OFFSET) } else { f32::INFINITY };
    Some(ShadowRay { l, li, n_dot_l, ray: ray.spawn(s.shadow_origin, l_s), t_max })
}

/// What `shade` works out of a hit before its lights: the surface, how
/// it looks there, and where its shadow rays leave from.
struct Shading {
    material: u32,
    p: Vec3,
    /// The ray's direction (unit).
    d: Vec3,
    ng: Vec3,
    front: bool,
    eps: f32,
    look: Look,
    shadow_origin: Vec3,
    /// Whether shadow rays leave from a point lifted off the facet
    /// (`terminator`), not from the hit point.
    lifted: bool,
}

impl Shading {
    #[inline(always)]
    fn new(scene: &Scene, ray: &Ray, hit: &Hit) -> Shading {
        let at = scene.locate(ray, hit);
        let m = &scene.materials[at.material as usize];
        let p = ray.at(hit.t);
        let d = ray.dir.normalize();
        let Surface { ng, ns, front, shadow_from } = surface(scene, &at, p, d);
        let eps = offset(p, ray.origin);
        let look = Look::at(scene, m, &at, (p, ray.origin), ns, front);
        let lifted = shadow_from != p;
        let shadow_origin =
            if lifted { shadow_from + ng * offset(shadow_from, ray.origin) } else { p + ng * eps };
        Shading { material: at.material, p, d, ng, front, eps, look, shadow_origin, lifted }
    }
}

/// The colour of shading point `s` (hit by `ray`, `depth` bounces deep,
/// of weight `weight`, travelling in `media`): its lights, and what it
/// reflects and refracts. `known[i]`: what a shadow packet learned of the
/// shadow ray toward light `i` (`block_shadows`).
#[inline(always)]
fn lit(
    scene: &Scene,
    ray: &Ray,
    s: &Shading,
    (depth, weight, media): (u32, f32, Media),
    known: &[Shadow],
    st: &mut RayStats,
) -> Vec3 {
    let Shading { material, p, d, ng, front, eps, ref look, .. } = *s;
    let m = &scene.materials[material as usize];
    let above = p + ng * eps;
    let view = -d;
    let ns = look.normal;
    let colour = look.colour;

    let mut color = m.ka * scene.ambient * colour;
    if front {
        color += m.emission;
    }
    for (number, light) in scene.lights.iter().enumerate() {
        let samples = light.samples();
        // This shading point's stratified jitter for the lights with a size.
        let dim = st.next_dim();
        for k in 0..samples {
            let jitter = if samples > 1 || light.is_visible() {
                sample::jitter(st.key(), dim, k)
            } else {
                (0.5, 0.5)
            };
            let Some(ShadowRay { l, li, n_dot_l, ray: shadow, t_max }) =
                shadow_ray(light, s, ray, k, jitter)
            else {
                continue;
            };
            st.shadow += 1;
            let last = &mut st.occluders[number % OCCLUDERS];
            let through = match known.get(number) {
                Some(Shadow::Blocked) => Vec3::ZERO,
                Some(Shadow::Clear) => Vec3::ONE,
                _ => scene.transmittance_hinted(&shadow, t_max, last, |h| {
                    transmit(scene, &shadow, h, cone(scene, p, ray.origin))
                }),
            };
            if through == Vec3::ZERO {
                continue;
            }
            let mut c = m.kd * colour * li * n_dot_l;
            if m.ks > 0.0 {
                c += m.ks * li * highlight(m, look, l, view, n_dot_l);
            }
            color += through * c;
        }
    }

    if depth < scene.trace_depth {
        if m.ks > 0.0 && weight * m.ks >= MIN_WEIGHT {
            st.reflected += 1;
            let r = ray.spawn(above, reflect(d, ns));
            color += m.ks * trace(scene, &r, depth + 1, weight * m.ks, media, st);
        }
        if m.t > 0.0 {
            // The media on both sides of the surface.
            let (n_from, beyond) = if front {
                (media.ior(), media.enter(material, m.ior))
            } else {
                (m.ior, media.leave(material))
            };
            match refract(d, ns, n_from / beyond.ior()) {
                Some(dir) => {
                    let f = m.t * colour;
                    if weight * f.max_element() >= MIN_WEIGHT {
                        st.refracted += 1;
                        let r = ray.spawn(p - ng * eps, dir);
                        color +=
                            f * trace(scene, &r, depth + 1, weight * f.max_element(), beyond, st);
                    }
                }
                None => {
                    // Total internal reflection: what would have gone
                    // through stays on this side, all of it.
                    st.refracted += 1;
                    let r = ray.spawn(above, reflect(d, ns));
                    color += TIR * trace(scene, &r, depth + 1, weight * TIR, media, st);
                }
            }
        }
    }
    color
}

/// What the material looks like at a shading point: its colour (the
/// texture's, in the coordinates the object was written in), its shading
/// normal (bumped), and the tangent of anisotropic highlights.
pub(super) struct Look {
    pub(super) colour: Vec3,
    pub(super) normal: Vec3,
    /// The surface's u direction: the object's x axis, as written, laid
    /// onto the surface (its z axis where x is normal to it).
    pub(super) tangent: Vec3,
}

impl Look {
    /// (The plain material's look inlined, the rest out of line: a call
    /// returned the look through memory, written in narrower pieces than
    /// it was read back in, a store-forwarding stall per shading point.)
    #[inline(always)]
    pub(super) fn at(
        scene: &Scene,
        m: &Material,
        at: &Located,
        (p, origin): (Vec3, Vec3),
        ns: Vec3,
        front: bool,
    ) -> Look {
        let plain = m.texture.is_none()
            && m.bump.is_none()
            && !matches!(m.highlight, Highlight::Ward { .. });
        if plain {
            return Look { colour: m.color, normal: ns, tangent: Vec3::ZERO };
        }
        Look::textured(scene, m, at, (p, origin), ns, front)
    }

    /// `at` for a material with a texture, a bump or an anisotropic
    /// highlight.
    #[inline(never)]
    fn textured(
        scene: &Scene,
        m: &Material,
        at: &Located,
        (p, origin): (Vec3, Vec3),
        ns: Vec3,
        front: bool,
    ) -> Look {
        let to_tex = texture_frame(scene, m, at.level, at.moved);
        let q = to_tex.transform_point3(p);
        let cone = cone(scene, p, origin);
        // In texture units (their mean scale).
        let scale = to_tex.matrix3.determinant().abs().cbrt();
        let coords = surface_uv(scene, at);
        let tex = texture::TexPoint {
            p: q,
            uv: coords.map(|c| (c.uv, c.du.length().max(c.dv.length()) / scale)),
        };
        let colour =
            m.texture.and_then(|t| t.at(tex, &scene.images, cone * scale)).unwrap_or(m.color);
        let normal = match m.bump {
            None => ns,
            Some(b) => {
                // The height's gradient, in world coordinates.
                let g: Vec3 = match (b.image, coords) {
                    (None, _) => {
                        let g = texture::noise_gradient(q / b.size) * (b.amount / b.size);
                        (to_tex.matrix3.transpose() * glam::Vec3A::from(g)).into()
                    }
                    (Some((id, mapping)), coords) => {
                        // Central differences half a texel (of the unit
                        // square) wide: along u and v for the uv mapping,
                        // along the axes of texture space for the others.
                        let img = &scene.images[id as usize];
                        let (w, h) = img.size();
                        let e = 0.5 / w.max(h) as f32;
                        let height = |t: texture::TexPoint| {
                            let (u, v, _) = mapping.uv(t);
                            let c = img.sample(u - u.floor(), v - v.floor(), 1.0);
                            b.amount * crate::scene::luminance(c)
                        };
                        match coords {
                            Some(c) if mapping == texture::Mapping::Uv => {
                                let at = |du: f32, dv: f32| {
                                    let uv = [c.uv[0] + du, c.uv[1] + dv];
                                    height(texture::TexPoint { p: q, uv: Some((uv, 1.0)) })
                                };
                                let (gu, gv) = (
                                    (at(e, 0.0) - at(-e, 0.0)) / (2.0 * e),
                                    (at(0.0, e) - at(0.0, -e)) / (2.0 * e),
                                );
                                c.du * gu + c.dv * gv
                            }
                            _ => {
                                let d = |a: Vec3| {
                                    (height((q + a * e).into()) - height((q - a * e).into()))
                                        / (2.0 * e)
                                };
                                let g = Vec3::new(d(Vec3::X), d(Vec3::Y), d(Vec3::Z));
                                (to_tex.matrix3.transpose() * glam::Vec3A::from(g)).into()
                            }
                        }
                    }
                };
                let along: Vec3 = g - ns * ns.dot(g);
                let side = if front { 1.0 } else { -1.0 };
                (ns - side * along).try_normalize().unwrap_or(ns)
            }
        };
        let onto = |w: Vec3| (w - normal * normal.dot(w)).try_normalize();
        let axis = |a: Vec3| onto((to_tex.matrix3.inverse() * glam::Vec3A::from(a)).into());
        // Along u: the texture coordinates' where there are any.
        let tangent = coords
            .and_then(|c| onto(c.du))
            .or_else(|| axis(Vec3::X))
            .or_else(|| axis(Vec3::Z))
            .unwrap_or(Vec3::ZERO);
        Look { colour, normal, tangent }
    }
}

/// World to texture coordinates for material `m` of a surface in the
/// level `level` (`None`: the scene's, `moved` by its motion): through the
/// group the object was written in (or back from the eye), then the
/// object's own inverse transform.
fn texture_frame(
    scene: &Scene,
    m: &Material,
    level: Option<glam::Affine3A>,
    moved: Vec3,
) -> glam::Affine3A {
    let level = level.unwrap_or(glam::Affine3A::from_translation(scene.origin - moved));
    m.to_texture.map_or(level, |t| t * level)
}

/// The width of the ray cone at `p` of a camera ray from `origin`, in
/// world units; a pixel's n samples each cover 1/n of it.
fn cone(scene: &Scene, p: Vec3, origin: Vec3) -> f32 {
    (p - origin).length() * scene.camera.pixel_spread() / (scene.sampling.samples as f32).sqrt()
}

/// The texture coordinates of a triangle's corners (as `corners`, its
/// normals' indices, find them), if it has them.
fn corner_uvs(scene: &Scene, corners: [u32; 3]) -> Option<[[f32; 2]; 3]> {
    let corner = |i: u32| scene.uvs.get(i as usize).copied().filter(|c| !c[0].is_nan());
    let [Some(a), Some(b), Some(c)] = corners.map(corner) else { return None };
    Some([a, b, c])
}

/// The texture coordinates at barycentric point (u, v) of corners `c`.
fn blend(c: [[f32; 2]; 3], [u, v]: [f32; 2]) -> [f32; 2] {
    let w = [1.0 - u - v, u, v];
    [0, 1].map(|k| c[0][k] * w[0] + c[1][k] * w[1] + c[2][k] * w[2])
}

/// A surface's texture coordinates at a hit, and how they change along it.
#[derive(Clone, Copy, Debug)]
struct SurfaceUv {
    uv: [f32; 2],
    /// The gradients of u and of v along the surface, in world units.
    du: Vec3,
    dv: Vec3,
}

/// The texture coordinates of a hit on a triangle whose corners have them.
fn surface_uv(scene: &Scene, at: &Located) -> Option<SurfaceUv> {
    let Local::Triangle(t) = &at.local else { return None };
    let [a, b, c] = corner_uvs(scene, t.normals)?;
    let uv = blend([a, b, c], at.uv);
    // The gradient g in the triangle's plane with g·e1 = d1 and g·e2 = d2.
    let (e1, e2) = (t.p[1] - t.p[0], t.p[2] - t.p[0]);
    let n = e1.cross(e2);
    let grad = |d1: f32, d2: f32| (e2.cross(n) * d1 + n.cross(e1) * d2) / n.length_squared();
    let (du, dv) = (grad(b[0] - a[0], c[0] - a[0]), grad(b[1] - a[1], c[1] - a[1]));
    // Gradients leave the triangle's coordinates by the transpose.
    let out = |g: Vec3| match at.to_local {
        None => g,
        Some(m) => (m.matrix3.transpose() * glam::Vec3A::from(g)).into(),
    };
    Some(SurfaceUv { uv, du: out(du), dv: out(dv) })
}

/// The specular term per unit of light and of Ks, for light from `l` seen
/// along `view` (unit vectors; `n_dot_l` > 0): Phong's (R·V)^n, Blinn's
/// (N·H)^n, or Ward's anisotropic lobe π·f·cosθi with
/// f = 1/(4π·ax·ay·√(cosθi·cosθo))·exp(−((H·u/ax)² + (H·v/ay)²)/(H·N)²).
pub(super) fn highlight(m: &Material, look: &Look, l: Vec3, view: Vec3, n_dot_l: f32) -> f32 {
    let n = look.normal;
    match m.highlight {
        Highlight::Phong => {
            let r_dot_v = reflect(-l, n).dot(view);
            if r_dot_v > 0.0 { r_dot_v.powf(m.ns) } else { 0.0 }
        }
        Highlight::Blinn => {
            let n_dot_h = n.dot((l + view).normalize());
            if n_dot_h > 0.0 { n_dot_h.powf(m.ns) } else { 0.0 }
        }
        Highlight::Ward { ax, ay } => {
            let n_dot_v = n.dot(view);
            if n_dot_v <= 0.0 {
                return 0.0;
            }
            let h = (l + view).normalize();
            let (u, v) = (look.tangent, n.cross(look.tangent));
            let (hu, hv, hn) = (h.dot(u) / ax, h.dot(v) / ay, h.dot(n));
            let e = (-(hu * hu + hv * hv) / (hn * hn)).exp();
            n_dot_l * e / (4.0 * ax * ay * (n_dot_l * n_dot_v).sqrt())
        }
    }
}

/// How much of the light a transmitting surface lets through at each
/// crossing (T·colour); opaque surfaces, none.
/// What a shadow ray keeps of the light crossing surface `h`: T times the
/// colour there (the texture's, where the material has one, sampled for a
/// ray cone `cone` wide), nothing through an opaque surface.
fn transmit(scene: &Scene, ray: &Ray, h: ShadowHit, cone: f32) -> Vec3 {
    let m = &scene.materials[h.material as usize];
    if m.t <= 0.0 {
        return Vec3::ZERO;
    }
    let Some(texture) = m.texture else { return m.t * m.color };
    let to_tex = texture_frame(scene, m, h.level, h.moved);
    let scale = to_tex.matrix3.determinant().abs().cbrt();
    // Texture coordinates change at an unknown rate here: taken as one
    // unit per unit of distance.
    let tex = texture::TexPoint {
        p: to_tex.transform_point3(ray.at(h.t)),
        uv: corner_uvs(scene, h.corners).map(|c| (blend(c, h.uv), 1.0 / scale)),
    };
    m.t * texture.at(tex, &scene.images, cone * scale).unwrap_or(m.color)
}

/// The weight of a totally internally reflected ray.
const TIR: f32 = 1.0;

#[cfg(test)]
mod tests {
    use super::*;

    /// A picture finished band by band as it is traced (`render_finished`)
    /// is the picture `render_into` makes with the look applied after,
    /// and its bytes are `to_rgb8`'s, to the bit: plain, in passes, with
    /// samples (in passes or not), cropped, tone-mapped, in either
    /// encoding, on a picture short enough for bands of one row.
    #[test]
    fn finished_bands_are_the_picture_and_its_bytes() {
        use crate::scene::{Builder, Falloff, Light, Tonemap};
        use glam::DVec3;
        for (progressive, samples, crop, tonemap, height) in [
            (false, 1, false, Tonemap::Clamp, 29),
            (true, 1, false, Tonemap::Aces, 29),
            (false, 4, true, Tonemap::Reinhard, 29),
            (true, 4, false, Tonemap::Clamp, 29),
            (false, 1, true, Tonemap::Clamp, 3u32),
        ] {
            let mut b = Builder::new();
            b.camera_from(DVec3::new(0.0, 1.0, 6.0)).unwrap();
            b.camera_resolution(37, height as i64).unwrap();
            b.set_ambient(Vec3::splat(0.2)).unwrap();
            let light =
                Light::point(Vec3::splat(40.0), DVec3::new(2.0, 4.0, 3.0), Falloff::INVERSE_SQUARE);
            b.add_light(light.unwrap()).unwrap();
            for k in 0..5 {
                b.sphere(DVec3::new(k as f64 - 2.0, 0.0, -(k as f64)), 0.7).unwrap();
            }
            b.sampling.samples = samples;
            b.sampling.tonemap = tonemap;
            b.sampling.exposure = 0.5;
            let scene = Scene::freeze(&b).unwrap();
            let crop = crop.then_some(super::super::Rect { x0: 3, y0: 1, x1: 30, y1: height - 1 });
            let job = || Job { progressive, crop, ..Job::default() };
            let (mut want, _) = render_into(&scene, &job(), Vec::new()).unwrap();
            apply_look(&scene.sampling, &mut want);
            for enc in [Encoding::Linear, Encoding::Srgb] {
                let mut bytes = vec![7u8; 5];
                let (img, _, finished) =
                    render_finished(&scene, &job(), Vec::new(), &mut bytes, enc).unwrap();
                assert!(finished);
                let bits = |i: &Image| {
                    i.pixels.iter().map(|p| p.to_array().map(f32::to_bits)).collect::<Vec<_>>()
                };
                assert_eq!(bits(&img), bits(&want), "{progressive} {samples} {crop:?}");
                assert_eq!(bytes, want.to_rgb8(enc), "{progressive} {samples} {crop:?} {enc:?}");
            }
        }
    }

    /// A scene big enough for shadow packets (`Bvh::packs_shadows`): a
    /// wavy ground of 33,800 triangles, half smooth (so shadow rays leave
    /// from lifted points) and half flat, under an opaque ball and a glass
    /// one, lit by two point lights, a spot light and a parallel light.
    fn packed() -> Scene {
        use crate::scene::{Builder, Falloff, Light};
        use glam::DVec3;
        let mut b = Builder::new();
        b.camera_from(DVec3::new(0.0, 7.0, 11.0)).unwrap();
        b.camera_target(DVec3::new(0.0, 0.5, 0.0)).unwrap();
        b.camera_angle(40.0).unwrap();
        b.camera_resolution(48, 40).unwrap();
        b.set_ambient(Vec3::splat(0.1)).unwrap();
        let sq = Falloff::INVERSE_SQUARE;
        let lights = [
            Light::point(Vec3::splat(30.0), DVec3::new(3.0, 8.0, 4.0), sq),
            Light::point(Vec3::new(10.0, 8.0, 6.0), DVec3::new(-5.0, 3.0, -2.0), sq),
            Light::spot(Vec3::splat(40.0), DVec3::new(0.0, 9.0, 0.0), -Vec3::Y, 20.0, 30.0, sq),
            Light::parallel(Vec3::splat(0.3), Vec3::new(-1.0, -1.0, -0.5)),
        ];
        for l in lights {
            b.add_light(l.unwrap()).unwrap();
        }
        let m = |color, ks, t, ior| Material { color, ks, ns: 20.0, t, ior, ..Material::default() };
        b.set_material(m(Vec3::new(0.8, 0.7, 0.6), 0.3, 0.0, 1.0)).unwrap();
        let n = 130i64;
        for i in 0..=n {
            for j in 0..=n {
                let (x, z) = (i as f64 * 16.0 / n as f64 - 8.0, j as f64 * 16.0 / n as f64 - 8.0);
                b.vertex(DVec3::new(x, 0.3 * x.sin() * z.cos(), z)).unwrap();
                let (nx, nz) = (-0.3 * x.cos() * z.cos(), 0.3 * x.sin() * z.sin());
                b.normal(Vec3::new(nx as f32, 1.0, nz as f32)).unwrap();
            }
        }
        for i in 0..n {
            for j in 0..n {
                let a = i * (n + 1) + j;
                let (b1, c, d) = (a + 1, a + n + 1, a + n + 2);
                if i < n / 2 {
                    b.ntri([(a, a), (b1, b1), (d, d)]).unwrap();
                    b.ntri([(a, a), (d, d), (c, c)]).unwrap();
                } else {
                    b.tri([a, b1, d]).unwrap();
                    b.tri([a, d, c]).unwrap();
                }
            }
        }
        b.sphere(DVec3::new(1.5, 1.2, 1.0), 0.8).unwrap();
        b.set_material(m(Vec3::new(0.5, 0.6, 0.9), 0.2, 0.6, 1.3)).unwrap();
        b.sphere(DVec3::new(-1.5, 1.4, 0.0), 1.0).unwrap();
        Scene::freeze(&b).unwrap()
    }

    /// A block's camera rays shaded with their shadow rays in packets get
    /// the colours each gets shaded alone, to the bit; and the packets do
    /// settle shadow rays, blocked and clear.
    #[test]
    fn shadow_packets_shade_as_single_rays() {
        let scene = packed();
        assert!(scene.bvh.packs_shadows() && packet_shadows(&scene));
        let cam = &scene.camera;
        let (mut settled, mut blocked) = (0, 0);
        for (bx, by) in
            (0..cam.height).step_by(8).flat_map(|y| (0..cam.width).step_by(8).map(move |x| (x, y)))
        {
            let rays: Vec<Ray> = (0..64).map(|k| cam.ray(bx + k % 8, by + k / 8)).collect();
            let mut hits = vec![(None, 0); 64];
            scene.intersect_packet(&rays, &mut hits);
            let (mut st, mut together) = (RayStats::default(), Vec::new());
            let begin = |i: usize, st: &mut RayStats| st.start(i as u64);
            shade_packet(&scene, (&rays, &hits), &mut st, begin, |_, c| together.push(c));
            let mut st = RayStats::default();
            for (i, (r, &found)) in rays.iter().zip(&hits).enumerate() {
                st.start(i as u64);
                let alone = trace_from(&scene, r, found, &mut st);
                let bits = |v: Vec3| v.to_array().map(f32::to_bits);
                assert_eq!(bits(together[i]), bits(alone), "block ({bx}, {by}), ray {i}");
            }
            let points: Vec<Option<Shading>> = rays
                .iter()
                .zip(&hits)
                .map(|(r, (h, _))| h.as_ref().map(|h| Shading::new(&scene, r, h)))
                .collect();
            for k in block_shadows(&scene, &rays, &points, &mut st).iter().flatten() {
                settled += (*k != Shadow::Unknown) as u32;
                blocked += (*k == Shadow::Blocked) as u32;
            }
        }
        assert!(blocked > 100 && settled - blocked > 1000, "{blocked} blocked of {settled}");
    }

    #[test]
    fn mirror_and_snell() {
        let d = Vec3::new(1.0, -1.0, 0.0).normalize();
        assert!((reflect(d, Vec3::Y) - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-6);
        // 45 degrees into glass (1.5): sin(t) = sin(45)/1.5.
        let t = refract(d, Vec3::Y, 1.0 / 1.5).unwrap();
        let sin_t = t.x / t.length();
        assert!((sin_t - (45f32.to_radians().sin() / 1.5)).abs() < 1e-6, "{sin_t}");
        assert!((t.length() - 1.0).abs() < 1e-6);
        // Leaving glass at 60 degrees: total internal reflection.
        let d = Vec3::new(60f32.to_radians().sin(), -60f32.to_radians().cos(), 0.0);
        assert!(refract(d, Vec3::Y, 1.5).is_none());
        // Head-on passes straight through.
        assert!((refract(Vec3::NEG_Y, Vec3::Y, 0.7).unwrap() - Vec3::NEG_Y).length() < 1e-6);
    }

    /// The sine of the angle between unit `d` and the normal line `n`.
    fn sin_to(d: Vec3, n: Vec3) -> f32 {
        d.cross(n).length()
    }

    #[test]
    fn nested_media_bend_by_the_indices_on_both_sides() {
        // A ray through a water core (material 2, ior 1.33) inside a glass
        // ball (material 1, ior 1.5), crossing four interfaces whose normals
        // all point along +y, at 30 degrees: at each, n1 sin(t1) = n2 sin(t2)
        // with the indices of the media on both sides.
        let (glass, water) = ((1, 1.5f32), (2, 1.33f32));
        let mut media = Media::default();
        let mut d = Vec3::new(30f32.to_radians().sin(), -30f32.to_radians().cos(), 0.0);
        let steps: [(bool, (u32, f32), f32, f32); 4] = [
            (true, glass, 1.0, 1.5),
            (true, water, 1.5, 1.33),
            (false, water, 1.33, 1.5),
            (false, glass, 1.5, 1.0),
        ];
        for (i, (entering, (material, ior), n1, n2)) in steps.into_iter().enumerate() {
            let (from, beyond) = if entering {
                (media.ior(), media.enter(material, ior))
            } else {
                (ior, media.leave(material))
            };
            assert_eq!((from, beyond.ior()), (n1, n2), "interface {i}");
            let t = refract(d, Vec3::Y, from / beyond.ior()).expect("no total reflection here");
            let (s1, s2) = (sin_to(d, Vec3::Y), sin_to(t, Vec3::Y));
            assert!((n1 * s1 - n2 * s2).abs() < 1e-5, "interface {i}: {n1}*{s1} != {n2}*{s2}");
            media = beyond;
            d = t;
        }
        // Back in air, travelling as it came in.
        assert_eq!(media.ior(), 1.0);
        assert!((d - Vec3::new(0.5, -(0.75f32.sqrt()), 0.0)).length() < 1e-5);
        // An air bubble in glass: leaving glass into the bubble goes 1.5 -> 1,
        // past the critical angle (41.8 degrees) totally reflected.
        let inside = Media::default().enter(1, 1.5);
        let bubble = inside.enter(3, 1.0);
        assert_eq!(inside.ior() / bubble.ior(), 1.5);
        let steep = Vec3::new(50f32.to_radians().sin(), -50f32.to_radians().cos(), 0.0);
        assert!(refract(steep, Vec3::Y, inside.ior() / bubble.ior()).is_none());
        // Leaving what the ray was never known to be in changes nothing.
        assert_eq!(inside.leave(7).ior(), 1.5);
    }

    #[test]
    fn media_forget_the_outermost_when_full() {
        let mut m = Media::default();
        for k in 0..(MAX_MEDIA as u32 + 3) {
            m = m.enter(k, 1.0 + k as f32);
        }
        assert_eq!(m.ior(), 1.0 + (MAX_MEDIA as f32 + 2.0));
        let top = MAX_MEDIA as u32 + 2;
        assert_eq!(m.leave(top).ior(), 1.0 + (top - 1) as f32);
    }
}
