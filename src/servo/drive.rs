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
    full: Option<Step>,
    /// The last few partial sub-step lengths (round robin): a servo rate that does not divide
    /// the interpolation period repeats a short cycle of them.
    #[serde(skip)]
    partial: [Option<Step>; PARTIAL_STEPS],
    #[serde(skip)]
    next_partial: usize,
}

/// Partial sub-step lengths kept (see `ServoAxis::partial`).
const PARTIAL_STEPS: usize = 4;

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
            full: None,
            partial: [None; PARTIAL_STEPS],
            next_partial: 0,
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
        if self.params.linear_scale != 0.0 {
            return self.x.x;
        }
        let theta = if self.params.encoder_counts > 0.0 {
            let q = 2.0 * std::f64::consts::PI / self.params.encoder_counts;
            (self.x.theta / q).round() * q
        } else {
            self.x.theta
        };
        self.lead_radius() * theta
    }

    /// Control law at the start of a servo period.
    fn control(&mut self, cmd: &AxisCommand, period: f64) {
        let p = &self.params;
        let r = self.lead_radius();
        let e = cmd.position - self.feedback();
        let omega_ref = (p.kv * e + p.velocity_feedforward * cmd.velocity) / r;
        let e_omega = omega_ref - self.x.omega;
        let j_total = p.rotor_inertia + p.screw_inertia + p.table_mass * r * r;
        let ff = p.acceleration_feedforward * j_total * cmd.acceleration / r;
        let ki = p.velocity_gain / p.velocity_integral_time;
        let integral = self.integral + ki * e_omega * period;
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
        for _ in 0..passes {
            if left.is_nan() || left <= 0.0 {
                break;
            }
            if self.phase == 0.0 {
                self.control(cmd, period);
            }
            let room = period - self.phase;
            // Sub-steps that end within 1e-9 of a period boundary complete it (rounding of dt).
            let (h, completes) = if left >= room - PERIOD_SLACK * period {
                (room.min(left), true)
            } else {
                (left, false)
            };
            let u = [self.torque_ref, load_force - self.friction];
            let step = self.step_of(h, period);
            self.x = step.apply(&self.x, u);
            left -= h;
            self.phase = if completes { 0.0 } else { self.phase + h };
            if completes && left < PERIOD_SLACK * period {
                break;
            }
        }
    }

    /// Φ and Γ of a sub-step of length h: the full period's, or a cached partial one.
    fn step_of(&mut self, h: f64, period: f64) -> Step {
        if (h - period).abs() <= SAME_STEP * period {
            return *self.full.get_or_insert_with(|| Step::new(&self.params, period));
        }
        if let Some(s) = self.partial.iter().flatten().find(|s| s.h == h) {
            return *s;
        }
        let s = Step::new(&self.params, h);
        self.partial[self.next_partial] = Some(s);
        self.next_partial = (self.next_partial + 1) % PARTIAL_STEPS;
        s
    }
}
