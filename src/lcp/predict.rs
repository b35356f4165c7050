//! A **predicted complementary basis** for a large contact LCP: a block
//! nonsmooth Gauss–Seidel sweep (NSGS) on the LCP's own data, whose final
//! local bases are handed to the exact driver as a guess
//! ([`super::solve_warm_into`] with the warm Lemke path).
//!
//! # Scheme
//!
//! The unknowns are partitioned into small blocks ([`Blocks`]): on the
//! contact LCP of docs/physics.md §3.1 (`z = (λ, β̃, α)`, size `4m` with
//! friction, `m` without) one block per contact, `{λ_j, β̃⁺_j, β̃⁻_j, α_j}`
//! or `{λ_j}` ([`Blocks::contacts`]). A sweep visits the blocks in order and
//! solves each block's own LCP **exactly**,
//!
//! ```text
//! w_a = M_aa z_a + r_a ≥ 0,  z_a ≥ 0,  z_aᵀ w_a = 0,   r_a = q_a + Σ_{b≠a} M_ab z_b
//! ```
//!
//! with the other blocks at their current values (Gauss–Seidel: a block
//! sees the values its predecessors took in the same sweep). The local
//! problem (at most [`MAX_BLOCK`] unknowns) is solved by enumeration of its
//! complementary bases: `z = 0` if `r_a ≥ 0`, else the block's basis of the
//! previous sweep (most blocks keep theirs: this makes a sweep about ten
//! times cheaper), then every basis by increasing number of basic `z`
//! (then by index order); the first basis whose basic solution is feasible
//! (to a relative [`LOCAL_FEASIBILITY`]) is taken. On a Stewart–Trinkle contact block the
//! order is: separate (`z = 0`), then the two-unknown bases (stick:
//! `{λ, β̃±}` basic, `w(β̃∓)`, `w(α)` basic), then the three-unknown ones
//! (slide: `{λ, β̃ opposing, α}`, `w` of the other `β̃`), which in 2D is
//! exactly Coulomb's law at the contact (the two friction directions `±T`
//! describe the whole 2D cone). A block whose local LCP has no feasible
//! basis (a non-solvable local problem, e.g. a singular diagonal block)
//! keeps its values and its basis, and is counted
//! ([`Prediction::local_failures`]).
//!
//! The off-block couplings are kept sparse (a contact couples only with the
//! contacts that share a floe): the structure is built once per prediction
//! from the dense `M` (one O(n²) scan, cheaper than one dense pivot of the
//! tableau), as one row list of the non-zero `M_ij` with `i`, `j` in
//! different blocks; a sweep then costs the non-zeros, not n².
//!
//! # Stopping rule
//!
//! After each sweep, `w = M z + q` is evaluated (sparse) and so is the
//! driver's residual `‖min(z, w)‖₂ / ‖q‖₂`. The sweeps stop when the
//! concatenated local bases have not changed for
//! [`PredictOptions::stable_sweeps`] consecutive sweeps **and** the residual
//! is at most [`PredictOptions::residual`], or when the residual is at most
//! [`PredictOptions::residual`] / 1e4 (the values have converged whatever
//! the basis does on degenerate ties), or after
//! [`PredictOptions::max_sweeps`] sweeps (then the last bases are the
//! guess all the same).
//!
//! # The guess
//!
//! `basic[i]` is true when `z_i` is basic in the final local basis of its
//! block. For a non-degenerate point this is `z_i > w_i`; on ties
//! (`z_i = w_i = 0`, a contact closing with no impulse) it is the local
//! basis actually used, which is a definite complementary basis (separate,
//! stick or slide) of the block.
//!
//! # Why the guarantees are kept
//!
//! The prediction is only a starting basis. The driver crashes it into a
//! non-singular basis of the factorised tableau and runs Lemke's path from
//! it ([`super::Strategy::WarmLemke`], with the lexicographic rule and its
//! pivot cap); its candidate is accepted only by the residual on the
//! original data, and otherwise the cold attempts follow as if the
//! prediction had not been made. A wrong guess costs time, never accuracy.
//!
//! # References
//!
//! * M. Jean, "The non-smooth contact dynamics method", *Comput. Methods
//!   Appl. Mech. Engrg.* 177 (1999) 235–257 (NSGS on contact blocks).
//! * V. Acary, B. Brogliato, *Numerical Methods for Nonsmooth Dynamical
//!   Systems*, Springer, 2008, §13 (block splitting methods for LCPs).
//! * R. W. Cottle, J.-S. Pang, R. E. Stone, *The Linear Complementarity
//!   Problem*, 1992, §5.2 (projected/block Gauss–Seidel splittings).
//! * D. E. Stewart, J. C. Trinkle, "An implicit time-stepping scheme for
//!   rigid body dynamics with inelastic collisions and Coulomb friction",
//!   *Int. J. Numer. Methods Eng.* 39 (1996) 2673–2691.

