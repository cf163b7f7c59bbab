//! What the FMU's outputs read, computed once at the end of every step (not once per variable
//! read), and the check that none of them is NaN or infinite.

use super::Engine;
use crate::interp::Tick;
use crate::servo::{AxisState, ServoAxis};
use crate::Vec3;

/// The drives' states and the contour error at the engine's time (the command is the tick).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Outputs {
    /// Actual axis states after the drives (equal to the command when the servo is off).
    pub axes: [AxisState; 3],
    /// Distance of the actual tool point from the programmed path (m), measured from the
    /// tangent line at the commanded point.
    pub contour_error: f64,
}

impl Outputs {
    pub fn of(tick: &Tick, drives: Option<&[ServoAxis]>) -> Outputs {
        let axes: [AxisState; 3] = std::array::from_fn(|i| match drives {
            Some(d) => d[i].state(),
            None => AxisState {
                position: tick.p[i],
                velocity: tick.v[i],
                ..AxisState::default()
            },
        });
        let e: Vec3 = std::array::from_fn(|i| axes[i].position - tick.p[i]);
        let u = tick.tangent;
        let along = crate::geometry::dot(e, u);
        let normal = crate::geometry::sub(e, crate::geometry::scale(u, along));
        Outputs {
            axes,
            contour_error: crate::geometry::norm(normal),
        }
    }
}

/// Zero where every value is finite, NaN otherwise: x·0 is ±0 for a finite x and NaN for an
/// infinite or NaN one, and a NaN stays NaN through the sum (a multiply and an add a value).
fn zero_if_finite(values: &[f64]) -> f64 {
    // −0 + y is y for every y: the sum starts at the first product.
    values.iter().fold(-0.0, |sum, v| sum + v * 0.0)
}

impl Engine {
    /// Outputs are never NaN or infinite with status OK: the first one that is, named. Called
    /// every tick by the CLI: one test of everything first, the names only on a failure.
    pub fn check_outputs(&self) -> Result<(), String> {
        let t = self.tick();
        let command = zero_if_finite(&t.p) + zero_if_finite(&t.v) + zero_if_finite(&t.a);
        let all = if self.servo() {
            let o = &self.outputs;
            o.axes.iter().fold(command, |sum, s| {
                sum + zero_if_finite(&[s.position, s.velocity, s.motor_torque])
            }) + zero_if_finite(&[t.feed, o.contour_error])
        } else {
            // The actual axes are the command; the contour error is 0 when the tangent is
            // finite (the point is on its line), NaN otherwise.
            command + zero_if_finite(&t.tangent) + zero_if_finite(&[t.feed])
        };
        if all == 0.0 {
            return Ok(());
        }
        self.name_non_finite()
    }

    /// The first output that is NaN or infinite, named.
    #[cold]
    #[inline(never)]
    fn name_non_finite(&self) -> Result<(), String> {
        let (t, axes) = (self.tick(), self.axes());
        let named: [(&str, [f64; 3]); 6] = [
            ("command.position", t.p),
            ("command.velocity", t.v),
            ("command.acceleration", t.a),
            ("position", axes.map(|s| s.position)),
            ("velocity", axes.map(|s| s.velocity)),
            ("motorTorque", axes.map(|s| s.motor_torque)),
        ];
        for (name, values) in named {
            for (axis, v) in ["x", "y", "z"].iter().zip(values) {
                if !v.is_finite() {
                    return Err(format!(
                        "{axis}.{name} = {v} at t = {} s: the model diverged (check the servo parameters)",
                        self.time()
                    ));
                }
            }
        }
        if !(t.feed.is_finite() && self.contour_error().is_finite()) {
            return Err(format!(
                "path.feed or path.contourError not finite at t = {} s",
                self.time()
            ));
        }
        Ok(())
    }
}
