//! Malformed 2D frictional contact problem files (`src/model/fc2d`): each
//! refused with one line naming the file, the line and what was expected;
//! none panics, whatever token is changed or wherever the file is cut.

use crate::common::guarded;
use crate::fc2d::{csc_text, dense_text, sbm_text, triplet_text};
use floebench::model::fc2d::{parse_fc2d, read_fc2d, Fc2dError, Fc2dProblem};
use std::path::Path;

fn parse(text: &str) -> Result<Fc2dProblem, Fc2dError> {
    parse_fc2d(text, Path::new("x.dat"))
}

/// `text` with line `l` (1-based) replaced by `new`.
fn with_line(text: &str, l: usize, new: &str) -> String {
    let mut lines: Vec<&str> = text.lines().collect();
    lines[l - 1] = new;
    lines.join("\n") + "\n"
}

/// `text` cut after line `l`.
fn cut_after(text: &str, l: usize) -> String {
    text.lines().take(l).collect::<Vec<_>>().join("\n") + "\n"
}

/// Checks that `text` is refused at `line` with a message holding `want`.
fn refused(what: &str, text: &str, line: usize, want: &str) -> Result<(), String> {
    let r = guarded(what, || parse(text))?;
    let e = match r {
        Ok(_) => return Err(format!("{what}: read without an error")),
        Err(e) => e,
    };
    let msg = e.to_string();
    let ok = e.line == line
        && msg.starts_with(&format!("x.dat:{line}: "))
        && msg.contains("expected")
        && msg.contains(want)
        && !msg.contains('\n');
    if ok {
        Ok(())
    } else {
        Err(format!(
            "{what}: line {line}, \"{want}\" wanted; got: {msg}"
        ))
    }
}

#[test]
fn fc2d_bad_header_and_sparse_block_refused() {
    let s = sbm_text();
    let cases: &[(usize, &str, &str)] = &[
        (1, "3", "the dimension d = 2"),
        (1, "2x", "the dimension d = 2"),
        (2, "-2", "the number of contacts"),
        (2, "1e18", "the number of contacts"),
        (2, "1000000000000000000", "hold at most"),
        (2, "0", "nc ≥ 1"),
        (3, "abc", "storage: 0, 1 or 2"),
        (4, "6", "size0 = 2 nc = 4"),
        (5, "2", "size1 = 2 nc = 4"),
        (6, "1000000000000000000", "hold at most"),
        (6, "-3", "nbblocks"),
        (7, "3", "nb0 = 2"),
        (9, "2 3", "cum0[1] = 4"),
        (10, "4 6", "cum1[0] = 2"),
        (11, "4", "filled1 = nc + 1 = 3"),
        (12, "2", "filled2 = nbblocks = 3"),
        (13, "1 1 3", "rowptr[0] = 0"),
        (13, "0 2 1", "rowptr[2] = nbblocks = 3"),
        (13, "0 4 3", "rowptr[1] between"),
        (14, "0 0 2", "a block column below 2"),
        (15, "1", "the block number 0"),
        (17, "nan", "a finite real"),
        (18, "inf", "a finite real"),
        (21, "1e999", "a finite real"),
        (30, "1 -2 1e999 -4", "a finite real (q"),
        (31, "0.3 -0.6", "mu ≥ 0 (2 of 2)"),
    ];
    let mut defects: Vec<String> = Vec::new();
    for &(l, new, want) in cases {
        let what = format!("storage 1, line {l} \"{new}\"");
        defects.extend(refused(&what, &with_line(&s, l, new), l, want).err());
    }
    // nbblocks one too many: refused by the bound on the tokens left, or
    // (tokens added after mu) at filled2.
    defects.extend(
        refused(
            "nbblocks 4",
            &with_line(&s, 6, "4"),
            6,
            "the 36 tokens left hold at most 3",
        )
        .err(),
    );
    let more = with_line(&s, 6, "4") + "0 0 0 0 0 0\n";
    defects.extend(refused("nbblocks 4, more", &more, 12, "filled2 = nbblocks = 4").err());
    // Cut after q: too few tokens for the blocks with q and mu after them.
    defects.extend(
        refused(
            "no mu",
            &cut_after(&s, 30),
            6,
            "the 33 tokens left hold at most 2",
        )
        .err(),
    );
    // Cut at the start: the end of the file.
    defects.extend(refused("cut", "2\n2\n", 2, "expected the number of contacts nc").err());
    defects.extend(refused("empty", "", 1, "end of file: expected the dimension d = 2").err());
    assert!(defects.is_empty(), "{}", defects.join("\n"));
}

