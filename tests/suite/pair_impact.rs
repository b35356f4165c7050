//! The impact of two lattices (docs/physics.md §9.9): the pair's momenta,
//! the energy ledger, Saint-Venant's restitution of bars end-on, a floe
//! against a fixed obstacle.
//!
//! The bars are 1 m wide, of ice, 1 m thick, on the case's default random
//! mesh (seed 1) at spacing 0.25 m (four cells across), unbreakable and
//! without dashpots (`damping = 0`: the lattice allows it, the stable step
//! needs none), so that every joule that is not in the rigid motions is
//! in vibration.

use floebench::fracture::chain::{BondRule, ChainOptions};
use floebench::fracture::lattice::bars::Bars;
use floebench::fracture::lattice::pair::{PairBody, PairImpact, PairOutcome};
use floebench::fracture::lattice::LatticeSpec;
use floebench::geometry::{cross, Vec2};
use floebench::state::BodyState;

/// Ice at `spacing`, the random mesh of seed 1.
fn ice(spacing: f64) -> LatticeSpec {
    LatticeSpec {
        spacing,
        ..LatticeSpec::default()
    }
}

/// No dashpots, unbreakable.
fn undamped() -> ChainOptions {
    ChainOptions {
        damping: 0.0,
        ..ChainOptions::default()
    }
}

/// Bars `l1` and `l2` (m) 1 m wide, the first at 1 m/s, the second
/// offset laterally by `offset` (m).
fn bars(l1: f64, l2: f64, offset: f64) -> Bars {
    Bars {
        lengths: (l1, l2),
        width: 1.0,
        speed: 1.0,
        offset,
        gap: 0.0,
    }
}

/// Angular momentum about the fixed point `c` from the one about the
/// origin `l` and the linear momentum `p`.
fn about(c: Vec2, l: f64, p: Vec2) -> f64 {
    l - cross(&c, &p)
}

#[test]
fn an_off_centre_impact_conserves_the_pairs_momenta_and_sets_both_bars_spinning() {
    let o = bars(10.0, 20.0, 0.6)
        .run(ice(0.25), undamped())
        .expect("impact");
    let [p0, p1] = o.momentum;
    assert!(p0.norm() > 0.0);
    let dp = (p1 - p0).norm() / p0.norm();
    assert!(dp < 1e-9, "linear momentum changed by {dp:e} (relative)");
    // About a fixed point off the bars' line (the origin is on it, where
    // the first bar's angular momentum is 0).
    let c = Vec2::new(-5.0, -3.0);
    let [l0, l1] = o.angular_momentum;
    let (a0, a1) = (about(c, l0, p0), about(c, l1, p1));
    let dl = (a1 - a0).abs() / a0.abs();
    assert!(
        dl < 1e-9,
        "angular momentum changed by {dl:e} (relative), {a0} → {a1}"
    );
    // The impact is off-centre: both bars spin afterwards, in opposite
    // senses (the pair's angular momentum about the contact is shared).
    let (w1, w2) = (o.bodies[0].angular_velocity, o.bodies[1].angular_velocity);
    assert!(
        w1.abs() > 1e-4 && w2.abs() > 1e-4,
        "spins {w1} and {w2} rad/s"
    );
    // The bodies' own momenta add up to the pair's.
    let sum: Vec2 = o.bodies.iter().map(|b| b.momentum).sum();
    assert!((sum - p1).norm() <= 1e-9 * p0.norm());
}

/// `initial − (rigid + vibration + damping + fracture + contact)` over the
/// initial kinetic energy.
fn defect(o: &PairOutcome) -> f64 {
    o.energy_defect() / o.initial_energy
}

/// The energy closes to 5e-3 of the initial kinetic energy: velocity
/// Verlet's energy error is O(Δt²) and bounded, but a node is found in
/// contact already a step's travel inside the other body (an O(Δt) error
/// at each contact's onset, the penalty's), and the dashpots' power is
/// integrated by the trapezoid rule on the half-step velocities the
/// forces use. Measured: 3e-4 to 1.3e-3.
const ENERGY_TOLERANCE: f64 = 5e-3;

