//! Clean ends on SIGINT (Ctrl-C) and SIGTERM.
//!
//! [`install`] (called once by the command line, never by the library on its
//! own) makes the first SIGINT or SIGTERM set a flag instead of killing the
//! process. The flag is the process's [`Interrupt`] handle, which a run
//! gets in its [`super::RunOptions`] (the default): the runner polls it at
//! each output time, and the formulations at each step of their own grid
//! ([`crate::formulation::Context::poll_interrupt`]), and the long loops
//! inside a step (Lemke's pivots, iterative solvers, percussions) through
//! the run's handle made current on its thread ([`crate::stop`]); a
//! program that embeds
//! runs can give each its own handle ([`Interrupt::own`]). An interrupted run ends with
//! [`super::EndReason::Interrupted`], its outputs written up to its last
//! output time, and the batch runner starts no new run. A second signal has
//! the default effect (the process ends at once), so a step that takes long
//! can still be stopped.
//!
//! The handler only stores to an atomic flag, which is async-signal-safe.

use crate::stop::Interrupt;

extern "C" fn on_signal(_signal: libc::c_int) {
    Interrupt::Process.request();
}

/// Installs the handler of SIGINT and SIGTERM (see the module doc). The
/// error is the OS's, for a message; the process then keeps the default
/// behaviour.
pub fn install() -> Result<(), std::io::Error> {
    for signal in [libc::SIGINT, libc::SIGTERM] {
        // SAFETY: `sigaction` is given a zeroed, then filled, struct and a
        // handler that only stores to an atomic; SA_RESETHAND restores the
        // default action after the first delivery.
        let rc = unsafe {
            let mut action: libc::sigaction = std::mem::zeroed();
            action.sa_sigaction = on_signal as *const () as libc::sighandler_t;
            action.sa_flags = libc::SA_RESETHAND | libc::SA_RESTART;
            libc::sigemptyset(&mut action.sa_mask);
            libc::sigaction(signal, &action, std::ptr::null_mut())
        };
        if rc != 0 {
            return Err(std::io::Error::last_os_error());
        }
    }
    Ok(())
}

/// Whether an interrupt was asked for (a signal, or [`request`]).
pub fn requested() -> bool {
    Interrupt::Process.requested()
}

/// Asks every run of this process to stop at its next output time, as a
/// signal would (for embedding programs and tests).
pub fn request() {
    Interrupt::Process.request();
}
