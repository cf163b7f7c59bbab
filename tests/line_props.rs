//! The reported line (CSV `line`, FMU `status.line`) is the block the tool is on, and G64 P Q
//! keeps P + Q. Checked from the emitted ticks against the programmed geometry, in the default
//! (smooth) mode, where runs of short moves are fitted as one curve and G64 Q merges nearly
//! straight runs:
//! - every tick lies within P (+ Q where a Q is given) of the programmed geometry of the block it
//!   reports, and the reported line never goes back (random runs of micro-moves of any length
//!   ratio, gentle and sharp turns, arcs among them);
//! - on a circle of 0.05 mm chords the reported block is the one nearest the tool (it was a median
//!   19 blocks behind);
//! - G64 P Q: every tick within P + Q of the program (LinuxCNC's rule: Q for the merge into one
//!   line, P for the blending of that line), and a bump of 0.9 Q shows the bound is not P.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

use cnc_motion::config::{Machine, MM};
use cnc_motion::engine::Engine;
use cnc_motion::geometry::{Arc as ArcGeo, Line, Plane, Source};
use proptest::prelude::*;
use std::collections::HashMap;
use std::f64::consts::TAU;
use std::sync::Arc;

/// A program and the programmed geometry of each of its motion lines (SI).
struct Program {
    text: String,
    geometry: HashMap<u32, Source>,
    /// Motion lines in program order.
    order: Vec<u32>,
    at: [f64; 3],
    lines: u32,
    decimals: usize,
}

impl Program {
    fn new(header: &str, decimals: usize) -> Program {
        Program {
            text: header.to_string(),
            geometry: HashMap::new(),
            order: Vec::new(),
            at: [0.0; 3],
            lines: header.lines().count() as u32,
            decimals,
        }
    }
    fn round(&self, x: f64) -> f64 {
        format!("{x:.*}", self.decimals).parse().unwrap()
    }
    fn push(&mut self, code: String, geo: Option<Source>, end: [f64; 3]) {
        self.text.push_str(&code);
        self.text.push('\n');
        self.lines += 1;
        if let Some(g) = geo {
            self.geometry.insert(self.lines, g);
            self.order.push(self.lines);
        }
        self.at = end;
    }
    /// G1 to p (mm).
    fn line(&mut self, p: [f64; 3]) {
        let q = p.map(|x| self.round(x));
        let d = self.decimals;
        let code = format!("G1 X{:.d$} Y{:.d$} Z{:.d$}", q[0], q[1], q[2]);
        let end = q.map(|x| x * MM);
        let l = Line { start: self.at, end };
        self.push(code, Some(Source::Line(l)), end);
    }
    /// G2/G3 in XY to p about the centre offset (i, j) from the current point (mm).
    fn arc(&mut self, p: [f64; 3], ij: [f64; 2], clockwise: bool) {
        let q = p.map(|x| self.round(x));
        let ij = ij.map(|x| self.round(x));
        let d = self.decimals;
        let g = if clockwise { 2 } else { 3 };
        let code = format!(
            "G{g} X{:.d$} Y{:.d$} Z{:.d$} I{:.d$} J{:.d$}",
            q[0], q[1], q[2], ij[0], ij[1]
        );
        let end = q.map(|x| x * MM);
        let centre = [self.at[0] + ij[0] * MM, self.at[1] + ij[1] * MM, self.at[2]];
        let geo = ArcGeo::from_gcode(self.at, end, centre, Plane::XY, clockwise, 0).map(Source::Arc);
        self.push(code, geo, end);
    }
}

/// Run `prog`; for every tick the distance to the programmed geometry of the line it reports,
/// and whether the reported lines run forward. Returns the worst distance (m).
fn worst_reported_distance(prog: &Program, m: &Machine) -> Result<f64, String> {
    let text = format!("{}M30\n", prog.text);
    let mut e = Engine::new(Arc::from(text.as_str()), "p.ngc", m).map_err(|e| e.to_string())?;
    let rank: HashMap<u32, usize> = prog.order.iter().enumerate().map(|(k, &l)| (l, k)).collect();
    let (mut worst, mut last_rank) = (0.0f64, 0usize);
    let mut ticks = 0usize;
    while !e.finished() {
        let t = *e.step().map_err(|e| e.to_string())?;
        ticks += 1;
        if ticks > 5_000_000 {
            return Err("does not finish".into());
        }
        if t.line == 0 {
            continue;
        }
        let Some(geo) = prog.geometry.get(&t.line) else {
            return Err(format!("tick at {:?} reports line {}, not a motion", t.p, t.line));
        };
        let r = rank[&t.line];
        if r < last_rank {
            return Err(format!(
                "the reported line went back to {} at t = {}",
                t.line, t.t
            ));
        }
        last_rank = r;
        worst = worst.max(geo.distance(t.p));
    }
    Ok(worst)
}