use super::arith::ResidualScale;
use super::solution::BasisGuess;
use super::Lcp;

/// Largest block handled by the local enumeration (2^8 = 256 bases): a
/// contact is 4 unknowns, a flush edge pair with merged friction 5
/// (docs/physics.md §3.1), three points of one pair 6.
pub const MAX_BLOCK: usize = 8;

/// Relative feasibility tolerance of a local basic solution: `z_k` and
/// `w_k` may be as low as `−LOCAL_FEASIBILITY · max|r_a|` (rounding of a
/// ≤ 4×4 elimination is about 1e-15 relative).
pub const LOCAL_FEASIBILITY: f64 = 1e-12;

/// Relative pivot below which a local principal submatrix is singular for
/// the enumeration (the basis is skipped).
const LOCAL_PIVOT: f64 = 1e-13;

/// A partition of the unknowns `0..n` into blocks of at most
/// [`MAX_BLOCK`] indices.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Blocks {
    n: usize,
    blocks: Vec<Vec<usize>>,
}

impl Blocks {
    /// The blocks `blocks` of `0..n`, or `None` unless every index of
    /// `0..n` is in exactly one block of 1 to [`MAX_BLOCK`] indices.
    pub fn new(n: usize, blocks: Vec<Vec<usize>>) -> Option<Blocks> {
        let mut seen = vec![false; n];
        for b in &blocks {
            if b.is_empty() || b.len() > MAX_BLOCK {
                return None;
            }
            for &i in b {
                if i >= n || seen[i] {
                    return None;
                }
                seen[i] = true;
            }
        }
        seen.iter().all(|&s| s).then_some(Blocks { n, blocks })
    }

    /// The contact blocks of a contact LCP of `n` unknowns and `m` contacts
    /// (docs/physics.md §3.1): with `n = 4m`, contact `j` owns
    /// `{j, m + 2j, m + 2j + 1, 3m + j}` (`λ_j`, `β̃⁺_j`, `β̃⁻_j`, `α_j`);
    /// with `n = m`, `{j}`. `None` for any other `n` (or `m = 0`).
    pub fn contacts(n: usize, m: usize) -> Option<Blocks> {
        if m == 0 {
            return None;
        }
        let blocks = if n == 4 * m {
            (0..m)
                .map(|j| vec![j, m + 2 * j, m + 2 * j + 1, 3 * m + j])
                .collect()
        } else if n == m {
            (0..m).map(|j| vec![j]).collect()
        } else {
            return None;
        };
        Blocks::new(n, blocks)
    }

    /// Number of unknowns.
    pub fn n(&self) -> usize {
        self.n
    }

    /// The blocks.
    pub fn blocks(&self) -> &[Vec<usize>] {
        &self.blocks
    }
}

