//! MachineStructure FMU: a modal model of a machine frame, driven by the axis drive forces, giving
//! the tool-point deflection and frame acceleration, and the inertial force the moving frame puts
//! back on each axis (two-way coupling). Built on the generic FMI layer (crates/fmi2): the whole
//! model glue is the table below.

pub mod modal;
pub mod ranges;

use fmi2::table::{index_of, Entry};
use fmi2::Causality::{Input as IN, Output as OUT, Parameter as PAR};
use fmi2::Variability::{Continuous as CONT, Fixed as FIX};
use fmi2::{ModelInfo, Type, Value};
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

/// What a row of the table reads or writes on its axis: (mode, field) or the axis' own value.
#[derive(Clone, Copy, Debug)]
enum Slot {
    Mode(usize, usize),
    Coupling,
    Force,
    Deflection,
    Acceleration,
    LoadForce,
}

const NO: Option<f64> = None;
/// Declared ranges: the ones `ranges` enforces (one source).
const fn lo(range: (f64, f64)) -> Option<f64> {
    Some(range.0)
}
const fn hi(range: (f64, f64)) -> Option<f64> {
    Some(range.1)
}
use ranges::{COUPLING_MASS_KG as CM, DAMPING as DZ, FREQUENCY_HZ as FHZ, MODAL_MASS_KG as MM};
const FORCE: (f64, f64) = (-ranges::MAX_DRIVE_FORCE_N, ranges::MAX_DRIVE_FORCE_N);

/// The variables, one row per axis each (see [`fmi2::table::Row`]).
#[rustfmt::skip]
const ROWS: &[fmi2::table::Row<Slot>] = &[
    ("#.mode1.frequency", Type::Real, PAR, FIX,  "Hz",   lo(FHZ),   hi(FHZ), Slot::Mode(0, 0),   "# mode 1: natural frequency"),
    ("#.mode1.damping",   Type::Real, PAR, FIX,  "1",    lo(DZ),    hi(DZ),  Slot::Mode(0, 1),   "# mode 1: damping ratio"),
    ("#.mode1.mass",      Type::Real, PAR, FIX,  "kg",   lo(MM),    hi(MM),  Slot::Mode(0, 2),   "# mode 1: modal mass"),
    ("#.mode2.frequency", Type::Real, PAR, FIX,  "Hz",   lo(FHZ),   hi(FHZ), Slot::Mode(1, 0),   "# mode 2: natural frequency"),
    ("#.mode2.damping",   Type::Real, PAR, FIX,  "1",    lo(DZ),    hi(DZ),  Slot::Mode(1, 1),   "# mode 2: damping ratio"),
    ("#.mode2.mass",      Type::Real, PAR, FIX,  "kg",   lo(MM),    hi(MM),  Slot::Mode(1, 2),   "# mode 2: modal mass"),
    ("#.couplingMass",    Type::Real, PAR, FIX,  "kg",   lo(CM),    hi(CM),  Slot::Coupling,     "mass riding on the frame along # (table); loadForce = −couplingMass·acceleration"),
    ("#.driveForce",      Type::Real, IN,  CONT, "N",    lo(FORCE), hi(FORCE), Slot::Force,        "force of the # drive on the frame"),
    ("#.deflection",      Type::Real, OUT, CONT, "m",    NO,        NO,      Slot::Deflection,   "tool-point deflection of the frame along #"),
    ("#.acceleration",    Type::Real, OUT, CONT, "m/s2", NO,        NO,      Slot::Acceleration, "frame acceleration along # (direct feed-through of #.driveForce)"),
    ("#.loadForce",       Type::Real, OUT, CONT, "N",    NO,        NO,      Slot::LoadForce,    "inertial force of the moving frame on the # table, −couplingMass·(modal acceleration without the direct F/m term); to CncMotion #.loadForce"),
];

