//! Circular arcs and helices (G2/G3, circular corner blends): exact evaluation w.r.t. arc length
//! and the path limits of seed 004 §2.3–2.4 (eq. 17–24) with the chord-error limit of seed 003.

use super::budget::Budget;
use super::{add, cross, scale, Geo};
use crate::config::Machine;
use crate::feed::bands::{Band, Bands, MAX_BANDS};
use crate::feed::Limits;
use crate::gcode::Plane;
use crate::Vec3;
use serde::{Deserialize, Serialize};
use std::f64::consts::TAU;

/// p(φ) = center + R(cos φ·e1 + sin φ·e2) + rise·φ/sweep·axis, φ ∈ [0, sweep], traversed with
/// φ increasing (e2 is the direction of motion at the start, so CW/CCW is in e2's sign).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Arc {
    pub center: Vec3,
    pub e1: Vec3,
    pub e2: Vec3,
    /// Unit vector along which the helix rises (normal to the plane).
    pub axis: Vec3,
    pub radius: f64,
    /// Swept angle (rad, > 0; full turns included).
    pub sweep: f64,
    /// Displacement along `axis` over the whole arc (helix; 0 for a plane arc).
    pub rise: f64,
    /// Programmed start point, returned exactly by `eval(0)`.
    pub start: Vec3,
    /// Programmed end point, returned exactly by `end()` and by `eval(length)`.
    pub end: Vec3,
}

/// Indices (a, b, n) of a plane: (a, b) in-plane with a × b = n, so G3 turns from a towards b.
pub fn plane_axes(plane: Plane) -> (usize, usize, usize) {
    match plane {
        Plane::XY => (0, 1, 2),
        Plane::XZ => (2, 0, 1),
        Plane::YZ => (1, 2, 0),
    }
}

fn basis(i: usize) -> Vec3 {
    let mut e = [0.0; 3];
    e[i] = 1.0;
    e
}

impl Arc {
    /// G2/G3 from `from` to `to` about `center` in `plane`, plus `turns` extra full turns. The
    /// centre is moved onto the perpendicular bisector of the chord (nearest point to the
    /// programmed one) so start and end lie on one circle and the end is met exactly.
    /// None when the radius is zero.
    pub fn from_gcode(
        from: Vec3,
        to: Vec3,
        center: Vec3,
        plane: Plane,
        clockwise: bool,
        turns: u32,
    ) -> Option<Arc> {
        let (a, b, n) = plane_axes(plane);
        let p0 = [from[a], from[b]];
        let p1 = [to[a], to[b]];
        let mut c = [center[a], center[b]];
        let chord = [p1[0] - p0[0], p1[1] - p0[1]];
        let chord_len = chord[0].hypot(chord[1]);
        if chord_len > 0.0 {
            let mid = [0.5 * (p0[0] + p1[0]), 0.5 * (p0[1] + p1[1])];
            let perp = [-chord[1] / chord_len, chord[0] / chord_len];
            let k = (c[0] - mid[0]) * perp[0] + (c[1] - mid[1]) * perp[1];
            c = [mid[0] + k * perp[0], mid[1] + k * perp[1]];
        }
        let r0 = [p0[0] - c[0], p0[1] - c[1]];
        let r1 = [p1[0] - c[0], p1[1] - c[1]];
        let radius = r0[0].hypot(r0[1]);
        if radius.is_nan() || radius <= 0.0 || !radius.is_finite() {
            return None;
        }
        let ang0 = r0[1].atan2(r0[0]);
        let ang1 = r1[1].atan2(r1[0]);
        let mut sweep = if clockwise { ang0 - ang1 } else { ang1 - ang0 };
        sweep = sweep.rem_euclid(TAU);
        // Same start and end (to rounding): a full circle.
        if chord_len <= 1e-12 * radius || sweep <= 1e-12 {
            sweep = TAU;
        }
        sweep += TAU * turns as f64;
        let (ea, eb, en) = (basis(a), basis(b), basis(n));
        let e1 = add(scale(ea, r0[0] / radius), scale(eb, r0[1] / radius));
        let ccw_dir = cross(en, e1);
        let e2 = if clockwise { scale(ccw_dir, -1.0) } else { ccw_dir };
        let mut center3 = from;
        center3[a] = c[0];
        center3[b] = c[1];
        Some(Arc {
            center: center3,
            e1,
            e2,
            axis: en,
            radius,
            sweep,
            rise: to[n] - from[n],
            start: from,
            end: to,
        })
    }

