//! Fixed solids inside a 2D section (baffles, columns), per metre of depth out of plane: each
//! is a closed outline whose wall particles lie inside it, in a part of its own name.

use std::f64::consts::PI;

use crate::error::{check_finite, check_positive, GeometryError};
use crate::mesh::circle_segments;
use crate::section2::simple_ccw_polygon;

/// Checks a part name given by the user: non-empty, letters, digits, `_` or `-` only (it
/// becomes part of series column names, `<part>_force_x`).
pub(crate) fn check_part_name(what: &str, name: &str) -> Result<(), GeometryError> {
    if name.is_empty()
        || !name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-')
    {
        return Err(GeometryError::InvalidShape(format!(
            "{what}: part name \"{name}\" must be non-empty and made of letters, digits, '_' \
             or '-' (it names the series columns <part>_force_x, …)"
        )));
    }
    Ok(())
}

/// Shape of a fixed solid inside a 2D section, in section coordinates (m).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub enum Solid2Shape {
    /// A rectangular plate (a baffle): `length` (m) along its axis, `thickness` (m) across it,
    /// centred on `centre` (m), its axis turned `angle_deg` (degrees, counter-clockwise) from
    /// the +x axis (0: a horizontal plate, 90: a vertical one).
    Plate {
        /// Centre of the plate (m).
        centre: [f64; 2],
        /// Length along the plate's axis (m).
        length: f64,
        /// Thickness across the axis (m).
        thickness: f64,
        /// Angle of the axis from +x, counter-clockwise (degrees); `angle` in scripts.
        #[serde(rename = "angle")]
        angle_deg: f64,
    },
    /// A circle of `radius` (m) centred on `centre` (m): the section of a horizontal pipe or
    /// column running through the tank.
    Circle {
        /// Centre (m).
        centre: [f64; 2],
        /// Radius (m).
        radius: f64,
    },
    /// A closed simple polygon of (x, y) vertices (m), any orientation.
    Polygon(Vec<[f64; 2]>),
}

/// A fixed solid inside a 2D section with the part name its wall particles get (solids of the
/// same name share a part; a solid named `bottom`, `wall` or `roof` adds to that tank part).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Solid2 {
    /// Part name, used in the load outputs (e.g. "baffle").
    pub name: String,
    /// Its shape.
    pub shape: Solid2Shape,
}

impl Solid2 {
    /// A plate `length` × `thickness` (m) centred on `centre` (m), axis at `angle_deg` (degrees
    /// from +x, counter-clockwise).
    pub fn plate(
        name: &str,
        centre: [f64; 2],
        length: f64,
        thickness: f64,
        angle_deg: f64,
    ) -> Self {
        Solid2 {
            name: name.to_string(),
            shape: Solid2Shape::Plate {
                centre,
                length,
                thickness,
                angle_deg,
            },
        }
    }

    /// A circle of `radius` (m) centred on `centre` (m).
    pub fn circle(name: &str, centre: [f64; 2], radius: f64) -> Self {
        Solid2 {
            name: name.to_string(),
            shape: Solid2Shape::Circle { centre, radius },
        }
    }

    /// A closed polygon of `vertices` (m), any orientation.
    pub fn polygon(name: &str, vertices: Vec<[f64; 2]>) -> Self {
        Solid2 {
            name: name.to_string(),
            shape: Solid2Shape::Polygon(vertices),
        }
    }

    /// Smallest thickness the solid may have for spacing `dx` (m): 2 dx, so that its inside
    /// holds lattice points at any angle and the liquid cannot pass through it.
    pub fn min_thickness(dx: f64) -> f64 {
        2.0 * dx
    }

    /// Checks the shape alone, before a spacing is known (numbers, a simple polygon).
    pub fn check_shape(&self) -> Result<(), GeometryError> {
        let size = match &self.shape {
            Solid2Shape::Plate {
                length, thickness, ..
            } => length.min(*thickness),
            Solid2Shape::Circle { radius, .. } => 2.0 * radius,
            Solid2Shape::Polygon(_) => 1.0,
        };
        let dx = if size.is_finite() && size > 0.0 {
            size / 8.0
        } else {
            1.0
        };
        self.outline(dx).map(|_| ())
    }

    /// The closed outline for spacing `dx` (m), counter-clockwise (a circle as a polygon with
    /// sides ≤ dx and chord error ≤ dx/1000), and the solid's exact perimeter (m). Checks the
    /// numbers and that the solid is at least [`Solid2::min_thickness`] thick where that is
    /// known in closed form (plate, circle).
    pub fn outline(&self, dx: f64) -> Result<(Vec<[f64; 2]>, f64), GeometryError> {
        let name = &self.name;
        check_part_name("internal solid", name)?;
        let too_thin = |what: &str, size: f64| {
            GeometryError::InvalidShape(format!(
                "solid '{name}': {what} {size} m is thinner than 2 dx = {} m; the solid would let \
                 the liquid through (make it thicker or use a smaller dx)",
                Self::min_thickness(dx)
            ))
        };
        match &self.shape {
            Solid2Shape::Plate {
                centre,
                length,
                thickness,
                angle_deg,
            } => {
                check_finite("plate centre x", centre[0])?;
                check_finite("plate centre y", centre[1])?;
                check_positive("plate length", *length)?;
                check_positive("plate thickness", *thickness)?;
                check_finite("plate angle", *angle_deg)?;
                if *thickness < Self::min_thickness(dx) * (1.0 - 1e-9) {
                    return Err(too_thin("plate thickness", *thickness));
                }
                if *length < Self::min_thickness(dx) * (1.0 - 1e-9) {
                    return Err(too_thin("plate length", *length));
                }
                let (s, c) = angle_deg.to_radians().sin_cos();
                let (a, t) = (0.5 * length, 0.5 * thickness);
                let corner =
                    |u: f64, v: f64| [centre[0] + u * c - v * s, centre[1] + u * s + v * c];
                let vertices = vec![corner(-a, -t), corner(a, -t), corner(a, t), corner(-a, t)];
                Ok((vertices, 2.0 * (length + thickness)))
            }
            Solid2Shape::Circle { centre, radius } => {
                check_finite("circle centre x", centre[0])?;
                check_finite("circle centre y", centre[1])?;
                check_positive("circle radius", *radius)?;
                if 2.0 * radius < Self::min_thickness(dx) * (1.0 - 1e-9) {
                    return Err(too_thin("circle diameter", 2.0 * radius));
                }
                let n = circle_segments(*radius, dx, 1e-3 * dx);
                let vertices = (0..n)
                    .map(|k| {
                        let t = 2.0 * PI * k as f64 / n as f64;
                        [centre[0] + radius * t.cos(), centre[1] + radius * t.sin()]
                    })
                    .collect();
                Ok((vertices, 2.0 * PI * radius))
            }
            Solid2Shape::Polygon(points) => {
                let vertices = simple_ccw_polygon(&format!("solid '{name}'"), points)?;
                let n = vertices.len();
                let perimeter = (0..n)
                    .map(|k| {
                        let (a, b) = (vertices[k], vertices[(k + 1) % n]);
                        (b[0] - a[0]).hypot(b[1] - a[1])
                    })
                    .sum();
                Ok((vertices, perimeter))
            }
        }
    }
}
