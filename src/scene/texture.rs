//! Procedural textures: POV-Ray's `checker`, and patterns from a gradient
//! noise of our own (Perlin's improved noise, 2002: a fixed permutation,
//! quintic fade, twelve gradient directions) and its turbulence: `noise`,
//! `marble`, `wood` and `granite`. Evaluated in the coordinates the object
//! was written in, so a texture moves with its object's transform.

use glam::Vec3;

use super::builder::{SceneError, check_color};

/// A texture: what colour a surface has at a point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Texture {
    /// Colour `a` where ⌊x/size⌋ + ⌊y/size⌋ + ⌊z/size⌋ is even, `b` where odd.
    Checker { a: Vec3, b: Vec3, size: f32 },
    /// A blend from `a` to `b` by a pattern of points scaled by 1/`scale`.
    Pattern { kind: Pattern, a: Vec3, b: Vec3, scale: f32 },
}

/// The noise patterns.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Pattern {
    /// The noise itself, mapped to [0, 1].
    Noise,
    /// Veins: sin(x + 4·turbulence).
    Marble,
    /// Rings around the y axis, wobbled by noise.
    Wood,
    /// Eight octaves of |noise|, a grainy stone.
    Granite,
}

impl Pattern {
    pub const NAMES: &'static str = "checker, noise, marble, wood, granite or none";

    pub fn parse(s: &str) -> Option<Pattern> {
        Some(match s {
            "noise" => Pattern::Noise,
            "marble" => Pattern::Marble,
            "wood" => Pattern::Wood,
            "granite" => Pattern::Granite,
            _ => return None,
        })
    }

    /// The default colours (from, to).
    pub fn colours(self) -> (Vec3, Vec3) {
        match self {
            Pattern::Noise => (Vec3::ZERO, Vec3::ONE),
            Pattern::Marble => (Vec3::new(0.95, 0.93, 0.88), Vec3::new(0.25, 0.22, 0.3)),
            Pattern::Wood => (Vec3::new(0.78, 0.55, 0.3), Vec3::new(0.45, 0.25, 0.1)),
            Pattern::Granite => (Vec3::new(0.75, 0.72, 0.7), Vec3::new(0.2, 0.18, 0.18)),
        }
    }
}

impl Texture {
    pub fn check(&self) -> Result<(), SceneError> {
        let (a, b, size) = match *self {
            Texture::Checker { a, b, size } => (a, b, size),
            Texture::Pattern { a, b, scale, .. } => (a, b, scale),
        };
        check_color(a)?;
        check_color(b)?;
        if !(size > 0.0 && size.is_finite()) {
            return Err(SceneError::Invalid(format!("texture size must be above 0, got {size}")));
        }
        Ok(())
    }

    /// The colour at `p`.
    pub fn at(&self, p: Vec3) -> Vec3 {
        match *self {
            Texture::Checker { a, b, size } => {
                let c = (p / size).floor();
                let s = c.x as i64 + c.y as i64 + c.z as i64;
                if s.rem_euclid(2) == 0 { a } else { b }
            }
            Texture::Pattern { kind, a, b, scale } => a.lerp(b, pattern(kind, p / scale)),
        }
    }
}

/// The pattern's value in [0, 1] at `p`.
pub fn pattern(kind: Pattern, p: Vec3) -> f32 {
    let v = match kind {
        Pattern::Noise => 0.5 + 0.5 * noise(p),
        Pattern::Marble => 0.5 + 0.5 * (p.x * 3.0 + 4.0 * turbulence(p, 6)).sin(),
        Pattern::Wood => {
            let r = (p.x * p.x + p.z * p.z).sqrt() * 6.0 + 2.0 * noise(p * 0.8);
            let ring = r - r.floor();
            ring * ring
        }
        Pattern::Granite => (2.5 * turbulence(p * 4.0, 8)).min(1.0),
    };
    v.clamp(0.0, 1.0)
}

/// A fixed permutation of 0..256 (SplitMix64-shuffled, seed 426).
fn perm() -> &'static [u8; 512] {
    static P: std::sync::OnceLock<[u8; 512]> = std::sync::OnceLock::new();
    P.get_or_init(|| {
        let mut p: [u8; 256] = std::array::from_fn(|i| i as u8);
        let mut s: u64 = 426;
        for i in (1..256).rev() {
            s = s.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = s;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            let j = ((z ^ (z >> 31)) % (i as u64 + 1)) as usize;
            p.swap(i, j);
        }
        std::array::from_fn(|i| p[i % 256])
    })
}

fn fade(t: f32) -> f32 {
    t * t * t * (t * (t * 6.0 - 15.0) + 10.0)
}

