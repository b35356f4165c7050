//! What is saved never changes the dynamics: every bundled small case, run
//! by every formulation that applies to it at three output intervals (the
//! case's `Δ`, `3Δ` and `1.25Δ`), gives the same states at the times the
//! runs share, to 1e-12; a fixed-step formulation refuses an interval that
//! is not a multiple of its step, naming it; and a single output at the end
//! of the run (`output_interval = duration`) neither hangs nor changes the
//! final state.
//!
//! The three drift cases are cut to their first [`LONGEST`] s (rapier's
//! 0.1 s steps over their 20,000–110,000 s take seconds per run); the others
//! run whole.
//!
//! Scales of the comparison (relative 1e-12): positions by the largest floe
//! diameter of the case (`2 r_max`, the size a position error is judged
//! against; rounding of a position 10 km from the origin is 2e-12 m);
//! velocities by the largest speed of the reference run (at least 1e-3 m/s);
//! angles by 1 rad and angular velocities by that speed over `r_max`; the
//! energy ledger by the energy the run exchanged.

use crate::common::{case_text, cases_dir};
use floebench::analysis::divergence::row_frames;
use floebench::formulation::{build, parse_case, FormulationOptions, REGISTRY};
use floebench::model::Scenario;
use floebench::run::energy::Column;
use floebench::run::{batch, RunOptions, RunResult, Runner, TrajectoryRow};
use std::path::Path;

/// Relative tolerance of the comparison.
const TOLERANCE: f64 = 1e-12;

/// A run with one output still running after this hangs.
const HANG: std::time::Duration = std::time::Duration::from_secs(120);

/// The longest duration run, s.
const LONGEST: f64 = 4500.0;

/// `text` with the value of its `key` line replaced by `value`.
fn with_key(text: &str, key: &str, value: f64) -> String {
    let line = text
        .lines()
        .find(|l| l.trim_start().starts_with(key))
        .unwrap_or_else(|| panic!("a case sets {key}"));
    text.replacen(line, &format!("{key} = {value:?}"), 1)
}

/// `text` with its output interval (s) replaced and its duration cut to
/// [`LONGEST`].
fn with_interval(text: &str, interval: f64) -> String {
    let scn = parse_case(text, &cases_dir().join("inline.toml")).unwrap_or_else(|e| panic!("{e}"));
    let text = if scn.duration > LONGEST {
        with_key(text, "duration", LONGEST)
    } else {
        text.to_string()
    };
    with_key(&text, "output_interval", interval)
}

/// The case `text` with output interval `interval`, run by `name`, or the
/// formulation's refusal.
fn run_at(text: &str, interval: f64, name: &str) -> Result<RunResult, String> {
    let scn = parse_case(
        &with_interval(text, interval),
        &cases_dir().join("inline.toml"),
    )
    .unwrap();
    // The case loads (an output interval is not refused by the case's own
    // rules); the formulation's builder refuses it, naming the file and line.
    let mut f = build(name, &scn, &FormulationOptions::default())?;
    Ok(Runner::new(RunOptions::default()).run(&scn, name, f.formulation.as_mut()))
}

/// The largest difference between the states and ledgers of `a` and `b` at
/// the output times they share, each relative to its scale (module doc),
/// with the number of shared times.
fn largest_difference(scn: &Scenario, a: &RunResult, b: &RunResult) -> (f64, usize) {
    // One frame of rows per energy sample: the floes alive then (pieces of
    // broken floes included).
    let fa: Vec<&[TrajectoryRow]> = row_frames(&a.trajectory).collect();
    let fb: Vec<&[TrajectoryRow]> = row_frames(&b.trajectory).collect();
    let r_max = scn.floes.iter().map(|f| f.radius).fold(0.0, f64::max);
    let speed = a
        .trajectory
        .iter()
        .map(|r| r.vx.hypot(r.vy))
        .fold(1e-3, f64::max);
    let energy = a.summary.energy.exchanged.max(f64::MIN_POSITIVE);
    let mut worst = 0.0f64;
    let mut shared = 0;
    for (ka, ea) in a.energy.iter().enumerate() {
        let Some(kb) = b
            .energy
            .iter()
            .position(|eb| (eb.t - ea.t).abs() <= 1e-9 * ea.t.abs().max(1.0))
        else {
            continue;
        };
        shared += 1;
        let eb = &b.energy[kb];
        // The kinetic energy and every field of the ledger.
        for c in Column::all().filter(|c| !matches!(c, Column::Residual)) {
            worst = worst.max((c.of(ea) - c.of(eb)).abs() / energy);
        }
        assert_eq!(
            fa[ka].len(),
            fb[kb].len(),
            "the same floes at t = {} s",
            ea.t
        );
        for (p, q) in fa[ka].iter().zip(fb[kb]) {
            assert_eq!(p.floe, q.floe);
            worst = worst
                .max((p.x - q.x).hypot(p.y - q.y) / (2.0 * r_max))
                .max((p.vx - q.vx).hypot(p.vy - q.vy) / speed)
                .max((p.theta - q.theta).abs())
                .max((p.omega - q.omega).abs() * r_max / speed);
        }
    }
    (worst, shared)
}

