//! Ramp – cruise – ramp composition, generic over the ramp law (quintic, jerk15, mixed57).
//!
//! Every ramp of these laws is point-symmetric, so the fastest change v1 → v2 covers its mean speed
//! times its duration T(|v2 − v1|): a law only gives T and dT/dΔv ([`RampLaw`]). The peak speed of a
//! block too short for its feed is the root of D(v) = d(v_in, v) + d(v, v_out) = L, increasing in
//! v: bracketed Newton in u = sqrt(v − max(v_in, v_out)), started from two equal ramps from the
//! higher end speed (`rise_estimate`), then made exact against D as evaluated (a few ulps down).
//! Laws with a closed-form largest ramp (`max_rise`) give it; the default is the same Newton.

use super::roots::{bisect, fit_down, newton_bounded};
use super::tolerance::{BRACKET_DOUBLINGS, BRACKET_START, RESIDUAL};
use super::{BlockRequest, FeedLaw, Kin};

/// A family of point-symmetric speed changes with a = 0 at both ends.
pub trait RampLaw {
    /// Duration T(Δv) of the fastest speed change by Δv ≥ 0, and dT/dΔv (Δv > 0).
    fn time(&self, dv: f64) -> (f64, f64);
    /// Limits that make T finite and positive (otherwise the bounded fall-backs are used).
    fn valid(&self) -> bool;
    /// Largest x ≥ 0 with d(v, v + x) ≤ length, within a few ulps (made exact by the caller).
    fn max_rise(&self, length: f64, v: f64) -> f64 {
        max_rise_newton(self, length, v)
    }
    /// A cheap estimate of `max_rise`, where Newton starts for the peak speed.
    fn rise_estimate(&self, length: f64, v: f64) -> f64 {
        self.max_rise(length, v)
    }
    /// Speed drops y ∈ [0, v] with d(v, v − y) = length in closed form (NaN where absent), for laws
    /// that have them; `None`: the bracketed Newton of [`drop_root`] finds the one wanted.
    fn drop_roots(&self, _length: f64, _v: f64) -> Option<[f64; 5]> {
        None
    }
}

/// The drop y ∈ [lo, hi] with d(v, v − y) = length, given that [lo, hi] holds exactly one
/// (d − length changes sign once there): the closed-form root if the law has one, else bracketed
/// Newton on d(v, v − y), with slope −T/2 + (2v − y)/2 · T'(y). NaN if rounding lost the root.
fn drop_root<R: RampLaw>(law: &R, length: f64, v: f64, [lo, hi]: [f64; 2], smallest: bool) -> f64 {
    if let Some(roots) = law.drop_roots(length, v) {
        let within = roots.into_iter().filter(|y| *y >= lo && *y <= hi);
        let pick = if smallest { f64::min } else { f64::max };
        return within.reduce(pick).unwrap_or(f64::NAN);
    }
    // d rises through `length` at the smallest root and falls through it at the largest: with the
    // sign, f is increasing across the root wanted (f(lo) ≤ 0 < f(hi), as newton_bounded needs).
    let sign = if smallest { 1.0 } else { -1.0 };
    let f = |y: f64| {
        let (t, dt) = law.time(y);
        let d = 0.5 * (2.0 * v - y) * t;
        (sign * (d - length), sign * (0.5 * (2.0 * v - y) * dt - 0.5 * t))
    };
    newton_bounded(lo, hi, 0.5 * (lo + hi), RESIDUAL * length, f)
}

/// Exit of a slow-down v_in → v_out that does not fit in `length` (d(v_in, v_out) > length): the
/// lowest speed whose ramp from v_in fits. d(v_in, v_in − y) is unimodal in the drop y, zero at
/// y = 0 and above `length` at y = v_in − v_out, so the one crossing in between is on its rising
/// side: the smallest root, then made exact (a few ulps less drop).
pub fn slow_down_exit<R: RampLaw>(law: &R, length: f64, v_in: f64, v_out: f64) -> f64 {
    let g = |y: f64| distance(law, v_in, v_in - y);
    let y_max = v_in - v_out;
    if !law.valid() {
        // No finite ramp times to solve with: the bounded bisection copes with any limits.
        return bisect(v_in, v_out, |x| distance(law, v_in, x) <= length);
    }
    let y = drop_root(law, length, v_in, [0.0, y_max], true);
    if y.is_nan() {
        // Rounding put the root just outside [0, y_max]: bisection on the predicate as evaluated.
        return bisect(v_in, v_out, |x| distance(law, v_in, x) <= length);
    }
    v_in - fit_down(y.clamp(0.0, y_max), 0.0, length, g).0
}