/// The table expanded; a = Σ (F/m − 2ζω q̇ − ω² q): each axis' acceleration depends directly on
/// the drive force of the same axis, every other output on no input.
fn table() -> &'static [Entry<Slot>] {
    static T: OnceLock<Vec<Entry<Slot>>> = OnceLock::new();
    T.get_or_init(|| {
        let mut t = fmi2::table::expand(ROWS, &AXES, fmi2::table::one);
        for a in AXES {
            let force = index_of(&t, &format!("{a}.driveForce"));
            let acceleration = index_of(&t, &format!("{a}.acceleration")).expect("in the table");
            t[acceleration].var.dependencies = force.map(|f| vec![f]);
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
            let description = "Modal model of a machine frame driven by the axis drive forces";
            fmi2::crate_model_info!("MachineStructure", description, fmi2::table::variables(table()))
        })
    }

    fn new(_resources: Option<&Path>) -> Self {
        MachineStructureFmu(MachineStructure::default())
    }

    fn get(&self, index: usize) -> Value {
        let (m, e, i) = (&self.0, &table()[index], table()[index].axis);
        Value::Real(match e.slot {
            Slot::Mode(k, 0) => m.modes[i][k].frequency,
            Slot::Mode(k, 1) => m.modes[i][k].damping,
            Slot::Mode(k, _) => m.modes[i][k].mass,
            Slot::Coupling => m.coupling_mass[i],
            Slot::Force => m.drive_force[i],
            Slot::Deflection => m.deflection(i),
            Slot::Acceleration => m.acceleration(i),
            Slot::LoadForce => m.load_force(i),
        })
    }

    fn set(&mut self, index: usize, value: Value) -> Result<(), String> {
        let Value::Real(x) = value else {
            return Err("not a Real".into());
        };
        if !x.is_finite() {
            return Err(format!("{x} is not finite"));
        }
        let (m, e, i) = (&mut self.0, &table()[index], table()[index].axis);
        match e.slot {
            Slot::Mode(k, f) => {
                let mut mode = m.modes[i][k];
                match f {
                    0 => mode.frequency = x,
                    1 => mode.damping = x,
                    _ => mode.mass = x,
                }
                mode.check()?;
                m.modes[i][k] = mode;
            }
            Slot::Coupling => {
                ranges::within("couplingMass", x, ranges::COUPLING_MASS_KG, "kg")?;
                m.coupling_mass[i] = x;
            }
            Slot::Force => {
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

    /// bincode of the whole model (fixed-size plain data; the layer adds magic, version, GUID
    /// and length).
    fn serialize(&self) -> Vec<u8> {
        bincode::serialize(&self.0).unwrap_or_default()
    }

    fn deserialize(&mut self, bytes: &[u8]) -> Result<(), String> {
        let state: MachineStructure =
            bincode::deserialize(bytes).map_err(|e| format!("MachineStructure state: {e}"))?;
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

/// sources/: this crate (its manifest as a workspace root, fmi2 beside src/), the fmi2 crate and
/// the lock file.
pub fn sources() -> Result<Vec<fmi2::package::Entry>, String> {
    use fmi2::package::{manifest, sources_readme, tree};
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("Cargo.toml")).map_err(|e| format!("Cargo.toml: {e}"))?;
    let cargo = manifest(&text, &[], &[("../fmi2", "fmi2")]) + "\n[workspace]\n";
    let fmi2_toml = std::fs::read(root.join("../fmi2/Cargo.toml")).map_err(|e| format!("fmi2: {e}"))?;
    // The workspace's lock: the versions the shipped binaries were built with (cargo drops the
    // entries this smaller workspace does not use).
    let lock = std::fs::read(root.join("../../Cargo.lock")).map_err(|e| format!("Cargo.lock: {e}"))?;
    let mut files = vec![
        ("Cargo.toml".to_string(), cargo.into_bytes()),
        ("Cargo.lock".to_string(), lock),
        ("fmi2/Cargo.toml".to_string(), fmi2_toml),
        sources_readme(
            "MachineStructure",
            "machine-structure",
            "machine_structure",
            env!("CARGO_PKG_RUST_VERSION"),
        ),
    ];
    files.extend(tree(&root.join("src"), "src")?);
    files.extend(tree(&root.join("../fmi2/src"), "fmi2/src")?);
    Ok(files)
}

/// Write MachineStructure.fmu from the built shared libraries (by platform).
pub fn write_fmu(
    path: &Path,
    binaries: Vec<(&'static fmi2::package::Platform, std::path::PathBuf)>,
) -> Result<(), String> {
    let xml = model_description();
    let doc = fmi2::documentation::<MachineStructureFmu>(
        "<p>Modal model of a machine frame (two modes per direction, exact zero-order-hold \
         discretisation, any step size). Inputs: <code>x.driveForce</code> … from CncMotion; outputs: \
         <code>x.deflection</code>, <code>x.acceleration</code>, <code>x.loadForce</code> (back to \
         CncMotion <code>x.loadForce</code> for two-way coupling). Only <code>x.acceleration</code> \
         depends directly on an input (<code>x.driveForce</code>). Defaults: a small mill (45/120 Hz \
         in x). The flexible variant (first mode 12 Hz) is in examples/flexible_structure.json. \
         Binaries: linux64 and win64; reference result of the default experiment (no input: at rest) \
         in <code>extra/org.fmi-standard.fmi-ls-ref/</code>; Rust sources in <code>sources/</code>.</p>",
    );
    fmi2::package::write_fmu(
        path,
        &fmi2::package::FmuFiles {
            model_identifier: "MachineStructure",
            model_description: &xml,
            binaries,
            resources: Vec::new(),
            documentation_html: &doc,
            extra: fmi2::reference::files::<MachineStructureFmu>(None, 10)?,
            sources: sources()?,
        },
    )
}

fmi2::export_fmi2!(crate::MachineStructureFmu);
