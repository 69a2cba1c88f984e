//! Tanks as parry shapes, turned into the solver's initial particles
//! ([`slosh_core::ParticleSetup`]).
//!
//! * [`RectTank2`]: the paper's 2D rectangular tank (two lattice layouts, [`Layout`]).
//! * [`CylinderTank`]: an upright cylinder (axis x = y = 0, floor z = 0) with a [`Roof`]
//!   (none, flat, cone, dome, or a closed mesh file of the whole interior), optional
//!   [`InternalSolid`]s (columns, baffle rings, blocks; each at least 2 dx thick).
//! * [`SectionTank2`]: any other 2D section: a rectangle with a cone, dome or polyline roof
//!   ([`SectionRoof`]), a simple polygon, or a circle (horizontal cylindrical tank), built by
//!   the 2D form of the 3D rules below with the outline as a parry2d `Polyline`; fixed
//!   [`Solid2`]s inside it (plate baffles, circular columns, polygons) with wall particles in
//!   layers inside each solid, in a part of the solid's name.
//! * [`BoxTank`]: a 3D rectangular box, to compare 2D and 3D runs.
//! * [`SphereTank`]: a spherical tank, parts by the way its surface faces.
//! * [`MeshTank`]: any 3D tank as a closed OBJ/STL mesh of its whole interior, parts named by
//!   the mesh's groups (or by the way untagged triangles face), internal solids as in the
//!   cylinder ([`TankMesh`] reads and checks the file).
//! * [`SurfaceMesh`]: OBJ/STL reading, OBJ writing, closedness checks, procedural meshes
//!   ([`cylinder_roof_mesh_obj`] writes the example files of `geometry/`).
//!
//! All lengths are in metres; the vertical axis is the last coordinate, up positive.
//! Wall particles carry their part (`bottom` = 0, `wall` = 1, `roof` = 2, then user parts),
//! layer (1 = next to the liquid), normal (from the liquid into the wall) and the boundary
//! area they stand for (innermost layer only; each part's areas sum to its surface area).
//!
//! # 3D rules (cylinder and box)
//! The tank is a closed triangle mesh (a parry3d `TriMesh` with the `ORIENTED` flag; the
//! built-in shapes are meshed with facets ≤ dx and chord error ≤ dx/1000; open tanks get a
//! virtual lid above the shell that makes no particles). Lattice points are at
//! ((i+½)dx, (j+½)dx, (k+½)dx).
//! * fluid: lattice points inside the tank and outside every internal solid, below the
//!   (tilted) fill surface z < fill_level + tilt·(1 − 2ξ), ξ the fractional x position across
//!   the tank (or the first-mode surface, [`InitialSurface`]), each lattice column holding a
//!   whole number of rows chosen by error diffusion along x; `fill_level` is the top of the lattice rows below the fill depth (rows·dx);
//! * walls: lattice points outside the tank, or inside an internal solid, within
//!   `layers`·dx (+1e-6 dx) Euclidean distance of that surface; open tanks only below the shell
//!   top; a point that qualifies for several surfaces takes the nearest;
//! * layer = ceil(distance/dx) clamped to 1..=layers;
//! * part: that of the nearest surface triangle (floor triangles `bottom`, triangles at or
//!   above the shell top `roof`, others `wall`, solids their own name); where parts meet the
//!   part whose face plane is nearest, ties to roof over wall over bottom (as the 2D corners);
//! * normal (liquid → wall): the face normal of that triangle, or the direction from the
//!   nearest surface point to the particle where edges/vertices of a single part are nearest;
//! * area: the wetted surface of each part is sampled at ≤ dx/2 spacing, each sample's area
//!   goes to the nearest innermost-layer particle of the same part, and each part's areas are
//!   scaled to sum exactly to its area (analytic for the built-in shapes, the wetted mesh area
//!   otherwise). All other particles get 0.
//!
//! A cylinder can instead stand on the polar lattice ([`CylinderLattice::Polar`]): the liquid
//! on rings about the axis and the shell's wall layers on rings at R + (k − ½)dx, so the liquid
//! meets a smooth shell rather than the cubic lattice's staircase; floor and roof walls stay on
//! the cubic lattice (the corners below the floor and above the shell top keep theirs).

