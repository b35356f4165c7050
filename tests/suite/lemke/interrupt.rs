//! A stop request (SIGINT, SIGTERM: `floebench::stop`) inside a long
//! solve: Lemke's path and the driver end at once with a finite answer,
//! marked interrupted (not failed), and an uninterrupted solve is the
//! same to the bit.

use super::diag_dominant;
use floebench::lcp::{solve, Lcp, SolveOptions, SolveStatus, Termination};
use floebench::rng::SplitMix64;
use floebench::stop::{self, Interrupt};
use std::time::{Duration, Instant};

/// A dense P-matrix LCP whose solution has every unknown positive (`q < 0`
/// on a diagonally dominant M): a path of about `n` pivots.
fn long_lcp(n: usize) -> Lcp {
    let mut rng = SplitMix64::new(0x5EED_570B);
    let m = diag_dominant(&mut rng, n);
    let q = (0..n).map(|_| -1.0 - rng.uniform()).collect();
    Lcp::new(n, m, q).unwrap()
}

#[test]
fn a_stop_asked_before_a_solve_ends_it_within_a_poll() {
    let lcp = long_lcp(400);
    let handle = Interrupt::own();
    handle.request();
    let _current = stop::current(&handle);
    let sol = solve(&lcp, &SolveOptions::default());
    assert_eq!(sol.status, SolveStatus::Interrupted);
    assert!(!sol.status.is_solved());
    assert_eq!(sol.attempts.len(), 1, "no fallback after a stop");
    assert_eq!(sol.attempts[0].termination, Termination::Interrupted);
    assert!(
        sol.pivots as u64 <= stop::POLL_EVERY,
        "{} pivots",
        sol.pivots
    );
    assert!(sol.z.iter().chain(&sol.w).all(|x| x.is_finite()));
    assert!(sol.residual.is_finite());
}

#[test]
fn a_stop_asked_during_a_long_solve_ends_it_promptly_and_others_are_unchanged() {
    let lcp = long_lcp(500);
    let opts = SolveOptions::default();
    // Uninterrupted (a handle of its own, never set): solved.
    let quiet = Interrupt::own();
    let started = Instant::now();
    let full = {
        let _current = stop::current(&quiet);
        solve(&lcp, &opts)
    };
    let t_full = started.elapsed();
    assert!(full.status.is_solved(), "{:?}", full.status);
    assert!(full.pivots > 300, "a long path: {} pivots", full.pivots);
    // The same solve under the process's handle (no signal): bit-identical.
    let again = solve(&lcp, &opts);
    assert_eq!(again.z, full.z);
    assert_eq!(again.pivots, full.pivots);
    // Stopped a tenth of the way in, from another thread.
    let handle = Interrupt::own();
    let setter = {
        let h = handle.clone();
        let wait = t_full / 10;
        std::thread::spawn(move || {
            std::thread::sleep(wait);
            h.request();
        })
    };
    let started = Instant::now();
    let cut = {
        let _current = stop::current(&handle);
        solve(&lcp, &opts)
    };
    let t_cut = started.elapsed();
    setter.join().unwrap();
    assert_eq!(cut.status, SolveStatus::Interrupted);
    assert!(
        cut.pivots < full.pivots,
        "{} of {}",
        cut.pivots,
        full.pivots
    );
    assert!(cut.z.iter().all(|x| x.is_finite()));
    assert!(
        t_cut < t_full / 2 + Duration::from_millis(20),
        "stopped after {t_cut:?} of {t_full:?}"
    );
    println!(
        "n = {}: full solve {t_full:?} ({} pivots), stopped after {t_cut:?} ({} pivots)",
        lcp.n, full.pivots, cut.pivots
    );
}
