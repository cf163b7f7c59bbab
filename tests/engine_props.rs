//! Properties of the whole motion core (reader → path → plan → feed → interp) on random programs:
//! every interpolated axis velocity, acceleration and jerk within its limit (analytic values and
//! finite differences of the emitted positions), end point exact, path length conserved.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

use cnc_motion::config::Machine;
use cnc_motion::engine::Engine;
use cnc_motion::feed::ProfileKind;
use proptest::prelude::*;
use std::fmt::Write;
use std::sync::Arc;

/// Relative slack on analytic values (rounding only).
const REL: f64 = 1e-9;

struct Run {
    p: Vec<[f64; 3]>,
    v: Vec<[f64; 3]>,
    a: Vec<[f64; 3]>,
    j: Vec<[f64; 3]>,
    distance: f64,
    end: [f64; 3],
}

fn run(program: &str, machine: &Machine) -> Run {
    let mut e = Engine::new(Arc::from(program), "prop.ngc", machine).expect("valid program");
    let mut r = Run {
        p: vec![e.tick().p],
        v: vec![],
        a: vec![],
        j: vec![],
        distance: 0.0,
        end: [0.0; 3],
    };
    let mut n = 0;
    while !e.finished() {
        let t = *e.step().expect("no runtime error");
        r.p.push(t.p);
        r.v.push(t.v);
        r.a.push(t.a);
        r.j.push(t.j);
        n += 1;
        assert!(n < 5_000_000, "program does not finish");
    }
    r.distance = e.tick().distance;
    r.end = e.tick().p;
    r
}

/// A program of G1 moves through the given points (mm) at the given feeds (mm/min).
fn line_program(points: &[[f64; 3]], feeds: &[f64], exact_stop: bool) -> (String, f64, [f64; 3]) {
    let mut text = String::from("G21 G90 G17\n");
    text.push_str(if exact_stop { "G61\n" } else { "G64\n" });
    let mut from = [0.0; 3];
    let mut length = 0.0;
    for (p, f) in points.iter().zip(feeds) {
        writeln!(text, "G1 X{:.4} Y{:.4} Z{:.4} F{:.1}", p[0], p[1], p[2], f).unwrap();
        // The program's own rounding of the coordinates is what the machine must follow.
        let q = p.map(|x| format!("{x:.4}").parse::<f64>().unwrap());
        length += ((q[0] - from[0]).powi(2) + (q[1] - from[1]).powi(2) + (q[2] - from[2]).powi(2)).sqrt();
        from = q;
    }
    text.push_str("M30\n");
    (text, length * 1e-3, from.map(|x| x * 1e-3))
}

fn check_limits(r: &Run, machine: &Machine, check_jerk: bool) {
    let t = machine.interpolation_period;
    for i in 0..3 {
        let lim = &machine.axes[i];
        for k in 0..r.v.len() {
            assert!(
                r.v[k][i].abs() <= lim.max_velocity * (1.0 + REL),
                "v[{k}][{i}] = {}",
                r.v[k][i]
            );
            assert!(
                r.a[k][i].abs() <= lim.max_acceleration * (1.0 + REL),
                "a[{k}][{i}] = {}",
                r.a[k][i]
            );
            if check_jerk {
                assert!(
                    r.j[k][i].abs() <= lim.max_jerk * (1.0 + REL),
                    "j[{k}][{i}] = {}",
                    r.j[k][i]
                );
            }
        }
        // Finite differences are averages of the derivative over the window (B-spline weights),
        // so they obey the same bounds; the slack covers the rounding of positions (~1e-17 m).
        let p: Vec<f64> = r.p.iter().map(|q| q[i]).collect();
        for k in 1..p.len() {
            let v = (p[k] - p[k - 1]) / t;
            assert!(v.abs() <= lim.max_velocity * (1.0 + 1e-6) + 1e-9, "fd v = {v}");
        }
        for k in 2..p.len() {
            let a = (p[k] - 2.0 * p[k - 1] + p[k - 2]) / (t * t);
            assert!(
                a.abs() <= lim.max_acceleration * (1.0 + 1e-6) + 1e-6,
                "fd a = {a} at {k}"
            );
        }
        if check_jerk {
            for k in 3..p.len() {
                let j = (p[k] - 3.0 * p[k - 1] + 3.0 * p[k - 2] - p[k - 3]) / (t * t * t);
                assert!(j.abs() <= lim.max_jerk * (1.0 + 1e-6) + 1e-2, "fd j = {j} at {k}");
            }
        }
    }
}

