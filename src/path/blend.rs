//! Seed 004 §3: quintic corner transition between two lines (eq. 25–52), run as the paper runs it:
//! in time, at the entry speed V_In.
//!
//! With O the corner, u the unit vector from O back along the incoming line, v the unit vector
//! along the outgoing line and L = |OM| = |ON| (eq. 26), the boundary conditions 37–44 give
//! a2 = a5 = 0 (eq. 47, 50), T = 2L/V_In (eq. 51) and, in the normalised time τ = t/T,
//!   P(τ) = O + L·[u·(1 − 2τ + 2τ³ − τ⁴) + v·(2τ³ − τ⁴)],
//! which is eq. 45–49 written per vector; P(½) = Q = (3/16)·L·(u + v) (eq. 52). The segment's
//! parameter is s = 2L·τ ∈ [0, 2L]: passed at the constant parameter speed ṡ = V_In it takes
//! T = 2L/V_In and its axis motion is the paper's polynomial in time exactly (the path speed is
//! V_In at M and N and V_In·|v − u|/2 at Q: Table 2's "feed rate in the transition").

use crate::geometry::{add, norm, scale, Geo};
use crate::Vec3;
use serde::{Deserialize, Serialize};

/// The quintic corner transition (see the module comment).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Blend {
    /// Programmed corner point O.
    pub corner: Vec3,
    /// Unit vector from O back along the incoming line (direction of OA).
    pub u: Vec3,
    /// Unit vector from O along the outgoing line (direction of OB).
    pub v: Vec3,
    /// L = |OM| = |ON|: how much of each line the transition replaces.
    pub half: f64,
    /// Parameter length 2L: the distance V_In·T of eq. 51 (the arc length is a little less).
    pub length: f64,
}

impl Blend {
    /// Transition at corner O, incoming travel direction `d_in`, outgoing `d_out`, cutting
    /// `half` of each line.
    pub fn new(corner: Vec3, d_in: Vec3, d_out: Vec3, half: f64) -> Blend {
        Blend {
            corner,
            u: scale(d_in, -1.0),
            v: d_out,
            half,
            length: 2.0 * half,
        }
    }

    /// L from the axis tolerances (eq. 27–30, 52): Q lies on w = (u + v)/|u + v| with
    /// |OQ| = min_i tol/|w_i| (eq. 30, every axis given `tolerance`), and L = 16·|OQ|/(3·|u + v|).
    pub fn half_for_tolerance(d_in: Vec3, d_out: Vec3, tolerance: f64) -> f64 {
        let s = add(scale(d_in, -1.0), d_out);
        let w = norm(s);
        let widest = s.iter().fold(0.0f64, |m, x| m.max(x.abs())) / w;
        let oq = tolerance / widest;
        16.0 * oq / (3.0 * w)
    }

    /// OQ, the point reached half way (eq. 27, 52).
    pub fn apex(&self) -> Vec3 {
        add(self.corner, scale(add(self.u, self.v), 3.0 / 16.0 * self.half))
    }

    pub fn start(&self) -> Vec3 {
        add(self.corner, scale(self.u, self.half))
    }

    pub fn end(&self) -> Vec3 {
        add(self.corner, scale(self.v, self.half))
    }

    /// Point and derivatives w.r.t. s = 2L·τ (clamped to [0, 2L]).
    pub fn eval(&self, s: f64) -> Geo {
        let l = self.half;
        let t = (s / self.length).clamp(0.0, 1.0);
        let (t2, t3) = (t * t, t * t * t);
        let a = 1.0 - 2.0 * t + 2.0 * t3 - t2 * t2;
        let b = 2.0 * t3 - t2 * t2;
        // dτ/ds = 1/(2L): the τ-derivatives L·(…) scaled by (2L)^-k.
        let a1 = -2.0 + 6.0 * t2 - 4.0 * t3;
        let b1 = 6.0 * t2 - 4.0 * t3;
        let w = add(self.u, self.v);
        let p = add(self.corner, scale(add(scale(self.u, a), scale(self.v, b)), l));
        Geo {
            p: if t >= 1.0 { self.end() } else { p },
            d1: scale(add(scale(self.u, a1), scale(self.v, b1)), 0.5),
            d2: scale(w, (12.0 * t - 12.0 * t2) / (4.0 * l)),
            d3: scale(w, (12.0 - 24.0 * t) / (8.0 * l * l)),
        }
    }

