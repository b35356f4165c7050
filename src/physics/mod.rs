//! The smooth dynamics: the force model (environment forces and their
//! accelerations) and the integrator used between impacts.

pub mod force_model;
pub mod forces;
pub mod integrator;

pub use force_model::{air_drag_quadrature, air_is_uniform_in_space, air_velocity, ForceModel};
pub use forces::{drag_traction, integrate_traction, Forces, Quadrature};
pub use integrator::{IntegrationError, IntegratorStats, SmoothIntegrator, StepRecord, Wrench};
