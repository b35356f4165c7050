//! A floe rammed into a coast (docs/physics.md §7.3): the percussion by an
//! obstacle at rest ([`ram`]), what counts as a break ([`Break`]) and the
//! critical ramming speed, by bisection ([`critical_ram_speed`]).

use super::{Impact, Outcome, Percussion, RigidMotion};
use crate::fracture::chain::ChainOptions;
use crate::fracture::lattice::Lattice;
use crate::geometry::Vec2;

/// The percussion of `lattice`'s floe rammed at `speed` (m/s) along
/// `normal` (unit, into the floe) into a fixed coast touching it at
/// `point` (m): the floe moves rigidly at `−speed · normal`, the striker is
/// an obstacle at rest ([`Impact::mass`] infinite).
pub fn ram(
    lattice: &Lattice,
    point: Vec2,
    normal: Vec2,
    speed: f64,
    options: ChainOptions,
) -> Result<Outcome, String> {
    let motion = RigidMotion {
        velocity: -normal * speed,
        angular_velocity: 0.0,
    };
    let impact = Impact {
        point,
        normal,
        mass: f64::INFINITY,
        speed,
    };
    Ok(Percussion::new(lattice, motion, impact, options)?.run())
}

/// What counts as a break in [`critical_ram_speed`] (docs/physics.md §7.3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Break {
    /// At least two pieces of this many nodes or more (a piece of fewer is
    /// debris). A fixed node count is a piece whose size shrinks with the
    /// spacing.
    Pieces(usize),
    /// At least two pieces each holding this fraction (in `(0, 0.5]`) of
    /// the floe's mass or more: a piece of a fixed physical size.
    MassFraction(f64),
    /// Any bond broken: the onset of damage, where the lattice's largest
    /// bond strain reaches the critical one.
    FirstBond,
}

impl Break {
    /// Whether the percussion `outcome` of a floe of mass `total` (kg) is a
    /// break.
    pub fn holds(&self, outcome: &Outcome, total: f64) -> bool {
        match *self {
            Break::Pieces(n) => {
                outcome
                    .fragments
                    .iter()
                    .filter(|f| f.nodes.len() >= n)
                    .count()
                    >= 2
            }
            Break::MassFraction(q) => {
                outcome
                    .fragments
                    .iter()
                    .filter(|f| f.mass >= q * total)
                    .count()
                    >= 2
            }
            Break::FirstBond => !outcome.broken.is_empty(),
        }
    }
}

/// The critical ramming speed of [`ram`], m/s: the least speed at which
/// the floe ends in at least two pieces of `min_nodes` nodes or more (a
/// piece of fewer is debris), found by doubling from 1 m/s until it
/// breaks (an error past `max_speed`), then bisection to `rel_tol` of the
/// speed (docs/physics.md §7.3). Bisection assumes that a floe that breaks
/// at a speed breaks at every higher one; returned is the upper end of the
/// last bracket (a speed that breaks it). [`critical_ram_speed_by`] with
/// [`Break::Pieces`].
pub fn critical_ram_speed(
    lattice: &Lattice,
    point: Vec2,
    normal: Vec2,
    options: ChainOptions,
    min_nodes: usize,
    rel_tol: f64,
    max_speed: f64,
) -> Result<f64, String> {
    critical_ram_speed_by(
        lattice,
        point,
        normal,
        options,
        Break::Pieces(min_nodes),
        rel_tol,
        max_speed,
    )
}

/// [`critical_ram_speed`] with what counts as a break given by `criterion`
/// (a criterion met at 1 m/s is bisected from `[0, 1]`).
pub fn critical_ram_speed_by(
    lattice: &Lattice,
    point: Vec2,
    normal: Vec2,
    options: ChainOptions,
    criterion: Break,
    rel_tol: f64,
    max_speed: f64,
) -> Result<f64, String> {
    if !(rel_tol > 0.0 && rel_tol < 1.0) {
        return Err(format!("the tolerance must be in (0, 1), got {rel_tol}"));
    }
    if let Break::MassFraction(q) = criterion {
        if !(q > 0.0 && q <= 0.5) {
            return Err(format!("the mass fraction must be in (0, 0.5], got {q}"));
        }
    }
    let total: f64 = lattice.mass.iter().sum();
    let breaks = |v: f64| -> Result<bool, String> {
        Ok(criterion.holds(&ram(lattice, point, normal, v, options)?, total))
    };
    let (mut lo, mut hi) = (0.0, 1.0);
    while !breaks(hi)? {
        lo = hi;
        hi *= 2.0;
        if hi > max_speed {
            return Err(format!("the floe does not break up to {max_speed} m/s"));
        }
    }
    while hi - lo > rel_tol * hi {
        let mid = 0.5 * (lo + hi);
        if breaks(mid)? {
            hi = mid;
        } else {
            lo = mid;
        }
    }
    Ok(hi)
}

/// The mean and the sample standard deviation (m/s) of critical speeds
/// over seeds or mesh variants (the standard deviation 0 for one speed).
pub fn mean_and_deviation(speeds: &[f64]) -> (f64, f64) {
    let n = speeds.len() as f64;
    let mean = speeds.iter().sum::<f64>() / n;
    let var = speeds.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0).max(1.0);
    (mean, var.sqrt())
}
