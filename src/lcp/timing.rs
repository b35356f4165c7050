//! Timing the driver on a folder of LCP dumps (`floebench lcp DIR --time`).
//!
//! Every `*.json` dump of a folder (sorted by file name) is read, re-solved
//! by [`solve`] with the default [`SolveOptions`], and timed in **thread CPU
//! time** (`CLOCK_THREAD_CPUTIME_ID`, see
//! [`crate::run::clock::thread_cpu_seconds`]). Reading that clock is a system
//! call of about 0.3 µs here, more than a whole solve of a 4-unknown LCP, so
//! a measurement is a *batch*: the same solve repeated until at least
//! [`TimingOptions::min_batch_seconds`] (default 1 ms) of CPU time has
//! elapsed, divided by the number of solves. The reported figure is the
//! median over [`TimingOptions::repeats`] batches (default 5).
//!
//! With [`TimingOptions::predict`] (`--predict`) every solve is the
//! driver from a predicted basis ([`super::predict::solve_predicted_into`]:
//! the block Gauss–Seidel prediction on the dump's contact blocks, then the
//! warm Lemke path from it, then the cold attempts if needed), the
//! prediction included in the timed CPU; the rows then also give its
//! sweeps and how many indices of its guess differ from the basis of the
//! accepted solution. A dump whose size is neither `4 · contacts` nor
//! `contacts` is solved cold.
//!
//! The per-problem rows ([`TimedSolve`]) are written as CSV by [`csv`] and
//! summarised per size bucket (unknowns 1–8, 9–40, 41–200, 201–800, > 800)
//! by [`summarize`].

use super::dump::{DumpError, LcpDump};
use super::lemke::Workspace;
use super::lemke_options::Termination;
use super::predict::{basis_mismatch, solve_predicted_into, Blocks, PredictOptions, Prediction};
use super::solution::{BasisGuess, LcpSolution, SolveStatus, Strategy};
use super::solve::{solve_into, solve_warm_into};
use super::solve_options::SolveOptions;
use crate::record::clock::thread_cpu_seconds;
use std::hint::black_box;
use std::path::{Path, PathBuf};

/// Size buckets of the summary: inclusive bounds on the number of unknowns n.
pub const BUCKETS: [(usize, usize); 5] =
    [(1, 8), (9, 40), (41, 200), (201, 800), (801, usize::MAX)];

/// Label of bucket `b` of [`BUCKETS`] (`"1-8"`, …, `">800"`).
pub fn bucket_label(b: usize) -> String {
    match BUCKETS.get(b) {
        Some(&(lo, hi)) if hi == usize::MAX => format!(">{}", lo - 1),
        Some(&(lo, hi)) => format!("{lo}-{hi}"),
        None => String::from("?"),
    }
}

/// Index in [`BUCKETS`] of a problem with `n` unknowns (`None` for n = 0).
pub fn bucket_of(n: usize) -> Option<usize> {
    BUCKETS.iter().position(|&(lo, hi)| n >= lo && n <= hi)
}

/// Options of [`time_solve`] and [`time_folder`].
#[derive(Debug, Clone, PartialEq)]
pub struct TimingOptions {
    /// Number of timed batches; the median is reported. At least 1.
    pub repeats: usize,
    /// Minimum CPU time of one batch, s (default 1e-3).
    pub min_batch_seconds: f64,
    /// Options of the driver.
    pub solve: SolveOptions,
    /// Warm-start every solve ([`solve_warm`]) from the dump's own stored
    /// solution (`basic = z > 0`, starting point `z`): the cost of a warm
    /// start whose guess is right.
    pub warm: bool,
    /// Solve every dump from a predicted basis (module doc), with these
    /// options of the prediction; `None`: cold (or `warm`). Takes
    /// precedence over `warm`.
    pub predict: Option<PredictOptions>,
}

impl Default for TimingOptions {
    fn default() -> Self {
        Self {
            repeats: 5,
            min_batch_seconds: 1e-3,
            solve: SolveOptions::default(),
            warm: false,
            predict: None,
        }
    }
}

