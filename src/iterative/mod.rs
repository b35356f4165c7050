//! Iterative contact solvers for dense packs (docs/physics.md §3.5):
//! nonsmooth Gauss–Seidel on Coulomb's law ([`nsgs`], `solver = "nsgs"`)
//! and accelerated projected gradient descent on the Anitescu–Tasora cone
//! relaxation ([`apgd`], `solver = "apgd"`), on the sparse contact problem
//! of a group ([`SparseContacts`]: no `m × m` matrix is ever formed) or on
//! any other problem given by its Delassus operator ([`Delassus`]: a Siconos
//! file's `W`, [`Fc2dOperator`]),
//! warm-started from the contact cache ([`ContactCache`]) and stopped on
//! the natural-map residual ([`SparseContacts::residual`]), the one
//! accuracy measure that is also computed for the Lemke and clarabel
//! answers.
//!
//! # Scheme
//!
//! For a group of `m` contacts with impulses `p_j = (λ_j, β_j)` (N·s) and
//! relative velocities `u = W p + q` (`W = HᵀM⁻¹H`, applied through the
//! floes' velocities), find `p` with, at every contact, Signorini's
//! condition with the formulation's offset and Coulomb's law (NSGS), or the
//! cone complementarity `K ∋ p ⟂ u ∈ K*` of the relaxation (APGD). Each
//! solve starts from the cache's impulses of the same contacts, rescaled to
//! the new step (`p = f h`, `f` the cached mean force), or from zero.
//!
//! # Parameters (`[formulation.moreau]`, `[formulation.event-driven]`)
//!
//! | key | unit | default | meaning |
//! | --- | --- | --- | --- |
//! | `solver` | – | `"lcp"` | `"nsgs"` or `"apgd"` select these solvers |
//! | `tolerance` | – | [`DEFAULT_TOLERANCE`] | relative natural-map residual at which a solve stops |
//! | `max_iterations` | – | [`DEFAULT_MAX_ITERATIONS`] | sweeps (NSGS) or iterations (APGD) at most |
//! | `relaxation` | – | 1.0 | NSGS over-relaxation ω (1: Gauss–Seidel) |
//!
//! # References
//!
//! - M. Jean (1999), *The non-smooth contact dynamics method*, CMAME 177,
//!   235–257 (NSGS, LMGC90's NLGS).
//! - V. Acary, M. Brémond, O. Huber (2018), *On solving contact problems
//!   with Coulomb friction: formulations and numerical comparisons*, in
//!   Advanced Topics in Nonsmooth Dynamics, Springer (the natural-map
//!   residual, NSGS with an exact local solver, warm start).
//! - H. Mazhar, T. Heyn, D. Negrut, A. Tasora (2015), *Using Nesterov's
//!   method to accelerate multibody dynamics with friction and contact*,
//!   ACM TOG 34(3) 32 (APGD with adaptive step and restart).
//! - G. De Saxcé, Z.-Q. Feng (1998), *The bipotential method*, Math.
//!   Comput. Modelling 28 (the change `u_N + μ|u_T|` that makes Coulomb's
//!   law a cone complementarity).

pub mod apgd;
mod cache;
mod fc2d;
pub mod fc2d_lcp;
pub mod nsgs;
pub mod operator;
mod problem;

pub use cache::ContactCache;
pub use fc2d::{solve_fc2d, Fc2dAnswer, Fc2dOperator, Fc2dSolver};
pub use nsgs::{local_coulomb, local_coulomb_boxed, Outcome};
pub use operator::{project_boxed, project_cone, residual_at, Delassus};
pub use problem::{SparseContacts, RESIDUAL_FLOOR, ROUNDING_FRACTION};

use crate::contact::problem::Gen;
use crate::model::limits::Limit;
use crate::model::settings::SettingsReader;
use crate::model::CaseError;
use crate::record::{SettingValue, Settings, Unit};

/// Default relative residual at which a solve stops (-): the middle of the
/// literature's range 1e-4 … 1e-8 (Acary, Brémond & Huber 2018), four
/// orders below the relative size of a contact force's daily variation, and
/// where the closed-form checks pass (docs/physics.md §3.5).
pub const DEFAULT_TOLERANCE: f64 = 1e-6;

