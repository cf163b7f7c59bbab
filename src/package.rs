//! `cnc-motion package`: CncMotion.fmu from the built shared library, the generated
//! modelDescription.xml, the default program and an HTML page describing the variables.

use crate::fmu::{model_description, CncMotionFmu, DEFAULT_PROGRAM};
use fmi2::package::{manifest, sources_readme, tree, write_fmu as write_archive, Entry, FmuFiles};
use fmi2::Model;
use std::path::{Path, PathBuf};

/// The cdylib built beside the running executable (target/<profile>/libcnc_motion.so).
fn shared_library() -> Result<PathBuf, String> {
    let exe = std::env::current_exe().map_err(|e| format!("current executable: {e}"))?;
    let mut dir = exe.parent().map(Path::to_path_buf).unwrap_or_default();
    // Test and example binaries live one level deeper (target/<profile>/deps, …/examples).
    for _ in 0..2 {
        let lib = dir.join("libcnc_motion.so");
        if lib.exists() {
            return Ok(lib);
        }
        if !dir.pop() {
            break;
        }
    }
    Err(format!(
        "libcnc_motion.so not found beside {} (build the library: cargo build --release)",
        exe.display()
    ))
}

/// documentation/index.html: what the FMU does and an example, then the variables (fmi2).
pub fn documentation() -> String {
    let intro = format!(
        "<p>A CNC motion controller as an FMI 2.0 Co-Simulation FMU. It reads a G-code program (parameter \
         <code>program</code>, or the file <code>programFile</code>, relative to the FMU's resources; the \
         default program <code>default.ngc</code> is shipped), plans it with a bounded look-ahead and a \
         jerk-limited feed law (<code>machine.profile</code>, or the Integer <code>machine.profileIndex</code> \
         for importers without Enumerations), interpolates it every <code>machine.interpolationPeriod</code> \
         (outputs <code>*.command.*</code>, <code>path.*</code> and <code>status.*</code> change at these \
         ticks, zero-order hold between), and drives three servo axes (outputs <code>x.position</code>, \
         <code>x.followingError</code>, <code>x.motorTorque</code>, <code>x.driveForce</code>, …) that are \
         sub-stepped inside every communication step, so any step size h &gt; 0 works. Inputs: \
         <code>feedOverride</code> (0…2), <code>feedHold</code>, <code>x.loadForce</code>/<code>y.</code>/\
         <code>z.</code> from a structure model; no output depends directly on an input. A bad program \
         makes fmi2ExitInitializationMode return fmi2Error with <code>file:line:col: message</code> in the \
         log. The Rust sources of the binary are in <code>sources/</code>.</p>\
         <h2>Example (fmpy)</h2><pre>from fmpy import simulate_fmu\n\
         res = simulate_fmu('CncMotion.fmu', stop_time={}, output_interval=0.001,\n    \
         start_values={{'program': 'G21 G90 G1 X10 Y5 F3000\\nM30\\n', 'machine.profile': 1}})\n\
         print(res['x.command.position'][-1])</pre>",
        CncMotionFmu::info().default_experiment.1
    );
    fmi2::documentation::<CncMotionFmu>(&intro)
}

/// sources/: this crate (manifest without its benches and dev-dependencies, in a workspace of
/// itself and crates/fmi2), its lock file, src/, the default program, and the fmi2 crate.
pub fn sources() -> Result<Vec<Entry>, String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let read = |p: &str| std::fs::read_to_string(root.join(p)).map_err(|e| format!("{p}: {e}"));
    let members = [(r#""crates/fmi2", "crates/machine-structure""#, r#""crates/fmi2""#)];
    let cargo = manifest(
        &read("Cargo.toml")?,
        &["[dev-dependencies]", "[[bench]]"],
        &members,
    );
    let mut files = vec![
        ("Cargo.toml".to_string(), cargo.into_bytes()),
        ("Cargo.lock".to_string(), read("Cargo.lock")?.into_bytes()),
        (
            "resources/default.ngc".to_string(),
            DEFAULT_PROGRAM.as_bytes().to_vec(),
        ),
        (
            "crates/fmi2/Cargo.toml".to_string(),
            read("crates/fmi2/Cargo.toml")?.into_bytes(),
        ),
        sources_readme("CncMotion", "cnc_motion"),
    ];
    files.extend(tree(&root.join("src"), "src")?);
    files.extend(tree(&root.join("crates/fmi2/src"), "crates/fmi2/src")?);
    Ok(files)
}

pub fn write_fmu(path: &Path) -> Result<(), String> {
    let lib = shared_library()?;
    let xml = model_description();
    let doc = documentation();
    write_archive(
        path,
        &FmuFiles {
            model_identifier: &CncMotionFmu::info().model_identifier,
            model_description: &xml,
            shared_library: &lib,
            resources: vec![("default.ngc".into(), DEFAULT_PROGRAM.as_bytes().to_vec())],
            documentation_html: &doc,
            sources: sources()?,
        },
    )
}
