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

use super::start::{Start, StartSpec};
use crate::formulation::{self, parse_case, Entry};
use crate::model::{CaseError, Scenario};
use crate::run::batch::case_files;
use grid::{check_key, plan_formulation};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::ops::Range;
use std::path::{Path, PathBuf};
use toml::Spanned;

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
    /// run over the output times, relative to the mean floe diameter.
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

// ---------------------------------------------------------------------------
// The file as written.

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct PlanFile {
    sweep: Spanned<SweepSpec>,
    #[serde(default)]
    formulation: Vec<Spanned<FormulationSpec>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SweepSpec {
    #[allow(dead_code)] // checked on the raw table before typed parsing
    version: i64,
    name: Option<Spanned<String>>,
    cases: Spanned<Vec<Spanned<String>>>,
    reference: Spanned<toml::Value>,
    measures: Option<Spanned<Vec<Spanned<String>>>>,
    start: Option<Spanned<StartSpec>>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FormulationSpec {
    name: Spanned<String>,
    cases: Option<Vec<Spanned<String>>>,
    #[serde(default)]
    grid: BTreeMap<String, Spanned<Vec<Spanned<toml::Value>>>>,
}

/// Where errors point: the plan file and its text.
struct At<'a> {
    file: &'a Path,
    text: &'a str,
}

impl At<'_> {
    fn line(&self, span: &Range<usize>) -> usize {
        let end = span.start.min(self.text.len());
        1 + self.text[..end].matches('\n').count()
    }

    fn err(&self, span: Option<&Range<usize>>, message: impl Into<String>) -> CaseError {
        CaseError {
            file: self.file.to_path_buf(),
            line: span.map(|s| self.line(s)),
            message: message.into(),
        }
    }
}

/// Reads and validates a plan file (see the module doc).
pub fn load_plan(path: &Path) -> Result<Plan, CaseError> {
    let text = std::fs::read_to_string(path).map_err(|e| CaseError {
        file: path.to_path_buf(),
        line: None,
        message: format!("cannot read the plan: {e}"),
    })?;
    parse_plan(&text, path)
}

/// [`load_plan`] on plan text; `file` names it in messages and is the base
/// of the relative case paths.
pub fn parse_plan(text: &str, file: &Path) -> Result<Plan, CaseError> {
    let at = At { file, text };
    let raw: toml::Table =
        toml::from_str(text).map_err(|e| at.err(e.span().as_ref(), e.message().trim_end()))?;
    check_version(&at, &raw)?;
    let spec: PlanFile = toml::from_str(text).map_err(|e| {
        let hint = if nested_grid_key(&raw) {
            " (a dotted grid key is written in quotes: \"contact.distance\" = [...])"
        } else {
            ""
        };
        at.err(
            e.span().as_ref(),
            format!("{}{hint}", e.message().trim_end()),
        )
    })?;
    let sweep_span = spec.sweep.span();
    let sweep = spec.sweep.into_inner();

    let name = match &sweep.name {
        Some(n) => {
            let ok = !n.get_ref().is_empty()
                && n.get_ref()
                    .chars()
                    .all(|c| c.is_ascii_lowercase() || c.is_ascii_digit() || c == '_' || c == '-');
            if !ok {
                return Err(at.err(
                    Some(&n.span()),
                    format!(
                        "[sweep] name = \"{}\" must be [a-z0-9_-]+ (it names the output folder)",
                        n.get_ref()
                    ),
                ));
            }
            n.get_ref().clone()
        }
        None => file
            .file_stem()
            .map_or_else(|| "sweep".to_string(), |s| s.to_string_lossy().into_owned()),
    };

    let start = match &sweep.start {
        Some(spec) => {
            let base = file.parent().unwrap_or_else(|| Path::new(""));
            let st = Start::read(spec.get_ref(), base)
                .map_err(|m| at.err(Some(&spec.span()), format!("[sweep] start: {m}")))?;
            Some((st, spec.span()))
        }
        None => None,
    };
    let mut cases = load_plan_cases(&at, &sweep.cases)?;
    if let Some((st, span)) = &start {
        for c in &mut cases {
            st.apply(&mut c.scenario).map_err(|m| {
                at.err(
                    Some(span),
                    format!("[sweep] start on {}: {m}", c.path.display()),
                )
            })?;
            c.digest = super::digest(format!("{:016x} {}", c.digest, st.label()).as_bytes());
        }
    }
    let start = start.map(|(st, _)| st);
    let reference = reference(&at, &sweep.reference, &cases)?;
    let measures = measures(&at, sweep.measures.as_ref(), &reference)?;

    if spec.formulation.is_empty() {
        return Err(at.err(
            Some(&sweep_span),
            "no [[formulation]] table: a plan sweeps at least one formulation",
        ));
    }
    let mut formulations = Vec::new();
    for (k, f) in spec.formulation.iter().enumerate() {
        formulations.push(plan_formulation(&at, k, f, &sweep.cases, &cases)?);
    }
    let plan = Plan {
        file: file.to_path_buf(),
        name,
        cases,
        reference,
        measures,
        formulations,
        start,
    };
    // Every combination must load (a combination of valid values may still
    // break a rule of the case); reported at the formulation's name.
    for (k, (f, spec)) in plan.formulations.iter().zip(&spec.formulation).enumerate() {
        for &c in &f.cases {
            for s in f.combinations().iter().filter(|s| s.len() > 1) {
                plan.scenario(c, table_of(f.entry), s).map_err(|e| {
                    at.err(
                        Some(&spec.get_ref().name.span()),
                        format!(
                            "[[formulation]] #{k} ({}): the combination {} on {}: {e}",
                            f.entry.name,
                            settings_label(s),
                            plan.cases[c].path.display()
                        ),
                    )
                })?;
            }
        }
    }
    Ok(plan)
}

