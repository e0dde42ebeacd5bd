//! Metaballs with POV-Ray's blob field: each component of centre c,
//! radius r and strength s adds s·(1 − d²/r²)² within distance d < r of c;
//! the surface is where the sum equals the threshold, and the inside is
//! where it is above.
//!
//! Along a ray, d² is quadratic in t, so inside one component's sphere its
//! term is a quartic; between consecutive entries and exits of the spheres
//! the field is a sum of quartics, one polynomial, whose roots (`poly`)
//! are the crossings. Exact, with no step size to miss a thin part.

use glam::Vec3;

use super::poly;
use super::{Aabb, Ray};

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Component {
    pub center: Vec3,
    pub radius: f32,
    pub strength: f32,
}

#[derive(Clone, Debug)]
pub struct Blob {
    comps: Vec<Component>,
    threshold: f32,
    bounds: Aabb,
}

impl Blob {
    /// `threshold` above 0; components with positive strength bound it.
    pub fn new(comps: Vec<Component>, threshold: f32) -> Blob {
        let bounds = comps.iter().filter(|c| c.strength > 0.0).fold(Aabb::EMPTY, |b, c| {
            let r = Vec3::splat(c.radius);
            b.union(Aabb { min: (c.center - r).into(), max: (c.center + r).into() })
        });
        Blob { comps, threshold, bounds }
    }

    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// The field at `p`.
    pub fn field(&self, p: Vec3) -> f32 {
        self.comps
            .iter()
            .map(|c| {
                let q = 1.0 - (p - c.center).length_squared() / (c.radius * c.radius);
                if q > 0.0 { c.strength * q * q } else { 0.0 }
            })
            .sum()
    }

    pub fn contains(&self, p: Vec3) -> bool {
        self.field(p) > self.threshold
    }

    /// The outward normal (not unit length) at `p`: minus the field's
    /// gradient, over 4.
    pub fn normal(&self, p: Vec3) -> Vec3 {
        self.comps.iter().fold(Vec3::ZERO, |n, c| {
            let r2 = c.radius * c.radius;
            let q = 1.0 - (p - c.center).length_squared() / r2;
            if q > 0.0 { n + (p - c.center) * (c.strength * q / r2) } else { n }
        })
    }

    /// Every crossing of the ray's line, in order, passed to `each` until
    /// it returns true.
    pub fn crossings(&self, ray: &Ray, mut each: impl FnMut(f32) -> bool) {
        let o = ray.origin.as_dvec3();
        let len = ray.dir.as_dvec3().length();
        if len == 0.0 || !len.is_finite() {
            return;
        }
        let u = ray.dir.as_dvec3() / len;
        // Measured from the point of the line nearest the blob's centre, in
        // unit steps: coefficients of the blob's size, not the distance.
        let mid = (self.bounds.min + self.bounds.max).as_dvec3() / 2.0;
        let s0 = (mid - o).dot(u);
        let base = o + u * s0;
        // Each component the line passes through: its interval and its
        // term (s·q², q = 1 − |base + s·u − c|²/r² = a·s² + b·s + k).
        let mut spans: Vec<(f64, f64, [f64; 3], f64)> = Vec::new();
        for c in &self.comps {
            let f = base - c.center.as_dvec3();
            let r2 = c.radius as f64 * c.radius as f64;
            let b = f.dot(u);
            let disc = b * b - (f.length_squared() - r2);
            if disc <= 0.0 {
                continue;
            }
            let h = disc.sqrt();
            let (a, bq, k) = (-1.0 / r2, -2.0 * b / r2, 1.0 - f.length_squared() / r2);
            spans.push((-b - h, -b + h, [k, bq, a], c.strength as f64));
        }
        if spans.is_empty() {
            return;
        }
        let mut cuts: Vec<f64> = spans.iter().flat_map(|s| [s.0, s.1]).collect();
        cuts.sort_by(f64::total_cmp);
        let threshold = self.threshold as f64;
        for w in cuts.windows(2) {
            let (lo, hi) = (w[0], w[1]);
            if hi <= lo {
                continue;
            }
            let mid_s = 0.5 * (lo + hi);
            // The field's polynomial here: Σ s·q² − threshold.
            let mut c = [-threshold, 0.0, 0.0, 0.0, 0.0];
            for (a, b, q, s) in &spans {
                if *a <= mid_s && mid_s <= *b {
                    let [k, l, m] = *q;
                    c[0] += s * k * k;
                    c[1] += s * 2.0 * k * l;
                    c[2] += s * (l * l + 2.0 * k * m);
                    c[3] += s * 2.0 * l * m;
                    c[4] += s * m * m;
                }
            }
            let mut roots = [0.0; poly::MAX_DEGREE];
            // Closed at the cut on the left: a root exactly there counts.
            let n = poly::roots(&c, lo - 1e-12 * (1.0 + lo.abs()), hi, &mut roots);
            for &s in &roots[..n] {
                if s >= lo && each(((s + s0) / len) as f32) {
                    return;
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Crossings against marching the field, on rays through two
    /// overlapping components (a neck between them) and one negative one.
    #[test]
    fn crossings_agree_with_marching_the_field() {
        let b = Blob::new(
            vec![
                Component { center: Vec3::new(-0.6, 0.0, 0.0), radius: 1.0, strength: 1.0 },
                Component { center: Vec3::new(0.6, 0.0, 0.0), radius: 1.0, strength: 1.0 },
                Component { center: Vec3::new(0.0, 0.7, 0.0), radius: 0.5, strength: -1.0 },
            ],
            0.5,
        );
        let mut checked = 0;
        for k in 0..400 {
            let a = k as f32 * 0.7;
            let o = Vec3::new(4.0 * a.cos(), 0.9 * (a * 1.3).sin(), 4.0 * a.sin());
            let target = Vec3::new(0.5 * (a * 2.1).sin(), 0.3 * (a * 0.7).cos(), 0.0);
            let d = (target - o) * (0.5 + (k % 3) as f32);
            let ray = Ray::new(o, d);
            let mut got = Vec::new();
            b.crossings(&ray, |t| {
                got.push(t);
                false
            });
            let steps = 20_000;
            let (t0, t1) = (0.0f32, 8.0 / d.length());
            let h = (t1 - t0) / steps as f32;
            let mut flips = Vec::new();
            let mut was = b.contains(ray.at(t0));
            for i in 1..=steps {
                let t = t0 + h * i as f32;
                let now = b.contains(ray.at(t));
                if now != was {
                    flips.push(t - h / 2.0);
                }
                was = now;
            }
            if flips.windows(2).any(|w| w[1] - w[0] < 3.0 * h) {
                continue;
            }
            assert_eq!(got.len(), flips.len(), "ray {k}: {got:?} vs {flips:?}");
            for (g, f) in got.iter().zip(&flips) {
                assert!((g - f).abs() <= h, "ray {k}: {got:?} vs {flips:?}");
                // The normal points out of the field.
                let p = ray.at(*g);
                let n = b.normal(p).normalize();
                assert!(b.contains(p - n * 1e-3) && !b.contains(p + n * 1e-3));
            }
            checked += !got.is_empty() as usize;
        }
        assert!(checked > 100, "{checked}");
    }
}
