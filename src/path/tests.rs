//! Builder-level tests: corner rules, continuity, limits and length conservation.

use super::*;
use crate::gcode::StopKind;
use crate::geometry::{add, norm, scale, Plane};
use crate::si::MM;
const FEED: f64 = 6000.0 / 60.0 * MM;

/// The seed-004 corner mode these tests are about (the default is `smooth`, tests/cam_programs.rs).
fn polynomial() -> Machine {
    Machine {
        corner: CornerMode::Polynomial,
        ..Machine::default()
    }
}

fn blend_mode(tol: Option<f64>) -> PathMode {
    PathMode::Blend {
        tolerance: tol,
        q: None,
    }
}

/// Run a polyline (mm) through the builder.
fn polyline(machine: &Machine, pts: &[[f64; 3]], mode: PathMode) -> Vec<PathBlock> {
    let mut b = PathBuilder::new(machine);
    let mut out = Vec::new();
    for (i, w) in pts.windows(2).enumerate() {
        let block = Block {
            line: i as u32 + 1,
            from: scale(w[0], MM),
            motion: Motion::Linear { to: scale(w[1], MM) },
            feed: FEED,
            path_mode: mode,
        };
        b.push(&block, &mut out);
    }
    b.finish(&mut out);
    out
}

fn assert_continuous(out: &[PathBlock]) {
    for w in out.windows(2) {
        let gap = norm(sub(w[1].segment.start(), w[0].segment.end()));
        assert!(gap < 1e-15, "gap {gap}");
    }
}

fn square() -> Vec<[f64; 3]> {
    vec![
        [0.0, 0.0, 0.0],
        [10.0, 0.0, 0.0],
        [10.0, 10.0, 0.0],
        [0.0, 10.0, 0.0],
        [0.0, 0.0, 2.0],
    ]
}

#[test]
fn polynomial_corners_on_a_square() {
    let m = polynomial();
    let pts = square();
    let out = polyline(&m, &pts, blend_mode(None));
    assert_continuous(&out);
    let kinds: Vec<_> = out
        .iter()
        .map(|b| matches!(b.segment, Segment::Blend(_)))
        .collect();
    assert_eq!(kinds, [false, true, false, true, false, true, false]);
    assert_eq!(out.last().unwrap().v_end_max, 0.0);
    assert_eq!(out.last().unwrap().segment.end(), [0.0, 0.0, 2.0 * MM]);
    for (i, pb) in out.iter().enumerate() {
        let Segment::Blend(b) = pb.segment else { continue };
        assert!(pb.constant_speed);
        let v = pb.v_feed;
        // Junction speeds on both sides equal the transition speed.
        assert_eq!(out[i - 1].v_end_max, v);
        assert_eq!(pb.v_end_max, v);
        assert!(v > 0.0 && v <= FEED);
        // eq. 29–30: every axis within the tolerance (10 µm) of the corner at the apex, the widest
        // at it; no point of the transition nearer the corner than the apex.
        let corner = scale(pts[i / 2 + 1], MM);
        let oq = sub(b.apex(), corner);
        let widest = oq.iter().fold(0.0f64, |w, x| w.max(x.abs()));
        assert!((widest - m.path_tolerance).abs() < 1e-15, "{oq:?}");
        let mut closest = f64::INFINITY;
        let n = 4000;
        for k in 0..=n {
            let g = b.eval(b.length * k as f64 / n as f64);
            closest = closest.min(norm(sub(g.p, corner)));
            // Axis limits at the constant parameter speed (eq. 54–57), on a fine grid.
            for (ax, lim) in m.axes.iter().enumerate() {
                assert!(g.d1[ax].abs() * v <= lim.max_velocity * (1.0 + 1e-9));
                assert!(g.d2[ax].abs() * v * v <= lim.max_acceleration * (1.0 + 1e-9));
                assert!(g.d3[ax].abs() * v.powi(3) <= lim.max_jerk * (1.0 + 1e-9));
            }
        }
        assert!((closest - norm(oq)).abs() < 1e-15, "{closest}");
        // G1/G2 continuity with the lines: same tangent, zero curvature at both ends.
        let (g0, g1) = (b.eval(0.0), b.eval(b.length));
        let Segment::Line(before) = out[i - 1].segment else {
            panic!()
        };
        let Segment::Line(after) = out[i + 1].segment else {
            panic!()
        };
        assert!(norm(sub(g0.d1, before.direction())) < 1e-12);
        assert!(norm(sub(g1.d1, after.direction())) < 1e-12);
        assert!(norm(g0.d2) < 1e-6 && norm(g1.d2) < 1e-6);
        // The parameter runs over 2L, V_In·T of eq. 51.
        assert_eq!(b.length, 2.0 * b.half);
        // Some axis uses most of its acceleration or jerk: the speed is not needlessly low.
        let bounds = b.derivative_bounds();
        let used = (0..3)
            .map(|ax| {
                let a = bounds[1][ax] * v * v / m.axes[ax].max_acceleration;
                let j = bounds[2][ax] * v.powi(3) / m.axes[ax].max_jerk;
                a.max(j)
            })
            .fold(0.0, f64::max);
        assert!(v == FEED || used > 0.95, "used {used}");
    }
    // The lengths add up to the programmed polyline: each transition runs over the 2L it cuts.
    let programmed: f64 = pts.windows(2).map(|w| norm(sub(w[1], w[0])) * MM).sum();
    let total: f64 = out.iter().map(|b| b.segment.length()).sum();
    assert!((programmed - total).abs() < 1e-15, "{programmed} {total}");
}

