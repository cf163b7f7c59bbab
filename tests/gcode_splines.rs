//! Issue 20: G5, G5.1 and G5.2/G5.3 (LinuxCNC G-code reference, "G5 Cubic Spline", "G5.1
//! Quadratic Spline", "G5.2 G5.3 NURBS Block"), turned into arcs and lines by the reader within
//! 0.1 × the chord tolerance of the exact curve — the curve evaluated here independently
//! (Bernstein form, Cox–de Boor basis recursion) — ending at the documented end points, and run
//! by the engine within the path tolerance and the axis limits, checked from the ticks.
#![allow(unused_crate_dependencies)]

use cnc_motion::config::{Machine, MM};
use cnc_motion::engine::Engine;
use cnc_motion::gcode::{validate, Block, Motion, Reader};
use cnc_motion::geometry::{distance_to_segment, Source};
use cnc_motion::interp::Differences;
use std::sync::Arc;

type P2 = [f64; 2];

fn blocks(text: &str, m: &Machine) -> Vec<Block> {
    let mut r = Reader::new(Arc::from(text), "s.ngc", [0.0; 3]).with_machine(m);
    let mut out = Vec::new();
    while let Some(b) = r.next_block().unwrap_or_else(|e| panic!("{e}")) {
        out.push(b);
    }
    out
}

fn error(text: &str) -> String {
    validate(text, "s.ngc").unwrap_err().to_string()
}

/// The pieces (path geometry) of the blocks of line `line`.
fn pieces(b: &[Block], line: u32) -> Vec<Source> {
    b.iter()
        .filter(|b| b.line == line)
        .filter_map(Block::geometry)
        .collect()
}

/// Bernstein form of a Bézier curve with control points `p` (mm) at t.
fn bezier(p: &[P2], t: f64) -> P2 {
    let n = p.len() - 1;
    let binom = |k: usize| (0..k).fold(1.0, |a, i| a * (n - i) as f64 / (i + 1) as f64);
    let mut out = [0.0; 2];
    for (k, q) in p.iter().enumerate() {
        let b = binom(k) * t.powi(k as i32) * (1.0 - t).powi((n - k) as i32);
        out[0] += b * q[0];
        out[1] += b * q[1];
    }
    out
}

/// Cox–de Boor basis N_{i,k}(u) on LinuxCNC's clamped uniform knots (the last span closed).
fn basis(i: usize, k: usize, u: f64, t: &[f64]) -> f64 {
    if k == 1 {
        let last = u == t[t.len() - 1] && t[i + 1] == u && t[i] < u;
        return if (t[i] <= u && u < t[i + 1]) || last {
            1.0
        } else {
            0.0
        };
    }
    let a = if t[i + k - 1] > t[i] {
        (u - t[i]) / (t[i + k - 1] - t[i]) * basis(i, k - 1, u, t)
    } else {
        0.0
    };
    let b = if t[i + k] > t[i + 1] {
        (t[i + k] - u) / (t[i + k] - t[i + 1]) * basis(i + 1, k - 1, u, t)
    } else {
        0.0
    };
    a + b
}

/// The rational B-spline of (x, y, w) control points, order k, at u ∈ [0, n − k + 2].
fn nurbs(p: &[[f64; 3]], k: usize, u: f64) -> P2 {
    let n = p.len() - 1;
    let t: Vec<f64> = (0..=n + k)
        .map(|i| {
            if i < k {
                0.0
            } else if i <= n {
                (i + 1 - k) as f64
            } else {
                (n + 2 - k) as f64
            }
        })
        .collect();
    let (mut x, mut y, mut w) = (0.0, 0.0, 0.0);
    for (i, q) in p.iter().enumerate() {
        let b = basis(i, k, u, &t) * q[2];
        (x, y, w) = (x + b * q[0], y + b * q[1], w + b);
    }
    [x / w, y / w]
}

