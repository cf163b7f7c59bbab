//! modelDescription.xml (FMI 3.0) of a model's [`View`], and terminalsAndIcons.xml of its
//! terminals: the same units, log categories and default experiment as the FMI 2 description
//! (fmi2's writer helpers), the variables as FMI 3 typed elements with `<Dimension>` for arrays.

use crate::view::{Kind, Var, View};
use fmi2::instance::LOG_CATEGORIES;
use fmi2::xml::{
    causality, document, empty, end, header, real, start, text, unit_definitions, variability, W,
};
use fmi2::{Causality, ModelInfo, Value};

fn value_text(v: &Value) -> String {
    match v {
        Value::Real(x) => real(*x),
        Value::Integer(n) => n.to_string(),
        Value::Boolean(b) => b.to_string(),
        Value::String(s) => s.clone(),
    }
}

/// The XML text; `start_values[i]` is the start of table variable i (None for calculated ones).
pub fn model_description(info: &ModelInfo, view: &View, start_values: &[Option<Value>]) -> String {
    let mut w = document();
    let header = header(
        "3.0",
        info,
        ("instantiationToken", view.token.clone()),
        "fmi3",
        &[],
    );
    start(&mut w, "fmiModelDescription", &header);
    co_simulation(&mut w, info);
    if !info.clocks.is_empty() {
        scheduled_execution(&mut w, info);
    }
    unit_definitions(&mut w, info);
    if !info.enumerations.is_empty() {
        start(&mut w, "TypeDefinitions", &[]);
        for e in &info.enumerations {
            start(&mut w, "EnumerationType", &[("name", e.name.clone())]);
            for (k, (name, desc)) in e.items.iter().enumerate() {
                let item = [
                    ("name", name.clone()),
                    ("value", (k + 1).to_string()),
                    ("description", desc.clone()),
                ];
                empty(&mut w, "Item", &item);
            }
            end(&mut w, "EnumerationType");
        }
        end(&mut w, "TypeDefinitions");
    }
    start(&mut w, "LogCategories", &[]);
    for (name, desc) in LOG_CATEGORIES {
        empty(
            &mut w,
            "Category",
            &[("name", name.into()), ("description", desc.into())],
        );
    }
    end(&mut w, "LogCategories");
    let (t0, t1, tol, step) = info.default_experiment;
    let experiment = [
        ("startTime", real(t0)),
        ("stopTime", real(t1)),
        ("tolerance", real(tol)),
        ("stepSize", real(step)),
    ];
    empty(&mut w, "DefaultExperiment", &experiment);
    start(&mut w, "ModelVariables", &[]);
    for v in &view.vars {
        let starts: Vec<Value> = v
            .elements
            .iter()
            .filter_map(|&i| start_values[i].clone())
            .collect();
        variable(&mut w, info, v, &starts);
    }
    end(&mut w, "ModelVariables");
    model_structure(&mut w, view);
    end(&mut w, "fmiModelDescription");
    text(w)
}

fn co_simulation(w: &mut W, info: &ModelInfo) {
    let caps = &info.capabilities;
    let derivatives = caps.provides_directional_derivative.to_string();
    let mut cs: Vec<(&str, String)> = vec![
        ("modelIdentifier", info.model_identifier.clone()),
        ("canGetAndSetFMUState", "true".into()),
        ("canSerializeFMUState", "true".into()),
        ("providesDirectionalDerivatives", derivatives.clone()),
        ("providesAdjointDerivatives", derivatives),
        ("canHandleVariableCommunicationStepSize", "true".into()),
    ];
    if let Some(h) = caps.fixed_internal_step {
        cs.push(("fixedInternalStepSize", real(h)));
    }
    if caps.max_output_derivative_order > 0 {
        cs.push((
            "maxOutputDerivativeOrder",
            caps.max_output_derivative_order.to_string(),
        ));
    }
    if caps.might_return_early {
        cs.push(("mightReturnEarlyFromDoStep", "true".into()));
    }
    // The standard: an FMU with clocks has Event Mode (there the importer activates them).
    cs.push(("hasEventMode", (!info.clocks.is_empty()).to_string()));
    empty(w, "CoSimulation", &cs);
}

/// Scheduled Execution: the clocks' model partitions activated by the importer's scheduler.
fn scheduled_execution(w: &mut W, info: &ModelInfo) {
    let derivatives = info.capabilities.provides_directional_derivative.to_string();
    let se = [
        ("modelIdentifier", info.model_identifier.clone()),
        ("canGetAndSetFMUState", "true".into()),
        ("canSerializeFMUState", "true".into()),
        ("providesDirectionalDerivatives", derivatives.clone()),
        ("providesAdjointDerivatives", derivatives),
    ];
    empty(w, "ScheduledExecution", &se);
}

