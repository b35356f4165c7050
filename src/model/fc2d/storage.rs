//! The three storages of `W` in a problem file: dense (0), sparse block (1),
//! CSparse's text print (2), each read into a [`BlockSparse`].

use super::tokens::{parse_uint, Tokens};
use super::{BlockSparse, Fc2dError};

/// The place of entry `(a, b)` of `W` (scalar row and column): its block
/// and its index in the block's row-major `[NN, NT, TN, TT]`.
fn place(a: usize, b: usize) -> (usize, usize, usize) {
    (a / 2, b / 2, 2 * (a % 2) + b % 2)
}

/// One entry as a triple of [`BlockSparse::from_triples`].
fn entry(a: usize, b: usize, x: f64) -> (usize, usize, [f64; 4]) {
    let (i, j, k) = place(a, b);
    let mut blk = [0.0; 4];
    blk[k] = x;
    (i, j, blk)
}

/// `W` built from `triples`, refused (at the next token) if summing
/// repeated entries overflowed.
fn build(
    tk: &Tokens,
    nc: usize,
    triples: Vec<(usize, usize, [f64; 4])>,
) -> Result<BlockSparse, Fc2dError> {
    let w = BlockSparse::from_triples(nc, triples);
    if w.blocks.iter().flatten().all(|x| x.is_finite()) {
        Ok(w)
    } else {
        Err(tk.error_here(
            "entries of W whose repeats sum to finite reals (W ended before this token)",
        ))
    }
}

/// Storage 0: `size0 size1` again, then `(2 nc)²` reals, column-major.
/// Blocks that are exactly zero are not stored. `tail`: the tokens that
/// must follow `W`.
pub(super) fn dense(tk: &mut Tokens, nc: usize, tail: usize) -> Result<BlockSparse, Fc2dError> {
    let m = 2 * nc;
    tk.uint_eq(
        m,
        &format!("size0 = {m} again (dense storage: size0 size1)"),
    )?;
    tk.uint_eq(
        m,
        &format!("size1 = {m} again (dense storage: size0 size1)"),
    )?;
    let room = tk.left().saturating_sub(tail);
    let n = m.checked_mul(m).filter(|&n| n <= room).ok_or_else(|| {
        tk.error_here(format!(
            "{m}×{m} reals of a dense W, then {tail} of q and mu; only {} tokens left",
            tk.left()
        ))
    })?;
    let a = tk.reals(n, "W, dense, column-major")?;
    let mut triples = Vec::new();
    for bj in 0..nc {
        for bi in 0..nc {
            let at = |r: usize, c: usize| a[(2 * bj + c) * m + 2 * bi + r];
            let blk = [at(0, 0), at(0, 1), at(1, 0), at(1, 1)];
            if blk.iter().any(|&x| x != 0.0) {
                triples.push((bi, bj, blk));
            }
        }
    }
    build(tk, nc, triples)
}

/// Storage 1: Siconos' sparse block matrix (`SBM_write_in_file`), of 2×2
/// blocks only.
pub(super) fn sparse_block(
    tk: &mut Tokens,
    nc: usize,
    tail: usize,
) -> Result<BlockSparse, Fc2dError> {
    // Each block: its column index, its number and 4 reals; the block
    // structure (nb0 nb1 cum0 cum1 filled1 filled2 rowptr) needs 3 nc + 5
    // tokens besides.
    let reserve = tail.saturating_add(3 * nc + 5);
    let nb = tk.count(6, reserve, &[], "the number of blocks nbblocks")?;
    let per = format!("{nc} (one 2×2 block row per contact)");
    tk.uint_eq(nc, &format!("nb0 = {per}"))?;
    tk.uint_eq(nc, &format!("nb1 = {per}"))?;
    for name in ["cum0", "cum1"] {
        for i in 0..nc {
            let want = 2 * (i + 1);
            tk.uint_eq(
                want,
                &format!("{name}[{i}] = {want} (2×2 blocks: 2, 4, 6, …)"),
            )?;
        }
    }
    tk.uint_eq(nc + 1, &format!("filled1 = nc + 1 = {}", nc + 1))?;
    tk.uint_eq(nb, &format!("filled2 = nbblocks = {nb}"))?;
    let mut row_ptr = Vec::with_capacity(nc + 1);
    tk.uint_eq(0, "rowptr[0] = 0")?;
    row_ptr.push(0usize);
    for i in 1..=nc {
        let (t, l) = tk.peek();
        let prev = row_ptr[i - 1];
        let what = if i == nc {
            format!("rowptr[{nc}] = nbblocks = {nb}")
        } else {
            format!(
                "rowptr[{i}] between rowptr[{}] = {prev} and nbblocks = {nb}",
                i - 1
            )
        };
        let v = tk.uint(&what)?;
        if v < prev || v > nb || (i == nc && v != nb) {
            return Err(tk.error_at(t, l, what));
        }
        row_ptr.push(v);
    }
    let mut col = Vec::with_capacity(nb);
    for k in 0..nb {
        col.push(tk.index(nc, &format!("colidx[{k}], a block column below {nc}"))?);
    }
    let mut triples = Vec::with_capacity(nb);
    for i in 0..nc {
        for (k, &j) in col.iter().enumerate().take(row_ptr[i + 1]).skip(row_ptr[i]) {
            tk.uint_eq(k, &format!("the block number {k}"))?;
            let b = tk.reals(4, &format!("block {k}, W_NN W_TN W_NT W_TT"))?;
            triples.push((i, j, [b[0], b[2], b[1], b[3]]));
        }
    }
    build(tk, nc, triples)
}