#[test]
fn fc2d_bad_dense_and_csparse_refused() {
    let (d, c, t) = (dense_text(), csc_text(), triplet_text());
    let cases: &[(&String, usize, &str, &str)] = &[
        (&d, 6, "4 5", "size1 = 4 again"),
        (&d, 8, "1 5 0.25 NaN", "a finite real (W"),
        (&c, 6, "3", "3 (CSR) is not read"),
        (&c, 6, "7", "origin: 1 triplet, 2 CSC"),
        (&c, 7, "Version 3", "CSparse Version"),
        (
            &c,
            8,
            "5-by-5, nzmax: 12 nnz: 12, 1-norm: 15",
            "\"4-by-4,\"",
        ),
        (
            &c,
            8,
            "4-by-4, nzmax: 12 nnz: 1000000000000000000, 1-norm: 15",
            "hold at most",
        ),
        (
            &c,
            8,
            "4-by-4, nzmax: 12 nnz: 12, 1-norm: inf",
            "the 1-norm",
        ),
        (&c, 9, "col 1 : locations 0 to 3", "the column 0"),
        (
            &c,
            9,
            "col 0 : locations 0 to 12",
            "the last location of column 0",
        ),
        (&c, 10, "0 : x", "a finite real (an entry of W)"),
        (&c, 12, "4 : 0.5", "a row index below 4 (column 0)"),
        (
            &c,
            14,
            "col 1 : locations 5 to 7",
            "the first location 4 of column 1",
        ),
        (&t, 8, "4-by-4, nzmax: 13 nnz: 13", "\"triplet:\""),
        (&t, 9, "4 3 : 8", "a row index below 4"),
        (&t, 9, "3 9 : 8", "a column index below 4"),
        (&t, 9, "3 3 ; 8", "\":\" (i j : x)"),
    ];
    let mut defects: Vec<String> = Vec::new();
    for &(text, l, new, want) in cases {
        let what = format!("line {l} \"{new}\"");
        defects.extend(refused(&what, &with_line(text, l, new), l, want).err());
    }
    // Repeated triplet entries whose sum overflows: refused at q.
    let big = with_line(&with_line(&t, 19, "3 2 : 1e308"), 20, "3 2 : 1e308");
    defects.extend(refused("sum overflows", &big, 22, "repeats sum to finite reals").err());
    // An entry of 3 tokens (":" missing): nnz no longer fits the tokens.
    let fewer = with_line(&t, 9, "3 3 8");
    defects.extend(
        refused(
            "3 3 8",
            &fewer,
            8,
            "nnz; the 57 tokens left hold at most 12",
        )
        .err(),
    );
    // A dense W one column short: refused before it is read, at its first
    // token.
    let short = format!(
        "{}\n{}",
        cut_after(&d, 9),
        d.lines().skip(10).collect::<Vec<_>>().join("\n")
    );
    defects.extend(
        refused(
            "dense short",
            &short,
            7,
            "4×4 reals of a dense W, then 6 of q and mu; only 18 tokens left",
        )
        .err(),
    );
    // nnz larger than the columns hold (tokens after mu to pass the bound
    // on nnz): refused at q.
    let more = with_line(&c, 8, "4-by-4, nzmax: 12 nnz: 13, 1-norm: 15") + "0 0 0 0\n";
    defects.extend(refused("nnz 13", &more, 25, "nnz = 13 entries; the columns hold 12").err());
    assert!(defects.is_empty(), "{}", defects.join("\n"));
}

#[test]
fn fc2d_bad_error_reads_as_one_line() {
    let e = parse(&with_line(&sbm_text(), 3, "abc")).expect_err("storage abc");
    assert_eq!(
        e.to_string(),
        "x.dat:3: token \"abc\": expected an integer (storage: 0, 1 or 2)"
    );
    let e = read_fc2d(Path::new("/nonexistent/y.dat")).expect_err("no file");
    assert!(
        e.to_string()
            .starts_with("/nonexistent/y.dat: expected a readable text file"),
        "{e}"
    );
}

#[test]
fn fc2d_tokens_after_mu_ignored() {
    let p = parse(&(sbm_text() + "anything 1e999 -1\n")).unwrap_or_else(|e| panic!("{e}"));
    assert_eq!(p.mu, vec![0.3, 0.6]);
}

#[test]
fn fc2d_bad_no_panic_on_any_cut_or_token() {
    let mut defects: Vec<String> = Vec::new();
    for base in [dense_text(), sbm_text(), csc_text(), triplet_text()] {
        // Every cut: refused whenever it leaves out a whole token of mu.
        let mu_start = base.find("0.3 0.6").expect("mu");
        for cut in (0..base.len()).filter(|&k| base.is_char_boundary(k)) {
            match guarded("cut", || parse(&base[..cut])) {
                Err(d) => defects.push(d),
                Ok(Ok(_)) if cut < mu_start + 4 => defects.push(format!("cut at {cut} read")),
                Ok(_) => {}
            }
        }
        // Every token replaced by each of a few bad ones.
        let toks: Vec<&str> = base.split_whitespace().collect();
        for k in 0..toks.len() {
            for bad in ["-1", "x", "1e300", "nan", "99999999999999999999", "0", "4"] {
                let mut t = toks.clone();
                t[k] = bad;
                if let Err(d) = guarded("token", || parse(&t.join(" "))) {
                    defects.push(format!("token {k} → {bad}: {d}"));
                }
            }
        }
    }
    assert!(defects.is_empty(), "{}", defects.join("\n"));
}

#[test]
fn fc2d_bad_siconos_file_cut_refused() {
    let text = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR"))
            .join("tests/data/fc2d/FrictionContactProblem00071.dat"),
    )
    .expect("test data");
    // Cut anywhere before its last line of numbers (mu): refused, not a panic.
    let mu_line = text.rfind("9.000000000000000222044605e-01").expect("mu");
    for k in 1..40 {
        let cut = mu_line * k / 40;
        let cut = (cut..).find(|&c| text.is_char_boundary(c)).unwrap_or(cut);
        match guarded("cut", || parse(&text[..cut])) {
            Ok(Err(e)) => assert!(e.to_string().contains("expected"), "{e}"),
            Ok(Ok(_)) => panic!("cut at {cut} read"),
            Err(d) => panic!("{d}"),
        }
    }
}
