//! documentation/index.html of an FMU: the model's own introduction and the table of its
//! variables, generated from the same description as the XML (text escaped).

use crate::xml::real;
use crate::{ModelInfo, Type, Value};
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
        Some(Value::String(s)) if s.chars().count() > 40 => {
            format!("{}…", escape(&s.chars().take(40).collect::<String>()))
        }
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
        let kind = match v.kind {
            Type::Enumeration(e) => format!("Enumeration {}", escape(&info.enumerations[e].name)),
            k => format!("{k:?}"),
        };
        let _ = writeln!(
            h,
            "<tr><td><code>{}</code></td><td>{}</td><td>{:?}</td><td>{:?}</td><td>{}</td>\
             <td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td>{}</td></tr>",
            escape(&v.name),
            v.value_reference,
            v.causality,
            v.variability,
            kind,
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

#[cfg(test)]
mod tests {
    use crate::{Causality, ModelInfo, Type, Variability, VariableInfo};

    #[test]
    fn names_and_descriptions_are_escaped() {
        let v = VariableInfo::new(
            "a<b",
            Type::Real,
            Causality::Output,
            Variability::Continuous,
            "x < y & \"z\"",
        );
        let info = ModelInfo::new("M&N", "d", vec![v.unit("m")]);
        let html = super::html(&info, "<p>intro</p>", &[None]);
        assert!(html.contains("<code>a&lt;b</code>"), "{html}");
        assert!(html.contains("x &lt; y &amp; &quot;z&quot;"), "{html}");
        assert!(html.contains("<title>M&amp;N</title>") && html.contains("<p>intro</p>"));
        assert!(
            html.contains("<td>m</td><td>mm</td>"),
            "unit and its default display unit"
        );
    }
}
