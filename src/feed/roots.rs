//! Small bounded root solvers shared by the feed laws (after Ruckig's roots.hpp): the positive
//! quadratic root without cancellation, the real root of a depressed cubic with one sign change,
//! the real roots of a depressed cubic by the trigonometric form, a bracketed Newton iteration, and
//! the two bounded fall-backs (bisection, stepping down by ulps) that make a closed-form root exact
//! against the distance function as the laws evaluate it.

use super::tolerance::{BISECTIONS, FIT_DOWN_STEPS, NEWTON_STEP, NEWTON_STEPS, ROOT_TOL};

/// Positive root of a·x² + b·x + c = 0 (a > 0, c ≤ 0), written without cancellation for b ≥ 0.
pub fn quadratic_pos(a: f64, b: f64, c: f64) -> f64 {
    let disc = (b * b - 4.0 * a * c).max(0.0).sqrt();
    let r = if b >= 0.0 {
        -2.0 * c / (b + disc)
    } else {
        (disc - b) / (2.0 * a)
    };
    if r.is_finite() {
        r.max(0.0)
    } else {
        0.0
    }
}

/// The real root of s³ + p·s − q = 0 with p ≥ 0, q ≥ 0 (exactly one real root, ≥ 0): Cardano,
/// polished by two Newton steps against its cancellation when p³ ≫ q².
pub fn cubic_pos(p: f64, q: f64) -> f64 {
    if q <= 0.0 {
        return 0.0;
    }
    let disc = (0.25 * q * q + p * p * p / 27.0).sqrt();
    let w = (0.5 * q + disc).cbrt();
    let mut s = if w > 0.0 { w - p / (3.0 * w) } else { 0.0 };
    if s.is_nan() || s <= 0.0 || s * p > 2.0 * q {
        // Cancellation: for p³ ≫ q² the root is ≈ q/p.
        s = q / p.max(f64::MIN_POSITIVE);
    }
    for _ in 0..2 {
        let f = s * s * s + p * s - q;
        let df = 3.0 * s * s + p;
        if df > 0.0 {
            s -= f / df;
        }
    }
    s.max(0.0)
}

/// Real roots of the depressed cubic s³ + p·s + q = 0, ascending (NaN for absent ones): the
/// trigonometric form when there are three (p < 0, 4p³ + 27q² ≤ 0), Cardano when there is one.
pub fn cubic_depressed(p: f64, q: f64) -> [f64; 3] {
    let disc = 4.0 * p * p * p + 27.0 * q * q;
    if p < 0.0 && disc <= 0.0 {
        let m = 2.0 * (-p / 3.0).sqrt();
        let theta = ((3.0 * q / (p * m)).clamp(-1.0, 1.0)).acos() / 3.0;
        let third = 2.0 * std::f64::consts::PI / 3.0;
        let mut r = [
            m * theta.cos(),
            m * (theta - third).cos(),
            m * (theta - 2.0 * third).cos(),
        ];
        r.sort_by(f64::total_cmp);
        return r.map(|s| polish_cubic(p, q, s));
    }
    let w = (0.25 * q * q + p * p * p / 27.0).max(0.0).sqrt();
    let root = (-0.5 * q + w).cbrt() + (-0.5 * q - w).cbrt();
    [polish_cubic(p, q, root), f64::NAN, f64::NAN]
}

/// Two Newton steps on s³ + p·s + q (the closed forms lose digits near a root of small magnitude).
fn polish_cubic(p: f64, q: f64, mut s: f64) -> f64 {
    for _ in 0..2 {
        let df = 3.0 * s * s + p;
        if df != 0.0 {
            s -= (s * s * s + p * s + q) / df;
        }
    }
    s
}

/// Root of an increasing f on [lo, hi] with f(lo) ≤ 0 < f(hi): Newton from x0, bisection whenever a
/// step leaves the bracket (bounded). `f` returns (f(x), f'(x)); it stops at |f| ≤ `tol` or a Newton
/// step below [`NEWTON_STEP`] relative (quadratic convergence: the error left is its square).
/// Returns the last iterate, next to the root; the caller makes it exact with [`fit_down`].
pub fn newton_bounded(mut lo: f64, mut hi: f64, x0: f64, tol: f64, f: impl Fn(f64) -> (f64, f64)) -> f64 {
    let mut x = x0.clamp(lo, hi);
    for _ in 0..NEWTON_STEPS {
        let (fx, dfx) = f(x);
        if fx.is_nan() || fx.abs() <= tol {
            break;
        }
        if fx < 0.0 {
            lo = x;
        } else {
            hi = x;
        }
        let next = x - fx / dfx;
        if next > lo && next < hi {
            let small = (next - x).abs() <= NEWTON_STEP * x.abs();
            x = next;
            if small {
                break;
            }
        } else {
            x = 0.5 * (lo + hi);
            if hi - lo <= f64::EPSILON * hi {
                break;
            }
        }
    }
    x
}

