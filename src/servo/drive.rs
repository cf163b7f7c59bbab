//! One feed drive: cascaded P position loop, PI velocity loop and feed-forward, sampled at the
//! servo rate; the plant (current-loop lag, two-mass motor/screw/table mechanics) integrated
//! exactly over each sub-step with the matrix exponential (zero-order hold on the torque command
//! and the external force), so the discretisation is stable and exact for any stiffness, mass or
//! step; the nonlinear parts (torque saturation, Coulomb friction) are held per sub-step.

mod rest;

use super::{AxisState, ServoParams};
use crate::tolerance::{PERIOD_SLACK, SAME_STEP};
use nalgebra::{SMatrix, SVector, Vector2};
use serde::{Deserialize, Serialize};

/// Plant states: motor angle θ (rad), motor speed ω (rad/s), table position x (m),
/// table velocity v (m/s), motor torque τ (N·m).
const N: usize = 5;
/// With the two held inputs (torque command, external force) for the exact discretisation.
const NA: usize = N + 2;

type Mat = [[f64; NA]; NA];

/// The plant's state, by name (the order of `plant_matrix`'s rows).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct PlantState {
    /// Motor angle θ (rad).
    pub theta: f64,
    /// Motor speed ω (rad/s).
    pub omega: f64,
    /// Table position x (m).
    pub x: f64,
    /// Table velocity v (m/s).
    pub v: f64,
    /// Motor torque τ (N·m), behind the current-loop lag.
    pub tau: f64,
}

impl PlantState {
    fn vector(&self) -> SVector<f64, N> {
        SVector::from([self.theta, self.omega, self.x, self.v, self.tau])
    }

    fn from_vector(s: &SVector<f64, N>) -> PlantState {
        PlantState {
            theta: s[0],
            omega: s[1],
            x: s[2],
            v: s[3],
            tau: s[4],
        }
    }
}

/// Most squarings `expm` allows (‖M‖ up to 2^63).
pub const MAX_SQUARINGS: i32 = 64;

/// e^M (nalgebra: scaling and squaring with Padé approximants, Al-Mohy & Higham 2009).
///
/// The norm is checked first: nalgebra squares ⌈log2(‖M‖/θ13)⌉ times, so a norm beyond
/// 2^MAX_SQUARINGS (or NaN/∞, from parameters no range check let through) gives a NaN matrix,
/// which the outputs' check reports, instead of billions of squarings. Within that bound the
/// scaled Padé denominator is well conditioned (‖M/2^s‖ ≤ θ13), so nalgebra's LU solve cannot
/// meet a singular matrix; an overflow in the squarings ends as ∞/NaN entries, never a panic.
pub fn expm(m: &Mat) -> Mat {
    let m = SMatrix::<f64, NA, NA>::from_fn(|i, j| m[i][j]);
    let norm = m
        .row_iter()
        .map(|r| r.iter().map(|x| x.abs()).sum::<f64>())
        .fold(0.0, f64::max);
    if m.iter().any(|x| !x.is_finite()) || norm > 0.5 * 2f64.powi(MAX_SQUARINGS) {
        return [[f64::NAN; NA]; NA];
    }
    let e = m.exp();
    std::array::from_fn(|i| std::array::from_fn(|j| e[(i, j)]))
}

/// Continuous plant: ẋ = A x + B u, u = (τ_ref, F_ext), as the augmented matrix [[A, B], [0, 0]].
pub fn plant_matrix(p: &ServoParams) -> Mat {
    let r = p.screw_lead / (2.0 * std::f64::consts::PI);
    let j = p.rotor_inertia + p.screw_inertia;
    let (k, c, m, b, ti) = (
        p.axial_stiffness,
        p.axial_damping,
        p.table_mass,
        p.viscous_friction,
        p.current_time_constant,
    );
    let mut a = [[0.0; NA]; NA];
    // θ' = ω
    a[0][1] = 1.0;
    // J ω' = τ − r·F_s, F_s = k(rθ − x) + c(rω − v)
    a[1][0] = -r * r * k / j;
    a[1][1] = -r * r * c / j;
    a[1][2] = r * k / j;
    a[1][3] = r * c / j;
    a[1][4] = 1.0 / j;
    // x' = v
    a[2][3] = 1.0;
    // m v' = F_s − b v + F_ext
    a[3][0] = r * k / m;
    a[3][1] = r * c / m;
    a[3][2] = -k / m;
    a[3][3] = -(c + b) / m;
    a[3][6] = 1.0 / m;
    // τ' = (τ_ref − τ)/T_i
    a[4][4] = -1.0 / ti;
    a[4][5] = 1.0 / ti;
    a
}

/// Φ and Γ of one step h: the top rows of e^{[[A, B], [0, 0]] h}.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Step {
    h: f64,
    phi: SMatrix<f64, N, N>,
    gamma: SMatrix<f64, N, 2>,
}

impl Step {
    fn new(p: &ServoParams, h: f64) -> Step {
        let mut m = plant_matrix(p);
        for row in m.iter_mut() {
            for x in row.iter_mut() {
                *x *= h;
            }
        }
        let e = expm(&m);
        Step {
            h,
            phi: SMatrix::from_fn(|i, j| e[i][j]),
            gamma: SMatrix::from_fn(|i, j| e[i][N + j]),
        }
    }

