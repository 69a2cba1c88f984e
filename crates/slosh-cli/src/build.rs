//! From a script's tank description to the solver's initial particles.

use anyhow::{bail, Context, Result};
use slosh_core::ParticleSetup;
use slosh_geometry::{Layout, RectTank2};
use slosh_script::TankSpec;

/// Builds the 2D particles of a 2D tank.
pub fn build_2d(tank: &TankSpec, dx: f64) -> Result<ParticleSetup<2>> {
    match tank {
        TankSpec::Rect {
            width,
            height,
            depth,
            roof,
            layout,
            tilt,
        } => {
            let layout = Layout::from_name(layout).with_context(|| {
                format!("unknown layout \"{layout}\" (use \"offset\" or \"paper\")")
            })?;
            Ok(RectTank2::new(*width, *height, *depth)
                .with_roof(*roof)
                .with_layout(layout)
                .with_initial_tilt(*tilt)
                .build(dx)?)
        }
        _ => bail!("internal: a 3D tank was handed to the 2D builder"),
    }
}

/// Builds the 3D particles of a 3D tank.
pub fn build_3d(tank: &TankSpec, dx: f64, script_dir: &std::path::Path) -> Result<ParticleSetup<3>> {
    let _ = (tank, dx, script_dir);
    bail!("3D tanks are not available in this build yet (cylinder and box builders are being added)")
}
