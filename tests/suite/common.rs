//! Helpers shared by the test modules: bundled and bad case files, case
//! text, scenarios, runs of a formulation by name, the command-line binary,
//! reads of a run (final velocities, rest time, counters, settings), the
//! closed forms of docs/physics.md §6 that several formulations are held
//! to, a temporary folder, a signal to the binary once it says it is ready,
//! the check of an LCP solution, and the guards against panics and hangs of
//! the fuzz harness.

use floebench::analysis::check;
use floebench::formulation::{build, load_case, parse_case, FormulationOptions};
use floebench::geometry::Vec2;
use floebench::model::Scenario;
use floebench::run::{RunOptions, RunResult, Runner, TrajectoryRow};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::mpsc::{self, RecvTimeoutError};
use std::time::Duration;

// ---------------------------------------------------------------------------
// Case files and scenarios

/// The bundled cases, `cases/`.
pub fn cases_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("cases")
}

/// The path of `cases/<name>.toml` (`name` may hold a folder:
/// `fields/field_200_coast`).
pub fn case_path(name: &str) -> PathBuf {
    cases_dir().join(format!("{name}.toml"))
}

/// The text of `cases/<name>.toml`.
pub fn case_text(name: &str) -> String {
    std::fs::read_to_string(case_path(name)).unwrap()
}

/// The bundled case `cases/<name>.toml`, loaded (panics with the error).
pub fn load(name: &str) -> Scenario {
    load_case(&case_path(name)).unwrap_or_else(|e| panic!("{e}"))
}

/// The bad case files, `tests/cases/bad/`.
pub fn bad_cases_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/cases/bad")
}

/// The path of `tests/cases/bad/<name>.toml`.
pub fn bad_case(name: &str) -> PathBuf {
    bad_cases_dir().join(format!("{name}.toml"))
}

/// A scenario from case text (panics with the parse error).
pub fn scenario(text: &str) -> Scenario {
    parse_case(text, Path::new("inline.toml")).unwrap_or_else(|e| panic!("{e}"))
}

/// Case text with a `[formulation.<formulation>]` table of `settings` (TOML
/// lines) appended.
pub fn with_formulation_table(text: &str, formulation: &str, settings: &str) -> String {
    format!("{text}\n[formulation.{formulation}]\n{settings}\n")
}

// ---------------------------------------------------------------------------
// Panics and hangs

/// What broke an assertion of an input (a panic, a hang, a wrong answer).
pub type Defect = String;

/// An input that takes longer is a hang: a generous bound (inputs take
/// milliseconds), for detection only, never a measure of speed.
pub const TIME_BOUND: Duration = Duration::from_secs(30);

/// The text of a panic's payload.
fn panic_text(p: Box<dyn std::any::Any + Send>) -> String {
    p.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| p.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "(no message)".into())
}

/// `f()`, or the panic it raised as a defect naming `stage`.
pub fn guarded<T>(stage: &str, f: impl FnOnce() -> T) -> Result<T, Defect> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|p| format!("panic in {stage}: {}", panic_text(p)))
}

/// Runs `f` on a thread of its own and waits for it at most
/// [`TIME_BOUND`]; a longer wait is a hang (the thread is left behind).
pub fn within_bound<T: Send + 'static>(
    f: impl FnOnce() -> Result<T, Defect> + Send + 'static,
) -> Result<T, Defect> {
    let (tx, rx) = mpsc::channel();
    let spawned = std::thread::Builder::new()
        .stack_size(32 << 20)
        .spawn(move || {
            let r = guarded("the input's thread", f).and_then(|r| r);
            let _ = tx.send(r);
        });
    if let Err(e) = spawned {
        return Err(format!("cannot start a thread: {e}"));
    }
    match rx.recv_timeout(TIME_BOUND) {
        Ok(r) => r,
        Err(RecvTimeoutError::Timeout) => Err(format!("hang: no answer within {TIME_BOUND:?}")),
        Err(RecvTimeoutError::Disconnected) => Err("the input's thread died".into()),
    }
}

// ---------------------------------------------------------------------------
// LCPs

/// The largest magnitude of `v` (0 when empty).
pub fn max_abs(v: &[f64]) -> f64 {
    v.iter().fold(0.0_f64, |a, x| a.max(x.abs()))
}

