//! Cutter radius compensation (LinuxCNC G-code reference, "G40", "G41, G42", "G41.1, G42.1";
//! Siemens 840D G450/G451) and seed 003's own example program.
#![allow(unused_crate_dependencies)]

use cnc_motion::config::Machine;
use cnc_motion::gcode::{Block, Motion, Reader};
use std::sync::Arc;

fn run(text: &str, machine: &Machine) -> Result<Vec<Block>, String> {
    let mut r = Reader::new(Arc::from(text), "t.ngc", [0.0; 3]).with_machine(machine);
    let mut out = Vec::new();
    while let Some(b) = r.next_block().map_err(|e| e.to_string())? {
        out.push(b);
    }
    Ok(out)
}

fn machine(toml: &str) -> Machine {
    Machine::from_toml(toml, "m.toml").unwrap()
}

/// End points (mm) of the motion blocks.
fn ends(blocks: &[Block]) -> Vec<[f64; 3]> {
    blocks
        .iter()
        .filter_map(|b| match b.motion {
            Motion::Rapid { to } | Motion::Linear { to } | Motion::Arc { to, .. } => {
                Some(to.map(|v| v * 1e3))
            }
            _ => None,
        })
        .collect()
}

/// Seed 003's example (`T1 D1 M06`, `G54`, `G41`) runs as written; with tool 1 of radius 5 mm
/// and convex corners extended by straight lines (G451-like `cutter_corner = "extension"`) its
/// tool-centre path is the seed's interpreted program vertex by vertex, within 1e-3 mm.
#[test]
fn seed003_pocket_matches_the_interpreted_tool_centre_path() {
    let program = std::fs::read_to_string("corpus/seed003_pocket.txt").unwrap();
    let target = std::fs::read_to_string("corpus/seed003_pocket_interpreted.txt").unwrap();
    let m = machine("cutter_corner = \"extension\"\n[tool.1]\nradius_mm = 5\n");
    let got = ends(&run(&program, &m).unwrap());
    // Columns: N type comp plane F X Y Z I J K R; every G0/G1/G2/G3 row is a vertex.
    let want: Vec<[f64; 3]> = target
        .lines()
        .map(|l| l.split_whitespace().collect::<Vec<_>>())
        .filter(|c| c.len() == 12 && ["G0", "G1", "G2", "G3"].contains(&c[1]))
        .map(|c| [c[5], c[6], c[7]].map(|v| v.parse::<f64>().unwrap()))
        .collect();
    assert_eq!(got.len(), want.len(), "{got:?}");
    let mut worst: f64 = 0.0;
    for (g, w) in got.iter().zip(&want) {
        let e = (0..3).map(|i| (g[i] - w[i]).abs()).fold(0.0, f64::max);
        worst = worst.max(e);
        assert!(e < 1e-3, "vertex {g:?} vs {w:?}");
    }
    eprintln!("seed 003: worst vertex error {worst:e} mm");
}

/// Tool-centre vertices (mm, rounded to 1e-6) of a program.
fn vertices(text: &str, toml: &str) -> Vec<[f64; 2]> {
    ends(&run(text, &machine(toml)).unwrap_or_else(|e| panic!("{e}")))
        .iter()
        .map(|p| [(p[0] * 1e6).round() / 1e6, (p[1] * 1e6).round() / 1e6])
        .collect()
}

/// The arcs (centre, radius, clockwise) of a program, mm.
fn arcs(text: &str, toml: &str) -> Vec<([f64; 2], f64, bool)> {
    run(text, &machine(toml))
        .unwrap()
        .iter()
        .filter_map(|b| match b.motion {
            Motion::Arc {
                center, clockwise, ..
            } => {
                let c = [center[0] * 1e3, center[1] * 1e3];
                Some((
                    c,
                    (b.from[0] * 1e3 - c[0]).hypot(b.from[1] * 1e3 - c[1]),
                    clockwise,
                ))
            }
            _ => None,
        })
        .collect()
}

const SQUARE: &str = "G0 X10 Y5\nG1 F1000 X10 Y0\nX20\nY20\nX0\nY0\nX10\nG40 X10 Y5\nM2\n";

