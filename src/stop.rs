//! The stop request (SIGINT, SIGTERM, or a program's own), polled by the
//! runner, the formulations' step loops and, inside one step, the long
//! computations: Lemke's pivots, NSGS and APGD iterations, the lattice and
//! chain percussions.
//!
//! A run's handle is an [`Interrupt`]: the process's (set by the signal
//! handler of [`crate::run::interrupt`]) or one of its own. The runner
//! makes it the thread's *current* handle for the run ([`current`], a guard
//! that restores the earlier one), so that the solvers, which are given no
//! handle, poll [`requested`]: the current handle's request (the process's
//! when none is set). A poll is an access to a thread-local and an atomic
//! load; the loops poll every [`POLL_EVERY`] pivots, sweeps or steps, so an
//! uninterrupted solve does the same arithmetic as without polls (its
//! results are bit-identical) and a stop is seen within milliseconds.
//!
//! A solve that sees the request stops early with a finite answer and says
//! so (`Termination::Interrupted`, `SolveStatus::Interrupted`, an iterative
//! outcome's `interrupted`, a percussion's `Stop::Interrupted`); the runner
//! then discards the step that held it and ends the run at its last output
//! time, so no interrupted answer reaches an output.

use std::cell::RefCell;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;

/// The pivots, sweeps or steps between two polls of [`requested`] in the
/// long loops: a poll costs a few nanoseconds, a pivot of a problem that
/// can run long (hundreds of unknowns) microseconds or more.
pub const POLL_EVERY: u64 = 32;

/// The process-wide flag that SIGINT and SIGTERM set
/// ([`crate::run::interrupt::install`]).
static PROCESS: AtomicBool = AtomicBool::new(false);

/// A handle on a stop request: the process's (set by a signal) or one of
/// its own (for embedding programs and tests). The runner polls it at each
/// output time, formulations at each step of their own grid, and the
/// solvers inside a step through [`requested`].
#[derive(Debug, Clone, Default)]
pub enum Interrupt {
    /// The process-wide request: a signal, or [`Interrupt::request`] on any
    /// handle of the process.
    #[default]
    Process,
    /// A request of its own, shared by the clones of the handle.
    Own(Arc<AtomicBool>),
}

impl Interrupt {
    /// A handle of its own, not set by signals.
    pub fn own() -> Interrupt {
        Interrupt::Own(Arc::new(AtomicBool::new(false)))
    }

    /// Whether a stop was asked for.
    pub fn requested(&self) -> bool {
        match self {
            Interrupt::Process => PROCESS.load(Ordering::SeqCst),
            Interrupt::Own(flag) => flag.load(Ordering::SeqCst),
        }
    }

    /// Asks the runs polling this handle to stop.
    pub fn request(&self) {
        match self {
            Interrupt::Process => PROCESS.store(true, Ordering::SeqCst),
            Interrupt::Own(flag) => flag.store(true, Ordering::SeqCst),
        }
    }
}

thread_local! {
    /// The handle the solvers of this thread poll (`None`: the process's).
    static CURRENT: RefCell<Option<Interrupt>> = const { RefCell::new(None) };
}

/// Whether the current handle of this thread ([`current`]; the process's
/// when none is set) asks to stop: what the long loops poll.
pub fn requested() -> bool {
    CURRENT.with(|c| match &*c.borrow() {
        Some(h) => h.requested(),
        None => PROCESS.load(Ordering::SeqCst),
    })
}

/// [`requested`], polled only on every [`POLL_EVERY`]-th count `k` (the
/// loops' pivot, sweep or step count), so that a loop pays one poll per
/// [`POLL_EVERY`] rounds.
pub fn poll(k: u64) -> bool {
    k.is_multiple_of(POLL_EVERY) && requested()
}

/// The guard of [`current`]: restores the thread's earlier handle when
/// dropped.
#[must_use = "the handle is current only while the guard lives"]
pub struct Current {
    earlier: Option<Interrupt>,
}

impl Drop for Current {
    fn drop(&mut self) {
        let earlier = self.earlier.take();
        CURRENT.with(|c| *c.borrow_mut() = earlier);
    }
}

/// Makes `handle` the handle this thread's solvers poll ([`requested`])
/// while the returned guard lives (the runner, for the time of a run).
pub fn current(handle: &Interrupt) -> Current {
    let earlier = CURRENT.with(|c| c.borrow_mut().replace(handle.clone()));
    Current { earlier }
}
