//! The lattice model in the formulations (docs/physics.md §9.8): its
//! `[fracture]` keys are read, the trigger bound never skips an impact
//! that could break a bond, a k-piece split conserves mass and momenta, and
//! a fast ram breaks where a slow one does not, in every formulation.
//!
//! This file holds what the submodules share: the 50 m² diamond, the
//! lattice settings and the two-sided squeeze. The tests are in the
//! submodules, one topic each.

mod keys;
mod pieces;
mod runs;
mod squeeze;
mod trigger_bound;

use floebench::fracture::lattice::percussion::Impact;
use floebench::geometry::Vec2;
use floebench::model::fracture::{FractureModel, FractureSettings};
use floebench::model::{Floe, FloeOrigin};

/// A 50 m² diamond (a 7.07 m square turned by 45°), h = 1 m.
fn diamond() -> Floe {
    let poly = [
        Vec2::new(0.0, 5.0),
        Vec2::new(5.0, 0.0),
        Vec2::new(10.0, 5.0),
        Vec2::new(5.0, 10.0),
    ];
    Floe::from_world_polygon(&poly, 1.0, 917.0, Vec2::zeros(), 0.0, FloeOrigin::Listed(0))
}

fn settings(spacing: f64) -> FractureSettings {
    FractureSettings {
        model: FractureModel::Lattice,
        min_area: 1.0,
        spacing: Some(spacing),
        ..FractureSettings::default()
    }
}

/// The diamond's two side corners struck at once towards each other by
/// strikers of the floe's mass at `speed` (both: `true`), or only the right
/// one.
fn squeeze(f: &Floe, speed: f64, both: bool) -> Vec<Impact> {
    let right = Impact {
        point: Vec2::new(5.0, 0.0),
        normal: Vec2::new(-1.0, 0.0),
        mass: f.mass,
        speed,
    };
    let left = Impact {
        point: Vec2::new(-5.0, 0.0),
        normal: Vec2::new(1.0, 0.0),
        ..right
    };
    if both {
        vec![right, left]
    } else {
        vec![right]
    }
}
