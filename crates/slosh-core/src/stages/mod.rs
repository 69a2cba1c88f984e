//! The stages of the time step, each in its own file.

mod continuity;
mod forces;
mod leapfrog;
mod shifting;
mod summation;
mod symplectic;
mod walls;
pub(crate) use continuity::*;
pub(crate) use forces::*;
pub(crate) use summation::*;
pub(crate) use walls::*;