/// Default most sweeps or iterations of one solve: a jammed group of
/// 2,000 floes converges warm-started in tens of sweeps; a cold chain of
/// `L` floes needs about `L²` Gauss–Seidel sweeps to carry a load along it.
pub const DEFAULT_MAX_ITERATIONS: u64 = 2000;

/// The relative change of a group's kinetic energy that is rounding, not
/// work done by its contact impulses (see [`creates_energy`]).
pub const ENERGY_ROUNDING: f64 = 1e-12;

/// Whether contact impulses that took a group's kinetic energy from
/// `before` to `after` (J) created energy: by more than
/// [`ENERGY_ROUNDING`] of it (and 1e-300 J, for a group at rest). The one
/// test of Moreau–Jean's `contact_energy_increases` and of
/// [`IterativeSolver::continue_while_creating_energy`].
pub fn creates_energy(before: f64, after: f64) -> bool {
    after > before * (1.0 + ENERGY_ROUNDING) + 1e-300
}

/// The bound of `tolerance`.
pub const TOLERANCE: Limit = Limit::range(
    "tolerance",
    "[formulation.moreau], [formulation.event-driven]",
    1e-14,
    0.5,
    "",
    "a relative residual below 1e-14 is rounding; above 0.5 the answer is no contact solution",
);

/// The bound of `max_iterations`.
pub const MAX_ITERATIONS: Limit = Limit::range(
    "max_iterations",
    "[formulation.moreau], [formulation.event-driven]",
    1.0,
    1e7,
    "",
    "at least one sweep; 1e7 sweeps of a 20,000-floe pack would take days per step",
)
.integers();

/// The bound of `relaxation`.
pub const RELAXATION: Limit = Limit::range(
    "relaxation",
    "[formulation.moreau], [formulation.event-driven]",
    0.0,
    1.95,
    "",
    "over-relaxed Gauss-Seidel converges only for 0 < ω < 2",
)
.exclusive_min();

/// The iterative method.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Method {
    /// Nonsmooth Gauss–Seidel on Coulomb's law.
    Nsgs,
    /// Accelerated projected gradient on the cone relaxation.
    Apgd,
}

impl Method {
    /// The name in settings and reports.
    pub fn name(self) -> &'static str {
        match self {
            Method::Nsgs => "nsgs",
            Method::Apgd => "apgd",
        }
    }
}

/// The settings of an iterative solve.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IterativeOptions {
    /// The method.
    pub method: Method,
    /// `tolerance`: relative natural-map residual at which to stop (default
    /// [`DEFAULT_TOLERANCE`]).
    pub tolerance: f64,
    /// `max_iterations`: most sweeps or iterations (default
    /// [`DEFAULT_MAX_ITERATIONS`]).
    pub max_iterations: u64,
    /// `relaxation`: NSGS over-relaxation ω (default 1: plain
    /// Gauss–Seidel; APGD takes no relaxation).
    pub relaxation: f64,
    /// `polish`: finish every NSGS answer exactly, by the pivoting solver
    /// started from the answer's active set (docs/physics.md §3.5, "Exact
    /// polish"; default off: the answer at the tolerance is the result).
    /// APGD has none: its answer solves the cone relaxation, not the LCP.
    pub polish: bool,
}

impl IterativeOptions {
    /// The defaults for `method`.
    pub fn new(method: Method) -> IterativeOptions {
        IterativeOptions {
            method,
            tolerance: DEFAULT_TOLERANCE,
            max_iterations: DEFAULT_MAX_ITERATIONS,
            relaxation: 1.0,
            polish: false,
        }
    }

