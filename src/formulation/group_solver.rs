//! The contact problems of a group, solved by the solver a formulation
//! was given ([`GroupSolver`]: the direct [`ContactSolver`] or an
//! iterative one, with the accuracy record of every solve), and the
//! `solver` key that chooses it in `[formulation.moreau]` and
//! `[formulation.event-driven]`, with the iterative solvers' keys, read in
//! one place ([`read_solver`]).
//!
//! `solver` is `"lcp"` (Lemke on the Stewart–Trinkle LCP), `"cone"`
//! (clarabel on the Anitescu–Tasora relaxation), `"nsgs"` (nonsmooth
//! Gauss–Seidel on Coulomb's law) or `"apgd"` (accelerated projected
//! gradient on the relaxation); the last two take `tolerance`,
//! `max_iterations` and (nsgs) `relaxation` ([`crate::iterative`],
//! docs/physics.md §3.5), which the direct solvers refuse.

use super::contact_solver::{ContactSolver, LastAnswer, SolverKind};
use crate::contact::problem::{ContactGroup, ContactLcp, Friction, Gen};
use crate::contact::Contact;
use crate::geometry::Vec2;
use crate::iterative::{Answer, IterativeOptions, IterativeSolver, Method, SparseContacts};
use crate::model::settings::SettingsReader;
use crate::model::CaseError;
use crate::model::Scenario;
use crate::record::accuracy::Accuracy;
use crate::record::{Counter, Counters, Settings};

/// What the `solver` key chose.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum Choice {
    Direct(SolverKind),
    Iterative(Method),
}

impl std::str::FromStr for Choice {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        match s {
            "nsgs" => Ok(Choice::Iterative(Method::Nsgs)),
            "apgd" => Ok(Choice::Iterative(Method::Apgd)),
            other => other
                .parse::<SolverKind>()
                .map(Choice::Direct)
                .map_err(|_| {
                    let hint = crate::model::case::closest(other, &["lcp", "cone", "nsgs", "apgd"])
                        .map_or(String::new(), |k| format!(" (did you mean `{k}`?)"));
                    format!(
                        "unknown solver `{other}`{hint}; expected `lcp`, `cone`, `nsgs` or `apgd`"
                    )
                }),
        }
    }
}

/// Reads `solver` (default `default`) and the iterative solvers' keys:
/// the direct solver (Lemke for an iterative choice: the event-driven
/// scheme's impacts under APGD use it), and
/// the iterative settings when `"nsgs"` or `"apgd"` was chosen.
pub fn read_solver(
    r: &mut SettingsReader<'_>,
    default: SolverKind,
) -> Result<(SolverKind, Option<IterativeOptions>), CaseError> {
    let choice = r.choice::<Choice>("solver")?;
    let (direct, method) = match choice {
        None => (default, None),
        Some(Choice::Direct(k)) => (k, None),
        Some(Choice::Iterative(m)) => (SolverKind::Lcp, Some(m)),
    };
    let iterative = IterativeOptions::read(r, method, direct.name())?;
    Ok((direct, iterative))
}

/// The answer of one group's contact problem, whichever solver gave it.
#[derive(Debug, Clone, PartialEq)]
pub struct GroupAnswer {
    /// Normal impulses `λ_j`, N·s, in the group's contact order.
    pub normal: Vec<f64>,
    /// Tangential impulses `β_j` along `T_j`, N·s.
    pub tangential: Vec<f64>,
    /// Tangential compliance of each contact (1/kg; its friction group's
    /// for a merged LCP), for the event-driven stick rule.
    pub compliance: Vec<f64>,
    /// Generalised impulses `H p` per floe of the group (group order).
    pub impulses: Vec<Gen>,
    /// Velocity changes `M⁻¹ H p` per floe of the group (group order).
    pub dv: Vec<Gen>,
}

/// The solvers of a formulation's contact problems: the direct one
/// (Lemke or clarabel, [`ContactSolver`]), the iterative one when chosen,
/// and the accuracy record of every solve.
#[derive(Debug)]
pub struct GroupSolver {
    /// The direct solver (also the impacts' under APGD).
    pub direct: ContactSolver,
    /// The iterative solver (`solver = "nsgs"` or `"apgd"`).
    pub iterative: Option<IterativeSolver>,
    /// The residual and work of every solve.
    pub accuracy: Accuracy,
    /// Whether an iterative answer stopped at its cap that gives the group
    /// kinetic energy is continued
    /// ([`IterativeSolver::continue_while_creating_energy`]): Moreau–Jean's
    /// steps, whose problems are velocity jumps.
    pub energy_guard: bool,
    /// Solves continued by the guard.
    continued: u64,
    /// Direct solves refused as too large for a dense LCP, solved by NSGS.
    too_large: u64,
}

