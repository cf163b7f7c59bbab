//! 7-phase jerk-limited S-curve (seed 004, eq. 1–7 and the appendix cases 1–10).
//!
//! A block is: ramp 1 from v_in to the cruise speed v_c (phases 1–3, jerk ±J, a plateau at ±A
//! when the speed change exceeds A²/J), cruise at v_c (phase 4), ramp 2 from v_c to v_end
//! (phases 5–7). Each ramp is the fastest speed change with a = 0 at both ends, so its time is
//! T(Δv) = 2·sqrt(Δv/J) (Δv ≤ A²/J) or Δv/A + A/J, and its distance is (v1 + v2)/2 · T.
//!
//! The ten appendix cases are the regimes of the two ramps (triangular / with plateau) times
//! "V_F reached or not" times "V_Out reached or not". Instead of one branch per case, the peak
//! speed is found on the total ramp distance D(v_c) = d(v_in, v_c) + d(v_c, v_out), which is
//! increasing and convex in u = sqrt(v_c − max(v_in, v_out)): closed form when both ramps have a
//! plateau (quadratic), Cardano start + Newton otherwise (a bounded number of steps; on a convex
//! increasing function Newton lands right of the root after one step and then decreases
//! monotonically to it). Rest to rest this is the time-optimal profile.

use super::roots::{bisect, cubic_depressed, cubic_pos, fit_down, quadratic_pos};
use super::tolerance::{PEAK_NEWTON_STEPS, PEAK_RESIDUAL, PEAK_STEP, ROOT_SLACK};
use super::{BlockRequest, FeedLaw, Kin, Limits};
use serde::{Deserialize, Serialize};

/// Phase durations `tau`, the jerk of the two ramps and the distance and speed at each phase
/// start, so that `at(t)` is one cubic (eq. 1–7). Kept to 26 numbers (the `Profile` enum holds it
/// inline): phase jerks, start accelerations and start times follow from these (methods below).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Scurve7 {
    /// Phase durations τ1…τ7 (s).
    pub tau: [f64; 7],
    /// Distance (m) and speed (m/s) at each phase start; v_start[0] = v_in, v_start[3] = cruise.
    pub s_start: [f64; 7],
    pub v_start: [f64; 7],
    /// Jerk of phase 1 (ramp 1) and phase 5 (ramp 2): +J speeding up, −J slowing down, 0 if the
    /// ramp is empty; phases 3 and 7 have the opposite jerk, phases 2, 4, 6 none.
    pub ramp_jerk: [f64; 2],
    pub v_end: f64,
    pub duration: f64,
    pub length: f64,
}

/// One ramp between two speeds: jerk phase, plateau, jerk phase (a = 0 at both ends).
#[derive(Clone, Copy, Debug)]
struct Ramp {
    /// Duration of each of the two jerk phases.
    t_jerk: f64,
    /// Duration of the acceleration plateau.
    t_plateau: f64,
    /// +1 speeding up, −1 slowing down.
    sign: f64,
}

fn ramp(v1: f64, v2: f64, a: f64, j: f64) -> Ramp {
    let dv = (v2 - v1).abs();
    let sign = if v2 >= v1 { 1.0 } else { -1.0 };
    if dv * j <= a * a {
        // A not reached (seed cases 2, 6, 10): τ = sqrt(Δv/J).
        Ramp {
            t_jerk: (dv / j).sqrt(),
            t_plateau: 0.0,
            sign,
        }
    } else {
        // Plateau at ±A (seed eq. 60, 70): τ_jerk = A/J, τ_plateau = Δv/A − A/J.
        Ramp {
            t_jerk: a / j,
            t_plateau: dv / a - a / j,
            sign,
        }
    }
}

/// Ramp time T(Δv).
fn ramp_time(dv: f64, a: f64, j: f64) -> f64 {
    if dv * j <= a * a {
        2.0 * (dv / j).sqrt()
    } else {
        dv / a + a / j
    }
}