    /// x(t + h) = Φ x(t) + Γ u, u = (τ_ref, F_ext) held.
    fn apply(&self, x: &PlantState, u: [f64; 2]) -> PlantState {
        PlantState::from_vector(&(self.phi * x.vector() + self.gamma * Vector2::from(u)))
    }
}

/// The constants of the control law, from the parameters (once per step, not per period).
struct Law {
    /// Lead per radian (m/rad).
    r: f64,
    /// Encoder count (rad), None for an ideal encoder.
    count: Option<f64>,
    /// Velocity-loop integral gain (N·m/rad).
    ki: f64,
    /// Inertia at the motor of motor, screw and table (kg·m²).
    inertia: f64,
}

impl Law {
    fn of(p: &ServoParams) -> Law {
        let r = p.screw_lead / (2.0 * std::f64::consts::PI);
        Law {
            r,
            count: (p.encoder_counts > 0.0).then(|| 2.0 * std::f64::consts::PI / p.encoder_counts),
            ki: p.velocity_gain / p.velocity_integral_time,
            inertia: p.rotor_inertia + p.screw_inertia + p.table_mass * r * r,
        }
    }
}

/// x rounded half away from zero, as `f64::round`, without its libm call (x86-64 has no
/// rounding instruction before SSE4.1): the encoder count, 24 times per interpolation period.
fn round(x: f64) -> f64 {
    if x.abs() >= 4_503_599_627_370_496.0 || x.is_nan() {
        return x; // 2^52 and beyond: already whole.
    }
    let t = x as i64 as f64;
    // x − t is exact here (|x| < 2^52, t = x truncated).
    let d = x - t;
    let r = if d >= 0.5 {
        t + 1.0
    } else if d <= -0.5 {
        t - 1.0
    } else {
        t
    };
    r.copysign(x)
}

/// The command the interpolator gives an axis (held between ticks).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct AxisCommand {
    pub position: f64,
    pub velocity: f64,
    pub acceleration: f64,
}

/// One servo axis.
#[derive(Clone, Debug, Serialize, Deserialize)]
pub struct ServoAxis {
    params: ServoParams,
    x: PlantState,
    /// Velocity-loop integrator (N·m).
    integral: f64,
    /// Torque command held over the current servo period (N·m).
    torque_ref: f64,
    /// Coulomb friction sampled with the control and held over the period (N).
    friction: f64,
    /// Time already spent in the current control period (s).
    phase: f64,
    /// Command position in force (m): the following error is read against it at any instant.
    command_position: f64,
    #[serde(skip)]
    steps: Steps,
}

/// Partial sub-step lengths kept (see [`Steps`]).
const PARTIAL_STEPS: usize = 4;

/// Φ and Γ of the full period and of the last few partial sub-step lengths (round robin): a
/// servo rate that does not divide the interpolation period repeats a short cycle of them.
#[derive(Clone, Debug, Default)]
struct Steps {
    full: Option<Step>,
    partial: [Option<Step>; PARTIAL_STEPS],
    next: usize,
}

impl Steps {
    /// The step of length h: the full period's (h within SAME_STEP of it), or a partial one.
    fn of(&mut self, p: &ServoParams, h: f64, period: f64) -> &Step {
        if (h - period).abs() <= SAME_STEP * period {
            return self.full.get_or_insert_with(|| Step::new(p, period));
        }
        let k = match self.partial.iter().position(|s| s.is_some_and(|s| s.h == h)) {
            Some(k) => k,
            None => {
                let k = self.next;
                self.partial[k] = Some(Step::new(p, h));
                self.next = (k + 1) % PARTIAL_STEPS;
                k
            }
        };
        self.partial[k].as_ref().expect("stored above")
    }
}

impl ServoAxis {
    /// At rest at `position` (m), screw unloaded.
    pub fn new(params: ServoParams, position: f64) -> ServoAxis {
        let r = params.screw_lead / (2.0 * std::f64::consts::PI);
        ServoAxis {
            params,
            x: PlantState {
                theta: position / r,
                x: position,
                ..PlantState::default()
            },
            integral: 0.0,
            torque_ref: 0.0,
            friction: 0.0,
            phase: 0.0,
            command_position: position,
            steps: Steps::default(),
        }
    }