fn point() -> impl Strategy<Value = [f64; 3]> {
    [-50.0..50.0f64, -50.0..50.0f64, -20.0..20.0f64]
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn random_line_programs_stay_within_limits(
        points in prop::collection::vec(point(), 1..8),
        feeds in prop::collection::vec(300.0..8000.0f64, 8),
        exact_stop in any::<bool>(),
        kind in prop::sample::select(vec![ProfileKind::Scurve7, ProfileKind::Trapezoid]),
    ) {
        let machine = Machine { profile: kind, ..Machine::default() };
        let (text, length, end) = line_program(&points, &feeds, exact_stop);
        let r = run(&text, &machine);
        for i in 0..3 {
            prop_assert!((r.end[i] - end[i]).abs() <= 1e-12, "end {:?} vs {:?}", r.end, end);
        }
        if exact_stop {
            // Nothing is cut at corners: the distance travelled is the programmed length.
            prop_assert!((r.distance - length).abs() <= 1e-9 * length.max(1.0));
        } else {
            prop_assert!(r.distance <= length * (1.0 + 1e-12) + 1e-12);
        }
        check_limits(&r, &machine, kind != ProfileKind::Trapezoid);
    }
}

/// Steps the engine and checks every tick against the axis limits (analytic a and j, and the
/// change of a per tick against J·T).
fn step_checked(e: &mut Engine, last_a: &mut [f64; 3]) {
    let t = *e.step().unwrap();
    let m = e.machine().clone();
    for (i, lim) in m.axes.iter().enumerate() {
        assert!(
            t.v[i].abs() <= lim.max_velocity * (1.0 + REL),
            "v {} at {}",
            t.v[i],
            t.t
        );
        assert!(
            t.a[i].abs() <= lim.max_acceleration * (1.0 + REL),
            "a {} at {}",
            t.a[i],
            t.t
        );
        assert!(
            t.j[i].abs() <= lim.max_jerk * (1.0 + REL),
            "j {} at {}",
            t.j[i],
            t.t
        );
        let da = (t.a[i] - last_a[i]).abs();
        assert!(
            da <= lim.max_jerk * m.interpolation_period * (1.0 + REL) + 1e-12,
            "Δa {da} at {}",
            t.t
        );
        last_a[i] = t.a[i];
    }
}

#[test]
fn override_and_hold_change_speed_smoothly_and_resume() {
    let machine = Machine::default();
    let text = "G21 G90\nG1 X500 F6000\nM30\n";
    let mut e = Engine::new(Arc::from(text), "hold.ngc", &machine).unwrap();
    let mut a = [0.0; 3];
    for _ in 0..1500 {
        step_checked(&mut e, &mut a);
    }
    let cruise = e.tick().feed;
    assert!(
        (cruise - 0.1).abs() < 1e-12,
        "cruising at the programmed feed, got {cruise}"
    );
    e.set_feed_hold(true);
    let mut last = e.tick().p[0];
    let mut stopped = false;
    for _ in 0..2000 {
        step_checked(&mut e, &mut a);
        assert!(e.tick().p[0] >= last, "never moves backwards");
        last = e.tick().p[0];
        if e.tick().feed == 0.0 {
            stopped = true;
            break;
        }
    }
    assert!(stopped, "hold stops");
    let held = e.tick().p[0];
    for _ in 0..100 {
        step_checked(&mut e, &mut a);
    }
    assert_eq!(e.tick().p[0], held, "stays on the path while held");
    e.set_feed_hold(false);
    e.set_feed_override(0.5);
    for _ in 0..2000 {
        step_checked(&mut e, &mut a);
    }
    assert!(
        (e.tick().feed - 0.05).abs() < 1e-9,
        "50 % override, got {}",
        e.tick().feed
    );
    // Back to 150 % while cruising: up, then the path's own stop at the end, all within limits.
    e.set_feed_override(1.5);
    while !e.finished() {
        step_checked(&mut e, &mut a);
    }
    assert_eq!(e.tick().p, [0.5, 0.0, 0.0]);
    assert!(
        (e.tick().distance - 0.5).abs() < 1e-12,
        "nothing of the path lost or doubled"
    );
}

