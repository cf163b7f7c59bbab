//! Inch machine files (`units = "inch"`, LinuxCNC's `LINEAR_UNITS = inch`): every length of the
//! file is converted to mm on load, so a G20 program on an inch machine moves exactly as its
//! mm equivalent on the same machine written in mm (25.4 mm per inch).
#![allow(unused_crate_dependencies)]

use cnc_motion::config::Machine;
use cnc_motion::engine::Engine;

/// The same machine: inch values × 25.4 = the mm values.
const INCH: &str = "units = \"inch\"\nmax_feed_mm_min = 250\npath_tolerance_mm = 0.0004\n\
    [axis.x]\nmax_velocity_mm_min = 250\nmax_acceleration_mm_s2 = 80\nmax_jerk_mm_s3 = 2000\n\
    [axis.y]\nmax_velocity_mm_min = 250\nmax_acceleration_mm_s2 = 80\nmax_jerk_mm_s3 = 2000\n\
    [tool.1]\nradius_mm = 0.125\nlength_mm = 2\n[work_offset.g54]\nx_mm = 1\ny_mm = -0.5\n\
    [home.g28]\nz_mm = 4\n";
const MM: &str = "max_feed_mm_min = 6350\npath_tolerance_mm = 0.01016\n\
    [axis.x]\nmax_velocity_mm_min = 6350\nmax_acceleration_mm_s2 = 2032\nmax_jerk_mm_s3 = 50800\n\
    [axis.y]\nmax_velocity_mm_min = 6350\nmax_acceleration_mm_s2 = 2032\nmax_jerk_mm_s3 = 50800\n\
    [tool.1]\nradius_mm = 3.175\nlength_mm = 50.8\n[work_offset.g54]\nx_mm = 25.4\ny_mm = -12.7\n\
    [home.g28]\nz_mm = 101.6\n";

/// Every tick's position (m) of a program through the whole engine.
fn ticks(program: &str, machine: &Machine) -> Vec<[f64; 3]> {
    let mut e = Engine::new(program, "t.ngc", machine).unwrap_or_else(|e| panic!("{e}"));
    let mut out = Vec::new();
    while !e.finished() {
        out.push(e.step().unwrap().p);
        assert!(out.len() < 1_000_000);
    }
    out
}

#[test]
fn inch_machine_file_converts_every_length() {
    let inch = Machine::from_toml(INCH, "inch.toml").unwrap();
    let mm = Machine::from_toml(MM, "mm.toml").unwrap();
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * b.abs().max(1e-3);
    assert!(close(inch.max_feed, mm.max_feed));
    assert!(close(inch.path_tolerance, mm.path_tolerance));
    for (a, b) in inch.axes.iter().zip(&mm.axes) {
        assert!(close(a.max_velocity, b.max_velocity) && close(a.max_jerk, b.max_jerk));
        assert!(close(a.max_acceleration, b.max_acceleration));
    }
    assert!(close(inch.nc.tools[&1].radius, 3.175e-3) && close(inch.nc.tools[&1].length, 50.8e-3));
    assert!(close(inch.nc.work_offsets[0][0], 25.4e-3) && close(inch.nc.work_offsets[0][1], -12.7e-3));
    assert!(close(inch.nc.home[0][2], 101.6e-3));
    assert!(inch.nc.inch && !mm.nc.inch);
}

/// A G20 program with a work offset, tool length, cutter compensation and an arc on the inch
/// machine, and the same program in G21 (every number × 25.4) on the mm machine: the same ticks.
#[test]
fn g20_program_on_an_inch_machine_moves_as_its_mm_equivalent() {
    let inch = Machine::from_toml(INCH, "inch.toml").unwrap();
    let mm = Machine::from_toml(MM, "mm.toml").unwrap();
    let g20 = "G20 G17 G90 G54 F100\nT1 M6 G43 H1\nG0 X-0.5 Y0 Z0.1\nG1 Z-0.1\nG41 D1 G1 X0 Y0\nX2\n\
               G3 X3 Y1 R1\nG1 Y2\nX0\nY0\nG40 G1 X-0.5 Y-0.5\nG0 Z1\nG28\nM2\n";
    let g21 = "G21 G17 G90 G54 F2540\nT1 M6 G43 H1\nG0 X-12.7 Y0 Z2.54\nG1 Z-2.54\nG41 D1 G1 X0 Y0\nX50.8\n\
               G3 X76.2 Y25.4 R25.4\nG1 Y50.8\nX0\nY0\nG40 G1 X-12.7 Y-12.7\nG0 Z25.4\nG28\nM2\n";
    let a = ticks(g20, &inch);
    let b = ticks(g21, &mm);
    assert_eq!(a.len(), b.len());
    let worst = a
        .iter()
        .zip(&b)
        .flat_map(|(p, q)| (0..3).map(move |i| (p[i] - q[i]).abs()))
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "largest difference {worst} m");
    // G28 ends at the inch home position (4 in on Z).
    let end = a.last().unwrap();
    assert!((end[2] - 101.6e-3).abs() < 1e-12, "{end:?}");
    // An inch machine starts in G20: the program without G20 is the same.
    let c = ticks(&g20.replacen("G20 ", "", 1), &inch);
    assert_eq!(a, c);
}

#[test]
fn units_key_errors_are_located() {
    let e = Machine::from_toml("units = \"cm\"\n", "m.toml")
        .unwrap_err()
        .to_string();
    assert!(e.starts_with("m.toml:1:9: unknown variant `cm`"), "{e}");
}
