//! Building a [`Lattice`] from a floe's outline ([`Lattice::build`]): its
//! nodes, Delaunay triangles, calibrated central and torsion springs, and
//! the lumped node masses ([`lumped_masses`]).

use super::points::{poisson_disc, triangular_points};
use super::{corner_angle, delaunay, Corner, Lattice, LatticeSpec, Mesh, Spring};
use crate::fracture::chain::positive;
use crate::geometry::{area_properties, cross, Vec2};
use crate::model::limits::fracture::{POISSON_MAX, POISSON_MIN};
use nalgebra::{Matrix4, Vector4};
use std::collections::HashMap;

/// The angle-sine of the corner `c` of triangle `a b c`.
fn sine_at(a: &Vec2, b: &Vec2, c: &Vec2) -> f64 {
    let (u, v) = (a - c, b - c);
    cross(&u, &v).abs() / (u.norm() * v.norm())
}

impl Lattice {
    /// The lattice of the convex counter-clockwise outline `poly` (m).
    /// Fails when the spec is not positive and finite, the spacing is not
    /// below the outline's size, the triangles do not cover the outline
    /// (area to 1e-9 relative), or the mass correction would make a mass
    /// not positive.
    pub fn build(poly: &[Vec2], spec: LatticeSpec) -> Result<Lattice, String> {
        positive("spacing", spec.spacing)?;
        positive("thickness", spec.thickness)?;
        positive("density", spec.density)?;
        positive("Young's modulus", spec.young)?;
        if !(spec.poisson > POISSON_MIN && spec.poisson <= POISSON_MAX) {
            return Err(format!(
                "the lattice's Poisson ratio must be in (-1, 1/3] (central springs give 1/3, \
                 torsion springs lower it; -1 would need infinitely stiff ones), got {}",
                spec.poisson
            ));
        }
        let props = area_properties(poly);
        if props.area.is_nan() || props.area <= 0.0 {
            return Err("the outline has no area".into());
        }
        if spec.spacing * spec.spacing > props.area {
            return Err(format!(
                "spacing {} m is not below the outline's size (area {} m²)",
                spec.spacing, props.area
            ));
        }
        let (nodes, nb) = match spec.mesh {
            Mesh::Random => poisson_disc(poly, spec.spacing, spec.seed),
            Mesh::Triangular { angle, offset } => {
                if !(angle.is_finite() && offset.iter().all(|o| o.is_finite())) {
                    return Err(format!(
                        "the triangular mesh's angle and offset must be finite, got {angle} and \
                         {offset:?}"
                    ));
                }
                triangular_points(poly, spec.spacing, angle, offset)
            }
        };
        let triangles = delaunay::triangulate(&nodes);
        let tri_area = |t: &[usize; 3]| {
            0.5 * cross(&(nodes[t[1]] - nodes[t[0]]), &(nodes[t[2]] - nodes[t[0]]))
        };
        let area: f64 = triangles.iter().map(tri_area).sum();
        if (area - props.area).abs() > 1e-9 * props.area {
            return Err(format!(
                "the triangulation covers {area} m² of an outline of {} m²",
                props.area
            ));
        }
        // Springs: k / sin θ per triangle edge, with k = 1 N/m for now.
        let mut index: HashMap<(usize, usize), usize> = HashMap::new();
        let mut springs: Vec<Spring> = Vec::new();
        let mut triangle_springs = Vec::with_capacity(triangles.len());
        let mut sum = 0.0; // Σ_T Σ_e l² / sin θ
        for t in &triangles {
            let mut row = [(0, 0.0); 3];
            for e in 0..3 {
                let (i, j, o) = (t[e], t[(e + 1) % 3], t[(e + 2) % 3]);
                let s = sine_at(&nodes[i], &nodes[j], &nodes[o]);
                let d = nodes[j] - nodes[i];
                let l = d.norm();
                let key = (i.min(j), i.max(j));
                let k = *index.entry(key).or_insert_with(|| {
                    springs.push(Spring {
                        nodes: [key.0, key.1],
                        stiffness: 0.0,
                        length: l,
                        dir: (nodes[key.1] - nodes[key.0]) / l,
                    });
                    springs.len() - 1
                });
                springs[k].stiffness += 1.0 / s;
                row[e] = (k, 1.0 / s);
                sum += l * l / s;
            }
            triangle_springs.push(row);
        }
        // The isotropic average of the affine response of the springs:
        // λ_s = μ_s = k Σ / (8 A) (times the thickness: k carries it); the
        // bulk modulus λ + μ = 2 μ_s is theirs alone, E h / (2 (1 − ν)), so
        // k = 2 A E h / ((1 − ν) Σ) (3 A E h / Σ at ν = 1/3).
        let k = 2.0 * area * spec.young * spec.thickness / ((1.0 - spec.poisson) * sum);
        // Torsion springs add Δμ = c Σ sin²θ / (2 A) to μ and take it from
        // λ; Δμ = μ_s (1 − 3ν)/(1 + ν) gives the Poisson ratio ν.
        let mut corners = Vec::new();
        let mut torsion = 0.0;
        let ratio = spec.torsion_ratio();
        if ratio > 0.0 {
            let mut sines = 0.0;
            for t in &triangles {
                for e in 0..3 {
                    let (o, a, b) = (t[e], t[(e + 1) % 3], t[(e + 2) % 3]);
                    let (angle, grad) = corner_angle(&nodes[o], &nodes[a], &nodes[b]);
                    sines += angle.sin().powi(2);
                    corners.push(Corner {
                        nodes: [o, a, b],
                        stiffness: 0.0,
                        angle,
                        grad,
                    });
                }
            }
            let mu_s = k * sum / (8.0 * area);
            torsion = 2.0 * area * ratio * mu_s / sines;
            corners.iter_mut().for_each(|c| c.stiffness = torsion);
        }
        for s in &mut springs {
            s.stiffness *= k;
        }
        for row in &mut triangle_springs {
            for e in row.iter_mut() {
                e.1 *= k;
            }
        }
        let mass = lumped_masses(&nodes, &triangles, poly, spec.density * spec.thickness)?;
        let mut on_boundary = vec![false; nodes.len()];
        on_boundary[..nb].iter_mut().for_each(|b| *b = true);
        Ok(Lattice {
            nodes,
            on_boundary,
            mass,
            triangles,
            springs,
            triangle_springs,
            k,
            corners,
            torsion,
            area,
            spec,
        })
    }
}

