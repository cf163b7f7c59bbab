//! Modal model of a machine frame: per direction a few modes m q̈ + c q̇ + k q = F, each integrated
//! exactly over a step with the force held (zero-order hold), for any step size.

use serde::{Deserialize, Serialize};

/// One mode: natural frequency (Hz), damping ratio, modal mass (kg).
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
pub struct Mode {
    pub frequency: f64,
    pub damping: f64,
    pub mass: f64,
}

impl Mode {
    pub fn omega(&self) -> f64 {
        2.0 * std::f64::consts::PI * self.frequency
    }
    pub fn stiffness(&self) -> f64 {
        self.mass * self.omega() * self.omega()
    }
    pub fn check(&self) -> Result<(), String> {
        crate::ranges::check_mode(self).map_err(|e| format!("mode {self:?}: {e}"))
    }
}

/// e^{At} of ẍ + 2ζω ẋ + ω² x = 0 as [[a, b], [c, d]] (under-, critically and over-damped).
pub fn free_response(zeta: f64, omega: f64, t: f64) -> [[f64; 2]; 2] {
    let decay = (-zeta * omega * t).exp();
    let z2 = zeta * zeta - 1.0;
    // s(t) = sin(ω_d t)/ω_d (or sinh, or t), c(t) = cos(ω_d t) (or cosh, or 1)
    let (c, s) = if z2.abs() < 1e-10 {
        (1.0, t)
    } else if z2 < 0.0 {
        let wd = omega * (-z2).sqrt();
        ((wd * t).cos(), (wd * t).sin() / wd)
    } else {
        let wd = omega * z2.sqrt();
        ((wd * t).cosh(), (wd * t).sinh() / wd)
    };
    let zw = zeta * omega;
    [
        [decay * (c + zw * s), decay * s],
        [-decay * omega * omega * s, decay * (c - zw * s)],
    ]
}

/// State of one mode: displacement (m) and velocity (m/s).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct ModeState {
    pub q: f64,
    pub v: f64,
}

impl ModeState {
    /// Exact step of length h with the force held: the deviation from the static deflection F/k
    /// evolves freely.
    pub fn step(&mut self, mode: &Mode, force: f64, h: f64) {
        let w = mode.omega();
        let q_static = force / mode.stiffness();
        let e = free_response(mode.damping, w, h);
        let dq = self.q - q_static;
        self.q = q_static + e[0][0] * dq + e[0][1] * self.v;
        self.v = e[1][0] * dq + e[1][1] * self.v;
    }

    /// Exact step of length h under the force F(τ) = force + rate·τ (first-order hold): the
    /// deviation from the ramp's particular solution q_p = F(τ)/k − 2ζ·rate/(kω), q̇_p = rate/k
    /// evolves freely. With rate 0 it is [`ModeState::step`], bit for bit.
    pub fn step_ramp(&mut self, mode: &Mode, force: f64, rate: f64, h: f64) {
        if rate == 0.0 {
            return self.step(mode, force, h);
        }
        let (w, k) = (mode.omega(), mode.stiffness());
        let lag = 2.0 * mode.damping * rate / (k * w);
        let e = free_response(mode.damping, w, h);
        let dq = self.q - (force / k - lag);
        let dv = self.v - rate / k;
        self.q = (force + rate * h) / k - lag + e[0][0] * dq + e[0][1] * dv;
        self.v = rate / k + e[1][0] * dq + e[1][1] * dv;
    }

    /// q̈ under the force (m/s²).
    pub fn acceleration(&self, mode: &Mode, force: f64) -> f64 {
        let w = mode.omega();
        force / mode.mass - 2.0 * mode.damping * w * self.v - w * w * self.q
    }
}

/// Default modes per direction of a small vertical mill's frame (column and bed): a first bending
/// mode near 45 Hz and a second near 120 Hz, a few per cent damping, modal masses of the moving
/// column/bed share.
pub fn small_mill() -> [[Mode; 2]; 3] {
    let m = |frequency: f64, damping: f64, mass: f64| Mode {
        frequency,
        damping,
        mass,
    };
    [
        [m(45.0, 0.03, 400.0), m(120.0, 0.02, 250.0)],
        [m(40.0, 0.03, 450.0), m(110.0, 0.02, 250.0)],
        [m(60.0, 0.03, 350.0), m(150.0, 0.02, 200.0)],
    ]
}

