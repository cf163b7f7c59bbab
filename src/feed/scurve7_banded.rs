//! The 7-phase S-curve under speed bands (bands.rs): a ramp whose acceleration and jerk limits
//! change with the speed, without coming back to zero acceleration at the band edges.
//!
//! In the phase plane (v, a) a constant-jerk phase is a² = α + 2j·v, a plateau a = const. The
//! fastest ramp from v_lo to v_hi (a = 0 at both ends; dt = dv/a) has, at every speed, the
//! largest acceleration both reachable from v_lo and leaving room to come back to zero at v_hi:
//! a(v) = min(F(v), B(v)), with
//! - F, the forward envelope: from a = 0 at v_lo, a² grows by 2·J_k per unit of speed in band k,
//!   at most that band's A_k (cut to the next band's at its edge);
//! - B, the backward envelope: from a = 0 at v_hi, the same going down in speed — the most
//!   acceleration from which jerk −J_k brings it to zero at v_hi and below each band's A_k on
//!   the way.
//!
//! Both are continuous where they bind: F drops at a band edge only onto a lower band's A, which
//! B already keeps below; B rises at an edge only onto a higher band's A, from which F is below.
//! So min(F, B) is continuous, feasible and, taking the most acceleration at every speed, the
//! fastest. Each of its pieces is one phase of constant jerk (±J_k or 0); the ramp time and
//! distance are sums over the phases, in closed form. A speed drop is the time reverse of the rise between the same speeds. A block is ramp,
//! cruise, ramp as in scurve7.rs; the peak, the largest entry and exit are found by regula falsi on
//! the ramp distance (increasing in the far speed), bounded, or, where the answer lies in the
//! band the ramps start in, by scurve7's closed form with that band's limits, which two
//! evaluations of the distance confirm (`crossing_near`).

use super::bands::{Banded, MAX_BANDS};
use super::roots::{crossing_near, falsi_from, falsi_until};
use super::tolerance::{BRACKET_DOUBLINGS, BRACKET_START};
use super::{scurve7, FeedLaw, Kin, Limits};
use serde::{Deserialize, Serialize};

mod envelope;
pub use envelope::Rise;
use envelope::{band_below, rise, rise_time_distance, Piece};

/// One phase of constant jerk, with the state at its start.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Phase {
    pub t0: f64,
    pub tau: f64,
    pub jerk: f64,
    pub s0: f64,
    pub v0: f64,
    pub a0: f64,
}

/// Time and distance of the fastest speed change v1 → v2 under the bands.
pub fn ramp(b: &Banded, v1: f64, v2: f64) -> (f64, f64) {
    let (lo, hi) = (v1.min(v2).max(0.0), v1.max(v2).max(0.0));
    rise_time_distance(b, lo, hi)
}

/// Time of the fastest speed change v1 → v2 under the bands (with none, scurve7's).
pub fn ramp_time(b: &Banded, v1: f64, v2: f64) -> f64 {
    let (lo, hi) = (v1.min(v2).max(0.0), v1.max(v2).max(0.0));
    rise_time_distance(b, lo, hi).0
}

/// Distance of the fastest speed change v1 → v2 under the bands.
pub fn ramp_distance(b: &Banded, v1: f64, v2: f64) -> f64 {
    let (lo, hi) = (v1.min(v2).max(0.0), v1.max(v2).max(0.0));
    rise_time_distance(b, lo, hi).1
}

/// Largest v ≥ v0 with a ramp between v0 and v within `length` (max_entry and max_exit alike):
/// the distance grows with v. Bracketed by the block's top speed first (the look-ahead seldom
/// needs more), else by doubling; then regula falsi on the distance as evaluated.
pub fn max_speed(b: &Banded, length: f64, v0: f64) -> f64 {
    Rise::build_in(&mut None, b, v0.max(0.0)).max_speed(length)
}

/// One band's limits for scurve7's closed forms: inside one band the banded law is scurve7's
/// (equal bands are no bands), so where its answer stays in the band it is the crossing to
/// rounding, and the regula falsi only confirms it (`crossing_near`).
fn one_band(a: f64, j: f64) -> Limits {
    Limits {
        v_max: f64::INFINITY,
        a_max: a,
        j_max: j,
        snap_max: f64::INFINITY,
    }
}

