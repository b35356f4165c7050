//! The predicted basis of a contact LCP (`lcp::predict`, docs/physics.md
//! §3.3 "Predicted basis"): block Gauss–Seidel on contact blocks, then the
//! driver's warm Lemke path from its guess, judged by the residual on the
//! original data.

use crate::common::{case_text, counter, run, scenario, with_formulation_table};
use crate::lemke::{family_lcp, stewart_trinkle, Family, FAMILIES};
use floebench::lcp::predict::{basis_mismatch, predict, solve_predicted, Blocks, PredictOptions};
use floebench::lcp::{residual, solve, Lcp, SolveOptions, SolveStatus, Strategy};
use floebench::rng::SplitMix64;

/// A random partition of `0..n` into blocks of 1 to 4 indices.
fn random_blocks(rng: &mut SplitMix64, n: usize) -> Blocks {
    let mut idx: Vec<usize> = (0..n).collect();
    for i in (1..n).rev() {
        idx.swap(i, (rng.next_u64() % (i as u64 + 1)) as usize);
    }
    let mut blocks = Vec::new();
    let mut k = 0;
    while k < n {
        let len = (1 + (rng.next_u64() % 4) as usize).min(n - k);
        blocks.push(idx[k..k + len].to_vec());
        k += len;
    }
    Blocks::new(n, blocks).expect("a partition")
}

/// The blocks of `lcp`: its contact blocks when it is a Stewart–Trinkle
/// LCP of `n / 4` contacts, else a random partition.
fn blocks_of(rng: &mut SplitMix64, family: Family, lcp: &Lcp) -> Blocks {
    if family == Family::StewartTrinkle {
        Blocks::contacts(lcp.n, lcp.n / 4).expect("4 unknowns per contact")
    } else {
        random_blocks(rng, lcp.n)
    }
}

#[test]
fn contact_blocks_partition_the_unknowns() {
    let b = Blocks::contacts(8, 2).expect("friction");
    assert_eq!(b.blocks(), &[vec![0, 2, 3, 6], vec![1, 4, 5, 7]]);
    let b = Blocks::contacts(3, 3).expect("frictionless");
    assert_eq!(b.blocks(), &[vec![0], vec![1], vec![2]]);
    assert_eq!(Blocks::contacts(7, 2), None, "neither 4m nor m");
    assert_eq!(Blocks::contacts(0, 0), None);
    assert_eq!(
        Blocks::new(3, vec![vec![0, 1], vec![1, 2]]),
        None,
        "overlap"
    );
    assert_eq!(Blocks::new(3, vec![vec![0, 1]]), None, "2 not covered");
    // A flush edge pair with merged friction is a block of 5 (λ_1, λ_2,
    // β̃⁺, β̃⁻, α); beyond MAX_BLOCK (8) a block is refused.
    assert!(
        Blocks::new(5, vec![(0..5).collect()]).is_some(),
        "block of 5"
    );
    assert_eq!(Blocks::new(9, vec![(0..9).collect()]), None, "block of 9");
    assert_eq!(
        Blocks::new(2, vec![vec![0], vec![2]]),
        None,
        "index out of range"
    );
}