#[test]
fn exact_stop_everywhere() {
    let pts = square();
    let m = Machine {
        corner: CornerMode::ExactStop,
        ..Machine::default()
    };
    let out = polyline(&m, &pts, blend_mode(None));
    assert_eq!(out.len(), 4);
    assert!(out.iter().all(|b| b.v_end_max == 0.0 && !b.constant_speed));
    // G61 on a polynomial machine, also on collinear junctions.
    let mut pts = square();
    pts.insert(1, [5.0, 0.0, 0.0]);
    let out = polyline(&polynomial(), &pts, PathMode::ExactStop);
    assert_eq!(out.len(), 5);
    assert!(out.iter().all(|b| b.v_end_max == 0.0));
}

#[test]
fn acceleration_period_corner() {
    let m = Machine {
        corner: CornerMode::AccelerationPeriod,
        ..Machine::default()
    };
    let out = polyline(&m, &square(), blend_mode(None));
    assert_eq!(out.len(), 4);
    // 90° corners: F_c = A·T = 2 m/s² · 1 ms.
    assert!((out[0].v_end_max - 2.0e-3).abs() < 1e-15);
    assert!((out[1].v_end_max - 2.0e-3).abs() < 1e-15);
    // 3rd corner: (−1,0,0) → (0,−10,2)/|…|: cos θ = 0 too.
    assert!((out[2].v_end_max - 2.0e-3).abs() < 1e-15);
    assert_eq!(out[3].v_end_max, 0.0);
}

#[test]
fn collinear_full_speed() {
    let out = polyline(
        &polynomial(),
        &[[0.0; 3], [3.0, 4.0, 0.0], [6.0, 8.0, 0.0]],
        blend_mode(None),
    );
    assert_eq!(out.len(), 2);
    assert_eq!(out[0].v_end_max, out[0].v_feed.min(out[1].v_feed));
    assert!(out[0].v_end_max > 0.0);
}

