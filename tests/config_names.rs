//! One list of names: strum's names of the profile and corner modes (CLI, FMU Enumeration items)
//! are the names the machine file's reader (serde) accepts, and the documented ones.
#![allow(unused_crate_dependencies)]

use cnc_motion::config::{CornerMode, Machine};
use cnc_motion::feed::ProfileKind;

#[test]
fn profile_names_are_the_machine_file_names() {
    let names: Vec<_> = ProfileKind::ALL.iter().map(|k| k.name()).collect();
    assert_eq!(names, ["scurve7", "quintic", "jerk15", "mixed57", "trapezoid"]); // README table
    for kind in ProfileKind::ALL {
        let m = Machine::from_toml(&format!("profile = \"{}\"\n", kind.name()), "m.toml").unwrap();
        assert_eq!(m.profile, kind);
        assert_eq!(ProfileKind::from_name(kind.name()), Some(kind));
    }
    assert_eq!(ProfileKind::from_name("Scurve7"), None);
    let err = Machine::from_toml("profile = \"scurve5\"\n", "m.toml")
        .unwrap_err()
        .to_string();
    assert!(
        err.starts_with("m.toml:1:11: ") && err.contains("scurve7"),
        "{err}"
    );
}

#[test]
fn corner_names_are_the_machine_file_names() {
    let names: Vec<_> = CornerMode::ALL.iter().map(|c| c.name()).collect();
    assert_eq!(
        names,
        [
            "exact_stop",
            "acceleration_period",
            "circular",
            "polynomial",
            "smooth"
        ]
    );
    for corner in CornerMode::ALL {
        let m = Machine::from_toml(&format!("corner = \"{}\"\n", corner.name()), "m.toml").unwrap();
        assert_eq!(m.corner, corner);
    }
}
