//! Two rectangular bars meeting end-on, both as lattices
//! ([`super::pair`], docs/physics.md §9.9): Saint-Venant's check of the
//! two-lattice impact. Two elastic bars of one material, the first
//! (`L₁`) striking the second (`L₂`) at rest, part with the restitution
//! `min(L₁, L₂) / max(L₁, L₂)` in one-dimensional wave theory: the shorter
//! bar's wave has come back when the longer's has not, and the energy left
//! behind rings in the longer bar.
//!
//! No scheme of its own: this places the bars and runs
//! [`super::pair::PairImpact`].

use super::pair::{PairBody, PairImpact, PairOutcome};
use super::LatticeSpec;
use crate::fracture::chain::ChainOptions;
use crate::geometry::Vec2;
use crate::state::BodyState;

/// The first bar, `[−L₁, 0] × [−W/2, W/2]`, moving at `speed` along `+x`
/// into the second, `[0, L₂] × [o − W/2, o + W/2]` at rest (`o` the
/// lateral offset: 0 end-on, else an off-centre impact).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Bars {
    /// The bars' lengths `(L₁, L₂)`, m.
    pub lengths: (f64, f64),
    /// Their width `W`, m.
    pub width: f64,
    /// The first bar's speed, m/s.
    pub speed: f64,
    /// The second bar's lateral offset `o`, m, `|o| < W`.
    pub offset: f64,
    /// The gap between the faces, m: 0 touching, negative overlapping (as
    /// a time-stepping scheme leaves floes, §9.9 **Start**).
    pub gap: f64,
}

impl Bars {
    /// The outline of a bar `length × width` about its centre, m.
    fn shape(&self, length: f64) -> [Vec2; 4] {
        let (l, w) = (0.5 * length, 0.5 * self.width);
        [
            Vec2::new(-l, -w),
            Vec2::new(l, -w),
            Vec2::new(l, w),
            Vec2::new(-l, w),
        ]
    }

    /// Saint-Venant's restitution `min(L₁, L₂) / max(L₁, L₂)` (-).
    pub fn saint_venant(&self) -> f64 {
        let (a, b) = self.lengths;
        a.min(b) / a.max(b)
    }

    /// Runs the impact of the bars, both lattices of `spec`, with the
    /// chain's `options`; the contact point is the middle of the faces'
    /// overlap, the normal `+x`. Fails when the faces do not overlap or on
    /// what [`PairImpact::run`] refuses.
    pub fn run(&self, spec: LatticeSpec, options: ChainOptions) -> Result<PairOutcome, String> {
        if self.offset.is_nan() || self.offset.abs() >= self.width {
            return Err(format!(
                "the bars' faces do not overlap (offset {} m, width {} m)",
                self.offset, self.width
            ));
        }
        let (l1, l2) = self.lengths;
        let (s1, s2) = (self.shape(l1), self.shape(l2));
        let state = |x: f64, y: f64, v: f64| BodyState {
            position: Vec2::new(x, y),
            angle: 0.0,
            velocity: Vec2::new(v, 0.0),
            angular_velocity: 0.0,
        };
        PairImpact {
            first: PairBody {
                shape: &s1,
                state: state(-0.5 * l1, 0.0, self.speed),
                spec,
            },
            second: Some(PairBody {
                shape: &s2,
                state: state(0.5 * l2 + self.gap, self.offset, 0.0),
                spec,
            }),
            point: Vec2::new(0.0, 0.5 * self.offset),
            normal: Vec2::new(1.0, 0.0),
            options,
        }
        .run()
    }
}
