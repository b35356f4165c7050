//! Reading a plan file: [`load_plan`] and [`parse_plan`] check
//! `[sweep]` (its version, name, start, cases, reference and measures),
//! then each `[[formulation]]` (`grid.rs`) and every combination.

use super::grid::{check_key, plan_formulation};
use super::spec::{lexical, At, PlanFile};
use super::{
    scenario_with, settings_label, table_of, Measure, Plan, PlanCase, Reference, Setting, VERSION,
};
use crate::formulation::{self, parse_case};
use crate::model::CaseError;
use crate::run::batch::case_files;
use crate::sweep::start::Start;
use std::path::Path;
use toml::Spanned;

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
