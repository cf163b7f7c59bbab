//! The drive's discretisation e^{[[A, B], [0, 0]] h} (nalgebra's Padé `exp`) against the former
//! hand-written scaling-and-squaring Taylor series (kept here as the reference) on several drives
//! and steps, and against closed forms: the current-loop lag and the undamped two-mass mechanics.
#![allow(unused_crate_dependencies)]

use cnc_motion::servo::{expm, plant_matrix, ServoParams};

type Mat = [[f64; 7]; 7];

fn mat_mul(a: &Mat, b: &Mat) -> Mat {
    std::array::from_fn(|i| std::array::from_fn(|j| (0..7).map(|k| a[i][k] * b[k][j]).sum()))
}

/// The code this replaced: ‖M/2^s‖ ≤ 1/2, degree-16 Taylor polynomial, s squarings.
fn taylor_expm(m: &Mat) -> Mat {
    let norm = m
        .iter()
        .map(|r| r.iter().map(|x| x.abs()).sum::<f64>())
        .fold(0.0, f64::max);
    let s = if norm > 0.5 {
        (norm / 0.5).log2().ceil() as i32
    } else {
        0
    };
    let a: Mat = m.map(|r| r.map(|x| x * 0.5f64.powi(s)));
    let mut result: Mat = std::array::from_fn(|i| std::array::from_fn(|j| f64::from(u8::from(i == j))));
    let mut term = result;
    for k in 1..=16 {
        term = mat_mul(&term, &a).map(|r| r.map(|x| x / k as f64));
        result = std::array::from_fn(|i| std::array::from_fn(|j| result[i][j] + term[i][j]));
    }
    for _ in 0..s {
        result = mat_mul(&result, &result);
    }
    result
}

fn scaled(p: &ServoParams, h: f64) -> Mat {
    plant_matrix(p).map(|r| r.map(|x| x * h))
}

fn drives() -> Vec<(&'static str, ServoParams)> {
    let d = ServoParams::default();
    vec![
        ("default", d),
        (
            "stiff screw, light table",
            ServoParams {
                axial_stiffness: 1e11,
                table_mass: 0.5,
                ..d
            },
        ),
        (
            "heavy table, soft screw",
            ServoParams {
                axial_stiffness: 2e7,
                table_mass: 2000.0,
                ..d
            },
        ),
        (
            "damped, slow current loop",
            ServoParams {
                axial_damping: 5e4,
                viscous_friction: 800.0,
                current_time_constant: 5e-3,
                ..d
            },
        ),
        (
            "fine lead, fast current loop",
            ServoParams {
                screw_lead: 0.5e-3,
                current_time_constant: 1e-5,
                ..d
            },
        ),
    ]
}

/// Every entry within `tol` of its row's largest entry (rows mix rad, m and N·m). The former code
/// loses about 2^s·ε in its s squarings: measured 6.6e-11 on the default drive at h = 1 ms and
/// 1.3e-10 on a damped one (7
/// squarings), 8e-8 on the 1e11 N/m screw (25); the closed forms below show which one is off:
/// nalgebra's entries are within 2e-13 of them, the Taylor series' within 7e-9.
#[test]
fn nalgebra_exp_equals_the_former_taylor_series() {
    for (name, p) in drives() {
        let tol = if p.axial_stiffness > 1e10 { 1e-7 } else { 2e-10 };
        for h in [1.0 / p.servo_rate, 0.37 / p.servo_rate, 1e-3] {
            let m = scaled(&p, h);
            let (new, old) = (expm(&m), taylor_expm(&m));
            for i in 0..5 {
                let scale = old[i].iter().fold(0.0f64, |a, x| a.max(x.abs()));
                for j in 0..7 {
                    let err = (new[i][j] - old[i][j]).abs() / scale;
                    assert!(
                        err <= tol,
                        "{name}, h {h}: [{i}][{j}] {} vs {} ({err:e})",
                        new[i][j],
                        old[i][j]
                    );
                }
            }
        }
    }
}