#[test]
fn state_round_trip_is_bit_identical() {
    let machine = Machine::default();
    let text = "G21 G90 G64\nG1 X10 Y5 F3000\nG1 X20 Y0\nG1 X25 Y10 Z-2\nM30\n";
    let mut a = Engine::new(Arc::from(text), "s.ngc", &machine).unwrap();
    for _ in 0..137 {
        a.step().unwrap();
    }
    let saved = a.save_state();
    let mut b = Engine::new(Arc::from(text), "s.ngc", &machine).unwrap();
    b.restore_state(&saved).unwrap();
    while !a.finished() {
        a.step().unwrap();
        b.step().unwrap();
        assert_eq!(a.tick(), b.tick());
    }
    assert!(b.restore_state(&saved[..3]).is_err());
}

/// A move of a random program: a line by (dx, dy, dz) mm, or an arc of `sweep` rad about a centre
/// at `radius` mm in direction `heading`, G2 or G3, with a helix rise dz.
#[derive(Clone, Debug)]
enum Move {
    Line([f64; 3]),
    Arc {
        radius: f64,
        heading: f64,
        sweep: f64,
        clockwise: bool,
        dz: f64,
    },
}

fn a_move() -> impl Strategy<Value = Move> {
    prop_oneof![
        [-30.0..30.0f64, -30.0..30.0f64, -5.0..5.0f64].prop_map(Move::Line),
        (
            2.0..30.0f64,
            0.0..std::f64::consts::TAU,
            0.2..4.0f64,
            any::<bool>(),
            -3.0..3.0f64
        )
            .prop_map(|(radius, heading, sweep, clockwise, dz)| Move::Arc {
                radius,
                heading,
                sweep,
                clockwise,
                dz
            }),
    ]
}

/// The program text (coordinates rounded to 0.1 µm as a post-processor writes them), its
/// programmed length (mm) and end point (m).
fn arc_program(moves: &[Move], exact_stop: bool) -> (String, f64, [f64; 3]) {
    let mut text = String::from("G21 G90 G17 F2400\n");
    text.push_str(if exact_stop { "G61\n" } else { "G64\n" });
    let round = |x: f64| format!("{x:.4}").parse::<f64>().unwrap();
    let mut p = [0.0f64; 3];
    let mut length = 0.0;
    for m in moves {
        match *m {
            Move::Line(d) => {
                let q = [round(p[0] + d[0]), round(p[1] + d[1]), round(p[2] + d[2])];
                writeln!(text, "G1 X{:.4} Y{:.4} Z{:.4}", q[0], q[1], q[2]).unwrap();
                length += ((q[0] - p[0]).powi(2) + (q[1] - p[1]).powi(2) + (q[2] - p[2]).powi(2)).sqrt();
                p = q;
            }
            Move::Arc {
                radius,
                heading,
                sweep,
                clockwise,
                dz,
            } => {
                let c = [p[0] + radius * heading.cos(), p[1] + radius * heading.sin()];
                let start = (p[1] - c[1]).atan2(p[0] - c[0]);
                let end = if clockwise { start - sweep } else { start + sweep };
                let q = [
                    round(c[0] + radius * end.cos()),
                    round(c[1] + radius * end.sin()),
                    round(p[2] + dz),
                ];
                let (i, j) = (round(c[0] - p[0]), round(c[1] - p[1]));
                let g = if clockwise { 2 } else { 3 };
                writeln!(
                    text,
                    "G{g} X{:.4} Y{:.4} Z{:.4} I{i:.4} J{j:.4}",
                    q[0], q[1], q[2]
                )
                .unwrap();
                // The arc as written: centre moved onto the chord's bisector, as the reader does.
                let (mx, my) = (0.5 * (p[0] + q[0]), 0.5 * (p[1] + q[1]));
                let (ux, uy) = (q[0] - p[0], q[1] - p[1]);
                let chord = ux.hypot(uy);
                let (mut cx, mut cy) = (p[0] + i, p[1] + j);
                if chord > 0.0 {
                    let along = ((cx - mx) * ux + (cy - my) * uy) / (chord * chord);
                    cx -= along * ux;
                    cy -= along * uy;
                }
                let r = (p[0] - cx).hypot(p[1] - cy);
                let a0 = (p[1] - cy).atan2(p[0] - cx);
                let a1 = (q[1] - cy).atan2(q[0] - cx);
                let two_pi = std::f64::consts::TAU;
                let mut phi = if clockwise { a0 - a1 } else { a1 - a0 };
                phi = phi.rem_euclid(two_pi);
                if phi == 0.0 {
                    phi = two_pi;
                }
                length += (r * phi).hypot(q[2] - p[2]);
                p = q;
            }
        }
    }
    text.push_str("M30\n");
    (text, length * 1e-3, p.map(|x| x * 1e-3))
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn random_line_and_arc_programs_stay_within_limits(
        moves in prop::collection::vec(a_move(), 1..7),
        exact_stop in any::<bool>(),
        kind in prop::sample::select(vec![ProfileKind::Scurve7, ProfileKind::Quintic, ProfileKind::Jerk15]),
    ) {
        let machine = Machine { profile: kind, ..Machine::default() };
        let (text, length, end) = arc_program(&moves, exact_stop);
        let r = run(&text, &machine);
        for i in 0..3 {
            prop_assert!((r.end[i] - end[i]).abs() <= 1e-12, "end {:?} vs {:?}", r.end, end);
        }
        // Corners only cut; with exact stops nothing is cut.
        prop_assert!(r.distance <= length * (1.0 + 1e-9) + 1e-12, "{} vs {}", r.distance, length);
        if exact_stop {
            prop_assert!((r.distance - length).abs() <= 1e-9 * length + 1e-12, "{} vs {}", r.distance, length);
        }
        check_limits(&r, &machine, true);
    }
}

