//! What a formulation refuses in a case when it is built, checked at
//! validation too ([`crate::formulation::Entry::check`]): the one function
//! per formulation that its builder, `floebench validate`
//! ([`validate_case`]) and the batch before any run all call, so that a
//! case is refused once, naming the file, the line and the key.

use super::{grid_index, load_case, REGISTRY};
use crate::model::{limits, CaseError, Scenario, SettingsTable};
use std::path::Path;

/// A formulation's check of a case ([`crate::formulation::Entry::check`]).
pub type Check = fn(&Scenario) -> Result<(), CaseError>;

/// Whether `value` (s) is a whole positive number of steps `h` (s), to
/// rounding.
fn on_grid(h: f64, value: f64) -> bool {
    grid_index(0.0, h, value).is_some_and(|j| j > 0)
}

/// The largest `h / k` (k = 1 … 1000) on whose grid both the output
/// interval `a` and the duration `b` (s) lie, within the limits of a step
/// ([`limits::STEP`], [`limits::STEPS`] over `b`), if any: a step to
/// suggest.
fn fitting_step(h: f64, a: f64, b: f64) -> Option<f64> {
    (1..=1000u32)
        .map(|k| h / f64::from(k))
        .take_while(|&c| limits::STEP.admits(c) && limits::STEPS.admits(limits::output_count(b, c)))
        .find(|&c| on_grid(c, a) && on_grid(c, b))
}

/// Refuses a case whose output times (`k × output_interval` and the
/// duration) are not on the grid `t_k = k h` of the fixed step `h` (s) of
/// formulation `what`, read from `key` of its settings `table`: the
/// fixed-step schemes report only states of their own grid. The error is
/// at the line of `key` when the case writes it, else at the line of the
/// `[case]` key that is off the grid, and says which step would do.
pub fn check_output_grid(
    scn: &Scenario,
    what: &str,
    table: &SettingsTable,
    key: &str,
    h: f64,
) -> Result<(), CaseError> {
    let Some((name, value)) = [
        ("output_interval", scn.output_interval),
        ("duration", scn.duration),
    ]
    .into_iter()
    .find(|&(_, v)| !on_grid(h, v)) else {
        return Ok(());
    };
    let written = table.values.contains_key(key);
    let hint = match fitting_step(h, scn.output_interval, scn.duration) {
        Some(c) => format!("{key} = {c} would do"),
        None => format!("choose a {key} that divides both output_interval and duration"),
    };
    let message = format!(
        "{what}: {name} = {value} s is not a multiple of its step {h} s ([formulation.{}] {key}{}): a fixed-step scheme reports only the states of its own grid (docs/case-format.md \"Output times\"); {hint}, or an output_interval and a duration that are multiples of {h} s",
        table.name,
        if written { "" } else { ", the default" }
    );
    Err(if written {
        table.error(Some(key), message)
    } else {
        scn.source.case_error(name, message)
    })
}

/// Every check that the formulations that apply to `scn`
/// ([`Entry::applies`]) make when they are built ([`Entry::check`]), the
/// first refusal as the error.
pub fn check_formulations(scn: &Scenario) -> Result<(), CaseError> {
    REGISTRY
        .iter()
        .filter(|e| e.applies(scn))
        .filter_map(|e| e.check)
        .try_for_each(|check| check(scn))
}

/// [`load_case`], then [`check_formulations`]: a case every formulation
/// that applies to it accepts (`floebench validate`, docs/case-format.md).
pub fn validate_case(path: &Path) -> Result<Scenario, CaseError> {
    let scn = load_case(path)?;
    check_formulations(&scn)?;
    Ok(scn)
}
