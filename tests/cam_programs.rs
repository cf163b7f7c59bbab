//! Programs of the kind CAM systems write, on a realistic machine (every axis 15 000 mm/min,
//! 2 000 mm/s², 50 000 mm/s³; path tolerance 0.01 mm), in the default corner mode. Checked from
//! the emitted ticks as an outsider would: finite differences from rest against the axis limits,
//! every tick against the programmed geometry, the programmed end reached, and the time against
//! the 1-D time-optimal bound (the 7-phase rest-to-rest law over the same length at the feed;
//! it equals Ruckig's to 1e-9, tests/python/test_ruckig.py).

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

mod emitted;

use cnc_motion::config::{AxisLimits, Machine, MM};
use cnc_motion::engine::Engine;
use cnc_motion::feed::{BlockRequest, FeedLaw, Limits, Profile, ProfileKind};
use cnc_motion::geometry::{Arc as ArcGeo, Line, Plane, Source};
use std::f64::consts::{PI, TAU};
use std::fmt::Write;
use std::sync::Arc;

const A: f64 = 2.0;
const J: f64 = 50.0;
const V: f64 = 0.25;
const TOL: f64 = 0.01 * MM;

fn machine() -> Machine {
    Machine {
        axes: [AxisLimits {
            max_velocity: V,
            max_acceleration: A,
            max_jerk: J,
        }; 3],
        max_feed: V,
        path_tolerance: TOL,
        ..Machine::default()
    }
}

/// A program being written, with its programmed geometry (SI) as the reader will see it.
struct Program {
    text: String,
    at: [f64; 3],
    geometry: Vec<Source>,
    length: f64,
}

fn round4(x: f64) -> f64 {
    format!("{x:.4}").parse().unwrap()
}

impl Program {
    fn new(feed_mm_min: f64) -> Program {
        Program {
            text: format!("G21 G90 G17 G64\nG1 F{feed_mm_min}\n"),
            at: [0.0; 3],
            geometry: Vec::new(),
            length: 0.0,
        }
    }
    /// G1 to (mm), coordinates written with 4 decimals as CAM output is.
    fn line(&mut self, p: [f64; 3]) {
        self.line_to_decimals(p, 4);
    }
    /// G1 to (mm), coordinates written with `d` decimals.
    fn line_to_decimals(&mut self, p: [f64; 3], d: usize) {
        let q = p.map(|x| format!("{x:.d$}").parse::<f64>().unwrap());
        writeln!(self.text, "G1 X{:.d$} Y{:.d$} Z{:.d$}", q[0], q[1], q[2]).unwrap();
        let end = q.map(|x| x * MM);
        let l = Line { start: self.at, end };
        if l.length() > 0.0 {
            self.length += l.length();
            self.geometry.push(Source::Line(l));
        }
        self.at = end;
    }
    /// G2/G3 in XY to `p` about centre offset (i, j) from the current point (mm).
    fn arc(&mut self, p: [f64; 3], ij: [f64; 2], clockwise: bool) {
        let q = p.map(round4);
        let ij = ij.map(round4);
        let g = if clockwise { 2 } else { 3 };
        writeln!(
            self.text,
            "G{g} X{:.4} Y{:.4} Z{:.4} I{:.4} J{:.4}",
            q[0], q[1], q[2], ij[0], ij[1]
        )
        .unwrap();
        let end = q.map(|x| x * MM);
        let center = [self.at[0] + ij[0] * MM, self.at[1] + ij[1] * MM, self.at[2]];
        let a = ArcGeo::from_gcode(self.at, end, center, Plane::XY, clockwise, 0).expect("an arc");
        self.length += a.length();
        self.geometry.push(Source::Arc(a));
        self.at = end;
    }
}

struct Outcome {
    time: f64,
    worst_fd: [f64; 3],
    worst_deviation: f64,
}

