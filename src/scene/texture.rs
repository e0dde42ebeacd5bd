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
    /// Image `id` of the scene's images, mapped by `mapping`; repeating
    /// unless `once` (outside it, the material's colour).
    Image { id: u32, mapping: Mapping, once: bool },
}

/// How an image is laid on an object (POV-Ray's `image_map` map types).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Mapping {
    /// The unit square [0, 1]² of the xy-plane (map_type 0).
    Planar,
    /// Around the y axis, height 0 to 1 (map_type 2).
    Cylindrical,
    /// Longitude and latitude around the origin (map_type 1).
    Spherical,
    /// The surface's own texture coordinates (a mesh's `vt`); where it has
    /// none, the planar mapping.
    Uv,
}

/// Where a texture is looked up: the point in the coordinates the object
/// was written in, and the surface's texture coordinates, if it has any,
/// with how fast they change per unit of those coordinates.
#[derive(Clone, Copy, Debug)]
pub struct TexPoint {
    pub p: Vec3,
    pub uv: Option<([f32; 2], f32)>,
}

impl From<Vec3> for TexPoint {
    fn from(p: Vec3) -> TexPoint {
        TexPoint { p, uv: None }
    }
}

impl Mapping {
    pub const NAMES: &'static str = "planar, cylindrical, spherical or uv";

    pub fn parse(s: &str) -> Option<Mapping> {
        Some(match s {
            "planar" => Mapping::Planar,
            "cylindrical" => Mapping::Cylindrical,
            "spherical" => Mapping::Spherical,
            "uv" => Mapping::Uv,
            _ => return None,
        })
    }

    /// The image point (u, v) of `p`, and how fast (u, v) change per unit
    /// of distance there (for the filter's footprint). u runs around the y
    /// axis from +x (u = 0) through +z (u = 1/4), as POV-Ray's map types 1
    /// and 2 measure it (`spherical_image_map`: the angle from +x in the
    /// x-z plane, 2π less it where z < 0); v runs up.
    pub fn uv(self, at: TexPoint) -> (f32, f32, f32) {
        let p = at.p;
        let around = || {
            let a = p.z.atan2(p.x) / std::f32::consts::TAU;
            if a < 0.0 { a + 1.0 } else { a }
        };
        match self {
            Mapping::Uv if at.uv.is_some() => {
                let ([u, v], rate) = at.uv.unwrap_or_default();
                (u, v, rate)
            }
            Mapping::Planar | Mapping::Uv => (p.x, p.y, 1.0),
            Mapping::Cylindrical => {
                let rho = (p.x * p.x + p.z * p.z).sqrt().max(1e-6);
                (around(), p.y, (1.0 / (std::f32::consts::TAU * rho)).max(1.0))
            }
            Mapping::Spherical => {
                let r = p.length().max(1e-6);
                let lat = (p.y / r).clamp(-1.0, 1.0).asin();
                (around(), 0.5 + lat / std::f32::consts::PI, 1.0 / (std::f32::consts::PI * r))
            }
        }
    }
}

/// An image texture: linear colours, with its mip-map (each level half
/// the last, by 2×2 box averages), sampled bilinearly within a level and
/// linearly between the two levels the footprint falls between.
#[derive(Clone, Debug)]
pub struct Image {
    levels: Vec<(u32, u32, Vec<Vec3>)>,
}

impl Image {
    /// `px` row by row from the top, `w`×`h` (both above 0).
    pub fn new(w: u32, h: u32, px: Vec<Vec3>) -> Image {
        let mut levels = vec![(w, h, px)];
        loop {
            let (w, h, px) = levels.last().expect("one level at least");
            if *w == 1 && *h == 1 {
                break;
            }
            let (nw, nh) = ((w / 2).max(1), (h / 2).max(1));
            let at = |x: u32, y: u32| px[(y.min(h - 1) * w + x.min(w - 1)) as usize];
            let next = (0..nh)
                .flat_map(|y| (0..nw).map(move |x| (x, y)))
                .map(|(x, y)| {
                    (at(2 * x, 2 * y)
                        + at(2 * x + 1, 2 * y)
                        + at(2 * x, 2 * y + 1)
                        + at(2 * x + 1, 2 * y + 1))
                        / 4.0
                })
                .collect();
            levels.push((nw, nh, next));
        }
        Image { levels }
    }

    pub fn size(&self) -> (u32, u32) {
        (self.levels[0].0, self.levels[0].1)
    }

