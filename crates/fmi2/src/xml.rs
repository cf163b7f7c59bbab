//! modelDescription.xml from the model's own description (quick-xml writer).

use crate::instance::LOG_CATEGORIES;
use crate::{Causality, ModelInfo, Type, Value, Variability, VariableInfo};
use quick_xml::events::{BytesDecl, BytesEnd, BytesStart, Event};
use quick_xml::Writer;

/// Shortest text that reads back as the same f64.
pub fn real(v: f64) -> String {
    let s = format!("{v:?}");
    s.strip_suffix(".0").map(str::to_string).unwrap_or(s)
}

fn value_text(v: &Value) -> String {
    match v {
        Value::Real(x) => real(*x),
        Value::Integer(n) => n.to_string(),
        Value::Boolean(b) => b.to_string(),
        Value::String(s) => s.clone(),
    }
}

/// The XML name of a causality.
pub fn causality(c: Causality) -> &'static str {
    match c {
        Causality::Parameter => "parameter",
        Causality::CalculatedParameter => "calculatedParameter",
        Causality::Input => "input",
        Causality::Output => "output",
        Causality::Local => "local",
        Causality::Independent => "independent",
    }
}

/// The XML name of a variability.
pub fn variability(v: Variability) -> &'static str {
    match v {
        Variability::Constant => "constant",
        Variability::Fixed => "fixed",
        Variability::Tunable => "tunable",
        Variability::Discrete => "discrete",
        Variability::Continuous => "continuous",
    }
}

/// The XML writer (in memory, indented by two spaces).
pub type W = Writer<Vec<u8>>;

/// `<name attrs>`.
pub fn start(w: &mut W, name: &str, attrs: &[(&str, String)]) {
    let mut e = BytesStart::new(name);
    for (k, v) in attrs {
        e.push_attribute((*k, v.as_str()));
    }
    w.write_event(Event::Start(e)).expect("writing to memory");
}

/// `<name attrs/>`.
pub fn empty(w: &mut W, name: &str, attrs: &[(&str, String)]) {
    let mut e = BytesStart::new(name);
    for (k, v) in attrs {
        e.push_attribute((*k, v.as_str()));
    }
    w.write_event(Event::Empty(e)).expect("writing to memory");
}

/// `</name>`.
pub fn end(w: &mut W, name: &str) {
    w.write_event(Event::End(BytesEnd::new(name)))
        .expect("writing to memory");
}

/// A new document: the XML declaration written.
pub fn document() -> W {
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))
        .expect("writing to memory");
    w
}

/// The document's text, with a final newline.
pub fn text(w: W) -> String {
    let mut text = String::from_utf8(w.into_inner()).expect("UTF-8 input");
    text.push('\n');
    text
}

