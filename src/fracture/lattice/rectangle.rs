//! The percussion of a rectangular floe struck on its left face along `+x`
//! (docs/physics.md §7.3; `floebench percussion-2d`): the floe `[0, W] ×
//! [0, H]`, its lattice ([`super::Lattice`]), and a striker touching the
//! left face at height `at`, either a moving effective mass hitting the
//! floe at rest or a fixed coast the floe moves into.
//!
//! No scheme of its own: this places the floe and the impact and runs
//! [`super::percussion::Percussion`].

use super::percussion::{Impact, Outcome, Percussion, RigidMotion};
use super::{Lattice, LatticeSpec};
use crate::fracture::chain::ChainOptions;
use crate::geometry::Vec2;
use crate::model::fracture::PercussionRecord;

/// A strike on the left face of a rectangular floe, along `+x`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FaceStrike {
    /// The floe's size `(W, H)`, m; its outline is `[0, W] × [0, H]`.
    pub size: (f64, f64),
    /// The relative normal speed of the impact, m/s.
    pub speed: f64,
    /// The striker's effective mass, kg: `Some(m)` a striker moving at
    /// `speed` into the floe at rest, `None` a fixed coast, the floe
    /// moving at `speed` into it.
    pub mass: Option<f64>,
    /// The height of the contact point on the left face, m, in `(0, H)`.
    pub at: f64,
}

/// A resolved [`FaceStrike`]: the floe's lattice, the impact, what the
/// percussion did.
#[derive(Debug, Clone)]
pub struct Struck {
    /// The floe's lattice, at rest (the springs' indices are those of
    /// [`Outcome::broken`]).
    pub lattice: Lattice,
    /// The impact that started the percussion.
    pub impact: Impact,
    /// The percussion's outcome.
    pub outcome: Outcome,
    /// The least energy that breaks a bond of the lattice, J
    /// ([`Percussion::weakest_bond_energy`]).
    pub weakest_bond_energy: f64,
}

impl FaceStrike {
    /// The floe's counter-clockwise outline, m.
    pub fn outline(&self) -> [Vec2; 4] {
        let (w, h) = self.size;
        [
            Vec2::new(0.0, 0.0),
            Vec2::new(w, 0.0),
            Vec2::new(w, h),
            Vec2::new(0.0, h),
        ]
    }

    /// The floe's rigid motion and the impact: a striker of finite mass
    /// hits the floe at rest; a coast (no mass) is hit by the floe moving
    /// at `−speed` along `x`.
    pub fn start(&self) -> (RigidMotion, Impact) {
        let (motion, mass) = match self.mass {
            Some(m) => (RigidMotion::default(), m),
            None => (
                RigidMotion {
                    velocity: Vec2::new(-self.speed, 0.0),
                    angular_velocity: 0.0,
                },
                f64::INFINITY,
            ),
        };
        let impact = Impact {
            point: Vec2::new(0.0, self.at),
            normal: Vec2::new(1.0, 0.0),
            mass,
            speed: self.speed,
        };
        (motion, impact)
    }

    /// Whether the contact point is on the left face, strictly between its
    /// corners; else the error `"<at> is not on the left face (0, <H>)"`.
    pub fn on_face(&self) -> Result<(), String> {
        let h = self.size.1;
        if self.at > 0.0 && self.at < h {
            Ok(())
        } else {
            Err(format!("{} is not on the left face (0, {h})", self.at))
        }
    }

    /// Builds the floe's lattice of `spec` and runs the percussion with
    /// the chain's `options`. Fails when the contact point is not on the
    /// left face ([`FaceStrike::on_face`], the error prefixed with `at `),
    /// or on what [`Lattice::build`] and [`Percussion::new`] refuse.
    pub fn run(&self, spec: LatticeSpec, options: ChainOptions) -> Result<Struck, String> {
        self.on_face().map_err(|e| format!("at {e}"))?;
        let lattice = Lattice::build(&self.outline(), spec)?;
        let (motion, impact) = self.start();
        let mut percussion = Percussion::new(&lattice, motion, impact, options)?;
        let outcome = percussion.run();
        let weakest_bond_energy = percussion.weakest_bond_energy();
        Ok(Struck {
            lattice,
            impact,
            outcome,
            weakest_bond_energy,
        })
    }
}

impl Struck {
    /// The crack pattern of the percussion ([`crate::fracture::crack::of_lattice`]),
    /// with its impact energy bound, weakest bond and lattice loss.
    pub fn record(&self) -> PercussionRecord {
        let broken: Vec<usize> = self.outcome.broken.iter().map(|b| b.spring).collect();
        PercussionRecord {
            bound: self.outcome.impact_energy,
            weakest: self.weakest_bond_energy,
            loss: self.outcome.fracture_energy,
            ..crate::fracture::crack::of_lattice(&self.lattice, &broken, &[self.impact])
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn strike(mass: Option<f64>, at: f64) -> FaceStrike {
        FaceStrike {
            size: (4.0, 2.0),
            speed: 3.0,
            mass,
            at,
        }
    }

    #[test]
    fn the_contact_point_must_be_strictly_inside_the_left_face() {
        assert!(strike(None, 1.0).on_face().is_ok());
        for at in [0.0, 2.0, -1.0, f64::NAN] {
            assert!(strike(None, at).on_face().is_err(), "{at}");
        }
        let e = strike(None, 5.0).run(LatticeSpec::default(), ChainOptions::default());
        assert_eq!(
            e.err().as_deref(),
            Some("at 5 is not on the left face (0, 2)")
        );
    }

    #[test]
    fn a_coast_is_rammed_and_a_striker_hits_the_floe_at_rest() {
        let (motion, impact) = strike(None, 0.5).start();
        assert_eq!(motion.velocity, Vec2::new(-3.0, 0.0));
        assert_eq!(impact.mass, f64::INFINITY);
        let (motion, impact) = strike(Some(7.0), 0.5).start();
        assert_eq!(motion, RigidMotion::default());
        assert_eq!(impact.mass, 7.0);
        assert_eq!(impact.point, Vec2::new(0.0, 0.5));
        assert_eq!(impact.normal, Vec2::new(1.0, 0.0));
        assert_eq!(impact.speed, 3.0);
    }
}