/// The largest dense LCP matrix the direct solvers build, bytes: 4 GiB
/// (about 23,000 unknowns; a sixth of this machine's memory, and Lemke
/// needs a few such matrices). A group above it would make the run fail
/// on an allocation, not finish late.
pub const DENSE_LCP_MAX_BYTES: f64 = 4.0 * 1024.0 * 1024.0 * 1024.0;

/// Whether a group of `contacts` contact points (`friction`: with a
/// friction pair each) could need a dense LCP above [`DENSE_LCP_MAX_BYTES`]:
/// at most four unknowns per contact point with friction (`λ`, `β⁺`, `β⁻`,
/// the slip `α`), one without, eight bytes per entry.
pub fn dense_lcp_too_large(contacts: usize, friction: bool) -> bool {
    let per = if friction { 4.0 } else { 1.0 };
    let n = per * contacts as f64;
    8.0 * n * n > DENSE_LCP_MAX_BYTES
}

/// Direct solves of groups too large for a dense LCP, solved instead by
/// NSGS at its defaults (kept only by runs that had one).
pub const LCP_TOO_LARGE: Counter = Counter::sum(
    "lcp_too_large_solved_by_nsgs",
    "contact problems whose dense LCP would exceed 4 GiB (about 23,000 unknowns), solved instead by NSGS, cold, at its default tolerance and cap",
);

/// Iterative solves continued because their capped answer gave the group
/// kinetic energy (kept by formulations with the guard and an iterative
/// solver).
pub const CONTACT_SOLVES_CONTINUED: Counter = Counter::sum(
    "contact_solves_continued",
    "iterative contact solves stopped at max_iterations whose answer gave the group kinetic energy, continued (up to 2,000 sweeps in all) until it gave none or converged",
);

/// The problem of one group, as both solvers take it: the scene, the
/// centres of mass (m), every contact, the group, the free velocities and
/// the offsets (m/s) of [`ContactLcp::assemble`].
#[derive(Debug, Clone, Copy)]
pub struct GroupData<'a> {
    /// The scene.
    pub scn: &'a Scenario,
    /// Centre of mass of every floe, m.
    pub centres: &'a [Vec2],
    /// The contacts the group indexes.
    pub contacts: &'a [Contact],
    /// The group.
    pub group: &'a ContactGroup,
    /// Free velocity of every floe.
    pub w_free: &'a [Gen],
    /// Offset `c` of every contact, m/s.
    pub offsets: &'a [f64],
    /// The crushing bound of every contact's normal impulse, N·s
    /// ([`crate::contact::crush::normal_bounds`]); empty: rigid contacts.
    pub bounds: &'a [f64],
}

impl GroupData<'_> {
    /// The bounds of the group's contacts, in its order; empty when the
    /// contacts are rigid.
    fn group_bounds(&self) -> Vec<f64> {
        if self.bounds.is_empty() {
            return Vec::new();
        }
        self.group
            .contacts
            .iter()
            .map(|&k| self.bounds[k])
            .collect()
    }

    /// The group's sparse problem, bounded by the crushing bounds.
    fn sparse(&self) -> SparseContacts {
        let prob = SparseContacts::build(
            self.scn,
            self.centres,
            self.contacts,
            self.group,
            self.w_free,
            self.offsets,
        );
        match self.bounds.is_empty() {
            true => prob,
            false => prob.with_normal_bounds(self.group_bounds()),
        }
    }

    /// The group's LCP with `layout`, bounded by the crushing bounds.
    fn assemble(&self, layout: Friction) -> ContactLcp {
        ContactLcp::assemble(
            self.scn,
            self.centres,
            self.contacts,
            self.group,
            self.w_free,
            self.offsets,
            layout,
        )
        .with_normal_bounds(&self.group_bounds())
    }
}

impl GroupSolver {
    /// `direct`, with `iterative` when given, and an empty record.
    pub fn new(direct: ContactSolver, iterative: Option<IterativeOptions>) -> GroupSolver {
        GroupSolver {
            direct,
            iterative: iterative.map(IterativeSolver::new),
            accuracy: Accuracy::default(),
            energy_guard: false,
            continued: 0,
            too_large: 0,
        }
    }