    /// ds/dφ = sqrt(R² + h²), h = rise per radian.
    fn speed(&self) -> f64 {
        self.radius.hypot(self.rise / self.sweep)
    }

    pub fn length(&self) -> f64 {
        self.sweep * self.speed()
    }

    /// Radius of curvature of the helix, (R² + h²)/R.
    pub fn curvature_radius(&self) -> f64 {
        let k = self.speed();
        k * k / self.radius
    }

    pub fn start(&self) -> Vec3 {
        self.start
    }

    /// Exact derivatives w.r.t. arc length (φ = s/k): d1 = (R·e_θ + h·axis)/k,
    /// d2 = −R·e_r/k², d3 = −R·e_θ/k³, with e_r = cos φ e1 + sin φ e2, e_θ = −sin φ e1 + cos φ e2.
    pub fn eval(&self, s: f64) -> Geo {
        let k = self.speed();
        let h = self.rise / self.sweep;
        let phi = (s / k).clamp(0.0, self.sweep);
        let (sn, cs) = phi.sin_cos();
        let e_r = add(scale(self.e1, cs), scale(self.e2, sn));
        let e_t = add(scale(self.e1, -sn), scale(self.e2, cs));
        let r = self.radius;
        let p = if s >= self.length() {
            self.end
        } else if s <= 0.0 {
            self.start
        } else {
            add(add(self.center, scale(e_r, r)), scale(self.axis, h * phi))
        };
        Geo {
            p,
            d1: scale(add(scale(e_t, r), scale(self.axis, h)), 1.0 / k),
            d2: scale(e_r, -r / (k * k)),
            d3: scale(e_t, -r / (k * k * k)),
        }
    }

    /// Upper bounds over the arc of |d1_i|, |d2_i|, |d3_i| per axis (the in-plane part of axis i
    /// has amplitude sqrt(e1_i² + e2_i²) over a turn).
    pub fn derivative_bounds(&self) -> [Vec3; 3] {
        let k = self.speed();
        let h = self.rise / self.sweep;
        let r = self.radius;
        let mut b = [[0.0; 3]; 3];
        for i in 0..3 {
            let amp = self.e1[i].hypot(self.e2[i]);
            let [d1, d2, d3] = &mut b;
            d1[i] = ((r * amp + (h * self.axis[i]).abs()) / k).min(1.0);
            d2[i] = r * amp / (k * k);
            d3[i] = r * amp / (k * k * k);
        }
        b
    }
}

impl Arc {
    /// Per-axis bounds of |p'|, |p''|, |p'''| on stretches of at most `CELL_ANGLE` of the sweep:
    /// each component is a sinusoid of φ of amplitude R·|(e1_i, e2_i)| (over k, k², k³), so on
    /// [φc − δ, φc + δ] it stays within its value at φc plus the amplitude times δ.
    pub fn cells(&self, mut take: impl FnMut([Vec3; 3])) {
        let k = self.speed();
        let h = self.rise / self.sweep;
        let r = self.radius;
        let n = ((self.sweep / CELL_ANGLE).ceil() as usize).clamp(1, MAX_CELLS);
        let delta = 0.5 * self.sweep / n as f64;
        for c in 0..n {
            let phi = (2 * c + 1) as f64 * delta;
            let (sn, cs) = phi.sin_cos();
            // Per axis (|p'|, |p''|, |p'''|), then as rows of the cell.
            let axis: [[f64; 3]; 3] = std::array::from_fn(|i| {
                let amp = self.e1[i].hypot(self.e2[i]);
                let e_t = (-sn * self.e1[i] + cs * self.e2[i]).abs();
                let e_r = (cs * self.e1[i] + sn * self.e2[i]).abs();
                let grow = amp * delta;
                [
                    ((r * (e_t + grow).min(amp) + (h * self.axis[i]).abs()) / k).min(1.0),
                    r * (e_r + grow).min(amp) / (k * k),
                    r * (e_t + grow).min(amp) / (k * k * k),
                ]
            });
            take(std::array::from_fn(|n| [axis[0][n], axis[1][n], axis[2][n]]));
        }
    }
}

