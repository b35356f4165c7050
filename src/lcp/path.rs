//! The Lemke path, independent of how the basis is represented.
//!
//! Lemke's method (Cottle–Pang–Stone 1992, Alg. 4.4.5) only ever needs, at
//! each pivot, the entering column `c = B⁻¹ a_s`, the basic values
//! `b = B⁻¹ q`, for the lexicographic rule (CPS §4.9) some entries of the
//! rows of `B⁻¹` of the rows tied in the ratio test, and the exchange of one
//! basic variable. [`Basis`] is that interface; [`run`] is the method
//! written once over it: the first pivot on `z0`, the ratio test with its
//! pivot tolerance, the negligible-`z0` exit, the tie-breaking rules and the
//! termination tests documented in [`super::lemke`]. Two representations
//! implement it:
//!
//! * the dense condensed tableau of [`super::lemke::Workspace`] (every entry
//!   of `B⁻¹ [I | −M | −d | q]` stored and updated by an exchange step, O(n²)
//!   per pivot);
//! * the factorised (revised) basis of [`super::revised`] (a sparse LU of
//!   the basis and a product of eta matrices, O(nnz) per pivot on the
//!   block-sparse Delassus matrices of large contact groups).
//!
//! Given the same data both make the same choices up to rounding: the
//! entries they compare are the same numbers, computed in a different order.

use super::lemke_options::{LemkeOptions, PivotRule, Termination};

/// Sentinel for "no row" / "no column".
pub(crate) const NONE: usize = usize::MAX;

/// Largest infeasibility (scaled units) that the negligible-`z0` exit may
/// leave in a basic variable: about 500 ulps of the initial `z0`, so that
/// the exit does not trade a pivot or two for a residual near the driver's
/// tolerance.
const Z0_EXIT_VIOLATION: f64 = 1e-13;

/// A basis of the augmented system `w − M z − d z0 = q` (variables `0..n`
/// for `w`, `n..2n` for `z`, `2n` for `z0`), scaled as described in
/// [`super::lemke`], as seen by the pivoting rules of [`run`].
pub(crate) trait Basis {
    /// Dimension n.
    fn n(&self) -> usize;
    /// The variable basic in row `i`.
    fn basic(&self, i: usize) -> usize;
    /// The row of variable `v`, or [`NONE`] if it is non-basic.
    fn row_of(&self, v: usize) -> usize;
    /// Makes `v` (non-basic) the entering variable: afterwards [`Basis::c`]
    /// reads its column `B⁻¹ a_v`. `false` if a non-finite entry appeared.
    fn load(&mut self, v: usize) -> bool;
    /// Entry `i` of the loaded entering column.
    fn c(&self, i: usize) -> f64;
    /// `max |c_i|` over the loaded column: the scale of the ratio test.
    /// The default compares the entries one by one (a NaN is skipped); a
    /// representation that computes the column at load, and refuses it
    /// there if an entry is not finite, takes the maximum in the same pass.
    fn c_max(&self) -> f64 {
        let mut cmax = 0.0_f64;
        for i in 0..self.n() {
            let a = self.c(i).abs();
            if a > cmax {
                cmax = a;
            }
        }
        cmax
    }
    /// Basic value of row `i` (`(B⁻¹ q)_i`).
    fn b(&self, i: usize) -> f64;
    /// Prepares [`Basis::binv`] for the rows in `rows`; `false` if it could
    /// not (non-finite entries).
    fn prepare_rows(&mut self, rows: &[usize]) -> bool;
    /// `(B⁻¹ a_v)_i` for a row `i` given to [`Basis::prepare_rows`] and a
    /// non-basic variable `v` (`a_v` its column of `[I | −M | −d]`): for
    /// `v = w_k`, the entry `(B⁻¹)_{ik}`.
    fn binv(&self, i: usize, v: usize) -> f64;
    /// The variable of column `k` of the reference basis `B_s` of the
    /// lexicographic rule, which compares the rows of `B⁻¹ B_s`: the basis
    /// the path started from. `w_k` (the default) for a path started at
    /// `B = I`; `w_k` or `z_k` for a path started from a guessed
    /// complementary basis (see [`run`]).
    fn reference(&self, k: usize) -> usize {
        k
    }
    /// Exchanges the basic variable of row `r` for the loaded entering
    /// variable; `false` if a non-finite entry appeared or the new basis
    /// could not be factorised.
    fn pivot(&mut self, r: usize) -> bool;
    /// Pivots performed since the set-up.
    fn pivots(&self) -> usize;
}