    /// This solver with the energy guard on (see [`GroupSolver::energy_guard`]).
    pub fn with_energy_guard(mut self) -> GroupSolver {
        self.energy_guard = true;
        self
    }

    /// Solves a sustained (or time-stepping) problem at time `t` over a
    /// step `h` (s) by the iterative solver if there is one, else by the
    /// direct one, and records its residual and work.
    pub fn solve(&mut self, d: &GroupData<'_>, t: f64, h: f64) -> GroupAnswer {
        let prob = d.sparse();
        let Some(it) = &mut self.iterative else {
            return self.solve_direct(d, &prob, t, false);
        };
        let mut a = it.solve(&prob, t, h, d.scn.floes.len());
        if self.energy_guard {
            let rounds;
            (a, rounds) = it.continue_while_creating_energy(&prob, a, h);
            self.continued += u64::from(rounds > 0);
        }
        self.finish(d, &prob, a, t)
    }

    /// The iterative answer `a` of `prob`, finished exactly when `polish`
    /// is on (docs/physics.md §3.5, "Exact polish"): the LCP of the same
    /// problem solved by the pivoting solver from `a`'s active set. The
    /// record gets the answer returned: the polished one (its residual,
    /// the iterations plus the pivots), or `a` when the polish failed
    /// (counted).
    fn finish(
        &mut self,
        d: &GroupData<'_>,
        prob: &SparseContacts,
        a: Answer,
        t: f64,
    ) -> GroupAnswer {
        // The polish's basis guess knows no bound rows: a bounded problem
        // keeps the iterative answer.
        if a.outcome.interrupted
            || !self.iterative.as_ref().is_some_and(|it| it.options.polish)
            || !d.bounds.is_empty()
        {
            return self.iterative_answer(prob, a, t, self.method());
        }
        // The NSGS problem itself: one friction pair per point (merged
        // friction would change the problem, and its answers are not
        // per-point Coulomb).
        let lcp = d.assemble(Friction::PerPoint);
        let guess = lcp.guess_from(&a.normal(), &a.tangential());
        let work = self.direct.work();
        let Some(z) = self.direct.polish(&lcp, &guess, t) else {
            return self.iterative_answer(prob, a, t, self.method());
        };
        let answer = direct_answer(&lcp, &z);
        let p: Vec<[f64; 2]> = answer
            .normal
            .iter()
            .zip(&answer.tangential)
            .map(|(l, b)| [*l, *b])
            .collect();
        let o = a.outcome;
        let res = prob.residual(&p, true);
        self.accuracy.iterative(
            res,
            o.iterations + (self.direct.work() - work),
            true,
            prob.len(),
            a.warm_hits,
        );
        // The polished answer solves the per-point LCP to Lemke's tolerance.
        self.accuracy.solver(res, true);
        answer
    }

    /// The iterative method in use (NSGS when none is set).
    fn method(&self) -> Method {
        self.iterative
            .as_ref()
            .map_or(Method::Nsgs, |it| it.options.method)
    }

    /// Records the answer `a` of `prob` by `method` and returns it.
    fn iterative_answer(
        &mut self,
        prob: &SparseContacts,
        a: Answer,
        t: f64,
        method: Method,
    ) -> GroupAnswer {
        let o = a.outcome;
        if o.interrupted {
            // Cut short by a stop request: counted apart, not as an
            // unconverged solve; the run discards the step (crate::stop).
            self.direct.count_interrupted();
        } else {
            self.accuracy.iterative(
                o.residual,
                o.iterations,
                o.converged,
                prob.len(),
                a.warm_hits,
            );
            // NSGS solves Coulomb's law itself; APGD the cone relaxation, whose
            // natural map (without De Saxcé's term) is its stopping residual.
            let own = match method {
                Method::Apgd => prob.residual_at(&a.p, &a.dv, false),
                _ => o.residual,
            };
            self.accuracy.solver(own, o.converged);
        }
        let (normal, tangential) = (a.normal(), a.tangential());
        if prob.friction() && !o.interrupted {
            self.direct
                .check_coulomb(t, &normal, &tangential, prob.mu, &[]);
        }
        GroupAnswer {
            compliance: (0..prob.len())
                .map(|j| prob.tangential_compliance(j))
                .collect(),
            impulses: prob.impulses(&a.p),
            normal,
            tangential,
            dv: a.dv,
        }
    }

