//! Block delete, optional stop, tool table, tool length, work offsets, G10, G92, G53, G28/G30:
//! all applied in the reader, blocks come out in machine coordinates.
#![allow(unused_crate_dependencies)]

use cnc_motion::config::Machine;
use cnc_motion::gcode::{Block, Motion, Reader, StopKind};
use std::sync::Arc;

fn run(text: &str, toml: &str) -> Result<Vec<Block>, String> {
    let m = Machine::from_toml(toml, "m.toml").map_err(|e| e.to_string())?;
    let mut r = Reader::new(Arc::from(text), "t.ngc", [0.0; 3]).with_machine(&m);
    let mut out = Vec::new();
    while let Some(b) = r.next_block().map_err(|e| e.to_string())? {
        out.push(b);
    }
    Ok(out)
}

/// End points of the motion blocks, mm.
fn ends(text: &str, toml: &str) -> Vec<[f64; 3]> {
    run(text, toml)
        .unwrap_or_else(|e| panic!("{e}"))
        .iter()
        .filter_map(|b| match b.motion {
            Motion::Rapid { to } | Motion::Linear { to } | Motion::Arc { to, .. } => {
                Some(to.map(|v| (v * 1e6).round() / 1e3))
            }
            _ => None,
        })
        .collect()
}

fn error(text: &str, toml: &str) -> String {
    run(text, toml).unwrap_err()
}

/// LinuxCNC G-code overview, "Block Delete": a line starting with `/` is skipped when the
/// switch is on, run when it is off. "M1": optional stop only when the switch is on.
#[test]
fn block_delete_and_optional_stop_switches() {
    let text = "G0 X1\n/G0 X5\n  / G0 Y7\nM1\nG0 X2\n";
    assert_eq!(ends(text, ""), vec![[1.0, 0.0, 0.0], [2.0, 0.0, 0.0]]);
    assert_eq!(
        ends(text, "block_delete = false"),
        vec![[1.0, 0.0, 0.0], [5.0, 0.0, 0.0], [5.0, 7.0, 0.0], [2.0, 7.0, 0.0]]
    );
    let stops = |toml| {
        run(text, toml)
            .unwrap()
            .iter()
            .filter(|b| b.motion == Motion::Stop(StopKind::OptionalPause))
            .count()
    };
    assert_eq!((stops(""), stops("optional_stop = false")), (1, 0));
}

const TOOLS: &str = "[tool.1]\nradius_mm = 5\nlength_mm = 100\n[tool.2]\nradius_mm = 3\nlength_mm = 50.5\n";

/// LinuxCNC "G43, G43.1, G49": G43 H adds the table length to Z (H omitted: the loaded tool),
/// G43.1 Z gives the offset in the word, G49 cancels; axes not programmed stay where they are.
#[test]
fn tool_length_offsets() {
    let text = "T1 M6 G43 H1\nG0 Z10\nT2 M6 G43\nG0 Z10\nG43.1 Z2.5\nG0 Z0\nG49\nG0 Z10\nG43 H0\nG0 Z1\n";
    let z: Vec<f64> = ends(text, TOOLS).iter().map(|p| p[2]).collect();
    assert_eq!(z, vec![110.0, 60.5, 2.5, 10.0, 1.0]);
    assert_eq!(
        error("G43 H7\n", TOOLS),
        "t.ngc:1:5: H7: tool 7 is not in the machine's tool table ([tool.7])"
    );
    assert_eq!(
        error("G43.1\n", TOOLS),
        "t.ngc:1:1: G43.1 needs Z (the tool length offset)"
    );
}

