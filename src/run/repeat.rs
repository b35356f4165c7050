//! Repeated runs of the same (case, formulation): the physics must be
//! bit-identical between repeats (every formulation is deterministic), only
//! the timing may differ.
//!
//! [`merge`] folds the repeats of one pair into one [`Repeated`]: the run
//! whose CPU time is the median of the repeats (its trajectory, ledger,
//! counters and contact log are those of every repeat), the timing of every
//! repeat in run order, and a finding for every repeat whose physics differs
//! from the first ([`physics_difference`]: the first quantity of any output
//! but the timing that differs, compared bit for bit).

use super::energy::Column;
use super::output::PERCUSSION_FILE;
use super::{RunResult, RunSummary, Timing};
use serde::Serialize;
use serde_json::Value;

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
/// bit for bit (`to_bits` of every number, so `-0` differs from `0`): every
/// output of a run but its timing, in this order: how the run ended and the
/// time reached, the trajectory, the energy ledger (every [`Column`] of
/// every sample), the fractures (their number and every record of
/// `fractures.csv`), the floes (their number at the end and every record of
/// `floes.json`), the percussion record (`percussion.json`), the final
/// state, the counters, the contact log, and the rest of `summary.json`
/// (the energy totals, the LCP profile's counts, …). `None` when they are
/// identical. Timing (`summary.timing`, the LCP profile's seconds and timer
/// overhead) is not physics and is not compared.
pub fn physics_difference(a: &RunResult, b: &RunResult) -> Option<String> {
    type Compare = fn(&RunResult, &RunResult) -> Option<String>;
    const IN_ORDER: [Compare; 8] = [
        end_difference,
        trajectory_difference,
        energy_difference,
        fracture_difference,
        floe_difference,
        percussion_difference,
        state_difference,
        summary_difference,
    ];
    IN_ORDER.iter().find_map(|compare| compare(a, b))
}

/// How the run ended, the time reached.
fn end_difference(a: &RunResult, b: &RunResult) -> Option<String> {
    let (sa, sb) = (&a.summary, &b.summary);
    if sa.end != sb.end {
        return Some(format!("the run ended `{}` and `{}`", sa.end, sb.end));
    }
    (sa.t_reached.to_bits() != sb.t_reached.to_bits())
        .then(|| format!("time reached {} s and {} s", sa.t_reached, sb.t_reached))
}

