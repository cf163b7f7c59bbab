//! Corner rules between two segments: seed 003 corner feed, seed 004 eq. 8–9 circular blend,
//! eq. 10 curvature-change speed at tangent junctions, and the quintic transition (blend.rs).

use super::arc::{chord_error_speed, constant_speed_limit};
use super::tolerance::{COLLINEAR_EPS, NEGLIGIBLE, REVERSAL_COS};
use super::{arc_limits, line_limits, PathBlock, Segment};
use crate::config::{CornerMode, Machine};
#[cfg(test)]
use crate::geometry::norm;
use crate::geometry::Arc;
use crate::geometry::{add, cross, dot, scale, sub, unit};
use crate::Vec3;

/// Seed 003: at a corner of turning angle θ (between the two directions), each axis may change
/// its speed by A·T within one interpolation period T, giving F_c = A·T/(1 − cos θ); the smallest
/// over the axes that move on either side. θ = 90° → F_c = A·T.
pub fn corner_feed(d_in: Vec3, d_out: Vec3, machine: &Machine) -> f64 {
    let one_minus_cos = 1.0 - dot(d_in, d_out).clamp(-1.0, 1.0);
    if one_minus_cos <= COLLINEAR_EPS {
        return f64::INFINITY;
    }
    let mut f = f64::INFINITY;
    for (i, ax) in machine.axes.iter().enumerate() {
        if d_in[i].abs() > NEGLIGIBLE || d_out[i].abs() > NEGLIGIBLE {
            f = f.min(ax.max_acceleration * machine.interpolation_period / one_minus_cos);
        }
    }
    f
}

/// Seed 004 eq. 10 (Pateloup): at a tangent junction whose curvature jumps by Δκ, the centripetal
/// acceleration jumps by v²·Δκ within one period δt: v²·|Δκ| ≤ δt·j. (The printed eq. 10,
/// V = sqrt(R1R2/(|R1 − R2| δt j)), is not a speed dimensionally; this is its intended form,
/// V = sqrt(R1R2·δt·j/|R1 − R2|).) We apply it per axis to the vector jump `dk` of d2 (so S-bends
/// count both curvatures), with the jerk `step_jerk` each axis may spend on the step.
pub fn curvature_change_speed(dk: Vec3, step_jerk: Vec3, period: f64) -> f64 {
    let mut v2 = f64::INFINITY;
    for i in 0..3 {
        if dk[i].abs() > NEGLIGIBLE {
            v2 = v2.min(step_jerk[i].max(0.0) * period / dk[i].abs());
        }
    }
    v2.sqrt()
}

/// Share of the axis jerk left to the blocks on both sides of a curvature step in the
/// `polynomial` mode (the rest goes to the step).
pub const STEP_NEIGHBOUR_JERK: f64 = 0.5;

/// The jerk per axis that eq. 10's acceleration step may use: J_c of seed 004 Table 1 (the jerk on
/// passage of a discontinuity in curvature, `max_transition_jerk`) where set, else the axis jerk J.
/// Where the axis jerk must hold as the emitted positions show it (`keeps_jerk`, the `polynomial`
/// mode), the step shares it with the blocks on both sides: a step Δa between two ticks adds at
/// most ¾·Δa/T to a third difference of the positions (the weights of the quadratic B-spline of
/// 3 ticks, largest ¾), the blocks add their own jerk, at most `STEP_NEIGHBOUR_JERK`·J with eased
/// limits (`eased`): ¾·Δa/T ≤ J_c − ½·J. Elsewhere (modes that step by design) half of J_c, as
/// before, the other half for the tangential acceleration's change.
pub fn step_jerk(machine: &Machine, keeps_jerk: bool) -> Vec3 {
    let mut j = [0.0; 3];
    for (ji, ax) in j.iter_mut().zip(&machine.axes) {
        let jc = machine.max_transition_jerk.unwrap_or(ax.max_jerk);
        *ji = if keeps_jerk {
            4.0 / 3.0 * (jc - STEP_NEIGHBOUR_JERK * ax.max_jerk)
        } else {
            0.5 * jc
        };
    }
    j
}

/// The machine of the blocks next to a curvature step in the `polynomial` mode: every axis jerk
/// at `STEP_NEIGHBOUR_JERK` of its own (see `step_jerk`).
pub fn eased(machine: &Machine) -> Machine {
    let mut m = machine.clone();
    for a in &mut m.axes {
        a.max_jerk *= STEP_NEIGHBOUR_JERK;
    }
    m
}