/// Distance of the fastest change v1 → v2 with a = 0 at both ends: (v1 + v2)/2 · T(|v2 − v1|).
/// Symmetric in (v1, v2); increasing in the larger speed for a fixed smaller one.
pub fn ramp_distance(v1: f64, v2: f64, lim: &Limits) -> f64 {
    if !valid_limits(lim) {
        return 0.0;
    }
    let (v1, v2) = (v1.max(0.0), v2.max(0.0));
    0.5 * (v1 + v2) * ramp_time((v2 - v1).abs(), lim.a_max, lim.j_max)
}

fn valid_limits(lim: &Limits) -> bool {
    lim.a_max.is_finite() && lim.j_max.is_finite() && lim.a_max > 0.0 && lim.j_max > 0.0
}

/// Time and distance of the fastest rise from v toward `top` (a = 0 at both ends), up to `top`
/// or as far as `length` takes it (`max_rise`), whichever comes first.
pub fn rise_within(v: f64, top: f64, length: f64, lim: &Limits) -> (f64, f64) {
    if !valid_limits(lim) || top <= v {
        return (0.0, 0.0);
    }
    let v = v.max(0.0);
    let full = ramp_distance(v, top, lim);
    let (end, x) = if full <= length {
        (top, full)
    } else {
        let end = v + max_rise(length, v, lim);
        (end, ramp_distance(v, end, lim))
    };
    (ramp_time(end - v, lim.a_max, lim.j_max), x)
}

/// Largest speed change x ≥ 0 from base speed v (up or down to v) with d(v, v + x) ≤ length.
/// d is increasing in x, so this is the one root of d(v, v + x) = length.
pub(super) fn max_rise(length: f64, v: f64, lim: &Limits) -> f64 {
    if !valid_limits(lim) || length.is_nan() || length <= 0.0 {
        return 0.0;
    }
    let (a, j) = (lim.a_max, lim.j_max);
    let v = v.max(0.0);
    let ac = a * a / j;
    // Without plateau: (2v + x)·sqrt(x/J) = L, with s = sqrt(x): s³ + 2v·s − L·sqrt(J) = 0 (Cardano).
    let s = cubic_pos(2.0 * v, length * j.sqrt());
    let x = s * s;
    if x <= ac {
        return x;
    }
    // With plateau: (2v + x)(x/A + A/J) = 2L → x²/A + x(A/J + 2v/A) + 2vA/J − 2L = 0.
    let b = a / j + 2.0 * v / a;
    let c = 2.0 * v * a / j - 2.0 * length;
    quadratic_pos(1.0 / a, b, c)
}

/// v + `max_rise` with the rounding of the closed form removed: step the speed down (by ulps of
/// v when the rise is tiny next to v) until the ramp distance, evaluated the way `plan` does, is
/// ≤ length, so that planning with max_entry/max_exit really reaches the other end.
fn max_speed_fitting(length: f64, v: f64, lim: &Limits) -> f64 {
    let v = v.max(0.0);
    let w = v + max_rise(length, v, lim);
    fit_down(w, v, length, |w| ramp_distance(v, w, lim)).0
}

/// Largest entry speed v_in ≥ v_out from which the S-curve slows to v_out within `length`.
/// d(v_in, v_out) is increasing in v_in for a fixed v_out, so the closed-form root is the true max.
pub fn max_entry(length: f64, v_out: f64, lim: &Limits) -> f64 {
    let v_out = v_out.max(0.0);
    max_speed_fitting(length, v_out, lim)
}

/// Largest exit speed v_out ≥ v_in the S-curve reaches from v_in within `length`.
pub fn max_exit(length: f64, v_in: f64, lim: &Limits) -> f64 {
    let v_in = v_in.max(0.0);
    max_speed_fitting(length, v_in, lim)
}

