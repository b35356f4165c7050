//! CPU time per stage: measured by the runner, charged by the formulations
//! to the stage they are in, at a cost that does not distort what it
//! measures.
//!
//! The figure reported is the run's **thread CPU time**
//! (`CLOCK_THREAD_CPUTIME_ID`), so runs in parallel threads do not distort
//! each other. That clock is a system call here (about 0.3 µs), too dear to
//! read around every stage of every step (a cheap fixed step costs a few
//! µs). So:
//!
//! - the runner reads the thread CPU clock twice per run (start and end);
//! - the stages are timed with the monotonic clock ([`Instant`], read in user
//!   space through the vDSO, tens of ns), and each stage's CPU time is the
//!   run's CPU time split in the proportions of the stages' monotonic times
//!   ([`StageClock::split`]): exact in total, an estimate of the split that
//!   assumes the thread was descheduled evenly across stages;
//! - every monotonic read is counted, and its cost, measured once per
//!   process ([`monotonic_read_cost`]), gives the timer's own overhead,
//!   reported beside the CPU time ([`StageClock::overhead`]).

pub use super::stage::{Stage, StageTimes};
use std::sync::OnceLock;
use std::time::Instant;

/// The CPU time of the calling thread, s (a system call: read it rarely).
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
    static START: OnceLock<Instant> = OnceLock::new();
    START.get_or_init(Instant::now).elapsed().as_secs_f64()
}

/// CPU cost of one monotonic clock read ([`Instant::now`]), s: measured once
/// per process as the thread CPU time of 100,000 reads divided by their
/// number (a few tens of ns on this machine).
pub fn monotonic_read_cost() -> f64 {
    static COST: OnceLock<f64> = OnceLock::new();
    *COST.get_or_init(|| {
        const READS: u32 = 100_000;
        let c0 = thread_cpu_seconds();
        let mut last = Instant::now();
        for _ in 1..READS {
            last = std::hint::black_box(Instant::now());
        }
        std::hint::black_box(last);
        ((thread_cpu_seconds() - c0) / f64::from(READS)).max(0.0)
    })
}

/// Regions whose mean monotonic time is at least this many clock-read costs
/// are always timed (the two reads then cost at most 1 % of the region).
const ALWAYS_TIMED_READS: f64 = 200.0;
/// Cheaper regions are timed with this probability (1 in 64, independently),
/// each timed duration weighted by its inverse (an unbiased estimate of the
/// stage's total), so the timer costs about 1 % of a sub-microsecond step.
const SAMPLE_PROBABILITY: f64 = 1.0 / 64.0;
/// A drawn region longer than this many times its kind's mean, and longer
/// than [`OUTLIER_FLOOR`], counts as the larger of the two (see
/// [`StageClock`]).
const OUTLIER_FACTOR: f64 = 20.0;
/// The cap of a drawn region is never below this, s: a scheduler tick is
/// about 4 ms, and a cheap kind's genuinely dear calls (an LCP among cheap
/// calls of the same stage) are mostly shorter.
const OUTLIER_FLOOR: f64 = 1e-3;
/// The first region of each kind is timed, to learn its mean (the timed
/// ones after it refine the mean; a cold first region taken for a dear kind
/// is timed again until the mean falls below [`ALWAYS_TIMED_READS`]). One,
/// not more: each costs two reads, and the runs of 40 µs (`newtons_cannon`
/// by `moreau`) pay the warm-up of every kind (8 per kind put 1.5 µs, 3.6 %
/// of such a run, on the timer).
const WARM_UP: u64 = 1;

/// The start of a region ([`StageClock::start`]), timed or not.
#[derive(Debug, Clone, Copy)]
pub struct Started {
    at: Option<Instant>,
    weight: f64,
    /// [`measured_inside`]'s total when the region began.
    inner0: f64,
    /// The stage clock's time charged to stages when the region began
    /// ([`StageClock::start`]; zero for a bare [`Sampler`]).
    charged0: f64,
}

thread_local! {
    /// Monotonic seconds of the regions this thread has timed whole
    /// (weight 1), by every [`Sampler`], nested regions counted once: when
    /// a region timed whole ends, the total becomes its value at the
    /// region's start plus the region's duration (which includes whatever
    /// was measured inside it).
    static MEASURED: std::cell::Cell<f64> = const { std::cell::Cell::new(0.0) };
}

