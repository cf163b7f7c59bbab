//! Rational B-spline curves in the plane (LinuxCNC G-code reference, "G5.2 G5.3 NURBS Block";
//! G5 and G5.1 are the single-span cases, a cubic and a quadratic Bézier curve). Order k
//! (degree k − 1), control points P_i with weights w_i, and LinuxCNC's clamped uniform knot
//! vector: k zeros, 1 … n − k + 1, k times n − k + 2 (n + 1 control points), so the curve starts
//! at the first control point and ends at the last. Evaluation by de Boor's algorithm on the
//! homogeneous points (w·x, w·y, w); the derivative from the derived B-spline of order k − 1
//! and the quotient rule.

/// Largest order evaluated.
pub const MAX_ORDER: usize = 16;

/// A NURBS curve: control points (x, y, w) and order k (2 ≤ k ≤ number of points, MAX_ORDER).
#[derive(Clone, Debug, PartialEq)]
pub struct Nurbs {
    /// Homogeneous control points (w·x, w·y, w).
    h: Vec<[f64; 3]>,
    k: usize,
    knots: Vec<f64>,
}

impl Nurbs {
    /// The curve of `points` (x, y, weight > 0) of order `k`; None unless 2 ≤ k ≤ points.
    pub fn new(points: &[[f64; 3]], k: usize) -> Option<Nurbs> {
        let bad_weight = points.iter().any(|p| p[2] <= 0.0 || !p[2].is_finite());
        if !(2..=MAX_ORDER).contains(&k) || points.len() < k || bad_weight {
            return None;
        }
        let n = points.len() - 1;
        // LinuxCNC's knot_vector_creator: i < k → 0, k ≤ i ≤ n → i − k + 1, else n − k + 2.
        let knots = (0..=n + k)
            .map(|i| {
                if i < k {
                    0.0
                } else if i <= n {
                    (i + 1 - k) as f64
                } else {
                    (n + 2 - k) as f64
                }
            })
            .collect();
        let h = points.iter().map(|p| [p[0] * p[2], p[1] * p[2], p[2]]).collect();
        Some(Nurbs { h, k, knots })
    }

    /// The parameter range [0, u_max].
    pub fn u_max(&self) -> f64 {
        self.knots[self.knots.len() - 1]
    }

    /// The distinct interior knots (span boundaries), in order.
    pub fn breaks(&self) -> Vec<f64> {
        let mut out: Vec<f64> = Vec::new();
        for &t in &self.knots {
            if t > 0.0 && t < self.u_max() && out.last() != Some(&t) {
                out.push(t);
            }
        }
        out
    }

    /// The knot span index s with t_s ≤ u < t_{s+1} (the last non-empty span at u_max).
    fn span(&self, u: f64) -> usize {
        let n = self.h.len() - 1;
        let u = u.clamp(0.0, self.u_max());
        let mut s = self.k - 1;
        while s < n && self.knots[s + 1] <= u {
            s += 1;
        }
        s
    }

    /// De Boor: the homogeneous point of order `k` (≤ MAX_ORDER) with control points `c` and
    /// knots `t` at `u` in span `s` (c[j] for j in s + 1 − k ..= s).
    fn de_boor(c: impl Fn(usize) -> [f64; 3], t: &[f64], k: usize, s: usize, u: f64) -> [f64; 3] {
        let mut d = [[0.0; 3]; MAX_ORDER];
        for (j, dj) in d.iter_mut().enumerate().take(k) {
            *dj = c(j + s + 1 - k);
        }
        for r in 1..k {
            for j in (r..k).rev() {
                let i = j + s + 1 - k;
                let den = t[i + k - r] - t[i];
                let a = if den > 0.0 { (u - t[i]) / den } else { 0.0 };
                let (lo, hi) = (d[j - 1], d[j]);
                d[j] = std::array::from_fn(|m| (1.0 - a) * lo[m] + a * hi[m]);
            }
        }
        d[k - 1]
    }

    fn homogeneous(&self, u: f64) -> [f64; 3] {
        let u = u.clamp(0.0, self.u_max());
        Self::de_boor(|i| self.h[i], &self.knots, self.k, self.span(u), u)
    }

