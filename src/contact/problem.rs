//! The frictional contact problem of a group of touching floes, as the
//! velocity–impulse LCP of docs/physics.md §3.1 (Rabatel 2015;
//! Stewart & Trinkle 1996), shared by the event-driven and the Moreau–Jean
//! formulations.
//!
//! For `m` contacts between the floes of one connected group, with `J` (`D`)
//! the normal (tangential, both directions `±T_j`) Jacobians, `M` the block
//! mass matrix (obstacles have no rows: zero inverse mass), `E` summing the
//! two friction entries of a contact and `W_free` the velocities the floes
//! would have without contact:
//!
//! ```text
//! W⁺ = W_free + M⁻¹ (J λ + D β̃)
//! w = Jᵀ W⁺ + c     ≥ 0 ⟂ λ ≥ 0        (Signorini, with an offset c)
//! γ = Dᵀ W⁺ + E α   ≥ 0 ⟂ β̃ ≥ 0       (friction directions)
//! σ = μ λ − Eᵀ β̃    ≥ 0 ⟂ α ≥ 0       (Coulomb cone, facets ±T)
//! ```
//!
//! so `z = (λ, β̃, α)` (size `4m`) solves `w = A z + q ≥ 0 ⟂ z ≥ 0` with
//! `A = [[JᵀM⁻¹J, JᵀM⁻¹D, 0], [DᵀM⁻¹J, DᵀM⁻¹D, E], [μ, −Eᵀ, 0]]` and
//! `q = (JᵀW_free + c, DᵀW_free, 0)` (the Coulomb rows then scaled to
//! velocities, below), with `H = (J, D)`. Without friction (`μ = 0`) only the
//! normal block is kept (size `m`): the friction unknowns would be zero and
//! the slack `α` undetermined.
//!
//! **Flush edge pairs** ([`Friction::Merged`]). The two points of a
//! nearly flush edge pair have tangential columns equal up to the angle
//! between the edges; the contacts of one body pair whose columns
//! agree to [`FRICTION_MERGE_TOLERANCE`] form one friction group with one
//! friction pair (along the mean of their columns) and one Coulomb row
//! `σ_G = μ Σ_{j∈G} λ_j − β̃⁺_G − β̃⁻_G`: `z = (λ, β̃_G, α_G)` of size
//! `m + 3G`. A lone contact keeps its own column and row, bit for bit
//! (docs/physics.md §3.1, "Flush edge pairs").
//!
//! **Coulomb rows in velocity units.** Each Coulomb row
//! `σ_j = μ λ_j − β̃⁺_j − β̃⁻_j` is assembled multiplied by the contact's
//! scaled normal Delassus diagonal `(JᵀM⁻¹J)_jj / g` (left as it is if that
//! diagonal is not positive and finite), so that every row of `w` is a
//! velocity (m/s). A positive row scaling keeps the solutions (`z`
//! unchanged, `w ≥ 0 ⟂ z ≥ 0` row by row) but makes the residual
//! `‖min(z, w)‖ / ‖q‖` of [`crate::lcp::solve()`] consistent in units:
//! unscaled, `σ` is in N·s while `q` is in m/s, and the rounding of impulses
//! of 1e6 N·s (`σ` ≈ −2e-11 N·s) alone exceeds the acceptance threshold
//! 1e-10 ‖q‖ — measured: a third of the frictional LCPs of
//! `field_200_coast` were rejected after Lemke solved them. (The scaling
//! was a copy of the assembled LCP made before each solve; it is now part
//! of the assembly, the same numbers without the copy.)
//!
//! **Block-sparse Delassus matrix.** A contact couples only with the
//! contacts that share one of its floes, so `HᵀM⁻¹H` can be summed floe
//! by floe over the columns touching each floe (`Σ_l 3 k_l²` fused
//! multiply–adds for `k_l` columns touching floe `l`) instead of as a dense
//! product over every floe of the group; each entry is then the fused sum
//! of its non-zero terms in row order. This is what the assembly computes
//! (the dense product it replaced differs at the last bit on about 1 % of
//! the entries of a 200-floe group, where faer adds its sums by cache
//! blocks of rows: docs/physics.md §3.1).
//!
//! **Scaling.** Delassus entries are inverse masses (1e-8 /kg for a
//! 100 m floe) while `μ` and `E` are of order one; unscaled, Lemke's rounding
//! on the friction rows would swamp the normal rows. The LCP is therefore
//! solved for `z' = (g λ, g β̃, α)` with `g` the mean diagonal of the
//! Delassus matrix: the blocks `HᵀM⁻¹H` are divided by `g`, `q` (velocities)
//! is unchanged, so `w` keeps its unit (m/s) and so does `z'` for the
//! impulses. Dumps hold this scaled LCP; [`ContactLcp::physical`] undoes it.
//!
//! The offset `c` is Rabatel's relaxed Signorini condition `Jᵀ W⁺ ≥ −c`:
//! zero at an impact; for a penetrating sustained contact `c = g / h < 0`
//! asks the contact to separate by `−g` over the step.

