//! The cost of one 2D percussion (docs/physics.md §7.3) against the number
//! of nodes: a 10 m square floe 1 m thick struck in the middle of a face by
//! a striker of its own mass at 0.1 m/s (it stays whole), at lattice
//! spacings 1, 0.5 and 0.25 m (about 90, 300 and 1100 nodes), with
//! central springs alone (`percussion_2d`, ν = 1/3) and with torsion
//! springs (`percussion_2d_torsion`, ν = 0.3: three corners per triangle,
//! about six per node, each an `atan2` per force evaluation), and on the
//! regular triangular mesh (`percussion_2d_triangular`, ν = 1/3, about
//! 130, 500 and 1900 nodes: its density is `2/(√3 s²)`, against about
//! `0.65/s²` for the Poisson-disc set). The lattice is built once; one
//! iteration is one percussion, from the impact to the stopping rule.
//!
//! `cargo bench --bench percussion`

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion};
use floebench::fracture::chain::{BondRule, ChainOptions};
use floebench::fracture::lattice::percussion::{Impact, Percussion, RigidMotion};
use floebench::fracture::lattice::{Lattice, LatticeSpec, Mesh};
use floebench::geometry::Vec2;
use std::hint::black_box;

fn percussion(c: &mut Criterion) {
    let square = [
        Vec2::new(0.0, 0.0),
        Vec2::new(10.0, 0.0),
        Vec2::new(10.0, 10.0),
        Vec2::new(0.0, 10.0),
    ];
    let triangular = Mesh::triangular_variant(0.0, 1);
    for (name, poisson, mesh) in [
        ("percussion_2d", 1.0 / 3.0, Mesh::Random),
        ("percussion_2d_torsion", 0.3, Mesh::Random),
        ("percussion_2d_triangular", 1.0 / 3.0, triangular),
    ] {
        let mut group = c.benchmark_group(name);
        group.sample_size(10);
        for spacing in [1.0, 0.5, 0.25] {
            let lattice = Lattice::build(
                &square,
                LatticeSpec {
                    spacing,
                    thickness: 1.0,
                    density: 917.0,
                    young: 8.95e9,
                    poisson,
                    seed: 1,
                    mesh,
                },
            )
            .expect("lattice");
            let mass: f64 = lattice.mass.iter().sum();
            let impact = Impact {
                point: Vec2::new(0.0, 5.0),
                normal: Vec2::new(1.0, 0.0),
                mass,
                speed: 0.1,
            };
            let options = ChainOptions {
                bond: BondRule::Strain(1e-4),
                ..ChainOptions::default()
            };
            group.bench_with_input(
                BenchmarkId::new("nodes", lattice.nodes.len()),
                &lattice,
                |b, l| {
                    b.iter(|| {
                        let mut p = Percussion::new(l, RigidMotion::default(), impact, options)
                            .expect("percussion");
                        black_box(p.run().steps)
                    })
                },
            );
        }
        group.finish();
    }
}

criterion_group!(benches, percussion);
criterion_main!(benches);
