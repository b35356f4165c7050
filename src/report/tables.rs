//! The tables of the report page: the headline (one row per case and
//! formulation), and per case the runs, the pairs and the checks.

use super::checks::{table_cells, TABLE_HEADER};
use super::format::{fmt_measured, fmt_num, fmt_spread};
use super::page::Block;
use crate::analysis::check::CheckOutcome;
use crate::analysis::comparison::CaseComparison;
use crate::formulation::contact_solver::{
    CONE_FALLBACK_LCP, CONE_SOLVES, LCP_LAST_RESORT_FRICTIONLESS, LCP_SOLVED_BY_FALLBACK,
    LCP_SOLVES, LCP_UNRESOLVED,
};
use crate::record::accuracy::{
    ITERATIONS_MAX, ITERATIONS_MEDIAN, RESIDUAL_MAX, RESIDUAL_MEDIAN, RESIDUAL_P95, SOLVER_MISSED,
    SOLVER_RESIDUAL_MAX,
};
use crate::record::counters::common::{IMPACTS, MAX_PENETRATION, STEPS};
use crate::record::spread::Spread;
use crate::record::Counter;
use crate::run::{EndReason, RunSummary};
use std::fmt::Write as _;

/// The sum of the counts `keys`, or `-` if the formulation keeps none of them.
fn count(s: &RunSummary, keys: &[&Counter]) -> String {
    let found: Vec<u64> = keys
        .iter()
        .filter_map(|k| s.counters.count(k).ok())
        .collect();
    if found.is_empty() {
        "-".into()
    } else {
        found.iter().sum::<u64>().to_string()
    }
}

/// Contact problems solved (LCPs and cone programs).
fn solves(s: &RunSummary) -> String {
    count(s, &[&LCP_SOLVES, &CONE_SOLVES])
}

/// Contact problems that needed a fallback or were not solved.
fn fallbacks(s: &RunSummary) -> String {
    count(
        s,
        &[
            &LCP_SOLVED_BY_FALLBACK,
            &LCP_LAST_RESORT_FRICTIONLESS,
            &LCP_UNRESOLVED,
            &CONE_FALLBACK_LCP,
        ],
    )
}

pub(super) fn end_text(e: &EndReason) -> String {
    e.to_string()
}

/// A CPU time cell: `median (min–max)`, with `; IQR q1–q3` from four
/// repeats on when `iqr`, to the digits the spread supports; the median
/// alone for one run.
pub(super) fn cpu_cell(c: &Spread, iqr: bool) -> String {
    let (q1, q3) = c.iqr.unwrap_or((c.median, c.median));
    let v = fmt_measured(&[c.median, c.min, c.max, q1, q3], width(c));
    if c.count() < 2 {
        return v[0].clone();
    }
    let mut s = format!("{} ({}–{}", v[0], v[1], v[2]);
    if c.iqr.is_some() && iqr {
        let _ = write!(s, "; IQR {}–{}", v[3], v[4]);
    }
    s.push(')');
    s
}

/// The ratio of `c`'s median to `fastest`'s, to the digits their spreads
/// support (the range of the ratio is `c.min / fastest.max` to
/// `c.max / fastest.min`).
pub(super) fn ratio_text(c: &Spread, fastest: &Spread) -> String {
    let f = |v: f64| v.max(1e-12);
    fmt_spread(
        c.median / f(fastest.median),
        c.min / f(fastest.max),
        c.max / f(fastest.min),
    )
    .0
}

/// The spread of smallest median (`None` without any).
pub(super) fn fastest(cpu: &[Spread]) -> Option<&Spread> {
    cpu.iter().min_by(|a, b| a.median.total_cmp(&b.median))
}

/// The width of a spread (0 for one run), s.
fn width(c: &Spread) -> f64 {
    c.max - c.min
}

