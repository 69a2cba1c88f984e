//! The 2D rectangular tank of the paper: a lattice of fluid particles and a ring of fixed wall
//! particles in `layers` layers.

use nalgebra::Vector2;
use parry2d_f64::math::Vector as PVec2;
use parry2d_f64::query::PointQuery;
use parry2d_f64::shape::Cuboid;
use slosh_core::{ParticleSetup, TankInterior, PART_BOTTOM, PART_ROOF, PART_WALL};

use crate::error::{check_finite, check_layers, check_positive, GeometryError, MAX_PARTICLES};

/// Where the particle lattice sits relative to the tank walls.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Layout {
    /// Lattice points at cell centres ((i+½)dx, (j+½)dx) of the interior [0, W] × [0, H]:
    /// the fluid block is exactly W × depth ((W/dx)·(depth/dx) particles).
    #[default]
    Offset,
    /// The paper's count: lattice points from wall to wall at x = 0, dx, …, W and
    /// y = 0, dx, …, depth; the effective interior is [−dx/2, W+dx/2] × [−dx/2, H+dx/2]
    /// and the fill level depth + dx/2 (51 × 26 fluid + 648 wall = 1,974 for the §3.1 tank).
    Paper,
}

impl Layout {
    /// Parses `"offset"` or `"paper"` (case-insensitive), as scripts spell it.
    pub fn from_name(name: &str) -> Option<Layout> {
        match name.trim().to_ascii_lowercase().as_str() {
            "offset" => Some(Layout::Offset),
            "paper" => Some(Layout::Paper),
            _ => None,
        }
    }
}

/// A 2D rectangular tank (per metre of depth out of plane), floor at y = 0, left wall at x = 0.
#[derive(Debug, Clone, PartialEq)]
pub struct RectTank2 {
    /// Inner width W between the side walls (m).
    pub width: f64,
    /// Height of the side walls, floor to roof (m).
    pub tank_height: f64,
    /// Still liquid depth (m).
    pub fill_depth: f64,
    /// True for a closed tank with a fixed roof at `tank_height`; false for an open tank
    /// (side walls up to `tank_height`, no roof layer).
    pub roof: bool,
    /// Lattice placement (default [`Layout::Offset`]).
    pub layout: Layout,
    /// Number of wall particle layers (default 3).
    pub layers: u8,
    /// Initial linear free-surface tilt: elevation of the surface above the still level at the
    /// left wall (m); −tilt at the right wall; 0 = flat (volume preserving).
    pub initial_tilt: f64,
    /// Shape of the tilted surface (plane by default).
    pub initial_shape: crate::InitialSurface,
}

/// The lattice numbers of a [`RectTank2`] at a given spacing (what `build` will produce).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RectLattice2 {
    /// Particle spacing dx (m).
    pub spacing: f64,
    /// Lower-left corner of the (effective) interior (m).
    pub interior_min: [f64; 2],
    /// Upper-right corner of the (effective) interior (m); top of the shell for open tanks.
    pub interior_max: [f64; 2],
    /// Lattice columns across the interior.
    pub columns: usize,
    /// Lattice rows between floor and roof (top of the shell).
    pub rows_tank: usize,
    /// Lattice rows of fluid for a flat surface.
    pub rows_fluid: usize,
    /// Still free-surface height actually represented by the particles (m):
    /// `interior_min.y + rows_fluid·dx` (Offset: the fill depth rounded to whole rows of dx;
    /// Paper: depth + dx/2).
    pub fill_level: f64,
}

impl RectTank2 {
    /// A closed tank with the default layout (Offset), 3 wall layers and no tilt.
    pub fn new(width: f64, tank_height: f64, fill_depth: f64) -> Self {
        RectTank2 {
            width,
            tank_height,
            fill_depth,
            roof: true,
            layout: Layout::Offset,
            layers: 3,
            initial_tilt: 0.0,
            initial_shape: crate::InitialSurface::Plane,
        }
    }