/// The junction speed at a tangent junction whose second derivative jumps by `dk` (eq. 10); in
/// the `polynomial` mode the blocks on both sides get the eased limits that keep the axis jerk
/// (`step_jerk`).
pub(super) fn tangent_junction(dk: Vec3, held: &mut PathBlock, next: &mut PathBlock, m: &Machine) -> f64 {
    let keeps_jerk = m.corner == CornerMode::Polynomial;
    let v = curvature_change_speed(dk, step_jerk(m, keeps_jerk), m.interpolation_period);
    if keeps_jerk && v > 0.0 && dk != [0.0; 3] {
        let eased = eased(m);
        ease(held, &eased);
        ease(next, &eased);
    }
    v
}

/// Limits a line can stop with whatever comes after it: in the `polynomial` mode those it gets
/// if a curvature step follows (`ease`).
pub(super) fn stop_limits(line: &PathBlock, m: &Machine) -> crate::feed::Limits {
    match (&line.segment, m.corner) {
        (Segment::Line(l), CornerMode::Polynomial) => line_limits(l.direction(), &eased(m)),
        _ => line.limits,
    }
}

/// New limits for a block next to a curvature step of the polynomial mode (`eased`).
fn ease(block: &mut PathBlock, eased: &Machine) {
    block.limits = match &block.segment {
        Segment::Line(l) => line_limits(l.direction(), eased),
        Segment::Arc(a) => arc_limits(a, eased),
        _ => return,
    };
    block.v_feed = block.v_feed.min(block.limits.v_max);
}

/// Seed 004 eq. 8: the arc tangent to both lines whose middle passes `tolerance` (TIT) from the
/// corner has R = TIT·cos(β/2)/(1 − cos(β/2)), β the turning angle; it meets each line at
/// R·tan(β/2) from the corner, which must not exceed `max_cut` (half of the shorter line, our form
/// of the paper's second term), so R ≤ max_cut/tan(β/2).
pub fn circular_blend(corner: Vec3, d_in: Vec3, d_out: Vec3, tolerance: f64, max_cut: f64) -> Option<Arc> {
    let c = dot(d_in, d_out).clamp(-1.0, 1.0);
    if 1.0 - c <= COLLINEAR_EPS
        || c < REVERSAL_COS
        || tolerance.is_nan()
        || tolerance <= 0.0
        || max_cut.is_nan()
        || max_cut <= 0.0
    {
        return None;
    }
    let beta = c.acos();
    let (ch, th) = ((beta / 2.0).cos(), (beta / 2.0).tan());
    let radius = (tolerance * ch / (1.0 - ch)).min(max_cut / th);
    let cut = radius * th;
    let start = sub(corner, scale(d_in, cut));
    // Inward normal: the part of d_out normal to d_in.
    let n = unit(sub(d_out, scale(d_in, c)));
    let center = add(start, scale(n, radius));
    let e1 = scale(n, -1.0);
    Some(Arc {
        center,
        e1,
        e2: d_in,
        axis: unit(cross(e1, d_in)),
        radius,
        sweep: beta,
        rise: 0.0,
        start,
        end: add(corner, scale(d_out, cut)),
    })
}

