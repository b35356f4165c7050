//! The smooth dynamics: environment forces and the integrator used between
//! impacts.

pub mod forces;
pub mod integrator;

pub use forces::{environment_forces, Forces, Quadrature};
pub use integrator::{IntegrationError, IntegratorStats, SmoothIntegrator, Wrench};
