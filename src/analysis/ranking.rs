//! Ranking formulations by a figure, with ties: by their error to an exact
//! answer (the checks), by the energy they dissipate, by CPU time. What is
//! a tie depends on the figure: within rounding for deterministic physics
//! ([`ROUNDING`] of the figure's scale), overlapping spreads for a measured
//! time ([`crate::record::spread::Spread::overlaps`]).

use super::check::CheckOutcome;

/// Two physics figures closer than this fraction of their scale are tied:
/// different schemes reach the same exact answer only to rounding, and an
/// LCP is accepted at a residual of 1e-10 of the velocities; the checks'
/// tightest tolerances are 1e-9 of their scale for the same reason.
pub const ROUNDING: f64 = 1e-9;

/// Items grouped by rank: ascending `value`, consecutive items tied with
/// the first of their group when `tied(first, item)`; non-finite values
/// last, each alone.
pub fn rank<T: Clone>(
    items: &[T],
    value: impl Fn(&T) -> f64,
    tied: impl Fn(&T, &T) -> bool,
) -> Vec<Vec<T>> {
    let mut sorted: Vec<T> = items.to_vec();
    sorted.sort_by(|a, b| value(a).total_cmp(&value(b)));
    let mut groups: Vec<Vec<T>> = Vec::new();
    for it in sorted {
        match groups.last_mut() {
            Some(g) if value(&g[0]).is_finite() && value(&it).is_finite() && tied(&g[0], &it) => {
                g.push(it)
            }
            _ => groups.push(vec![it]),
        }
    }
    groups
}

/// Whether two physics figures `a` and `b` are equal within rounding of `scale`.
pub fn within_rounding(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= ROUNDING * scale.abs()
}

/// The ranking of the formulations on one check with an exact answer.
#[derive(Debug, Clone, PartialEq)]
pub struct CheckRanking {
    /// The check id.
    pub check: String,
    /// Its unit.
    pub unit: String,
    /// The exact answer, if a value.
    pub expected: Option<f64>,
    /// The scale of the answer.
    pub scale: f64,
    /// The tolerance.
    pub tolerance: f64,
    /// `(formulation, error, pass)` grouped by rank, best first; a
    /// formulation with several rows of the check (one per floe) counts
    /// with its largest error.
    pub groups: Vec<Vec<(String, f64, bool)>>,
}

/// The rankings of `formulations` on every check of `outcomes` that has an
/// exact answer ([`CheckOutcome::scale`]), in the order the checks first
/// appear.
pub fn rank_checks(outcomes: &[CheckOutcome], formulations: &[String]) -> Vec<CheckRanking> {
    let mut ids: Vec<&str> = Vec::new();
    for o in outcomes.iter().filter(|o| o.scale.is_some()) {
        if !ids.contains(&o.check.as_str()) {
            ids.push(&o.check);
        }
    }
    ids.into_iter()
        .filter_map(|id| {
            let mine: Vec<&CheckOutcome> = outcomes.iter().filter(|o| o.check == id).collect();
            let first = mine.first()?;
            let scale = mine.iter().filter_map(|o| o.scale).fold(0.0, f64::max);
            let items: Vec<(String, f64, bool)> = formulations
                .iter()
                .filter_map(|f| {
                    let rows: Vec<&&CheckOutcome> =
                        mine.iter().filter(|o| &o.formulation == f).collect();
                    if rows.is_empty() {
                        return None;
                    }
                    let err = rows.iter().map(|o| o.error()).fold(0.0, f64::max);
                    Some((f.clone(), err, rows.iter().all(|o| o.pass)))
                })
                .collect();
            Some(CheckRanking {
                check: id.to_string(),
                unit: first.unit.clone(),
                expected: first.expected,
                scale,
                tolerance: first.tolerance,
                groups: rank(&items, |i| i.1, |a, b| within_rounding(a.1, b.1, scale)),
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ties_are_grouped() {
        let items = [("a", 3.0), ("b", 1.0), ("c", 1.0 + 1e-12), ("d", f64::NAN)];
        let g = rank(&items, |i| i.1, |x, y| within_rounding(x.1, y.1, 1.0));
        let names: Vec<Vec<&str>> = g.iter().map(|g| g.iter().map(|i| i.0).collect()).collect();
        assert_eq!(names, vec![vec!["b", "c"], vec!["a"], vec!["d"]]);
    }
}
