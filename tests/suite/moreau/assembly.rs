//! The assembly of the contact LCPs: the block-sparse Delassus matrix
//! against the dense product, the driver's residual over compressed
//! columns, and recycled matrix buffers.

use super::{problems_at_start, problems_with};
use crate::common::{case_text, scenario};
use floebench::contact::problem::{spare_matrix_capacity, Friction};
use floebench::contact::NarrowOptions;
use floebench::lcp::{solve, SolveOptions};

#[test]
fn block_sparse_assembly_equals_the_dense_product() {
    // The Delassus block of every group of real packs (several floes, walls,
    // shores and coast as obstacles, with and without friction) against the
    // dense faer product over every row of H that the assembly used before,
    // and the assembly's own block (the block-sparse sum) against both.
    // Each entry is now one fused sum over its non-zero terms in row order;
    // the dense product splits the rows of H into cache blocks (of a size
    // chosen by the CPU's caches) and adds the blocks' sums, so on groups
    // larger than one block an entry may differ by one rounding. Small
    // groups (at most 64 rows of H, within any block) must agree bit for
    // bit, large ones to 1e-15 of sqrt(G_rr G_cc) (the scale of the terms);
    // the assembled LCP holds the block-sparse sum, bit for bit.
    let mut groups_checked = 0;
    let mut multi_floe = 0;
    let mut with_obstacle = 0;
    let mut coupled_entries = 0usize;
    let mut large_differing = 0usize;
    let mut impulse_entries = 0usize;
    let mut with_columns = 0usize;
    for (name, distance, frictionless) in [
        ("elastic_pool", 12.0, true),
        ("narrow_channel", 6.0, false),
        ("narrow_channel", 6.0, true),
        ("l_shaped_corner", 3.0, false),
        ("fields/bay_jam_200", 30.0, false),
        ("fields/bay_jam_200", 30.0, true),
    ] {
        let mut text = case_text(name);
        if frictionless {
            text = without_friction(&text);
        }
        let scn = scenario(&text);
        assert_eq!(scn.contact.friction == 0.0, frictionless, "{name}");
        let (lcps, _) = problems_at_start(&scn, distance);
        for lcp in &lcps {
            let reference = lcp.dense_delassus_reference();
            let sparse = lcp.block_sparse_delassus();
            let cols = if lcp.friction { 3 * lcp.m } else { lcp.m };
            let n = lcp.lcp().n;
            let small = 3 * lcp.floes.len() <= 64;
            for r in 0..cols {
                for c in 0..cols {
                    let want = reference[r * cols + c];
                    let got = sparse[r * cols + c];
                    assert_eq!(lcp.lcp().m[r * n + c].to_bits(), got.to_bits());
                    let bound = 1e-15 * (reference[r * cols + r] * reference[c * cols + c]).sqrt();
                    let same = got.to_bits() == want.to_bits();
                    assert!(
                        same || (!small && (got - want).abs() <= bound),
                        "{name}: entry ({r}, {c}) of a group of {} floes: {got:e} vs {want:e}",
                        lcp.floes.len()
                    );
                    large_differing += usize::from(!same);
                    coupled_entries += usize::from(r != c && want != 0.0);
                }
            }
            // The compressed columns built at assembly from the pattern
            // against a scan of every entry of the matrix.
            if let Some(same) = lcp.columns_match_a_full_scan() {
                assert!(
                    same,
                    "{name}: columns of a group of {} unknowns",
                    lcp.lcp().n
                );
                with_columns += 1;
            }
            // The impulses summed over each floe's own columns against the
            // row sums over every column, for a z with zeros and spread
            // magnitudes, and for the frictionless sub-problem.
            for sub in [lcp.clone(), lcp.frictionless()] {
                let z: Vec<f64> = (0..sub.lcp().n)
                    .map(|k| {
                        if k % 3 == 1 {
                            0.0
                        } else {
                            10f64.powi((k % 7) as i32 - 3) * (1.0 + k as f64)
                        }
                    })
                    .collect();
                let got = sub.impulses(&z);
                let want = sub.dense_impulses_reference(&z);
                assert_eq!(got.len(), want.len());
                for (g, w) in got.iter().zip(&want) {
                    for d in 0..3 {
                        // The same number (a zero may differ in sign).
                        assert!(g[d] == w[d], "{name}: {g:?} vs {w:?}");
                        assert!(g[d] == 0.0 || g[d].to_bits() == w[d].to_bits());
                    }
                    impulse_entries += g.iter().filter(|x| **x != 0.0).count();
                }
            }
            groups_checked += 1;
            multi_floe += usize::from(lcp.floes.len() >= 3);
            with_obstacle += usize::from(
                lcp.keys
                    .iter()
                    .any(|k| k.a >= scn.floes.len() || k.b >= scn.floes.len()),
            );
        }
    }
    assert_eq!(groups_checked, 6);
    assert!(
        multi_floe >= 5,
        "{multi_floe} groups of three floes or more"
    );
    assert!(
        with_obstacle >= 1,
        "{with_obstacle} groups touching an obstacle"
    );
    assert!(
        coupled_entries >= 100_000,
        "{coupled_entries} coupled entries"
    );
    assert!(with_columns >= 4, "{with_columns} groups with columns");
    assert!(
        impulse_entries >= 2_000,
        "{impulse_entries} non-zero impulse entries"
    );
    eprintln!("{large_differing} entries of the large groups differ by one rounding");
}