/// Largest distance (mm) between the curve (sampled densely, mm) and the pieces, both ways.
fn deviation(curve: &[P2], pieces: &[Source]) -> f64 {
    let to_pieces = curve
        .iter()
        .map(|q| {
            pieces
                .iter()
                .map(|g| g.distance([q[0] * MM, q[1] * MM, 0.0]))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max);
    let to_curve = pieces
        .iter()
        .flat_map(|g| {
            (0..=50).map(move |k| {
                let s = g.length() * k as f64 / 50.0;
                match g {
                    Source::Line(l) => l.eval(s).p,
                    Source::Arc(a) => a.eval(s).p,
                }
            })
        })
        .map(|p| {
            curve
                .windows(2)
                .map(|w| distance_to_segment(p, mm3(w[0]), mm3(w[1])))
                .fold(f64::INFINITY, f64::min)
        })
        .fold(0.0, f64::max);
    to_pieces.max(to_curve) / MM
}

fn mm3(p: P2) -> [f64; 3] {
    [p[0] * MM, p[1] * MM, 0.0]
}

fn samples(n: usize, f: impl Fn(f64) -> P2) -> Vec<P2> {
    (0..=n).map(|i| f(i as f64 / n as f64)).collect()
}

/// 0.1 × the chord tolerance (mm) at the defaults, plus the float noise of the checks.
fn spline_tol(m: &Machine) -> f64 {
    0.1 * m.chord_tolerance.min(m.path_tolerance) / MM * (1.0 + 1e-6) + 1e-9
}

fn end(b: &[Block]) -> P2 {
    let to = b
        .iter()
        .rev()
        .find_map(|b| match b.motion {
            Motion::Linear { to } | Motion::Arc { to, .. } | Motion::Rapid { to } => Some(to),
            _ => None,
        })
        .expect("a move");
    [to[0] / MM, to[1] / MM]
}

/// "G5 Cubic Spline", the curvy N and the second N continuing it without I J (I J = −P −Q of
/// the first): control points start + (I, J) and end + (P, Q): (0,0) (0,3) (1,−2) (1,1), then
/// (1,1) (1,4) (2,−1) (2,2); ends (1, 1) and (2, 2).
#[test]
fn g5_curvy_n_as_documented() {
    let m = Machine::default();
    let b = blocks(
        "G90 G17 F100\nG0 X0 Y0\nG5 I0 J3 P0 Q-3 X1 Y1\nG5 P0 Q-3 X2 Y2\n",
        &m,
    );
    let first = [[0.0, 0.0], [0.0, 3.0], [1.0, -2.0], [1.0, 1.0]];
    let second = [[1.0, 1.0], [1.0, 4.0], [2.0, -1.0], [2.0, 2.0]];
    for (line, ctrl) in [(3, first), (4, second)] {
        let curve = samples(8_000, |t| bezier(&ctrl, t));
        let d = deviation(&curve, &pieces(&b, line));
        assert!(d <= spline_tol(&m), "line {line}: {d} mm > {}", spline_tol(&m));
    }
    assert_eq!(end(&b), [2.0, 2.0]);
    let arcs = b
        .iter()
        .filter(|b| matches!(b.motion, Motion::Arc { .. }))
        .count();
    assert!(arcs > 10, "{arcs} arcs");
}

/// "G5.1 Quadratic Spline": the parabola through the origin from X−2 Y4 to X2 Y4 (control
/// point (0, −4)); ends at (2, 4).
#[test]
fn g5_1_parabola_as_documented() {
    let m = Machine::default();
    let b = blocks("G90 G17 F100\nG0 X-2 Y4\nG5.1 X2 I2 J-8\n", &m);
    let ctrl = [[-2.0, 4.0], [0.0, -4.0], [2.0, 4.0]];
    let p = pieces(&b, 3);
    assert!(deviation(&samples(8_000, |t| bezier(&ctrl, t)), &p) <= spline_tol(&m));
    let through_origin = p
        .iter()
        .map(|g| g.distance([0.0; 3]))
        .fold(f64::INFINITY, f64::min);
    assert!(through_origin / MM <= spline_tol(&m));
    assert_eq!(end(&b), [2.0, 4.0]);
}

/// "G5.2 G5.3 NURBS Block": the documentation's example (order 3, the last weight 2), ending at
/// its last control point (0, 0).
#[test]
fn g5_2_nurbs_as_documented() {
    let m = Machine::default();
    let text =
        "G0 X0 Y0\nF10\nG5.2 P1 L3\n     X0 Y1 P1\n     X2 Y2 P1\n     X2 Y0 P1\n     X0 Y0 P2\nG5.3\nM2\n";
    let b = blocks(text, &m);
    let ctrl = [
        [0.0, 0.0, 1.0],
        [0.0, 1.0, 1.0],
        [2.0, 2.0, 1.0],
        [2.0, 0.0, 1.0],
        [0.0, 0.0, 2.0],
    ];
    let curve = samples(8_000, |u| nurbs(&ctrl, 3, 3.0 * u));
    let d = deviation(&curve, &pieces(&b, 8));
    assert!(d <= spline_tol(&m), "{d} mm");
    assert_eq!(end(&b), [0.0, 0.0]);
}

/// The spline's arcs run as any curve: every tick within the path tolerance (plus the spline's
/// share) of the exact curve, the axis limits from finite differences, the exact end.
#[test]
fn splines_run_within_the_tolerance_and_the_limits() {
    let m = Machine::default();
    let text =
        "G21 G90 G17 G64\nG0 X0 Y0\nG5 I0 J3 P0 Q-3 X1 Y1 F3000\nG5 P0 Q-3 X2 Y2\nG5.1 X4 Y2 I1 J2\nM2\n";
    let mut curve = samples(1500, |t| {
        bezier(&[[0.0, 0.0], [0.0, 3.0], [1.0, -2.0], [1.0, 1.0]], t)
    });
    curve.extend(samples(1500, |t| {
        bezier(&[[1.0, 1.0], [1.0, 4.0], [2.0, -1.0], [2.0, 2.0]], t)
    }));
    curve.extend(samples(1500, |t| {
        bezier(&[[2.0, 2.0], [3.0, 4.0], [4.0, 2.0]], t)
    }));
    let tol = m.path_tolerance / MM + spline_tol(&m) + 1e-6;
    let mut e = Engine::new(Arc::from(text), "s.ngc", &m).unwrap();
    let mut fd = Differences::new(e.tick().p, m.interpolation_period);
    let mut ticks = 0;
    while !e.finished() {
        let p = e.step().unwrap().p;
        ticks += 1;
        assert!(ticks < 1_000_000);
        let (v, a, j) = fd.push(p);
        for (i, ax) in m.axes.iter().enumerate() {
            assert!(v[i].abs() <= ax.max_velocity * (1.0 + 1e-6), "v {v:?}");
            assert!(a[i].abs() <= ax.max_acceleration * (1.0 + 1e-6), "a {a:?}");
            assert!(j[i].abs() <= ax.max_jerk * (1.0 + 1e-6), "j {j:?}");
        }
        let off = curve
            .windows(2)
            .map(|w| distance_to_segment(p, mm3(w[0]), mm3(w[1])))
            .fold(f64::INFINITY, f64::min)
            / MM;
        assert!(off <= tol, "tick {p:?} {off} mm off the curves");
    }
    let p = e.tick().p;
    assert!(
        (p[0] - 4.0 * MM).abs() < 1e-12 && (p[1] - 2.0 * MM).abs() < 1e-12,
        "{p:?}"
    );
}

/// G93 (LinuxCNC "G93, G94, G95"): the whole spline takes 1/F minutes (LinuxCNC gives each of
/// its biarcs 1/F: a G5 would take 32/F).
#[test]
fn inverse_time_spans_the_whole_spline() {
    let b = blocks("G93 G5 I0 J3 P0 Q-3 X1 Y1 F2\n", &Machine::default());
    let length: f64 = b.iter().filter_map(Block::geometry).map(|g| g.length()).sum();
    let time: f64 = b
        .iter()
        .filter_map(|b| b.geometry().map(|g| g.length() / b.feed))
        .sum();
    assert!((time - 30.0).abs() < 1e-9, "{time} s for {length} m");
}

/// The documented errors ("It is an error if …"), and what LinuxCNC would run differently.
#[test]
fn spline_errors_are_located() {
    let cases = [
        ("G5 X1 Y1 P0 Q1 F100\n", "s.ngc:1:1: G5 needs I and J unless it follows a G5 (LinuxCNC \"G5 Cubic Spline\")"),
        ("G5 X1 Y1 I1 P0 Q1 F100\n", "s.ngc:1:10: G5: give both I and J, or neither"),
        ("G5 X1 Y1 I1 J1 P0 Q1 Z1 F100\n", "s.ngc:1:22: G5: splines move X and Y only, no Z"),
        ("G18 G5 X1 Y1 I1 J1 P0 Q1 F100\n", "s.ngc:1:5: G5: splines run in the G17 (XY) plane only"),
        ("G5.1 X1 Y1 F100\n", "s.ngc:1:1: G5.1 needs I or J, not both zero (LinuxCNC \"G5.1 Quadratic Spline\")"),
        ("F100 G5.2 L2\nX1 Y1\nX2 Y0\nG5.3\n", "s.ngc:1:11: G5.2 L2: the order must be 3 … 16 (LinuxCNC runs a lower L as 3)"),
        ("F100 G5.2\nX1 Y1\nG5.3\n", "s.ngc:3:1: G5.3: the NURBS block of line 1 has 2 control points, fewer than its order L3"),
        ("G5.3\n", "s.ngc:1:1: G5.3 without G5.2 first (LinuxCNC \"G5.2 G5.3 NURBS Block\")"),
        ("F100 G5.2\nX1 Y1\nG1 X3\n", "s.ngc:3:1: G1 inside the NURBS block opened on line 1 (close it with G5.3 first)"),
        ("F100 G5.2\nX1 Y1\nX2 Y0\n", "s.ngc:1:1: G5.2 NURBS block not closed by G5.3 before the end of the program"),
        ("G93 G5.2 X1 Y1 F1\n", "s.ngc:1:5: G5.2 in G93: a NURBS block spans several lines, no one F gives its time; use G94"),
        ("F100 G5.2\nX1 Y1 P0\n", "s.ngc:2:7: G5.2: the weight P0 out of range (0.000001 … 1000000)"),
        (
            "G41.1 D1 G1 X1 F100\nG5 I0 J1 P0 Q-1 X2 Y2\n",
            "s.ngc:2:1: G5 with cutter compensation on (LinuxCNC: cannot convert spline with cutter radius compensation)",
        ),
    ];
    for (text, want) in cases {
        assert_eq!(error(text), want, "{text:?}");
    }
}
