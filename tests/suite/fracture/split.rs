//! The split: a chord cuts a convex floe into two convex pieces that
//! conserve area, mass, momenta and kinetic energy; a chord that misses or
//! grazes the floe does not cut it.

use super::rel;
use floebench::fracture::split::{cut, cut_floe, split};
use floebench::geometry::{area_properties, check_convex_ccw, cross, sat_separation, Vec2};
use floebench::model::{Floe, FloeOrigin};
use floebench::rng::SplitMix64;
use floebench::state::BodyState;

/// A random convex polygon: `n` points on an ellipse at sorted random
/// angles, about `c`.
fn convex(rng: &mut SplitMix64, n: usize, c: Vec2) -> Vec<Vec2> {
    let (a, b) = (rng.range(5.0, 50.0), rng.range(5.0, 50.0));
    let mut angles: Vec<f64> = (0..n)
        .map(|_| rng.range(0.0, std::f64::consts::TAU))
        .collect();
    angles.sort_by(f64::total_cmp);
    angles.dedup_by(|x, y| (*x - *y).abs() < 0.05);
    angles
        .iter()
        .map(|t| c + Vec2::new(a * t.cos(), b * t.sin()))
        .collect()
}

#[test]
fn a_split_conserves_area_mass_momenta_and_kinetic_energy_and_makes_two_convex_pieces() {
    let mut rng = SplitMix64::new(13);
    let mut tested = 0;
    for _ in 0..400 {
        let n = 3 + (rng.next_u64() % 10) as usize;
        let c = Vec2::new(rng.range(-1e4, 1e4), rng.range(-1e4, 1e4));
        let poly = convex(&mut rng, n, c);
        if poly.len() < 3 || check_convex_ccw(&poly).is_err() {
            continue;
        }
        let thickness = rng.range(0.5, 3.0);
        let floe = Floe::from_world_polygon(
            &poly,
            thickness,
            917.0,
            Vec2::zeros(),
            0.0,
            FloeOrigin::Listed(0),
        );
        let b = BodyState {
            position: floe.position,
            angle: 0.0,
            velocity: Vec2::new(rng.range(-1.0, 1.0), rng.range(-1.0, 1.0)),
            angular_velocity: rng.range(-0.05, 0.05),
        };
        // A chord through a random interior point in a random direction.
        let w = rng.range(0.05, 0.95);
        let point = floe.position * w + poly[0] * (1.0 - w);
        let t = rng.range(0.0, std::f64::consts::PI);
        let dir = Vec2::new(t.cos(), t.sin());
        let Some(c) = cut_floe(&floe, &b, &point, &dir) else {
            continue;
        };
        let Some(pieces) = split(&floe, &b, &c) else {
            continue;
        };
        tested += 1;
        let (mut area, mut mass, mut p, mut l, mut e) = (0.0, 0.0, Vec2::zeros(), 0.0, 0.0);
        for q in &pieces {
            let shape: Vec<Vec2> = q.floe.shape.iter().map(|v| v + q.state.position).collect();
            check_convex_ccw(&shape).unwrap_or_else(|e| panic!("piece not convex, CCW: {e}"));
            area += q.floe.area;
            mass += q.floe.mass;
            p += q.state.velocity * q.floe.mass;
            let r = q.state.position - b.position;
            l += q.floe.inertia * q.state.angular_velocity
                + q.floe.mass * cross(&r, &q.state.velocity);
            e += q
                .floe
                .kinetic_energy(&q.state.velocity, q.state.angular_velocity);
            assert_eq!(q.floe.parent, Some(floe.id));
            assert_eq!(q.state.angle, 0.0);
        }
        assert!(
            rel(area, floe.area) <= 1e-12,
            "area {area} vs {}",
            floe.area
        );
        assert!(
            rel(mass, floe.mass) <= 1e-12,
            "mass {mass} vs {}",
            floe.mass
        );
        let p0 = b.velocity * floe.mass;
        let pscale = floe.mass * (b.velocity.norm() + b.angular_velocity.abs() * floe.radius);
        assert!((p - p0).norm() <= 1e-12 * pscale, "momentum {p} vs {p0}");
        let l0 = floe.inertia * b.angular_velocity;
        let lscale = pscale * floe.radius;
        assert!(
            (l - l0).abs() <= 1e-12 * lscale,
            "angular momentum {l} vs {l0}"
        );
        let e0 = floe.kinetic_energy(&b.velocity, b.angular_velocity);
        assert!(rel(e, e0) <= 1e-12, "kinetic energy {e} vs {e0}");
        // Non-overlapping: the pieces share the chord and nothing more.
        let world = |q: &floebench::fracture::split::Piece| -> Vec<Vec2> {
            q.floe.shape.iter().map(|v| v + q.state.position).collect()
        };
        let sep = sat_separation(&world(&pieces[0]), &world(&pieces[1]));
        assert!(sep >= -1e-9 * floe.radius, "pieces overlap by {}", -sep);
        assert!(c.length > 0.0 && c.length <= 2.0 * floe.radius * (1.0 + 1e-12));
    }
    assert!(tested >= 200, "only {tested} splits tested");
}

#[test]
fn a_chord_that_misses_or_grazes_the_floe_does_not_cut_it() {
    let square = [
        Vec2::new(0.0, 0.0),
        Vec2::new(10.0, 0.0),
        Vec2::new(10.0, 10.0),
        Vec2::new(0.0, 10.0),
    ];
    let x = Vec2::new(1.0, 0.0);
    assert!(cut(&square, &Vec2::new(0.0, 20.0), &x).is_none(), "misses");
    assert!(
        cut(&square, &Vec2::new(0.0, 10.0), &x).is_none(),
        "along an edge"
    );
    assert!(
        cut(&square, &Vec2::new(0.0, 0.0), &Vec2::new(1.0, -1.0)).is_none(),
        "touches a vertex"
    );
    let c = cut(&square, &Vec2::new(3.0, 3.0), &Vec2::new(1.0, 1.0)).unwrap_or_else(|| panic!());
    assert!(rel(c.length, 200f64.sqrt()) <= 1e-15, "the diagonal");
    assert_eq!(c.left.len(), 3);
    assert_eq!(c.right.len(), 3);
    let a = area_properties(&c.left).area + area_properties(&c.right).area;
    assert!(rel(a, 100.0) <= 1e-15);
}
