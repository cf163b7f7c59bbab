//! The 7-phase jerk-limited S-curve of Pessoles et al. (seed 004, eq. 1–7 and the appendix):
//! jerk ±J or 0 in each phase, acceleration zero at block ends. A block is
//! ramp (v_in → v_p, phases 1–3), cruise at v_p (phase 4), ramp (v_p → v_out, phases 5–7).
//!
//! The ten cases of the appendix are the combinations this code meets through three choices:
//! each ramp reaches A (a constant-acceleration phase exists) or not, and the cruise exists
//! (v_p = V_F) or not (v_p below V_F, found by a bounded solve); plus the two cases where the
//! block is too short for V_out, where one ramp covers the whole block and the exit speed actually
//! reached is reported.

use super::{BlockRequest, FeedLaw, Kin, Limits};
use serde::{Deserialize, Serialize};

/// One block's 7-phase profile: phase durations, jerks, and the state at each phase start.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Scurve7 {
    /// τ1 … τ7 (s).
    pub tau: [f64; 7],
    /// Jerk in each phase (m/s³).
    pub jerk: [f64; 7],
    /// State (s, v, a) at the start of each phase and at the end (index 7).
    pub start: [[f64; 3]; 8],
    /// Start time of each phase and the end (index 7).
    pub t0: [f64; 8],
}

/// Time of the fastest change of speed by Δv ≥ 0 with a = 0 at both ends (eq. 1–3):
/// (jerk phase τ_j, constant-acceleration phase τ_a).
fn ramp_times(dv: f64, lim: &Limits) -> (f64, f64) {
    let (a, j) = (lim.a_max, lim.j_max);
    if dv >= a * a / j {
        (a / j, dv / a - a / j)
    } else {
        ((dv / j).sqrt(), 0.0)
    }
}

/// Distance of the fastest speed change v1 → v2: the ramp is point-symmetric in time, so the
/// distance is the mean speed times the duration, (v1 + v2)/2 · (2τ_j + τ_a).
pub fn ramp_distance(v1: f64, v2: f64, lim: &Limits) -> f64 {
    let (tj, ta) = ramp_times((v2 - v1).abs(), lim);
    0.5 * (v1 + v2) * (2.0 * tj + ta)
}

/// Largest v ≥ v0 with ramp_distance(v0, v) ≤ length, in closed form: below Δv = A²/J the ramp
/// is (v + v0)·sqrt(Δv/J) = L, with w = sqrt(Δv) the depressed cubic w³ + 2v0·w − L·sqrt(J) = 0
/// (one real root, Cardano); above, (v² − v0²)/(2A) + (v + v0)·A/(2J) = L, a quadratic.
fn max_speed_after(length: f64, v0: f64, lim: &Limits) -> f64 {
    let (a, j) = (lim.a_max, lim.j_max);
    let length = length.max(0.0);
    let v0 = v0.max(0.0);
    let dv_a = a * a / j;
    let boundary = (2.0 * v0 + dv_a) * a / j;
    if length <= boundary {
        let p = 2.0 * v0;
        let q = length * j.sqrt();
        let disc = (0.25 * q * q + p * p * p / 27.0).sqrt();
        // Cardano's w = c − d with c = cbrt(q/2 + disc), d = p/(3c), written without the
        // cancellation of c − d: c³ − d³ = q, so w = q / (c² + cd + d²), cd = p/3.
        let c = (0.5 * q + disc).cbrt();
        let w = if c > 0.0 {
            let d = p / (3.0 * c);
            q / (c * c + p / 3.0 + d * d)
        } else {
            0.0
        };
        // One Newton step polishes the last bits.
        let f = w * w * w + p * w - q;
        let df = 3.0 * w * w + p;
        let w = if df > 0.0 { (w - f / df).max(0.0) } else { w };
        v0 + w * w
    } else {
        // v²/(2A) + v·A/(2J) + (−v0²/(2A) + v0·A/(2J) − L) = 0
        let qa = 0.5 / a;
        let qb = 0.5 * a / j;
        let qc = -v0 * v0 * qa + v0 * qb - length;
        (-qb + (qb * qb - 4.0 * qa * qc).sqrt()) / (2.0 * qa)
    }
}

/// Largest entry speed v_in ≥ v_out that can slow to v_out within `length`.
pub fn max_entry(length: f64, v_out: f64, lim: &Limits) -> f64 {
    max_speed_after(length, v_out, lim)
}