/// LinuxCNC "G41, G42" (tool left / right of the programmed path) and "G41.1, G42.1" (diameter in
/// the D word): a 20 mm square run counter-clockwise. G41 puts a 2 mm tool inside: every corner is
/// concave, reached by the intersection of the offset edges; entry ends on the offset of the next
/// edge's start, exit starts at the offset of the last edge's end.
#[test]
fn inside_corners_by_intersection() {
    let text = SQUARE.replace("G1 F1000", "G41.1 D4 G1 F1000");
    let want = [
        [10.0, 5.0],
        [10.0, 2.0],
        [18.0, 2.0],
        [18.0, 18.0],
        [2.0, 18.0],
        [2.0, 2.0],
        [10.0, 2.0],
        [10.0, 5.0],
    ];
    assert_eq!(vertices(&text, ""), want);
    // The same through the tool table (G41 D3, tool 3 of radius 2 mm).
    let text = SQUARE.replace("G1 F1000", "G41 D3 G1 F1000");
    assert_eq!(vertices(&text, "[tool.3]\nradius_mm = 2\n"), want);
}

/// Outside corners (G42 on the counter-clockwise square): 840D G450 (default) inserts an arc of
/// the tool radius about each programmed corner, turning counter-clockwise; G451 / `extension`
/// meets the extended edges at the corner of the offset square.
#[test]
fn outside_corners_by_arc_or_extension() {
    let text = SQUARE.replace("G1 F1000", "G42.1 D4 G1 F1000");
    let a = arcs(&text, "");
    assert_eq!(a.len(), 4);
    for ((c, r, cw), corner) in a.iter().zip([[20.0, 0.0], [20.0, 20.0], [0.0, 20.0], [0.0, 0.0]]) {
        assert!(
            (c[0] - corner[0]).abs() < 1e-9 && (c[1] - corner[1]).abs() < 1e-9,
            "{c:?}"
        );
        assert!((r - 2.0).abs() < 1e-9 && !cw);
    }
    let v = vertices(&text, "");
    assert_eq!(v[2], [20.0, -2.0]);
    assert_eq!(v[3], [22.0, 0.0]);
    let want = [
        [10.0, 5.0],
        [10.0, -2.0],
        [22.0, -2.0],
        [22.0, 22.0],
        [-2.0, 22.0],
        [-2.0, -2.0],
        [10.0, -2.0],
        [10.0, 5.0],
    ];
    assert_eq!(vertices(&text, "cutter_corner = \"extension\""), want);
    assert_eq!(vertices(&text.replace("G42.1", "G451 G42.1"), ""), want);
}

/// Seed 003's example with the default G450: its five outside corners become arcs of radius 5
/// about the programmed corners, beside its two programmed arcs (offset to radius 30 and 20).
#[test]
fn seed003_with_transition_arcs() {
    let program = std::fs::read_to_string("corpus/seed003_pocket.txt").unwrap();
    let a = arcs(&program, "[tool.1]\nradius_mm = 5\n");
    let radii: Vec<f64> = a.iter().map(|x| (x.1 * 1e6).round() / 1e6).collect();
    assert_eq!(radii, vec![5.0, 30.0, 20.0, 5.0, 5.0, 5.0, 5.0]);
    let centres: Vec<[f64; 2]> = a.iter().map(|x| x.0).collect();
    assert_eq!(centres[0], [40.0, 80.0]);
    assert_eq!(centres[3], [110.0, 70.0]);
    // The diameter given in the word (G41.1 D10) is the same path as D1 from the table.
    let word = program.replace("N10 G41", "N10 G41.1 D10");
    assert_eq!(
        vertices(&word, ""),
        vertices(&program, "[tool.1]\nradius_mm = 5\n")
    );
}

/// Gouge checks as located errors (LinuxCNC "G41, G42": the tool must fit the path).
#[test]
fn gouges_are_located_errors() {
    let m = machine("");
    let e = run(
        "G0 X0 Y0\nG41.1 D10 G1 X10 Y0 F100\nG3 X10 Y6 R3\nG1 X0\nG40 X0 Y0\n",
        &m,
    )
    .unwrap_err();
    assert_eq!(
        e,
        "t.ngc:3:1: arc radius 3.0000 mm is smaller than the tool radius 5.0000 mm on the tool's side: the tool cannot follow it (gouge)"
    );
    // A 4 mm slot for a 10 mm tool: the offset edges of the right end do not meet.
    let e = run(
        "G0 X0 Y-10\nG41.1 D10 G1 X0 Y0 F100\nX20\nY4\nX0\nY0\nG40 X0 Y-10\n",
        &m,
    )
    .unwrap_err();
    assert!(
        e.starts_with("t.ngc:4:1: concave corner cannot be reached by the tool (radius 5.0000 mm)"),
        "{e}"
    );
    // An entry arc runs (LinuxCNC "Programming Entry Moves"), if longer than the tool radius.
    assert!(run("G0 X0 Y0\nG41.1 D2 G2 X2 Y0 R1 F100\n", &m).is_ok());
    let e = run("G0 X0 Y0\nG41.1 D4 G2 X2 Y0 R1 F100\n", &m).unwrap_err();
    assert!(
        e.starts_with("t.ngc:2:1: the G41/G42 entry arc ends 2.0000 mm from its start, not farther than the tool radius 2.0000 mm"),
        "{e}"
    );
    let e = run("G41.1 D2\nG42.1 D2\n", &m).unwrap_err();
    assert!(
        e.starts_with("t.ngc:2:1: cutter compensation is already on"),
        "{e}"
    );
    let e = run("G41.1 D-1\n", &m).unwrap_err();
    assert_eq!(e, "t.ngc:1:7: D (tool diameter) must not be negative");
}

