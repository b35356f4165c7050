//! The critical ramming speed of the lattice model (docs/physics.md §7.3):
//! a 10 m square floe 1 m thick rammed face-on into a fixed coast, at a
//! series of lattice spacings, by bisection on the speed; the bond rule a
//! critical strain (`--strain E`) or a toughness (`--toughness G`).
//!
//! `cargo run --release --example lattice_ram -- --strain 1e-4 1 0.5 0.25`

use floebench::fracture::chain::{BondRule, ChainOptions};
use floebench::fracture::lattice::percussion::{Impact, Percussion, RigidMotion};
use floebench::fracture::lattice::{Lattice, LatticeSpec};
use floebench::geometry::Vec2;

/// Pieces of at least `min` nodes after a ram at `v0` (m/s).
fn pieces(l: &Lattice, v0: f64, bond: BondRule, min: usize) -> usize {
    let mut p = Percussion::new(
        l,
        RigidMotion {
            velocity: Vec2::new(-v0, 0.0),
            angular_velocity: 0.0,
        },
        Impact {
            point: Vec2::new(0.0, 5.0),
            normal: Vec2::new(1.0, 0.0),
            mass: f64::INFINITY,
            speed: v0,
        },
        ChainOptions {
            bond,
            ..ChainOptions::default()
        },
    )
    .expect("percussion");
    let o = p.run();
    o.fragments.iter().filter(|f| f.nodes.len() >= min).count()
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let value: f64 = args[1].parse().expect("number");
    let bond = match args[0].as_str() {
        "--strain" => BondRule::Strain(value),
        "--toughness" => BondRule::Toughness(value),
        other => panic!("unknown rule {other}"),
    };
    let square = [
        Vec2::new(0.0, 0.0),
        Vec2::new(10.0, 0.0),
        Vec2::new(10.0, 10.0),
        Vec2::new(0.0, 10.0),
    ];
    for s in &args[2..] {
        let spacing: f64 = s.parse().expect("spacing");
        for seed in 1..=3 {
            let l = Lattice::build(
                &square,
                LatticeSpec {
                    spacing,
                    thickness: 1.0,
                    density: 917.0,
                    young: 8.95e9,
                    poisson: 1.0 / 3.0,
                    seed,
                },
            )
            .expect("lattice");
            // Pieces of at least 3 nodes: a broken-off node is debris.
            let breaks = |v: f64| pieces(&l, v, bond, 3) >= 2;
            let (mut lo, mut hi) = (0.0, 1.0);
            while !breaks(hi) {
                lo = hi;
                hi *= 2.0;
                if hi > 1e3 {
                    break;
                }
            }
            while hi - lo > 1e-3 * hi {
                let mid = 0.5 * (lo + hi);
                if breaks(mid) {
                    hi = mid
                } else {
                    lo = mid
                }
            }
            println!(
                "spacing {spacing} seed {seed} nodes {} v_c {hi:.4}",
                l.nodes.len()
            );
        }
    }
}
