//! `[sweep] start`: every run of a plan (its reference and its points)
//! started from the state of an earlier run at one of its output times, as
//! `floebench run --from FILE --at T` starts one run, and optionally run
//! for a shorter `duration`: a work–precision sweep of a pack's jammed
//! phase without paying for its formation (docs/sweep-format.md).

use crate::model::{Restart, Scenario};
use crate::run::output::read_state;
use crate::state::BodyState;
use serde::Deserialize;
use std::path::{Path, PathBuf};

/// `start = { trajectory = "...", at = T, duration = D }` as written.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct StartSpec {
    /// The trajectory file (`trajectory.csv` of a run), relative to the plan.
    trajectory: String,
    /// Its output time to start from, s (default: its last).
    at: Option<f64>,
    /// The span each run covers from there, s (default: the case's
    /// duration).
    duration: Option<f64>,
}

/// The start of every run of a plan (see the module doc).
#[derive(Debug, Clone, PartialEq)]
pub struct Start {
    /// The trajectory file the state is read from.
    pub file: PathBuf,
    /// The output time of that file the runs start from, s.
    pub t: f64,
    /// The span each run covers, s (`None`: the case's duration).
    pub duration: Option<f64>,
    /// Each floe's pose and velocities there.
    bodies: Vec<BodyState>,
}

impl Start {
    /// Reads the state `spec` names, the file relative to `base` (the
    /// plan's folder).
    pub(super) fn read(spec: &StartSpec, base: &Path) -> Result<Start, String> {
        if let Some(d) = spec.duration {
            if !(d.is_finite() && d > 0.0) {
                return Err(format!("duration = {d} s must be finite and > 0"));
            }
        }
        let file = base.join(&spec.trajectory);
        let (t, bodies) = read_state(&file, spec.at).map_err(|e| {
            format!(
                "{e} (make it with `floebench run <case> -f <formulation> -o <folder>`: its trajectory.csv)"
            )
        })?;
        Ok(Start {
            file,
            t,
            duration: spec.duration,
            bodies,
        })
    }

    /// `scn` started from this state (time starts again at 0), for the
    /// start's duration: refused when the case's floes are not the
    /// state's, or the duration is not a multiple of the case's output
    /// interval.
    pub fn apply(&self, scn: &mut Scenario) -> Result<(), String> {
        crate::state::restart(
            scn,
            &self.bodies,
            Restart {
                file: self.file.clone(),
                t: self.t,
            },
        )?;
        if let Some(d) = self.duration {
            let k = d / scn.output_interval;
            if (k - k.round()).abs() > 1e-9 * k.max(1.0) || k.round() < 1.0 {
                return Err(format!(
                    "start duration = {d} s is not a multiple of case `{}`'s output_interval = {} s",
                    scn.name, scn.output_interval
                ));
            }
            scn.duration = d;
        }
        Ok(())
    }

    /// What distinguishes this start in a point's fingerprint: the file,
    /// the time, the duration and every state value's bits.
    pub fn label(&self) -> String {
        let mut s = format!(
            "start {} at {:?} for {:?}",
            self.file.display(),
            self.t,
            self.duration
        );
        for b in &self.bodies {
            for v in [
                b.position.x,
                b.position.y,
                b.angle,
                b.velocity.x,
                b.velocity.y,
                b.angular_velocity,
            ] {
                s.push_str(&format!(" {:016x}", v.to_bits()));
            }
        }
        s
    }
}
