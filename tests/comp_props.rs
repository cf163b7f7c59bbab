//! The path stage's properties on cutter-compensated paths (issue 14): random star-shaped
//! contours (convex and concave corners, lines and arcs bulging either way) cut with G41 or
//! G42 (LinuxCNC "G41, G42") and G450 / G451 corners, run through the whole engine in the
//! default (smooth) mode and in seed 004's (polynomial). Checked from the emitted ticks, as an
//! outsider would:
//! - finite differences from rest (velocity, acceleration, jerk) within the axis limits;
//! - every tick within the path tolerance of the tool-centre geometry the reader emits (in the
//!   polynomial mode the tolerance binds each axis, eq. 29–30: √3 of it in space);
//! - with G450, every tick away from the entry and exit moves at the tool radius ± the
//!   tolerance from the programmed contour (the tool-centre path of a correct compensation is
//!   at exactly the radius from the contour, and distance is 1-Lipschitz) — independent of the
//!   compensation code;
//! - the programmed end point of the G40 move, exactly.
#![allow(unused_crate_dependencies)]

use cnc_motion::config::{CornerMode, Machine, MM};
use cnc_motion::engine::Engine;
use cnc_motion::gcode::{Motion, Reader};
use cnc_motion::geometry::{Arc as ArcGeo, Line, Plane, Source};
use cnc_motion::interp::Differences;
use proptest::prelude::*;
use std::fmt::Write;
use std::sync::Arc;

fn round4(x: f64) -> f64 {
    format!("{x:.4}").parse().unwrap()
}

/// One edge of the contour: to vertex k; an arc when `bulge` ≠ 0 (sweep in rad, sign = side).
#[derive(Clone, Debug)]
struct Edge {
    radius: f64,
    bulge: f64,
}

fn an_edge() -> impl Strategy<Value = Edge> {
    let bulge = prop_oneof![Just(0.0), -1.2..-0.2f64, 0.2..1.2f64];
    (20.0..45.0f64, bulge).prop_map(|(radius, bulge)| Edge { radius, bulge })
}

struct Case {
    text: String,
    /// Programmed contour (m).
    contour: Vec<Source>,
    /// Lines of the G41/G42 entry and the G40 exit move.
    entry_line: u32,
    exit_line: u32,
    end: [f64; 3],
}

fn line(a: [f64; 3], b: [f64; 3]) -> Source {
    Source::Line(Line {
        start: a.map(|x| x * MM),
        end: b.map(|x| x * MM),
    })
}

/// A star-shaped contour about the origin, counter-clockwise, entered and left at the middle M
/// of its (straight) closing edge, so that the entry and exit do not meet a corner: from the
/// origin with G41 (inside), from outside with G42.
fn case(edges: &[Edge], left: bool, radius: f64, g451: bool) -> Case {
    let n = edges.len();
    let v: Vec<[f64; 3]> = edges
        .iter()
        .enumerate()
        .map(|(k, e)| {
            let phi = std::f64::consts::TAU * k as f64 / n as f64;
            [round4(e.radius * phi.cos()), round4(e.radius * phi.sin()), 0.0]
        })
        .collect();
    // M: the midpoint of the closing edge v[n-1] → v[0], on its line to 1e-4 mm precision.
    let m = [
        round4(0.5 * (v[n - 1][0] + v[0][0])),
        round4(0.5 * (v[n - 1][1] + v[0][1])),
        0.0,
    ];
    let start = if left {
        [0.0; 3]
    } else {
        [round4(3.0 * m[0]), round4(3.0 * m[1]), 0.0]
    };
    let (side, corner) = (if left { 41 } else { 42 }, if g451 { 451 } else { 450 });
    let mut text = format!(
        "G21 G90 G17 G64 F3000 G{corner}\nG0 X{} Y{}\n",
        start[0], start[1]
    );
    // G41.1 / G42.1 D: the tool diameter.
    let d = 2.0 * radius;
    writeln!(text, "G{side}.1 D{d} G1 X{:.4} Y{:.4}", m[0], m[1]).unwrap();
    let mut contour = Vec::new();
    let mut at = m;
    let mut points: Vec<([f64; 3], f64)> = (0..n).map(|k| (v[k], edges[k].bulge)).collect();
    points[0].1 = 0.0;
    points.push((m, 0.0));
    for (b, bulge) in points {
        let a = at;
        at = b;
        if bulge == 0.0 {
            writeln!(text, "G1 X{:.4} Y{:.4}", b[0], b[1]).unwrap();
            contour.push(line(a, b));
            continue;
        }
        // Centre on the chord's bisector; bulge > 0: counter-clockwise (G3), centre left of the
        // chord, bulging right of it: outwards for this counter-clockwise contour; < 0 inwards.
        let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
        let chord = dx.hypot(dy);
        let h = 0.5 * chord / (0.5 * bulge.abs()).tan();
        let ccw = bulge > 0.0;
        let s = if ccw { 1.0 } else { -1.0 };
        let c = [
            0.5 * (a[0] + b[0]) - s * h * dy / chord,
            0.5 * (a[1] + b[1]) + s * h * dx / chord,
        ];
        let (i, j) = (round4(c[0] - a[0]), round4(c[1] - a[1]));
        let g = if ccw { 3 } else { 2 };
        writeln!(text, "G{g} X{:.4} Y{:.4} I{i:.4} J{j:.4}", b[0], b[1]).unwrap();
        let centre = [(a[0] + i) * MM, (a[1] + j) * MM, 0.0];
        let geo = ArcGeo::from_gcode(a.map(|x| x * MM), b.map(|x| x * MM), centre, Plane::XY, !ccw, 0);
        contour.push(Source::Arc(geo.expect("an arc")));
    }
    let exit_line = 5 + n as u32;
    writeln!(text, "G40 G1 X{} Y{}\nM30", start[0], start[1]).unwrap();
    Case {
        text,
        contour,
        entry_line: 3,
        exit_line,
        end: start.map(|x| x * MM),
    }
}

