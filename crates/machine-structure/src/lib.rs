//! MachineStructure FMU: a modal model of a machine frame, driven by the axis drive forces, giving
//! the tool-point deflection and frame acceleration, and the inertial force the moving frame puts
//! back on each axis (two-way coupling). Built on the generic FMI layer (crates/fmi2): the whole
//! model glue is the table below.

pub mod modal;
pub mod ranges;

use fmi2::{Causality, DisplayUnit, ModelInfo, Type, UnitDefinition, Value, Variability, VariableInfo};
use modal::{Mode, ModeState};
use serde::{Deserialize, Serialize};
use std::path::Path;
use std::sync::OnceLock;

const AXES: [&str; 3] = ["x", "y", "z"];
const MODES: usize = 2;

/// Parameters, inputs and state of the frame.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct MachineStructure {
    pub modes: [[Mode; MODES]; 3],
    /// Mass riding on the frame per axis (table, kg): −m·a_frame is the load on that axis.
    pub coupling_mass: [f64; 3],
    pub drive_force: [f64; 3],
    pub state: [[ModeState; MODES]; 3],
}

impl Default for MachineStructure {
    fn default() -> Self {
        MachineStructure {
            modes: modal::small_mill(),
            // Two-way coupling is opt-in (set x.couplingMass to the table mass, 50 kg for the
            // default axes). With a one-step co-simulation delay at h = 1 ms the loop through the
            // stiff servo is stable for the x/y modes of the defaults but not for the 150 Hz z
            // mode, and masters with different delay conventions no longer agree bit for bit.
            coupling_mass: [0.0; 3],
            drive_force: [0.0; 3],
            state: Default::default(),
        }
    }
}

impl MachineStructure {
    pub fn deflection(&self, i: usize) -> f64 {
        self.state[i].iter().map(|s| s.q).sum()
    }
    pub fn acceleration(&self, i: usize) -> f64 {
        self.state[i]
            .iter()
            .zip(&self.modes[i])
            .map(|(s, m)| s.acceleration(m, self.drive_force[i]))
            .sum()
    }
    /// −m·a of the frame from its modal states alone (−2ζω q̇ − ω² q per mode), without the
    /// instantaneous F/m term: no direct feed-through from driveForce, so the two-way loop through
    /// the axis (whose stiff servo answers within a step) stays stable in a co-simulation with a
    /// one-step delay.
    pub fn load_force(&self, i: usize) -> f64 {
        let a: f64 = self.state[i]
            .iter()
            .zip(&self.modes[i])
            .map(|(s, m)| s.acceleration(m, 0.0))
            .sum();
        -self.coupling_mass[i] * a
    }
    pub fn step(&mut self, h: f64) {
        for i in 0..3 {
            for k in 0..MODES {
                self.state[i][k].step(&self.modes[i][k], self.drive_force[i], h);
            }
        }
    }
}

/// What a row of the table reads or writes.
#[derive(Clone, Copy)]
enum Slot {
    Mode(usize, usize, usize),
    Coupling(usize),
    Force(usize),
    Deflection(usize),
    Acceleration(usize),
    LoadForce(usize),
}

