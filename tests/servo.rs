//! The servo-axis model against closed forms and an independent integration.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]

use cnc_motion::servo::{expm, plant_matrix, AxisCommand, ServoAxis, ServoParams};

const T: f64 = 1e-3;

fn ideal(p: ServoParams) -> ServoParams {
    // Ideal encoder so that closed forms hold exactly (quantisation is tested elsewhere).
    ServoParams {
        encoder_counts: 0.0,
        ..p
    }
}

/// Ramp command x = v·t (after a jerk-free start) held per 1 ms tick, as the interpolator gives it.
fn ramp(axis: &mut ServoAxis, v: f64, seconds: f64) {
    let n = (seconds / T) as usize;
    for k in 0..n {
        let t = k as f64 * T;
        let cmd = AxisCommand {
            position: v * t,
            velocity: v,
            acceleration: 0.0,
        };
        axis.step(&cmd, 0.0, T);
    }
}

#[test]
fn steady_following_error_is_v_over_kv_without_feedforward() {
    let p = ideal(ServoParams {
        velocity_feedforward: 0.0,
        ..ServoParams::default()
    });
    let mut axis = ServoAxis::new(p, 0.0);
    let v = 0.05;
    ramp(&mut axis, v, 1.5);
    // The error is read at the end of a tick against the command held since its start (v·T older
    // than the ramp there), and the axis follows the held staircase, whose mean lags the ramp by
    // v·T/2: e = v/k_v − v·T/2.
    let e = axis.state().following_error;
    let want = v / p.kv - 0.5 * v * T;
    assert!((e - want).abs() < 0.005 * want, "e = {e}, v/kv − vT/2 = {want}");
}

#[test]
fn full_velocity_feedforward_removes_the_steady_error() {
    let p = ideal(ServoParams::default());
    assert_eq!(p.velocity_feedforward, 1.0);
    let mut axis = ServoAxis::new(p, 0.0);
    let v = 0.05;
    ramp(&mut axis, v, 1.5);
    let e = axis.state().following_error;
    // Only the zero-order hold of the command is left: |e| ≤ v·T.
    assert!(e.abs() <= v * T, "e = {e}");
    assert!(e.abs() < 0.05 * v / p.kv, "much smaller than v/kv: {e}");
}

