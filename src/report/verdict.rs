//! The verdict on a case: one sentence per aspect, printed by
//! `floebench compare` and written on the page and in `summary.json`:
//!
//! - **against the exact answers**: where a check has one
//!   ([`crate::analysis::check::CheckOutcome::scale`]), the formulations ranked by their error to
//!   it, ties within rounding ([`ranking::ROUNDING`]) joined by `=`; the
//!   first formulation is just another run there;
//! - **chaos**: whether a 1e-12 perturbation of the reference's initial
//!   positions grows exponentially ([`crate::analysis::chaos`]);
//! - **divergence between runs**: the RMS position difference from the
//!   first formulation, in median floe diameters `d_med` (the unit of every
//!   divergence of the report), against the threshold; on a chaotic case it
//!   is not a disagreement about the physics;
//! - **dissipation** in contacts, ranked, ties within rounding;
//! - **speed**: the fastest by median CPU time, tied with every formulation
//!   the repeats cannot tell from it ([`Spread::tied_with`]; with one run
//!   each no tie is called), the others given by their ratio to it (no
//!   claim is made among them), numbers to the digits the spread supports;
//! - runs that did not complete, and repeats whose physics differed.

use super::format::{fmt_num, fmt_spread};
use super::tables::{end_text, ratio_text};
use crate::analysis::comparison::CaseComparison;
use crate::analysis::ranking::{self, within_rounding, CheckRanking};
use crate::record::spread::Spread;
use crate::run::EndReason;
use std::fmt::Write as _;

/// `a, b and c`.
fn and_list(names: &[String]) -> String {
    match names {
        [] => String::new(),
        [one] => one.clone(),
        [init @ .., last] => format!("{} and {last}", init.join(", ")),
    }
}

/// One check's ranking: `check (exact X u): a = b (≤ e u) < c (e u, beyond the tolerance)`.
fn check_text(r: &CheckRanking) -> String {
    let unit = if r.unit == "1" {
        String::new()
    } else {
        format!(" {}", r.unit)
    };
    let mut s = r.check.clone();
    if let Some(x) = r.expected.filter(|x| *x != 0.0) {
        let _ = write!(s, " (exact {}{unit})", fmt_num(x));
    }
    s.push_str(": ");
    let groups: Vec<String> = r
        .groups
        .iter()
        .map(|g| {
            let names: Vec<&str> = g.iter().map(|i| i.0.as_str()).collect();
            let worst = g.iter().map(|i| i.1).fold(0.0, f64::max);
            let err = if worst.is_finite() {
                format!(
                    "{}{}{unit}",
                    if g.len() > 1 { "≤ " } else { "" },
                    fmt_num(worst)
                )
            } else {
                "not measured".into()
            };
            let fails = if g.iter().all(|i| i.2) {
                ""
            } else {
                ", beyond the tolerance"
            };
            format!("{} ({err}{fails})", names.join(" = "))
        })
        .collect();
    s.push_str(&groups.join(" < "));
    s
}

/// The sentences on the exact answers, or `None` when no check has one.
fn truth(comp: &CaseComparison, names: &[String]) -> Option<String> {
    let ranks = ranking::rank_checks(&comp.checks, names);
    if ranks.is_empty() {
        return None;
    }
    let mut s = format!(
        "Against the exact answers (each formulation's error to the closed form; `=` is a tie within rounding, {:e} of the answer's scale): {}.",
        ranking::ROUNDING,
        ranks.iter().map(check_text).collect::<Vec<_>>().join("; ")
    );
    let mut best: Vec<(String, usize)> = names
        .iter()
        .map(|n| {
            let k = ranks
                .iter()
                .filter(|r| {
                    r.groups
                        .first()
                        .is_some_and(|g| g.iter().any(|i| &i.0 == n))
                })
                .count();
            (n.clone(), k)
        })
        .filter(|(n, _)| {
            ranks
                .iter()
                .any(|r| r.groups.iter().flatten().any(|i| &i.0 == n))
        })
        .collect();
    best.sort_by_key(|b| std::cmp::Reverse(b.1));
    if let Some(&(_, top)) = best.first() {
        let leaders: Vec<String> = best
            .iter()
            .filter(|b| b.1 == top)
            .map(|b| b.0.clone())
            .collect();
        let _ = write!(
            s,
            " Closest to the exact answers: {} (first or tied first on {top} of {} checks).",
            and_list(&leaders),
            ranks.len()
        );
    }
    Some(s)
}

