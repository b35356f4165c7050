//! The trigger bound: the least energy an impact (or several strikers at
//! once) can put into the floe, and an impact below the weakest bond's
//! energy never breaks one.

use super::{diamond, settings, squeeze};
use floebench::fracture::lattice::percussion::{impact_energy_bound, Impact, RigidMotion};
use floebench::fracture::lattice::Lattice;
use floebench::fracture::strike::{chain_options, lattice_spec, strike, strike_all, Strike};
use floebench::geometry::Vec2;

/// Counts a strike run whatever its bound: one below the bound (`below`)
/// must break no bond; `broke_above` counts those above it that broke one.
fn tally(o: &Strike, what: &str, below: &mut usize, broke_above: &mut usize) {
    if o.bound < o.weakest {
        *below += 1;
        assert_eq!(
            o.broken, 0,
            "{what}: bound {} weakest {}",
            o.bound, o.weakest
        );
    } else if o.broken > 0 {
        *broke_above += 1;
    }
}

#[test]
fn the_trigger_bound_skips_only_impacts_that_break_no_bond() {
    // A sweep of impacts run whatever the bound (`trigger = "always"`): on
    // the corner, on a face, off-centre, by a coast and by floes of several
    // masses, from far below the weakest bond's energy to far above. An
    // impact whose bound is below the weakest bond must break none.
    let f = diamond();
    let s = settings(1.0);
    let l = Lattice::build(&f.shape, lattice_spec(&s, &f)).unwrap();
    let (mut below, mut broke_above) = (0, 0);
    let strikes = [
        (Vec2::new(5.0, 0.0), Vec2::new(-1.0, 0.0)),
        (Vec2::new(2.5, 2.5), Vec2::new(-1.0, -1.0).normalize()),
        (Vec2::new(3.5, 1.5), Vec2::new(-1.0, -1.0).normalize()),
        (Vec2::new(-1.0, -4.0), Vec2::new(0.0, 1.0)),
    ];
    for (point, normal) in strikes {
        for mass in [f64::INFINITY, 4.0 * f.mass, 0.2 * f.mass] {
            for k in 0..12 {
                let speed = 1e-3 * 2f64.powi(k) * 0.5;
                let impact = Impact {
                    point,
                    normal,
                    mass,
                    speed,
                };
                let o = strike(&l, impact, chain_options(&s), true, s.min_area, 917.0).unwrap();
                let what = format!("{point:?} {mass} {speed}");
                tally(&o, &what, &mut below, &mut broke_above);
            }
        }
    }
    assert!(
        below >= 12 && broke_above >= 12,
        "{below} below, {broke_above} broke above"
    );
}

#[test]
fn the_bound_of_several_strikers_is_the_least_energy_over_the_frames_that_stop_the_walls() {
    let m = 1000.0;
    let i = 5.0e4;
    let rest = RigidMotion::default();
    let at = |normal: Vec2, mass: f64, speed: f64| Impact {
        point: Vec2::zeros(),
        normal,
        mass,
        speed,
    };
    let x = Vec2::new(1.0, 0.0);
    let rel = |a: f64, b: f64| (a - b).abs() / b;
    // One finite striker: ½ μ_G u², μ_G = m* M / (m* + M); one wall: ½ M u².
    let one = impact_energy_bound(m, i, rest, &[at(x, 3000.0, 2.0)], &[2.0]);
    assert!(rel(one, 0.5 * 750.0 * 4.0) < 1e-12, "{one}");
    let wall = impact_energy_bound(m, i, rest, &[at(x, f64::INFINITY, 2.0)], &[2.0]);
    assert!(rel(wall, 0.5 * m * 4.0) < 1e-12, "{wall}");
    // Squeezed by two equal strikers from opposite sides: the frame stays,
    // both strikers' energy can go into the floe, m* u² (4× one's at m* = M).
    let two = impact_energy_bound(m, i, rest, &[at(x, m, 2.0), at(-x, m, 2.0)], &[2.0, 2.0]);
    assert!(rel(two, m * 4.0) < 1e-12, "{two}");
    // A striker across a wall's normal: W = (u, w) with w minimising.
    let y = Vec2::new(0.0, 1.0);
    let cross_ = impact_energy_bound(
        m,
        i,
        rest,
        &[at(x, f64::INFINITY, 1.0), at(y, m, 2.0)],
        &[1.0, 2.0],
    );
    assert!(
        rel(cross_, 0.5 * m * 1.0 + 0.5 * 500.0 * 4.0) < 1e-12,
        "{cross_}"
    );
    // Two walls closing on the floe: no frame stops both.
    let crush = impact_energy_bound(
        m,
        i,
        rest,
        &[at(x, f64::INFINITY, 1.0), at(-x, f64::INFINITY, 1.0)],
        &[1.0, 1.0],
    );
    assert!(crush.is_infinite());
    // Parallel walls moving together (the floe drifts between them): finite.
    let drift = impact_energy_bound(
        m,
        i,
        rest,
        &[at(x, f64::INFINITY, 1.0), at(-x, f64::INFINITY, -1.0)],
        &[1.0, -1.0],
    );
    assert!(rel(drift, 0.5 * m) < 1e-12, "{drift}");
}

#[test]
fn the_trigger_bound_of_several_strikers_skips_only_impacts_that_break_no_bond() {
    // As the one-striker sweep: squeezed from both sides, and struck on a
    // corner and a face at once by a wall and a floe, from far below the
    // weakest bond's energy to far above, run whatever the bound.
    let f = diamond();
    let s = settings(1.0);
    let l = Lattice::build(&f.shape, lattice_spec(&s, &f)).unwrap();
    let (mut below, mut broke_above) = (0, 0);
    for k in 0..12 {
        let speed = 1e-3 * 2f64.powi(k) * 0.5;
        let mixed = vec![
            Impact {
                point: Vec2::new(5.0, 0.0),
                normal: Vec2::new(-1.0, 0.0),
                mass: f64::INFINITY,
                speed,
            },
            Impact {
                point: Vec2::new(-2.5, -2.5),
                normal: Vec2::new(1.0, 1.0).normalize(),
                mass: 0.3 * f.mass,
                speed: 2.0 * speed,
            },
        ];
        for impacts in [squeeze(&f, speed, true), mixed] {
            let o = strike_all(&l, &impacts, chain_options(&s), true, s.min_area, 917.0).unwrap();
            tally(&o, &format!("{speed}"), &mut below, &mut broke_above);
        }
    }
    assert!(
        below >= 4 && broke_above >= 4,
        "{below} below, {broke_above} broke above"
    );
}