/// Result of the ratio test.
enum Step {
    Pivot(usize),
    Ray,
    TooSmall,
}

/// Runs Lemke's method from the complementary basis set up in `e`; `cand`
/// is scratch. Returns the termination and a failure detail.
///
/// The basis is `B = I` (every `w` basic) for the classical method, or a
/// guessed complementary basis `B_s` (`z_i` basic for `i` in a set `α`,
/// `w_i` for the others) with the covering column `d = B_s 1`, so that the
/// loaded column of `z0` is `B_s⁻¹(−d) = −1` (see [`super::revised`]). The
/// latter is the classical method on the principal pivot transform of the
/// LCP on `α`: its basic values `B_s⁻¹ q` are the transformed `q`, and the
/// lexicographic rule compares the rows of `B⁻¹ B_s` ([`Basis::reference`]),
/// which are those of the transformed problem's `B⁻¹`. If the basic values
/// are already non-negative the basis solves the LCP: 0 pivots.
pub(crate) fn run<B: Basis>(
    e: &mut B,
    cand: &mut Vec<usize>,
    opts: &LemkeOptions,
    max_pivots: usize,
) -> (Termination, Option<&'static str>) {
    let n = e.n();
    if (0..n).all(|i| e.b(i) >= 0.0) {
        return (Termination::Solved, None);
    }
    if max_pivots == 0 {
        return (Termination::MaxPivots, Some("pivot cap is 0"));
    }
    let z0 = 2 * n;
    // First pivot: z0 enters; the leaving row minimises b_i / (B⁻¹d)_i
    // (q_i / d_i from B = I; lexicographically for the lexicographic
    // rule), which makes every right-hand side non-negative.
    if !e.load(z0) {
        return (
            Termination::NumericalFailure,
            Some("non-finite tableau entry"),
        );
    }
    cand.clear();
    cand.extend(0..n);
    let Some(r) = select(e, cand, -1.0, opts, false) else {
        return (Termination::NumericalFailure, Some("no initial pivot row"));
    };
    let mut leaving = e.basic(r);
    if !e.pivot(r) {
        return (
            Termination::NumericalFailure,
            Some("non-finite tableau entry"),
        );
    }
    loop {
        if leaving == z0 {
            return (Termination::Solved, None);
        }
        let entering = if leaving < n {
            leaving + n
        } else {
            leaving - n
        };
        if e.pivots() >= max_pivots {
            return (Termination::MaxPivots, Some("pivot cap reached"));
        }
        // Polled at every pivot of a large problem (a pivot costs O(n²)
        // there, the poll nanoseconds), every POLL_EVERY of a small one.
        if (n >= POLL_EACH_PIVOT_FROM || crate::stop::poll(e.pivots() as u64))
            && crate::stop::requested()
        {
            return (Termination::Interrupted, Some("a stop was asked for"));
        }
        if !e.load(entering) {
            return (
                Termination::NumericalFailure,
                Some("non-finite tableau entry"),
            );
        }
        let r = match ratio_test(e, cand, opts) {
            Step::Pivot(r) => r,
            Step::Ray => {
                if z0_negligible(e, opts) {
                    return (Termination::Solved, None);
                }
                return (
                    Termination::RayTermination,
                    Some("secondary ray: entering column has no positive entry"),
                );
            }
            Step::TooSmall => {
                if z0_negligible(e, opts) {
                    return (Termination::Solved, None);
                }
                return (
                    Termination::NumericalFailure,
                    Some("pivot too small: blocking entries below the pivot tolerance"),
                );
            }
        };
        leaving = e.basic(r);
        if !e.pivot(r) {
            return (
                Termination::NumericalFailure,
                Some("non-finite tableau entry"),
            );
        }
    }
}

