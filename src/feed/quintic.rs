//! Quintic feedrate law (seed 000, Chen/Yeh/Sun 2011): each speed change F_s → F_s + F_d follows
//! F(t) = F_s + a3 t³ + a4 t⁴ + a5 t⁵ (eq. 2.14) with a = j = 0 at both ends (eq. 2.11–2.17), over the
//! ramp time t_d of eq. 2.28. A block is ramp – cruise – ramp (`compose`); the largest ramp in a
//! length is a cubic (t_d by the jerk) or a quadratic (t_d by the acceleration) in closed form.

use super::compose::{self, Composed, RampCruiseRamp, RampLaw, Shape};
use super::roots::{cubic_depressed, cubic_pos, quadratic_pos};
use super::tolerance::ROOT_SLACK;
use super::{BlockRequest, Kin, Limits};
use serde::{Deserialize, Serialize};

/// Peak acceleration of a quintic ramp is 1.875·F_d/t_d (eq. 2.24; exactly 15/8, at t = t_d/2).
pub const ACC_FACTOR: f64 = 1.875;
/// Peak jerk is 5.773·F_d/t_d² (eq. 2.25, at t = 0.211 t_d). The paper prints 5.773; the exact value is
/// 10/√3 = 5.77350…, used here so that the jerk limit is never exceeded by the rounding.
pub const JERK_FACTOR: f64 = 5.773_502_691_896_258;

/// Ramp time of eq. 2.28: t_d = max(1.875 F_d/A, sqrt(5.773 F_d/J)).
pub fn ramp_time(f_d: f64, lim: &Limits) -> f64 {
    let f_d = f_d.abs();
    if f_d == 0.0 {
        return 0.0;
    }
    (ACC_FACTOR * f_d / lim.a_max).max((JERK_FACTOR * f_d / lim.j_max).sqrt())
}

/// The quintic ramp is point-symmetric, so it covers the mean speed times t_d.
pub fn ramp_distance(v1: f64, v2: f64, lim: &Limits) -> f64 {
    0.5 * (v1 + v2) * ramp_time(v2 - v1, lim)
}

pub fn max_entry(length: f64, v_out: f64, lim: &Limits) -> f64 {
    compose::max_speed(&Law(*lim), length, v_out)
}

/// Largest exit x ≤ `target` whose ramp from v_in fits in `length`, when a stop does (else 0).
pub fn lowest_exit(length: f64, v_in: f64, target: f64, lim: &Limits) -> f64 {
    compose::lowest_exit(&Law(*lim), length, v_in, target)
}

pub fn max_exit(length: f64, v_in: f64, lim: &Limits) -> f64 {
    compose::max_speed(&Law(*lim), length, v_in)
}

/// The quintic ramp as a [`RampLaw`]: T = max(1.875·Δv/A, sqrt(5.773·Δv/J)).
struct Law(Limits);

