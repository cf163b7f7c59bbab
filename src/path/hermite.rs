//! Quintic Hermite curve: the G2 transition of the `smooth` corner mode and the spline span
//! through smooth micro-segment vertices. It matches position, first and second derivative at
//! both ends, so joining it to lines, arcs and other spans keeps the axis acceleration continuous.
//! With the seed-004 boundary data (lines on both sides, zero curvature, λ = 2L) it is exactly
//! the transition of eq. 45–52.
//!
//! The curve is parameterised by u ∈ [0, λ] with |dp/du| = 1 at both ends (λ ≈ arc length),
//! and evaluated in u: the planner runs the feed law in u and the chain rule uses p', p'', p'''
//! w.r.t. u, so no arc-length inversion is needed and the derivative bounds are polynomial bounds.

use super::budget::raise_bounds;
use super::tolerance::{BOUND_ROUNDING, END_CHECK, MAX_TERM};
use crate::geometry::{add, norm, scale, sub, Geo};
use crate::Vec3;
use serde::{Deserialize, Serialize};

/// Sub-intervals of the Taylor bound (guaranteed for any number; more is tighter).
pub(super) const BOUND_PIECES: usize = 8;
/// Sub-intervals of the parameter speed's bound.
const SPEED_PIECES: usize = 8;
/// C(n, k) for n, k ≤ 8 (whole numbers, exact), of the Taylor coefficients of |p'|² (degree 8).
const BINOMIAL: [[f64; 9]; 9] = {
    let mut c = [[0.0; 9]; 9];
    let mut n = 0;
    while n < 9 {
        c[n][0] = 1.0;
        let mut k = 1;
        while k <= n {
            c[n][k] = c[n - 1][k - 1] + c[n - 1][k];
            k += 1;
        }
        n += 1;
    }
    c
};
/// Relative margin of `Unbounded::speed_ceiling` over the speed bound: far above the rounding of
/// either (`BOUND_ROUNDING` and a few hundred roundings of 2⁻⁵³).
const SPEED_CEILING_MARGIN: f64 = 1e-9;

/// p(u) = start + Σ_{k=1..5} c_k·u^k for u ∈ [0, lambda]; p(lambda) is `end` exactly.
/// Restored from its coefficients (`Coefficients`); the speed bound is derived again then.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(from = "Coefficients")]
pub struct Hermite {
    pub start: Vec3,
    pub end: Vec3,
    pub lambda: f64,
    /// Power coefficients in u, c[0] for u¹ … c[4] for u⁵.
    c: [Vec3; 5],
    /// `speed_bound`, computed once: the transition search, the deviation check, the source
    /// map and the planner each ask for it.
    #[serde(skip_serializing)]
    speed: f64,
}

/// A curve as it is saved: the fields of `Hermite` without the derived speed bound.
#[derive(Deserialize)]
struct Coefficients {
    start: Vec3,
    end: Vec3,
    lambda: f64,
    c: [Vec3; 5],
}

impl From<Coefficients> for Hermite {
    fn from(k: Coefficients) -> Hermite {
        Hermite::with_coefficients(k.start, k.end, k.lambda, k.c)
    }
}

/// A curve as `Hermite::new` builds it, before its speed bound: its points and derivatives only.
/// The fit checks a span's chords first, and the curves they reject need no bound; the corner
/// search needs it only where it may cap a cut's speed (`chain::Own::of_shape`).
pub(super) struct Unbounded(Hermite);

impl Unbounded {
    pub(super) fn length(&self) -> f64 {
        self.0.length()
    }

    pub(super) fn jet(&self, u: f64) -> Jet {
        self.0.jet(u)
    }

    /// The curve with its speed bound (`Hermite::speed_bound`).
    pub(super) fn bounded(&self) -> Hermite {
        self.bounded_with(None)
    }

    /// `bounded`, with the speed bound where it was worked out already (`speed_bound`).
    pub(super) fn bounded_with(&self, speed: Option<f64>) -> Hermite {
        let mut h = self.0;
        h.speed = speed.unwrap_or_else(|| h.speed_bound_of_coefficients());
        h
    }