/// Storage 2: CSparse's text print (`cs_print`) of a CSC (origin 2) or
/// triplet (origin 1) matrix.
pub(super) fn csparse(tk: &mut Tokens, nc: usize, tail: usize) -> Result<BlockSparse, Fc2dError> {
    let m = 2 * nc;
    let (t, l) = tk.next("the CSparse origin (1 triplet, 2 CSC)")?;
    let triplet = match t {
        "1" => true,
        "2" => false,
        "3" => return Err(tk.error_at(t, l, "origin 1 (triplet) or 2 (CSC); 3 (CSR) is not read")),
        _ => return Err(tk.error_at(t, l, "an integer (origin: 1 triplet, 2 CSC)")),
    };
    let (_, l) = tk.peek();
    tk.word("CSparse", "the line \"CSparse Version …\"")?;
    tk.skip_line(l);
    if triplet {
        tk.word("triplet:", "\"triplet:\" (origin 1)")?;
    }
    let (t, l) = tk.next("the size \"m-by-n,\"")?;
    let size = t.trim_end_matches(',').split_once("-by-");
    let sizes = size.map(|(a, b)| (parse_uint(a), parse_uint(b)));
    if sizes != Some((Some(m), Some(m))) {
        return Err(tk.error_at(t, l, format!("the size \"{m}-by-{m},\" (2 nc by 2 nc)")));
    }
    tk.word("nzmax:", "\"nzmax:\"")?;
    tk.uint_trim(&[','], "nzmax, an integer")?;
    tk.word("nnz:", "\"nnz:\"")?;
    // An entry is "i : x" (3 tokens) or "i j : x" (4); in CSC each column
    // has its 7 tokens "col j : locations a to b" besides.
    let (per, reserve) = if triplet {
        (4, tail)
    } else {
        (3, tail.saturating_add(7 * m))
    };
    let nnz = tk.count(per, reserve, &[','], "the number of entries nnz")?;
    let mut triples = Vec::with_capacity(nnz);
    if triplet {
        for _ in 0..nnz {
            let a = tk.index(m, &format!("a row index below {m}"))?;
            let b = tk.index(m, &format!("a column index below {m}"))?;
            tk.word(":", "\":\" (i j : x)")?;
            triples.push(entry(a, b, tk.real("a finite real (an entry of W)")?));
        }
        return build(tk, nc, triples);
    }
    tk.word("1-norm:", "\"1-norm:\"")?;
    tk.real("the 1-norm, a finite real")?;
    let mut p = 0usize;
    for j in 0..m {
        tk.word("col", &format!("\"col {j} : locations {p} to …\""))?;
        tk.uint_eq(j, &format!("the column {j}"))?;
        tk.word(":", "\":\" (col j : locations a to b)")?;
        tk.word("locations", "\"locations\" (col j : locations a to b)")?;
        tk.uint_eq(p, &format!("the first location {p} of column {j}"))?;
        tk.word("to", "\"to\" (col j : locations a to b)")?;
        let (t, l) = tk.peek();
        let what = format!(
            "the last location of column {j}: from {} to nnz − 1 = {}",
            p as i64 - 1,
            nnz as i64 - 1
        );
        let last = tk.uint(&what)?;
        if last + 1 < p || last >= nnz {
            return Err(tk.error_at(t, l, what));
        }
        while p <= last {
            let a = tk.index(m, &format!("a row index below {m} (column {j})"))?;
            tk.word(":", "\":\" (i : x)")?;
            triples.push(entry(a, j, tk.real("a finite real (an entry of W)")?));
            p += 1;
        }
    }
    if p != nnz {
        return Err(tk.error_here(format!("nnz = {nnz} entries; the columns hold {p}")));
    }
    build(tk, nc, triples)
}
