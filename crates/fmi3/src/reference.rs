//! The reference result of the FMI 3 archive (`org.fmi-standard.fmi-ls-ref`, as the Reference-FMUs
//! ship theirs): the default experiment's outputs under their FMI 3 names, an array's values in
//! one cell separated by spaces (`0.001 0.002 0`), from the same run as the FMI 2 result.

use crate::View;
use fmi2::package::Entry;
use fmi2::reference::{cell, manifest, run_default_experiment, DIR};
use fmi2::xml::real;
use fmi2::{Causality, Model};
use std::path::Path;

/// The default experiment's outputs as CSV (`time` then the FMI 3 outputs in value-reference
/// order).
pub fn outputs_csv<M: Model>(view: &View, resources: Option<&Path>, every: usize) -> Result<String, String> {
    let outputs: Vec<&crate::Var> = view
        .vars
        .iter()
        .filter(|v| v.causality == Causality::Output)
        .collect();
    let mut csv = String::from("time");
    for v in &outputs {
        csv.push(',');
        csv.push_str(&v.name);
    }
    csv.push('\n');
    run_default_experiment::<M>(resources, every, |model, t| {
        csv.push_str(&real(t));
        for v in &outputs {
            let cells: Vec<String> = v.elements.iter().map(|&i| cell(&model.get(i))).collect();
            csv.push(',');
            csv.push_str(&cells.join(" "));
        }
        csv.push('\n');
    })?;
    Ok(csv)
}

/// The files under `extra/`: the manifest and `<model identifier>_out.csv`.
pub fn files<M: Model>(resources: Option<&Path>, every: usize) -> Result<Vec<Entry>, String> {
    let info = M::info();
    let csv_name = format!("{}_out.csv", info.model_identifier);
    let (_, _, _, h) = info.default_experiment;
    Ok(vec![
        (
            format!("{DIR}/fmi-ls-manifest.xml"),
            manifest(&csv_name, h, every).into_bytes(),
        ),
        (
            format!("{DIR}/{csv_name}"),
            outputs_csv::<M>(&View::of::<M>(), resources, every)?.into_bytes(),
        ),
    ])
}