/// Node masses (kg) of a triangulation of `poly` with surface density
/// `sigma` (kg/m²): each triangle's mass in thirds to its vertices, then
/// the smallest relative change `m_i = m⁰_i (1 + b_iᵀ λ)`,
/// `b_i = (1, x_i, y_i, |x_i − G|²)`, that makes the total mass, the
/// centre of mass `G` and the polar inertia about it the rigid floe's (a
/// 4 × 4 solve). The thirds alone overestimate the inertia by
/// `Σ_T m_T (a² + b² + c²)/12` (three point masses at the corners against
/// the triangle's own `m_T (a² + b² + c²)/36`), a relative `O(h²/D²)`.
pub fn lumped_masses(
    nodes: &[Vec2],
    triangles: &[[usize; 3]],
    poly: &[Vec2],
    sigma: f64,
) -> Result<Vec<f64>, String> {
    let props = area_properties(poly);
    let g = props.centroid;
    let mut m0 = vec![0.0; nodes.len()];
    for t in triangles {
        let a = 0.5 * cross(&(nodes[t[1]] - nodes[t[0]]), &(nodes[t[2]] - nodes[t[0]]));
        for &i in t {
            m0[i] += sigma * a / 3.0;
        }
    }
    let b = |i: usize| {
        let d = nodes[i] - g;
        Vector4::new(1.0, d.x, d.y, d.norm_squared())
    };
    let target = Vector4::new(sigma * props.area, 0.0, 0.0, sigma * props.polar_moment);
    let mut lhs = Matrix4::zeros();
    let mut have = Vector4::zeros();
    for (i, &m) in m0.iter().enumerate() {
        let bi = b(i);
        lhs += bi * bi.transpose() * m;
        have += bi * m;
    }
    let lambda = lhs
        .try_inverse()
        .ok_or("the mass correction is singular (too few nodes)")?
        * (target - have);
    let mass: Vec<f64> = (0..nodes.len())
        .map(|i| m0[i] * (1.0 + b(i).dot(&lambda)))
        .collect();
    if mass.iter().any(|m| m.is_nan() || *m <= 0.0) {
        return Err("the mass correction makes a node mass not positive".into());
    }
    Ok(mass)
}