/// Largest stretch of an arc in one cell (rad), and most cells per arc.
const CELL_ANGLE: f64 = std::f64::consts::PI / 16.0;
const MAX_CELLS: usize = 256;

/// Seed 003: the chord of one interpolation period T at speed v deviates from a circle of radius R
/// by δ when v·T = 2·sqrt(δ(2R − δ)), so v ≤ 2·sqrt(δ(2R − δ))/T.
pub fn chord_error_speed(radius: f64, chord_tolerance: f64, period: f64) -> f64 {
    let d = chord_tolerance.min(radius);
    2.0 * (d * (2.0 * radius - d)).sqrt() / period
}

/// Largest constant speed on a curve whose arc-length derivatives are bounded by `bounds` per
/// axis (axis velocity d1·v, acceleration d2·v², jerk d3·v³ at constant speed; eq. 9 is the
/// circle case: sqrt(A·R) and (J·R²)^(1/3)), also within the path-level limits.
pub fn constant_speed_limit(bounds: &[Vec3; 3], machine: &Machine) -> f64 {
    let mut v = machine.max_feed;
    let (mut d2n, mut d3n): (f64, f64) = (0.0, 0.0);
    for (i, ax) in machine.axes.iter().enumerate() {
        let [d1, d2, d3] = [bounds[0][i], bounds[1][i], bounds[2][i]];
        if d1 > 1e-12 {
            v = v.min(ax.max_velocity / d1);
        }
        if d2 > 1e-12 {
            v = v.min((ax.max_acceleration / d2).sqrt());
        }
        if d3 > 1e-12 {
            v = v.min((ax.max_jerk / d3).cbrt());
        }
        d2n = d2n.max(d2);
        d3n = d3n.max(d3);
    }
    if let (Some(a), true) = (machine.max_path_acceleration, d2n > 1e-12) {
        v = v.min((a / d2n).sqrt());
    }
    if let (Some(j), true) = (machine.max_path_jerk, d3n > 1e-12) {
        v = v.min((j / d3n).cbrt());
    }
    v
}

/// Share of the free acceleration and jerk (A_i/|d1_i|, J_i/|d1_i|) that the tangential law keeps
/// on an arc, at least.
const TANGENTIAL_SHARE: f64 = 0.1;

/// Path limits of an arc (seed 004 §2.4). Start from v_max = min(feed limit, chord error (seed
/// 003), sqrt(A_n·ρ), (J_n·ρ²)^(1/3)) with A_n, J_n the axis limits over the in-plane amplitudes
/// (eq. 9 form, ρ the helix's radius of curvature). The curvilinear acceleration follows eq. 23–24
/// with the centripetal term at v_max, A_c = min_i (A_i − |d2_i|·v²)/|d1_i|, and the curvilinear
/// jerk eq. 19–20 with the chain-rule terms, J_c = min_i (J_i − |d3_i|·v³ − 3|d2_i|·v·A_c)/|d1_i|;
/// the paper evaluates them at the arc ends only, we bound them over the whole sweep. A_c is taken
/// no larger than half its free value nor than what leaves the jerk its share; if A_c or J_c
/// would fall below `TANGENTIAL_SHARE` of their free values, v_max is lowered to where they do not.
/// So axis a = d2·v² + d1·a and j = d3·v³ + 3·d2·v·a + d1·j stay within the axis limits for any
/// v ≤ v_max, |a| ≤ A_c, |j| ≤ J_c.
pub fn arc_limits(arc: &Arc, machine: &Machine) -> Limits {
    let shares = Shares {
        a_cap: 0.5,
        tangential: TANGENTIAL_SHARE,
    };
    let mut cells = Vec::new();
    arc.cells(|c| cells.push(c));
    curve_limits(&cells, arc.curvature_radius(), f64::INFINITY, machine, shares)
}

