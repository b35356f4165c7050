//! Sweep plans, version 1: parsing and validation (the contract is
//! `docs/sweep-format.md`).
//!
//! A plan names case files (relative to the plan), a reference, the error
//! measures and, per `[[formulation]]`, a grid of settings. Every rule is
//! checked before anything runs, and every error is one line naming the
//! plan file, the line and the key.
//!
//! **How a setting is applied.** A point's scenario is its case file with
//! the point's values written into it (`contact.distance` into
//! `[contact] distance`, `integrator.tolerance` into `[integrator]
//! tolerance`, any other key into the formulation's own
//! `[formulation.<table>]`), read again by the case loader
//! ([`crate::formulation::parse_case`]). So a value is held to exactly the
//! rules of a case file (the formulation's own table parser, the contact and
//! integrator rules), and a formulation reads it as it reads any case's
//! settings. A value that the loader refuses is reported at the plan line
//! that writes it, with the loader's message.

mod grid;
mod parse;
mod spec;

pub use parse::{load_plan, parse_plan};

use super::digest; // for parse.rs, whose code calls `super::digest`
use super::start::Start;
use crate::formulation::{parse_case, Entry};
use crate::model::Scenario;
use std::path::PathBuf;

/// The plan version this reader knows.
pub const VERSION: i64 = 1;

/// The grid key of the contact distance (`[contact] distance` of the case), m.
pub const CONTACT_DISTANCE: &str = "contact.distance";

/// The grid key of the integrator tolerance (`[integrator] tolerance` of the
/// case), relative.
pub const INTEGRATOR_TOLERANCE: &str = "integrator.tolerance";

/// One setting of a point: a key as the plan writes it and its value.
#[derive(Debug, Clone, PartialEq)]
pub struct Setting {
    /// `contact.distance`, `integrator.tolerance` or a key of the
    /// formulation's `[formulation.<table>]`.
    pub key: String,
    /// The value as written.
    pub value: toml::Value,
}

impl Setting {
    /// `key=value`, the value in its shortest form ([`format_value`]).
    pub fn label(&self) -> String {
        format!("{}={}", self.key, format_value(&self.value))
    }

    /// The value as a number, when it is one.
    pub fn number(&self) -> Option<f64> {
        value_number(&self.value)
    }
}

/// A value in its shortest form: integers as written, floats as Rust's
/// shortest round-trip form in scientific notation when that is shorter
/// (`0.25`, `1e-9`), strings without quotes.
pub fn format_value(v: &toml::Value) -> String {
    match v {
        toml::Value::Integer(i) => i.to_string(),
        toml::Value::Float(x) => format!("{x:?}"),
        toml::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// A value as a number, when it is one.
pub fn value_number(v: &toml::Value) -> Option<f64> {
    match v {
        toml::Value::Integer(i) => Some(*i as f64),
        toml::Value::Float(x) => Some(*x),
        _ => None,
    }
}

/// `key=value;key=value` for a list of settings (`defaults` when empty).
pub fn settings_label(settings: &[Setting]) -> String {
    if settings.is_empty() {
        "defaults".to_string()
    } else {
        settings
            .iter()
            .map(Setting::label)
            .collect::<Vec<_>>()
            .join(";")
    }
}

/// What the points are measured against.
#[derive(Debug, Clone, PartialEq)]
pub enum Reference {
    /// The checks' own expected values only (closed forms): no reference
    /// run, so no position, kinetic-energy or dissipation error.
    Exact,
    /// One run per case of a formulation at the case's settings with these
    /// overrides (none: the case's defaults).
    Run {
        /// The formulation.
        formulation: &'static str,
        /// Overrides of the case's settings.
        settings: Vec<Setting>,
    },
}

impl Reference {
    /// `exact`, or `formulation` with its overrides (`event-driven
    /// [contact.distance=1e-9]`).
    pub fn label(&self) -> String {
        match self {
            Reference::Exact => "exact".to_string(),
            Reference::Run {
                formulation,
                settings,
            } if settings.is_empty() => formulation.to_string(),
            Reference::Run {
                formulation,
                settings,
            } => format!("{formulation} [{}]", settings_label(settings)),
        }
    }
}

/// An error measure a plan asks for.
#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Measure {
    /// `position`: the largest RMS position difference from the reference
    /// run over the output times, relative to the median floe diameter.
    Position,
    /// `kinetic_final`: the relative error of the final kinetic energy.
    KineticFinal,
    /// `dissipated`: the relative error of the energy dissipated by contacts.
    Dissipated,
    /// `first_event`: the relative error of the time of the first contact
    /// event against the exact first impact of a bouncing case (the
    /// formulation's own event time, which the `bouncing_first_impact`
    /// check, measured by free flight to the face, does not see).
    FirstEvent,
    /// `checks`: every check with an expected value that applies.
    Checks,
    /// `check:<id>`: that check only.
    Check(String),
}

impl Measure {
    fn parse(s: &str) -> Result<Measure, String> {
        match s {
            "position" => Ok(Measure::Position),
            "kinetic_final" => Ok(Measure::KineticFinal),
            "dissipated" => Ok(Measure::Dissipated),
            "first_event" => Ok(Measure::FirstEvent),
            "checks" => Ok(Measure::Checks),
            other => match other.strip_prefix("check:") {
                Some(id)
                    if !id.is_empty()
                        && id.chars().all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_') =>
                {
                    Ok(Measure::Check(id.to_string()))
                }
                _ => Err(format!(
                    "unknown measure `{other}`; known: position, kinetic_final, dissipated, first_event, checks, check:<id>"
                )),
            },
        }
    }

    /// Whether it needs a reference run.
    fn needs_run(&self) -> bool {
        matches!(
            self,
            Measure::Position | Measure::KineticFinal | Measure::Dissipated
        )
    }

    /// Whether the metric `name` (as [`super::measures`] names them) is one
    /// of this measure's.
    pub fn selects(&self, name: &str) -> bool {
        match self {
            Measure::Position => name == "position",
            Measure::KineticFinal => name == "kinetic_final",
            Measure::Dissipated => name == "dissipated",
            Measure::FirstEvent => name == "first_event",
            Measure::Checks => name.starts_with("check:"),
            Measure::Check(id) => name.strip_prefix("check:") == Some(id.as_str()),
        }
    }
}

/// A case of the plan.
#[derive(Debug, Clone)]
pub struct PlanCase {
    /// The case file.
    pub path: PathBuf,
    /// The case file as written (each point's scenario is built from it).
    pub raw: toml::Table,
    /// The case at its own settings.
    pub scenario: Scenario,
    /// A digest of the case file's text (a point computed on other text is
    /// not reused).
    pub digest: u64,
}

/// One key of a grid and its values.
#[derive(Debug, Clone, PartialEq)]
pub struct GridKey {
    /// The key as written.
    pub key: String,
    /// Its values, in the order written.
    pub values: Vec<toml::Value>,
}

/// A `[[formulation]]` of the plan.
#[derive(Debug, Clone)]
pub struct PlanFormulation {
    /// The registry entry.
    pub entry: &'static Entry,
    /// The plan's cases it runs on (indices into [`Plan::cases`]).
    pub cases: Vec<usize>,
    /// The grid, keys in the order written; the points are every
    /// combination (the first key varies slowest).
    pub grid: Vec<GridKey>,
}

impl PlanFormulation {
    /// Every combination of the grid's values (one empty combination for an
    /// empty grid), the first key varying slowest.
    pub fn combinations(&self) -> Vec<Vec<Setting>> {
        product(self.grid.iter())
    }
}

/// Every combination of the values of `keys` (one empty combination for
/// no key), the first key varying slowest.
pub fn product<'a>(keys: impl Iterator<Item = &'a GridKey>) -> Vec<Vec<Setting>> {
    let mut out: Vec<Vec<Setting>> = vec![Vec::new()];
    for g in keys {
        out = out
            .into_iter()
            .flat_map(|head| {
                g.values.iter().map(move |v| {
                    let mut s = head.clone();
                    s.push(Setting {
                        key: g.key.clone(),
                        value: v.clone(),
                    });
                    s
                })
            })
            .collect();
    }
    out
}