/// Options of [`predict`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PredictOptions {
    /// Sweep cap. Default 100: a sweep costs about 0.14 ms at n = 1,550
    /// (bay jam), so 100 sweeps cost about as much as 120 pivots of the
    /// factorised Lemke path (a cold solve there takes 1,000–26,000); more
    /// sweeps give better guesses but were not faster (docs/physics.md §3.3).
    pub max_sweeps: usize,
    /// Consecutive sweeps without a change of basis that (with the residual
    /// test) end the sweeps. Default 3.
    pub stable_sweeps: usize,
    /// Residual (`‖min(z, w)‖₂ / ‖q‖₂`, the driver's) at or below which a
    /// stable basis ends the sweeps. Default 1e-7: on the bay-jam dumps
    /// (n ≈ 1,500) a guess at a residual of 1e-3 still has 40–250 wrong
    /// indices, at 1e-7 about 3 to 5 (docs/physics.md §3.3).
    pub residual: f64,
}

impl Default for PredictOptions {
    fn default() -> Self {
        Self {
            max_sweeps: 100,
            stable_sweeps: 3,
            residual: 1e-7,
        }
    }
}

/// Result of [`predict`].
#[derive(Debug, Clone, PartialEq)]
pub struct Prediction {
    /// The guessed basis and the NSGS point as starting values.
    pub guess: BasisGuess,
    /// Sweeps made.
    pub sweeps: usize,
    /// Residual of the NSGS point (driver's definition).
    pub residual: f64,
    /// Whether the stopping rule was met before the sweep cap.
    pub converged: bool,
    /// Local problems without a feasible basis, over every sweep.
    pub local_failures: usize,
}

/// Off-block couplings in compressed rows: row `i` holds `M_ij` for the
/// `j` outside `i`'s block.
struct Coupling {
    start: Vec<usize>,
    col: Vec<usize>,
    val: Vec<f64>,
}

impl Coupling {
    fn of(m: &[f64], n: usize, block_of: &[usize]) -> Coupling {
        let mut start = Vec::with_capacity(n + 1);
        let (mut col, mut val) = (Vec::new(), Vec::new());
        start.push(0);
        for i in 0..n {
            let row = &m[i * n..(i + 1) * n];
            for (j, &v) in row.iter().enumerate() {
                if v != 0.0 && block_of[j] != block_of[i] {
                    col.push(j);
                    val.push(v);
                }
            }
            start.push(col.len());
        }
        Coupling { start, col, val }
    }

    /// `Σ_j M_ij z_j` over the off-block `j`.
    fn row_dot(&self, i: usize, z: &[f64]) -> f64 {
        let (a, b) = (self.start[i], self.start[i + 1]);
        self.col[a..b]
            .iter()
            .zip(&self.val[a..b])
            .fold(0.0, |s, (&j, &v)| s + v * z[j])
    }
}

/// Solves the local LCP `w = A z + r` of `b ≤ MAX_BLOCK` unknowns (`a`
/// row-major `b×b`) by enumeration of its complementary bases (module doc).
/// Writes `z` and returns the basis mask (bit k: `z_k` basic), or `None` if
/// no basis is feasible.
fn local_solve(a: &[f64], r: &[f64], z: &mut [f64], previous: u32) -> Option<u32> {
    let b = r.len();
    let rmax = r.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    if r.iter().all(|&v| v >= 0.0) {
        z.iter_mut().for_each(|x| *x = 0.0);
        return Some(0);
    }
    let tol = LOCAL_FEASIBILITY * rmax;
    let amax = a.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    let feasible = |mask: u32, z: &mut [f64]| {
        basic_solution(a, r, mask, amax, z).is_some()
            && (0..b).all(|k| {
                if mask & (1 << k) != 0 {
                    z[k] >= -tol
                } else {
                    let w: f64 = (0..b).map(|l| a[k * b + l] * z[l]).sum::<f64>() + r[k];
                    w >= -tol
                }
            })
    };
    // The block's basis of the previous sweep first (most blocks keep it).
    let order = std::iter::once(previous).chain(
        (1..=b as u32).flat_map(|c| (1u32..(1 << b)).filter(move |mk| mk.count_ones() == c)),
    );
    for mask in order {
        if mask != 0 && mask < (1 << b) && feasible(mask, z) {
            z.iter_mut().for_each(|x| *x = x.max(0.0));
            return Some(mask);
        }
    }
    None
}