    /// The colour at image point (u, v) in [0, 1)² ((0, 0) the bottom
    /// left) for a footprint of `texels` texels of the full image.
    pub fn sample(&self, u: f32, v: f32, texels: f32) -> Vec3 {
        let top = (self.levels.len() - 1) as f32;
        let level = texels.max(1.0).log2().clamp(0.0, top);
        let (l0, f) = (level.floor() as usize, level.fract());
        let a = self.bilinear(l0, u, v);
        if f == 0.0 || l0 + 1 >= self.levels.len() {
            return a;
        }
        a.lerp(self.bilinear(l0 + 1, u, v), f)
    }

    fn bilinear(&self, level: usize, u: f32, v: f32) -> Vec3 {
        let (w, h, px) = &self.levels[level];
        let (w, h) = (*w as i64, *h as i64);
        // Texel centres at half-integers; wrapped, as the texture repeats.
        let x = u * w as f32 - 0.5;
        let y = (1.0 - v) * h as f32 - 0.5;
        let (x0, y0) = (x.floor(), y.floor());
        let (fx, fy) = (x - x0, y - y0);
        let at = |i: i64, j: i64| px[(j.rem_euclid(h) * w + i.rem_euclid(w)) as usize];
        let (i, j) = (x0 as i64, y0 as i64);
        let top = at(i, j).lerp(at(i + 1, j), fx);
        let bottom = at(i, j + 1).lerp(at(i + 1, j + 1), fx);
        top.lerp(bottom, fy)
    }
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
            Texture::Image { .. } => return Ok(()),
        };
        check_color(a)?;
        check_color(b)?;
        if !(size > 0.0 && size.is_finite()) {
            return Err(SceneError::Invalid(format!("texture size must be above 0, got {size}")));
        }
        Ok(())
    }

    /// The colour at `p`; `images` are the scene's, and `footprint` the
    /// width of the ray's cone there in the same coordinates (for image
    /// filtering). `None` outside a `-once` image.
    pub fn at(
        &self,
        at: TexPoint,
        images: &[std::sync::Arc<Image>],
        footprint: f32,
    ) -> Option<Vec3> {
        Some(match *self {
            Texture::Image { id, mapping, once } => {
                let (u, v, rate) = mapping.uv(at);
                if once && !((0.0..1.0).contains(&u) && (0.0..1.0).contains(&v)) {
                    return None;
                }
                let img = &images[id as usize];
                let (w, h) = img.size();
                let texels = footprint * rate * w.max(h) as f32;
                img.sample(u - u.floor(), v - v.floor(), texels)
            }
            t => t.pattern_at(at.p),
        })
    }

    fn pattern_at(&self, p: Vec3) -> Vec3 {
        match *self {
            Texture::Checker { a, b, size } => {
                let c = (p / size).floor();
                let s = c.x as i64 + c.y as i64 + c.z as i64;
                if s.rem_euclid(2) == 0 { a } else { b }
            }
            Texture::Pattern { kind, a, b, scale } => a.lerp(b, pattern(kind, p / scale)),
            Texture::Image { .. } => Vec3::ZERO,
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
        let at = |p: Vec3| t.at(p.into(), &[], 0.0).unwrap();
        assert_eq!(at(Vec3::new(0.25, 0.25, 0.25)), Vec3::ONE);
        assert_eq!(at(Vec3::new(0.75, 0.25, 0.25)), Vec3::ZERO);
        assert_eq!(at(Vec3::new(-0.25, 0.25, 0.25)), Vec3::ZERO, "⌊−0.5⌋ = −1: odd");
        assert_eq!(at(Vec3::new(-0.25, -0.25, 0.25)), Vec3::ONE);
    }

    /// Texel centres come back exactly; the mip-map's top level is the
    /// mean; a wide footprint blurs towards it.
    #[test]
    fn images_sample_texels_and_average_far_away() {
        let px: Vec<Vec3> = (0..16).map(|i| Vec3::splat(i as f32 / 15.0)).collect();
        let img = Image::new(4, 4, px.clone());
        for (k, p) in px.iter().enumerate() {
            let (x, y) = ((k % 4) as f32, (k / 4) as f32);
            let (u, v) = ((x + 0.5) / 4.0, 1.0 - (y + 0.5) / 4.0);
            assert!((img.sample(u, v, 1.0) - *p).length() < 1e-6, "texel {k}");
        }
        let mean = px.iter().copied().sum::<Vec3>() / 16.0;
        assert!((img.sample(0.3, 0.7, 1e6) - mean).length() < 1e-6);
        assert_eq!(img.levels.len(), 3);
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
