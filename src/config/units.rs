//! `units = "inch"` machine files (LinuxCNC's `LINEAR_UNITS = inch`): every length in the file —
//! the keys ending in `_mm`, `_mm_min`, `_mm_s2`, `_mm_s3`, `_mm_s4` and the tool table, work
//! offsets and home positions — is read in inches and converted to millimetres on load, so the
//! rest of the controller works in mm as for any file. The drive parameters (`[servo.*]`) keep
//! their physical units. Programs on an inch machine start in G20.

use super::{AxisFile, MachineFile};
use serde::{Deserialize, Serialize};

/// Length unit of a machine file.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Units {
    #[default]
    Mm,
    Inch,
}

use super::ranges::INCH_MM;

fn scale(v: &mut Option<f64>) {
    if let Some(x) = v.as_mut() {
        *x *= INCH_MM;
    }
}

/// The file with its lengths in mm (unchanged for `units = "mm"`).
pub fn to_mm(f: &MachineFile) -> MachineFile {
    let mut m = f.clone();
    if f.units != Some(Units::Inch) {
        return m;
    }
    for v in [
        &mut m.path_tolerance_mm,
        &mut m.chord_tolerance_mm,
        &mut m.arc_radius_tolerance_mm,
        &mut m.max_feed_mm_min,
        &mut m.max_path_acceleration_mm_s2,
        &mut m.max_path_jerk_mm_s3,
        &mut m.max_snap_mm_s4,
        &mut m.max_transition_jerk_mm_s3,
    ] {
        scale(v);
    }
    if let Some(axes) = m.axis.as_mut() {
        for a in [&mut axes.x, &mut axes.y, &mut axes.z].into_iter().flatten() {
            let AxisFile {
                max_velocity_mm_min,
                max_acceleration_mm_s2,
                max_jerk_mm_s3,
            } = a;
            for v in [max_velocity_mm_min, max_acceleration_mm_s2, max_jerk_mm_s3] {
                scale(v);
            }
        }
    }
    for t in m.tool.iter_mut().flat_map(|t| t.values_mut()) {
        scale(&mut t.radius_mm);
        scale(&mut t.length_mm);
    }
    let points = m.work_offset.iter_mut().chain(m.home.iter_mut());
    for p in points.flat_map(|p| p.values_mut()) {
        for v in [&mut p.x_mm, &mut p.y_mm, &mut p.z_mm] {
            scale(v);
        }
    }
    m
}
