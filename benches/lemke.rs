//! Lemke on contact LCPs of 4, 40 and 400 unknowns built from real impacts:
//! the impact LCP (docs/physics.md §3.1, Stewart–Trinkle friction, size 4m) that
//! the event-driven formulation assembles when a floe strikes
//! - a wall with one corner (1 contact, 4 unknowns),
//! - a row of 5 touching floes (10 contacts, 40 unknowns),
//! - a row of 50 touching floes (100 contacts, 400 unknowns),
//!
//! obliquely and spinning, so that friction is active.
//!
//! `cargo bench --bench lemke`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use floebench::contact::problem::{groups, ContactLcp, Gen};
use floebench::contact::BroadPhase;
use floebench::formulation::parse_case;
use floebench::lcp::{solve, Lcp, SolveOptions};
use floebench::model::Scenario;
use floebench::state::{detect_contacts, System};
use std::hint::black_box;
use std::path::Path;

const HEAD: &str = "[case]\nversion = 1\nname = \"bench\"\nduration = 1.0\noutput_interval = 1.0\n[contact]\nrestitution = 0.5\nfriction = 0.3\n";

fn corner_on_wall() -> Scenario {
    let text = format!(
        "{HEAD}[[floe]]\npolygon = [[10.0, 5.0], [15.0, 0.0], [20.0, 5.0], [15.0, 10.0]]\nthickness = 1.0\nvelocity = [0.5, 0.2]\nangular_velocity = 0.05\n[[obstacle]]\npolygon = [[20.0, -50.0], [30.0, -50.0], [30.0, 50.0], [20.0, 50.0]]\n"
    );
    parse_case(&text, Path::new("bench.toml")).expect("bench case")
}

fn row(n: usize) -> Scenario {
    let mut text = HEAD.to_string();
    for k in 0..n {
        let x = 10.0 * k as f64;
        let v = if k == 0 {
            "velocity = [0.5, 0.2]\nangular_velocity = 0.02\n"
        } else {
            ""
        };
        text += &format!(
            "[[floe]]\npolygon = [[{x:?}, 0.0], [{:?}, 0.0], [{:?}, 10.0], [{x:?}, 10.0]]\nthickness = 1.0\n{v}",
            x + 10.0,
            x + 10.0
        );
    }
    parse_case(&text, Path::new("bench.toml")).expect("bench case")
}

/// The impact LCP of the first (only) contact group of a scenario at t = 0.
fn impact_lcp(scn: &Scenario) -> Lcp {
    let sys = System::initial(scn);
    let mut contacts = Vec::new();
    detect_contacts(
        scn,
        &sys.bodies,
        1e-3,
        &mut BroadPhase::new(),
        &mut contacts,
    );
    let g = groups(&contacts, scn.floes.len()).remove(0);
    let centres = sys.centres();
    let w: Vec<Gen> = sys.velocities();
    let zeros = vec![0.0; contacts.len()];
    ContactLcp::assemble(scn, &centres, &contacts, &g, &w, &zeros).lcp
}

fn lemke_on_impacts(c: &mut Criterion) {
    faer::set_global_parallelism(faer::Par::Seq);
    let mut g = c.benchmark_group("lemke_impact_lcp");
    let opts = SolveOptions::default();
    for scn in [corner_on_wall(), row(6), row(51)] {
        let lcp = impact_lcp(&scn);
        let sol = solve(&lcp, &opts);
        assert!(
            sol.status.is_solved(),
            "bench LCP of size {} unsolved",
            lcp.n
        );
        eprintln!(
            "LCP of {} unknowns: {} pivots, residual {:.2e}, status {}",
            lcp.n,
            sol.pivots,
            sol.residual,
            sol.status.as_str()
        );
        g.bench_with_input(BenchmarkId::from_parameter(lcp.n), &lcp, |b, lcp| {
            b.iter(|| black_box(solve(lcp, &opts).pivots))
        });
    }
    g.finish();
}

criterion_group! {
    name = benches;
    config = Criterion::default().without_plots();
    targets = lemke_on_impacts
}
criterion_main!(benches);
