//! A plane curve approximated by biarcs (pairs of tangent-continuous circular arcs), as
//! LinuxCNC's interpreter turns G5, G5.1 and G5.2 into arcs (emccanon `biarc`, the equal-tangent-
//! length biarc through two points with their tangents), here refined until every piece is
//! within a tolerance of the curve: a piece whose distance to the curve, measured at
//! `SAMPLES` points of the curve inside it, exceeds MEASURED_SHARE of the tolerance is split at
//! its middle parameter. The result is tangent-continuous (G1) where the curve is.

/// Points of the curve inside a piece at which its distance to the biarc is measured.
pub const SAMPLES: usize = 16;
/// The measured distance must be within this share of the tolerance: between the measured
/// points it can be larger (by 1.4 % on LinuxCNC's NURBS example).
const MEASURED_SHARE: f64 = 0.75;
/// Most halvings of one initial piece.
const MAX_DEPTH: u32 = 40;

use crate::geometry::vec2::{along, angle, cross, dot, norm, sub, P2};

/// One piece of the approximation, from the end of the previous one.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Piece {
    Line {
        to: P2,
    },
    /// A circular arc about `center`, counter-clockwise when `ccw`.
    Arc {
        to: P2,
        center: P2,
        ccw: bool,
    },
}

impl Piece {
    pub fn to(&self) -> P2 {
        match *self {
            Piece::Line { to } | Piece::Arc { to, .. } => to,
        }
    }

    /// Distance from `q` to this piece starting at `from`.
    fn distance(&self, from: P2, q: P2) -> f64 {
        match *self {
            Piece::Line { to } => segment_distance(from, to, q),
            Piece::Arc { to, center, ccw } => {
                let r = norm(sub(from, center));
                let (a0, a1, aq) = (angle(center, from), angle(center, to), angle(center, q));
                let sweep = |a: f64, b: f64| {
                    let s = if ccw { b - a } else { a - b };
                    s.rem_euclid(std::f64::consts::TAU)
                };
                if sweep(a0, aq) <= sweep(a0, a1) {
                    (norm(sub(q, center)) - r).abs()
                } else {
                    norm(sub(q, from)).min(norm(sub(q, to)))
                }
            }
        }
    }
}