/// The size from which Lemke's path polls the stop request
/// ([`crate::stop`]) at every pivot rather than every
/// [`crate::stop::POLL_EVERY`]: a pivot of 64 unknowns costs some 10⁴
/// operations, a poll a few nanoseconds.
const POLL_EACH_PIVOT_FROM: usize = 64;

/// `true` if `z0` is basic with a value at or below `z0_tol`.
fn z0_negligible<B: Basis>(e: &B, opts: &LemkeOptions) -> bool {
    let r0 = e.row_of(2 * e.n());
    opts.prefer_z0 && r0 != NONE && e.b(r0) <= opts.z0_tol
}

/// Minimum-ratio test on the loaded entering column.
fn ratio_test<B: Basis>(e: &mut B, cand: &mut Vec<usize>, opts: &LemkeOptions) -> Step {
    let n = e.n();
    let scale = e.c_max().max(1.0);
    let thresh = opts.pivot_tol * scale;
    let noise = opts.pivot_tol * 1e-3 * scale;
    // The smallest ratio, its row and the smallest ratio of the other
    // rows: when that is beyond the tie tolerance the minimiser is the only
    // candidate, and the ratios need not be computed again to list ties.
    let mut least = Least::default();
    let mut small = false;
    for i in 0..n {
        let c = e.c(i);
        if c > thresh {
            least.add_ratio(i, e.b(i), c);
        } else if c > noise {
            small = true;
        }
    }
    let Least { min, arg, second } = least;
    if min == f64::INFINITY {
        return if small { Step::TooSmall } else { Step::Ray };
    }
    // z0 would become negligible with this step: let it leave.
    let r0 = e.row_of(2 * n);
    if opts.prefer_z0 && r0 != NONE && opts.z0_tol > 0.0 {
        let c0 = e.c(r0);
        if c0 > thresh {
            let b0 = e.b(r0);
            let after = b0 - c0 * min;
            if after <= opts.z0_tol * c0 / scale && z0_exit_feasible(e, b0 / c0) {
                return Step::Pivot(r0);
            }
        }
    }
    if opts.rule == PivotRule::Harris {
        let r = harris(e, thresh, r0, opts.prefer_z0);
        return if r == NONE {
            Step::TooSmall
        } else {
            Step::Pivot(r)
        };
    }
    cand.clear();
    let tol = opts.tie_tol * min.abs();
    if second > min + tol {
        return Step::Pivot(arg);
    }
    for i in 0..n {
        let c = e.c(i);
        if c > thresh && e.b(i).max(0.0) / c <= min + tol {
            cand.push(i);
        }
    }
    match select_among_ties(e, cand, 1.0, opts, opts.prefer_z0) {
        Some(r) => Step::Pivot(r),
        None => Step::TooSmall,
    }
}

/// The second pass of [`PivotRule::Harris`]: among the rows whose ratio is
/// within the bound of the first pass, the largest blocking entry (`z0`'s
/// row if it is among them and `prefer_z0`). At least one row blocks (the
/// caller found a finite minimum ratio), and the minimiser is within the
/// bound, so a row is returned ([`NONE`] only if rounding defeated that).
fn harris<B: Basis>(e: &B, thresh: f64, r0: usize, prefer_z0: bool) -> usize {
    let n = e.n();
    let delta = super::lemke_options::HARRIS_FEASIBILITY;
    let mut bound = f64::INFINITY;
    for i in 0..n {
        let c = e.c(i);
        if c > thresh {
            bound = bound.min((e.b(i).max(0.0) + delta) / c);
        }
    }
    let (mut best, mut best_c) = (NONE, 0.0_f64);
    for i in 0..n {
        let c = e.c(i);
        if c > thresh && e.b(i).max(0.0) / c <= bound {
            if prefer_z0 && i == r0 {
                return i;
            }
            if c > best_c {
                (best, best_c) = (i, c);
            }
        }
    }
    best
}

