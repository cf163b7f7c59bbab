//! The NC part of the machine file: switches (block delete, optional stop), the tool table, the
//! work offsets G54…G59.3, the G28/G30 home positions and the cutter-compensation corner
//! strategy. Lengths are read in mm and kept in metres.

use super::ranges::{number, significant, RangeError, INCH_MM};
use crate::Vec3;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::{Path, PathBuf};

/// How cutter radius compensation passes an outside (convex) corner.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum CutterCorner {
    /// A transition arc of the tool radius about the programmed corner (840D G450).
    #[default]
    Arc,
    /// The offset elements extended along their tangents to their intersection; beyond a 90°
    /// turn each is extended by the tool radius and the two ends joined by a line (G451; seed
    /// 003's interpreted program).
    Extension,
}

/// One tool of the table (m).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Tool {
    pub radius: f64,
    pub length: f64,
}

pub use super::ranges::{MAX_OFFSET_M, MAX_TOOL, MAX_TOOL_RADIUS_M};

/// Names of the nine work coordinate systems, in order (G54 … G59.3).
pub const WORK_SYSTEMS: [&str; 9] = [
    "g54", "g55", "g56", "g57", "g58", "g59", "g59.1", "g59.2", "g59.3",
];

/// The machine's NC setup (SI).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct NcSetup {
    /// `/` at the start of a line skips the line (true) or is ignored (false).
    pub block_delete: bool,
    /// M1 stops (true) or is ignored (false).
    pub optional_stop: bool,
    pub cutter_corner: CutterCorner,
    pub tools: BTreeMap<u32, Tool>,
    /// G54 … G59.3 offsets (m), machine = R·program + offset.
    pub work_offsets: [Vec3; 9],
    /// G54 … G59.3 rotations R of the XY axes about Z (degrees, G10 L2 R; 0 from the file).
    pub work_rotation: [f64; 9],
    /// G28 and G30 home positions (m, machine coordinates).
    pub home: [Vec3; 2],
    /// O-word loops: most jumps back (loop passes) in one run of a program.
    pub max_loop_iterations: u64,
    /// An inch machine (`units = "inch"`): programs start in G20.
    pub inch: bool,
    /// Directories searched for subroutine files (`subroutine_path`, LinuxCNC's
    /// `[RS274NGC]SUBROUTINE_PATH`), resolved against the machine file's directory.
    pub subroutine_path: Vec<PathBuf>,
}

/// Most `subroutine_path` directories (LinuxCNC's MAX_SUB_DIRS).
pub const MAX_SUBROUTINE_DIRS: usize = 10;
/// Longest `subroutine_path` entry (bytes).
pub const MAX_SUBROUTINE_DIR_BYTES: usize = 4096;

/// Default and largest `max_loop_iterations`.
pub const DEFAULT_MAX_LOOP_ITERATIONS: u64 = 1_000_000;
pub const MAX_LOOP_ITERATIONS: u64 = 1_000_000_000;

impl NcSetup {
    /// A restored setup (FMU state; G10 changes the reader's copy): the machine-file ranges.
    pub fn check_state(&self) -> Result<(), String> {
        use crate::valid::{at_most, point, within};
        for (&n, t) in &self.tools {
            within("tool number", f64::from(n), 1.0, f64::from(MAX_TOOL))?;
            within("tool radius", t.radius, 0.0, MAX_TOOL_RADIUS_M)?;
            within("tool length", t.length, -MAX_OFFSET_M, MAX_OFFSET_M)?;
        }
        for p in self.work_offsets.iter().chain(&self.home) {
            point("work offset or home", *p, MAX_OFFSET_M)?;
        }
        at_most(
            "max_loop_iterations",
            self.max_loop_iterations,
            MAX_LOOP_ITERATIONS,
        )
    }

    /// `subroutine_path`: at most MAX_SUBROUTINE_DIRS directories, each non-empty and at most
    /// MAX_SUBROUTINE_DIR_BYTES long, relative ones taken from `base` (the machine file's
    /// directory). Whether they exist is seen when a call looks there.
    pub fn set_subroutine_path(&mut self, dirs: &[String], base: &Path) -> Result<(), RangeError> {
        let key = "subroutine_path".to_string();
        if dirs.len() > MAX_SUBROUTINE_DIRS {
            let m = format!(
                "subroutine_path: {} directories, at most {MAX_SUBROUTINE_DIRS} (LinuxCNC's SUBROUTINE_PATH)",
                dirs.len()
            );
            return Err(range_error(key, m));
        }
        for d in dirs {
            if d.trim().is_empty() || d.len() > MAX_SUBROUTINE_DIR_BYTES || d.contains('\0') {
                let m =
                    format!("subroutine_path: each entry a directory, 1 … {MAX_SUBROUTINE_DIR_BYTES} bytes");
                return Err(range_error(key, m));
            }
            self.subroutine_path.push(base.join(d));
        }
        Ok(())
    }