/// Total ramp distance v_in → v_c → v_out as a function of u = sqrt(v_c − v_hi), and dD/du.
/// Both ramps speed up into v_c ≥ v_hi = max(v_in, v_out), so D is increasing and convex in u.
fn peak_distance(u: f64, v_in: f64, v_out: f64, a: f64, j: f64) -> (f64, f64) {
    let (d1, g1) = rise_distance(u, v_in, v_in.max(v_out), a, j);
    let (d2, g2) = rise_distance(u, v_out, v_in.max(v_out), a, j);
    (d1 + d2, g1 + g2)
}

/// d(v1, v_c) and its derivative w.r.t. u, with v_c = v_hi + u², v1 ≤ v_hi.
fn rise_distance(u: f64, v1: f64, v_hi: f64, a: f64, j: f64) -> (f64, f64) {
    let x = (v_hi - v1) + u * u;
    if x * j <= a * a {
        let r = (x / j).sqrt();
        let d = (2.0 * v1 + x) * r;
        // dd/dx = r + (2v1 + x)/(2·J·r); times dx/du = 2u. At x = 0 (only when u = 0) the limit is
        // 2v1/sqrt(J) · (u/r) with u/r = sqrt(J) when v1 = v_hi.
        let g = if r > 0.0 {
            2.0 * u * (r + (2.0 * v1 + x) / (2.0 * j * r))
        } else {
            2.0 * v1 / j.sqrt()
        };
        (d, g)
    } else {
        let t = x / a + a / j;
        let d = 0.5 * (2.0 * v1 + x) * t;
        let g = 2.0 * u * (0.5 * t + 0.5 * (2.0 * v1 + x) / a);
        (d, g)
    }
}

/// Peak speed v_c ∈ [v_hi, v_cap] with D(v_c) = length, given D(v_hi) ≤ length < D(v_cap).
pub(super) fn solve_peak(length: f64, v_in: f64, v_out: f64, v_cap: f64, a: f64, j: f64) -> f64 {
    let v_hi = v_in.max(v_out);
    let ac = a * a / j;
    let u_max = (v_cap - v_hi).max(0.0).sqrt();
    // Both ramps with a plateau (seed case 3): quadratic in v_c,
    // v_c²/A + v_c·A/J − (v_in² + v_out²)/(2A) + (v_in + v_out)·A/(2J) − L = 0.
    let u_plateau = ac.sqrt();
    if u_plateau < u_max && peak_distance(u_plateau, v_in, v_out, a, j).0 <= length {
        let c = -(v_in * v_in + v_out * v_out) / (2.0 * a) + (v_in + v_out) * a / (2.0 * j) - length;
        let vc = quadratic_pos(1.0 / a, a / j, c);
        return vc.clamp(v_hi, v_cap);
    }
    // Start: Cardano for both ramps triangular from v_hi (exact when v_in = v_out, e.g. rest to
    // rest: 2(2v + u²)·u/sqrt(J) = L), shifted by the ramp v_lo → v_hi.
    let d0 = peak_distance(0.0, v_in, v_out, a, j).0;
    let mut u = cubic_pos(2.0 * v_hi, 0.5 * (length - d0).max(0.0) * j.sqrt()).min(u_max);
    for _ in 0..PEAK_NEWTON_STEPS {
        let (d, g) = peak_distance(u, v_in, v_out, a, j);
        if g.is_nan() || g <= 0.0 {
            break;
        }
        let next = (u - (d - length) / g).clamp(0.0, u_max);
        let step = (next - u).abs();
        u = next;
        // Quadratic convergence: a residual below 1e-8 leaves ~1e-16 after this step (the rest is
        // taken by fit_down or the cruise).
        if step <= PEAK_STEP * u.max(f64::MIN_POSITIVE) || (d - length).abs() <= PEAK_RESIDUAL * length {
            break;
        }
    }
    (v_hi + u * u).clamp(v_hi, v_cap)
}

