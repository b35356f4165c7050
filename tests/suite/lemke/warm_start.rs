//! The warm start of the driver and of the contact solver: never accepted
//! on a non-solution, hits on the same contacts, the `warm_start` setting of
//! both LCP formulations, and `floebench run --warm-check`.

use crate::common::tempdir;
use floebench::lcp::{
    residual, solve_warm_with, solve_with, BasisGuess, Lcp, SolveCounters, SolveOptions,
    SolveStatus, Workspace,
};

#[test]
fn a_warm_start_never_accepts_a_non_solution() {
    // Infeasible LCPs (1×1 with m = 0, q < 0; the PSD [[1, −1], [−1, 1]]
    // with q = (−1, −1), whose two rows sum to w1 + w2 = −2) and a
    // non-finite starting point: every path fails cleanly, z finite ≥ 0.
    let mut ws = Workspace::default();
    let opts = SolveOptions {
        warm_lemke: true,
        ..SolveOptions::default()
    };
    let cases = [
        Lcp::new(1, vec![0.0], vec![-1.0]).expect("sizes"),
        Lcp::new(2, vec![1.0, -1.0, -1.0, 1.0], vec![-1.0, -1.0]).expect("sizes"),
    ];
    for lcp in &cases {
        let cold = solve_with(&mut ws, lcp, &opts);
        assert_eq!(cold.status, SolveStatus::Failed, "{lcp:?}");
        for basic in [vec![true; lcp.n], vec![false; lcp.n]] {
            let guess = BasisGuess {
                basic,
                z: vec![f64::NAN; lcp.n],
            };
            let s = solve_warm_with(&mut ws, lcp, &opts, &guess);
            assert_eq!(s.status, SolveStatus::Failed, "{lcp:?}: {s:?}");
            assert!(!s.warm.expect("tried").accepted);
            assert!(s.z.iter().all(|v| v.is_finite() && *v >= 0.0));
        }
    }
    // Counted: a hit and a miss.
    let lcp = Lcp::new(2, vec![2.0, 1.0, 1.0, 2.0], vec![-1.0, -1.0]).expect("sizes");
    let mut counters = SolveCounters::default();
    let hit = BasisGuess {
        basic: vec![true, true],
        z: vec![0.0, 0.0],
    };
    counters.record(&solve_warm_with(&mut ws, &lcp, &opts, &hit));
    let miss = BasisGuess {
        basic: vec![false, false],
        z: vec![0.0, 0.0],
    };
    let s = solve_warm_with(
        &mut ws,
        &lcp,
        &SolveOptions {
            warm_solves: 1,
            ..opts.clone()
        },
        &miss,
    );
    counters.record(&s);
    assert_eq!(
        (counters.warm_hits, counters.warm_misses),
        (1, 1),
        "{counters:?}"
    );
}

#[test]
fn contact_solver_warm_start_hits_on_the_same_contacts() {
    // The elastic pool's contact problems at t = 0 with friction 0.3 (12 m
    // detection distance: one group of 46 contacts and smaller ones),
    // solved twice at successive times: the second solve of each finds the
    // first one's basis by contact identity and is accepted without a
    // Lemke pivot, with a residual within the tolerance on the (row-scaled)
    // LCP that the solver solves. Without warm start nothing is tried.
    use floebench::formulation::contact_solver::{
        ContactSolver, SolverKind, LCP_WARM_HITS, LCP_WARM_MISSES,
    };
    let text = crate::common::case_text("elastic_pool");
    let scn = crate::common::scenario(&text.replace("friction = 0.0", "friction = 0.3"));
    assert_eq!(scn.contact.friction, 0.3);
    let (lcps, _) = crate::moreau::problems_at_start(&scn, 12.0);
    assert!(lcps.iter().any(|l| l.m >= 20), "a large group");
    let mut warm = ContactSolver::with_warm_start(SolverKind::Lcp, None, true);
    let mut cold = ContactSolver::new(SolverKind::Lcp, None);
    assert!(warm.warm_start() && !cold.warm_start());
    for lcp in &lcps {
        let z1 = warm.solve(lcp, 0.0);
        let z2 = warm.solve(lcp, 1.0);
        let zc = cold.solve(lcp, 0.0);
        assert_eq!(z1, zc, "the first solve has no history: cold");
        let r = residual(&lcp.lcp().m, &lcp.lcp().q, &z2);
        assert!(r <= SolveOptions::default().tolerance, "residual {r:e}");
    }
    let c = warm.counters();
    assert_eq!(
        c.count(&LCP_WARM_HITS).expect("declared"),
        lcps.len() as u64
    );
    assert_eq!(c.count(&LCP_WARM_MISSES).expect("declared"), 0);
    assert_eq!(cold.counters().count(&LCP_WARM_HITS).expect("declared"), 0);
}