    /// `Hermite::speed_bound` of the curve.
    pub(super) fn speed_bound(&self) -> f64 {
        self.0.speed_bound_of_coefficients()
    }

    /// `Hermite::cells_into` (the cells take no speed bound).
    pub(super) fn cells_into(&self, out: &mut [[Vec3; 3]; BOUND_PIECES]) {
        self.0.cells_into(out);
    }

    /// `Hermite::derivative_bounds`.
    pub(super) fn derivative_bounds(&self) -> [Vec3; 3] {
        self.0.derivative_bounds()
    }

    /// A bound of the speed bound from above, without its Taylor sums: with p' = Σ_k a_k·u^k,
    /// each piece's sum is at most Σ_n |q_n|·(m + r)^n (the binomial theorem), m + r ≤ λ, and
    /// |q_n| ≤ Σ_{k+l=n} Σ_i |a_k,i|·|a_l,i|: so the bound's square is at most
    /// Σ_i (Σ_k |a_k,i|·λ^k)², up to rounding (`SPEED_CEILING_MARGIN`).
    pub(super) fn speed_ceiling(&self) -> f64 {
        let h = &self.0;
        let mut square = 0.0;
        for i in 0..3 {
            let (mut axis, mut lk) = (0.0, 1.0);
            for (k, c) in h.c.iter().enumerate() {
                axis += (k + 1) as f64 * c[i].abs() * lk;
                lk *= h.lambda;
            }
            square += axis * axis;
        }
        square.sqrt() * (1.0 + SPEED_CEILING_MARGIN)
    }
}

/// End data of a curve piece: point, first and second derivative w.r.t. its parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Jet {
    pub p: Vec3,
    pub d1: Vec3,
    pub d2: Vec3,
}

impl Hermite {
    /// The quintic with jet `a` at u = 0 and jet `b` at u = `lambda` (derivatives w.r.t. u).
    pub fn new(a: Jet, b: Jet, lambda: f64) -> Hermite {
        Hermite::unbounded(a, b, lambda).bounded()
    }

    /// `new` before its speed bound is computed.
    pub(super) fn unbounded(a: Jet, b: Jet, lambda: f64) -> Unbounded {
        let l = lambda;
        // In τ = u/λ: M = λ·p', A = λ²·p'' at both ends (standard quintic Hermite basis).
        let d = sub(b.p, a.p);
        let (m0, m1) = (scale(a.d1, l), scale(b.d1, l));
        let (a0, a1) = (scale(a.d2, l * l), scale(b.d2, l * l));
        let comb = |kd: f64, km0: f64, ka0: f64, ka1: f64, km1: f64| -> Vec3 {
            let mut r = [0.0; 3];
            for i in 0..3 {
                r[i] = kd * d[i] + km0 * m0[i] + ka0 * a0[i] + ka1 * a1[i] + km1 * m1[i];
            }
            r
        };
        let t3 = comb(10.0, -6.0, -1.5, 0.5, -4.0);
        let t4 = comb(-15.0, 8.0, 1.5, -1.0, 7.0);
        let t5 = comb(6.0, -3.0, -0.5, 0.5, -3.0);
        let tau = [m0, scale(a0, 0.5), t3, t4, t5];
        let mut c = [[0.0; 3]; 5];
        let mut lk = 1.0;
        for k in 0..5 {
            lk *= l;
            c[k] = scale(tau[k], 1.0 / lk);
        }
        Hermite::unbounded_with(a.p, b.p, lambda, c)
    }

    fn with_coefficients(start: Vec3, end: Vec3, lambda: f64, c: [Vec3; 5]) -> Hermite {
        Hermite::unbounded_with(start, end, lambda, c).bounded()
    }

    fn unbounded_with(start: Vec3, end: Vec3, lambda: f64, c: [Vec3; 5]) -> Unbounded {
        Unbounded(Hermite {
            start,
            end,
            lambda,
            c,
            speed: f64::NAN,
        })
    }

    pub fn length(&self) -> f64 {
        self.lambda
    }