impl RampLaw for Law {
    fn time(&self, dv: f64) -> (f64, f64) {
        let t_a = ACC_FACTOR * dv / self.0.a_max;
        let t_j = (JERK_FACTOR * dv / self.0.j_max).sqrt();
        if dv == 0.0 {
            (0.0, 0.0)
        } else if t_a >= t_j {
            (t_a, ACC_FACTOR / self.0.a_max)
        } else {
            (t_j, 0.5 * t_j / dv)
        }
    }
    fn valid(&self) -> bool {
        let (a, j) = (self.0.a_max, self.0.j_max);
        a.is_finite() && j.is_finite() && a > 0.0 && j > 0.0
    }
    /// (2v + x)·T(x) = 2L: with T by the jerk, s = sqrt(x) solves s³ + 2v·s − 2L·sqrt(J/5.773) = 0;
    /// with T by the acceleration, 1.875/A·x² + 3.75v/A·x − 2L = 0.
    fn max_rise(&self, length: f64, v: f64) -> f64 {
        let (a, j) = (self.0.a_max, self.0.j_max);
        // T by the jerk up to x_c = 5.773·A²/(1.875²·J).
        let x_c = JERK_FACTOR * a * a / (ACC_FACTOR * ACC_FACTOR * j);
        let s = cubic_pos(2.0 * v, 2.0 * length * (j / JERK_FACTOR).sqrt());
        if s * s <= x_c {
            return s * s;
        }
        quadratic_pos(ACC_FACTOR / a, 2.0 * ACC_FACTOR * v / a, -2.0 * length)
    }
    /// (2v − y)·T(y) = 2L: with T by the jerk, s = sqrt(y) solves s³ − 2v·s + 2L·sqrt(J/5.773) = 0
    /// (up to three real roots: trigonometric form); with T by the acceleration,
    /// y² − 2v·y + 2L·A/1.875 = 0, y = v ∓ sqrt(v² − 2L·A/1.875).
    fn drop_roots(&self, length: f64, v: f64) -> Option<[f64; 5]> {
        let (a, j) = (self.0.a_max, self.0.j_max);
        let x_c = JERK_FACTOR * a * a / (ACC_FACTOR * ACC_FACTOR * j);
        let mut out = [f64::NAN; 5];
        let cubic = cubic_depressed(-2.0 * v, 2.0 * length * (j / JERK_FACTOR).sqrt());
        for (k, s) in cubic.into_iter().enumerate() {
            // (Roots within rounding of a regime's end are kept: both forms agree there.)
            if s >= 0.0 && s * s <= x_c.min(v) * (1.0 + ROOT_SLACK) {
                out[k] = (s * s).min(v);
            }
        }
        let c = 2.0 * length * a / ACC_FACTOR;
        let disc = v * v - c;
        if disc >= 0.0 {
            let w = disc.sqrt();
            // The smaller root without cancellation: c/(v + w).
            for (k, y) in [c / (v + w), v + w].into_iter().enumerate() {
                if y > x_c && y <= v * (1.0 + ROOT_SLACK) {
                    out[3 + k] = y.min(v);
                }
            }
        }
        Some(out)
    }
}

/// Ramp up v_in → v_peak (t_up), cruise (t_cruise), ramp v_peak → v_end (t_down).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Quintic {
    pub v_in: f64,
    pub v_peak: f64,
    pub v_end: f64,
    pub t_up: f64,
    pub t_cruise: f64,
    pub t_down: f64,
}

pub fn plan(req: &BlockRequest) -> Quintic {
    let lim = req.limits;
    let shape = Shape::solve(&Law(lim), req);
    Quintic {
        v_in: shape.v_in,
        v_peak: shape.v_peak,
        v_end: shape.v_end,
        t_up: ramp_time(shape.v_peak - shape.v_in, &lim),
        t_cruise: shape.cruise_time(),
        t_down: ramp_time(shape.v_end - shape.v_peak, &lim),
    }
}

/// State along one quintic ramp v1 → v2 of duration t_d, t from its start (eq. 2.14–2.17 integrated).
fn ramp_at(v1: f64, v2: f64, t_d: f64, t: f64) -> Kin {
    if t_d <= 0.0 {
        return Kin {
            s: v1 * t,
            v: v1,
            a: 0.0,
            j: 0.0,
        };
    }
    let f_d = v2 - v1;
    let x = (t / t_d).clamp(0.0, 1.0);
    let (x2, x3) = (x * x, x * x * x);
    Kin {
        // a3 = 10F_d/t_d³, a4 = −15F_d/t_d⁴, a5 = 6F_d/t_d⁵ (eq. 2.17), in the normalised time x = t/t_d.
        s: v1 * t + f_d * t_d * x2 * x2 * (2.5 - 3.0 * x + x2),
        v: v1 + f_d * x3 * (10.0 - 15.0 * x + 6.0 * x2),
        a: f_d / t_d * x2 * (30.0 - 60.0 * x + 30.0 * x2),
        j: f_d / (t_d * t_d) * x * (60.0 - 180.0 * x + 120.0 * x2),
    }
}

