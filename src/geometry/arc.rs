//! Circular arcs and helices (G2/G3, circular corner blends): exact evaluation w.r.t. arc length
//! and bounds of the derivatives per axis (the path stage projects the axis limits through them).

use super::{add, basis, cross, dot, scale, sub, Geo, Plane, Vec3};
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
        if !plane.principal() {
            return Arc::turned(from, to, center, plane, clockwise, turns);
        }
        let (a, b, n) = plane.axes();
        let p0 = [from[a], from[b]];
        let p1 = [to[a], to[b]];
        let c = [center[a], center[b]];
        let (ea, eb, en) = (basis(a), basis(b), basis(n));
        let (mut arc, c) = Arc::in_plane([p0, p1, c], [ea, eb, en], clockwise, turns)?;
        arc.center = from;
        (arc.center[a], arc.center[b]) = (c[0], c[1]);
        arc.finish(from, to, to[n] - from[n])
    }

    /// `from_gcode` in a plane that is not one of the machine's (G18/G19 of a rotated system):
    /// in-plane coordinates relative to `from` along the plane's turned axes.
    fn turned(from: Vec3, to: Vec3, center: Vec3, plane: Plane, clockwise: bool, turns: u32) -> Option<Arc> {
        let (ea, eb, en) = plane.basis();
        let rel = |p: Vec3| {
            let d = [p[0] - from[0], p[1] - from[1], p[2] - from[2]];
            [dot(d, ea), dot(d, eb)]
        };
        let (mut arc, c) = Arc::in_plane([[0.0; 2], rel(to), rel(center)], [ea, eb, en], clockwise, turns)?;
        arc.center = add(from, add(scale(ea, c[0]), scale(eb, c[1])));
        let rise = dot([to[0] - from[0], to[1] - from[1], to[2] - from[2]], en);
        arc.finish(from, to, rise)
    }

    /// The arc from in-plane start `p0` to end `p1` about (nearly) `c` in the plane of unit
    /// axes `[ea, eb, en]`, and its in-plane centre; its centre, start, end and rise are set by
    /// the caller.
    fn in_plane(
        [p0, p1, mut c]: [[f64; 2]; 3],
        [ea, eb, en]: [Vec3; 3],
        clockwise: bool,
        turns: u32,
    ) -> Option<(Arc, [f64; 2])> {
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
        if chord_len <= FULL_CIRCLE * radius || sweep <= FULL_CIRCLE {
            sweep = TAU;
        }
        sweep += TAU * turns as f64;
        let e1 = add(scale(ea, r0[0] / radius), scale(eb, r0[1] / radius));
        let ccw_dir = cross(en, e1);
        let e2 = if clockwise { scale(ccw_dir, -1.0) } else { ccw_dir };
        let arc = Arc {
            center: [0.0; 3],
            e1,
            e2,
            axis: en,
            radius,
            sweep,
            rise: 0.0,
            start: [0.0; 3],
            end: [0.0; 3],
        };
        Some((arc, c))
    }

    /// The programmed start and end (met exactly) and the rise along the normal.
    fn finish(mut self, from: Vec3, to: Vec3, rise: f64) -> Option<Arc> {
        (self.start, self.end, self.rise) = (from, to, rise);
        Some(self)
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
        self.eval_at_speed(self.speed(), s)
    }

    /// s clamped to [0, length] and the point there, with the one `hypot` they share (the
    /// interpolator's tick).
    pub fn eval_clamped(&self, s: f64) -> (f64, Geo) {
        let k = self.speed();
        let s = s.clamp(0.0, self.sweep * k);
        (s, self.eval_at_speed(k, s))
    }

    /// `eval` given ds/dφ (`speed`), which `length` multiplies by the sweep.
    fn eval_at_speed(&self, k: f64, s: f64) -> Geo {
        let h = self.rise / self.sweep;
        let phi = (s / k).clamp(0.0, self.sweep);
        let (sn, cs) = phi.sin_cos();
        let e_r = add(scale(self.e1, cs), scale(self.e2, sn));
        let e_t = add(scale(self.e1, -sn), scale(self.e2, cs));
        let r = self.radius;
        let p = if s >= self.sweep * k {
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

/// A point seen from an arc's axis (`Arc::at_angle`): its coordinates along e1, e2 and the axis,
/// its distance ρ from the axis, and, of the arc's turns at the point's own angle, the nearest:
/// its angle from the start (at most the sweep) and its distance hypot(ρ − R, z − h·angle), h
/// the rise per radian (None where no turn of the arc reaches that angle).
#[derive(Clone, Copy, Debug)]
pub struct AtAngle {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub rho: f64,
    pub turn: Option<(f64, f64)>,
}

impl Arc {
    /// Where `p` lies about the arc's axis, and the arc's nearest point at its angle (`AtAngle`):
    /// the distance from the arc where its foot is not an end (`Source::distance`).
    pub fn at_angle(&self, p: Vec3) -> AtAngle {
        let (x, y, z) = self.about_axis(p);
        let rho = x.hypot(y);
        let turn = self.nearest_turn(x, y, z, rho);
        AtAngle { x, y, z, rho, turn }
    }

    /// `at_angle(p).turn`'s distance alone (`Source::distance`).
    pub fn distance_at_angle(&self, p: Vec3) -> Option<f64> {
        let (x, y, z) = self.about_axis(p);
        self.nearest_turn(x, y, z, x.hypot(y)).map(|(_, d)| d)
    }

    /// Whether `distance_at_angle(p)` is certainly at most `bound`, told without its `atan2`
    /// and `hypot`, for a point ahead of the start by less than a quarter turn (x > 0, y ≥ 0):
    /// its angle atan(t), t = y/x, lies in [t − t³/3, t], and the distance at that angle,
    /// hypot(ρ − R, z − h·φ), is linear in φ under the root. `BOUND_MARGIN` covers the rounding
    /// of both ways (the libm's `atan2` and `hypot` are within an ulp or two). False where it
    /// cannot tell.
    pub fn at_angle_at_most(&self, p: Vec3, bound: f64) -> bool {
        let (x, y, z) = self.about_axis(p);
        if !(x > 0.0 && y >= 0.0) {
            return false;
        }
        let k = BOUND_MARGIN;
        let t = y / x;
        let (lo, hi) = (t - t * t * t / 3.0 - k * t, t + k * t);
        let h = self.rise / self.sweep;
        let rho = (x * x + y * y).sqrt();
        let radial = (rho - self.radius).abs() + k * (rho + self.radius);
        let along = (z - h * lo).abs().max((z - h * hi).abs()) + k * (z.abs() + h.abs() * hi);
        // The angle within the sweep: the first turn is among those measured.
        hi <= self.sweep && (radial * radial + along * along).sqrt() * (1.0 + k) <= bound
    }

    /// The coordinates of `p` along e1, e2 and the axis.
    fn about_axis(&self, p: Vec3) -> (f64, f64, f64) {
        let rel = sub(p, self.center);
        (dot(rel, self.e1), dot(rel, self.e2), dot(rel, self.axis))
    }

    /// `AtAngle::turn` of the point at (x, y, z) about the axis, ρ from it.
    fn nearest_turn(&self, x: f64, y: f64, z: f64, rho: f64) -> Option<(f64, f64)> {
        // atan2 lies in [−π, π], where `rem_euclid(TAU)` is this (its fmod returns |phi| < TAU
        // as is).
        let phi = y.atan2(x);
        let phi = if phi < 0.0 { phi + TAU } else { phi };
        let h = self.rise / self.sweep;
        let radial = rho - self.radius;
        let turn_at = |k: usize| phi + TAU * k as f64;
        let distance_at = |f: f64| (f, radial.hypot(z - h * f));
        let turns = self.sweep / TAU;
        // Less than a full turn (all arcs but full circles): the first turn alone, which is what
        // the search over the turns below takes from one.
        if turns < 1.0 || turns.is_nan() {
            return Some(turn_at(0)).filter(|&f| f <= self.sweep).map(distance_at);
        }
        (0..=(turns.floor() as usize).min(64))
            .map(turn_at)
            .filter(|&f| f <= self.sweep)
            .map(distance_at)
            .min_by(|a, b| a.1.total_cmp(&b.1))
    }

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

/// An arc whose chord is at most this share of its radius, or whose sweep is at most this (rad),
/// ends where it starts: a full circle (G2/G3 with the end at the start).
const FULL_CIRCLE: f64 = 1e-12;
/// Relative margin of `Arc::at_angle_at_most` over the rounding (about 1e-16 a step): far
/// below any tolerance's share, far above rounding.
const BOUND_MARGIN: f64 = 1e-12;
/// Largest stretch of an arc in one cell (rad), and most cells per arc.
const CELL_ANGLE: f64 = std::f64::consts::PI / 16.0;
const MAX_CELLS: usize = 256;

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{dot, norm, sub};

    fn dist(a: Vec3, b: Vec3) -> f64 {
        norm(sub(a, b))
    }
    use std::f64::consts::PI;

    use crate::si::MM;

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

    /// The bound without `atan2` and `hypot` never says a point is nearer than
    /// `distance_at_angle` measures (at bounds 1e-6 below it, at it and 1e-12 above it), on
    /// 200 000 points up to 0.2 rad ahead of the starts of random arcs and helices (up to three
    /// turns), and it tells two thirds of them within 1.1 times their distance.
    #[test]
    fn the_bound_at_the_start_is_never_below_the_distance() {
        use crate::test_rng::unit;
        let mut s = 0x51_7cc1_b727_220au64;
        let (mut told, mut clear) = (0, 0);
        for case in 0..2000 {
            let r = 1e-3 * 10f64.powf(2.0 * unit(&mut s));
            let center = [unit(&mut s), unit(&mut s), unit(&mut s)];
            let start = add(center, [r, 0.0, 0.0]);
            let angle = 0.05 + 6.0 * unit(&mut s);
            let end = add(
                center,
                [r * angle.cos(), r * angle.sin(), r * (unit(&mut s) - 0.5)],
            );
            let cw = case % 2 == 0;
            let Some(arc) = Arc::from_gcode(start, end, center, Plane::XY, cw, case % 3) else {
                continue;
            };
            for _ in 0..100 {
                let at = arc.eval(0.2 * r * unit(&mut s)).p;
                let off = 1e-5 * r * 10f64.powf(3.0 * unit(&mut s));
                let p = add(
                    at,
                    [
                        off * (unit(&mut s) - 0.5),
                        off * (unit(&mut s) - 0.5),
                        off * (unit(&mut s) - 0.5),
                    ],
                );
                let Some(d) = arc.distance_at_angle(p) else {
                    continue;
                };
                for bound in [d * (1.0 - 1e-6), d, d * (1.0 + 1e-12)] {
                    assert!(
                        !arc.at_angle_at_most(p, bound) || d <= bound,
                        "case {case}: {d:e} above {bound:e}"
                    );
                }
                told += 1;
                clear += usize::from(arc.at_angle_at_most(p, 1.1 * d));
            }
        }
        assert!(told > 150_000 && clear > told * 2 / 3, "{clear} of {told} told");
    }
}