/// Whether the step `theta` on the loaded column (the one that makes `z0`
/// leave) keeps every basic variable above `−Z0_EXIT_VIOLATION`, so that
/// the complementary basis it reaches is feasible up to rounding.
fn z0_exit_feasible<B: Basis>(e: &B, theta: f64) -> bool {
    (0..e.n()).all(|i| {
        let c = e.c(i);
        c <= 0.0 || e.b(i) - c * theta >= -Z0_EXIT_VIOLATION
    })
}

/// Chooses the leaving row among all rows of `cand` by the minimum ratio
/// `b_i / (sign · c_i)` (every divisor positive) and the tie-break.
fn select<B: Basis>(
    e: &mut B,
    cand: &mut Vec<usize>,
    sign: f64,
    opts: &LemkeOptions,
    prefer_z0: bool,
) -> Option<usize> {
    filter_min(cand, |i| e.b(i) / (sign * e.c(i)), opts.tie_tol, 0.0);
    select_among_ties(e, cand, sign, opts, prefer_z0)
}

/// The leaving row among the tied rows in `cand` (divisors `sign · c_i`).
fn select_among_ties<B: Basis>(
    e: &mut B,
    cand: &mut Vec<usize>,
    sign: f64,
    opts: &LemkeOptions,
    prefer_z0: bool,
) -> Option<usize> {
    if cand.len() <= 1 {
        return cand.first().copied();
    }
    let n = e.n();
    if prefer_z0 {
        let r0 = e.row_of(2 * n);
        if r0 != NONE && cand.contains(&r0) {
            return Some(r0);
        }
    }
    match opts.rule {
        PivotRule::Lexicographic => {
            if !e.prepare_rows(cand) {
                return None;
            }
            for k in 0..n {
                if cand.len() <= 1 {
                    break;
                }
                let v = e.reference(k);
                let rk = e.row_of(v);
                if rk != NONE {
                    // v basic in row rk: column k of B⁻¹ B_s is the unit
                    // vector of that row, whose ratio 1/c is positive,
                    // every other candidate's is 0.
                    cand.retain(|&i| i != rk);
                } else {
                    filter_min(
                        cand,
                        |i| e.binv(i, v) / (sign * e.c(i)),
                        opts.lex_tol,
                        opts.lex_tol,
                    );
                }
            }
            if cand.len() == 1 {
                cand.first().copied()
            } else {
                // Only reachable through rounding (rows of B⁻¹ are
                // independent): take the most stable pivot.
                largest_pivot(cand, |i| sign * e.c(i))
            }
        }
        PivotRule::MinRatioSmallestIndex => cand.iter().copied().min_by_key(|&i| e.basic(i)),
        PivotRule::MinRatioLargestPivot | PivotRule::Harris => {
            largest_pivot(cand, |i| sign * e.c(i))
        }
    }
}

/// Keeps the entries of `cand` whose `key` is at most
/// `min + rel_tol · |min| + abs_tol`.
///
/// The smallest key of the other entries is tracked with the minimum: when
/// it is beyond the tolerance (the usual case, no tie) the minimiser alone
/// is kept without computing the keys a second time.
fn filter_min(cand: &mut Vec<usize>, key: impl Fn(usize) -> f64, rel_tol: f64, abs_tol: f64) {
    let mut least = Least::default();
    for &i in cand.iter() {
        least.add(i, key(i));
    }
    let Least { min, arg, second } = least;
    if !min.is_finite() {
        return;
    }
    let tol = rel_tol * min.abs() + abs_tol;
    if second > min + tol {
        cand.clear();
        cand.push(arg);
        return;
    }
    cand.retain(|&i| key(i) <= min + tol);
}

/// The smallest of a stream of keys, its index, and the smallest key of the
/// other indices (NaN keys are skipped: a comparison with NaN is false).
struct Least {
    min: f64,
    arg: usize,
    second: f64,
}

impl Default for Least {
    fn default() -> Self {
        Self {
            min: f64::INFINITY,
            arg: NONE,
            second: f64::INFINITY,
        }
    }
}

