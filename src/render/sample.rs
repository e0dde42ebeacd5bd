//! Sampling: random numbers that are a hash of (seed, frame, pixel, sample,
//! dimension), so a pixel's value never depends on the thread, tile, crop,
//! shard or pass that traces it; stratified points in the pixel square
//! (Kensler's correlated multi-jittered sampling, "Correlated Multi-Jittered
//! Sampling", Pixar 2013); and reconstruction filters sampled by importance
//! (pbrt-v4's `FilterSampler`): each sample lands where its pixel's filter
//! reaches, into neighbouring pixels too, with weight f/pdf, and a pixel is
//! the weighted mean of its own samples.

use crate::scene::{Filter, FilterKind, Sampling};

/// SplitMix64's finalizer: a good 64-bit mix.
#[inline]
pub fn mix(mut z: u64) -> u64 {
    z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
    z ^ (z >> 31)
}

/// The key of one pixel's random numbers in one frame.
#[inline]
pub fn pixel_key(s: &Sampling, pixel: u64) -> u64 {
    key_of_pixel(frame_key(s), pixel)
}

/// The part of `pixel_key` shared by every pixel of a frame (worked out
/// once per render).
#[inline]
pub fn frame_key(s: &Sampling) -> u64 {
    let seeds = mix(s.seed ^ 0x9e37_79b9_7f4a_7c15) ^ mix(s.base_seed ^ 0x2545_f491_4f6c_dd1d);
    mix(seeds ^ s.frame as u64)
}

/// `pixel_key` from the frame's `frame_key`.
#[inline]
pub fn key_of_pixel(frame: u64, pixel: u64) -> u64 {
    mix(seed_of_pixel(frame, pixel))
}

/// What `key_of_pixel` mixes (a `RayStats` mixes it when it is used).
#[inline]
pub fn seed_of_pixel(frame: u64, pixel: u64) -> u64 {
    frame ^ pixel
}

/// Two numbers in [0, 1) for stratum `k` of shading dimension `dim` of a
/// camera ray with key `key`.
#[inline]
pub fn jitter(key: u64, dim: u32, k: u32) -> (f32, f32) {
    let h = mix(key ^ mix(((dim as u64) << 32) | k as u64));
    let unit = |bits: u64| (bits & 0xff_ffff) as f32 * (1.0 / (1u32 << 24) as f32);
    (unit(h), unit(h >> 32))
}

/// Kensler's permutation of 0..l by the pattern `p` (cycle walking).
fn permute(mut i: u32, l: u32, p: u32) -> u32 {
    let mut w = l - 1;
    w |= w >> 1;
    w |= w >> 2;
    w |= w >> 4;
    w |= w >> 8;
    w |= w >> 16;
    loop {
        i ^= p;
        i = i.wrapping_mul(0xe170_893d);
        i ^= p >> 16;
        i ^= (i & w) >> 4;
        i ^= p >> 8;
        i = i.wrapping_mul(0x0929_eb3f);
        i ^= p >> 23;
        i ^= (i & w) >> 1;
        i = i.wrapping_mul(1 | p >> 27);
        i = i.wrapping_mul(0x6935_fa69);
        i ^= (i & w) >> 11;
        i = i.wrapping_mul(0x74dc_b303);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0x9e50_1cc3);
        i ^= (i & w) >> 2;
        i = i.wrapping_mul(0xc860_a3df);
        i &= w;
        i ^= i >> 5;
        if i < l {
            break;
        }
    }
    (i.wrapping_add(p)) % l
}