    /// Sets whether the tank has a fixed roof.
    pub fn with_roof(mut self, roof: bool) -> Self {
        self.roof = roof;
        self
    }

    /// Sets the lattice layout.
    pub fn with_layout(mut self, layout: Layout) -> Self {
        self.layout = layout;
        self
    }

    /// Sets the number of wall layers.
    pub fn with_layers(mut self, layers: u8) -> Self {
        self.layers = layers;
        self
    }

    /// Sets the initial free-surface tilt (m, elevation at the left wall).
    pub fn with_initial_tilt(mut self, tilt: f64) -> Self {
        self.initial_tilt = tilt;
        self
    }

    /// Sets the shape of the tilted initial surface.
    pub fn with_initial_shape(mut self, shape: crate::InitialSurface) -> Self {
        self.initial_shape = shape;
        self
    }

    /// Validates the tank for spacing `dx` (m) and returns its lattice numbers.
    ///
    /// Width and tank height must be whole multiples of dx (relative tolerance 1e-6), else the
    /// walls would not sit where the user put them. The fill depth may be anything in
    /// (dx, tank height]: the fluid takes the lattice rows whose points lie below it, and the
    /// level those rows represent is reported as `fill_level`.
    pub fn lattice(&self, dx: f64) -> Result<RectLattice2, GeometryError> {
        check_positive("tank width", self.width)?;
        check_positive("tank height", self.tank_height)?;
        check_positive("fill depth", self.fill_depth)?;
        check_positive("particle spacing dx", dx)?;
        check_finite("initial tilt", self.initial_tilt)?;
        check_layers(self.layers)?;
        if self.fill_depth > self.tank_height * (1.0 + 1e-12) {
            return Err(GeometryError::FillAboveTank {
                fill: self.fill_depth,
                height: self.tank_height,
            });
        }
        if dx > self.width {
            return Err(GeometryError::SpacingTooLarge {
                dx,
                what: "width",
                size: self.width,
            });
        }
        if dx > self.tank_height {
            return Err(GeometryError::SpacingTooLarge {
                dx,
                what: "height",
                size: self.tank_height,
            });
        }
        if dx > self.fill_depth {
            return Err(GeometryError::SpacingAboveFill {
                dx,
                fill: self.fill_depth,
            });
        }
        let n_width = whole_spacings("tank width", self.width, dx)?;
        let n_height = whole_spacings("tank height", self.tank_height, dx)?;
        let ratio_fill = self.fill_depth / dx;
        let (columns, rows_tank, rows_fluid, origin) = match self.layout {
            Layout::Offset => {
                // rows j with (j + 1/2) dx < depth
                let rows = if (ratio_fill - ratio_fill.round()).abs() < 1e-6 {
                    ratio_fill.round() as usize
                } else {
                    (ratio_fill - 0.5).ceil().max(0.0) as usize
                };
                (n_width, n_height, rows, 0.0)
            }
            Layout::Paper => {
                // rows j with j dx <= depth
                let rows = if (ratio_fill - ratio_fill.round()).abs() < 1e-6 {
                    ratio_fill.round() as usize + 1
                } else {
                    ratio_fill.floor() as usize + 1
                };
                (n_width + 1, n_height + 1, rows, -0.5 * dx)
            }
        };
        let rows_fluid = rows_fluid.min(rows_tank);
        let fill_level = origin + rows_fluid as f64 * dx;
        let top = origin + rows_tank as f64 * dx;
        let bottom = origin;
        let tilt = self.initial_tilt;
        if fill_level - tilt.abs() < bottom - 1e-12 {
            return Err(GeometryError::TiltTooLarge {
                tilt,
                reason: format!(
                    "the tilted surface would dip below the floor at one wall (fill level {fill_level} m); use |tilt| <= {fill_level} m"
                ),
            });
        }
        if fill_level + tilt.abs() > top + 1e-12 {
            return Err(GeometryError::TiltTooLarge {
                tilt,
                reason: format!(
                    "the tilted surface would rise above the tank top {top} m at one wall (fill level {fill_level} m); use |tilt| <= {} m",
                    top - fill_level
                ),
            });
        }
        let estimate =
            (columns as u64 + 2 * self.layers as u64) * (rows_tank as u64 + 2 * self.layers as u64);
        if estimate > MAX_PARTICLES {
            return Err(GeometryError::TooManyParticles {
                dx,
                estimate,
                limit: MAX_PARTICLES,
            });
        }
        Ok(RectLattice2 {
            spacing: dx,
            interior_min: [origin, origin],
            interior_max: [origin + columns as f64 * dx, top],
            columns,
            rows_tank,
            rows_fluid,
            fill_level,
        })
    }

