//! Generated families of curved programs (issue 19), in the default corner mode on a machine of
//! 250 mm/s, 2000 mm/s² per axis with the jerk limit at 5e4 and lifted to 1e9 mm/s³, tolerance
//! 0.01 mm: full circles from rest at F6000 … F15000, a spiral of 1000 short G2 R arcs, an
//! Archimedean G1 spiral pocket, a surface raster. Every run is checked as an outsider would:
//! finite differences of the ticks from rest within every axis limit, every tick within the
//! tolerance of the programmed geometry, the programmed end reached exactly. And the time never
//! grows with the feed or with the jerk limit. (Their times against toppra's acceleration-limited
//! optimum on the same emitted path are in tests/python/test_toppra.py.)

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

mod emitted;

use cnc_motion::config::{AxisLimits, Machine, MM};
use cnc_motion::engine::Engine;
use cnc_motion::geometry::{Arc as ArcGeo, Line, Plane, Source};
use std::f64::consts::TAU;
use std::fmt::Write;
use std::sync::Arc;

const V: f64 = 0.25;
const A: f64 = 2.0;
const TOL: f64 = 0.01 * MM;

fn machine(jerk: f64) -> Machine {
    Machine {
        axes: [AxisLimits {
            max_velocity: V,
            max_acceleration: A,
            max_jerk: jerk,
        }; 3],
        max_feed: V,
        path_tolerance: TOL,
        ..Machine::default()
    }
}

fn round4(x: f64) -> f64 {
    format!("{x:.4}").parse().unwrap()
}

/// A program and its programmed geometry (SI, machine coordinates), written from a start point
/// that G92 names at the machine's origin (so machine = program − start).
struct Program {
    text: String,
    start: [f64; 3],
    /// The current point, in program coordinates (mm).
    at_mm: [f64; 3],
    at: [f64; 3],
    geometry: Vec<Source>,
}

impl Program {
    fn new(start_mm: [f64; 3]) -> Program {
        let s = start_mm.map(round4);
        Program {
            text: format!(
                "G21 G90 G17 G64 P0.01\nG92 X{:.4} Y{:.4} Z{:.4}\n",
                s[0], s[1], s[2]
            ),
            start: s,
            at_mm: s,
            at: [0.0; 3],
            geometry: Vec::new(),
        }
    }
    fn machine(&self, q: [f64; 3]) -> [f64; 3] {
        std::array::from_fn(|i| (q[i] - self.start[i]) * MM)
    }
    fn line(&mut self, p: [f64; 3], feed: f64) {
        let q = p.map(round4);
        writeln!(self.text, "G1 X{:.4} Y{:.4} Z{:.4} F{feed}", q[0], q[1], q[2]).unwrap();
        let end = self.machine(q);
        self.geometry.push(Source::Line(Line { start: self.at, end }));
        (self.at, self.at_mm) = (end, q);
    }
    /// G2/G3 in XY to `p` about the centre offset (i, j) from the current point (mm).
    fn arc(&mut self, p: [f64; 3], ij: [f64; 2], clockwise: bool, feed: f64) {
        let (q, ij) = (p.map(round4), ij.map(round4));
        let q = [q[0], q[1], self.at_mm[2]];
        let g = if clockwise { 2 } else { 3 };
        writeln!(
            self.text,
            "G{g} X{:.4} Y{:.4} I{:.4} J{:.4} F{feed}",
            q[0], q[1], ij[0], ij[1]
        )
        .unwrap();
        let end = self.machine(q);
        let centre = [self.at[0] + ij[0] * MM, self.at[1] + ij[1] * MM, self.at[2]];
        let arc = ArcGeo::from_gcode(self.at, end, centre, Plane::XY, clockwise, 0).expect("an arc");
        self.geometry.push(Source::Arc(arc));
        (self.at, self.at_mm) = (end, q);
    }
}

/// Run to the end; check limits (finite differences from rest), tolerance and the end point;
/// the motion time.
fn run(prog: &Program, m: &Machine) -> f64 {
    let text = format!("{}M30\n", prog.text);
    let mut e = Engine::new(Arc::from(text.as_str()), "family.ngc", m).expect("valid program");
    let t = m.interpolation_period;
    let mut p: Vec<[f64; 3]> = vec![e.tick().p; 3];
    let (mut cursor, mut worst) = (0usize, 0.0f64);
    while !e.finished() {
        let tick = *e.step().expect("no runtime error");
        p.push(tick.p);
        let from = cursor.saturating_sub(16);
        let (mut best, mut best_k) = (f64::INFINITY, cursor);
        for (k, g) in prog.geometry.iter().enumerate().take(cursor + 400).skip(from) {
            let d = g.distance(tick.p);
            if d < best {
                (best, best_k) = (d, k);
            }
        }
        cursor = best_k;
        worst = worst.max(best);
        assert!(p.len() < 10_000_000, "the program does not finish");
    }
    assert!(
        worst <= TOL * (1.0 + 1e-6),
        "a tick {:.6} mm off the path",
        worst / MM
    );
    let end = e.tick().p;
    assert!((0..3).all(|i| (end[i] - prog.at[i]).abs() < 1e-12), "end {end:?}");
    emitted::assert_within(&p, t, V, A, m.axes[0].max_jerk);
    e.motion_time()
}

