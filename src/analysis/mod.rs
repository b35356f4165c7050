//! Analysis of recorded runs: the physical checks with exact answers
//! (physics.md section 6) that every formulation is held to.

pub mod check;