/// Φ and Γ of one servo period (matrix exponential) against a fine RK4 integration of ẋ = Ax + Bu.
#[test]
fn discretisation_equals_the_exact_solution_of_the_linear_part() {
    // Scaling and squaring loses about 2^s·ε: s = 5 squarings for the default drive, 25 for a
    // 1e11 N/m screw on a 0.5 kg table.
    for (p, tol) in [
        (ServoParams::default(), 1e-10),
        (
            ServoParams {
                axial_stiffness: 1e11,
                table_mass: 0.5,
                ..ServoParams::default()
            },
            1e-7,
        ),
    ] {
        let a = plant_matrix(&p);
        let h = 1.0 / p.servo_rate;
        let mut m = a;
        for row in m.iter_mut() {
            for x in row.iter_mut() {
                *x *= h;
            }
        }
        let e = expm(&m);
        // Initial state with all states and both inputs non-zero (inputs as constant states).
        let x0 = [1.0, 20.0, 1.9e-4, 3e-3, 0.5, 1.2, -30.0];
        let exact: Vec<f64> = (0..7).map(|i| (0..7).map(|j| e[i][j] * x0[j]).sum()).collect();
        let f = |x: &[f64; 7]| -> [f64; 7] { std::array::from_fn(|i| (0..7).map(|j| a[i][j] * x[j]).sum()) };
        let n = 200_000;
        let dt = h / n as f64;
        let mut x = x0;
        for _ in 0..n {
            let k1 = f(&x);
            let k2 = f(&std::array::from_fn(|i| x[i] + 0.5 * dt * k1[i]));
            let k3 = f(&std::array::from_fn(|i| x[i] + 0.5 * dt * k2[i]));
            let k4 = f(&std::array::from_fn(|i| x[i] + dt * k3[i]));
            x = std::array::from_fn(|i| x[i] + dt / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
        }
        for i in 0..5 {
            let scale = x[i].abs().max(1e-6);
            assert!(
                (exact[i] - x[i]).abs() <= tol * scale,
                "state {i}: {} vs {}",
                exact[i],
                x[i]
            );
        }
    }
}

#[test]
fn harmonic_oscillator_closed_form() {
    // e^{A h} of x'' = −ω² x embedded in the 7×7 form: [[cos, sin/ω], [−ω sin, cos]].
    let w = 1500.0;
    let h = 1e-3;
    let mut m = [[0.0; 7]; 7];
    m[0][1] = h;
    m[1][0] = -w * w * h;
    let e = expm(&m);
    let (c, s) = ((w * h).cos(), (w * h).sin());
    assert!((e[0][0] - c).abs() < 1e-12 && (e[1][1] - c).abs() < 1e-12);
    assert!((e[0][1] - s / w).abs() < 1e-15 && (e[1][0] + w * s).abs() < 1e-9);
}

/// Peak table acceleration and the final state after a 5 mm step command.
fn step_response(p: ServoParams) -> (f64, bool, cnc_motion::servo::AxisState) {
    let mut axis = ServoAxis::new(p, 0.0);
    let cmd = AxisCommand {
        position: 5e-3,
        velocity: 0.0,
        acceleration: 0.0,
    };
    let (mut peak_a, mut v_last, mut saturated) = (0.0f64, 0.0, false);
    for _ in 0..1500 {
        axis.step(&cmd, 0.0, T);
        let s = axis.state();
        // The current loop lags the saturated command: |τ| ≤ τ_peak always.
        assert!(
            s.motor_torque.abs() <= p.peak_torque * (1.0 + 1e-9),
            "torque {}",
            s.motor_torque
        );
        saturated |= s.motor_torque.abs() > 0.99 * p.peak_torque;
        peak_a = peak_a.max(((s.velocity - v_last) / T).abs());
        v_last = s.velocity;
    }
    (peak_a, saturated, axis.state())
}

#[test]
fn torque_saturates_and_the_axis_recovers() {
    let p = ideal(ServoParams::default());
    let (peak_a, saturated, s) = step_response(p);
    assert!(saturated, "a 5 mm step must saturate the torque");
    // Rigid-body bound τ_peak·r/J_total; a torque step on the two-mass axis rings the screw mode,
    // which can at most double the table's acceleration (step response of an undamped spring).
    let r = p.screw_lead / (2.0 * std::f64::consts::PI);
    let j_total = p.rotor_inertia + p.screw_inertia + p.table_mass * r * r;
    let a_rigid = p.peak_torque * r / j_total;
    assert!(
        peak_a <= 2.0 * a_rigid + (p.coulomb_friction + 0.1 * p.viscous_friction) / p.table_mass,
        "{peak_a} vs {a_rigid}"
    );
    // The same drive with 100× the torque accelerates far harder: the saturation is what limits.
    let (peak_free, _, _) = step_response(ServoParams {
        peak_torque: 190.0,
        rated_torque: 64.0,
        ..p
    });
    assert!(peak_free > 3.0 * peak_a, "{peak_free} vs {peak_a}");
    assert!(
        (s.position - 5e-3).abs() < 1e-6,
        "recovered to the target: {}",
        s.position
    );
    assert!(s.velocity.abs() < 1e-5);
}

#[test]
fn stiff_two_mass_converges_to_the_rigid_axis() {
    let run = |k: f64| {
        let p = ideal(ServoParams {
            axial_stiffness: k,
            axial_damping: 2.0 * (k * 50.0).sqrt() * 0.05,
            ..ServoParams::default()
        });
        let mut axis = ServoAxis::new(p, 0.0);
        let mut out = Vec::new();
        for i in 0..300 {
            let t = i as f64 * T;
            // Smooth S-shaped move of 2 mm.
            let u = (t / 0.2).min(1.0);
            let pos = 2e-3 * (10.0 * u.powi(3) - 15.0 * u.powi(4) + 6.0 * u.powi(5));
            axis.step(
                &AxisCommand {
                    position: pos,
                    velocity: 0.0,
                    acceleration: 0.0,
                },
                0.0,
                T,
            );
            out.push(axis.state().position);
        }
        out
    };
    let (a, b, c) = (run(1e10), run(1e11), run(1e12));
    let d1 = a.iter().zip(&b).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    let d2 = b.iter().zip(&c).map(|(x, y)| (x - y).abs()).fold(0.0, f64::max);
    assert!(d2 < d1, "differences shrink as stiffness grows: {d1} then {d2}");
    assert!(d2 < 1e-8, "{d2}");
}

#[test]
fn stable_for_extreme_parameters() {
    for p in [
        ServoParams {
            axial_stiffness: 1e13,
            table_mass: 0.01,
            ..ServoParams::default()
        },
        ServoParams {
            axial_stiffness: 1e5,
            axial_damping: 0.0,
            table_mass: 5000.0,
            ..ServoParams::default()
        },
        ServoParams {
            current_time_constant: 1e-7,
            servo_rate: 1000.0,
            ..ServoParams::default()
        },
    ] {
        let mut axis = ServoAxis::new(p, 0.1);
        for i in 0..2000 {
            let pos = 0.1 + 1e-3 * (i as f64 * T * 3.0).sin();
            axis.step(
                &AxisCommand {
                    position: pos,
                    velocity: 0.0,
                    acceleration: 0.0,
                },
                0.0,
                T,
            );
            let s = axis.state();
            assert!(
                s.position.is_finite() && (s.position - 0.1).abs() < 0.05,
                "{p:?}: {}",
                s.position
            );
        }
    }
}

#[test]
fn any_step_size_gives_the_same_motion() {
    // 1 ms in one call or in uneven pieces: the same control samples, the same exact plant.
    let p = ServoParams::default();
    let mut a = ServoAxis::new(p, 0.0);
    let mut b = ServoAxis::new(p, 0.0);
    let cmd = AxisCommand {
        position: 1e-4,
        velocity: 0.0,
        acceleration: 0.0,
    };
    for _ in 0..20 {
        a.step(&cmd, 0.0, T);
        for piece in [0.3e-3, 0.25e-3, 0.45e-3] {
            b.step(&cmd, 0.0, piece);
        }
    }
    let (sa, sb) = (a.state(), b.state());
    assert!(
        (sa.position - sb.position).abs() < 1e-12,
        "{} vs {}",
        sa.position,
        sb.position
    );
}

#[test]
fn machine_file_servo_keys() {
    let t: toml::Table = toml::from_str("kv_1_s = 30\nscrew_lead_mm = 10\ntable_mass_kg = 120.5").unwrap();
    let p = ServoParams::from_table(&t).unwrap();
    assert_eq!((p.kv, p.screw_lead, p.table_mass), (30.0, 0.01, 120.5));
    let bad: toml::Table = toml::from_str("kv = 30").unwrap();
    let (key, message) = ServoParams::from_table(&bad).unwrap_err();
    assert!(key == "kv" && message.starts_with("unknown servo key `kv`"));
    // Ranges are checked with the whole machine (config::ranges), located at the value.
    let neg: toml::Table = toml::from_str("table_mass_kg = -1").unwrap();
    let s = ServoParams::from_table(&neg).unwrap();
    assert!(cnc_motion::config::ranges::check_servo("", "", &s).is_err());
    let e = cnc_motion::config::Machine::from_toml(
        "[servo.x]
table_mass_kg = -1
",
        "m.toml",
    )
    .unwrap_err();
    assert!(
        e.to_string()
            .starts_with("m.toml:2:17: servo.x.table_mass_kg = -1 out of range"),
        "{e}"
    );
}
