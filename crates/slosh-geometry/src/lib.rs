//! Tanks as parry shapes, turned into the solver's initial particles.
//!
//! * [`RectTank2`]: the paper's 2D rectangular tank (two lattice layouts, [`Layout`]).
//!
//! All lengths are in metres; the vertical axis is the last coordinate, up positive.
//! Wall particles carry their part (`bottom` = 0, `wall` = 1, `roof` = 2, then user parts),
//! layer (1 = next to the liquid), outward normal (from the liquid into the wall) and the
//! boundary area they stand for (innermost layer only).

mod error;
mod rect2;

pub use error::{GeometryError, MAX_PARTICLES};
pub use rect2::{Layout, RectInterior2, RectLattice2, RectTank2};
