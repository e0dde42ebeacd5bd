//! How pixels are sampled and how values reach the file: samples per
//! pixel, the reconstruction filter, the noise seed, exposure and tone
//! mapping. Settings only (checked here); `render::sample` does the work.

use super::builder::SceneError;

/// The reconstruction filters (separable: f(x, y) = f(x)·f(y)).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FilterKind {
    Box,
    Tent,
    Gaussian,
    Mitchell,
}

impl FilterKind {
    pub const NAMES: &'static str = "box, tent, gaussian or mitchell";

    pub fn parse(s: &str) -> Option<FilterKind> {
        Some(match s {
            "box" => FilterKind::Box,
            "tent" => FilterKind::Tent,
            "gaussian" => FilterKind::Gaussian,
            "mitchell" => FilterKind::Mitchell,
            _ => return None,
        })
    }

    /// The radius used when `filter` names none, in pixels (pbrt's).
    pub fn default_radius(self) -> f32 {
        match self {
            FilterKind::Box => 0.5,
            FilterKind::Tent => 1.0,
            FilterKind::Gaussian => 1.5,
            FilterKind::Mitchell => 2.0,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Filter {
    pub kind: FilterKind,
    /// Half the filter's width, in pixels.
    pub radius: f32,
}

impl Default for Filter {
    fn default() -> Filter {
        Filter { kind: FilterKind::Box, radius: 0.5 }
    }
}

impl Filter {
    /// The largest radius accepted, in pixels.
    pub const MAX_RADIUS: f32 = 16.0;

    pub fn new(kind: FilterKind, radius: Option<f32>) -> Result<Filter, SceneError> {
        let radius = radius.unwrap_or(kind.default_radius());
        if !(radius.is_finite() && radius > 0.0 && radius <= Filter::MAX_RADIUS) {
            return Err(SceneError::Invalid(format!(
                "filter radius must be above 0 and at most {} pixels, got {radius}",
                Filter::MAX_RADIUS
            )));
        }
        Ok(Filter { kind, radius })
    }

    /// The filter's 1D profile at `x` pixels from the centre (zero past the
    /// radius). Gaussian: σ = radius/3, less its value at the radius, as in
    /// pbrt. Mitchell–Netravali with B = C = 1/3, its support scaled to the
    /// radius (it has negative lobes).
    pub fn eval(&self, x: f32) -> f32 {
        let (r, ax) = (self.radius, x.abs());
        if ax > r {
            return 0.0;
        }
        match self.kind {
            FilterKind::Box => 1.0,
            FilterKind::Tent => 1.0 - ax / r,
            FilterKind::Gaussian => {
                let s = r / 3.0;
                let g = |t: f32| (-t * t / (2.0 * s * s)).exp();
                g(ax) - g(r)
            }
            FilterKind::Mitchell => {
                let t = 2.0 * ax / r;
                let (b, c) = (1.0 / 3.0, 1.0 / 3.0);
                let v = if t < 1.0 {
                    (12.0 - 9.0 * b - 6.0 * c) * t * t * t
                        + (-18.0 + 12.0 * b + 6.0 * c) * t * t
                        + (6.0 - 2.0 * b)
                } else {
                    (-b - 6.0 * c) * t * t * t
                        + (6.0 * b + 30.0 * c) * t * t
                        + (-12.0 * b - 48.0 * c) * t
                        + (8.0 * b + 24.0 * c)
                };
                v / 6.0
            }
        }
    }
}

/// Tone mapping: how values above 1 reach an 8-bit file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Tonemap {
    /// Each channel clipped at 1 (the COS 426 output).
    #[default]
    Clamp,
    /// x / (1 + x) on the largest channel, the others scaled with it.
    Reinhard,
    /// Narkowicz's fit of the ACES film curve, on the largest channel.
    Aces,
}

impl Tonemap {
    pub const NAMES: &'static str = "clamp, reinhard or aces";

    pub fn parse(s: &str) -> Option<Tonemap> {
        Some(match s {
            "clamp" => Tonemap::Clamp,
            "reinhard" => Tonemap::Reinhard,
            "aces" => Tonemap::Aces,
            _ => return None,
        })
    }
}

/// The light transport `render` computes (`integrator`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Integrator {
    /// COS 426's recursive ray tracer: direct light, mirror and glass.
    #[default]
    Whitted,
    /// Monte Carlo path tracing: all the light, diffuse bounces too.
    Path,
}

impl Integrator {
    pub const NAMES: &'static str = "whitted or path";

    pub fn parse(s: &str) -> Option<Integrator> {
        Some(match s {
            "whitted" => Integrator::Whitted,
            "path" => Integrator::Path,
            _ => return None,
        })
    }
}

/// The sampling state of a scene.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sampling {
    /// Camera rays per pixel; 1 traces the pixel centre.
    pub samples: u32,
    pub filter: Filter,
    /// Changes the noise pattern and nothing else (`seed`).
    pub seed: u64,
    /// The same, from the command line (`--seed`); `clear_scene` keeps it.
    pub base_seed: u64,
    /// The animation frame (`--frames`), also in every random number;
    /// `clear_scene` keeps it.
    pub frame: i64,
    /// Values are multiplied by 2^exposure before tone mapping.
    pub exposure: f32,
    pub tonemap: Tonemap,
    /// Adaptive sampling: (threshold, most samples per pixel).
    pub adaptive: Option<(f32, u32)>,
    /// The shutter interval (`shutter t0 t1`): camera rays sample times in
    /// it, where moving objects are seen.
    pub shutter: [f32; 2],
    pub integrator: Integrator,
    /// `--noise-target`: a pixel stops once its relative standard error
    /// is below this (from the command line; `clear_scene` keeps it).
    pub noise_target: Option<f32>,
}

