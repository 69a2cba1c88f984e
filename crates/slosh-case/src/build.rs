//! From a script's tank description to the solver's initial particles.

use anyhow::{bail, Context, Result};
use slosh_core::ParticleSetup;
use slosh_geometry::{
    BoxTank, CylinderLattice, CylinderTank, InitialSurface, Layout, MeshTank, RectTank2, Roof,
    SphereTank,
};
use slosh_script::{ReadSandbox, TankSpec};

/// The geometry's initial-surface shape from its script name ("plane" or "mode1").
fn initial_surface(name: &str) -> InitialSurface {
    if name == "mode1" {
        InitialSurface::FirstMode
    } else {
        InitialSurface::Plane
    }
}

/// Largest change of dx (fraction) accepted to fit the lattice to the tank's horizontal size.
pub const MAX_SPACING_CHANGE: f64 = 0.02;

/// A tank fitted to the particle lattice: the dimensions that will be simulated.
#[derive(Clone, Debug)]
pub struct FittedTank {
    /// The tank with its lattice-bound dimensions (width, length, breadth, height).
    pub tank: TankSpec,
    /// The lattice spacing used (m).
    pub dx: f64,
    /// What changed, in words (empty when the tank fits the requested dx exactly).
    pub notes: Vec<String>,
}

/// Fits the lattice to the tank: dx is adjusted (within [`MAX_SPACING_CHANGE`]) so that the
/// width of a 2D section or the length of a box is a whole number of spacings, and the other
/// lattice-bound dimensions (the roof or shell top, a box's breadth) go to the nearest
/// lattice level. A cylinder's wall is not on the lattice and keeps dx as given. The fill
/// depth is taken to whole rows by the geometry itself.
pub fn fit_to_lattice(tank: &TankSpec, dx: f64) -> Result<FittedTank> {
    if !(dx.is_finite() && dx > 0.0) {
        bail!("the particle spacing dx must be a positive number of m (got {dx})");
    }
    let mut notes = Vec::new();
    let mut fitted = tank.clone();
    let fit_dx = |what: &str, size: f64, notes: &mut Vec<String>| -> Result<f64> {
        if !(size.is_finite() && size > 0.0) {
            return Ok(dx);
        }
        let n = (size / dx).round().max(1.0);
        let fitted = size / n;
        let change = fitted / dx - 1.0;
        if change.abs() <= 1e-9 {
            return Ok(dx);
        }
        if change.abs() > MAX_SPACING_CHANGE {
            bail!(
                "the {what} {size} m is {:.3} spacings of dx = {dx} m; fitting the lattice would \
                 change dx by {:+.1} % (more than {} %): use dx = {} m ({} spacings) or {} m",
                size / dx,
                100.0 * change,
                100.0 * MAX_SPACING_CHANGE,
                size / n,
                n,
                size / (n + 1.0)
            );
        }
        notes.push(format!(
            "dx {dx} m → {fitted} m ({:+.2} %) so that the {what} {size} m holds {n} spacings",
            100.0 * change
        ));
        Ok(fitted)
    };
    let level = |what: &str, size: f64, dx: f64, notes: &mut Vec<String>| -> f64 {
        let n = (size / dx).round().max(1.0);
        let fitted = n * dx;
        if (fitted - size).abs() > 1e-9 * size.max(1.0) {
            notes.push(format!(
                "{what} {size} m → {fitted} m (the nearest lattice level, {n} spacings)"
            ));
            fitted
        } else {
            size
        }
    };
    let dx = match &mut fitted {
        TankSpec::Rect { width, height, .. } => {
            let dx = fit_dx("tank width", *width, &mut notes)?;
            *height = level("tank height", *height, dx, &mut notes);
            dx
        }
        TankSpec::Box {
            length,
            breadth,
            height,
            ..
        } => {
            let dx = fit_dx("tank length", *length, &mut notes)?;
            *breadth = level("tank breadth", *breadth, dx, &mut notes);
            *height = level("tank height", *height, dx, &mut notes);
            dx
        }
        TankSpec::Cylinder { .. }
        | TankSpec::Section { .. }
        | TankSpec::Sphere { .. }
        | TankSpec::Mesh { .. } => dx,
    };
    // Keep a fill that was within the shell within the fitted shell (a fill above the shell
    // as given is the geometry's error to report).
    let fill_fitted_shell = tank.depth() <= tank_height(tank);
    match &mut fitted {
        TankSpec::Rect { height, depth, .. } | TankSpec::Box { height, depth, .. } => {
            if fill_fitted_shell && *depth > *height {
                notes.push(format!(
                    "fill depth {depth} m → {height} m (the fitted shell top)"
                ));
                *depth = *height;
            }
        }
        TankSpec::Cylinder { .. }
        | TankSpec::Section { .. }
        | TankSpec::Sphere { .. }
        | TankSpec::Mesh { .. } => {}
    }
    Ok(FittedTank {
        tank: fitted,
        dx,
        notes,
    })
}

/// The shell height of a tank (m).
fn tank_height(tank: &TankSpec) -> f64 {
    match tank {
        TankSpec::Rect { height, .. }
        | TankSpec::Box { height, .. }
        | TankSpec::Cylinder { height, .. } => *height,
        TankSpec::Section { outline, .. } => {
            let (lo, hi) = outline.bounds();
            hi[1] - lo[1]
        }
        TankSpec::Sphere { radius, .. } => 2.0 * radius,
        TankSpec::Mesh { extent, .. } => extent.max[2] - extent.min[2],
    }
}