#[test]
fn warm_start_setting_turns_the_warm_start_on_in_both_lcp_formulations() {
    // `[formulation.<name>] warm_start = true` reaches the contact solver of
    // event-driven and moreau: the sliding floe's sustained contact is the
    // same from one solve to the next, so warm starts are tried and hit;
    // without the key none is tried, and the summary says which.
    use crate::common::{case_text, counter, run, scenario, with_formulation_table};
    let text = case_text("sliding_floe");
    for name in ["event-driven", "moreau"] {
        let cold = run(&scenario(&text), name);
        assert_eq!(counter(&cold, "lcp_warm_hits"), 0.0, "{name} cold");
        assert_eq!(counter(&cold, "lcp_warm_misses"), 0.0, "{name} cold");
        let table = with_formulation_table(&text, name, "warm_start = true");
        assert_ne!(table, text);
        let warm = run(&scenario(&table), name);
        let hits = counter(&warm, "lcp_warm_hits");
        assert!(hits > 0.0, "{name}: {hits} warm hits");
        let setting = |r: &floebench::run::RunResult| {
            r.summary.settings.get_text("warm_start").map(String::from)
        };
        assert_eq!(setting(&warm).as_deref(), Some("on"), "{name}");
        assert_eq!(setting(&cold).as_deref(), Some("off"), "{name}");
    }
}

#[test]
fn run_warm_check_solves_every_warm_hit_cold_too_and_counts_the_differences() {
    // `floebench run --warm-check` on the sliding floe with the warm start
    // on: every LCP the warm start solved is solved cold too, so the
    // compared solves (sustained + impact) are exactly the warm hits, and
    // the cold driver solves them all. The square lies flush on the wall:
    // two contact points with friction, four constraints on three degrees
    // of freedom, a singular Delassus matrix, so its LCP has many solutions
    // and warm and cold pick different ones (event-driven 4 of 18, moreau
    // 309 of 999 when written). Without the flag no warm_check_* counter is
    // written and the run is the same warm run, to the last digit.
    use crate::common::{case_text, floebench, stdout_of_success, with_formulation_table};
    let dir = tempdir();
    for name in ["event-driven", "moreau"] {
        let text = with_formulation_table(&case_text("sliding_floe"), name, "warm_start = true");
        let case = dir.path().join(format!("{name}.toml"));
        std::fs::write(&case, text).unwrap();
        let summary = |check: bool| {
            let out = dir.path().join(format!("{name}_{check}"));
            let mut cmd = floebench();
            cmd.arg("run")
                .arg(&case)
                .args(["-f", name, "--quiet", "-o"]);
            cmd.arg(&out);
            if check {
                cmd.arg("--warm-check");
            }
            stdout_of_success(&mut cmd);
            let s: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                    .unwrap();
            (
                s,
                std::fs::read_to_string(out.join("trajectory.csv")).unwrap(),
            )
        };
        let value = |s: &serde_json::Value, k: &str| s["counters"][k]["value"].as_f64();
        let (checked, checked_trajectory) = summary(true);
        let count = |k: &str| value(&checked, k).unwrap_or(f64::NAN);
        let hits = count("lcp_warm_hits");
        assert!(hits > 0.0, "{name}: {hits} warm hits");
        let compared = count("warm_check_sustained") + count("warm_check_impact");
        assert_eq!(compared, hits, "{name}: every warm hit compared");
        assert_eq!(count("warm_check_cold_failed"), 0.0, "{name}");
        let different =
            count("warm_check_sustained_different") + count("warm_check_impact_different");
        let rounding = count("warm_check_sustained_rounding") + count("warm_check_impact_rounding");
        assert!(
            different > 0.0,
            "{name}: the flush square's LCP has many solutions"
        );
        assert!(different + rounding <= compared, "{name}");
        let d = count("warm_check_max_difference");
        assert!(d > 1e-6 && d <= 1.0, "{name}: {d:e}");
        let (plain, plain_trajectory) = summary(false);
        assert_eq!(value(&plain, "warm_check_sustained"), None, "{name}");
        assert_eq!(value(&plain, "lcp_warm_hits"), Some(hits), "{name}");
        assert!(
            plain_trajectory == checked_trajectory,
            "{name}: the check changes the run"
        );
    }
}
