//! The pattern of an assembled contact LCP's matrix (the entries that can
//! be non-zero), the compressed columns built from it for a large LCP, and
//! the reuse of a large matrix's buffer: a dropped LCP zeroes its pattern
//! and leaves the buffer to the next assembly on its thread.

use super::ContactLcp;
use crate::lcp::sparse::Columns;

/// Unknowns from which the assembly builds the compressed columns of the
/// LCP's matrix for the solver: where the solver uses them (the factorised
/// basis, [`crate::lcp::lemke_options::REVISED_FROM`]).
pub(super) const COLUMNS_FROM: usize = crate::lcp::lemke_options::REVISED_FROM;

/// Calls `entry(row, column)` for every entry of the assembled matrix
/// (`m` contacts, `nf` friction groups, `nf = 0` without friction) that can
/// be non-zero, from its pattern: the Delassus entry `(r, c)` only if
/// columns `r` and `c` of `H` touch a common floe (`touching`), the γ
/// entries in the rows of the two friction columns of a group and its σ
/// column, and in a σ row its group's normal and friction columns. Repeats
/// are allowed. Every entry the assembly writes is in this pattern (the
/// columns built from it are those of a full scan, tested); the others
/// stay `+0.0`.
fn pattern(
    m: usize,
    nf: usize,
    touching: &[Vec<usize>],
    fgroup: &[usize],
    mut entry: impl FnMut(usize, usize),
) {
    for t in touching {
        for &c in t {
            for &r in t {
                entry(r, c);
            }
        }
    }
    for (j, &g) in fgroup.iter().enumerate() {
        entry(m + 2 * nf + g, j);
    }
    for g in 0..nf {
        let s = m + 2 * nf + g;
        entry(s, m + 2 * g);
        entry(s, m + 2 * g + 1);
        entry(m + 2 * g, s);
        entry(m + 2 * g + 1, s);
    }
}

/// The compressed columns of the assembled matrix `a` (`n × n`, row-major)
/// from its [`pattern`].
pub(super) fn columns_of(
    a: &[f64],
    n: usize,
    m: usize,
    nf: usize,
    touching: &[Vec<usize>],
    fgroup: &[usize],
) -> Columns {
    let mut cand: Vec<Vec<usize>> = vec![Vec::new(); n];
    pattern(m, nf, touching, fgroup, |r, c| cand[c].push(r));
    let mut cols = Columns::default();
    cols.fill_from_candidates(a, n, |j| &cand[j], &mut Vec::new());
    cols
}

thread_local! {
    /// A zeroed buffer for the dense matrix of the next large assembly,
    /// left by the last large [`ContactLcp`] dropped on this thread (see
    /// [`zeroed_matrix`]).
    static SPARE_MATRIX: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// A vector of `len` zeros (`+0.0`) for an assembled matrix: the spare
/// buffer of this thread when there is one (only the part beyond its
/// length is written), else a new one.
///
/// Zeroing the `n²` entries of a large group's matrix at each assembly
/// (13.5 MB for 1,300 unknowns) cost 6.5 % of an hour of field_200_coast
/// (event-driven), more than the entries the assembly then writes; a
/// dropped large LCP instead zeroes only its [`pattern`] and
/// leaves its buffer here.
pub(super) fn zeroed_matrix(len: usize) -> Vec<f64> {
    let mut a = SPARE_MATRIX
        .try_with(|s| std::mem::take(&mut *s.borrow_mut()))
        .unwrap_or_default();
    if a.len() >= len {
        a.truncate(len);
    } else {
        a.resize(len, 0.0);
    }
    a
}

/// The capacity (entries) of this thread's spare matrix buffer
/// ([`zeroed_matrix`]): 0 when there is none. For the tests of its reuse.
#[doc(hidden)]
pub fn spare_matrix_capacity() -> usize {
    SPARE_MATRIX
        .try_with(|s| s.borrow().capacity())
        .unwrap_or(0)
}

impl Drop for ContactLcp {
    /// A large LCP (one with columns built at assembly) zeroes the entries
    /// of its matrix in the [`pattern`] of the assembly (every entry the
    /// assembly wrote; the others are zeros) and leaves the
    /// buffer for the next assembly on this thread ([`zeroed_matrix`]), if
    /// it is larger than the one there.
    fn drop(&mut self) {
        if self.columns.is_none() {
            return;
        }
        let n = self.lcp.n;
        let mut a = std::mem::take(&mut self.lcp.m);
        if a.len() != n * n {
            return;
        }
        pattern(
            self.m,
            self.friction_groups,
            &self.touching,
            &self.fgroup,
            |r, c| a[r * n + c] = 0.0,
        );
        let _ = SPARE_MATRIX.try_with(|s| {
            let mut s = s.borrow_mut();
            if a.capacity() > s.capacity() {
                *s = a;
            }
        });
    }
}

impl ContactLcp {
    /// Whether the columns built at assembly from the pattern (if any) are
    /// those of a scan of every entry of `lcp.m`, bit for bit; `None` if
    /// this LCP has none. For the tests of the pattern.
    #[doc(hidden)]
    pub fn columns_match_a_full_scan(&self) -> Option<bool> {
        let built = self.columns.as_ref()?;
        let mut scanned = Columns::default();
        scanned.scan(&self.lcp.m, self.lcp.n);
        Some(built.same_as(&scanned))
    }
}
