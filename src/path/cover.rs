//! When a transition's samples keep every point of it within the tolerance of a programmed
//! move: the rule the cut search admits a cut by (junction.rs) and the reported line keeps
//! (source_map.rs). The transition p(u) is sampled every `step` of u; a sample at distance d
//! from a move keeps the half-steps about it within the tolerance where d ≤ tol − guard, the
//! guard bounding how much the distance can grow over half a step:
//! - at most σ_max·step/2 (σ_max bounds |p'|; the distance to a set grows no faster than the
//!   point moves);
//! - or, where the nearest point of the move stays inside it over the half-steps, the
//!   distance's own growth: it grows at the rate N of the component of p' away from the move
//!   (across a line; across the helix's turns and radius for an arc), and N changes at most
//!   at a rate D (from M₂, a bound of |p''|, and the turning of the arc's frame), so by at
//!   most N·δ + D·δ²/2 over δ = step/2.
//!
//! A transition runs nearly along the moves it replaces, so the second is mostly far smaller:
//! for a 0.5 mm cut the first is 7.8 µm, which leaves 2.2 µm of a 10 µm tolerance.

use super::hermite::Hermite;
use super::smooth::Move;
use super::tolerance::TRANSITION_SAMPLES;
use crate::geometry::{add, dot, norm, scale, sub, Arc, AtAngle, Line, Source};
use crate::Vec3;

/// The distance from each sample of a transition to the move its tolerance check measures
/// first (`lead`), carried from the cut search to the reported line (source_map.rs), which
/// needs the same distances; None between two lines (checked in closed form).
/// `UNMEASURED` where the sample guard was found to hold by a bound alone (`Guards::held`).
pub(super) type Leads = Option<[f64; TRANSITION_SAMPLES + 1]>;

/// A lead distance not measured: the sample guard holds by a bound of it (below any distance,
/// so `Guards::by_speed` holds at it too).
pub(super) const UNMEASURED: f64 = f64::NEG_INFINITY;

/// The move the tolerance check of sample k measures first, the one nearest the sample's end
/// of the corner, as an index into the `before` moves then the `after` ones.
pub(super) fn lead(k: usize, before: usize, after: usize) -> usize {
    if 2 * k <= TRANSITION_SAMPLES {
        before.saturating_sub(1)
    } else if after > 0 {
        before
    } else {
        before - 1
    }
}

/// A transition's sample spacing and the bounds its guards come from.
#[derive(Clone, Copy, Debug)]
pub(super) struct Guards {
    pub(super) step: f64,
    /// The guard from the speed bound alone, σ_max·step/2.
    pub(super) sample: f64,
    sigma: f64,
    m2: f64,
}

/// A sample: its parameter's point, and the curve for its first derivative (taken only where
/// the sample guard alone does not hold).
#[derive(Clone, Copy, Debug)]
pub(super) struct Sample<'a> {
    pub(super) p: Vec3,
    u: f64,
    h: &'a Hermite,
}

impl Sample<'_> {
    fn d1(&self) -> Vec3 {
        self.h.tangent(self.u)
    }
}

impl Guards {
    pub(super) fn of(h: &Hermite) -> Guards {
        let step = h.length() / TRANSITION_SAMPLES as f64;
        let sigma = h.speed_bound();
        Guards {
            step,
            sample: sigma * step / 2.0,
            sigma,
            m2: h.curvature_bound(),
        }
    }