/// Why `z` does not solve LCP(M, q) (M row-major n×n), or `None` when it
/// does up to `rel_tol` relative to `s = max(‖q‖∞, ‖M‖∞ ‖z‖∞)`: `z ≥ 0`,
/// `w ≥ −rel_tol s`, `|zᵀw| ≤ rel_tol s ‖z‖₁`, with `w = M z + q` computed
/// here, independently of the library's (compensated) `compute_w`.
pub fn lcp_violation(m: &[f64], q: &[f64], z: &[f64], rel_tol: f64) -> Option<String> {
    let n = q.len();
    if z.len() != n || m.len() != n * n {
        return Some(format!("sizes: z {}, q {n}, M {}", z.len(), m.len()));
    }
    if let Some(i) = z.iter().position(|v| !v.is_finite()) {
        return Some(format!("z[{i}] = {} is not finite", z[i]));
    }
    // z solves LCP(M, q) iff z/σ solves LCP(M, q/σ): judged on the scaled
    // problem, so that a problem near the f64 range (q of 1e308, z of 1e307)
    // does not overflow the check itself.
    let sigma = max_abs(q).max(max_abs(z)).max(f64::MIN_POSITIVE);
    let q: Vec<f64> = q.iter().map(|v| v / sigma).collect();
    let z: Vec<f64> = z.iter().map(|v| v / sigma).collect();
    let w: Vec<f64> = (0..n)
        .map(|i| (0..n).map(|j| m[i * n + j] * z[j]).sum::<f64>() + q[i])
        .collect();
    let s = max_abs(&q)
        .max(max_abs(m) * max_abs(&z))
        .max(f64::MIN_POSITIVE);
    for (i, (&zi, &wi)) in z.iter().zip(w.iter()).enumerate() {
        if zi.is_nan() || zi < 0.0 {
            return Some(format!("z[{i}] = {} < 0", zi * sigma));
        }
        if wi.is_nan() || wi < -rel_tol * s {
            return Some(format!(
                "w[{i}] = {wi} < -{rel_tol}*{s} (scaled by {sigma})"
            ));
        }
    }
    let ztw: f64 = z.iter().zip(w.iter()).map(|(a, b)| a * b).sum();
    let z1: f64 = z.iter().sum();
    if ztw.is_nan() || ztw.abs() > rel_tol * s * z1.max(f64::MIN_POSITIVE) {
        return Some(format!(
            "zᵀw = {ztw} too large (s = {s}, ‖z‖₁ = {z1}, scaled by {sigma})"
        ));
    }
    None
}

// ---------------------------------------------------------------------------
// Runs

/// Runs the formulation `name` of the registry on `scn` with the default
/// options; the run is labelled with the registry name.
pub fn run(scn: &Scenario, name: &str) -> RunResult {
    run_with(scn, name, &FormulationOptions::default())
}

/// [`run`] with formulation options `opts`.
pub fn run_with(scn: &Scenario, name: &str, opts: &FormulationOptions) -> RunResult {
    let mut f = build(name, scn, opts).unwrap_or_else(|e| panic!("{name}: {e}"));
    Runner::new(RunOptions::default()).run(scn, f.name(), f.formulation.as_mut())
}

/// The `floebench` binary of this build, as a command to give arguments.
pub fn floebench() -> Command {
    Command::new(env!("CARGO_BIN_EXE_floebench"))
}

/// Starts `floebench args`, waits for a line of its standard error holding
/// `ready`, waits `after` more, sends `signal`; returns (exit code, stderr).
pub fn interrupt_after(
    args: &[&std::ffi::OsStr],
    ready: &str,
    after: std::time::Duration,
    signal: libc::c_int,
) -> (Option<i32>, String) {
    let (code, seen, _) = interrupt_after_timed(args, ready, after, signal);
    (code, seen)
}

/// [`interrupt_after`], with the time from the signal to the process's end.
pub fn interrupt_after_timed(
    args: &[&std::ffi::OsStr],
    ready: &str,
    after: std::time::Duration,
    signal: libc::c_int,
) -> (Option<i32>, String, std::time::Duration) {
    use std::io::{BufRead, Read};
    let mut child = floebench()
        .args(args)
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut err = std::io::BufReader::new(child.stderr.take().unwrap());
    let mut seen = String::new();
    loop {
        let mut line = String::new();
        assert!(err.read_line(&mut line).unwrap() > 0, "ended early: {seen}");
        seen.push_str(&line);
        if line.contains(ready) {
            break;
        }
    }
    std::thread::sleep(after);
    let pid = libc::pid_t::try_from(child.id()).unwrap();
    // SAFETY: a signal to our own child process.
    assert_eq!(unsafe { libc::kill(pid, signal) }, 0);
    let sent = std::time::Instant::now();
    err.read_to_string(&mut seen).unwrap();
    let code = child.wait().unwrap().code();
    (code, seen, sent.elapsed())
}

