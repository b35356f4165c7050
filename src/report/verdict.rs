//! The verdict on a case: one sentence per aspect (agreement with the
//! reference, dissipation, speed, incomplete runs), printed by
//! `floebench compare` and written on the page and in `summary.json`.

use super::format::fmt_num;
use super::tables::end_text;
use crate::analysis::comparison::CaseComparison;
use crate::run::{EndReason, RunResult, RunSummary};
use std::fmt::Write as _;

/// The verdict on a case, one sentence per aspect: agreement with the first
/// formulation (the reference), dissipation, speed, incomplete runs.
pub fn verdict(comp: &CaseComparison) -> Vec<String> {
    let mut lines = Vec::new();
    let Some(reference) = comp.runs.first() else {
        return lines;
    };
    let rname = &reference.summary.formulation;
    let (mut agree, mut differ) = (Vec::new(), Vec::new());
    for p in comp.pairs.iter().filter(|p| &p.a == rname) {
        match p.diverged_at {
            None => agree.push(format!(
                "{} (≤ {} %)",
                p.b,
                fmt_num(100.0 * p.max_rms_position_rel)
            )),
            Some(t) => differ.push(format!(
                "{} from t = {} s (up to {} %)",
                p.b,
                fmt_num(t),
                fmt_num(100.0 * p.max_rms_position_rel)
            )),
        }
    }
    if !agree.is_empty() || !differ.is_empty() {
        let thr = comp.pairs.first().map_or(0.0, |p| p.threshold);
        let mut s = format!(
            "Trajectories against {rname} (RMS position difference, % of the mean floe diameter; threshold {} %): ",
            fmt_num(100.0 * thr)
        );
        if !agree.is_empty() {
            let _ = write!(s, "agree: {}", agree.join(", "));
        }
        if !differ.is_empty() {
            let _ = write!(
                s,
                "{}diverge: {}",
                if agree.is_empty() { "" } else { "; " },
                differ.join(", ")
            );
        }
        s.push('.');
        lines.push(s);
    }
    let done: Vec<&RunResult> = comp
        .runs
        .iter()
        .filter(|r| r.summary.end == EndReason::Completed)
        .collect();
    let by = |f: fn(&RunSummary) -> f64| {
        let mut v: Vec<&RunResult> = done.clone();
        v.sort_by(|a, b| f(&a.summary).total_cmp(&f(&b.summary)));
        v
    };
    let diss = by(|s| s.energy.dissipated);
    if let (Some(lo), Some(hi)) = (diss.first(), diss.last()) {
        let (l, h) = (lo.summary.energy.dissipated, hi.summary.energy.dissipated);
        let scale = hi.summary.energy.exchanged.max(1e-300);
        if h.abs() <= 1e-9 * scale && l.abs() <= 1e-9 * scale {
            lines.push("No formulation dissipates energy in contacts.".into());
        } else if done.len() > 1 {
            lines.push(format!(
                "Dissipation in contacts: most by {} ({} J), least by {} ({} J{}), of {} J exchanged.",
                hi.summary.formulation,
                fmt_num(h),
                lo.summary.formulation,
                fmt_num(l),
                if l < -1e-9 * scale {
                    ": its contacts created energy"
                } else {
                    ""
                },
                fmt_num(scale)
            ));
        } else {
            lines.push(format!("Dissipation in contacts: {} J.", fmt_num(h)));
        }
    }
    let cpu = by(|s| s.timing.cpu_total);
    if let (Some(fast), Some(slow)) = (cpu.first(), cpu.last()) {
        let (f, s) = (fast.summary.timing.cpu_total, slow.summary.timing.cpu_total);
        if done.len() > 1 {
            lines.push(format!(
                "Fastest: {} ({} s CPU), {}× faster than the slowest, {} ({} s).",
                fast.summary.formulation,
                fmt_num(f),
                fmt_num(s / f.max(1e-9)),
                slow.summary.formulation,
                fmt_num(s)
            ));
        }
    }
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
    lines
}