/// Run the program; check limits (finite differences from rest), tolerance and the end point.
fn run(program: &Program, m: &Machine) -> Outcome {
    let text = format!("{}M30\n", program.text);
    let mut e = Engine::new(Arc::from(text.as_str()), "cam.ngc", m).expect("valid program");
    let t = m.interpolation_period;
    let mut p: Vec<[f64; 3]> = vec![[0.0; 3]; 3];
    let mut cursor = 0usize;
    let mut worst_deviation: f64 = 0.0;
    let bound_ticks = 10_000_000;
    while !e.finished() {
        let tick = *e.step().expect("no runtime error");
        p.push(tick.p);
        // Nearest programmed piece, searched forward from the last one (ticks move forward).
        let geo = &program.geometry;
        let (mut best, mut best_k) = (f64::INFINITY, cursor);
        let from = cursor.saturating_sub(16);
        for (k, g) in geo.iter().enumerate().take(cursor + 400).skip(from) {
            let d = g.distance(tick.p);
            if d < best {
                (best, best_k) = (d, k);
            }
        }
        cursor = best_k;
        worst_deviation = worst_deviation.max(best);
        assert!(p.len() < bound_ticks, "program does not finish");
    }
    let end = e.tick().p;
    let d_end = ((end[0] - program.at[0]).powi(2)
        + (end[1] - program.at[1]).powi(2)
        + (end[2] - program.at[2]).powi(2))
    .sqrt();
    assert!(d_end < 1e-12, "end point off by {d_end}");
    let peak = emitted::peak_differences(&p, t);
    let limits = [[V; 3], [A; 3], m.axes.map(|a| a.max_jerk)];
    let worst_fd: [f64; 3] = std::array::from_fn(|order| {
        (0..3)
            .map(|i| peak[order][i] / limits[order][i])
            .fold(0.0, f64::max)
    });
    for (n, w) in ["velocity", "acceleration", "jerk"].iter().zip(worst_fd) {
        assert!(w <= 1.0 + 1e-6, "finite-difference {n} at {w} × the limit");
    }
    assert!(
        worst_deviation <= TOL * (1.0 + 1e-6),
        "tick {:.6} mm off the programmed path",
        worst_deviation / MM
    );
    Outcome {
        time: e.motion_time(),
        worst_fd,
        worst_deviation,
    }
}

/// 1-D time-optimal bound: rest to rest over `length` at `feed` with the axis limits.
fn optimal_time(length: f64, feed: f64) -> f64 {
    let limits = Limits {
        v_max: feed,
        a_max: A,
        j_max: J,
        snap_max: f64::INFINITY,
    };
    let req = BlockRequest {
        length,
        v_in: 0.0,
        v_out: 0.0,
        v_feed: feed,
        limits,
    };
    Profile::plan(ProfileKind::Scurve7, &req).duration()
}

fn report(name: &str, program: &Program, o: &Outcome, feed_mm_min: f64) -> f64 {
    let ratio = o.time / optimal_time(program.length, feed_mm_min / 60.0 * MM);
    println!(
        "{name}: {:.3} s, {:.2} × the 1-D optimum; fd v/a/j {:.6}/{:.6}/{:.6} of the limits; deviation {:.5} mm",
        o.time,
        ratio,
        o.worst_fd[0],
        o.worst_fd[1],
        o.worst_fd[2],
        o.worst_deviation / MM
    );
    ratio
}

/// A circle of radius 20 mm through the origin as chords of `chord` mm.
fn chord_circle(chord: f64, feed: f64) -> Program {
    let r = 20.0;
    let n = (TAU * r / chord).round() as usize;
    let mut prog = Program::new(feed);
    for k in 1..=n {
        let a = TAU * k as f64 / n as f64;
        prog.line([r * a.cos() - r, r * a.sin(), 0.0]);
    }
    prog
}

#[test]
fn chord_circles_run_near_the_time_optimum() {
    let m = machine();
    for chord in [0.05, 0.2, 1.0] {
        for feed in [3000.0, 10000.0] {
            let prog = chord_circle(chord, feed);
            let o = run(&prog, &m);
            let ratio = report(
                &format!("circle R20, {chord} mm chords, F{feed}"),
                &prog,
                &o,
                feed,
            );
            // Within 1.15 of the 1-D bound, also at F10000, where the centripetal acceleration
            // takes 1389 of the 2000 mm/s² at full speed.
            let bound = 1.15;
            assert!(ratio <= bound, "{chord} mm chords at F{feed}: {ratio:.3}");
        }
    }
}

