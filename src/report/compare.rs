//! Writing a comparison: data first (CSV, JSON), then the plots and the
//! animation, then the report page.
//!
//! ```text
//! <out>/index.md, index.html          the page: headline table, per case verdict, tables, plots
//! <out>/<case>/metrics.csv            case,formulation,other,metric,value,unit (long format)
//! <out>/<case>/divergence.csv         t,a,b,rms_position_rel,max_position_m,rms_angle_rad,max_angle_rad
//! <out>/<case>/checks.csv             case,formulation,check,measured,expected,tolerance,unit,pass,claimed,note
//! <out>/<case>/floe_sizes.csv         formulation,when,area_m2,count_at_least (cases whose floes can break)
//! <out>/<case>/summary.json           the case, each run's summary, the pairs, the verdict
//! <out>/<case>/<formulation>/         trajectory.csv, energy.csv, summary.json, floes.json,
//!                                     fractures.csv, percussion.json (as `floebench run`)
//! <out>/<case>/*.png, *.svg           kinetic, dissipated, divergence, paths, snapshots, cpu, floe_sizes,
//!                                     crack_<formulation> (lattice runs that broke a floe)
//! <out>/<case>/animation.gif          the floes over time, one panel per completed run
//! ```
//!
//! A case's folder replaces only a folder of the same report
//! ([`super::folder`]); it is written under a temporary name and swapped into place
//! when complete, so a reader never sees a half-written case; the page is
//! written last. The CSV and JSON files hold every number at full precision
//! (Rust's shortest round-trip form); the page rounds them with
//! [`super::format::fmt_num`].

use super::checks::checks_csv;
use super::figures::{self, Animation, Figure};
use super::page::{self, Block};
use super::parameters::{case_parameters, settings_table};
use super::provenance::Provenance;
use super::tables::{checks_table, headline, pairs_table, runs_table, RESIDUALS_NOTE};
use super::verdict::verdict;
use super::ReportError;
use crate::analysis::chaos::ChaosProbe;
use crate::analysis::check::CheckOutcome;
use crate::analysis::comparison::CaseComparison;
use crate::analysis::divergence::PairDivergence;
use crate::analysis::floe_sizes::FloeSizes;
use crate::analysis::metrics::MetricRow;
use crate::fsio::write_atomic;
use crate::record::spread::Spread;
use crate::run::output;
use crate::run::RunSummary;
use serde::Serialize;
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