#[test]
fn every_case_gives_the_same_states_whatever_its_output_interval() {
    let cases = batch::load_cases(&[cases_dir()]).unwrap_or_else(|e| panic!("{e}"));
    assert!(cases.len() >= 12, "{} cases", cases.len());
    let (mut compared, mut refused) = (0, 0);
    for (path, scn) in &cases {
        let text = std::fs::read_to_string(path).unwrap();
        let dt = scn.output_interval;
        for entry in REGISTRY.iter().filter(|e| e.applies(scn)) {
            let label = format!("{} / {}", scn.name, entry.name);
            let base = run_at(&text, dt, entry.name).unwrap_or_else(|e| panic!("{label}: {e}"));
            for factor in [3.0, 1.25] {
                match run_at(&text, factor * dt, entry.name) {
                    Ok(other) => {
                        let (worst, shared) = largest_difference(scn, &base, &other);
                        assert!(shared >= 2, "{label} at {factor} Δ: {shared} shared times");
                        assert!(
                            worst <= TOLERANCE,
                            "{label}: output interval {factor} Δ changes the states by {worst:e} (relative)"
                        );
                        compared += 1;
                    }
                    Err(e) => {
                        // Only a fixed-step scheme refuses, and it says why.
                        assert!(
                            e.contains("is not a multiple of its step")
                                && e.contains("inline.toml:")
                                && e.contains("would do"),
                            "{label} at {factor} Δ: {e}"
                        );
                        refused += 1;
                    }
                }
            }
        }
    }
    assert!(
        compared >= 40 && refused >= 10,
        "{compared} compared, {refused} refused"
    );
}

#[test]
fn a_single_output_at_the_end_neither_hangs_nor_changes_the_final_state() {
    // bouncing_floe with output_interval = 400 s (its duration): the old
    // event-driven horizon τ = min(Δt_max, output_interval) made this spin.
    let text = case_text("bouncing_floe");
    let scn = parse_case(&text, Path::new("bouncing_floe.toml")).unwrap();
    assert_eq!(scn.duration, 400.0);
    for entry in REGISTRY.iter().filter(|e| e.applies(&scn)) {
        let every_second = run_at(&text, 1.0, entry.name).unwrap();
        // Hang detection, generous (the run takes milliseconds).
        let (send, receive) = std::sync::mpsc::channel();
        let (t, name) = (text.clone(), entry.name);
        std::thread::spawn(move || {
            // The receiver may have given up (a hang): nothing to send to.
            let _ = send.send(Box::new(run_at(&t, 400.0, name).unwrap()));
        });
        let once = receive
            .recv_timeout(HANG)
            .unwrap_or_else(|_| panic!("{}: no end after {HANG:?}", entry.name));
        assert_eq!(once.energy.len(), 2, "{}: t = 0 and 400 s", entry.name);
        let (worst, shared) = largest_difference(&scn, &every_second, &once);
        assert_eq!(shared, 2, "{}", entry.name);
        assert!(worst <= TOLERANCE, "{}: {worst:e}", entry.name);
        assert_eq!(once.final_state, every_second.final_state, "{}", entry.name);
    }
}
