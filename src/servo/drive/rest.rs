//! A drive at rest over a long interval, in closed form. With the command still (v = a = 0), the
//! load force constant, the torque command unsaturated and the table inside the linear part of
//! its Coulomb band (F·tanh(v/v_b) ≈ (F/v_b)·v), one servo period — the control law at its start,
//! then the plant's exact step Φ, Γ — is an affine map of z = (θ, ω, x, v, τ, integrator, 1).
//! N periods are its N-th power, by repeated squaring: the exact discretisation of the interval
//! in O(log N) instead of N sub-steps.
//!
//! The encoder count is held when the loop holds it over the interval (the map is then exactly
//! the sub-stepped one, to rounding). A loop hunting between two counts (an integrator and a
//! quantised position never agree) has no count to hold: there the encoder is taken as ideal,
//! and the drive ends at the linear loop's rest, within a count of where the hunting would be.

use super::{AxisCommand, ServoAxis, Step, N};
use nalgebra::{SMatrix, SVector};

/// The augmented state's size.
const Z: usize = N + 2;
type Map = SMatrix<f64, Z, Z>;

/// Table and motor count as still when both move slower than this fraction of the friction
/// band: tanh(v/v_b) is then linear to 3e-5 relative.
const STILL: f64 = 1e-2;
/// The torque command stays this far inside the peak torque (no saturation on the way).
const TORQUE_MARGIN: f64 = 0.5;

impl ServoAxis {
    /// Still: table and motor far inside the friction band, torque far from saturation.
    pub fn still(&self) -> bool {
        let p = &self.params;
        let v_still = STILL * p.friction_velocity;
        self.x.v.abs() <= v_still
            && (self.lead_radius() * self.x.omega).abs() <= v_still
            && self.torque_ref.abs() <= TORQUE_MARGIN * p.peak_torque
    }

    /// Advance `ticks` interpolation periods of `tick` seconds under a command at rest, in closed
    /// form, if the drive is still and stays so (count held, or the encoder taken as ideal);
    /// else nothing changes and the answer is false (the caller steps it).
    pub fn rest(&mut self, cmd: &AxisCommand, load_force: f64, ticks: u64, tick: f64) -> bool {
        if cmd.velocity != 0.0 || cmd.acceleration != 0.0 || !self.still() {
            return false;
        }
        let period = 1.0 / self.params.servo_rate;
        let mut next = self.clone();
        // To the next period boundary, then whole periods, then what is left.
        let first = if self.phase > 0.0 {
            period - self.phase
        } else {
            0.0
        };
        let per_tick = tick * self.params.servo_rate;
        let (periods, tail) = if first == 0.0 && (per_tick - per_tick.round()).abs() <= 1e-9 {
            // The servo rate divides the interpolation period: whole periods, exactly.
            (ticks.saturating_mul(per_tick.round() as u64), 0.0)
        } else {
            let left = ticks as f64 * tick - first;
            let n = (left / period).floor().max(0.0);
            (n as u64, (left - n * period).max(0.0))
        };
        if first > 0.0 {
            next.step(cmd, load_force, first);
        }
        let start = next.clone();
        let count = next.count();
        for ideal in [false, true] {
            if ideal && count.is_none() {
                break;
            }
            next = start.clone();
            if periods > 1 {
                next.periods_at_rest(cmd.position, load_force, periods - 1, ideal);
            }
            if periods > 0 {
                // The last whole period as usual: the held torque and friction are its own.
                next.step(cmd, load_force, period);
            }
            if tail > 0.0 {
                next.step(cmd, load_force, tail);
            }
            let finite = next.x.vector().iter().all(|x| x.is_finite());
            if finite && next.still() && (ideal || next.count() == count) {
                *self = next;
                return true;
            }
        }
        false
    }

    /// The encoder count the control reads (None without an encoder in the loop).
    fn count(&self) -> Option<f64> {
        let p = &self.params;
        (p.linear_scale == 0.0 && p.encoder_counts > 0.0)
            .then(|| super::round(self.x.theta / (2.0 * std::f64::consts::PI / p.encoder_counts)))
    }

    /// `n` whole periods from a period boundary: z ← M^n z (`ideal`: the encoder unquantised).
    fn periods_at_rest(&mut self, position: f64, load_force: f64, n: u64, ideal: bool) {
        let m = self.period_map(position, load_force, ideal);
        let s = &self.x;
        let z = SVector::<f64, Z>::from([s.theta, s.omega, s.x, s.v, s.tau, self.integral, 1.0]);
        let z = power(&m, n) * z;
        self.x = super::PlantState::from_vector(&z.fixed_rows::<N>(0).into_owned());
        self.integral = z[N];
        self.phase = 0.0;
    }

