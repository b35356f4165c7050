//! The 2D percussion of a floe (docs/physics.md §7.3): what the pieces
//! conserve, the integrator's energy error, a gentle strike that leaves the
//! floe whole, a strong one against a wall that breaks it.

use floebench::fracture::chain::{BondRule, ChainOptions, Stop};
use floebench::fracture::lattice::percussion::{Impact, Outcome, Percussion, RigidMotion};
use floebench::fracture::lattice::{Lattice, LatticeSpec};
use floebench::geometry::Vec2;

fn square(side: f64) -> Vec<Vec2> {
    vec![
        Vec2::new(0.0, 0.0),
        Vec2::new(side, 0.0),
        Vec2::new(side, side),
        Vec2::new(0.0, side),
    ]
}

/// A 10 m square floe 1 m thick, of ice, at `spacing`.
fn floe(spacing: f64) -> Lattice {
    Lattice::build(
        &square(10.0),
        LatticeSpec {
            spacing,
            thickness: 1.0,
            density: 917.0,
            young: 8.95e9,
            poisson: 1.0 / 3.0,
            seed: 1,
        },
    )
    .expect("lattice")
}

/// The floe struck on its left face at height `y` (m) along +x by a
/// striker of mass `mass` (kg) at relative speed `speed` (m/s), the floe
/// moving at `motion`.
fn strike(
    lattice: &Lattice,
    motion: RigidMotion,
    y: f64,
    mass: f64,
    speed: f64,
    options: ChainOptions,
) -> Outcome {
    Percussion::new(
        lattice,
        motion,
        Impact {
            point: Vec2::new(0.0, y),
            normal: Vec2::new(1.0, 0.0),
            mass,
            speed,
        },
        options,
    )
    .expect("valid percussion")
    .run()
}