/// Whether a grid holds a table (an unquoted dotted key such as
/// `contact.distance = [...]` is a nested table in TOML).
fn nested_grid_key(raw: &toml::Table) -> bool {
    raw.get("formulation")
        .and_then(|f| f.as_array())
        .into_iter()
        .flatten()
        .filter_map(|f| f.get("grid").and_then(|g| g.as_table()))
        .any(|g| g.values().any(|v| v.is_table()))
}

fn check_version(at: &At, raw: &toml::Table) -> Result<(), CaseError> {
    let Some(header) = raw.get("sweep").and_then(|v| v.as_table()) else {
        return Err(at.err(
            None,
            "missing [sweep] table (with version = 1, cases, reference)",
        ));
    };
    match header.get("version") {
        Some(toml::Value::Integer(VERSION)) => Ok(()),
        None => Err(at.err(
            None,
            "missing key `version` in [sweep]; this reader knows version = 1",
        )),
        Some(v) => {
            let line = at
                .text
                .lines()
                .position(|l| l.trim_start().starts_with("version"))
                .map(|i| i + 1);
            Err(CaseError {
                file: at.file.to_path_buf(),
                line,
                message: format!(
                    "[sweep] version = {v} is not supported; this reader knows version = 1"
                ),
            })
        }
    }
}

/// `path` with its `.` and `dir/..` components taken out, without reading
/// the file system (so messages name `cases/x.toml`, not
/// `plans/../cases/x.toml`).
fn lexical(path: &Path) -> PathBuf {
    use std::path::Component;
    let mut out = PathBuf::new();
    for c in path.components() {
        match c {
            Component::CurDir => {}
            Component::ParentDir
                if matches!(out.components().next_back(), Some(Component::Normal(_))) =>
            {
                out.pop();
            }
            other => out.push(other),
        }
    }
    out
}

/// The cases of `[sweep] cases`, relative to the plan (folders expanded).
fn load_plan_cases(
    at: &At,
    list: &Spanned<Vec<Spanned<String>>>,
) -> Result<Vec<PlanCase>, CaseError> {
    if list.get_ref().is_empty() {
        return Err(at.err(
            Some(&list.span()),
            "[sweep] cases is empty: name at least one case file",
        ));
    }
    let base = at.file.parent().unwrap_or_else(|| Path::new(""));
    let mut cases: Vec<PlanCase> = Vec::new();
    for p in list.get_ref() {
        let here = |m: String| {
            at.err(
                Some(&p.span()),
                format!("[sweep] cases: \"{}\": {m}", p.get_ref()),
            )
        };
        let files =
            case_files(&[lexical(&base.join(p.get_ref()))]).map_err(|e| here(e.to_string()))?;
        for path in files {
            let text = std::fs::read_to_string(&path).map_err(|e| {
                here(format!(
                    "{}: cannot read the case file: {e}",
                    path.display()
                ))
            })?;
            let scenario = parse_case(&text, &path).map_err(|e| here(e.to_string()))?;
            let raw: toml::Table = toml::from_str(&text).map_err(|e| here(e.to_string()))?;
            if let Some(other) = cases.iter().find(|c| c.scenario.name == scenario.name) {
                return Err(here(format!(
                    "two cases are named `{}` ({} and {}): their results would mix",
                    scenario.name,
                    other.path.display(),
                    path.display()
                )));
            }
            cases.push(PlanCase {
                digest: super::digest(text.as_bytes()),
                path,
                raw,
                scenario,
            });
        }
    }
    Ok(cases)
}