/// Bisection between `good` (predicate holds) and `bad` (it does not); returns the last good point.
/// Works whichever way round the two lie; bounded iteration count.
pub fn bisect(mut good: f64, mut bad: f64, ok: impl Fn(f64) -> bool) -> f64 {
    for _ in 0..BISECTIONS {
        let mid = 0.5 * (good + bad);
        if mid == good || mid == bad {
            break;
        }
        if ok(mid) {
            good = mid;
        } else {
            bad = mid;
        }
    }
    good
}

/// The last point where g ≤ 0 between `good` (g ≤ 0) and `bad` (g > 0), g changing sign once in
/// between (either way round), to within [`ROOT_TOL`] of its size: regula falsi with the
/// Illinois halving, which converges superlinearly where bisection halves, bounded.
pub fn falsi(good: f64, bad: f64, g: impl Fn(f64) -> f64) -> f64 {
    let (g_good, g_bad) = (g(good), g(bad));
    falsi_from(good, g_good, bad, g_bad, g)
}

/// `falsi` with g already evaluated at both ends (`g_good` = g(good), `g_bad` = g(bad)), where
/// the caller has them from bracketing: the same steps without solving them again. The bracket
/// ends within `ROOT_TOL` of the larger end's magnitude (or at a zero of g): no step lands
/// nearer either end than half that, so where the rounding of g near the crossing leaves the
/// secant pointing at an end (which made the steps those of a bisection down to adjacent
/// floats), the next step closes the bracket instead.
pub fn falsi_from(good: f64, g_good: f64, bad: f64, g_bad: f64, g: impl Fn(f64) -> f64) -> f64 {
    // Never given up: the crossing itself.
    falsi_until(good, g_good, bad, g_bad, g, |_, _| false).unwrap_or(good)
}

/// `falsi_from`, given up (None) as soon as its bracket is `done` (given its good and bad ends;
/// it starts so, or a step makes it so): the point it would return is the good end or lies
/// between the two. The same steps until then.
pub fn falsi_until(
    mut good: f64,
    mut g_good: f64,
    mut bad: f64,
    mut g_bad: f64,
    g: impl Fn(f64) -> f64,
    done: impl Fn(f64, f64) -> bool,
) -> Option<f64> {
    if !(g_good <= 0.0 && g_bad > 0.0) {
        return Some(good);
    }
    if done(good, bad) {
        return None;
    }
    // Which end moved last: the other end's value is halved when the same one moves twice.
    let mut last_good = None;
    // Whether the last step probed the margin beside an end.
    let mut probed = false;
    for _ in 0..BISECTIONS {
        let margin = 0.5 * ROOT_TOL * good.abs().max(bad.abs());
        if g_good == 0.0 || (bad - good).abs() <= 2.0 * margin {
            break;
        }
        let mut x = good - g_good * (bad - good) / (g_bad - g_good);
        // A secant that rounds onto an end (g there is rounding noise beside the other's) is
        // taken once to the margin next to it, which closes the bracket where the crossing is
        // that near; again (it was not), or outside the bracket, it bisects.
        let inside = (x - good) * (x - bad);
        if !(x.is_finite() && (inside < 0.0 || inside == 0.0 && !probed)) {
            x = 0.5 * (good + bad);
        }
        probed = inside == 0.0;
        x = if good < bad {
            x.clamp(good + margin, bad - margin)
        } else {
            x.clamp(bad + margin, good - margin)
        };
        if x == good || x == bad {
            break;
        }
        let gx = g(x);
        if gx <= 0.0 {
            (good, g_good) = (x, gx);
            if done(good, bad) {
                return None;
            }
            if last_good == Some(true) {
                g_bad *= 0.5;
            }
            last_good = Some(true);
        } else {
            (bad, g_bad) = (x, gx);
            if done(good, bad) {
                return None;
            }
            if last_good == Some(false) {
                g_good *= 0.5;
            }
            last_good = Some(false);
        }
    }
    Some(good)
}

/// The crossing of g between `good` (g ≤ 0) and `bad` (g > 0), to within `ROOT_TOL`, from a
/// guess `x0` that a closed form gave to about its rounding: g at x0 and at the point half
/// `ROOT_TOL` of |x0| past it (on the side g(x0) points to) bracket it, and the good one of the
/// two is returned; None where they do not (or leave [good, bad]): then the regula falsi.
pub fn crossing_near(x0: f64, good: f64, bad: f64, g: impl Fn(f64) -> f64) -> Option<f64> {
    let inside = |x: f64| (x - good) * (x - bad) < 0.0;
    let step = (0.5 * ROOT_TOL * x0.abs()).copysign(bad - good);
    if !inside(x0) || step == 0.0 {
        return None;
    }
    if g(x0) <= 0.0 {
        let x1 = x0 + step;
        (inside(x1) && g(x1) > 0.0).then_some(x0)
    } else {
        let x1 = x0 - step;
        (inside(x1) && g(x1) <= 0.0).then_some(x1)
    }
}