#[test]
fn spiral_pocket_in_micro_segments() {
    // Archimedean spiral r = 1 mm + 2 mm per turn out to 15 mm, 0.1 mm segments, F3000.
    let m = machine();
    let mut prog = Program::new(3000.0);
    let (r0, pitch) = (1.0, 2.0);
    prog.line([r0, 0.0, 0.0]);
    let mut phi: f64 = 0.0;
    while r0 + pitch * phi / TAU < 15.0 {
        let r = r0 + pitch * phi / TAU;
        phi += 0.1 / r;
        let r = r0 + pitch * phi / TAU;
        prog.line([r * phi.cos(), r * phi.sin(), 0.0]);
    }
    let o = run(&prog, &m);
    let ratio = report("spiral pocket", &prog, &o, 3000.0);
    assert!(ratio <= 1.5, "{ratio}");
}

#[test]
fn surface_raster_in_zig_zag_rows() {
    // z = 2 sin(x/5) cos(y/7) mm, rows along x 1 mm apart, segments 0.1–0.3 mm, F3000.
    let m = machine();
    let mut prog = Program::new(3000.0);
    let z = |x: f64, y: f64| 2.0 * (x / 5.0).sin() * (y / 7.0).cos();
    let mut seed: u64 = 12345;
    let mut step = || {
        seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        0.1 + 0.2 * ((seed >> 11) as f64 / (1u64 << 53) as f64)
    };
    prog.line([0.0, 0.0, z(0.0, 0.0)]);
    for row in 0..8 {
        let y = row as f64;
        let forward = row % 2 == 0;
        let mut x: f64 = if forward { 0.0 } else { 20.0 };
        loop {
            x += if forward { step() } else { -step() };
            let xc = x.clamp(0.0, 20.0);
            prog.line([xc, y, z(xc, y)]);
            if xc == 0.0 || xc == 20.0 {
                break;
            }
        }
        prog.line([x.clamp(0.0, 20.0), y + 1.0, z(x.clamp(0.0, 20.0), y + 1.0)]);
    }
    let o = run(&prog, &m);
    let ratio = report("surface raster", &prog, &o, 3000.0);
    assert!(ratio <= 1.5, "{ratio}");
}

#[test]
fn zig_zag_longer_than_the_window_then_a_line() {
    // 600 moves of 0.05 × ±0.025 mm, then 10 mm: no skip, no jump (|Δp| ≤ v_max·T per tick).
    for window in [16, 256] {
        let mut m = machine();
        m.lookahead_blocks = window;
        let mut prog = Program::new(3000.0);
        for k in 0..600 {
            let y = if k % 2 == 0 { 0.025 } else { 0.0 };
            prog.line([0.05 * (k + 1) as f64, y, 0.0]);
        }
        prog.line([0.05 * 600.0 + 10.0, 0.0, 0.0]);
        let o = run(&prog, &m);
        report(&format!("zig-zag, window {window}"), &prog, &o, 3000.0);
    }
}

#[test]
fn line_arc_petals_with_non_tangent_joins() {
    let m = machine();
    let mut prog = Program::new(4000.0);
    for k in 0..6 {
        let a0 = PI / 3.0 * k as f64;
        let a1 = a0 + PI / 6.0;
        let (r, c) = (10.0, [0.0, 0.0]);
        prog.line([r * a0.cos(), r * a0.sin(), 0.0]);
        // Arc about the origin to a1 (meets the radial line at 90°), back to the centre.
        let ij = [c[0] - prog.at[0] / MM, c[1] - prog.at[1] / MM];
        prog.arc([r * a1.cos(), r * a1.sin(), 0.0], ij, false);
        prog.line([0.0, 0.0, 0.0]);
    }
    let o = run(&prog, &m);
    report("line-arc petals", &prog, &o, 4000.0);
}

