//! The assembly of a group's contact LCP (docs/physics.md §3.1; the module
//! doc of [`super`]): the Jacobians, the friction groups of flush edge
//! pairs ([`Friction`]), the block-sparse Delassus matrix, the Coulomb
//! rows in velocity units and the scaling.

use super::delassus::delassus_blocks;
use super::pattern::{columns_of, zeroed_matrix, COLUMNS_FROM};
use super::{ContactGroup, ContactLcp, Gen};
use crate::contact::Contact;
use crate::geometry::{cross, Vec2};
use crate::lcp::Lcp;
use crate::model::Scenario;
use faer::Mat;

/// How friction enters the assembled LCP ([`ContactLcp::assemble`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Friction {
    /// One friction resultant per group of contacts of one body pair whose
    /// tangential columns agree to [`FRICTION_MERGE_TOLERANCE`] (the two
    /// points of a flush edge pair), bounded by `μ` times the sum of their
    /// normal impulses: the Lemke formulations (docs/physics.md §3.1,
    /// "Flush edge pairs").
    Merged,
    /// One friction pair per contact point, whatever the columns: the cone
    /// programs (one Coulomb cone per point) and the reference of the tests.
    PerPoint,
}

/// Largest difference between the tangential Jacobian columns of two
/// contacts of one body pair, per body, for one friction resultant to
/// replace theirs ([`Friction::Merged`]): the tangents (unit vectors) and
/// the lever terms `r × T` divided by the body's radius of gyration
/// `√(I/m)` (m) differ by at most this. The two points of a flush edge
/// pair differ by the angle between the edges and by their offset across
/// the edge line (at most the contact distance, 1e-3 of the smallest floe
/// radius by default) over the radius of gyration: 1e-10 to 1e-4 on the
/// jammed bay (`bay_jam_200`), where near-equal columns made Lemke's pivots
/// as small as 1e-10 and cost its feasibility (docs/physics.md §3.3). Two
/// points of one body pair on different edges differ by order one.
pub const FRICTION_MERGE_TOLERANCE: f64 = 1e-3;

/// Whether two contacts of the body pair of `c` have the same friction
/// column to [`FRICTION_MERGE_TOLERANCE`], from their per-body tangential
/// Jacobians `jc`, `jo` (`None`: an obstacle, no rows).
fn same_friction_column(
    scn: &Scenario,
    c: &Contact,
    jc: &[Option<Gen>; 2],
    jo: &[Option<Gen>; 2],
) -> bool {
    [c.a, c.b].iter().enumerate().all(|(slot, &body)| {
        let (Some(x), Some(y)) = (jc[slot], jo[slot]) else {
            return jc[slot].is_none() && jo[slot].is_none();
        };
        let Some(f) = scn.floes.get(body) else {
            return false;
        };
        let gyration = (f.inertia / f.mass).sqrt();
        let dt = (x[0] - y[0]).abs().max((x[1] - y[1]).abs());
        let dr = (x[2] - y[2]).abs() / gyration;
        dt.max(dr) <= FRICTION_MERGE_TOLERANCE
    })
}

/// One Jacobian column block: `(n, r × n)` for a direction `n` at lever arm `r`.
fn jac(n: &Vec2, r: &Vec2) -> Gen {
    [n.x, n.y, cross(r, n)]
}

