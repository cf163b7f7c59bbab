//! The reference result an FMU ships, as the Modelica Reference-FMUs ship theirs (FMI layered
//! standard for reference results, `org.fmi-standard.fmi-ls-ref`): under
//! `extra/org.fmi-standard.fmi-ls-ref/`, a manifest naming the file and the outputs of the default
//! experiment as CSV. Computed by the model itself when the FMU is packaged, so it is always the
//! result of the binary's own code; a test checks it against a fresh simulation through an importer.

use crate::package::Entry;
use crate::xml::real;
use crate::{Causality, Model, Value};
use std::fmt::Write;
use std::path::Path;

/// The layered standard's folder under `extra/`.
pub const DIR: &str = "org.fmi-standard.fmi-ls-ref";

/// Run the default experiment of `M` (start, stop, step size of its DefaultExperiment) from the
/// start values with `resources` as the resources folder, calling `row(model, time)` after
/// initialization and after every `every`-th step.
pub fn run_default_experiment<M: Model>(
    resources: Option<&Path>,
    every: usize,
    mut row: impl FnMut(&M, f64),
) -> Result<(), String> {
    let (start, stop, _, h) = M::info().default_experiment;
    let mut model = M::new(resources);
    model.exit_initialization()?;
    let steps = ((stop - start) / h).round() as usize;
    row(&model, start);
    for k in 1..=steps {
        model.do_step(h)?;
        if k % every.max(1) == 0 {
            row(&model, start + k as f64 * h);
        }
    }
    Ok(())
}

/// A value as a CSV cell (Reals in their shortest round-trip form, Booleans 0/1).
pub fn cell(v: &Value) -> String {
    match v {
        Value::Real(x) => real(*x),
        Value::Integer(n) => n.to_string(),
        Value::Boolean(b) => u8::from(*b).to_string(),
        Value::String(s) => s.clone(),
    }
}

/// The default experiment's outputs as CSV (`time` then the outputs in value-reference order).
pub fn outputs_csv<M: Model>(resources: Option<&Path>, every: usize) -> Result<String, String> {
    let info = M::info();
    let outputs: Vec<usize> = (0..info.variables.len())
        .filter(|&i| info.variables[i].causality == Causality::Output)
        .collect();
    let mut csv = String::from("time");
    for &i in &outputs {
        csv.push(',');
        csv.push_str(&info.variables[i].name);
    }
    csv.push('\n');
    run_default_experiment::<M>(resources, every, |model, t| {
        csv.push_str(&real(t));
        for &i in &outputs {
            let _ = write!(csv, ",{}", cell(&model.get(i)));
        }
        csv.push('\n');
    })?;
    Ok(csv)
}

/// The manifest of the layered standard naming `csv_name`, the result of the default experiment
/// at step `h`, a row every `every` steps.
pub fn manifest(csv_name: &str, h: f64, every: usize) -> String {
    let rows = match every {
        0 | 1 => "every step".to_string(),
        n => format!("every {n} steps"),
    };
    let description = format!(
        "Outputs of the default experiment (communication step {} s; a row {rows})",
        real(h)
    );
    format!(
        "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n\
         <fmiReferences\n    xmlns:fmi-ls=\"http://fmi-standard.org/fmi-ls-manifest\"\n    \
         fmi-ls:fmi-ls-name=\"{DIR}\"\n    fmi-ls:fmi-ls-version=\"1.0.0-alpha.1\">\n  \
         <Related type=\"text/csv\" source=\"{csv_name}\" role=\"result\" description=\"{description}\"/>\n\
         </fmiReferences>\n"
    )
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
            outputs_csv::<M>(resources, every)?.into_bytes(),
        ),
    ])
}