/// Step `w` down towards `floor` (a few ulps at first, doubling) until f(w) ≤ target; f(floor) ≤
/// target is known, so at most a bounded number of steps. Returns w and f(w).
pub fn fit_down(mut w: f64, floor: f64, target: f64, f: impl Fn(f64) -> f64) -> (f64, f64) {
    let mut step = w * f64::EPSILON;
    for _ in 0..FIT_DOWN_STEPS {
        let fw = f(w);
        if fw <= target || w <= floor {
            return (w, fw);
        }
        w = (w - step).max(floor);
        step *= 2.0;
    }
    (w, f(w))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quadratic_and_cubic_roots() {
        // (x − 2)(x + 3) = x² + x − 6.
        assert!((quadratic_pos(1.0, 1.0, -6.0) - 2.0).abs() < 1e-15);
        assert!((quadratic_pos(1.0, -1.0, -6.0) - 3.0).abs() < 1e-15);
        // s³ + s − 10 = 0 at s = 2; tiny q against large p: s ≈ q/p.
        assert!((cubic_pos(1.0, 10.0) - 2.0).abs() < 1e-15);
        let s = cubic_pos(1e6, 1e-9);
        assert!((s - 1e-15).abs() < 1e-28, "{s}");
        // (s − 1)(s − 2)(s + 3) = s³ − 7s + 6: three real roots by the trigonometric form.
        let r = cubic_depressed(-7.0, 6.0);
        for (got, want) in r.iter().zip([-3.0, 1.0, 2.0]) {
            assert!((got - want).abs() < 1e-14, "{r:?}");
        }
        // One real root: s³ + 3s − 4 = 0 at s = 1.
        let r = cubic_depressed(3.0, -4.0);
        assert!((r[0] - 1.0).abs() < 1e-15 && r[1].is_nan());
    }

    #[test]
    fn newton_bounded_is_safe_on_a_bad_derivative() {
        // x^(1/3) − 0.5 has an infinite slope at 0: the bracket keeps Newton inside.
        let f = |x: f64| (x.cbrt() - 0.5, 1.0 / (3.0 * x.cbrt().powi(2)).max(1e-300));
        let x = newton_bounded(0.0, 1.0, 1.0, 0.0, f);
        assert!((x - 0.125).abs() < 1e-15, "{x}");
        let (x, fx) = fit_down(x, 0.0, 0.5, |x| x.cbrt());
        assert_eq!(fx, x.cbrt());
        assert!(x.cbrt() <= 0.5);
        assert!((bisect(0.0, 1.0, |x| x * x <= 0.25) - 0.5).abs() < 1e-15);
        // The same crossing by regula falsi, from either side, within the tolerance.
        let x = falsi(0.0, 1.0, |x| x * x - 0.25);
        assert!(x * x <= 0.25 && (x - 0.5).abs() <= ROOT_TOL, "{x}");
        let x = falsi(1.0, 0.0, |x| 0.25 - x * x);
        assert!(0.25 - x * x <= 0.0 && (x - 0.5).abs() <= ROOT_TOL, "{x}");
        // A crossing where g on one side is rounding noise (the secant points at that end):
        // closed within the tolerance, not by bisection to adjacent floats (54 steps here).
        let calls = std::cell::Cell::new(0);
        let noisy = |x: f64| {
            calls.set(calls.get() + 1);
            if x <= 0.3 {
                (x - 0.3) * 1e-3
            } else {
                1e-30
            }
        };
        // From a guess at the crossing to rounding: two evaluations close it; a far one does not.
        let g = |x: f64| x * x - 0.25;
        for guess in [0.5 * (1.0 - 1e-15), 0.5, 0.5 * (1.0 + 1e-15)] {
            let x = crossing_near(guess, 0.0, 1.0, g).unwrap();
            assert!(g(x) <= 0.0 && 0.5 - x <= ROOT_TOL, "{x}");
        }
        assert_eq!(crossing_near(0.49, 0.0, 1.0, g), None);
        assert_eq!(crossing_near(0.5, 0.6, 1.0, g), None);
        let x = falsi(0.0, 1.0, noisy);
        assert!(x <= 0.3 && 0.3 - x <= ROOT_TOL, "{x}");
        assert!(calls.get() < 50, "{} steps", calls.get());
        // The other way round: the crossing at the good end, where g is rounding noise and
        // grows as a square root past it (a block whose ramp between its ends just fits): one
        // step beside that end closes it, where bisecting towards it took 35 to 40.
        calls.set(0);
        let root_like = |x: f64| {
            calls.set(calls.get() + 1);
            if x <= 0.3 {
                -1e-19
            } else {
                (x - 0.3).sqrt()
            }
        };
        let x = falsi(0.3, 0.35, root_like);
        assert_eq!(x, 0.3);
        assert!(calls.get() <= 3, "{} steps", calls.get());
    }
}