#[test]
fn the_energy_closes_without_and_with_dashpots_and_broken_bonds() {
    let free = bars(10.0, 20.0, 0.0)
        .run(ice(0.25), undamped())
        .expect("impact");
    assert_eq!(free.damping, 0.0);
    assert_eq!(free.fracture(), 0.0);
    assert!(
        free.vibration() > 0.3 * free.initial_energy,
        "the long bar rings"
    );
    assert!(
        defect(&free).abs() < ENERGY_TOLERANCE,
        "undamped: {:e}",
        defect(&free)
    );

    let damped = bars(10.0, 20.0, 0.3)
        .run(ice(0.25), ChainOptions::default())
        .expect("impact");
    assert!(
        damped.damping > 0.05 * damped.initial_energy,
        "{}",
        damped.damping
    );
    assert!(
        defect(&damped).abs() < ENERGY_TOLERANCE,
        "damped: {:e}",
        defect(&damped)
    );

    // Strain 1e-4 is below the impact's 1.7e-4 (ρ c v / (2E)): bonds break.
    // Breaking runs close only to first order in the step (measured
    // -1.75e-2 at safety 0.9, -5.9e-3 at 0.45, -2.4e-3 at 0.2; the source
    // is not pinned down: bonds break at the end of a step, after the step
    // they were still pulling): 3e-2 at the default step, and it must
    // shrink with the step.
    let breaking_at = |safety: f64| {
        bars(10.0, 20.0, 0.0)
            .run(
                ice(0.25),
                ChainOptions {
                    bond: BondRule::Strain(1e-4),
                    safety,
                    ..ChainOptions::default()
                },
            )
            .expect("impact")
    };
    let breaking = breaking_at(0.9);
    assert!(breaking.fracture() > 0.0);
    assert!(breaking.bodies.iter().map(|b| b.broken).sum::<usize>() > 0);
    let (coarse, fine) = (defect(&breaking), defect(&breaking_at(0.45)));
    assert!(coarse.abs() < 3e-2, "breaking: {coarse:e}");
    assert!(
        fine.abs() < coarse.abs(),
        "breaking: {coarse:e}, then {fine:e}"
    );
    for o in [&free, &damped, &breaking] {
        assert!(
            o.contact_energy.abs() < 1e-9 * o.initial_energy,
            "still touching"
        );
        assert!(o.normal_velocity[1] >= 0.0, "not separating");
    }
}

/// Saint-Venant's restitution is one-dimensional: the 2D lattice's bars
/// have a width (the Poisson effect near the contact, lateral modes) and
/// the lattice's dispersion smears the wave fronts, and both shrink with
/// the spacing; at 0.25 m (four cells across) the measured errors are
/// 3 % (equal), 3 % (1/2) and 9 % (1/3). Tolerance: 5 % for the equal
/// bars (e ≤ 1 in any case), 10 % (the target) for L1/L2, and the
/// error must fall from spacing 0.5 m to 0.25 m.
#[test]
fn equal_bars_part_with_e_close_to_1_and_unequal_ones_with_saint_venants_ratio() {
    let equal = bars(10.0, 10.0, 0.0)
        .run(ice(0.25), undamped())
        .expect("impact");
    let e = equal.restitution;
    assert!(e > 0.95 && e <= 1.0, "equal bars: e = {e}");
    for (l2, coarse_spacing) in [(20.0, 0.5), (30.0, 0.5)] {
        let b = bars(10.0, l2, 0.0);
        let target = b.saint_venant();
        let error = |spacing: f64| {
            let o = b.run(ice(spacing), undamped()).expect("impact");
            (o.restitution - target).abs() / target
        };
        let (coarse, fine) = (error(coarse_spacing), error(0.25));
        assert!(fine < 0.10, "10/{l2}: e off by {fine:.3} (relative)");
        assert!(
            fine < coarse,
            "10/{l2}: {coarse:.3} at 0.5 m, {fine:.3} at 0.25 m"
        );
    }
}

#[test]
fn the_longer_bar_striking_gives_the_same_ratio() {
    let o = bars(20.0, 10.0, 0.0)
        .run(ice(0.25), undamped())
        .expect("impact");
    let e = o.restitution;
    assert!((e - 0.5).abs() < 0.05, "20 on 10: e = {e}");
    // The striker keeps going, slower; the struck bar leaves faster.
    let (v1, v2) = (o.bodies[0].velocity.x, o.bodies[1].velocity.x);
    assert!(v1 > 0.0 && v2 > v1, "{v1} and {v2} m/s");
}

