//! Writing a .fmu (FMI 2.0 or 3.0): modelDescription.xml, binaries/<platform>/<id>.<so|dll>
//! (linux64 and win64; FMI 3: x86_64-linux, x86_64-windows and aarch64-linux, the same libraries,
//! which export both versions' functions), resources/, documentation/, extra/ (the reference result),
//! terminalsAndIcons/ (FMI 3), sources/. The archive is
//! reproducible: entries in a fixed order, each with the same fixed timestamp (1980-01-01, the zip
//! epoch) and permissions, so the same inputs give the same bytes.

use std::io::Write;
use std::path::{Path, PathBuf};
use zip::write::SimpleFileOptions;

/// A file inside the archive: path and bytes.
pub type Entry = (String, Vec<u8>);

/// A platform the FMU ships a binary for: FMI 2.0 name (None: FMI 2.0 names no such platform, the
/// binary goes into the FMI 3.0 archive only), FMI 3.0 name, Rust target (None: the host build),
/// shared-library file name from the crate's library name.
#[derive(Debug)]
pub struct Platform {
    /// The name in `--platforms` lists: the FMI 2.0 name where there is one, else the FMI 3.0 one.
    pub name: &'static str,
    pub fmi2_name: Option<&'static str>,
    pub fmi3_name: &'static str,
    pub target: Option<&'static str>,
    pub library: fn(&str) -> String,
    pub extension: &'static str,
}

/// linux64 (the host build), win64 (cross-compiled with mingw-w64) and aarch64-linux (cross-compiled
/// with Debian's aarch64 gcc; FMI 2.0 has no name for it: an FMI 2 importer on aarch64 looks into
/// `linux64`, which holds the x86_64 library, so it ships in the FMI 3.0 archive only).
pub const PLATFORMS: [Platform; 3] = [
    Platform {
        name: "linux64",
        fmi2_name: Some("linux64"),
        fmi3_name: "x86_64-linux",
        target: None,
        library: |lib| format!("lib{lib}.so"),
        extension: "so",
    },
    Platform {
        name: "win64",
        fmi2_name: Some("win64"),
        fmi3_name: "x86_64-windows",
        target: Some("x86_64-pc-windows-gnu"),
        library: |lib| format!("{lib}.dll"),
        extension: "dll",
    },
    Platform {
        name: "aarch64-linux",
        fmi2_name: None,
        fmi3_name: "aarch64-linux",
        target: Some("aarch64-unknown-linux-gnu"),
        library: |lib| format!("lib{lib}.so"),
        extension: "so",
    },
];

/// Every platform, as a `--platforms` list.
pub const ALL_PLATFORMS: &str = "linux64,win64,aarch64-linux";

/// The platforms named in a comma-separated list (`linux64,win64`), in [`PLATFORMS`] order.
pub fn platforms(list: &str) -> Result<Vec<&'static Platform>, String> {
    let names: Vec<&str> = list.split(',').map(str::trim).filter(|n| !n.is_empty()).collect();
    if let Some(bad) = names.iter().find(|n| PLATFORMS.iter().all(|p| p.name != **n)) {
        return Err(format!("unknown platform '{bad}' (known: {ALL_PLATFORMS})"));
    }
    Ok(PLATFORMS.iter().filter(|p| names.contains(&p.name)).collect())
}

