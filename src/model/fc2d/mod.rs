//! Siconos' 2D frictional contact problems (`FrictionContact` `.dat` files),
//! read into an [`Fc2dProblem`].
//!
//! A local 2D frictional contact problem: for `nc` contacts, find reactions
//! `r = (r_N, r_T)` per contact (impulses, N·s) and relative velocities
//! `u = W r + q` (m/s) with, at every contact `j`, Signorini
//! (`0 ≤ u_N ⟂ r_N ≥ 0`) and Coulomb (`|r_T| ≤ μ_j r_N`, sliding opposite to
//! `u_T` at the bound). `W` is a Delassus matrix (symmetric positive
//! semidefinite in exact arithmetic).
//!
//! # The file format
//!
//! The files are written by Siconos numerics (`frictionContact_printInFile`,
//! `NM_write_in_file`); whitespace-separated tokens, reals in C `%le` or `%g`
//! form:
//!
//! ```text
//! d nc MATRIX q[2 nc] mu[nc]
//! ```
//!
//! `d` must be 2 and `nc ≥ 1`. `MATRIX` is `storage size0 size1`
//! (`size0 = size1 = 2 nc`), then one of:
//!
//! - storage 0, dense: `size0 size1` again, then `size0·size1` reals in
//!   column-major order;
//! - storage 1, sparse block: `nbblocks nb0 nb1`, `cum0[nb0]`, `cum1[nb1]`
//!   (cumulative block sizes, which must be 2, 4, …, 2 nc: one 2×2 block per
//!   contact pair), `filled1 filled2` (`nc + 1` and `nbblocks`), the block-row
//!   pointers `rowptr[filled1]` and block column indices `colidx[filled2]`
//!   (CSR on blocks), then for each block `k` in order: `k` and the 2×2 block
//!   in column-major order (`W_NN W_TN W_NT W_TT`); a block repeated in a
//!   row is summed;
//! - storage 2, CSparse's text print (`cs_print`): `origin` (1 triplet, 2 CSC;
//!   3, CSR, is refused: no file to check it on), the line
//!   `CSparse Version …`, then for CSC the line
//!   `m-by-n, nzmax: Z nnz: Z, 1-norm: x` and per column
//!   `col j : locations a to b` followed by `b − a + 1` lines `i : x`; for a
//!   triplet matrix the line `triplet: m-by-n, nzmax: Z nnz: Z` and `nnz`
//!   lines `i j : x` (repeated entries are summed). The entries are scattered
//!   into the 2×2 blocks; a block with no entry is zero. Such files carry
//!   6 significant digits (`%g`).
//!
//! `q` is in the order (N, T) per contact; `mu` holds one coefficient per
//! contact (finite, `≥ 0`). Tokens after `mu` are ignored (some files end
//! with an extra number).
//!
//! A malformed file gets one line naming the file, the line, the token and
//! what was expected ([`Fc2dError`]); no size read from the file is allocated
//! before it is checked against the tokens left to hold it.
//!
//! # The test files
//!
//! `tests/data/fc2d/` holds three files of Siconos' test data
//! (siconos/siconos, `numerics/src/FrictionContact/test/data/`, Apache-2.0
//! licence), copied unchanged: storages 1 and 2.

mod parse;
mod storage;
mod tokens;

use std::fmt;
use std::path::{Path, PathBuf};

pub use parse::parse_fc2d;

/// A sparse matrix of 2×2 blocks, stored by block row (CSR on blocks): the
/// block columns of each block row are sorted and distinct.
///
/// Each block is `[W_NN, W_NT, W_TN, W_TT]`: row-major within the block,
/// row contact `i`, column contact `j`, so `W_NT` is the normal velocity of
/// contact `i` per unit tangential reaction of contact `j`.
#[derive(Debug, Clone, PartialEq)]
pub struct BlockSparse {
    /// Number of block rows and columns (the contacts).
    pub n: usize,
    /// Block-row pointers: the blocks of row `i` are `row_ptr[i]..row_ptr[i + 1]`
    /// (`n + 1` entries).
    pub row_ptr: Vec<usize>,
    /// Block column of each block, sorted within a row.
    pub col: Vec<usize>,
    /// The blocks, `[W_NN, W_NT, W_TN, W_TT]` each, m/s per N·s (1/kg).
    pub blocks: Vec<[f64; 4]>,
}

impl BlockSparse {
    /// Builds the matrix from `(block row, block column, block)` triples,
    /// in any order; blocks at the same place are summed. Rows and columns
    /// must be below `n` (the readers check them first).
    pub(crate) fn from_triples(n: usize, mut triples: Vec<(usize, usize, [f64; 4])>) -> Self {
        triples.sort_by_key(|t| (t.0, t.1));
        let mut row_ptr = vec![0usize; n + 1];
        let mut col: Vec<usize> = Vec::with_capacity(triples.len());
        let mut rows: Vec<usize> = Vec::with_capacity(triples.len());
        let mut blocks: Vec<[f64; 4]> = Vec::with_capacity(triples.len());
        for (i, j, b) in triples {
            match (rows.last(), col.last(), blocks.last_mut()) {
                (Some(&ri), Some(&cj), Some(last)) if ri == i && cj == j => {
                    for (s, v) in last.iter_mut().zip(b) {
                        *s += v;
                    }
                }
                _ => {
                    rows.push(i);
                    col.push(j);
                    blocks.push(b);
                }
            }
        }
        for &i in &rows {
            row_ptr[i + 1] += 1;
        }
        for i in 0..n {
            row_ptr[i + 1] += row_ptr[i];
        }
        BlockSparse {
            n,
            row_ptr,
            col,
            blocks,
        }
    }

