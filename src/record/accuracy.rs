//! The accuracy of a run's contact solves, beside their cost
//! (docs/physics.md §3.5): every contact problem a formulation solves, by
//! any solver, is recorded with the natural-map residual of its answer and
//! the work it took (Lemke pivots, interior-point iterations, Gauss–Seidel
//! sweeps or gradient iterations); the iterative solvers add whether they
//! stopped unconverged and how many of their contacts the cache started.
//!
//! Reported as counters (`summary.json`, `metrics.csv`): the median, 95th
//! percentile (nearest rank) and largest residual and iterations, the
//! count of unconverged solves and the warm-start hit rate.
//!
//! Two residuals are kept apart, because they answer two questions:
//! - **the law's** (`contact_residual_*`): the natural-map residual of the
//!   impulses applied on Signorini's condition and Coulomb's law with one
//!   friction pair per contact point, whatever solver gave them. It holds
//!   the solver's error *and* the departure of the problem it solved from
//!   that law: the cone relaxation's lift (clarabel, APGD: up to order 1 on
//!   a sliding contact), the merged friction of flush edge pairs (Lemke,
//!   `merge_friction`: of the order of the columns' 1e-3 difference);
//! - **the solver's** (`contact_solver_residual_max`,
//!   `contact_solver_missed`): the residual of the answer on the problem its
//!   solver solved (Lemke: the LCP's `‖min(z, w)‖/‖q‖`; clarabel and APGD:
//!   the cone relaxation's natural map; NSGS: Coulomb's law's), and the
//!   solves whose answer missed that solver's tolerance.

use super::counters::{Counter, Counters, Unit};

/// Contact solves recorded.
pub const CONTACT_SOLVES: Counter = Counter::sum(
    "contact_solves_measured",
    "contact problems whose answer's natural-map residual was measured",
);
/// Median residual.
pub const RESIDUAL_MEDIAN: Counter = Counter::value(
    "contact_residual_median",
    Unit::Dimensionless,
    "median natural-map residual (Coulomb form, relative to |q|) of the contact solves",
);
/// 95th percentile residual.
pub const RESIDUAL_P95: Counter = Counter::value(
    "contact_residual_p95",
    Unit::Dimensionless,
    "95th percentile of the natural-map residual of the contact solves",
);
/// Largest residual.
pub const RESIDUAL_MAX: Counter = Counter::value(
    "contact_residual_max",
    Unit::Dimensionless,
    "largest natural-map residual of the contact solves",
);
/// Largest residual of an answer on the problem its solver solved.
pub const SOLVER_RESIDUAL_MAX: Counter = Counter::value(
    "contact_solver_residual_max",
    Unit::Dimensionless,
    "largest residual of a contact answer on the problem its solver solved (Lemke: the LCP's |min(z, w)|/|q|, accepted at 1e-10; clarabel and APGD: the cone relaxation's natural map; NSGS: Coulomb's law's, at its tolerance): the solver's error",
);
/// Solves that missed their solver's tolerance.
pub const SOLVER_MISSED: Counter = Counter::sum(
    "contact_solver_missed",
    "contact solves whose answer missed its solver's tolerance (Lemke: no attempt accepted, a fallback answer applied; clarabel: not fully solved; NSGS, APGD: stopped by max_iterations)",
);
/// Median iterations.
pub const ITERATIONS_MEDIAN: Counter = Counter::value(
    "contact_iterations_median",
    Unit::Count,
    "median work of one contact solve: pivots (Lemke), interior-point iterations (clarabel), sweeps (nsgs), iterations (apgd)",
);
/// 95th percentile iterations.
pub const ITERATIONS_P95: Counter = Counter::value(
    "contact_iterations_p95",
    Unit::Count,
    "95th percentile of the work of one contact solve",
);
/// Most iterations.
pub const ITERATIONS_MAX: Counter = Counter::value(
    "contact_iterations_max",
    Unit::Count,
    "most work of one contact solve",
);
/// Iterative solves stopped by `max_iterations`.
pub const UNCONVERGED: Counter = Counter::sum(
    "contact_unconverged",
    "iterative contact solves stopped by max_iterations above their tolerance (answer kept)",
);
/// Warm-start hit rate.
pub const WARM_HIT_RATE: Counter = Counter::value(
    "contact_warm_hit_rate",
    Unit::Dimensionless,
    "fraction of the contacts of the iterative solves started from the contact cache",
);