/// The thread's [`MEASURED`] total, s.
fn measured_inside() -> f64 {
    MEASURED.with(|m| m.get())
}

/// What is known of one kind of region: calls, timed calls and the mean of
/// the timed durations.
#[derive(Debug, Clone, Copy, Default)]
struct Kind {
    timed: u64,
    mean: f64,
    /// Cheap regions still to pass untimed before the next drawn one.
    skip: u64,
}

/// A timer of regions of several kinds at a cost that stays small: a kind
/// whose mean is dear is timed every time, a cheap one with probability
/// 1/64, each timed duration weighted by 64 (see [`StageClock`] for the
/// rule and its price). Used by the stage clock and by the contact solver's
/// profile by size.
#[derive(Debug, Clone)]
pub struct Sampler {
    kinds: Vec<Kind>,
    reads: u64,
    untimed: u64,
    rng: u64,
    /// Mean region time from which every region is timed, s.
    dear: f64,
}

impl Sampler {
    /// A sampler of `kinds` kinds of regions.
    pub fn new(kinds: usize) -> Sampler {
        Sampler {
            kinds: vec![Kind::default(); kinds],
            reads: 0,
            untimed: 0,
            rng: 0x9E37_79B9_7F4A_7C15,
            dear: ALWAYS_TIMED_READS * monotonic_read_cost(),
        }
    }

    /// Starts a region of `kind`; whether it is timed is decided here.
    pub fn begin(&mut self, kind: usize) -> Started {
        let inner0 = measured_inside();
        let Some(k) = self.kinds.get_mut(kind) else {
            return Started {
                at: None,
                weight: 0.0,
                inner0,
                charged0: 0.0,
            };
        };
        if k.skip > 0 {
            // Counted in `untimed` when the skip was drawn.
            k.skip -= 1;
            return Started {
                at: None,
                weight: 0.0,
                inner0,
                charged0: 0.0,
            };
        }
        let always = k.timed < WARM_UP || k.mean >= self.dear;
        let weight = if always {
            1.0
        } else {
            // Independent draws of probability p, as the number of regions
            // to pass before the next one: geometric, ⌊ln U / ln(1 − p)⌋
            // with U uniform in (0, 1] (xorshift64).
            self.rng ^= self.rng << 13;
            self.rng ^= self.rng >> 7;
            self.rng ^= self.rng << 17;
            let u = ((self.rng >> 11) + 1) as f64 / (1u64 << 53) as f64;
            k.skip = (u.ln() / (1.0 - SAMPLE_PROBABILITY).ln()) as u64;
            self.untimed += k.skip;
            1.0 / SAMPLE_PROBABILITY
        };
        self.reads += 1;
        Started {
            at: Some(Instant::now()),
            weight,
            inner0,
            charged0: 0.0,
        }
    }

    /// Ends a region of `kind`: its estimated monotonic time, s, or `None`
    /// when nothing of it is known.
    ///
    /// Regions timed whole inside it (by any sampler of this thread: an
    /// LCP of a size whose solves are dear, inside a call of a stage whose
    /// calls are mostly cheap) are known exactly, whether this region is
    /// timed or not, and count once, unweighted: an untimed region is
    /// charged their time alone; a drawn one, its own time (capped, see
    /// [`StageClock`]) weighted, plus theirs. Without this, a run whose
    /// dear solves fall in untimed calls of a cheap stage showed them in no
    /// stage (100 s of the bay jam: 52.7 s of CPU, its solve stage 0.03 s).
    pub fn end(&mut self, kind: usize, s: Started) -> Option<f64> {
        let inside = (measured_inside() - s.inner0).max(0.0);
        let Some(at) = s.at else {
            return (inside > 0.0).then_some(inside);
        };
        self.reads += 1;
        let dt = at.elapsed().as_secs_f64();
        let k = self.kinds.get_mut(kind)?;
        let cap = (OUTLIER_FACTOR * k.mean).max(OUTLIER_FLOOR);
        let mut own = (dt - inside).max(0.0);
        if s.weight > 1.0 && k.timed > 0 {
            // A drawn (cheap) region far above its kind's mean was most
            // likely descheduled or interrupted: weighted by 64 it would
            // swamp the estimate, so it counts as OUTLIER_FACTOR × the mean.
            own = own.min(cap);
        }
        // The mean decides whether the kind is dear: a region descheduled
        // for a scheduler tick must not make a cheap kind look dear for
        // thousands of regions, so it enters the mean capped like a drawn
        // one (an always-timed region is still charged in full).
        let typical = if k.timed > 0 {
            (own + inside).min(cap)
        } else {
            own + inside
        };
        k.timed += 1;
        k.mean += (typical - k.mean) / k.timed as f64;
        if s.weight == 1.0 {
            // Timed whole: what encloses it sees its whole duration.
            MEASURED.with(|m| m.set(s.inner0 + dt));
        }
        Some(own * s.weight + inside)
    }

