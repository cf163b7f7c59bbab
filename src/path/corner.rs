//! Corner rules between two segments: seed 003 corner feed, seed 004 eq. 8–9 circular blend,
//! eq. 10 curvature-change speed at tangent junctions, and the quintic transition (blend.rs).

use super::arc::{chord_error_speed, constant_speed_limit, Arc};
#[cfg(test)]
use super::norm;
use super::{add, cross, dot, scale, sub, unit};
use crate::config::Machine;
use crate::Vec3;

/// Turns sharper than this (cos of the turning angle below it) stop exactly: the transition
/// would be a near-cusp whose speed limit is practically zero anyway.
pub const REVERSAL_COS: f64 = -0.996;
/// Directions closer than this (1 − cos θ) are one direction: no corner.
pub const COLLINEAR_EPS: f64 = 1e-12;
/// Tangent-continuous junction (1 − cos θ) involving arcs.
pub const TANGENT_EPS: f64 = 1e-9;

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
        if d_in[i].abs() > 1e-12 || d_out[i].abs() > 1e-12 {
            f = f.min(ax.max_acceleration * machine.interpolation_period / one_minus_cos);
        }
    }
    f
}

/// Seed 004 eq. 10 (Pateloup): at a tangent junction whose curvature jumps by Δκ, the centripetal
/// acceleration jumps by v²·Δκ within one period δt, which the axis jerk must allow:
/// v²·|Δκ| ≤ δt·j. (The printed eq. 10, V = sqrt(R1R2/(|R1 − R2| δt j)), is not a speed
/// dimensionally; this is its intended form, V = sqrt(R1R2·δt·j/|R1 − R2|).) We apply it per axis to
/// the vector jump `dk` of d2 (so S-bends count both curvatures), with half of each axis' δt·j, the
/// other half left for the change of the tangential acceleration in the same period.
pub fn curvature_change_speed(dk: Vec3, machine: &Machine) -> f64 {
    let mut v2 = f64::INFINITY;
    for (i, ax) in machine.axes.iter().enumerate() {
        if dk[i].abs() > 1e-12 {
            v2 = v2.min(0.5 * ax.max_jerk * machine.interpolation_period / dk[i].abs());
        }
    }
    v2.sqrt()
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

    const MM: f64 = 1e-3;

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
        let v = curvature_change_speed([0.0, 100.0, 0.0], &m);
        assert!((v - (0.5 * 0.001 * 50.0 * 0.01f64).sqrt()).abs() < 1e-12);
        // R1 = 10, R2 = 20 mm, same side: R1R2/|R1 − R2| = 20 mm.
        let v = curvature_change_speed([0.0, 100.0 - 50.0, 0.0], &m);
        assert!((v - (0.5 * 0.001 * 50.0 * 0.02f64).sqrt()).abs() < 1e-12);
    }
}
