//! Trapezoid (linear acc/dec): the baseline every seed compares to. Acceleration jumps between
//! 0 and ±A, so jerk is unbounded at the phase changes (reported as 0 inside the phases).

use super::{BlockRequest, FeedLaw, Kin, Limits};
use serde::{Deserialize, Serialize};

/// Accelerate at ±A from v_in to v_peak (t1), cruise (t2), ramp at ±A to v_end (t3).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Trapezoid {
    pub v_in: f64,
    pub v_peak: f64,
    pub v_end: f64,
    pub a_max: f64,
    pub t1: f64,
    pub t2: f64,
    pub t3: f64,
}

/// Distance of a constant-acceleration change v1 → v2: (v1 + v2)/2 · |v2 − v1|/A.
pub fn ramp_distance(v1: f64, v2: f64, lim: &Limits) -> f64 {
    0.5 * (v1 + v2) * (v2 - v1).abs() / lim.a_max
}

pub fn max_entry(length: f64, v_out: f64, lim: &Limits) -> f64 {
    (v_out * v_out + 2.0 * lim.a_max * length.max(0.0)).sqrt()
}

pub fn max_exit(length: f64, v_in: f64, lim: &Limits) -> f64 {
    (v_in * v_in + 2.0 * lim.a_max * length.max(0.0)).sqrt()
}

pub fn plan(req: &BlockRequest) -> Trapezoid {
    let a = req.limits.a_max;
    let l = req.length.max(0.0);
    let (v_in, v_out) = (req.v_in.max(0.0), req.v_out.max(0.0));
    let reach = ramp_distance(v_in, v_out, &req.limits);
    if reach > l {
        // V_Out cannot be reached: one ramp over the whole length, report the speed reached.
        let sign = if v_out > v_in { 1.0 } else { -1.0 };
        let v_end = (v_in * v_in + sign * 2.0 * a * l).max(0.0).sqrt();
        let t1 = (v_end - v_in).abs() / a;
        return if sign > 0.0 {
            Trapezoid {
                v_in,
                v_peak: v_end,
                v_end,
                a_max: a,
                t1,
                t2: 0.0,
                t3: 0.0,
            }
        } else {
            Trapezoid {
                v_in,
                v_peak: v_in,
                v_end,
                a_max: a,
                t1: 0.0,
                t2: 0.0,
                t3: t1,
            }
        };
    }
    let v_feed = req.v_feed.max(v_in).max(v_out);
    // Peak of the triangle through v_in and v_out: L = (2v_p² − v_in² − v_out²)/(2A).
    let v_tri = ((2.0 * a * l + v_in * v_in + v_out * v_out) / 2.0).sqrt();
    let v_peak = v_feed.min(v_tri);
    let t1 = (v_peak - v_in) / a;
    let t3 = (v_peak - v_out) / a;
    let cruise = l - ramp_distance(v_in, v_peak, &req.limits) - ramp_distance(v_peak, v_out, &req.limits);
    let t2 = if v_peak > 0.0 {
        (cruise / v_peak).max(0.0)
    } else {
        0.0
    };
    Trapezoid {
        v_in,
        v_peak,
        v_end: v_out,
        a_max: a,
        t1,
        t2,
        t3,
    }
}

impl FeedLaw for Trapezoid {
    fn duration(&self) -> f64 {
        self.t1 + self.t2 + self.t3
    }
    fn length(&self) -> f64 {
        0.5 * (self.v_in + self.v_peak) * self.t1
            + self.v_peak * self.t2
            + 0.5 * (self.v_peak + self.v_end) * self.t3
    }
    fn v_end(&self) -> f64 {
        self.v_end
    }
    fn at(&self, t: f64) -> Kin {
        let t = t.clamp(0.0, self.duration());
        let a1 = if self.v_peak >= self.v_in {
            self.a_max
        } else {
            -self.a_max
        };
        let a3 = if self.v_end >= self.v_peak {
            self.a_max
        } else {
            -self.a_max
        };
        let s1 = 0.5 * (self.v_in + self.v_peak) * self.t1;
        if t < self.t1 {
            return Kin {
                s: self.v_in * t + 0.5 * a1 * t * t,
                v: self.v_in + a1 * t,
                a: a1,
                j: 0.0,
            };
        }
        let t = t - self.t1;
        if t < self.t2 {
            return Kin {
                s: s1 + self.v_peak * t,
                v: self.v_peak,
                a: 0.0,
                j: 0.0,
            };
        }
        let t = (t - self.t2).min(self.t3);
        let s2 = s1 + self.v_peak * self.t2;
        let a = if t < self.t3 { a3 } else { 0.0 };
        Kin {
            s: s2 + self.v_peak * t + 0.5 * a3 * t * t,
            v: self.v_peak + a3 * t,
            a,
            j: 0.0,
        }
    }
    fn phases(&self) -> Vec<f64> {
        vec![self.t1, self.t2, self.t3]
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn lim() -> Limits {
        Limits {
            v_max: 1.0,
            a_max: 2.0,
            j_max: 60.0,
            snap_max: 6000.0,
        }
    }

    #[test]
    fn rest_to_rest_closed_form() {
        // Triangle: L = v_p²/A with v_p < V_F → t = 2·sqrt(L/A).
        let req = BlockRequest {
            length: 0.004,
            v_in: 0.0,
            v_out: 0.0,
            v_feed: 0.1,
            limits: lim(),
        };
        let p = plan(&req);
        assert!((p.duration() - 2.0 * (0.004f64 / 2.0).sqrt()).abs() < 1e-15);
        // Trapezoid: t = L/V + V/A.
        let req = BlockRequest { length: 0.02, ..req };
        let p = plan(&req);
        assert!((p.duration() - (0.02 / 0.1 + 0.1 / 2.0)).abs() < 1e-15);
        let end = p.at(p.duration());
        assert!((end.s - 0.02).abs() < 1e-15 && end.v.abs() < 1e-15);
    }
}
