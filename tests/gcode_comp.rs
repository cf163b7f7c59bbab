//! Cutter radius compensation (LinuxCNC G-code reference, "G40", "G41, G42", "G41.1, G42.1";
//! Siemens 840D G450/G451) and seed 003's own example program.

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
    let program = std::fs::read_to_string("../shared/corpus/seed003_pocket.txt").unwrap();
    let target = std::fs::read_to_string("../shared/corpus/seed003_pocket_interpreted.txt").unwrap();
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
