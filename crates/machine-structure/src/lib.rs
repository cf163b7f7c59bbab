//! MachineStructure FMU: a modal model of a machine frame, driven by the axis drive forces, giving
//! the tool-point deflection and frame acceleration, and the inertial force the moving frame puts
//! back on each axis (two-way coupling). Built on the generic FMI layer (crates/fmi2): the whole
//! model glue is the table below.

// The unit-test build sees the integration tests' dependencies.
#[cfg(test)]
use libloading as _;

pub mod modal;
pub mod ranges;

use fmi2::table::{index_of, Entry};
use fmi2::Causality::{Input as IN, Local as LOC, Output as OUT, Parameter as PAR};
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
    /// d(driveForce)/dt over the coming steps (fmi2SetRealInputDerivatives, first-order hold);
    /// 0 holds the force. Setting the force sets it back to 0.
    pub drive_rate: [f64; 3],
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
            drive_rate: [0.0; 3],
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
    /// Exact over h with each drive force held, or ramped at its rate; a ramped force ends at its
    /// value at the new time.
    pub fn step(&mut self, h: f64) {
        for i in 0..3 {
            let (force, rate) = (self.drive_force[i], self.drive_rate[i]);
            for k in 0..MODES {
                self.state[i][k].step_ramp(&self.modes[i][k], force, rate, h);
            }
            if rate != 0.0 {
                self.drive_force[i] = force + rate * h;
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
    /// Continuous state of a mode (mode, 0: displacement q, 1: velocity q̇) or its q̈ (2).
    State(usize, usize),
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
    ("#.mode1.q",         Type::Real, LOC, CONT, "m",    NO,        NO,      Slot::State(0, 0),  "# mode 1: modal displacement (continuous state)"),
    ("#.mode1.v",         Type::Real, LOC, CONT, "m/s",  NO,        NO,      Slot::State(0, 1),  "# mode 1: modal velocity (continuous state, der(q))"),
    ("#.mode1.a",         Type::Real, LOC, CONT, "m/s2", NO,        NO,      Slot::State(0, 2),  "# mode 1: modal acceleration der(v) = F/m − 2ζω v − ω² q"),
    ("#.mode2.q",         Type::Real, LOC, CONT, "m",    NO,        NO,      Slot::State(1, 0),  "# mode 2: modal displacement (continuous state)"),
    ("#.mode2.v",         Type::Real, LOC, CONT, "m/s",  NO,        NO,      Slot::State(1, 1),  "# mode 2: modal velocity (continuous state, der(q))"),
    ("#.mode2.a",         Type::Real, LOC, CONT, "m/s2", NO,        NO,      Slot::State(1, 2),  "# mode 2: modal acceleration der(v) = F/m − 2ζω v − ω² q"),
];

/// The table expanded, with the state-space structure of each axis (per mode q̇ = v,
/// v̇ = F/m − 2ζω v − ω² q): the modal q and v are the continuous states (v the derivative of q,
/// a of v); deflection = Σ q, acceleration = Σ v̇ (directly on the drive force of the same axis),
/// loadForce = −M·Σ(−2ζω v − ω² q). Dependencies list the inputs and states each unknown reads.
fn table() -> &'static [Entry<Slot>] {
    static T: OnceLock<Vec<Entry<Slot>>> = OnceLock::new();
    T.get_or_init(|| {
        let mut t = fmi2::table::expand(ROWS, &AXES, fmi2::table::one);
        let at = |t: &[Entry<Slot>], name: String| index_of(t, &name).expect("in the table");
        for a in AXES {
            let force = at(&t, format!("{a}.driveForce"));
            let q: Vec<usize> = (1..=MODES).map(|k| at(&t, format!("{a}.mode{k}.q"))).collect();
            let v: Vec<usize> = (1..=MODES).map(|k| at(&t, format!("{a}.mode{k}.v"))).collect();
            let qv: Vec<usize> = q.iter().chain(&v).copied().collect();
            for k in 0..MODES {
                let acc = at(&t, format!("{a}.mode{}.a", k + 1));
                t[v[k]].var.derivative_of = Some(q[k]);
                t[v[k]].var.dependencies = Some(vec![v[k]]);
                t[acc].var.derivative_of = Some(v[k]);
                t[acc].var.dependencies = Some(sorted(vec![force, q[k], v[k]]));
            }
            let outputs = [
                ("deflection", q.clone()),
                ("acceleration", qv.iter().copied().chain([force]).collect()),
                ("loadForce", qv),
            ];
            for (name, deps) in outputs {
                let o = at(&t, format!("{a}.{name}"));
                t[o].var.dependencies = Some(sorted(deps));
            }
        }
        t
    })
}

fn sorted(mut v: Vec<usize>) -> Vec<usize> {
    v.sort_unstable();
    v
}

/// ∂unknown/∂known of the state-space form (see [`table`]) for the variables of axis `i`: the
/// model is linear, so these are the entries of its matrices A, B, C, D.
fn partial(m: &MachineStructure, unknown: Slot, known: Slot, i: usize) -> f64 {
    let mode = |k: usize| m.modes[i][k];
    // d(Σ_k v̇_k)/d(known) without the force term, times `scale`.
    let modal = |known: Slot, scale: f64| match known {
        Slot::State(k, 0) => -mode(k).omega().powi(2) * scale,
        Slot::State(k, _) => -2.0 * mode(k).damping * mode(k).omega() * scale,
        _ => 0.0,
    };
    match (unknown, known) {
        (Slot::Deflection, Slot::State(_, 0)) => 1.0,
        (Slot::Acceleration, Slot::Force) => (0..MODES).map(|k| 1.0 / mode(k).mass).sum(),
        (Slot::Acceleration, _) => modal(known, 1.0),
        (Slot::LoadForce, _) => modal(known, -m.coupling_mass[i]),
        (Slot::State(k, 1), Slot::State(l, 1)) if k == l => 1.0,
        (Slot::State(k, 2), Slot::Force) => 1.0 / mode(k).mass,
        (Slot::State(k, 2), Slot::State(l, _)) if k == l => modal(known, 1.0),
        _ => 0.0,
    }
}

#[derive(Clone, Debug)]
pub struct MachineStructureFmu(pub MachineStructure);

impl fmi2::Model for MachineStructureFmu {
    fn info() -> &'static ModelInfo {
        static INFO: OnceLock<ModelInfo> = OnceLock::new();
        INFO.get_or_init(|| {
            let description = "Modal model of a machine frame driven by the axis drive forces";
            let info =
                fmi2::crate_model_info!("MachineStructure", description, fmi2::table::variables(table()));
            let capabilities = fmi2::Capabilities {
                provides_directional_derivative: true,
                // The drive forces with a first-order hold (exact: the model is linear).
                max_input_derivative_order: 1,
                ..info.capabilities
            };
            // CncMotion's terminal of the same name (`plug`): drive forces in, load forces out.
            let terminals = vec![fmi2::Terminal {
                name: "frame".into(),
                kind: "org.cnc-motion.frameCoupling".into(),
                description: "two-way coupling with the axis drives: drive forces in, load forces out".into(),
                members: vec![
                    ("driveForce".into(), "driveForce".into()),
                    ("loadForce".into(), "loadForce".into()),
                ],
            }];
            ModelInfo {
                terminals,
                ..info.with_capabilities(capabilities)
            }
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
            Slot::State(k, 0) => m.state[i][k].q,
            Slot::State(k, 1) => m.state[i][k].v,
            Slot::State(k, _) => m.state[i][k].acceleration(&m.modes[i][k], m.drive_force[i]),
        })
    }

    /// The entries of A, B, C, D ([`partial`]); variables of different axes do not interact.
    fn partial_derivative(&self, unknown: usize, known: usize) -> f64 {
        let (u, k) = (&table()[unknown], &table()[known]);
        if u.axis != k.axis {
            return 0.0;
        }
        partial(&self.0, u.slot, k.slot, u.axis)
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
                m.drive_rate[i] = 0.0;
            }
            _ => return Err("outputs cannot be set".into()),
        }
        Ok(())
    }

    /// The first derivative of a drive force: the force ramps over the coming steps (exact,
    /// [`modal::ModeState::step_ramp`]).
    fn set_input_derivative(&mut self, index: usize, _order: u32, value: f64) -> Result<(), String> {
        let (e, i) = (&table()[index], table()[index].axis);
        match e.slot {
            Slot::Force => {
                ranges::check_drive_rate(value)?;
                self.0.drive_rate[i] = value;
                Ok(())
            }
            _ => Err("not an input".into()),
        }
    }

    fn exit_initialization(&mut self) -> Result<(), String> {
        ranges::check_structure(&self.0)
    }

    fn do_step(&mut self, h: f64) -> Result<(), String> {
        self.0.step(h);
        // A ramped force stays within the input's range.
        self.0
            .drive_force
            .iter()
            .try_for_each(|&f| ranges::check_drive_force(f))?;
        ranges::check_outputs(&self.0)
    }

    /// postcard of the whole model (fixed-size plain data; the layer adds magic, version, GUID
    /// and length).
    fn serialize(&self) -> Vec<u8> {
        postcard::to_stdvec(&self.0).unwrap_or_default()
    }

    fn deserialize(&mut self, bytes: &[u8]) -> Result<(), String> {
        let (state, rest): (MachineStructure, _) =
            postcard::take_from_bytes(bytes).map_err(|e| format!("MachineStructure state: {e}"))?;
        if !rest.is_empty() {
            return Err(format!(
                "MachineStructure state: {} bytes after its end",
                rest.len()
            ));
        }
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

/// sources/: this crate (its manifest as a workspace root, fmi2 and fmi3 beside src/), the fmi2
/// and fmi3 crates and the lock file.
pub fn sources() -> Result<Vec<fmi2::package::Entry>, String> {
    use fmi2::package::{manifest, sources_readme, tree};
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let text = std::fs::read_to_string(root.join("Cargo.toml")).map_err(|e| format!("Cargo.toml: {e}"))?;
    let cargo = manifest(
        &text,
        &["[dev-dependencies]"],
        &[("../fmi2", "fmi2"), ("../fmi3", "fmi3")],
    ) + "\n[workspace]\n";
    let fmi2_toml = std::fs::read(root.join("../fmi2/Cargo.toml")).map_err(|e| format!("fmi2: {e}"))?;
    let fmi3_toml = std::fs::read(root.join("../fmi3/Cargo.toml")).map_err(|e| format!("fmi3: {e}"))?;
    // The workspace's lock: the versions the shipped binaries were built with (cargo drops the
    // entries this smaller workspace does not use).
    let lock = std::fs::read(root.join("../../Cargo.lock")).map_err(|e| format!("Cargo.lock: {e}"))?;
    let mut files = vec![
        ("Cargo.toml".to_string(), cargo.into_bytes()),
        ("Cargo.lock".to_string(), lock),
        ("fmi2/Cargo.toml".to_string(), fmi2_toml),
        ("fmi3/Cargo.toml".to_string(), fmi3_toml),
        sources_readme(
            "MachineStructure",
            "machine-structure",
            "machine_structure",
            env!("CARGO_PKG_RUST_VERSION"),
        ),
    ];
    files.extend(tree(&root.join("src"), "src")?);
    files.extend(tree(&root.join("../fmi2/src"), "fmi2/src")?);
    files.extend(tree(&root.join("../fmi3/src"), "fmi3/src")?);
    Ok(files)
}

/// Write MachineStructure.fmu from the built shared libraries (by platform), and beside it the
/// FMI 3.0 archive ([`fmi3::archive_path`]) with the same binaries.
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
         Binaries: linux64 and win64 (FMI 3.0: also aarch64-linux); reference result of the default experiment (no input: at rest) \
         in <code>extra/org.fmi-standard.fmi-ls-ref/</code>; Rust sources in <code>sources/</code>.</p>",
    );
    let files = fmi2::package::FmuFiles {
        fmi_version: 2,
        model_identifier: "MachineStructure",
        model_description: &xml,
        binaries,
        resources: Vec::new(),
        documentation_html: &doc,
        extra: fmi2::reference::files::<MachineStructureFmu>(None, 10)?,
        sources: sources()?,
        terminals: None,
    };
    fmi2::package::write_fmu(path, &files)?;
    let xml3 = fmi3::model_description::<MachineStructureFmu>();
    let files3 = fmi2::package::FmuFiles {
        fmi_version: 3,
        model_description: &xml3,
        extra: fmi3::reference::files::<MachineStructureFmu>(None, 10)?,
        terminals: fmi3::terminals_and_icons::<MachineStructureFmu>(),
        ..files
    };
    fmi2::package::write_fmu(&fmi3::archive_path(path), &files3)
}

fmi2::export_fmi2!(crate::MachineStructureFmu);
fmi3::export_fmi3!(crate::MachineStructureFmu);