impl RampCruiseRamp for Quintic {
    fn composed(&self) -> Composed {
        Composed {
            v_in: self.v_in,
            v_peak: self.v_peak,
            v_end: self.v_end,
            t_up: self.t_up,
            t_cruise: self.t_cruise,
            t_down: self.t_down,
        }
    }
    fn up_at(&self, tau: f64) -> Kin {
        ramp_at(self.v_in, self.v_peak, self.t_up, tau)
    }
    fn down_at(&self, tau: f64) -> Kin {
        ramp_at(self.v_peak, self.v_end, self.t_down, tau)
    }
    fn phase_list(&self) -> Vec<f64> {
        vec![self.t_up, self.t_cruise, self.t_down]
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::feed::FeedLaw;

    #[test]
    fn constants_from_sampled_curve() {
        // Sample one ramp F_d = 1, t_d = 1 finely: the peaks are the factors of eq. 2.24 and 2.25.
        let n = 1_000_000;
        let (mut a_max, mut j_max, mut t_a, mut t_j) = (0.0f64, 0.0f64, 0.0, 0.0);
        for i in 0..=n {
            let t = i as f64 / n as f64;
            let k = ramp_at(0.0, 1.0, 1.0, t);
            if k.a > a_max {
                (a_max, t_a) = (k.a, t);
            }
            if k.j > j_max {
                (j_max, t_j) = (k.j, t);
            }
        }
        assert!((a_max - 1.875).abs() < 1e-9, "{a_max}");
        assert!((t_a - 0.5).abs() < 1e-6); // eq. 2.22
                                           // 5.773 as printed (the paper truncates 5.77350…), and the exact 10/√3 we use.
        assert!((j_max - 5.773).abs() < 1e-3, "{j_max}");
        assert!((j_max - JERK_FACTOR).abs() < 1e-9);
        assert!((t_j - 0.211).abs() < 1e-3, "{t_j}"); // eq. 2.23
        let end = ramp_at(0.0, 1.0, 1.0, 1.0);
        assert!((end.v - 1.0).abs() < 1e-15 && end.a.abs() < 1e-15 && (end.s - 0.5).abs() < 1e-15);
    }

    #[test]
    fn ramp_time_meets_limits() {
        // Seed 000 test: A = 12.5 m/s², J = 25000 m/s³ (as printed), feed 800 mm/min.
        let lim = Limits {
            v_max: 1.0,
            a_max: 12.5,
            j_max: 25_000.0,
            snap_max: 1e9,
        };
        let f_d = 0.8 / 60.0;
        let t_d = ramp_time(f_d, &lim);
        assert!((t_d - 1.875 * f_d / 12.5).abs() < 1e-15); // acceleration bound
        let p = plan(&BlockRequest {
            length: 0.01,
            v_in: 0.0,
            v_out: 0.0,
            v_feed: f_d,
            limits: lim,
        });
        assert!((p.t_up - t_d).abs() < 1e-15 && p.t_cruise > 0.0);
        let peak_a = (0..=1000)
            .map(|i| p.at(p.t_up * i as f64 / 1000.0).a)
            .fold(0.0, f64::max);
        assert!(peak_a <= 12.5 && peak_a > 12.5 * 0.9999);
    }

    #[test]
    fn general_block_and_short_block() {
        let lim = Limits {
            v_max: 1.0,
            a_max: 2.0,
            j_max: 60.0,
            snap_max: 6000.0,
        };
        let req = BlockRequest {
            length: 0.003,
            v_in: 0.05,
            v_out: 0.02,
            v_feed: 0.5,
            limits: lim,
        };
        let p = plan(&req);
        assert!(p.v_peak < 0.5 && p.v_peak > 0.05);
        let end = p.at(p.duration());
        assert!((end.s - 0.003).abs() < 1e-15 && (end.v - 0.02).abs() < 1e-15 && end.a.abs() < 1e-15);
        // v_out unreachable: one ramp, exit speed reported, its ramp is exactly the length.
        let p = plan(&BlockRequest {
            length: 1e-4,
            v_in: 0.0,
            v_out: 0.3,
            ..req
        });
        assert!(p.v_end < 0.3 && (ramp_distance(0.0, p.v_end, &lim) - 1e-4).abs() < 1e-15);
        assert!((p.at(p.duration()).s - 1e-4).abs() < 1e-15);
        assert!((max_exit(1e-4, 0.0, &lim) - p.v_end).abs() < 1e-12);
        let v = max_entry(0.01, 0.1, &lim);
        assert!((ramp_distance(v, 0.1, &lim) - 0.01).abs() < 1e-14);
    }
}