/// `1 + 2⁻⁵¹`: with it, `b ≥ fl(fl(s·c)·SKIP_MARGIN)` implies `b ≥ s·c`
/// exactly when `fl(s·c)` is a normal number (two roundings of relative
/// error at most `2⁻⁵³` each: `(1 − 2⁻⁵³)²(1 + 2⁻⁵¹) ≥ 1`).
const SKIP_MARGIN: f64 = 1.0 + 2.0 * f64::EPSILON;

impl Least {
    /// [`Least::add`] of the ratio `max(b, 0) / c` (`c > 0` finite), without
    /// the division when the ratio cannot change anything: when `b > 0` and
    /// the ratio is at least the current second smallest key `s`, which
    /// holds if `s = 0` or if `b ≥ s·c` exactly (then `b / c ≥ s` and its
    /// rounding too, `s` being a float). The test of the latter is
    /// conservative ([`SKIP_MARGIN`]); a skipped ratio would have left the
    /// three fields as they are, so the result is the same, bit for bit,
    /// with one division for the few rows that can still matter instead of
    /// one per row (the division's latency was a fifth of the ratio test).
    #[inline(always)]
    fn add_ratio(&mut self, i: usize, b: f64, c: f64) {
        if b > 0.0 {
            let s = self.second;
            let t = s * c;
            if s == 0.0 || (t >= f64::MIN_POSITIVE && b >= t * SKIP_MARGIN) {
                return;
            }
            self.add(i, b / c);
        } else {
            // `max(b, 0) / c` is 0 (also for a NaN `b`); its sign, which
            // `max` leaves unspecified for `b = −0`, changes no comparison
            // or sum the ratio test makes with the minimum.
            self.add(i, 0.0);
        }
    }

    #[inline(always)]
    fn add(&mut self, i: usize, v: f64) {
        if v < self.min {
            self.second = self.min;
            self.min = v;
            self.arg = i;
        } else if v < self.second {
            self.second = v;
        }
    }
}

fn largest_pivot(rows: &[usize], c: impl Fn(usize) -> f64) -> Option<usize> {
    let mut best: Option<(usize, f64)> = None;
    for &i in rows {
        let ci = c(i);
        match best {
            Some((_, bc)) if bc >= ci => {}
            _ => best = Some((i, ci)),
        }
    }
    best.map(|(i, _)| i)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn uniform(state: &mut u64) -> f64 {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    /// `add_ratio` keeps the same minimum, index and second key as `add` of
    /// the divided ratio, bit for bit, on streams whose ratios sit within a
    /// few ulps of the running second key (where a skip that is not
    /// conservative would show), with zeros, negatives, NaN and entries of
    /// six binades. (Checked to fail with a margin of 1.)
    #[test]
    fn skipping_a_division_keeps_the_least_ratios_bit_for_bit() {
        let mut state = 7_u64;
        let mut near = 0usize;
        for _ in 0..2_000 {
            let (mut fast, mut plain) = (Least::default(), Least::default());
            for i in 0..40 {
                let c = (0.5 + uniform(&mut state)) * 10f64.powi((i % 6) as i32 - 3);
                let pick = uniform(&mut state);
                let b = if pick < 0.1 {
                    0.0
                } else if pick < 0.15 {
                    -uniform(&mut state)
                } else if pick < 0.17 {
                    f64::NAN
                } else if pick < 0.6 && plain.second.is_finite() {
                    // Within a few ulps of second · c.
                    near += 1;
                    let t = plain.second * c;
                    let k = (uniform(&mut state) * 9.0) as i64 - 4;
                    f64::from_bits((t.to_bits() as i64 + k) as u64)
                } else {
                    uniform(&mut state) * 10f64.powi((i % 5) as i32 - 2)
                };
                fast.add_ratio(i, b, c);
                plain.add(i, b.max(0.0) / c);
                // Equal values (bit for bit but for the sign of a zero).
                assert!(
                    fast.min == plain.min && fast.arg == plain.arg && fast.second == plain.second,
                    "b = {b:e}, c = {c:e}"
                );
            }
        }
        assert!(near > 10_000, "{near} ratios near the second key");
    }
}
