//! The machine file (TOML, in mm, mm/min, mm/s², mm/s³ as the keys name) and the machine it
//! describes (SI). Every key is optional; the defaults are a small 3-axis mill after seed 000,
//! Table 1 (1.2 mm screw lead, 5000 rpm → 6000 mm/min).

pub mod nc;
pub mod ranges;
pub mod units;

pub use nc::{CutterCorner, NcSetup, Tool};

use crate::feed::ProfileKind;
use crate::servo::ServoParams;
use serde::{Deserialize, Serialize};

/// How the planner passes the corner between two blocks whose tangents differ. Names as
/// `ProfileKind`'s: strum's from the variant names, serde's attribute the same rule.
#[derive(
    Clone,
    Copy,
    Debug,
    Default,
    PartialEq,
    Eq,
    Serialize,
    Deserialize,
    strum::IntoStaticStr,
    strum::EnumString,
    strum::VariantArray,
)]
#[serde(rename_all = "snake_case")]
#[strum(serialize_all = "snake_case")]
pub enum CornerMode {
    /// Stop at every corner.
    ExactStop,
    /// Seed 003: corner feed F_c = A·T/(1 − cos θ), per axis.
    AccelerationPeriod,
    /// Seed 004 eq. 8–10: a circular arc inserted inside the tolerance.
    Circular,
    /// Seed 004 §3 eq. 25–57: a quintic transition inside the axis tolerances, at one speed.
    Polynomial,
    /// Every junction blended by a C2 quintic transition planned with the path, micro-segment
    /// runs smoothed as one curve (path/smooth.rs).
    #[default]
    Smooth,
}

impl CornerMode {
    /// Every mode, in the FMU Enumeration's order.
    pub const ALL: [CornerMode; 5] = crate::feed::variants(<CornerMode as strum::VariantArray>::VARIANTS);

    pub fn name(self) -> &'static str {
        self.into()
    }

    /// What the mode does (the FMU's Enumeration item description).
    pub fn description(self) -> &'static str {
        match self {
            CornerMode::ExactStop => "stop at every corner",
            CornerMode::AccelerationPeriod => "corner feed A·T/(1−cos θ) per axis (seed 003)",
            CornerMode::Circular => "circular blend within the path tolerance",
            CornerMode::Polynomial => "quintic transition at one speed within the path tolerance (seed 004)",
            CornerMode::Smooth => {
                "C2 quintic transitions planned with the path, micro-segment runs as one curve"
            }
        }
    }
}

/// Limits of one axis (SI).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct AxisLimits {
    /// m/s
    pub max_velocity: f64,
    /// m/s²
    pub max_acceleration: f64,
    /// m/s³
    pub max_jerk: f64,
}

impl Default for AxisLimits {
    fn default() -> Self {
        AxisLimits {
            max_velocity: 6000.0 / 60.0 * 1e-3,
            max_acceleration: 2.0,
            max_jerk: 50.0,
        }
    }
}

/// The machine, in SI.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Machine {
    /// s
    pub interpolation_period: f64,
    pub lookahead_blocks: usize,
    pub profile: ProfileKind,
    pub corner: CornerMode,
    /// Default G64 tolerance (m).
    pub path_tolerance: f64,
    /// Chord error allowed on arcs (m).
    pub chord_tolerance: f64,
    /// Arc end points may miss the circle by this much (m, G21; × 2.54 in G20 programs) or by
    /// 0.1 % of the radius.
    pub arc_radius_tolerance: f64,
    /// Largest feed, also the rapid (G0) feed (m/s).
    pub max_feed: f64,
    /// Optional path-level acceleration and jerk limits, on top of the axes' (m/s², m/s³).
    pub max_path_acceleration: Option<f64>,
    pub max_path_jerk: Option<f64>,
    /// Snap limit of the jerk15 law (m/s⁴).
    pub max_snap: f64,
    /// Axis jerk on passage of a discontinuity in curvature (seed 004 Table 1: 60 m/s³ on the
    /// 840D): eq. 10's acceleration step where a line and an arc or two arcs meet tangentially,
    /// and the `circular` mode's corner arcs; m/s³, the axes' own when None. The `polynomial`
    /// mode's quintic corners are curvature-continuous and keep the axis jerk (eq. 54).
    pub max_transition_jerk: Option<f64>,
    pub axes: [AxisLimits; 3],
    pub servo: [ServoParams; 3],
    /// Block delete, optional stop, tool table, work offsets, home positions.
    pub nc: NcSetup,
}