#[derive(Clone, Debug)]
struct Move {
    /// Length (mm), log-uniform over 1 µm … 0.5 mm.
    length: f64,
    /// Turn from the previous direction (rad): gentle, or now and then sharp.
    turn: f64,
    /// Climb out of the XY plane (rad).
    climb: f64,
    /// An arc of this sweep (rad) instead of a line, now and then.
    arc: Option<(f64, bool)>,
}

fn a_move() -> impl Strategy<Value = Move> {
    let turn = prop_oneof![
        8 => -0.05..0.05f64,
        1 => -0.5..0.5f64,
        1 => -2.5..2.5f64,
    ];
    let arc = prop_oneof![
        9 => Just(None),
        1 => (0.1..1.5f64, any::<bool>()).prop_map(Some),
    ];
    (-3.0..(0.5f64).log10(), turn, -0.2..0.2f64, arc).prop_map(|(lg, turn, climb, arc)| Move {
        length: 10f64.powf(lg),
        turn,
        climb,
        arc,
    })
}

/// A run of moves: every other one `short` times the length drawn (alternating lengths, as
/// pcb2gcode writes them), coordinates with `decimals` decimals.
fn run_of(moves: &[Move], short: f64, decimals: usize, header: &str) -> Program {
    let mut prog = Program::new(header, decimals);
    let mut p = [0.0f64; 3];
    let mut heading: f64 = 0.3;
    for (k, mv) in moves.iter().enumerate() {
        heading += mv.turn;
        let l = if k % 2 == 1 { short * mv.length } else { mv.length };
        match mv.arc {
            Some((sweep, clockwise)) if l > 0.01 => {
                // Chord l along the heading, the centre on its bisector.
                let r = 0.5 * l / (0.5 * sweep).sin();
                let side = if clockwise { -1.0 } else { 1.0 };
                let q = [p[0] + l * heading.cos(), p[1] + l * heading.sin(), p[2]];
                let h = r * (0.5 * sweep).cos() * side;
                let mid = [0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1])];
                let c = [mid[0] - h * heading.sin(), mid[1] + h * heading.cos()];
                let at = prog.at.map(|x| x / MM);
                prog.arc(q, [c[0] - at[0], c[1] - at[1]], clockwise);
                heading += if clockwise { -sweep } else { sweep };
            }
            _ => {
                let q = [
                    p[0] + l * heading.cos() * mv.climb.cos(),
                    p[1] + l * heading.sin() * mv.climb.cos(),
                    p[2] + l * mv.climb.sin(),
                ];
                prog.line(q);
            }
        }
        p = prog.at.map(|x| x / MM);
    }
    prog
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn every_tick_is_on_the_block_it_reports(
        moves in prop::collection::vec(a_move(), 2..300),
        short in prop_oneof![Just(1.0), 0.05..1.0f64],
        decimals in 4usize..6,
        p in 0.002..0.05f64,
        q in prop_oneof![2 => Just(0.0), 1 => 0.001..0.02f64],
        feed in 300.0..9000.0f64,
    ) {
        let q_word = if q > 0.0 { format!(" Q{q:.4}") } else { String::new() };
        let header = format!("G21 G90 G17 G64 P{p:.4}{q_word}\nG1 F{feed:.0}\n");
        let prog = run_of(&moves, short, decimals, &header);
        let m = Machine::default();
        let bound = (round4(p) + round4(q)) * MM * (1.0 + 1e-6) + 1e-12;
        match worst_reported_distance(&prog, &m) {
            Ok(worst) => prop_assert!(
                worst <= bound,
                "a tick {worst} m from its reported block (P + Q = {bound})\n{}", prog.text
            ),
            Err(e) => prop_assert!(false, "{e}\n{}", prog.text),
        }
    }
}

