//! A generic FMI 2.0 Co-Simulation slave: the C ABI, the state machine, argument and rule checks,
//! logging, FMU state and serialization, and the modelDescription.xml writer. A model plugs in
//! through [`Model`] and one call of [`export_fmi2!`]; nothing here knows a model's variables
//! except through the table it describes itself with. The FMI 3.0 side (crates/fmi3) builds on
//! the same [`Model`], table, [`instance::Instance`] and state machine ([`abi::guard`]).

pub mod abi;
pub mod doc;
pub mod instance;
pub mod package;
pub mod reference;
pub mod table;
pub mod units;
pub mod uri;
pub mod xml;

use std::path::Path;

/// FMI 2.0 scalar types; enumerations carry the index of their type definition.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Type {
    Real,
    Integer,
    Boolean,
    String,
    Enumeration(usize),
}

impl Type {
    /// The get/set family the type belongs to (enumerations are read as integers).
    pub fn family(self) -> Type {
        match self {
            Type::Enumeration(_) => Type::Integer,
            t => t,
        }
    }
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Causality {
    Parameter,
    CalculatedParameter,
    Input,
    Output,
    Local,
    Independent,
}

#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Variability {
    Constant,
    Fixed,
    Tunable,
    Discrete,
    Continuous,
}

/// A value of any type (start values, state of the table).
#[derive(Clone, Debug, PartialEq)]
pub enum Value {
    Real(f64),
    Integer(i32),
    Boolean(bool),
    String(String),
}

impl Value {
    /// The value as a number (Integer as is, Boolean as 0 or 1), for models that keep numbers as f64.
    pub fn number(&self) -> Result<f64, String> {
        match *self {
            Value::Real(x) => Ok(x),
            Value::Integer(n) => Ok(f64::from(n)),
            Value::Boolean(b) => Ok(f64::from(u8::from(b))),
            Value::String(_) => Err("not a number".into()),
        }
    }

    /// A number kept as f64 as a value of type `kind` (Integer truncated, Boolean: not 0).
    pub fn of_type(kind: Type, x: f64) -> Value {
        match kind {
            Type::Integer | Type::Enumeration(_) => Value::Integer(x as i32),
            Type::Boolean => Value::Boolean(x != 0.0),
            _ => Value::Real(x),
        }
    }
}

/// Item `n` (1-based, as Enumeration values are) of a list of choices.
pub fn enum_item<T: Copy>(all: &[T], n: i32) -> Result<T, String> {
    // No `n - 1` on i32: i32::MIN would overflow.
    let i = usize::try_from(n)
        .ok()
        .and_then(|n| n.checked_sub(1))
        .filter(|&i| i < all.len());
    i.map(|i| all[i])
        .ok_or(format!("must be 1 … {}, got {n}", all.len()))
}

/// The Enumeration value (1-based item number) of `x` in `all`.
pub fn enum_value<T: PartialEq>(all: &[T], x: &T) -> i32 {
    all.iter().position(|k| k == x).map_or(1, |i| i as i32 + 1)
}

/// One variable as the importer sees it.
#[derive(Clone, Debug)]
pub struct VariableInfo {
    pub name: String,
    pub value_reference: u32,
    pub kind: Type,
    pub causality: Causality,
    pub variability: Variability,
    pub unit: Option<String>,
    pub display_unit: Option<String>,
    pub description: String,
    /// Declared range (Real, Integer), emitted as `min`/`max` in the XML.
    pub min: Option<f64>,
    pub max: Option<f64>,
    /// Outputs and state derivatives: indices (in `ModelInfo::variables`) of the inputs and
    /// states this unknown depends on directly (`Some(vec![])`: none); `None` declares nothing
    /// (depends on all).
    pub dependencies: Option<Vec<usize>>,
    /// This variable is the time derivative of variable `i` (a continuous state; FMI
    /// `derivative` attribute): it is listed under ModelStructure/Derivatives.
    pub derivative_of: Option<usize>,
    /// Element of an array in FMI 3.0 (the per-axis variables of a `#` row, see
    /// [`table::expand`]); None: a scalar in both versions.
    pub element: Option<Element>,
}