/// A validated plan.
#[derive(Debug, Clone)]
pub struct Plan {
    /// The plan file.
    pub file: PathBuf,
    /// `[sweep] name`, or the file's stem: names the default output folder.
    pub name: String,
    /// The cases, in the order written (folders expanded to their `*.toml`).
    pub cases: Vec<PlanCase>,
    /// What the points are measured against.
    pub reference: Reference,
    /// The error measures reported (sweep.csv, orders, plots).
    pub measures: Vec<Measure>,
    /// The formulations with their grids, in the order written.
    pub formulations: Vec<PlanFormulation>,
    /// `[sweep] start`: the state every run starts from, if given.
    pub start: Option<Start>,
}

impl Plan {
    /// The scenario of case `case` with `settings` applied (see the module
    /// doc); the error is the case loader's message.
    pub fn scenario(
        &self,
        case: usize,
        table: Option<&str>,
        settings: &[Setting],
    ) -> Result<Scenario, String> {
        let c = &self.cases[case];
        if settings.is_empty() {
            return Ok(c.scenario.clone());
        }
        let mut scn = scenario_with(c, table, settings)?;
        if let Some(start) = &self.start {
            start.apply(&mut scn)?;
        }
        Ok(scn)
    }
}

/// The `[formulation.<table>]` an entry reads, if any.
pub fn table_of(entry: &Entry) -> Option<&'static str> {
    entry.settings.map(|t| t.name)
}

/// `case` with `settings` written into its file and read again.
fn scenario_with(
    case: &PlanCase,
    table: Option<&str>,
    settings: &[Setting],
) -> Result<Scenario, String> {
    let mut raw = case.raw.clone();
    for s in settings {
        let (section, key, value) = match s.key.as_str() {
            CONTACT_DISTANCE => ("contact", "distance", as_float(&s.value)),
            INTEGRATOR_TOLERANCE => ("integrator", "tolerance", as_float(&s.value)),
            key => match table {
                Some(_) => ("formulation", key, s.value.clone()),
                None => {
                    return Err(format!(
                        "`{key}`: this formulation reads no [formulation.*] table"
                    ))
                }
            },
        };
        let mut slot = raw
            .entry(section)
            .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        if section == "formulation" {
            let Some(t) = slot.as_table_mut() else {
                return Err("[formulation] is not a table".into());
            };
            slot = t
                .entry(table.unwrap_or_default())
                .or_insert_with(|| toml::Value::Table(toml::Table::new()));
        }
        match slot.as_table_mut() {
            Some(t) => {
                t.insert(key.to_string(), value);
            }
            None => return Err(format!("[{section}] is not a table")),
        }
    }
    let text = toml::to_string(&raw)
        .map_err(|e| format!("cannot write the case with the settings: {e}"))?;
    parse_case(&text, &case.path).map_err(|e| e.message)
}

/// An integer written for a float key, as the float (the case file's keys
/// `distance` and `tolerance` are floats).
fn as_float(v: &toml::Value) -> toml::Value {
    match v {
        toml::Value::Integer(i) => toml::Value::Float(*i as f64),
        other => other.clone(),
    }
}