/// The runs table of a case: one row per formulation.
pub(super) fn runs_table(comp: &CaseComparison) -> Block {
    // The lattice stage's column only where impacts ran in the lattices.
    let lattice = comp
        .runs
        .iter()
        .any(|r| r.summary.timing.stages.lattice > 0.0);
    let stages_header = if lattice {
        "detection / solve / integration / lattice (s)"
    } else {
        "detection / solve / integration (s)"
    };
    let header = [
        "formulation",
        "end",
        "CPU (s): median (range; IQR)",
        "CPU per sim. s",
        stages_header,
        "E_k final (J)",
        "dissipated (J)",
        "residual / exchanged",
        "steps",
        "impacts",
        "contact solves",
        "fallbacks",
        "solver",
        "solver residual (max)",
        "Coulomb-law residual: median / p95 / max",
        "work per solve: median / max",
        "missed tolerance",
        "max penetration (m)",
    ];
    let rows = comp
        .runs
        .iter()
        .zip(&comp.cpu)
        .map(|(r, c)| {
            let s = &r.summary;
            let t = &s.timing;
            let w = width(c);
            let per = s.t_reached.max(1e-300);
            vec![
                s.formulation.clone(),
                end_text(&s.end),
                cpu_cell(c, true),
                fmt_measured(&[c.median / per], w / per).remove(0),
                fmt_measured(
                    &[
                        t.stages.detection,
                        t.stages.solve,
                        t.stages.integration,
                        t.stages.lattice,
                    ][..if lattice { 4 } else { 3 }],
                    w,
                )
                .join(" / "),
                fmt_num(s.energy.final_kinetic),
                fmt_num(s.energy.ledger.dissipated),
                fmt_num(s.energy.max_abs_residual / s.energy.exchanged.max(1e-300)),
                count(s, &[&STEPS]),
                count(s, &[&IMPACTS]),
                solves(s),
                fallbacks(s),
                s.settings.get_text("solver").unwrap_or("-").to_string(),
                figures(s, &[&SOLVER_RESIDUAL_MAX]),
                figures(s, &[&RESIDUAL_MEDIAN, &RESIDUAL_P95, &RESIDUAL_MAX]),
                figures(s, &[&ITERATIONS_MEDIAN, &ITERATIONS_MAX]),
                figures(s, &[&SOLVER_MISSED]),
                s.counters
                    .value(&MAX_PENETRATION)
                    .ok()
                    .flatten()
                    .map_or("-".into(), fmt_num),
            ]
        })
        .collect();
    Block::Table {
        header: header.iter().map(|h| h.to_string()).collect(),
        rows,
    }
}

/// The pairs table of a case.
pub(super) fn pairs_table(comp: &CaseComparison) -> Block {
    let header = [
        "a",
        "b",
        "max RMS Δx / d_med",
        "final RMS Δx / d_med",
        "max Δx (m)",
        "max Δθ (rad)",
        "diverged at (s)",
    ];
    let rows = comp
        .pairs
        .iter()
        .map(|p| {
            vec![
                p.a.clone(),
                p.b.clone(),
                fmt_num(p.max_rms_position_rel),
                fmt_num(p.final_rms_position_rel),
                fmt_num(p.max_position_m),
                fmt_num(p.max_angle_rad),
                p.diverged_at.map_or("never".into(), fmt_num),
            ]
        })
        .collect();
    Block::Table {
        header: header.iter().map(|h| h.to_string()).collect(),
        rows,
    }
}

/// The check table of a case (as `floebench check` prints it).
pub(super) fn checks_table(comp: &CaseComparison) -> Block {
    Block::Table {
        header: TABLE_HEADER[1..].iter().map(|h| h.to_string()).collect(),
        rows: comp
            .checks
            .iter()
            .map(|o| table_cells(o)[1..].to_vec())
            .collect(),
    }
}

