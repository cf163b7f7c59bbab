//! Straight lines: evaluation by arc length, the programmed end exact.

use super::{add, norm, scale, sub, Geo, Vec3};
use serde::{Deserialize, Serialize};

/// Straight line from `start` to `end`.
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Line {
    pub start: Vec3,
    pub end: Vec3,
}

impl Line {
    pub fn length(&self) -> f64 {
        norm(sub(self.end, self.start))
    }
    /// Unit direction (zero for a zero-length line).
    pub fn direction(&self) -> Vec3 {
        let l = self.length();
        if l > 0.0 {
            scale(sub(self.end, self.start), 1.0 / l)
        } else {
            [0.0; 3]
        }
    }
    /// Point at arc length s; s ≥ length gives the programmed end exactly.
    pub fn eval(&self, s: f64) -> Geo {
        // `direction` and `length` with the one square root they share.
        let d = sub(self.end, self.start);
        let l = norm(d);
        let u = if l > 0.0 { scale(d, 1.0 / l) } else { [0.0; 3] };
        let p = if s >= l {
            self.end
        } else {
            add(self.start, scale(u, s))
        };
        Geo {
            p,
            d1: u,
            ..Geo::default()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn line_end_is_exact() {
        let l = Line {
            start: [0.1, 0.2, 0.3],
            end: [0.7, -0.1, 0.05],
        };
        assert_eq!(l.eval(l.length()).p, l.end);
        assert!((norm(l.eval(0.3).d1) - 1.0).abs() < 1e-15);
    }
}
