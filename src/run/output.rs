//! Writing a run's results: `trajectory.csv`, `energy.csv`, `summary.json`,
//! `floes.json` (every floe that existed), `fractures.csv` (one row per
//! fracture; only its header without fracture), `stress.csv` (the pack's
//! mean stress per output interval), `obstacles.csv` (the mean force on
//! each obstacle per output interval; only for a case with obstacles) and, for a run of the
//! lattice model that broke a floe, `percussion.json` (the crack of its
//! largest percussion, [`crate::model::fracture::PercussionRecord`]).
//!
//! Every file is written to a temporary name in the output folder and renamed
//! into place ([`crate::fsio`]), so a reader never sees a half-written file.

use super::energy::Column;
use super::RunResult;
use crate::fsio::write_atomic;
use std::fmt::Write as _;
use std::io;
use std::path::{Path, PathBuf};

/// The first line of `trajectory.csv`.
pub const TRAJECTORY_HEADER: &str = "t,floe,x,y,theta,vx,vy,omega";

/// The trajectory as CSV: `t,floe,x,y,theta,vx,vy,omega` (s, -, m, m, rad, m/s, m/s, rad/s).
pub fn trajectory_csv(result: &RunResult) -> String {
    let mut s = String::with_capacity(64 * result.trajectory.len() + 64);
    s.push_str(TRAJECTORY_HEADER);
    s.push('\n');
    for r in &result.trajectory {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{}",
            r.t, r.floe, r.x, r.y, r.theta, r.vx, r.vy, r.omega
        );
    }
    s
}

/// The first line of `energy.csv`: `t`, then the name of every
/// [`Column`].
pub fn energy_header() -> String {
    std::iter::once("t")
        .chain(Column::all().map(Column::name))
        .collect::<Vec<_>>()
        .join(",")
}

/// The energy ledger as CSV, under [`energy_header`]: one row per sample,
/// its time (s), then every [`Column`] (J).
pub fn energy_csv(result: &RunResult) -> String {
    let mut s = String::with_capacity(96 * result.energy.len() + 80);
    s.push_str(&energy_header());
    s.push('\n');
    for e in &result.energy {
        let _ = write!(s, "{}", e.t);
        for (_, v) in e.values() {
            let _ = write!(s, ",{v}");
        }
        s.push('\n');
    }
    s
}

/// The first line of `fractures.csv`.
pub const FRACTURES_HEADER: &str = "t,parent,children,model,measure,threshold,energy,kinetic_gain";

/// The fractures as CSV:
/// `t,parent,children,model,measure,threshold,energy,kinetic_gain` (s, id,
/// ids joined by `;`, name, then the criterion's unit: J for `energy` and
/// `lattice`, the yield function for `stress`; then the energy booked in
/// the ledger's `fracture` column and the pieces' kinetic energy above the
/// parent's, J).
pub fn fractures_csv(result: &RunResult) -> String {
    let mut s = String::from(FRACTURES_HEADER);
    s.push('\n');
    for f in &result.fractures {
        let children: Vec<String> = f.children.iter().map(|c| c.to_string()).collect();
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{},{}",
            f.t,
            f.parent,
            children.join(";"),
            f.model,
            f.measure,
            f.threshold,
            f.energy,
            f.kinetic_gain
        );
    }
    s
}

/// The first line of `obstacles.csv`.
pub const OBSTACLES_HEADER: &str = "t,obstacle,fx,fy,torque";

/// The name of the forces on the obstacles a run of a case with obstacles
/// writes.
pub const OBSTACLES_FILE: &str = "obstacles.csv";

/// The forces on the obstacles as CSV: `t,obstacle,fx,fy,torque` (s,
/// index, N, N, N·m about the obstacle's centroid), the mean over the
/// output interval ending at `t` ([`crate::fracture::forces`]).
pub fn obstacles_csv(result: &RunResult) -> String {
    let mut s = String::with_capacity(64 * result.obstacle_forces.len() + 32);
    s.push_str(OBSTACLES_HEADER);
    s.push('\n');
    for r in &result.obstacle_forces {
        let _ = writeln!(s, "{},{},{},{},{}", r.t, r.obstacle, r.fx, r.fy, r.torque);
    }
    s
}

/// The first line of `stress.csv`.
pub const STRESS_HEADER: &str = "t,sxx,sxy,syx,syy,area";

