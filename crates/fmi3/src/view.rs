//! The FMI 3.0 variables of a model, derived from its one table (the FMI 2 variables of
//! [`fmi2::ModelInfo`]): the independent variable `time` first (value reference 0), then every
//! table variable in order, the elements of a per-axis row gathered into one array at the place
//! of its first element (`x.command.position`, `y.…`, `z.…` → `command.position`, 3 elements).
//! The model's clocks follow (input clocks, no table index). Value references are the positions
//! in this list.

use fmi2::{Causality, Model, ModelInfo, Type, Variability, VariableInfo};

/// FMI 3 types of the variables: Reals are Float64; Integers that cannot be negative (a declared
/// min ≥ 0: counts and indices) UInt64, the others Int32; Enumerations are read and written as
/// Int64 (fmi3GetInt64), as the standard says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Kind {
    Float64,
    Int32,
    UInt64,
    Boolean,
    String,
    Enumeration(usize),
    /// An input clock: its index in [`fmi2::ModelInfo::clocks`].
    Clock(usize),
}

impl Kind {
    pub fn of(v: &VariableInfo) -> Kind {
        match v.kind {
            Type::Real => Kind::Float64,
            Type::Integer if v.min.is_some_and(|m| m >= 0.0) => Kind::UInt64,
            Type::Integer => Kind::Int32,
            Type::Boolean => Kind::Boolean,
            Type::String => Kind::String,
            Type::Enumeration(e) => Kind::Enumeration(e),
        }
    }

    /// The XML element (and fmi3Get*/fmi3Set* family) name.
    pub fn name(self) -> &'static str {
        match self {
            Kind::Float64 => "Float64",
            Kind::Int32 => "Int32",
            Kind::UInt64 => "UInt64",
            Kind::Boolean => "Boolean",
            Kind::String => "String",
            Kind::Enumeration(_) => "Enumeration",
            Kind::Clock(_) => "Clock",
        }
    }
}

/// One FMI 3 variable.
#[derive(Clone, Debug)]
pub struct Var {
    pub name: String,
    pub value_reference: u32,
    pub kind: Kind,
    pub causality: Causality,
    pub variability: Variability,
    pub unit: Option<String>,
    pub display_unit: Option<String>,
    pub description: String,
    pub min: Option<f64>,
    pub max: Option<f64>,
    /// The table indices of its values in serialization order: one for a scalar, one per
    /// element for an array; none for `time` and clocks.
    pub elements: Vec<usize>,
    /// An array (a `<Dimension>`), even of one element.
    pub array: bool,
    /// The variable (index in [`View::vars`]) this one is the time derivative of.
    pub derivative_of: Option<usize>,
    /// Outputs and state derivatives: the knowns they depend on (indices in [`View::vars`]).
    pub dependencies: Option<Vec<usize>>,
}

impl Var {
    /// Number of values (1 for a scalar).
    pub fn size(&self) -> usize {
        self.elements.len().max(1)
    }
}

/// A model's FMI 3 variables.
#[derive(Clone, Debug)]
pub struct View {
    /// instantiationToken: a name-based UUID (v5) of the FMI 2 GUID, which hashes the table.
    pub token: String,
    pub vars: Vec<Var>,
    /// The FMI 3 variable of each table index.
    pub of_table: Vec<usize>,
}

/// Namespace of the instantiation tokens (a fixed random UUID, other than the GUIDs').
const TOKEN_NAMESPACE: uuid::Uuid = uuid::Uuid::from_u128(0x7e0b_62c4_2f1d_4a8e_9c35_d1a6_04f7_b2e9);

impl View {
    pub fn of<M: Model>() -> View {
        View::from_info(M::info())
    }

