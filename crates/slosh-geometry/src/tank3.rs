//! 3D tanks: an upright cylinder with flat, conical, dome or meshed roof, and a box; optional
//! internal solids (centre column, baffle ring). All are turned into particles through one
//! mesh-based builder (parry3d `TriMesh` with pseudo-normal containment).

use std::f64::consts::PI;
use std::path::PathBuf;
use std::sync::Arc;

use nalgebra::Vector3;
use parry3d_f64::math::Vector as PVec3;
use parry3d_f64::query::{PointQuery, PointQueryWithLocation};
use parry3d_f64::shape::{TriMesh, TriMeshFlags, TrianglePointLocation};
use rayon::prelude::*;
use slosh_core::{ParticleSetup, TankInterior, PART_BOTTOM, PART_ROOF, PART_WALL};

use crate::error::{check_finite, check_layers, check_positive, GeometryError, MAX_PARTICLES};
use crate::lattice::{
    cell_of, lattice_rows_below, part_priority, scale_areas_to_part_totals, NO_PART,
};
use crate::mesh::{box_mesh, circle_segments, revolve_profile, SurfaceMesh};

/// The roof of an upright cylindrical tank.
#[derive(Debug, Clone, PartialEq)]
pub enum Roof {
    /// Open tank: no roof; the interior extends upwards without limit.
    None,
    /// Flat roof at the top of the shell.
    Flat,
    /// Conical roof rising from the shell top to an apex `apex_height` (m) above it, on the axis.
    Cone {
        /// Height of the apex above the shell top (m).
        apex_height: f64,
    },
    /// Spherical-cap (dome) roof rising `rise` (m) above the shell top at the axis (rise ≤ radius).
    Dome {
        /// Height of the dome's top above the shell top (m).
        rise: f64,
    },
    /// The whole tank interior as a closed triangle mesh file (OBJ or STL, metres): axis on
    /// x = y = 0, floor at z = 0, normals pointing out of the liquid (inward-facing meshes are
    /// flipped). Triangles entirely at z ≈ 0 are the bottom, those entirely at or above the shell
    /// height are the roof, the rest the wall. The path is used as given (callers resolve it).
    Mesh(PathBuf),
}

impl Roof {
    /// A conical roof given by its slope (rise per run, e.g. 1/16 for API 650 cone roofs) on a
    /// tank of radius `radius` (m).
    pub fn cone_with_slope(radius: f64, slope: f64) -> Roof {
        Roof::Cone {
            apex_height: slope * radius,
        }
    }

    /// Parses a script's roof choice: `"none"`/`"open"`, `"flat"`, `"cone"` (apex `rise` m
    /// above the shell top), `"dome"` (rise `rise` m), or else a mesh file path (a name ending
    /// in `.obj` or `.stl`, any case). Returns `None` for anything else.
    pub fn from_name(name: &str, rise: f64) -> Option<Roof> {
        let lower = name.trim().to_ascii_lowercase();
        match lower.as_str() {
            "none" | "open" => Some(Roof::None),
            "flat" => Some(Roof::Flat),
            "cone" => Some(Roof::Cone { apex_height: rise }),
            "dome" => Some(Roof::Dome { rise }),
            _ if lower.ends_with(".obj") || lower.ends_with(".stl") => {
                Some(Roof::Mesh(PathBuf::from(name.trim())))
            }
            _ => None,
        }
    }

    /// Height of the roof above the shell top at the axis (m); 0 for none and flat.
    pub fn rise(&self) -> f64 {
        match self {
            Roof::Cone { apex_height } => *apex_height,
            Roof::Dome { rise } => *rise,
            _ => 0.0,
        }
    }
}

/// The profile of a spherical-cap roof of `rise` (m) over a shell of radius `radius` whose top
/// is at `shell_top` (m): (r, z) points from just inside the shell top (excluded) to the crown
/// (r = 0, z = shell_top + rise), with chord error ≤ `sag` (m) and at least 4 pieces.
pub(crate) fn dome_profile(radius: f64, shell_top: f64, rise: f64, sag: f64) -> Vec<[f64; 2]> {
    let (r, h) = (radius, shell_top);
    let a = (r * r + rise * rise) / (2.0 * rise);
    let zc = h + rise - a;
    let theta0 = (r / a).clamp(-1.0, 1.0).asin();
    let step = 2.0 * (1.0 - (sag / a).min(1.0)).acos();
    let pieces = ((theta0 / step).ceil() as usize).max(4);
    (1..=pieces)
        .map(|k| {
            let th = theta0 * (1.0 - k as f64 / pieces as f64);
            let rr = if k == pieces { 0.0 } else { a * th.sin() };
            let zz = if k == pieces {
                h + rise
            } else {
                zc + a * th.cos()
            };
            [rr, zz]
        })
        .collect()
}

/// Arc length of a spherical-cap (dome) profile of `rise` (m) over a half-width `radius` (m),
/// from the shell top to the crown: a·asin(radius/a), a = (radius² + rise²)/(2 rise).
pub(crate) fn dome_arc_length(radius: f64, rise: f64) -> f64 {
    let a = (radius * radius + rise * rise) / (2.0 * rise);
    a * (radius / a).clamp(-1.0, 1.0).asin()
}

/// Shape of an internal solid (a fixed obstacle inside the tank), in tank coordinates (m).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub enum SolidShape {
    /// A vertical solid cylinder, e.g. a centre column.
    Column {
        /// Horizontal position of its axis (x, y) (m).
        centre: [f64; 2],
        /// Radius (m).
        radius: f64,
        /// Height of its lower end (m).
        bottom: f64,
        /// Height of its upper end (m).
        top: f64,
    },
    /// A horizontal annular ring centred on the tank axis, e.g. a baffle ring on the shell.
    Ring {
        /// Inner radius (m).
        inner_radius: f64,
        /// Outer radius (m).
        outer_radius: f64,
        /// Height of its lower face (m).
        bottom: f64,
        /// Height of its upper face (m).
        top: f64,
    },
    /// An axis-aligned rectangular block, e.g. a plate baffle or a pump housing.
    Block {
        /// Lowest corner (x, y, z) (m).
        min: [f64; 3],
        /// Highest corner (x, y, z) (m).
        max: [f64; 3],
    },
}

/// An internal solid with the part name its wall particles get (solids with the same name
/// share a part).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct InternalSolid {
    /// Part name, used in load outputs (e.g. "column").
    pub name: String,
    /// Its shape.
    pub shape: SolidShape,
}

impl InternalSolid {
    /// A vertical column of `radius` (m) on the axis point `centre` (m), from `bottom` to `top` (m).
    pub fn column(name: &str, centre: [f64; 2], radius: f64, bottom: f64, top: f64) -> Self {
        InternalSolid {
            name: name.to_string(),
            shape: SolidShape::Column {
                centre,
                radius,
                bottom,
                top,
            },
        }
    }

    /// A horizontal ring between radii `inner_radius` and `outer_radius` (m), from `bottom` to
    /// `top` (m), centred on the tank axis.
    pub fn ring(name: &str, inner_radius: f64, outer_radius: f64, bottom: f64, top: f64) -> Self {
        InternalSolid {
            name: name.to_string(),
            shape: SolidShape::Ring {
                inner_radius,
                outer_radius,
                bottom,
                top,
            },
        }
    }

    /// An axis-aligned block between the corners `min` and `max` (m).
    pub fn block(name: &str, min: [f64; 3], max: [f64; 3]) -> Self {
        InternalSolid {
            name: name.to_string(),
            shape: SolidShape::Block { min, max },
        }
    }

