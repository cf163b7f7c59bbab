//! The committed modelDescription/CncMotion.xml is the one the code generates: a change to the
//! variable table must be committed with its XML (regenerate with `cnc-motion package` and copy).
#[test]
fn committed_model_description_is_current() {
    let generated = cnc_motion::fmu::model_description();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/modelDescription/CncMotion.xml");
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
             regenerate: cargo run --release -- package && unzip -p target/fmu/CncMotion.fmu \
             modelDescription.xml > modelDescription/CncMotion.xml"
        );
    }
}
