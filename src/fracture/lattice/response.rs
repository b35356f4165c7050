//! The lattice under displacements (docs/physics.md §7.2): its stiffness
//! applied without assembling it, the torsion springs' exact forces,
//! tensions and stresses, the force across a cut, static solutions by
//! conjugate gradients ([`Lattice::solve`]) and the effective moduli
//! ([`moduli`]).

use super::{corner_angle, Corner, Lattice};
use crate::geometry::{cross, Vec2};
use nalgebra::{Matrix2, Matrix3};

impl Lattice {
    /// `K u`: the stiffness matrix of the linearised springs applied to
    /// the node displacements `u` (m), in N.
    pub fn apply(&self, u: &[Vec2], out: &mut [Vec2]) {
        out.iter_mut().for_each(|f| *f = Vec2::zeros());
        for s in &self.springs {
            let [i, j] = s.nodes;
            let f = s.dir * (s.stiffness * s.dir.dot(&(u[j] - u[i])));
            out[i] -= f;
            out[j] += f;
        }
        for c in &self.corners {
            let m = c.stiffness * c.angle_change(u);
            for (&i, g) in c.nodes.iter().zip(&c.grad) {
                out[i] += g * m;
            }
        }
    }

    /// The torsion springs' forces (N) at the node positions `x` (m),
    /// geometrically exact (a rigid motion gives none), added to `out`,
    /// those of the triangles `t` with `intact(t)` false left out; returns
    /// their energy `Σ ½ c (θ − θ₀)²`, J.
    pub fn torsion_forces(
        &self,
        x: &[Vec2],
        intact: impl Fn(usize) -> bool,
        out: &mut [Vec2],
    ) -> f64 {
        let mut energy = 0.0;
        for (n, c) in self.corners.iter().enumerate() {
            if !intact(n / 3) {
                continue;
            }
            let [o, a, b] = c.nodes;
            let (theta, grad) = corner_angle(&x[o], &x[a], &x[b]);
            let d = theta - c.angle;
            energy += 0.5 * c.stiffness * d * d;
            for (&i, g) in c.nodes.iter().zip(&grad) {
                out[i] -= g * (c.stiffness * d);
            }
        }
        energy
    }

    /// The virial `Σ_i x_i ⊗ g_i` of corner `c`'s rest gradient, m/m: times
    /// the corner's moment `c δθ` it is its contribution to `A h σ`.
    fn corner_virial(&self, c: &Corner) -> Matrix2<f64> {
        c.nodes
            .iter()
            .zip(&c.grad)
            .map(|(&i, g)| self.nodes[i] * g.transpose())
            .sum()
    }

    /// The tension of each spring under displacements `u`, N.
    pub fn tensions(&self, u: &[Vec2]) -> Vec<f64> {
        self.springs
            .iter()
            .map(|s| s.stiffness * s.dir.dot(&(u[s.nodes[1]] - u[s.nodes[0]])))
            .collect()
    }

    /// The stress of each triangle under displacements `u`, Pa: the virial
    /// `(1/(A_T h)) Σ_e f_e l_e t_e ⊗ t_e` of its share of its three springs,
    /// plus that of its torsion springs, `(1/(A_T h)) Σ_corners c δθ Σ_i x_i ⊗ ∇_i θ`.
    pub fn triangle_stress(&self, u: &[Vec2]) -> Vec<Matrix2<f64>> {
        self.triangles
            .iter()
            .zip(&self.triangle_springs)
            .enumerate()
            .map(|(n, (t, row))| {
                let a = 0.5
                    * cross(
                        &(self.nodes[t[1]] - self.nodes[t[0]]),
                        &(self.nodes[t[2]] - self.nodes[t[0]]),
                    );
                let mut sigma = Matrix2::zeros();
                for &(k, kt) in row {
                    let s = &self.springs[k];
                    let f = kt * s.dir.dot(&(u[s.nodes[1]] - u[s.nodes[0]]));
                    sigma += s.dir * s.dir.transpose() * (f * s.length);
                }
                for c in self.corners.iter().skip(3 * n).take(3) {
                    sigma += self.corner_virial(c) * (c.stiffness * c.angle_change(u));
                }
                sigma / (a * self.spec.thickness)
            })
            .collect()
    }