    /// Checks the name and the numbers, and that the solid is at least 2 dx thick in every
    /// direction ([`crate::Solid2::min_thickness`], as in 2D): a thinner solid holds no
    /// lattice row at some positions and would let the liquid through.
    pub(crate) fn validate(&self, dx: f64) -> Result<(), GeometryError> {
        crate::solid2::check_part_name("internal solid", &self.name)?;
        let min_thickness = crate::Solid2::min_thickness(dx);
        let name = &self.name;
        let too_thin = |what: &str, size: f64| {
            if size < min_thickness * (1.0 - 1e-9) {
                Err(GeometryError::InvalidShape(format!(
                    "solid '{name}': {what} {size} m is thinner than 2 dx = {min_thickness} m;                      the solid would let the liquid through (make it thicker or use a smaller dx)"
                )))
            } else {
                Ok(())
            }
        };
        if let SolidShape::Block { min, max } = &self.shape {
            for (k, axis) in ["x", "y", "z"].iter().enumerate() {
                check_finite("block corner", min[k])?;
                check_finite("block corner", max[k])?;
                if max[k] <= min[k] {
                    return Err(GeometryError::InvalidShape(format!(
                        "solid '{name}': block max {axis} {} m must be above its min {axis} {} m",
                        max[k], min[k]
                    )));
                }
                too_thin(&format!("block size along {axis}"), max[k] - min[k])?;
            }
            return Ok(());
        }
        let (bottom, top) = match &self.shape {
            SolidShape::Column {
                centre,
                radius,
                bottom,
                top,
            } => {
                check_finite("column centre x", centre[0])?;
                check_finite("column centre y", centre[1])?;
                check_positive("column radius", *radius)?;
                too_thin("column diameter", 2.0 * radius)?;
                (*bottom, *top)
            }
            SolidShape::Ring {
                inner_radius,
                outer_radius,
                bottom,
                top,
            } => {
                check_positive("ring inner radius", *inner_radius)?;
                check_positive("ring outer radius", *outer_radius)?;
                if inner_radius >= outer_radius {
                    return Err(GeometryError::InvalidShape(format!(
                        "solid '{}': ring inner radius {inner_radius} m must be smaller than its outer radius {outer_radius} m",
                        self.name
                    )));
                }
                too_thin(
                    "ring width (outer − inner radius)",
                    outer_radius - inner_radius,
                )?;
                (*bottom, *top)
            }
            SolidShape::Block { .. } => unreachable!("checked above"),
        };
        check_finite("solid bottom height", bottom)?;
        check_finite("solid top height", top)?;
        if top <= bottom {
            return Err(GeometryError::InvalidShape(format!(
                "solid '{}': top {top} m must be above bottom {bottom} m",
                self.name
            )));
        }
        too_thin("height", top - bottom)
    }

    fn surface(&self, dx: f64) -> SurfaceMesh {
        let sag = 1e-3 * dx;
        match &self.shape {
            SolidShape::Column {
                centre,
                radius,
                bottom,
                top,
            } => {
                let n = circle_segments(*radius, dx, sag);
                let profile = [
                    [0.0, *bottom],
                    [*radius, *bottom],
                    [*radius, *top],
                    [0.0, *top],
                ];
                let mut m = revolve_profile(&profile, false, n, dx);
                m.translate([centre[0], centre[1], 0.0]);
                m
            }
            SolidShape::Ring {
                inner_radius,
                outer_radius,
                bottom,
                top,
            } => {
                let n = circle_segments(*outer_radius, dx, sag);
                let profile = [
                    [*inner_radius, *bottom],
                    [*outer_radius, *bottom],
                    [*outer_radius, *top],
                    [*inner_radius, *top],
                ];
                revolve_profile(&profile, true, n, dx)
            }
            SolidShape::Block { min, max } => box_mesh(*min, *max, dx),
        }
    }

    fn contains(&self, p: &Vector3<f64>) -> bool {
        match &self.shape {
            SolidShape::Column {
                centre,
                radius,
                bottom,
                top,
            } => {
                let (x, y) = (p.x - centre[0], p.y - centre[1]);
                x * x + y * y <= radius * radius && p.z >= *bottom && p.z <= *top
            }
            SolidShape::Ring {
                inner_radius,
                outer_radius,
                bottom,
                top,
            } => {
                let r2 = p.x * p.x + p.y * p.y;
                r2 >= inner_radius * inner_radius
                    && r2 <= outer_radius * outer_radius
                    && p.z >= *bottom
                    && p.z <= *top
            }
            SolidShape::Block { min, max } => (0..3).all(|k| p[k] >= min[k] && p[k] <= max[k]),
        }
    }
}

/// An upright cylindrical tank: axis on x = y = 0, floor at z = 0.
#[derive(Debug, Clone, PartialEq)]
pub struct CylinderTank {
    /// Inner radius R (m).
    pub radius: f64,
    /// Height of the cylindrical shell, floor to shell top (m).
    pub shell_height: f64,
    /// Still liquid depth (m).
    pub fill_depth: f64,
    /// The roof.
    pub roof: Roof,
    /// Number of wall particle layers (default 3).
    pub layers: u8,
    /// Initial free-surface tilt along x: elevation above the still level at x = −R (m),
    /// −tilt at x = +R; 0 = flat.
    pub initial_tilt: f64,
    /// Shape of the tilted surface (plane by default).
    pub initial_shape: crate::InitialSurface,
    /// Internal solids (columns, baffle rings).
    pub solids: Vec<InternalSolid>,
    /// How the liquid and the shell's wall particles are laid out (the cubic lattice by
    /// default).
    pub lattice: CylinderLattice,
}

/// How the particles of a cylinder are laid out.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum CylinderLattice {
    /// The cubic lattice ((i+½)dx, (j+½)dx, (k+½)dx) for liquid and walls alike: beside the
    /// shell the liquid and the wall meet in a staircase of steps up to dx deep.
    #[default]
    Cubic,
    /// Rings about the axis, fitted to the shell: the liquid on N = round(R/dx) rings at
    /// radii (k − ½)R/N, the shell's wall layer k on the ring R + (k − ½)dx, points ≈ dx
    /// apart along each ring (each liquid point stands for dx³ to the rounding of the ring's
    /// point count), one ring per lattice row (j + ½)dx; the floor and roof walls keep the
    /// cubic lattice. No staircase at the shell.
    Polar,
}

impl CylinderLattice {
    /// True when the polar lattice can lay out a cylinder with this roof and, with
    /// `has_solids`, internal solids: a built-in roof (rings fit its analytic shell) and no
    /// solids (their walls stand on the cubic lattice).
    pub fn polar_fits(roof: &Roof, has_solids: bool) -> bool {
        !matches!(roof, Roof::Mesh(_)) && !has_solids
    }

    /// Parses a script's `lattice`: `"cubic"` or `"polar"`.
    pub fn from_name(name: &str) -> Option<CylinderLattice> {
        match name.trim().to_ascii_lowercase().as_str() {
            "cubic" => Some(CylinderLattice::Cubic),
            "polar" => Some(CylinderLattice::Polar),
            _ => None,
        }
    }
}

impl CylinderTank {
    /// A tank of radius `radius`, shell height `shell_height` and fill depth `fill_depth` (m),
    /// with the given roof, 3 wall layers, no tilt and no internal solids.
    pub fn new(radius: f64, shell_height: f64, fill_depth: f64, roof: Roof) -> Self {
        CylinderTank {
            radius,
            shell_height,
            fill_depth,
            roof,
            layers: 3,
            initial_tilt: 0.0,
            initial_shape: crate::InitialSurface::Plane,
            solids: Vec::new(),
            lattice: CylinderLattice::Cubic,
        }
    }

    /// Sets the layout of the liquid and shell particles.
    pub fn with_lattice(mut self, lattice: CylinderLattice) -> Self {
        self.lattice = lattice;
        self
    }

    /// Sets the initial free-surface tilt (m, elevation at x = −R).
    pub fn with_initial_tilt(mut self, tilt: f64) -> Self {
        self.initial_tilt = tilt;
        self
    }

    /// Sets the shape of the tilted initial surface.
    pub fn with_initial_shape(mut self, shape: crate::InitialSurface) -> Self {
        self.initial_shape = shape;
        self
    }

    /// Sets the number of wall layers.
    pub fn with_layers(mut self, layers: u8) -> Self {
        self.layers = layers;
        self
    }

    /// Adds an internal solid.
    pub fn with_solid(mut self, solid: InternalSolid) -> Self {
        self.solids.push(solid);
        self
    }