#[test]
fn circular_blend_corners() {
    let m = Machine {
        corner: CornerMode::Circular,
        ..Machine::default()
    };
    let pts = square();
    let out = polyline(&m, &pts, blend_mode(Some(0.02 * MM)));
    assert_continuous(&out);
    assert_eq!(out.len(), 7);
    for (i, pb) in out.iter().enumerate() {
        let Segment::Arc(a) = pb.segment else { continue };
        assert!(pb.constant_speed);
        assert_eq!(out[i - 1].v_end_max, pb.v_feed);
        let corner = scale(pts[i / 2 + 1], MM);
        let mid = pb.segment.eval(pb.segment.length() / 2.0).p;
        assert!((norm(sub(mid, corner)) - 0.02 * MM).abs() < 1e-12);
        // eq. 9: v ≤ sqrt(A·R), (J·R²)^(1/3).
        let v = pb.v_feed;
        assert!(v <= (2.0 * a.radius).sqrt() * (1.0 + 1e-12));
        assert!(v <= (50.0 * a.radius * a.radius).cbrt() * (1.0 + 1e-12));
    }
}

#[test]
fn short_segments_cut_at_most_half() {
    // 20 µm segments with a 1 mm tolerance: L is capped at 10 µm on each side.
    let m = polynomial();
    let pts = [
        [0.0; 3],
        [0.02, 0.0, 0.0],
        [0.02, 0.02, 0.0],
        [0.04, 0.02, 0.0],
        [0.04, 0.04, 0.0],
    ];
    let out = polyline(&m, &pts, blend_mode(Some(1.0)));
    assert_continuous(&out);
    for pb in &out {
        if let Segment::Blend(b) = pb.segment {
            assert!(b.half <= 0.01 * MM * (1.0 + 1e-12));
        }
    }
    // Middle lines are eaten completely (two halves): only transitions remain between them.
    assert!(out.iter().all(|b| b.segment.length() > 0.0));
    assert_eq!(out.last().unwrap().segment.end(), scale([0.04, 0.04, 0.0], MM));
}

#[test]
fn g64_tolerance_is_used() {
    let m = polynomial();
    let out = polyline(&m, &square(), blend_mode(Some(0.05 * MM)));
    let Segment::Blend(b) = out[1].segment else {
        panic!()
    };
    // The axis tolerance of eq. 29–30 is the G64 P.
    let oq = sub(b.apex(), b.corner);
    assert!((oq[0].abs().max(oq[1].abs()) - 0.05 * MM).abs() < 1e-15);
}

#[test]
fn reversal_stops() {
    let out = polyline(
        &polynomial(),
        &[[0.0; 3], [5.0, 0.0, 0.0], [1.0, 0.01, 0.0]],
        blend_mode(None),
    );
    assert_eq!(out.len(), 2);
    assert_eq!(out[0].v_end_max, 0.0);
}

fn arc_block(line: u32, from: Vec3, to: Vec3, center: Vec3, clockwise: bool) -> Block {
    Block {
        line,
        from,
        motion: Motion::Arc {
            to,
            center,
            plane: Plane::XY,
            clockwise,
            turns: 0,
        },
        feed: FEED,
        path_mode: blend_mode(None),
    }
}