#[test]
fn predicted_solves_are_accepted_only_within_the_tolerance() {
    // Random P-matrix, PSD, degenerate and Stewart–Trinkle LCPs, with
    // random blocks (contact blocks for Stewart–Trinkle): whatever the
    // prediction, the driver's answer is a solution, its residual
    // recomputed here from (M, q, z) within the tolerance, z finite and
    // ≥ 0; and a solve accepted from the prediction is a solution too.
    let mut rng = SplitMix64::new(0x5EED_9E0D_0001);
    let opts = SolveOptions::default();
    let popts = PredictOptions::default();
    let (mut total, mut hits) = (0, 0);
    for family in FAMILIES {
        for k in 0..25 {
            let n = 2 + (rng.next_u64() % 40) as usize;
            let lcp = family_lcp(&mut rng, family, n);
            let blocks = blocks_of(&mut rng, family, &lcp);
            let (sol, p) = solve_predicted(&lcp, &opts, &blocks, &popts);
            let label = format!("{family:?} {k} (n = {})", lcp.n);
            let p = p.expect("finite data of the right size: a prediction");
            assert!(p.sweeps >= 1 && p.sweeps <= popts.max_sweeps, "{label}");
            assert!(
                p.guess.z.iter().all(|v| v.is_finite() && *v >= 0.0),
                "{label}"
            );
            assert!(sol.status.is_solved(), "{label}: {:?}", sol.attempts);
            assert!(sol.z.iter().all(|v| v.is_finite() && *v >= 0.0), "{label}");
            let r = residual(&lcp.m, &lcp.q, &sol.z);
            assert!(r <= opts.tolerance, "{label}: residual {r:e}");
            total += 1;
            if sol.accepted_by == Some(Strategy::WarmLemke) {
                hits += 1;
            }
        }
    }
    eprintln!("{hits} of {total} accepted from the predicted basis");
    assert!(hits > 0, "the predicted path was exercised");
}

#[test]
fn the_prediction_of_a_p_matrix_lcp_is_its_solution_basis() {
    // Diagonally dominant P-matrices (unique solution; block Gauss–Seidel
    // converges for strictly diagonally dominant M): the predicted basis
    // is exactly the solution's on every non-degenerate index, and the
    // warm Lemke path from it is accepted after at most a few pivots.
    let mut rng = SplitMix64::new(0x5EED_9E0D_0002);
    let opts = SolveOptions::default();
    for k in 0..20 {
        let n = 20 + (rng.next_u64() % 60) as usize;
        let mut m: Vec<f64> = (0..n * n).map(|_| rng.range(-1.0, 1.0)).collect();
        for i in 0..n {
            let off: f64 = (0..n).filter(|&j| j != i).map(|j| m[i * n + j].abs()).sum();
            m[i * n + i] = 1.5 * off + 1.0;
        }
        let q: Vec<f64> = (0..n).map(|_| rng.range(-1.0, 1.0)).collect();
        let lcp = Lcp::new(n, m, q).expect("sizes");
        let blocks = random_blocks(&mut rng, n);
        let cold = solve(&lcp, &opts);
        assert_eq!(cold.status, SolveStatus::Solved);
        let p = predict(&lcp, &blocks, &PredictOptions::default()).expect("prediction");
        let (wrong, _) = basis_mismatch(&p.guess.basic, &cold.z, &cold.w, 1e-12);
        assert_eq!(wrong, 0, "problem {k} (n = {n}): {wrong} wrong");
        let (sol, _) = solve_predicted(&lcp, &opts, &blocks, &PredictOptions::default());
        assert_eq!(sol.accepted_by, Some(Strategy::WarmLemke), "problem {k}");
        assert!(sol.pivots <= 2, "problem {k}: {} pivots", sol.pivots);
    }
}

#[test]
fn the_predicted_guess_saves_pivots_on_a_large_stewart_trinkle_lcp() {
    // 150 bodies, 180 contacts with friction (720 unknowns), each contact
    // coupled only with those sharing a body: the solve from the predicted
    // basis takes far fewer pivots than the cold solve. This fails if the
    // guess is not used (the same path as cold) or is poor.
    let mut rng = SplitMix64::new(0x5EED_9E0D_0003);
    let opts = SolveOptions::default();
    let mut checked = 0;
    for k in 0..3 {
        let lcp = stewart_trinkle(&mut rng, 150, 180, 0.7);
        let blocks = Blocks::contacts(lcp.n, 180).expect("contact blocks");
        let cold = solve(&lcp, &opts);
        let (sol, p) = solve_predicted(&lcp, &opts, &blocks, &PredictOptions::default());
        let p = p.expect("prediction");
        let label = format!("problem {k}");
        assert!(sol.status.is_solved(), "{label}: {:?}", sol.attempts);
        let r = residual(&lcp.m, &lcp.q, &sol.z);
        assert!(r <= opts.tolerance, "{label}: residual {r:e}");
        eprintln!(
            "{label}: {} sweeps (residual {:.1e}), {} pivots from the prediction ({:?}), {} cold",
            p.sweeps, p.residual, sol.pivots, sol.accepted_by, cold.pivots
        );
        if cold.status.is_solved() && cold.pivots >= 100 {
            assert!(
                sol.pivots * 4 <= cold.pivots,
                "{label}: {} pivots predicted against {} cold",
                sol.pivots,
                cold.pivots
            );
            checked += 1;
        }
    }
    assert!(checked >= 2, "only {checked} problems compared");
}