/// Where an FMI 2 scalar sits in an FMI 3 array variable: `x.command.position` is element 0 of
/// `command.position` (3 elements, x, y, z).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Element {
    /// The array's name (the row's name without its `#.` prefix).
    pub array: String,
    pub index: usize,
    pub len: usize,
    /// The array's description (the row's, naming every axis).
    pub description: String,
}

impl VariableInfo {
    /// A row of a model's table; the value reference is assigned by [`ModelInfo::new`].
    pub fn new(
        name: impl Into<String>,
        kind: Type,
        causality: Causality,
        variability: Variability,
        description: impl Into<String>,
    ) -> Self {
        VariableInfo {
            name: name.into(),
            value_reference: 0,
            kind,
            causality,
            variability,
            unit: None,
            display_unit: None,
            description: description.into(),
            min: None,
            max: None,
            dependencies: None,
            derivative_of: None,
            element: None,
        }
    }

    /// SI unit from [`units`]; the display unit is the unit's default one (mm for m, …).
    pub fn unit(mut self, unit: &str) -> Self {
        self.display_unit = units::default_display(unit).map(str::to_string);
        self.unit = Some(unit.to_string());
        self
    }

    /// Another of the unit's display units.
    pub fn display(mut self, display_unit: &str) -> Self {
        self.display_unit = Some(display_unit.to_string());
        self
    }

    /// Declared range (either bound may be open).
    pub fn range(mut self, min: Option<f64>, max: Option<f64>) -> Self {
        self.min = min;
        self.max = max;
        self
    }

    /// Direct dependencies of an output on inputs (indices into the table).
    pub fn depends_on(mut self, inputs: Vec<usize>) -> Self {
        self.dependencies = Some(inputs);
        self
    }

    /// Parameters and inputs carry a start value (initial = exact); outputs and locals (states,
    /// derivatives) are calculated.
    pub fn has_start(&self) -> bool {
        matches!(self.causality, Causality::Parameter | Causality::Input)
    }
}

/// An enumeration type: name and items (name, description), values 1…n.
#[derive(Clone, Debug)]
pub struct EnumerationType {
    pub name: String,
    pub items: Vec<(String, String)>,
}

impl EnumerationType {
    /// From items (name, description), values 1…n in the given order.
    pub fn new<'a>(name: &str, items: impl IntoIterator<Item = (&'a str, &'a str)>) -> Self {
        let items = items
            .into_iter()
            .map(|(n, d)| (n.to_string(), d.to_string()))
            .collect();
        EnumerationType {
            name: name.into(),
            items,
        }
    }
}

/// A display unit of an SI unit: value_display = factor · value + offset.
#[derive(Clone, Debug)]
pub struct DisplayUnit {
    pub name: String,
    pub factor: f64,
    pub offset: f64,
}

/// A unit with its SI base-unit exponents (kg, m, s, A, K, mol, cd, rad).
#[derive(Clone, Debug)]
pub struct UnitDefinition {
    pub name: String,
    pub base: [i32; 8],
    pub display: Vec<DisplayUnit>,
}

/// Optional abilities of a model, declared in both versions' XML (FMI 2 / FMI 3 attribute names).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Capabilities {
    /// maxOutputDerivativeOrder: [`Model::output_derivative`] answers orders 1…n (0 where it
    /// does not know one, as the standard says).
    pub max_output_derivative_order: u32,
    /// canInterpolateInputs (FMI 2): [`Model::set_input_derivative`] takes orders 1…n of the
    /// continuous Real inputs (n = `max_input_derivative_order`).
    pub max_input_derivative_order: u32,
    /// providesDirectionalDerivative(s) and, in FMI 3, providesAdjointDerivatives:
    /// [`Model::partial_derivative`] of outputs and state derivatives.
    pub provides_directional_derivative: bool,
    /// fixedInternalStepSize (FMI 3).
    pub fixed_internal_step: Option<f64>,
    /// mightReturnEarlyFromDoStep (FMI 3): [`Model::do_step_early`] may stop inside a step.
    pub might_return_early: bool,
}

