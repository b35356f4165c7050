//! The floe-size distribution of a fracture case (docs/physics.md §9.7):
//! the number of floes of area at least `A` against `A` (a complementary
//! cumulative count), of the initial floes and of the floes alive at the
//! end of every run. `compare` writes it as `floe_sizes.csv` and draws it
//! log–log as `floe_sizes.png/.svg`.

use crate::model::Scenario;
use crate::run::RunResult;

/// Areas that agree to this relative difference are one size: the pieces
/// of one floe halved carry the rounding of the polygon formulas (about
/// 1e-15 relative), which would otherwise read as two sizes.
pub const SAME_AREA: f64 = 1e-9;

/// When a distribution is taken.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum When {
    /// The case's initial floes (the same for every formulation).
    Start,
    /// The floes alive at the end of a run (where it stopped, if it did
    /// not complete).
    End,
}

impl When {
    /// The `when` column of `floe_sizes.csv`: `start` or `end`.
    pub fn name(self) -> &'static str {
        match self {
            When::Start => "start",
            When::End => "end",
        }
    }
}

/// One distribution: `points[k] = (A_k, N_k)`, `A_k` ascending (m²), `N_k`
/// the number of floes of area at least `A_k`.
#[derive(Debug, Clone, PartialEq)]
pub struct FloeSizes {
    /// The run's formulation; empty for [`When::Start`] (every run starts
    /// from the case's floes).
    pub formulation: String,
    /// Start or end.
    pub when: When,
    /// `(area m², count of floes with at least that area)`, area ascending.
    pub points: Vec<(f64, usize)>,
}

/// The complementary cumulative count of `areas` (m²): for each distinct
/// area `A` (areas within [`SAME_AREA`] relative of the smallest of a run
/// of near-equal ones are one, reported as that smallest), the number of
/// areas `≥ A`; ascending in `A`, so the counts decrease from the total.
/// Non-finite areas are left out.
pub fn count_at_least(areas: impl IntoIterator<Item = f64>) -> Vec<(f64, usize)> {
    let mut a: Vec<f64> = areas.into_iter().filter(|v| v.is_finite()).collect();
    a.sort_by(f64::total_cmp);
    let n = a.len();
    let mut out: Vec<(f64, usize)> = Vec::new();
    for (k, &v) in a.iter().enumerate() {
        match out.last() {
            Some(&(first, _)) if v - first <= SAME_AREA * first.abs() => {}
            _ => out.push((v, n - k)),
        }
    }
    out
}

/// The distributions of a case and its runs: the initial floes, then each
/// run's floes alive at its end, in the order of `runs`. Empty unless the
/// case can break floes (a `[fracture]` model other than `none`) or a run
/// broke one.
pub fn floe_sizes(scn: &Scenario, runs: &[RunResult]) -> Vec<FloeSizes> {
    if !scn.fracture.enabled() && runs.iter().all(|r| r.fractures.is_empty()) {
        return Vec::new();
    }
    let mut out = vec![FloeSizes {
        formulation: String::new(),
        when: When::Start,
        points: count_at_least(scn.floes.iter().map(|f| f.area)),
    }];
    out.extend(runs.iter().map(|r| FloeSizes {
        formulation: r.summary.formulation.clone(),
        when: When::End,
        points: count_at_least(r.floes.iter().filter(|f| f.t_end.is_none()).map(|f| f.area)),
    }));
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_at_least_merge_rounding_and_decrease_from_the_total() {
        let c = count_at_least([50.0, 100.0, 50.0 * (1.0 + 1e-15), 20.0, f64::NAN]);
        assert_eq!(c, vec![(20.0, 4), (50.0, 3), (100.0, 1)]);
        assert!(count_at_least([]).is_empty());
    }
}