    /// The closed interior surface (cylinder and roof) for spacing `dx` (m), oriented outwards,
    /// with facets no wider than dx and a chord error below dx/1000. For [`Roof::None`] the
    /// shell is closed by a lid `lid_height` (m) above the floor; for [`Roof::Mesh`] the file
    /// is read and checked.
    pub fn interior_surface(&self, dx: f64, lid_height: f64) -> Result<SurfaceMesh, GeometryError> {
        let (r, h) = (self.radius, self.shell_height);
        let sag = 1e-3 * dx;
        let n = circle_segments(r, dx, sag);
        let mut profile = vec![[0.0, 0.0], [r, 0.0], [r, h]];
        match &self.roof {
            Roof::None => {
                profile.push([r, lid_height]);
                profile.push([0.0, lid_height]);
            }
            Roof::Flat => profile.push([0.0, h]),
            Roof::Cone { apex_height } => profile.push([0.0, h + apex_height]),
            Roof::Dome { rise } => profile.extend(dome_profile(r, h, *rise, sag)),
            Roof::Mesh(path) => {
                let mut mesh = SurfaceMesh::read(path)?;
                let name = path.display().to_string();
                mesh.check_closed(&name)?;
                mesh.orient_outwards();
                let (lo, hi) = mesh.bounds();
                let rmax = mesh
                    .vertices
                    .iter()
                    .map(|v| (v[0] * v[0] + v[1] * v[1]).sqrt())
                    .fold(0.0, f64::max);
                let tol = 0.02 * r;
                if (rmax - r).abs() > tol || lo[2].abs() > tol || hi[2] < h - tol {
                    return Err(GeometryError::InvalidShape(format!(
                        "mesh {name} does not fit the cylinder of radius {r} m and shell height {h} m: \
                         its largest radius is {rmax} m, floor at z = {} m, top at z = {} m. The mesh must be \
                         the whole tank interior in metres, axis on x = y = 0, floor at z = 0",
                        lo[2], hi[2]
                    )));
                }
                return Ok(mesh);
            }
        }
        Ok(revolve_profile(&profile, false, n, dx))
    }

    fn validate(&self, dx: f64) -> Result<(), GeometryError> {
        check_positive("tank radius", self.radius)?;
        check_positive("shell height", self.shell_height)?;
        check_positive("fill depth", self.fill_depth)?;
        check_positive("particle spacing dx", dx)?;
        check_finite("initial tilt", self.initial_tilt)?;
        check_layers(self.layers)?;
        if self.lattice == CylinderLattice::Polar {
            if matches!(self.roof, Roof::Mesh(_)) {
                return Err(GeometryError::InvalidShape(
                    "the polar lattice fits rings to the analytic shell; a meshed tank keeps the \
                     cubic lattice (use a flat, cone, dome or no roof, or lattice \"cubic\")"
                        .into(),
                ));
            }
            if !self.solids.is_empty() {
                return Err(GeometryError::InvalidShape(
                    "the polar lattice is for tanks without internal solids (their walls stand \
                     on the cubic lattice); use lattice \"cubic\""
                        .into(),
                ));
            }
        }
        match &self.roof {
            Roof::Cone { apex_height } => check_positive("cone roof apex height", *apex_height)?,
            Roof::Dome { rise } => {
                check_positive("dome roof rise", *rise)?;
                if *rise > self.radius {
                    return Err(GeometryError::InvalidShape(format!(
                        "dome roof rise {rise} m is larger than the tank radius {} m (a spherical cap over the shell rises at most R)",
                        self.radius
                    )));
                }
            }
            _ => {}
        }
        if dx > self.radius {
            return Err(GeometryError::SpacingTooLarge {
                dx,
                what: "radius",
                size: self.radius,
            });
        }
        for s in &self.solids {
            s.validate(dx)?;
        }
        Ok(())
    }

    /// Builds the initial particles for spacing `dx` (m), following the 3D rules in the
    /// crate documentation. Part areas sum to πR² (bottom), 2πRH (wall) and the exact roof
    /// area (flat πR², cone πR√(R²+h²), dome π(R²+rise²)); mesh roofs: the mesh areas.
    pub fn build(&self, dx: f64) -> Result<ParticleSetup<3>, GeometryError> {
        self.validate(dx)?;
        let (r, h) = (self.radius, self.shell_height);
        let open = matches!(self.roof, Roof::None);
        let lid = h + (self.layers as f64 + 3.0) * dx;
        let surface = self.interior_surface(dx, lid)?;
        let (_, hi) = surface.bounds();
        let top = if open { h } else { hi[2] };
        let roof_area = match &self.roof {
            Roof::None => None,
            Roof::Flat => Some(PI * r * r),
            Roof::Cone { apex_height } => Some(PI * r * (r * r + apex_height * apex_height).sqrt()),
            Roof::Dome { rise } => Some(PI * (r * r + rise * rise)),
            Roof::Mesh(_) => None,
        };
        let analytic = if matches!(self.roof, Roof::Mesh(_)) {
            [None, None, None]
        } else {
            [Some(PI * r * r), Some(2.0 * PI * r * h), roof_area]
        };
        let region = match &self.roof {
            Roof::Mesh(_) => RegionShape::Mesh,
            roof => RegionShape::Cylinder {
                radius: r,
                shell_height: h,
                roof: roof.clone(),
            },
        };
        let spec = MeshTankSpec {
            surface,
            shell_height: h,
            open,
            fill_depth: self.fill_depth,
            initial_tilt: self.initial_tilt,
            tilt_shape: match self.initial_shape {
                crate::InitialSurface::Plane => TiltShape::Plane { span: [-r, r] },
                crate::InitialSurface::FirstMode => TiltShape::CylinderMode { radius: r },
            },
            layers: self.layers,
            solids: self.solids.clone(),
            analytic_part_area: analytic,
            interior_min: [-r, -r, 0.0],
            interior_max: [r, r, top],
            region,
            extra_parts: Vec::new(),
        };
        let tilt_shape = spec.tilt_shape;
        let mut setup = build_mesh_tank(&spec, dx)?;
        if self.lattice == CylinderLattice::Polar {
            self.fit_polar_lattice(&mut setup, tilt_shape, dx);
        }
        Ok(setup)
    }

    /// Lays the liquid and the shell's walls on rings about the axis
    /// ([`CylinderLattice::Polar`]) in a tank built on the cubic lattice. Liquid: N =
    /// round(R/dx) rings at radii r = (k − ½)R/N with round(2π r (R/N)/dx²) points (at least
    /// one), each column of rows (j + ½)dx up to the fill surface, its rows rounded by error
    /// diffusion along the rings as the cubic builder's columns are; shell: wall layer k on the
    /// ring R + (k − ½)dx with round(2π r/dx) points, radial normals, the innermost layer
    /// sharing the shell area 2πRH. Alternate rings are turned by half a spacing. The cubic
    /// particles beside the shell (outside the radius, floor to shell top) are dropped; the
    /// corners below the floor and above the shell top keep theirs.
    fn fit_polar_lattice(&self, setup: &mut ParticleSetup<3>, tilt_shape: TiltShape, dx: f64) {
        let (r, h) = (self.radius, self.shell_height);
        let wall_part = 1u16;
        let ring_points = |radius: f64, width: f64| {
            ((2.0 * PI * radius * width / (dx * dx)).round() as usize).max(1)
        };
        let on_ring = |radius: f64, m: usize, points: usize, turned: bool| {
            let turn = if turned { 0.5 } else { 0.0 };
            let angle = 2.0 * PI * (m as f64 + turn) / points as f64;
            let (sin, cos) = angle.sin_cos();
            (radius * cos, radius * sin, cos, sin)
        };

        // Liquid: one column per ring point, its rows rounded by error diffusion along the
        // rings (the residual carried from one column to the next keeps the volume).
        setup.fluid_positions.clear();
        let rings = (r / dx).round().max(1.0) as usize;
        let width = r / rings as f64;
        let mut owed = 0.0;
        for k in 1..=rings {
            let radius = (k as f64 - 0.5) * width;
            let points = ring_points(radius, width);
            for m in 0..points {
                let (x, y, _, _) = on_ring(radius, m, points, k % 2 == 0);
                let wanted =
                    (setup.fill_level + self.initial_tilt * tilt_shape.at(x, y)) / dx + owed;
                let rows = wanted.round().max(0.0);
                owed = wanted - rows;
                for j in 0..rows as usize {
                    let p = Vector3::new(x, y, (j as f64 + 0.5) * dx);
                    if setup.interior.contains(&p) {
                        setup.fluid_positions.push(p);
                    }
                }
            }
        }

        // Shell: drop the cubic wall particles beside it, then add the rings.
        let beside_shell =
            |p: &Vector3<f64>| p.z > 0.0 && p.z < h && (p.x * p.x + p.y * p.y).sqrt() > r;
        setup.retain_walls(|p, _| !beside_shell(p));
        // The shell's area goes to the rings alone.
        for (a, part) in setup.wall_area.iter_mut().zip(&setup.wall_part) {
            if *part == wall_part {
                *a = 0.0;
            }
        }
        let first_ring = setup.wall_positions.len();
        let rows = (0..).map(|j| (j as f64 + 0.5) * dx).take_while(|z| *z < h);
        for z in rows {
            for layer in 1..=self.layers {
                let radius = r + (layer as f64 - 0.5) * dx;
                let points = ring_points(radius, dx);
                for m in 0..points {
                    let (x, y, cos, sin) = on_ring(radius, m, points, layer % 2 == 0);
                    setup.wall_positions.push(Vector3::new(x, y, z));
                    setup.wall_part.push(wall_part);
                    setup.wall_normal.push(Vector3::new(cos, sin, 0.0));
                    setup.wall_layer.push(layer);
                    setup
                        .wall_area
                        .push(if layer == 1 { 1.0 / points as f64 } else { 0.0 });
                }
            }
        }
        let rings_area: f64 = setup.wall_area[first_ring..].iter().sum();
        let shell_area = 2.0 * PI * r * h;
        for a in &mut setup.wall_area[first_ring..] {
            *a *= shell_area / rings_area;
        }
    }
}