impl Default for Sampling {
    fn default() -> Sampling {
        Sampling {
            samples: 1,
            filter: Filter::default(),
            seed: 0,
            base_seed: 0,
            frame: 0,
            exposure: 0.0,
            tonemap: Tonemap::Clamp,
            adaptive: None,
            shutter: [0.0, 0.0],
            integrator: Integrator::Whitted,
            noise_target: None,
        }
    }
}

impl Sampling {
    /// The most camera rays per pixel `samples` accepts.
    pub const MAX_SAMPLES: u32 = 1 << 16;
    /// The most samples adaptive sampling spends on a pixel unless told.
    pub const DEFAULT_ADAPTIVE_MAX: u32 = 1024;

    pub fn set_samples(&mut self, n: i64) -> Result<(), SceneError> {
        if !(1..=Sampling::MAX_SAMPLES as i64).contains(&n) {
            return Err(SceneError::Invalid(format!(
                "samples must be between 1 and {}, got {n}",
                Sampling::MAX_SAMPLES
            )));
        }
        self.samples = n as u32;
        Ok(())
    }

    /// `adaptive threshold ?max?`: a threshold of 0 turns it off.
    pub fn set_adaptive(&mut self, threshold: f64, max: Option<i64>) -> Result<(), SceneError> {
        if !(threshold >= 0.0 && threshold.is_finite()) {
            return Err(SceneError::Invalid(format!(
                "adaptive threshold must be 0 (off) or more, got {threshold}"
            )));
        }
        let max = max.unwrap_or(Sampling::DEFAULT_ADAPTIVE_MAX as i64);
        if !(1..=Sampling::MAX_SAMPLES as i64).contains(&max) {
            return Err(SceneError::Invalid(format!(
                "adaptive maximum must be between 1 and {}, got {max}",
                Sampling::MAX_SAMPLES
            )));
        }
        self.adaptive = (threshold > 0.0).then_some((threshold as f32, max as u32));
        Ok(())
    }

    pub fn set_shutter(&mut self, t0: f64, t1: f64) -> Result<(), SceneError> {
        let ok = |t: f64| t.is_finite() && t.abs() <= 1e9;
        if !(ok(t0) && ok(t1) && t0 <= t1) {
            return Err(SceneError::Invalid(format!(
                "shutter must open before it closes, at finite times, got {t0} {t1}"
            )));
        }
        self.shutter = [t0 as f32, t1 as f32];
        Ok(())
    }

    /// Whether the shutter is open for a while (camera rays need a time).
    pub fn has_shutter(&self) -> bool {
        self.shutter[0] < self.shutter[1]
    }

    pub fn set_exposure(&mut self, ev: f64) -> Result<(), SceneError> {
        if !(-64.0..=64.0).contains(&ev) {
            return Err(SceneError::Invalid(format!(
                "exposure must be between -64 and 64 stops, got {ev}"
            )));
        }
        self.exposure = ev as f32;
        Ok(())
    }

    /// What a linear value becomes before it is written (exposure, then the
    /// tone map on the largest channel, so hue is kept; `Clamp` clips later).
    pub fn look(&self, c: glam::Vec3) -> glam::Vec3 {
        let c = c * self.exposure.exp2();
        let m = c.max_element();
        if self.tonemap == Tonemap::Clamp || m.is_nan() || m <= 0.0 {
            return c;
        }
        let mapped = match self.tonemap {
            Tonemap::Reinhard => m / (1.0 + m),
            _ => {
                let (a, b, cc, d, e) = (2.51, 0.03, 2.43, 0.59, 0.14);
                ((m * (a * m + b)) / (m * (cc * m + d) + e)).clamp(0.0, 1.0)
            }
        };
        c * (mapped / m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn filters_peak_at_the_centre_and_end_at_the_radius() {
        for kind in [FilterKind::Box, FilterKind::Tent, FilterKind::Gaussian, FilterKind::Mitchell]
        {
            let f = Filter::new(kind, None).unwrap();
            assert!(f.eval(0.0) > 0.0, "{kind:?}");
            assert!(f.eval(0.0) >= f.eval(0.3), "{kind:?}");
            assert_eq!(f.eval(f.radius * 1.01), 0.0, "{kind:?}");
            assert!(f.eval(f.radius * 0.999).abs() < 0.01 || kind == FilterKind::Box, "{kind:?}");
        }
        // Mitchell's negative lobe, between 1/2 and the whole radius.
        let m = Filter::new(FilterKind::Mitchell, None).unwrap();
        assert!(m.eval(1.5) < 0.0);
        assert!(Filter::new(FilterKind::Box, Some(0.0)).is_err());
        assert!(Filter::new(FilterKind::Box, Some(f32::NAN)).is_err());
    }

    #[test]
    fn tone_maps_keep_hue_and_stay_below_one() {
        let mut s = Sampling { tonemap: Tonemap::Reinhard, ..Sampling::default() };
        let c = s.look(glam::Vec3::new(4.0, 2.0, 1.0));
        assert!((c.x - 0.8).abs() < 1e-6 && (c.y - 0.4).abs() < 1e-6 && (c.z - 0.2).abs() < 1e-6);
        s.tonemap = Tonemap::Aces;
        let c = s.look(glam::Vec3::new(100.0, 50.0, 0.0));
        assert!(c.x <= 1.0 && (c.y / c.x - 0.5).abs() < 1e-6);
        s.tonemap = Tonemap::Clamp;
        s.exposure = -1.0;
        assert_eq!(s.look(glam::Vec3::splat(3.0)), glam::Vec3::splat(1.5));
    }
}
