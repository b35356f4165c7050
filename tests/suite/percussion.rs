//! Percussion in a granular bar (docs/physics.md §7.1): Saint-Venant's
//! restitution of two bars, the spall threshold and its convergence with
//! dashpots, and what the chain conserves.

use floebench::fracture::chain::{BarSpec, BondRule, Chain, ChainOptions, Material, Outcome};

/// A striker of length `l1` (m) at `v` (m/s) with `n1` masses against a
/// bar of length `l2` at rest, at the same resolution.
fn bars(l1: f64, n1: usize, l2: f64, v: f64) -> Vec<BarSpec> {
    let n2 = ((l2 / l1) * n1 as f64).round() as usize;
    vec![
        BarSpec {
            length: l1,
            nodes: n1,
            velocity: v,
        },
        BarSpec {
            length: l2,
            nodes: n2,
            velocity: 0.0,
        },
    ]
}

fn run(bars: &[BarSpec], options: ChainOptions) -> Outcome {
    Chain::new(&Material::default(), bars, options)
        .expect("valid chain")
        .run()
}

fn undamped() -> ChainOptions {
    ChainOptions {
        damping: 0.0,
        ..ChainOptions::default()
    }
}

/// The restitution of a 1 m striker on a bar of `l2` m at `n` masses on
/// the striker, undamped and unbreakable.
fn restitution(n: usize, l2: f64) -> f64 {
    run(&bars(1.0, n, l2, 1.0), undamped()).restitution(0, 1, 1.0, 0.0)
}

#[test]
fn two_elastic_bars_separate_with_saint_venant_restitution_l1_over_l2() {
    // At L2/L1 = 5 the error at 40 masses is 2.5 % (the absolute error,
    // about 0.2/n, does not depend on L2/L1): docs/physics.md §7.1.
    for l2 in [2.0, 3.0] {
        let exact = 1.0 / l2;
        let errors: Vec<f64> = [10, 20, 40, 80]
            .iter()
            .map(|&n| (restitution(n, l2) - exact).abs() / exact)
            .collect();
        println!("L2/L1 = {l2}: relative error at 10, 20, 40, 80 masses {errors:?}");
        assert!(errors[2] < 0.02, "L2/L1 = {l2}: {errors:?}");
        assert!(
            errors.windows(2).all(|w| w[1] < w[0]),
            "L2/L1 = {l2}: the error must shrink with resolution: {errors:?}"
        );
    }
}

/// The outcome of a 1 m striker at 1 m/s on a 3 m bar at rest, `n` masses
/// on the striker, bonds of strength `ratio × Z v / 2`.
fn spall(n: usize, damping: f64, ratio: f64) -> Outcome {
    let mat = Material::default();
    let strength = ratio * mat.impedance() * 1.0 / 2.0;
    run(
        &bars(1.0, n, 3.0, 1.0),
        ChainOptions {
            damping,
            bond: BondRule::Force(strength),
            ..ChainOptions::default()
        },
    )
}

