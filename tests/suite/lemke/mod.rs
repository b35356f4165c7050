//! Tests of the LCP module: Lemke's method, the robust driver and dumps.
//!
//! Random inputs come from the crate's seeded SplitMix64 generator, so
//! every run sees the same problems. Figures (pivots, time) are printed with
//! `cargo test --release -- --nocapture`.
//!
//! This file holds what the submodules share: the problem generators
//! (random P-matrix, PSD and Stewart–Trinkle LCPs, the path-test
//! families), a brute-force reference solver and the readers of the
//! committed dumps of `tests/data`. The tests are in the submodules, one
//! topic each.

mod cold_attempts;
mod contact_lcps;
mod copositive;
mod degenerate;
mod direct_exits;
mod dumps;
mod failures;
mod float_range;
mod interrupt;
mod p_matrix;
mod paths;
mod residual;
mod revised;
mod small_problems;
mod warm_lemke;
mod warm_start;
mod workspace;

use crate::common::lcp_violation;
use floebench::lcp::{compute_w, Lcp, LcpDump};
use floebench::rng::SplitMix64;

fn random_matrix(rng: &mut SplitMix64, n: usize) -> Vec<f64> {
    (0..n * n).map(|_| rng.range(-1.0, 1.0)).collect()
}

/// Symmetric positive definite: A Aᵀ / n + δ I, δ in [0.01, 1].
fn spd(rng: &mut SplitMix64, n: usize) -> Vec<f64> {
    let a = random_matrix(rng, n);
    let delta = 0.01 + 0.99 * rng.uniform();
    let mut m = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            let s: f64 = (0..n).map(|k| a[i * n + k] * a[j * n + k]).sum();
            m[i * n + j] = s / n as f64 + if i == j { delta } else { 0.0 };
        }
    }
    m
}

/// Non-symmetric positive definite (hence P): SPD + σ (S − Sᵀ), σ in [0, 2].
fn nonsym_pd(rng: &mut SplitMix64, n: usize) -> Vec<f64> {
    let mut m = spd(rng, n);
    let s = random_matrix(rng, n);
    let sigma = 2.0 * rng.uniform();
    for i in 0..n {
        for j in 0..n {
            m[i * n + j] += sigma * (s[i * n + j] - s[j * n + i]);
        }
    }
    m
}

/// Strictly row diagonally dominant with positive diagonal and random-sign
/// off-diagonal entries (a non-symmetric P-matrix).
fn diag_dominant(rng: &mut SplitMix64, n: usize) -> Vec<f64> {
    let mut m = random_matrix(rng, n);
    for i in 0..n {
        let off: f64 = (0..n).filter(|&j| j != i).map(|j| m[i * n + j].abs()).sum();
        m[i * n + i] = off * (1.05 + rng.uniform()) + 0.1;
    }
    m
}

fn random_q(rng: &mut SplitMix64, n: usize) -> Vec<f64> {
    (0..n).map(|_| rng.range(-1.0, 1.0)).collect()
}

/// Asserts that `z` solves LCP(M, q) up to a tolerance relative to the
/// magnitudes in `w = M z + q` ([`lcp_violation`]).
fn assert_valid_solution(m: &[f64], q: &[f64], z: &[f64], rel_tol: f64, label: &str) {
    if let Some(v) = lcp_violation(m, q, z, rel_tol) {
        panic!("{label}: {v}");
    }
}

/// Dense Gaussian elimination with partial pivoting (test-local reference).
fn solve_dense(mut a: Vec<f64>, mut b: Vec<f64>, k: usize) -> Option<Vec<f64>> {
    for c in 0..k {
        let p = (c..k).max_by(|&x, &y| a[x * k + c].abs().total_cmp(&a[y * k + c].abs()))?;
        if a[p * k + c].abs() < 1e-13 {
            return None;
        }
        for j in 0..k {
            a.swap(c * k + j, p * k + j);
        }
        b.swap(c, p);
        for r in c + 1..k {
            let f = a[r * k + c] / a[c * k + c];
            for j in c..k {
                a[r * k + j] -= f * a[c * k + j];
            }
            b[r] -= f * b[c];
        }
    }
    for r in (0..k).rev() {
        let s: f64 = (r + 1..k).map(|j| a[r * k + j] * b[j]).sum();
        b[r] = (b[r] - s) / a[r * k + r];
    }
    Some(b)
}