/// `pass/known/FAIL` counts of a run's checks.
fn check_counts(comp: &CaseComparison, formulation: &str) -> String {
    let mine: Vec<&CheckOutcome> = comp
        .checks
        .iter()
        .filter(|o| o.formulation == formulation)
        .collect();
    let pass = mine.iter().filter(|o| o.pass).count();
    let known = mine.iter().filter(|o| !o.pass && !o.claimed).count();
    let fail = mine.iter().filter(|o| !o.pass && o.claimed).count();
    let mut s = format!("{pass}/{}", mine.len());
    if known > 0 {
        let _ = write!(s, ", {known} known");
    }
    if fail > 0 {
        let _ = write!(s, ", **{fail} FAIL**");
    }
    s
}

/// The figures `counters` of a run, ` / `-separated (`-` for one it does
/// not keep or never set: rapier solves no contact problem).
fn figures(s: &RunSummary, counters: &[&Counter]) -> String {
    counters
        .iter()
        .map(|c| {
            s.counters
                .value(c)
                .ok()
                .flatten()
                .map_or("-".into(), fmt_num)
        })
        .collect::<Vec<_>>()
        .join(" / ")
}

/// The solver's largest residual, flagged with the count of solves that
/// missed the solver's tolerance (`-` for a run that solves no contact
/// problem).
fn solver_cell(s: &RunSummary) -> String {
    let missed = s
        .counters
        .value(&SOLVER_MISSED)
        .ok()
        .flatten()
        .unwrap_or(0.0);
    let max = figures(s, &[&SOLVER_RESIDUAL_MAX]);
    if missed > 0.0 {
        format!("{max} (**{missed} missed their tolerance**)")
    } else {
        max
    }
}

/// What the two residual columns measure, for the report page (the
/// definitions are in docs/output-format.md).
pub(super) const RESIDUALS_NOTE: &str = "Two residuals stand beside the CPU. The **solver \
     residual** is the solver's error: the residual of each answer on the problem its solver \
     solved (Lemke: the LCP's ‖min(z, w)‖/‖q‖, accepted at 1e-10; clarabel and APGD: the cone \
     relaxation's; NSGS: Coulomb's law's, at its tolerance), with the solves that missed \
     their solver's tolerance flagged. The **Coulomb-law residual** is the departure of the \
     impulses applied from Signorini's condition and Coulomb's law with one friction pair per \
     contact point: the solver's error plus the departure of the problem solved from that \
     law, by design (the cone relaxation lifts a sliding contact: up to order 1; the merged \
     friction of flush edge pairs: about 1e-3). rapier solves no contact problem (`-`).";

/// The headline table: one row per (case, formulation).
pub(super) fn headline(comps: &[CaseComparison]) -> Block {
    let header = [
        "case",
        "formulation",
        "end",
        "CPU (s): median (range)",
        "× fastest median",
        "solver residual (max)",
        "Coulomb-law residual (max)",
        "E_k final (J)",
        "dissipated (J)",
        "max divergence from the first (d_med)",
        "checks passed",
    ];
    let mut rows = Vec::new();
    for c in comps {
        let none = Spread::of(&[]);
        let fastest = fastest(&c.cpu).unwrap_or(&none);
        for (i, (r, cpu)) in c.runs.iter().zip(&c.cpu).enumerate() {
            let s = &r.summary;
            let div = if i == 0 {
                "(reference)".to_string()
            } else {
                c.pairs
                    .iter()
                    .find(|p| p.a == c.runs[0].summary.formulation && p.b == s.formulation)
                    .map_or("-".into(), |p| fmt_num(p.max_rms_position_rel))
            };
            let ratio = ratio_text(cpu, fastest);
            rows.push(vec![
                s.case.clone(),
                s.formulation.clone(),
                end_text(&s.end),
                cpu_cell(cpu, false),
                ratio,
                solver_cell(s),
                figures(s, &[&RESIDUAL_MAX]),
                fmt_num(s.energy.final_kinetic),
                fmt_num(s.energy.ledger.dissipated),
                div,
                check_counts(c, &s.formulation),
            ]);
        }
    }
    Block::Table {
        header: header.iter().map(|h| h.to_string()).collect(),
        rows,
    }
}