/// Constant speed of a circular blend: eq. 9 projected on the axes (A_i and J_i over the in-plane
/// amplitudes), with the chord-error limit of seed 003.
pub fn circular_blend_speed(arc: &Arc, machine: &Machine) -> f64 {
    let v = constant_speed_limit(&arc.derivative_bounds(), machine);
    v.min(chord_error_speed(
        arc.radius,
        machine.chord_tolerance,
        machine.interpolation_period,
    ))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::path::Segment;

    use crate::si::MM;

    #[test]
    fn corner_feed_90_degrees_is_a_t() {
        let m = Machine::default();
        let f = corner_feed([1.0, 0.0, 0.0], [0.0, 1.0, 0.0], &m);
        // A = 2 m/s², T = 1 ms → F_c = 2 mm/s.
        assert!((f - 2.0 * 1e-3).abs() < 1e-15);
        // 60°: 1 − cos θ = 1/2 → 2·A·T.
        let th = 60f64.to_radians();
        let f = corner_feed([1.0, 0.0, 0.0], [th.cos(), th.sin(), 0.0], &m);
        assert!((f - 4.0e-3).abs() < 1e-12);
        assert_eq!(corner_feed([1.0, 0.0, 0.0], [1.0, 0.0, 0.0], &m), f64::INFINITY);
    }

    #[test]
    fn circular_blend_eq8() {
        let tol = 0.01 * MM;
        let corner = [5.0 * MM, 0.0, 0.0];
        let arc = circular_blend(corner, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], tol, 1.0).unwrap();
        // β = 90°: R = TIT·cos45°/(1 − cos45°), middle of the arc at TIT from the corner.
        let c = (std::f64::consts::FRAC_PI_4).cos();
        assert!((arc.radius - tol * c / (1.0 - c)).abs() < 1e-18);
        let seg = Segment::Arc(arc);
        let mid = seg.eval(seg.length() / 2.0).p;
        assert!((norm(sub(mid, corner)) - tol).abs() < 1e-15);
        // Tangent to both lines at its ends, and meets them.
        let g0 = seg.eval(0.0);
        let g1 = seg.eval(seg.length());
        assert!(norm(sub(g0.d1, [1.0, 0.0, 0.0])) < 1e-15);
        assert!(norm(sub(g1.d1, [0.0, 1.0, 0.0])) < 1e-15);
        assert!(g0.p[1].abs() < 1e-18 && (g1.p[0] - corner[0]).abs() < 1e-18);
        assert!(norm(sub(add(arc.center, scale(arc.e1, arc.radius)), g0.p)) < 1e-18);
        // Capped by the line length: the cut is max_cut.
        let arc = circular_blend(corner, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], 1.0, 2.0 * MM).unwrap();
        assert!((norm(sub(arc.end, corner)) - 2.0 * MM).abs() < 1e-15);
        // Speed: eq. 9, sqrt(A·R) and (J·R²)^(1/3) with axis limits.
        let m = Machine::default();
        let arc = circular_blend(corner, [1.0, 0.0, 0.0], [0.0, 1.0, 0.0], tol, 1.0).unwrap();
        let v = circular_blend_speed(&arc, &m);
        let r = arc.radius;
        let expect = (2.0 * r).sqrt().min((50.0 * r * r).cbrt()).min(m.max_feed);
        assert!((v - expect.min(chord_error_speed(r, m.chord_tolerance, 1e-3))).abs() < 1e-12);
    }

    #[test]
    fn eq10_line_to_arc() {
        // Line into a tangent R = 10 mm arc: v = sqrt(½·δt·j·R) = sqrt(0.5·0.001·50·0.01).
        let m = Machine::default();
        let v = curvature_change_speed([0.0, 100.0, 0.0], step_jerk(&m, false), 1e-3);
        assert!((v - (0.5 * 0.001 * 50.0 * 0.01f64).sqrt()).abs() < 1e-12);
        // R1 = 10, R2 = 20 mm, same side: R1R2/|R1 − R2| = 20 mm.
        let v = curvature_change_speed([0.0, 100.0 - 50.0, 0.0], step_jerk(&m, false), 1e-3);
        assert!((v - (0.5 * 0.001 * 50.0 * 0.02f64).sqrt()).abs() < 1e-12);
        // Keeping the jerk: ¾·v²κ/δt + ½·j ≤ j, so v² = (2/3)·δt·j·R.
        let v = curvature_change_speed([0.0, 100.0, 0.0], step_jerk(&m, true), 1e-3);
        assert!((v - (2.0 / 3.0 * 0.001 * 50.0 * 0.01f64).sqrt()).abs() < 1e-12);
        // With seed 004's J_c = 60 m/s³ on a 40 m/s³ axis: ¾·v²κ/δt ≤ 60 − 20.
        let jc = Machine {
            max_transition_jerk: Some(60.0),
            axes: [crate::config::AxisLimits {
                max_jerk: 40.0,
                ..m.axes[0]
            }; 3],
            ..Machine::default()
        };
        let v = curvature_change_speed([0.0, 100.0, 0.0], step_jerk(&jc, true), 2e-3);
        assert!((v - (4.0 / 3.0 * 40.0 * 0.002 * 0.01f64).sqrt()).abs() < 1e-12);
    }
}