/// Seed 003's example through the whole engine: it runs to the end, at the programmed exit.
#[test]
fn seed003_runs_through_the_engine() {
    let program = std::fs::read_to_string("corpus/seed003_pocket.txt").unwrap();
    let m = machine("[tool.1]\nradius_mm = 5\n");
    let mut e = cnc_motion::engine::Engine::new(program.as_str(), "seed003_pocket.txt", &m).unwrap();
    let mut n = 0;
    while !e.finished() {
        e.advance(0.01).unwrap();
        n += 1;
        assert!(n < 100_000);
    }
    let p = e.tick().p;
    assert!(
        (p[0] - 0.005).abs() < 1e-12 && (p[1] - 0.060).abs() < 1e-12 && (p[2] - 0.050).abs() < 1e-12,
        "{p:?}"
    );
}

/// Distance (mm) from `p` to the segment a–b.
fn to_segment(p: [f64; 2], a: [f64; 2], b: [f64; 2]) -> f64 {
    let (dx, dy) = (b[0] - a[0], b[1] - a[1]);
    let t = (((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / (dx * dx + dy * dy)).clamp(0.0, 1.0);
    (p[0] - a[0] - t * dx).hypot(p[1] - a[1] - t * dy)
}

proptest::proptest! {
    #![proptest_config(proptest::prelude::ProptestConfig::with_cases(64))]
    /// Any convex polygon cut outside (G42 on a counter-clockwise contour, LinuxCNC "G41, G42"):
    /// the tool-centre path is continuous and never comes nearer than the tool radius to the
    /// contour; with G450 every vertex and every corner arc is exactly at the radius.
    #[test]
    fn outside_offset_keeps_the_radius(
        angles in proptest::collection::vec(0.0f64..1.0, 3..8),
        size in 20.0f64..50.0,
        r in 0.5f64..5.0,
        extension in proptest::bool::ANY,
    ) {
        let mut a: Vec<f64> = angles.iter().enumerate().map(|(i, u)| (i as f64 + 0.2 + 0.6 * u) / angles.len() as f64).collect();
        a.sort_by(f64::total_cmp);
        let pts: Vec<[f64; 2]> = a.iter().map(|t| {
            let t = t * std::f64::consts::TAU;
            [size * t.cos(), size * t.sin()]
        }).collect();
        let mut text = format!("G0 X{:.6} Y{:.6}\nG42.1 D{:.6} G1 F1000 X{:.6} Y{:.6}\n", 3.0 * pts[0][0], 3.0 * pts[0][1], 2.0 * r, pts[0][0], pts[0][1]);
        for p in pts.iter().skip(1).chain(std::iter::once(&pts[0])) {
            text += &format!("X{:.6} Y{:.6}\n", p[0], p[1]);
        }
        text += &format!("G40 X{:.6} Y{:.6}\nM2\n", 3.0 * pts[0][0], 3.0 * pts[0][1]);
        let toml = if extension { "cutter_corner = \"extension\"" } else { "" };
        let blocks = run(&text, &machine(toml)).unwrap();
        let r = (2.0 * r * 1e6).round() / 2e6;
        let edges: Vec<([f64; 2], [f64; 2])> = (0..pts.len()).map(|i| (pts[i], pts[(i + 1) % pts.len()])).collect();
        let mut last: Option<[f64; 3]> = None;
        let n = blocks.len();
        for (k, b) in blocks.iter().enumerate() {
            let to = match b.motion {
                Motion::Rapid { to } | Motion::Linear { to } | Motion::Arc { to, .. } => to,
                _ => continue,
            };
            if let Some(l) = last {
                proptest::prop_assert!((0..3).all(|i| (l[i] - b.from[i]).abs() < 1e-12));
            }
            last = Some(to);
            if k == 0 || k + 2 >= n {
                continue; // the rapid to the start and the exit move
            }
            let p = [to[0] * 1e3, to[1] * 1e3];
            let d = edges.iter().map(|(a, b)| to_segment(p, *a, *b)).fold(f64::MAX, f64::min);
            proptest::prop_assert!(d >= r - 1e-6, "vertex {p:?} at {d} < {r}");
            if !extension {
                proptest::prop_assert!((d - r).abs() < 1e-6, "G450 vertex {p:?} at {d} ≠ {r}");
            }
        }
        let end = last.unwrap();
        proptest::prop_assert!((end[0] * 1e3 - 3.0 * pts[0][0]).abs() < 1e-6, "exit at the programmed point");
    }
}

/// Blocks without motion in the plane (a repeated point, a Z move, a dwell) between compensated
/// elements run at the tool's place in order, before the G40 exit (found by the fuzz harness).
#[test]
fn blocks_without_plane_motion_keep_their_order() {
    let text = "G0 X0 Y-5\nG41.1 D2 G1 X0 Y0 F100\nX10\nX10\nZ-1\nG4 P0.5\nY10\nY10\nG40 X0 Y10\nG0 Z5\nM2\n";
    let b = run(text, &machine("")).unwrap();
    let z: Vec<f64> = ends(&b).iter().map(|p| p[2]).collect();
    assert_eq!(z.last(), Some(&5.0), "{z:?}");
    let lines: Vec<u32> = b.iter().map(|b| b.line).collect();
    assert!(lines.windows(2).all(|w| w[0] <= w[1]), "{lines:?}");
    assert!(b.iter().any(|b| matches!(b.motion, Motion::Dwell { .. })));
}

/// Compensated rapids (G0 with G41/G42) keep straight moves: outside corners are extended, not
/// arcs, since an arc needs a programmed feed (found by the fuzz harness).
#[test]
fn compensated_rapids_have_no_corner_arcs() {
    let text = SQUARE.replace("G1 F1000", "G42.1 D4 G0");
    assert!(arcs(&text, "").is_empty());
    let want = [
        [10.0, 5.0],
        [10.0, -2.0],
        [22.0, -2.0],
        [22.0, 22.0],
        [-2.0, 22.0],
        [-2.0, -2.0],
        [10.0, -2.0],
        [10.0, 5.0],
    ];
    assert_eq!(vertices(&text, ""), want);
}

/// Compensation in G18 (LinuxCNC "G41, G42": in the active plane): the square of
/// `inside_corners_by_intersection` drawn in Z–X (G18's first and second axes) gives the same
/// offset vertices in (Z, X), with Y untouched.
#[test]
fn compensation_in_the_xz_plane() {
    let text = "G18 G0 Z10 X5\nG41.1 D4 G1 F1000 Z10 X0\nZ20\nX20\nZ0\nX0\nZ10\nG40 Z10 X5\nM2\n";
    let zx: Vec<[f64; 3]> = ends(&run(text, &machine("")).unwrap())
        .iter()
        .map(|p| [(p[2] * 1e6).round() / 1e6, (p[0] * 1e6).round() / 1e6, p[1]])
        .collect();
    let want = [
        [10.0, 5.0],
        [10.0, 2.0],
        [18.0, 2.0],
        [18.0, 18.0],
        [2.0, 18.0],
        [2.0, 2.0],
        [10.0, 2.0],
        [10.0, 5.0],
    ];
    assert_eq!(zx.len(), want.len());
    for (g, w) in zx.iter().zip(want) {
        assert_eq!([g[0], g[1], g[2]], [w[0], w[1], 0.0]);
    }
}

/// A saved engine state in the middle of a compensated program restores to the same motion
/// (the look-ahead of the compensation is part of the state; FMI 2.0 fmi2GetFMUstate).
#[test]
fn engine_state_round_trip_during_compensation() {
    let program = std::fs::read_to_string("corpus/seed003_pocket.txt").unwrap();
    let m = machine("[tool.1]\nradius_mm = 5\n");
    let new = || cnc_motion::engine::Engine::new(program.as_str(), "p", &m).unwrap();
    let mut a = new();
    a.advance(1.5).unwrap();
    let state = a.save_state();
    let mut b = new();
    b.restore_state(&state).unwrap();
    for _ in 0..400 {
        a.advance(0.01).unwrap();
        b.advance(0.01).unwrap();
        assert_eq!(a.tick().p, b.tick().p);
    }
}