    /// Reads `tolerance`, `max_iterations` and `relaxation` from a
    /// formulation's table whose `solver` is `solver` (`None`: an
    /// iterative solver was not chosen, and then these keys are refused
    /// with the line of the first one given).
    pub fn read(
        r: &mut SettingsReader<'_>,
        method: Option<Method>,
        solver: &str,
    ) -> Result<Option<IterativeOptions>, CaseError> {
        let tolerance = r.bounded(&TOLERANCE)?;
        let max_iterations = r.integer(&MAX_ITERATIONS)?;
        let relaxation = r.bounded(&RELAXATION)?;
        let polish = r.boolean("polish")?;
        let Some(method) = method else {
            let given = [
                ("tolerance", tolerance.is_some()),
                ("max_iterations", max_iterations.is_some()),
                ("relaxation", relaxation.is_some()),
                ("polish", polish.is_some()),
            ];
            return match given.iter().find(|(_, g)| *g) {
                Some((key, _)) => Err(r.error(
                    key,
                    format!(
                        "{key} is a setting of the iterative solvers (solver = \"nsgs\" or \"apgd\"), not of solver = \"{solver}\""
                    ),
                )),
                None => Ok(None),
            };
        };
        if method == Method::Apgd && relaxation.is_some() {
            return Err(r.error(
                "relaxation",
                "relaxation is a setting of solver = \"nsgs\" (Gauss-Seidel's ω); apgd chooses its own step",
            ));
        }
        if method == Method::Apgd && polish.is_some() {
            return Err(r.error(
                "polish",
                "polish is a setting of solver = \"nsgs\": apgd's answer solves the cone relaxation, which has no exact Coulomb LCP to finish on",
            ));
        }
        let d = IterativeOptions::new(method);
        Ok(Some(IterativeOptions {
            method,
            tolerance: tolerance.unwrap_or(d.tolerance),
            max_iterations: max_iterations.map_or(d.max_iterations, |k| k.max(1) as u64),
            relaxation: relaxation.unwrap_or(d.relaxation),
            polish: polish.unwrap_or(d.polish),
        }))
    }
}

/// The answer of one iterative solve.
#[derive(Debug, Clone, PartialEq)]
pub struct Answer {
    /// Impulses `(λ_j, β_j)` per contact, N·s (finite).
    pub p: Vec<[f64; 2]>,
    /// The floes' velocity changes `M⁻¹ H p`, group order.
    pub dv: Vec<Gen>,
    /// Iterations, residual (Coulomb form), convergence.
    pub outcome: Outcome,
    /// Contacts whose start came from the cache.
    pub warm_hits: usize,
}

impl Answer {
    /// The normal impulses `λ`, N·s.
    pub fn normal(&self) -> Vec<f64> {
        self.p.iter().map(|p| p[0]).collect()
    }

    /// The tangential impulses `β`, N·s.
    pub fn tangential(&self) -> Vec<f64> {
        self.p.iter().map(|p| p[1]).collect()
    }
}

/// An iterative solver with its contact cache.
#[derive(Debug, Clone)]
pub struct IterativeSolver {
    /// Its settings.
    pub options: IterativeOptions,
    cache: ContactCache,
}

impl IterativeSolver {
    /// A solver with `options` and an empty cache.
    pub fn new(options: IterativeOptions) -> IterativeSolver {
        IterativeSolver {
            options,
            cache: ContactCache::default(),
        }
    }

    /// Whether this solver also solves the impacts' compression problems
    /// (NSGS: the same frictional contact problem with zero offsets; APGD's
    /// cone relaxation would not be Poisson's law, so its impacts stay on
    /// Lemke).
    pub fn solves_impacts(&self) -> bool {
        self.options.method == Method::Nsgs
    }

    /// Solves an impact's compression problem `prob` (zero offsets) by
    /// NSGS from zero impulses: the cache is neither read nor written (an
    /// impulse of a compression is no step's force).
    pub fn solve_impact(&self, prob: &SparseContacts) -> Answer {
        let o = &self.options;
        let mut p = vec![[0.0; 2]; prob.len()];
        let (outcome, dv) = nsgs::solve(prob, &mut p, o.tolerance, o.max_iterations, o.relaxation);
        Answer {
            p,
            dv,
            outcome,
            warm_hits: 0,
        }
    }