    /// The interior as a parry2d shape: a cuboid and the position of its centre (m).
    pub fn interior_shape(&self, dx: f64) -> Result<(Cuboid, [f64; 2]), GeometryError> {
        let lat = self.lattice(dx)?;
        Ok(lattice_cuboid(&lat))
    }

    /// Builds the initial particles for spacing `dx` (m).
    ///
    /// Fluid: lattice points of the interior with y < fill_level + tilt·(1 − 2ξ), ξ the
    /// fractional distance from the left face (tilt·cos πξ for [`crate::InitialSurface::FirstMode`]). Walls: lattice points outside the interior
    /// within `layers` spacings in the max-norm (full corners); open tanks have no roof layer
    /// and side walls only up to the shell top. Each wall particle gets its part (corner
    /// points: the part of the nearest face line; ties go to the wall at the bottom corners
    /// and to the roof at the top corners), the outward normal of that part, its layer
    /// (1 = innermost, max-norm distance in cells), and an area of dx (m per m depth) for
    /// innermost non-corner particles, 0 otherwise, so each part's areas sum to its face length.
    pub fn build(&self, dx: f64) -> Result<ParticleSetup<2>, GeometryError> {
        let lat = self.lattice(dx)?;
        let nx = lat.columns as i64;
        let ny = lat.rows_tank as i64;
        let layers = self.layers as i64;
        let [x0, y0] = lat.interior_min;
        let width_eff = nx as f64 * dx;
        let point =
            |i: i64, j: i64| Vector2::new(x0 + (i as f64 + 0.5) * dx, y0 + (j as f64 + 0.5) * dx);

        let mut fluid = Vec::with_capacity((nx * lat.rows_fluid as i64) as usize);
        for j in 0..ny {
            for i in 0..nx {
                let p = point(i, j);
                let xi = (p.x - x0) / width_eff;
                let shape = match self.initial_shape {
                    crate::InitialSurface::Plane => 1.0 - 2.0 * xi,
                    crate::InitialSurface::FirstMode => (std::f64::consts::PI * xi).cos(),
                };
                let surface = lat.fill_level + self.initial_tilt * shape;
                if p.y < surface {
                    fluid.push(p);
                }
            }
        }

        let mut setup = ParticleSetup {
            spacing: dx,
            fluid_positions: fluid,
            wall_positions: Vec::new(),
            wall_part: Vec::new(),
            wall_normal: Vec::new(),
            wall_area: Vec::new(),
            wall_layer: Vec::new(),
            part_names: vec![PART_BOTTOM.into(), PART_WALL.into(), PART_ROOF.into()],
            interior_min: Vector2::new(lat.interior_min[0], lat.interior_min[1]),
            interior_max: Vector2::new(lat.interior_max[0], lat.interior_max[1]),
            fill_level: lat.fill_level,
            interior: Box::new(RectInterior2::new(&lat, !self.roof)),
        };

        let j_end = if self.roof { ny + layers } else { ny };
        for j in -layers..j_end {
            for i in -layers..nx + layers {
                let out_x = if i < 0 {
                    -i
                } else if i >= nx {
                    i - nx + 1
                } else {
                    0
                };
                let (out_below, out_above) = if j < 0 {
                    (-j, 0)
                } else if j >= ny {
                    (0, j - ny + 1)
                } else {
                    (0, 0)
                };
                let out_y = out_below.max(out_above);
                if out_x == 0 && out_y == 0 {
                    continue;
                }
                let layer = out_x.max(out_y);
                let wall_normal = Vector2::new(if i < 0 { -1.0 } else { 1.0 }, 0.0);
                let (part, normal) = if out_x == 0 {
                    if out_below > 0 {
                        (0u16, Vector2::new(0.0, -1.0))
                    } else {
                        (2u16, Vector2::new(0.0, 1.0))
                    }
                } else if out_y == 0 {
                    (1u16, wall_normal)
                } else if out_below > 0 {
                    // bottom corner: nearest face line, tie -> wall
                    if out_below < out_x {
                        (0u16, Vector2::new(0.0, -1.0))
                    } else {
                        (1u16, wall_normal)
                    }
                } else if out_above <= out_x {
                    // top corner: tie -> roof
                    (2u16, Vector2::new(0.0, 1.0))
                } else {
                    (1u16, wall_normal)
                };
                let face = out_x == 0 || out_y == 0;
                let area = if layer == 1 && face { dx } else { 0.0 };
                setup.wall_positions.push(point(i, j));
                setup.wall_part.push(part);
                setup.wall_normal.push(normal);
                setup.wall_area.push(area);
                setup.wall_layer.push(layer as u8);
            }
        }
        Ok(setup)
    }
}

