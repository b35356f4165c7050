//! Writing a comparison: data first (CSV, JSON), then the plots, then the
//! report page.
//!
//! ```text
//! <out>/index.md, index.html          the page: headline table, per case verdict, tables, plots
//! <out>/<case>/metrics.csv            case,formulation,other,metric,value,unit (long format)
//! <out>/<case>/divergence.csv         t,a,b,rms_position_rel,max_position_m,rms_angle_rad,max_angle_rad
//! <out>/<case>/checks.csv             case,formulation,check,measured,expected,tolerance,unit,pass,claimed,note
//! <out>/<case>/summary.json           the case, each run's summary, the pairs, the verdict
//! <out>/<case>/<formulation>/         trajectory.csv, energy.csv, summary.json (as `floebench run`)
//! <out>/<case>/*.png, *.svg           kinetic, dissipated, divergence, paths, snapshots, cpu
//! ```
//!
//! A case's folder is written under a temporary name and swapped into place
//! when complete, so a reader never sees a half-written case; the page is
//! written last.

use super::figures::{self, Figure};
use super::page::{self, Block};
use super::ReportError;
use crate::analysis::check::{self, CheckOutcome};
use crate::analysis::comparison::CaseComparison;
use crate::analysis::divergence::{self, PairDivergence};
use crate::analysis::metrics::MetricRow;
use crate::formulation::contact_solver::{
    CONE_FALLBACK_LCP, CONE_SOLVES, LCP_LAST_RESORT_FRICTIONLESS, LCP_SOLVED_BY_FALLBACK,
    LCP_SOLVES, LCP_UNRESOLVED,
};
use crate::record::counters::common::{IMPACTS, MAX_PENETRATION, STEPS};
use crate::record::Counter;
use crate::run::output::{self, write_atomic};
use crate::run::{EndReason, RunResult, RunSummary};
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> ReportError + '_ {
    move |source| ReportError::Io {
        path: path.to_path_buf(),
        source,
    }
}

/// A number with four significant digits, fixed or scientific by magnitude.
pub fn fmt_num(v: f64) -> String {
    if !v.is_finite() {
        return format!("{v}");
    }
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if (1e-3..1e5).contains(&a) {
        let decimals = (3 - a.log10().floor() as i32).clamp(0, 6) as usize;
        format!("{v:.decimals$}")
    } else {
        format!("{v:.3e}")
    }
}

/// `metrics.csv`: `case,formulation,other,metric,value,unit`.
pub fn metrics_csv(rows: &[MetricRow]) -> String {
    let mut s = String::from("case,formulation,other,metric,value,unit\n");
    for r in rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{}",
            r.case, r.formulation, r.other, r.metric, r.value, r.unit
        );
    }
    s
}

/// `divergence.csv`: one row per pair and output time.
pub fn divergence_csv(pairs: &[PairDivergence]) -> String {
    let mut s = String::from("t,a,b,rms_position_rel,max_position_m,rms_angle_rad,max_angle_rad\n");
    for p in pairs {
        for d in &p.samples {
            let _ = writeln!(
                s,
                "{},{},{},{},{},{},{}",
                d.t,
                p.a,
                p.b,
                d.rms_position_rel,
                d.max_position_m,
                d.rms_angle_rad,
                d.max_angle_rad
            );
        }
    }
    s
}

/// A pair's summary, without its time series (which is in `divergence.csv`).
#[derive(Debug, Serialize)]
struct PairSummary<'a> {
    a: &'a str,
    b: &'a str,
    max_rms_position_rel: f64,
    final_rms_position_rel: f64,
    max_position_m: f64,
    max_angle_rad: f64,
    threshold: f64,
    diverged_at_s: Option<f64>,
}

/// `summary.json` of a case.
#[derive(Debug, Serialize)]
struct CaseSummary<'a> {
    case: &'a str,
    file: String,
    description: &'a str,
    floes: usize,
    obstacles: usize,
    duration_s: f64,
    output_interval_s: f64,
    restitution: f64,
    friction: f64,
    mean_diameter_m: f64,
    verdict: Vec<String>,
    runs: Vec<&'a RunSummary>,
    pairs: Vec<PairSummary<'a>>,
    checks: &'a [CheckOutcome],
}

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

fn end_text(e: &EndReason) -> String {
    match e {
        EndReason::Completed => "completed".into(),
        EndReason::Failed { message } => format!("failed: {message}"),
        EndReason::NonFinite { floe } => format!("non-finite state (floe {floe})"),
    }
}

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

