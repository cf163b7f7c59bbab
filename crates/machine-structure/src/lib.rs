//! MachineStructure FMU: a modal model of a machine frame, driven by the axis drive forces, giving
//! the tool-point deflection and frame acceleration, and the inertial force the moving frame puts
//! back on each axis (two-way coupling). Built on the generic FMI layer (crates/fmi2): the whole
//! model glue is the table below.

pub mod modal;

use fmi2::{Causality, ModelInfo, Type, Value, Variability, VariableInfo};
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

/// The table: one row per variable and what it reads or writes.
fn table() -> &'static [(VariableInfo, Slot)] {
    static T: OnceLock<Vec<(VariableInfo, Slot)>> = OnceLock::new();
    T.get_or_init(|| {
        use Causality::{Input, Output, Parameter};
        use Variability::{Continuous, Fixed};
        let row = |name: String, c, v, unit, desc: String| {
            VariableInfo::new(name, Type::Real, c, v, desc).unit(unit)
        };
        let mut t = Vec::new();
        for (i, a) in AXES.iter().enumerate() {
            for k in 0..MODES {
                let n = k + 1;
                let modes = [
                    ("frequency", "natural frequency", "Hz"),
                    ("damping", "damping ratio", "1"),
                    ("mass", "modal mass", "kg"),
                ];
                for (f, (field, what, unit)) in modes.into_iter().enumerate() {
                    let v = row(
                        format!("{a}.mode{n}.{field}"),
                        Parameter,
                        Fixed,
                        unit,
                        format!("{a} mode {n}: {what}"),
                    );
                    t.push((v.range(Some(0.0), None), Slot::Mode(i, k, f)));
                }
            }
            let desc =
                format!("mass riding on the frame along {a} (table); loadForce = −couplingMass·acceleration");
            let v = row(format!("{a}.couplingMass"), Parameter, Fixed, "kg", desc);
            t.push((v.range(Some(0.0), None), Slot::Coupling(i)));
        }
        let force0 = t.len();
        for (i, a) in AXES.iter().enumerate() {
            let desc = format!("force of the {a} drive on the frame");
            t.push((
                row(format!("{a}.driveForce"), Input, Continuous, "N", desc),
                Slot::Force(i),
            ));
        }
        for (i, a) in AXES.iter().enumerate() {
            let desc = format!("tool-point deflection of the frame along {a}");
            let v = row(format!("{a}.deflection"), Output, Continuous, "m", desc);
            t.push((v.depends_on(vec![]), Slot::Deflection(i)));
            // a = Σ (F/m − 2ζω q̇ − ω² q): the drive force of the same axis feeds through.
            let desc = format!("frame acceleration along {a} (direct feed-through of {a}.driveForce)");
            let v = row(format!("{a}.acceleration"), Output, Continuous, "m/s2", desc);
            t.push((v.depends_on(vec![force0 + i]), Slot::Acceleration(i)));
            let desc = format!(
                "inertial force of the moving frame on the {a} table, −couplingMass·(modal acceleration \
                 without the direct F/m term); to CncMotion {a}.loadForce"
            );
            let v = row(format!("{a}.loadForce"), Output, Continuous, "N", desc);
            t.push((v.depends_on(vec![]), Slot::LoadForce(i)));
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
            let variables = table().iter().map(|(v, _)| v.clone()).collect();
            let description = "Modal model of a machine frame driven by the axis drive forces";
            ModelInfo {
                version: env!("CARGO_PKG_VERSION").into(),
                author: "cnc-motion authors".into(),
                copyright: "Copyright (c) 2026 the cnc-motion authors".into(),
                license: "MIT".into(),
                ..ModelInfo::new("MachineStructure", description, variables)
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
            Slot::Coupling(i) if x >= 0.0 => m.coupling_mass[i] = x,
            Slot::Coupling(_) => return Err("couplingMass must not be negative".into()),
            Slot::Force(i) => m.drive_force[i] = x,
            _ => return Err("outputs cannot be set".into()),
        }
        Ok(())
    }

    fn exit_initialization(&mut self) -> Result<(), String> {
        self.0.modes.iter().flatten().try_for_each(Mode::check)
    }

    fn do_step(&mut self, h: f64) -> Result<(), String> {
        self.0.step(h);
        Ok(())
    }

    /// bincode of the whole model (fixed-size plain data; the layer adds magic, version, GUID
    /// and length).
    fn serialize(&self) -> Vec<u8> {
        bincode::serialize(&self.0).unwrap_or_default()
    }

    fn deserialize(&mut self, bytes: &[u8]) -> Result<(), String> {
        self.0 = bincode::deserialize(bytes).map_err(|e| format!("MachineStructure state: {e}"))?;
        Ok(())
    }
}

/// modelDescription.xml of MachineStructure.
pub fn model_description() -> String {
    fmi2::model_description::<MachineStructureFmu>()
}

/// sources/: this crate (its manifest as a workspace root, fmi2 beside src/) and the fmi2 crate.
pub fn sources() -> Result<Vec<fmi2::package::Entry>, String> {
    use fmi2::package::{manifest, sources_readme, tree};
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("Cargo.toml")).map_err(|e| format!("Cargo.toml: {e}"))?;
    let cargo = manifest(&text, &[], &[("../fmi2", "fmi2")]) + "\n[workspace]\n";
    let fmi2_toml = std::fs::read(root.join("../fmi2/Cargo.toml")).map_err(|e| format!("fmi2: {e}"))?;
    let mut files = vec![
        ("Cargo.toml".to_string(), cargo.into_bytes()),
        ("fmi2/Cargo.toml".to_string(), fmi2_toml),
        sources_readme("MachineStructure", "machine_structure"),
    ];
    files.extend(tree(&root.join("src"), "src")?);
    files.extend(tree(&root.join("../fmi2/src"), "fmi2/src")?);
    Ok(files)
}

/// Write MachineStructure.fmu from the built shared library `lib`.
pub fn write_fmu(path: &Path, lib: &Path) -> Result<(), String> {
    let xml = model_description();
    let doc = fmi2::documentation::<MachineStructureFmu>(
        "<p>Modal model of a machine frame (two modes per direction, exact zero-order-hold \
         discretisation, any step size). Inputs: <code>x.driveForce</code> … from CncMotion; outputs: \
         <code>x.deflection</code>, <code>x.acceleration</code>, <code>x.loadForce</code> (back to \
         CncMotion <code>x.loadForce</code> for two-way coupling). Only <code>x.acceleration</code> \
         depends directly on an input (<code>x.driveForce</code>). Defaults: a small mill (45/120 Hz \
         in x). The flexible variant (first mode 12 Hz) is in examples/flexible_structure.json.</p>",
    );
    fmi2::package::write_fmu(
        path,
        &fmi2::package::FmuFiles {
            model_identifier: "MachineStructure",
            model_description: &xml,
            shared_library: lib,
            resources: Vec::new(),
            documentation_html: &doc,
            sources: sources()?,
        },
    )
}

fmi2::export_fmi2!(crate::MachineStructureFmu);