/// Largest exit x ≤ `target` with d(v_in, x) ≤ `length` when a stop fits (0 otherwise): `target`
/// if its ramp fits, else the slow-down exit below it (closed form).
pub fn lowest_exit(length: f64, v_in: f64, target: f64, lim: &Limits) -> f64 {
    if ramp_distance(v_in, target, lim) <= length {
        return target;
    }
    if ramp_distance(v_in, 0.0, lim) > length {
        return 0.0;
    }
    slow_down_exit(length, v_in, target, lim)
}

/// Exit speed of a slow-down v_in → v_out that does not fit in `length` (cruise at v_in first).
/// D(v_in, x) is unimodal in x (see plan/mod.rs): the largest exit below v_out if a stop fits, else
/// the lowest one above v_out. In the speed drop y = v_in − x, D = L is one of the roots of
/// [`drop_roots`] (exactly one lies in the interval searched); bisection only if rounding loses it.
pub(super) fn slow_down_exit(length: f64, v_in: f64, v_out: f64, lim: &Limits) -> f64 {
    let d = |x: f64| ramp_distance(v_in, x, lim);
    let g = |y: f64| d(v_in - y);
    let roots = drop_roots(length, v_in, lim.a_max, lim.j_max);
    let within = |lo: f64, hi: f64| roots.into_iter().filter(move |y| *y >= lo && *y <= hi);
    if d(0.0) <= length {
        // Stop fits: the crossing on the rising side of D in x, i.e. the largest drop root.
        match within(v_in - v_out, v_in).reduce(f64::max) {
            Some(y) => fit_down((v_in - y).min(v_out), 0.0, length, d).0,
            None => bisect(0.0, v_out, |x| d(x) <= length),
        }
    } else {
        // d(v_in) = 0 ≤ L < d(v_out): the smallest speed drop whose ramp reaches L.
        let y = match within(0.0, v_in - v_out).reduce(f64::min) {
            Some(y) => fit_down(y, 0.0, length, g).0,
            None => bisect(0.0, v_in - v_out, |y| g(y) <= length),
        };
        v_in - y
    }
}

/// Speed drops y ∈ [0, v] with d(v, v − y) = length (NaN where absent): without plateau
/// (y ≤ A²/J), (2v − y)·sqrt(y/J) = L, a depressed cubic s³ − 2v·s + L·sqrt(J) = 0 in s = sqrt(y)
/// (three real roots: trigonometric form); with plateau, (2v − y)(y/A + A/J) = 2L, the quadratic
/// y²/A + (A/J − 2v/A)·y + 2L − 2vA/J = 0.
pub(super) fn drop_roots(length: f64, v: f64, a: f64, j: f64) -> [f64; 5] {
    let ac = a * a / j;
    let mut out = [f64::NAN; 5];
    for (k, s) in cubic_depressed(-2.0 * v, length * j.sqrt())
        .into_iter()
        .enumerate()
    {
        // (Roots within rounding of a regime's end are kept: both forms agree there.)
        if s >= 0.0 && s * s <= ac.min(v) * (1.0 + ROOT_SLACK) {
            out[k] = (s * s).min(v);
        }
    }
    let (qa, qb, qc) = (1.0 / a, a / j - 2.0 * v / a, 2.0 * length - 2.0 * v * a / j);
    let disc = qb * qb - 4.0 * qa * qc;
    if disc >= 0.0 {
        let w = disc.sqrt();
        // Both roots without cancellation: the larger-magnitude one first, then c/(a·y).
        let big = -0.5 * (qb + qb.signum() * w) / qa;
        for (k, y) in [big, qc / (qa * big)].into_iter().enumerate() {
            if y > ac && y <= v * (1.0 + ROOT_SLACK) {
                out[3 + k] = y.min(v);
            }
        }
    }
    out
}