/// The runs table of a case: one row per formulation.
fn runs_table(comp: &CaseComparison) -> Block {
    let header = [
        "formulation",
        "end",
        "CPU (s)",
        "CPU per sim. s",
        "detection / solve / integration (s)",
        "E_k final (J)",
        "dissipated (J)",
        "residual / exchanged",
        "steps",
        "impacts",
        "contact solves",
        "fallbacks",
        "max penetration (m)",
    ];
    let rows = comp
        .runs
        .iter()
        .map(|r| {
            let s = &r.summary;
            let t = &s.timing;
            vec![
                s.formulation.clone(),
                end_text(&s.end),
                fmt_num(t.cpu_total),
                fmt_num(t.cpu_total / s.t_reached.max(1e-300)),
                format!(
                    "{} / {} / {}",
                    fmt_num(t.stages.detection),
                    fmt_num(t.stages.solve),
                    fmt_num(t.stages.integration)
                ),
                fmt_num(s.energy.final_kinetic),
                fmt_num(s.energy.dissipated),
                fmt_num(s.energy.max_abs_residual / s.energy.exchanged.max(1e-300)),
                count(s, &[&STEPS]),
                count(s, &[&IMPACTS]),
                solves(s),
                fallbacks(s),
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
fn pairs_table(comp: &CaseComparison) -> Block {
    let header = [
        "a",
        "b",
        "max RMS Δx / d̄",
        "final RMS Δx / d̄",
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
fn checks_table(comp: &CaseComparison) -> Block {
    Block::Table {
        header: check::TABLE_HEADER[1..]
            .iter()
            .map(|h| h.to_string())
            .collect(),
        rows: comp
            .checks
            .iter()
            .map(|o| check::table_cells(o)[1..].to_vec())
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

/// `checks.csv`: one row per check outcome.
pub fn checks_csv(rows: &[CheckOutcome]) -> String {
    let mut s =
        String::from("case,formulation,check,measured,expected,tolerance,unit,pass,claimed,note\n");
    for o in rows {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{},{},\"{}\"",
            o.case,
            o.formulation,
            o.check,
            o.measured,
            o.expected.map_or(String::new(), |e| e.to_string()),
            o.tolerance,
            o.unit,
            o.pass,
            o.claimed,
            o.note.replace('"', "'")
        );
    }
    s
}

/// The headline table: one row per (case, formulation).
fn headline(comps: &[CaseComparison]) -> Block {
    let header = [
        "case",
        "formulation",
        "end",
        "CPU (s)",
        "× fastest",
        "E_k final (J)",
        "dissipated (J)",
        "max RMS Δx / d̄ vs first",
        "checks passed",
    ];
    let mut rows = Vec::new();
    for c in comps {
        let fastest = c
            .runs
            .iter()
            .map(|r| r.summary.timing.cpu_total)
            .fold(f64::INFINITY, f64::min)
            .max(1e-9);
        for (i, r) in c.runs.iter().enumerate() {
            let s = &r.summary;
            let div = if i == 0 {
                "(reference)".to_string()
            } else {
                c.pairs
                    .iter()
                    .find(|p| p.a == c.runs[0].summary.formulation && p.b == s.formulation)
                    .map_or("-".into(), |p| fmt_num(p.max_rms_position_rel))
            };
            rows.push(vec![
                s.case.clone(),
                s.formulation.clone(),
                end_text(&s.end),
                fmt_num(s.timing.cpu_total),
                fmt_num(s.timing.cpu_total / fastest),
                fmt_num(s.energy.final_kinetic),
                fmt_num(s.energy.dissipated),
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

/// Writes one case's folder at `dir` (which must not exist yet): data, then
/// the plots; returns the verdict and the figures.
fn write_case(
    comp: &CaseComparison,
    dir: &Path,
) -> Result<(Vec<String>, Vec<Figure>), ReportError> {
    std::fs::create_dir_all(dir).map_err(io_err(dir))?;
    for r in &comp.runs {
        let d = dir.join(&r.summary.formulation);
        output::write_run(&d, r).map_err(io_err(&d))?;
    }
    let verdict = verdict(comp);
    let summary = CaseSummary {
        case: &comp.scenario.name,
        file: comp.path.display().to_string(),
        description: &comp.scenario.description,
        floes: comp.scenario.floes.len(),
        obstacles: comp.scenario.obstacles.len(),
        duration_s: comp.scenario.duration,
        output_interval_s: comp.scenario.output_interval,
        restitution: comp.scenario.contact.restitution,
        friction: comp.scenario.contact.friction,
        mean_diameter_m: divergence::mean_diameter(&comp.scenario),
        verdict: verdict.clone(),
        runs: comp.runs.iter().map(|r| &r.summary).collect(),
        pairs: comp
            .pairs
            .iter()
            .map(|p| PairSummary {
                a: &p.a,
                b: &p.b,
                max_rms_position_rel: p.max_rms_position_rel,
                final_rms_position_rel: p.final_rms_position_rel,
                max_position_m: p.max_position_m,
                max_angle_rad: p.max_angle_rad,
                threshold: p.threshold,
                diverged_at_s: p.diverged_at,
            })
            .collect(),
        checks: &comp.checks,
    };
    let json = serde_json::to_vec_pretty(&summary).map_err(|e| ReportError::Io {
        path: dir.join("summary.json"),
        source: std::io::Error::other(e),
    })?;
    let files = [
        ("metrics.csv", metrics_csv(&comp.metrics).into_bytes()),
        ("divergence.csv", divergence_csv(&comp.pairs).into_bytes()),
        ("checks.csv", checks_csv(&comp.checks).into_bytes()),
        ("summary.json", json),
    ];
    for (name, bytes) in files {
        let p = dir.join(name);
        write_atomic(&p, &bytes).map_err(io_err(&p))?;
    }
    let figs = figures::draw(comp, dir)?;
    Ok((verdict, figs))
}

/// Replaces `target` by the complete folder `staged`.
fn swap_into_place(staged: &Path, target: &Path) -> Result<(), ReportError> {
    let old = target.with_file_name(format!(
        ".{}.old{}",
        target
            .file_name()
            .map_or("case".into(), |n| n.to_string_lossy()),
        std::process::id()
    ));
    if target.exists() {
        std::fs::rename(target, &old).map_err(io_err(target))?;
    }
    std::fs::rename(staged, target).map_err(io_err(target))?;
    if old.exists() {
        std::fs::remove_dir_all(&old).map_err(io_err(&old))?;
    }
    Ok(())
}

/// Writes the whole report into `out`: one folder per case, then
/// `index.md` and `index.html`. `command` is the command line that
/// produced it, quoted on the page. Returns the files of the page.
pub fn write_report(
    comps: &[CaseComparison],
    out: &Path,
    command: &str,
) -> Result<Vec<PathBuf>, ReportError> {
    let mut names: Vec<&str> = comps.iter().map(|c| c.scenario.name.as_str()).collect();
    names.sort_unstable();
    if let Some(w) = names.windows(2).find(|w| w[0] == w[1]) {
        return Err(ReportError::DuplicateName(w[0].to_string()));
    }
    std::fs::create_dir_all(out).map_err(io_err(out))?;
    let mut blocks = vec![
        Block::Heading(1, "floebench comparison report".into()),
        Block::Para(format!(
            "Produced by `{command}` (floebench {}). CPU times are each run's own thread CPU seconds \
             (runs go in parallel); Δx is a floe's centre-of-mass distance between two runs at the \
             same output time, d̄ the mean equal-area floe diameter. Data: each case's \
             `metrics.csv`, `divergence.csv`, `summary.json` and `<formulation>/` folder.",
            env!("CARGO_PKG_VERSION")
        )),
        Block::Heading(2, "Headline".into()),
        headline(comps),
    ];
    for comp in comps {
        let name = &comp.scenario.name;
        let staged = out.join(format!(".{name}.partial{}", std::process::id()));
        if staged.exists() {
            std::fs::remove_dir_all(&staged).map_err(io_err(&staged))?;
        }
        let (verdict, figs) = write_case(comp, &staged)?;
        swap_into_place(&staged, &out.join(name))?;
        blocks.push(Block::Heading(2, name.clone()));
        blocks.push(Block::Para(format!(
            "`{}`: {} floes, {} obstacles, {} s, e = {}, μ = {}. {}",
            comp.path.display(),
            comp.scenario.floes.len(),
            comp.scenario.obstacles.len(),
            fmt_num(comp.scenario.duration),
            comp.scenario.contact.restitution,
            comp.scenario.contact.friction,
            comp.scenario.description
        )));
        blocks.push(Block::Para(format!("**Verdict.** {}", verdict.join(" "))));
        blocks.push(runs_table(comp));
        if !comp.pairs.is_empty() {
            blocks.push(pairs_table(comp));
        }
        if !comp.checks.is_empty() {
            blocks.push(Block::Para(format!(
                "Physical checks (`floebench check {}`): \"fail (known)\" is a failure the formulation does not claim to pass (a finding, with its reason); FAIL is a claimed check that failed.",
                comp.path.display()
            )));
            blocks.push(checks_table(comp));
        }
        blocks.push(Block::Figures(
            figs.iter()
                .map(|f| {
                    (
                        format!("{name}: {}", f.alt),
                        format!("{name}/{}.png", f.stem),
                        format!("{name}/{}.svg", f.stem),
                    )
                })
                .collect(),
        ));
    }
    let md = out.join("index.md");
    let html = out.join("index.html");
    write_atomic(&md, page::markdown(&blocks).as_bytes()).map_err(io_err(&md))?;
    write_atomic(
        &html,
        page::html("floebench comparison report", &blocks).as_bytes(),
    )
    .map_err(io_err(&html))?;
    Ok(vec![md, html])
}
