//! Running a sweep as a Slurm job array.
//!
//! `floebench sweep PLAN -o OUT --slurm DIR [--chunk N]` writes:
//!
//! - `OUT/manifest.json`: the plan, the output folder, the chunking, a
//!   digest of the plan's work, and the task list (task `k`: the reference
//!   run of one case, or up to `N` points);
//! - `DIR/sweep.sbatch`: the array job; each array task runs
//!   `floebench sweep PLAN -o OUT --task $SLURM_ARRAY_TASK_ID`;
//! - `DIR/submit.sh`: submits the reference tasks, then the point tasks
//!   with `--dependency=afterok` on them (one submission without a
//!   reference run);
//! - `DIR/logs/`: each task's output, `%A_%a.out`.
//!
//! **Resource request** of each array task: one task, one CPU
//! (`--cpus-per-task=1`: a run is single-threaded and its CPU time is its
//! thread's), `--mem` (default 2G: the bundled cases need under 100 MB,
//! a 10,000-floe field under 1 GB) and `--time` (default 01:00:00 per
//! task), set with `--slurm-mem` and `--slurm-time`; a partition or
//! account is given to `sbatch` as usual (`SBATCH_PARTITION`,
//! `SBATCH_ACCOUNT` in the environment, or options on its command line).
//! Slurm's default `MaxArraySize` is 1001 (task ids 0–1000): a larger sweep
//! takes `--chunk`.
//!
//! `--task K` refuses a manifest whose digest is not the plan's (the plan
//! or a case changed since `--slurm`): its task numbers would name other
//! work. `--collect` then merges whatever finished, like a local run.

use super::plan::Plan;
use super::points::{plan_digest, tasks, Point, Task};
use super::SweepError;
use crate::fsio::write_atomic;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// The manifest file inside a sweep's output folder.
pub const MANIFEST: &str = "manifest.json";

/// Slurm's default largest array index is 1000 (`MaxArraySize` = 1001).
pub const DEFAULT_MAX_ARRAY_INDEX: usize = 1000;

/// One task of the manifest.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct ManifestTask {
    /// The array task id.
    pub task: usize,
    /// `reference` or `points`.
    pub kind: String,
    /// The case of a reference task, or the ids of the points.
    pub items: Vec<String>,
}

/// `OUT/manifest.json`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Manifest {
    /// The plan file (absolute).
    pub plan: PathBuf,
    /// The output folder (absolute).
    pub out: PathBuf,
    /// Points per task.
    pub chunk: usize,
    /// The digest of the plan's work ([`plan_digest`]).
    pub digest: String,
    /// Reference tasks (they come first).
    pub references: usize,
    /// Every task.
    pub tasks: Vec<ManifestTask>,
}

/// Options of the job script.
#[derive(Debug, Clone)]
pub struct SlurmOptions {
    /// Points per array task, at least 1.
    pub chunk: usize,
    /// `--time` of each task (`HH:MM:SS`).
    pub time: String,
    /// `--mem` of each task (`2G`).
    pub mem: String,
}

impl Default for SlurmOptions {
    fn default() -> Self {
        SlurmOptions {
            chunk: 1,
            time: "01:00:00".into(),
            mem: "2G".into(),
        }
    }
}

/// What was written.
#[derive(Debug, Clone)]
pub struct Written {
    /// The files.
    pub files: Vec<PathBuf>,
    /// The number of array tasks.
    pub tasks: usize,
    /// Of which reference tasks.
    pub references: usize,
}

/// `s` quoted for a POSIX shell.
fn quote(s: &str) -> String {
    format!("'{}'", s.replace('\'', "'\\''"))
}

fn absolute(p: &Path) -> Result<PathBuf, SweepError> {
    std::path::absolute(p).map_err(|source| SweepError::Io {
        path: p.to_path_buf(),
        source,
    })
}

