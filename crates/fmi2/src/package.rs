//! Writing a .fmu: modelDescription.xml, binaries/linux64/<id>.so, resources/, documentation/.

use std::io::Write;
use std::path::Path;
use zip::write::SimpleFileOptions;

/// Files of an FMU archive, by path inside the archive.
pub struct FmuFiles<'a> {
    pub model_identifier: &'a str,
    pub model_description: &'a str,
    /// The built shared library (cdylib) of the model.
    pub shared_library: &'a Path,
    pub resources: Vec<(String, Vec<u8>)>,
    pub documentation_html: &'a str,
}

pub fn write_fmu(path: &Path, files: &FmuFiles) -> Result<(), String> {
    let lib = std::fs::read(files.shared_library)
        .map_err(|e| format!("{}: {e}", files.shared_library.display()))?;
    if let Some(dir) = path.parent() {
        std::fs::create_dir_all(dir).map_err(|e| format!("{}: {e}", dir.display()))?;
    }
    let file = std::fs::File::create(path).map_err(|e| format!("{}: {e}", path.display()))?;
    let mut zip = zip::ZipWriter::new(file);
    let opts = SimpleFileOptions::default().compression_method(zip::CompressionMethod::Deflated);
    let mut add = |name: &str, bytes: &[u8]| -> Result<(), String> {
        zip.start_file(name, opts).map_err(|e| format!("{name}: {e}"))?;
        zip.write_all(bytes).map_err(|e| format!("{name}: {e}"))
    };
    add("modelDescription.xml", files.model_description.as_bytes())?;
    add(&format!("binaries/linux64/{}.so", files.model_identifier), &lib)?;
    for (name, bytes) in &files.resources {
        add(&format!("resources/{name}"), bytes)?;
    }
    add("documentation/index.html", files.documentation_html.as_bytes())?;
    zip.finish().map_err(|e| format!("{}: {e}", path.display()))?;
    Ok(())
}