fn segment_distance(a: P2, b: P2, q: P2) -> f64 {
    let d = sub(b, a);
    let l2 = dot(d, d);
    let s = if l2 > 0.0 {
        (dot(sub(q, a), d) / l2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    norm(sub(q, along(a, d, s)))
}

/// The arc from `p` with unit tangent `t` to `q`, or a line when it is within `flat` of one
/// (sagitta) or `q` lies on the tangent.
fn arc_to(p: P2, t: P2, q: P2, flat: f64) -> Piece {
    let v = sub(q, p);
    let (c2, side) = (dot(v, v), cross(t, v));
    // Signed radius: centre at p + r·n, n the left normal of t (LinuxCNC's `arc`).
    if side.abs() <= 1e-12 * c2.sqrt() {
        return Piece::Line { to: q };
    }
    let r = c2 / (2.0 * side);
    let center = [p[0] - r * t[1], p[1] + r * t[0]];
    // Half the swept angle is the angle between the tangent and the chord.
    let half = cross(t, v).atan2(dot(t, v)).abs();
    let sagitta = r.abs() * (1.0 - half.cos());
    if half < std::f64::consts::FRAC_PI_2 && sagitta <= flat {
        return Piece::Line { to: q };
    }
    Piece::Arc {
        to: q,
        center,
        ccw: r > 0.0,
    }
}

/// The equal-tangent-length biarc from `p0` (unit tangent `t0`) to `p1` (unit tangent `t1`):
/// control points p0 + d·t0 and p1 − d·t1, joint halfway between them, d > 0 solving
/// |p1 − p0 − d(t0 + t1)| = 2d. None when no such d exists.
pub fn biarc(p0: P2, t0: P2, p1: P2, t1: P2, flat: f64) -> Option<[Piece; 2]> {
    let v = sub(p1, p0);
    let t = [t0[0] + t1[0], t0[1] + t1[1]];
    // v·v − 2d v·t + 2d²(t0·t1 − 1) = 0
    let (a, b, c) = (2.0 * (dot(t0, t1) - 1.0), -2.0 * dot(v, t), dot(v, v));
    let d = if a.abs() < 1e-12 {
        (b < 0.0).then(|| -c / b)?
    } else {
        let disc = b * b - 4.0 * a * c;
        if disc < 0.0 {
            return None;
        }
        let q = disc.sqrt();
        let roots = [(-b - q) / (2.0 * a), (-b + q) / (2.0 * a)];
        roots
            .into_iter()
            .filter(|r| *r > 0.0 && r.is_finite())
            .reduce(f64::min)?
    };
    let (c0, c1) = (along(p0, t0, d), along(p1, t1, -d));
    let joint = [(c0[0] + c1[0]) / 2.0, (c0[1] + c1[1]) / 2.0];
    let first = arc_to(p0, t0, joint, flat);
    let tm = sub(c1, c0);
    let l = norm(tm);
    let tm = if l > 0.0 { [tm[0] / l, tm[1] / l] } else { t0 };
    Some([first, arc_to(joint, tm, p1, flat)])
}

/// A plane curve: its point and (not necessarily unit) tangent at a parameter.
pub trait Curve {
    fn point(&self, u: f64) -> P2;
    fn derivative(&self, u: f64) -> P2;
}

/// Why a curve could not be approximated.
#[derive(Debug, PartialEq)]
pub enum FitError {
    /// More than the allowed number of pieces.
    TooManyPieces,
}

/// Unit tangent at `u`, looking a little ahead (or back at the end) where the derivative
/// vanishes (coincident control points, a cusp).
fn tangent(c: &dyn Curve, u: f64, lo: f64, hi: f64) -> P2 {
    let d = c.derivative(u);
    let l = norm(d);
    if l > 1e-12 * (1.0 + norm(c.point(u))) && l.is_finite() {
        return [d[0] / l, d[1] / l];
    }
    let h = (hi - lo) * 1e-6;
    let v = if u + h <= hi {
        sub(c.point(u + h), c.point(u))
    } else {
        sub(c.point(u), c.point(u - h))
    };
    let l = norm(v);
    if l > 0.0 {
        [v[0] / l, v[1] / l]
    } else {
        [1.0, 0.0]
    }
}

/// Approximate `curve` on [u0, u1], starting the refinement from the pieces between `breaks`
/// (each cut in `initial` equal parts), each piece within `tol` of the curve at the measured
/// points; lines where an arc is within `tol / 4` of its chord. At most `max_pieces` pieces.
pub fn fit(
    curve: &dyn Curve,
    breaks: &[f64],
    initial: usize,
    tol: f64,
    max_pieces: usize,
) -> Result<Vec<Piece>, FitError> {
    let mut out = Vec::new();
    let (lo, hi) = (breaks[0], breaks[breaks.len() - 1]);
    for span in breaks.windows(2) {
        let n = initial.max(1);
        for i in 0..n {
            let a = span[0] + (span[1] - span[0]) * i as f64 / n as f64;
            let b = span[0] + (span[1] - span[0]) * (i + 1) as f64 / n as f64;
            refine(curve, (a, b), (lo, hi), tol, 0, max_pieces, &mut out)?;
        }
    }
    Ok(out)
}

fn refine(
    c: &dyn Curve,
    (a, b): (f64, f64),
    (lo, hi): (f64, f64),
    tol: f64,
    depth: u32,
    max: usize,
    out: &mut Vec<Piece>,
) -> Result<(), FitError> {
    let (p0, p1) = (c.point(a), c.point(b));
    let samples: [P2; SAMPLES] =
        std::array::from_fn(|i| c.point(a + (b - a) * (i + 1) as f64 / (SAMPLES + 1) as f64));
    let start = out.last().map_or(p0, Piece::to);
    let tol_measured = MEASURED_SHARE * tol;
    if norm(sub(p1, p0)) <= tol && samples.iter().all(|q| norm(sub(*q, p0)) <= tol) {
        // A piece shorter than the tolerance: one line (none if it ends where it starts).
        if norm(sub(p1, start)) > 0.0 {
            out.push(Piece::Line { to: p1 });
        }
        return Ok(());
    }
    let (t0, t1) = (tangent(c, a, lo, hi), tangent(c, b, lo, hi));
    if let Some(pair) = biarc(start, t0, p1, t1, tol / 4.0) {
        let fits = samples
            .iter()
            .all(|&q| pair[0].distance(start, q).min(pair[1].distance(pair[0].to(), q)) <= tol_measured);
        if fits || depth >= MAX_DEPTH {
            if out.len() + 2 > max {
                return Err(FitError::TooManyPieces);
            }
            out.extend(pair);
            return Ok(());
        }
    } else if depth >= MAX_DEPTH {
        out.push(Piece::Line { to: p1 });
        return Ok(());
    }
    let m = (a + b) / 2.0;
    refine(c, (a, m), (lo, hi), tol, depth + 1, max, out)?;
    refine(c, (m, b), (lo, hi), tol, depth + 1, max, out)
}

#[cfg(test)]
mod tests {
    use super::*;

    struct Circle;
    impl Curve for Circle {
        fn point(&self, u: f64) -> P2 {
            [u.cos(), u.sin()]
        }
        fn derivative(&self, u: f64) -> P2 {
            [-u.sin(), u.cos()]
        }
    }

    #[test]
    fn a_circle_is_one_biarc_of_two_quarter_arcs() {
        let pair = biarc([1.0, 0.0], [0.0, 1.0], [-1.0, 0.0], [0.0, -1.0], 1e-9).unwrap();
        let Piece::Arc { to, center, ccw } = pair[0] else {
            panic!("{pair:?}")
        };
        assert!(ccw && norm(center) < 1e-15 && norm(sub(to, [0.0, 1.0])) < 1e-15);
        let pieces = fit(&Circle, &[0.0, std::f64::consts::PI], 1, 1e-9, 100).unwrap();
        assert_eq!(pieces.len(), 2);
    }

    #[test]
    fn an_s_curve_gets_arcs_of_both_senses_within_the_tolerance() {
        struct S;
        impl Curve for S {
            fn point(&self, u: f64) -> P2 {
                [u, u.sin()]
            }
            fn derivative(&self, u: f64) -> P2 {
                [1.0, u.cos()]
            }
        }
        let tol = 1e-6;
        let pieces = fit(&S, &[0.0, 6.0], 4, tol, 10_000).unwrap();
        let mut from = [0.0, 0.0];
        let mut worst: f64 = 0.0;
        for p in &pieces {
            // The sine's distance to the piece, at points between the piece's ends.
            let (x0, x1) = (from[0], p.to()[0]);
            for i in 0..=50 {
                let x = x0 + (x1 - x0) * i as f64 / 50.0;
                worst = worst.max(p.distance(from, [x, x.sin()]));
            }
            from = p.to();
        }
        assert!(worst <= tol * 1.01, "{worst}");
        assert_eq!(from, [6.0, 6f64.sin()]);
        let senses: Vec<bool> = pieces
            .iter()
            .filter_map(|p| match p {
                Piece::Arc { ccw, .. } => Some(*ccw),
                _ => None,
            })
            .collect();
        assert!(senses.contains(&true) && senses.contains(&false));
    }
}