impl Rise<'_> {
    /// `max_speed` from this rise's speed: every ramp from it shares its forward envelope.
    pub fn max_speed(&self, length: f64) -> f64 {
        // Never given up: the speed itself.
        let all = (f64::NEG_INFINITY, f64::INFINITY);
        self.max_speed_within(length, all).unwrap_or(self.lo())
    }

    /// `max_speed`, or None as soon as its search has found it outside (below, above): below
    /// `below` (a speed at or below it whose ramp does not fit) or at or above `above` (one at
    /// or above it whose ramp fits). The same steps until then.
    pub fn max_speed_within(&self, length: f64, (below, above): (f64, f64)) -> Option<f64> {
        let v0 = self.lo();
        let length = length.max(0.0);
        let fits = |v: f64| {
            let d = self.time_distance(v).1;
            (d <= length, d - length)
        };
        // The crossing in the band the rise starts in: scurve7's closed form there.
        let seed = self.first_band().and_then(|(band_top, a, j)| {
            let x0 = v0 + scurve7::max_rise(length, v0, &one_band(a, j));
            (x0 < band_top).then_some(x0)
        });
        if let Some(x) = seed.and_then(|x0| crossing_near(x0, v0, f64::INFINITY, |v| fits(v).1)) {
            return Some(x);
        }
        let done = |good: f64, bad: f64| bad <= below || good >= above;
        // The bracket's ends with the distances already solved there, for the regula falsi.
        let top = self.banded().top.v_max;
        let (mut good, mut g_good) = (v0, fits(v0).1);
        if top.is_finite() && top > v0 {
            let (fit, g_top) = fits(top);
            if !fit {
                return falsi_until(good, g_good, top, g_top, |v| fits(v).1, done);
            }
            (good, g_good) = (top, g_top);
            if good >= above {
                return None;
            }
        }
        let mut step = good.max(BRACKET_START);
        for _ in 0..BRACKET_DOUBLINGS {
            let hi = good + step;
            let (fit, g_hi) = fits(hi);
            if !fit {
                return falsi_until(good, g_good, hi, g_hi, |v| fits(v).1, done);
            }
            (good, g_good) = (hi, g_hi);
            if good >= above {
                return None;
            }
            step *= 2.0;
        }
        Some(good)
    }
}

/// Largest exit x ≤ `target` with a ramp from `v_in` within `length`, when a stop fits (0 if
/// not): the distance from v_in rises as the exit falls from v_in and may fall again towards 0,
/// so below the target the exits that fit are [0, x1]: regula falsi for x1.
pub fn lowest_exit(b: &Banded, length: f64, v_in: f64, target: f64) -> f64 {
    let d = |x: f64| ramp_distance(b, v_in, x);
    let d_target = d(target);
    if d_target <= length {
        return target;
    }
    let d_stop = d(0.0);
    if d_stop > length {
        return 0.0;
    }
    stop_fits_exit(b, length, v_in, target, d_stop, d_target)
}

/// The largest exit x ≤ `target` whose drop from `v_in` fits in `length` where a stop fits
/// (`d_stop`, `d_target`: the drops to 0 and to the target, solved already): scurve7's closed
/// form in the band of v_in where the exit stays in it, else regula falsi.
fn stop_fits_exit(b: &Banded, length: f64, v_in: f64, target: f64, d_stop: f64, d_target: f64) -> f64 {
    let g = |x: f64| ramp_distance(b, v_in, x) - length;
    let (floor, a, j) = band_below(b, v_in);
    let x0 = scurve7::slow_down_exit(length, v_in, target, &one_band(a, j));
    let near = (x0 > floor).then(|| crossing_near(x0, 0.0, target, g)).flatten();
    near.unwrap_or_else(|| falsi_from(0.0, d_stop - length, target, d_target - length, g))
}

/// One block's profile under bands: ramp, cruise, ramp.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Scurve7Banded {
    phases: Vec<Phase>,
    v_peak: f64,
    v_end: f64,
    duration: f64,
    length: f64,
}

