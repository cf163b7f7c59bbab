//! `package-machine-structure [OUTPUT] [--platforms linux64,win64,aarch64-linux]`: writes
//! target/fmu/MachineStructure.fmu (or OUTPUT) from the shared libraries built beside this
//! executable (linux64) and in target/<triple>/release (win64 and aarch64-linux, `make cross`).

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]
use std::path::PathBuf;

fn main() -> std::process::ExitCode {
    let mut out = "target/fmu/MachineStructure.fmu".to_string();
    let mut platforms = fmi2::package::ALL_PLATFORMS.to_string();
    let mut args = std::env::args().skip(1);
    while let Some(a) = args.next() {
        match a.as_str() {
            "--platforms" => platforms = args.next().unwrap_or_default(),
            _ => out = a,
        }
    }
    let exe = std::env::current_exe().unwrap_or_default();
    let dir: PathBuf = exe.parent().map(PathBuf::from).unwrap_or_default();
    let written = fmi2::package::platforms(&platforms)
        .and_then(|p| fmi2::package::built_libraries(&dir, "machine_structure", &p))
        .and_then(|libs| machine_structure::write_fmu(std::path::Path::new(&out), libs));
    match written {
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