    /// The block at block row `i`, column `j`, if stored.
    pub fn block(&self, i: usize, j: usize) -> Option<&[f64; 4]> {
        let range = self.row_ptr[i]..self.row_ptr[i + 1];
        let cols = &self.col[range.clone()];
        cols.binary_search(&j)
            .ok()
            .map(|k| &self.blocks[range.start + k])
    }

    /// The number of stored blocks.
    pub fn nnz_blocks(&self) -> usize {
        self.blocks.len()
    }
}

/// A 2D frictional contact problem read from a Siconos file: find `r` with
/// `u = W r + q` satisfying Signorini and Coulomb at each contact.
#[derive(Debug, Clone, PartialEq)]
pub struct Fc2dProblem {
    /// Number of contacts `nc`.
    pub contacts: usize,
    /// The Delassus matrix `W` (2nc × 2nc) as 2×2 blocks, m/s per N·s.
    pub w: BlockSparse,
    /// The free velocity `q`, 2 nc entries, (N, T) per contact, m/s.
    pub q: Vec<f64>,
    /// Friction coefficient of each contact, dimensionless, `≥ 0`.
    pub mu: Vec<f64>,
    /// The storage of `W` in the file: 0 dense, 1 sparse block, 2 CSparse.
    pub storage: u8,
}

impl Fc2dProblem {
    /// `W` as a dense row-major `2nc × 2nc` matrix (for tests and Lemke;
    /// 8 (2nc)² bytes).
    pub fn dense(&self) -> Vec<f64> {
        let m = 2 * self.contacts;
        let mut a = vec![0.0; m * m];
        for i in 0..self.w.n {
            for k in self.w.row_ptr[i]..self.w.row_ptr[i + 1] {
                let j = self.w.col[k];
                let b = &self.w.blocks[k];
                a[2 * i * m + 2 * j] += b[0];
                a[2 * i * m + 2 * j + 1] += b[1];
                a[(2 * i + 1) * m + 2 * j] += b[2];
                a[(2 * i + 1) * m + 2 * j + 1] += b[3];
            }
        }
        a
    }

    /// `W r`, for `r` of length `2 nc` (panics on another length: a
    /// programming error, not a file's).
    pub fn apply(&self, r: &[f64]) -> Vec<f64> {
        assert_eq!(r.len(), 2 * self.contacts, "apply: r has the wrong length");
        let mut out = vec![0.0; 2 * self.contacts];
        for i in 0..self.w.n {
            let (mut n, mut t) = (0.0, 0.0);
            for k in self.w.row_ptr[i]..self.w.row_ptr[i + 1] {
                let j = self.w.col[k];
                let b = &self.w.blocks[k];
                n += b[0] * r[2 * j] + b[1] * r[2 * j + 1];
                t += b[2] * r[2 * j] + b[3] * r[2 * j + 1];
            }
            out[2 * i] = n;
            out[2 * i + 1] = t;
        }
        out
    }

    /// The asymmetry of `W`: `max |W_ab − W_ba|` over all entries, divided by
    /// `max |W_ab|` (0 for a zero matrix). A block absent counts as zero.
    /// The reader does not refuse an unsymmetric `W`; this measures it.
    pub fn max_asymmetry(&self) -> f64 {
        let w = &self.w;
        let mut largest = 0.0f64;
        let mut diff = 0.0f64;
        for i in 0..w.n {
            for k in w.row_ptr[i]..w.row_ptr[i + 1] {
                let j = w.col[k];
                let b = &w.blocks[k];
                largest = b.iter().fold(largest, |m, v| m.max(v.abs()));
                // (W_ji)ᵀ, zero if absent: [NN, TN, NT, TT] of block (j, i).
                let t = w.block(j, i).map_or([0.0; 4], |c| [c[0], c[2], c[1], c[3]]);
                for (x, y) in b.iter().zip(t) {
                    diff = diff.max((x - y).abs());
                }
            }
        }
        if largest > 0.0 {
            diff / largest
        } else {
            0.0
        }
    }
}

/// A file that cannot be read as a 2D frictional contact problem: the file,
/// the line, the token (none at the end of the file) and what was expected.
#[derive(Debug, Clone, PartialEq)]
pub struct Fc2dError {
    /// The file.
    pub path: PathBuf,
    /// The line (1-based) of the token, or the last line at the end of the
    /// file; 0 when the file cannot be read at all.
    pub line: usize,
    /// The token found (shortened to 40 characters); `None` at the end of
    /// the file or when the file cannot be read.
    pub token: Option<String>,
    /// What was expected there.
    pub expected: String,
}

impl fmt::Display for Fc2dError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let p = self.path.display();
        match (&self.token, self.line) {
            (_, 0) => write!(f, "{p}: expected {}", self.expected),
            (Some(t), l) => write!(f, "{p}:{l}: token \"{t}\": expected {}", self.expected),
            (None, l) => write!(f, "{p}:{l}: end of file: expected {}", self.expected),
        }
    }
}

impl std::error::Error for Fc2dError {}

/// Reads a Siconos 2D frictional contact problem file (see the module doc).
pub fn read_fc2d(path: &Path) -> Result<Fc2dProblem, Fc2dError> {
    let text = std::fs::read_to_string(path).map_err(|e| Fc2dError {
        path: path.to_path_buf(),
        line: 0,
        token: None,
        expected: format!("a readable text file ({e})"),
    })?;
    parse_fc2d(&text, path)
}