    /// Goes on with an answer `a` of `prob` (a step of `h`, s) that stopped
    /// at `max_iterations` above the tolerance while giving the group
    /// kinetic energy (more than [`ENERGY_ROUNDING`] of it): more sweeps or
    /// iterations from `a`, `max_iterations` at a time, until the answer
    /// converges or creates no energy, or the solve has taken
    /// [`DEFAULT_MAX_ITERATIONS`] (or `max_iterations`, if more) in all.
    /// Returns the answer (stored in the cache when continued) and the
    /// number of continuations. A low cap saves the sweeps of the stalled
    /// solves of a jam (docs/physics.md §3.5, "A cap that creates no
    /// energy"), but not at the price of contact impulses that do work.
    pub fn continue_while_creating_energy(
        &mut self,
        prob: &SparseContacts,
        mut a: Answer,
        h: f64,
    ) -> (Answer, u64) {
        let o = self.options;
        let ceiling = o.max_iterations.max(DEFAULT_MAX_ITERATIONS);
        let creates = |dv: &[Gen]| {
            let (before, after) = prob.kinetic_energies(dv);
            creates_energy(before, after)
        };
        let mut rounds = 0;
        while !(a.outcome.converged || a.outcome.interrupted)
            && a.outcome.iterations < ceiling
            && creates(&a.dv)
        {
            let budget = o.max_iterations.min(ceiling - a.outcome.iterations);
            let (outcome, dv) = match o.method {
                Method::Nsgs => nsgs::solve(prob, &mut a.p, o.tolerance, budget, o.relaxation),
                Method::Apgd => apgd::solve(prob, &mut a.p, o.tolerance, budget),
            };
            a.outcome = Outcome {
                iterations: a.outcome.iterations + outcome.iterations,
                ..outcome
            };
            a.dv = dv;
            rounds += 1;
        }
        if rounds > 0 {
            self.cache.store(prob, &a.p, h);
        }
        (a, rounds)
    }

    /// `settings` with `solver` set to this method's name (replacing a
    /// direct solver's) and the iterative settings added.
    pub fn settings(&self, settings: Settings) -> Settings {
        let o = &self.options;
        let mut s = settings;
        match s.0.iter_mut().find(|x| x.name == "solver") {
            Some(x) => x.value = SettingValue::Text(o.method.name().to_string()),
            None => s = s.text("solver", o.method.name()),
        }
        // One cone per contact point: a direct solver's merged friction
        // stays only on the LCPs it still solves (APGD's impacts; NSGS
        // solves them too, so none).
        if let Some(x) = s.0.iter_mut().find(|x| x.name == "merge_friction") {
            if x.value != SettingValue::Text("off".to_string()) {
                let v = if self.solves_impacts() {
                    "off"
                } else {
                    "impact LCPs only"
                };
                x.value = SettingValue::Text(v.to_string());
            }
        }
        let s = s
            .number("tolerance", o.tolerance, Unit::Dimensionless)
            .number("max_iterations", o.max_iterations as f64, Unit::Count);
        match o.method {
            Method::Nsgs => s
                .number("relaxation", o.relaxation, Unit::Dimensionless)
                .text("polish", if o.polish { "on" } else { "off" }),
            Method::Apgd => s,
        }
    }

    /// Solves `prob`, a problem of a step of length `h` (s) at time `t`
    /// (s) of a scene of `n_floes` floes (a change of the count clears the
    /// cache: floe and obstacle indices moved), warm-started from the
    /// cache, and stores the answer in it.
    pub fn solve(&mut self, prob: &SparseContacts, t: f64, h: f64, n_floes: usize) -> Answer {
        self.cache.begin(t, n_floes);
        let (mut p, warm_hits) = self.cache.start(prob, h);
        let o = &self.options;
        let (outcome, dv) = match o.method {
            Method::Nsgs => nsgs::solve(prob, &mut p, o.tolerance, o.max_iterations, o.relaxation),
            Method::Apgd => apgd::solve(prob, &mut p, o.tolerance, o.max_iterations),
        };
        self.cache.store(prob, &p, h);
        Answer {
            p,
            dv,
            outcome,
            warm_hits,
        }
    }
}