/// A terminal (FMI 3 terminalsAndIcons.xml): variables grouped for connecting, each by its FMI 3
/// name with a member name that matches the other side's (`plug` rule).
#[derive(Clone, Debug, PartialEq)]
pub struct Terminal {
    pub name: String,
    pub kind: String,
    pub description: String,
    /// (FMI 3 variable name, member name).
    pub members: Vec<(String, String)>,
}

/// A periodic time-based input clock (FMI 3 `Clock`, intervalVariability `constant`): each
/// activation runs the clock's model partition up to the activation time
/// ([`Model::activate`]). FMI 3 only: Scheduled Execution activates it with
/// fmi3ActivateModelPartition, Co-Simulation in Event Mode with fmi3SetClock.
#[derive(Clone, Debug, PartialEq)]
pub struct Clock {
    pub name: String,
    pub description: String,
    /// The constant interval (s); activations at t_start + k·interval.
    pub interval: f64,
    /// Scheduling priority (0: highest).
    pub priority: u32,
}

/// What the model tells the layer (and the XML) about itself.
#[derive(Clone, Debug)]
pub struct ModelInfo {
    pub model_name: String,
    pub model_identifier: String,
    pub guid: String,
    pub description: String,
    pub version: String,
    pub author: String,
    pub copyright: String,
    pub license: String,
    pub variables: Vec<VariableInfo>,
    pub enumerations: Vec<EnumerationType>,
    pub units: Vec<UnitDefinition>,
    /// DefaultExperiment: start, stop, tolerance, step size.
    pub default_experiment: (f64, f64, f64, f64),
    pub capabilities: Capabilities,
    pub terminals: Vec<Terminal>,
    /// FMI 3 clocks (value references after the table's); none: no Event Mode or Scheduled
    /// Execution.
    pub clocks: Vec<Clock>,
}

impl ModelInfo {
    /// A description from the model's table: value references 1…n in table order, the GUID of
    /// the table, the units it names; version, author, copyright and license of the crate that
    /// builds it (override the fields as needed).
    pub fn new(name: &str, description: &str, mut variables: Vec<VariableInfo>) -> ModelInfo {
        for (k, v) in variables.iter_mut().enumerate() {
            v.value_reference = k as u32 + 1;
        }
        let units = units::definitions(variables.iter().filter_map(|v| v.unit.as_deref()));
        ModelInfo {
            model_name: name.into(),
            model_identifier: name.into(),
            guid: guid_of(&variables, &Capabilities::default()),
            description: description.into(),
            version: String::new(),
            author: String::new(),
            copyright: String::new(),
            license: String::new(),
            variables,
            enumerations: Vec::new(),
            units,
            default_experiment: (0.0, 1.0, 1e-6, 1e-3),
            capabilities: Capabilities::default(),
            terminals: Vec::new(),
            clocks: Vec::new(),
        }
    }

    /// The description with these capabilities, and a GUID that fingerprints them too (a model
    /// that starts to take input derivatives is another FMU to its importers).
    pub fn with_capabilities(self, capabilities: Capabilities) -> ModelInfo {
        ModelInfo {
            guid: guid_of(&self.variables, &capabilities),
            capabilities,
            ..self
        }
    }

    /// Indices of the continuous states: the variables some other variable is the derivative of.
    pub fn states(&self) -> Vec<usize> {
        let mut s: Vec<usize> = self.variables.iter().filter_map(|v| v.derivative_of).collect();
        s.sort_unstable();
        s.dedup();
        s
    }

    /// Whether variable `i` may be an unknown of a directional derivative: an output or a state
    /// derivative.
    pub fn is_unknown(&self, i: usize) -> bool {
        let v = &self.variables[i];
        v.causality == Causality::Output || v.derivative_of.is_some()
    }