/// The sentence on chaos, if the probe ran.
fn chaos(comp: &CaseComparison) -> Option<String> {
    let c = comp.chaos.as_ref()?;
    Some(if c.chaotic {
        let rate = c.rate.unwrap_or(f64::NAN);
        format!(
            "Chaotic case: a {:e} perturbation of {}'s initial positions grew ×{} (rate {} /s, e-folding time {} s, from t = {} s to {} s; docs/physics.md §6.5), so runs that differ at rounding diverge: the divergence between runs below is expected here and is not a disagreement about the physics.",
            c.perturbation,
            c.formulation,
            fmt_num(c.growth),
            fmt_num(rate),
            fmt_num(1.0 / rate),
            fmt_num(c.window.0),
            fmt_num(c.window.1)
        )
    } else {
        format!(
            "Not chaotic: a {:e} perturbation of {}'s initial positions grew ×{} at most (docs/physics.md §6.5).",
            c.perturbation,
            c.formulation,
            fmt_num(c.growth)
        )
    })
}

/// The sentence on the divergence between runs.
fn divergence(comp: &CaseComparison, reference: &str) -> Option<String> {
    let mine: Vec<_> = comp.pairs.iter().filter(|p| p.a == reference).collect();
    let thr = mine.first()?.threshold;
    let items: Vec<String> = mine
        .iter()
        .map(|p| match p.diverged_at {
            None => format!(
                "{} within it (max {} d_med)",
                p.b,
                fmt_num(p.max_rms_position_rel)
            ),
            Some(t) => format!(
                "{} beyond it from t = {} s (max {} d_med)",
                p.b,
                fmt_num(t),
                fmt_num(p.max_rms_position_rel)
            ),
        })
        .collect();
    Some(format!(
        "Divergence between runs (RMS position difference from {reference}, in median floe diameters d_med; threshold {thr} d_med): {}.",
        items.join("; ")
    ))
}

/// The sentence on the dissipation.
fn dissipation(comp: &CaseComparison) -> Option<String> {
    let done: Vec<(String, f64)> = comp
        .runs
        .iter()
        .filter(|r| r.summary.end == EndReason::Completed)
        .map(|r| {
            (
                r.summary.formulation.clone(),
                r.summary.energy.ledger.dissipated,
            )
        })
        .collect();
    let scale = comp
        .runs
        .iter()
        .map(|r| r.summary.energy.exchanged)
        .fold(0.0, f64::max)
        .max(f64::MIN_POSITIVE);
    if done.is_empty() {
        return None;
    }
    if done.iter().all(|d| within_rounding(d.1, 0.0, scale)) {
        return Some("No formulation dissipates energy in contacts.".into());
    }
    let groups = ranking::rank(&done, |d| -d.1, |a, b| within_rounding(a.1, b.1, scale));
    let mut texts: Vec<String> = Vec::new();
    for (k, g) in groups.iter().enumerate() {
        let names: Vec<&str> = g.iter().map(|d| d.0.as_str()).collect();
        let v = g[0].1;
        let created = if v < 0.0 && !within_rounding(v, 0.0, scale) {
            ", its contacts created energy"
        } else {
            ""
        };
        // Two ranks that print alike: say by how much they differ.
        let less = match k.checked_sub(1).map(|p| groups[p][0].1) {
            Some(prev) if fmt_num(prev) == fmt_num(v) => {
                format!(", {} J less", fmt_num(prev - v))
            }
            _ => String::new(),
        };
        texts.push(format!(
            "{} ({} J{less}{created})",
            names.join(" = "),
            fmt_num(v)
        ));
    }
    Some(if groups.len() == 1 {
        format!(
            "Dissipation in contacts: the same for {} to rounding, {} J of {} J exchanged.",
            if done.len() > 1 {
                "every formulation"
            } else {
                "the one run"
            },
            fmt_num(groups[0][0].1),
            fmt_num(scale)
        )
    } else {
        format!(
            "Dissipation in contacts, most first (of {} J exchanged; `=` is a tie within rounding): {}.",
            fmt_num(scale),
            texts.join(" > ")
        )
    })
}

