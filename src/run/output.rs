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

/// The first non-finite number of the trajectory or the energy ledger, as
/// a message naming the file, time and column.
fn non_finite(result: &RunResult) -> Option<String> {
    for r in &result.trajectory {
        let cols = [
            ("x", r.x),
            ("y", r.y),
            ("theta", r.theta),
            ("vx", r.vx),
            ("vy", r.vy),
            ("omega", r.omega),
            ("t", r.t),
        ];
        if let Some((c, _)) = cols.iter().find(|(_, v)| !v.is_finite()) {
            return Some(format!(
                "trajectory.csv: non-finite {c} of floe {} at t = {} s",
                r.floe, r.t
            ));
        }
    }
    for e in &result.energy {
        let cols = [
            ("kinetic", e.kinetic),
            ("work_air", e.work_air),
            ("work_water", e.work_water),
            ("work_coriolis", e.work_coriolis),
            ("dissipated", e.dissipated),
            ("residual", e.residual),
            ("t", e.t),
        ];
        if let Some((c, _)) = cols.iter().find(|(_, v)| !v.is_finite()) {
            return Some(format!("energy.csv: non-finite {c} at t = {} s", e.t));
        }
    }
    None
}

/// Writes the three output files into `dir`; returns their paths. Refuses
/// (before writing anything) a result with a non-finite number in its
/// trajectory or ledger: the runner ends a run at the last finite output,
/// so this is a safety net that names the number.
pub fn write_run(dir: &Path, result: &RunResult) -> io::Result<Vec<PathBuf>> {
    if let Some(m) = non_finite(result) {
        return Err(io::Error::new(io::ErrorKind::InvalidData, m));
    }
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
