//! The `[[formulation]]` tables of a plan: which keys may be swept, and
//! each grid's values checked against the cases (docs/sweep-format.md).

use super::spec::{lexical, At, FormulationSpec};
use super::*;
use crate::formulation::{self, Entry};
use crate::model::CaseError;
use crate::run::batch::case_files;
use std::ops::Range;
use std::path::Path;
use toml::Spanned;

/// Whether `key` may be swept for `entry` (the formulation's own table keys
/// are checked by its parser when a value is applied).
pub(super) fn check_key(entry: &Entry, key: &str) -> Result<(), String> {
    if key == CONTACT_DISTANCE || key == INTEGRATOR_TOLERANCE {
        return Ok(());
    }
    if key.contains('.') {
        return Err(format!(
            "unknown key `{key}`: the case keys that may be swept are {CONTACT_DISTANCE} and {INTEGRATOR_TOLERANCE}"
        ));
    }
    match table_of(entry) {
        Some(_) => Ok(()),
        None => Err(format!(
            "`{key}`: {} reads no [formulation.*] table; it may sweep {CONTACT_DISTANCE} and {INTEGRATOR_TOLERANCE}",
            entry.name
        )),
    }
}

pub(super) fn plan_formulation(
    at: &At,
    k: usize,
    spec: &Spanned<FormulationSpec>,
    plan_cases: &Spanned<Vec<Spanned<String>>>,
    cases: &[PlanCase],
) -> Result<PlanFormulation, CaseError> {
    let f = spec.get_ref();
    let label = format!("[[formulation]] #{k}");
    let entry = formulation::entry(f.name.get_ref())
        .map_err(|e| at.err(Some(&f.name.span()), format!("{label}: name: {e}")))?;
    let label = format!("{label} ({})", entry.name);
    // The cases: a subset of the plan's, written as there; by default every
    // case of the plan the formulation applies to.
    let chosen: Vec<usize> = match &f.cases {
        None => (0..cases.len())
            .filter(|&c| entry.applies(&cases[c].scenario))
            .collect(),
        Some(list) => {
            let base = at.file.parent().unwrap_or_else(|| Path::new(""));
            let mut chosen = Vec::new();
            for p in list {
                let here = |m: String| {
                    at.err(
                        Some(&p.span()),
                        format!("{label}: cases: \"{}\": {m}", p.get_ref()),
                    )
                };
                if !plan_cases
                    .get_ref()
                    .iter()
                    .any(|q| q.get_ref() == p.get_ref())
                {
                    return Err(here("not one of [sweep] cases (write it as there)".into()));
                }
                let files = case_files(&[lexical(&base.join(p.get_ref()))])
                    .map_err(|e| here(e.to_string()))?;
                for path in files {
                    let Some(c) = cases.iter().position(|c| c.path == path) else {
                        return Err(here(format!(
                            "{} is not a case of the plan",
                            path.display()
                        )));
                    };
                    if !entry.applies(&cases[c].scenario) {
                        return Err(here(format!(
                            "{} ignores contacts and {} has obstacles or moving floes",
                            entry.name,
                            path.display()
                        )));
                    }
                    if !chosen.contains(&c) {
                        chosen.push(c);
                    }
                }
            }
            chosen
        }
    };
    if chosen.is_empty() {
        return Err(at.err(
            Some(&f.name.span()),
            format!("{label}: applies to none of the plan's cases (it ignores contacts)"),
        ));
    }
    // The grid, keys in the order written.
    let mut keys: Vec<(&String, &Spanned<Vec<Spanned<toml::Value>>>)> = f.grid.iter().collect();
    keys.sort_by_key(|(_, v)| v.span().start);
    // Each other key at its first value: a value that a case refuses alone
    // may need another key of the grid (`tolerance` with `solver =
    // "nsgs"`).
    let firsts: Vec<Setting> = keys
        .iter()
        .filter_map(|(key, values)| {
            let v = values.get_ref().first()?;
            Some(Setting {
                key: (*key).clone(),
                value: v.get_ref().clone(),
            })
        })
        .collect();
    let mut grid = Vec::new();
    for &(key, values) in &keys {
        let here = |span: &Range<usize>, m: String| {
            at.err(Some(span), format!("{label}: grid {key}: {m}"))
        };
        check_key(entry, key).map_err(|m| here(&values.span(), m))?;
        if values.get_ref().is_empty() {
            return Err(here(&values.span(), "no value".into()));
        }
        let mut seen: Vec<toml::Value> = Vec::new();
        for v in values.get_ref() {
            let value = v.get_ref().clone();
            if seen.contains(&value) {
                return Err(here(
                    &v.span(),
                    format!("{} is listed twice", format_value(&value)),
                ));
            }
            let setting = [Setting {
                key: key.clone(),
                value: value.clone(),
            }];
            let mut with_others: Vec<Setting> =
                firsts.iter().filter(|s| &s.key != key).cloned().collect();
            with_others.extend(setting.iter().cloned());
            for &c in &chosen {
                let checked = scenario_with(&cases[c], table_of(entry), &setting)
                    .map(|_| ())
                    .or_else(|e| {
                        // Accepted beside the others' first values: every
                        // combination is checked below, with its label.
                        let others = scenario_with(&cases[c], table_of(entry), &with_others);
                        if with_others.len() > 1 && others.is_ok() {
                            Ok(())
                        } else {
                            Err(e)
                        }
                    });
                checked.map_err(|e| {
                    here(
                        &v.span(),
                        format!(
                            "{} on {}: {e}",
                            format_value(&value),
                            cases[c].path.display()
                        ),
                    )
                })?;
            }
            seen.push(value);
        }
        grid.push(GridKey {
            key: key.clone(),
            values: seen,
        });
    }
    Ok(PlanFormulation {
        entry,
        cases: chosen,
        grid,
    })
}
