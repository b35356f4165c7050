//! The iterative contact solvers (`solver = "nsgs"` and `"apgd"`,
//! docs/physics.md §3.5): the exact local Coulomb solve, the natural-map
//! residual (zero at Lemke's answers, large at a spoiled one), NSGS and
//! APGD against Lemke on the bundled cases and the closed-form checks, the
//! contact cache, the counted unconverged solve, the stop test that
//! evaluates the residual only when a sweep's change bound allows, the
//! impacts solved by NSGS, the bounded normal impulse (boxed law), the
//! continuation of capped answers that would create energy, and the
//! settings' refusals.
//!
//! This file holds what the submodules share: the contact problems of a
//! case's initial state (dense and sparse), Lemke's answer to one, the
//! frictional cradle and the cases with solver settings added. The tests
//! are in the submodules, one topic each.

mod against_lemke;
mod boxed;
mod local_solve;
mod residual;
mod runs;
mod settings;
mod solver_residual;

use crate::common::{case_text, scenario, with_formulation_table};
use floebench::contact::problem::{groups, ContactLcp, Friction, Gen};
use floebench::contact::BroadPhase;
use floebench::iterative::SparseContacts;
use floebench::lcp::{solve, SolveOptions};
use floebench::model::Scenario;
use floebench::state::{detect_contacts, normal_velocity, System};

/// The contact groups of the active contacts of `scn` at its initial
/// state, with the free velocities and zero offsets (an impact problem).
fn problems(scn: &Scenario) -> Vec<(ContactLcp, SparseContacts)> {
    let sys = System::initial(scn);
    let mut bp = BroadPhase::new();
    let mut contacts = Vec::new();
    detect_contacts(scn, &sys.bodies, 1e-3, &mut bp, &mut contacts);
    let w: Vec<Gen> = sys.velocities();
    let offsets: Vec<f64> = contacts.iter().map(|_| 0.0).collect();
    assert!(contacts
        .iter()
        .any(|c| normal_velocity(scn, &sys.bodies, c) < 0.0));
    let centres = sys.centres();
    groups(&contacts, scn.floes.len())
        .iter()
        .map(|g| {
            let lcp = ContactLcp::assemble(
                scn,
                &centres,
                &contacts,
                g,
                &w,
                &offsets,
                Friction::PerPoint,
            );
            let sp = SparseContacts::build(scn, &centres, &contacts, g, &w, &offsets);
            (lcp, sp)
        })
        .collect()
}

/// Lemke's solution of `lcp` (asserted solved) and its impulses `(λ, β)`
/// per contact.
fn lemke_answer(lcp: &ContactLcp) -> (floebench::lcp::LcpSolution, Vec<[f64; 2]>) {
    let sol = solve(lcp.lcp(), &SolveOptions::default());
    assert!(sol.status.is_solved());
    let (l, b) = (lcp.normal(&sol.z), lcp.tangential(&sol.z));
    let p = l.iter().zip(&b).map(|(l, b)| [*l, *b]).collect();
    (sol, p)
}

/// A frictional touching row: the cradle with friction and a sideways speed.
fn frictional_cradle() -> Scenario {
    scenario(
        &case_text("cradle_touching")
            .replace("friction = 0.0", "friction = 0.5")
            .replace("velocity = [0.5, 0.0]", "velocity = [0.5, 0.2]"),
    )
}

/// The case `name` with `settings` in `[formulation.<table>]` (added to an
/// existing table of that name, or appended).
fn with_settings(name: &str, table: &str, settings: &str) -> String {
    let text = case_text(name);
    let header = format!("[formulation.{table}]");
    if text.contains(&header) {
        text.replace(&header, &format!("{header}\n{settings}"))
    } else {
        with_formulation_table(&text, table, settings)
    }
}

/// A random contact's `2 × 2` Delassus block `J M⁻¹ Jᵀ` (row-major, the
/// rows of two random floes), a friction coefficient and a free velocity
/// `r`, drawn from `rng`; `None` outside the uniqueness condition
/// `W_NN > μ |W_NT|` (the draws are made all the same).
pub(super) fn random_contact(
    rng: &mut floebench::rng::SplitMix64,
) -> Option<([f64; 4], f64, [f64; 2])> {
    let mut w = [0.0; 4];
    for _ in 0..2 {
        let (mi, ii) = (rng.range(1e-6, 1e-4), rng.range(1e-10, 1e-8));
        let (rn, rt) = (rng.range(-30.0, 30.0), rng.range(-30.0, 30.0));
        let jn = [1.0, 0.0, rn];
        let jt = [0.0, 1.0, rt];
        let m = [mi, mi, ii];
        for d in 0..3 {
            w[0] += jn[d] * m[d] * jn[d];
            w[1] += jn[d] * m[d] * jt[d];
            w[3] += jt[d] * m[d] * jt[d];
        }
    }
    w[2] = w[1];
    let mu = rng.range(0.0, 1.0);
    if w[0] <= mu * w[1].abs() {
        return None;
    }
    let r = [rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)];
    Some((w, mu, r))
}