    /// The point at parameter `u`.
    pub fn point(&self, u: f64) -> [f64; 2] {
        let p = self.homogeneous(u);
        [p[0] / p[2], p[1] / p[2]]
    }

    /// The derivative dC/du at `u` (right-hand at interior knots).
    pub fn derivative(&self, u: f64) -> [f64; 2] {
        let k = self.k;
        // Derived control points (k − 1)(Q_{i+1} − Q_i)/(t_{i+k} − t_{i+1}), order k − 1, knots
        // t_1 … t_{m−1}; only the k − 1 of the span are formed.
        let derived = |i: usize| -> [f64; 3] {
            let den = self.knots[i + k] - self.knots[i + 1];
            let f = if den > 0.0 { (k - 1) as f64 / den } else { 0.0 };
            std::array::from_fn(|m| f * (self.h[i + 1][m] - self.h[i][m]))
        };
        let s = self.span(u);
        let u = u.clamp(0.0, self.u_max());
        let d = Self::de_boor(derived, &self.knots[1..self.knots.len() - 1], k - 1, s - 1, u);
        let a = self.homogeneous(u);
        let w = a[2];
        [(d[0] - d[2] * a[0] / w) / w, (d[1] - d[2] * a[1] / w) / w]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A cubic Bézier curve in Bernstein form (the closed form G5 describes).
    fn bezier(p: &[[f64; 2]; 4], t: f64) -> [f64; 2] {
        let s = 1.0 - t;
        let b = [s * s * s, 3.0 * s * s * t, 3.0 * s * t * t, t * t * t];
        [0, 1].map(|m| (0..4).map(|i| b[i] * p[i][m]).sum())
    }

    #[test]
    fn single_span_is_the_bezier_curve_and_its_derivative() {
        let p = [[0.0, 0.0], [0.0, 3.0], [1.0, 4.0], [1.0, 1.0]];
        let pts: Vec<[f64; 3]> = p.iter().map(|q| [q[0], q[1], 1.0]).collect();
        let c = Nurbs::new(&pts, 4).unwrap();
        assert_eq!(c.u_max(), 1.0);
        for i in 0..=10 {
            let t = i as f64 / 10.0;
            let (a, b) = (c.point(t), bezier(&p, t));
            assert!((a[0] - b[0]).abs() < 1e-15 && (a[1] - b[1]).abs() < 1e-15, "{t}");
            // Central difference of the closed form.
            let h = 1e-6;
            let (lo, hi) = (bezier(&p, t - h), bezier(&p, t + h));
            let d = c.derivative(t);
            for m in 0..2 {
                assert!((d[m] - (hi[m] - lo[m]) / (2.0 * h)).abs() < 1e-7, "{t} {d:?}");
            }
        }
    }

    #[test]
    fn weights_make_a_circle_and_the_knots_follow_linuxcnc() {
        // Quarter circle: order 3, middle weight cos 45°.
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let c = Nurbs::new(&[[1.0, 0.0, 1.0], [1.0, 1.0, h], [0.0, 1.0, 1.0]], 3).unwrap();
        for i in 0..=20 {
            let p = c.point(i as f64 / 20.0);
            assert!((p[0].hypot(p[1]) - 1.0).abs() < 1e-15);
        }
        let five = [
            [0.0, 0.0, 1.0],
            [0.0, 1.0, 1.0],
            [2.0, 2.0, 1.0],
            [2.0, 0.0, 1.0],
            [0.0, 0.0, 2.0],
        ];
        let c = Nurbs::new(&five, 3).unwrap();
        assert_eq!(c.knots, vec![0.0, 0.0, 0.0, 1.0, 2.0, 3.0, 3.0, 3.0]);
        assert_eq!(c.breaks(), vec![1.0, 2.0]);
        assert_eq!(c.point(0.0), [0.0, 0.0]);
        assert_eq!(c.point(3.0), [0.0, 0.0]);
        assert!(Nurbs::new(&five[..2], 3).is_none() && Nurbs::new(&five, 1).is_none());
    }
}