/// See the module doc.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct Accuracy {
    residuals: Vec<f64>,
    iterations: Vec<f64>,
    solver_max: Option<f64>,
    missed: u64,
    iterative: bool,
    unconverged: u64,
    contacts: u64,
    warm_hits: u64,
}

/// The nearest-rank `q`-quantile of sorted `v` (`None` when empty).
fn quantile(v: &[f64], q: f64) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let rank = (q * v.len() as f64).ceil() as usize;
    Some(v[rank.clamp(1, v.len()) - 1])
}

impl Accuracy {
    /// Records a direct solve (Lemke, clarabel): its residual and work.
    pub fn direct(&mut self, residual: f64, iterations: u64) {
        self.residuals.push(residual);
        self.iterations.push(iterations as f64);
    }

    /// Records the solver's side of the last solve: the residual of its
    /// answer on the problem the solver solved, and whether it met the
    /// solver's tolerance (the module doc).
    pub fn solver(&mut self, residual: f64, met: bool) {
        self.solver_max = Some(self.solver_max.map_or(residual, |m| m.max(residual)));
        self.missed += u64::from(!met);
    }

    /// Records an iterative solve of `contacts` contacts, `warm_hits` of
    /// them started from the cache.
    pub fn iterative(
        &mut self,
        residual: f64,
        iterations: u64,
        converged: bool,
        contacts: usize,
        warm_hits: usize,
    ) {
        self.iterative = true;
        self.direct(residual, iterations);
        self.unconverged += u64::from(!converged);
        self.contacts += contacts as u64;
        self.warm_hits += warm_hits as u64;
    }

    /// The counters of the module doc (the unconverged count and hit rate
    /// only when an iterative solve was recorded; the figures unset when no
    /// solve was).
    pub fn counters(&self) -> Counters {
        let mut c = Counters::new(&[&CONTACT_SOLVES]);
        c.add(&CONTACT_SOLVES, self.residuals.len() as u64);
        let sorted = |v: &[f64]| {
            let mut s = v.to_vec();
            s.sort_by(|a, b| a.total_cmp(b));
            s
        };
        for (v, [median, p95, max]) in [
            (
                sorted(&self.residuals),
                [&RESIDUAL_MEDIAN, &RESIDUAL_P95, &RESIDUAL_MAX],
            ),
            (
                sorted(&self.iterations),
                [&ITERATIONS_MEDIAN, &ITERATIONS_P95, &ITERATIONS_MAX],
            ),
        ] {
            for (counter, q) in [(median, 0.5), (p95, 0.95), (max, 1.0)] {
                match quantile(&v, q) {
                    Some(x) => c.set(counter, x),
                    None => c.declare(&[counter]),
                }
            }
        }
        if let Some(m) = self.solver_max {
            c.set(&SOLVER_RESIDUAL_MAX, m);
            c.add(&SOLVER_MISSED, self.missed);
        }
        if self.iterative {
            c.add(&UNCONVERGED, self.unconverged);
            if self.contacts > 0 {
                c.set(&WARM_HIT_RATE, self.warm_hits as f64 / self.contacts as f64);
            }
        }
        c
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantiles_are_nearest_rank() {
        let v: Vec<f64> = (1..=20).map(f64::from).collect();
        assert_eq!(quantile(&v, 0.5), Some(10.0));
        assert_eq!(quantile(&v, 0.95), Some(19.0));
        assert_eq!(quantile(&v, 1.0), Some(20.0));
        assert_eq!(quantile(&[], 0.5), None);
        assert_eq!(quantile(&[3.0], 0.95), Some(3.0));
    }

    #[test]
    fn iterative_solves_add_the_unconverged_count_and_hit_rate() {
        let mut a = Accuracy::default();
        a.direct(1e-12, 7);
        assert!(a.counters().by_name("contact_unconverged").is_err());
        a.iterative(1e-3, 100, false, 4, 1);
        a.iterative(1e-7, 3, true, 4, 3);
        let c = a.counters();
        assert_eq!(c.by_name("contact_solves_measured"), Ok(Some(3.0)));
        assert_eq!(c.by_name("contact_unconverged"), Ok(Some(1.0)));
        assert_eq!(c.by_name("contact_warm_hit_rate"), Ok(Some(0.5)));
        assert_eq!(c.by_name("contact_residual_max"), Ok(Some(1e-3)));
        assert_eq!(c.by_name("contact_iterations_median"), Ok(Some(7.0)));
    }
}