/// Solution of a small LCP by enumerating all 2ⁿ complementary bases
/// (independent of Lemke). Returns the first solution found.
fn brute_force(m: &[f64], q: &[f64]) -> Option<Vec<f64>> {
    let n = q.len();
    for mask in 0u32..(1 << n) {
        let idx: Vec<usize> = (0..n).filter(|&i| mask & (1 << i) != 0).collect();
        let k = idx.len();
        let mut a = vec![0.0; k * k];
        for (r, &i) in idx.iter().enumerate() {
            for (c, &j) in idx.iter().enumerate() {
                a[r * k + c] = m[i * n + j];
            }
        }
        let b: Vec<f64> = idx.iter().map(|&i| -q[i]).collect();
        let Some(x) = solve_dense(a, b, k) else {
            continue;
        };
        let mut z = vec![0.0; n];
        for (r, &i) in idx.iter().enumerate() {
            z[i] = x[r];
        }
        let w = compute_w(m, q, &z).ok()?;
        // 1e-9: well-conditioned small systems are solved to ~1e-14.
        if z.iter().all(|&v| v >= -1e-9) && w.iter().all(|&v| v >= -1e-9) {
            return Some(z.iter().map(|&v| v.max(0.0)).collect());
        }
    }
    None
}

/// A feasible copositive-plus LCP of size `n`: `M = B Bᵀ + (S − Sᵀ)` with
/// `B` of `rank` columns (positive semidefinite, non-symmetric) and
/// `q = w* − M z*` for a random complementary pair `(z*, w*) ≥ 0`.
fn feasible_psd(rng: &mut SplitMix64, n: usize, rank: usize) -> (Vec<f64>, Vec<f64>) {
    let b: Vec<f64> = (0..n * rank).map(|_| rng.range(-1.0, 1.0)).collect();
    let s = random_matrix(rng, n);
    let mut m = vec![0.0; n * n];
    for i in 0..n {
        for j in 0..n {
            let bb: f64 = (0..rank).map(|t| b[i * rank + t] * b[j * rank + t]).sum();
            m[i * n + j] = bb + (s[i * n + j] - s[j * n + i]);
        }
    }
    let (mut zs, mut ws) = (vec![0.0; n], vec![0.0; n]);
    for i in 0..n {
        match rng.next_u64() % 3 {
            0 => zs[i] = rng.uniform(),
            1 => ws[i] = rng.uniform(),
            _ => {}
        }
    }
    let mz = compute_w(&m, &vec![0.0; n], &zs).expect("sizes");
    let q = (0..n).map(|i| ws[i] - mz[i]).collect();
    (m, q)
}

/// The dumps of `tests/data/lcp` (39 LCPs sampled from `floebench run
/// --dump-lcp` on field_200_coast, narrow_channel and elastic_pool, chosen
/// for sizes 4–144 and for the hard cases of the solver before the
/// condensed-tableau version: 29 solved only by a fallback, 2 failed).
fn corpus() -> Vec<(String, Lcp)> {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/lcp");
    let mut files: Vec<_> = std::fs::read_dir(&dir)
        .expect("tests/data/lcp")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.extension().is_some_and(|x| x == "json"))
        .collect();
    files.sort();
    files
        .iter()
        .map(|f| {
            let d = LcpDump::read(f).expect("committed dump reads");
            (
                f.file_name().expect("name").to_string_lossy().into_owned(),
                d.to_lcp().expect("square"),
            )
        })
        .collect()
}

/// The LCP of a committed dump, by its path under `tests/data/`.
fn committed_dump(path: &str) -> Lcp {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("tests/data")
        .join(path);
    LcpDump::read(&path)
        .expect("read")
        .to_lcp()
        .expect("an LCP")
}

