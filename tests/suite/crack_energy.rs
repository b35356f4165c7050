//! The toughness rule's crack energy per unit length (docs/physics.md §7.3,
//! "The crack energy of the toughness rule"): a straight cut across a
//! lattice, the breaking energies `½ κ δ_c²` of the bonds it crosses
//! summed, against `G h L` times the lattice's geometry factor
//! `2 ⟨|t·n|⟩` (`4/π` for an isotropic mesh, `2/√3` along a direction of the
//! triangular mesh, `4/3` across one), at two spacings; and the same for
//! the cohesive rule, whose bonds take `G h w` too (the area under their
//! softening envelope).

use crate::common::square;
use floebench::fracture::chain::{BondRule, ChainOptions};
use floebench::fracture::lattice::percussion::{Impact, Percussion, RigidMotion};
use floebench::fracture::lattice::{Lattice, LatticeSpec, Mesh};
use floebench::geometry::{cross, Vec2};

/// The toughness of the tests, J/m².
const G: f64 = 2.5;
/// The floe's side (a square) and thickness, m.
const SIDE: f64 = 10.0;
const THICKNESS: f64 = 1.0;

/// A 10 m square of ice at `spacing` on `mesh` (seed `seed`).
fn floe(spacing: f64, seed: u64, mesh: Mesh) -> Lattice {
    Lattice::build(
        &square(SIDE),
        LatticeSpec {
            spacing,
            thickness: THICKNESS,
            seed,
            mesh,
            ..LatticeSpec::default()
        },
    )
    .expect("lattice")
}

/// Whether the segments `a b` and `c d` cross (at a point inside both).
fn crosses(a: &Vec2, b: &Vec2, c: &Vec2, d: &Vec2) -> bool {
    let side = |p: &Vec2, q: &Vec2, r: &Vec2| cross(&(q - p), &(r - p));
    side(a, b, c) * side(a, b, d) < 0.0 && side(c, d, a) * side(c, d, b) < 0.0
}

/// The cut of the square at height `y` (horizontal) or abscissa `y`
/// (vertical): the summed breaking energy (J) of the bonds its chord
/// crosses under the toughness rule, over `G h L` (`L` = the side, the
/// chord's length).
fn cut(lattice: &Lattice, y: f64, vertical: bool) -> f64 {
    cut_by(lattice, y, vertical, BondRule::Toughness(G))
}

/// [`cut`] under the bond rule `bond`.
fn cut_by(lattice: &Lattice, y: f64, vertical: bool, bond: BondRule) -> f64 {
    let percussion = Percussion::new(
        lattice,
        RigidMotion::default(),
        Impact {
            point: Vec2::new(0.0, 0.5 * SIDE),
            normal: Vec2::new(1.0, 0.0),
            mass: f64::INFINITY,
            speed: 1.0,
        },
        ChainOptions {
            bond,
            ..ChainOptions::default()
        },
    )
    .expect("percussion");
    let (a, b) = if vertical {
        (Vec2::new(y, -1.0), Vec2::new(y, SIDE + 1.0))
    } else {
        (Vec2::new(-1.0, y), Vec2::new(SIDE + 1.0, y))
    };
    let energy: f64 = lattice
        .springs
        .iter()
        .enumerate()
        .filter(|(_, s)| {
            crosses(
                &a,
                &b,
                &lattice.nodes[s.nodes[0]],
                &lattice.nodes[s.nodes[1]],
            )
        })
        .map(|(k, _)| percussion.breaking_energy(k))
        .sum();
    energy / (G * THICKNESS * SIDE)
}