    /// A restored drive: this axis' parameters, its phase inside a period, its torques within
    /// the peak and the Coulomb force, its positions and speeds in range.
    pub fn check_state(&self, params: &ServoParams) -> Result<(), String> {
        use crate::valid::{within, MAX_POSITION_M, MAX_SPEED_M_S};
        if self.params != *params {
            return Err("drive: saved with other servo parameters".into());
        }
        let p = &self.params;
        within("servo phase", self.phase, 0.0, 1.0 / p.servo_rate)?;
        within("torque command", self.torque_ref, -p.peak_torque, p.peak_torque)?;
        let peak = p.peak_torque * (1.0 + 1e-9);
        within("motor torque", self.x.tau, -peak, peak)?;
        within("friction", self.friction, -p.coulomb_friction, p.coulomb_friction)?;
        let r = self.lead_radius();
        for (name, x) in [
            ("table", self.x.x),
            ("motor", r * self.x.theta),
            ("command", self.command_position),
        ] {
            within(&format!("{name} position"), x, -MAX_POSITION_M, MAX_POSITION_M)?;
        }
        within("table speed", self.x.v, -MAX_SPEED_M_S, MAX_SPEED_M_S)?;
        within("motor speed", r * self.x.omega, -MAX_SPEED_M_S, MAX_SPEED_M_S)
    }

    fn lead_radius(&self) -> f64 {
        self.params.screw_lead / (2.0 * std::f64::consts::PI)
    }

    /// Force of the screw on the table (N).
    fn screw_force(&self) -> f64 {
        let r = self.lead_radius();
        let p = &self.params;
        let s = &self.x;
        p.axial_stiffness * (r * s.theta - s.x) + p.axial_damping * (r * s.omega - s.v)
    }

    pub fn state(&self) -> AxisState {
        AxisState {
            position: self.x.x,
            velocity: self.x.v,
            following_error: self.command_position - self.feedback(),
            motor_torque: self.x.tau,
            // The nut pushes the table; the screw bearings push the frame the other way.
            drive_force: -self.screw_force(),
        }
    }

    /// Position the control loop sees: motor encoder (quantised) × lead, or the linear scale.
    fn feedback(&self) -> f64 {
        self.feedback_with(&Law::of(&self.params))
    }

    fn feedback_with(&self, law: &Law) -> f64 {
        if self.params.linear_scale != 0.0 {
            return self.x.x;
        }
        let theta = match law.count {
            Some(q) => round(self.x.theta / q) * q,
            None => self.x.theta,
        };
        law.r * theta
    }

    /// Control law at the start of a servo period.
    fn control(&mut self, cmd: &AxisCommand, period: f64, law: &Law) {
        let p = &self.params;
        let r = law.r;
        let e = cmd.position - self.feedback_with(law);
        let omega_ref = (p.kv * e + p.velocity_feedforward * cmd.velocity) / r;
        let e_omega = omega_ref - self.x.omega;
        let ff = p.acceleration_feedforward * law.inertia * cmd.acceleration / r;
        let integral = self.integral + law.ki * e_omega * period;
        let unclamped = p.velocity_gain * e_omega + integral + ff;
        let torque = unclamped.clamp(-p.peak_torque, p.peak_torque);
        // Anti-windup: keep the integrator only while the torque is not saturated.
        if torque == unclamped {
            self.integral = integral;
        }
        self.torque_ref = torque;
        self.friction = p.coulomb_friction * (self.x.v / p.friction_velocity).tanh();
    }

    /// Advance by dt (s) with the command held and an external force on the table (N).
    pub fn step(&mut self, cmd: &AxisCommand, load_force: f64, dt: f64) {
        let period = 1.0 / self.params.servo_rate;
        self.command_position = cmd.position;
        let mut left = dt;
        // Each pass completes a period or ends the step (bounded by construction, whatever the
        // phase a restored state brings).
        let passes = (dt / period).min(1e12) as u64 + 2;
        let law = Law::of(&self.params);
        for _ in 0..passes {
            if left.is_nan() || left <= 0.0 {
                break;
            }
            if self.phase == 0.0 {
                self.control(cmd, period, &law);
            }
            let room = period - self.phase;
            // Sub-steps that end within 1e-9 of a period boundary complete it (rounding of dt).
            let (h, completes) = if left >= room - PERIOD_SLACK * period {
                (room.min(left), true)
            } else {
                (left, false)
            };
            let u = [self.torque_ref, load_force - self.friction];
            self.x = self.steps.of(&self.params, h, period).apply(&self.x, u);
            left -= h;
            self.phase = if completes { 0.0 } else { self.phase + h };
            if completes && left < PERIOD_SLACK * period {
                break;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn round_is_f64_round() {
        let mut x = 0x9e37_79b9_7f4a_7c15u64;
        let mut values = vec![
            0.5,
            -0.5,
            1.5,
            -2.5,
            0.49999999999999994,
            -0.49999999999999994,
            0.0,
            -0.0,
        ];
        values.extend([
            4503599627370495.5,
            4503599627370497.0,
            -4503599627370495.5,
            1e300,
            f64::INFINITY,
        ]);
        for _ in 0..100_000 {
            x ^= x << 13;
            x ^= x >> 7;
            x ^= x << 17;
            // Magnitudes from 1e-3 to 1e17, whole and half numbers among them.
            let m = 10f64.powi((x % 21) as i32 - 3) * ((x >> 11) as f64 / (1u64 << 53) as f64);
            values.extend([m, -m, m.trunc() + 0.5, -(m.trunc() + 0.5)]);
        }
        for v in values {
            assert_eq!(super::round(v).to_bits(), v.round().to_bits(), "{v:e}");
        }
        assert!(super::round(f64::NAN).is_nan());
    }
}