impl ContactLcp {
    /// Assembles the LCP of `group`, with one friction resultant per flush
    /// edge pair ([`Friction::Merged`], the Lemke formulations) or one per
    /// contact point ([`Friction::PerPoint`]).
    ///
    /// - `centres[i]`: centre of mass of floe `i` (m), for the lever arms;
    /// - `w_free[i]`: free velocity of floe `i`;
    /// - `offset[k]`: the offset `c` of contact `k` (m/s; 0 at an impact).
    pub fn assemble(
        scn: &Scenario,
        centres: &[Vec2],
        contacts: &[Contact],
        group: &ContactGroup,
        w_free: &[Gen],
        offset: &[f64],
        layout: Friction,
    ) -> ContactLcp {
        let n_floes = scn.floes.len();
        let mu = scn.contact.friction;
        let friction = mu > 0.0;
        let m = group.contacts.len();
        let ng = group.floes.len();
        let local = |i: usize| group.floes.binary_search(&i).ok();
        // The tangential Jacobian of each contact, per body (`None` for an
        // obstacle): `(T, r × T)` at its lever arm; computed once, for the
        // grouping and for `H`.
        let jts: Vec<[Option<Gen>; 2]> = group
            .contacts
            .iter()
            .map(|&k| {
                let c = &contacts[k];
                [c.a, c.b].map(|body| {
                    (friction && body < n_floes && local(body).is_some())
                        .then(|| jac(&c.geom.tangent, &(c.geom.point - centres[body])))
                })
            })
            .collect();
        // Friction groups: a contact joins the latest group of its body
        // pair whose first member's tangential columns it matches
        // (`same_friction_column`), else starts one.
        let mut fgroup: Vec<usize> = Vec::with_capacity(if friction { m } else { 0 });
        let mut first: Vec<usize> = Vec::new();
        if friction {
            for (j, &k) in group.contacts.iter().enumerate() {
                let c = &contacts[k];
                let joined = (layout == Friction::Merged)
                    .then(|| {
                        first.iter().rposition(|&f| {
                            let o = &contacts[group.contacts[f]];
                            (o.a, o.b) == (c.a, c.b)
                                && same_friction_column(scn, c, &jts[j], &jts[f])
                        })
                    })
                    .flatten();
                match joined {
                    Some(g) => fgroup.push(g),
                    None => {
                        fgroup.push(first.len());
                        first.push(j);
                    }
                }
            }
        }
        let nf = first.len();
        let cols = m + 2 * nf;
        let mut members = vec![0usize; nf];
        for &g in &fgroup {
            members[g] += 1;
        }
        let mut h = Mat::<f64>::zeros(3 * ng, cols);
        for (j, &k) in group.contacts.iter().enumerate() {
            let c = &contacts[k];
            let n = c.geom.normal;
            let jt = jts[j];
            for (slot, (body, sign)) in [(c.a, -1.0), (c.b, 1.0)].into_iter().enumerate() {
                if body >= n_floes {
                    continue;
                }
                let Some(l) = local(body) else { continue };
                let r = c.geom.point - centres[body];
                let jn = jac(&n, &r);
                for d in 0..3 {
                    h[(3 * l + d, j)] += sign * jn[d];
                }
                if let (true, Some(jt)) = (friction, jt[slot]) {
                    // The group's column: the mean of its members' columns
                    // (a lone contact's own column, exactly).
                    let g = fgroup[j];
                    let k = members[g] as f64;
                    for d in 0..3 {
                        h[(3 * l + d, m + 2 * g)] += sign * jt[d] / k;
                        h[(3 * l + d, m + 2 * g + 1)] -= sign * jt[d] / k;
                    }
                }
            }
        }
        let mut minv = Vec::with_capacity(3 * ng);
        for &i in &group.floes {
            let f = &scn.floes[i];
            minv.extend([1.0 / f.mass, 1.0 / f.mass, 1.0 / f.inertia]);
        }
        // Block-sparse Delassus matrix: the columns of H touching each floe
        // (sorted below), and for each floe the products of those columns'
        // 3-row blocks only (docs/physics.md §3.1).
        let mut touching: Vec<Vec<usize>> = vec![Vec::new(); ng];
        let mut col_floes: Vec<[usize; 2]> = vec![[usize::MAX; 2]; m];
        for (j, &k) in group.contacts.iter().enumerate() {
            let c = &contacts[k];
            let mut ls = [c.a, c.b].map(|b| if b < n_floes { local(b) } else { None });
            ls.sort_unstable_by_key(|l| l.unwrap_or(usize::MAX));
            for (slot, l) in ls.iter().enumerate() {
                if let Some(l) = *l {
                    col_floes[j][slot] = l;
                    touching[l].push(j);
                    // A group's columns once, with its first member.
                    if friction && first[fgroup[j]] == j {
                        let g = fgroup[j];
                        touching[l].extend([m + 2 * g, m + 2 * g + 1]);
                    }
                }
            }
        }
        // Increasing order: what `impulses` sums in (the order does not
        // matter to `delassus_blocks`, which writes each entry once per
        // floe).
        touching.iter_mut().for_each(|t| t.sort_unstable());
        let n = if friction { m + 3 * nf } else { m };
        let mut a = if n >= COLUMNS_FROM {
            zeroed_matrix(n * n)
        } else {
            vec![0.0; n * n]
        };
        delassus_blocks(&h, &minv, &touching, n, &mut a);
        let scale = {
            let d: f64 = (0..cols).map(|k| a[k * n + k]).sum::<f64>() / cols.max(1) as f64;
            if d.is_finite() && d > 0.0 {
                d
            } else {
                1.0
            }
        };
        for r in 0..cols {
            for x in &mut a[r * n..r * n + cols] {
                *x /= scale;
            }
        }
        // Free velocities in group order.
        let mut wf = vec![0.0; 3 * ng];
        for (l, &i) in group.floes.iter().enumerate() {
            wf[3 * l..3 * l + 3].copy_from_slice(&w_free[i]);
        }
        let mut q = vec![0.0; n];
        let mut v_scale = 0.0f64;
        for r in 0..cols {
            // Rows of H non-zero in column r: the blocks of its floes, in
            // increasing order (the same sum as over every row: the others
            // add exact zeros).
            let j = if r < m { r } else { first[(r - m) / 2] };
            let mut hw = 0.0;
            for &l in col_floes[j].iter().filter(|&&l| l != usize::MAX) {
                for k in 3 * l..3 * l + 3 {
                    let term = h[(k, r)] * wf[k];
                    hw += term;
                    v_scale = v_scale.max(term.abs());
                }
            }
            q[r] = hw;
        }
        for (j, &k) in group.contacts.iter().enumerate() {
            q[j] += offset[k];
            v_scale = v_scale.max(offset[k].abs());
        }
        if friction {
            for g in 0..nf {
                // γ rows: + E α.
                a[(m + 2 * g) * n + m + 2 * nf + g] = 1.0;
                a[(m + 2 * g + 1) * n + m + 2 * nf + g] = 1.0;
            }
            // σ row of group g: μ Σ_j λ_j − Eᵀ β̃, in velocity units (see
            // the module doc): times the mean scaled normal diagonal of its
            // members (a lone contact's own).
            let mut diag = vec![0.0; nf];
            for (j, &g) in fgroup.iter().enumerate() {
                diag[g] += a[j * n + j];
            }
            let f_of = |g: usize| {
                let d = diag[g] / members[g] as f64;
                if d > 0.0 && d.is_finite() {
                    d
                } else {
                    1.0
                }
            };
            for (j, &g) in fgroup.iter().enumerate() {
                a[(m + 2 * nf + g) * n + j] = mu * f_of(g);
            }
            for g in 0..nf {
                let s = m + 2 * nf + g;
                a[s * n + m + 2 * g] = -f_of(g);
                a[s * n + m + 2 * g + 1] = -f_of(g);
            }
        }
        let columns = (n >= COLUMNS_FROM).then(|| columns_of(&a, n, m, nf, &touching, &fgroup));
        ContactLcp {
            lcp: Lcp { n, m: a, q },
            m,
            friction,
            mu,
            scale,
            h,
            minv,
            touching,
            columns,
            floes: group.floes.clone(),
            v_scale,
            keys: group.contacts.iter().map(|&k| contacts[k].key()).collect(),
            fgroup,
            friction_groups: nf,
            bounds: Vec::new(),
        }
    }
}
