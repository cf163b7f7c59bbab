//! One feed drive: cascaded P position loop, PI velocity loop and feed-forward, sampled at the
//! servo rate; the plant (current-loop lag, two-mass motor/screw/table mechanics) integrated
//! exactly over each sub-step with the matrix exponential (zero-order hold on the torque command
//! and the external force), so the discretisation is stable and exact for any stiffness, mass or
//! step; the nonlinear parts (torque saturation, Coulomb friction) are held per sub-step.

use super::{AxisState, ServoParams};
use crate::tolerance::{PERIOD_SLACK, SAME_STEP};
use serde::{Deserialize, Serialize};

/// Plant states: motor angle θ (rad), motor speed ω (rad/s), table position x (m),
/// table velocity v (m/s), motor torque τ (N·m).
const N: usize = 5;
/// With the two held inputs (torque command, external force) for the exact discretisation.
const NA: usize = N + 2;

type Mat = [[f64; NA]; NA];

fn mat_mul(a: &Mat, b: &Mat) -> Mat {
    let mut c = [[0.0; NA]; NA];
    for i in 0..NA {
        for k in 0..NA {
            let aik = a[i][k];
            if aik != 0.0 {
                for j in 0..NA {
                    c[i][j] += aik * b[k][j];
                }
            }
        }
    }
    c
}

/// Most squarings `expm` does (‖M‖ up to 2^63).
pub const MAX_SQUARINGS: i32 = 64;

/// e^M by scaling and squaring with a degree-16 Taylor polynomial (‖M/2^s‖ ≤ 1/2, so the
/// truncation error is below 1e-19 relative before squaring).
pub fn expm(m: &Mat) -> Mat {
    let norm = m
        .iter()
        .map(|r| r.iter().map(|x| x.abs()).sum::<f64>())
        .fold(0.0, f64::max);
    // The squaring count is bounded: a norm beyond 2^MAX_SQUARINGS (or NaN/∞, from parameters no
    // range check let through) gives a NaN matrix, which the outputs' check reports, instead of
    // billions of squarings.
    if norm.is_nan() || norm > 0.5 * 2f64.powi(MAX_SQUARINGS) {
        return [[f64::NAN; NA]; NA];
    }
    let s = if norm > 0.5 {
        (norm / 0.5).log2().ceil() as i32
    } else {
        0
    };
    let scale = 0.5f64.powi(s);
    let mut a = *m;
    for row in a.iter_mut() {
        for x in row.iter_mut() {
            *x *= scale;
        }
    }
    let mut result = [[0.0; NA]; NA];
    let mut term = [[0.0; NA]; NA];
    for i in 0..NA {
        result[i][i] = 1.0;
        term[i][i] = 1.0;
    }
    for k in 1..=16 {
        term = mat_mul(&term, &a);
        for row in term.iter_mut() {
            for x in row.iter_mut() {
                *x /= k as f64;
            }
        }
        for i in 0..NA {
            for j in 0..NA {
                result[i][j] += term[i][j];
            }
        }
    }
    for _ in 0..s {
        result = mat_mul(&result, &result);
    }
    result
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

/// Φ and Γ of one step h, stored as the top rows of e^{[[A, B], [0, 0]] h}.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Step {
    h: f64,
    rows: [[f64; NA]; N],
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
        let mut rows = [[0.0; NA]; N];
        rows.copy_from_slice(&e[..N]);
        Step { h, rows }
    }

    fn apply(&self, x: &[f64; N], u: [f64; 2]) -> [f64; N] {
        let mut out = [0.0; N];
        for (o, row) in out.iter_mut().zip(&self.rows) {
            let mut acc = row[5] * u[0] + row[6] * u[1];
            for j in 0..N {
                acc += row[j] * x[j];
            }
            *o = acc;
        }
        out
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
    x: [f64; N],
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
    #[serde(skip)]
    partial: Option<Step>,
}

impl ServoAxis {
    /// At rest at `position` (m), screw unloaded.
    pub fn new(params: ServoParams, position: f64) -> ServoAxis {
        let r = params.screw_lead / (2.0 * std::f64::consts::PI);
        ServoAxis {
            params,
            x: [position / r, 0.0, position, 0.0, 0.0],
            integral: 0.0,
            torque_ref: 0.0,
            friction: 0.0,
            phase: 0.0,
            command_position: position,
            full: None,
            partial: None,
        }
    }

    fn lead_radius(&self) -> f64 {
        self.params.screw_lead / (2.0 * std::f64::consts::PI)
    }

    /// Force of the screw on the table (N).
    fn screw_force(&self) -> f64 {
        let r = self.lead_radius();
        let p = &self.params;
        p.axial_stiffness * (r * self.x[0] - self.x[2]) + p.axial_damping * (r * self.x[1] - self.x[3])
    }

    pub fn state(&self) -> AxisState {
        AxisState {
            position: self.x[2],
            velocity: self.x[3],
            following_error: self.command_position - self.feedback(),
            motor_torque: self.x[4],
            // The nut pushes the table; the screw bearings push the frame the other way.
            drive_force: -self.screw_force(),
        }
    }

    /// Position the control loop sees: motor encoder (quantised) × lead, or the linear scale.
    fn feedback(&self) -> f64 {
        if self.params.linear_scale != 0.0 {
            return self.x[2];
        }
        let theta = if self.params.encoder_counts > 0.0 {
            let q = 2.0 * std::f64::consts::PI / self.params.encoder_counts;
            (self.x[0] / q).round() * q
        } else {
            self.x[0]
        };
        self.lead_radius() * theta
    }

    /// Control law at the start of a servo period.
    fn control(&mut self, cmd: &AxisCommand, period: f64) {
        let p = &self.params;
        let r = self.lead_radius();
        let e = cmd.position - self.feedback();
        let omega_ref = (p.kv * e + p.velocity_feedforward * cmd.velocity) / r;
        let e_omega = omega_ref - self.x[1];
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
        self.friction = p.coulomb_friction * (self.x[3] / p.friction_velocity).tanh();
    }

    /// Advance by dt (s) with the command held and an external force on the table (N).
    pub fn step(&mut self, cmd: &AxisCommand, load_force: f64, dt: f64) {
        let period = 1.0 / self.params.servo_rate;
        self.command_position = cmd.position;
        let mut left = dt;
        while left > 0.0 {
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
            let step = if (h - period).abs() <= SAME_STEP * period {
                *self.full.get_or_insert_with(|| Step::new(&self.params, period))
            } else {
                match self.partial {
                    Some(s) if s.h == h => s,
                    _ => {
                        let s = Step::new(&self.params, h);
                        self.partial = Some(s);
                        s
                    }
                }
            };
            self.x = step.apply(&self.x, u);
            left -= h;
            self.phase = if completes { 0.0 } else { self.phase + h };
            if completes && left < PERIOD_SLACK * period {
                break;
            }
        }
    }
}