    /// Sample k (0…`TRANSITION_SAMPLES`).
    pub(super) fn sample<'a>(&self, h: &'a Hermite, k: usize) -> Sample<'a> {
        let u = self.step * k as f64;
        Sample { p: h.point(u), u, h }
    }

    /// Sample `s`, at distance `d` from `mv` (`Source::distance`), keeps the half-steps about
    /// it within the tolerance of `mv`.
    #[inline]
    pub(super) fn holds(&self, mv: &Move, s: &Sample, d: f64) -> bool {
        // The sample guard first: where it holds, the finer one (never larger) is not needed.
        self.by_speed(mv, d) || self.by_growth(mv, s, d)
    }

    /// `holds` by the finer guard: out of line, as few samples need it (the sample guard's one
    /// comparison stays where it is asked).
    #[inline(never)]
    pub(super) fn by_growth(&self, mv: &Move, s: &Sample, d: f64) -> bool {
        d <= mv.tolerance - self.growth(mv, s, d)
    }

    /// The sample guard keeps sample `s` within the tolerance of `mv` by a bound of its
    /// distance (`Arc::at_angle_at_most`, an arc's without its `atan2` and `hypot`), unmeasured.
    #[inline]
    pub(super) fn held(&self, mv: &Move, s: &Sample) -> bool {
        match &mv.source {
            Source::Arc(a) => a.at_angle_at_most(s.p, mv.tolerance - self.sample),
            Source::Line(_) => false,
        }
    }

    /// The sample guard alone keeps the half-steps about a sample at distance `d` from `mv`
    /// within its tolerance (`holds` without the sample).
    #[inline]
    pub(super) fn by_speed(&self, mv: &Move, d: f64) -> bool {
        d <= mv.tolerance - self.sample
    }

    /// How much the distance from `mv` can grow over half a step from sample `s` (at distance
    /// `d`): the distance's own growth where the nearest point stays inside the move, else
    /// the sample guard.
    fn growth(&self, mv: &Move, s: &Sample, d: f64) -> f64 {
        let delta = 0.5 * self.step;
        let own = match &mv.source {
            Source::Line(l) => self.across_line(l, s, delta),
            Source::Arc(a) => self.across_arc(a, s, d, delta),
        };
        own.map_or(self.sample, |g| g.min(self.sample))
    }

    /// A line: the distance to it grows at |p'| across it (its direction t fixed), which changes
    /// at most at M₂; None where the foot may leave the segment.
    fn across_line(&self, l: &Line, s: &Sample, delta: f64) -> Option<f64> {
        let length = l.length();
        let reach = self.sigma * delta;
        if length <= 2.0 * reach {
            return None;
        }
        let t = scale(sub(l.end, l.start), 1.0 / length);
        let along = dot(sub(s.p, l.start), t);
        if along < reach || along > length - reach {
            return None;
        }
        let d1 = s.d1();
        let across = norm(sub(d1, scale(t, dot(d1, t))));
        Some(across * delta + self.m2 * delta * delta / 2.0)
    }

    /// An arc or helix: the distance measured at the same angle of the turn nearest the
    /// sample (`F`, at least the distance from the arc), |∇F·p'| ≤ N = |(p'_ρ, p'_z −
    /// (h/ρ)·p'_φ)| (h the rise per radian), and N changes at most at D = M₂ + σ²/ρ + M₂·(1 +
    /// |h|/ρ) + 2|h|σ²/ρ² (the frame turns at |p'_φ|/ρ ≤ σ/ρ). The guard also carries F − d
    /// where the sample's distance was an end point's. None where the angle may leave the
    /// sweep or the point come near the axis.
    fn across_arc(&self, a: &Arc, s: &Sample, d: f64, delta: f64) -> Option<f64> {
        let AtAngle { x, y, rho, turn, .. } = a.at_angle(s.p);
        let reach = self.sigma * delta;
        let rho_min = rho - reach;
        if rho_min <= 0.0 {
            return None;
        }
        let h = a.rise / a.sweep;
        // The turn whose point at the sample's angle is nearest (as `Source::distance`).
        let (f, big_f) = turn?;
        let angle_reach = reach / rho_min;
        if f < angle_reach || f > a.sweep - angle_reach {
            return None;
        }
        let e_rho = scale(add(scale(a.e1, x), scale(a.e2, y)), 1.0 / rho);
        let e_phi = scale(add(scale(a.e1, -y), scale(a.e2, x)), 1.0 / rho);
        let d1 = s.d1();
        let (d_rho, d_phi, d_z) = (dot(d1, e_rho), dot(d1, e_phi), dot(d1, a.axis));
        let n = d_rho.hypot(d_z - h / rho * d_phi);
        let (hr, s2) = (h.abs() / rho_min, self.sigma * self.sigma / rho_min);
        let rate = self.m2 + s2 + self.m2 * (1.0 + hr) + 2.0 * hr * s2;
        Some(big_f - d + n * delta + rate * delta * delta / 2.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{unit as direction, Plane};
    use crate::path::hermite::Jet;
    use crate::path::junction::within_tolerance;
    use crate::test_rng::unit;

    fn mv(source: Source, tolerance: f64) -> Move {
        Move {
            source,
            line: 1,
            feed: 0.05,
            tolerance,
            exact: false,
            absorbed: 0.0,
        }
    }

    /// The longest cut the check admits (by bisection: some sample lies at the edge of what its
    /// guard allows) keeps the tolerance of one of the moves at 20 000 points of the transition
    /// (to rounding): 1500 random corners of a line and a line, an arc or a helix turning either
    /// way, at shares of 2d from 0.7 to 1. And the guards of the moves' own growth let some of
    /// them be longer than the sample guard alone would.
    #[test]
    fn the_longest_admitted_transition_keeps_the_tolerance_everywhere() {
        let mut s = 0x9e37_79b9_7f4a_7c15u64;
        let mut longer = 0;
        for case in 0..1500 {
            let tol = 1e-6 * 10f64.powf(2.0 * unit(&mut s));
            let turn = 0.02 + 1.5 * unit(&mut s);
            let corner = [0.01 * unit(&mut s), 0.01 * unit(&mut s), 0.0];
            let t_in = [1.0, 0.0, 0.0];
            let t_out = [turn.cos(), turn.sin(), 0.0];
            let length = 0.002 + 0.01 * unit(&mut s);
            let line = |start, end| mv(Source::Line(Line { start, end }), tol);
            let before = line(sub(corner, scale(t_in, length)), corner);
            let curved = case % 3 != 0;
            let after = if curved {
                // Half a turn of radius 20 to 1000 times the tolerance either way, every other
                // one a helix.
                let r = tol * 10f64.powf(1.3 + 1.7 * unit(&mut s));
                let cw = case % 2 == 0;
                let side = if cw { -r } else { r };
                let center = add(corner, scale([-t_out[1], t_out[0], 0.0], side));
                let rise = if case % 4 < 2 {
                    0.0
                } else {
                    r * (unit(&mut s) - 0.5)
                };
                let end = add(add(center, sub(center, corner)), [0.0, 0.0, rise]);
                let a = Arc::from_gcode(corner, end, center, Plane::XY, cw, 0).expect("an arc");
                mv(Source::Arc(a), tol)
            } else {
                line(corner, add(corner, scale(t_out, length)))
            };
            let share = 0.7 + 0.3 * unit(&mut s);
            let curve = |d: f64| {
                let a = Jet {
                    p: sub(corner, scale(t_in, d)),
                    d1: t_in,
                    d2: [0.0; 3],
                };
                let b = match after.source {
                    Source::Arc(arc) => {
                        let g = arc.eval(d);
                        Jet {
                            p: g.p,
                            d1: direction(g.d1),
                            d2: g.d2,
                        }
                    }
                    Source::Line(_) => Jet {
                        p: add(corner, scale(t_out, d)),
                        d1: t_out,
                        d2: [0.0; 3],
                    },
                };
                Hermite::new(a, b, 2.0 * share * d)
            };
            let (ins, outs) = (std::slice::from_ref(&before), std::slice::from_ref(&after));
            let admits = |d: f64| within_tolerance(&curve(d), ins, outs, &mut [0.0; TRANSITION_SAMPLES + 1]);
            let (mut lo, mut hi) = (tol * 1e-3, 0.5 * length.min(after.source.length()));
            if !admits(lo) || admits(hi) {
                continue;
            }
            for _ in 0..30 {
                let mid = (lo * hi).sqrt();
                if admits(mid) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            let h = curve(lo);
            let g = Guards::of(&h);
            let by_speed = (0..=TRANSITION_SAMPLES).all(|k| {
                let p = g.sample(&h, k).p;
                [&before, &after]
                    .iter()
                    .any(|m| m.source.distance(p) <= tol - g.sample)
            });
            longer += usize::from(!by_speed);
            for i in 0..=20_000 {
                let p = h.point(h.length() * i as f64 / 20_000.0);
                let worst = before.source.distance(p).min(after.source.distance(p));
                assert!(
                    worst <= tol * (1.0 + 1e-9),
                    "case {case}: a point {worst:e} from the moves (tolerance {tol:e}, cut {lo:e})"
                );
            }
        }
        assert!(longer > 300, "{longer} longer by the moves' own growth");
    }

    /// The distance from a move by 200 000 points along it.
    fn true_distance(source: &Source, p: Vec3) -> f64 {
        let n = 200_000;
        (0..=n)
            .map(|i| {
                let at = source.length() * i as f64 / n as f64;
                let q = match source {
                    Source::Line(l) => add(l.start, scale(sub(l.end, l.start), at / l.length())),
                    Source::Arc(a) => a.eval(at).p,
                };
                norm(sub(p, q))
            })
            .fold(f64::INFINITY, f64::min)
    }

    /// The guard bounds the growth itself: on random curves near random lines, arcs and helices
    /// (where the distance may grow steeply at a sample) and along arcs and helices (as a
    /// transition runs), no point of the half-steps about a sample lies farther from the move
    /// than the sample's distance plus its guard (to rounding; the largest growth seen along an
    /// arc is 0.61 of its guard: the bound is within 1.7 times of tight there); and the moves'
    /// own growth is the smaller guard for many samples (half of them here).
    #[test]
    fn the_guard_bounds_how_far_the_distance_grows() {
        let mut s = 0x2545_f491_4f6c_dd1du64;
        let (mut checked, mut refined) = (0, 0);
        let r = |s: &mut u64, a: f64| a * (2.0 * unit(s) - 1.0);
        for case in 0..400 {
            let scale_mm = 1e-3 * 10f64.powf(unit(&mut s));
            let v = |s: &mut u64, a: f64| [r(s, a), r(s, a), r(s, a)];
            let jet = |s: &mut u64| Jet {
                p: v(s, scale_mm),
                d1: direction(v(s, 1.0)),
                d2: v(s, 1.0 / scale_mm),
            };
            let (mut a, mut b) = (jet(&mut s), jet(&mut s));
            let mut lambda = scale_mm * (1.0 + unit(&mut s));
            let mut along = None;
            if case % 2 == 1 {
                // Along an arc or a helix (as a transition runs), off it by up to a thousandth
                // of its radius, tangents and curvature perturbed.
                let radius = scale_mm * (0.5 + 3.0 * unit(&mut s));
                let rise = if case % 4 == 3 { r(&mut s, radius) } else { 0.0 };
                let start = [radius, 0.0, 0.0];
                let end = [-radius, 1e-3 * radius, rise];
                let arc = Arc::from_gcode(start, end, [0.0; 3], Plane::XY, case % 8 < 4, 0).expect("an arc");
                let l = arc.length();
                let (s0, s1) = (l * (0.05 + 0.4 * unit(&mut s)), l * (0.55 + 0.4 * unit(&mut s)));
                let off = |s: &mut u64, at: f64| {
                    let q = arc.eval(at);
                    Jet {
                        p: add(q.p, v(s, 1e-3 * radius)),
                        d1: direction(add(direction(q.d1), v(s, 0.05))),
                        d2: add(q.d2, v(s, 0.3 / radius)),
                    }
                };
                (a, b) = (off(&mut s, s0), off(&mut s, s1));
                lambda = (s1 - s0) * (0.98 + 0.04 * unit(&mut s));
                along = Some(Source::Arc(arc));
            }
            let h = Hermite::new(a, b, lambda);
            let g = Guards::of(&h);
            let near = h.point(0.5 * h.length());
            let source = match (along, case % 3) {
                (Some(arc), _) => arc,
                (None, 0) => Source::Line(Line {
                    start: add(near, v(&mut s, scale_mm)),
                    end: add(near, v(&mut s, 3.0 * scale_mm)),
                }),
                (None, k) => {
                    let radius = scale_mm * (0.2 + 3.0 * unit(&mut s));
                    let center = add(near, v(&mut s, radius));
                    let start = add(center, [radius, 0.0, 0.0]);
                    let end = add(
                        center,
                        [
                            -radius,
                            1e-3 * radius,
                            if k == 2 { r(&mut s, radius) } else { 0.0 },
                        ],
                    );
                    match Arc::from_gcode(start, end, center, Plane::XY, case % 2 == 0, 0) {
                        Some(a) => Source::Arc(a),
                        None => continue,
                    }
                }
            };
            let m = mv(source, f64::INFINITY);
            for k in 0..=TRANSITION_SAMPLES {
                let sample = g.sample(&h, k);
                let d = m.source.distance(sample.p);
                let grow = g.growth(&m, &sample, d);
                refined += usize::from(grow < g.sample);
                checked += 1;
                let u = g.step * k as f64;
                for i in 0..=100 {
                    let at = (u + g.step * (i as f64 / 100.0 - 0.5)).clamp(0.0, h.length());
                    let q = h.point(at);
                    let allowed = d + grow + 1e-9 * (d + grow) + 1e-15;
                    // `Source::distance` measures a helix at the point's own angle, at least
                    // the distance from it: where that is past the bound, the distance itself.
                    let far = match m.source.distance(q) {
                        far if far > allowed => true_distance(&m.source, q),
                        far => far,
                    };
                    assert!(
                        far <= allowed,
                        "case {case} sample {k}: {far:e} from the move, {d:e} + {grow:e} allowed"
                    );
                }
            }
        }
        assert!(
            checked > 20_000 && refined > checked / 4,
            "{refined} of {checked} refined"
        );
    }
}