/// How `curve_limits` splits the axis budgets: A_c at most `a_cap` of its free value, and the
/// tangential acceleration and jerk at least `tangential` of theirs.
#[derive(Clone, Copy, Debug)]
pub struct Shares {
    pub a_cap: f64,
    pub tangential: f64,
}

/// Path limits on any curve whose derivatives w.r.t. its parameter are bounded per axis by
/// `b` (|p'|, |p''|, |p'''|), `rho` its smallest radius of curvature (chord error), as described
/// for arcs above, the speed never above `v_cap`. The largest v_max whose budget keeps the
/// tangential shares is solved in closed form (`Budget::max_speed`: each constraint is monotone).
pub fn curve_limits(cells: &[[Vec3; 3]], rho: f64, v_cap: f64, machine: &Machine, shares: Shares) -> Limits {
    let frame = Frame::of(cells, rho, v_cap, machine);
    let (v, (a_c, j_c)) = frame.budget(cells, machine, shares).max_speed(frame.v0);
    Limits {
        v_max: v,
        a_max: a_c,
        j_max: j_c,
        snap_max: machine.max_snap,
    }
}

/// What every budget of a curve starts from: the speed bound without tangential motion (axis
/// limits, chord error, cap) and the free tangential acceleration and jerk A_i/|d1_i|, J_i/|d1_i|.
struct Frame {
    v0: f64,
    a_free: f64,
    j_free: f64,
}

impl Frame {
    fn of(cells: &[[Vec3; 3]], rho: f64, v_cap: f64, machine: &Machine) -> Frame {
        let b = &max_bounds(cells);
        let v0 = constant_speed_limit(b, machine)
            .min(chord_error_speed(
                rho,
                machine.chord_tolerance,
                machine.interpolation_period,
            ))
            .min(v_cap);
        let (mut a_free, mut j_free) = (f64::INFINITY, f64::INFINITY);
        for (i, ax) in machine.axes.iter().enumerate() {
            if b[0][i] > 1e-12 {
                a_free = a_free.min(ax.max_acceleration / b[0][i]);
                j_free = j_free.min(ax.max_jerk / b[0][i]);
            }
        }
        if let Some(a) = machine.max_path_acceleration {
            a_free = a_free.min(a);
        }
        if let Some(j) = machine.max_path_jerk {
            j_free = j_free.min(j);
        }
        Frame { v0, a_free, j_free }
    }

    fn budget<'a>(&self, cells: &'a [[Vec3; 3]], machine: &'a Machine, shares: Shares) -> Budget<'a> {
        Budget {
            cells,
            machine,
            a_cap: shares.a_cap * self.a_free,
            j_free: self.j_free,
            a_min: shares.tangential * self.a_free,
            j_min: shares.tangential * self.j_free,
        }
    }
}

/// A speed above any a curve allows (m/s): where the search for its budget's end starts.
const CURVE_SPEED_CEILING: f64 = 1e4;
/// Band tops lie on one grid of speeds for every curve, q^n m/s (n whole), the `MAX_BANDS`
/// below its top speed: so a higher feed, axis speed or chord tolerance only adds bands above
/// the ones there were (and drops the lowest, 1/q^MAX_BANDS of the top, where the budget is
/// nearly whole).
const BAND_GRID: f64 = 1.259_921_049_894_873_2; // 2^(1/3)
/// Share of the curve's speed limit (its budget's end) that its top speed may reach.
const TOP_SHARE: f64 = 0.985;
/// Share of the jerk a band's pair leaves (of what is left at zero tangential acceleration).
const BAND_JERK_SHARE: f64 = 0.5;

/// The smallest grid speed q^n m/s (n whole) at or above v > 0: by multiplying and dividing from
/// 1 m/s (no logarithm, so every platform's libm gives the same grid).
fn grid_at_or_above(v: f64) -> f64 {
    let mut g = 1.0;
    while g < v {
        g *= BAND_GRID;
    }
    while g / BAND_GRID >= v {
        g /= BAND_GRID;
    }
    g
}