/// `[sweep] reference`: `"exact"`, a formulation name, or
/// `{ formulation = "...", settings = { key = value, ... } }`.
fn reference(
    at: &At,
    spec: &Spanned<toml::Value>,
    cases: &[PlanCase],
) -> Result<Reference, CaseError> {
    let span = spec.span();
    let err = |m: String| at.err(Some(&span), format!("[sweep] reference: {m}"));
    let (name, settings) = match spec.get_ref() {
        toml::Value::String(s) if s == "exact" => return Ok(Reference::Exact),
        toml::Value::String(s) => (s.clone(), toml::Table::new()),
        toml::Value::Table(t) => {
            if let Some(k) = t.keys().find(|k| *k != "formulation" && *k != "settings") {
                return Err(err(format!("unknown key `{k}`; known: formulation, settings")));
            }
            let Some(toml::Value::String(name)) = t.get("formulation") else {
                return Err(err("a table needs `formulation = \"<name>\"`".into()));
            };
            let settings = match t.get("settings") {
                None => toml::Table::new(),
                Some(toml::Value::Table(s)) => s.clone(),
                Some(other) => return Err(err(format!("settings = {other} must be a table of key = value"))),
            };
            (name.clone(), settings)
        }
        other => {
            return Err(err(format!(
                "{other} must be \"exact\", a formulation name, or {{ formulation = \"...\", settings = {{ ... }} }}"
            )))
        }
    };
    let entry = formulation::entry(&name).map_err(&err)?;
    let settings: Vec<Setting> = settings
        .into_iter()
        .map(|(key, value)| Setting { key, value })
        .collect();
    for (c, case) in cases.iter().enumerate() {
        if !entry.applies(&case.scenario) {
            return Err(err(format!(
                "{} does not apply to {} (it ignores contacts and the case has obstacles or moving floes)",
                entry.name,
                case.path.display()
            )));
        }
        for s in &settings {
            check_key(entry, &s.key).map_err(&err)?;
        }
        scenario_with(&cases[c], table_of(entry), &settings).map_err(|e| {
            err(format!(
                "settings {}: {}: {e}",
                settings_label(&settings),
                case.path.display()
            ))
        })?;
    }
    Ok(Reference::Run {
        formulation: entry.name,
        settings,
    })
}

fn measures(
    at: &At,
    spec: Option<&Spanned<Vec<Spanned<String>>>>,
    reference: &Reference,
) -> Result<Vec<Measure>, CaseError> {
    let Some(list) = spec else {
        return Ok(match reference {
            Reference::Exact => vec![Measure::Checks],
            Reference::Run { .. } => vec![
                Measure::Position,
                Measure::KineticFinal,
                Measure::Dissipated,
                Measure::Checks,
            ],
        });
    };
    if list.get_ref().is_empty() {
        return Err(at.err(
            Some(&list.span()),
            "[sweep] measures is empty (leave it out for every measure)",
        ));
    }
    let mut out = Vec::new();
    for m in list.get_ref() {
        let here = |msg: String| at.err(Some(&m.span()), format!("[sweep] measures: {msg}"));
        let measure = Measure::parse(m.get_ref()).map_err(here)?;
        if measure.needs_run() && *reference == Reference::Exact {
            return Err(here(format!(
                "`{}` needs a reference run; reference = \"exact\" gives the checks only",
                m.get_ref()
            )));
        }
        if out.contains(&measure) {
            return Err(here(format!("`{}` is listed twice", m.get_ref())));
        }
        out.push(measure);
    }
    Ok(out)
}