#[test]
fn arc_junctions() {
    let m = polynomial();
    let r = 10.0 * MM;
    let mut b = PathBuilder::new(&m);
    let mut out = Vec::new();
    // Line along +X into a tangent CCW quarter arc (R = 10 mm), then a non-tangent line, a dwell,
    // a line, an M0 and a last line.
    let line = |line, from, to| Block {
        line,
        from,
        motion: Motion::Linear { to },
        feed: FEED,
        path_mode: blend_mode(None),
    };
    b.push(&line(1, [-r, -r, 0.0], [0.0, -r, 0.0]), &mut out);
    b.push(
        &arc_block(2, [0.0, -r, 0.0], [r, 0.0, 0.0], [0.0; 3], false),
        &mut out,
    );
    b.push(&line(3, [r, 0.0, 0.0], [2.0 * r, 0.0, 0.0]), &mut out);
    b.push(&line(4, [2.0 * r, 0.0, 0.0], [2.0 * r, 0.0, 0.0]), &mut out); // zero length: dropped
    b.push(
        &Block {
            line: 5,
            from: [2.0 * r, 0.0, 0.0],
            motion: Motion::Dwell { seconds: 0.5 },
            feed: FEED,
            path_mode: blend_mode(None),
        },
        &mut out,
    );
    b.push(&line(6, [2.0 * r, 0.0, 0.0], [2.0 * r, r, 0.0]), &mut out);
    b.push(
        &Block {
            line: 7,
            from: [2.0 * r, r, 0.0],
            motion: Motion::Stop(StopKind::Pause),
            feed: FEED,
            path_mode: blend_mode(None),
        },
        &mut out,
    );
    b.push(&line(8, [2.0 * r, r, 0.0], [3.0 * r, r, 0.0]), &mut out);
    b.finish(&mut out);
    assert_continuous(&out);
    let lines: Vec<u32> = out.iter().map(|b| b.line).collect();
    assert_eq!(lines, [1, 2, 3, 5, 6, 8]);
    // Line → tangent arc: eq. 10, ¾·(v²/R)/δt ≤ j − ½·j (the step between two ticks shares the
    // axis jerk with the blocks on both sides, whose jerk is halved: corner::step_jerk).
    let eq10 = (2.0 / 3.0 * m.interpolation_period * 50.0 * r).sqrt();
    assert!((out[0].v_end_max - eq10.min(out[0].v_feed).min(out[1].v_feed)).abs() < 1e-12);
    assert!(out[0].v_end_max > 0.0);
    assert_eq!(out[0].limits.j_max, 25.0);
    // Arc end tangent is +Y, next line +X: a sharp corner with no transition stops (the seed-003
    // corner feed A·T is the acceleration_period mode's, tested below).
    assert_eq!(out[1].v_end_max, 0.0);
    // Dwell and M0 stop.
    assert_eq!(out[2].v_end_max, 0.0);
    assert!(matches!(out[3].segment, Segment::Dwell { seconds, .. } if seconds == 0.5));
    assert_eq!(out[4].v_end_max, 0.0);
    assert_eq!(out[5].v_end_max, 0.0);
    // The arc's limits: v ≤ chord-error and eq. 9 limits.
    let v = out[1].limits.v_max;
    assert!(v <= chord_error_speed(r, m.chord_tolerance, m.interpolation_period));
    assert!(v <= (2.0 * r).sqrt());
}

#[test]
fn tangent_arcs_curvature_change() {
    // Two CCW arcs R = 10 mm then R = 20 mm, tangent at (10, 0): eq. 10 with R1R2/|R1 − R2| = 20 mm
    // (and the jerk kept: corner::step_jerk).
    let m = polynomial();
    let r = 10.0 * MM;
    let mut b = PathBuilder::new(&m);
    let mut out = Vec::new();
    b.push(
        &arc_block(1, [0.0, -r, 0.0], [r, 0.0, 0.0], [0.0; 3], false),
        &mut out,
    );
    b.push(
        &arc_block(2, [r, 0.0, 0.0], [-r, 2.0 * r, 0.0], [-r, 0.0, 0.0], false),
        &mut out,
    );
    b.finish(&mut out);
    let eq10 = (2.0 / 3.0 * m.interpolation_period * 50.0 * 2.0 * r).sqrt();
    let expect = eq10.min(out[0].v_feed).min(out[1].v_feed);
    assert!((out[0].v_end_max - expect).abs() < 1e-12);
    assert_eq!(out[1].segment.end(), [-r, 2.0 * r, 0.0]);
}

#[test]
fn builder_state_roundtrips() {
    let m = polynomial();
    let mut b = PathBuilder::new(&m);
    let mut out = Vec::new();
    b.push(
        &Block {
            line: 1,
            from: [0.0; 3],
            motion: Motion::Linear { to: [0.01, 0.0, 0.0] },
            feed: FEED,
            path_mode: blend_mode(None),
        },
        &mut out,
    );
    let json = serde_json::to_string(&b).unwrap();
    let back: PathBuilder = serde_json::from_str(&json).unwrap();
    assert_eq!(serde_json::to_string(&back).unwrap(), json);
}

