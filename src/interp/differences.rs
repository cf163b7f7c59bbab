//! Finite differences of emitted positions, starting from rest: what an outsider measures from
//! the ticks. Backward differences of order 1–3 over one interpolation period; a corner mode that
//! steps the acceleration by design (seed 003's acceleration period, seed 004's circular blend)
//! shows its steps here, where the analytic values of the feed law do not.

use crate::Vec3;

#[derive(Clone, Debug)]
pub struct Differences {
    period: f64,
    /// The last three positions, newest last.
    p: [Vec3; 3],
}

impl Differences {
    /// Start at rest at `start`.
    pub fn new(start: Vec3, period: f64) -> Differences {
        Differences {
            period,
            p: [start; 3],
        }
    }

    /// Take the next position; velocity, acceleration and jerk per axis.
    pub fn push(&mut self, q: Vec3) -> (Vec3, Vec3, Vec3) {
        let t = self.period;
        let [p3, p2, p1] = self.p;
        let mut out = ([0.0; 3], [0.0; 3], [0.0; 3]);
        for i in 0..3 {
            out.0[i] = (q[i] - p1[i]) / t;
            out.1[i] = (q[i] - 2.0 * p1[i] + p2[i]) / (t * t);
            out.2[i] = (q[i] - 3.0 * p1[i] + 3.0 * p2[i] - p3[i]) / (t * t * t);
        }
        self.p = [p2, p1, q];
        out
    }
}