    /// # Panics
    /// If the elements of one array disagree on type, causality, variability, unit or range (a
    /// table error: each model's tests build its view).
    pub fn from_info(info: &ModelInfo) -> View {
        let table = &info.variables;
        let mut vars = vec![Var {
            name: "time".into(),
            value_reference: 0,
            kind: Kind::Float64,
            causality: Causality::Independent,
            variability: Variability::Continuous,
            // In seconds where the model defines the unit (a unit must be defined to be used).
            unit: info.units.iter().any(|u| u.name == "s").then(|| "s".into()),
            display_unit: None,
            description: "simulation time".into(),
            min: None,
            max: None,
            elements: Vec::new(),
            array: false,
            derivative_of: None,
            dependencies: None,
        }];
        let mut of_table = vec![usize::MAX; table.len()];
        for (i, v) in table.iter().enumerate() {
            if of_table[i] != usize::MAX {
                continue;
            }
            let (name, description, elements) = match &v.element {
                None => (v.name.clone(), v.description.clone(), vec![i]),
                Some(e) => {
                    let mut elements = vec![usize::MAX; e.len];
                    for (j, w) in table.iter().enumerate() {
                        if let Some(f) = w.element.as_ref().filter(|f| f.array == e.array) {
                            assert!(f.len == e.len && elements[f.index] == usize::MAX, "{}", w.name);
                            elements[f.index] = j;
                        }
                    }
                    assert!(
                        !elements.contains(&usize::MAX),
                        "{}: an element is missing",
                        e.array
                    );
                    (e.array.clone(), e.description.clone(), elements)
                }
            };
            let k = vars.len();
            for &j in &elements {
                let w = &table[j];
                let same = (w.kind, w.causality, w.variability, &w.unit, w.min, w.max)
                    == (v.kind, v.causality, v.variability, &v.unit, v.min, v.max);
                assert!(same, "{} and {} differ but form one array", v.name, w.name);
                of_table[j] = k;
            }
            vars.push(Var {
                name,
                value_reference: k as u32,
                kind: Kind::of(v),
                causality: v.causality,
                variability: v.variability,
                unit: v.unit.clone(),
                display_unit: v.display_unit.clone(),
                description,
                min: v.min,
                max: v.max,
                array: v.element.is_some(),
                elements,
                derivative_of: None,
                dependencies: None,
            });
        }
        for var in vars.iter_mut().skip(1) {
            let first = &table[var.elements[0]];
            var.derivative_of = first.derivative_of.map(|d| of_table[d]);
            let deps: Option<Vec<usize>> = var.elements.iter().try_fold(Vec::new(), |mut all, &j| {
                all.extend(table[j].dependencies.as_ref()?.iter().map(|&d| of_table[d]));
                Some(all)
            });
            var.dependencies = deps.map(|mut d| {
                d.sort_unstable();
                d.dedup();
                d
            });
        }
        add_clocks(info, &mut vars);
        // The clocks are FMI 3 only: they change the token, not the FMI 2 GUID.
        let clocks: String = info.clocks.iter().map(|c| format!("|{c:?}")).collect();
        let token = uuid::Uuid::new_v5(&TOKEN_NAMESPACE, (info.guid.clone() + &clocks).as_bytes());
        View {
            token: format!("{{{token}}}"),
            vars,
            of_table,
        }
    }

    /// The clock (index in [`fmi2::ModelInfo::clocks`]) of value reference `vr`, if it is one.
    pub fn clock(&self, vr: u32) -> Option<usize> {
        match self.get(vr)?.kind {
            Kind::Clock(k) => Some(k),
            _ => None,
        }
    }

    /// The variable of value reference `vr`.
    #[inline]
    pub fn get(&self, vr: u32) -> Option<&Var> {
        self.vars.get(vr as usize)
    }

    /// Index of the variable called `name`.
    pub fn index_of(&self, name: &str) -> Option<usize> {
        self.vars.iter().position(|v| v.name == name)
    }
}