fn breakable(strain: f64) -> ChainOptions {
    ChainOptions {
        bond: BondRule::Strain(strain),
        ..ChainOptions::default()
    }
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn the_pieces_conserve_mass_and_linear_and_angular_momentum_with_the_strikers() {
    let l = floe(1.0);
    let mass: f64 = l.mass.iter().sum();
    let motion = RigidMotion {
        velocity: Vec2::new(0.3, 0.1),
        angular_velocity: 0.02,
    };
    let striker = 2.0e4;
    let o = strike(&l, motion, 3.0, striker, 30.0, breakable(1e-4));
    println!(
        "{:?}: {} pieces, {} broken, {} steps, hull area error {:.3e}",
        o.reason,
        o.fragments.len(),
        o.broken.len(),
        o.steps,
        o.hull_area_error
    );
    assert!(o.fragments.len() >= 2, "the strike must break the floe");
    let m: f64 = o.fragments.iter().map(|f| f.mass).sum();
    assert!(rel(m, mass) < 1e-12, "mass {m} against {mass}");
    // What the striker gave is what the striker lost.
    let n = Vec2::new(1.0, 0.0);
    let given = -striker * (o.striker_velocity[1] - o.striker_velocity[0]);
    assert!(
        rel(o.impulse.dot(&n), given) < 1e-12,
        "{:?} against {given}",
        o.impulse
    );
    assert!(o.impulse.y.abs() < 1e-12 * given.abs());
    // The pieces' momenta: the floe's at the impact plus the striker's impulse.
    let (p0, l0) = o.initial_momentum;
    let scale = p0.norm() + o.impulse.norm();
    let dp = (o.momentum() - p0 - o.impulse).norm() / scale;
    assert!(dp < 1e-12, "linear momentum off by {dp:e}");
    let dl = (o.angular_momentum() - l0 - o.impulse_moment).abs() / (scale * 10.0);
    assert!(dl < 1e-12, "angular momentum off by {dl:e}");
    // Every node is in one piece.
    let nodes: usize = o.fragments.iter().map(|f| f.nodes.len()).sum();
    assert_eq!(nodes, l.nodes.len());
}

#[test]
fn without_dashpots_or_breaking_the_energy_error_is_small_and_shrinks_with_the_step() {
    let l = floe(1.0);
    let mass: f64 = l.mass.iter().sum();
    let errors: Vec<f64> = [0.9, 0.45, 0.225]
        .iter()
        .map(|&safety| {
            let o = strike(
                &l,
                RigidMotion::default(),
                4.0,
                0.5 * mass,
                1.0,
                ChainOptions {
                    damping: 0.0,
                    safety,
                    ..ChainOptions::default()
                },
            );
            assert_eq!(o.fragments.len(), 1);
            assert!(o.energies.fracture == 0.0);
            o.energy_drift / o.initial_energy
        })
        .collect();
    println!("relative energy error at safety 0.9, 0.45, 0.225: {errors:?}");
    assert!(errors[0] < 0.01, "{errors:?}");
    assert!(errors.windows(2).all(|w| w[1] < 0.5 * w[0]), "{errors:?}");
}

#[test]
fn a_gentle_strike_leaves_the_floe_whole_with_a_restitution_below_one() {
    let l = floe(1.0);
    let mass: f64 = l.mass.iter().sum();
    let speed = 0.1;
    let o = strike(
        &l,
        RigidMotion::default(),
        5.0,
        mass,
        speed,
        breakable(1e-4),
    );
    assert_eq!(o.fragments.len(), 1, "{} pieces", o.fragments.len());
    assert!(o.broken.is_empty());
    let f = &o.fragments[0];
    let [u0, u1] = o.striker_velocity;
    // The floe's momentum is the striker's loss.
    assert!(rel(f.momentum.x, mass * 0.0 + mass * (u0 - u1)) < 1e-12);
    let e = (f.velocity.x - u1) / speed;
    println!(
        "{:?} after {} transits: restitution {e}, striker {u1} m/s, floe {} m/s",
        o.reason,
        o.t / (10.0 / 3300.0),
        f.velocity.x
    );
    assert!(e > 0.0 && e < 1.0, "restitution {e}");
    assert!(o.fracture_energy > 0.0);
}

#[test]
fn a_strong_ram_into_a_fixed_coast_breaks_the_floe() {
    let l = floe(1.0);
    let v0 = 20.0;
    let o = strike(
        &l,
        RigidMotion {
            velocity: Vec2::new(-v0, 0.0),
            angular_velocity: 0.0,
        },
        5.0,
        f64::INFINITY,
        v0,
        breakable(1e-4),
    );
    let big = o.fragments.iter().filter(|f| f.nodes.len() >= 3).count();
    println!(
        "{} pieces ({big} of 3 nodes or more), {} bonds broken, fracture energy {} J of {} J",
        o.fragments.len(),
        o.broken.len(),
        o.fracture_energy,
        o.initial_energy
    );
    assert!(big >= 2);
    assert_eq!(o.work, 0.0, "a coast at rest does no work");
    assert!(o.fracture_energy > 0.0 && o.fracture_energy < o.initial_energy);
    assert!(o.striker_velocity == [0.0, 0.0]);
    assert!(matches!(o.reason, Stop::Settled | Stop::Rang));
}

#[test]
fn percussion_2d_prints_the_pieces_draws_the_crack_and_refuses_a_bad_point() {
    let dir = crate::common::tempdir();
    let stem = dir.path().join("crack");
    let stdout = crate::common::stdout_of_success(
        crate::common::floebench()
            .args(["percussion-2d", "--speed", "20", "--strain", "1e-4"])
            .args(["--spacing", "1", "--plot"])
            .arg(&stem),
    );
    let mut lines = stdout.lines();
    assert_eq!(
        lines.next(),
        Some("piece,nodes,mass,x,y,vx,vy,omega,hull_area")
    );
    // A ram at 20 m/s breaks the floe (as the library test).
    assert!(lines.count() >= 2, "{stdout}");
    for ext in ["png", "svg"] {
        let f = stem.with_extension(ext);
        assert!(std::fs::metadata(&f).map(|m| m.len() > 0).unwrap_or(false));
    }
    let bad = crate::common::floebench()
        .args(["percussion-2d", "--speed", "1", "--at", "20"])
        .output()
        .expect("runs");
    assert!(!bad.status.success());
    assert!(String::from_utf8_lossy(&bad.stderr).contains("not on the left face"));
}