    /// Monotonic clock reads so far.
    pub fn reads(&self) -> u64 {
        self.reads
    }

    /// Regions that were not timed.
    pub fn untimed(&self) -> u64 {
        // Skips are counted when drawn; those not yet passed are not regions.
        self.untimed - self.kinds.iter().map(|k| k.skip).sum::<u64>()
    }

    /// The CPU time the sampler itself cost, s: its reads times the
    /// measured cost of one read, plus its untimed regions times the
    /// measured cost of passing one.
    pub fn overhead(&self) -> f64 {
        self.reads as f64 * monotonic_read_cost() + self.untimed() as f64 * untimed_region_cost()
    }
}

/// The clock a formulation charges its stages to: an estimate of the
/// monotonic time per stage from timed regions (every region while its kind
/// is dear, a random 1 in 64 while it is cheap, weighted by 64), and the
/// count of clock reads.
///
/// A drawn region is capped at the larger of [`OUTLIER_FACTOR`] times its
/// kind's mean and [`OUTLIER_FLOOR`]: on a shared machine a region that
/// spans a deschedule would otherwise, weighted by 64, move the split by a
/// large amount from run to run. The price: calls dearer than a millisecond
/// in a kind whose mean is cheap are underestimated (a kind whose mean is
/// dear is timed whole, without cap), except for what another sampler
/// timed whole inside them, which counts in full whether the call was
/// timed or not ([`Sampler::end`]): the contact solver times every LCP of
/// a size whose solves are dear, so a rare dear solve inside a stage call
/// that is usually cheap (an impact among many steps without one) is
/// charged to its stage. The split is an estimate in any case; the total
/// CPU time is exact.
#[derive(Debug)]
pub struct StageClock {
    times: StageTimes,
    sampler: Sampler,
    reads: u64,
    born: Instant,
    /// Monotonic seconds charged to the stages so far (the sum of
    /// `times`, kept apart so that a region sees what regions nested in
    /// it were charged).
    charged: f64,
}

impl Default for StageClock {
    fn default() -> Self {
        StageClock {
            times: StageTimes::default(),
            sampler: Sampler::new(6),
            reads: 1,
            born: Instant::now(),
            charged: 0.0,
        }
    }
}

fn index(stage: Stage) -> usize {
    match stage {
        Stage::Detection => 0,
        Stage::Solve => 1,
        Stage::Integration => 2,
        Stage::Lattice => 4,
        Stage::Crushing => 5,
    }
}

/// The kind of the regions a caller splits among the stages itself.
const MIXED: usize = 3;

impl StageClock {
    /// A clock at zero.
    pub fn new() -> Self {
        Self::default()
    }

    /// Runs `f`, charging its monotonic time to `stage`.
    pub fn time<R>(&mut self, stage: Stage, f: impl FnOnce() -> R) -> R {
        let s = self.start(stage);
        let r = f();
        self.stop(stage, s);
        r
    }

    /// Starts a region of `stage` that [`StageClock::stop`] ends (for regions
    /// a closure cannot hold). Whether it is timed is decided here.
    pub fn start(&mut self, stage: Stage) -> Started {
        Started {
            charged0: self.charged,
            ..self.sampler.begin(index(stage))
        }
    }

