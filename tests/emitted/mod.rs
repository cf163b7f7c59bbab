//! What an outsider measures from emitted ticks, shared by the motion test files (`mod emitted;`):
//! computed here, independently of the library's own `interp::Differences`.

/// Per order (velocity, acceleration, jerk) and axis, the largest |backward difference| of the
/// positions `p`, one per period `t` (from the fourth on, so each reaches back to real ticks; a
/// run starting from rest repeats its start before them).
pub fn peak_differences(p: &[[f64; 3]], t: f64) -> [[f64; 3]; 3] {
    let mut peak = [[0.0f64; 3]; 3];
    for i in 0..3 {
        for k in 3..p.len() {
            let v = (p[k][i] - p[k - 1][i]) / t;
            let a = (p[k][i] - 2.0 * p[k - 1][i] + p[k - 2][i]) / (t * t);
            let j = (p[k][i] - 3.0 * p[k - 1][i] + 3.0 * p[k - 2][i] - p[k - 3][i]) / (t * t * t);
            for (order, d) in [v, a, j].into_iter().enumerate() {
                peak[order][i] = peak[order][i].max(d.abs());
            }
        }
    }
    peak
}

/// Every axis's finite-difference velocity, acceleration and jerk within `v`, `a` and `j` (1e-6
/// relative). Two second differences are each a mean of the acceleration, so their difference
/// over T is at most 2A/T: below a 1e9 jerk limit, the bound that means something there.
#[allow(dead_code)] // not every test file that includes the module asserts this
pub fn assert_within(p: &[[f64; 3]], t: f64, v: f64, a: f64, j: f64) {
    let peak = peak_differences(p, t);
    let j = j.min(2.0 * a / t);
    for (order, (name, limit)) in [("v", v), ("a", a), ("j", j)].into_iter().enumerate() {
        for (i, d) in peak[order].into_iter().enumerate() {
            assert!(d <= limit * (1.0 + 1e-6), "axis {i} {name} {d} (limit {limit})");
        }
    }
}