/// One timed problem (a row of the CSV).
#[derive(Debug, Clone, PartialEq)]
pub struct TimedSolve {
    /// File name of the dump (without the folder).
    pub file: String,
    /// Number of unknowns.
    pub n: usize,
    /// Number of contacts stored in the dump.
    pub contacts: usize,
    /// Total pivots of the solve (all attempts).
    pub pivots: usize,
    /// Status of the solve.
    pub status: SolveStatus,
    /// Accepted attempt: `WarmStart`, `Lexicographic`, `AlternativeRule`,
    /// `Perturbed:<ε_rel>` (with `/revised` appended when it ran on the
    /// factorised basis), or `none`.
    pub accepted_attempt: String,
    /// Residual on the original data.
    pub residual: f64,
    /// Median thread CPU time per solve, µs.
    pub cpu_us: f64,
    /// What Lemke reported on the first attempt (lexicographic, or Harris
    /// from [`crate::lcp::SolveOptions::harris_from`] unknowns)
    /// ([`Termination::Solved`] for `q >= 0`, which needs no attempt).
    pub first_termination: Termination,
    /// Pivots of the first attempt.
    pub first_pivots: usize,
    /// Sweeps of the prediction (0 without one).
    pub predict_sweeps: usize,
    /// Indices where the predicted basis differs from the basis of the
    /// accepted solution, non-degenerate indices only (0 without a
    /// prediction; see [`basis_mismatch`], ties at `tolerance · ‖q‖₂`).
    pub predict_wrong: usize,
    /// Degenerate indices of the accepted solution (both `z_i` and `w_i`
    /// within the tie level), left out of `predict_wrong`.
    pub predict_ties: usize,
    /// Size of the support of the accepted `z` ([`super::support`]): a cold
    /// Lemke path to it takes at least one pivot more
    /// ([`super::min_cold_pivots`]).
    pub support: usize,
}

/// Name of the accepted attempt of `sol` as written in the CSV, with
/// `/revised` appended when it ran on the factorised basis.
pub fn accepted_attempt_name(sol: &LcpSolution) -> String {
    if sol.accepted_by == Some(Strategy::WarmStart) {
        return String::from("WarmStart");
    }
    match sol.attempts.iter().find(|a| a.accepted) {
        None => String::from("none"),
        Some(a) => {
            let name = match a.strategy {
                Strategy::Lexicographic => String::from("Lexicographic"),
                Strategy::AlternativeRule => String::from("AlternativeRule"),
                Strategy::Perturbed => format!("Perturbed:{:e}", a.epsilon_rel),
                Strategy::WarmStart => String::from("WarmStart"),
                Strategy::WarmLemke => String::from("WarmLemke"),
                Strategy::Harris => String::from("Harris"),
            };
            if a.revised {
                name + "/revised"
            } else {
                name
            }
        }
    }
}

/// Solves `lcp` once (the returned solution) and then times it: the median
/// over `opts.repeats` batches of the CPU time per solve, µs (see the
/// module doc). With `guess`, every solve is [`solve_warm_into`] from it.
/// The solves share one [`Workspace`] and one output ([`solve_into`]), as a
/// caller that solves many LCPs would: the figure is the solver's, without
/// the allocation of its result.
pub fn time_solve(
    lcp: &super::Lcp,
    opts: &TimingOptions,
    guess: Option<&BasisGuess>,
) -> (LcpSolution, f64) {
    let (sol, us, _) = time_start(lcp, opts, guess.map_or(Start::Cold, Start::Guess));
    (sol, us)
}

/// How [`time_start`] starts each solve.
#[derive(Debug, Clone, Copy)]
pub enum Start<'a> {
    /// The cold driver ([`solve_into`]).
    Cold,
    /// A warm start from a guess ([`solve_warm_into`]).
    Guess(&'a BasisGuess),
    /// A predicted basis on these blocks, with these options
    /// ([`solve_predicted_into`]).
    Predict(&'a Blocks, &'a PredictOptions),
}

/// [`time_solve`] with any [`Start`]; also returns the prediction of the
/// first solve, if one was made.
pub fn time_start(
    lcp: &super::Lcp,
    opts: &TimingOptions,
    start: Start<'_>,
) -> (LcpSolution, f64, Option<Prediction>) {
    let mut ws = Workspace::default();
    let mut out = LcpSolution::empty();
    let mut run = |l: &super::Lcp, out: &mut LcpSolution| match start {
        Start::Guess(g) => {
            solve_warm_into(&mut ws, l, &opts.solve, g, out);
            None
        }
        Start::Cold => {
            solve_into(&mut ws, l, &opts.solve, out);
            None
        }
        Start::Predict(b, p) => solve_predicted_into(&mut ws, l, &opts.solve, b, p, out),
    };
    let t0 = thread_cpu_seconds();
    let prediction = run(black_box(lcp), &mut out);
    let first = (thread_cpu_seconds() - t0).max(0.0);
    let sol = out.clone();
    let min_batch = if opts.min_batch_seconds.is_finite() {
        opts.min_batch_seconds.max(0.0)
    } else {
        1e-3
    };
    // Batch size from the first solve, at least 1; then doubled while a
    // batch stays below the minimum (the first solve may be slow: cold
    // caches, page faults).
    let mut batch: u64 = if first > 0.0 {
        ((min_batch / first).ceil() as u64).clamp(1, 1 << 24)
    } else {
        1 << 10
    };
    let mut samples = Vec::with_capacity(opts.repeats.max(1));
    while samples.len() < opts.repeats.max(1) {
        let t0 = thread_cpu_seconds();
        for _ in 0..batch {
            run(black_box(lcp), &mut out);
            black_box(&out);
        }
        let dt = (thread_cpu_seconds() - t0).max(0.0);
        if dt < min_batch && batch < (1 << 24) {
            batch = batch.saturating_mul(2);
            continue;
        }
        samples.push(dt / batch as f64 * 1e6);
    }
    (sol, median(&mut samples), prediction)
}

