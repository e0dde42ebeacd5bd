//! Real roots of polynomials of low degree in an interval, in double
//! precision: the torus's quartic and the blob's piecewise quartics.
//!
//! Roots are isolated by the derivative's roots (found the same way, down
//! to a quadratic solved in closed form): between two neighbouring
//! critical points the polynomial is monotonic, so a sign change there
//! brackets exactly one root, refined by bisection guarded Newton steps.
//! No root is lost to a bad starting guess, and a tangent touch (a double
//! root, no sign change) is not a crossing.

/// At most this degree.
pub const MAX_DEGREE: usize = 4;

/// Evaluates c[0] + c[1]·x + ... at `x` (Horner).
#[inline]
pub fn eval(c: &[f64], x: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &k| acc * x + k)
}

/// The roots of `c` (coefficients from the constant term up, degree at
/// most `MAX_DEGREE`) strictly inside `(lo, hi)`, ascending, into `out`;
/// returns how many.
pub fn roots(c: &[f64], lo: f64, hi: f64, out: &mut [f64; MAX_DEGREE]) -> usize {
    // Drop leading zeros (a quartic whose top term vanishes).
    let mut n = c.len();
    while n > 0 && c[n - 1] == 0.0 {
        n -= 1;
    }
    let c = &c[..n];
    if lo.partial_cmp(&hi) != Some(std::cmp::Ordering::Less) || n < 2 {
        return 0;
    }
    match n - 1 {
        1 => {
            let x = -c[0] / c[1];
            if x > lo && x < hi {
                out[0] = x;
                1
            } else {
                0
            }
        }
        2 => quadratic(c[2], c[1], c[0], lo, hi, out),
        deg => {
            debug_assert!(deg <= MAX_DEGREE);
            let mut d = [0.0; MAX_DEGREE];
            for k in 1..=deg {
                d[k - 1] = c[k] * k as f64;
            }
            let mut crit = [0.0; MAX_DEGREE];
            let m = roots(&d[..deg], lo, hi, &mut crit);
            let mut count = 0;
            let mut a = lo;
            let mut fa = eval(c, a);
            for b in crit[..m].iter().copied().chain(std::iter::once(hi)) {
                let fb = eval(c, b);
                if (fa < 0.0 && fb > 0.0) || (fa > 0.0 && fb < 0.0) {
                    out[count] = refine(c, a, b, fa);
                    count += 1;
                }
                (a, fa) = (b, fb);
            }
            count
        }
    }
}

/// The roots of a·x² + b·x + c in `(lo, hi)`, in the cancellation-free
/// form.
pub fn quadratic(a: f64, b: f64, c: f64, lo: f64, hi: f64, out: &mut [f64; MAX_DEGREE]) -> usize {
    let disc = b * b - 4.0 * a * c;
    if disc < 0.0 {
        return 0;
    }
    let q = -0.5 * (b + b.signum() * disc.sqrt());
    let (mut x0, mut x1) = (q / a, if q != 0.0 { c / q } else { x0_of(a, b) });
    if x0 > x1 {
        std::mem::swap(&mut x0, &mut x1);
    }
    let mut n = 0;
    for x in [x0, x1] {
        if x > lo && x < hi && (n == 0 || x != out[0]) {
            out[n] = x;
            n += 1;
        }
    }
    n
}

/// The other root when q = 0 (b = 0 and c = 0): both are −b/2a.
fn x0_of(a: f64, b: f64) -> f64 {
    -b / (2.0 * a)
}

/// The one root of `c` in `(a, b)` where it changes sign (f(a) = `fa`):
/// Newton steps kept inside the shrinking bracket, bisection otherwise.
fn refine(c: &[f64], mut a: f64, mut b: f64, fa: f64) -> f64 {
    let rising = fa < 0.0;
    let mut x = 0.5 * (a + b);
    for _ in 0..100 {
        let f = eval(c, x);
        if f == 0.0 {
            return x;
        }
        if (f < 0.0) == rising {
            a = x;
        } else {
            b = x;
        }
        // Newton from x; bisect when it leaves the bracket.
        let df =
            c.iter().enumerate().skip(1).rev().fold(0.0, |acc, (k, &ck)| acc * x + ck * k as f64);
        let nx = x - f / df;
        let next = if nx > a && nx < b { nx } else { 0.5 * (a + b) };
        if (next - x).abs() <= 1e-15 * x.abs().max(1e-300) || b - a <= 1e-15 * a.abs().max(b.abs())
        {
            return next;
        }
        x = next;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    fn from_roots(r: &[f64]) -> Vec<f64> {
        // The monic polynomial with these roots.
        let mut c = vec![1.0];
        for &x in r {
            let mut n = vec![0.0; c.len() + 1];
            for (k, &ck) in c.iter().enumerate() {
                n[k + 1] += ck;
                n[k] -= x * ck;
            }
            c = n;
        }
        c
    }

    #[test]
    fn finds_every_simple_root_in_order() {
        let mut out = [0.0; MAX_DEGREE];
        for r in
            [vec![-3.0, -1.0, 0.5, 2.0], vec![0.1, 0.2, 0.3, 10.0], vec![-1.0, 1.0, 1.001, 5.0]]
        {
            let c = from_roots(&r);
            let n = roots(&c, -100.0, 100.0, &mut out);
            assert_eq!(n, 4, "{r:?}");
            for (a, b) in out.iter().zip(&r) {
                assert!((a - b).abs() < 1e-9, "{out:?} vs {r:?}");
            }
            // Only those inside the interval.
            assert_eq!(
                roots(&c, 0.0, 3.0, &mut out),
                r.iter().filter(|&&x| x > 0.0 && x < 3.0).count()
            );
        }
        // x² + 1: none; a double root touches, it does not cross.
        assert_eq!(roots(&[1.0, 0.0, 1.0], -5.0, 5.0, &mut out), 0);
        // (Rounding may split it into two roots next to each other.)
        let n = roots(&from_roots(&[1.0, 1.0, 3.0, 4.0]), -5.0, 5.0, &mut out);
        assert!(n == 2 || (n == 4 && (out[1] - out[0]).abs() < 1e-6), "{out:?}");
        assert!((out[n - 2] - 3.0).abs() < 1e-9 && (out[n - 1] - 4.0).abs() < 1e-9);
        // A vanishing top term is a lower degree.
        assert_eq!(roots(&[-2.0, 1.0, 0.0, 0.0, 0.0], -5.0, 5.0, &mut out), 1);
        assert!((out[0] - 2.0).abs() < 1e-12);
    }
}
