//! A model's variables as a table of plain rows, expanded into [`VariableInfo`]s: rows whose name
//! holds `#` stand for one variable per axis (x, y, z, …), with the axis index given to the row's
//! slot (what the model reads or writes). In FMI 3 the variables of a `#` row are one array (its
//! name without the `#.` prefix, one element per axis: [`crate::Element`]).

use crate::{Causality, Element, Type, Variability, VariableInfo};

/// name (`#`: per axis), type, causality, variability, unit ("": none), min, max, slot,
/// description (`#` replaced by the axis name too).
pub type Row<S> = (
    &'static str,
    Type,
    Causality,
    Variability,
    &'static str,
    Option<f64>,
    Option<f64>,
    S,
    &'static str,
);

/// The variable of one row on one axis (`""` for rows without `#`). Outputs declare no direct
/// dependency on any input (`dependencies=""`); a model with feed-through sets its own.
pub fn variable<S>(row: &Row<S>, axis: &str) -> VariableInfo {
    let (name, kind, causality, variability, unit, min, max, _, desc) = row;
    let mut v = VariableInfo::new(
        name.replace('#', axis),
        *kind,
        *causality,
        *variability,
        desc.replace('#', axis),
    );
    if !unit.is_empty() {
        v = v.unit(unit);
    }
    if *causality == Causality::Output {
        v = v.depends_on(vec![]);
    }
    v.range(*min, *max)
}

/// One variable of an expanded table: what the importer sees, what the model reads or writes, and
/// on which axis (0 for rows without `#`).
#[derive(Clone, Debug)]
pub struct Entry<S> {
    pub var: VariableInfo,
    pub slot: S,
    pub axis: usize,
}

/// A row as its one variable (the usual `expand` of [`expand`]).
pub fn one<S: Copy>(row: &Row<S>, axis: &str) -> Vec<(VariableInfo, S)> {
    vec![(variable(row, axis), row.7)]
}

/// `text` with every whole word `word` replaced by `by` (words: runs of letters and digits).
fn replace_word(text: &str, word: &str, by: &str) -> String {
    let mut out = String::with_capacity(text.len());
    let mut rest = text;
    while let Some(at) = rest.find(word) {
        let before = text[..text.len() - rest.len() + at].chars().next_back();
        let after = rest[at + word.len()..].chars().next();
        let alone = !before.is_some_and(char::is_alphanumeric) && !after.is_some_and(char::is_alphanumeric);
        out.push_str(&rest[..at]);
        out.push_str(if alone { by } else { word });
        rest = &rest[at + word.len()..];
    }
    out.push_str(rest);
    out
}

/// The table expanded in order: a row without `#` once (axis 0, name ""); a run of `#` rows of one
/// causality once for each axis (all rows of the run for the first axis, then the second, …).
/// `expand(row, axis name)` turns one row on one axis into its variables (usually [`one`]; a row
/// may stand for several, e.g. one per drive parameter). The variables of a `#` row are the
/// elements of one FMI 3 array: their name without the `axis.` prefix, the description of the
/// first axis' naming all of them (`x commanded position` → `x/y/z commanded position`).
///
/// # Panics
/// If a `#` row's variable does not start with its axis' name and a dot (a table error; every
/// model's tests build its table).
pub fn expand<S: Copy>(
    rows: &[Row<S>],
    axes: &[&str],
    mut expand: impl FnMut(&Row<S>, &str) -> Vec<(VariableInfo, S)>,
) -> Vec<Entry<S>> {
    let mut out = Vec::new();
    let all = axes.join("/");
    let mut push = |row: &Row<S>, axis: usize, name: &str| {
        let per_axis = row.0.contains('#');
        let vars = expand(row, name).into_iter().map(|(mut var, slot)| {
            if per_axis {
                let array = var.name.strip_prefix(name).and_then(|n| n.strip_prefix('.'));
                let array = array.unwrap_or_else(|| panic!("{}: not named after its axis", var.name));
                var.element = Some(Element {
                    array: array.to_string(),
                    index: axis,
                    len: axes.len(),
                    description: replace_word(&var.description, name, &all),
                });
            }
            Entry { var, slot, axis }
        });
        out.extend(vars);
    };
    let mut k = 0;
    while k < rows.len() {
        let per_axis = |r: &&Row<S>| r.0.contains('#') && r.2 == rows[k].2;
        let run = rows[k..].iter().take_while(per_axis).count();
        if run == 0 {
            push(&rows[k], 0, "");
            k += 1;
            continue;
        }
        for (i, axis) in axes.iter().enumerate() {
            for row in &rows[k..k + run] {
                push(row, i, axis);
            }
        }
        k += run;
    }
    out
}

/// Index of the variable called `name` (for dependencies).
pub fn index_of<S>(table: &[Entry<S>], name: &str) -> Option<usize> {
    table.iter().position(|e| e.var.name == name)
}

/// The variables of an expanded table, in order (for [`crate::ModelInfo::new`]).
pub fn variables<S>(table: &[Entry<S>]) -> Vec<VariableInfo> {
    table.iter().map(|e| e.var.clone()).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Causality::{Input, Output, Parameter};
    use crate::Variability::{Continuous, Fixed};

    #[test]
    fn per_axis_runs_expand_axis_by_axis() {
        let rows: &[Row<(usize, u8)>] = &[
            (
                "p",
                Type::Real,
                Parameter,
                Fixed,
                "m",
                Some(0.0),
                None,
                (9, 0),
                "p",
            ),
            (
                "#.a",
                Type::Real,
                Input,
                Continuous,
                "N",
                None,
                None,
                (0, 1),
                "a of #",
            ),
            ("#.b", Type::Real, Output, Continuous, "", None, None, (0, 2), "b"),
            ("q", Type::Boolean, Parameter, Fixed, "", None, None, (9, 3), "q"),
        ];
        let t = expand(rows, &["x", "y"], one);
        let names: Vec<&str> = t.iter().map(|e| e.var.name.as_str()).collect();
        assert_eq!(
            names,
            ["p", "x.a", "y.a", "x.b", "y.b", "q"],
            "runs break where the causality changes"
        );
        assert_eq!((t[2].slot, t[2].axis), ((0, 1), 1));
        assert_eq!(t[2].var.description, "a of y");
        assert_eq!(
            (t[0].var.min, t[0].var.display_unit.as_deref()),
            (Some(0.0), Some("mm"))
        );
        assert_eq!(t[3].var.dependencies, Some(vec![]));
        assert_eq!(index_of(&t, "y.b"), Some(4));
        let e = t[2]
            .var
            .element
            .as_ref()
            .expect("a # row's variable is an array element");
        assert_eq!((e.array.as_str(), e.index, e.len), ("a", 1, 2));
        assert_eq!(e.description, "a of x/y");
        assert!(t[0].var.element.is_none() && t[5].var.element.is_none());
    }

    #[test]
    fn words_are_replaced_whole() {
        assert_eq!(
            replace_word("x axis, x-limit (max x)", "x", "x/y"),
            "x/y axis, x/y-limit (max x/y)"
        );
        assert_eq!(replace_word("xx box x1 ax", "x", "-"), "xx box x1 ax");
    }
}