    /// Solves an impact's compression problem (Poisson's law, zero
    /// offsets) and records its residual and work: by NSGS, cold, when
    /// `solver = "nsgs"`, else by Lemke on the LCP (the direct solvers, and
    /// APGD, whose relaxation is not Coulomb's law).
    pub fn solve_impact(&mut self, d: &GroupData<'_>, t: f64) -> GroupAnswer {
        let prob = d.sparse();
        match &self.iterative {
            Some(it) if it.solves_impacts() => {
                let a = it.solve_impact(&prob);
                self.finish(d, &prob, a, t)
            }
            _ => self.solve_direct(d, &prob, t, true),
        }
    }

    fn solve_direct(
        &mut self,
        d: &GroupData<'_>,
        prob: &SparseContacts,
        t: f64,
        impact: bool,
    ) -> GroupAnswer {
        if dense_lcp_too_large(prob.len(), prob.friction()) {
            // The dense LCP would not fit in memory (a jammed group of
            // tens of thousands of contacts): NSGS, cold, at its defaults.
            self.too_large += 1;
            let it = IterativeSolver::new(IterativeOptions::new(Method::Nsgs));
            let a = it.solve_impact(prob);
            return self.iterative_answer(prob, a, t, Method::Nsgs);
        }
        let layout = self.direct.friction_layout(impact);
        let lcp = d.assemble(layout);
        let work = self.direct.work();
        let z = if impact {
            self.direct.solve_lcp(&lcp, t)
        } else {
            self.direct.solve(&lcp, t)
        };
        let (normal, tangential) = (lcp.normal(&z), lcp.tangential(&z));
        let p: Vec<[f64; 2]> = normal
            .iter()
            .zip(&tangential)
            .map(|(l, b)| [*l, *b])
            .collect();
        // A solve cut short by a stop request (counted by the direct
        // solver) is no measure of its accuracy: the run discards the step.
        if !crate::stop::requested() {
            let dv = prob.velocity_changes(&p);
            let res = prob.residual_at(&p, &dv, true);
            self.accuracy.direct(res, self.direct.work() - work);
            match self.direct.last_answer() {
                LastAnswer::Lcp { residual, met } => self.accuracy.solver(residual, met),
                // clarabel's answer on the problem it solved: the relaxation.
                LastAnswer::Cone { met } => {
                    self.accuracy.solver(prob.residual_at(&p, &dv, false), met)
                }
                LastAnswer::None => {}
            }
        }
        direct_answer(&lcp, &z)
    }

    /// The counters of both solvers and of the accuracy record.
    pub fn counters(&self) -> Counters {
        let mut c = self.direct.counters();
        c.absorb(&self.accuracy.counters());
        if self.energy_guard && self.iterative.is_some() {
            let mut g = Counters::new(&[&CONTACT_SOLVES_CONTINUED]);
            g.add(&CONTACT_SOLVES_CONTINUED, self.continued);
            c.absorb(&g);
        }
        if self.too_large > 0 {
            let mut g = Counters::new(&[&LCP_TOO_LARGE]);
            g.add(&LCP_TOO_LARGE, self.too_large);
            c.absorb(&g);
        }
        c
    }

    /// `settings` with the direct solver's, then the iterative one's.
    pub fn settings(&self, settings: Settings) -> Settings {
        let s = self.direct.settings(settings);
        match &self.iterative {
            Some(it) => it.settings(s),
            None => s,
        }
    }
}

/// The answer of the LCP `lcp` whose unknowns are `z`.
fn direct_answer(lcp: &ContactLcp, z: &[f64]) -> GroupAnswer {
    GroupAnswer {
        compliance: (0..lcp.m).map(|j| lcp.tangential_compliance(j)).collect(),
        impulses: lcp.impulses(z),
        dv: lcp.velocity_changes(z),
        normal: lcp.normal(z),
        tangential: lcp.tangential(z),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The dense LCP's bound: 4 GiB of `f64` is 23,170 unknowns, so 5,792
    /// frictional contact points (four unknowns each) fit and 5,793 do not;
    /// without friction, one unknown each.
    #[test]
    fn the_dense_lcp_bound_is_four_gibibytes() {
        assert!(!dense_lcp_too_large(5_792, true));
        assert!(dense_lcp_too_large(5_793, true));
        assert!(!dense_lcp_too_large(23_170, false));
        assert!(dense_lcp_too_large(23_171, false));
    }
}
