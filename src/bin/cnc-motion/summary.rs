//! The human summary of `cnc-motion run`: figures rounded for reading, each maximum beside its
//! limit. `--json` prints the same figures with every digit (design.md's contract).

use cnc_motion::config::{CornerMode, Machine};

/// Relative excess over a limit that is still rounding in the feed law's own values (the emitted
/// ticks' finite differences have their own floor, `Differences::rounding`).
const ROUNDING: f64 = 1e-9;

/// Decimals that show `scale` with four significant digits (0 from 1000 up, at most 6).
pub fn decimals(scale: f64) -> usize {
    if !(scale.is_finite() && scale > 0.0) {
        return 3;
    }
    (3 - scale.log10().floor() as i64).clamp(0, 6) as usize
}

/// `X 83.2  Y 55.5  Z 76.6 mm/s` with one number of decimals for the three axes.
pub fn per_axis(values: [f64; 3], decimals: usize, unit: &str) -> String {
    let parts: Vec<String> = values
        .iter()
        .zip(["X", "Y", "Z"])
        .map(|(v, axis)| format!("{axis} {v:.decimals$}"))
        .collect();
    format!("{} {unit}", parts.join("  "))
}

/// `X 2000 / 2000  Y 1578 / 2000  Z 1950 / 2000 mm/s² (peak / limit)`, rounded to four
/// significant digits of the largest limit; a peak above its limit by more than rounding (relative,
/// plus the per-axis `floor` of the finite differences) is marked `OVER` (the corner modes that
/// step the acceleration by design show it on the jerk).
pub fn against_limits(peaks: [f64; 3], limits: [f64; 3], floor: [f64; 3], unit: &str) -> String {
    let d = decimals(limits.iter().copied().fold(0.0, f64::max));
    let parts: Vec<String> = peaks
        .iter()
        .zip(limits)
        .zip(floor)
        .zip(["X", "Y", "Z"])
        .map(|(((peak, limit), floor), axis)| {
            let over = if *peak > limit * (1.0 + ROUNDING) + floor {
                " OVER"
            } else {
                ""
            };
            format!("{axis} {peak:.d$} / {limit:.d$}{over}")
        })
        .collect();
    format!("{} {unit} (peak / limit)", parts.join("  "))
}

/// The axis limits of the machine, in mm units: velocity, acceleration, jerk.
pub fn axis_limits(machine: &Machine, mm: f64) -> [[f64; 3]; 3] {
    let a = &machine.axes;
    [
        std::array::from_fn(|i| a[i].max_velocity / mm),
        std::array::from_fn(|i| a[i].max_acceleration / mm),
        std::array::from_fn(|i| a[i].max_jerk / mm),
    ]
}

/// Why a jerk above the limit is expected in this corner mode, if it is.
pub fn corner_note(corner: CornerMode) -> Option<&'static str> {
    matches!(corner, CornerMode::AccelerationPeriod | CornerMode::Circular).then_some(
        "this corner mode steps the acceleration at corners by design: acceleration and jerk measured from the ticks exceed the limits there",
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use cnc_motion::interp::Differences;

    #[test]
    fn four_significant_digits_of_the_scale() {
        assert_eq!(decimals(50_000.0), 0);
        assert_eq!(decimals(1000.0), 0);
        assert_eq!(decimals(999.0), 1);
        assert_eq!(decimals(100.0), 1);
        assert_eq!(decimals(0.05), 5);
        assert_eq!(decimals(1e-9), 6);
        assert_eq!(decimals(0.0), 3);
    }

    #[test]
    fn rounding_noise_is_not_over_the_limit() {
        // The figure: 50000.00002919336 against a limit of 50000 mm/s³.
        let text = against_limits(
            [50_000.000_029_193_36, 50_000.0, 12_345.678],
            [50_000.0; 3],
            [0.0; 3],
            "mm/s³",
        );
        assert_eq!(
            text,
            "X 50000 / 50000  Y 50000 / 50000  Z 12346 / 50000 mm/s³ (peak / limit)"
        );
        let over = against_limits([50_100.0, 0.0, 0.0], [50_000.0; 3], [0.0; 3], "mm/s³");
        assert!(over.starts_with("X 50100 / 50000 OVER  Y 0 / 50000"), "{over}");
        // A CAM-like program 62 mm from the origin: its ticks differenced show 5.7e-5 mm/s³
        // over, within what rounding the positions allows.
        let floor = Differences::rounding(0.062, 1e-3)[2] / 1e-3;
        let cam = against_limits([50_000.000_056_948_935; 3], [50_000.0; 3], [floor; 3], "mm/s³");
        assert!(!cam.contains("OVER"), "{cam}");
    }

    #[test]
    fn axes_share_their_decimals() {
        assert_eq!(
            per_axis([1.0, -2.5, 0.125], 3, "mm"),
            "X 1.000  Y -2.500  Z 0.125 mm"
        );
        assert_eq!(
            against_limits([83.205, 55.47, 76.63], [100.0; 3], [0.0; 3], "mm/s"),
            "X 83.2 / 100.0  Y 55.5 / 100.0  Z 76.6 / 100.0 mm/s (peak / limit)"
        );
    }
}