/// Largest exit speed v_out ≥ v_in reachable from v_in within `length`.
pub fn max_exit(length: f64, v_in: f64, lim: &Limits) -> f64 {
    max_speed_after(length, v_in, lim)
}

/// Distance of the ramp v1 → vp (vp ≥ v1) and its derivative in vp: long ramps (A reached)
/// D = (v1 + vp)/2 · (Δv/A + A/J), short ones D = (v1 + vp)·τ_j with τ_j = sqrt(Δv/J).
fn ramp_distance_slope(v1: f64, vp: f64, lim: &Limits) -> (f64, f64) {
    let (a, j) = (lim.a_max, lim.j_max);
    let dv = (vp - v1).max(0.0);
    if dv >= a * a / j {
        let t = dv / a + a / j;
        (0.5 * (v1 + vp) * t, 0.5 * t + 0.5 * (v1 + vp) / a)
    } else {
        let tj = (dv / j).sqrt();
        let slope = if tj > 0.0 {
            tj + (v1 + vp) / (2.0 * j * tj)
        } else {
            f64::INFINITY
        };
        ((v1 + vp) * tj, slope)
    }
}

/// Peak speed v_p ≥ max(v_in, v_out) with ramp(v_in, v_p) + ramp(v_p, v_out) = L, when the
/// cruise does not fit. Both distances rise with v_p, so the root is unique. When both ramps
/// reach A it is the root of a quadratic, v_p²/A + v_p·A/J + c = 0; otherwise that root starts a
/// Newton iteration with the analytic slope, kept inside a shrinking bracket (bounded steps).
fn peak_speed(length: f64, v_in: f64, v_out: f64, v_hi: f64, lim: &Limits) -> f64 {
    let (a, j) = (lim.a_max, lim.j_max);
    let mut lo = v_in.max(v_out);
    let mut hi = v_hi;
    let c = -(v_in * v_in + v_out * v_out) / (2.0 * a) + (v_in + v_out) * a / (2.0 * j) - length;
    let (qa, qb) = (1.0 / a, a / j);
    let mut v = (-qb + (qb * qb - 4.0 * qa * c).max(0.0).sqrt()) / (2.0 * qa);
    let dv_a = a * a / j;
    if v - v_in >= dv_a && v - v_out >= dv_a && v > lo && v < hi {
        return v;
    }
    if !(v > lo && v < hi) {
        v = 0.5 * (lo + hi);
    }
    for _ in 0..60 {
        let (d1, s1) = ramp_distance_slope(v_in, v, lim);
        let (d2, s2) = ramp_distance_slope(v_out, v, lim);
        let f = d1 + d2 - length;
        if f > 0.0 {
            hi = v;
        } else {
            lo = v;
        }
        let newton = v - f / (s1 + s2);
        let next = if newton > lo && newton < hi {
            newton
        } else {
            0.5 * (lo + hi)
        };
        if (next - v).abs() <= 4.0 * f64::EPSILON * v || hi - lo <= 4.0 * f64::EPSILON * hi {
            v = next;
            break;
        }
        v = next;
    }
    v.clamp(v_in.max(v_out), v_hi)
}

/// Jerks and durations of a ramp v1 → v2 (3 phases).
fn ramp(v1: f64, v2: f64, lim: &Limits) -> ([f64; 3], [f64; 3]) {
    let (tj, ta) = ramp_times((v2 - v1).abs(), lim);
    let j = if v2 >= v1 { lim.j_max } else { -lim.j_max };
    ([tj, ta, tj], [j, 0.0, -j])
}