/// The block's profile: V_F if the length allows, the highest peak V_F' otherwise, and the
/// exit speed v_out if reachable within L, the closest reachable exit otherwise (reported in v_end).
pub fn plan(req: &BlockRequest) -> Scurve7 {
    let lim = &req.limits;
    let v_in = finite_or_zero(req.v_in).max(0.0);
    if !valid_limits(lim) {
        return Scurve7::build(v_in, v_in, v_in, 0.0, 1.0, 1.0);
    }
    let (a, j) = (lim.a_max, lim.j_max);
    let length = finite_or_zero(req.length).max(0.0);
    let v_out = finite_or_zero(req.v_out).max(0.0);
    let mut v_feed = finite_or_zero(req.v_feed).max(0.0);
    if lim.v_max.is_finite() && lim.v_max > 0.0 {
        v_feed = v_feed.min(lim.v_max);
    }
    let reach = ramp_distance(v_in, v_out, lim);
    if reach > length {
        // V_Out not reachable (seed cases 1, 2): one ramp over the whole length.
        if v_out > v_in {
            let v_end = max_exit(length, v_in, lim).min(v_out);
            return Scurve7::build(v_in, v_end, v_end, length, a, j);
        }
        let v_end = slow_down_exit(length, v_in, v_out, lim);
        return Scurve7::build(v_in, v_in, v_end, length, a, j);
    }
    let v_hi = v_in.max(v_out);
    let v_c = if v_feed >= v_hi {
        let v_cap = v_feed;
        let total = |v: f64| ramp_distance(v_in, v, lim) + ramp_distance(v, v_out, lim);
        if total(v_cap) <= length {
            v_cap // V_F reached (seed cases 7–10)
        } else {
            // V_F' (seed cases 3–6), then made to fit with the speed as stored: v_c = v_hi + u²
            // rounds, and a short ramp's distance is sensitive to it.
            let v_c = solve_peak(length, v_in, v_out, v_cap, a, j);
            fit_down(v_c, v_hi, length, total).0
        }
    } else {
        // V_F below an end speed (the look-ahead never asks this): cruise at V_F if the length
        // allows (seed cases 9, 10 with v_in > V_F), else a cruise speed in [V_F, v_hi] where the
        // ramps fill L (bisection between D(V_F) > L and D(v_hi) = d(v_in, v_out) ≤ L).
        let total = |v: f64| ramp_distance(v_in, v, lim) + ramp_distance(v, v_out, lim);
        if total(v_feed) <= length {
            v_feed
        } else {
            let excess = bisect(0.0, v_hi - v_feed, |dv| total(v_hi - dv) <= length);
            v_hi - excess
        }
    };
    Scurve7::build(v_in, v_c, v_out, length, a, j)
}

fn finite_or_zero(x: f64) -> f64 {
    if x.is_finite() {
        x
    } else {
        0.0
    }
}

impl Scurve7 {
    /// Ramp v_in → v_c, cruise at v_c for what is left of `length`, ramp v_c → v_end; phase start
    /// states integrated with eq. 1–7.
    fn build(v_in: f64, v_c: f64, v_end: f64, length: f64, a: f64, j: f64) -> Scurve7 {
        let r1 = ramp(v_in, v_c, a, j);
        let r2 = ramp(v_c, v_end, a, j);
        let ramps = 0.5 * (v_in + v_c) * (2.0 * r1.t_jerk + r1.t_plateau)
            + 0.5 * (v_c + v_end) * (2.0 * r2.t_jerk + r2.t_plateau);
        let cruise = if v_c > 0.0 {
            ((length - ramps) / v_c).max(0.0)
        } else {
            0.0
        };
        let j1 = if r1.t_jerk > 0.0 { r1.sign * j } else { 0.0 };
        let j2 = if r2.t_jerk > 0.0 { r2.sign * j } else { 0.0 };
        let mut p = Scurve7 {
            tau: [
                r1.t_jerk,
                r1.t_plateau,
                r1.t_jerk,
                cruise,
                r2.t_jerk,
                r2.t_plateau,
                r2.t_jerk,
            ],
            s_start: [0.0; 7],
            v_start: [0.0; 7],
            ramp_jerk: [j1, j2],
            v_end,
            duration: 0.0,
            length: 0.0,
        };
        let jerk = p.jerk();
        let acc = p.a_start();
        let (mut t, mut s, mut v) = (0.0, 0.0, v_in);
        for k in 0..7 {
            p.s_start[k] = s;
            p.v_start[k] = v;
            let (ds, dv, _) = advance(p.tau[k], v, acc[k], jerk[k]);
            t += p.tau[k];
            s += ds;
            v += dv;
            // The speed at the end of ramp 1 and in the cruise is known exactly.
            if k == 2 || k == 3 {
                v = v_c;
            }
        }
        p.duration = t;
        p.length = s;
        p
    }