use super::{Contact, ContactKey};
use crate::geometry::{cross, Vec2};
use crate::lcp::sparse::Columns;
use crate::lcp::Lcp;
use crate::model::Scenario;
use faer::Mat;

/// Generalised velocity (or impulse) of one floe: `(x, y, θ)` components.
pub type Gen = [f64; 3];

/// A connected group of floes linked by contacts (obstacles do not link).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct ContactGroup {
    /// Floe indices, sorted.
    pub floes: Vec<usize>,
    /// Indices into the contact list, sorted.
    pub contacts: Vec<usize>,
}

/// Splits `contacts` into connected groups of floes (union–find). Bodies
/// with index `>= n_floes` are obstacles and link nothing.
pub fn groups(contacts: &[Contact], n_floes: usize) -> Vec<ContactGroup> {
    fn find(p: &mut [usize], mut i: usize) -> usize {
        while p[i] != i {
            p[i] = p[p[i]];
            i = p[i];
        }
        i
    }
    let mut parent: Vec<usize> = (0..n_floes).collect();
    for c in contacts {
        if c.a < n_floes && c.b < n_floes {
            let (ra, rb) = (find(&mut parent, c.a), find(&mut parent, c.b));
            if ra != rb {
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    let mut by_root: std::collections::BTreeMap<usize, ContactGroup> = Default::default();
    for (k, c) in contacts.iter().enumerate() {
        let floe = if c.a < n_floes { c.a } else { c.b };
        if floe >= n_floes {
            continue; // obstacle–obstacle: never reported by detection
        }
        let root = find(&mut parent, floe);
        let g = by_root.entry(root).or_default();
        g.contacts.push(k);
        for body in [c.a, c.b] {
            if body < n_floes {
                g.floes.push(body);
            }
        }
    }
    by_root
        .into_values()
        .map(|mut g| {
            g.floes.sort_unstable();
            g.floes.dedup();
            g
        })
        .collect()
}

/// The assembled LCP of one group, with what is needed to turn its solution
/// into velocity changes.
#[derive(Debug, Clone)]
pub struct ContactLcp {
    /// The LCP `w = A z + q` ([`ContactLcp::lcp`]; private so that it
    /// keeps the pattern of the assembly, which [`Drop`] relies on).
    lcp: Lcp,
    /// Number of contacts `m`.
    pub m: usize,
    /// Whether friction unknowns are present (size `4m`, else `m`).
    pub friction: bool,
    /// Friction coefficient `μ`.
    pub mu: f64,
    /// The scale `g` (kg⁻¹): mean diagonal of the Delassus matrix; the LCP
    /// unknowns for impulses are `g λ`, `g β̃` (m/s).
    pub scale: f64,
    /// `H = (J, D)`: `3 n_g × (m + 2m)` (or `× m` without friction).
    h: Mat<f64>,
    /// Inverse mass per generalised coordinate of the group (`3 n_g`).
    minv: Vec<f64>,
    /// The columns of `H` that may be non-zero in the rows of each floe of
    /// the group (those of its contacts), in increasing order.
    touching: Vec<Vec<usize>>,
    /// The compressed columns of `lcp.m`, built from the known pattern for
    /// a large LCP (at least [`COLUMNS_FROM`] unknowns), so that the solver
    /// does not read all of `M` to find its non-zeros.
    columns: Option<Columns>,
    /// Floe indices of the group.
    pub floes: Vec<usize>,
    /// Largest term of the free relative velocities `q` (a single body's
    /// contribution or an offset), m/s: the scale of their rounding.
    pub v_scale: f64,
    /// Identity of each contact, in LCP order (for warm starts).
    pub keys: Vec<ContactKey>,
    /// The friction group of each contact (length `m` with friction, empty
    /// without): contacts of one body pair whose friction columns agree
    /// share one friction resultant (see the module doc).
    fgroup: Vec<usize>,
    /// Number of friction groups `G` (`m` when nothing is merged, 0
    /// without friction); `n = m + 3G`.
    pub friction_groups: usize,
}

/// Unknowns from which the assembly builds the compressed columns of the
/// LCP's matrix for the solver: where the solver uses them (the factorised
/// basis, [`crate::lcp::lemke_options::REVISED_FROM`]).
const COLUMNS_FROM: usize = crate::lcp::lemke_options::REVISED_FROM;

/// Calls `entry(row, column)` for every entry of the assembled matrix
/// (`m` contacts, `nf` friction groups, `nf = 0` without friction) that can
/// be non-zero, from its pattern: the Delassus entry `(r, c)` only if
/// columns `r` and `c` of `H` touch a common floe (`touching`), the γ
/// entries in the rows of the two friction columns of a group and its σ
/// column, and in a σ row its group's normal and friction columns. Repeats
/// are allowed. Every entry the assembly writes is in this pattern (the
/// columns built from it are those of a full scan, tested); the others
/// stay `+0.0`.
fn pattern(
    m: usize,
    nf: usize,
    touching: &[Vec<usize>],
    fgroup: &[usize],
    mut entry: impl FnMut(usize, usize),
) {
    for t in touching {
        for &c in t {
            for &r in t {
                entry(r, c);
            }
        }
    }
    for (j, &g) in fgroup.iter().enumerate() {
        entry(m + 2 * nf + g, j);
    }
    for g in 0..nf {
        let s = m + 2 * nf + g;
        entry(s, m + 2 * g);
        entry(s, m + 2 * g + 1);
        entry(m + 2 * g, s);
        entry(m + 2 * g + 1, s);
    }
}

/// The compressed columns of the assembled matrix `a` (`n × n`, row-major)
/// from its [`pattern`].
fn columns_of(
    a: &[f64],
    n: usize,
    m: usize,
    nf: usize,
    touching: &[Vec<usize>],
    fgroup: &[usize],
) -> Columns {
    let mut cand: Vec<Vec<usize>> = vec![Vec::new(); n];
    pattern(m, nf, touching, fgroup, |r, c| cand[c].push(r));
    let mut cols = Columns::default();
    cols.fill_from_candidates(a, n, |j| &cand[j], &mut Vec::new());
    cols
}

thread_local! {
    /// A zeroed buffer for the dense matrix of the next large assembly,
    /// left by the last large [`ContactLcp`] dropped on this thread (see
    /// [`zeroed_matrix`]).
    static SPARE_MATRIX: std::cell::RefCell<Vec<f64>> = const { std::cell::RefCell::new(Vec::new()) };
}

/// A vector of `len` zeros (`+0.0`) for an assembled matrix: the spare
/// buffer of this thread when there is one (only the part beyond its
/// length is written), else a new one.
///
/// Zeroing the `n²` entries of a large group's matrix at each assembly
/// (13.5 MB for 1,300 unknowns) cost 6.5 % of an hour of field_200_coast
/// (event-driven), more than the entries the assembly then writes; a
/// dropped large LCP instead zeroes only its [`pattern`] and
/// leaves its buffer here.
fn zeroed_matrix(len: usize) -> Vec<f64> {
    let mut a = SPARE_MATRIX
        .try_with(|s| std::mem::take(&mut *s.borrow_mut()))
        .unwrap_or_default();
    if a.len() >= len {
        a.truncate(len);
    } else {
        a.resize(len, 0.0);
    }
    a
}

/// `HᵀM⁻¹H` by the dense faer product over every row of `H`
/// (`minv`: the inverse mass of each row): what the assembly computed
/// before the block-sparse sum ([`delassus_blocks`]), kept as the
/// reference of its tests ([`ContactLcp::dense_delassus_reference`]).
fn dense_delassus(h: &Mat<f64>, minv: &[f64]) -> Mat<f64> {
    let mut minv_h = h.clone();
    for r in 0..h.nrows() {
        for c in 0..h.ncols() {
            minv_h[(r, c)] *= minv[r];
        }
    }
    h.transpose() * &minv_h
}

/// Adds the Delassus matrix `HᵀM⁻¹H` into the row-major `a` (leading
/// dimension `n`), floe by floe: for floe `l` (rows `3l..3l + 3` of `H`,
/// inverse masses `minv`) and every pair `(r, c)` of the columns
/// `touching[l]` that are non-zero in those rows,
/// `a_rc ← fma(H_kr, M⁻¹_k H_kc, a_rc)` for `k = 3l, 3l + 1, 3l + 2`.
/// Floes are visited in increasing order, so each entry is the fused sum
/// over `k` in increasing order of its non-zero terms — what the dense
/// product over every row computed (the rows of other floes add exact
/// zeros) — at the cost of `Σ_l 3 |touching[l]|²` instead of
/// `3 n_g · cols²`.
fn delassus_blocks(h: &Mat<f64>, minv: &[f64], touching: &[Vec<usize>], n: usize, a: &mut [f64]) {
    #[cfg(target_arch = "x86_64")]
    {
        if std::arch::is_x86_feature_detected!("fma") {
            // SAFETY: the CPU supports FMA, checked just above.
            unsafe { delassus_blocks_fma(h, minv, touching, n, a) };
            return;
        }
    }
    delassus_blocks_body(h, minv, touching, n, a);
}

/// [`delassus_blocks`] compiled with FMA (`mul_add` is then one
/// instruction instead of a correctly rounded software routine: the same
/// result).
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "fma")]
unsafe fn delassus_blocks_fma(
    h: &Mat<f64>,
    minv: &[f64],
    touching: &[Vec<usize>],
    n: usize,
    a: &mut [f64],
) {
    delassus_blocks_body(h, minv, touching, n, a);
}

#[inline(always)]
fn delassus_blocks_body(
    h: &Mat<f64>,
    minv: &[f64],
    touching: &[Vec<usize>],
    n: usize,
    a: &mut [f64],
) {
    for (l, cols) in touching.iter().enumerate() {
        for &r in cols {
            let hr = [h[(3 * l, r)], h[(3 * l + 1, r)], h[(3 * l + 2, r)]];
            for &c in cols {
                let e = &mut a[r * n + c];
                for (d, &hd) in hr.iter().enumerate() {
                    let k = 3 * l + d;
                    *e = hd.mul_add(h[(k, c)] * minv[k], *e);
                }
            }
        }
    }
}

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

/// The capacity (entries) of this thread's spare matrix buffer
/// ([`zeroed_matrix`]): 0 when there is none. For the tests of its reuse.
#[doc(hidden)]
pub fn spare_matrix_capacity() -> usize {
    SPARE_MATRIX
        .try_with(|s| s.borrow().capacity())
        .unwrap_or(0)
}

impl Drop for ContactLcp {
    /// A large LCP (one with columns built at assembly) zeroes the entries
    /// of its matrix in the [`pattern`] of the assembly (every entry the
    /// assembly wrote; the others are zeros) and leaves the
    /// buffer for the next assembly on this thread ([`zeroed_matrix`]), if
    /// it is larger than the one there.
    fn drop(&mut self) {
        if self.columns.is_none() {
            return;
        }
        let n = self.lcp.n;
        let mut a = std::mem::take(&mut self.lcp.m);
        if a.len() != n * n {
            return;
        }
        pattern(
            self.m,
            self.friction_groups,
            &self.touching,
            &self.fgroup,
            |r, c| a[r * n + c] = 0.0,
        );
        let _ = SPARE_MATRIX.try_with(|s| {
            let mut s = s.borrow_mut();
            if a.capacity() > s.capacity() {
                *s = a;
            }
        });
    }
}

impl ContactLcp {
    /// The assembled LCP `w = A z + q` (scaled: see the module doc).
    pub fn lcp(&self) -> &Lcp {
        &self.lcp
    }

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
        }
    }

    /// The number of friction groups when some contacts share one
    /// (`n = m + 3G`), `None` when each contact has its own or there is no
    /// friction (what an LCP dump records, [`crate::lcp::LcpDump`]).
    pub fn merged_groups(&self) -> Option<usize> {
        (self.friction && self.friction_groups != self.m).then_some(self.friction_groups)
    }

    /// The friction group of contact `j` (`j` itself without merging).
    pub fn friction_group(&self, j: usize) -> usize {
        self.fgroup.get(j).copied().unwrap_or(j)
    }

    /// The indices of contact `j`'s unknowns `(λ_j, β̃⁺, β̃⁻, α)` (the last
    /// three its friction group's; only `λ_j` without friction).
    pub fn unknowns(&self, j: usize) -> impl Iterator<Item = usize> {
        let (m, nf, g) = (self.m, self.friction_groups, self.friction_group(j));
        [j, m + 2 * g, m + 2 * g + 1, m + 2 * nf + g]
            .into_iter()
            .take(if self.friction { 4 } else { 1 })
    }

    /// The unknowns of each friction group (its members' `λ`, then its
    /// `β̃⁺`, `β̃⁻`, `α`), or of each contact (`λ_j`) without friction: the
    /// blocks of a block Gauss–Seidel sweep.
    pub fn blocks(&self) -> Vec<Vec<usize>> {
        if !self.friction {
            return (0..self.m).map(|j| vec![j]).collect();
        }
        let (m, nf) = (self.m, self.friction_groups);
        let mut out: Vec<Vec<usize>> = vec![Vec::new(); nf];
        for (j, &g) in self.fgroup.iter().enumerate() {
            out[g].push(j);
        }
        for (g, b) in out.iter_mut().enumerate() {
            b.extend([m + 2 * g, m + 2 * g + 1, m + 2 * nf + g]);
        }
        out
    }

    /// The scaled Delassus block `HᵀM⁻¹H / g` (`cols × cols`, row-major,
    /// `cols` the columns of `H`) by the dense faer product over every row
    /// of `H` (what the assembly computed before the block-sparse sum). A
    /// reference for the tests of the block-sparse sum only.
    #[doc(hidden)]
    pub fn dense_delassus_reference(&self) -> Vec<f64> {
        let cols = self.h.ncols();
        let g = dense_delassus(&self.h, &self.minv);
        let mut out = vec![0.0; cols * cols];
        for r in 0..cols {
            for c in 0..cols {
                out[r * cols + c] = g[(r, c)] / self.scale;
            }
        }
        out
    }

    /// The compressed columns of `lcp.m` built at assembly, if the LCP is
    /// large enough to have them.
    pub(crate) fn columns(&self) -> Option<&Columns> {
        self.columns.as_ref()
    }

    /// Whether the columns built at assembly from the pattern (if any) are
    /// those of a scan of every entry of `lcp.m`, bit for bit; `None` if
    /// this LCP has none. For the tests of the pattern.
    #[doc(hidden)]
    pub fn columns_match_a_full_scan(&self) -> Option<bool> {
        let built = self.columns.as_ref()?;
        let mut scanned = Columns::default();
        scanned.scan(&self.lcp.m, self.lcp.n);
        Some(built.same_as(&scanned))
    }

    /// The generalised impulses `H (λ, β̃)` per floe by the row sums over
    /// every column of `H` (what [`ContactLcp::impulses`] computed before it
    /// summed over each floe's own columns). A reference for its tests only.
    #[doc(hidden)]
    pub fn dense_impulses_reference(&self, z: &[f64]) -> Vec<Gen> {
        let cols = self.h.ncols();
        let zp = self.physical(z);
        let mut out = vec![[0.0; 3]; self.floes.len()];
        for (l, o) in out.iter_mut().enumerate() {
            for (d, od) in o.iter_mut().enumerate() {
                let r = 3 * l + d;
                *od = zp
                    .iter()
                    .take(cols)
                    .enumerate()
                    .map(|(c, zc)| self.h[(r, c)] * zc)
                    .sum();
            }
        }
        out
    }

    /// The scaled Delassus block `HᵀM⁻¹H / g` (`cols × cols`, row-major)
    /// by the block-sparse sum ([`delassus_blocks`], what the assembly
    /// computes), recomputed from `H` alone, for its tests.
    #[doc(hidden)]
    pub fn block_sparse_delassus(&self) -> Vec<f64> {
        let (rows, cols) = (self.h.nrows(), self.h.ncols());
        let touching: Vec<Vec<usize>> = (0..rows / 3)
            .map(|l| {
                (0..cols)
                    .filter(|&c| (3 * l..3 * l + 3).any(|k| self.h[(k, c)] != 0.0))
                    .collect()
            })
            .collect();
        let mut out = vec![0.0; cols * cols];
        delassus_blocks(&self.h, &self.minv, &touching, cols, &mut out);
        out.iter_mut().for_each(|x| *x /= self.scale);
        out
    }

    /// The physical unknowns `(λ, β̃, α)` (N·s, N·s, m/s) of an LCP
    /// solution `z' = (g λ, g β̃, α)`.
    pub fn physical(&self, z: &[f64]) -> Vec<f64> {
        let cols = self.h.ncols();
        z.iter()
            .enumerate()
            .map(|(k, v)| if k < cols { v / self.scale } else { *v })
            .collect()
    }

    /// The generalised impulses `H (λ, β̃)` per floe of the group, in group
    /// order, from an LCP solution `z'`.
    ///
    /// Each floe's sums run over the columns of its own contacts, in
    /// increasing order: the terms of the other columns are exact zeros
    /// (`H` is zero there and `z'` finite), so this is the row sum over
    /// every column, up to the sign of a zero.
    pub fn impulses(&self, z: &[f64]) -> Vec<Gen> {
        let zp = self.physical(z);
        let mut out = vec![[0.0; 3]; self.floes.len()];
        for ((l, o), cols) in out.iter_mut().enumerate().zip(&self.touching) {
            for (d, od) in o.iter_mut().enumerate() {
                let r = 3 * l + d;
                *od = cols.iter().map(|&c| self.h[(r, c)] * zp[c]).sum();
            }
        }
        out
    }

    /// The velocity changes `M⁻¹ H (λ, β̃)` per floe of the group.
    pub fn velocity_changes(&self, z: &[f64]) -> Vec<Gen> {
        let mut p = self.impulses(z);
        for (l, g) in p.iter_mut().enumerate() {
            for (d, gd) in g.iter_mut().enumerate() {
                *gd *= self.minv[3 * l + d];
            }
        }
        p
    }

    /// Normal impulses `λ` (N·s) from an LCP solution `z'`.
    pub fn normal(&self, z: &[f64]) -> Vec<f64> {
        z.iter().take(self.m).map(|v| v / self.scale).collect()
    }

    /// Signed tangential impulses `β_j = β̃⁺_j − β̃⁻_j` along `T_j` (N·s).
    /// A merged friction group's resultant is shared among its members in
    /// proportion to their normal impulses (equally if none pushes), which
    /// keeps each member within its own cone `|β_j| ≤ μ λ_j`.
    pub fn tangential(&self, z: &[f64]) -> Vec<f64> {
        let (m, nf) = (self.m, self.friction_groups);
        if !self.friction || z.len() < m + 2 * nf {
            return vec![0.0; m];
        }
        let mut lam = vec![0.0; nf];
        let mut count = vec![0usize; nf];
        for (j, &g) in self.fgroup.iter().enumerate() {
            lam[g] += z[j].max(0.0);
            count[g] += 1;
        }
        (0..m)
            .map(|j| {
                let g = self.fgroup[j];
                let b = (z[m + 2 * g] - z[m + 2 * g + 1]) / self.scale;
                if count[g] == 1 {
                    b
                } else if lam[g] > 0.0 {
                    b * (z[j].max(0.0) / lam[g])
                } else {
                    b / count[g] as f64
                }
            })
            .collect()
    }

    /// The tangential compliance of contact `j`: the change of its
    /// tangential relative velocity per unit tangential impulse at it,
    /// `T_jᵀ M⁻¹ T_j` over the floes of the group (1/kg; 0 without
    /// friction). For a merged friction group, that of its resultant.
    pub fn tangential_compliance(&self, j: usize) -> f64 {
        if !self.friction {
            return 0.0;
        }
        let (n, r) = (self.lcp.n, self.m + 2 * self.friction_group(j));
        self.lcp.m[r * n + r] * self.scale
    }

    /// The frictionless sub-problem (normal block only), for the last resort
    /// when the frictional LCP cannot be solved.
    pub fn frictionless(&self) -> ContactLcp {
        let m = self.m;
        let n = self.lcp.n;
        let mut a = vec![0.0; m * m];
        for r in 0..m {
            for c in 0..m {
                a[r * m + c] = self.lcp.m[r * n + c];
            }
        }
        let mut h = Mat::<f64>::zeros(self.h.nrows(), m);
        for r in 0..self.h.nrows() {
            for c in 0..m {
                h[(r, c)] = self.h[(r, c)];
            }
        }
        ContactLcp {
            lcp: Lcp {
                n: m,
                m: a,
                q: self.lcp.q[..m].to_vec(),
            },
            m,
            friction: false,
            mu: self.mu,
            scale: self.scale,
            h,
            minv: self.minv.clone(),
            // The normal columns only.
            touching: self
                .touching
                .iter()
                .map(|t| t.iter().copied().filter(|&c| c < m).collect())
                .collect(),
            columns: None,
            floes: self.floes.clone(),
            v_scale: self.v_scale,
            keys: self.keys.clone(),
            fgroup: Vec::new(),
            friction_groups: 0,
        }
    }
}

