//! The reader of Siconos' 2D frictional contact problem files
//! (`src/model/fc2d`): three of Siconos' own files (tests/data/fc2d, Apache-2.0),
//! hand-written problems in each storage, and malformed files, each refused
//! with its line and what was expected.

use floebench::model::fc2d::{parse_fc2d, read_fc2d, Fc2dError, Fc2dProblem};
use std::path::{Path, PathBuf};

fn data(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data/fc2d")
        .join(name)
}

fn text(name: &str) -> String {
    std::fs::read_to_string(data(name)).expect("test data")
}

const F71: &str = "FrictionContactProblem00071.dat";
const F237: &str = "FrictionContactProblem00237.dat";
const F667: &str = "fc2d_granularflowonwall_00667_00000.dat";

/// The numbers of line `l` (1-based) of a text, read by plain splitting.
fn line_reals(text: &str, l: usize) -> Vec<f64> {
    let line = text.lines().nth(l - 1).expect("line");
    line.split_whitespace()
        .map(|t| t.parse().expect("a number"))
        .collect()
}

/// `q` as written: the last line holding 2 nc numbers.
fn q_line(text: &str, nc: usize) -> Vec<f64> {
    let line = text
        .lines()
        .rfind(|l| l.split_whitespace().count() == 2 * nc)
        .expect("a line of 2 nc numbers");
    line.split_whitespace()
        .map(|t| t.parse().expect("a number"))
        .collect()
}

/// Checks a storage-1 file against its text: the sizes, `q`, `mu` and,
/// read from the lines by their place, the first block and the last block
/// (its block row and column from the row pointers and column indices).
fn check_sparse_block(name: &str, nc: usize, blocks: usize, mu: f64) {
    let p = read_fc2d(&data(name)).unwrap_or_else(|e| panic!("{e}"));
    let t = text(name);
    assert_eq!((p.contacts, p.storage), (nc, 1));
    assert_eq!((p.q.len(), p.mu.len(), p.w.n), (2 * nc, nc, nc));
    assert_eq!(p.w.nnz_blocks(), blocks);
    assert!(p.mu.iter().all(|&m| m == mu), "mu of {name}");
    assert_eq!(p.q, q_line(&t, nc), "q of {name}");
    // Lines: 1 d, 2 nc, 3 storage, 4-5 sizes, 6 nbblocks, 7-8 nb0 nb1,
    // 9-10 cum0 cum1, 11-12 filled1 filled2, 13 rowptr, 14 colidx, then
    // per block its number and 4 lines (column-major W_NN W_TN W_NT W_TT).
    assert_eq!(line_reals(&t, 6), vec![blocks as f64]);
    let rowptr = line_reals(&t, 13);
    let colidx = line_reals(&t, 14);
    let d = p.dense();
    let m = 2 * nc;
    for k in [0, 1, blocks - 1] {
        let first = 15 + 5 * k;
        assert_eq!(line_reals(&t, first), vec![k as f64]);
        let v: Vec<f64> = (1..=4).flat_map(|o| line_reals(&t, first + o)).collect();
        let i = rowptr.iter().filter(|&&r| r <= k as f64).count() - 1;
        let j = colidx[k] as usize;
        let at = |r: usize, c: usize| d[(2 * i + r) * m + 2 * j + c];
        assert_eq!(
            [at(0, 0), at(1, 0), at(0, 1), at(1, 1)],
            [v[0], v[1], v[2], v[3]],
            "block {k} of {name}"
        );
        assert_eq!(
            p.w.block(i, j).map(|b| b[1]),
            Some(v[2]),
            "W_NT is [1] of block {k}"
        );
    }
}

#[test]
fn fc2d_siconos_00071_sparse_block() {
    check_sparse_block(F71, 89, 287, 0.9);
}

#[test]
fn fc2d_siconos_00237_sparse_block() {
    check_sparse_block(F237, 376, 1656, 0.9);
}

#[test]
fn fc2d_siconos_00667_csparse() {
    let p = read_fc2d(&data(F667)).unwrap_or_else(|e| panic!("{e}"));
    let t = text(F667);
    assert_eq!((p.contacts, p.storage, p.w.n), (667, 2, 667));
    assert!(p.mu.iter().all(|&m| m == 0.5));
    assert_eq!(p.q, q_line(&t, 667));
    let qn = p.q.iter().map(|x| x * x).sum::<f64>().sqrt();
    assert!(
        qn > 0.0 && qn < 1e-16,
        "‖q‖ = {qn:e}: the file's q is nearly zero"
    );
    // Lines 8 and on: "1334-by-1334, nzmax: 3822 nnz: 3822, …", then
    // "col 0 : locations 0 to 1", "0 : 856.713", "649 : -454.43", "col 1 …".
    let header: Vec<&str> = t
        .lines()
        .nth(7)
        .expect("line 8")
        .split_whitespace()
        .collect();
    let nnz: usize = header[4].trim_end_matches(',').parse().expect("nnz");
    let d = p.dense();
    let m = 1334;
    let mut col = 0usize;
    let mut entries = 0usize;
    for line in t.lines().skip(8) {
        let w: Vec<&str> = line.split_whitespace().collect();
        match w.as_slice() {
            ["col", j, ..] => col = j.parse().expect("col"),
            [i, ":", x] => {
                let (i, x): (usize, f64) = (i.parse().expect("i"), x.parse().expect("x"));
                assert_eq!(d[i * m + col], x, "W[{i}][{col}]");
                entries += 1;
            }
            _ => break,
        }
    }
    assert_eq!(entries, nnz);
    assert_eq!(d.iter().filter(|&&x| x != 0.0).count(), nnz);
}