/// `median s, min–max over N repeats`, to the digits the spread supports.
fn cpu_text(c: &Spread) -> String {
    let (m, lo, hi) = fmt_spread(c.median, c.min, c.max);
    if c.count() > 1 {
        format!("{m} s, {lo}–{hi} over {} repeats", c.count())
    } else {
        format!("{m} s, one run")
    }
}

/// The sentence on the speed.
fn speed(comp: &CaseComparison) -> Option<String> {
    let done: Vec<(String, Spread)> = comp
        .runs
        .iter()
        .zip(&comp.cpu)
        .filter(|(r, _)| r.summary.end == EndReason::Completed)
        .map(|(r, c)| (r.summary.formulation.clone(), c.clone()))
        .collect();
    if done.len() < 2 {
        return None;
    }
    let groups = ranking::rank(&done, |d| d.1.median, |a, b| a.1.tied_with(&b.1));
    let show = |g: &[(String, Spread)]| -> String {
        g.iter()
            .map(|(n, c)| format!("{n} ({})", cpu_text(c)))
            .collect::<Vec<_>>()
            .join(", ")
    };
    // One rule (`Spread::tied_with`): ties from the repeats' spread only;
    // with one run each no tie is called, and the sentence says so.
    let single = done.iter().all(|d| d.1.count() < 2);
    let note = if single {
        "; one run each: no spread is known, so no tie is called (--repeat N measures it)"
    } else {
        ""
    };
    if groups.len() == 1 {
        return Some(format!(
            "CPU time: all tied (the repeats cannot tell them apart): {}.",
            show(&groups[0])
        ));
    }
    let fast = &groups[0];
    let tied = if fast.len() > 1 {
        " (tied: the repeats cannot tell them apart)"
    } else {
        ""
    };
    // Only the fastest is claimed; the others are given by their ratio.
    let others: Vec<String> = groups[1..]
        .iter()
        .flatten()
        .map(|(n, c)| format!("{n} {}×", ratio_text(c, &fast[0].1)))
        .collect();
    Some(format!(
        "Fastest: {}{tied}; the others' median CPU time, as a multiple of the fastest's: {}{note}.",
        show(fast),
        others.join(", ")
    ))
}

/// The verdict on a case, one sentence per aspect (see the module doc).
pub fn verdict(comp: &CaseComparison) -> Vec<String> {
    let mut lines = Vec::new();
    let Some(reference) = comp.runs.first() else {
        return lines;
    };
    let rname = reference.summary.formulation.as_str();
    let names: Vec<String> = comp
        .runs
        .iter()
        .map(|r| r.summary.formulation.clone())
        .collect();
    match truth(comp, &names) {
        Some(t) => lines.push(t),
        None if comp.runs.len() > 1 => lines.push(
            "No check of this case has an exact answer: the divergence between runs shows how differently the formulations resolve it, not which one is right.".into(),
        ),
        None => {}
    }
    lines.extend(chaos(comp));
    lines.extend(divergence(comp, rname));
    lines.extend(dissipation(comp));
    lines.extend(speed(comp));
    for r in comp
        .runs
        .iter()
        .filter(|r| r.summary.end != EndReason::Completed)
    {
        lines.push(format!(
            "{} stopped at t = {} s: {}.",
            r.summary.formulation,
            fmt_num(r.summary.t_reached),
            end_text(&r.summary.end)
        ));
    }
    for f in &comp.findings {
        lines.push(format!("Finding: {f}."));
    }
    lines
}
