//! The cut of a crushed floe and the transfer of the crushed ice
//! (docs/physics.md §10.5–10.6).
//!
//! A floe is cut on a plane by the split ([`mod@crate::fracture::split`]):
//! both pieces take the floe's rigid velocity field, so the cut alone
//! conserves mass, momentum and kinetic energy. The kept piece stays the
//! floe (same id, same angle: its outline in the body frame is the kept
//! piece turned back by the floe's angle, about its new centre of mass).
//! The crushed piece ([`Ice`]) joins another floe as thickness
//! (Subzero.jl's rule: `Δh = m / (ρ A)` with the receiving floe's density
//! `ρ` and area `A`), which takes its momentum and angular momentum: a
//! perfectly inelastic merge, whose kinetic-energy loss the caller books.

use crate::fracture::split::{cut_floe, split, Piece};
use crate::geometry::{cross, perp, rotate, Vec2};
use crate::model::{parts_of, Floe};
use crate::state::BodyState;

/// The crushed ice of one cut: its mass, centre of mass, velocity there
/// and its own angular momentum about that centre.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ice {
    /// Mass, kg.
    pub mass: f64,
    /// Volume at the cut floe's thickness, m³.
    pub volume: f64,
    /// Centre of mass (world), m.
    pub position: Vec2,
    /// Velocity of the centre of mass, m/s.
    pub velocity: Vec2,
    /// Angular momentum about its centre of mass `I_c ω`, kg·m²/s.
    pub spin: f64,
    /// Kinetic energy, J.
    pub kinetic: f64,
}

impl Ice {
    /// The ice of the crushed piece `p`.
    pub fn of(p: &Piece) -> Ice {
        let s = &p.state;
        Ice {
            mass: p.floe.mass,
            volume: p.floe.area * p.floe.thickness,
            position: s.position,
            velocity: s.velocity,
            spin: p.floe.inertia * s.angular_velocity,
            kinetic: p.floe.kinetic_energy(&s.velocity, s.angular_velocity),
        }
    }

    /// Its linear momentum, kg·m/s.
    pub fn momentum(&self) -> Vec2 {
        self.velocity * self.mass
    }

    /// Its angular momentum about the point `o` (m), kg·m²/s.
    pub fn angular_momentum_about(&self, o: &Vec2) -> f64 {
        self.spin + self.mass * cross(&(self.position - o), &self.velocity)
    }
}

/// The cut of floe `f` in state `b` on the plane `n·x = c` (`n` a unit
/// vector, `c` in m, world): (kept piece, crushed piece), the kept one on
/// the side `n·x ≤ c` when `below`, `n·x ≥ c` otherwise; `None` when the
/// plane leaves a side without area ([`crate::fracture::split::cut`]).
pub fn cut_on_plane(
    f: &Floe,
    b: &BodyState,
    n: &Vec2,
    c: f64,
    below: bool,
) -> Option<(Piece, Piece)> {
    // Along d = perp(n), the left of the line is n·x < c.
    let cut = cut_floe(f, b, &(n * c), &perp(n))?;
    let [left, right] = split(f, b, &cut)?;
    Some(if below { (left, right) } else { (right, left) })
}

/// Floe `f`, whose state had angle `angle` (rad), reduced to the kept
/// piece `kept` ([`cut_on_plane`]): its outline in the body frame about
/// the piece's centre of mass, the piece's mass properties; id, history
/// and material unchanged. The state that goes with it is
/// [`kept_state`].
pub fn reshaped(f: &Floe, kept: &Piece, angle: f64) -> Floe {
    let shape: Vec<Vec2> = kept.floe.shape.iter().map(|p| rotate(p, -angle)).collect();
    Floe {
        parts: parts_of(&shape),
        shape,
        area: kept.floe.area,
        mass: kept.floe.mass,
        inertia: kept.floe.inertia,
        area_moment: kept.floe.area_moment,
        radius: kept.floe.radius,
        ..f.clone()
    }
}

/// The state of a floe reduced to the kept piece `kept` from state `b`:
/// the piece's centre of mass and rigid velocity, the floe's angle.
pub fn kept_state(kept: &Piece, b: &BodyState) -> BodyState {
    BodyState {
        angle: b.angle,
        ..kept.state
    }
}

/// Floe `f` in state `b` with the crushed ice `ice` added as thickness
/// (`Δh = Σ m / (ρ A)`, spread evenly, so its centre of mass stays): its
/// mass and inertia grow, its velocity is the momentum over the new mass,
/// its angular velocity the angular momentum about its centre of mass
/// over the new inertia.
pub fn ridged(f: &Floe, b: &BodyState, ice: &[Ice]) -> (Floe, BodyState) {
    let added: f64 = ice.iter().map(|i| i.mass).sum();
    let thickness = f.thickness + added / (f.density * f.area);
    let surface = f.density * thickness;
    let g = Floe {
        thickness,
        mass: surface * f.area,
        inertia: surface * f.area_moment,
        ..f.clone()
    };
    let momentum = ice
        .iter()
        .fold(b.velocity * f.mass, |p, i| p + i.momentum());
    let spin = ice.iter().fold(f.inertia * b.angular_velocity, |l, i| {
        l + i.angular_momentum_about(&b.position)
    });
    let state = BodyState {
        velocity: momentum / g.mass,
        angular_velocity: spin / g.inertia,
        ..*b
    };
    (g, state)
}