#![warn(missing_docs)]

mod error;
mod lattice;
mod mesh;
mod rect2;
mod section2;
mod solid2;
mod tank3;
mod tank_mesh;

/// Shape of the initial free surface of a free-decay test (`initial_tilt` ≠ 0). Both keep the
/// liquid volume of the flat surface.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum InitialSurface {
    /// A plane through the still level, `initial_tilt` above it at one wall and below it at
    /// the opposite wall. It excites the higher modes too: in a cylinder a plane is 84 % first
    /// mode at the wall (2/(ξ₁² − 1)), 7 % second, 3 % third; in a rectangle 81 % (8/π²).
    #[default]
    Plane,
    /// The first sloshing mode alone, `initial_tilt` at the same wall point: in a cylinder
    /// −(x/r)·J₁(ξ₁ r/R)/J₁(ξ₁), ξ₁ = 1.841184 (first zero of J₁′); in a rectangle or box
    /// cos(π ξ), ξ the fractional x position across the tank. The clean start of a
    /// free-sloshing period measurement.
    FirstMode,
}

impl InitialSurface {
    /// Parses a script's `tilt_shape`: `"plane"` or `"mode1"`.
    pub fn from_name(name: &str) -> Option<InitialSurface> {
        match name.trim().to_ascii_lowercase().as_str() {
            "plane" => Some(InitialSurface::Plane),
            "mode1" => Some(InitialSurface::FirstMode),
            _ => None,
        }
    }
}

pub use error::{GeometryError, MAX_PARTICLES};
pub use mesh::{box_mesh, circle_segments, revolve_profile, SurfaceMesh};
pub use rect2::{Layout, RectInterior2, RectLattice2, RectTank2};
pub use section2::{
    bounding_box_2d, PartRange, RectPiece, SectionOutline, SectionRegion2, SectionRoof,
    SectionShape, SectionTank2,
};
pub use solid2::{Solid2, Solid2Shape};
pub use tank3::{
    BoxTank, CylinderLattice, CylinderTank, InternalSolid, Roof, SolidShape, SphereTank,
    TankRegion3,
};
pub use tank_mesh::{MeshTank, TankMesh};

/// Writes the closed interior surface of a cylinder of `radius` and `shell_height` (m) with
/// `roof` (not `Roof::Mesh`/`Roof::None`) to an OBJ file at `path`, using facets no wider than
/// `max_edge` (m); returns the mesh written. Used to make the example meshes in `geometry/`.
pub fn cylinder_roof_mesh_obj(
    path: &std::path::Path,
    radius: f64,
    shell_height: f64,
    roof: Roof,
    max_edge: f64,
) -> Result<SurfaceMesh, GeometryError> {
    if matches!(roof, Roof::Mesh(_) | Roof::None) {
        return Err(GeometryError::InvalidShape(
            "cylinder_roof_mesh_obj needs a flat, cone or dome roof".into(),
        ));
    }
    let tank = CylinderTank::new(radius, shell_height, shell_height, roof.clone());
    let mesh = tank.interior_surface(max_edge, shell_height)?;
    let comment = format!(
        "slosh tank interior: upright cylinder R = {radius} m, shell height {shell_height} m, roof {roof:?}\n\
         units m; axis x = y = 0; floor z = 0; normals point out of the liquid (CCW seen from outside)"
    );
    mesh.write_obj(path, &comment)
        .map_err(|e| GeometryError::MeshRead {
            path: path.display().to_string(),
            message: format!("cannot write: {e}"),
        })?;
    Ok(mesh)
}
