//! Seed 004 §3: quintic corner transition between two lines (eq. 25–52), evaluated w.r.t. arc
//! length through a fixed Gauss–Legendre table and bounded Newton steps.
//!
//! With O the corner, u the unit vector from O back along the incoming line, v the unit vector
//! along the outgoing line and L = |OM| = |ON| (eq. 26), the boundary conditions 37–44 give
//! a2 = a5 = 0 (eq. 47, 50), T = 2L/V_In (eq. 51) and, in the normalised parameter τ = t/T,
//!   P(τ) = O + L·[u·(1 − 2τ + 2τ³ − τ⁴) + v·(2τ³ − τ⁴)],
//! which is eq. 45–49 written per vector; P(½) = Q = (3/16)·L·(u + v) (eq. 52). The geometry does
//! not depend on V_In; we traverse it at one path speed, so d/ds replaces d/dt.

use super::{add, dot, norm, scale, Geo};
use crate::Vec3;
use serde::{Deserialize, Serialize};

/// Panels of the arc-length table (≤ 32 so the array stays serde-friendly).
const PANELS: usize = 32;
/// 5-point Gauss–Legendre nodes and weights on [−1, 1].
const GL_X: [f64; 5] = [
    -0.906_179_845_938_664,
    -0.538_469_310_105_683_1,
    0.0,
    0.538_469_310_105_683_1,
    0.906_179_845_938_664,
];
const GL_W: [f64; 5] = [
    0.236_926_885_056_189_1,
    0.478_628_670_499_366_5,
    0.568_888_888_888_888_9,
    0.478_628_670_499_366_5,
    0.236_926_885_056_189_1,
];
/// Newton steps of the inverse s → τ (quadratic convergence from a panel-local guess).
const NEWTON_STEPS: usize = 8;

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
    /// Arc length of the transition.
    pub length: f64,
    /// Arc length at the end of each τ panel.
    table: [f64; PANELS],
}

impl Blend {
    /// Transition at corner O, incoming travel direction `d_in`, outgoing `d_out`, cutting
    /// `half` of each line.
    pub fn new(corner: Vec3, d_in: Vec3, d_out: Vec3, half: f64) -> Blend {
        let mut b = Blend {
            corner,
            u: scale(d_in, -1.0),
            v: d_out,
            half,
            length: 0.0,
            table: [0.0; PANELS],
        };
        let mut s = 0.0;
        for k in 0..PANELS {
            let (t0, t1) = (k as f64 / PANELS as f64, (k + 1) as f64 / PANELS as f64);
            s += b.integrate(t0, t1);
            b.table[k] = s;
        }
        b.length = s;
        b
    }