/// Limits and speed bands of a curve (feed/bands.rs). v_0 is where the curve's budget ends: the
/// speed with no tangential acceleration or jerk left (the centripetal and chain-rule terms take
/// the axes' acceleration or jerk). The top speed is `TOP_SHARE` of it, within the caps (axis
/// speeds, chord error, feed); the bands end at the grid speeds below it (`BAND_GRID`). At a
/// speed v the axes leave A(v) = min_i (A_i − |d2_i|·v²)/|d1_i| and, with acceleration a, the
/// jerk J(v, a) = min_i (J_i − |d3_i|·v³ − 3|d2_i|·v·a)/|d1_i|: more acceleration leaves less
/// jerk. A band ending at v reserves the jerk terms of an acceleration a_r that depends on the
/// jerk limits only — the one leaving `BAND_JERK_SHARE` of J(v, 0), and no more than
/// sqrt(2·v·J(v, 0)), about the most a ramp within the band reaches — and takes
/// (min(A(v), a_r), J(v, a_r)): the acceleration grows with every acceleration limit, the jerk
/// with every jerk limit, and the pair holds at every speed up to v (each term grows with v).
/// The top band takes its pair at the next grid speed above the top (or at the top, where the
/// curve itself limits it), so a band's pair does not depend on the caps: a higher cap leaves
/// every band as it was and adds speed above.
pub fn curve_bands(cells: &[[Vec3; 3]], rho: f64, v_cap: f64, machine: &Machine) -> (Limits, Bands) {
    let frame = Frame::of(cells, rho, v_cap, machine);
    let zero = Shares {
        a_cap: 1.0,
        tangential: 0.0,
    };
    let budget = frame.budget(cells, machine, zero);
    let v_zero = budget.max_speed(CURVE_SPEED_CEILING).0;
    let v_capped = budget.max_speed(frame.v0).0;
    let v_curve = TOP_SHARE * v_zero;
    let v_top = v_curve.min(v_capped);
    let pair = |v: f64| {
        let (a_free, j0) = budget.free_at(v);
        let j_share = BAND_JERK_SHARE * j0;
        let a_jerk = budget.acceleration_leaving(v, j_share);
        let a_reach = (2.0 * v * j0.max(0.0)).sqrt();
        // Reserving for a_jerk leaves exactly j_share (its cell binds); for less, what is left.
        let (reserved, j) = if a_jerk <= a_reach {
            (a_jerk, budget.jerk_with(v, a_jerk).max(j_share))
        } else {
            (a_reach, budget.jerk_with(v, a_reach))
        };
        (a_free.min(reserved), j)
    };
    if v_top <= 0.0 || !v_top.is_finite() {
        return (curve_limits(cells, rho, v_cap, machine, zero), Bands::default());
    }
    // The grid speed at or just above the top, and the ones below it.
    let above = grid_at_or_above(v_top);
    let mut levels = Vec::with_capacity(MAX_BANDS);
    let mut v = above;
    for _ in 0..MAX_BANDS {
        v /= BAND_GRID;
        if v < v_top {
            let (a, j) = pair(v);
            levels.push(Band {
                v_top: v,
                a_max: a,
                j_max: j,
            });
        }
    }
    let (a, j) = pair(above.min(v_curve).max(v_top));
    let limits = Limits {
        v_max: v_top,
        a_max: a,
        j_max: j,
        snap_max: machine.max_snap,
    };
    if a <= 0.0 || j <= 0.0 {
        return (curve_limits(cells, rho, v_cap, machine, zero), Bands::default());
    }
    (limits, Bands::below(&limits, &levels))
}

