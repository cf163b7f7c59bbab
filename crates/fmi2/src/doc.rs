//! documentation/index.html of an FMU: the model's own introduction and the table of its
//! variables, generated from the same description as the XML (text escaped).

use crate::xml::real;
use crate::{ModelInfo, Value};
use std::fmt::Write;

/// Text as HTML (element content and attribute values).
pub fn escape(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

fn value_html(v: &Option<Value>) -> String {
    match v {
        Some(Value::Real(x)) => real(*x),
        Some(Value::Integer(n)) => n.to_string(),
        Some(Value::Boolean(b)) => b.to_string(),
        Some(Value::String(s)) if s.len() > 40 => format!("{}…", escape(&s[..s.floor_char_boundary(40)])),
        Some(Value::String(s)) => escape(s),
        None => String::new(),
    }
}

/// The page: `intro_html` (trusted HTML written by the model) then every variable.
pub fn html(info: &ModelInfo, intro_html: &str, starts: &[Option<Value>]) -> String {
    let mut h = String::new();
    let _ = writeln!(
        h,
        "<!DOCTYPE html><html><head><meta charset=\"utf-8\"><title>{0}</title></head><body>\
         <h1>{0} {1}</h1>{2}<p>{3}</p><h2>Variables</h2>\
         <table border=\"1\" cellspacing=\"0\" cellpadding=\"3\"><tr><th>name</th><th>vr</th>\
         <th>causality</th><th>variability</th><th>type</th><th>unit</th><th>display</th>\
         <th>min</th><th>max</th><th>start</th><th>description</th></tr>",
        escape(&info.model_name),
        escape(&info.version),
        intro_html,
        escape(&info.copyright),
    );
    for (v, start) in info.variables.iter().zip(starts) {
        let num = |x: Option<f64>| x.map(real).unwrap_or_default();
        let _ = writeln!(
            h,
            "<tr><td><code>{}</code></td><td>{}</td><td>{:?}</td><td>{:?}</td><td>{:?}</td>\
             <td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            escape(&v.name),
            v.value_reference,
            v.causality,
            v.variability,
            v.kind,
            escape(v.unit.as_deref().unwrap_or("")),
            escape(v.display_unit.as_deref().unwrap_or("")),
            num(v.min),
            num(v.max),
            value_html(start),
            escape(&v.description)
        );
    }
    h.push_str("</table></body></html>\n");
    h
}