#[test]
fn arcs_meeting_with_small_kinks() {
    let m = machine();
    for kink_deg in [0.002f64, 0.02, 0.1, 0.5] {
        let mut prog = Program::new(3000.0);
        // Quarter arc R 10 from the origin, then an arc of R 15 whose start tangent is turned
        // by the kink, then a line out.
        prog.arc([10.0, 10.0, 0.0], [10.0, 0.0], true);
        let kink = kink_deg.to_radians();
        // Tangent at the end of the first arc is +x; the second arc starts along (cos k, sin k)
        // and turns clockwise: its centre is 15 mm to the right of that tangent.
        let t = [kink.cos(), kink.sin()];
        let ij = [15.0 * t[1], -15.0 * t[0]];
        let c = [10.0 + ij[0], 10.0 + ij[1]];
        let end_angle = (10.0 - c[1]).atan2(10.0 - c[0]) - PI / 3.0;
        prog.arc(
            [c[0] + 15.0 * end_angle.cos(), c[1] + 15.0 * end_angle.sin(), 0.0],
            ij,
            true,
        );
        let at = prog.at.map(|x| x / MM);
        prog.line([at[0] + 5.0, at[1] - 5.0, 0.0]);
        let o = run(&prog, &m);
        report(&format!("arcs with a {kink_deg}° kink"), &prog, &o, 3000.0);
    }
}

#[test]
fn g64_q_merges_nearly_collinear_moves() {
    // 200 points 0.1 mm apart along X, Y jittering by ±2 µm, ending on Y0: with Q 5 µm (the
    // greedy merge sees lines to ±2 µm ends, so inner points up to 4 µm off) the run is one
    // straight move, every tick on Y = 0; with Q 1 µm it is not.
    let m = machine();
    for (q, straight) in [(0.005, true), (0.001, false)] {
        let mut text = format!("G21 G90 G17 G64 P0.01 Q{q}\nG1 F3000\n");
        for k in 1..=200 {
            let y = if k == 200 {
                0.0
            } else if k % 2 == 0 {
                0.002
            } else {
                -0.002
            };
            writeln!(text, "X{:.4} Y{:.4}", 0.1 * k as f64, y).unwrap();
        }
        text.push_str("M30\n");
        let mut e = Engine::new(Arc::from(text.as_str()), "q.ngc", &m).unwrap();
        let mut worst_y: f64 = 0.0;
        while !e.finished() {
            worst_y = worst_y.max(e.step().unwrap().p[1].abs());
        }
        assert_eq!(worst_y < 1e-12, straight, "Q {q}: |y| up to {worst_y}");
        assert!((e.tick().p[0] - 0.02).abs() < 1e-12);
    }
}

#[test]
fn long_lines_with_rounding_kinks_run_at_the_feed() {
    // Nearly collinear 10 mm lines, the kinks (1e-5 rad) of 4-decimal output: no stop at any of
    // them, at a finishing feed and a roughing one (before: a stop at every kink, 1.02× at F600).
    for feed in [600.0, 3000.0] {
        let mut prog = Program::new(feed);
        for k in 1..=8 {
            prog.line([10.0 * k as f64, if k % 2 == 1 { 0.0001 } else { 0.0 }, 0.0]);
        }
        let o = run(&prog, &machine());
        let ratio = report(&format!("kinked lines, F{feed}"), &prog, &o, feed);
        assert!(ratio <= 1.005, "F{feed}: {ratio}");
    }
}

#[test]
fn sub_tolerance_jogs_are_absorbed() {
    // A 0.0001 mm jog (a tenth of a micrometre: CAM rounding) before every 10 mm line of a
    // square, sideways and along: each would otherwise be a piece of its own with two sharp turns.
    let square = [[20.0, 0.0], [20.0, 20.0], [0.0, 20.0], [0.0, 0.0]];
    let mut with_jogs = Program::new(3000.0);
    let mut plain = Program::new(3000.0);
    let mut at = [0.0, 0.0];
    for c in square {
        for half in [0.5, 1.0] {
            let p = [at[0] + half * (c[0] - at[0]), at[1] + half * (c[1] - at[1])];
            with_jogs.line([p[0] + 0.0001, p[1], 0.0]);
            with_jogs.line([p[0], p[1], 0.0]);
            plain.line([p[0], p[1], 0.0]);
        }
        at = c;
    }
    let m = machine();
    let jogs = run(&with_jogs, &m);
    let reference = run(&plain, &m);
    report("square with 0.0001 mm jogs", &with_jogs, &jogs, 3000.0);
    let ratio = jogs.time / reference.time;
    println!("square with jogs: {ratio:.4} × the plain square's time");
    assert!(ratio <= 1.01, "jogs cost {ratio:.4} × the plain square's time");
}