/// The model's clocks after the table's variables: input clocks, and every output the model
/// computes depends on them (their partition computes it; the outputs are not clocked variables,
/// since Co-Simulation reads them in Step Mode, as the Reference-FMUs' `Clocks` declares an output
/// a partition updates).
fn add_clocks(info: &ModelInfo, vars: &mut Vec<Var>) {
    for (k, c) in info.clocks.iter().enumerate() {
        let vr = vars.len();
        for v in vars.iter_mut().filter(|v| v.causality == Causality::Output) {
            if let Some(deps) = v.dependencies.as_mut() {
                deps.push(vr);
            }
        }
        vars.push(Var {
            name: c.name.clone(),
            value_reference: vr as u32,
            kind: Kind::Clock(k),
            causality: Causality::Input,
            variability: Variability::Discrete,
            unit: None,
            display_unit: None,
            description: c.description.clone(),
            min: None,
            max: None,
            elements: Vec::new(),
            array: false,
            derivative_of: None,
            dependencies: None,
        });
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use fmi2::table::{expand, one, variables, Row};
    use fmi2::Causality::{Input, Output, Parameter};
    use fmi2::Variability::{Continuous, Fixed};

    #[test]
    fn per_axis_rows_become_arrays_at_their_first_element() {
        let rows: &[Row<u8>] = &[
            ("p", Type::Integer, Parameter, Fixed, "", Some(0.0), None, 0, "p"),
            ("#.a", Type::Real, Input, Continuous, "N", None, None, 1, "a of #"),
            (
                "#.b",
                Type::Real,
                Output,
                Continuous,
                "m",
                None,
                None,
                2,
                "b of #",
            ),
            ("n", Type::Integer, Parameter, Fixed, "", Some(-1.0), None, 3, "n"),
        ];
        let mut t = variables(&expand(rows, &["x", "y", "z"], one));
        t[5].dependencies = Some(vec![2]); // y.b on y.a
        let view = View::from_info(&ModelInfo::new("M", "m", t));
        let names: Vec<&str> = view.vars.iter().map(|v| v.name.as_str()).collect();
        assert_eq!(names, ["time", "p", "a", "b", "n"]);
        assert_eq!(view.vars[2].elements, [1, 2, 3]);
        assert_eq!(view.vars[3].elements, [4, 5, 6]);
        assert_eq!(view.vars[3].description, "b of x/y/z");
        assert_eq!(view.of_table, [1, 2, 2, 2, 3, 3, 3, 4]);
        assert_eq!(
            (view.vars[1].kind, view.vars[4].kind),
            (Kind::UInt64, Kind::Int32)
        );
        assert_eq!(
            view.vars[3].dependencies,
            Some(vec![2]),
            "b depends on a (one element does)"
        );
        assert!(view
            .vars
            .iter()
            .enumerate()
            .all(|(k, v)| v.value_reference == k as u32));
        assert!(view.token.len() == 38 && view.token != ModelInfo::new("M", "m", vec![]).guid);
    }

    #[test]
    fn clocks_follow_the_table_and_the_outputs_depend_on_them() {
        let rows: &[Row<u8>] = &[
            ("u", Type::Real, Input, Continuous, "N", None, None, 0, "u"),
            ("y", Type::Real, Output, Continuous, "m", None, None, 1, "y"),
        ];
        let mut t = variables(&expand(rows, &["x"], one));
        t[1].dependencies = Some(vec![]);
        let plain = ModelInfo::new("M", "m", t);
        let clocked = ModelInfo {
            clocks: vec![fmi2::Clock {
                name: "tick".into(),
                description: "tick".into(),
                interval: 1e-3,
                priority: 0,
            }],
            ..plain.clone()
        };
        let (a, b) = (View::from_info(&plain), View::from_info(&clocked));
        assert_eq!(b.vars.len(), a.vars.len() + 1);
        let tick = b.vars.last().unwrap();
        assert_eq!(
            (tick.value_reference, tick.kind, tick.causality),
            (3, Kind::Clock(0), Input)
        );
        assert_eq!((b.clock(3), b.clock(1)), (Some(0), None));
        assert_eq!(
            b.vars[2].dependencies,
            Some(vec![3]),
            "y is computed by the tick's partition"
        );
        assert_ne!(a.token, b.token, "the FMI 3 interface changed");
        assert_eq!(plain.guid, clocked.guid, "the FMI 2 one did not");
    }
}