/// A rectangular box tank [0, width] × [0, breadth] × [0, tank_height] (m), for comparing 2D
/// and 3D runs (x and z as in [`crate::RectTank2`], y across).
#[derive(Debug, Clone, PartialEq)]
pub struct BoxTank {
    /// Inner length along x (m).
    pub width: f64,
    /// Inner length along y (m).
    pub breadth: f64,
    /// Height of the side walls (m).
    pub tank_height: f64,
    /// Still liquid depth (m).
    pub fill_depth: f64,
    /// True for a flat roof at `tank_height`.
    pub roof: bool,
    /// Number of wall layers (default 3).
    pub layers: u8,
    /// Initial tilt along x: elevation above the still level at x = 0 (m), −tilt at x = W.
    pub initial_tilt: f64,
    /// Shape of the tilted surface (plane by default).
    pub initial_shape: crate::InitialSurface,
    /// Internal solids.
    pub solids: Vec<InternalSolid>,
}

impl BoxTank {
    /// A closed box tank with 3 wall layers, no tilt, no solids.
    pub fn new(width: f64, breadth: f64, tank_height: f64, fill_depth: f64) -> Self {
        BoxTank {
            width,
            breadth,
            tank_height,
            fill_depth,
            roof: true,
            layers: 3,
            initial_tilt: 0.0,
            initial_shape: crate::InitialSurface::Plane,
            solids: Vec::new(),
        }
    }

    /// Sets whether the box has a roof.
    pub fn with_roof(mut self, roof: bool) -> Self {
        self.roof = roof;
        self
    }

    /// Sets the initial tilt (m, elevation at x = 0).
    pub fn with_initial_tilt(mut self, tilt: f64) -> Self {
        self.initial_tilt = tilt;
        self
    }

    /// Sets the shape of the tilted initial surface.
    pub fn with_initial_shape(mut self, shape: crate::InitialSurface) -> Self {
        self.initial_shape = shape;
        self
    }

    /// Sets the number of wall layers.
    pub fn with_layers(mut self, layers: u8) -> Self {
        self.layers = layers;
        self
    }

    /// Adds an internal solid.
    pub fn with_solid(mut self, solid: InternalSolid) -> Self {
        self.solids.push(solid);
        self
    }

    /// Builds the particles for spacing `dx` (m), following the 3D rules in the crate
    /// documentation. Width, breadth and height must be whole multiples of dx; the lattice is
    /// at cell centres, so the fluid block is exact (W·B·depth/dx³ particles).
    pub fn build(&self, dx: f64) -> Result<ParticleSetup<3>, GeometryError> {
        check_positive("tank width", self.width)?;
        check_positive("tank breadth", self.breadth)?;
        check_positive("tank height", self.tank_height)?;
        check_positive("fill depth", self.fill_depth)?;
        check_positive("particle spacing dx", dx)?;
        check_finite("initial tilt", self.initial_tilt)?;
        check_layers(self.layers)?;
        for (what, size) in [
            ("width", self.width),
            ("breadth", self.breadth),
            ("height", self.tank_height),
        ] {
            if dx > size {
                return Err(GeometryError::SpacingTooLarge { dx, what, size });
            }
        }
        for (what, size) in [
            ("tank width", self.width),
            ("tank breadth", self.breadth),
            ("tank height", self.tank_height),
        ] {
            let ratio = size / dx;
            let n = ratio.round();
            if (ratio - n).abs() > 1e-6 * ratio.max(1.0) {
                return Err(GeometryError::NotMultipleOfSpacing {
                    what,
                    size,
                    dx,
                    ratio,
                    suggestion: size / n.max(1.0),
                });
            }
        }
        for s in &self.solids {
            s.validate(dx)?;
        }
        let (w, b, h) = (self.width, self.breadth, self.tank_height);
        let lid = h + (self.layers as f64 + 3.0) * dx;
        let top = if self.roof { h } else { lid };
        let surface = box_mesh([0.0, 0.0, 0.0], [w, b, top], dx);
        let spec = MeshTankSpec {
            surface,
            shell_height: h,
            open: !self.roof,
            fill_depth: self.fill_depth,
            initial_tilt: self.initial_tilt,
            tilt_shape: match self.initial_shape {
                crate::InitialSurface::Plane => TiltShape::Plane { span: [0.0, w] },
                crate::InitialSurface::FirstMode => TiltShape::Cosine { span: [0.0, w] },
            },
            layers: self.layers,
            solids: self.solids.clone(),
            analytic_part_area: [
                Some(w * b),
                Some(2.0 * (w + b) * h),
                self.roof.then_some(w * b),
            ],
            interior_min: [0.0, 0.0, 0.0],
            interior_max: [w, b, h],
            region: RegionShape::Box { max: [w, b, h] },
            extra_parts: Vec::new(),
        };
        build_mesh_tank(&spec, dx)
    }
}

/// A spherical tank of inner radius `radius` (m), centre on the axis at z = radius (the lowest
/// point at z = 0). Parts by the way the surface faces out of the liquid: `roof` within 45° of
/// straight up (the polar cap above latitude 45°), `bottom` within 45° of straight down, `wall`
/// the zone between; their areas are the spherical zones 2πR²(1 − 1/√2), 2√2 πR² and
/// 2πR²(1 − 1/√2) (Archimedes: a zone's area is 2πR times its height).
#[derive(Debug, Clone, PartialEq)]
pub struct SphereTank {
    /// Inner radius R (m).
    pub radius: f64,
    /// Still liquid depth above the lowest point (m).
    pub fill_depth: f64,
    /// Number of wall particle layers (default 3).
    pub layers: u8,
    /// Initial free-surface tilt along x: elevation above the still level at x = −R (m).
    pub initial_tilt: f64,
    /// Shape of the tilted surface (plane by default; the first mode is the rectangle's
    /// cos(πξ) across the diameter).
    pub initial_shape: crate::InitialSurface,
}

impl SphereTank {
    /// A sphere of `radius` filled to `fill_depth` (m), 3 wall layers, no tilt.
    pub fn new(radius: f64, fill_depth: f64) -> Self {
        SphereTank {
            radius,
            fill_depth,
            layers: 3,
            initial_tilt: 0.0,
            initial_shape: crate::InitialSurface::Plane,
        }
    }

    /// Sets the initial free-surface tilt (m, elevation at x = −R).
    pub fn with_initial_tilt(mut self, tilt: f64) -> Self {
        self.initial_tilt = tilt;
        self
    }

    /// Sets the shape of the tilted initial surface.
    pub fn with_initial_shape(mut self, shape: crate::InitialSurface) -> Self {
        self.initial_shape = shape;
        self
    }

    /// Sets the number of wall layers.
    pub fn with_layers(mut self, layers: u8) -> Self {
        self.layers = layers;
        self
    }