fn variable(w: &mut W, info: &ModelInfo, v: &Var, starts: &[Value]) {
    if let Kind::Clock(k) = v.kind {
        return clock(w, info, v, k);
    }
    let mut a = vec![
        ("name", v.name.clone()),
        ("valueReference", v.value_reference.to_string()),
        ("description", v.description.clone()),
        ("causality", causality(v.causality).into()),
        ("variability", variability(v.variability).into()),
    ];
    match v.causality {
        Causality::Output | Causality::Local => a.push(("initial", "calculated".into())),
        Causality::Parameter => a.push(("initial", "exact".into())),
        _ => {}
    }
    if let Kind::Enumeration(e) = v.kind {
        a.push(("declaredType", info.enumerations[e].name.clone()));
    }
    if let Some(u) = &v.unit {
        a.push(("unit", u.clone()));
    }
    if let Some(d) = &v.display_unit {
        a.push(("displayUnit", d.clone()));
    }
    if matches!(v.kind, Kind::Float64 | Kind::Int32 | Kind::UInt64) {
        let n = |x: f64| match v.kind {
            Kind::Float64 => real(x),
            _ => (x as i64).to_string(),
        };
        a.extend(v.min.map(|x| ("min", n(x))));
        a.extend(v.max.map(|x| ("max", n(x))));
    }
    let strings = v.kind == Kind::String;
    if !starts.is_empty() && !strings {
        let list: Vec<String> = starts.iter().map(value_text).collect();
        a.push(("start", list.join(" ")));
    }
    if let Some(d) = v.derivative_of {
        a.push(("derivative", d.to_string()));
    }
    let name = v.kind.name();
    if !v.array && (!strings || starts.is_empty()) {
        empty(w, name, &a);
        return;
    }
    start(w, name, &a);
    if v.array {
        empty(w, "Dimension", &[("start", v.elements.len().to_string())]);
    }
    if strings {
        for s in starts {
            empty(w, "Start", &[("value", value_text(s))]);
        }
    }
    end(w, name);
}

/// An input clock, periodic with the constant interval the model declares.
fn clock(w: &mut W, info: &ModelInfo, v: &Var, k: usize) {
    let c = &info.clocks[k];
    let a = [
        ("name", v.name.clone()),
        ("valueReference", v.value_reference.to_string()),
        ("description", v.description.clone()),
        ("causality", causality(v.causality).into()),
        ("variability", variability(v.variability).into()),
        ("intervalVariability", "constant".into()),
        ("intervalDecimal", real(c.interval)),
        ("priority", c.priority.to_string()),
    ];
    empty(w, "Clock", &a);
}

/// Outputs and state derivatives with their dependencies (value references), and the initial
/// unknowns: outputs, states and derivatives (all calculated).
fn model_structure(w: &mut W, view: &View) {
    start(w, "ModelStructure", &[]);
    let unknown = |w: &mut W, element: &str, v: &Var| {
        let mut a = vec![("valueReference", v.value_reference.to_string())];
        if let Some(deps) = &v.dependencies {
            let list: Vec<String> = deps
                .iter()
                .map(|&d| view.vars[d].value_reference.to_string())
                .collect();
            a.push(("dependencies", list.join(" ")));
        }
        empty(w, element, &a);
    };
    for v in view.vars.iter().filter(|v| v.causality == Causality::Output) {
        unknown(w, "Output", v);
    }
    for v in view.vars.iter().filter(|v| v.derivative_of.is_some()) {
        unknown(w, "ContinuousStateDerivative", v);
    }
    let state = |k: usize| view.vars.iter().any(|u| u.derivative_of == Some(k));
    for (k, v) in view.vars.iter().enumerate() {
        if v.causality == Causality::Output || v.derivative_of.is_some() || state(k) {
            empty(
                w,
                "InitialUnknown",
                &[("valueReference", v.value_reference.to_string())],
            );
        }
    }
    end(w, "ModelStructure");
}

/// terminalsAndIcons/terminalsAndIcons.xml of the model's terminals (None without any).
pub fn terminals_and_icons(info: &ModelInfo) -> Option<String> {
    if info.terminals.is_empty() {
        return None;
    }
    let mut w = document();
    start(&mut w, "fmiTerminalsAndIcons", &[("fmiVersion", "3.0".into())]);
    start(&mut w, "Terminals", &[]);
    for t in &info.terminals {
        let a = [
            ("name", t.name.clone()),
            ("matchingRule", "plug".into()),
            ("terminalKind", t.kind.clone()),
            ("description", t.description.clone()),
        ];
        start(&mut w, "Terminal", &a);
        for (variable, member) in &t.members {
            let m = [
                ("variableName", variable.clone()),
                ("memberName", member.clone()),
                ("variableKind", "signal".into()),
            ];
            empty(&mut w, "TerminalMemberVariable", &m);
        }
        end(&mut w, "Terminal");
    }
    end(&mut w, "Terminals");
    end(&mut w, "fmiTerminalsAndIcons");
    Some(text(w))
}