/// A temporary folder, removed when the value is dropped: keep it alive for
/// as long as the test uses its files.
/// Runs `cmd`, asserts that it succeeded (showing its stderr if not) and
/// returns its standard output.
pub fn stdout_of_success(cmd: &mut Command) -> String {
    let out = cmd.output().expect("runs");
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

pub fn tempdir() -> tempfile::TempDir {
    tempfile::tempdir().expect("a temporary folder")
}

// ---------------------------------------------------------------------------
// Reading a run

/// The velocity of `floe` at the end of the run, m/s.
pub fn final_velocity(r: &RunResult, floe: usize) -> Vec2 {
    r.final_state.bodies[floe].velocity
}

/// The first output time after the last row (of any floe) for which
/// `moving` holds.
pub fn rest_time_by(r: &RunResult, moving: impl Fn(&TrajectoryRow) -> bool) -> f64 {
    let last_move = r
        .trajectory
        .iter()
        .filter(|row| moving(row))
        .map(|row| row.t)
        .fold(0.0, f64::max);
    r.trajectory
        .iter()
        .map(|row| row.t)
        .find(|&t| t > last_move)
        .unwrap()
}

/// The first output time after which no floe moves along x
/// (|vx| ≤ 1e-12 m/s).
pub fn rest_time(r: &RunResult) -> f64 {
    rest_time_by(r, |row| row.vx.abs() > 1e-12)
}

/// The first output time from which every floe's speed stays below `v`
/// (m/s).
pub fn rest_time_below(r: &RunResult, v: f64) -> f64 {
    rest_time_by(r, |row| row.vx.hypot(row.vy) > v)
}

/// The counter `name` of a run as a real number; panics if the run does not
/// keep it (a misspelt name fails the test instead of reading 0).
pub fn counter(r: &RunResult, name: &str) -> f64 {
    match r.summary.counters.by_name(name) {
        Ok(Some(v)) => v,
        Ok(None) => panic!("{}: counter `{name}` kept but never set", r.summary.case),
        Err(e) => panic!("{}: {e}", r.summary.case),
    }
}

/// The numeric setting `name` of a run; panics if the run has none.
pub fn setting(r: &RunResult, name: &str) -> f64 {
    r.summary
        .settings
        .get(name)
        .unwrap_or_else(|| panic!("{}: no numeric setting `{name}`", r.summary.case))
}

// ---------------------------------------------------------------------------
// Closed forms (docs/physics.md §6)

/// The head-on case (`cases/head_on.toml`) with restitution `e`.
pub fn head_on(e: f64) -> Scenario {
    scenario(&case_text("head_on").replace("restitution = 0.4", &format!("restitution = {e:?}")))
}

/// The head-on closed form (docs/physics.md §6.1) for the head-on case's speeds
/// (0.5 and −0.1 m/s): `(v1', v2')`, m/s.
pub fn head_on_expected(scn: &Scenario, e: f64) -> (f64, f64) {
    let (m1, m2) = (scn.floes[0].mass, scn.floes[1].mass);
    let (v1, v2) = (0.5, -0.1);
    let v1p = (m1 * v1 + m2 * v2 - m2 * e * (v1 - v2)) / (m1 + m2);
    let v2p = (m1 * v1 + m2 * v2 + m1 * e * (v1 - v2)) / (m1 + m2);
    (v1p, v2p)
}

/// Asserts the head-on closed form to 1e-9 (relative), no transverse
/// velocity, and momentum to 1e-12; `label` names the run in messages.
pub fn assert_head_on(r: &RunResult, scn: &Scenario, e: f64, label: &str) {
    let (m1, m2) = (scn.floes[0].mass, scn.floes[1].mass);
    let (v1, v2) = (0.5, -0.1);
    let (v1p, v2p) = head_on_expected(scn, e);
    let (a, b) = (final_velocity(r, 0), final_velocity(r, 1));
    assert!(
        (a.x - v1p).abs() <= 1e-9 * v1p.abs().max(1e-3),
        "{label}: v1' {} vs {v1p}",
        a.x
    );
    assert!(
        (b.x - v2p).abs() <= 1e-9 * v2p.abs().max(1e-3),
        "{label}: v2' {} vs {v2p}",
        b.x
    );
    assert!(a.y.abs() < 1e-12 && b.y.abs() < 1e-12);
    let p0 = m1 * v1 + m2 * v2;
    let p1 = r.final_state.momentum(scn);
    assert!(
        (p1.x - p0).abs() <= 1e-12 * p0.abs(),
        "{label}: momentum {} vs {p0}",
        p1.x
    );
}

/// The bouncing floe (docs/physics.md §6): pushed by the wind at `a` (m/s²)
/// across a gap of 1 m, it first hits the wall at `t1` (s) with speed `v1`
/// (m/s), and with restitution `e` the bounces accumulate at `t_inf` (s).
#[derive(Debug, Clone, Copy)]
pub struct Bouncing {
    pub a: f64,
    pub t1: f64,
    pub v1: f64,
    pub t_inf: f64,
}

/// The bouncing-floe closed form for floe 0 of `scn` (a 1 m gap along the
/// wind), with the case's restitution.
pub fn bouncing_expected(scn: &Scenario) -> Bouncing {
    let e = scn.contact.restitution;
    let a = check::wind_acceleration(scn, 0);
    let d = 1.0;
    let t1 = (2.0 * d / a).sqrt();
    let v1 = a * t1;
    let t_inf = t1 * (1.0 + e) / (1.0 - e);
    Bouncing { a, t1, v1, t_inf }
}

/// The sliding floe (docs/physics.md §6): pressed on the wall by the wind at `a`
/// (m/s²), sliding along it at `v0` = 0.05 m/s with friction `mu`, it stops
/// after `t_stop` (s) and `dist` (m).
#[derive(Debug, Clone, Copy)]
pub struct Sliding {
    pub a: f64,
    pub mu: f64,
    pub v0: f64,
    pub t_stop: f64,
    pub dist: f64,
}

/// The sliding-floe closed form for floe 0 of `scn`.
pub fn sliding_expected(scn: &Scenario) -> Sliding {
    let a = check::wind_acceleration(scn, 0);
    let (mu, v0) = (scn.contact.friction, 0.05);
    let t_stop = v0 / (mu * a);
    let dist = v0 * v0 / (2.0 * mu * a);
    Sliding {
        a,
        mu,
        v0,
        t_stop,
        dist,
    }
}

/// The steady free-drift velocity without Coriolis (docs/physics.md §6),
/// `U_w + sqrt(ρ_a C_a / (ρ_w C_w)) U_a` at t = 0, m/s.
pub fn drift_velocity(scn: &Scenario) -> Vec2 {
    let env = &scn.environment;
    env.water.velocity.at(&Vec2::zeros(), 0.0, &env.outside)
        + env.air.velocity.at(&Vec2::zeros(), 0.0, &env.outside)
            * (env.air.drag_factor() / env.water.drag_factor()).sqrt()
}

/// The square of side `side` (m) with a corner at the origin, counter-clockwise.
pub fn square(side: f64) -> Vec<Vec2> {
    vec![
        Vec2::new(0.0, 0.0),
        Vec2::new(side, 0.0),
        Vec2::new(side, side),
        Vec2::new(0.0, side),
    ]
}

/// A square of side `2 half` (m) centred at the origin, turned by `tilt`
/// (rad): its outline as a case's `polygon` value, and its largest x (m).
pub fn turned_square(half: f64, tilt: f64) -> (String, f64) {
    let corners: Vec<[f64; 2]> = [[-half, -half], [half, -half], [half, half], [-half, half]]
        .iter()
        .map(|[x, y]| {
            [
                x * tilt.cos() - y * tilt.sin(),
                x * tilt.sin() + y * tilt.cos(),
            ]
        })
        .collect();
    let lead = corners.iter().map(|c| c[0]).fold(f64::MIN, f64::max);
    let polygon = corners
        .iter()
        .map(|[x, y]| format!("[{x:.17}, {y:.17}]"))
        .collect::<Vec<_>>()
        .join(", ");
    (format!("[{polygon}]"), lead)
}
