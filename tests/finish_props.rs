//! Every program finishes, in every corner mode, with every feed law and any look-ahead window:
//! random short programs (3–30 moves of 1 µm–50 mm; lines, arcs and helices; any turning angle
//! including reversals and near-collinear joins) run to the programmed end within a bound taken
//! from the same program in exact stop, and the motion never skips or jumps (|Δp| ≤ v_max·T per
//! tick and axis). In the default (smooth) mode every tick also stays within the path tolerance
//! of the programmed geometry.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

use cnc_motion::config::{CornerMode, Machine, MM};
use cnc_motion::engine::Engine;
use cnc_motion::feed::ProfileKind;
use cnc_motion::geometry::{Arc as ArcGeo, Line, Plane, Source};
use proptest::prelude::*;
use std::fmt::Write;
use std::sync::Arc;

#[derive(Clone, Debug)]
struct Step {
    /// Length (mm), log-uniform over 1 µm … 50 mm.
    length: f64,
    /// Turn from the previous direction (rad): near 0, near π, or anything.
    turn: f64,
    /// Climb out of the XY plane (rad).
    climb: f64,
    /// 0: line; 1: arc (G2/G3 in XY, radius from the sweep); 2: helix.
    kind: u8,
    sweep: f64,
    clockwise: bool,
}

fn a_step() -> impl Strategy<Value = Step> {
    let turn = prop_oneof![
        (-1e-6..1e-6f64),
        (-0.05..0.05f64),
        (-std::f64::consts::PI..std::f64::consts::PI),
        (std::f64::consts::PI - 1e-3..std::f64::consts::PI),
    ];
    (
        -3.0..(50f64).log10(),
        turn,
        -0.5..0.5f64,
        0u8..3,
        0.05..3.0f64,
        any::<bool>(),
    )
        .prop_map(|(lg, turn, climb, kind, sweep, clockwise)| Step {
            length: 10f64.powf(lg),
            turn,
            climb,
            kind,
            sweep,
            clockwise,
        })
}

struct Program {
    text: String,
    geometry: Vec<Source>,
    end: [f64; 3],
}

fn round4(x: f64) -> f64 {
    format!("{x:.4}").parse().unwrap()
}

fn program(steps: &[Step]) -> Program {
    let mut text = String::from("G21 G90 G17 G64 F3000\n");
    let mut p = [0.0f64; 3];
    let mut heading: f64 = 0.0;
    let mut geometry = Vec::new();
    for s in steps {
        heading += s.turn;
        let l = s.length;
        if s.kind == 0 || l < 0.01 {
            let q = [
                round4(p[0] + l * heading.cos() * s.climb.cos()),
                round4(p[1] + l * heading.sin() * s.climb.cos()),
                round4(p[2] + l * s.climb.sin()),
            ];
            writeln!(text, "G1 X{:.4} Y{:.4} Z{:.4}", q[0], q[1], q[2]).unwrap();
            let line = Line {
                start: p.map(|x| x * MM),
                end: q.map(|x| x * MM),
            };
            if line.length() > 0.0 {
                geometry.push(Source::Line(line));
            }
            p = q;
        } else {
            // Chord of length l along the heading; the centre on its bisector for the sweep.
            let r = 0.5 * l / (0.5 * s.sweep).sin();
            let dz = if s.kind == 2 { l * s.climb } else { 0.0 };
            let q = [
                round4(p[0] + l * heading.cos()),
                round4(p[1] + l * heading.sin()),
                round4(p[2] + dz),
            ];
            let side = if s.clockwise { -1.0 } else { 1.0 };
            let h = r * (0.5 * s.sweep).cos() * side;
            let m = [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])];
            let c = [m[0] - h * heading.sin(), m[1] + h * heading.cos()];
            let (i, j) = (round4(c[0] - p[0]), round4(c[1] - p[1]));
            let g = if s.clockwise { 2 } else { 3 };
            writeln!(
                text,
                "G{g} X{:.4} Y{:.4} Z{:.4} I{i:.4} J{j:.4}",
                q[0], q[1], q[2]
            )
            .unwrap();
            let centre = [(p[0] + i) * MM, (p[1] + j) * MM, p[2] * MM];
            if let Some(a) = ArcGeo::from_gcode(
                p.map(|x| x * MM),
                q.map(|x| x * MM),
                centre,
                Plane::XY,
                s.clockwise,
                0,
            ) {
                geometry.push(Source::Arc(a));
            }
            p = q;
            heading += if s.clockwise { -s.sweep } else { s.sweep };
        }
    }
    text.push_str("M30\n");
    Program {
        text,
        geometry,
        end: p.map(|x| x * MM),
    }
}

/// Run to the end or to `max_time` (s); the motion time if finished. Checks continuity and, with
/// `tolerance`, the distance of every tick to the programmed geometry.
fn run(prog: &Program, m: &Machine, max_time: f64, tolerance: Option<f64>) -> Option<f64> {
    let mut e = Engine::new(Arc::from(prog.text.as_str()), "p.ngc", m).expect("valid program");
    let step_max: Vec<f64> = m
        .axes
        .iter()
        .map(|a| a.max_velocity * m.interpolation_period)
        .collect();
    let mut last = e.tick().p;
    while !e.finished() {
        let t = *e.step().expect("no runtime error");
        for i in 0..3 {
            let dp = (t.p[i] - last[i]).abs();
            assert!(
                dp <= step_max[i] * (1.0 + 1e-9) + 1e-15,
                "axis {i} jumps {dp} m in one tick at t = {}",
                t.t
            );
        }
        last = t.p;
        if let Some(tol) = tolerance {
            // Programs are short: the nearest of all programmed pieces.
            let best = prog
                .geometry
                .iter()
                .map(|g| g.distance(t.p))
                .fold(f64::INFINITY, f64::min);
            assert!(
                best <= tol * (1.0 + 1e-6) + 1e-12,
                "tick {:?} is {best} m off the path in: {}",
                t.p,
                prog.text.replace('\n', " | ")
            );
        }
        if t.t > max_time {
            return None;
        }
    }
    let end = e.tick().p;
    for i in 0..3 {
        assert!(
            (end[i] - prog.end[i]).abs() <= 1e-12,
            "end {end:?} vs {:?}",
            prog.end
        );
    }
    Some(e.motion_time())
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 96, ..ProptestConfig::default() })]

    #[test]
    fn every_program_finishes_in_every_mode(
        steps in prop::collection::vec(a_step(), 3..30),
        kind in prop::sample::select(ProfileKind::ALL.to_vec()),
        corner in prop::sample::select(CornerMode::ALL.to_vec()),
        window in 1usize..512,
    ) {
        let prog = program(&steps);
        let base = Machine { profile: kind, lookahead_blocks: window, ..Machine::default() };
        let exact = Machine { corner: CornerMode::ExactStop, ..base.clone() };
        let t_exact = run(&prog, &exact, 1e4, None).expect("exact stop finishes");
        let m = Machine { corner, ..base };
        // Blending may slow some corners below their exact-stop pace, never by this much.
        let bound = 3.0 * t_exact + 1.0;
        let tol = (corner == CornerMode::Smooth).then_some(m.path_tolerance);
        let t = run(&prog, &m, bound, tol);
        prop_assert!(t.is_some(), "{corner:?}/{kind:?}/window {window}: not finished within {bound} s (exact stop {t_exact} s)\n{}", prog.text);
    }
}