impl Default for Machine {
    fn default() -> Self {
        Machine {
            interpolation_period: 0.001,
            lookahead_blocks: 256,
            profile: ProfileKind::Scurve7,
            corner: CornerMode::Smooth,
            path_tolerance: 0.01e-3,
            chord_tolerance: 0.001e-3,
            arc_radius_tolerance: DEFAULT_ARC_TOLERANCE_M,
            max_feed: 6000.0 / 60.0 * 1e-3,
            max_path_acceleration: None,
            max_path_jerk: None,
            max_snap: 6.0e6 * 1e-3,
            max_transition_jerk: None,
            axes: [AxisLimits::default(); 3],
            servo: [
                ServoParams::default(),
                ServoParams::default(),
                ServoParams::default(),
            ],
            nc: NcSetup::default(),
        }
    }
}

/// `[axis.x]` in the machine file.
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct AxisFile {
    pub max_velocity_mm_min: Option<f64>,
    pub max_acceleration_mm_s2: Option<f64>,
    pub max_jerk_mm_s3: Option<f64>,
}

#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct AxesFile {
    pub x: Option<AxisFile>,
    pub y: Option<AxisFile>,
    pub z: Option<AxisFile>,
}

#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct ServoFile {
    pub x: Option<toml::Table>,
    pub y: Option<toml::Table>,
    pub z: Option<toml::Table>,
}

/// The machine file as written (mm units).
#[derive(Clone, Debug, Default, Deserialize, Serialize)]
#[serde(deny_unknown_fields)]
pub struct MachineFile {
    pub interpolation_period_s: Option<f64>,
    pub lookahead_blocks: Option<usize>,
    pub profile: Option<ProfileKind>,
    pub corner: Option<CornerMode>,
    pub path_tolerance_mm: Option<f64>,
    pub chord_tolerance_mm: Option<f64>,
    pub arc_radius_tolerance_mm: Option<f64>,
    pub max_feed_mm_min: Option<f64>,
    pub max_path_acceleration_mm_s2: Option<f64>,
    pub max_path_jerk_mm_s3: Option<f64>,
    pub max_snap_mm_s4: Option<f64>,
    pub max_transition_jerk_mm_s3: Option<f64>,
    pub axis: Option<AxesFile>,
    pub servo: Option<ServoFile>,
    pub block_delete: Option<bool>,
    pub optional_stop: Option<bool>,
    pub cutter_corner: Option<CutterCorner>,
    pub tool: Option<std::collections::BTreeMap<String, nc::ToolFile>>,
    pub work_offset: Option<std::collections::BTreeMap<String, nc::PointFile>>,
    pub home: Option<std::collections::BTreeMap<String, nc::PointFile>>,
    pub max_loop_iterations: Option<i64>,
    /// Directories of subroutine files, relative to the machine file's directory.
    pub subroutine_path: Option<Vec<String>>,
    /// Length unit of the file's numbers: mm (default) or inch (`units.rs`).
    pub units: Option<units::Units>,
}

/// One millimetre (m) and one mm/min (m/s): machine files and tests write their numbers in these.
pub use crate::si::{MM, MM_MIN};

/// Arc end points may disagree with the centre by the machine's `arc_radius_tolerance_mm`
/// (default 0.028 mm, LinuxCNC's CENTER_ARC_RADIUS_TOLERANCE; in G20 programs 2.54 times that,
/// 0.0028 in, LinuxCNC's inch value) or by the reader's share of the radius; an arc is refused
/// only when it exceeds both.
pub const DEFAULT_ARC_TOLERANCE_M: f64 = 0.028e-3;

impl Machine {
    /// Parse a machine file; errors name `file:line:col`. `file` is its path too: relative
    /// `subroutine_path` entries are taken from its directory.
    pub fn from_toml(text: &str, file: &str) -> Result<Machine, crate::error::ProgramError> {
        let dir = std::path::Path::new(file)
            .parent()
            .unwrap_or(std::path::Path::new(""));
        Machine::from_toml_in(text, file, dir)
    }

    /// `from_toml` for a file named `file` in messages that lies in directory `dir` (the FMU
    /// resolves `machineFile` against its resources).
    pub fn from_toml_in(
        text: &str,
        file: &str,
        dir: &std::path::Path,
    ) -> Result<Machine, crate::error::ProgramError> {
        let parsed: MachineFile = toml::from_str(text).map_err(|e| {
            let (line, col) = e.span().map(|span| line_col(text, span.start)).unwrap_or((1, 1));
            crate::error::ProgramError::new(file, line, col, e.message().to_string())
        })?;
        let located = |e: ranges::RangeError| {
            let (line, col) = locate(text, &e.key);
            crate::error::ProgramError::new(file, line, col, e.message)
        };
        let m = Machine::apply(&parsed, dir).map_err(located)?;
        ranges::check_machine(&m).map_err(located)?;
        Ok(m)
    }

