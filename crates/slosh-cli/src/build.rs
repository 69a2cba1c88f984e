//! From a script's tank description to the solver's initial particles.

use anyhow::{bail, Context, Result};
use slosh_core::ParticleSetup;
use slosh_geometry::{BoxTank, CylinderTank, InitialSurface, Layout, RectTank2, Roof};
use slosh_script::{ReadSandbox, TankSpec};

/// The geometry's initial-surface shape from its script name ("plane" or "mode1").
fn initial_surface(name: &str) -> InitialSurface {
    if name == "mode1" {
        InitialSurface::FirstMode
    } else {
        InitialSurface::Plane
    }
}

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
            tilt_shape,
        } => {
            let layout = Layout::from_name(layout).with_context(|| {
                format!("unknown layout \"{layout}\" (use \"offset\" or \"paper\")")
            })?;
            Ok(RectTank2::new(*width, *height, *depth)
                .with_roof(*roof)
                .with_layout(layout)
                .with_initial_tilt(*tilt)
                .with_initial_shape(initial_surface(tilt_shape))
                .build(dx)?)
        }
        _ => bail!("internal: a 3D tank was handed to the 2D builder"),
    }
}

/// Builds the 3D particles of a 3D tank. A roof mesh path is read through the script's
/// `sandbox` (below its folder, its project folder or an `--allow-read` folder).
pub fn build_3d(tank: &TankSpec, dx: f64, sandbox: &ReadSandbox) -> Result<ParticleSetup<3>> {
    match tank {
        TankSpec::Cylinder {
            radius,
            height,
            depth,
            roof,
            roof_rise,
            tilt,
            tilt_shape,
        } => {
            let mut roof = Roof::from_name(roof, *roof_rise).with_context(|| {
                format!(
                    "unknown roof \"{roof}\": use \"none\", \"flat\", \"cone\", \"dome\" or a \
                     mesh file (.obj/.stl) next to the script"
                )
            })?;
            if let Roof::Mesh(path) = &roof {
                let rel = path.to_string_lossy().to_string();
                let resolved = sandbox.resolve(&rel).map_err(anyhow::Error::msg)?;
                roof = Roof::Mesh(resolved);
            }
            Ok(CylinderTank::new(*radius, *height, *depth, roof)
                .with_initial_tilt(*tilt)
                .with_initial_shape(initial_surface(tilt_shape))
                .build(dx)?)
        }
        TankSpec::Box {
            length,
            breadth,
            height,
            depth,
            roof,
            tilt,
            tilt_shape,
        } => Ok(BoxTank::new(*length, *breadth, *height, *depth)
            .with_roof(*roof)
            .with_initial_tilt(*tilt)
            .with_initial_shape(initial_surface(tilt_shape))
            .build(dx)?),
        TankSpec::Rect { .. } => bail!("internal: a 2D tank was handed to the 3D builder"),
    }
}