/// Largest exit x ≤ `target` with d(v_in, x) ≤ `length`, for a slow-down whose ramp to `target`
/// does not fit but a stop does (0 if neither): d(v_in, x) rises from x = 0 to a peak, then falls
/// to 0 at v_in, so the crossing is on the rising side in x: the largest drop root in
/// [v_in − target, v_in], then made exact (a few ulps lower).
pub fn lowest_exit<R: RampLaw>(law: &R, length: f64, v_in: f64, target: f64) -> f64 {
    let d = |x: f64| distance(law, v_in, x);
    if d(target) <= length {
        return target;
    }
    if d(0.0) > length {
        return 0.0;
    }
    let y = if law.valid() {
        drop_root(law, length, v_in, [v_in - target, v_in], false)
    } else {
        f64::NAN
    };
    if y.is_nan() {
        // No finite ramp times, or rounding lost the root: bisection on the predicate.
        return bisect(0.0, target, |x| d(x) <= length);
    }
    fit_down((v_in - y).clamp(0.0, target), 0.0, length, d).0
}

/// Distance of the fastest change v1 → v2: (v1 + v2)/2 · T(|v2 − v1|).
pub fn distance<R: RampLaw + ?Sized>(law: &R, v1: f64, v2: f64) -> f64 {
    0.5 * (v1 + v2) * law.time((v2 - v1).abs()).0
}

/// Largest v ≥ v0 whose ramp from (or to) v0 fits in `length`: max_exit and max_entry alike.
pub fn max_speed<R: RampLaw>(law: &R, length: f64, v0: f64) -> f64 {
    let (v0, length) = (v0.max(0.0), length.max(0.0));
    if !law.valid() || length.is_nan() {
        return largest_within(v0, length, |v| distance(law, v0, v));
    }
    let w = v0 + law.max_rise(length, v0);
    fit_down(w, v0, length, |w| distance(law, v0, w)).0
}

/// Default `max_rise`: d(v, v + u²) is increasing in u; bracket by doubling, then Newton.
fn max_rise_newton<R: RampLaw + ?Sized>(law: &R, length: f64, v: f64) -> f64 {
    let mut hi = v.max(BRACKET_START).sqrt();
    let mut lo = 0.0;
    for _ in 0..BRACKET_DOUBLINGS {
        if distance(law, v, v + hi * hi) > length {
            break;
        }
        lo = hi;
        hi *= 2.0;
    }
    max_rise_within(law, length, v, lo, hi)
}

/// Largest rise x = u² from v with d(v, v + x) ≤ length, given u ∈ [lo, hi] bracketing it:
/// bracketed Newton from hi (within a few ulps; the caller makes it exact).
pub fn max_rise_within<R: RampLaw + ?Sized>(law: &R, length: f64, v: f64, lo: f64, hi: f64) -> f64 {
    let f = |u: f64| {
        let x = u * u;
        let (t, dt) = law.time(x);
        let mean = v + 0.5 * x;
        (mean * t - length, 2.0 * u * (0.5 * t + mean * dt))
    };
    let u = newton_bounded(lo, hi, hi, RESIDUAL * length, f);
    u * u
}

