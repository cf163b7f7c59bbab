//! The committed modelDescription/MachineStructure.xml is the generated one.
#[test]
fn committed_model_description_is_current() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../modelDescription/MachineStructure.xml"
    );
    let committed = std::fs::read_to_string(path).expect("modelDescription/MachineStructure.xml");
    assert!(
        committed == machine_structure::model_description(),
        "modelDescription/MachineStructure.xml is stale; regenerate with `make fmu` and copy it from the FMU"
    );
}