/// Writes the manifest, the job script and the submission script (see the
/// module doc); `exe` is the floebench binary the tasks run.
pub fn write_slurm(
    plan: &Plan,
    points: &[Point],
    out: &Path,
    dir: &Path,
    exe: &Path,
    opts: &SlurmOptions,
) -> Result<Written, SweepError> {
    let chunk = opts.chunk.max(1);
    for (what, v) in [("--slurm-time", &opts.time), ("--slurm-mem", &opts.mem)] {
        if v.is_empty()
            || !v
                .chars()
                .all(|c| c.is_ascii_alphanumeric() || c == ':' || c == '-')
        {
            return Err(SweepError::Usage(format!(
                "{what} `{v}` is not a Slurm value (e.g. 01:00:00, 2G)"
            )));
        }
    }
    let (plan_abs, out_abs, dir_abs, exe_abs) = (
        absolute(&plan.file)?,
        absolute(out)?,
        absolute(dir)?,
        absolute(exe)?,
    );
    let list = tasks(plan, points, chunk);
    let references = list
        .iter()
        .filter(|t| matches!(t, Task::Reference(_)))
        .count();
    let manifest = Manifest {
        plan: plan_abs.clone(),
        out: out_abs.clone(),
        chunk,
        digest: plan_digest(plan, points, chunk),
        references,
        tasks: list
            .iter()
            .enumerate()
            .map(|(k, t)| match t {
                Task::Reference(c) => ManifestTask {
                    task: k,
                    kind: "reference".into(),
                    items: vec![plan.cases[*c].scenario.name.clone()],
                },
                Task::Points(ps) => ManifestTask {
                    task: k,
                    kind: "points".into(),
                    items: ps.iter().map(|&p| points[p].id.clone()).collect(),
                },
            })
            .collect(),
    };
    let n = list.len();
    let io = |path: &Path| {
        let path = path.to_path_buf();
        move |source| SweepError::Io { path, source }
    };
    let logs = dir_abs.join("logs");
    std::fs::create_dir_all(&logs).map_err(io(&logs))?;
    let manifest_path = out_abs.join(MANIFEST);
    let bytes = serde_json::to_vec_pretty(&manifest)
        .map_err(|e| io(&manifest_path)(std::io::Error::other(e)))?;
    write_atomic(&manifest_path, &bytes).map_err(io(&manifest_path))?;

    let sbatch = format!(
        "#!/bin/bash\n\
         # floebench sweep {plan_name}: {n} array tasks ({references} reference runs, then the points, {chunk} per task).\n\
         # Written by `floebench sweep --slurm`; submit with submit.sh (it sets --array and the dependency).\n\
         # Each task: one CPU (a run is single-threaded), --mem, --time; add a partition or an account\n\
         # with SBATCH_PARTITION / SBATCH_ACCOUNT or on the sbatch command line.\n\
         #SBATCH --job-name=floebench-{plan_name}\n\
         #SBATCH --ntasks=1\n\
         #SBATCH --cpus-per-task=1\n\
         #SBATCH --mem={mem}\n\
         #SBATCH --time={time}\n\
         #SBATCH --output={logs}/%A_%a.out\n\
         set -euo pipefail\n\
         exec {exe} sweep {plan} -o {out} --task \"$SLURM_ARRAY_TASK_ID\"\n",
        plan_name = plan.name,
        mem = opts.mem,
        time = opts.time,
        logs = logs.display(),
        exe = quote(&exe_abs.to_string_lossy()),
        plan = quote(&plan_abs.to_string_lossy()),
        out = quote(&out_abs.to_string_lossy()),
    );
    let script = dir_abs.join("sweep.sbatch");
    let submit_path = dir_abs.join("submit.sh");
    let job = quote(&script.to_string_lossy());
    let mut submit = String::from(
        "#!/bin/sh\n# Submits the sweep's array job(s); prints the job ids.\nset -eu\n",
    );
    let points_from = references;
    if n == points_from {
        submit.push_str("echo 'nothing to run'\n");
    } else if references > 0 {
        submit.push_str(&format!(
            "ref=$(sbatch --parsable --array=0-{} {job})\necho \"references: job ${{ref%%;*}}\"\n\
             pts=$(sbatch --parsable --dependency=afterok:${{ref%%;*}} --array={points_from}-{} {job})\necho \"points: job ${{pts%%;*}}\"\n",
            references - 1,
            n - 1
        ));
    } else {
        submit.push_str(&format!(
            "pts=$(sbatch --parsable --array=0-{} {job})\necho \"points: job ${{pts%%;*}}\"\n",
            n - 1
        ));
    }
    for (path, text) in [(&script, &sbatch), (&submit_path, &submit)] {
        write_atomic(path, text.as_bytes()).map_err(io(path))?;
        set_executable(path).map_err(io(path))?;
    }
    Ok(Written {
        files: vec![manifest_path, script, submit_path],
        tasks: n,
        references,
    })
}

#[cfg(unix)]
fn set_executable(path: &Path) -> std::io::Result<()> {
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(path, std::fs::Permissions::from_mode(0o755))
}

#[cfg(not(unix))]
fn set_executable(_: &Path) -> std::io::Result<()> {
    Ok(())
}

/// Task `k` of the manifest in `out`, checked against the plan.
pub fn manifest_task(
    plan: &Plan,
    points: &[Point],
    out: &Path,
    k: usize,
) -> Result<Task, SweepError> {
    let path = out.join(MANIFEST);
    let bytes = std::fs::read(&path).map_err(|source| SweepError::Io {
        path: path.clone(),
        source,
    })?;
    let m: Manifest = serde_json::from_slice(&bytes)
        .map_err(|e| SweepError::Usage(format!("{}: not a sweep manifest: {e}", path.display())))?;
    if m.digest != plan_digest(plan, points, m.chunk) {
        return Err(SweepError::Usage(format!(
            "{}: written for another version of the plan or its cases (write it again with --slurm)",
            path.display()
        )));
    }
    tasks(plan, points, m.chunk)
        .into_iter()
        .nth(k)
        .ok_or_else(|| {
            SweepError::Usage(format!(
                "--task {k}: the manifest has tasks 0 to {}",
                m.tasks.len().saturating_sub(1)
            ))
        })
}