    /// L from the tolerance: |OQ| = (3/16)·L·|u + v| (eq. 52) set to `tolerance`; a Euclidean
    /// tolerance also bounds every axis, i.e. eq. 29–30 with tol_x = tol_y = tol_z.
    pub fn half_for_tolerance(d_in: Vec3, d_out: Vec3, tolerance: f64) -> f64 {
        let w = norm(add(scale(d_in, -1.0), d_out));
        16.0 * tolerance / (3.0 * w)
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

    /// P and its τ-derivatives up to the third.
    fn poly(&self, t: f64) -> [Vec3; 4] {
        let l = self.half;
        let (t2, t3) = (t * t, t * t * t);
        let a = 1.0 - 2.0 * t + 2.0 * t3 - t2 * t2;
        let b = 2.0 * t3 - t2 * t2;
        let a1 = -2.0 + 6.0 * t2 - 4.0 * t3;
        let b1 = 6.0 * t2 - 4.0 * t3;
        let w = add(self.u, self.v);
        let p = add(self.corner, scale(add(scale(self.u, a), scale(self.v, b)), l));
        let p1 = scale(add(scale(self.u, a1), scale(self.v, b1)), l);
        let p2 = scale(w, l * (12.0 * t - 12.0 * t2));
        let p3 = scale(w, l * (12.0 - 24.0 * t));
        [p, p1, p2, p3]
    }

    /// |dP/dτ|
    fn sigma(&self, t: f64) -> f64 {
        norm(self.poly(t)[1])
    }

    fn integrate(&self, t0: f64, t1: f64) -> f64 {
        let (m, h) = (0.5 * (t0 + t1), 0.5 * (t1 - t0));
        GL_X.iter()
            .zip(&GL_W)
            .map(|(x, w)| w * self.sigma(m + h * x))
            .sum::<f64>()
            * h
    }

    /// τ at arc length s (bounded work: panel lookup, then Newton on the panel's integral).
    pub fn parameter(&self, s: f64) -> f64 {
        if s <= 0.0 {
            return 0.0;
        }
        if s >= self.length {
            return 1.0;
        }
        let k = self.table.partition_point(|&c| c < s).min(PANELS - 1);
        let s0 = if k == 0 { 0.0 } else { self.table[k - 1] };
        let (t0, t1) = (k as f64 / PANELS as f64, (k + 1) as f64 / PANELS as f64);
        let mut t = t0 + (t1 - t0) * (s - s0) / (self.table[k] - s0);
        for _ in 0..NEWTON_STEPS {
            let f = s0 + self.integrate(t0, t) - s;
            let step = f / self.sigma(t);
            t = (t - step).clamp(t0, t1);
            if step.abs() < 1e-16 {
                break;
            }
        }
        t
    }

    /// Point and derivatives w.r.t. arc length: with σ = |P'|, T = P'/σ, σ' = T·P'',
    /// σ'' = (|P''|² + P'·P''' − σ'²)/σ: d2 = (P'' − Tσ')/σ², d3 = (P''' − Tσ'')/σ³ − 3σ'·d2/σ².
    pub fn eval(&self, s: f64) -> Geo {
        self.at_parameter(self.parameter(s))
    }

    /// Point and arc-length derivatives at τ.
    fn at_parameter(&self, t: f64) -> Geo {
        let [p, p1, p2, p3] = self.poly(t);
        let sig = norm(p1);
        let tan = scale(p1, 1.0 / sig);
        let sig1 = dot(tan, p2);
        let sig2 = (dot(p2, p2) + dot(p1, p3) - sig1 * sig1) / sig;
        let d2 = scale(add(p2, scale(tan, -sig1)), 1.0 / (sig * sig));
        let d3 = add(
            scale(add(p3, scale(tan, -sig2)), 1.0 / (sig * sig * sig)),
            scale(d2, -3.0 * sig1 / (sig * sig)),
        );
        Geo {
            p: if t >= 1.0 { self.end() } else { p },
            d1: tan,
            d2,
            d3,
        }
    }

    /// Upper bounds per axis of |d1_i|, |d2_i|, |d3_i| over the transition (dense sampling in τ,
    /// no inversion needed; the caller keeps a margin for what falls between samples).
    pub fn derivative_bounds(&self) -> [Vec3; 3] {
        const SAMPLES: usize = 256;
        let mut b = [[0.0f64; 3]; 3];
        for k in 0..=SAMPLES {
            let g = self.at_parameter(k as f64 / SAMPLES as f64);
            for (bound, d) in b.iter_mut().zip([g.d1, g.d2, g.d3]) {
                for (x, y) in bound.iter_mut().zip(d) {
                    *x = x.max(y.abs());
                }
            }
        }
        b
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::path::sub;

    const MM: f64 = 1e-3;

    fn corner_90() -> Blend {
        let d_in = [1.0, 0.0, 0.0];
        let d_out = [0.0, 1.0, 0.0];
        let half = Blend::half_for_tolerance(d_in, d_out, 0.01 * MM);
        Blend::new([10.0 * MM, 0.0, 0.0], d_in, d_out, half)
    }

    #[test]
    fn boundary_conditions_eq37_to_44() {
        let b = corner_90();
        // eq. 52: L = 16·|OQ|/(3·|u + v|) = 16·0.01/(3·√2) mm.
        assert!((b.half - 16.0 * 0.01 * MM / (3.0 * 2f64.sqrt())).abs() < 1e-18);
        assert!((norm(sub(b.apex(), b.corner)) - 0.01 * MM).abs() < 1e-18);
        let g0 = b.eval(0.0);
        let g1 = b.eval(b.length);
        // Tangent continuity with the lines, curvature zero at both ends (G2).
        assert!(norm(sub(g0.d1, [1.0, 0.0, 0.0])) < 1e-15);
        assert!(norm(sub(g1.d1, [0.0, 1.0, 0.0])) < 1e-15);
        assert!(norm(g0.d2) < 1e-9 && norm(g1.d2) < 1e-9);
        assert_eq!(g0.p, b.start());
        assert_eq!(g1.p, b.end());
        // Half way in τ is Q (eq. 39) and is half way in s by symmetry.
        let q = b.eval(b.length / 2.0).p;
        assert!(norm(sub(q, b.apex())) < 1e-15);
    }

    #[test]
    fn deviation_within_tolerance() {
        for deg in [10.0f64, 45.0, 90.0, 135.0, 170.0] {
            let th = deg.to_radians();
            let d_in = [1.0, 0.0, 0.0];
            let d_out = [th.cos(), th.sin(), 0.0];
            let tol = 0.02 * MM;
            let b = Blend::new([0.0; 3], d_in, d_out, Blend::half_for_tolerance(d_in, d_out, tol));
            let mut closest = f64::INFINITY;
            for k in 0..=2000 {
                let p = b.eval(b.length * k as f64 / 2000.0).p;
                closest = closest.min(norm(p));
            }
            assert!(closest <= tol * (1.0 + 1e-12), "{deg}: {closest}");
            assert!(closest >= 0.99 * tol, "{deg}: {closest}");
        }
    }

    #[test]
    fn arc_length_is_consistent() {
        // Successive samples: the chord between points ds apart is ds (up to curvature), d1 unit,
        // and d1/d2/d3 match finite differences.
        let b = corner_90();
        let n = 400;
        let ds = b.length / n as f64;
        for k in 1..n {
            let s = k as f64 * ds;
            let g = b.eval(s);
            assert!((norm(g.d1) - 1.0).abs() < 1e-14);
            let (a, c) = (b.eval(s - ds), b.eval(s + ds));
            // Chord of an arc of length 2ds: 2ds·(1 − κ²(2ds)²/24) — within 1e-9 m of 2ds here.
            let chord = norm(sub(c.p, a.p));
            let k2 = dot(g.d2, g.d2);
            let expect = 2.0 * ds * (1.0 - k2 * 4.0 * ds * ds / 24.0);
            assert!((chord - expect).abs() < 1e-12, "{chord} {expect}");
            let e = ds * 1e-2;
            let (a, c) = (b.eval(s - e), b.eval(s + e));
            let fd1 = scale(sub(c.p, a.p), 0.5 / e);
            assert!(norm(sub(fd1, g.d1)) < 1e-6);
            let fd2 = scale(sub(c.d1, a.d1), 0.5 / e);
            assert!(norm(sub(fd2, g.d2)) < 1e-4 * (1.0 + norm(g.d2)));
            let fd3 = scale(sub(c.d2, a.d2), 0.5 / e);
            assert!(norm(sub(fd3, g.d3)) < 1e-4 * (1.0 + norm(g.d3)));
        }
        // Total length against a fine trapezoid sum of |P'|.
        let m = 200_000;
        let mut sum = 0.0;
        for k in 0..m {
            let (t0, t1) = (k as f64 / m as f64, (k + 1) as f64 / m as f64);
            sum += 0.5 * (b.sigma(t0) + b.sigma(t1)) / m as f64;
        }
        assert!((sum - b.length).abs() < 1e-13);
    }

    #[test]
    fn inverse_arc_length_is_exact() {
        // s(τ(s)) against a fine Simpson integral of |P'|, on a gentle and on a sharp corner.
        let mut worst: f64 = 0.0;
        for deg in [20.0f64, 174.0] {
            let th = deg.to_radians();
            let d_out = [th.cos(), th.sin(), 0.0];
            let b = Blend::new([0.0; 3], [1.0, 0.0, 0.0], d_out, 0.05 * MM);
            for k in 1..40 {
                let s = b.length * k as f64 / 40.0;
                let t = b.parameter(s);
                let n = 20_000;
                let h = t / n as f64;
                let mut sum = b.sigma(0.0) + b.sigma(t);
                for i in 1..n {
                    sum += if i % 2 == 1 { 4.0 } else { 2.0 } * b.sigma(i as f64 * h);
                }
                let s_back = sum * h / 3.0;
                assert!((s_back - s).abs() < 1e-12, "{deg}° s {s}: {}", s_back - s);
                worst = worst.max((s_back - s).abs());
            }
        }
        println!("worst arc-length error {worst:e} m");
    }
}