    /// The mean stress of the whole lattice under `u`, Pa: the virial of
    /// every spring and torsion spring over the lattice's volume.
    pub fn mean_stress(&self, u: &[Vec2]) -> Matrix2<f64> {
        let mut sigma = Matrix2::zeros();
        for (s, f) in self.springs.iter().zip(self.tensions(u)) {
            sigma += s.dir * s.dir.transpose() * (f * s.length);
        }
        for c in &self.corners {
            sigma += self.corner_virial(c) * (c.stiffness * c.angle_change(u));
        }
        sigma / (self.area * self.spec.thickness)
    }

    /// The force (N) that the material on the left of the segment `a → b`
    /// exerts on the material on its right, through the springs that cross
    /// the segment and the torsion springs of the triangles it cuts (in
    /// the share of the triangle's two cut edges that it crosses), under
    /// displacements `u` (small displacements: the crossing is judged at
    /// rest). Across a cut through the whole body this is exact statics,
    /// with no averaging window.
    pub fn force_across(&self, u: &[Vec2], a: &Vec2, b: &Vec2) -> Vec2 {
        let d = b - a;
        let side = |p: &Vec2| cross(&d, &(p - a));
        let mut total = Vec2::zeros();
        for (s, f) in self.springs.iter().zip(self.tensions(u)) {
            let (p, q) = (self.nodes[s.nodes[0]], self.nodes[s.nodes[1]]);
            let (sp, sq) = (side(&p), side(&q));
            if sp * sq >= 0.0 {
                continue;
            }
            let e = q - p;
            let (ta, tb) = (cross(&e, &(a - p)), cross(&e, &(b - p)));
            if ta * tb >= 0.0 {
                continue;
            }
            // The spring pulls its right node towards its left one.
            total += if sp > 0.0 { -s.dir * f } else { s.dir * f };
        }
        // A triangle the line separates has two edges across it; its
        // torsion springs push its nodes on the right with Σ_right f_i,
        // counted in the share of those two crossings inside the segment.
        let crosses = |p: &Vec2, q: &Vec2| {
            let e = q - p;
            side(p) * side(q) < 0.0 && cross(&e, &(a - p)) * cross(&e, &(b - p)) < 0.0
        };
        for (n, t) in self.triangles.iter().enumerate() {
            let Some(corners) = self.corners.get(3 * n..3 * n + 3) else {
                break;
            };
            let p: Vec<Vec2> = t.iter().map(|&i| self.nodes[i]).collect();
            let cut = (0..3).filter(|&e| crosses(&p[e], &p[(e + 1) % 3])).count();
            if cut == 0 {
                continue;
            }
            let mut push = Vec2::zeros();
            for c in corners {
                let m = c.stiffness * c.angle_change(u);
                for (&i, g) in c.nodes.iter().zip(&c.grad) {
                    if side(&self.nodes[i]) < 0.0 {
                        push -= g * m;
                    }
                }
            }
            total += push * (cut as f64 / 2.0);
        }
        total
    }

