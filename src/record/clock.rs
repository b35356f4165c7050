//! CPU time per stage, measured by the runner's clock and charged by the
//! formulations to the stage they are in.
//!
//! Time is the calling thread's CPU time (`CLOCK_THREAD_CPUTIME_ID`), so runs
//! in parallel threads do not distort each other; wall time is kept beside it.

use serde::Serialize;
use std::time::Instant;

/// The stages of a step, after rapier's pipeline: detect, solve, integrate.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// Contact detection: broad and narrow phase, event location.
    Detection,
    /// Contact problems: assembly and solution (LCP, cone program, …).
    Solve,
    /// Smooth integration of the environment forces.
    Integration,
}

/// The CPU time of the calling thread, s.
pub fn thread_cpu_seconds() -> f64 {
    #[cfg(unix)]
    {
        let mut ts = libc::timespec {
            tv_sec: 0,
            tv_nsec: 0,
        };
        // SAFETY: `ts` is a valid, writable timespec; the call only writes it.
        let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
        if rc == 0 {
            return ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9;
        }
    }
    // Fallback: wall time since the first call.
    use std::sync::OnceLock;
    static START: OnceLock<Instant> = OnceLock::new();
    START.get_or_init(Instant::now).elapsed().as_secs_f64()
}

/// CPU seconds spent in each stage.
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize)]
pub struct StageTimes {
    /// Contact detection, s.
    pub detection: f64,
    /// Contact solve, s.
    pub solve: f64,
    /// Smooth integration, s.
    pub integration: f64,
}

/// The clock a formulation charges its stages to.
#[derive(Debug, Default)]
pub struct StageClock {
    times: StageTimes,
}

impl StageClock {
    /// A clock at zero.
    pub fn new() -> Self {
        Self::default()
    }

    /// Runs `f`, charging its CPU time to `stage`.
    pub fn time<R>(&mut self, stage: Stage, f: impl FnOnce() -> R) -> R {
        let t0 = thread_cpu_seconds();
        let r = f();
        self.charge(stage, thread_cpu_seconds() - t0);
        r
    }

    /// Adds `seconds` of CPU time to `stage`.
    pub fn charge(&mut self, stage: Stage, seconds: f64) {
        let slot = match stage {
            Stage::Detection => &mut self.times.detection,
            Stage::Solve => &mut self.times.solve,
            Stage::Integration => &mut self.times.integration,
        };
        *slot += seconds;
    }

    /// Totals so far.
    pub fn times(&self) -> StageTimes {
        self.times
    }
}
