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

fn causality(c: Causality) -> &'static str {
    match c {
        Causality::Parameter => "parameter",
        Causality::CalculatedParameter => "calculatedParameter",
        Causality::Input => "input",
        Causality::Output => "output",
        Causality::Local => "local",
        Causality::Independent => "independent",
    }
}

fn variability(v: Variability) -> &'static str {
    match v {
        Variability::Constant => "constant",
        Variability::Fixed => "fixed",
        Variability::Tunable => "tunable",
        Variability::Discrete => "discrete",
        Variability::Continuous => "continuous",
    }
}

type W = Writer<Vec<u8>>;

fn start(w: &mut W, name: &str, attrs: &[(&str, String)]) {
    let mut e = BytesStart::new(name);
    for (k, v) in attrs {
        e.push_attribute((*k, v.as_str()));
    }
    w.write_event(Event::Start(e)).expect("writing to memory");
}

fn empty(w: &mut W, name: &str, attrs: &[(&str, String)]) {
    let mut e = BytesStart::new(name);
    for (k, v) in attrs {
        e.push_attribute((*k, v.as_str()));
    }
    w.write_event(Event::Empty(e)).expect("writing to memory");
}

fn end(w: &mut W, name: &str) {
    w.write_event(Event::End(BytesEnd::new(name)))
        .expect("writing to memory");
}

/// The XML text; `start_values[i]` is the start of variable i (None for calculated outputs).
pub fn model_description(info: &ModelInfo, start_values: &[Option<Value>]) -> String {
    let mut w = Writer::new_with_indent(Vec::new(), b' ', 2);
    w.write_event(Event::Decl(BytesDecl::new("1.0", Some("UTF-8"), None)))
        .expect("writing to memory");
    let header: Vec<(&str, String)> = [
        ("fmiVersion", "2.0".into()),
        ("modelName", info.model_name.clone()),
        ("guid", info.guid.clone()),
        ("description", info.description.clone()),
        ("version", info.version.clone()),
        ("author", info.author.clone()),
        ("copyright", info.copyright.clone()),
        ("license", info.license.clone()),
        (
            "generationTool",
            format!("fmi2 layer of cnc-motion {}", env!("CARGO_PKG_VERSION")),
        ),
        ("variableNamingConvention", "structured".into()),
        ("numberOfEventIndicators", "0".into()),
    ]
    .into_iter()
    .filter(|(_, v)| !v.is_empty())
    .collect();
    start(&mut w, "fmiModelDescription", &header);
    empty(
        &mut w,
        "CoSimulation",
        &[
            ("modelIdentifier", info.model_identifier.clone()),
            ("canHandleVariableCommunicationStepSize", "true".into()),
            ("canInterpolateInputs", "false".into()),
            ("canBeInstantiatedOnlyOncePerProcess", "false".into()),
            ("canNotUseMemoryManagementFunctions", "true".into()),
            ("canGetAndSetFMUstate", "true".into()),
            ("canSerializeFMUstate", "true".into()),
            ("providesDirectionalDerivative", "false".into()),
        ],
    );
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
    let mut text = String::from_utf8(w.into_inner()).expect("UTF-8 input");
    text.push('\n');
    text
}

fn unit_definitions(w: &mut W, info: &ModelInfo) {
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

/// Outputs with their declared dependencies (attribute left out: depends on every input), and
/// the initial unknowns (dependencies not declared).
fn model_structure(w: &mut W, info: &ModelInfo) {
    start(w, "ModelStructure", &[]);
    let outputs: Vec<usize> = (0..info.variables.len())
        .filter(|&i| info.variables[i].causality == Causality::Output)
        .collect();
    if !outputs.is_empty() {
        start(w, "Outputs", &[]);
        for &i in &outputs {
            let mut a = vec![("index", (i + 1).to_string())];
            if let Some(deps) = &info.variables[i].dependencies {
                let list: Vec<String> = deps.iter().map(|d| (d + 1).to_string()).collect();
                a.push(("dependencies", list.join(" ")));
            }
            empty(w, "Unknown", &a);
        }
        end(w, "Outputs");
        start(w, "InitialUnknowns", &[]);
        for i in &outputs {
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
    if v.causality == Causality::Output {
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
    empty(w, elem, &t);
    end(w, "ScalarVariable");
}