    /// A restored curve as `new` builds it: each power term c_k·λ^k a sum of the chord and the
    /// end derivatives scaled by λ (bounded by a million times the larger of λ and the chord),
    /// and the terms adding up to the chord (p(λ) is the end point).
    pub fn check_state(&self) -> Result<(), String> {
        let d = sub(self.end, self.start);
        let scale = self.lambda.max(norm(d));
        let (mut lk, mut sum) = (1.0, [0.0; 3]);
        for c in &self.c {
            lk *= self.lambda;
            for i in 0..3 {
                let term = c[i] * lk;
                if term.is_nan() || term.abs() > MAX_TERM * scale {
                    return Err(format!(
                        "a curve's power term {term:e} for a length of {scale:e} m"
                    ));
                }
                sum[i] += term;
            }
        }
        if norm(sub(sum, d)) > END_CHECK * scale {
            return Err("a curve does not end at its end point".into());
        }
        Ok(())
    }

    /// p − start and its first three derivatives at u.
    fn poly(&self, u: f64) -> [Vec3; 4] {
        let c = &self.c;
        let mut out = [[0.0; 3]; 4];
        for i in 0..3 {
            let (c1, c2, c3, c4, c5) = (c[0][i], c[1][i], c[2][i], c[3][i], c[4][i]);
            out[0][i] = u * (c1 + u * (c2 + u * (c3 + u * (c4 + u * c5))));
            out[1][i] = c1 + u * (2.0 * c2 + u * (3.0 * c3 + u * (4.0 * c4 + u * 5.0 * c5)));
            out[2][i] = 2.0 * c2 + u * (6.0 * c3 + u * (12.0 * c4 + u * 20.0 * c5));
            out[3][i] = 6.0 * c3 + u * (24.0 * c4 + u * 60.0 * c5);
        }
        out
    }

    /// The point at u alone (as `eval` gives it, without the derivatives: the tolerance checks
    /// sample points, and take a sample's derivative only where they need it, `tangent`).
    pub fn point(&self, u: f64) -> Vec3 {
        let u = u.clamp(0.0, self.lambda);
        if u >= self.lambda {
            return self.end;
        }
        let c = &self.c;
        let p = std::array::from_fn(|i| {
            let (c1, c2, c3, c4, c5) = (c[0][i], c[1][i], c[2][i], c[3][i], c[4][i]);
            u * (c1 + u * (c2 + u * (c3 + u * (c4 + u * c5))))
        });
        add(self.start, p)
    }

    /// The first derivative at u, as `eval` gives it (the tolerance checks need it only where a
    /// sample's distance is near the tolerance; `point` gives the point).
    pub fn tangent(&self, u: f64) -> Vec3 {
        let u = u.clamp(0.0, self.lambda);
        let c = &self.c;
        std::array::from_fn(|i| {
            let (c1, c2, c3, c4, c5) = (c[0][i], c[1][i], c[2][i], c[3][i], c[4][i]);
            c1 + u * (2.0 * c2 + u * (3.0 * c3 + u * (4.0 * c4 + u * 5.0 * c5)))
        })
    }

    /// Point and derivatives w.r.t. u (clamped to [0, λ]; the end point is exact).
    pub fn eval(&self, u: f64) -> Geo {
        let u = u.clamp(0.0, self.lambda);
        let [p, d1, d2, d3] = self.poly(u);
        Geo {
            p: if u >= self.lambda {
                self.end
            } else {
                add(self.start, p)
            },
            d1,
            d2,
            d3,
        }
    }

    pub fn jet(&self, u: f64) -> Jet {
        let g = self.eval(u);
        Jet {
            p: g.p,
            d1: g.d1,
            d2: g.d2,
        }
    }

    /// Guaranteed bounds per axis of |p'|, |p''|, |p'''| over [0, λ] (the largest of `cells`).
    pub fn derivative_bounds(&self) -> [Vec3; 3] {
        let mut b = [[0.0f64; 3]; 3];
        self.cells(|cell| raise_bounds(&mut b, &cell));
        b
    }

