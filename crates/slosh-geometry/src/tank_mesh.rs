//! A 3D tank of any shape: a closed triangle mesh of the whole interior (OBJ or STL), its
//! parts named by the mesh's groups, turned into particles by the 3D rules of the crate.

use std::f64::consts::FRAC_1_SQRT_2;
use std::path::{Path, PathBuf};

use slosh_core::{ParticleSetup, PART_BOTTOM, PART_ROOF, PART_WALL};

use crate::error::{check_finite, check_layers, check_positive, GeometryError};
use crate::mesh::{cross, norm, sub, SurfaceMesh};
use crate::solid2::check_part_name;
use crate::tank3::{
    build_mesh_tank_with_parts, InternalSolid, MeshTankSpec, RegionShape, TiltShape,
};
use crate::InitialSurface;

/// A tank mesh read from a file and checked: closed, manifold, consistently oriented, no
/// zero-area triangle; normals out of the liquid; moved up so its lowest point is at z = 0.
#[derive(Debug, Clone)]
pub struct TankMesh {
    /// The interior surface (m), lowest point at z = 0, normals out of the liquid.
    pub surface: SurfaceMesh,
    /// Part index of each triangle into `part_names`.
    pub triangle_part: Vec<u16>,
    /// `bottom`, `wall`, `roof`, then the mesh's other group names in order of appearance.
    pub part_names: Vec<String>,
    /// Height the file's coordinates were raised by to put the lowest point at z = 0 (m).
    pub raised_by: f64,
}

impl TankMesh {
    /// Reads and checks the mesh file at `path`. Triangles of a group named `bottom`, `wall`
    /// or `roof` belong to that built-in part, those of any other group to a part of the
    /// group's name; triangles without a group go by the way they face (out of the liquid):
    /// `roof` within 45° of straight up, `bottom` within 45° of straight down, `wall`
    /// otherwise (as the 2D polygon's sides and the sphere). Errors name the file.
    pub fn read(path: &Path) -> Result<TankMesh, GeometryError> {
        let name = path.display().to_string();
        let (surface, groups) = SurfaceMesh::read_grouped(path)?;
        TankMesh::from_grouped(surface, groups, &name)
    }

    /// [`TankMesh::read`] for a mesh already in memory (`source` names it in errors).
    pub fn from_grouped(
        mut surface: SurfaceMesh,
        groups: Vec<Option<String>>,
        source: &str,
    ) -> Result<TankMesh, GeometryError> {
        surface.check_closed(source)?;
        let (lo, hi) = surface.bounds();
        let size = norm(sub(hi, lo));
        for (k, t) in surface.triangles.iter().enumerate() {
            let [a, b, c] = t.map(|i| surface.vertices[i as usize]);
            if norm(cross(sub(b, a), sub(c, a))) <= 1e-12 * size * size {
                return Err(GeometryError::MeshRead {
                    path: source.to_string(),
                    message: format!(
                        "triangle {} ({a:?}, {b:?}, {c:?}) has zero area (its corners are in a \
                         line); remove it or mend the mesh",
                        k + 1
                    ),
                });
            }
        }
        surface.orient_outwards();
        let volume = surface.signed_volume();
        if volume <= 0.0 {
            return Err(GeometryError::MeshRead {
                path: source.to_string(),
                message: format!("the mesh encloses no volume ({volume} m³)"),
            });
        }
        let mut part_names: Vec<String> =
            vec![PART_BOTTOM.into(), PART_WALL.into(), PART_ROOF.into()];
        let mut triangle_part = Vec::with_capacity(surface.triangles.len());
        for (t, group) in surface.triangles.iter().zip(&groups) {
            let part = match group {
                Some(g) => {
                    check_part_name(&format!("mesh {source}: group \"{g}\""), g).map_err(|e| {
                        GeometryError::MeshRead {
                            path: source.to_string(),
                            message: e.to_string(),
                        }
                    })?;
                    match part_names.iter().position(|n| n == g) {
                        Some(i) => i,
                        None => {
                            part_names.push(g.clone());
                            part_names.len() - 1
                        }
                    }
                }
                None => {
                    let [a, b, c] = t.map(|i| surface.vertices[i as usize]);
                    let n = cross(sub(b, a), sub(c, a));
                    let nz = n[2] / norm(n);
                    if nz > FRAC_1_SQRT_2 {
                        2
                    } else if nz < -FRAC_1_SQRT_2 {
                        0
                    } else {
                        1
                    }
                }
            };
            triangle_part.push(part as u16);
        }
        let raised_by = -lo[2];
        surface.translate([0.0, 0.0, raised_by]);
        Ok(TankMesh {
            surface,
            triangle_part,
            part_names,
            raised_by,
        })
    }

    /// Surface area of each part of `part_names` (m²).
    pub fn part_areas(&self) -> Vec<f64> {
        let mut areas = vec![0.0; self.part_names.len()];
        for (k, &p) in self.triangle_part.iter().enumerate() {
            areas[p as usize] += self.surface.triangle_area(k);
        }
        areas
    }