#[test]
fn a_floe_against_a_fixed_obstacle_rebounds_with_its_momentum_from_the_wall() {
    let shape = [
        Vec2::new(-5.0, -0.5),
        Vec2::new(5.0, -0.5),
        Vec2::new(5.0, 0.5),
        Vec2::new(-5.0, 0.5),
    ];
    let state = BodyState {
        position: Vec2::new(-5.0, 0.0),
        angle: 0.0,
        velocity: Vec2::new(1.0, 0.0),
        angular_velocity: 0.0,
    };
    let o = PairImpact {
        first: PairBody {
            shape: &shape,
            state,
            spec: ice(0.25),
        },
        second: None,
        point: Vec2::new(0.0, 0.0),
        normal: Vec2::new(1.0, 0.0),
        options: undamped(),
    }
    .run()
    .expect("impact");
    assert_eq!(o.bodies.len(), 1);
    // A bar against a rigid wall: Saint-Venant's e = 1 (the bar's wave
    // comes back whole), less the 2D lattice's ringing.
    let e = o.restitution;
    assert!(e > 0.9 && e <= 1.0, "e = {e}");
    assert!(o.bodies[0].velocity.x < 0.0);
    assert!(
        o.work.abs() < 1e-9 * o.initial_energy,
        "the wall is at rest"
    );
    assert!(defect(&o).abs() < ENERGY_TOLERANCE, "{:e}", defect(&o));
    // Bodies that are not approaching are refused.
    let away = PairImpact {
        first: PairBody {
            shape: &shape,
            state: BodyState {
                velocity: Vec2::new(-1.0, 0.0),
                ..state
            },
            spec: ice(0.25),
        },
        second: None,
        point: Vec2::new(0.0, 0.0),
        normal: Vec2::new(1.0, 0.0),
        options: undamped(),
    };
    assert!(away.run().is_err());
}

/// Floes that a time-stepping scheme left overlapping (by 0.3 m here,
/// more than a spacing) start their impact at first touch (docs/physics.md
/// §9.9, **Start**): the same bounce as bars placed touching (to 1e-6:
/// the start leaves a gap of 1e-9 of the overlap, so the first touch comes
/// a fraction of a step later; measured 1.3e-8), and no energy created by
/// the overlap. Without the start rule the overlap's
/// contact links hold `½ κ̄ d²` per node and throw the bars apart (the
/// moreau run of lattice_field_impact blew up so, at 115 m of
/// penetration).
#[test]
fn overlapping_floes_start_their_impact_at_first_touch() {
    let touching = bars(10.0, 20.0, 0.0).run(ice(0.25), undamped());
    let overlapping = Bars {
        gap: -0.3,
        ..bars(10.0, 20.0, 0.0)
    }
    .run(ice(0.25), undamped());
    let (touching, overlapping) = (touching.expect("impact"), overlapping.expect("impact"));
    let (e0, e1) = (touching.restitution, overlapping.restitution);
    assert!(
        (e1 - e0).abs() < 1e-6,
        "e = {e1} overlapping, {e0} touching"
    );
    assert!(
        defect(&overlapping).abs() < ENERGY_TOLERANCE,
        "{:e}",
        defect(&overlapping)
    );
    assert!(overlapping.rigid_energy() <= overlapping.initial_energy);
}

/// Bars 10 m / 20 m a little apart (2 mm) approaching slowly (1 mm/s, as
/// floes pressed by the wind meet in the event-driven field) bounce as the
/// touching bars do: the lattices start at first touch (docs/physics.md
/// §9.9, **Start**). Without the closing move the 200 transit times of
/// the run's time limit (1.3 s) pass before the gap closes, and the impact
/// returns the velocities it was given (`e = −1`).
#[test]
fn floes_a_little_apart_start_their_impact_at_first_touch() {
    let slow = Bars {
        speed: 1e-3,
        ..bars(10.0, 20.0, 0.0)
    };
    let touching = slow.run(ice(0.25), undamped()).expect("impact");
    let apart = Bars { gap: 2e-3, ..slow }
        .run(ice(0.25), undamped())
        .expect("impact");
    let (e0, e1) = (touching.restitution, apart.restitution);
    assert!(e0 > 0.3, "e = {e0} touching");
    assert!((e1 - e0).abs() < 1e-6, "e = {e1} apart, {e0} touching");
    assert!(
        defect(&apart).abs() < ENERGY_TOLERANCE,
        "{:e}",
        defect(&apart)
    );
}
