//! A model's variables as a table of plain rows, expanded into [`VariableInfo`]s: rows whose name
//! holds `#` stand for one variable per axis (x, y, z, …), with the axis index given to the row's
//! slot (what the model reads or writes).

use crate::{Causality, Type, Variability, VariableInfo};

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

/// The table expanded in order: a row without `#` once (axis 0, name ""); a run of `#` rows once
/// of one causality for each axis (all rows of the run for the first axis, then the second, …). `expand(row, axis
/// index, axis name)` turns one row on one axis into its variables (usually
/// `[(variable(row, axis), slot)]`; a row may stand for several).
pub fn expand<S: Copy>(
    rows: &[Row<S>],
    axes: &[&str],
    mut expand: impl FnMut(&Row<S>, usize, &str) -> Vec<(VariableInfo, S)>,
) -> Vec<(VariableInfo, S)> {
    let mut out = Vec::new();
    let mut k = 0;
    while k < rows.len() {
        let per_axis = |r: &&Row<S>| r.0.contains('#') && r.2 == rows[k].2;
        let run = rows[k..].iter().take_while(per_axis).count();
        if run == 0 {
            out.extend(expand(&rows[k], 0, ""));
            k += 1;
            continue;
        }
        for (i, axis) in axes.iter().enumerate() {
            for row in &rows[k..k + run] {
                out.extend(expand(row, i, axis));
            }
        }
        k += run;
    }
    out
}

/// Index of the variable called `name` (for dependencies).
pub fn index_of<S>(table: &[(VariableInfo, S)], name: &str) -> Option<usize> {
    table.iter().position(|(v, _)| v.name == name)
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
        let t = expand(rows, &["x", "y"], |r, i, axis| {
            vec![(variable(r, axis), (i, r.7 .1))]
        });
        let names: Vec<&str> = t.iter().map(|(v, _)| v.name.as_str()).collect();
        assert_eq!(
            names,
            ["p", "x.a", "y.a", "x.b", "y.b", "q"],
            "runs break where the causality changes"
        );
        assert_eq!(t[2].1, (1, 1));
        assert_eq!(t[2].0.description, "a of y");
        assert_eq!(
            (t[0].0.min, t[0].0.display_unit.as_deref()),
            (Some(0.0), Some("mm"))
        );
        assert_eq!(t[3].0.dependencies, Some(vec![]));
        assert_eq!(index_of(&t, "y.b"), Some(4));
    }
}