fn table() -> &'static [(VariableInfo, Slot)] {
    static T: OnceLock<Vec<(VariableInfo, Slot)>> = OnceLock::new();
    T.get_or_init(|| {
        let mut t = Vec::new();
        let mut add = |name: String,
                       kind: Causality,
                       var: Variability,
                       unit: Option<&str>,
                       desc: String,
                       slot: Slot| {
            let vr = t.len() as u32 + 1;
            t.push((
                VariableInfo {
                    name,
                    value_reference: vr,
                    kind: Type::Real,
                    causality: kind,
                    variability: var,
                    unit: unit.map(str::to_string),
                    display_unit: (unit == Some("m")).then(|| "mm".to_string()),
                    description: desc,
                },
                slot,
            ));
        };
        for (i, a) in AXES.iter().enumerate() {
            for k in 0..MODES {
                let n = k + 1;
                add(
                    format!("{a}.mode{n}.frequency"),
                    Causality::Parameter,
                    Variability::Fixed,
                    Some("Hz"),
                    format!("{a} mode {n}: natural frequency"),
                    Slot::Mode(i, k, 0),
                );
                add(
                    format!("{a}.mode{n}.damping"),
                    Causality::Parameter,
                    Variability::Fixed,
                    Some("1"),
                    format!("{a} mode {n}: damping ratio"),
                    Slot::Mode(i, k, 1),
                );
                add(
                    format!("{a}.mode{n}.mass"),
                    Causality::Parameter,
                    Variability::Fixed,
                    Some("kg"),
                    format!("{a} mode {n}: modal mass"),
                    Slot::Mode(i, k, 2),
                );
            }
            add(
                format!("{a}.couplingMass"),
                Causality::Parameter,
                Variability::Fixed,
                Some("kg"),
                format!("mass riding on the frame along {a} (table); loadForce = −couplingMass·acceleration"),
                Slot::Coupling(i),
            );
        }
        for (i, a) in AXES.iter().enumerate() {
            add(
                format!("{a}.driveForce"),
                Causality::Input,
                Variability::Continuous,
                Some("N"),
                format!("force of the {a} drive on the frame"),
                Slot::Force(i),
            );
        }
        for (i, a) in AXES.iter().enumerate() {
            add(
                format!("{a}.deflection"),
                Causality::Output,
                Variability::Continuous,
                Some("m"),
                format!("tool-point deflection of the frame along {a}"),
                Slot::Deflection(i),
            );
            add(
                format!("{a}.acceleration"),
                Causality::Output,
                Variability::Continuous,
                Some("m/s2"),
                format!("frame acceleration along {a}"),
                Slot::Acceleration(i),
            );
            add(
                format!("{a}.loadForce"),
                Causality::Output,
                Variability::Continuous,
                Some("N"),
                format!("inertial force of the moving frame on the {a} table, −couplingMass·(modal acceleration without the direct F/m term); to CncMotion {a}.loadForce"),
                Slot::LoadForce(i),
            );
        }
        t
    })
}

#[derive(Clone, Debug)]
pub struct MachineStructureFmu(pub MachineStructure);

