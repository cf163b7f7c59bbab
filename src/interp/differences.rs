//! Finite differences of emitted positions, starting from rest: what an outsider measures from
//! the ticks. Backward differences of order 1–3 over one interpolation period; a corner mode that
//! steps the acceleration by design (seed 003's acceleration period, seed 004's circular blend)
//! shows its steps here, where the analytic values of the feed law do not.

use crate::Vec3;

/// Units in the last place of the largest |position| that rounding alone can put into a first,
/// second and third difference: the positions carry half an ulp each, weighted 1+1, 1+2+1 and
/// 1+3+3+1, and the products and sums round again (twice that sum, to be safe).
const ROUNDING_ULPS: [f64; 3] = [4.0, 8.0, 16.0];

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

    /// What rounding alone can make of each difference (velocity, acceleration, jerk) over
    /// `period` where no position exceeds `extent` in magnitude: a 60 mm position is good to
    /// 7e-18 m, which a third difference over 1 ms turns into 7e-9 m/s³ per ulp.
    pub fn rounding(extent: f64, period: f64) -> [f64; 3] {
        let ulp = f64::EPSILON * extent.abs();
        let t = period;
        [
            ROUNDING_ULPS[0] * ulp / t,
            ROUNDING_ULPS[1] * ulp / (t * t),
            ROUNDING_ULPS[2] * ulp / (t * t * t),
        ]
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Constant jerk far from the origin (p = x0 + j·t³/6 from rest): every third difference
    /// equals j up to rounding, and `rounding` bounds what rounding does.
    #[test]
    fn rounding_bounds_the_differences_of_a_cubic() {
        let (period, jerk) = (1e-3, 50.0);
        for x0 in [0.0, 0.0625, 0.37, -1.9, 12.5] {
            let at = |n: u32| {
                let t = f64::from(n) * period;
                x0 + jerk * t * t * t / 6.0
            };
            let mut d = Differences::new([at(0); 3], period);
            let extent = at(0).abs().max(at(200).abs());
            let floor = Differences::rounding(extent, period)[2];
            let worst = (1..=200)
                .map(|n| (d.push([at(n); 3]).2[0] - jerk).abs())
                .skip(2) // the first two differences reach back before the start, to rest
                .fold(0.0, f64::max);
            assert!(worst <= floor, "x0 {x0}: {worst} > {floor}");
        }
    }
}
