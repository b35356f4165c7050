//! The pieces of a lattice split: mass, momenta and area conserved, the
//! floe partitioned, and the kinetic energy they gain booked apart from the
//! crack.

use super::{diamond, settings};
use crate::common::{case_path, scenario};
use floebench::fracture::lattice::percussion::Impact;
use floebench::fracture::lattice::Lattice;
use floebench::fracture::split::conservation_error;
use floebench::fracture::strike::{chain_options, lattice_spec, pieces, strike};
use floebench::fracture::{Fracturer, Load};
use floebench::geometry::{area_properties, check_convex_ccw, cross, sat_separation, Vec2};
use floebench::state::{BodyState, System};

#[test]
fn the_pieces_of_a_percussion_conserve_mass_and_momenta_and_partition_the_floe() {
    let f = diamond();
    let s = settings(0.5);
    let l = Lattice::build(&f.shape, lattice_spec(&s, &f)).unwrap();
    let impact = Impact {
        point: Vec2::new(5.0, 0.0),
        normal: Vec2::new(-1.0, 0.0),
        mass: f64::INFINITY,
        speed: 2.0,
    };
    let o = strike(&l, impact, chain_options(&s), false, s.min_area, 917.0).unwrap();
    let split = o.split.expect("a 2 m/s ram breaks the floe");
    assert!(split.pieces.len() >= 3, "{} pieces", split.pieces.len());
    // A parent moving, spinning and turned, far from the origin.
    let b = BodyState {
        position: Vec2::new(1.0e5, -2.0e4),
        angle: 0.7,
        velocity: Vec2::new(-0.3, 0.8),
        angular_velocity: 0.05,
    };
    let ps = pieces(&f, &b, &split).unwrap();
    assert_eq!(ps.len(), split.pieces.len());
    let rel = |a: f64, b: f64| (a - b).abs() / b.abs();
    let area: f64 = ps.iter().map(|p| p.floe.area).sum();
    let mass: f64 = ps.iter().map(|p| p.floe.mass).sum();
    let p: Vec2 = ps.iter().map(|p| p.state.velocity * p.floe.mass).sum();
    let lz: f64 = ps
        .iter()
        .map(|p| {
            p.floe.inertia * p.state.angular_velocity
                + p.floe.mass * cross(&(p.state.position - b.position), &p.state.velocity)
        })
        .sum();
    let scale = f.mass * (b.velocity.norm() + b.angular_velocity.abs() * f.radius);
    assert!(rel(area, f.area) < 1e-12, "area {area} {}", f.area);
    assert!(rel(mass, f.mass) < 1e-12, "mass {mass} {}", f.mass);
    assert!(
        (p - b.velocity * f.mass).norm() / scale < 1e-12,
        "momentum {p:?}"
    );
    assert!(
        (lz - f.inertia * b.angular_velocity).abs() / (scale * f.radius) < 1e-12,
        "angular momentum {lz} {}",
        f.inertia * b.angular_velocity
    );
    assert!(conservation_error(&f, &b, &ps, false) < 1e-12);
    // Convex, counter-clockwise, not overlapping; the pieces fly apart.
    let mut world = Vec::new();
    for q in &ps {
        let mut w = Vec::new();
        q.floe.world_polygon(&q.state.position, 0.0, &mut w);
        check_convex_ccw(&w).unwrap();
        assert!(area_properties(&w).area > 0.0);
        world.push(w);
    }
    for i in 0..world.len() {
        for j in i + 1..world.len() {
            let sep = sat_separation(&world[i], &world[j]);
            assert!(
                sep > -1e-9 * f.radius,
                "pieces {i} and {j} overlap by {sep}"
            );
        }
    }
    let k: f64 = ps
        .iter()
        .map(|q| {
            q.floe
                .kinetic_energy(&q.state.velocity, q.state.angular_velocity)
        })
        .sum();
    assert!(k > f.kinetic_energy(&b.velocity, b.angular_velocity));
}

#[test]
fn a_lattice_split_books_the_pieces_kinetic_energy_gain_apart_from_the_crack() {
    // The 2 m/s diamond of lattice_ram loaded by its rigid impact on the
    // coast, (1 + e) M v at its corner: its lattice breaks it, and the
    // kinetic energy the pieces gain is the record's `kinetic_gain`, taken
    // from `dissipated` with the crack energy, which alone goes to `fracture`.
    let mut scn = scenario(&std::fs::read_to_string(case_path("lattice_ram")).unwrap());
    let mut sys = System::initial(&scn);
    let k = 3;
    let f = scn.floes[k].clone();
    let v = sys.bodies[k].velocity;
    let corner = sys.bodies[k].position + Vec2::new(5.0, 0.0);
    let loads = [Load {
        floe: k,
        other: scn.floes.len(),
        point: corner,
        impulse: -v * ((1.0 + scn.contact.restitution) * f.mass),
    }];
    // The formulation's post-impact motion: bounced at e v.
    sys.bodies[k].velocity = -v * scn.contact.restitution;
    let mut fr = Fracturer::default();
    let decisions = fr.decide(&scn, &sys, &loads);
    assert_eq!(decisions.len(), 1);
    let k0 = sys.kinetic_energy(&scn);
    let ledger0 = sys.ledger;
    // The impact's own loss: ½ M v² (1 − e²).
    let lost = 0.5 * f.mass * v.norm_squared() * (1.0 - scn.contact.restitution.powi(2));
    assert_eq!(fr.apply(&mut scn, &mut sys, &decisions, lost), 1);
    let rec = &scn.history.fractures[0];
    let k1 = sys.kinetic_energy(&scn);
    assert!(rec.kinetic_gain > 0.0, "{rec:?}");
    assert!(
        (k1 - k0 - rec.kinetic_gain).abs() <= 1e-12 * k0,
        "kinetic energy {k0} -> {k1}, gain {}",
        rec.kinetic_gain
    );
    let dd = sys.ledger.dissipated - ledger0.dissipated;
    let df = sys.ledger.fracture - ledger0.fracture;
    assert_eq!(df, rec.energy);
    assert!(
        (dd + rec.energy + rec.kinetic_gain).abs() <= 1e-12 * lost,
        "dissipated moved by {dd}; crack {} gain {}",
        rec.energy,
        rec.kinetic_gain
    );
    assert!(rec.energy > 0.0 && rec.energy + rec.kinetic_gain <= lost * (1.0 + 1e-12));
}