#[test]
fn blend_speed_matches_eq54_on_gentle_corners() {
    // For gentle turns the binding limit is the axis jerk at M (eq. 53): the exact bounds give
    // the speed of eq. 54.
    let m = polynomial();
    for deg in [10.0f64, 30.0, 45.0] {
        let th = deg.to_radians();
        let end = [10.0 + 10.0 * th.cos(), 10.0 * th.sin(), 0.0];
        let out = polyline(&m, &[[0.0; 3], [10.0, 0.0, 0.0], end], blend_mode(None));
        let Segment::Blend(b) = out[1].segment else {
            panic!()
        };
        let (w, q) = (add(b.u, b.v), sub(b.apex(), b.corner));
        let mut v_lim_j = f64::INFINITY;
        for i in 0..3 {
            if w[i].abs() > 1e-9 {
                let jmax = m.axes[i].max_jerk;
                v_lim_j = v_lim_j.min(8.0 / (3.0 * w[i].abs()) * (q[i] * q[i] * jmax).cbrt());
            }
        }
        let v = out[1].v_feed;
        assert!(
            (v - v_lim_j).abs() < 1e-12 * v_lim_j,
            "{deg}: {v} vs eq.54 {v_lim_j}"
        );
    }
}

#[test]
fn sharp_arc_corner_uses_the_corner_feed_in_acceleration_period_mode() {
    let m = Machine {
        corner: CornerMode::AccelerationPeriod,
        ..Machine::default()
    };
    let r = 10.0 * MM;
    let mut b = PathBuilder::new(&m);
    let mut out = Vec::new();
    b.push(
        &arc_block(1, [0.0, -r, 0.0], [r, 0.0, 0.0], [0.0; 3], false),
        &mut out,
    );
    let next = Block {
        line: 2,
        from: [r, 0.0, 0.0],
        motion: Motion::Linear {
            to: [2.0 * r, 0.0, 0.0],
        },
        feed: FEED,
        path_mode: blend_mode(None),
    };
    b.push(&next, &mut out);
    b.finish(&mut out);
    // Arc end tangent +Y, line +X: 90° → seed-003 corner feed F_c = A·T/(1 − cos 90°) = A·T.
    assert!((out[0].v_end_max - 2.0e-3).abs() < 1e-15, "{}", out[0].v_end_max);
}

/// A chain takes the worst limits of its pieces, so a faster piece whose limits ramp far slower
/// to the chain's speed is not joined for the little it saves. Found case (issue 19, tolerance
/// seed 5): a 1.9 mm transition at 61.5 mm/s after a 31.8 mm arc from rest at 60.7 mm/s saved
/// 2.2 µs joined, but the arc then ramped within the transition's top limits (0.079 m/s²,
/// 0.139 m/s³ against its own 0.402 m/s², 2.378 m/s³): 1.494 s against 1.421 s.
#[test]
fn a_faster_piece_with_much_tighter_limits_does_not_join() {
    let limits = |a_max: f64, j_max: f64, v_max: f64| Limits {
        v_max,
        a_max,
        j_max,
        snap_max: 6000.0,
    };
    let (arc, transition) = (limits(0.402, 2.378, 0.0607), limits(0.0789, 0.1386, 0.0615));
    let none = Bands::default();
    // From rest to 60.7 mm/s (closed forms): 2·sqrt(v/J) within the arc's limits (no
    // acceleration plateau: v < A²/J), v/A + A/J within the transition's.
    let (v, within_arc) = (0.0607, 2.0 * (0.0607f64 / 2.378).sqrt());
    let within_transition = v / 0.0789 + 0.0789 / 0.1386;
    assert!(
        within_transition - within_arc > 1.0,
        "{within_transition} vs {within_arc}"
    );
    let joined = smooth::joined_loss(
        0.0,
        (31.8e-3, 0.0607),
        (1.9e-3, 0.0615),
        (&transition, &none),
        (&arc, &none),
        (false, false),
    );
    assert_eq!(joined, None);
}
