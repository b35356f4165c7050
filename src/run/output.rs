//! Writing a run's results: `trajectory.csv`, `energy.csv`, `summary.json`.
//!
//! Every file is written to a temporary name in the output folder and renamed
//! into place, so a reader never sees a half-written file.

use super::RunResult;
use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};

/// Writes `contents` to `path` atomically (temporary file, then rename).
pub fn write_atomic(path: &Path, contents: &[u8]) -> io::Result<()> {
    let dir = path.parent().unwrap_or_else(|| Path::new("."));
    std::fs::create_dir_all(dir)?;
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    let tmp = dir.join(format!(".{name}.tmp{}", std::process::id()));
    std::fs::write(&tmp, contents)?;
    std::fs::rename(&tmp, path)
}

/// The trajectory as CSV: `t,floe,x,y,theta,vx,vy,omega` (s, -, m, m, rad, m/s, m/s, rad/s).
pub fn trajectory_csv(result: &RunResult) -> String {
    let mut s = String::with_capacity(64 * result.trajectory.len() + 64);
    s.push_str("t,floe,x,y,theta,vx,vy,omega\n");
    for r in &result.trajectory {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{}",
            r.t, r.floe, r.x, r.y, r.theta, r.vx, r.vy, r.omega
        );
    }
    s
}

/// The energy ledger as CSV:
/// `t,kinetic,work_air,work_water,work_coriolis,dissipated,residual` (s, then J).
pub fn energy_csv(result: &RunResult) -> String {
    let mut s = String::with_capacity(96 * result.energy.len() + 80);
    s.push_str("t,kinetic,work_air,work_water,work_coriolis,dissipated,residual\n");
    for e in &result.energy {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{}",
            e.t, e.kinetic, e.work_air, e.work_water, e.work_coriolis, e.dissipated, e.residual
        );
    }
    s
}

/// Writes the three output files into `dir`; returns their paths.
pub fn write_run(dir: &Path, result: &RunResult) -> io::Result<Vec<PathBuf>> {
    let files = [
        ("trajectory.csv", trajectory_csv(result).into_bytes()),
        ("energy.csv", energy_csv(result).into_bytes()),
        (
            "summary.json",
            serde_json::to_vec_pretty(&result.summary).map_err(io::Error::other)?,
        ),
    ];
    let mut paths = Vec::new();
    for (name, bytes) in files {
        let p = dir.join(name);
        write_atomic(&p, &bytes)?;
        paths.push(p);
    }
    Ok(paths)
}