fn io_err(path: &Path) -> impl FnOnce(std::io::Error) -> ReportError + '_ {
    move |source| ReportError::Io {
        path: path.to_path_buf(),
        source,
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

/// `floe_sizes.csv`: one row per point of each distribution
/// (`formulation` empty for the start, the case's initial floes).
pub fn floe_sizes_csv(sizes: &[FloeSizes]) -> String {
    let mut s = String::from("formulation,when,area_m2,count_at_least\n");
    for d in sizes {
        for (a, n) in &d.points {
            let _ = writeln!(s, "{},{},{a},{n}", d.formulation, d.when.name());
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

/// The CPU time of a run over its repeats.
#[derive(Debug, Serialize)]
struct CpuSummary<'a> {
    formulation: &'a str,
    #[serde(flatten)]
    spread: &'a Spread,
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
    /// The median equal-area floe diameter `d_med`, m: the unit of every
    /// divergence.
    median_diameter_m: f64,
    verdict: Vec<String>,
    /// Runs of each formulation.
    repeats: usize,
    /// The spread of each run's CPU time over its repeats, s.
    cpu: Vec<CpuSummary<'a>>,
    /// Repeats whose physics was not bit-identical.
    findings: &'a [String],
    /// The chaos probe (`null` when not run).
    chaos: Option<&'a ChaosProbe>,
    runs: Vec<&'a RunSummary>,
    pairs: Vec<PairSummary<'a>>,
    checks: &'a [CheckOutcome],
}

/// What the page shows of a case folder: the verdict, the figures and the
/// animation (`None` when no run completed).
type CaseParts = (Vec<String>, Vec<Figure>, Option<Animation>);

/// Writes one case's folder at `dir` (which must not exist yet): data, then
/// the plots and the animation.
fn write_case(comp: &CaseComparison, dir: &Path, netcdf: bool) -> Result<CaseParts, ReportError> {
    std::fs::create_dir_all(dir).map_err(io_err(dir))?;
    for r in &comp.runs {
        let d = dir.join(&r.summary.formulation);
        output::write_run(&d, r).map_err(io_err(&d))?;
        if netcdf {
            output::write_netcdf(&d, r, &comp.scenario).map_err(io_err(&d))?;
        }
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
        median_diameter_m: comp.scenario.median_floe_diameter(),
        verdict: verdict.clone(),
        repeats: comp.cpu.iter().map(Spread::count).max().unwrap_or(0),
        cpu: comp
            .runs
            .iter()
            .zip(&comp.cpu)
            .map(|(r, c)| CpuSummary {
                formulation: &r.summary.formulation,
                spread: c,
            })
            .collect(),
        findings: &comp.findings,
        chaos: comp.chaos.as_ref(),
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
    let mut files = vec![
        ("metrics.csv", metrics_csv(&comp.metrics).into_bytes()),
        ("divergence.csv", divergence_csv(&comp.pairs).into_bytes()),
        ("checks.csv", checks_csv(&comp.checks).into_bytes()),
        ("summary.json", json),
    ];
    if !comp.floe_sizes.is_empty() {
        files.push((
            "floe_sizes.csv",
            floe_sizes_csv(&comp.floe_sizes).into_bytes(),
        ));
    }
    for (name, bytes) in files {
        let p = dir.join(name);
        write_atomic(&p, &bytes).map_err(io_err(&p))?;
    }
    let figs = figures::draw(comp, dir)?;
    let anim = figures::animate(comp, dir)?;
    Ok((verdict, figs, anim))
}

/// The line under a case's heading: `` `path`: description ``, or the path
/// alone when the case has no description.
fn case_line(comp: &CaseComparison) -> String {
    let (path, d) = (comp.path.display(), &comp.scenario.description);
    if d.trim().is_empty() {
        format!("`{path}`")
    } else {
        format!("`{path}`: {d}")
    }
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
    write_report_with(comps, out, command, false)
}

/// [`write_report`], with each run's trajectory also written as
/// `trajectory.nc` when `netcdf` (`compare --netcdf`).
pub fn write_report_with(
    comps: &[CaseComparison],
    out: &Path,
    command: &str,
    netcdf: bool,
) -> Result<Vec<PathBuf>, ReportError> {
    let names: Vec<&str> = comps.iter().map(|c| c.scenario.name.as_str()).collect();
    super::folder::check(out, &names)?;
    std::fs::create_dir_all(out).map_err(io_err(out))?;
    let prov = Provenance::current();
    let repeats = comps
        .iter()
        .flat_map(|c| c.cpu.iter().map(Spread::count))
        .max()
        .unwrap_or(1);
    let mut blocks = vec![
        Block::Heading(1, "floebench comparison report".into()),
        Block::Para(format!(
            "Produced by `{command}`: floebench {}, commit `{}`, on `{}` ({}, {} cores), {}.",
            prov.version, prov.commit, prov.host, prov.cpu, prov.cores, prov.date
        )),
        Block::Para(format!(
            "CPU times are each run's own thread CPU seconds (runs go in parallel), over {} of \
             each run: the median, then the range (min–max) and from four repeats the \
             interquartile range, every number to the digits that spread supports; two \
             formulations are tied on speed when the 95 % confidence intervals of their medians \
             (ranges up to 7 repeats) overlap or their medians are within 1.25×, and runs under 0.25 s are repeated until \
             they total that (docs/physics.md §6.6). The physics of the \
             repeats is bit-identical (checked). Δx is a floe's centre-of-mass distance between \
             two runs at the same output time, d_med the median equal-area floe diameter (the \
             median, so that one floe of another size does not set the scale): every \
             divergence is in d_med. Verdicts rank formulations by their error to the exact \
             answers where a check has one; divergence between runs says how much two runs \
             differ, not which is right. Data: each case's `metrics.csv`, `divergence.csv`, \
             `checks.csv`, `summary.json` and `<formulation>/` folder.",
            if repeats > 1 {
                format!("{repeats} repeats")
            } else {
                "a single run (`--repeat N` measures the spread)".to_string()
            }
        )),
        Block::Heading(2, "Headline".into()),
        headline(comps),
        Block::Para(format!(
            "Physical checks over every case and formulation (docs/physics.md §6; as \
             `floebench check` gives them on the same cases): {}.",
            super::checks::totals(&comps.iter().flat_map(|c| c.checks.clone()).collect::<Vec<_>>())
        )),
        Block::Para(RESIDUALS_NOTE.into()),
    ];
    for comp in comps {
        let name = &comp.scenario.name;
        let staged = out.join(format!(".{name}.partial{}", std::process::id()));
        if staged.exists() {
            std::fs::remove_dir_all(&staged).map_err(io_err(&staged))?;
        }
        let (verdict, figs, anim) = write_case(comp, &staged, netcdf)?;
        swap_into_place(&staged, &out.join(name))?;
        blocks.push(Block::Heading(2, name.clone()));
        blocks.push(Block::Para(case_line(comp)));
        blocks.push(case_parameters(&comp.scenario));
        blocks.push(Block::Para("**Verdict.**".into()));
        blocks.push(Block::List(verdict.clone()));
        blocks.push(settings_table(comp));
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
        blocks.push(Block::List(
            figs.iter()
                .map(|f| format!("**{}**: {}.", f.stem, f.caption))
                .collect(),
        ));
        match anim {
            Some(a) => {
                blocks.push(Block::Animation(
                    format!("{name}: {}", a.alt),
                    format!("{name}/{}", a.file),
                ));
                blocks.push(Block::Para(format!(
                    "**Animation** (`{name}/{}`): {}.",
                    a.file, a.caption
                )));
            }
            None => blocks.push(Block::Para("**Animation**: none, no run completed.".into())),
        }
    }
    let md = out.join("index.md");
    let html = out.join("index.html");
    write_atomic(&md, page::markdown(&blocks).as_bytes()).map_err(io_err(&md))?;
    write_atomic(
        &html,
        page::html("floebench comparison report", &blocks).as_bytes(),
    )
    .map_err(io_err(&html))?;
    super::folder::record(out, &names)?;
    Ok(vec![md, html])
}
