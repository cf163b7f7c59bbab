//! Path limits of straight lines (seed 004 eq. 11).

use super::tolerance::NEGLIGIBLE;
use crate::config::Machine;
use crate::feed::Limits;
use crate::Vec3;

/// Seed 004 eq. 11: on a line of unit direction u, axis i moves at u_i·v, so the path limits
/// are the smallest axis limit divided by |u_i| — the slowest axis sets the pace, all in phase.
pub fn line_limits(u: Vec3, machine: &Machine) -> Limits {
    let mut lim = Limits {
        v_max: machine.max_feed,
        a_max: f64::INFINITY,
        j_max: f64::INFINITY,
        snap_max: machine.max_snap,
    };
    for (ui, ax) in u.iter().zip(&machine.axes) {
        let k = ui.abs();
        if k > NEGLIGIBLE {
            lim.v_max = lim.v_max.min(ax.max_velocity / k);
            lim.a_max = lim.a_max.min(ax.max_acceleration / k);
            lim.j_max = lim.j_max.min(ax.max_jerk / k);
        }
    }
    if let Some(a) = machine.max_path_acceleration {
        lim.a_max = lim.a_max.min(a);
    }
    if let Some(j) = machine.max_path_jerk {
        lim.j_max = lim.j_max.min(j);
    }
    lim
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn eq11_on_a_diagonal_line() {
        // Direction (3, 4, 0)/5: X carries 0.6 of the path, Y 0.8; Y limits (eq. 11).
        let m = Machine::default();
        let u = [0.6, 0.8, 0.0];
        let lim = line_limits(u, &m);
        let ax = m.axes[1];
        assert!((lim.v_max - (ax.max_velocity / 0.8).min(m.max_feed)).abs() < 1e-15);
        assert!((lim.a_max - ax.max_acceleration / 0.8).abs() < 1e-12);
        assert!((lim.j_max - ax.max_jerk / 0.8).abs() < 1e-12);
        // Each axis at the path limits stays within its own limits: V_i = u_i·V (eq. 11).
        for (ui, a) in u.iter().zip(&m.axes) {
            assert!(ui * lim.a_max <= a.max_acceleration + 1e-12);
            assert!(ui * lim.j_max <= a.max_jerk + 1e-12);
        }
        // Space diagonal: every axis carries 1/sqrt(3).
        let k = 1.0 / 3f64.sqrt();
        let lim = line_limits([k, k, k], &m);
        assert!((lim.a_max - 2.0 * 3f64.sqrt()).abs() < 1e-12);
    }
}