/// τ' = (τ_ref − τ)/T_i: Φ_ττ = e^{−h/T_i}, Γ_τ = 1 − e^{−h/T_i}.
#[test]
fn current_loop_lag_closed_form() {
    for (name, p) in drives() {
        let h = 1.0 / p.servo_rate;
        let e = expm(&scaled(&p, h));
        let decay = (-h / p.current_time_constant).exp();
        assert!((e[4][4] - decay).abs() <= 1e-14, "{name}: {} vs {decay}", e[4][4]);
        assert!((e[4][5] - (1.0 - decay)).abs() <= 1e-14, "{name}: {}", e[4][5]);
        assert!(
            e[4][..4].iter().chain(&e[4][6..]).all(|&x| x == 0.0),
            "{name}: {:?}",
            e[4]
        );
    }
}

/// Undamped, frictionless two-mass mechanics: with q1 = rθ (motor side, mass J/r²) and q2 = x
/// (table, m), the centre of mass drifts uniformly and q1 − q2 oscillates at
/// ω² = k (r²/J + 1/m). Φ's mechanical 4×4 block is that free response.
#[test]
fn two_mass_free_response_closed_form() {
    for (name, p0) in drives() {
        let p = ServoParams {
            axial_damping: 0.0,
            viscous_friction: 0.0,
            ..p0
        };
        let h = 1.0 / p.servo_rate;
        let e = expm(&scaled(&p, h));
        let r = p.screw_lead / (2.0 * std::f64::consts::PI);
        let (m1, m2) = ((p.rotor_inertia + p.screw_inertia) / (r * r), p.table_mass);
        let w = (p.axial_stiffness * (1.0 / m1 + 1.0 / m2)).sqrt();
        let (c, s) = ((w * h).cos(), (w * h).sin());
        // Free response in (q1, q̇1, q2, q̇2) from each unit initial condition.
        let response = |q1: f64, v1: f64, q2: f64, v2: f64| -> [f64; 4] {
            let (cm, vcm) = ((m1 * q1 + m2 * q2) / (m1 + m2), (m1 * v1 + m2 * v2) / (m1 + m2));
            let (d, vd) = (q1 - q2, v1 - v2);
            let (d_h, vd_h) = (d * c + vd / w * s, -d * w * s + vd * c);
            let (cm_h, share1, share2) = (cm + vcm * h, m2 / (m1 + m2), m1 / (m1 + m2));
            [
                cm_h + share1 * d_h,
                vcm + share1 * vd_h,
                cm_h - share2 * d_h,
                vcm - share2 * vd_h,
            ]
        };
        // State j of the model is (θ, ω, x, v); in q coordinates θ = q1/r, ω = q̇1/r.
        let units = [
            [r, 0.0, 0.0, 0.0],
            [0.0, r, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ];
        let old = taylor_expm(&scaled(&p, h));
        let (mut worst, mut worst_old) = (0.0f64, 0.0f64);
        for (j, u) in units.iter().enumerate() {
            let q = response(u[0], u[1], u[2], u[3]);
            let want = [q[0] / r, q[1] / r, q[2], q[3]];
            let scale = want.iter().fold(0.0f64, |a, x| a.max(x.abs()));
            for i in 0..4 {
                let err = (e[i][j] - want[i]).abs() / scale;
                assert!(
                    err <= 1e-12,
                    "{name}: Φ[{i}][{j}] {} vs {} ({err:e})",
                    e[i][j],
                    want[i]
                );
                worst = worst.max(err);
                worst_old = worst_old.max((old[i][j] - want[i]).abs() / scale);
            }
        }
        assert!(
            worst <= worst_old,
            "{name}: nalgebra {worst:e}, Taylor {worst_old:e}"
        );
    }
}

/// A NaN or ∞ anywhere, or a norm beyond 2^64 (more squarings than `MAX_SQUARINGS`), gives a NaN
/// matrix (reported by the outputs' check), not a panic or a long loop.
#[test]
fn non_finite_or_huge_matrices_give_nan() {
    let p = ServoParams::default();
    for (i, j, x) in [(3, 2, f64::NAN), (1, 4, f64::INFINITY), (0, 1, 1e30)] {
        let mut m = scaled(&p, 1.0 / p.servo_rate);
        m[i][j] = x;
        let e = expm(&m);
        assert!(e.iter().flatten().all(|v| v.is_nan()), "[{i}][{j}] = {x}: {e:?}");
    }
    // Just inside the bound: finite work (≤ 64 squarings), whatever the entries become.
    let mut m = [[0.0; 7]; 7];
    m[0][1] = 2f64.powi(62);
    let e = expm(&m);
    assert_eq!(e[0][0], 1.0);
    assert_eq!(e[0][1], 2f64.powi(62));
}