    /// Lowest and highest corner of the mesh's bounding box (m, lowest point at z = 0).
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        self.surface.bounds()
    }
}

/// A tank given by a closed triangle mesh of its whole interior (OBJ or STL, metres, z up):
/// the liquid fills it to `fill_depth` above the mesh's lowest point.
///
/// The mesh is checked and its parts are named as [`TankMesh::read`] says; the particles
/// follow the 3D rules of the crate, each part's areas summing to its mesh area. The mesh is
/// raised so that its lowest point is at z = 0 (the floor of the particle lattice); internal
/// solids are given in those raised coordinates.
#[derive(Debug, Clone, PartialEq)]
pub struct MeshTank {
    /// The mesh file (used as given; callers resolve it).
    pub path: PathBuf,
    /// Still liquid depth above the mesh's lowest point (m).
    pub fill_depth: f64,
    /// Number of wall particle layers (default 3).
    pub layers: u8,
    /// Initial free-surface tilt along x: elevation above the still level at the mesh's
    /// smallest x (m), −tilt at its largest x.
    pub initial_tilt: f64,
    /// Shape of the tilted surface: a plane, or the first mode as the rectangle's cos(π ξ)
    /// across the mesh's x extent (ξ the fractional x position).
    pub initial_shape: InitialSurface,
    /// For a mesh of an upright cylinder of this radius (m) on the z axis: its first mode
    /// −(x/r) J₁(ξ₁ r/R)/J₁(ξ₁) as the tilted surface instead of the cosine.
    pub cylinder_mode_radius: Option<f64>,
    /// Internal solids (columns, rings, blocks).
    pub solids: Vec<InternalSolid>,
}

impl MeshTank {
    /// A tank from the mesh file `path` filled to `fill_depth` (m), 3 wall layers, no tilt,
    /// no internal solids.
    pub fn new(path: impl Into<PathBuf>, fill_depth: f64) -> Self {
        MeshTank {
            path: path.into(),
            fill_depth,
            layers: 3,
            initial_tilt: 0.0,
            initial_shape: InitialSurface::Plane,
            cylinder_mode_radius: None,
            solids: Vec::new(),
        }
    }

    /// Sets the initial free-surface tilt (m, elevation at the smallest x).
    pub fn with_initial_tilt(mut self, tilt: f64) -> Self {
        self.initial_tilt = tilt;
        self
    }

    /// Sets the shape of the tilted initial surface.
    pub fn with_initial_shape(mut self, shape: InitialSurface) -> Self {
        self.initial_shape = shape;
        self
    }

    /// Starts from the first mode of an upright cylinder of `radius` (m) on the z axis.
    pub fn with_cylinder_mode(mut self, radius: f64) -> Self {
        self.initial_shape = InitialSurface::FirstMode;
        self.cylinder_mode_radius = Some(radius);
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

    /// Builds the initial particles for spacing `dx` (m). Part names: `bottom`, `wall`,
    /// `roof`, the mesh's other groups, then the internal solids (a solid named as a group
    /// shares its part).
    pub fn build(&self, dx: f64) -> Result<ParticleSetup<3>, GeometryError> {
        check_positive("fill depth", self.fill_depth)?;
        check_positive("particle spacing dx", dx)?;
        check_finite("initial tilt", self.initial_tilt)?;
        check_layers(self.layers)?;
        let mesh = TankMesh::read(&self.path)?;
        self.build_from(mesh, dx)
    }

    /// [`MeshTank::build`] with the mesh already read (`self.path` is not read).
    pub fn build_from(&self, mesh: TankMesh, dx: f64) -> Result<ParticleSetup<3>, GeometryError> {
        let (lo, hi) = mesh.bounds();
        for (k, what) in ["x extent", "y extent", "height"].into_iter().enumerate() {
            if dx > hi[k] - lo[k] {
                return Err(GeometryError::SpacingTooLarge {
                    dx,
                    what,
                    size: hi[k] - lo[k],
                });
            }
        }
        for s in &self.solids {
            s.validate(dx)?;
        }
        let span = [lo[0], hi[0]];
        let tilt_shape = match (self.initial_shape, self.cylinder_mode_radius) {
            (InitialSurface::Plane, _) => TiltShape::Plane { span },
            (InitialSurface::FirstMode, Some(radius)) => TiltShape::CylinderMode { radius },
            (InitialSurface::FirstMode, None) => TiltShape::Cosine { span },
        };
        let extra_parts = mesh.part_names[3..].to_vec();
        let spec = MeshTankSpec {
            surface: mesh.surface,
            shell_height: hi[2],
            open: false,
            fill_depth: self.fill_depth,
            initial_tilt: self.initial_tilt,
            tilt_shape,
            layers: self.layers,
            solids: self.solids.clone(),
            analytic_part_area: [None, None, None],
            extra_parts,
            interior_min: lo,
            interior_max: hi,
            region: RegionShape::Mesh,
        };
        build_mesh_tank_with_parts(&spec, Some(mesh.triangle_part), dx)
    }
}