/// The largest ratio (bond strength over `Z v / 2`) at which a bond
/// breaks, by bisection to 1e-6.
fn threshold(n: usize, damping: f64) -> f64 {
    let (mut lo, mut hi) = (0.2, 3.0);
    while hi - lo > 1e-6 {
        let mid = 0.5 * (lo + hi);
        if spall(n, damping, mid).broken.is_empty() {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    lo
}

#[test]
fn a_short_striker_spalls_a_piece_of_its_length_off_the_far_end_below_zv_over_2_only() {
    let n = 80;
    let below = spall(n, 0.5, 0.95);
    let piece = below.fragments.last().expect("pieces");
    assert!(
        !below.broken.is_empty() && piece.first >= 3 * n && (piece.length - 1.0).abs() < 0.1,
        "at 0.95 Zv/2 the far end must spall a piece of about 1 m: {:?}",
        below.fragments
    );
    let above = spall(n, 0.5, 1.05);
    assert!(
        above.broken.is_empty(),
        "no bond may break at 1.05 Zv/2: {:?}",
        above.broken
    );
}

#[test]
fn with_dashpots_the_spall_threshold_converges_to_zv_over_2_without_it_does_not() {
    let damped: Vec<f64> = [10, 20, 40, 80]
        .iter()
        .map(|&n| threshold(n, 0.5))
        .collect();
    let ringing: Vec<f64> = [10, 20, 40, 80]
        .iter()
        .map(|&n| threshold(n, 0.0))
        .collect();
    println!("threshold ratio at 10, 20, 40, 80 masses: dashpots 0.5 {damped:?}, none {ringing:?}");
    let gaps: Vec<f64> = damped.iter().map(|t| (t - 1.0).abs()).collect();
    assert!(gaps.windows(2).all(|w| w[1] < w[0]), "{damped:?}");
    assert!(gaps[3] < 1e-3, "{damped:?}");
    assert!(ringing.iter().all(|t| *t > 1.3), "{ringing:?}");
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn the_chain_conserves_momentum_and_its_fragments_mass_and_momentum() {
    for (damping, ratio) in [(0.0, f64::INFINITY), (0.5, 0.8), (0.0, 0.8)] {
        let bond = if ratio.is_finite() {
            BondRule::Force(ratio * Material::default().impedance() / 2.0)
        } else {
            BondRule::Unbreakable
        };
        let o = run(
            &bars(1.0, 40, 3.0, 1.0),
            ChainOptions {
                damping,
                bond,
                ..ChainOptions::default()
            },
        );
        let mass: f64 = o.bars.iter().map(|b| b.0).sum();
        let p: f64 = o.fragments.iter().map(|f| f.mass * f.velocity).sum();
        let m: f64 = o.fragments.iter().map(|f| f.mass).sum();
        assert!(rel(m, mass) < 1e-12, "mass {m} vs {mass}");
        assert!(
            rel(p, o.initial_momentum) < 1e-12,
            "damping {damping}, ratio {ratio}: momentum {p} vs {}",
            o.initial_momentum
        );
    }
}

#[test]
fn without_dashpots_or_breaking_the_energy_error_is_under_one_percent_and_shrinks_with_the_step() {
    let drift = |safety: f64| {
        let o = run(
            &bars(1.0, 40, 2.0, 1.0),
            ChainOptions {
                safety,
                ..undamped()
            },
        );
        o.energy_drift / o.initial_energy
    };
    let d: Vec<f64> = [0.9, 0.45, 0.225].iter().map(|&s| drift(s)).collect();
    println!("largest relative energy error at safety 0.9, 0.45, 0.225: {d:?}");
    assert!(d[0] < 0.01, "{d:?}");
    for w in d.windows(2) {
        assert!(w[1] < 0.6 * w[0], "{d:?}");
    }
}

#[test]
fn percussion_1d_prints_the_pieces_and_refuses_a_bad_bar() {
    let dir = crate::common::tempdir();
    let nodes = dir.path().join("nodes.csv");
    let stdout = crate::common::stdout_of_success(
        crate::common::floebench()
            .args(["percussion-1d", "--bar", "1,20,1", "--bar", "3,60,0"])
            .args(["--strength", "1e6", "--nodes"])
            .arg(&nodes),
    );
    let mut lines = stdout.lines();
    assert_eq!(
        lines.next(),
        Some("fragment,first,last,mass,length,centre,velocity")
    );
    // A strength of 1e6 N is below Z v / 2 = 1.43e6 N: the far end spalls.
    assert!(lines.count() >= 3, "{stdout}");
    let text = std::fs::read_to_string(&nodes).expect("nodes written");
    assert!(text.starts_with("node,bar,fragment,x,v\n"));
    assert_eq!(text.lines().count(), 81);
    let bad = crate::common::floebench()
        .args(["percussion-1d", "--bar", "1,1,1"])
        .output()
        .expect("runs");
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("at least 2 nodes"));
}