/// A full circle of R 35.9 mm from rest (the issue's `G2 X0 Y0 I35.9 J0`).
fn circle(feed: f64) -> Program {
    let mut prog = Program::new([0.0; 3]);
    prog.arc([0.0, 0.0, 0.0], [35.9, 0.0], true, feed);
    prog
}

#[test]
fn circles_from_rest_are_no_slower_at_a_higher_feed() {
    for jerk in [50.0, 1e6] {
        let m = machine(jerk);
        let times: Vec<f64> = [6000.0, 9000.0, 12000.0, 15000.0]
            .iter()
            .map(|&f| run(&circle(f), &m))
            .collect();
        println!(
            "circle R 35.9 from rest, jerk {} mm/s³, F6000 … F15000: {times:.3?} s",
            jerk / MM
        );
        for w in times.windows(2) {
            assert!(w[1] <= w[0] * (1.0 + 1e-3), "{times:?}");
        }
    }
}

/// 1000 G2 arcs, 50 a turn, the radius shrinking linearly from 50 to 0.05 mm (each arc's
/// radius the mean of its ends': nearly tangent, the curvature steps at every joint).
fn arc_spiral() -> Program {
    let (r0, r1, n) = (50.0, 0.05, 1000);
    let mut prog = Program::new([r0, 0.0, 0.0]);
    let (mut r, mut ang) = (r0, 0.0f64);
    for _ in 0..n {
        let r2 = r - (r0 - r1) / n as f64;
        ang -= TAU / 50.0;
        let q = [round4(r2 * ang.cos()), round4(r2 * ang.sin())];
        let p = [prog.at_mm[0], prog.at_mm[1]];
        // The centre on the chord's bisector at the mean radius, to the right (G2).
        let chord = [q[0] - p[0], q[1] - p[1]];
        let c = chord[0].hypot(chord[1]);
        let rad = (0.5 * (r + r2)).max(0.5 * c * 1.0001);
        let h = (rad * rad - 0.25 * c * c).sqrt();
        let centre = [
            0.5 * (p[0] + q[0]) + h * chord[1] / c,
            0.5 * (p[1] + q[1]) - h * chord[0] / c,
        ];
        prog.arc(
            [q[0], q[1], 0.0],
            [centre[0] - p[0], centre[1] - p[1]],
            true,
            15000.0,
        );
        r = r2;
    }
    prog
}

/// An Archimedean spiral pocket r 0.5 → 20 mm, 2 mm a turn, in G1 moves of about 0.2 mm, F6000.
fn g1_spiral() -> Program {
    let (r0, b) = (0.5, 2.0 / TAU);
    let mut prog = Program::new([r0, 0.0, 0.0]);
    let (mut th, mut r) = (0.0f64, r0);
    while r < 20.0 {
        th += 0.2 / r.max(0.1);
        r = r0 + b * th;
        prog.line([r * th.cos(), r * th.sin(), 0.0], 6000.0);
    }
    prog
}

/// Zig-zag rows over z = 0.5 sin(x/3) cos(y/2) mm, 0.2 mm G1 moves, rows 0.5 mm apart, F3000.
fn raster() -> Program {
    let mut prog = Program::new([0.0; 3]);
    for row in 0..10 {
        let y = 0.5 * row as f64;
        for i in 0..=100 {
            let x = if row % 2 == 0 {
                0.2 * i as f64
            } else {
                20.0 - 0.2 * i as f64
            };
            prog.line([x, y, 0.5 * (x / 3.0).sin() * (y / 2.0).cos()], 3000.0);
        }
    }
    prog
}

#[test]
fn curved_families_keep_every_limit_and_are_no_slower_without_the_jerk_limit() {
    for (name, prog) in [
        ("spiral of 1000 short G2 arcs", arc_spiral()),
        ("G1 spiral pocket", g1_spiral()),
        ("raster", raster()),
    ] {
        let jerk_limited = run(&prog, &machine(50.0));
        let lifted = run(&prog, &machine(1e6));
        println!("{name}: {jerk_limited:.3} s at jerk 5e4, {lifted:.3} s at 1e9");
        assert!(lifted <= jerk_limited * (1.0 + 1e-3), "{name}");
    }
}