/// The cut heights: ten lines spread over the square's inner 80 %, off the
/// triangular mesh's rows and the Poisson disc's outline points.
fn heights() -> Vec<f64> {
    (0..10)
        .map(|i| 1.0 + 8.0 * (i as f64 + 0.37) / 10.0)
        .collect()
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

/// On the triangular mesh (its first direction along x), a cut along x
/// crosses `2/s` bonds per metre, each holding `G h s/√3`: `(2/√3) G h`
/// per metre; a cut along y crosses `4/(√3 s)`: `(4/3) G h`. Inside, this
/// is exact; the boundary cells, at most one spacing at each end of the
/// 10 m chord, are not equilateral, so each cut is held to `2 s / L` of
/// that (10 % at 0.5 m, 5 % at 0.25 m) and the mean of ten cuts to 2 %,
/// at both spacings: the energy per unit length does not depend on it.
#[test]
fn a_straight_cut_of_the_triangular_mesh_costs_g_times_its_geometry_factor_at_any_spacing() {
    for spacing in [0.5, 0.25] {
        let lattice = floe(spacing, 1, Mesh::triangular_variant(0.0, 1));
        for (vertical, factor) in [(false, 2.0 / 3f64.sqrt()), (true, 4.0 / 3.0)] {
            let ratios: Vec<f64> = heights()
                .iter()
                .map(|&y| cut(&lattice, y, vertical) / factor)
                .collect();
            let m = mean(&ratios);
            eprintln!("triangular s = {spacing} vertical = {vertical}: mean {m}, {ratios:?}");
            for r in &ratios {
                assert!(
                    (r - 1.0).abs() < 2.0 * spacing / SIDE,
                    "spacing {spacing}, vertical {vertical}: cut energy {r} of the factor's"
                );
            }
            assert!(
                (m - 1.0).abs() < 0.02,
                "spacing {spacing}, vertical {vertical}: mean cut energy {m} of the factor's"
            );
        }
    }
}

/// On the random mesh (isotropic), a straight cut costs on average
/// `(4/π) G h` per metre, `4/π = 2 ⟨|cos|⟩` the mean number of facets'
/// lengths crossed per unit length; one cut crosses some 20–40 bonds of
/// scattered facets, so the mean over ten cuts, both directions, three
/// seeds, is held to 3 % of `4/π` at 0.5 m and at 0.25 m, and the two
/// spacings' means to 3 % of each other.
#[test]
fn a_straight_cut_of_the_random_mesh_costs_four_over_pi_g_per_metre_at_any_spacing() {
    let factor = 4.0 / std::f64::consts::PI;
    let mut means = Vec::new();
    for spacing in [0.5, 0.25] {
        let ratios: Vec<f64> = random_cuts(spacing, BondRule::Toughness(G))
            .iter()
            .map(|c| c / factor)
            .collect();
        let m = mean(&ratios);
        let spread = ratios.iter().fold(0.0f64, |a, r| a.max((r - m).abs()));
        eprintln!("random s = {spacing}: mean {m}, largest departure from it {spread}");
        assert!(
            (m - 1.0).abs() < 0.03,
            "spacing {spacing}: mean cut energy {m} of (4/π) G h L"
        );
        means.push(m);
    }
    assert!(
        (means[0] / means[1] - 1.0).abs() < 0.03,
        "the mean cut energy moves with the spacing: {means:?}"
    );
}

/// The cuts of the random mesh at `spacing`, seeds 1–3, ten along x and
/// ten along y each, under `bond`: their energies over `G h L`.
fn random_cuts(spacing: f64, bond: BondRule) -> Vec<f64> {
    let mut cuts = Vec::new();
    for seed in 1..=3 {
        let lattice = floe(spacing, seed, Mesh::Random);
        for vertical in [false, true] {
            for y in heights() {
                cuts.push(cut_by(&lattice, y, vertical, bond));
            }
        }
    }
    cuts
}

/// The cohesive rule (strength 0.3 MPa, the same `G`) on the random mesh at
/// 0.5 m and 0.25 m, both fine enough for its crack band (below 0.746 m):
/// every bond crossed takes `G h w`, the area under its envelope (or, for
/// the bonds too coarse to soften, 29 % at 0.5 m, the toughness rule's
/// `G h w`), so each cut costs what the toughness rule's does (to 1e-9)
/// and the mean of sixty cuts is `4/π G h L` to 3 % at both spacings.
#[test]
fn a_straight_cut_costs_four_over_pi_g_per_metre_under_the_cohesive_rule_too() {
    let cohesive = BondRule::Cohesive {
        toughness: G,
        strength: 3.0e5,
    };
    let factor = 4.0 / std::f64::consts::PI;
    for spacing in [0.5, 0.25] {
        let toughness = random_cuts(spacing, BondRule::Toughness(G));
        let cuts = random_cuts(spacing, cohesive);
        for (c, t) in cuts.iter().zip(&toughness) {
            assert!(
                (c - t).abs() < 1e-9 * t,
                "cohesive {c} against toughness {t}"
            );
        }
        let m = mean(&cuts) / factor;
        eprintln!("cohesive, random s = {spacing}: mean {m}");
        assert!(
            (m - 1.0).abs() < 0.03,
            "spacing {spacing}: mean cut energy {m} of (4/π) G h L"
        );
    }
}