/// Largest v ≥ v0 with dist(v) ≤ length, for dist increasing in v and dist(v0) ≤ length: the
/// bracket grows geometrically a bounded number of times, then bisection (any limits, NaN-safe).
fn largest_within(v0: f64, length: f64, dist: impl Fn(f64) -> f64) -> f64 {
    let mut good = v0;
    let mut step = v0.max(BRACKET_START);
    for _ in 0..BRACKET_DOUBLINGS {
        let hi = v0 + step;
        let fits = dist(hi) <= length; // NaN counts as "does not fit"
        if !fits {
            return bisect(good, hi, |v| dist(v) <= length);
        }
        good = hi;
        step *= 2.0;
    }
    good
}

/// Speeds of a ramp–cruise–ramp block and the distance left for the cruise at v_peak.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Shape {
    pub v_in: f64,
    pub v_peak: f64,
    pub v_end: f64,
    pub cruise: f64,
}

impl Shape {
    /// If v_out cannot be reached the block is one ramp towards it, to the closest speed whose ramp
    /// fits (the few ulps left are cruised). Otherwise the peak is the feed (capped by v_max) or,
    /// when too long, the largest peak that fits.
    pub fn solve<R: RampLaw>(law: &R, req: &BlockRequest) -> Shape {
        let dist = |v1: f64, v2: f64| distance(law, v1, v2);
        let l = req.length.max(0.0);
        let (v_in, v_out) = (req.v_in.max(0.0), req.v_out.max(0.0));
        let d_direct = dist(v_in, v_out);
        let reachable = d_direct <= l; // NaN counts as unreachable
        if !reachable {
            let v_end = if v_out > v_in {
                max_speed(law, l, v_in).min(v_out)
            } else {
                slow_down_exit(law, l, v_in, v_out)
            };
            return Shape {
                v_in,
                v_peak: v_in.max(v_end),
                v_end,
                cruise: l - dist(v_in, v_end),
            };
        }
        let v_cap = req.v_feed.min(req.limits.v_max).max(v_in).max(v_out);
        let total = |v: f64| dist(v_in, v) + dist(v, v_out);
        let d_cap = total(v_cap);
        let (v_peak, d_peak) = if d_cap <= l {
            (v_cap, d_cap)
        } else if law.valid() {
            peak(law, l, [v_in, v_out, v_cap], d_direct)
        } else {
            let v = bisect(v_in.max(v_out), v_cap, |v| total(v) <= l);
            (v, total(v))
        };
        Shape {
            v_in,
            v_peak,
            v_end: v_out,
            cruise: l - d_peak,
        }
    }

    pub fn cruise_time(&self) -> f64 {
        if self.v_peak > 0.0 {
            self.cruise.max(0.0) / self.v_peak
        } else {
            0.0
        }
    }
}

/// Peak v ∈ [v_hi, v_cap] with D(v) = l, given D(v_hi) = d0 ≤ l < D(v_cap), and D(v). Newton starts from the
/// peak of two equal ramps from v_hi sharing what the ramp v_lo → v_hi leaves (exact when
/// v_in = v_out, e.g. rest to rest).
fn peak<R: RampLaw>(law: &R, l: f64, [v_in, v_out, v_cap]: [f64; 3], d0: f64) -> (f64, f64) {
    let v_hi = v_in.max(v_out);
    let total = |v: f64| distance(law, v_in, v) + distance(law, v, v_out);
    let f = |u: f64| {
        let v = v_hi + u * u;
        let (t1, dt1) = law.time(v - v_in);
        let (t2, dt2) = law.time(v - v_out);
        let d = 0.5 * (v_in + v) * t1 + 0.5 * (v_out + v) * t2;
        let slope = 0.5 * (t1 + t2) + 0.5 * (v_in + v) * dt1 + 0.5 * (v_out + v) * dt2;
        (d - l, 2.0 * u * slope)
    };
    let u_max = (v_cap - v_hi).max(0.0).sqrt();
    let u0 = law.rise_estimate(0.5 * (l - d0).max(0.0), v_hi).sqrt();
    let u = newton_bounded(0.0, u_max, u0, RESIDUAL * l, f);
    fit_down((v_hi + u * u).clamp(v_hi, v_cap), v_hi, l, total)
}