/// The dot product of one of twelve gradients (chosen by `h`) with (x, y, z).
fn grad(h: u8, x: f32, y: f32, z: f32) -> f32 {
    let h = h & 15;
    let u = if h < 8 { x } else { y };
    let v = if h < 4 {
        y
    } else if h == 12 || h == 14 {
        x
    } else {
        z
    };
    (if h & 1 == 0 { u } else { -u }) + (if h & 2 == 0 { v } else { -v })
}

/// Gradient noise in [−1, 1], continuous with continuous derivatives, 0 at
/// integer points, periodic with period 256 on each axis.
pub fn noise(p: Vec3) -> f32 {
    let pm = perm();
    let f = p.floor();
    let (xi, yi, zi) = (
        (f.x as i64).rem_euclid(256) as usize,
        (f.y as i64).rem_euclid(256) as usize,
        (f.z as i64).rem_euclid(256) as usize,
    );
    let (x, y, z) = (p.x - f.x, p.y - f.y, p.z - f.z);
    let (u, v, w) = (fade(x), fade(y), fade(z));
    let a = pm[xi] as usize + yi;
    let (aa, ab) = (pm[a] as usize + zi, pm[a + 1] as usize + zi);
    let b = pm[xi + 1] as usize + yi;
    let (ba, bb) = (pm[b] as usize + zi, pm[b + 1] as usize + zi);
    let lerp = |t: f32, a: f32, b: f32| a + t * (b - a);
    let n = lerp(
        w,
        lerp(
            v,
            lerp(u, grad(pm[aa], x, y, z), grad(pm[ba], x - 1.0, y, z)),
            lerp(u, grad(pm[ab], x, y - 1.0, z), grad(pm[bb], x - 1.0, y - 1.0, z)),
        ),
        lerp(
            v,
            lerp(u, grad(pm[aa + 1], x, y, z - 1.0), grad(pm[ba + 1], x - 1.0, y, z - 1.0)),
            lerp(
                u,
                grad(pm[ab + 1], x, y - 1.0, z - 1.0),
                grad(pm[bb + 1], x - 1.0, y - 1.0, z - 1.0),
            ),
        ),
    );
    n.clamp(-1.0, 1.0)
}

/// Σ |noise(2^k·p)| / 2^k over `octaves`.
pub fn turbulence(p: Vec3, octaves: u32) -> f32 {
    (0..octaves).map(|k| noise(p * (1 << k) as f32).abs() / (1 << k) as f32).sum()
}

/// The gradient of `noise` at `p`, by central differences (for bumps).
pub fn noise_gradient(p: Vec3) -> Vec3 {
    let h = 1e-3;
    let d = |e: Vec3| (noise(p + e) - noise(p - e)) / (2.0 * h);
    Vec3::new(d(Vec3::X * h), d(Vec3::Y * h), d(Vec3::Z * h))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checker_follows_povray_parity() {
        let t = Texture::Checker { a: Vec3::ONE, b: Vec3::ZERO, size: 0.5 };
        assert_eq!(t.at(Vec3::new(0.25, 0.25, 0.25)), Vec3::ONE);
        assert_eq!(t.at(Vec3::new(0.75, 0.25, 0.25)), Vec3::ZERO);
        assert_eq!(t.at(Vec3::new(-0.25, 0.25, 0.25)), Vec3::ZERO, "⌊−0.5⌋ = −1: odd");
        assert_eq!(t.at(Vec3::new(-0.25, -0.25, 0.25)), Vec3::ONE);
    }

    /// In range, 0 at lattice points, continuous (small steps, small
    /// changes), periodic with period 256, and not constant.
    #[test]
    fn noise_is_bounded_continuous_and_periodic() {
        let (mut lo, mut hi) = (f32::MAX, f32::MIN);
        for i in 0..20_000 {
            let p = Vec3::new(i as f32 * 0.0137, (i % 97) as f32 * 0.311, (i % 13) as f32 * 1.7);
            let n = noise(p);
            assert!((-1.0..=1.0).contains(&n));
            lo = lo.min(n);
            hi = hi.max(n);
            let q = p + Vec3::splat(1e-3);
            assert!((noise(q) - n).abs() < 0.01, "a jump at {p}");
            assert!((noise(p + Vec3::new(256.0, 0.0, -256.0)) - n).abs() < 1e-3, "period at {p}");
        }
        assert!(lo < -0.4 && hi > 0.4, "{lo} {hi}");
        assert_eq!(noise(Vec3::new(3.0, -7.0, 12.0)), 0.0);
        for kind in [Pattern::Noise, Pattern::Marble, Pattern::Wood, Pattern::Granite] {
            let v = pattern(kind, Vec3::new(0.3, 0.7, 0.2));
            assert!((0.0..=1.0).contains(&v), "{kind:?}");
        }
    }
}