    /// The same bounds on each of `BOUND_PIECES` sub-intervals [m − r, m + r]: the Taylor
    /// expansion of a polynomial is exact, so |q^(n)(m + t)| ≤ Σ_k |q^(n+k)(m)|·r^k/k! (no
    /// sampling; rounding is below 1e-15 relative). Per sub-interval, the bounds of p' and p''
    /// hold at the same points, which `curve_limits` uses.
    pub fn cells(&self, mut take: impl FnMut([Vec3; 3])) {
        let r = 0.5 * self.lambda / BOUND_PIECES as f64;
        for piece in 0..BOUND_PIECES {
            let m = (2 * piece + 1) as f64 * r;
            let mut b = [[0.0f64; 3]; 3];
            for i in 0..3 {
                // q^(n)(m) for n = 1..5.
                let c: [f64; 5] = std::array::from_fn(|k| self.c[k][i]);
                let q = [
                    c[0] + m * (2.0 * c[1] + m * (3.0 * c[2] + m * (4.0 * c[3] + m * 5.0 * c[4]))),
                    2.0 * c[1] + m * (6.0 * c[2] + m * (12.0 * c[3] + m * 20.0 * c[4])),
                    6.0 * c[2] + m * (24.0 * c[3] + m * 60.0 * c[4]),
                    24.0 * c[3] + m * 120.0 * c[4],
                    120.0 * c[4],
                ];
                for (n, bound) in b.iter_mut().enumerate() {
                    let mut sum = 0.0;
                    let mut rk = 1.0;
                    for k in 0..(5 - n) {
                        sum += q[n + k].abs() * rk;
                        rk *= r / (k + 1) as f64;
                    }
                    // Relative guard for the rounding of the sums above.
                    bound[i] = sum * (1.0 + BOUND_ROUNDING);
                }
            }
            take(b);
        }
    }

    /// `cells` into one array (no list to grow: a junction's search bounds many transitions),
    /// the caller's: a returned array was copied out.
    pub fn cells_into(&self, out: &mut [[Vec3; 3]; BOUND_PIECES]) {
        let mut k = 0;
        self.cells(|c| {
            out[k] = c;
            k += 1;
        });
    }

    /// Guaranteed bound of the parameter speed |p'| over [0, λ]: the Taylor bound, as above, of
    /// the scalar polynomial |p'(u)|² (degree 8) on `SPEED_PIECES` sub-intervals. Squared, the
    /// first-order term is 2·p'·p'', nearly zero where the speed is nearly 1 (p'' is then nearly
    /// normal to p'), so the bound is tight where the vector bound is not.
    pub fn speed_bound(&self) -> f64 {
        self.speed
    }

    fn speed_bound_of_coefficients(&self) -> f64 {
        // p'(u) = Σ_k a_k·u^k, k = 0…4, and |p'|² = Σ_n q_n·u^n, n = 0…8.
        let a: [Vec3; 5] = std::array::from_fn(|k| scale(self.c[k], (k + 1) as f64));
        let mut q = [0.0f64; 9];
        for (k, ak) in a.iter().enumerate() {
            for (l, al) in a.iter().enumerate() {
                q[k + l] += ak[0] * al[0] + ak[1] * al[1] + ak[2] * al[2];
            }
        }
        let r = 0.5 * self.lambda / SPEED_PIECES as f64;
        let mut bound: f64 = 0.0;
        for piece in 0..SPEED_PIECES {
            let m = (2 * piece + 1) as f64 * r;
            // Taylor coefficients at m: q^(k)(m)/k! = Σ_{n ≥ k} C(n, k)·q_n·m^(n−k), the powers of
            // m by repeated products (the same for every k).
            let mut mp = [1.0f64; 9];
            for j in 1..9 {
                mp[j] = mp[j - 1] * m;
            }
            let mut sum = 0.0;
            let mut rk = 1.0;
            for k in 0..9 {
                let mut t = 0.0;
                for n in k..9 {
                    t += BINOMIAL[n][k] * q[n] * mp[n - k];
                }
                sum += t.abs() * rk;
                rk *= r;
            }
            bound = bound.max(sum);
        }
        (bound * (1.0 + BOUND_ROUNDING)).sqrt()
    }