    /// `max_loop_iterations`, 1 … MAX_LOOP_ITERATIONS.
    pub fn set_max_loop_iterations(&mut self, n: i64) -> Result<(), RangeError> {
        if n < 1 || n as u64 > MAX_LOOP_ITERATIONS {
            let key = "max_loop_iterations".to_string();
            let m = format!("max_loop_iterations = {n} out of range (1 … {MAX_LOOP_ITERATIONS})");
            return Err(range_error(key, m));
        }
        self.max_loop_iterations = n as u64;
        Ok(())
    }
}

impl Default for NcSetup {
    fn default() -> Self {
        NcSetup {
            block_delete: true,
            optional_stop: true,
            cutter_corner: CutterCorner::Arc,
            tools: BTreeMap::new(),
            work_offsets: [[0.0; 3]; 9],
            work_rotation: [0.0; 9],
            home: [[0.0; 3]; 2],
            max_loop_iterations: DEFAULT_MAX_LOOP_ITERATIONS,
            inch: false,
            subroutine_path: Vec::new(),
        }
    }
}

/// `[tool.N]` as written.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ToolFile {
    pub radius_mm: Option<f64>,
    pub length_mm: Option<f64>,
}

/// `[work_offset.g54]`, `[home.g28]`: a position in mm.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct PointFile {
    pub x_mm: Option<f64>,
    pub y_mm: Option<f64>,
    pub z_mm: Option<f64>,
}

fn range_error(key: String, message: String) -> RangeError {
    RangeError { key, message }
}

/// A length `v` (mm, converted from inches for an `inch` file) within min … max (m); the
/// message quotes the value and range in the file's unit.
fn length(key: String, v: f64, max: f64, min: f64, inch: bool) -> Result<f64, RangeError> {
    let m = v * 1e-3;
    if m.is_finite() && m >= min && m <= max {
        Ok(m)
    } else {
        let (f, unit) = if inch { (INCH_MM, "in") } else { (1.0, "mm") };
        let shown = |x: f64| number(if inch { significant(x / f) } else { x / f });
        let message = format!(
            "{key} = {} out of range ({} … {} {unit})",
            shown(v),
            shown(min * 1e3),
            shown(max * 1e3)
        );
        Err(range_error(key, message))
    }
}

fn point(prefix: &str, p: &PointFile, inch: bool) -> Result<Vec3, RangeError> {
    let mut out = [0.0; 3];
    for (i, (v, name)) in [p.x_mm, p.y_mm, p.z_mm]
        .iter()
        .zip(["x_mm", "y_mm", "z_mm"])
        .enumerate()
    {
        if let Some(v) = v {
            out[i] = length(format!("{prefix}.{name}"), *v, MAX_OFFSET_M, -MAX_OFFSET_M, inch)?;
        }
    }
    Ok(out)
}

impl NcSetup {
    /// The tool table from `[tool.N]`: N a whole number 1 … MAX_TOOL, radius 0 … 1000 mm,
    /// |length| ≤ 100 000 mm.
    pub fn set_tools(&mut self, tools: &BTreeMap<String, ToolFile>) -> Result<(), RangeError> {
        for (name, t) in tools {
            let key = format!("tool.{name}");
            let n: u32 = match name.parse() {
                Ok(n) if (1..=MAX_TOOL).contains(&n) => n,
                _ => {
                    let m = format!("{key}: the tool number must be a whole number 1 … {MAX_TOOL}");
                    return Err(range_error(key, m));
                }
            };
            let inch = self.inch;
            let radius = t.radius_mm.map_or(Ok(0.0), |v| {
                length(format!("{key}.radius_mm"), v, MAX_TOOL_RADIUS_M, 0.0, inch)
            })?;
            let length = t.length_mm.map_or(Ok(0.0), |v| {
                length(format!("{key}.length_mm"), v, MAX_OFFSET_M, -MAX_OFFSET_M, inch)
            })?;
            self.tools.insert(n, Tool { radius, length });
        }
        Ok(())
    }

    /// Work offsets `[work_offset.g54]` … `[work_offset."g59.3"]`, each axis within ±100 000 mm.
    pub fn set_work_offsets(&mut self, offsets: &BTreeMap<String, PointFile>) -> Result<(), RangeError> {
        for (name, p) in offsets {
            let key = format!("work_offset.{name}");
            let Some(i) = WORK_SYSTEMS.iter().position(|s| s.eq_ignore_ascii_case(name)) else {
                let m = format!("{key}: not a work coordinate system (g54 … g59, g59.1 … g59.3)");
                return Err(range_error(key, m));
            };
            self.work_offsets[i] = point(&key, p, self.inch)?;
        }
        Ok(())
    }

    /// Home positions `[home.g28]`, `[home.g30]` (machine coordinates, ±100 000 mm).
    pub fn set_home(&mut self, home: &BTreeMap<String, PointFile>) -> Result<(), RangeError> {
        for (name, p) in home {
            let key = format!("home.{name}");
            let i = match name.to_ascii_lowercase().as_str() {
                "g28" => 0,
                "g30" => 1,
                _ => return Err(range_error(key.clone(), format!("{key}: not g28 or g30"))),
            };
            self.home[i] = point(&key, p, self.inch)?;
        }
        Ok(())
    }
}