#[test]
fn the_prediction_of_a_frictional_contact_lcp_of_a_case_is_within_a_few_indices() {
    // The elastic pool's contact problems at t = 0 with friction 0.3 (12 m
    // detection distance: a group of 46 contacts, 184 unknowns, and smaller
    // ones), row-scaled as the contact solver solves them: the predicted
    // basis differs from the basis of the solution on at most 2 of the
    // non-degenerate indices of each problem, and the solve from it is a
    // solution.
    let text = case_text("elastic_pool");
    let scn = scenario(&text.replace("friction = 0.0", "friction = 0.3"));
    let (lcps, _) = crate::moreau::problems_at_start(&scn, 12.0);
    assert!(lcps.iter().any(|l| l.m >= 20), "a large group");
    let opts = SolveOptions::default();
    for (k, c) in lcps.iter().enumerate() {
        // The assembly already writes the Coulomb rows as the solver solves
        // them.
        let lcp = c.lcp();
        assert!(c.friction);
        let blocks = Blocks::contacts(lcp.n, c.m).expect("contact blocks");
        let (sol, p) = solve_predicted(lcp, &opts, &blocks, &PredictOptions::default());
        let p = p.expect("prediction");
        assert!(sol.status.is_solved(), "group {k}: {:?}", sol.attempts);
        let r = residual(&lcp.m, &lcp.q, &sol.z);
        assert!(r <= opts.tolerance, "group {k}: residual {r:e}");
        let qn = lcp.q.iter().map(|v| v * v).sum::<f64>().sqrt();
        let (wrong, ties) = basis_mismatch(&p.guess.basic, &sol.z, &sol.w, opts.tolerance * qn);
        eprintln!(
            "group {k} (n = {}): {} sweeps, {wrong} wrong, {ties} degenerate, {} pivots",
            lcp.n, p.sweeps, sol.pivots
        );
        assert!(wrong <= 2, "group {k}: {wrong} wrong indices");
    }
}

#[test]
fn predict_from_setting_solves_from_the_prediction_in_both_lcp_formulations() {
    // `[formulation.<name>] predict_from = 1` reaches the contact solver of
    // event-driven and moreau: every LCP is started from a predicted basis
    // and counted; the run keeps every LCP solved. Without the key the
    // counters are not declared.
    let text = case_text("sliding_floe");
    for name in ["event-driven", "moreau"] {
        let plain = run(&scenario(&text), name);
        assert!(
            plain
                .summary
                .counters
                .by_name("lcp_predict_solves")
                .is_err(),
            "{name}: not declared when off"
        );
        let table = with_formulation_table(&text, name, "predict_from = 1");
        let predicted = run(&scenario(&table), name);
        let solves = counter(&predicted, "lcp_predict_solves");
        assert!(solves > 0.0, "{name}: {solves} predicted solves");
        assert_eq!(counter(&predicted, "lcp_failed"), 0.0, "{name}");
        let setting = predicted.summary.settings.get_text("predict_from");
        assert_eq!(setting, Some("1"), "{name}");
    }
}