/// Every row of the trajectory: its floe and time, then its state.
fn trajectory_difference(a: &RunResult, b: &RunResult) -> Option<String> {
    if a.trajectory.len() != b.trajectory.len() {
        return Some(format!(
            "{} and {} trajectory rows",
            a.trajectory.len(),
            b.trajectory.len()
        ));
    }
    for (k, (ra, rb)) in a.trajectory.iter().zip(&b.trajectory).enumerate() {
        if ra.floe != rb.floe || ra.t.to_bits() != rb.t.to_bits() {
            return Some(format!(
                "trajectory: row {} is floe {} at t = {} s and floe {} at t = {} s",
                k + 1,
                ra.floe,
                ra.t,
                rb.floe,
                rb.t
            ));
        }
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
    None
}

/// Every column of every sample of the energy ledger.
fn energy_difference(a: &RunResult, b: &RunResult) -> Option<String> {
    if a.energy.len() != b.energy.len() {
        return Some(format!(
            "{} and {} energy samples",
            a.energy.len(),
            b.energy.len()
        ));
    }
    a.energy.iter().zip(&b.energy).find_map(|(ea, eb)| {
        let differs = |c: &Column| c.of(ea).to_bits() != c.of(eb).to_bits();
        Column::all().find(differs).map(|c| {
            format!(
                "energy: {} at t = {} s is {} {u} and {} {u}",
                c.name(),
                ea.t,
                c.of(ea),
                c.of(eb),
                u = c.unit()
            )
        })
    })
}

/// The number of fractures, then every fracture record.
fn fracture_difference(a: &RunResult, b: &RunResult) -> Option<String> {
    let (na, nb) = (a.summary.fractures, b.summary.fractures);
    if na != nb {
        return Some(format!("{na} and {nb} fractures"));
    }
    if a.fractures.len() != b.fractures.len() {
        return Some(format!(
            "fractures.csv: {} and {} fractures",
            a.fractures.len(),
            b.fractures.len()
        ));
    }
    a.fractures
        .iter()
        .zip(&b.fractures)
        .enumerate()
        .find_map(|(k, (fa, fb))| {
            json_difference(fa, fb).map(|d| {
                format!(
                    "fractures.csv: fracture {} (floe {} at t = {} s): {d}",
                    k + 1,
                    fa.parent,
                    fa.t
                )
            })
        })
}

/// The number of floes at the end, then every floe record.
fn floe_difference(a: &RunResult, b: &RunResult) -> Option<String> {
    let (na, nb) = (a.summary.floes_at_end, b.summary.floes_at_end);
    if na != nb {
        return Some(format!("{na} and {nb} floes at the end"));
    }
    if a.floes.len() != b.floes.len() {
        return Some(format!(
            "floes.json: {} and {} floes",
            a.floes.len(),
            b.floes.len()
        ));
    }
    a.floes.iter().zip(&b.floes).find_map(|(fa, fb)| {
        json_difference(fa, fb).map(|d| format!("floes.json: floe {}: {d}", fa.id))
    })
}

/// The percussion record, if either run has one.
fn percussion_difference(a: &RunResult, b: &RunResult) -> Option<String> {
    match (&a.percussion, &b.percussion) {
        (None, None) => None,
        (Some(_), None) => Some(format!("a percussion record ({PERCUSSION_FILE}) and none")),
        (None, Some(_)) => Some(format!("no percussion record and one ({PERCUSSION_FILE})")),
        (Some(pa), Some(pb)) => json_difference(pa, pb).map(|d| format!("{PERCUSSION_FILE}: {d}")),
    }
}

/// The final state, the counters, the contact log.
fn state_difference(a: &RunResult, b: &RunResult) -> Option<String> {
    if a.final_state != b.final_state {
        return Some("the final state differs".into());
    }
    if a.summary.counters != b.summary.counters {
        return Some("the counters differ".into());
    }
    (a.contacts != b.contacts).then(|| "the contact log differs".into())
}

/// The rest of `summary.json`, without its timing.
fn summary_difference(a: &RunResult, b: &RunResult) -> Option<String> {
    json_difference(&untimed(&a.summary), &untimed(&b.summary))
        .map(|d| format!("summary.json: {d}"))
}

/// `s` with its timing zeroed: the whole `timing`, and the LCP profile's
/// seconds and timer overhead.
fn untimed(s: &RunSummary) -> RunSummary {
    let mut s = s.clone();
    s.timing = Timing::default();
    if let Some(p) = &mut s.lcp_profile {
        p.timer_overhead = 0.0;
        p.buckets.iter_mut().for_each(|b| b.seconds = 0.0);
    }
    s
}

/// Where the JSON forms of `a` and `b` first differ (`` `energy.fracture` is 1
/// and 2 ``; keys in alphabetical order, array items in order), every
/// number compared in its shortest round-trip form, that is bit for bit
/// (`-0` differs from `0`); `None` when they are the same.
fn json_difference<T: Serialize>(a: &T, b: &T) -> Option<String> {
    match (serde_json::to_value(a), serde_json::to_value(b)) {
        (Ok(va), Ok(vb)) => first_difference(&va, &vb, String::new()).map(|(path, x, y)| {
            if path.is_empty() {
                format!("{x} and {y}")
            } else {
                format!("`{path}` is {x} and {y}")
            }
        }),
        (Err(e), _) | (_, Err(e)) => Some(format!("not comparable ({e})")),
    }
}

/// The path (`energy.fracture`, `nodes[3][0]`) to the first place where
/// `a` and `b` differ, under `path`, with what each holds there.
fn first_difference(a: &Value, b: &Value, path: String) -> Option<(String, String, String)> {
    let child = |key: &dyn std::fmt::Display, index: bool| match (path.is_empty(), index) {
        (_, true) => format!("{path}[{key}]"),
        (true, false) => key.to_string(),
        (false, false) => format!("{path}.{key}"),
    };
    match (a, b) {
        (Value::Object(ma), Value::Object(mb)) => {
            let keys = ma.keys().chain(mb.keys().filter(|k| !ma.contains_key(*k)));
            for k in keys {
                let found = match (ma.get(k), mb.get(k)) {
                    (Some(x), Some(y)) => first_difference(x, y, child(k, false)),
                    (x, y) => Some((child(k, false), shown(x), shown(y))),
                };
                if found.is_some() {
                    return found;
                }
            }
            None
        }
        (Value::Array(xa), Value::Array(xb)) if xa.len() == xb.len() => xa
            .iter()
            .zip(xb)
            .enumerate()
            .find_map(|(i, (x, y))| first_difference(x, y, child(&i, true))),
        _ => {
            let (x, y) = (a.to_string(), b.to_string());
            (x != y).then(|| (path, shown(Some(a)), shown(Some(b))))
        }
    }
}

/// `v` in a finding: a number or a short value as JSON, an array or an
/// object by its size, `absent` for none.
fn shown(v: Option<&Value>) -> String {
    match v {
        None => "absent".into(),
        Some(Value::Array(x)) => format!("{} items", x.len()),
        Some(Value::Object(m)) => format!("an object of {} keys", m.len()),
        Some(v) => v.to_string(),
    }
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