#[test]
fn the_driver_residual_of_large_lcps_equals_the_dense_compensated_sum() {
    // Above 64 unknowns the driver computes w = M z + q over the compressed
    // columns of M; its w must be the dense compensated sum's, bit for bit
    // (up to the sign of a zero), on real contact LCPs: the frictional
    // elastic pool (184 unknowns) and the frictionless bay jam (980).
    let pool = case_text("elastic_pool").replace("friction = 0.0", "friction = 0.3");
    let bay = without_friction(&case_text("fields/bay_jam_200"));
    let mut large = 0;
    for (text, distance) in [(pool, 12.0), (bay, 30.0)] {
        let (lcps, _) = problems_at_start(&scenario(&text), distance);
        for lcp in lcps.iter().filter(|l| l.lcp().n > 64) {
            // Every contact approaching (the packs start at rest or slow).
            let mut l = lcp.lcp().clone();
            for (j, q) in l.q.iter_mut().take(lcp.m).enumerate() {
                *q -= 0.1 * (1.0 + (j % 3) as f64);
            }
            let sol = solve(&l, &SolveOptions::default());
            assert!(sol.z.iter().filter(|z| **z != 0.0).count() >= 10);
            let dense = floebench::lcp::compute_w(&l.m, &l.q, &sol.z).unwrap();
            for (i, (a, b)) in sol.w.iter().zip(&dense).enumerate() {
                assert!(
                    a.to_bits() == b.to_bits() || (*a == 0.0 && *b == 0.0),
                    "n = {}, row {i}: {a:e} vs {b:e}",
                    lcp.lcp().n
                );
            }
            large += 1;
        }
    }
    assert!(large >= 2, "{large} large LCPs");
}

/// A case text with its `friction` line set to 0.
#[test]
fn recycled_matrix_buffers_assemble_the_same_lcps() {
    // A dropped large LCP zeroes the pattern of its matrix and leaves the
    // buffer for the next large assembly on its thread. The bay jam's
    // groups, with friction (merged and per point) and without, each
    // assembled on a fresh thread (no spare buffer) and all of them one
    // after another on one thread (each set on the buffer the previous set
    // left): the same matrices and right-hand sides, bit for bit.
    type Bits = Vec<(usize, Vec<u64>, Vec<u64>)>;
    fn assembled(frictionless: bool, layout: Friction) -> Bits {
        let mut text = case_text("fields/bay_jam_200");
        if frictionless {
            text = without_friction(&text);
        }
        let scn = scenario(&text);
        let (lcps, _) = problems_with(&scn, 30.0, layout, &NarrowOptions::default());
        lcps.iter()
            .map(|l| {
                let p = l.lcp();
                let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect();
                (p.n, bits(&p.m), bits(&p.q))
            })
            .collect()
    }
    let sets = [
        (false, Friction::Merged),
        (true, Friction::Merged),
        (false, Friction::PerPoint),
        (false, Friction::Merged),
    ];
    let fresh: Vec<Bits> = sets
        .iter()
        .map(|&(f, l)| {
            std::thread::spawn(move || {
                assert_eq!(spare_matrix_capacity(), 0, "a new thread has no spare");
                assembled(f, l)
            })
            .join()
            .unwrap()
        })
        .collect();
    let (reused, spares) = std::thread::spawn(move || {
        let mut spares = Vec::new();
        let reused: Vec<Bits> = sets
            .iter()
            .map(|&(f, l)| {
                let out = assembled(f, l);
                spares.push(spare_matrix_capacity());
                out
            })
            .collect();
        (reused, spares)
    })
    .join()
    .unwrap();
    // Large groups were assembled, and each set left a buffer.
    let large = fresh.iter().flatten().filter(|(n, _, _)| *n >= 41).count();
    assert!(large >= 4, "{large} large groups");
    assert!(spares.iter().all(|&c| c > 0), "spare capacities {spares:?}");
    for (k, (a, b)) in fresh.iter().zip(&reused).enumerate() {
        assert_eq!(a.len(), b.len(), "set {k}");
        for (g, (x, y)) in a.iter().zip(b).enumerate() {
            assert!(x == y, "set {k}, group {g} of {} unknowns", x.0);
        }
    }
}

fn without_friction(text: &str) -> String {
    text.lines()
        .map(|l| {
            if l.trim_start().starts_with("friction =") {
                "friction = 0.0"
            } else {
                l
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}
