//! The committed modelDescription/CncMotion.xml is the one the code generates: a change to the
//! variable table must be committed with its XML (regenerate: `UPDATE_MODEL_DESCRIPTION=1 cargo test --workspace --test model_description`).

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]
#[test]
fn committed_model_description_is_current() {
    let generated = cnc_motion::fmu::model_description();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/modelDescription/CncMotion.xml");
    if std::env::var_os("UPDATE_MODEL_DESCRIPTION").is_some() {
        std::fs::write(path, &generated).expect("writing modelDescription/CncMotion.xml");
    }
    let committed = std::fs::read_to_string(path).expect("modelDescription/CncMotion.xml");
    if committed != generated {
        let line = committed
            .lines()
            .zip(generated.lines())
            .position(|(a, b)| a != b)
            .unwrap_or(0)
            + 1;
        panic!(
            "modelDescription/CncMotion.xml differs from the generated XML from line {line}; \
             regenerate: UPDATE_MODEL_DESCRIPTION=1 cargo test --test model_description"
        );
    }
}