    /// Builds the initial particles for spacing `dx` (m), following the 3D rules in the crate
    /// documentation, with the parts by facing described on the type.
    pub fn build(&self, dx: f64) -> Result<ParticleSetup<3>, GeometryError> {
        let r = self.radius;
        check_positive("tank radius", r)?;
        check_positive("fill depth", self.fill_depth)?;
        check_positive("particle spacing dx", dx)?;
        check_finite("initial tilt", self.initial_tilt)?;
        check_layers(self.layers)?;
        if dx > r {
            return Err(GeometryError::SpacingTooLarge {
                dx,
                what: "radius",
                size: r,
            });
        }
        // meridian from the lowest to the highest point, with vertices on latitudes ±45° so
        // that no facet straddles two parts
        let sag = 1e-3 * dx;
        let n = circle_segments(r, dx, sag).div_ceil(8) * 8;
        let profile: Vec<[f64; 2]> = (0..=n / 2)
            .map(|k| {
                let phi = -0.5 * PI + PI * k as f64 / (n / 2) as f64;
                let rr = if k == 0 || k == n / 2 {
                    0.0
                } else {
                    r * phi.cos()
                };
                [rr, r + r * phi.sin()]
            })
            .collect();
        let surface = revolve_profile(&profile, false, n, dx);
        let triangle_parts = surface
            .triangles
            .iter()
            .map(|t| {
                let v = t.map(|i| PVec3::from(surface.vertices[i as usize]));
                let nz = (v[1] - v[0]).cross(v[2] - v[0]).normalize_or_zero().z;
                if nz > std::f64::consts::FRAC_1_SQRT_2 {
                    2
                } else if nz < -std::f64::consts::FRAC_1_SQRT_2 {
                    0
                } else {
                    1
                }
            })
            .collect();
        let cap = 2.0 * PI * r * r * (1.0 - std::f64::consts::FRAC_1_SQRT_2);
        let spec = MeshTankSpec {
            surface,
            shell_height: 2.0 * r,
            open: false,
            fill_depth: self.fill_depth,
            initial_tilt: self.initial_tilt,
            tilt_shape: match self.initial_shape {
                crate::InitialSurface::Plane => TiltShape::Plane { span: [-r, r] },
                crate::InitialSurface::FirstMode => TiltShape::Cosine { span: [-r, r] },
            },
            layers: self.layers,
            solids: Vec::new(),
            analytic_part_area: [Some(cap), Some(4.0 * PI * r * r - 2.0 * cap), Some(cap)],
            interior_min: [-r, -r, 0.0],
            interior_max: [r, r, 2.0 * r],
            region: RegionShape::Mesh,
            extra_parts: Vec::new(),
        };
        build_mesh_tank_with_parts(&spec, Some(triangle_parts), dx)
    }
}

/// The exact shape used by [`TankInterior::contains`] (fast analytic tests where possible).
#[derive(Debug, Clone)]
pub(crate) enum RegionShape {
    Cylinder {
        radius: f64,
        shell_height: f64,
        roof: Roof,
    },
    Box {
        max: [f64; 3],
    },
    Mesh,
}

/// The tilted initial surface: elevation above the fill level per unit tilt, as a function of
/// the horizontal position.
#[derive(Debug, Clone, Copy)]
pub(crate) enum TiltShape {
    /// Plane: +1 at x = span[0], −1 at x = span[1].
    Plane { span: [f64; 2] },
    /// First cylinder mode: −(x/r) J₁(ξ₁ r/R)/J₁(ξ₁) (+1 at x = −R).
    CylinderMode { radius: f64 },
    /// First rectangular mode: cos(π (x − span[0])/(span[1] − span[0])).
    Cosine { span: [f64; 2] },
}

impl TiltShape {
    /// Elevation per unit tilt at (x, y) (m/m).
    pub(crate) fn at(&self, x: f64, y: f64) -> f64 {
        match *self {
            TiltShape::Plane { span } => 1.0 - 2.0 * (x - span[0]) / (span[1] - span[0]),
            TiltShape::Cosine { span } => {
                (std::f64::consts::PI * (x - span[0]) / (span[1] - span[0])).cos()
            }
            TiltShape::CylinderMode { radius } => {
                let xi1 = slosh_theory::bessel::bessel_j_derivative_zero(1, 1);
                let r = (x * x + y * y).sqrt().min(radius);
                if r == 0.0 {
                    return 0.0;
                }
                -(x / r) * slosh_theory::bessel::bessel_j(1, xi1 * r / radius)
                    / slosh_theory::bessel::bessel_j(1, xi1)
            }
        }
    }

    /// Range of x the shape is defined over (m).
    pub(crate) fn span(&self) -> [f64; 2] {
        match *self {
            TiltShape::Plane { span } | TiltShape::Cosine { span } => span,
            TiltShape::CylinderMode { radius } => [-radius, radius],
        }
    }
}

/// A tank given by its closed interior surface; the common input of [`build_mesh_tank`].
#[derive(Debug, Clone)]
pub(crate) struct MeshTankSpec {
    /// Closed interior surface, normals out of the liquid. Open tanks: shell continued above
    /// `shell_height` and closed by a lid (those triangles make no wall particles).
    pub(crate) surface: SurfaceMesh,
    /// Height of the shell top (m): triangles entirely at or above it are roof (closed) or
    /// nothing (open).
    pub(crate) shell_height: f64,
    pub(crate) open: bool,
    pub(crate) fill_depth: f64,
    pub(crate) initial_tilt: f64,
    /// Shape of the tilted surface.
    pub(crate) tilt_shape: TiltShape,
    pub(crate) layers: u8,
    pub(crate) solids: Vec<InternalSolid>,
    /// Exact areas of bottom, wall, roof (m²) when known; the mesh areas are rescaled to them.
    pub(crate) analytic_part_area: [Option<f64>; 3],
    /// Parts of the tank surface after `bottom`, `wall`, `roof` (part indices 3, 4, …, before
    /// the internal solids' parts).
    pub(crate) extra_parts: Vec<String>,
    pub(crate) interior_min: [f64; 3],
    pub(crate) interior_max: [f64; 3],
    pub(crate) region: RegionShape,
}

/// One closed boundary surface as a parry mesh with a part per triangle.
struct Boundary {
    mesh: TriMesh,
    tri_part: Vec<u16>,
    /// Triangles around each vertex (CSR: offsets, list).
    vert_tri_start: Vec<u32>,
    vert_tri: Vec<u32>,
    /// True for internal solids (wall inside the mesh), false for the tank (wall outside).
    solid: bool,
    lo: PVec3,
    hi: PVec3,
}

impl Boundary {
    fn new(surface: &SurfaceMesh, tri_part: Vec<u16>, solid: bool) -> Result<Self, GeometryError> {
        let vertices: Vec<PVec3> = surface
            .vertices
            .iter()
            .map(|v| PVec3::new(v[0], v[1], v[2]))
            .collect();
        let mesh = TriMesh::with_flags(vertices, surface.triangles.clone(), TriMeshFlags::ORIENTED)
            .map_err(|e| GeometryError::InvalidShape(format!("cannot build the tank mesh: {e}")))?;
        let nv = mesh.vertices().len();
        let mut count = vec![0u32; nv + 1];
        for t in mesh.indices() {
            for &v in t {
                count[v as usize + 1] += 1;
            }
        }
        for i in 0..nv {
            count[i + 1] += count[i];
        }
        let mut fill = count.clone();
        let mut list = vec![0u32; count[nv] as usize];
        for (k, t) in mesh.indices().iter().enumerate() {
            for &v in t {
                list[fill[v as usize] as usize] = k as u32;
                fill[v as usize] += 1;
            }
        }
        let aabb = mesh.local_aabb();
        Ok(Boundary {
            tri_part,
            vert_tri_start: count,
            vert_tri: list,
            solid,
            lo: aabb.mins,
            hi: aabb.maxs,
            mesh,
        })
    }

    /// Unit normal of triangle `t`, pointing from the liquid into the wall.
    fn wallward_normal(&self, t: u32) -> PVec3 {
        let n = self.mesh.triangle(t).scaled_normal().normalize_or_zero();
        if self.solid {
            -n
        } else {
            n
        }
    }

