//! The committed modelDescription/MachineStructure.xml is the generated one.

// Targets other than the library share its dependency list; the lint guards the library.
#![allow(unused_crate_dependencies)]
#[test]
fn committed_model_description_is_current() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../modelDescription/MachineStructure.xml"
    );
    if std::env::var_os("UPDATE_MODEL_DESCRIPTION").is_some() {
        std::fs::write(path, machine_structure::model_description()).expect("writing the XML");
    }
    let committed = std::fs::read_to_string(path).expect("modelDescription/MachineStructure.xml");
    assert!(
        committed == machine_structure::model_description(),
        "modelDescription/MachineStructure.xml is stale; regenerate: UPDATE_MODEL_DESCRIPTION=1 cargo test -p machine-structure --test model_description"
    );
}
