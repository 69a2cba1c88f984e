//! Each physics term written once.

mod coupled;
mod density;
mod momentum;
mod riemann;
mod velocity_gradient;
mod viscous;
pub(crate) use coupled::*;
pub(crate) use density::*;
pub(crate) use momentum::*;
pub(crate) use riemann::*;
pub(crate) use velocity_gradient::*;
pub(crate) use viscous::*;
