//! Running a plan's work: the reference runs and the points, each result
//! written atomically to its own file, so that a sweep can stop anywhere
//! and resume, and so that array tasks on a cluster can share one folder.
//!
//! - `references/<case>.json`: the reference run of a case (its trajectory,
//!   final kinetic energy and dissipation), read back by every point of the
//!   case. A point that finds it missing (or written for another plan) runs
//!   it first, so the points of a case need not wait for its reference task
//!   (they only repeat its work).
//! - `points/<id>.json`: one point's result ([`PointResult`]).
//!
//! A file whose fingerprint is the plan's is finished and never
//! recomputed. An interrupt ([`crate::run::interrupt`]) stops the starting
//! of new work; a run that it stops ends at its next output time and
//! leaves no file (its point is not finished).

use super::measures::{measure, CheckValue, Metric, ReferenceData};
use super::plan::{settings_label, table_of, Plan, Reference};
use super::points::{reference_fingerprint, Point, Task};
use super::SweepError;
use crate::formulation::{self, FormulationOptions};
use crate::fsio::write_atomic;
use crate::run::{interrupt, EndReason, RunOptions, RunResult, Runner, TrajectoryRow};
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};

/// The folder of the point files inside a sweep's output folder.
pub const POINTS_DIR: &str = "points";

/// The folder of the reference files inside a sweep's output folder.
pub const REFERENCES_DIR: &str = "references";

/// The result of one point, as `points/<id>.json` holds it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PointResult {
    /// The point's id.
    pub id: String,
    /// The point's fingerprint ([`super::points`]).
    pub fingerprint: String,
    /// Case name.
    pub case: String,
    /// The case file.
    pub case_file: PathBuf,
    /// Formulation name.
    pub formulation: String,
    /// The point's settings, `key=value;…` (`defaults`).
    pub settings: String,
    /// How the run ended (`completed`, or the reason).
    pub end: String,
    /// Time reached, s.
    pub t_reached: f64,
    /// Wall time of the run, s (not a measure: CPU time is).
    pub wall: f64,
    /// The measures ([`super::measures`]).
    pub metrics: Vec<Metric>,
    /// Every check outcome, bound checks included.
    pub checks: Vec<CheckValue>,
    /// The settings the formulation ran with, defaults resolved, as in
    /// `summary.json`.
    pub resolved: serde_json::Value,
}

impl PointResult {
    /// The metric `name`, if measured.
    pub fn metric(&self, name: &str) -> Option<&Metric> {
        self.metrics.iter().find(|m| m.name == name)
    }
}

/// A reference run as `references/<case>.json` holds it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
struct ReferenceFile {
    case: String,
    fingerprint: String,
    formulation: String,
    settings: String,
    end: String,
    cpu: f64,
    kinetic_final: f64,
    dissipated: f64,
    /// `[t, floe, x, y, theta, vx, vy, omega]` per row.
    trajectory: Vec<[f64; 8]>,
}

/// What was done.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct Executed {
    /// Points run (their files written).
    pub run: usize,
    /// Points already finished, not recomputed.
    pub skipped: usize,
    /// Reference runs made.
    pub references: usize,
    /// Whether an interrupt stopped the work.
    pub interrupted: bool,
}

/// Options of the local execution.
#[derive(Debug, Clone, Copy)]
pub struct ExecOptions {
    /// Runs at a time (worker threads), at least 1.
    pub jobs: usize,
    /// A line on stderr per finished point.
    pub progress: bool,
}

/// The path of a point's file.
pub fn point_file(out: &Path, id: &str) -> PathBuf {
    out.join(POINTS_DIR).join(format!("{id}.json"))
}

fn reference_file(out: &Path, case: &str) -> PathBuf {
    out.join(REFERENCES_DIR).join(format!("{case}.json"))
}

fn read_json<T: for<'de> Deserialize<'de>>(path: &Path) -> Option<T> {
    let bytes = std::fs::read(path).ok()?;
    serde_json::from_slice(&bytes).ok()
}

/// The finished result of `point` in `out`, if there is one (its file
/// reads and has the point's fingerprint).
pub fn finished(out: &Path, point: &Point) -> Option<PointResult> {
    read_json::<PointResult>(&point_file(out, &point.id))
        .filter(|r| r.fingerprint == point.fingerprint)
}

fn write_json<T: Serialize>(path: &Path, value: &T) -> Result<(), SweepError> {
    let io = |source| SweepError::Io {
        path: path.to_path_buf(),
        source,
    };
    let bytes = serde_json::to_vec_pretty(value).map_err(|e| io(std::io::Error::other(e)))?;
    write_atomic(path, &bytes).map_err(io)
}