/// Largest per-axis bounds over the cells.
pub fn max_bounds(cells: &[[Vec3; 3]]) -> [Vec3; 3] {
    let mut b = [[0.0f64; 3]; 3];
    for cell in cells {
        for (acc, new) in b.iter_mut().zip(cell) {
            for i in 0..3 {
                acc[i] = acc[i].max(new[i]);
            }
        }
    }
    b
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::path::{dot, norm, sub};

    fn dist(a: Vec3, b: Vec3) -> f64 {
        norm(sub(a, b))
    }
    use std::f64::consts::PI;

    const MM: f64 = 1e-3;

    #[test]
    fn quarter_circle_end_points_and_derivatives() {
        // G3 X0 Y10 from (10, 0) about (0, 0): a quarter circle, R = 10 mm.
        let arc = Arc::from_gcode(
            [10.0 * MM, 0.0, 0.0],
            [0.0, 10.0 * MM, 0.0],
            [0.0; 3],
            Plane::XY,
            false,
            0,
        )
        .unwrap();
        assert!((arc.length() - PI / 2.0 * 10.0 * MM).abs() < 1e-15);
        assert_eq!(arc.eval(arc.length()).p, [0.0, 10.0 * MM, 0.0]);
        assert_eq!(arc.eval(0.0).p, [10.0 * MM, 0.0, 0.0]);
        assert!(dist(arc.eval(1e-15).p, [10.0 * MM, 0.0, 0.0]) < 2e-15);
        // Half way: (R cos 45°, R sin 45°), tangent (−1, 1)/√2, d2 = −e_r/R, d3 = −e_θ/R².
        let g = arc.eval(arc.length() / 2.0);
        let c = (PI / 4.0).cos();
        assert!(dist(g.p, [10.0 * MM * c, 10.0 * MM * c, 0.0]) < 1e-17);
        assert!(dist(g.d1, [-c, c, 0.0]) < 1e-15);
        let r = 10.0 * MM;
        assert!(dist(g.d2, [-c / r, -c / r, 0.0]) < 1e-12);
        assert!(dist(g.d3, [c / (r * r), -c / (r * r), 0.0]) < 1e-9);
        // G2 the other way round: three quarters of the circle, clockwise.
        let cw = Arc::from_gcode(
            [10.0 * MM, 0.0, 0.0],
            [0.0, 10.0 * MM, 0.0],
            [0.0; 3],
            Plane::XY,
            true,
            0,
        )
        .unwrap();
        assert!((cw.length() - 1.5 * PI * r).abs() < 1e-15);
        let g = cw.eval(0.0);
        assert!(dist(g.d1, [0.0, -1.0, 0.0]) < 1e-15);
        let g = cw.eval(cw.length() / 3.0);
        assert!(dist(g.p, [0.0, -r, 0.0]) < 1e-17);
    }

    #[test]
    fn helix_length_and_frame() {
        // Full turn + 1 extra (P2 style: turns = 1) rising 4 mm in G17: length = sqrt((2πR·n)² + H²).
        let r = 5.0 * MM;
        let from = [r, 0.0, 0.0];
        let to = [r, 0.0, 4.0 * MM];
        let arc = Arc::from_gcode(from, to, [0.0; 3], Plane::XY, false, 1).unwrap();
        let expected = ((2.0 * TAU * r).powi(2) + (4.0 * MM).powi(2)).sqrt();
        assert!((arc.length() - expected).abs() < 1e-15);
        assert_eq!(arc.eval(arc.length()).p, to);
        let k = arc.length() / (2.0 * TAU);
        let h = 4.0 * MM / (2.0 * TAU);
        for i in 0..=20 {
            let s = arc.length() * i as f64 / 20.0;
            let g = arc.eval(s);
            assert!((norm(g.d1) - 1.0).abs() < 1e-14);
            // Curvature of a helix R/(R² + h²), d2 ⟂ d1, |d3| = R/k³ (κ·τ-free: constant curvature).
            assert!((norm(g.d2) - r / (k * k)).abs() < 1e-9);
            assert!(dot(g.d1, g.d2).abs() < 1e-9);
            assert!((norm(g.d3) - r / (k * k * k)).abs() < 1e-6);
            // Rises linearly with arc length.
            assert!((g.p[2] - h * s / k).abs() < 1e-15);
            // Finite differences agree with d1 and d2.
            if i > 0 && i < 20 {
                let e = 1e-6;
                let (a, c) = (arc.eval(s - e), arc.eval(s + e));
                let fd1 = scale(sub(c.p, a.p), 0.5 / e);
                assert!(dist(fd1, g.d1) < 1e-6);
                let fd2 = scale(sub(c.d1, a.d1), 0.5 / e);
                assert!(dist(fd2, g.d2) < 1e-3 * norm(g.d2));
                let fd3 = scale(sub(c.d2, a.d2), 0.5 / e);
                assert!(dist(fd3, g.d3) < 1e-3 * norm(g.d3));
            }
        }
    }

    #[test]
    fn planes_g18_g19() {
        // G18 G3 from X10 to Z10 about the origin: Z × X = Y, so CCW turns from Z towards X.
        let r = 10.0 * MM;
        let arc = Arc::from_gcode([0.0, 0.0, r], [r, 0.0, 0.0], [0.0; 3], Plane::XZ, false, 0).unwrap();
        assert!((arc.length() - PI / 2.0 * r).abs() < 1e-15);
        let arc = Arc::from_gcode([0.0, r, 0.0], [0.0, 0.0, r], [0.0; 3], Plane::YZ, false, 0).unwrap();
        assert!((arc.length() - PI / 2.0 * r).abs() < 1e-15);
        // Off-bisector centre is projected: both radii equal, end exact.
        let arc = Arc::from_gcode(
            [r, 0.0, 0.0],
            [0.0, r, 0.0],
            [1e-6, 0.0, 0.0],
            Plane::XY,
            false,
            0,
        )
        .unwrap();
        assert_eq!(arc.eval(arc.length()).p, [0.0, r, 0.0]);
        assert_eq!(arc.eval(0.0).p, [r, 0.0, 0.0]);
        assert!(dist(add(arc.center, scale(arc.e1, arc.radius)), [r, 0.0, 0.0]) < 1e-17);
        // The centre moved to (5e-7, 5e-7) on the bisector: both ends on one circle.
        assert!(dist(arc.center, [5e-7, 5e-7, 0.0]) < 1e-18);
        assert!((dist(arc.center, [0.0, r, 0.0]) - arc.radius).abs() < 1e-17);
        let p = arc.eval(arc.length() * (1.0 - 1e-12)).p;
        assert!(dist(p, [0.0, r, 0.0]) < 1e-12);
    }

    #[test]
    fn chord_error_limit_r10_delta1um() {
        // Seed 003: v = 2·sqrt(δ(2R − δ))/T, R = 10 mm, δ = 1 µm, T = 1 ms → 0.28283 m/s.
        let v = chord_error_speed(10.0 * MM, 1e-6, 1e-3);
        let expected = 2.0 * (1e-6f64 * (20.0e-3 - 1e-6)).sqrt() / 1e-3;
        assert!((v - expected).abs() < 1e-15);
        assert!((v - 0.282_835).abs() < 1e-6);
        // The chord of one period at that speed deviates from the arc by exactly δ.
        let r = 10.0 * MM;
        let half = v * 1e-3 / 2.0;
        let sagitta = r - (r * r - half * half).sqrt();
        assert!((sagitta - 1e-6).abs() < 1e-12);
    }

    #[test]
    fn arc_limits_keep_axis_limits() {
        let m = Machine::default();
        for r_mm in [0.5, 2.0, 10.0, 100.0] {
            let r = r_mm * MM;
            let arc = Arc::from_gcode([r, 0.0, 0.0], [-r, 0.0, 0.0], [0.0; 3], Plane::XY, false, 0).unwrap();
            let lim = arc_limits(&arc, &m);
            let v = lim.v_max;
            // eq. 9 bounds and the chord limit hold.
            assert!(v <= (2.0 * r).sqrt() + 1e-12);
            assert!(v <= (50.0 * r * r).cbrt() + 1e-12);
            assert!(v <= chord_error_speed(r, m.chord_tolerance, m.interpolation_period) + 1e-12);
            assert!(lim.a_max > 0.0 && lim.j_max > 0.0);
            // Worst case of the chain rule over the arc, with the tangential law at its limits.
            for i in 0..=64 {
                let g = arc.eval(arc.length() * i as f64 / 64.0);
                for (ax, axis) in m.axes.iter().enumerate() {
                    let acc = g.d2[ax].abs() * v * v + g.d1[ax].abs() * lim.a_max;
                    let jerk = g.d3[ax].abs() * v.powi(3)
                        + 3.0 * g.d2[ax].abs() * v * lim.a_max
                        + g.d1[ax].abs() * lim.j_max;
                    assert!(acc <= axis.max_acceleration * (1.0 + 1e-9), "r {r_mm} acc {acc}");
                    assert!(jerk <= axis.max_jerk * (1.0 + 1e-9), "r {r_mm} jerk {jerk}");
                }
            }
        }
    }
}