impl fmi2::Model for MachineStructureFmu {
    fn info() -> &'static ModelInfo {
        static INFO: OnceLock<ModelInfo> = OnceLock::new();
        INFO.get_or_init(|| {
            let variables: Vec<VariableInfo> = table().iter().map(|(v, _)| v.clone()).collect();
            let u = |name: &str, base: [i32; 8], display: Vec<DisplayUnit>| UnitDefinition {
                name: name.into(),
                base,
                display,
            };
            ModelInfo {
                model_name: "MachineStructure".into(),
                model_identifier: "MachineStructure".into(),
                guid: fmi2::guid_of(&variables),
                description: "Modal model of a machine frame driven by the axis drive forces".into(),
                version: env!("CARGO_PKG_VERSION").into(),
                variables,
                enumerations: Vec::new(),
                units: vec![
                    u(
                        "m",
                        [0, 1, 0, 0, 0, 0, 0, 0],
                        vec![DisplayUnit {
                            name: "mm".into(),
                            factor: 1e3,
                            offset: 0.0,
                        }],
                    ),
                    u("m/s2", [0, 1, -2, 0, 0, 0, 0, 0], vec![]),
                    u("N", [1, 1, -2, 0, 0, 0, 0, 0], vec![]),
                    u("kg", [1, 0, 0, 0, 0, 0, 0, 0], vec![]),
                    u("Hz", [0, 0, -1, 0, 0, 0, 0, 0], vec![]),
                    u("1", [0; 8], vec![]),
                ],
                log_categories: Vec::new(),
                default_experiment: (0.0, 1.0, 1e-6, 0.001),
            }
        })
    }

    fn new(_resources: Option<&Path>) -> Self {
        MachineStructureFmu(MachineStructure::default())
    }

    fn get(&self, index: usize) -> Value {
        let m = &self.0;
        Value::Real(match table()[index].1 {
            Slot::Mode(i, k, 0) => m.modes[i][k].frequency,
            Slot::Mode(i, k, 1) => m.modes[i][k].damping,
            Slot::Mode(i, k, _) => m.modes[i][k].mass,
            Slot::Coupling(i) => m.coupling_mass[i],
            Slot::Force(i) => m.drive_force[i],
            Slot::Deflection(i) => m.deflection(i),
            Slot::Acceleration(i) => m.acceleration(i),
            Slot::LoadForce(i) => m.load_force(i),
        })
    }

    fn set(&mut self, index: usize, value: Value) -> Result<(), String> {
        let Value::Real(x) = value else {
            return Err("not a Real".into());
        };
        if !x.is_finite() {
            return Err(format!("{x} is not finite"));
        }
        let m = &mut self.0;
        match table()[index].1 {
            Slot::Mode(i, k, f) => {
                let mut mode = m.modes[i][k];
                match f {
                    0 => mode.frequency = x,
                    1 => mode.damping = x,
                    _ => mode.mass = x,
                }
                mode.check()?;
                m.modes[i][k] = mode;
            }
            Slot::Coupling(i) => {
                ranges::within("couplingMass", x, ranges::COUPLING_MASS_KG, "kg")?;
                m.coupling_mass[i] = x;
            }
            Slot::Force(i) => {
                ranges::check_drive_force(x)?;
                m.drive_force[i] = x;
            }
            _ => return Err("outputs cannot be set".into()),
        }
        Ok(())
    }

    fn exit_initialization(&mut self) -> Result<(), String> {
        ranges::check_structure(&self.0)
    }

    fn do_step(&mut self, h: f64) -> Result<(), String> {
        self.0.step(h);
        ranges::check_outputs(&self.0)
    }

    fn serialize(&self) -> Vec<u8> {
        serde_json::to_vec(&self.0).unwrap_or_default()
    }

    fn deserialize(&mut self, bytes: &[u8]) -> Result<(), String> {
        let state: MachineStructure =
            serde_json::from_slice(bytes).map_err(|e| format!("MachineStructure state: {e}"))?;
        ranges::check_structure(&state)
            .and_then(|()| ranges::check_outputs(&state))
            .map_err(|e| format!("MachineStructure state: {e}"))?;
        self.0 = state;
        Ok(())
    }
}

/// modelDescription.xml of MachineStructure.
pub fn model_description() -> String {
    fmi2::model_description::<MachineStructureFmu>()
}

/// Write MachineStructure.fmu from the built shared library `lib`.
pub fn write_fmu(path: &Path, lib: &Path) -> Result<(), String> {
    let xml = model_description();
    let mut doc = String::from(
        "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>MachineStructure</title></head><body>\
         <h1>MachineStructure</h1><p>Modal model of a machine frame (two modes per direction, exact \
         zero-order-hold discretisation, any step size). Inputs: <code>x.driveForce</code> … from \
         CncMotion; outputs: <code>x.deflection</code>, <code>x.acceleration</code>, <code>x.loadForce</code> \
         (back to CncMotion <code>x.loadForce</code> for two-way coupling). Defaults: a small mill \
         (45/120 Hz in x). The flexible variant (first mode 12 Hz) is in examples/flexible_structure.json.</p>\
         <table border=\"1\"><tr><th>name</th><th>causality</th><th>unit</th><th>description</th></tr>",
    );
    for (v, _) in table() {
        doc.push_str(&format!(
            "<tr><td><code>{}</code></td><td>{:?}</td><td>{}</td><td>{}</td></tr>",
            v.name,
            v.causality,
            v.unit.as_deref().unwrap_or(""),
            v.description
        ));
    }
    doc.push_str("</table></body></html>\n");
    fmi2::package::write_fmu(
        path,
        &fmi2::package::FmuFiles {
            model_identifier: "MachineStructure",
            model_description: &xml,
            shared_library: lib,
            resources: Vec::new(),
            documentation_html: &doc,
        },
    )
}

fmi2::export_fmi2!(crate::MachineStructureFmu);