/// Runs formulation `name` on a scenario; `None` when an interrupt stopped it.
fn run_one(
    scn: &crate::model::Scenario,
    name: &str,
    what: &str,
) -> Result<Option<RunResult>, SweepError> {
    let mut form = formulation::build(name, scn, &FormulationOptions::default())
        .map_err(|e| SweepError::Point(format!("{what}: {e}")))?;
    let r = Runner::new(RunOptions::default()).run(scn, form.name(), form.formulation.as_mut());
    Ok((!matches!(r.summary.end, EndReason::Interrupted { .. })).then_some(r))
}

/// The shared state of one execution: the plan, the output folder, and
/// the references read so far.
struct Work<'a> {
    plan: &'a Plan,
    out: &'a Path,
    references: Mutex<Vec<Option<Arc<ReferenceData>>>>,
}

impl<'a> Work<'a> {
    fn new(plan: &'a Plan, out: &'a Path) -> Work<'a> {
        Work {
            plan,
            out,
            references: Mutex::new(vec![None; plan.cases.len()]),
        }
    }

    /// Makes the reference run of `case` unless its file is there; `Ok(false)`
    /// when it was already there, `Ok(true)` when run, `None` inside when
    /// interrupted.
    fn reference_run(&self, case: usize) -> Result<Option<bool>, SweepError> {
        let Reference::Run {
            formulation,
            settings,
        } = &self.plan.reference
        else {
            return Ok(Some(false));
        };
        let c = &self.plan.cases[case];
        let path = reference_file(self.out, &c.scenario.name);
        let fingerprint = reference_fingerprint(self.plan, case);
        if read_json::<ReferenceFile>(&path).is_some_and(|r| r.fingerprint == fingerprint) {
            return Ok(Some(false));
        }
        let entry = formulation::entry(formulation).map_err(SweepError::Point)?;
        let what = format!(
            "{} / reference {}",
            c.scenario.name,
            self.plan.reference.label()
        );
        let scn = self
            .plan
            .scenario(case, table_of(entry), settings)
            .map_err(|e| SweepError::Point(format!("{what}: {e}")))?;
        let Some(r) = run_one(&scn, formulation, &what)? else {
            return Ok(None);
        };
        let file = ReferenceFile {
            case: c.scenario.name.clone(),
            fingerprint,
            formulation: formulation.to_string(),
            settings: settings_label(settings),
            end: r.summary.end.to_string(),
            cpu: r.summary.timing.cpu_total,
            kinetic_final: r.summary.energy.final_kinetic,
            dissipated: r.summary.energy.ledger.dissipated,
            trajectory: r
                .trajectory
                .iter()
                .map(|w| [w.t, w.floe as f64, w.x, w.y, w.theta, w.vx, w.vy, w.omega])
                .collect(),
        };
        write_json(&path, &file)?;
        Ok(Some(true))
    }

    /// The reference of `case`, read from its file (run first if missing);
    /// `Ok(None)`: `reference = "exact"`, or interrupted.
    fn reference(&self, case: usize) -> Result<Option<Arc<ReferenceData>>, SweepError> {
        if self.plan.reference == Reference::Exact {
            return Ok(None);
        }
        if let Some(r) = self.references.lock().ok().and_then(|v| v[case].clone()) {
            return Ok(Some(r));
        }
        if self.reference_run(case)?.is_none() {
            return Ok(None);
        }
        let name = &self.plan.cases[case].scenario.name;
        let path = reference_file(self.out, name);
        let file: ReferenceFile = read_json(&path).ok_or_else(|| {
            SweepError::Point(format!("{}: cannot read the reference run", path.display()))
        })?;
        let data = Arc::new(ReferenceData {
            label: file.formulation,
            rows: file
                .trajectory
                .iter()
                .map(|r| TrajectoryRow {
                    t: r[0],
                    floe: r[1] as usize,
                    x: r[2],
                    y: r[3],
                    theta: r[4],
                    vx: r[5],
                    vy: r[6],
                    omega: r[7],
                })
                .collect(),
            kinetic_final: file.kinetic_final,
            dissipated: file.dissipated,
        });
        if let Ok(mut v) = self.references.lock() {
            v[case] = Some(data.clone());
        }
        Ok(Some(data))
    }

    /// Runs `point` unless finished: `Ok(Some(true))` run, `Ok(Some(false))`
    /// skipped, `Ok(None)` interrupted.
    fn point(&self, point: &Point) -> Result<Option<bool>, SweepError> {
        if finished(self.out, point).is_some() {
            return Ok(Some(false));
        }
        let c = &self.plan.cases[point.case];
        let what = format!(
            "{} / {} {}",
            c.scenario.name,
            point.formulation,
            settings_label(&point.settings)
        );
        let reference = self.reference(point.case)?;
        if reference.is_none() && self.plan.reference != Reference::Exact {
            return Ok(None);
        }
        let scn = self
            .plan
            .scenario(point.case, point.table, &point.settings)
            .map_err(|e| SweepError::Point(format!("{what}: {e}")))?;
        let Some(run) = run_one(&scn, point.formulation, &what)? else {
            return Ok(None);
        };
        let (metrics, checks) = measure(&scn, &run, reference.as_deref())
            .map_err(|e| SweepError::Point(format!("{what}: {e}")))?;
        let s = &run.summary;
        let result = PointResult {
            id: point.id.clone(),
            fingerprint: point.fingerprint.clone(),
            case: c.scenario.name.clone(),
            case_file: c.path.clone(),
            formulation: point.formulation.to_string(),
            settings: settings_label(&point.settings),
            end: s.end.to_string(),
            t_reached: s.t_reached,
            wall: s.timing.wall,
            metrics,
            checks,
            resolved: serde_json::to_value(&s.settings).unwrap_or(serde_json::Value::Null),
        };
        write_json(&point_file(self.out, &point.id), &result)?;
        Ok(Some(true))
    }
}

