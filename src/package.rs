//! `cnc-motion package`: CncMotion.fmu from the built shared libraries (linux64, and win64
//! cross-compiled), the generated modelDescription.xml, the default program, an HTML page
//! describing the variables, the reference result of the default experiment and the sources.

use crate::fmu::{model_description, CncMotionFmu, DEFAULT_PROGRAM};
use fmi2::package::{manifest, sources_readme, tree, write_fmu as write_archive, Entry, FmuFiles};
use fmi2::Model;
use std::path::{Path, PathBuf};

/// The profile folder (target/<profile>) of the running executable; test and example binaries
/// live one level deeper (target/<profile>/deps, …/examples).
fn profile_dir() -> Result<PathBuf, String> {
    let exe = std::env::current_exe().map_err(|e| format!("current executable: {e}"))?;
    let dir = exe.parent().map(Path::to_path_buf).unwrap_or_default();
    let deeper = matches!(
        dir.file_name().and_then(|n| n.to_str()),
        Some("deps" | "examples")
    );
    Ok(if deeper {
        dir.parent().map(Path::to_path_buf).unwrap_or(dir)
    } else {
        dir
    })
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
         log. <code>machineFile</code> reads the machine file of the command line (tools, work offsets, \
         homes, switches, units, axes, drives); parameters set to other values than their start values \
         override its keys. Binaries: linux64 and win64 (Windows 10 or later); the FMI 3.0 archive also aarch64-linux. The reference result \
         of the default experiment is in <code>extra/org.fmi-standard.fmi-ls-ref/</code>; the Rust \
         sources of the binaries, with how to build them, in <code>sources/</code>.</p>\
         <h2>Example (fmpy)</h2><pre>from fmpy import simulate_fmu\n\
         res = simulate_fmu('CncMotion.fmu', stop_time={}, output_interval=0.001,\n    \
         start_values={{'program': 'G21 G90 G1 X10 Y5 F3000\\nM30\\n', 'machine.profile': 1}})\n\
         print(res['x.command.position'][-1])</pre>",
        CncMotionFmu::info().default_experiment.1
    );
    fmi2::documentation::<CncMotionFmu>(&intro)
}

/// sources/: this crate (manifest without its benches and dev-dependencies, in a workspace of
/// itself, crates/fmi2 and crates/fmi3), its lock file, src/, the default program, and the fmi2
/// and fmi3 crates.
pub fn sources() -> Result<Vec<Entry>, String> {
    let root = Path::new(env!("CARGO_MANIFEST_DIR"));
    let read = |p: &str| std::fs::read_to_string(root.join(p)).map_err(|e| format!("{p}: {e}"));
    let members = [(
        r#""crates/fmi2", "crates/fmi3", "crates/machine-structure""#,
        r#""crates/fmi2", "crates/fmi3""#,
    )];
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
        (
            "crates/fmi3/Cargo.toml".to_string(),
            read("crates/fmi3/Cargo.toml")?.into_bytes(),
        ),
        sources_readme(
            "CncMotion",
            "cnc-motion",
            "cnc_motion",
            env!("CARGO_PKG_RUST_VERSION"),
        ),
    ];
    files.extend(tree(&root.join("src"), "src")?);
    files.extend(tree(&root.join("crates/fmi2/src"), "crates/fmi2/src")?);
    files.extend(tree(&root.join("crates/fmi3/src"), "crates/fmi3/src")?);
    Ok(files)
}

/// Reference result: the default experiment at its 1 ms step, a row every 10 ms.
const REFERENCE_EVERY: usize = 10;

/// Write the FMU with the binaries of `platforms` (`linux64,win64`), and beside it the FMI 3.0
/// archive ([`fmi3::archive_path`]) with the same binaries, resources, documentation and sources.
pub fn write_fmu(path: &Path, platforms: &str) -> Result<(), String> {
    let platforms = fmi2::package::platforms(platforms)?;
    let binaries = fmi2::package::built_libraries(&profile_dir()?, "cnc_motion", &platforms)?;
    let xml = model_description();
    let doc = documentation();
    let resources = Path::new(env!("CARGO_MANIFEST_DIR")).join("resources");
    let extra = fmi2::reference::files::<CncMotionFmu>(Some(&resources), REFERENCE_EVERY)
        .map_err(|e| format!("reference result: {e}"))?;
    let files = FmuFiles {
        fmi_version: 2,
        model_identifier: &CncMotionFmu::info().model_identifier,
        model_description: &xml,
        binaries,
        resources: vec![("default.ngc".into(), DEFAULT_PROGRAM.as_bytes().to_vec())],
        documentation_html: &doc,
        extra,
        sources: sources()?,
        terminals: None,
    };
    write_archive(path, &files)?;
    let xml3 = fmi3::model_description::<CncMotionFmu>();
    let extra3 = fmi3::reference::files::<CncMotionFmu>(Some(&resources), REFERENCE_EVERY)
        .map_err(|e| format!("reference result: {e}"))?;
    let files3 = FmuFiles {
        fmi_version: 3,
        model_description: &xml3,
        extra: extra3,
        terminals: fmi3::terminals_and_icons::<CncMotionFmu>(),
        ..files
    };
    write_archive(&fmi3::archive_path(path), &files3)
}