    /// Whether x lies within `margin` of the bounding box.
    fn near_box(&self, x: PVec3, margin: f64) -> bool {
        x.x >= self.lo.x - margin
            && x.y >= self.lo.y - margin
            && x.z >= self.lo.z - margin
            && x.x <= self.hi.x + margin
            && x.y <= self.hi.y + margin
            && x.z <= self.hi.z + margin
    }

    /// Projects x: (inside the mesh, distance, nearest point, triangle, location).
    fn query(&self, x: PVec3) -> Query {
        let (proj, (tri, loc)) = self.mesh.project_local_point_and_get_location(x, false);
        Query {
            inside: proj.is_inside,
            dist: (x - proj.point).length(),
            point: proj.point,
            tri,
            on_face: matches!(
                loc,
                TrianglePointLocation::OnFace(..) | TrianglePointLocation::OnSolid
            ),
        }
    }

    /// Part and into-wall normal for a wall point x with projection `q` (None: no part).
    fn tag(&self, x: PVec3, q: &Query, dx: f64) -> Option<(u16, PVec3)> {
        let t = q.tri;
        if q.on_face {
            let part = self.tri_part[t as usize];
            return (part != NO_PART).then(|| (part, self.wallward_normal(t)));
        }
        // On an edge or a vertex: gather the triangles that are equally near.
        let tol = 1e-7 * dx;
        let mut cands: Vec<u32> = Vec::new();
        for &v in &self.mesh.indices()[t as usize] {
            let (s, e) = (
                self.vert_tri_start[v as usize] as usize,
                self.vert_tri_start[v as usize + 1] as usize,
            );
            for &k in &self.vert_tri[s..e] {
                if cands.contains(&k) {
                    continue;
                }
                let d = self.mesh.triangle(k).distance_to_local_point(x, false);
                if d <= q.dist + tol {
                    cands.push(k);
                }
            }
        }
        if cands.is_empty() {
            cands.push(t);
        }
        let first = self.tri_part[cands[0] as usize];
        if cands.iter().all(|&k| self.tri_part[k as usize] == first) {
            if first == NO_PART {
                return None;
            }
            let n = if q.dist > 1e-6 * dx {
                (x - q.point) / q.dist
            } else {
                self.wallward_normal(t)
            };
            return Some((first, n));
        }
        // Several parts meet here: the part of the nearest face plane; ties go to the part of
        // higher priority (roof over wall over bottom), as in the 2D ring corners.
        let mut best: Option<(f64, u16, u32)> = None;
        for &k in &cands {
            let tri = self.mesh.triangle(k);
            let n = self.wallward_normal(k);
            let plane = (x - tri.a).dot(n).abs();
            let part = self.tri_part[k as usize];
            let better = match best {
                None => true,
                Some((bd, bp, _)) => {
                    plane < bd - tol
                        || (plane <= bd + tol && part_priority(part) > part_priority(bp))
                }
            };
            if better {
                best = Some((plane, part, k));
            }
        }
        let (_, part, k) = best.expect("at least one candidate");
        (part != NO_PART).then(|| (part, self.wallward_normal(k)))
    }
}

#[derive(Clone, Copy)]
struct Query {
    inside: bool,
    dist: f64,
    point: PVec3,
    tri: u32,
    on_face: bool,
}

/// Tags the triangles of a tank interior surface: bottom if all corners are on the floor,
/// roof (closed) or no part (open) if all corners are at or above the shell top, wall otherwise.
fn tag_tank_triangles(surface: &SurfaceMesh, shell_height: f64, open: bool) -> Vec<u16> {
    let (lo, hi) = surface.bounds();
    let eps = 1e-9 * (hi[2] - lo[2]).abs().max(1.0);
    surface
        .triangles
        .iter()
        .map(|t| {
            let z = t.map(|i| surface.vertices[i as usize][2]);
            if z.iter().all(|&z| z <= lo[2] + eps) {
                0
            } else if z.iter().all(|&z| z >= shell_height - eps) {
                if open {
                    NO_PART
                } else {
                    2
                }
            } else {
                1
            }
        })
        .collect()
}

/// Result of classifying one lattice point.
#[derive(Clone, Copy)]
enum Class {
    Fluid(PVec3),
    Wall {
        pos: PVec3,
        part: u16,
        normal: PVec3,
        layer: u8,
    },
}

/// The interior region of a 3D tank (tank shape minus internal solids).
pub struct TankRegion3 {
    shape: RegionShape,
    mesh: Arc<TriMesh>,
    open_top: Option<f64>,
    solids: Vec<InternalSolid>,
}

impl TankInterior<3> for TankRegion3 {
    fn contains(&self, p: &Vector3<f64>) -> bool {
        let z = match self.open_top {
            Some(top) => p.z.min(top),
            None => p.z,
        };
        let in_tank = match &self.shape {
            RegionShape::Cylinder {
                radius,
                shell_height,
                roof,
            } => {
                let r2 = p.x * p.x + p.y * p.y;
                if r2 > radius * radius || z < 0.0 {
                    false
                } else {
                    let r = r2.sqrt();
                    let roof_z = match roof {
                        Roof::None => f64::INFINITY,
                        Roof::Flat | Roof::Mesh(_) => *shell_height,
                        Roof::Cone { apex_height } => {
                            shell_height + apex_height * (1.0 - r / radius)
                        }
                        Roof::Dome { rise } => {
                            let a = (radius * radius + rise * rise) / (2.0 * rise);
                            shell_height + rise - a + (a * a - r2).max(0.0).sqrt()
                        }
                    };
                    let _ = r;
                    z <= roof_z
                }
            }
            RegionShape::Box { max } => {
                p.x >= 0.0
                    && p.y >= 0.0
                    && z >= 0.0
                    && p.x <= max[0]
                    && p.y <= max[1]
                    && z <= max[2]
            }
            RegionShape::Mesh => {
                let aabb = self.mesh.local_aabb();
                let q = PVec3::new(p.x, p.y, z);
                q.x >= aabb.mins.x
                    && q.y >= aabb.mins.y
                    && q.z >= aabb.mins.z
                    && q.x <= aabb.maxs.x
                    && q.y <= aabb.maxs.y
                    && q.z <= aabb.maxs.z
                    && self.mesh.contains_local_point(q)
            }
        };
        in_tank && !self.solids.iter().any(|s| s.contains(p))
    }

    /// Distance to the tank surface mesh for points outside the tank; points inside an
    /// internal solid count as far outside.
    fn distance_outside(&self, p: &Vector3<f64>) -> f64 {
        if self.contains(p) {
            return 0.0;
        }
        if self.solids.iter().any(|s| s.contains(p)) {
            return f64::INFINITY;
        }
        let z = match self.open_top {
            Some(top) => p.z.min(top),
            None => p.z,
        };
        self.mesh
            .distance_to_local_point(PVec3::new(p.x, p.y, z), true)
    }
}

/// What the area sampling of one surface triangle produced.
struct TriangleSamples {
    /// Part of the triangle.
    part: u16,
    /// Triangle area (m²).
    full: f64,
    /// Wetted part of it (m²).
    wet: f64,
    /// (wall particle, raw area) for each wetted sample.
    assigned: Vec<(u32, f64)>,
}

/// Turns a closed tank surface into particles on the cubic lattice ((i+½)dx, (j+½)dx, (k+½)dx).
///
/// Rules:
/// * fluid: lattice points inside the tank and outside every internal solid, below the
///   (tilted) fill surface; the fill level reported is the top of the lattice rows below the
///   fill depth (rows·dx);
/// * walls: lattice points outside the tank (or inside a solid) within `layers`·dx (+1e-6 dx)
///   Euclidean distance of that surface; open tanks only below the shell top; a point that
///   qualifies for several surfaces takes the nearest;
/// * layer = ceil(distance/dx) clamped to 1..=layers;
/// * part: that of the nearest surface triangle; where parts meet (an edge or corner point)
///   the part whose face plane is nearest, ties to roof over wall over bottom;
/// * normal (liquid → wall): the face normal of that triangle, or the direction from the
///   nearest surface point to the particle where a single part's edges/vertices are nearest;
/// * area: the wetted surface of each part is sampled at ≤ dx/2 spacing and each sample's area
///   goes to the nearest innermost-layer particle of the same part; each part's areas are then
///   scaled so they sum to the part's exact area (analytic for the built-in shapes, the
///   wetted mesh area otherwise). Other particles get 0.
fn build_mesh_tank(spec: &MeshTankSpec, dx: f64) -> Result<ParticleSetup<3>, GeometryError> {
    build_mesh_tank_with_parts(spec, None, dx)
}