fn round4(x: f64) -> f64 {
    format!("{x:.4}").parse().unwrap()
}

#[test]
fn on_a_chord_circle_the_reported_block_is_the_nearest() {
    // Circle R 20 as 0.05 mm chords at F3000 and F10000 (one fitted curve): the reported block
    // against the nearest programmed chord, tick by tick.
    for feed in [3000.0, 10000.0] {
        let mut prog = Program::new(&format!("G21 G90 G17 G64 P0.01\nG1 F{feed}\n"), 4);
        let (r, n) = (20.0, (TAU * 20.0 / 0.05f64).round() as usize);
        for k in 1..=n {
            let a = TAU * k as f64 / n as f64;
            prog.line([r * a.cos() - r, r * a.sin(), 0.0]);
        }
        let text = format!("{}M30\n", prog.text);
        let m = Machine::default();
        let mut e = Engine::new(Arc::from(text.as_str()), "c.ngc", &m).unwrap();
        let mut lags = Vec::new();
        let mut cursor = 0usize;
        while !e.finished() {
            let t = *e.step().unwrap();
            if t.line == 0 {
                continue;
            }
            // Nearest chord, searched near the last one (the ticks go round once).
            let from = cursor.saturating_sub(8);
            let nearest = (from..(cursor + 64).min(n))
                .min_by(|&a, &b| {
                    let da = prog.geometry[&prog.order[a]].distance(t.p);
                    let db = prog.geometry[&prog.order[b]].distance(t.p);
                    da.total_cmp(&db)
                })
                .unwrap();
            cursor = nearest;
            let reported = prog.order.iter().position(|&l| l == t.line).unwrap();
            lags.push(nearest as i64 - reported as i64);
        }
        lags.sort();
        let median = lags[lags.len() / 2];
        let worst = lags.iter().map(|l| l.abs()).max().unwrap();
        println!(
            "F{feed}: lag median {median}, largest {worst} blocks over {} ticks",
            lags.len()
        );
        assert_eq!(median, 0);
        assert!(worst <= 1, "{worst}");
    }
}

#[test]
fn g64_q_keeps_p_plus_q() {
    // Points 1 mm apart along X, one of them 0.9·Q off the line: with Q the run is merged into
    // the straight line (the tool passes 0.9·Q from that point's moves, more than P), and every
    // tick stays within P + Q of the program; without Q it stays within P.
    let (p, q) = (0.005, 0.02);
    for with_q in [true, false] {
        let q_word = if with_q { format!(" Q{q}") } else { String::new() };
        let mut prog = Program::new(&format!("G21 G90 G17 G64 P{p}{q_word}\nG1 F3000\n"), 4);
        for k in 1..=20 {
            let y = if k == 10 { 0.9 * q } else { 0.0 };
            prog.line([k as f64, y, 0.0]);
        }
        let text = format!("{}M30\n", prog.text);
        let m = Machine::default();
        let mut e = Engine::new(Arc::from(text.as_str()), "q.ngc", &m).unwrap();
        let mut worst: f64 = 0.0;
        while !e.finished() {
            let t = *e.step().unwrap();
            let d = prog
                .geometry
                .values()
                .map(|g| g.distance(t.p))
                .fold(f64::INFINITY, f64::min);
            worst = worst.max(d);
        }
        let bound = if with_q { p + q } else { p };
        println!(
            "G64 P{p}{q_word}: farthest tick {:.5} mm from the program",
            worst / MM
        );
        assert!(worst <= bound * MM * (1.0 + 1e-6), "{worst}");
        if with_q {
            assert!(worst > p * MM, "the merge should pass the bump: {worst}");
        }
    }
    // And the reported lines of the merged run are the moves the tool is on.
    let mut prog = Program::new(&format!("G21 G90 G17 G64 P{p} Q{q}\nG1 F3000\n"), 4);
    for k in 1..=20 {
        prog.line([k as f64, if k == 10 { 0.9 * q } else { 0.0 }, 0.0]);
    }
    let worst = worst_reported_distance(&prog, &Machine::default()).unwrap();
    assert!(worst <= (p + q) * MM * (1.0 + 1e-6), "{worst}");
}