/// Number of whole spacings in `size`, or an error suggesting a dx that fits.
fn whole_spacings(what: &'static str, size: f64, dx: f64) -> Result<usize, GeometryError> {
    let ratio = size / dx;
    let n = ratio.round();
    if n < 1.0 || (ratio - n).abs() > 1e-6 * ratio.max(1.0) {
        let suggestion = size / n.max(1.0);
        return Err(GeometryError::NotMultipleOfSpacing {
            what,
            size,
            dx,
            ratio,
            suggestion,
        });
    }
    Ok(n as usize)
}

fn lattice_cuboid(lat: &RectLattice2) -> (Cuboid, [f64; 2]) {
    let half = PVec2::new(
        0.5 * (lat.interior_max[0] - lat.interior_min[0]),
        0.5 * (lat.interior_max[1] - lat.interior_min[1]),
    );
    let centre = [
        0.5 * (lat.interior_max[0] + lat.interior_min[0]),
        0.5 * (lat.interior_max[1] + lat.interior_min[1]),
    ];
    (Cuboid::new(half), centre)
}

/// The interior of a [`RectTank2`] as a parry2d cuboid (open tanks: extended upwards).
#[derive(Debug, Clone)]
pub struct RectInterior2 {
    cuboid: Cuboid,
    centre: PVec2,
    /// Top of the shell (m) when the tank is open, else `None`.
    open_top: Option<f64>,
}

impl RectInterior2 {
    fn new(lat: &RectLattice2, open: bool) -> Self {
        let (cuboid, c) = lattice_cuboid(lat);
        RectInterior2 {
            cuboid,
            centre: PVec2::new(c[0], c[1]),
            open_top: open.then_some(lat.interior_max[1]),
        }
    }
}

impl TankInterior<2> for RectInterior2 {
    fn contains(&self, point: &Vector2<f64>) -> bool {
        let mut y = point.y;
        if let Some(top) = self.open_top {
            y = y.min(top);
        }
        self.cuboid
            .contains_local_point(PVec2::new(point.x, y) - self.centre)
    }

    fn distance_outside(&self, point: &Vector2<f64>) -> f64 {
        let mut y = point.y;
        if let Some(top) = self.open_top {
            y = y.min(top);
        }
        let local = PVec2::new(point.x, y) - self.centre;
        let he = self.cuboid.half_extents;
        let dx = (local.x.abs() - he.x).max(0.0);
        let dy = (local.y.abs() - he.y).max(0.0);
        (dx * dx + dy * dy).sqrt()
    }
}
