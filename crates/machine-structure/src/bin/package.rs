//! Writes target/fmu/MachineStructure.fmu (or the path given) from the shared library built beside
//! this executable.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]
use std::path::PathBuf;

fn main() -> std::process::ExitCode {
    let out = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "target/fmu/MachineStructure.fmu".into());
    let exe = std::env::current_exe().unwrap_or_default();
    let lib: PathBuf = exe
        .parent()
        .map(|d| d.join("libmachine_structure.so"))
        .unwrap_or_default();
    match machine_structure::write_fmu(std::path::Path::new(&out), &lib) {
        Ok(()) => {
            println!("{out}");
            std::process::ExitCode::SUCCESS
        }
        Err(e) => {
            eprintln!("package-machine-structure: {e}");
            std::process::ExitCode::from(2)
        }
    }
}