/// The basic solution of basis `mask`: `A_SS z_S = −r_S`, `z = 0` off `S`,
/// by Gaussian elimination with partial pivoting; `None` if `A_SS` is
/// singular (a pivot below `LOCAL_PIVOT · amax`).
fn basic_solution(a: &[f64], r: &[f64], mask: u32, amax: f64, z: &mut [f64]) -> Option<()> {
    let b = r.len();
    let mut idx = [0usize; MAX_BLOCK];
    let mut s = 0;
    for k in 0..b {
        if mask & (1 << k) != 0 {
            idx[s] = k;
            s += 1;
        }
    }
    let mut mat = [[0.0f64; MAX_BLOCK + 1]; MAX_BLOCK];
    for (p, &i) in idx[..s].iter().enumerate() {
        for (c, &j) in idx[..s].iter().enumerate() {
            mat[p][c] = a[i * b + j];
        }
        mat[p][s] = -r[i];
    }
    for c in 0..s {
        let piv = (c..s).max_by(|&x, &y| mat[x][c].abs().total_cmp(&mat[y][c].abs()))?;
        // A NaN pivot fails this test too.
        if mat[piv][c].abs().partial_cmp(&(LOCAL_PIVOT * amax)) != Some(std::cmp::Ordering::Greater)
        {
            return None;
        }
        mat.swap(c, piv);
        let pivot_row = mat[c];
        for row in mat[c + 1..s].iter_mut() {
            let f = row[c] / pivot_row[c];
            for (x, y) in row[c..=s].iter_mut().zip(&pivot_row[c..=s]) {
                *x -= f * y;
            }
        }
    }
    z.iter_mut().for_each(|x| *x = 0.0);
    for c in (0..s).rev() {
        let mut v = mat[c][s];
        for k in c + 1..s {
            v -= mat[c][k] * z[idx[k]];
        }
        let x = v / mat[c][c];
        if !x.is_finite() {
            return None;
        }
        z[idx[c]] = x;
    }
    Some(())
}

/// Predicts a complementary basis of `lcp` by block NSGS on `blocks`
/// (module doc). `None` if the sizes do not match or the data are not
/// finite. Never panics; the returned `z` is finite and `≥ 0`.
pub fn predict(lcp: &Lcp, blocks: &Blocks, opts: &PredictOptions) -> Option<Prediction> {
    let n = lcp.n;
    if lcp.check().is_err() || blocks.n != n || !lcp.is_finite() {
        return None;
    }
    let (m, q) = (&lcp.m[..], &lcp.q[..]);
    let mut block_of = vec![0usize; n];
    for (a, b) in blocks.blocks.iter().enumerate() {
        for &i in b {
            block_of[i] = a;
        }
    }
    let coupling = Coupling::of(m, n, &block_of);
    // Diagonal blocks, row-major, one after the other.
    let diag: Vec<Vec<f64>> = blocks
        .blocks
        .iter()
        .map(|b| {
            b.iter()
                .flat_map(|&i| b.iter().map(move |&j| m[i * n + j]))
                .collect()
        })
        .collect();
    let mut z = vec![0.0; n];
    let mut w = vec![0.0; n];
    let mut mask = vec![0u32; blocks.blocks.len()];
    let scale = ResidualScale::of(q);
    let (mut r, mut zl) = ([0.0; MAX_BLOCK], [0.0; MAX_BLOCK]);
    let mut stable = 0usize;
    let mut sweeps = 0usize;
    let mut residual = f64::INFINITY;
    let mut converged = false;
    let mut local_failures = 0usize;
    while sweeps < opts.max_sweeps {
        sweeps += 1;
        let mut changed = false;
        for (a, b) in blocks.blocks.iter().enumerate() {
            let k = b.len();
            for (p, &i) in b.iter().enumerate() {
                r[p] = q[i] + coupling.row_dot(i, &z);
            }
            match local_solve(&diag[a], &r[..k], &mut zl[..k], mask[a]) {
                Some(mk) => {
                    for (p, &i) in b.iter().enumerate() {
                        z[i] = zl[p];
                    }
                    changed |= mk != mask[a];
                    mask[a] = mk;
                }
                None => local_failures += 1,
            }
        }
        // w = M z + q on the sparse structure, then the residual.
        for (a, b) in blocks.blocks.iter().enumerate() {
            let k = b.len();
            for (p, &i) in b.iter().enumerate() {
                let own: f64 = (0..k).map(|l| diag[a][p * k + l] * z[b[l]]).sum();
                w[i] = q[i] + own + coupling.row_dot(i, &z);
            }
        }
        residual = scale.residual(&z, &w);
        stable = if changed { 0 } else { stable + 1 };
        if (stable >= opts.stable_sweeps && residual <= opts.residual)
            || residual <= opts.residual * 1e-4
        {
            converged = true;
            break;
        }
    }
    let mut basic = vec![false; n];
    for (a, b) in blocks.blocks.iter().enumerate() {
        for (p, &i) in b.iter().enumerate() {
            basic[i] = mask[a] & (1 << p) != 0;
        }
    }
    for v in z.iter_mut() {
        if !v.is_finite() {
            *v = 0.0;
        }
    }
    Some(Prediction {
        guess: BasisGuess { basic, z },
        sweeps,
        residual,
        converged,
        local_failures,
    })
}