#[test]
fn fc2d_siconos_w_symmetric_to_rounding() {
    // Storage 1 writes 25 significant digits: W is symmetric to the last
    // bit of its doubles or so; storage 2 (%g) to 6 digits.
    for (name, tol) in [(F71, 1e-14), (F237, 1e-14), (F667, 1e-6)] {
        let p = read_fc2d(&data(name)).unwrap_or_else(|e| panic!("{e}"));
        let a = p.max_asymmetry();
        assert!(a < tol, "{name}: max asymmetry {a:e}");
    }
}

/// `W r` computed from the dense matrix.
fn dense_apply(p: &Fc2dProblem, r: &[f64]) -> Vec<f64> {
    let m = 2 * p.contacts;
    let d = p.dense();
    (0..m)
        .map(|i| (0..m).map(|j| d[i * m + j] * r[j]).sum())
        .collect()
}

#[test]
fn fc2d_apply_is_dense_times_r() {
    for name in [F71, F237, F667] {
        let p = read_fc2d(&data(name)).unwrap_or_else(|e| panic!("{e}"));
        let r: Vec<f64> = (0..2 * p.contacts)
            .map(|k| (k as f64 * 0.7).sin())
            .collect();
        let (a, b) = (p.apply(&r), dense_apply(&p, &r));
        let scale = b.iter().fold(0.0f64, |s, x| s.max(x.abs()));
        for (k, (x, y)) in a.iter().zip(&b).enumerate() {
            assert!(
                (x - y).abs() <= 1e-12 * scale,
                "{name}: (W r)[{k}] = {x} against {y}"
            );
        }
    }
}

/// An unsymmetric W (so that W_NT and W_TN cannot be swapped unnoticed),
/// with block (0, 1) zero, row-major.
const W: [[f64; 4]; 4] = [
    [4.0, 1.0, 0.0, 0.0],
    [2.0, 5.0, 0.0, 0.0],
    [0.5, 0.25, 6.0, 3.0],
    [0.75, 0.125, 7.0, 8.0],
];
const TAIL: &str = "1 -2 3 -4\n0.3 0.6\n";

/// The problem of [`W`] in storage 0: the columns of W, one a line.
pub fn dense_text() -> String {
    format!("2\n2\n0\n4\n4\n4\t4\n4 2 0.5 0.75\n1 5 0.25 0.125\n0 0 6 7\n0 0 3 8\n{TAIL}")
}

/// The problem of [`W`] in storage 1.
pub fn sbm_text() -> String {
    format!(
        "2\n2\n1\n4\n4\n3\n2\n2\n2\t4\t\n2\t4\t\n3\n3\n0\t1\t3\t\n0\t0\t1\t\n\
         0\n4\n2\n1\n5\n1\n0.5\n0.75\n0.25\n0.125\n2\n6\n7\n3\n8\n{TAIL}1\n"
    )
}

/// The problem of [`W`] in storage 2, CSC.
pub fn csc_text() -> String {
    format!(
        "2\n2\n2\n4\n4\n2\nCSparse Version 3.1.9, May 4, 2016.  Copyright (c) Timothy A. Davis, 2006-2016\n\
         4-by-4, nzmax: 12 nnz: 12, 1-norm: 15\n\
         \x20   col 0 : locations 0 to 3\n      0 : 4\n      1 : 2\n      2 : 0.5\n      3 : 0.75\n\
         \x20   col 1 : locations 4 to 7\n      0 : 1\n      1 : 5\n      2 : 0.25\n      3 : 0.125\n\
         \x20   col 2 : locations 8 to 9\n      2 : 6\n      3 : 7\n\
         \x20   col 3 : locations 10 to 11\n      2 : 3\n      3 : 8\n{TAIL}"
    )
}

/// The problem of [`W`] in storage 2, triplet (entries in any order; one
/// split in two, summed).
pub fn triplet_text() -> String {
    format!(
        "2\n2\n2\n4\n4\n1\nCSparse Version 3.1.9, May 4, 2016.\ntriplet: 4-by-4, nzmax: 13 nnz: 13\n\
         3 3 : 8\n0 0 : 4\n1 0 : 2\n2 0 : 0.5\n3 0 : 0.75\n0 1 : 1\n1 1 : 5\n2 1 : 0.25\n3 1 : 0.125\n\
         2 2 : 6\n3 2 : 3\n3 2 : 4\n2 3 : 3\n{TAIL}"
    )
}

fn parse(text: &str) -> Result<Fc2dProblem, Fc2dError> {
    parse_fc2d(text, Path::new("x.dat"))
}

#[test]
fn fc2d_every_storage_reads_the_same_problem() {
    let want: Vec<f64> = W.iter().flatten().copied().collect();
    for (storage, t) in [
        (0, dense_text()),
        (1, sbm_text()),
        (2, csc_text()),
        (2, triplet_text()),
    ] {
        let p = parse(&t).unwrap_or_else(|e| panic!("storage {storage}: {e}"));
        assert_eq!(p.storage, storage);
        assert_eq!(p.dense(), want, "W in storage {storage}");
        assert_eq!(p.q, vec![1.0, -2.0, 3.0, -4.0]);
        assert_eq!(p.mu, vec![0.3, 0.6]);
        assert!(p.w.block(0, 1).is_none(), "a zero block is not stored");
        // |W_23 − W_32| = 4 over max |W| = 8.
        assert_eq!(p.max_asymmetry(), 0.5);
        assert_eq!(p.apply(&[1.0, 0.0, 0.0, 1.0]), vec![4.0, 2.0, 3.5, 8.75]);
    }
}