/// Median of `v` (reorders it); NaN for an empty slice.
pub fn median(v: &mut [f64]) -> f64 {
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let k = v.len() / 2;
    if v.len() % 2 == 1 {
        v[k]
    } else {
        0.5 * (v[k - 1] + v[k])
    }
}

/// The `*.json` files of `dir`, sorted by name.
pub fn dump_files(dir: &Path) -> std::io::Result<Vec<PathBuf>> {
    let mut files: Vec<PathBuf> = std::fs::read_dir(dir)?
        .filter_map(|e| e.ok().map(|e| e.path()))
        .filter(|p| p.is_file() && p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    Ok(files)
}

/// Reads and times one dump file.
pub fn time_file(path: &Path, opts: &TimingOptions) -> Result<TimedSolve, DumpError> {
    let dump = LcpDump::read(path)?;
    let lcp = dump.to_lcp().map_err(|e| DumpError::Io {
        path: path.to_path_buf(),
        source: std::io::Error::new(std::io::ErrorKind::InvalidData, e.to_string()),
    })?;
    let guess = opts.warm.then(|| BasisGuess {
        basic: dump.z.iter().map(|&v| v > 0.0).collect(),
        z: dump.z.clone(),
    });
    let blocks = opts
        .predict
        .as_ref()
        .and_then(|p| Blocks::contacts(lcp.n, dump.contacts).map(|b| (b, p)));
    let start = match (&blocks, &guess) {
        (Some((b, p)), _) => Start::Predict(b, p),
        (None, Some(g)) => Start::Guess(g),
        (None, None) => Start::Cold,
    };
    let (sol, cpu_us, prediction) = time_start(&lcp, opts, start);
    let qn = lcp.q.iter().map(|v| v * v).sum::<f64>().sqrt();
    let (predict_wrong, predict_ties) = prediction.as_ref().map_or((0, 0), |p| {
        basis_mismatch(&p.guess.basic, &sol.z, &sol.w, opts.solve.tolerance * qn)
    });
    Ok(TimedSolve {
        file: path
            .file_name()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default(),
        n: lcp.n,
        contacts: dump.contacts,
        pivots: sol.pivots,
        status: sol.status,
        accepted_attempt: accepted_attempt_name(&sol),
        residual: sol.residual,
        cpu_us,
        first_termination: sol
            .attempts
            .first()
            .map_or(Termination::Solved, |a| a.termination),
        first_pivots: sol.attempts.first().map_or(0, |a| a.pivots),
        predict_sweeps: prediction.as_ref().map_or(0, |p| p.sweeps),
        predict_wrong,
        predict_ties,
        support: super::support(&sol.z),
    })
}

/// The CSV header of [`csv`].
pub const CSV_HEADER: &str =
    "file,n,contacts,pivots,status,accepted_attempt,residual,cpu_us,first_termination,first_pivots,predict_sweeps,predict_wrong,predict_ties,support";

/// The CSV text of `rows`, with the header [`CSV_HEADER`].
pub fn csv(rows: &[TimedSolve]) -> String {
    let mut s = format!("{CSV_HEADER}\n");
    for r in rows {
        s.push_str(&format!(
            "{},{},{},{},{},{},{:e},{:.4},{},{},{},{},{},{}\n",
            r.file,
            r.n,
            r.contacts,
            r.pivots,
            r.status.as_str(),
            r.accepted_attempt,
            r.residual,
            r.cpu_us,
            r.first_termination.as_str(),
            r.first_pivots,
            r.predict_sweeps,
            r.predict_wrong,
            r.predict_ties,
            r.support
        ));
    }
    s
}

/// Summary of one size bucket.
#[derive(Debug, Clone, PartialEq)]
pub struct BucketSummary {
    /// Label (`"1-8"`, …).
    pub label: String,
    /// Number of problems.
    pub count: usize,
    /// Median CPU time per solve, µs (NaN if empty).
    pub median_us: f64,
    /// Median pivots (NaN if empty).
    pub median_pivots: f64,
    /// Problems with status [`SolveStatus::Failed`].
    pub failures: usize,
    /// Problems solved by a fallback.
    pub fallbacks: usize,
    /// Problems whose first attempt ended on a secondary ray.
    pub rays: usize,
    /// Problems whose first attempt reached the pivot cap.
    pub caps: usize,
    /// Largest residual (0 if empty).
    pub max_residual: f64,
    /// Total CPU time of one solve of each problem, s.
    pub total_seconds: f64,
    /// Problems accepted by the warm Lemke path (from a predicted basis
    /// with `--predict`).
    pub warm_lemke_hits: usize,
    /// Median sweeps of the prediction (NaN if empty; 0 without one).
    pub median_sweeps: f64,
    /// Median of the guess's wrong indices ([`TimedSolve::predict_wrong`]).
    pub median_wrong: f64,
    /// Median over the problems solved by Lemke (pivots taken, `z ≠ 0`) of
    /// the pivots over the fewest a cold path to the same solution could
    /// take ([`super::min_cold_pivots`]); NaN if there is none. Meaningful
    /// for cold solves: a warm or predicted start may take fewer.
    pub median_path_ratio: f64,
}

/// One [`BucketSummary`] per entry of [`BUCKETS`] (empty buckets included).
pub fn summarize(rows: &[TimedSolve]) -> Vec<BucketSummary> {
    (0..BUCKETS.len())
        .map(|b| {
            let sel: Vec<&TimedSolve> = rows.iter().filter(|r| bucket_of(r.n) == Some(b)).collect();
            let mut us: Vec<f64> = sel.iter().map(|r| r.cpu_us).collect();
            let mut piv: Vec<f64> = sel.iter().map(|r| r.pivots as f64).collect();
            BucketSummary {
                label: bucket_label(b),
                count: sel.len(),
                median_us: median(&mut us),
                median_pivots: median(&mut piv),
                failures: sel
                    .iter()
                    .filter(|r| r.status == SolveStatus::Failed)
                    .count(),
                fallbacks: sel
                    .iter()
                    .filter(|r| r.status == SolveStatus::SolvedByFallback)
                    .count(),
                rays: sel
                    .iter()
                    .filter(|r| r.first_termination == Termination::RayTermination)
                    .count(),
                caps: sel
                    .iter()
                    .filter(|r| r.first_termination == Termination::MaxPivots)
                    .count(),
                max_residual: sel.iter().map(|r| r.residual).fold(0.0, f64::max),
                total_seconds: sel.iter().fold(0.0, |a, r| a + r.cpu_us) * 1e-6,
                warm_lemke_hits: sel
                    .iter()
                    .filter(|r| r.accepted_attempt.starts_with("WarmLemke"))
                    .count(),
                median_sweeps: median(
                    &mut sel
                        .iter()
                        .map(|r| r.predict_sweeps as f64)
                        .collect::<Vec<_>>(),
                ),
                median_wrong: median(
                    &mut sel
                        .iter()
                        .map(|r| r.predict_wrong as f64)
                        .collect::<Vec<_>>(),
                ),
                median_path_ratio: median(
                    &mut sel
                        .iter()
                        .filter(|r| r.pivots > 0 && r.support > 0 && r.status.is_solved())
                        .map(|r| r.pivots as f64 / super::min_cold_pivots(r.support) as f64)
                        .collect::<Vec<_>>(),
                ),
            }
        })
        .collect()
}

/// The summary as a fixed-width text table (`path`:
/// [`BucketSummary::median_path_ratio`]); with a prediction in any
/// bucket, three more columns: warm Lemke hits, median sweeps, median
/// wrong indices of the guess.
pub fn format_summary(rows: &[BucketSummary]) -> String {
    let predicted = rows.iter().any(|r| r.median_sweeps > 0.0);
    let mut s = format!(
        "{:<9} {:>6} {:>12} {:>9} {:>6} {:>9} {:>9} {:>6} {:>6} {:>11} {:>10}\n",
        "unknowns",
        "count",
        "median µs",
        "pivots",
        "path",
        "failures",
        "fallback",
        "rays",
        "caps",
        "max resid",
        "total s"
    );
    if predicted {
        s.pop();
        s.push_str(&format!(" {:>6} {:>7} {:>7}\n", "hits", "sweeps", "wrong"));
    }
    for r in rows {
        if r.count == 0 {
            s.push_str(&format!("{:<9} {:>6}\n", r.label, 0));
            continue;
        }
        s.push_str(&format!(
            "{:<9} {:>6} {:>12.3} {:>9.1} {:>6.2} {:>9} {:>9} {:>6} {:>6} {:>11.2e} {:>10.4}\n",
            r.label,
            r.count,
            r.median_us,
            r.median_pivots,
            r.median_path_ratio,
            r.failures,
            r.fallbacks,
            r.rays,
            r.caps,
            r.max_residual,
            r.total_seconds
        ));
        if predicted {
            s.pop();
            s.push_str(&format!(
                " {:>6} {:>7.1} {:>7.1}\n",
                r.warm_lemke_hits, r.median_sweeps, r.median_wrong
            ));
        }
    }
    s
}
