//! Repeated runs of the same (case, formulation): the physics must be
//! bit-identical between repeats (every formulation is deterministic), only
//! the timing may differ.
//!
//! [`merge`] folds the repeats of one pair into one [`Repeated`]: the run
//! whose CPU time is the median of the repeats (its trajectory, ledger,
//! counters and contact log are those of every repeat), the timing of every
//! repeat in run order, and a finding for every repeat whose physics differs
//! from the first ([`physics_difference`]: the first quantity that differs,
//! compared bit for bit).

use super::energy::Column;
use super::{RunResult, Timing};

/// The repeats of one (case, formulation), merged.
#[derive(Debug, Clone)]
pub struct Repeated {
    /// The repeat of median CPU time (for an even count, the lower of the two
    /// middle ones), with its own timing.
    pub result: RunResult,
    /// The timing of every repeat, in run order.
    pub timings: Vec<Timing>,
    /// One line per repeat whose physics is not bit-identical to the first
    /// (empty when every repeat agrees).
    pub findings: Vec<String>,
}

/// The first quantity in which the physics of `a` and `b` differ, compared
/// bit for bit (`to_bits` of every number, so `-0` differs from `0`):
/// how the run ended, the time reached, the trajectory, the energy ledger
/// (every [`Column`] of every sample),
/// the final state, the counters and the contact log; `None` when they are
/// identical. Timing (`summary.timing`, the LCP profile's seconds) is not
/// physics and is not compared.
pub fn physics_difference(a: &RunResult, b: &RunResult) -> Option<String> {
    let (sa, sb) = (&a.summary, &b.summary);
    if sa.end != sb.end {
        return Some(format!("the run ended `{}` and `{}`", sa.end, sb.end));
    }
    if sa.t_reached.to_bits() != sb.t_reached.to_bits() {
        return Some(format!(
            "time reached {} s and {} s",
            sa.t_reached, sb.t_reached
        ));
    }
    if a.trajectory.len() != b.trajectory.len() {
        return Some(format!(
            "{} and {} trajectory rows",
            a.trajectory.len(),
            b.trajectory.len()
        ));
    }
    for (ra, rb) in a.trajectory.iter().zip(&b.trajectory) {
        let fa = [ra.x, ra.y, ra.theta, ra.vx, ra.vy, ra.omega];
        let fb = [rb.x, rb.y, rb.theta, rb.vx, rb.vy, rb.omega];
        let names = ["x", "y", "theta", "vx", "vy", "omega"];
        if let Some(k) = (0..6).find(|&k| fa[k].to_bits() != fb[k].to_bits()) {
            return Some(format!(
                "trajectory: floe {} {} at t = {} s is {} and {}",
                ra.floe, names[k], ra.t, fa[k], fb[k]
            ));
        }
    }
    if a.energy.len() != b.energy.len() {
        return Some(format!(
            "{} and {} energy samples",
            a.energy.len(),
            b.energy.len()
        ));
    }
    for (ea, eb) in a.energy.iter().zip(&b.energy) {
        let differs = |c: &Column| c.of(ea).to_bits() != c.of(eb).to_bits();
        if let Some(c) = Column::all().find(differs) {
            return Some(format!(
                "energy: {} at t = {} s is {} {u} and {} {u}",
                c.name(),
                ea.t,
                c.of(ea),
                c.of(eb),
                u = c.unit()
            ));
        }
    }
    if a.final_state != b.final_state {
        return Some("the final state differs".into());
    }
    if sa.counters != sb.counters {
        return Some("the counters differ".into());
    }
    if a.contacts != b.contacts {
        return Some("the contact log differs".into());
    }
    None
}

/// Merges the repeats of one pair (in run order; at least one), labelled
/// `label` in the findings (e.g. `head_on: rapier`).
///
/// Returns `None` for an empty list.
pub fn merge(label: &str, repeats: Vec<RunResult>) -> Option<Repeated> {
    let first = repeats.first()?;
    let n = repeats.len();
    let findings = repeats
        .iter()
        .enumerate()
        .skip(1)
        .filter_map(|(k, r)| {
            physics_difference(first, r).map(|d| {
                format!(
                    "{label}: repeat {} of {n} is not bit-identical to repeat 1: {d}",
                    k + 1
                )
            })
        })
        .collect();
    let timings: Vec<Timing> = repeats.iter().map(|r| r.summary.timing).collect();
    let mut order: Vec<usize> = (0..n).collect();
    order.sort_by(|&i, &j| timings[i].cpu_total.total_cmp(&timings[j].cpu_total));
    let median = order[(n - 1) / 2];
    let result = repeats.into_iter().nth(median)?;
    Some(Repeated {
        result,
        timings,
        findings,
    })
}