#[test]
fn sub_tolerance_jogs_before_an_arc_and_at_the_end_are_absorbed() {
    // A 0.0001 mm jog where no line follows to take it: before an arc, and at the program's end.
    // Run alone, each is a piece of its own with sharp turns (in effect a stop); the line before
    // ends where the jog ends instead (path/micro.rs).
    let mut with_jogs = Program::new(3000.0);
    let mut plain = Program::new(3000.0);
    for (prog, jog) in [(&mut with_jogs, true), (&mut plain, false)] {
        prog.line([10.0, 0.0, 0.0]);
        if jog {
            prog.line([10.0, 0.0001, 0.0]);
        }
        prog.arc([15.0, 5.0, 0.0], [0.0, 5.0], false);
        prog.line([15.0, 15.0, 0.0]);
        if jog {
            prog.line([15.0001, 15.0, 0.0]);
        }
    }
    let m = machine();
    let jogs = run(&with_jogs, &m);
    let reference = run(&plain, &m);
    report(
        "line, arc and line with 0.0001 mm jogs",
        &with_jogs,
        &jogs,
        3000.0,
    );
    let ratio = jogs.time / reference.time;
    println!("with jogs before the arc and at the end: {ratio:.4} × the time without");
    assert!(ratio <= 1.01, "jogs cost {ratio:.4} × the time without");
}

/// A straight line of `pairs` × (`long` + `short`) µm from the origin along `angle` (deg) at
/// `feed`, written as moves alternating `long` and `short` µm with 5 decimals (pcb2gcode's
/// isolation output looks like this), and the same line as one G1.
fn alternating(pairs: usize, long: f64, short: f64, angle: f64, feed: f64) -> (Program, Program) {
    let (c, s) = (angle.to_radians().cos(), angle.to_radians().sin());
    let (mut micro, mut one) = (Program::new(feed), Program::new(feed));
    let mut d = 0.0;
    for k in 0..2 * pairs {
        d += 1e-3 * if k % 2 == 0 { long } else { short };
        micro.line_to_decimals([d * c, d * s, 0.0], 5);
    }
    one.line_to_decimals([d * c, d * s, 0.0], 5);
    (micro, one)
}

#[test]
fn alternating_micro_moves_run_as_the_line_they_stand_for() {
    // Before: a cliff at a 4:1 length ratio between neighbours (8/1 µm moves over 9 mm at F3000:
    // 5.76 s against 0.24 s as one G1; 40 moves of 8/1.9 µm 0.124 s against 0.049 s), and
    // exactly collinear moves crawled (8/1 µm at F600: 18.4 s against 0.93 s). Now every ratio
    // runs as the one G1 does, at jerk 5e4 and 1e9 mm/s³.
    let families = [
        (1000, 8.0, 1.0, 30.0, 3000.0),
        (1000, 8.0, 2.0, 30.0, 3000.0),
        (20, 8.0, 2.0, 30.0, 3000.0),
        (20, 8.0, 1.9, 30.0, 3000.0),
        (20, 8.0, 1.0, 30.0, 3000.0),
        (1000, 8.0, 1.0, 0.0, 600.0),
        (1000, 8.0, 1.0, 0.0, 3000.0),
        (20, 8.0, 2.0, 0.0, 3000.0),
    ];
    for jerk in [J, 1e6] {
        let mut m = machine();
        for a in &mut m.axes {
            a.max_jerk = jerk;
        }
        for (pairs, long, short, angle, feed) in families {
            let (micro, one) = alternating(pairs, long, short, angle, feed);
            let (o, reference) = (run(&micro, &m), run(&one, &m));
            let ratio = o.time / reference.time;
            println!(
                "jerk {:.0e} mm/s³, {} moves of {long}/{short} µm at {angle}°, F{feed}: {:.3} s, one G1 {:.3} s ({ratio:.4}×)",
                jerk * 1e3,
                2 * pairs,
                o.time,
                reference.time
            );
            assert!(
                ratio <= 1.01,
                "{long}/{short} µm at {angle}°, F{feed}: {ratio:.4}×"
            );
        }
    }
}
