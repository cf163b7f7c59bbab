//! The SI units a model may use, with their base-unit exponents and display units: a model names
//! a unit on a variable, the layer declares it (UnitDefinitions) and picks its display unit.

use crate::{DisplayUnit, UnitDefinition};

/// (name, exponents of kg, m, s, A, K, mol, cd, rad, display units (name, factor)); the first
/// display unit is the variables' default `displayUnit`.
type Known = (&'static str, [i32; 8], &'static [(&'static str, f64)]);

const RPM: f64 = 60.0 / (2.0 * std::f64::consts::PI);

const KNOWN: &[Known] = &[
    ("s", [0, 0, 1, 0, 0, 0, 0, 0], &[("ms", 1e3)]),
    ("m", [0, 1, 0, 0, 0, 0, 0, 0], &[("mm", 1e3)]),
    (
        "m/s",
        [0, 1, -1, 0, 0, 0, 0, 0],
        &[("mm/min", 6e4), ("mm/s", 1e3)],
    ),
    ("m/s2", [0, 1, -2, 0, 0, 0, 0, 0], &[("mm/s2", 1e3)]),
    ("m/s3", [0, 1, -3, 0, 0, 0, 0, 0], &[("mm/s3", 1e3)]),
    ("m/s4", [0, 1, -4, 0, 0, 0, 0, 0], &[("mm/s4", 1e3)]),
    ("N", [1, 1, -2, 0, 0, 0, 0, 0], &[]),
    ("N.m", [1, 2, -2, 0, 0, 0, 0, 0], &[]),
    ("1", [0, 0, 0, 0, 0, 0, 0, 0], &[]),
    ("kg", [1, 0, 0, 0, 0, 0, 0, 0], &[]),
    ("kg.m2", [1, 2, 0, 0, 0, 0, 0, 0], &[]),
    ("1/s", [0, 0, -1, 0, 0, 0, 0, 0], &[]),
    ("N/m", [1, 0, -2, 0, 0, 0, 0, 0], &[("N/um", 1e-6)]),
    ("N.s/m", [1, 0, -1, 0, 0, 0, 0, 0], &[]),
    ("Hz", [0, 0, -1, 0, 0, 0, 0, 0], &[]),
    ("rad/s", [0, 0, -1, 0, 0, 0, 0, 1], &[("rpm", RPM)]),
    ("N.m.s/rad", [1, 2, -1, 0, 0, 0, 0, -1], &[]),
];

fn known(name: &str) -> Option<&'static Known> {
    KNOWN.iter().find(|k| k.0 == name)
}

/// The default display unit of a unit (its first), if it has one.
pub fn default_display(unit: &str) -> Option<&'static str> {
    known(unit).and_then(|k| k.2.first()).map(|d| d.0)
}

/// UnitDefinitions for the units named in `used`, in the catalogue's order.
///
/// # Panics
/// On a unit the catalogue does not know (a programming error in a model table; the tests of
/// every model build its description).
pub fn definitions<'a>(used: impl IntoIterator<Item = &'a str>) -> Vec<UnitDefinition> {
    let used: Vec<&str> = used.into_iter().collect();
    if let Some(u) = used.iter().find(|u| known(u).is_none()) {
        panic!("unit '{u}' is not in fmi2::units");
    }
    KNOWN
        .iter()
        .filter(|k| used.contains(&k.0))
        .map(|(name, base, display)| UnitDefinition {
            name: name.to_string(),
            base: *base,
            display: display
                .iter()
                .map(|(n, f)| DisplayUnit {
                    name: n.to_string(),
                    factor: *f,
                    offset: 0.0,
                })
                .collect(),
        })
        .collect()
}