    /// The largest |d1_i|, |d2_i|, |d3_i| over the transition, in closed form (exact maxima, so
    /// the speed of eq. 54–57 needs no margin): d1 = ((u + v)·b1 − 2u)/2 is linear in b1, which
    /// rises from 0 to 2, so its extremes are −u and v at the ends; d2 = (u + v)·3τ(1 − τ)/L is
    /// largest at τ = ½ (eq. 55), d3 = (u + v)·(3 − 6τ)/(2L²) at the ends (eq. 53).
    pub fn derivative_bounds(&self) -> [Vec3; 3] {
        let l = self.half;
        let w = |i: usize| (self.u[i] + self.v[i]).abs();
        [
            std::array::from_fn(|i| self.u[i].abs().max(self.v[i].abs())),
            std::array::from_fn(|i| 0.75 * w(i) / l),
            std::array::from_fn(|i| 1.5 * w(i) / (l * l)),
        ]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{dot, sub};

    use crate::si::MM;

    fn corner_90() -> Blend {
        let d_in = [1.0, 0.0, 0.0];
        let d_out = [0.0, 1.0, 0.0];
        let half = Blend::half_for_tolerance(d_in, d_out, 0.01 * MM);
        Blend::new([10.0 * MM, 0.0, 0.0], d_in, d_out, half)
    }

    #[test]
    fn boundary_conditions_eq37_to_44() {
        let b = corner_90();
        // eq. 30: w = (−1, 1)/√2, |OQ| = tol/(1/√2); eq. 52: L = 16·|OQ|/(3·√2) = 16·tol/3.
        assert!((b.half - 16.0 * 0.01 * MM / 3.0).abs() < 1e-18);
        let q = sub(b.apex(), b.corner);
        assert!((q[0].abs() - 0.01 * MM).abs() < 1e-18 && (q[1] - 0.01 * MM).abs() < 1e-18);
        let (g0, g1) = (b.eval(0.0), b.eval(b.length));
        // eq. 40–43: V(0) = −V_In·u, V(T) = V_In·v, A(0) = A(T) = 0.
        assert!(norm(sub(g0.d1, [1.0, 0.0, 0.0])) < 1e-15);
        assert!(norm(sub(g1.d1, [0.0, 1.0, 0.0])) < 1e-15);
        assert!(norm(g0.d2) == 0.0 && norm(g1.d2) == 0.0);
        assert_eq!(g0.p, b.start());
        assert_eq!(g1.p, b.end());
        // eq. 39 and 44: Q at T/2, where the jerk is zero.
        let mid = b.eval(b.length / 2.0);
        assert!(norm(sub(mid.p, b.apex())) < 1e-18);
        assert!(norm(mid.d3) == 0.0);
    }

    #[test]
    fn the_time_law_is_eq45_to_51() {
        // A 3-D corner: the coefficients of eq. 48–49 and the time of eq. 51, per axis, against
        // the derivatives of the segment run at the constant parameter speed V_In.
        let d_in = [0.6, 0.8, 0.0];
        let out = [0.3, -0.5, 0.4];
        let d_out = scale(out, 1.0 / norm(out));
        let b = Blend::new([0.0; 3], d_in, d_out, 0.04 * MM);
        let v_in: f64 = 0.05;
        let oq = 3.0 / 16.0 * b.half * norm(add(b.u, b.v));
        let (g0, g1) = (b.eval(0.0), b.eval(b.length));
        for i in 0..3 {
            let s = b.u[i] + b.v[i];
            let q = oq * s / norm(add(b.u, b.v));
            let a3 = 9.0 * s.powi(3) * v_in.powi(3) / (1024.0 * q * q);
            let a4 = -27.0 * s.powi(4) * v_in.powi(4) / (65536.0 * q.powi(3));
            let t = 32.0 * q / (3.0 * v_in * s);
            assert!((t - b.length / v_in).abs() < 1e-15, "eq. 51");
            // Jerk 6·a3 + 24·a4·t at both ends.
            assert!((g0.d3[i] * v_in.powi(3) - 6.0 * a3).abs() < 1e-9 * a3.abs());
            let j_end = 6.0 * a3 + 24.0 * a4 * t;
            assert!((g1.d3[i] * v_in.powi(3) - j_end).abs() < 1e-9 * a3.abs());
        }
    }

    #[test]
    fn every_axis_within_its_tolerance() {
        // eq. 29–30: the apex is at most tol from O on every axis, and at tol on the widest;
        // every point of the transition (on a fine grid) lies between O and the chord MN, so no
        // axis deviates beyond the apex.
        for deg in [10.0f64, 45.0, 90.0, 135.0, 170.0] {
            let th = deg.to_radians();
            let d_in = [0.8, 0.0, 0.6];
            let d_out = [th.cos() * 0.8, th.sin(), th.cos() * 0.6];
            let d_out = scale(d_out, 1.0 / norm(d_out));
            let tol = 0.02 * MM;
            let b = Blend::new([0.0; 3], d_in, d_out, Blend::half_for_tolerance(d_in, d_out, tol));
            let q = b.apex();
            let widest = q.iter().fold(0.0f64, |m, x| m.max(x.abs()));
            assert!((widest - tol).abs() < 1e-15, "{deg}: {q:?}");
            let closest = (0..=2000)
                .map(|k| norm(b.eval(b.length * k as f64 / 2000.0).p))
                .fold(f64::INFINITY, f64::min);
            assert!((closest - norm(q)).abs() < 1e-15, "{deg}: {closest}");
        }
    }

    #[test]
    fn derivatives_and_bounds_are_consistent() {
        // d1/d2/d3 against finite differences in s, and the closed-form bounds attained.
        let b = corner_90();
        let n = 400;
        let ds = b.length / n as f64;
        let bounds = b.derivative_bounds();
        let mut seen = [[0.0f64; 3]; 3];
        for k in 0..=n {
            let s = k as f64 * ds;
            let g = b.eval(s);
            for (m, d) in seen.iter_mut().zip([g.d1, g.d2, g.d3]) {
                for i in 0..3 {
                    m[i] = m[i].max(d[i].abs());
                }
            }
            if k == 0 || k == n {
                continue;
            }
            let e = ds * 1e-2;
            let (a, c) = (b.eval(s - e), b.eval(s + e));
            let fd1 = scale(sub(c.p, a.p), 0.5 / e);
            assert!(norm(sub(fd1, g.d1)) < 1e-6);
            let fd2 = scale(sub(c.d1, a.d1), 0.5 / e);
            assert!(norm(sub(fd2, g.d2)) < 1e-6 * norm(bounds[1]));
            let fd3 = scale(sub(c.d2, a.d2), 0.5 / e);
            assert!(norm(sub(fd3, g.d3)) < 1e-6 * norm(bounds[2]));
        }
        for (m, bd) in seen.iter().zip(bounds) {
            for i in 0..3 {
                assert!(
                    m[i] <= bd[i] * (1.0 + 1e-12) && m[i] >= bd[i] * (1.0 - 1e-12),
                    "{m:?} {bd:?}"
                );
            }
        }
        // The path speed falls to |v − u|/2 of the entry speed at Q (Table 2's transition feed).
        let mid = b.eval(b.length / 2.0);
        assert!((norm(mid.d1) - norm(sub(b.v, b.u)) / 2.0).abs() < 1e-15);
        assert!(dot(mid.d1, b.v) > 0.0);
    }
}