/// [`build_mesh_tank`] with the part of each surface triangle given (`None`: floor, shell and
/// roof by height, [`tag_tank_triangles`]).
pub(crate) fn build_mesh_tank_with_parts(
    spec: &MeshTankSpec,
    triangle_parts: Option<Vec<u16>>,
    dx: f64,
) -> Result<ParticleSetup<3>, GeometryError> {
    let layers = spec.layers;
    let reach = layers as f64 * dx + 1e-6 * dx;
    let (lo, hi) = spec.surface.bounds();
    let top = hi[2];
    // fill level and checks
    let rows = lattice_rows_below(spec.fill_depth, dx);
    if rows < 1.0 {
        return Err(GeometryError::SpacingAboveFill {
            dx,
            fill: spec.fill_depth,
        });
    }
    let fill_level = rows * dx;
    let max_level = if spec.open { spec.shell_height } else { top };
    if spec.fill_depth > max_level * (1.0 + 1e-12) {
        return Err(GeometryError::FillAboveTank {
            fill: spec.fill_depth,
            height: max_level,
        });
    }
    let tilt = spec.initial_tilt;
    if fill_level - tilt.abs() < 0.0 {
        return Err(GeometryError::TiltTooLarge {
            tilt,
            reason: format!(
                "the tilted surface would dip below the floor (fill level {fill_level} m)"
            ),
        });
    }
    if fill_level + tilt.abs() > max_level + 1e-12 {
        return Err(GeometryError::TiltTooLarge {
            tilt,
            reason: format!(
                "the tilted surface would rise above the tank top {max_level} m (fill level {fill_level} m)"
            ),
        });
    }
    // lattice range
    let pad = reach + dx;
    let imin = [
        cell_of(lo[0] - pad, dx),
        cell_of(lo[1] - pad, dx),
        cell_of(lo[2] - pad, dx),
    ];
    let mut imax = [
        cell_of(hi[0] + pad, dx),
        cell_of(hi[1] + pad, dx),
        cell_of(hi[2] + pad, dx),
    ];
    if spec.open {
        // only points strictly below the shell top
        imax[2] = ((spec.shell_height / dx - 0.5).ceil() as i64 - 1).min(imax[2]);
    }
    let dims = [
        (imax[0] - imin[0] + 1) as usize,
        (imax[1] - imin[1] + 1) as usize,
        (imax[2] - imin[2] + 1) as usize,
    ];
    let estimate = dims[0] as u64 * dims[1] as u64 * dims[2] as u64;
    if estimate > 2 * MAX_PARTICLES {
        return Err(GeometryError::TooManyParticles {
            dx,
            estimate,
            limit: MAX_PARTICLES,
        });
    }

    // boundaries
    let tank = Boundary::new(
        &spec.surface,
        triangle_parts
            .unwrap_or_else(|| tag_tank_triangles(&spec.surface, spec.shell_height, spec.open)),
        false,
    )?;
    let mut part_names: Vec<String> = vec![PART_BOTTOM.into(), PART_WALL.into(), PART_ROOF.into()];
    part_names.extend(spec.extra_parts.iter().cloned());
    let mut solids = Vec::new();
    for s in &spec.solids {
        let idx = match part_names.iter().position(|n| *n == s.name) {
            Some(i) => i,
            None => {
                part_names.push(s.name.clone());
                part_names.len() - 1
            }
        } as u16;
        let surf = s.surface(dx);
        solids.push(Boundary::new(&surf, vec![idx; surf.triangles.len()], true)?);
    }

    let point = |i: i64, j: i64, k: i64| {
        PVec3::new(
            (i as f64 + 0.5) * dx,
            (j as f64 + 0.5) * dx,
            (k as f64 + 0.5) * dx,
        )
    };
    let span = spec.tilt_shape.span();
    let surface_z = |x: f64, y: f64| fill_level + tilt * spec.tilt_shape.at(x, y);
    // The tilted surface on the lattice: each column (i, j) holds a whole number of rows,
    // chosen by two-dimensional error diffusion (Floyd & Steinberg 1976, serpentine scan) so
    // that the staircase follows the tilted surface on average over a few columns — the kernel
    // sees the intended surface even when the tilt is smaller than dx, where cutting the
    // lattice at the surface would leave it flat, and the extra rows are spread over the
    // area instead of lining up in one ridge.
    let i_lo = (span[0] / dx).floor() as i64 - 1;
    let i_hi = (span[1] / dx).ceil() as i64 + 1;
    let j_lo = (spec.interior_min[1] / dx).floor() as i64 - 1;
    let j_hi = (spec.interior_max[1] / dx).ceil() as i64 + 1;
    let row_len = (i_hi - i_lo + 1) as usize;
    let n_rows = (j_hi - j_lo + 1) as usize;
    let mut column_tops = vec![fill_level; row_len * n_rows];
    if tilt != 0.0 {
        // residual[k]: rows still owed to column k by its already-rounded neighbours
        let mut residual = vec![0.0; row_len * n_rows];
        for jj in 0..n_rows {
            let y = ((j_lo + jj as i64) as f64 + 0.5) * dx;
            let forward = jj % 2 == 0;
            for step in 0..row_len {
                let ii = if forward { step } else { row_len - 1 - step };
                let k = jj * row_len + ii;
                let x = ((i_lo + ii as i64) as f64 + 0.5) * dx;
                let wanted = surface_z(x, y) / dx + residual[k];
                let rows = wanted.round();
                column_tops[k] = rows * dx;
                let error = wanted - rows;
                // 7/16 ahead in the row, 3/16, 5/16, 1/16 to the next row (behind, below, ahead)
                let ahead = |d: i64| -> Option<usize> {
                    let i = ii as i64 + if forward { d } else { -d };
                    (0..row_len as i64).contains(&i).then_some(i as usize)
                };
                if let Some(i) = ahead(1) {
                    residual[k - ii + i] += error * 7.0 / 16.0;
                }
                if jj + 1 < n_rows {
                    let below = (jj + 1) * row_len;
                    for (d, w) in [(-1, 3.0), (0, 5.0), (1, 1.0)] {
                        if let Some(i) = ahead(d) {
                            residual[below + i] += error * w / 16.0;
                        }
                    }
                }
            }
        }
    }
    let column_top = |x: f64, y: f64| -> f64 {
        let i = (x / dx).floor() as i64;
        let j = (y / dx).floor() as i64;
        if (i_lo..=i_hi).contains(&i) && (j_lo..=j_hi).contains(&j) {
            column_tops[(j - j_lo) as usize * row_len + (i - i_lo) as usize]
        } else {
            surface_z(x, y)
        }
    };

    // classify block by block
    const B: i64 = 8;
    let nb = [
        (dims[0] as i64 + B - 1) / B,
        (dims[1] as i64 + B - 1) / B,
        (dims[2] as i64 + B - 1) / B,
    ];
    let blocks: Vec<[i64; 3]> = (0..nb[2])
        .flat_map(|bk| (0..nb[1]).flat_map(move |bj| (0..nb[0]).map(move |bi| [bi, bj, bk])))
        .collect();
    let classify_point = |x: PVec3| -> Option<Class> {
        let qt = tank.query(x);
        let mut in_solid = false;
        let mut best: Option<(f64, &Boundary, Query)> = None;
        if !qt.inside && qt.dist <= reach {
            best = Some((qt.dist, &tank, qt));
        }
        let tank_inside = qt.inside;
        for s in &solids {
            if !s.near_box(x, reach) {
                continue;
            }
            let q = s.query(x);
            if q.inside {
                in_solid = true;
                if q.dist <= reach && best.as_ref().is_none_or(|b| q.dist < b.0) {
                    best = Some((q.dist, s, q));
                }
            }
        }
        if tank_inside && !in_solid {
            return (x.z < column_top(x.x, x.y)).then_some(Class::Fluid(x));
        }
        let (d, b, q) = best?;
        let (part, normal) = b.tag(x, &q, dx)?;
        let layer = ((d / dx - 1e-9).ceil() as i64).clamp(1, layers as i64) as u8;
        Some(Class::Wall {
            pos: x,
            part,
            normal,
            layer,
        })
    };
    let half_diag = 0.5 * 3f64.sqrt() * (B as f64) * dx;
    let classes: Vec<Vec<Class>> = blocks
        .par_iter()
        .map(|b| {
            let i0 = imin[0] + b[0] * B;
            let j0 = imin[1] + b[1] * B;
            let k0 = imin[2] + b[2] * B;
            let i1 = (i0 + B).min(imax[0] + 1);
            let j1 = (j0 + B).min(imax[1] + 1);
            let k1 = (k0 + B).min(imax[2] + 1);
            let centre = (point(i0, j0, k0) + point(i1 - 1, j1 - 1, k1 - 1)) * 0.5;
            let far = half_diag + reach + dx;
            let qc = tank.query(centre);
            let mut uniform = qc.dist > far;
            let mut in_solid = false;
            for s in &solids {
                if !s.near_box(centre, far) {
                    continue;
                }
                let q = s.query(centre);
                uniform &= q.dist > far;
                in_solid |= q.inside;
            }
            let mut out = Vec::new();
            if uniform {
                if qc.inside && !in_solid {
                    for k in k0..k1 {
                        for j in j0..j1 {
                            for i in i0..i1 {
                                let x = point(i, j, k);
                                if x.z < column_top(x.x, x.y) {
                                    out.push(Class::Fluid(x));
                                }
                            }
                        }
                    }
                }
                return out;
            }
            for k in k0..k1 {
                for j in j0..j1 {
                    for i in i0..i1 {
                        if let Some(c) = classify_point(point(i, j, k)) {
                            out.push(c);
                        }
                    }
                }
            }
            out
        })
        .collect();

    let to_na = |v: PVec3| Vector3::new(v.x, v.y, v.z);
    let mut fluid_positions = Vec::new();
    let mut wall_positions = Vec::new();
    let mut wall_part = Vec::new();
    let mut wall_normal = Vec::new();
    let mut wall_layer = Vec::new();
    for c in classes.into_iter().flatten() {
        match c {
            Class::Fluid(x) => fluid_positions.push(to_na(x)),
            Class::Wall {
                pos,
                part,
                normal,
                layer,
            } => {
                wall_positions.push(to_na(pos));
                wall_part.push(part);
                wall_normal.push(to_na(normal));
                wall_layer.push(layer);
            }
        }
    }
    if fluid_positions.is_empty() && !spec.solids.is_empty() {
        return Err(GeometryError::NoLiquidRegion {
            dx,
            fill: spec.fill_depth,
        });
    }

    // areas
    let n_parts = part_names.len();
    let grid_index = |x: PVec3| -> Option<usize> {
        let c = [cell_of(x.x, dx), cell_of(x.y, dx), cell_of(x.z, dx)];
        for a in 0..3 {
            if c[a] < imin[a] || c[a] > imax[a] {
                return None;
            }
        }
        Some(
            ((c[2] - imin[2]) as usize * dims[1] + (c[1] - imin[1]) as usize) * dims[0]
                + (c[0] - imin[0]) as usize,
        )
    };
    let mut inner_grid = vec![u32::MAX; dims[0] * dims[1] * dims[2]];
    for (w, p) in wall_positions.iter().enumerate() {
        if wall_layer[w] == 1 {
            if let Some(g) = grid_index(PVec3::new(p.x, p.y, p.z)) {
                inner_grid[g] = w as u32;
            }
        }
    }
    let all_bounds: Vec<&Boundary> = std::iter::once(&tank).chain(solids.iter()).collect();
    let wetted = |b_index: usize, s: PVec3| -> bool {
        let b = all_bounds[b_index];
        if b.solid && !tank.mesh.contains_local_point(s) {
            return false;
        }
        for (k, other) in solids.iter().enumerate() {
            if k + 1 == b_index || !other.near_box(s, 0.0) {
                continue;
            }
            if other.mesh.contains_local_point(s) {
                return false;
            }
        }
        true
    };
    let nearest_inner = |s: PVec3, part: u16| -> Option<u32> {
        let c = [cell_of(s.x, dx), cell_of(s.y, dx), cell_of(s.z, dx)];
        for radius in [2i64, 4] {
            let mut best: Option<(f64, u32)> = None;
            for dk in -radius..=radius {
                for dj in -radius..=radius {
                    for di in -radius..=radius {
                        let q = point(c[0] + di, c[1] + dj, c[2] + dk);
                        let Some(g) = grid_index(q) else { continue };
                        let w = inner_grid[g];
                        if w == u32::MAX || wall_part[w as usize] != part {
                            continue;
                        }
                        let d2 = (q - s).length_squared();
                        if best.is_none_or(|(bd, bw)| d2 < bd || (d2 == bd && w < bw)) {
                            best = Some((d2, w));
                        }
                    }
                }
            }
            if let Some((_, w)) = best {
                return Some(w);
            }
        }
        None
    };
    let max_sample_edge = 0.5 * dx;
    let mut tri_jobs: Vec<(usize, u32)> = Vec::new();
    for (bi, b) in all_bounds.iter().enumerate() {
        for t in 0..b.tri_part.len() as u32 {
            if b.tri_part[t as usize] != NO_PART {
                tri_jobs.push((bi, t));
            }
        }
    }
    let has_solids = !solids.is_empty();
    // per triangle: (part, full area, wetted area, assigned samples)
    let results: Vec<TriangleSamples> = tri_jobs
        .par_iter()
        .map(|&(bi, t)| {
            let b = all_bounds[bi];
            let part = b.tri_part[t as usize];
            let tri = b.mesh.triangle(t);
            let n = b.wallward_normal(t);
            let offset = -n * (1e-3 * dx);
            let mut full = 0.0;
            let mut wet = 0.0;
            let mut assigned = Vec::new();
            let mut stack = vec![[tri.a, tri.b, tri.c]];
            while let Some([a, bb, c]) = stack.pop() {
                let e = [(bb - a).length(), (c - bb).length(), (a - c).length()];
                let longest = (0..3).max_by(|&p, &q| e[p].total_cmp(&e[q])).unwrap_or(0);
                if e[longest] > max_sample_edge {
                    let v = [a, bb, c];
                    let (p, q, r) = (v[longest], v[(longest + 1) % 3], v[(longest + 2) % 3]);
                    let m = (p + q) * 0.5;
                    stack.push([p, m, r]);
                    stack.push([m, q, r]);
                    continue;
                }
                let area = 0.5 * (bb - a).cross(c - a).length();
                full += area;
                let s = (a + bb + c) / 3.0;
                if has_solids && !wetted(bi, s + offset) {
                    continue;
                }
                wet += area;
                if let Some(w) = nearest_inner(s, part) {
                    assigned.push((w, area));
                }
            }
            TriangleSamples {
                part,
                full,
                wet,
                assigned,
            }
        })
        .collect();
    let mut wall_area = vec![0.0; wall_positions.len()];
    let mut full_area = vec![0.0; n_parts];
    let mut wet_area = vec![0.0; n_parts];
    let mut assigned_area = vec![0.0; n_parts];
    for TriangleSamples {
        part,
        full,
        wet,
        assigned,
    } in results
    {
        full_area[part as usize] += full;
        wet_area[part as usize] += wet;
        for (w, a) in assigned {
            wall_area[w as usize] += a;
            assigned_area[part as usize] += a;
        }
    }
    let mut target = wet_area.clone();
    for (p, exact) in spec.analytic_part_area.iter().enumerate() {
        if let Some(exact) = exact {
            if full_area[p] > 0.0 {
                target[p] = wet_area[p] * exact / full_area[p];
            }
        }
    }
    scale_areas_to_part_totals(&mut wall_area, &wall_part, &assigned_area, &target);

    let mesh = Arc::new(tank.mesh.clone());
    Ok(ParticleSetup {
        spacing: dx,
        fluid_positions,
        wall_positions,
        wall_part,
        wall_normal,
        wall_area,
        wall_layer,
        part_names,
        interior_min: Vector3::from(spec.interior_min),
        interior_max: Vector3::from(spec.interior_max),
        fill_level,
        interior: Box::new(TankRegion3 {
            shape: spec.region.clone(),
            mesh,
            open_top: spec.open.then_some(spec.shell_height),
            solids: spec.solids.clone(),
        }),
    })
}