    /// One servo period at rest as an affine map of z (the control law of `control` with
    /// v = a = 0 and the count held or, `ideal`, the encoder unquantised; then the plant's
    /// exact step).
    fn period_map(&mut self, position: f64, load_force: f64, ideal: bool) -> Map {
        let p = self.params;
        let period = 1.0 / p.servo_rate;
        let r = self.lead_radius();
        let Step { phi, gamma, .. } = *self.steps.of(&p, period, period);
        let unit = |i: usize| SVector::<f64, Z>::from_fn(|k, _| f64::from(u8::from(k == i)));
        let one = unit(Z - 1);
        // Position error e = command − feedback, as a row acting on z.
        let e = if p.linear_scale != 0.0 {
            one * position - unit(2)
        } else if p.encoder_counts > 0.0 && !ideal {
            one * (position - self.feedback())
        } else {
            one * position - unit(0) * r
        };
        let ki = p.velocity_gain / p.velocity_integral_time;
        let e_omega = e * (p.kv / r) - unit(1);
        let integral = unit(N) + e_omega * (ki * period);
        let torque = e_omega * p.velocity_gain + integral;
        let force = one * load_force - unit(3) * (p.coulomb_friction / p.friction_velocity);
        let mut m = Map::zeros();
        for i in 0..N {
            let mut row = torque * gamma[(i, 0)] + force * gamma[(i, 1)];
            for j in 0..N {
                row[j] += phi[(i, j)];
            }
            m.set_row(i, &row.transpose());
        }
        m.set_row(N, &integral.transpose());
        m.set_row(Z - 1, &one.transpose());
        m
    }
}

/// m^n by repeated squaring (n ≥ 1).
fn power(m: &Map, mut n: u64) -> Map {
    let mut base = *m;
    let mut out = Map::identity();
    while n > 0 {
        if n & 1 == 1 {
            out = base * out;
        }
        n >>= 1;
        if n > 0 {
            base = base * base;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::servo::ServoParams;

    /// A drive `ms` after a step of its command from 0 to `at` (a load on the table).
    fn settling(p: ServoParams, at: f64, load: f64, ms: usize) -> (ServoAxis, AxisCommand) {
        let mut d = ServoAxis::new(p, 0.0);
        let cmd = AxisCommand {
            position: at,
            ..AxisCommand::default()
        };
        for _ in 0..ms {
            d.step(&cmd, load, 1e-3);
        }
        (d, cmd)
    }

    #[test]
    fn a_rest_in_closed_form_is_the_stepped_rest() {
        let default = ServoParams::default();
        let scale = ServoParams {
            linear_scale: 1.0,
            ..default
        };
        let ideal = ServoParams {
            encoder_counts: 0.0,
            ..default
        };
        // 0.0012 m is a whole number of counts (the count is held); every drive under a load,
        // still but not settled (its decay is the closed form's to follow) and settled.
        let cases = [(default, 1.2e-3), (scale, 1.234_567e-3), (ideal, 1.234_567e-3)];
        for ((p, at), ms) in cases.into_iter().flat_map(|c| [(c, 400), (c, 3000)]) {
            let (mut closed, cmd) = settling(p, at, 150.0, ms);
            let v0 = closed.state().velocity;
            let mut stepped = closed.clone();
            assert!(closed.rest(&cmd, 150.0, 2000, 1e-3), "{p:?}");
            for _ in 0..2000 {
                stepped.step(&cmd, 150.0, 1e-3);
            }
            let (a, b) = (closed.state(), stepped.state());
            assert!((a.position - b.position).abs() < 1e-15, "{a:?} {b:?}");
            assert!((a.velocity - b.velocity).abs() < 1e-12, "{a:?} {b:?}");
            assert!((a.motor_torque - b.motor_torque).abs() < 1e-12, "{a:?} {b:?}");
            assert!(
                (a.drive_force.abs() - 150.0).abs() < 1e-6,
                "the screw holds the load: {a:?}"
            );
            if ms == 400 {
                assert!(
                    v0.abs() > 1e-3 * a.velocity.abs().max(1e-15),
                    "still moving at {v0:e} m/s"
                );
            }
        }
    }

    #[test]
    fn a_moving_or_saturated_drive_is_not_at_rest() {
        let p = ServoParams::default();
        let (mut d, cmd) = settling(p, 1.2e-3, 0.0, 3000);
        let moving = AxisCommand {
            velocity: 0.01,
            ..cmd
        };
        assert!(!d.clone().rest(&moving, 0.0, 2000, 1e-3));
        // A load beyond the peak torque pushes the table away: not still.
        let mut pushed = d.clone();
        pushed.step(&cmd, 1e5, 1e-2);
        assert!(!pushed.rest(&cmd, 1e5, 2000, 1e-3));
        assert!(d.rest(&cmd, 0.0, 2000, 1e-3));
    }
}