/// A number in [0, 1) from `i` and the pattern `p`.
fn randfloat(mut i: u32, p: u32) -> f32 {
    i ^= p;
    i ^= i >> 17;
    i ^= i >> 10;
    i = i.wrapping_mul(0xb365_34e5);
    i ^= i >> 12;
    i ^= i >> 21;
    i = i.wrapping_mul(0x93fc_4795);
    i ^= 0xdf6e_307f;
    i ^= i >> 17;
    i = i.wrapping_mul(1 | p >> 18);
    // The top 24 bits: exactly representable, below 1.
    (i >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
}

/// Sample `s` of `n` of a correlated multi-jittered pattern `p`: a point in
/// the unit square, stratified in x and y at once.
pub fn cmj(s: u32, n: u32, p: u32) -> (f32, f32) {
    let m = ((n as f32).sqrt() as u32).max(1);
    let rows = n.div_ceil(m);
    let s = permute(s, n, p.wrapping_mul(0x5163_3e2d));
    let sx = permute(s % m, m, p.wrapping_mul(0x68bc_21eb));
    let sy = permute(s / m, rows, p.wrapping_mul(0x02e5_be93));
    let jx = randfloat(s, p.wrapping_mul(0x967a_889b));
    let jy = randfloat(s, p.wrapping_mul(0x368c_c8b7));
    let x = (sx as f32 + (sy as f32 + jx) / rows as f32) / m as f32;
    let y = (s as f32 + jy) / n as f32;
    (x.min(ONE_BELOW), y.min(ONE_BELOW))
}

const ONE_BELOW: f32 = 1.0 - f32::EPSILON / 2.0;

/// A filter's 1D profile tabulated for sampling by importance: offsets
/// are drawn with density proportional to |f| (piecewise constant over
/// `BINS` bins), and carry the weight f/pdf.
pub struct FilterTable {
    filter: Filter,
    /// Cumulative |f| at the bins' edges, 0 to 1.
    cdf: Vec<f32>,
    /// ∫|f| over the radius.
    integral: f32,
}

const BINS: usize = 256;

impl FilterTable {
    pub fn new(filter: Filter) -> FilterTable {
        let r = filter.radius;
        let dx = 2.0 * r / BINS as f32;
        let mut cdf = Vec::with_capacity(BINS + 1);
        cdf.push(0.0);
        let mut acc = 0.0f64;
        for i in 0..BINS {
            acc += filter.eval(-r + (i as f32 + 0.5) * dx).abs() as f64 * dx as f64;
            cdf.push(acc as f32);
        }
        let integral = acc as f32;
        for c in &mut cdf {
            *c /= integral;
        }
        FilterTable { filter, cdf, integral }
    }

    /// An offset from the pixel centre (in pixels) and its weight, from a
    /// number in [0, 1).
    pub fn sample(&self, u: f32) -> (f32, f32) {
        if self.filter.kind == FilterKind::Box {
            // Uniform: exactly (2u - 1)·r, weight 1.
            return ((2.0 * u - 1.0) * self.filter.radius, 1.0);
        }
        let i = self.cdf.partition_point(|&c| c <= u).clamp(1, BINS) - 1;
        let (c0, c1) = (self.cdf[i], self.cdf[i + 1]);
        let t = if c1 > c0 { (u - c0) / (c1 - c0) } else { 0.5 };
        let dx = 2.0 * self.filter.radius / BINS as f32;
        let x = -self.filter.radius + (i as f32 + t) * dx;
        let pdf = (c1 - c0) / dx;
        let f = self.filter.eval(x);
        // f/pdf, relative to the integral, so positive weights are near 1.
        let w = if pdf > 0.0 { f / (pdf * self.integral) } else { 0.0 };
        (x, w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cmj_is_stratified_in_both_axes() {
        for n in [1u32, 2, 7, 16, 33, 100] {
            let mut xs = vec![false; n as usize];
            let mut ys = vec![false; n as usize];
            for s in 0..n {
                let (x, y) = cmj(s, n, 12345);
                assert!((0.0..1.0).contains(&x) && (0.0..1.0).contains(&y));
                xs[(x * n as f32) as usize] = true;
                ys[(y * n as f32) as usize] = true;
            }
            // Every one of the n rows holds a sample; columns too when n
            // is a square (m·m strata of 1/n each).
            assert!(ys.iter().all(|&b| b), "n = {n}");
            let m = (n as f32).sqrt() as u32;
            if m * m == n {
                assert!(xs.iter().all(|&b| b), "n = {n}");
            }
        }
    }

    #[test]
    fn filter_samples_follow_the_filter() {
        for kind in [FilterKind::Tent, FilterKind::Gaussian, FilterKind::Mitchell] {
            let f = Filter::new(kind, None).unwrap();
            let t = FilterTable::new(f);
            // The weighted mean of x² over a fine stratification is the
            // filter's second moment.
            let n = 100_000;
            let (mut wsum, mut m2) = (0.0f64, 0.0f64);
            for i in 0..n {
                let (x, w) = t.sample((i as f32 + 0.5) / n as f32);
                assert!(x.abs() <= f.radius);
                wsum += w as f64;
                m2 += (w * x * x) as f64;
            }
            let (mut num, mut den) = (0.0f64, 0.0f64);
            for i in 0..n {
                let x = -f.radius + (i as f32 + 0.5) * 2.0 * f.radius / n as f32;
                num += (f.eval(x) * x * x) as f64;
                den += f.eval(x) as f64;
            }
            let (got, want) = (m2 / wsum, num / den);
            assert!((got - want).abs() < 1e-3 * want.max(0.1), "{kind:?}: {got} vs {want}");
        }
    }

    #[test]
    fn keys_differ_by_pixel_seed_and_frame() {
        let s = Sampling::default();
        let a = pixel_key(&s, 7);
        assert_ne!(a, pixel_key(&s, 8));
        assert_ne!(a, pixel_key(&Sampling { seed: 1, ..s }, 7));
        assert_ne!(a, pixel_key(&Sampling { frame: 1, ..s }, 7));
        assert_ne!(a, pixel_key(&Sampling { base_seed: 1, ..s }, 7));
        assert_ne!(
            pixel_key(&Sampling { seed: 1, ..s }, 7),
            pixel_key(&Sampling { base_seed: 1, ..s }, 7)
        );
    }
}