/// A change of the feed at a tick: an override factor, or the feed hold on or off.
#[derive(Clone, Copy, Debug)]
enum FeedChange {
    Override(f64),
    Hold(bool),
}

fn a_feed_change() -> impl Strategy<Value = (usize, FeedChange)> {
    (
        0..3000usize,
        prop_oneof![
            (0.0..2.0f64).prop_map(FeedChange::Override),
            Just(FeedChange::Override(0.0)),
            any::<bool>().prop_map(FeedChange::Hold),
        ],
    )
}

/// Runs a program with feed changes at the given ticks (then override 1 and no hold, so that it
/// can finish), recording every tick.
fn run_with_changes(program: &str, machine: &Machine, changes: &[(usize, FeedChange)]) -> Run {
    let mut e = Engine::new(Arc::from(program), "override.ngc", machine).expect("valid program");
    let mut r = Run {
        p: vec![e.tick().p],
        v: vec![],
        a: vec![],
        j: vec![],
        distance: 0.0,
        end: [0.0; 3],
    };
    let last_change = changes.iter().map(|c| c.0).max().unwrap_or(0);
    let mut n = 0;
    while !e.finished() || n <= last_change {
        for &(_, change) in changes.iter().filter(|c| c.0 == n) {
            match change {
                FeedChange::Override(k) => e.set_feed_override(k),
                FeedChange::Hold(on) => e.set_feed_hold(on),
            }
        }
        if n == last_change + 1 {
            e.set_feed_hold(false);
            e.set_feed_override(1.0);
        }
        let t = *e.step().expect("no runtime error");
        r.p.push(t.p);
        r.v.push(t.v);
        r.a.push(t.a);
        r.j.push(t.j);
        n += 1;
        assert!(n < 2_000_000, "program does not finish");
    }
    r.distance = e.tick().distance;
    r.end = e.tick().p;
    r
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    /// Overrides and holds at random ticks, mid-block or not, on line programs (feeds per block)
    /// and line-and-arc programs: every axis within its limits (from the ticks by finite
    /// differences too), the end point exact, the path neither cut nor doubled at the changes,
    /// and the program finishes.
    #[test]
    fn random_feed_changes_stay_within_limits_and_finish(
        points in prop::collection::vec(point(), 1..5),
        feeds in prop::collection::vec(600.0..8000.0f64, 5),
        moves in prop::collection::vec(a_move(), 1..5),
        arcs in any::<bool>(),
        changes in prop::collection::vec(a_feed_change(), 1..6),
        exact_stop in any::<bool>(),
        kind in prop::sample::select(ProfileKind::ALL.to_vec()),
    ) {
        let machine = Machine { profile: kind, ..Machine::default() };
        let (text, length, end) = if arcs {
            arc_program(&moves, exact_stop)
        } else {
            line_program(&points, &feeds, exact_stop)
        };
        let r = run_with_changes(&text, &machine, &changes);
        for i in 0..3 {
            prop_assert!((r.end[i] - end[i]).abs() <= 1e-12, "end {:?} vs {:?}", r.end, end);
        }
        prop_assert!(r.distance <= length * (1.0 + 1e-9) + 1e-12, "{} vs {}", r.distance, length);
        if exact_stop {
            prop_assert!((r.distance - length).abs() <= 1e-9 * length + 1e-12, "{} vs {}", r.distance, length);
        }
        check_limits(&r, &machine, kind != ProfileKind::Trapezoid);
    }
}
