//! The divergence of two runs of one case written to disk, with the metric
//! of `floebench compare` (`analysis::divergence`: at each output time the
//! RMS over floes of the centre-of-mass distance, divided by the mean floe
//! diameter, the largest distance of a floe, and the same for the angles).
//!
//! Used to compare a warm-started run with a cold one of the same case
//! (issue 12, docs/results/2026-12-04-dense-packs-lemke.md); both runs must
//! have recorded every output time of the case, which is read for the
//! floes (mean diameter) and the output times.
//!
//! ```sh
//! cargo run --release --example run_divergence -- CASE.toml RUN_A RUN_B
//! ```
//!
//! Prints, per output time, `t,rms_position_rel,max_position_m,
//! rms_angle_rad,max_angle_rad` as CSV, then the summary on stderr.

use floebench::analysis::divergence::divergence_of_rows;
use floebench::formulation::load_case;
use floebench::run::output::read_state;
use floebench::run::TrajectoryRow;
use std::path::{Path, PathBuf};
use std::process::ExitCode;

/// Every output time of `case` (0, the interval, … up to the duration) read
/// from `dir/trajectory.csv` as trajectory rows.
fn rows_of(dir: &Path, duration: f64, interval: f64) -> Result<Vec<TrajectoryRow>, String> {
    let file = dir.join("trajectory.csv");
    let mut rows = Vec::new();
    let count = (duration / interval + 1e-9).floor() as usize;
    for k in 0..=count {
        let (t, bodies) = read_state(&file, Some(k as f64 * interval))?;
        for (floe, b) in bodies.iter().enumerate() {
            rows.push(TrajectoryRow::of(t, floe, b));
        }
    }
    Ok(rows)
}

fn main() -> ExitCode {
    let args: Vec<PathBuf> = std::env::args_os().skip(1).map(PathBuf::from).collect();
    let [case, a, b] = args.as_slice() else {
        eprintln!("usage: run_divergence CASE.toml RUN_A RUN_B");
        return ExitCode::FAILURE;
    };
    let scn = match load_case(case) {
        Ok(s) => s,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let read = |d: &Path| rows_of(d, scn.duration, scn.output_interval);
    let (rows_a, rows_b) = match (read(a), read(b)) {
        (Ok(x), Ok(y)) => (x, y),
        (Err(e), _) | (_, Err(e)) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    let label = |d: &Path| d.display().to_string();
    let d = match divergence_of_rows(&scn, (&label(a), &rows_a), (&label(b), &rows_b), 0.1) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("error: {e}");
            return ExitCode::FAILURE;
        }
    };
    println!("t,rms_position_rel,max_position_m,rms_angle_rad,max_angle_rad");
    for s in &d.samples {
        println!(
            "{},{:e},{:e},{:e},{:e}",
            s.t, s.rms_position_rel, s.max_position_m, s.rms_angle_rad, s.max_angle_rad
        );
    }
    eprintln!(
        "{} against {}: {} output times; largest RMS position difference {:e} mean diameters, \
         final {:e}; largest floe distance {:e} m; largest angle difference {:e} rad",
        d.b,
        d.a,
        d.samples.len(),
        d.max_rms_position_rel,
        d.final_rms_position_rel,
        d.max_position_m,
        d.max_angle_rad
    );
    ExitCode::SUCCESS
}
