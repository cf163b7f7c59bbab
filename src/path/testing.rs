//! Random curves and machines for the path stage's unit tests (deterministic: a failure replays).

use crate::config::Machine;
use crate::test_rng::unit;
use crate::Vec3;

/// A default machine with random acceleration (0.5 … 10.5) and jerk (5 … 205) limits per axis.
pub fn machine(state: &mut u64) -> Machine {
    let mut m = Machine::default();
    for ax in m.axes.iter_mut() {
        ax.max_acceleration = 0.5 + 10.0 * unit(state);
        ax.max_jerk = 5.0 + 200.0 * unit(state);
    }
    m
}

/// 1 … `most` cells of derivative bounds [p′, p″, p‴]: each component 0 with probability
/// 0.15, else 10^(`decades`·x + `lowest` + k) for the k-th derivative.
pub fn cells(state: &mut u64, most: usize, decades: f64, lowest: f64) -> Vec<[Vec3; 3]> {
    let n = 1 + (unit(state) * most as f64) as usize;
    (0..n)
        .map(|_| {
            std::array::from_fn(|k| {
                std::array::from_fn(|_| {
                    let x = unit(state);
                    if x < 0.15 {
                        0.0
                    } else {
                        (10f64).powf(decades * x + lowest + k as f64)
                    }
                })
            })
        })
        .collect()
}