    pub fn v_in(&self) -> f64 {
        self.v_start[0]
    }

    /// Cruise speed of phase 4: V_F, or V_F' when V_F is not reached.
    pub fn v_cruise(&self) -> f64 {
        self.v_start[3]
    }

    /// Jerk of each phase (m/s³).
    pub fn jerk(&self) -> [f64; 7] {
        std::array::from_fn(|k| self.jerk_of(k))
    }

    /// Acceleration at each phase start (m/s²): 0 at the ramp ends, the ramp's peak on its plateau.
    pub fn a_start(&self) -> [f64; 7] {
        std::array::from_fn(|k| self.a_start_of(k))
    }

    /// `jerk()[k]`, without the other six (`at`, every tick).
    fn jerk_of(&self, k: usize) -> f64 {
        let [j1, j2] = self.ramp_jerk;
        match k {
            0 => j1,
            2 => -j1,
            4 => j2,
            6 => -j2,
            _ => 0.0,
        }
    }

    /// `a_start()[k]`, without the other six.
    fn a_start_of(&self, k: usize) -> f64 {
        match k {
            1 | 2 => self.ramp_jerk[0] * self.tau[0],
            5 | 6 => self.ramp_jerk[1] * self.tau[4],
            _ => 0.0,
        }
    }
}

/// Change of (s, v, a) over dt from speed v, acceleration a, constant jerk (eq. 1–7).
#[inline]
fn advance(dt: f64, v: f64, a: f64, jerk: f64) -> (f64, f64, f64) {
    let ds = dt * (v + dt * (0.5 * a + dt * jerk / 6.0));
    let dv = dt * (a + 0.5 * jerk * dt);
    (ds, dv, jerk * dt)
}

