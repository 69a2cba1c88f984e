//! Closed-form and semi-analytical references for liquid sloshing in rigid storage tanks:
//! natural frequencies, linear forced response, Housner/Veletsos pressures, masses and base
//! shear, viscous damping of free sloshing, Malhotra and Kurihara roof pressures, code
//! formulas (API 650 / ACI 350.3 / EC8-4), and a one-call tank report. Pure functions, SI
//! units (m, s, kg, Pa, N; 2D forces per metre).

#![warn(missing_docs)]

pub mod bessel;
pub mod codes;
pub mod cylinder;
pub mod damping;
pub mod housner;
pub mod linear;
pub mod modal;
pub mod natural;
pub mod pitch;
pub mod report;
pub mod roof;
pub mod section_modes;

pub use report::{tank_report, SineExcitation, TankInput, TankReport, TankShape};