    /// Whether variable `i` may be a known of a directional derivative: a continuous Real input
    /// or a continuous state.
    pub fn is_known(&self, i: usize) -> bool {
        let v = &self.variables[i];
        let input = v.causality == Causality::Input && v.variability == Variability::Continuous;
        input || self.variables.iter().any(|u| u.derivative_of == Some(i))
    }
}

/// A model behind the generic layer. Indices are positions in `info().variables`.
pub trait Model: Clone + Send + 'static {
    /// The description, built once.
    fn info() -> &'static ModelInfo;
    /// A model at its start values; `resources` is the FMU's resources folder, if given.
    fn new(resources: Option<&Path>) -> Self;
    fn get(&self, index: usize) -> Value;
    /// Set a variable; refusals come back as a message for the log.
    fn set(&mut self, index: usize, value: Value) -> Result<(), String>;
    /// End of initialization: check parameters, load what they name.
    fn exit_initialization(&mut self) -> Result<(), String>;
    /// Advance from the current time by h > 0.
    fn do_step(&mut self, h: f64) -> Result<(), String>;
    /// Whole state as bytes (versioned by the model), and back.
    fn serialize(&self) -> Vec<u8>;
    fn deserialize(&mut self, bytes: &[u8]) -> Result<(), String>;

    /// Advance by h > 0, or less when an event inside the step asks for a communication point
    /// of its own (FMI 3 early return, when the importer allows it): the time advanced, in (0, h].
    fn do_step_early(&mut self, h: f64) -> Result<f64, String> {
        self.do_step(h).map(|()| h)
    }

    /// Time derivative of order 1…`max_output_derivative_order` of Real output `index` at the
    /// current time, None where the model does not know it (the layer then answers 0 with a
    /// Warning naming the output and order).
    fn output_derivative(&self, _index: usize, _order: u32) -> Option<f64> {
        None
    }

    /// The `order`-th time derivative of continuous input `index` at the start of the next steps
    /// (FMI 2 fmi2SetRealInputDerivatives; models with `max_input_derivative_order` > 0).
    fn set_input_derivative(&mut self, _index: usize, _order: u32, _value: f64) -> Result<(), String> {
        Err("this model cannot interpolate inputs".into())
    }

    /// The model partition of clock `clock` ([`ModelInfo::clocks`]), activated `h` > 0 after the
    /// model's current time: everything up to the activation time. One-partition models advance
    /// as in a step.
    fn activate(&mut self, _clock: usize, h: f64) -> Result<(), String> {
        self.do_step(h)
    }

    /// After initialization, whether the parameters in force agree with clock `clock`'s declared
    /// constant `interval` (a clocked instance refuses to start otherwise, with this message).
    fn check_clock(&self, _clock: usize, _interval: f64) -> Result<(), String> {
        Ok(())
    }

    /// ∂unknown/∂known at the current communication point: unknowns are outputs and state
    /// derivatives, knowns continuous inputs and states ([`ModelInfo::is_unknown`],
    /// [`ModelInfo::is_known`]; models with `provides_directional_derivative`).
    fn partial_derivative(&self, _unknown: usize, _known: usize) -> f64 {
        0.0
    }
}

/// Reads `(variable name, value)` pairs into a model through the same checks as fmi2Set* (finite,
/// within the declared min/max), for tests and packaging tools.
pub fn set_by_name<M: Model>(model: &mut M, name: &str, value: Value) -> Result<(), String> {
    let info = M::info();
    let i = info
        .variables
        .iter()
        .position(|v| v.name == name)
        .ok_or_else(|| format!("no variable '{name}'"))?;
    match instance::out_of_range::<M>(&info.variables[i], &value) {
        Some(reason) => Err(format!("{name} = {reason}")),
        None => model.set(i, value),
    }
}

/// A [`ModelInfo`] with the version, authors and license of the calling crate's manifest
/// (`authors`, `license`), the copyright of its authors.
#[macro_export]
macro_rules! crate_model_info {
    ($name:expr, $description:expr, $variables:expr) => {
        $crate::ModelInfo {
            version: env!("CARGO_PKG_VERSION").into(),
            author: env!("CARGO_PKG_AUTHORS").into(),
            copyright: format!("Copyright (c) 2026 the {}", env!("CARGO_PKG_AUTHORS")),
            license: env!("CARGO_PKG_LICENSE").into(),
            ..$crate::ModelInfo::new($name, $description, $variables)
        }
    };
}