/// The contact problem of a group in the contact coordinates `p = (λ, β)`
/// (normal impulses `λ_1..λ_m`, then signed tangential impulses
/// `β_1..β_m` along `T_j`, N·s), as used by cone formulations: the
/// post-contact relative velocities are `u = G p + b` with `G = HᵀM⁻¹H` the
/// Delassus matrix of `H = (J, B)` and `b = (JᵀW_free + c, BᵀW_free)`.
/// Without friction only the normal part is present (`dim = m`).
#[derive(Debug, Clone, PartialEq)]
pub struct NormalTangentProblem {
    /// Number of contacts `m`.
    pub m: usize,
    /// Whether the tangential unknowns are present (`dim = 2m`, else `m`).
    pub friction: bool,
    /// Friction coefficient `μ`.
    pub mu: f64,
    /// Delassus matrix `G`, `dim × dim`, row-major, 1/kg (or 1/(kg·m²)).
    pub g: Vec<f64>,
    /// Free relative velocities with the offset, `b`, m/s.
    pub b: Vec<f64>,
    /// Scale of the rounding of `b` ([`ContactLcp::v_scale`]), m/s.
    pub v_scale: f64,
}

impl NormalTangentProblem {
    /// Number of unknowns (`2m` with friction, `m` without).
    pub fn dim(&self) -> usize {
        self.b.len()
    }