impl Scurve7Banded {
    /// A restored profile: at most the phases a plan through every band has (seven per band
    /// and the top), back to back in time from 0.
    pub fn check_state(&self) -> Result<(), String> {
        let most = 7 * (super::bands::MAX_BANDS + 1) as u64;
        crate::valid::at_most("banded phases", self.phases.len() as u64, most)?;
        let mut t = 0.0;
        for p in &self.phases {
            if p.t0 != t || p.tau.is_nan() || p.tau < 0.0 {
                return Err("banded profile: phases not back to back".into());
            }
            t += p.tau;
        }
        Ok(())
    }
}

/// The block from `v_in` to `v_out` through at most `v_feed` over `length`, as scurve7's plan:
/// the feed if the length allows, the highest peak otherwise; an exit that cannot be reached
/// becomes the closest one that can (reported in `v_end`).
pub fn plan(b: &Banded, length: f64, v_in: f64, v_out: f64, v_feed: f64) -> Scurve7Banded {
    speeds(
        b,
        length,
        v_in,
        v_out,
        v_feed,
        |(length, v_in, v_c, v_end), kept| build(b, kept, length, v_in, v_c, v_end),
    )
}

/// `plan`'s duration and cruise speed alone, the same bit for bit, without building its phases
/// (the chain decisions compare block times).
pub fn plan_time(b: &Banded, length: f64, v_in: f64, v_out: f64, v_feed: f64) -> (f64, f64) {
    let (duration, v_c, _) = plan_time_rise(b, length, v_in, v_out, v_feed);
    (duration, v_c)
}

/// `plan_time`, and the time of its ramp between its entry (v_in, finite and at least 0) and
/// its cruise speed, as `ramp_time` gives it: where the cruise is above the entry, the sum of
/// the rise the duration sums anyway (the chain decisions need both).
pub fn plan_time_rise(b: &Banded, length: f64, v_in: f64, v_out: f64, v_feed: f64) -> (f64, f64, f64) {
    speeds(
        b,
        length,
        v_in,
        v_out,
        v_feed,
        |(length, v_in, v_c, v_end), kept| {
            let (duration, t_up) = duration(b, kept, length, v_in, v_c, v_end);
            let rise = if v_c > v_in { t_up } else { ramp_time(b, v_in, v_c) };
            (duration, v_c, rise)
        },
    )
}

/// `plan`'s length, entry, cruise and exit speeds, to `then` with the rises the search for them
/// built (from the entry speed, and the exit speed where it differs; none where it built none):
/// the block's ramps are pieces of them.
fn speeds<R>(
    b: &Banded,
    length: f64,
    v_in: f64,
    v_out: f64,
    v_feed: f64,
    then: impl FnOnce((f64, f64, f64, f64), &[&Rise]) -> R,
) -> R {
    let finite = |x: f64| if x.is_finite() { x.max(0.0) } else { 0.0 };
    let (length, v_in, v_out) = (finite(length), finite(v_in), finite(v_out));
    let mut v_feed = finite(v_feed);
    if b.top.v_max.is_finite() && b.top.v_max > 0.0 {
        v_feed = v_feed.min(b.top.v_max);
    }
    let d = |x: f64, y: f64| ramp_distance(b, x, y);
    // Each ramp distance solved once: the regula falsi starts from the ones the tests here took.
    let d_through = d(v_in, v_out);
    if d_through > length {
        let drop = |x: f64| d(v_in, x) - length;
        if v_out > v_in {
            // `max_speed`, from a rise kept for the ramp.
            let mut up = None;
            let up = Rise::build_in(&mut up, b, v_in.max(0.0));
            let v = up.max_speed(length).min(v_out);
            return then((length, v_in, v, v), &[up]);
        }
        let d_stop = d(v_in, 0.0);
        let v_end = if d_stop <= length {
            // A stop fits: the largest exit below v_out whose drop fits (`lowest_exit`).
            stop_fits_exit(b, length, v_in, v_out, d_stop, d_through)
        } else {
            // It does not: the smallest drop that fits, above v_out.
            falsi_from(v_in, drop(v_in), v_out, d_through - length, drop)
        };
        return then((length, v_in, v_in, v_end), &[]);
    }
    // Above both ends, each ramp rises from its end: the forward envelopes built once (one
    // when the ends are equal, the two ramps then the same sum).
    // Each rise is a few kB: built where it stays.
    let (mut up, mut down) = (None, None);
    let up = Rise::build_in(&mut up, b, v_in);
    let down = (v_out != v_in)
        .then_some(&mut down)
        .map(|down| Rise::build_in(down, b, v_out));
    let v_c = peak(length, (v_in, v_out, v_feed), d_through, up, down);
    match down {
        Some(down) => then((length, v_in, v_c, v_out), &[up, down]),
        None => then((length, v_in, v_c, v_out), &[up]),
    }
}