/// The built libraries of `lib_name` for `platforms`, found from `profile_dir`
/// (target/release): the host's there, a cross target's in target/<triple>/release.
pub fn built_libraries(
    profile_dir: &Path,
    lib_name: &str,
    platforms: &[&'static Platform],
) -> Result<Vec<(&'static Platform, PathBuf)>, String> {
    let profile = profile_dir.file_name().map(PathBuf::from).unwrap_or_default();
    let target_dir = profile_dir.parent().unwrap_or(profile_dir);
    platforms
        .iter()
        .map(|p| {
            let dir = match p.target {
                None => profile_dir.to_path_buf(),
                Some(triple) => target_dir.join(triple).join(&profile),
            };
            let path = dir.join((p.library)(lib_name));
            if path.exists() {
                Ok((*p, path))
            } else {
                let how = match p.target {
                    None => "cargo build --release --lib".to_string(),
                    Some(t) => format!("make cross, or cargo build --release --lib --target {t}"),
                };
                Err(format!(
                    "{}: {} not found (build it: {how})",
                    p.name,
                    path.display()
                ))
            }
        })
        .collect()
}

/// Files of an FMU archive, by path inside the archive.
pub struct FmuFiles<'a> {
    /// 2 or 3: the binaries' platform folders (linux64 or x86_64-linux, …).
    pub fmi_version: u8,
    pub model_identifier: &'a str,
    pub model_description: &'a str,
    /// The built shared libraries (cdylib) of the model, by platform.
    pub binaries: Vec<(&'static Platform, PathBuf)>,
    pub resources: Vec<Entry>,
    pub documentation_html: &'a str,
    /// Files under `extra/` (layered standards: the reference result).
    pub extra: Vec<Entry>,
    /// The sources the binary is built from (paths relative to `sources/`).
    pub sources: Vec<Entry>,
    /// terminalsAndIcons/terminalsAndIcons.xml (FMI 3), if any.
    pub terminals: Option<String>,
}

pub fn write_fmu(path: &Path, files: &FmuFiles) -> Result<(), String> {
    let mut libs = Vec::new();
    for (platform, lib) in &files.binaries {
        let folder = if files.fmi_version >= 3 {
            platform.fmi3_name
        } else if let Some(name) = platform.fmi2_name {
            name
        } else {
            continue;
        };
        let bytes = std::fs::read(lib).map_err(|e| format!("{}: {e}", lib.display()))?;
        let name = format!(
            "binaries/{folder}/{}.{}",
            files.model_identifier, platform.extension
        );
        libs.push((name, bytes));
    }
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let opts = SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .last_modified_time(zip::DateTime::default())
        .unix_permissions(0o644);
    let mut entries: Vec<(String, &[u8])> =
        vec![("modelDescription.xml".into(), files.model_description.as_bytes())];
    entries.extend(libs.iter().map(|(n, b)| (n.clone(), b.as_slice())));
    entries.push((
        "documentation/index.html".into(),
        files.documentation_html.as_bytes(),
    ));
    if let Some(t) = &files.terminals {
        entries.push(("terminalsAndIcons/terminalsAndIcons.xml".into(), t.as_bytes()));
    }
    let fixed = entries.len();
    entries.extend(
        files
            .resources
            .iter()
            .map(|(n, b)| (format!("resources/{n}"), b.as_slice())),
    );
    entries.extend(
        files
            .extra
            .iter()
            .map(|(n, b)| (format!("extra/{n}"), b.as_slice())),
    );
    entries.extend(
        files
            .sources
            .iter()
            .map(|(n, b)| (format!("sources/{n}"), b.as_slice())),
    );
    entries[fixed..].sort_by(|a, b| a.0.cmp(&b.0));
    for (name, bytes) in entries {
        zip.start_file(name.as_str(), opts)
            .map_err(|e| format!("{name}: {e}"))?;
        zip.write_all(bytes).map_err(|e| format!("{name}: {e}"))?;
    }
    zip.finish().map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(())
}

/// Every file under `dir`, recursively, in sorted order, as `prefix/relative path`.
pub fn tree(dir: &Path, prefix: &str) -> Result<Vec<Entry>, String> {
    let mut out = Vec::new();
    let mut names: Vec<_> = std::fs::read_dir(dir)
        .map_err(|e| format!("{}: {e}", dir.display()))?
        .filter_map(|e| e.ok().map(|e| e.file_name()))
        .collect();
    names.sort();
    for name in names {
        let (path, rel) = (dir.join(&name), format!("{prefix}/{}", name.to_string_lossy()));
        if path.is_dir() {
            out.extend(tree(&path, &rel)?);
        } else {
            out.push((
                rel,
                std::fs::read(&path).map_err(|e| format!("{}: {e}", path.display()))?,
            ));
        }
    }
    Ok(out)
}

/// A Cargo.toml for the FMU's sources: the sections named in `drop` (e.g. `[dev-dependencies]`,
/// `[[bench]]`) removed and the `(from, to)` text replacements applied.
pub fn manifest(text: &str, drop: &[&str], replace: &[(&str, &str)]) -> String {
    let mut out = String::new();
    let mut keep = true;
    for line in text.lines() {
        if line.starts_with('[') {
            keep = !drop.contains(&line.trim());
        }
        if keep {
            out.push_str(line);
            out.push('\n');
        }
    }
    replace.iter().fold(out, |s, (from, to)| s.replace(from, to))
}

/// sources/README.md: exactly how the binaries are built, for another platform too.
/// `package` is the Cargo package, `lib_name` its library, `rust_version` the least Rust it needs.
pub fn sources_readme(model_identifier: &str, package: &str, lib_name: &str, rust_version: &str) -> Entry {
    let id = model_identifier;
    let text = format!(
        "# Sources of {id}\n\n\
         The Rust sources of this FMU's binaries: a Cargo workspace (the model crate `{package}` and the \
         generic FMI 2.0 layer `fmi2`), with the Cargo.lock the shipped binaries were built with. They \
         are not C sources: modelDescription.xml declares no SourceFiles, and an importer cannot \
         compile them. They are here to rebuild the binary, or build one for a platform the FMU \
         does not ship (it ships linux64 and win64; the FMI 3.0 archive also aarch64-linux).\n\n\
         Needs Rust {rust_version} or newer (`rust-version` in Cargo.toml; install with rustup) and \
         access to crates.io.\n\n\
         linux64, on Linux x86_64:\n\n\
         ```sh\ncargo build --release --lib -p {package}\n\
         cp target/release/lib{lib_name}.so ../binaries/linux64/{id}.so\n```\n\n\
         win64, cross-compiled on Linux (Debian: `apt-get install gcc-mingw-w64-x86-64`), or on \
         Windows with the same command (MSVC or GNU toolchain); the DLL needs Windows 10 or later:\n\n\
         ```sh\nrustup target add x86_64-pc-windows-gnu\n\
         cargo build --release --lib -p {package} --target x86_64-pc-windows-gnu\n\
         cp target/x86_64-pc-windows-gnu/release/{lib_name}.dll ../binaries/win64/{id}.dll\n```\n\n\
         aarch64-linux (FMI 3.0 archive), cross-compiled on Linux (Debian: `apt-get install \
         gcc-aarch64-linux-gnu`), or natively with the linux64 command:\n\n\
         ```sh\nrustup target add aarch64-unknown-linux-gnu\n\
         CARGO_TARGET_AARCH64_UNKNOWN_LINUX_GNU_LINKER=aarch64-linux-gnu-gcc \\\n  \
         cargo build --release --lib -p {package} --target aarch64-unknown-linux-gnu\n\
         cp target/aarch64-unknown-linux-gnu/release/lib{lib_name}.so ../binaries/aarch64-linux/{id}.so\n```\n\n\
         Other platforms: the same with their target (`rustup target list`), the library copied to \
         `binaries/<platform>/{id}.<so|dylib|dll>` (darwin64: `lib{lib_name}.dylib` → `{id}.dylib`).\n"
    );
    ("README.md".into(), text.into_bytes())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_inputs_give_the_same_bytes() {
        let dir = std::env::temp_dir().join(format!("fmi2-package-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let lib = dir.join("lib.so");
        std::fs::write(&lib, b"\x7fELF binary").unwrap();
        let dll = dir.join("m.dll");
        std::fs::write(&dll, b"MZ binary").unwrap();
        let write = |name: &str, sources: Vec<Entry>| {
            let path = dir.join(name);
            let files = FmuFiles {
                fmi_version: 2,
                model_identifier: "M",
                model_description: "<fmiModelDescription/>",
                binaries: vec![
                    (&PLATFORMS[0], lib.clone()),
                    (&PLATFORMS[1], dll.clone()),
                    (&PLATFORMS[2], lib.clone()),
                ],
                resources: vec![("a.txt".into(), b"a".to_vec())],
                documentation_html: "<html/>",
                extra: vec![("ls/manifest.xml".into(), b"<m/>".to_vec())],
                sources,
                terminals: None,
            };
            write_fmu(&path, &files).unwrap();
            std::fs::read(path).unwrap()
        };
        let src = |n: &str| (n.to_string(), n.as_bytes().to_vec());
        let a = write("a.fmu", vec![src("src/b.rs"), src("Cargo.toml")]);
        // Touch the library (a newer mtime) and list the sources in another order.
        std::fs::write(&lib, b"\x7fELF binary").unwrap();
        let b = write("b.fmu", vec![src("Cargo.toml"), src("src/b.rs")]);
        assert_eq!(a, b);
        let text = String::from_utf8_lossy(&a);
        assert!(text.find("sources/Cargo.toml").unwrap() < text.find("sources/src/b.rs").unwrap());
        let at = |name: &str| text.find(name).unwrap_or_else(|| panic!("{name}"));
        assert!(at("binaries/linux64/M.so") < at("binaries/win64/M.dll"));
        assert!(at("binaries/win64/M.dll") < at("documentation/index.html"));
        assert!(!text.contains("aarch64"), "FMI 2.0 names no aarch64 platform");
        assert!(at("extra/ls/manifest.xml") < at("resources/a.txt"));
        std::fs::remove_dir_all(dir).unwrap();
    }

    #[test]
    fn platforms_and_where_their_libraries_are_built() {
        let both = platforms("linux64, win64").unwrap();
        assert_eq!(
            both.iter().map(|p| p.name).collect::<Vec<_>>(),
            ["linux64", "win64"]
        );
        assert_eq!(platforms("win64").unwrap()[0].extension, "dll");
        assert!(platforms("linux64,win32").unwrap_err().contains("win32"));
        let all = platforms(ALL_PLATFORMS).unwrap();
        assert_eq!(all.len(), PLATFORMS.len());
        let arm = all[2];
        assert_eq!((arm.fmi2_name, arm.fmi3_name), (None, "aarch64-linux"));
        let e = built_libraries(Path::new("/nonexistent/target/release"), "m", &both).unwrap_err();
        assert!(
            e.starts_with("linux64: /nonexistent/target/release/libm.so not found"),
            "{e}"
        );
        let e = built_libraries(Path::new("/nonexistent/target/release"), "m", &both[1..]).unwrap_err();
        assert!(
            e.contains("/nonexistent/target/x86_64-pc-windows-gnu/release/m.dll not found"),
            "{e}"
        );
    }

    #[test]
    fn manifest_drops_sections_and_rewrites_paths() {
        let text = "[package]\nname = \"m\"\n\n[dependencies]\nfmi2 = { path = \"../fmi2\" }\n\n\
                    [dev-dependencies]\nproptest = \"1\"\n\n[[bench]]\nname = \"b\"\n";
        let m = manifest(text, &["[dev-dependencies]", "[[bench]]"], &[("../fmi2", "fmi2")]);
        assert_eq!(
            m,
            "[package]\nname = \"m\"\n\n[dependencies]\nfmi2 = { path = \"fmi2\" }\n\n"
        );
    }
}