    /// `u = G p + b`: normal and tangential relative velocities after the
    /// impulses `p`, m/s.
    pub fn velocities(&self, p: &[f64]) -> Vec<f64> {
        let n = self.dim();
        (0..n)
            .map(|r| {
                self.b[r]
                    + (0..n)
                        .map(|c| self.g[r * n + c] * p.get(c).copied().unwrap_or(0.0))
                        .sum::<f64>()
            })
            .collect()
    }
}

impl ContactLcp {
    /// The same problem in contact coordinates `(λ, β)`, read from the
    /// assembled LCP (no recomputation: `β_j` is the `+T_j` friction column).
    pub fn normal_tangent(&self) -> NormalTangentProblem {
        let m = self.m;
        let n = self.lcp.n;
        let idx: Vec<usize> = if self.friction {
            (0..m)
                .chain((0..m).map(|j| m + 2 * self.friction_group(j)))
                .collect()
        } else {
            (0..m).collect()
        };
        let dim = idx.len();
        let mut g = vec![0.0; dim * dim];
        for (r, &ir) in idx.iter().enumerate() {
            for (c, &ic) in idx.iter().enumerate() {
                // Undo the LCP's scaling: the Delassus matrix itself, 1/kg.
                g[r * dim + c] = self.lcp.m[ir * n + ic] * self.scale;
            }
        }
        NormalTangentProblem {
            m,
            friction: self.friction,
            mu: self.mu,
            g,
            b: idx.iter().map(|&i| self.lcp.q[i]).collect(),
            v_scale: self.v_scale,
        }
    }

    /// The (scaled) LCP unknowns `z' = (g λ, g β̃⁺, g β̃⁻, α)` of contact
    /// impulses `λ`, `β` (N·s; `β` ignored without friction; `α = 0`, it does
    /// not enter the impulses), for [`ContactLcp::impulses`] and
    /// [`ContactLcp::velocity_changes`].
    ///
    /// A merged friction group takes the sum of its members' `β`.
    pub fn z_from_impulses(&self, lambda: &[f64], beta: &[f64]) -> Vec<f64> {
        let (m, nf) = (self.m, self.friction_groups);
        let mut z = vec![0.0; self.lcp.n];
        let mut bsum = vec![0.0; nf];
        for j in 0..m {
            z[j] = lambda.get(j).copied().unwrap_or(0.0) * self.scale;
            if self.friction {
                bsum[self.fgroup[j]] += beta.get(j).copied().unwrap_or(0.0);
            }
        }
        for (g, b) in bsum.into_iter().enumerate() {
            let b = b * self.scale;
            z[m + 2 * g] = b.max(0.0);
            z[m + 2 * g + 1] = (-b).max(0.0);
        }
        z
    }
}