    /// Apply a parsed machine file over the defaults and check the values.
    /// Relative `subroutine_path` entries are taken from the current directory.
    pub fn from_file(f: &MachineFile) -> Result<Machine, String> {
        let m = Machine::apply(f, std::path::Path::new("")).map_err(|e| e.message)?;
        m.check()?;
        Ok(m)
    }

    /// A parsed machine file over the defaults, not yet range-checked; `dir` is its directory.
    fn apply(f: &MachineFile, dir: &std::path::Path) -> Result<Machine, ranges::RangeError> {
        let f = &units::to_mm(f);
        let mut m = Machine::default();
        m.nc.inch = f.units == Some(units::Units::Inch);
        if let Some(v) = f.interpolation_period_s {
            m.interpolation_period = v;
        }
        if let Some(v) = f.lookahead_blocks {
            m.lookahead_blocks = v;
        }
        if let Some(v) = f.profile {
            m.profile = v;
        }
        if let Some(v) = f.corner {
            m.corner = v;
        }
        if let Some(v) = f.path_tolerance_mm {
            m.path_tolerance = v * MM;
        }
        if let Some(v) = f.chord_tolerance_mm {
            m.chord_tolerance = v * MM;
        }
        if let Some(v) = f.arc_radius_tolerance_mm {
            m.arc_radius_tolerance = v * MM;
        }
        if let Some(v) = f.max_feed_mm_min {
            m.max_feed = v * MM_MIN;
        }
        m.max_path_acceleration = f.max_path_acceleration_mm_s2.map(|v| v * MM);
        m.max_path_jerk = f.max_path_jerk_mm_s3.map(|v| v * MM);
        if let Some(v) = f.max_snap_mm_s4 {
            m.max_snap = v * MM;
        }
        m.max_transition_jerk = f.max_transition_jerk_mm_s3.map(|v| v * MM);
        if let Some(axes) = &f.axis {
            for (i, a) in [&axes.x, &axes.y, &axes.z].into_iter().enumerate() {
                if let Some(a) = a {
                    if let Some(v) = a.max_velocity_mm_min {
                        m.axes[i].max_velocity = v * MM_MIN;
                    }
                    if let Some(v) = a.max_acceleration_mm_s2 {
                        m.axes[i].max_acceleration = v * MM;
                    }
                    if let Some(v) = a.max_jerk_mm_s3 {
                        m.axes[i].max_jerk = v * MM;
                    }
                }
            }
        }
        m.nc.block_delete = f.block_delete.unwrap_or(true);
        m.nc.optional_stop = f.optional_stop.unwrap_or(true);
        m.nc.cutter_corner = f.cutter_corner.unwrap_or_default();
        if let Some(t) = &f.tool {
            m.nc.set_tools(t)?;
        }
        if let Some(w) = &f.work_offset {
            m.nc.set_work_offsets(w)?;
        }
        if let Some(h) = &f.home {
            m.nc.set_home(h)?;
        }
        if let Some(n) = f.max_loop_iterations {
            m.nc.set_max_loop_iterations(n)?;
        }
        if let Some(dirs) = &f.subroutine_path {
            m.nc.set_subroutine_path(dirs, dir)?;
        }
        if let Some(servo) = &f.servo {
            for (i, s) in [&servo.x, &servo.y, &servo.z].into_iter().enumerate() {
                if let Some(table) = s {
                    m.servo[i] =
                        ServoParams::from_table(table).map_err(|(key, message)| ranges::RangeError {
                            key: format!("servo.{}.{key}", ["x", "y", "z"][i]),
                            message,
                        })?;
                }
            }
        }
        Ok(m)
    }

    /// Every value within its documented range (`ranges`); the message names the key.
    pub fn check(&self) -> Result<(), String> {
        ranges::check_machine(self).map_err(|e| e.message)
    }
}

/// Line and column of the value of a dotted key (`axis.x.max_jerk_mm_s3`) in the file; of its
/// nearest enclosing table when the key is not written there (a default in a relation); 1:1
/// when nothing is.
fn locate(text: &str, key: &str) -> (u32, u32) {
    let Ok(doc) = toml_edit::ImDocument::parse(text) else {
        return (1, 1);
    };
    let mut item = doc.as_item();
    let mut span = None;
    for part in key.split('.') {
        match item.get(part) {
            Some(next) => {
                item = next;
                span = item.span().or(span);
            }
            None => break,
        }
    }
    span.map_or((1, 1), |s| line_col(text, s.start))
}

/// 1-based line and column of a byte offset.
pub fn line_col(text: &str, offset: usize) -> (u32, u32) {
    let before = &text[..offset.min(text.len())];
    let line = before.matches('\n').count() as u32 + 1;
    let col = before.rfind('\n').map(|i| offset - i).unwrap_or(offset + 1) as u32;
    (line, col)
}
