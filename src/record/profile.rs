//! Where a run's contact-problem time goes: LCP solves by size.
//!
//! One row per size bucket of the LCP (unknowns 1–8, 9–40, 41–200, 201–800,
//! over 800): solves, pivots, which attempt solved them, and the monotonic
//! time of the solves (estimated by the same sampling timer as the stages,
//! [`crate::record::clock::Sampler`]), in `summary.json` as `lcp_profile`.

use serde::Serialize;

/// Upper bounds (unknowns, inclusive) of the size buckets; the last bucket
/// has no bound.
pub const BUCKET_BOUNDS: [usize; 4] = [8, 40, 200, 800];

/// The bucket of an LCP with `n` unknowns.
pub fn bucket_of(n: usize) -> usize {
    BUCKET_BOUNDS
        .iter()
        .position(|&b| n <= b)
        .unwrap_or(BUCKET_BOUNDS.len())
}

/// The LCP solves of one size bucket.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct SizeBucket {
    /// Smallest number of unknowns of the bucket.
    pub unknowns_min: usize,
    /// Largest number of unknowns of the bucket (`None`: no bound).
    pub unknowns_max: Option<usize>,
    /// LCPs solved.
    pub solves: u64,
    /// Lemke pivots over every attempt.
    pub pivots: u64,
    /// Unknowns, summed over the solves.
    pub unknowns: u64,
    /// The fewest pivots of a cold Lemke path to each accepted solution
    /// ([`crate::lcp::min_cold_pivots`]: 1 + the size of its support),
    /// summed over the cold solves that were solved;
    /// `bounded_pivots / min_pivots` is how much longer their paths were
    /// than the shortest possible (a solve warm-started, predicted or
    /// failed adds its pivots to `pivots` only).
    pub min_pivots: u64,
    /// Pivots of the solves counted in `min_pivots`.
    pub bounded_pivots: u64,
    /// Solved by the first attempt.
    pub first_attempt: u64,
    /// Solved by a fallback attempt.
    pub fallback: u64,
    /// Not solved by any attempt (the caller's last resort followed).
    pub failed: u64,
    /// Monotonic time of the solves, s (estimated: see the module doc).
    pub seconds: f64,
    /// Solves that had a guessed basis (warm start on; absent when 0).
    #[serde(skip_serializing_if = "is_zero")]
    pub warm_tried: u64,
    /// Of them, solved by its principal pivoting (0 pivots).
    #[serde(skip_serializing_if = "is_zero")]
    pub warm_hits: u64,
    /// Of them, solved by the warm Lemke path.
    #[serde(skip_serializing_if = "is_zero")]
    pub warm_lemke_hits: u64,
    /// Pivots of the warm Lemke paths (included in `pivots`).
    #[serde(skip_serializing_if = "is_zero")]
    pub warm_lemke_pivots: u64,
    /// Unknowns whose side differs between the guessed basis and the
    /// accepted solution's support, summed over the solved warm-started
    /// solves: how far the guess was.
    #[serde(skip_serializing_if = "is_zero")]
    pub warm_support_changes: u64,
}

fn is_zero(x: &u64) -> bool {
    *x == 0
}

/// The LCP solves of a run by size.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SolveProfile {
    /// One row per bucket, smallest first.
    pub buckets: Vec<SizeBucket>,
    /// CPU time the profile's timer cost, s (included in the run's).
    pub timer_overhead: f64,
}

impl Default for SolveProfile {
    fn default() -> Self {
        let mut lo = 1;
        let mut buckets = Vec::new();
        for hi in BUCKET_BOUNDS.iter().map(|&b| Some(b)).chain([None]) {
            buckets.push(SizeBucket {
                unknowns_min: lo,
                unknowns_max: hi,
                ..SizeBucket::default()
            });
            lo = hi.map_or(lo, |h| h + 1);
        }
        SolveProfile {
            buckets,
            timer_overhead: 0.0,
        }
    }
}