pub fn plan(req: &BlockRequest) -> Scurve7 {
    let lim = &req.limits;
    let length = req.length.max(0.0);
    let v_in = req.v_in.max(0.0);
    let mut v_out = req.v_out.max(0.0);
    let v_feed = req.v_feed.max(0.0);
    let mut v_peak;
    let mut cruise;
    // A block whose exit ramp overshoots L by rounding only (the planner's max_entry/max_exit
    // speeds) is feasible: the overshoot is below a femtometre per metre.
    if ramp_distance(v_in, v_out, lim) > length * (1.0 + 1e-12) + 1e-15 {
        // V_Out cannot be reached (appendix, cases where the block is too short).
        if v_out > v_in {
            v_out = max_exit(length, v_in, lim).min(v_out);
            v_peak = v_in;
            cruise = 0.0;
        } else {
            // Slowing down: the ramp distance rises then falls as the exit speed goes to 0, so the
            // feasible exits closest to V_out are the crossings above and below it.
            let above = exit_crossing(length, v_in, v_out, v_in, lim);
            let below = if ramp_distance(v_in, 0.0, lim) <= length {
                Some(exit_crossing(length, v_in, 0.0, v_out, lim))
            } else {
                None
            };
            v_out = match below {
                Some(b) if v_out - b <= above - v_out => b,
                _ => above,
            };
            v_peak = v_in;
            cruise = length - ramp_distance(v_in, v_out, lim);
        }
    } else {
        let v_top = v_feed.max(v_in).max(v_out);
        v_peak = v_top;
        cruise = length - ramp_distance(v_in, v_peak, lim) - ramp_distance(v_peak, v_out, lim);
        if cruise < 0.0 {
            let direct = ramp_distance(v_in, v_out, lim);
            // When one ramp v_in → v_out already fills L (the planner's max_exit/max_entry speeds),
            // a peak a few ulps above would add two ramps of sqrt(ulp/J) seconds: take none.
            v_peak = if direct >= length * (1.0 - 1e-12) {
                v_in.max(v_out)
            } else {
                peak_speed(length, v_in, v_out, v_top, lim)
            };
            cruise = 0.0;
        }
    }
    if v_peak <= 0.0 {
        cruise = 0.0;
        v_peak = 0.0;
    }
    let (t_up, j_up) = ramp(v_in, v_peak, lim);
    let (t_dn, j_dn) = ramp(v_peak, v_out, lim);
    let t_cruise = if v_peak > 0.0 {
        cruise.max(0.0) / v_peak
    } else {
        0.0
    };
    let tau = [t_up[0], t_up[1], t_up[2], t_cruise, t_dn[0], t_dn[1], t_dn[2]];
    let jerk = [j_up[0], j_up[1], j_up[2], 0.0, j_dn[0], j_dn[1], j_dn[2]];
    let mut start = [[0.0; 3]; 8];
    let mut t0 = [0.0; 8];
    start[0] = [0.0, v_in, 0.0];
    for i in 0..7 {
        start[i + 1] = advance(start[i], jerk[i], tau[i]);
        t0[i + 1] = t0[i] + tau[i];
        if i == 2 || i == 6 {
            // End of a ramp: acceleration is zero and the speed is the target, exactly.
            start[i + 1][2] = 0.0;
            start[i + 1][1] = if i == 2 { v_peak } else { v_out };
        }
    }
    Scurve7 { tau, jerk, start, t0 }
}

/// Exit speed x between `lo` and `hi` where the slowing ramp from v_in covers exactly `length`
/// (ramp_distance(v_in, lo) and ramp_distance(v_in, hi) on opposite sides of `length`).
fn exit_crossing(length: f64, v_in: f64, lo: f64, hi: f64, lim: &Limits) -> f64 {
    let f = |x: f64| ramp_distance(v_in, x, lim) - length;
    let (mut a, mut b) = (lo, hi);
    let fa = f(a);
    for _ in 0..80 {
        let m = 0.5 * (a + b);
        if (f(m) > 0.0) == (fa > 0.0) {
            a = m;
        } else {
            b = m;
        }
    }
    // The side where the ramp fits.
    if f(a) <= 0.0 {
        a
    } else {
        b
    }
}

fn advance(state: [f64; 3], j: f64, t: f64) -> [f64; 3] {
    let [s, v, a] = state;
    [
        s + v * t + 0.5 * a * t * t + j * t * t * t / 6.0,
        v + a * t + 0.5 * j * t * t,
        a + j * t,
    ]
}

impl FeedLaw for Scurve7 {
    fn duration(&self) -> f64 {
        self.t0[7]
    }
    fn length(&self) -> f64 {
        self.start[7][0]
    }
    fn v_end(&self) -> f64 {
        self.start[7][1]
    }
    fn at(&self, t: f64) -> Kin {
        if t >= self.t0[7] {
            let [s, v, _] = self.start[7];
            return Kin { s, v, a: 0.0, j: 0.0 };
        }
        let t = t.max(0.0);
        let mut i = 0;
        while i < 6 && t >= self.t0[i + 1] {
            i += 1;
        }
        let dt = t - self.t0[i];
        let [s, v, a] = advance(self.start[i], self.jerk[i], dt);
        Kin {
            s,
            v,
            a,
            j: self.jerk[i],
        }
    }
    fn phases(&self) -> Vec<f64> {
        self.tau.to_vec()
    }
}