/// The pack's mean stress as CSV: `t,sxx,sxy,syx,syy,area` (s, N/m ×4
/// with tension positive, m²), the mean over the output interval ending at
/// `t` ([`crate::fracture::forces`]).
pub fn stress_csv(result: &RunResult) -> String {
    let mut s = String::with_capacity(80 * result.stress.len() + 32);
    s.push_str(STRESS_HEADER);
    s.push('\n');
    for r in &result.stress {
        let _ = writeln!(
            s,
            "{},{},{},{},{},{}",
            r.t, r.sxx, r.sxy, r.syx, r.syy, r.area
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
        let mut cols = e.values().map(|(c, v)| (c.name(), v)).chain([("t", e.t)]);
        if let Some((c, _)) = cols.find(|(_, v)| !v.is_finite()) {
            return Some(format!("energy.csv: non-finite {c} at t = {} s", e.t));
        }
    }
    for r in &result.obstacle_forces {
        if ![r.fx, r.fy, r.torque].iter().all(|v| v.is_finite()) {
            return Some(format!(
                "{OBSTACLES_FILE}: a non-finite force on obstacle {} at t = {} s",
                r.obstacle, r.t
            ));
        }
    }
    for r in &result.stress {
        if ![r.sxx, r.sxy, r.syx, r.syy, r.area]
            .iter()
            .all(|v| v.is_finite())
        {
            return Some(format!("stress.csv: a non-finite stress at t = {} s", r.t));
        }
    }
    if let Some(p) = &result.percussion {
        let impacts = p.impacts.iter().flat_map(|i| {
            [i.speed]
                .into_iter()
                .chain(i.point)
                .chain(i.normal)
                .chain(i.striker_mass)
        });
        let numbers = [
            p.t, p.angle, p.bound, p.weakest, p.loss, p.energy, p.spacing,
        ]
        .into_iter()
        .chain(p.position)
        .chain(impacts)
        .chain(p.nodes.iter().flatten().copied());
        if numbers.into_iter().any(|v| !v.is_finite()) {
            return Some(format!(
                "{PERCUSSION_FILE}: a non-finite number in the percussion of floe {} at t = {} s",
                p.floe, p.t
            ));
        }
    }
    None
}

/// The name of the percussion record a run of the lattice model writes.
pub const PERCUSSION_FILE: &str = "percussion.json";

/// Writes the six output files into `dir`, [`OBSTACLES_FILE`] when the
/// case has obstacles and [`PERCUSSION_FILE`] when the run has a
/// percussion record (an earlier run's file of either, in `dir`, is
/// removed otherwise); returns their paths. Refuses
/// (before writing anything) a result with a non-finite number in its
/// trajectory or ledger: the runner ends a run at the last finite output,
/// so this is a safety net that names the number.
pub fn write_run(dir: &Path, result: &RunResult) -> io::Result<Vec<PathBuf>> {
    if let Some(m) = non_finite(result) {
        return Err(io::Error::new(io::ErrorKind::InvalidData, m));
    }
    let mut files = vec![
        ("trajectory.csv", trajectory_csv(result).into_bytes()),
        ("energy.csv", energy_csv(result).into_bytes()),
        (
            "summary.json",
            serde_json::to_vec_pretty(&result.summary).map_err(io::Error::other)?,
        ),
        (
            "floes.json",
            serde_json::to_vec_pretty(&result.floes).map_err(io::Error::other)?,
        ),
        ("fractures.csv", fractures_csv(result).into_bytes()),
        ("stress.csv", stress_csv(result).into_bytes()),
    ];
    match result.summary.obstacles {
        0 => remove_stale(&dir.join(OBSTACLES_FILE))?,
        _ => files.push((OBSTACLES_FILE, obstacles_csv(result).into_bytes())),
    }
    match &result.percussion {
        // One line: its arrays of nodes and springs are long.
        Some(p) => files.push((
            PERCUSSION_FILE,
            serde_json::to_vec(p).map_err(io::Error::other)?,
        )),
        // An earlier run's record in the same folder is not this run's.
        None => remove_stale(&dir.join(PERCUSSION_FILE))?,
    }
    let mut paths = Vec::new();
    for (name, bytes) in files {
        let p = dir.join(name);
        write_atomic(&p, &bytes)?;
        paths.push(p);
    }
    Ok(paths)
}

/// Removes an earlier run's file `path` (none there is fine).
fn remove_stale(path: &Path) -> io::Result<()> {
    match std::fs::remove_file(path) {
        Err(e) if e.kind() != io::ErrorKind::NotFound => Err(e),
        _ => Ok(()),
    }
}

/// Writes `trajectory.nc` (the trajectory as CF NetCDF,
/// [`super::netcdf_out::write_trajectory`]) into `dir` for a run of `scn`;
/// returns its path.
pub fn write_netcdf(
    dir: &Path,
    result: &RunResult,
    scn: &crate::model::Scenario,
) -> io::Result<PathBuf> {
    let p = dir.join(super::netcdf_out::TRAJECTORY_FILE);
    let title = format!("floebench {}: {}", result.summary.formulation, scn.name);
    super::netcdf_out::write_trajectory(
        &p,
        &result.trajectory,
        &title,
        scn.start_date().as_deref(),
    )
    .map_err(io::Error::other)?;
    Ok(p)
}

/// The state at one output time of a `trajectory.csv` written by
/// [`write_run`]: the time and one [`BodyState`] per floe, in floe order.
/// `at` (s) picks the output time (equal to within 1e-9 relative); `None`
/// takes the last one. Errors name the file, and the line or the times the
/// file has.
pub fn read_state(
    path: &Path,
    at: Option<f64>,
) -> Result<(f64, Vec<crate::state::BodyState>), String> {
    use crate::geometry::Vec2;
    let file = path.display();
    let text = std::fs::read_to_string(path).map_err(|e| format!("{file}: {e}"))?;
    let mut lines = text.lines().enumerate();
    match lines.next() {
        Some((_, h)) if h.trim() == TRAJECTORY_HEADER => {}
        _ => {
            return Err(format!(
                "{file}:1: not a trajectory file (its first line must be `{TRAJECTORY_HEADER}`)"
            ))
        }
    }
    let mut rows: Vec<(f64, usize, [f64; 6])> = Vec::new();
    for (k, line) in lines {
        if line.trim().is_empty() {
            continue;
        }
        let bad = |what: &str| format!("{file}:{}: {what}", k + 1);
        let fields: Vec<&str> = line.split(',').map(str::trim).collect();
        if fields.len() != 8 {
            return Err(bad(&format!("{} values, expected 8", fields.len())));
        }
        let num = |i: usize| {
            fields[i]
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| bad(&format!("`{}` is not a finite number", fields[i])))
        };
        let floe = fields[1]
            .parse::<usize>()
            .map_err(|_| bad(&format!("floe `{}` is not an index", fields[1])))?;
        rows.push((
            num(0)?,
            floe,
            [num(2)?, num(3)?, num(4)?, num(5)?, num(6)?, num(7)?],
        ));
    }
    let (Some(first), Some(last)) = (rows.first().map(|r| r.0), rows.last().map(|r| r.0)) else {
        return Err(format!("{file}: no state (the file has only its header)"));
    };
    let t = at.unwrap_or(last);
    let same = |x: f64| (x - t).abs() <= 1e-9 * t.abs().max(1.0);
    let mut bodies: Vec<Option<crate::state::BodyState>> = Vec::new();
    let mut found = None;
    for &(tr, floe, [x, y, theta, vx, vy, omega]) in rows.iter().filter(|r| same(r.0)) {
        found = Some(tr);
        if bodies.len() <= floe {
            bodies.resize(floe + 1, None);
        }
        if bodies[floe].is_some() {
            return Err(format!("{file}: floe {floe} appears twice at t = {tr} s"));
        }
        bodies[floe] = Some(crate::state::BodyState {
            position: Vec2::new(x, y),
            angle: theta,
            velocity: Vec2::new(vx, vy),
            angular_velocity: omega,
        });
    }
    let Some(tr) = found else {
        return Err(format!(
            "{file}: no output at t = {t} s (the file has outputs from {first} s to {last} s)"
        ));
    };
    let bodies = bodies
        .into_iter()
        .enumerate()
        .map(|(i, b)| b.ok_or_else(|| format!("{file}: floe {i} is missing at t = {tr} s")))
        .collect::<Result<Vec<_>, _>>()?;
    Ok((tr, bodies))
}