/// Calls `work(k)` for k in `0..n` on `jobs` threads, starting none after
/// an interrupt; returns each call's value (`None`: not started), in order.
fn on_threads<T: Send>(jobs: usize, n: usize, work: impl Fn(usize) -> T + Sync) -> Vec<Option<T>> {
    let slots: Mutex<Vec<Option<T>>> = Mutex::new((0..n).map(|_| None).collect());
    let next = AtomicUsize::new(0);
    std::thread::scope(|s| {
        for _ in 0..jobs.clamp(1, n.max(1)) {
            s.spawn(|| {
                while !interrupt::requested() {
                    let k = next.fetch_add(1, Ordering::SeqCst);
                    if k >= n {
                        break;
                    }
                    let v = work(k);
                    if let Ok(mut slots) = slots.lock() {
                        slots[k] = Some(v);
                    }
                }
            });
        }
    });
    slots.into_inner().unwrap_or_default()
}

/// Runs every unfinished reference and point of `plan` into `out`, on
/// `opts.jobs` threads: the references first, then the points.
pub fn run_local(
    plan: &Plan,
    points: &[Point],
    out: &Path,
    opts: ExecOptions,
) -> Result<Executed, SweepError> {
    let work = Work::new(plan, out);
    let mut done = Executed::default();
    let cases: Vec<usize> = (0..plan.cases.len())
        .filter(|&c| points.iter().any(|p| p.case == c))
        .collect();
    for r in on_threads(opts.jobs, cases.len(), |k| work.reference_run(cases[k])) {
        match r {
            Some(Ok(Some(true))) => done.references += 1,
            Some(Ok(Some(false))) => {}
            Some(Ok(None)) | None => done.interrupted = true,
            Some(Err(e)) => return Err(e),
        }
    }
    if done.interrupted {
        return Ok(done);
    }
    let count = AtomicUsize::new(0);
    let results = on_threads(opts.jobs, points.len(), |k| {
        let r = work.point(&points[k]);
        if opts.progress {
            if let Ok(Some(true)) = r {
                let n = count.fetch_add(1, Ordering::SeqCst) + 1;
                let p = &points[k];
                eprintln!(
                    "[{n}] {} / {} {}",
                    plan.cases[p.case].scenario.name,
                    p.formulation,
                    settings_label(&p.settings)
                );
            }
        }
        r
    });
    for r in results {
        match r {
            Some(Ok(Some(true))) => done.run += 1,
            Some(Ok(Some(false))) => done.skipped += 1,
            Some(Ok(None)) | None => done.interrupted = true,
            Some(Err(e)) => return Err(e),
        }
    }
    Ok(done)
}

/// Runs task `task` (one array task of a cluster job, see
/// [`super::slurm`]).
pub fn run_task(
    plan: &Plan,
    points: &[Point],
    out: &Path,
    task: &Task,
) -> Result<Executed, SweepError> {
    let work = Work::new(plan, out);
    let mut done = Executed::default();
    match task {
        Task::Reference(c) => match work.reference_run(*c)? {
            Some(true) => done.references += 1,
            Some(false) => {}
            None => done.interrupted = true,
        },
        Task::Points(list) => {
            for &k in list {
                if interrupt::requested() {
                    done.interrupted = true;
                    break;
                }
                match work.point(&points[k])? {
                    Some(true) => done.run += 1,
                    Some(false) => done.skipped += 1,
                    None => done.interrupted = true,
                }
            }
        }
    }
    Ok(done)
}