/// The cruise speed of a block whose ramp between its ends fits (`d_through`, the distance of
/// that ramp): the feed where both ramps to it fit, else the highest peak, with the rises from
/// the entry (`up`) and the exit (`down`, none when the ends are equal).
fn peak(length: f64, speeds: (f64, f64, f64), d_through: f64, up: &Rise, down: Option<&Rise>) -> f64 {
    let (v_in, v_out, v_feed) = speeds;
    let v_hi = v_in.max(v_out);
    let total = |v: f64| {
        let d_up = up.time_distance(v).1;
        d_up + down.map_or(d_up, |r| r.time_distance(v).1)
    };
    if v_feed <= v_hi {
        return v_feed.max(v_hi);
    }
    let t_feed = total(v_feed);
    if t_feed <= length {
        return v_feed.max(v_hi);
    }
    // At v_hi one of the two ramps is none: the total is the one ramp between.
    let t_hi = d_through + 0.0;
    let g = |v: f64| total(v) - length;
    // Both ramps in one band: scurve7's peak there.
    let band = |r: &Rise| r.first_band();
    let seed = match (band(up), down.map_or(band(up), band)) {
        (Some((top, a, j)), Some(other)) if other.0 == top => {
            let x0 = scurve7::solve_peak(length, v_in, v_out, v_feed, a, j);
            (x0 < top).then_some(x0)
        }
        _ => None,
    };
    let near = seed.and_then(|x0| crossing_near(x0, v_hi, v_feed, g));
    near.unwrap_or_else(|| falsi_from(v_hi, t_hi - length, v_feed, t_feed - length, g))
}

/// The pieces of the rise `from` → `hi` to `take`: from a kept rise that starts there (the
/// same pieces: `Rise::pieces`), else from one built for this ramp.
fn ramp_pieces(b: &Banded, kept: &[&Rise], from: f64, hi: f64, take: impl FnMut(&Piece)) {
    match kept.iter().find(|r| r.lo().to_bits() == from.to_bits()) {
        Some(r) => r.pieces(hi, take),
        None => rise(b, from, hi, take),
    }
}

/// The duration `build` sums: the rise's phases, the cruise, the drop's phases in reverse, each
/// added when it is longer than 0, in that order; and the rise's time as `rise_time_distance`
/// sums it (every phase, in order).
fn duration(b: &Banded, kept: &[&Rise], length: f64, v_in: f64, v_c: f64, v_end: f64) -> (f64, f64) {
    // Each ramp's phases into the caller's array (a returned array was copied out, and again
    // where the drop is the rise).
    let ramp = |from: f64, taus: &mut [f64; 4 * (MAX_BANDS + 1)]| {
        let (mut n, mut s, mut t) = (0, 0.0, 0.0);
        ramp_pieces(b, kept, from, v_c, |p| {
            let (tau, _, ds) = p.run();
            if n < taus.len() {
                taus[n] = tau;
                n += 1;
            }
            t += tau;
            s += ds;
        });
        (n, s, t)
    };
    let mut up = [0.0; 4 * (MAX_BANDS + 1)];
    let (n_up, s_up, t_up) = ramp(v_in, &mut up);
    let mut own_down;
    let (down, n_down, s_down) = if v_end == v_in {
        (&up, n_up, s_up)
    } else {
        own_down = [0.0; 4 * (MAX_BANDS + 1)];
        let (n, s, _) = ramp(v_end, &mut own_down);
        (&own_down, n, s)
    };
    let ramps = s_up + s_down;
    let cruise = if v_c > 0.0 {
        ((length - ramps) / v_c).max(0.0)
    } else {
        0.0
    };
    let phases = up[..n_up]
        .iter()
        .chain([&cruise])
        .chain(down[..n_down].iter().rev());
    let total = phases.filter(|&&tau| tau > 0.0).fold(0.0, |t, &tau| t + tau);
    (total, t_up)
}

/// Phases a ramp's list holds before it grows (`build`): 1 kB of (τ, jerk) pairs.
const RAMP_PHASES: usize = 64;