    /// Ends a region started by [`StageClock::start`] for the same `stage`.
    ///
    /// Stage regions nested in it (a lattice impact called from a contact
    /// solve) were charged to their own stages: their time is taken out of
    /// this region's (which includes it), so each second counts in one
    /// stage.
    pub fn stop(&mut self, stage: Stage, s: Started) {
        let nested = self.charged - s.charged0;
        if let Some(dt) = self.sampler.end(index(stage), s) {
            let own = (dt - nested).max(0.0);
            *self.times.slot(stage) += own;
            self.charged += own;
        }
    }

    /// Starts a region that the caller splits among the stages itself
    /// ([`StageClock::stop_split`]), e.g. by a library's own stage timers;
    /// [`Started::is_timed`] says whether to collect them.
    pub fn start_split(&mut self) -> Started {
        self.sampler.begin(MIXED)
    }

    /// Ends a region of [`StageClock::start_split`], charging it to the
    /// stages in the proportions `fractions` (detection, solve, integration;
    /// normalised here, all to solve if they are not positive).
    pub fn stop_split(&mut self, s: Started, fractions: [f64; 3]) {
        if let Some(dt) = self.sampler.end(MIXED, s) {
            let sum: f64 = fractions.iter().sum();
            if sum > 0.0 && fractions.iter().all(|f| *f >= 0.0) {
                self.times.detection += dt * fractions[0] / sum;
                self.times.solve += dt * fractions[1] / sum;
                self.times.integration += dt * fractions[2] / sum;
            } else {
                self.times.solve += dt;
            }
            self.charged += dt;
        }
    }

    /// Estimated monotonic seconds per stage so far.
    pub fn monotonic_times(&self) -> StageTimes {
        self.times
    }

    /// Monotonic seconds since the clock was made.
    pub fn monotonic_elapsed(&mut self) -> f64 {
        self.reads += 1;
        self.born.elapsed().as_secs_f64()
    }

    /// Monotonic clock reads so far.
    pub fn reads(&self) -> u64 {
        self.reads + self.sampler.reads()
    }

    /// Regions that were not timed (counted, not read).
    pub fn untimed(&self) -> u64 {
        self.sampler.untimed()
    }

    /// The CPU time of each stage: `cpu_total` (s, thread CPU time over the
    /// `elapsed` monotonic seconds the clock ran) split in the proportions of
    /// the stages' monotonic times.
    pub fn split(&self, cpu_total: f64, elapsed: f64) -> StageTimes {
        if !(elapsed > 0.0 && cpu_total.is_finite()) {
            return StageTimes::default();
        }
        let f = cpu_total / elapsed.max(self.times.total());
        StageTimes {
            detection: self.times.detection * f,
            solve: self.times.solve * f,
            integration: self.times.integration * f,
            lattice: self.times.lattice * f,
            crushing: self.times.crushing * f,
        }
    }

    /// The CPU time the stage clock itself cost, s.
    pub fn overhead(&self) -> f64 {
        self.reads as f64 * monotonic_read_cost() + self.sampler.overhead()
    }
}

impl Started {
    /// Whether this region is timed (its split is used).
    pub fn is_timed(&self) -> bool {
        self.at.is_some()
    }
}