/// Number of indices on which the guessed basis `basic` differs from the
/// basis of a solution `(z, w)`, counting only the non-degenerate indices
/// (where that basis is defined: `z_i > w_i` means `z_i` basic); an index
/// with both `z_i` and `w_i` at most `tie` is degenerate, and the number of
/// those is returned second.
pub fn basis_mismatch(basic: &[bool], z: &[f64], w: &[f64], tie: f64) -> (usize, usize) {
    let (mut wrong, mut ties) = (0, 0);
    for ((&g, &zi), &wi) in basic.iter().zip(z).zip(w) {
        if zi <= tie && wi <= tie {
            ties += 1;
        } else if g != (zi > wi) {
            wrong += 1;
        }
    }
    (wrong, ties)
}

/// The driver from a predicted basis: [`predict`] on `blocks`, then
/// [`super::solve_warm_into`] from its guess with the warm Lemke path
/// alone (`warm_solves = 0`, `warm_lemke` on: the dense principal
/// pivoting of the warm start costs an O(n³) factorisation per basis
/// solve, a large part of a cold solve at the sizes this is meant for),
/// followed by the cold attempts if its candidate is not accepted. Without
/// a prediction (sizes or non-finite data) this is [`super::solve_into`].
/// Returns the prediction made, if any.
pub fn solve_predicted_into(
    ws: &mut super::Workspace,
    lcp: &Lcp,
    opts: &super::SolveOptions,
    blocks: &Blocks,
    popts: &PredictOptions,
    out: &mut super::LcpSolution,
) -> Option<Prediction> {
    match predict(lcp, blocks, popts) {
        Some(p) => {
            let o = super::SolveOptions {
                warm_solves: 0,
                warm_lemke: true,
                ..opts.clone()
            };
            super::solve_warm_into(ws, lcp, &o, &p.guess, out);
            Some(p)
        }
        None => {
            super::solve_into(ws, lcp, opts, out);
            None
        }
    }
}

/// [`solve_predicted_into`] with this thread's work space, returning the
/// solution and the prediction made, if any.
pub fn solve_predicted(
    lcp: &Lcp,
    opts: &super::SolveOptions,
    blocks: &Blocks,
    popts: &PredictOptions,
) -> (super::LcpSolution, Option<Prediction>) {
    super::lemke::with_thread_workspace(|ws| {
        let mut out = super::LcpSolution::empty();
        let p = solve_predicted_into(ws, lcp, opts, blocks, popts, &mut out);
        (out, p)
    })
}