/// The flexible variant: a slender gantry or a light machine on soft mounts, with a first mode
/// at 12 Hz — inside the band a jerk-limited S-curve with ramps of some 40 ms excites.
pub fn flexible() -> [[Mode; 2]; 3] {
    let m = |frequency: f64, damping: f64, mass: f64| Mode {
        frequency,
        damping,
        mass,
    };
    [
        [m(12.0, 0.02, 150.0), m(55.0, 0.02, 120.0)],
        [m(12.0, 0.02, 150.0), m(50.0, 0.02, 120.0)],
        [m(20.0, 0.02, 120.0), m(70.0, 0.02, 100.0)],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn free_vibration_frequency_and_decay() {
        let mode = Mode {
            frequency: 45.0,
            damping: 0.03,
            mass: 400.0,
        };
        let w = mode.omega();
        let wd = w * (1.0f64 - 0.03 * 0.03).sqrt();
        let mut s = ModeState { q: 1e-6, v: 0.0 };
        // After one damped period the displacement is q0·e^{−ζω T_d}, with v back to its start
        // value times the same decay (q0 ≠ 0, v0 = 0 gives v = 0).
        let period = 2.0 * std::f64::consts::PI / wd;
        s.step(&mode, 0.0, period);
        assert!((s.q - 1e-6 * (-0.03 * w * period).exp()).abs() < 1e-18);
        assert!(s.v.abs() < 1e-15);
    }

    #[test]
    fn static_deflection_and_step_independence() {
        let mode = Mode {
            frequency: 12.0,
            damping: 0.5,
            mass: 150.0,
        };
        // One long step and 1000 short ones give the same state (exact discretisation).
        let (mut a, mut b) = (ModeState::default(), ModeState::default());
        a.step(&mode, 100.0, 0.25);
        for _ in 0..1000 {
            b.step(&mode, 100.0, 0.25e-3);
        }
        assert!((a.q - b.q).abs() < 1e-15 && (a.v - b.v).abs() < 1e-13);
        let mut c = ModeState::default();
        c.step(&mode, 100.0, 50.0);
        assert!((c.q - 100.0 / mode.stiffness()).abs() < 1e-15);
    }

    /// The ramp F = r·t on a mode at rest, against the textbook response
    /// q = (r/k)·[t − 2ζ/ω + e^{−ζωt}(2ζ/ω·cos ω_d t + (2ζ² − 1)/ω_d·sin ω_d t)] (under-damped),
    /// (r/k)·(t − sin ωt/ω) undamped; one long step and many short ones alike.
    #[test]
    fn ramp_force_against_the_closed_form() {
        for zeta in [0.0, 0.03, 0.5] {
            let mode = Mode {
                frequency: 45.0,
                damping: zeta,
                mass: 400.0,
            };
            let (w, k, r) = (mode.omega(), mode.stiffness(), 2.0e5);
            let wd = w * (1.0 - zeta * zeta).sqrt();
            let exact = |t: f64| {
                let decay = (-zeta * w * t).exp();
                let free = 2.0 * zeta / w * (wd * t).cos() + (2.0 * zeta * zeta - 1.0) / wd * (wd * t).sin();
                r / k * (t - 2.0 * zeta / w + decay * free)
            };
            for (n, h) in [(1, 0.0137), (10, 0.01), (1000, 1e-4)] {
                let mut s = ModeState::default();
                for j in 0..n {
                    s.step_ramp(&mode, r * j as f64 * h, r, h);
                }
                let t = n as f64 * h;
                let scale = r / k * t;
                assert!(
                    (s.q - exact(t)).abs() < 1e-12 * scale,
                    "ζ {zeta}, {n} × {h}: {} vs {}",
                    s.q,
                    exact(t)
                );
            }
        }
        // Rate 0 is the held force, bit for bit.
        let mode = small_mill()[2][1];
        let (mut a, mut b) = (ModeState { q: 1e-6, v: -2e-4 }, ModeState { q: 1e-6, v: -2e-4 });
        a.step(&mode, 300.0, 1e-3);
        b.step_ramp(&mode, 300.0, 0.0, 1e-3);
        assert_eq!((a.q.to_bits(), a.v.to_bits()), (b.q.to_bits(), b.v.to_bits()));
    }

    #[test]
    fn damping_regimes_agree_at_the_boundary() {
        let w = 10.0;
        for t in [0.01, 0.1, 1.0] {
            let crit = free_response(1.0, w, t);
            let under = free_response(1.0 - 1e-9, w, t);
            let over = free_response(1.0 + 1e-9, w, t);
            for i in 0..2 {
                for j in 0..2 {
                    let scale = crit[i][j].abs().max(1e-3);
                    // A change δ of ζ near 1 moves the response by about ω²·2δ·t² (relative).
                    assert!((crit[i][j] - under[i][j]).abs() < 1e-6 * scale);
                    assert!((crit[i][j] - over[i][j]).abs() < 1e-6 * scale);
                }
            }
        }
    }
}