/// Builds the 2D particles of a 2D tank with `layers` layers of wall particles (at least
/// [`slosh_core::SphParams::wall_layers`] of the run's parameters).
pub fn build_2d(tank: &TankSpec, dx: f64, layers: u8) -> Result<ParticleSetup<2>> {
    if let Some(section) = tank.section_tank().map_err(anyhow::Error::msg)? {
        let setup = section.with_layers(layers).build(dx)?;
        if let TankSpec::Section { solids, .. } | TankSpec::Rect { solids, .. } = tank {
            check_solids_inside(&setup, solids.iter().map(|s| s.name.as_str()))?;
        }
        return Ok(setup);
    }
    match tank {
        TankSpec::Rect {
            width,
            height,
            depth,
            roof,
            layout,
            tilt,
            tilt_shape,
            ..
        } => {
            let layout = Layout::from_name(layout).with_context(|| {
                format!("unknown layout \"{layout}\" (use \"offset\" or \"paper\")")
            })?;
            Ok(RectTank2::new(*width, *height, *depth)
                .with_roof(*roof)
                .with_layout(layout)
                .with_initial_tilt(*tilt)
                .with_initial_shape(initial_surface(tilt_shape))
                .with_layers(layers)
                .build(dx)?)
        }
        _ => bail!("internal: a 3D tank was handed to the 2D builder"),
    }
}

/// Refuses a solid part with no wetted side: every solid of that name lies outside the tank's
/// interior (or inside another solid), so it would be silently left out of the run. The
/// builders count a solid's side as wetted only where its liquid side lies inside the tank.
fn check_solids_inside<'a, const D: usize>(
    setup: &ParticleSetup<D>,
    solid_names: impl Iterator<Item = &'a str>,
) -> Result<()> {
    for name in solid_names {
        let area: f64 = setup
            .part_names
            .iter()
            .position(|n| n == name)
            .map_or(0.0, |p| {
                setup
                    .wall_part
                    .iter()
                    .zip(&setup.wall_area)
                    .filter(|(&k, _)| usize::from(k) == p)
                    .map(|(_, a)| a)
                    .sum()
            });
        if area <= 0.0 {
            bail!(
                "solid \"{name}\" lies outside the tank: none of its faces is inside the \
                 tank's interior (or it is inside another solid); check its position against \
                 the tank's size"
            );
        }
    }
    Ok(())
}

/// Builds the 3D particles of a 3D tank with `layers` layers of wall particles (as
/// [`build_2d`]). A roof or tank mesh path is read through the script's `sandbox` (below its
/// folder, its project folder or an `--allow-read` folder).
pub fn build_3d(
    tank: &TankSpec,
    dx: f64,
    layers: u8,
    sandbox: &ReadSandbox,
) -> Result<ParticleSetup<3>> {
    match tank {
        TankSpec::Cylinder {
            radius,
            height,
            depth,
            roof,
            roof_rise,
            tilt,
            tilt_shape,
            solids,
            lattice,
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
            let lattice = CylinderLattice::from_name(lattice).with_context(|| {
                format!("unknown lattice \"{lattice}\": use \"cubic\" or \"polar\"")
            })?;
            let mut tank = CylinderTank::new(*radius, *height, *depth, roof)
                .with_initial_tilt(*tilt)
                .with_initial_shape(initial_surface(tilt_shape))
                .with_layers(layers)
                .with_lattice(lattice);
            tank.solids = solids.clone();
            let setup = tank.build(dx)?;
            check_solids_inside(&setup, solids.iter().map(|s| s.name.as_str()))?;
            Ok(setup)
        }
        TankSpec::Box {
            length,
            breadth,
            height,
            depth,
            roof,
            tilt,
            tilt_shape,
            solids,
        } => {
            let mut tank = BoxTank::new(*length, *breadth, *height, *depth)
                .with_roof(*roof)
                .with_initial_tilt(*tilt)
                .with_initial_shape(initial_surface(tilt_shape))
                .with_layers(layers);
            tank.solids = solids.clone();
            let setup = tank.build(dx)?;
            check_solids_inside(&setup, solids.iter().map(|s| s.name.as_str()))?;
            Ok(setup)
        }
        TankSpec::Mesh {
            mesh,
            depth,
            tilt,
            tilt_shape,
            solids,
            ..
        } => {
            let path = sandbox.resolve(mesh).map_err(anyhow::Error::msg)?;
            let mut tank = MeshTank::new(path, *depth)
                .with_initial_tilt(*tilt)
                .with_initial_shape(initial_surface(tilt_shape))
                .with_layers(layers);
            tank.solids = solids.clone();
            let setup = tank.build(dx)?;
            check_solids_inside(&setup, solids.iter().map(|s| s.name.as_str()))?;
            Ok(setup)
        }
        TankSpec::Sphere {
            radius,
            depth,
            tilt,
            tilt_shape,
        } => Ok(SphereTank::new(*radius, *depth)
            .with_initial_tilt(*tilt)
            .with_initial_shape(initial_surface(tilt_shape))
            .with_layers(layers)
            .build(dx)?),
        TankSpec::Rect { .. } | TankSpec::Section { .. } => {
            bail!("internal: a 2D tank was handed to the 3D builder")
        }
    }
}