fn build(b: &Banded, kept: &[&Rise], length: f64, v_in: f64, v_c: f64, v_end: f64) -> Scurve7Banded {
    // The drop is the rise v_end → v_c played backwards: the same phases in reverse order. Each
    // ramp's distance is summed on the way, as `rise_time_distance` sums it (no pieces when the
    // ramp is none: its distance is 0 either way).
    let ramp = |from: f64| {
        // Room for a rise and a plateau per band, each cut once where the envelopes cross (the
        // list grows past that). Within 1 kB, as glibc's thread cache takes it: 1088 bytes, the
        // 4 · (MAX_BANDS + 1) pairs, went to its slower bins.
        let (mut phases, mut s) = (Vec::with_capacity(RAMP_PHASES), 0.0);
        ramp_pieces(b, kept, from, v_c, |p| {
            let (tau, j, ds) = p.run();
            phases.push((tau, j));
            s += ds;
        });
        (phases, s)
    };
    let (up, s_up) = ramp(v_in);
    // Equal ends: the drop is the rise (built once, not copied).
    let own_down;
    let (down, s_down) = if v_end == v_in {
        (&up, s_up)
    } else {
        own_down = ramp(v_end);
        (&own_down.0, own_down.1)
    };
    let ramps = s_up + s_down;
    let cruise = if v_c > 0.0 {
        ((length - ramps) / v_c).max(0.0)
    } else {
        0.0
    };
    let mut phases: Vec<Phase> = Vec::with_capacity(up.len() + down.len() + 1);
    let (mut t, mut s, mut v, mut a) = (0.0, 0.0, v_in, 0.0);
    let mut push = |tau: f64, jerk: f64, v: &mut f64, a: &mut f64| {
        if tau > 0.0 {
            phases.push(Phase {
                t0: t,
                tau,
                jerk,
                s0: s,
                v0: *v,
                a0: *a,
            });
            let (ds, dv, da) = advance(tau, *v, *a, jerk);
            t += tau;
            s += ds;
            *v += dv;
            *a += da;
        }
    };
    for &(tau, j) in &up {
        push(tau, j, &mut v, &mut a);
    }
    // The speed at the end of the rise and in the cruise is known exactly.
    (v, a) = (v_c, 0.0);
    push(cruise, 0.0, &mut v, &mut a);
    (v, a) = (v_c, 0.0);
    for &(tau, j) in down.iter().rev() {
        push(tau, j, &mut v, &mut a);
    }
    Scurve7Banded {
        phases,
        v_peak: v_c,
        v_end: if v_end < v_c { v_end } else { v_c },
        duration: t,
        length: s,
    }
}

/// Distance, speed and acceleration changes over `dt` from (v, a) with constant `jerk`.
fn advance(dt: f64, v: f64, a: f64, jerk: f64) -> (f64, f64, f64) {
    let ds = dt * (v + dt * (0.5 * a + dt * jerk / 6.0));
    let dv = dt * (a + 0.5 * jerk * dt);
    (ds, dv, jerk * dt)
}

impl Scurve7Banded {
    /// The cruise speed (the highest speed of the block).
    pub fn v_peak(&self) -> f64 {
        self.v_peak
    }
}

impl FeedLaw for Scurve7Banded {
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
        let Some(first) = self.phases.first() else {
            return Kin {
                s: 0.0,
                v: self.v_end,
                a: 0.0,
                j: 0.0,
            };
        };
        if t >= self.duration {
            return Kin {
                s: self.length,
                v: self.v_end,
                a: 0.0,
                j: 0.0,
            };
        }
        let t = t.max(0.0);
        let k = self.phases.partition_point(|p| p.t0 <= t).saturating_sub(1);
        let p = if t < first.t0 { first } else { &self.phases[k] };
        let dt = (t - p.t0).clamp(0.0, p.tau);
        let (ds, dv, da) = advance(dt, p.v0, p.a0, p.jerk);
        Kin {
            s: p.s0 + ds,
            v: p.v0 + dv,
            a: p.a0 + da,
            j: p.jerk,
        }
    }
    fn phases(&self) -> Vec<f64> {
        self.phases.iter().map(|p| p.tau).collect()
    }
}

#[cfg(test)]
mod tests;