impl FeedLaw for Scurve7 {
    fn duration(&self) -> f64 {
        self.duration
    }
    fn length(&self) -> f64 {
        self.length
    }
    fn v_end(&self) -> f64 {
        self.v_end
    }
    fn at(&self, t: f64) -> Kin {
        if t >= self.duration || t.is_nan() {
            return Kin {
                s: self.length,
                v: self.v_end,
                a: 0.0,
                j: 0.0,
            };
        }
        // Phase k holding t (t < duration, so it exists; empty phases are skipped).
        let mut rest = t.max(0.0);
        let mut k = 0;
        while k < 6 && rest >= self.tau[k] {
            rest -= self.tau[k];
            k += 1;
        }
        let jerk = self.jerk_of(k);
        let a0 = self.a_start_of(k);
        let (ds, dv, da) = advance(rest, self.v_start[k], a0, jerk);
        Kin {
            s: self.s_start[k] + ds,
            v: self.v_start[k] + dv,
            a: a0 + da,
            j: jerk,
        }
    }
    fn phases(&self) -> Vec<f64> {
        self.tau.to_vec()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `rise_within` is the banded law's rise without bands (an independent evaluation: its
    /// pieces summed, its exit by regula falsi): the same time and distance to the top where the
    /// length reaches it; else the whole length, in a time within the bisection's bracket.
    #[test]
    fn rise_within_matches_the_banded_rise() {
        use crate::feed::bands::{Banded, Bands};
        use crate::feed::{scurve7_banded, ProfileKind};
        let lim = Limits {
            v_max: 1.0,
            a_max: 2.0,
            j_max: 60.0,
            snap_max: 0.0,
        };
        let bands = Bands::default();
        let banded = Banded {
            kind: ProfileKind::Scurve7,
            top: &lim,
            bands: &bands,
        };
        for i in 0..20 {
            let v = 0.5 * i as f64 / 20.0;
            let rise = scurve7_banded::Rise::from(&banded, v);
            for top in [v + 1e-3, v + 0.05, v + 0.3, v + 0.9] {
                let (t_top, x_top) = rise.time_distance(top);
                for length in [1e-6, 1e-4, 1e-2, 0.5 * x_top, x_top, 2.0 * x_top] {
                    let (t, x) = rise_within(v, top, length, &lim);
                    if x_top <= length {
                        assert!((t - t_top).abs() <= 1e-12 * t_top.max(1.0), "{v} {top} {length}");
                        assert!((x - x_top).abs() <= 1e-12 * x_top.max(1e-3), "{v} {top} {length}");
                    } else {
                        // The closed form to its rounding where the rise is tiny next to v.
                        assert!((x - length).abs() <= 1e-6 * length, "{v} {top} {length}: {x}");
                        let w = v + bisect(0.0, top - v, |dv| rise.time_distance(v + dv).1 <= length);
                        let t_w = rise.time_distance(w).0;
                        assert!((t - t_w).abs() <= 1e-6 * t_w, "{v} {top} {length}: {t} {t_w}");
                    }
                }
            }
        }
    }

    /// The closed-form slow-down exit equals the bounded bisection it replaced, in both branches
    /// (a stop fits / does not) and both ramp regimes (with and without plateau).
    #[test]
    fn slow_down_exit_matches_bisection() {
        let lim = Limits {
            v_max: 1.0,
            a_max: 2.0,
            j_max: 60.0,
            snap_max: 0.0,
        };
        let mut checked = [0; 2];
        for i in 1..=40 {
            for k in 0..40 {
                let v_in = 0.6 * i as f64 / 40.0;
                let v_out = v_in * k as f64 / 40.0;
                // Absolute lengths, and lengths just above a stop's (where D(v_in, x) rises in x).
                let stop = ramp_distance(v_in, 0.0, &lim);
                let rel = [1.0, 1.01, 1.05, 1.1, 1.2].map(|f| f * stop);
                for length in [1e-6, 1e-4, 1e-3, 5e-3, 2e-2, 6e-2].into_iter().chain(rel) {
                    if ramp_distance(v_in, v_out, &lim) <= length {
                        continue;
                    }
                    let d = |x: f64| ramp_distance(v_in, x, &lim);
                    let stop_fits = d(0.0) <= length;
                    let want = if stop_fits {
                        bisect(0.0, v_out, |x| d(x) <= length)
                    } else {
                        v_in - bisect(0.0, v_in - v_out, |y| d(v_in - y) <= length)
                    };
                    // The closed form found a root (no fall-back to bisection).
                    let (lo, hi) = if stop_fits {
                        (v_in - v_out, v_in)
                    } else {
                        (0.0, v_in - v_out)
                    };
                    let roots = drop_roots(length, v_in, lim.a_max, lim.j_max);
                    assert!(
                        roots.iter().any(|y| *y >= lo && *y <= hi),
                        "{v_in} {v_out} {length}"
                    );
                    let got = slow_down_exit(length, v_in, v_out, &lim);
                    assert!(d(got) <= length, "{v_in} {v_out} {length}");
                    assert!(
                        (got - want).abs() <= 1e-12 * v_in,
                        "{v_in} {v_out} {length}: {got} vs {want}"
                    );
                    checked[stop_fits as usize] += 1;
                }
            }
        }
        assert!(checked[0] > 300 && checked[1] > 300, "{checked:?}");
    }
}