/// Namespace of the GUIDs of this layer's FMUs (a fixed random UUID: GUIDs never collide with
/// other v5 names).
const GUID_NAMESPACE: uuid::Uuid = uuid::Uuid::from_u128(0x4c1f_5a1e_9b0d_4e57_a6c3_2f8e_1d7b_90a4);

/// A GUID that changes whenever the variable table or the capabilities change: the name-based
/// UUID (v5) of the table's rows and the capabilities.
pub fn guid_of(variables: &[VariableInfo], capabilities: &Capabilities) -> String {
    let rows: String = variables
        .iter()
        .map(|v| {
            format!(
                "{}|{}|{:?}|{:?}|{:?}|{:?}|{:?}|{:?};",
                v.name,
                v.value_reference,
                v.kind,
                v.causality,
                v.variability,
                v.unit,
                v.dependencies,
                v.derivative_of
            )
        })
        .collect::<String>()
        + &format!("{capabilities:?}");
    format!("{{{}}}", uuid::Uuid::new_v5(&GUID_NAMESPACE, rows.as_bytes()))
}

/// Start values read from a model at its defaults (None for calculated variables).
pub fn start_values<M: Model>() -> Vec<Option<Value>> {
    let info = M::info();
    let m = M::new(None);
    (0..info.variables.len())
        .map(|i| info.variables[i].has_start().then(|| m.get(i)))
        .collect()
}

/// modelDescription.xml of a model.
pub fn model_description<M: Model>() -> String {
    xml::model_description(M::info(), &start_values::<M>())
}

/// documentation/index.html of a model: `intro_html` and the table of variables.
pub fn documentation<M: Model>(intro_html: &str) -> String {
    doc::html(M::info(), intro_html, &start_values::<M>())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn guid_is_a_v5_uuid_of_the_table() {
        let row = |unit: &str| {
            let v = VariableInfo::new("x.p", Type::Real, Causality::Output, Variability::Continuous, "p");
            vec![v.unit(unit)]
        };
        let none = Capabilities::default();
        let g = guid_of(&row("m"), &none);
        assert_eq!(g, guid_of(&row("m"), &none), "the same table, the same GUID");
        assert_ne!(g, guid_of(&row("N"), &none), "another unit, another GUID");
        let interpolating = Capabilities {
            max_input_derivative_order: 1,
            ..none
        };
        assert_ne!(
            g,
            guid_of(&row("m"), &interpolating),
            "other capabilities, another GUID"
        );
        let u = uuid::Uuid::parse_str(g.trim_matches(|c| c == '{' || c == '}')).unwrap();
        assert_eq!((g.len(), u.get_version_num()), (38, 5));
    }

    #[test]
    fn enumeration_values_are_one_based_items() {
        let all = ['a', 'b', 'c'];
        assert_eq!((enum_item(&all, 1), enum_item(&all, 3)), (Ok('a'), Ok('c')));
        assert_eq!(enum_item(&all, 0), Err("must be 1 … 3, got 0".to_string()));
        assert!(enum_item(&all, 4).is_err() && enum_item(&all, i32::MIN).is_err());
        assert_eq!(all.map(|c| enum_value(&all, &c)), [1, 2, 3]);
    }

    #[test]
    fn numbers_kept_as_f64_convert_to_and_from_values() {
        assert_eq!(Value::of_type(Type::Integer, 4096.0), Value::Integer(4096));
        assert_eq!(Value::of_type(Type::Boolean, 1.0), Value::Boolean(true));
        assert_eq!(Value::of_type(Type::Real, 0.5), Value::Real(0.5));
        assert_eq!(Value::Boolean(true).number(), Ok(1.0));
        assert_eq!(Value::Integer(-3).number(), Ok(-3.0));
        assert!(Value::String("1".into()).number().is_err());
    }
}