/// CPU cost of one region that is not timed (the draw and the counting), s:
/// measured once per process on 100,000 such regions.
pub fn untimed_region_cost() -> f64 {
    static COST: OnceLock<f64> = OnceLock::new();
    *COST.get_or_init(|| {
        const N: u64 = 100_000;
        let mut c = StageClock::new();
        // Past the warm-up, with a cheap mean: regions are drawn.
        c.sampler.kinds[0] = Kind {
            timed: WARM_UP,
            mean: 0.0,
            skip: 0,
        };
        let c0 = thread_cpu_seconds();
        for _ in 0..N {
            c.time(Stage::Detection, || std::hint::black_box(0u8));
        }
        let spent = thread_cpu_seconds() - c0;
        // Remove the timed ones (about 1 in 64) at the cost of their reads.
        let timed = c.sampler.reads() as f64 * monotonic_read_cost();
        ((spent - timed) / c.untimed().max(1) as f64).max(0.0)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Busy for at least `s` seconds of monotonic time.
    fn busy(s: f64) {
        let t0 = Instant::now();
        let mut x = 0u64;
        while t0.elapsed().as_secs_f64() < s {
            x = std::hint::black_box(x.wrapping_add(1));
        }
    }

    /// A clock whose solve stage is a cheap kind past its warm-up, and a
    /// sampler (the contact solver's) whose kind 0 is timed whole.
    fn cheap_solve_stage() -> (StageClock, Sampler) {
        let mut clock = StageClock::new();
        clock.sampler.kinds[index(Stage::Solve)] = Kind {
            timed: 10,
            mean: 1e-7,
            skip: 0,
        };
        (clock, Sampler::new(1))
    }

    #[test]
    fn a_dear_region_inside_an_untimed_call_is_charged_to_its_stage() {
        let (mut clock, mut inner) = cheap_solve_stage();
        // The next call of the stage is not timed.
        clock.sampler.kinds[index(Stage::Solve)].skip = 5;
        let mut measured = 0.0;
        clock.time(Stage::Solve, || {
            let s = inner.begin(0);
            busy(0.02);
            measured = inner.end(0, s).unwrap_or(0.0);
        });
        assert!(measured >= 0.02, "{measured}");
        let solve = clock.monotonic_times().solve;
        assert!(
            (solve - measured).abs() <= 1e-12,
            "untimed call: its inner dear region alone ({solve} vs {measured})"
        );
        // An untimed call with nothing timed inside charges nothing.
        clock.time(Stage::Solve, || busy(1e-4));
        assert_eq!(clock.monotonic_times().solve, solve);
    }

    #[test]
    fn a_dear_region_inside_a_drawn_call_counts_once_and_unweighted() {
        let (mut clock, mut inner) = cheap_solve_stage();
        let mut measured = 0.0;
        let s = clock.start(Stage::Solve);
        assert!(s.is_timed() && s.weight > 1.0, "a drawn call");
        let i = inner.begin(0);
        busy(0.1);
        measured += inner.end(0, i).unwrap_or(0.0);
        clock.stop(Stage::Solve, s);
        let solve = clock.monotonic_times().solve;
        // Its own time (outside the inner region) is capped at the floor
        // before the weight; the inner region counts once (longer than the
        // cap times the weight: capped with the call, it would be lost).
        let cap = OUTLIER_FLOOR / SAMPLE_PROBABILITY;
        assert!(
            solve >= measured && solve <= measured + cap,
            "{solve} vs {measured}"
        );
    }

    #[test]
    fn a_lattice_region_nested_in_a_solve_is_charged_to_its_own_stage() {
        let mut clock = StageClock::new();
        let s = clock.start(Stage::Solve);
        busy(0.01);
        let l = clock.start(Stage::Lattice);
        busy(0.02);
        clock.stop(Stage::Lattice, l);
        clock.stop(Stage::Solve, s);
        let t = clock.monotonic_times();
        // Both first regions of their kinds, timed whole: the lattice its
        // own 0.02 s, the solve its 0.01 s without the lattice's.
        assert!(t.lattice >= 0.02, "{t:?}");
        assert!(t.solve >= 0.01 && t.solve < 0.02, "{t:?}");
        let split = clock.split(1.0, t.total());
        assert!((split.total() - 1.0).abs() <= 1e-12, "{split:?}");
    }

    #[test]
    fn nested_regions_timed_whole_count_once_in_what_encloses_them() {
        let mut outer = Sampler::new(1);
        let mut middle = Sampler::new(1);
        let mut inner = Sampler::new(1);
        let before = measured_inside();
        let o = outer.begin(0);
        let m = middle.begin(0);
        let i = inner.begin(0);
        busy(0.01);
        let ti = inner.end(0, i).unwrap_or(0.0);
        busy(0.01);
        let tm = middle.end(0, m).unwrap_or(0.0);
        let to = outer.end(0, o).unwrap_or(0.0);
        assert!(ti >= 0.01 && tm >= ti + 0.01 && to >= tm, "{ti} {tm} {to}");
        // Each first region of a kind is timed whole: the thread's total grew
        // by the outermost one's duration, not by the sum of the three.
        assert!((measured_inside() - before - to).abs() <= 1e-12);
    }
}