    /// Bound of |p''| over [0, λ]: per axis, the sum of the second derivative's terms at their
    /// largest (u = λ), with the rounding allowance of the other bounds.
    pub fn curvature_bound(&self) -> f64 {
        let mut b = [0.0f64; 3];
        for (i, bi) in b.iter_mut().enumerate() {
            let mut lk = 1.0;
            for k in 2..=5 {
                *bi += (k * (k - 1)) as f64 * self.c[k - 1][i].abs() * lk;
                lk *= self.lambda;
            }
        }
        norm(b) * (1.0 + BOUND_ROUNDING)
    }

    /// Bézier control points (τ-form): the curve lies in their convex hull.
    pub fn control_points(&self) -> [Vec3; 6] {
        bezier(&self.jet(0.0), &self.jet(self.lambda), self.lambda)
    }
}

/// Bézier control points of the quintic Hermite from jet `a` to jet `b` over a parameter range
/// of length `l` (the curve, or any part of it given its end jets, lies in their hull).
pub fn bezier(a: &Jet, b: &Jet, l: f64) -> [Vec3; 6] {
    let (m0, m1) = (scale(a.d1, l), scale(b.d1, l));
    let (a0, a1) = (scale(a.d2, l * l), scale(b.d2, l * l));
    [
        a.p,
        add(a.p, scale(m0, 0.2)),
        add(add(a.p, scale(m0, 0.4)), scale(a0, 0.05)),
        add(sub(b.p, scale(m1, 0.4)), scale(a1, 0.05)),
        sub(b.p, scale(m1, 0.2)),
        b.p,
    ]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::norm;
    use crate::path::Blend;

    use crate::si::MM;

    fn line_jet(p: Vec3, d: Vec3) -> Jet {
        Jet {
            p,
            d1: d,
            d2: [0.0; 3],
        }
    }

    #[test]
    fn seed004_transition_is_the_special_case() {
        // Lines on both sides, zero curvature, λ = 2L: the curve of eq. 45–52 (blend.rs).
        let th = 70f64.to_radians();
        let (d_in, d_out) = ([1.0, 0.0, 0.0], [th.cos(), th.sin(), 0.0]);
        let blend = Blend::new([0.0; 3], d_in, d_out, 0.3 * MM);
        let h = Hermite::new(
            line_jet(blend.start(), d_in),
            line_jet(blend.end(), d_out),
            0.6 * MM,
        );
        // Same apex (eq. 52) at τ = ½.
        assert!(norm(sub(h.eval(0.3 * MM).p, blend.apex())) < 1e-18);
        assert_eq!(h.eval(h.length()).p, blend.end());
    }

    #[test]
    fn end_jets_are_met() {
        let a = Jet {
            p: [0.0, 0.0, 0.0],
            d1: [0.6, 0.8, 0.0],
            d2: [-80.0, 60.0, 5.0],
        };
        let b = Jet {
            p: [1e-3, 2e-3, 1e-4],
            d1: [0.0, 1.0, 0.0],
            d2: [-100.0, 0.0, 0.0],
        };
        let h = Hermite::new(a, b, 2.5e-3);
        for (want, got) in [(a, h.jet(0.0)), (b, h.jet(h.length()))] {
            assert!(norm(sub(want.p, got.p)) < 1e-18);
            assert!(norm(sub(want.d1, got.d1)) < 1e-12);
            assert!(norm(sub(want.d2, got.d2)) < 1e-8);
        }
    }

    #[test]
    fn bounds_hold_and_are_tight() {
        // Against a dense evaluation: never below it, at most 25 % above it on this curve.
        let a = Jet {
            p: [0.0; 3],
            d1: [1.0, 0.0, 0.0],
            d2: [0.0, 30.0, 0.0],
        };
        let b = Jet {
            p: [1e-3, 1e-3, 0.0],
            d1: [0.0, 1.0, 0.0],
            d2: [-20.0, 0.0, 0.0],
        };
        let h = Hermite::new(a, b, 1.6e-3);
        let bounds = h.derivative_bounds();
        let mut seen = [[0.0f64; 3]; 3];
        for k in 0..=20_000 {
            let g = h.eval(h.length() * k as f64 / 20_000.0);
            for (s, d) in seen.iter_mut().zip([g.d1, g.d2, g.d3]) {
                for i in 0..3 {
                    s[i] = s[i].max(d[i].abs());
                }
            }
        }
        for n in 0..3 {
            for i in 0..2 {
                assert!(bounds[n][i] >= seen[n][i], "n {n} axis {i}");
                assert!(
                    bounds[n][i] <= 1.25 * seen[n][i] + 1e-9,
                    "n {n} axis {i}: {} vs {}",
                    bounds[n][i],
                    seen[n][i]
                );
            }
        }
    }

    /// A transition through a corner of 90° with curvature at both ends.
    fn corner_of_90_degrees() -> Hermite {
        Hermite::new(
            Jet {
                p: [0.0; 3],
                d1: [1.0, 0.0, 0.0],
                d2: [0.0, 30.0, 0.0],
            },
            Jet {
                p: [1e-3, 1e-3, 0.0],
                d1: [0.0, 1.0, 0.0],
                d2: [-20.0, 0.0, 0.0],
            },
            1.6e-3,
        )
    }

    /// Saved without its speed bound (the state format is the coefficients), restored with the
    /// same bound bit for bit: the restored curve equals the saved one.
    #[test]
    fn restored_curve_has_its_speed_bound() {
        let h = corner_of_90_degrees();
        let json = serde_json::to_string(&h).expect("a curve serializes");
        assert!(!json.contains("speed"), "{json}");
        let back: Hermite = serde_json::from_str(&json).expect("and reads back");
        assert_eq!(back, h);
        assert_eq!(
            back.speed_bound().to_bits(),
            h.speed_bound_of_coefficients().to_bits()
        );
        assert!(h.speed_bound() > 1.0);
        let bytes = postcard::to_stdvec(&h).expect("postcard too");
        assert_eq!(postcard::from_bytes::<Hermite>(&bytes).expect("reads back"), h);
    }

    /// The speed bound is never below the sampled |p'| and close above it: on a corner of 90°
    /// and on a nearly straight transition (where a bound of the vector |p'| overshoots by the
    /// curvature term).
    #[test]
    fn speed_bound_holds_and_is_tight() {
        let corner = corner_of_90_degrees();
        let gentle = Hermite::new(
            line_jet([0.0; 3], [1.0, 0.0, 0.0]),
            Jet {
                p: [1e-3, 2e-6, 0.0],
                d1: [0.999_998, 0.002, 0.0],
                d2: [0.0, 50.0, 0.0],
            },
            1e-3,
        );
        for (h, slack) in [(corner, 1e-2), (gentle, 1e-5)] {
            let seen = (0..=20_000)
                .map(|k| norm(h.eval(h.length() * k as f64 / 20_000.0).d1))
                .fold(0.0, f64::max);
            let bound = h.speed_bound();
            assert!(
                bound >= seen && bound <= seen * (1.0 + slack),
                "{bound} vs {seen}"
            );
        }
    }

    #[test]
    fn control_points_reproduce_the_curve() {
        let a = Jet {
            p: [0.0; 3],
            d1: [1.0, 0.0, 0.0],
            d2: [0.0, 10.0, 0.0],
        };
        let b = Jet {
            p: [2e-3, 1e-4, 0.0],
            d1: [0.99, 0.1, 0.0],
            d2: [0.0, 5.0, 0.0],
        };
        let h = Hermite::new(a, b, 2e-3);
        let cp = h.control_points();
        // Bernstein form at τ = 0.3 equals the power form.
        let t: f64 = 0.3;
        let binom = [1.0, 5.0, 10.0, 10.0, 5.0, 1.0];
        let mut p = [0.0; 3];
        for k in 0..6 {
            let w = binom[k] * t.powi(k as i32) * (1.0 - t).powi(5 - k as i32);
            p = add(p, scale(cp[k], w));
        }
        assert!(norm(sub(p, h.eval(0.3 * h.length()).p)) < 1e-17);
    }
}
