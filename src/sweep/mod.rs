//! `floebench sweep`: work–precision sweeps over cases × formulations ×
//! settings, their error measures and observed convergence orders, run
//! locally or as a Slurm job array.
//!
//! A **plan** ([`plan`], the contract is `docs/sweep-format.md`) names the
//! cases, a reference (`"exact"`: the checks' closed forms; or a
//! formulation), the error measures and, per formulation, a grid of
//! settings. Its **points** ([`points`]) are every (case, formulation,
//! combination of the grid); each is run by the shared
//! [`crate::run::Runner`] on the case with its settings written in, and
//! measured ([`measures`]: thread CPU time, the position, kinetic-energy
//! and dissipation errors against the reference run, each check's error
//! against its exact value). Each result is written atomically to its own
//! file ([`execute`]), so a sweep resumes where it stopped and cluster
//! tasks share one folder ([`slurm`]). [`collect`] merges whatever has
//! finished; [`orders`] gives the observed convergence orders along each
//! grid key; [`crate::report::sweep`] writes `sweep.csv`, `orders.csv`,
//! the work–precision and error-against-setting plots and the page.

pub mod execute;
pub mod measures;
pub mod orders;
pub mod plan;
pub mod points;
pub mod slurm;
pub mod start;

use crate::model::CaseError;
use execute::{finished, PointResult};
use plan::Plan;
use points::Point;
use std::path::{Path, PathBuf};

/// Why a sweep could not be run.
#[derive(Debug, thiserror::Error)]
pub enum SweepError {
    /// The plan is bad (file, line, key).
    #[error(transparent)]
    Plan(#[from] CaseError),
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The error.
        source: std::io::Error,
    },
    /// A point or a reference could not be run or measured (named).
    #[error("{0}")]
    Point(String),
    /// The command was used wrongly (a task that does not exist, a manifest
    /// of another plan, a bad option).
    #[error("{0}")]
    Usage(String),
}

/// The 64-bit FNV-1a digest of `bytes` (fingerprints of points and plans:
/// stable across runs and machines, not cryptographic).
pub fn digest(bytes: &[u8]) -> u64 {
    bytes.iter().fold(0xcbf2_9ce4_8422_2325u64, |h, &b| {
        (h ^ u64::from(b)).wrapping_mul(0x0000_0100_0000_01b3)
    })
}

/// The default output folder of a plan: `sweeps/<plan name>`.
pub fn default_out(plan: &Plan) -> PathBuf {
    Path::new("sweeps").join(&plan.name)
}

/// The finished results of a plan's points, as found in its output folder.
#[derive(Debug, Clone)]
pub struct Collected<'a> {
    /// The plan.
    pub plan: &'a Plan,
    /// Its points.
    pub points: Vec<Point>,
    /// Each point's result, when finished.
    pub results: Vec<Option<PointResult>>,
}

impl Collected<'_> {
    /// The result of the point `id`, when finished.
    pub fn result(&self, id: &str) -> Option<&PointResult> {
        self.points
            .iter()
            .position(|p| p.id == id)
            .and_then(|k| self.results[k].as_ref())
    }

    /// The points not finished.
    pub fn missing(&self) -> Vec<&Point> {
        self.points
            .iter()
            .zip(&self.results)
            .filter(|(_, r)| r.is_none())
            .map(|(p, _)| p)
            .collect()
    }

    /// The error metrics the plan's measures select, in the order they
    /// first appear among the finished points.
    pub fn error_metrics(&self) -> Vec<String> {
        let mut out: Vec<String> = Vec::new();
        for m in self.results.iter().flatten().flat_map(|r| &r.metrics) {
            if self.plan.measures.iter().any(|s| s.selects(&m.name)) && !out.contains(&m.name) {
                out.push(m.name.clone());
            }
        }
        out
    }

    /// The observed orders along every grid key, for every error metric.
    pub fn orders(&self) -> Vec<orders::Order> {
        orders::orders(self.plan, &self.error_metrics(), |id| self.result(id))
    }
}

/// The finished results of `points` in `out` (see [`execute::finished`]).
pub fn collect<'a>(plan: &'a Plan, points: Vec<Point>, out: &Path) -> Collected<'a> {
    let results = points.iter().map(|p| finished(out, p)).collect();
    Collected {
        plan,
        points,
        results,
    }
}
