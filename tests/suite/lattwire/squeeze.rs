//! A floe squeezed from two sides: the percussion conserves momentum, the
//! joint equivalent impact, and in a run the squeeze breaks where one
//! strike does not.

use super::{diamond, settings, squeeze};
use crate::common::{run, scenario};
use floebench::fracture::lattice::percussion::{Percussion, RigidMotion};
use floebench::fracture::lattice::Lattice;
use floebench::fracture::strike::{
    chain_options, equivalent_impact, equivalent_impacts, lattice_spec, strike_all,
};
use floebench::fracture::PairLoad;
use floebench::geometry::Vec2;
use floebench::state::System;

#[test]
fn a_floe_squeezed_from_two_sides_conserves_momentum_and_breaks_where_one_strike_does_not() {
    // The percussion: the strikers' momentum loss is the floe's gain, to
    // 1e-12, and a squeeze puts 4× the energy of one strike into the floe.
    let f = diamond();
    let s = settings(0.5);
    let l = Lattice::build(&f.shape, lattice_spec(&s, &f)).unwrap();
    let impacts = squeeze(&f, 0.7, true);
    let mut p =
        Percussion::with_strikers(&l, RigidMotion::default(), &impacts, chain_options(&s)).unwrap();
    let o = p.run();
    let given: Vec2 = impacts
        .iter()
        .zip(&o.striker_velocities)
        .map(|(i, [u0, u1])| -i.normal * (i.mass * (u1 - u0)))
        .sum();
    let scale = f.mass * 0.7;
    assert!(
        (o.impulse - given).norm() / scale < 1e-12,
        "{:?} {given:?}",
        o.impulse
    );
    let (p0, l0) = o.initial_momentum;
    assert!((o.momentum() - p0 - o.impulse).norm() / scale < 1e-12);
    assert!((o.angular_momentum() - l0 - o.impulse_moment).abs() / (scale * f.radius) < 1e-12);
    let one = strike_all(
        &l,
        &squeeze(&f, 0.7, false),
        chain_options(&s),
        false,
        1.0,
        917.0,
    )
    .unwrap();
    assert!((o.impact_energy / one.bound - 4.0).abs() < 1e-12);

    // In a run: floe 1 (the 50 m² diamond at rest) is hit on its corners
    // by a 6 m square from each side at 1 m/s in one impact group. Struck
    // by one of them alone it stays whole; squeezed by both it breaks.
    let case = |both: bool| {
        let right = if both {
            "[[floe]]\npolygon = [[20.5, 2.0], [26.5, 2.0], [26.5, 8.0], [20.5, 8.0]]\nthickness = 1.0\nvelocity = [-1.0, 0.0]\n"
        } else {
            ""
        };
        scenario(&format!(
            "[case]\nversion = 1\nname = \"squeeze\"\ndescription = \"x\"\nduration = 2.0\noutput_interval = 1.0\n\
             [contact]\nrestitution = 0.5\nfriction = 0.0\n\
             [[floe]]\npolygon = [[3.5, 2.0], [9.5, 2.0], [9.5, 8.0], [3.5, 8.0]]\nthickness = 1.0\nvelocity = [1.0, 0.0]\n\
             [[floe]]\npolygon = [[10.0, 5.0], [15.0, 0.0], [20.0, 5.0], [15.0, 10.0]]\nthickness = 1.0\n\
             {right}\
             [fracture]\nmodel = \"lattice\"\nspacing = 0.5\ntoughness = 2.5\nmin_area = 1.0\n"
        ))
    };
    // The joint equivalent impact: the squares' impulses (1 + e) m v of a
    // symmetric squeeze of the resting diamond give back the approach speed
    // v = 1 m/s of each; one pair alone reads 1 + m/M m/s (the other side's
    // hold taken for the diamond's inertia).
    let scn = case(true);
    let sys = System::initial(&scn);
    let m = scn.floes[0].mass;
    let p = Vec2::new((1.0 + scn.contact.restitution) * m, 0.0);
    let pairs = [
        PairLoad {
            other: 0,
            impulse: p,
            point: Vec2::new(10.0, 5.0),
        },
        PairLoad {
            other: 2,
            impulse: -p,
            point: Vec2::new(20.0, 5.0),
        },
    ];
    let joint = equivalent_impacts(&scn, &sys, 1, &pairs).unwrap();
    for i in &joint {
        assert!((i.speed - 1.0).abs() < 1e-12, "{joint:?}");
        assert_eq!(i.mass, m);
    }
    let (alone, _) = equivalent_impact(&scn, &sys, 1, &pairs[0]).unwrap();
    assert!((alone.speed - (1.0 + m / scn.floes[1].mass)).abs() < 1e-12);
    for both in [false, true] {
        let scn = case(both);
        let r = run(&scn, "event-driven");
        let broke = r.fractures.iter().any(|f| f.parent == 1);
        assert_eq!(broke, both, "both sides {both}: {:?}", r.fractures);
        // Momentum: the initial floes' against the floes alive at the end.
        let mass = |id: usize| r.floes.iter().find(|f| f.id == id).unwrap().mass;
        let t_end = r.trajectory.last().unwrap().t;
        let (mut p_end, mut scale) = (Vec2::zeros(), 0.0);
        for row in r.trajectory.iter().filter(|row| row.t == t_end) {
            let v = Vec2::new(row.vx, row.vy);
            p_end += v * mass(row.floe);
            scale += v.norm() * mass(row.floe);
        }
        let p0: Vec2 = scn.floes.iter().map(|f| f.velocity * f.mass).sum();
        assert!((p_end - p0).norm() <= 1e-12 * scale, "{p_end:?} {p0:?}");
    }
}