/// LinuxCNC "Coordinate Systems" (G54–G59.3) with the offsets from the machine file, "G10 L2",
/// "G10 L20", "G53" (machine coordinates for one block).
#[test]
fn work_offsets_g10_and_g53() {
    let toml = "[work_offset.g55]\nx_mm = 100\ny_mm = 50\n[work_offset.\"g59.3\"]\nz_mm = -20\n";
    let text = "G55 G0 X1 Y2\nG59.3 G0 Z0\nG55 G53 G0 X1\nG0 X0\nG54 G0 X0 Y0\n";
    assert_eq!(
        ends(text, toml),
        vec![
            [101.0, 52.0, 0.0],
            [101.0, 52.0, -20.0],
            [1.0, 52.0, -20.0],
            [100.0, 52.0, -20.0],
            [0.0, 0.0, -20.0]
        ]
    );
    // G10 L2 P1 sets G54's offset; G10 L20 P0 makes the current point read the given value.
    let text = "G10 L2 P1 X10 Y-5\nG0 X1 Y1\nG10 L20 P0 X0\nG0 X2\nG10 L2 P2 Z3\nG55 G0 Z0\n";
    assert_eq!(
        ends(text, ""),
        vec![[11.0, -4.0, 0.0], [13.0, -4.0, 0.0], [13.0, -4.0, 3.0]]
    );
    assert_eq!(
        error("G10 L2 X1\n", ""),
        "t.ngc:1:1: G10 needs P (tool or coordinate system number)"
    );
    assert!(error("G10 L2 P10 X1\n", "").starts_with("t.ngc:1:8: P10 out of range"));
    assert!(Machine::from_toml("[work_offset.g60]\nx_mm = 1\n", "m.toml").is_err());
}

/// LinuxCNC "G92, G92.1, G92.2, G92.3": G92 makes the current point read the given values;
/// G92.1 clears, G92.2 suspends, G92.3 restores the offset.
#[test]
fn g92_family() {
    let text = "G0 X10 Y10\nG92 X0\nG0 X1\nG92.2\nG0 X1\nG92.3\nG0 X2\nG92.1\nG0 X3\n";
    let x: Vec<f64> = ends(text, "").iter().map(|p| p[0]).collect();
    assert_eq!(x, vec![10.0, 11.0, 1.0, 12.0, 3.0]);
    assert_eq!(error("G92\n", ""), "t.ngc:1:1: G92 needs at least one axis word");
}

/// LinuxCNC "G28, G28.1" and "G30, G30.1": without axis words a rapid of every axis to the
/// stored position; with axis words first to that point, then only those axes home.
#[test]
fn g28_g30_home_positions() {
    let toml = "[home.g28]\nx_mm = 50\ny_mm = 60\nz_mm = 70\n[home.g30]\nz_mm = 5\n";
    let text = "G0 X1 Y1 Z1\nG28\nG0 X2 Y2 Z2\nG28 Z4\nG30\nG0 X9 Y8 Z7\nG28.1\nG0 X0\nG28\n";
    assert_eq!(
        ends(text, toml),
        vec![
            [1.0, 1.0, 1.0],
            [1.0, 1.0, 1.0],
            [50.0, 60.0, 70.0],
            [2.0, 2.0, 2.0],
            [2.0, 2.0, 4.0],
            [2.0, 2.0, 70.0],
            [2.0, 2.0, 70.0],
            [0.0, 0.0, 5.0],
            [9.0, 8.0, 7.0],
            [0.0, 8.0, 7.0],
            [0.0, 8.0, 7.0],
            [9.0, 8.0, 7.0],
        ]
    );
}

/// LinuxCNC "G10 L1" (tool table: R radius, Z length) and "G10 L10" (the length that makes the
/// current point read Z); the new entries serve G43 and G41.
#[test]
fn g10_tool_table() {
    let text = "G10 L1 P3 R2 Z40\nT3 M6 G43\nG0 Z0\nG0 Z30\nG10 L10 P3 Z0\nG43 H3\nG0 Z5\n";
    let z: Vec<f64> = ends(text, "").iter().map(|p| p[2]).collect();
    // G10 L10 at machine Z 70 (program 30 + 40) with Z0: length 70; Z5 → machine 75.
    assert_eq!(z, vec![40.0, 70.0, 75.0]);
    assert!(Machine::from_toml("[tool.1]\nradius_mm = -1\n", "m.toml")
        .unwrap_err()
        .to_string()
        .contains("tool.1.radius_mm = -1 out of range"));
}
