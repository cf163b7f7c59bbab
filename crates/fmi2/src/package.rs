//! Writing a .fmu: modelDescription.xml, binaries/linux64/<id>.so, resources/, documentation/,
//! sources/. The archive is reproducible: entries in a fixed order, each with the same fixed
//! timestamp (1980-01-01, the zip epoch) and permissions, so the same inputs give the same bytes.

use std::io::Write;
use std::path::Path;
use zip::write::SimpleFileOptions;

/// A file inside the archive: path and bytes.
pub type Entry = (String, Vec<u8>);

/// Files of an FMU archive, by path inside the archive.
pub struct FmuFiles<'a> {
    pub model_identifier: &'a str,
    pub model_description: &'a str,
    /// The built shared library (cdylib) of the model.
    pub shared_library: &'a Path,
    pub resources: Vec<Entry>,
    pub documentation_html: &'a str,
    /// The sources the binary is built from (paths relative to `sources/`).
    pub sources: Vec<Entry>,
}

pub fn write_fmu(path: &Path, files: &FmuFiles) -> Result<(), String> {
    let lib = std::fs::read(files.shared_library)
        .map_err(|e| format!("{}: {e}", files.shared_library.display()))?;
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let opts = SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .last_modified_time(zip::DateTime::default())
        .unix_permissions(0o644);
    let mut entries: Vec<(String, &[u8])> = vec![
        ("modelDescription.xml".into(), files.model_description.as_bytes()),
        (format!("binaries/linux64/{}.so", files.model_identifier), &lib),
        (
            "documentation/index.html".into(),
            files.documentation_html.as_bytes(),
        ),
    ];
    entries.extend(
        files
            .resources
            .iter()
            .map(|(n, b)| (format!("resources/{n}"), b.as_slice())),
    );
    entries.extend(
        files
            .sources
            .iter()
            .map(|(n, b)| (format!("sources/{n}"), b.as_slice())),
    );
    entries[3..].sort_by(|a, b| a.0.cmp(&b.0));
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

/// sources/README.md: how to build the binary for another platform.
pub fn sources_readme(model_identifier: &str, lib_name: &str) -> Entry {
    let text = format!(
        "# Sources of {model_identifier}\n\nRust sources of the FMU's binary (FMI 2.0 allows shipping \
         the sources; they are Rust, not C, so modelDescription.xml lists no SourceFiles). Build with \
         a Rust toolchain (1.80 or newer):\n\n```sh\ncargo build --release --lib\n```\n\nand copy \
         `target/release/lib{lib_name}.so` (`{lib_name}.dll` on Windows, `lib{lib_name}.dylib` on \
         macOS) into the FMU as `binaries/<platform>/{model_identifier}.<so|dll|dylib>` \
         (platforms linux64, win64, darwin64).\n"
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
        let write = |name: &str, sources: Vec<Entry>| {
            let path = dir.join(name);
            let files = FmuFiles {
                model_identifier: "M",
                model_description: "<fmiModelDescription/>",
                shared_library: &lib,
                resources: vec![("a.txt".into(), b"a".to_vec())],
                documentation_html: "<html/>",
                sources,
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
        std::fs::remove_dir_all(dir).unwrap();
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