/// A block as ramp (t_up, v_in → v_peak), cruise at v_peak (t_cruise), ramp (t_down, → v_end).
pub struct Composed {
    pub v_in: f64,
    pub v_peak: f64,
    pub v_end: f64,
    pub t_up: f64,
    pub t_cruise: f64,
    pub t_down: f64,
}

/// A law whose block is ramp – cruise – ramp: the `FeedLaw` impl follows from these.
pub trait RampCruiseRamp {
    fn composed(&self) -> Composed;
    /// State τ after the start of the first (`up`) or second ramp, s from that ramp's start.
    fn up_at(&self, tau: f64) -> Kin;
    fn down_at(&self, tau: f64) -> Kin;
    /// Phase durations, in order.
    fn phase_list(&self) -> Vec<f64>;
}

impl<T: RampCruiseRamp> FeedLaw for T {
    fn duration(&self) -> f64 {
        self.composed().duration()
    }
    fn length(&self) -> f64 {
        self.composed().length()
    }
    fn v_end(&self) -> f64 {
        self.composed().v_end
    }
    fn at(&self, t: f64) -> Kin {
        self.composed()
            .at(t, |tau| self.up_at(tau), |tau| self.down_at(tau))
    }
    fn phases(&self) -> Vec<f64> {
        self.phase_list()
    }
}

/// A speed change kept as a record (jerk15's 7 jerk phases, mixed57's 3).
pub trait Ramp {
    fn duration(&self) -> f64;
    /// State τ after the ramp's start from speed v1, s from there.
    fn at(&self, v1: f64, tau: f64) -> Kin;
}

/// A block of two ramp records around a cruise: its `RampCruiseRamp` (so `FeedLaw`) follows.
pub trait TwoRamps {
    type Ramp: Ramp;
    /// ([v_in, v_peak, v_end], up, t_cruise, down).
    fn parts(&self) -> ([f64; 3], &Self::Ramp, f64, &Self::Ramp);
    fn ramp_phases(&self) -> Vec<f64>;
}

impl<T: TwoRamps> RampCruiseRamp for T {
    fn composed(&self) -> Composed {
        let ([v_in, v_peak, v_end], up, t_cruise, down) = self.parts();
        Composed {
            v_in,
            v_peak,
            v_end,
            t_up: up.duration(),
            t_cruise,
            t_down: down.duration(),
        }
    }
    fn up_at(&self, tau: f64) -> Kin {
        let ([v_in, ..], up, ..) = self.parts();
        up.at(v_in, tau)
    }
    fn down_at(&self, tau: f64) -> Kin {
        let ([_, v_peak, _], .., down) = self.parts();
        down.at(v_peak, tau)
    }
    fn phase_list(&self) -> Vec<f64> {
        self.ramp_phases()
    }
}

impl Composed {
    pub fn duration(&self) -> f64 {
        self.t_up + self.t_cruise + self.t_down
    }

    pub fn length(&self) -> f64 {
        0.5 * (self.v_in + self.v_peak) * self.t_up
            + self.v_peak * self.t_cruise
            + 0.5 * (self.v_peak + self.v_end) * self.t_down
    }

    /// State at t; `up(τ)` and `down(τ)` give a ramp's state τ after its own start (s from there).
    pub fn at(&self, t: f64, up: impl Fn(f64) -> Kin, down: impl Fn(f64) -> Kin) -> Kin {
        let total = self.duration();
        let t = t.clamp(0.0, total);
        let t_end = t >= total;
        if t < self.t_up {
            return up(t);
        }
        let s1 = 0.5 * (self.v_in + self.v_peak) * self.t_up;
        let t = t - self.t_up;
        if t < self.t_cruise {
            return Kin {
                s: s1 + self.v_peak * t,
                v: self.v_peak,
                a: 0.0,
                j: 0.0,
            };
        }
        // At the very end take the ramp's own duration, so that a = 0 exactly despite rounding of t.
        let t_down = if t_end {
            self.t_down
        } else {
            (t - self.t_cruise).min(self.t_down)
        };
        let k = down(t_down);
        Kin {
            s: s1 + self.v_peak * self.t_cruise + k.s,
            ..k
        }
    }
}