/// A Stewart–Trinkle contact LCP assembled as `contact::problem` does: `nb`
/// rigid bodies (3 coordinates each, mass and inertia in [0.5, 2]), `m`
/// contacts between random pairs or a body and a fixed wall, the Delassus
/// matrix `G = Hᵀ M⁻¹ H` of `H = (J, D)` scaled by its mean diagonal, the
/// unknowns `(λ, β⁺β⁻…, α)`, the rows `γ = … + E α` and the Coulomb rows
/// `μ λ − Eᵀ β` in velocity units (scaled by `G_jj`).
pub(crate) fn stewart_trinkle(rng: &mut SplitMix64, nb: usize, m: usize, mu: f64) -> Lcp {
    let cols = 3 * m;
    let mut h = vec![0.0; 3 * nb * cols];
    for j in 0..m {
        let a = (rng.next_u64() % nb as u64) as usize;
        let b = if nb == 1 || rng.uniform() < 0.3 {
            None // a fixed wall
        } else {
            Some((a + 1 + (rng.next_u64() % (nb as u64 - 1)) as usize) % nb)
        };
        let th = rng.range(0.0, std::f64::consts::TAU);
        let (nx, ny) = (th.cos(), th.sin());
        let (tx, ty) = (-ny, nx);
        for (body, sign) in [(Some(a), -1.0), (b, 1.0)] {
            let Some(body) = body else { continue };
            let (rx, ry) = (rng.range(-1.0, 1.0), rng.range(-1.0, 1.0));
            let jn = [nx, ny, rx * ny - ry * nx];
            let jt = [tx, ty, rx * ty - ry * tx];
            for d in 0..3 {
                let r = 3 * body + d;
                h[r * cols + j] += sign * jn[d];
                h[r * cols + m + 2 * j] += sign * jt[d];
                h[r * cols + m + 2 * j + 1] -= sign * jt[d];
            }
        }
    }
    let minv: Vec<f64> = (0..nb)
        .flat_map(|_| {
            let mass = rng.range(0.5, 2.0);
            let inertia = rng.range(0.5, 2.0);
            [1.0 / mass, 1.0 / mass, 1.0 / inertia]
        })
        .collect();
    let mut g = vec![0.0; cols * cols];
    for r in 0..cols {
        for c in 0..cols {
            g[r * cols + c] = (0..3 * nb)
                .map(|k| h[k * cols + r] * minv[k] * h[k * cols + c])
                .sum();
        }
    }
    let scale = (0..cols).map(|k| g[k * cols + k]).sum::<f64>() / cols as f64;
    let vfree: Vec<f64> = (0..3 * nb).map(|_| rng.range(-1.0, 1.0)).collect();
    let n = 4 * m;
    let mut mat = vec![0.0; n * n];
    let mut q = vec![0.0; n];
    for r in 0..cols {
        for c in 0..cols {
            mat[r * n + c] = g[r * cols + c] / scale;
        }
        q[r] = (0..3 * nb).map(|k| h[k * cols + r] * vfree[k]).sum();
    }
    for j in 0..m {
        mat[(m + 2 * j) * n + 3 * m + j] = 1.0;
        mat[(m + 2 * j + 1) * n + 3 * m + j] = 1.0;
        let s = 3 * m + j;
        let gjj = mat[j * n + j];
        mat[s * n + j] = mu * gjj;
        mat[s * n + m + 2 * j] = -gjj;
        mat[s * n + m + 2 * j + 1] = -gjj;
    }
    Lcp::new(n, mat, q).expect("sizes")
}

/// The problem families of the path tests.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(crate) enum Family {
    /// Non-symmetric positive definite or diagonally dominant: P-matrix,
    /// unique solution.
    PMatrix,
    /// `B Bᵀ + (S − Sᵀ)`, rank-deficient: copositive-plus, feasible by
    /// construction, solutions not unique.
    Psd,
    /// Integer P-matrices with `q ∈ {−1, 0, 1}`: ties and zero right-hand
    /// sides everywhere, unique solution.
    Degenerate,
    /// Stewart–Trinkle contact LCPs with friction.
    StewartTrinkle,
}

/// Every family of the path tests.
pub(crate) const FAMILIES: [Family; 4] = [
    Family::PMatrix,
    Family::Psd,
    Family::Degenerate,
    Family::StewartTrinkle,
];

/// A feasible LCP of `family` with about `n` unknowns.
pub(crate) fn family_lcp(rng: &mut SplitMix64, family: Family, n: usize) -> Lcp {
    match family {
        Family::PMatrix => {
            let m = if rng.uniform() < 0.5 {
                nonsym_pd(rng, n)
            } else {
                diag_dominant(rng, n)
            };
            Lcp::new(n, m, random_q(rng, n)).expect("sizes")
        }
        Family::Psd => {
            let rank = 1 + (rng.next_u64() % n as u64) as usize;
            let (m, q) = feasible_psd(rng, n, rank);
            Lcp::new(n, m, q).expect("sizes")
        }
        Family::Degenerate => {
            let mut m: Vec<f64> = (0..n * n)
                .map(|_| (rng.next_u64() % 3) as f64 - 1.0)
                .collect();
            for i in 0..n {
                let off: f64 = (0..n).filter(|&j| j != i).map(|j| m[i * n + j].abs()).sum();
                m[i * n + i] = off + 1.0;
            }
            let q = (0..n).map(|_| (rng.next_u64() % 3) as f64 - 1.0).collect();
            Lcp::new(n, m, q).expect("sizes")
        }
        Family::StewartTrinkle => {
            let nb = 1 + n / 8;
            let contacts = 1 + (rng.next_u64() % (3 * nb as u64)) as usize;
            let mu = [0.3, 0.7, 1.5][(rng.next_u64() % 3) as usize];
            stewart_trinkle(rng, nb, contacts, mu)
        }
    }
}