/// The tool-centre geometry the reader emits; None when it refuses the contour (a gouge).
fn tool_centre(case: &Case, m: &Machine) -> Option<(Vec<Source>, Vec<Source>)> {
    let mut r = Reader::new(Arc::from(case.text.as_str()), "c.ngc", [0.0; 3]).with_machine(m);
    let (mut path, mut ends) = (Vec::new(), Vec::new());
    while let Some(b) = r.next_block().ok()? {
        let line = b.line;
        let geo = match (b.geometry(), b.motion) {
            (Some(geo), _) => geo,
            (None, Motion::Arc { .. }) => return None,
            (None, _) => continue,
        };
        if line == case.entry_line || line == case.exit_line || line < case.entry_line {
            ends.push(geo);
        }
        path.push(geo);
    }
    Some((path, ends))
}

/// Some point of the exact tool-centre path (entry and exit moves aside) nearer the contour than
/// `min` (sampled every 1/64 of each element).
fn gouges_itself(path: &[Source], ends: &[Source], contour: &[Source], min: f64) -> bool {
    path.iter().filter(|g| !ends.contains(g)).any(|g| {
        (0..=64).any(|k| {
            let p = match g {
                Source::Line(l) => l.eval(l.length() * k as f64 / 64.0).p,
                Source::Arc(a) => a.eval(a.length() * k as f64 / 64.0).p,
            };
            nearest(contour, p) < min
        })
    })
}

fn nearest(geo: &[Source], p: [f64; 3]) -> f64 {
    geo.iter().map(|g| g.distance(p)).fold(f64::INFINITY, f64::min)
}

fn check(case: &Case, radius: f64, g451: bool, corner: CornerMode) -> Result<(), TestCaseError> {
    let m = Machine {
        corner,
        ..Machine::default()
    };
    let Some((path, ends)) = tool_centre(case, &m) else {
        return Err(TestCaseError::reject("the reader refuses the contour (gouge)"));
    };
    let per_axis = if corner == CornerMode::Polynomial {
        3f64.sqrt()
    } else {
        1.0
    };
    let tol = per_axis * m.path_tolerance * (1.0 + 1e-6) + 1e-12;
    let r = radius * MM;
    // A contour that comes back within the radius of itself (two non-adjacent elements) is
    // gouged by the exact tool-centre path already: the reader checks local gouges only, as
    // LinuxCNC does, so such a case says nothing about the motion.
    prop_assume!(
        !gouges_itself(&path, &ends, &case.contour, r - tol),
        "global gouge"
    );
    let mut e = Engine::new(Arc::from(case.text.as_str()), "c.ngc", &m).expect("valid program");
    let mut fd = Differences::new(e.tick().p, m.interpolation_period);
    let mut ticks = 0;
    while !e.finished() {
        let p = e.step().expect("no runtime error").p;
        ticks += 1;
        prop_assert!(ticks < 2_000_000, "does not finish");
        let (v, a, j) = fd.push(p);
        for (i, ax) in m.axes.iter().enumerate() {
            prop_assert!(
                v[i].abs() <= ax.max_velocity * (1.0 + 1e-6),
                "velocity {} axis {i}",
                v[i]
            );
            prop_assert!(
                a[i].abs() <= ax.max_acceleration * (1.0 + 1e-6),
                "acceleration {} axis {i}",
                a[i]
            );
            prop_assert!(j[i].abs() <= ax.max_jerk * (1.0 + 1e-6), "jerk {} axis {i}", j[i]);
        }
        let off = nearest(&path, p);
        prop_assert!(
            off <= tol,
            "tick {p:?} is {off} m off the tool-centre path\n{}",
            case.text
        );
        if !g451 && nearest(&ends, p) > tol {
            let d = nearest(&case.contour, p);
            prop_assert!(
                (d - r).abs() <= tol,
                "tick {p:?} at {d} m from the contour, radius {r}\n{}",
                case.text
            );
        }
    }
    let end = e.tick().p;
    for i in 0..3 {
        prop_assert!(
            (end[i] - case.end[i]).abs() <= 1e-12,
            "end {end:?} vs {:?}",
            case.end
        );
    }
    Ok(())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, max_global_rejects: 4096, ..ProptestConfig::default() })]

    #[test]
    fn compensated_contours_keep_limits_tolerance_and_end(
        edges in prop::collection::vec(an_edge(), 3..9),
        left in any::<bool>(),
        radius in 0.5..4.0f64,
        g451 in any::<bool>(),
    ) {
        let radius = round4(radius);
        let c = case(&edges, left, radius, g451);
        check(&c, radius, g451, CornerMode::Smooth)?;
    }

    /// Seed 004's mode: quintic corners at one speed, eq. 10 where the corner arcs of G450 meet
    /// the lines tangentially (the step of the centripetal acceleration shares the axis jerk with
    /// the blocks on both sides, corner::step_jerk).
    #[test]
    fn compensated_contours_keep_the_limits_in_the_seed004_mode(
        edges in prop::collection::vec(an_edge(), 3..9),
        left in any::<bool>(),
        radius in 0.5..4.0f64,
        g451 in any::<bool>(),
    ) {
        let radius = round4(radius);
        let c = case(&edges, left, radius, g451);
        check(&c, radius, g451, CornerMode::Polynomial)?;
    }
}