/// The attributes of `fmiModelDescription` both FMI versions share, in their order: the version, the
/// model name, the version's identity attribute (`guid` / `instantiationToken`), the model's metadata,
/// the generating layer and the naming convention, then `extra`; empty values left out.
pub fn header<'a>(
    fmi_version: &str,
    info: &ModelInfo,
    identity: (&'a str, String),
    layer: &str,
    extra: &[(&'a str, String)],
) -> Vec<(&'a str, String)> {
    [
        ("fmiVersion", fmi_version.into()),
        ("modelName", info.model_name.clone()),
        identity,
        ("description", info.description.clone()),
        ("version", info.version.clone()),
        ("author", info.author.clone()),
        ("copyright", info.copyright.clone()),
        ("license", info.license.clone()),
        (
            "generationTool",
            format!("{layer} layer of cnc-motion {}", env!("CARGO_PKG_VERSION")),
        ),
        ("variableNamingConvention", "structured".into()),
    ]
    .into_iter()
    .chain(extra.iter().cloned())
    .filter(|(_, v)| !v.is_empty())
    .collect()
}

/// The XML text; `start_values[i]` is the start of variable i (None for calculated outputs).
pub fn model_description(info: &ModelInfo, start_values: &[Option<Value>]) -> String {
    let mut w = document();
    let header = header(
        "2.0",
        info,
        ("guid", info.guid.clone()),
        "fmi2",
        &[("numberOfEventIndicators", "0".into())],
    );
    start(&mut w, "fmiModelDescription", &header);
    let caps = &info.capabilities;
    let mut cs: Vec<(&str, String)> = vec![
        ("modelIdentifier", info.model_identifier.clone()),
        ("canHandleVariableCommunicationStepSize", "true".into()),
        (
            "canInterpolateInputs",
            (caps.max_input_derivative_order > 0).to_string(),
        ),
    ];
    if caps.max_output_derivative_order > 0 {
        cs.push((
            "maxOutputDerivativeOrder",
            caps.max_output_derivative_order.to_string(),
        ));
    }
    cs.extend([
        ("canBeInstantiatedOnlyOncePerProcess", "false".into()),
        ("canNotUseMemoryManagementFunctions", "true".into()),
        ("canGetAndSetFMUstate", "true".into()),
        ("canSerializeFMUstate", "true".into()),
        (
            "providesDirectionalDerivative",
            caps.provides_directional_derivative.to_string(),
        ),
    ]);
    empty(&mut w, "CoSimulation", &cs);
    unit_definitions(&mut w, info);
    type_definitions(&mut w, info);
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
    empty(
        &mut w,
        "DefaultExperiment",
        &[
            ("startTime", real(t0)),
            ("stopTime", real(t1)),
            ("tolerance", real(tol)),
            ("stepSize", real(step)),
        ],
    );
    start(&mut w, "ModelVariables", &[]);
    for (i, v) in info.variables.iter().enumerate() {
        variable(&mut w, info, v, start_values.get(i).cloned().flatten());
    }
    end(&mut w, "ModelVariables");
    model_structure(&mut w, info);
    end(&mut w, "fmiModelDescription");
    text(w)
}

/// UnitDefinitions (the same in FMI 2.0 and 3.0).
pub fn unit_definitions(w: &mut W, info: &ModelInfo) {
    if !info.units.is_empty() {
        start(w, "UnitDefinitions", &[]);
    }
    for u in &info.units {
        start(w, "Unit", &[("name", u.name.clone())]);
        let names = ["kg", "m", "s", "A", "K", "mol", "cd", "rad"];
        let attrs: Vec<(&str, String)> = names
            .iter()
            .zip(u.base)
            .filter(|(_, e)| *e != 0)
            .map(|(n, e)| (*n, e.to_string()))
            .collect();
        empty(w, "BaseUnit", &attrs);
        for d in &u.display {
            let mut a = vec![("name", d.name.clone()), ("factor", real(d.factor))];
            if d.offset != 0.0 {
                a.push(("offset", real(d.offset)));
            }
            empty(w, "DisplayUnit", &a);
        }
        end(w, "Unit");
    }
    if !info.units.is_empty() {
        end(w, "UnitDefinitions");
    }
}

fn type_definitions(w: &mut W, info: &ModelInfo) {
    if !info.enumerations.is_empty() {
        start(w, "TypeDefinitions", &[]);
        for e in &info.enumerations {
            start(w, "SimpleType", &[("name", e.name.clone())]);
            start(w, "Enumeration", &[]);
            for (k, (name, desc)) in e.items.iter().enumerate() {
                empty(
                    w,
                    "Item",
                    &[
                        ("name", name.clone()),
                        ("value", (k + 1).to_string()),
                        ("description", desc.clone()),
                    ],
                );
            }
            end(w, "Enumeration");
            end(w, "SimpleType");
        }
        end(w, "TypeDefinitions");
    }
}

/// Outputs and state derivatives with their declared dependencies (attribute left out: depends
/// on every known), and the initial unknowns: outputs, states and derivatives, all calculated
/// (dependencies not declared).
fn model_structure(w: &mut W, info: &ModelInfo) {
    start(w, "ModelStructure", &[]);
    let of = |keep: &dyn Fn(&VariableInfo) -> bool| -> Vec<usize> {
        (0..info.variables.len())
            .filter(|&i| keep(&info.variables[i]))
            .collect()
    };
    let outputs = of(&|v| v.causality == Causality::Output);
    let derivatives = of(&|v| v.derivative_of.is_some());
    let unknowns = |w: &mut W, list: &[usize], element: &str| {
        if list.is_empty() {
            return;
        }
        start(w, element, &[]);
        for &i in list {
            let mut a = vec![("index", (i + 1).to_string())];
            if let Some(deps) = &info.variables[i].dependencies {
                let list: Vec<String> = deps.iter().map(|d| (d + 1).to_string()).collect();
                a.push(("dependencies", list.join(" ")));
            }
            empty(w, "Unknown", &a);
        }
        end(w, element);
    };
    unknowns(w, &outputs, "Outputs");
    unknowns(w, &derivatives, "Derivatives");
    let states = info.states();
    let initial = of(&|v| v.causality == Causality::Output || v.derivative_of.is_some());
    let mut initial: Vec<usize> = initial.into_iter().chain(states).collect();
    initial.sort_unstable();
    initial.dedup();
    if !initial.is_empty() {
        start(w, "InitialUnknowns", &[]);
        for i in &initial {
            empty(w, "Unknown", &[("index", (i + 1).to_string())]);
        }
        end(w, "InitialUnknowns");
    }
    end(w, "ModelStructure");
}

fn variable(w: &mut W, info: &ModelInfo, v: &VariableInfo, start_value: Option<Value>) {
    let mut attrs = vec![
        ("name", v.name.clone()),
        ("valueReference", v.value_reference.to_string()),
        ("description", v.description.clone()),
        ("causality", causality(v.causality).into()),
        ("variability", variability(v.variability).into()),
    ];
    if matches!(v.causality, Causality::Output | Causality::Local) {
        attrs.push(("initial", "calculated".into()));
    } else if v.has_start() && matches!(v.causality, Causality::Parameter) {
        attrs.push(("initial", "exact".into()));
    }
    start(w, "ScalarVariable", &attrs);
    let mut t = Vec::new();
    let elem = match v.kind {
        Type::Real => "Real",
        Type::Integer => "Integer",
        Type::Boolean => "Boolean",
        Type::String => "String",
        Type::Enumeration(e) => {
            t.push(("declaredType", info.enumerations[e].name.clone()));
            "Enumeration"
        }
    };
    if let Some(u) = &v.unit {
        t.push(("unit", u.clone()));
    }
    if let Some(d) = &v.display_unit {
        t.push(("displayUnit", d.clone()));
    }
    if matches!(v.kind, Type::Real | Type::Integer) {
        let n = |x: f64| match v.kind {
            Type::Integer => (x as i64).to_string(),
            _ => real(x),
        };
        t.extend(v.min.map(|x| ("min", n(x))));
        t.extend(v.max.map(|x| ("max", n(x))));
    }
    if let (true, Some(s)) = (v.has_start(), start_value) {
        t.push(("start", value_text(&s)));
    }
    if let Some(of) = v.derivative_of {
        t.push(("derivative", (of + 1).to_string()));
    }
    empty(w, elem, &t);
    end(w, "ScalarVariable");
}
