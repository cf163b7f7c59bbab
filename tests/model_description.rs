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

/// Issue 11: every Real and Integer parameter declares the range that `Machine::check` enforces,
/// and its start value lies inside it; a value outside is refused by the machine-file check too.
#[test]
fn parameters_declare_their_ranges() {
    let xml = cnc_motion::fmu::model_description();
    let attr = |v: &str, name: &str| -> Option<f64> {
        let key = format!(" {name}=\"");
        let at = v.find(&key)? + key.len();
        v[at..].split('"').next()?.parse().ok()
    };
    let mut checked = 0;
    for var in xml.split("<ScalarVariable").skip(1) {
        let var = var.split("</ScalarVariable>").next().unwrap();
        let numeric = var.contains("<Real") || var.contains("<Integer");
        if !var.contains("causality=\"parameter\"") || !numeric {
            continue;
        }
        let name = var.split("name=\"").nth(1).unwrap().split('"').next().unwrap();
        let (min, max) = (attr(var, "min"), attr(var, "max"));
        assert!(min.is_some() && max.is_some(), "{name}: no min/max");
        if let Some(start) = attr(var, "start") {
            assert!(
                min.unwrap() <= start && start <= max.unwrap(),
                "{name}: start {start}"
            );
        }
        checked += 1;
    }
    assert!(checked > 80, "{checked} parameters");
}