    /// The static displacements under node forces `force` (N), the nodes
    /// with `fixed[i]` held at `u0[i]` (m), the others starting from
    /// `u0`: conjugate gradients to a residual of `tol` times the norm of
    /// the right-hand side, at most `max_iter` iterations. With no node
    /// fixed the forces must be self-equilibrated (the solution is then
    /// defined up to a rigid motion, which leaves tensions and stresses
    /// unchanged). Returns the displacements, the iterations and the
    /// relative residual.
    pub fn solve(
        &self,
        force: &[Vec2],
        fixed: &[bool],
        u0: &[Vec2],
        tol: f64,
        max_iter: usize,
    ) -> (Vec<Vec2>, usize, f64) {
        let n = self.nodes.len();
        let mask = |v: &mut [Vec2]| {
            for (x, f) in v.iter_mut().zip(fixed) {
                if *f {
                    *x = Vec2::zeros();
                }
            }
        };
        let dot = |a: &[Vec2], b: &[Vec2]| a.iter().zip(b).map(|(x, y)| x.dot(y)).sum::<f64>();
        let mut u = u0.to_vec();
        let mut ku = vec![Vec2::zeros(); n];
        self.apply(&u, &mut ku);
        let mut r: Vec<Vec2> = force.iter().zip(&ku).map(|(f, k)| f - k).collect();
        mask(&mut r);
        let mut rhs: Vec<Vec2> = force.to_vec();
        mask(&mut rhs);
        let scale = dot(&rhs, &rhs).sqrt().max(dot(&r, &r).sqrt());
        if scale == 0.0 {
            return (u, 0, 0.0);
        }
        let mut p = r.clone();
        let mut rr = dot(&r, &r);
        let mut kp = vec![Vec2::zeros(); n];
        let mut it = 0;
        while it < max_iter && rr.sqrt() > tol * scale {
            self.apply(&p, &mut kp);
            mask(&mut kp);
            let pkp = dot(&p, &kp);
            if pkp.is_nan() || pkp <= 0.0 {
                break;
            }
            let alpha = rr / pkp;
            for i in 0..n {
                u[i] += p[i] * alpha;
                r[i] -= kp[i] * alpha;
            }
            let rr_new = dot(&r, &r);
            let beta = rr_new / rr;
            rr = rr_new;
            for i in 0..n {
                p[i] = r[i] + p[i] * beta;
            }
            it += 1;
        }
        (u, it, rr.sqrt() / scale)
    }

    /// The affine displacement field `u = ε x` of strain `eps`.
    pub fn affine(&self, eps: &Matrix2<f64>) -> Vec<Vec2> {
        self.nodes.iter().map(|x| eps * x).collect()
    }

    /// The effective stiffness (Voigt: xx, yy, xy against ε_xx, ε_yy,
    /// γ_xy), Pa, of the three unit strains: every node displaced affinely
    /// (`relaxed = false`), or only the outline's nodes, the inside
    /// relaxed to equilibrium (`relaxed = true`, conjugate gradients to
    /// 1e-10).
    pub fn stiffness(&self, relaxed: bool) -> Matrix3<f64> {
        let strains = [
            Matrix2::new(1.0, 0.0, 0.0, 0.0),
            Matrix2::new(0.0, 0.0, 0.0, 1.0),
            Matrix2::new(0.0, 0.5, 0.5, 0.0),
        ];
        let mut c = Matrix3::zeros();
        for (col, eps) in strains.iter().enumerate() {
            let mut u = self.affine(eps);
            if relaxed {
                let zero = vec![Vec2::zeros(); u.len()];
                u = self.solve(&zero, &self.on_boundary, &u, 1e-10, 100_000).0;
            }
            let s = self.mean_stress(&u);
            c[(0, col)] = s[(0, 0)];
            c[(1, col)] = s[(1, 1)];
            c[(2, col)] = s[(0, 1)];
        }
        c
    }
}

/// Young's moduli along x and y, Poisson ratio ν_xy and shear modulus
/// of a stiffness `c` (Voigt, Pa), from its compliance; `None` if it is
/// singular.
pub fn moduli(c: &Matrix3<f64>) -> Option<(f64, f64, f64, f64)> {
    let s = c.try_inverse()?;
    Some((
        1.0 / s[(0, 0)],
        1.0 / s[(1, 1)],
        -s[(1, 0)] / s[(0, 0)],
        1.0 / s[(2, 2)],
    ))
}
