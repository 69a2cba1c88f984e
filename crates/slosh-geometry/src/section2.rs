//! 2D tank sections of any closed outline (per metre of depth out of plane): a rectangle with a
//! cone, dome or polyline roof, any simple polygon, or a circle (the section of a horizontal
//! cylindrical tank). The outline is a closed parry2d `Polyline`, turned into particles by the
//! 2D form of the 3D rules of the crate documentation.

use std::f64::consts::{FRAC_1_SQRT_2, PI};

use nalgebra::Vector2;
use parry2d_f64::math::{Pose, Vector as PVec2};
use parry2d_f64::query::details::distance_segment_segment;
use parry2d_f64::shape::{Polyline, Segment, SegmentPointLocation};
use slosh_core::{ParticleSetup, TankInterior, PART_BOTTOM, PART_ROOF, PART_WALL};

use crate::error::{check_finite, check_layers, check_positive, GeometryError, MAX_PARTICLES};
use crate::lattice::{cell_of, lattice_rows_below, part_priority, scale_areas_to_part_totals};
use crate::mesh::circle_segments;
use crate::solid2::{check_part_name, Solid2};
use crate::tank3::{dome_arc_length, dome_profile, TiltShape};

/// The roof of a rectangular 2D section other than flat or none (those are [`crate::RectTank2`]).
#[derive(Debug, Clone, PartialEq)]
pub enum SectionRoof {
    /// Two straight pieces from the wall tops to an apex `apex_height` (m) above them at
    /// mid-width (the section through the axis of a cone-roof tank).
    Cone {
        /// Height of the apex above the wall tops (m).
        apex_height: f64,
    },
    /// A circular arc through both wall tops rising `rise` (m) above them at mid-width
    /// (rise ≤ half the width; the section through the axis of a dome-roof tank).
    Dome {
        /// Height of the crown above the wall tops (m).
        rise: f64,
    },
    /// Any polyline of (x, y) points (m) from one wall top to the other (either order).
    Outline(Vec<[f64; 2]>),
}

/// The outline of a [`SectionTank2`].
#[derive(Debug, Clone, PartialEq)]
pub enum SectionShape {
    /// Floor y = 0 from x = 0 to `width`, vertical walls up to `wall_height`, and `roof`.
    /// Parts: floor `bottom`, side walls `wall`, roof `roof`.
    RoofedRect {
        /// Inner width between the side walls (m).
        width: f64,
        /// Height of the side walls, floor to wall top (m).
        wall_height: f64,
        /// The roof from wall top to wall top.
        roof: SectionRoof,
    },
    /// A closed polygon of (x, y) vertices (m), any orientation, the last joined to the first;
    /// it must be simple (no two sides crossing or touching). Parts by the direction a side
    /// faces out of the liquid: `roof` within 45° of straight up, `bottom` within 45° of
    /// straight down, `wall` otherwise.
    Polygon(Vec<[f64; 2]>),
    /// A circle of `radius` (m) with its centre at (radius, radius), so that the floor touches
    /// y = 0; parts by facing as for polygons: the upper quarter `roof`, the lower quarter
    /// `bottom`, the two side quarters `wall` (lengths πR/2, πR/2, πR).
    Circle {
        /// Inner radius (m).
        radius: f64,
    },
}

/// A 2D tank section of any closed outline, per metre of depth out of plane.
///
/// The still liquid level is `fill_depth` above the lowest point of the outline; the particles
/// hold the lattice rows (cell centres (j+½)dx) below it, and `fill_level` is the top of those
/// rows.
#[derive(Debug, Clone, PartialEq)]
pub struct SectionTank2 {
    /// The outline.
    pub shape: SectionShape,
    /// Still liquid depth above the lowest point of the outline (m).
    pub fill_depth: f64,
    /// Number of wall particle layers (default 3).
    pub layers: u8,
    /// Initial free-surface tilt: elevation above the still level at the leftmost x of the
    /// outline (m), −tilt at the rightmost; 0 = flat.
    pub initial_tilt: f64,
    /// Shape of the tilted surface (plane by default; the first mode is the rectangle's
    /// cos(πξ) over the outline's width).
    pub initial_shape: crate::InitialSurface,
    /// Fixed solids inside the section (baffles, columns), each in a part of its name.
    pub solids: Vec<Solid2>,
    /// Parts named by the user, each a name and the piece of the outline it covers
    /// ([`PartRange`]). The names `bottom`, `wall` and `roof` put those pieces in that
    /// built-in part; pieces not named keep their built-in part.
    pub named_parts: Vec<(String, PartRange)>,
}

/// The piece of a [`SectionTank2`] outline a part named by the user covers.
#[derive(Debug, Clone, PartialEq)]
pub enum PartRange {
    /// On a [`SectionShape::Polygon`]: the first and last side (side k joins vertex k to
    /// vertex k+1 in the order given, the last side back to vertex 0; first > last wraps
    /// around past the last side).
    Sides([usize; 2]),
    /// On a [`SectionShape::Circle`]: the arc from the first to the last angle (degrees from
    /// +x, counter-clockwise about the centre; first > last wraps past 0°, and an arc of
    /// 360° is the whole circle).
    Arc([f64; 2]),
    /// On a [`SectionShape::RoofedRect`]: whole pieces of the rectangle.
    Pieces(Vec<RectPiece>),
}

/// A piece of a [`SectionShape::RoofedRect`] outline.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RectPiece {
    /// The floor, y = 0.
    Floor,
    /// The side wall at x = 0.
    LeftWall,
    /// The side wall at x = width.
    RightWall,
    /// The whole roof, wall top to wall top.
    Roof,
    /// The roof left of mid-width (x < width/2: one slope of a cone roof).
    RoofLeft,
    /// The roof right of mid-width (x > width/2).
    RoofRight,
}

impl RectPiece {
    /// The piece of a script name: `floor`, `left_wall`, `right_wall`, `roof`, `roof_left`,
    /// `roof_right`.
    pub fn from_name(name: &str) -> Option<RectPiece> {
        Some(match name {
            "floor" => RectPiece::Floor,
            "left_wall" => RectPiece::LeftWall,
            "right_wall" => RectPiece::RightWall,
            "roof" => RectPiece::Roof,
            "roof_left" => RectPiece::RoofLeft,
            "roof_right" => RectPiece::RoofRight,
            _ => return None,
        })
    }

    /// The script names of the pieces, for messages.
    pub const NAMES: &'static str =
        "\"floor\", \"left_wall\", \"right_wall\", \"roof\", \"roof_left\", \"roof_right\"";

    /// Built-in part of side `k` of a roofed rectangle's outline of `n` sides (as
    /// [`RectPiece::covers`] numbers them): 0 (bottom) for the floor, 1 (wall) for the side
    /// walls, 2 (roof) for the roof between.
    fn builtin_part(k: usize, n: usize) -> u16 {
        match k {
            0 => 0,
            1 => 1,
            k if k == n - 1 => 1,
            _ => 2,
        }
    }

    /// Whether the piece covers side `k` of a roofed rectangle's outline of `n` sides (side 0
    /// the floor, 1 the right wall, n−1 the left wall, the roof between) whose midpoint lies
    /// at `mid_x` (m) in a section `width` wide.
    fn covers(self, k: usize, n: usize, mid_x: f64, width: f64) -> bool {
        let roof = k >= 2 && k + 1 < n;
        match self {
            RectPiece::Floor => k == 0,
            RectPiece::RightWall => k == 1,
            RectPiece::LeftWall => k + 1 == n,
            RectPiece::Roof => roof,
            RectPiece::RoofLeft => roof && mid_x < 0.5 * width,
            RectPiece::RoofRight => roof && mid_x > 0.5 * width,
        }
    }
}

/// A closed outline ready for particles: counter-clockwise vertices (m), the part of each side
/// (side k joins vertex k to vertex k+1, the last side back to vertex 0), the part names, and
/// the exact length of each built-in part (bottom, wall, roof) where the sides only
/// approximate a curve.
#[derive(Debug, Clone, PartialEq)]
pub struct SectionOutline {
    /// Counter-clockwise vertices (m).
    pub vertices: Vec<[f64; 2]>,
    /// Part index of each side (0 bottom, 1 wall, 2 roof, then the parts named by the user).
    pub side_part: Vec<u16>,
    /// Name of each part: `bottom`, `wall`, `roof`, then the parts named by the user.
    pub part_names: Vec<String>,
    /// Exact length of each part (m) where known in closed form (curves); otherwise the
    /// sides' lengths are exact.
    pub exact_length: Vec<Option<f64>>,
}

impl SectionOutline {
    /// Total length of the sides of each part (m), indexed as [`SectionOutline::part_names`].
    pub fn side_lengths(&self) -> Vec<f64> {
        let mut total = vec![0.0; self.part_names.len()];
        let n = self.vertices.len();
        for k in 0..n {
            let (a, b) = (self.vertices[k], self.vertices[(k + 1) % n]);
            total[self.side_part[k] as usize] += (b[0] - a[0]).hypot(b[1] - a[1]);
        }
        total
    }

    /// Length each part's particle areas add up to (m): the exact length where known, else
    /// the sides' length.
    pub fn part_lengths(&self) -> Vec<f64> {
        let sides = self.side_lengths();
        (0..sides.len())
            .map(|p| {
                self.exact_length
                    .get(p)
                    .copied()
                    .flatten()
                    .unwrap_or(sides[p])
            })
            .collect()
    }

    /// Lowest and highest corner of the bounding box (m).
    pub fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        bounding_box_2d(&self.vertices)
    }

    /// Unit normal of side `k`, pointing out of the liquid.
    fn outward_normal(&self, k: usize) -> PVec2 {
        let n = self.vertices.len();
        let (a, b) = (self.vertices[k], self.vertices[(k + 1) % n]);
        PVec2::new(b[1] - a[1], a[0] - b[0]).normalize_or_zero()
    }

    /// The outline as a closed parry2d polyline.
    fn polyline(&self) -> Polyline {
        let n = self.vertices.len() as u32;
        let vertices = self
            .vertices
            .iter()
            .map(|v| PVec2::new(v[0], v[1]))
            .collect();
        let indices = (0..n).map(|k| [k, (k + 1) % n]).collect();
        Polyline::new(vertices, Some(indices))
    }
}

/// Lowest and highest corner of the bounding box of `points` (m); infinite when empty.
pub fn bounding_box_2d(points: &[[f64; 2]]) -> ([f64; 2], [f64; 2]) {
    let mut lo = [f64::INFINITY; 2];
    let mut hi = [f64::NEG_INFINITY; 2];
    for v in points {
        for a in 0..2 {
            lo[a] = lo[a].min(v[a]);
            hi[a] = hi[a].max(v[a]);
        }
    }
    (lo, hi)
}

/// Part of a side from the direction `normal` it faces out of the liquid: roof within 45° of
/// straight up, bottom within 45° of straight down, wall otherwise.
fn part_by_facing(normal: PVec2) -> u16 {
    if normal.y > FRAC_1_SQRT_2 {
        2
    } else if normal.y < -FRAC_1_SQRT_2 {
        0
    } else {
        1
    }
}

/// Checks that the closed polygon `vertices` (m) is simple — at least 3 vertices, finite, no
/// side of zero length, no two sides crossing, touching or folding back on each other — and
/// encloses a non-zero area; returns it counter-clockwise. Errors name the offending sides
/// (side k joins vertex k to vertex k+1, counted from 0 in the order given).
pub(crate) fn simple_ccw_polygon(
    what: &str,
    vertices: &[[f64; 2]],
) -> Result<Vec<[f64; 2]>, GeometryError> {
    let n = vertices.len();
    let bad = |m: String| GeometryError::InvalidShape(format!("{what}: {m}"));
    if n < 3 {
        return Err(bad(format!(
            "a closed outline needs at least 3 points (got {n})"
        )));
    }
    if let Some((k, v)) = vertices
        .iter()
        .enumerate()
        .find(|(_, v)| !(v[0].is_finite() && v[1].is_finite()))
    {
        return Err(bad(format!("point {k} {v:?} is not finite")));
    }
    let scale = vertices
        .iter()
        .map(|v| v[0].abs().max(v[1].abs()))
        .fold(0.0, f64::max)
        .max(1e-300);
    let tol = 1e-9 * scale;
    let p = |k: usize| PVec2::new(vertices[k % n][0], vertices[k % n][1]);
    let side = |k: usize| Segment::new(p(k), p(k + 1));
    let show = |k: usize| format!("side {k} ({:?} → {:?})", vertices[k], vertices[(k + 1) % n]);
    for k in 0..n {
        if (p(k + 1) - p(k)).length() <= tol {
            return Err(bad(format!("{} has zero length (repeated point)", show(k))));
        }
    }
    for i in 0..n {
        // neighbouring sides share a vertex; they must not fold back onto each other
        let j = (i + 1) % n;
        let (d0, d1) = (p(i + 1) - p(i), p(j + 1) - p(j));
        let cross = d0.x * d1.y - d0.y * d1.x;
        if cross.abs() <= 1e-12 * d0.length() * d1.length() && d0.dot(d1) < 0.0 {
            return Err(bad(format!(
                "{} and {} fold back onto each other",
                show(i),
                show(j)
            )));
        }
        for j in i + 2..n {
            if i == 0 && j == n - 1 {
                continue;
            }
            if distance_segment_segment(&Pose::IDENTITY, &side(i), &side(j)) <= tol {
                return Err(bad(format!(
                    "{} crosses or touches {}: the outline must be simple (not self-intersecting)",
                    show(i),
                    show(j)
                )));
            }
        }
    }
    let twice_area: f64 = (0..n)
        .map(|k| {
            let (a, b) = (p(k), p(k + 1));
            a.x * b.y - b.x * a.y
        })
        .sum();
    if twice_area.abs() <= tol * scale {
        return Err(bad("the outline encloses no area".into()));
    }
    let mut ccw = vertices.to_vec();
    if twice_area < 0.0 {
        ccw.reverse();
    }
    Ok(ccw)
}

impl SectionTank2 {
    /// A tank of the given outline and fill depth (m), 3 wall layers, no tilt.
    pub fn new(shape: SectionShape, fill_depth: f64) -> Self {
        SectionTank2 {
            shape,
            fill_depth,
            layers: 3,
            initial_tilt: 0.0,
            initial_shape: crate::InitialSurface::Plane,
            solids: Vec::new(),
            named_parts: Vec::new(),
        }
    }

    /// Adds a fixed solid inside the section.
    pub fn with_solid(mut self, solid: Solid2) -> Self {
        self.solids.push(solid);
        self
    }

    /// Names the sides `first..=last` of a polygon outline as part `name` (see
    /// [`SectionTank2::named_parts`]).
    pub fn with_named_sides(mut self, name: &str, first: usize, last: usize) -> Self {
        self.named_parts
            .push((name.to_string(), PartRange::Sides([first, last])));
        self
    }

    /// Names the arc of a circle outline from `first` to `last` degrees (counter-clockwise
    /// from +x) as part `name` (see [`PartRange::Arc`]).
    pub fn with_named_arc(mut self, name: &str, first: f64, last: f64) -> Self {
        self.named_parts
            .push((name.to_string(), PartRange::Arc([first, last])));
        self
    }

    /// Names pieces of a roofed rectangle as part `name` (see [`RectPiece`]).
    pub fn with_named_pieces(mut self, name: &str, pieces: &[RectPiece]) -> Self {
        self.named_parts
            .push((name.to_string(), PartRange::Pieces(pieces.to_vec())));
        self
    }

    /// Sets the number of wall layers.
    pub fn with_layers(mut self, layers: u8) -> Self {
        self.layers = layers;
        self
    }

    /// Sets the initial free-surface tilt (m, elevation at the leftmost x).
    pub fn with_initial_tilt(mut self, tilt: f64) -> Self {
        self.initial_tilt = tilt;
        self
    }

    /// Sets the shape of the tilted initial surface.
    pub fn with_initial_shape(mut self, shape: crate::InitialSurface) -> Self {
        self.initial_shape = shape;
        self
    }

    /// Checks the shape alone (numbers, a simple outline, a roof from wall top to wall top),
    /// before a spacing is known: the validity of a shape does not depend on dx.
    pub fn check_shape(&self) -> Result<(), GeometryError> {
        let size = match &self.shape {
            SectionShape::RoofedRect { width, .. } => *width,
            SectionShape::Circle { radius } => *radius,
            SectionShape::Polygon(_) => 1.0,
        };
        let dx = if size.is_finite() && size > 0.0 {
            size / 8.0
        } else {
            1.0
        };
        self.outline(dx)?;
        for s in &self.solids {
            s.check_shape()?;
        }
        Ok(())
    }

    /// The closed outline for spacing `dx` (m): curves (dome roof, circle) are polygons with
    /// sides no longer than dx and a chord error below dx/1000. Checks the shape.
    pub fn outline(&self, dx: f64) -> Result<SectionOutline, GeometryError> {
        check_positive("particle spacing dx", dx)?;
        let sag = 1e-3 * dx;
        for (name, range) in &self.named_parts {
            check_part_name("tank parts", name)?;
            let fits = matches!(
                (&self.shape, range),
                (SectionShape::Polygon(_), PartRange::Sides(_))
                    | (SectionShape::Circle { .. }, PartRange::Arc(_))
                    | (SectionShape::RoofedRect { .. }, PartRange::Pieces(_))
            );
            if !fits {
                return Err(GeometryError::InvalidShape(format!(
                    "tank parts: part '{name}': a polygon names [first side, last side], a \
                     circle [first angle, last angle] in degrees, a rectangle its pieces ({})",
                    RectPiece::NAMES
                )));
            }
        }
        let builtin = || vec![PART_BOTTOM.to_string(), PART_WALL.into(), PART_ROOF.into()];
        match &self.shape {
            SectionShape::RoofedRect {
                width,
                wall_height,
                roof,
            } => {
                let (w, h) = (*width, *wall_height);
                check_positive("tank width", w)?;
                check_positive("tank wall height", h)?;
                // the dome's radius, for the exact length of each of its chords
                let mut dome_radius = None;
                let (roof_points, roof_length): (Vec<[f64; 2]>, Option<f64>) = match roof {
                    SectionRoof::Cone { apex_height } => {
                        check_positive("cone roof rise", *apex_height)?;
                        (
                            vec![[0.5 * w, h + apex_height]],
                            Some(2.0 * (0.5 * w).hypot(*apex_height)),
                        )
                    }
                    SectionRoof::Dome { rise } => {
                        check_positive("dome roof rise", *rise)?;
                        if *rise > 0.5 * w * (1.0 + 1e-12) {
                            return Err(GeometryError::InvalidShape(format!(
                                "dome roof rise {rise} m is larger than half the tank width {} m \
                                 (a circular arc over the walls rises at most half the width)",
                                0.5 * w
                            )));
                        }
                        dome_radius = Some((0.25 * w * w + rise * rise) / (2.0 * rise));
                        let half = dome_profile(0.5 * w, h, *rise, sag);
                        let right = half.iter().map(|&[r, y]| [0.5 * w + r, y]);
                        let left = half.iter().rev().skip(1).map(|&[r, y]| [0.5 * w - r, y]);
                        (
                            right.chain(left).collect(),
                            Some(2.0 * dome_arc_length(0.5 * w, *rise)),
                        )
                    }
                    SectionRoof::Outline(points) => (roof_between_wall_tops(points, w, h)?, None),
                };
                let mut vertices = vec![[0.0, 0.0], [w, 0.0], [w, h]];
                vertices.extend(roof_points);
                vertices.push([0.0, h]);
                let given = simple_ccw_polygon("tank roof", &vertices)?;
                if given != vertices {
                    return Err(GeometryError::InvalidShape(
                        "tank roof: the roof must run above the floor between the wall tops".into(),
                    ));
                }
                if self.named_parts.is_empty() {
                    let n = vertices.len();
                    let side_part = (0..n).map(|k| RectPiece::builtin_part(k, n)).collect();
                    return Ok(SectionOutline {
                        vertices,
                        side_part,
                        part_names: builtin(),
                        exact_length: vec![Some(w), Some(2.0 * h), roof_length],
                    });
                }
                // parts named by piece: a vertex where the roof crosses mid-width splits it
                // into its left and right halves
                let mut split = vec![vertices[0], vertices[1], vertices[2]];
                for k in 2..vertices.len() - 1 {
                    let (a, b) = (vertices[k], vertices[k + 1]);
                    let (da, db) = (a[0] - 0.5 * w, b[0] - 0.5 * w);
                    if da * db < 0.0 {
                        let t = da / (da - db);
                        split.push([0.5 * w, a[1] + t * (b[1] - a[1])]);
                    }
                    split.push(b);
                }
                let vertices = split;
                let n = vertices.len();
                // exact length of each side: a dome chord of length c stands for the arc
                // 2a·asin(c/2a) of the dome's circle (radius a)
                let side_exact: Vec<f64> = (0..n)
                    .map(|k| {
                        let (a, b) = (vertices[k], vertices[(k + 1) % n]);
                        let c = (b[0] - a[0]).hypot(b[1] - a[1]);
                        match dome_radius {
                            Some(r) if k >= 2 && k + 1 < n => {
                                2.0 * r * (0.5 * c / r).min(1.0).asin()
                            }
                            _ => c,
                        }
                    })
                    .collect();
                let mid_x: Vec<f64> = (0..n)
                    .map(|k| 0.5 * (vertices[k][0] + vertices[(k + 1) % n][0]))
                    .collect();
                let outline = SectionOutline {
                    side_part: (0..n).map(|k| RectPiece::builtin_part(k, n)).collect(),
                    vertices,
                    part_names: builtin(),
                    exact_length: Vec::new(),
                };
                let covers = |p: usize, k: usize| match &self.named_parts[p].1 {
                    PartRange::Pieces(pieces) => {
                        pieces.iter().any(|piece| piece.covers(k, n, mid_x[k], w))
                    }
                    _ => false,
                };
                let describe = |k: usize| match k {
                    0 => "the floor".to_string(),
                    1 => "the right wall".into(),
                    k if k == n - 1 => "the left wall".into(),
                    _ => "the roof".into(),
                };
                self.name_parts_with_lengths(outline, covers, describe, &side_exact)
            }
            SectionShape::Polygon(points) => {
                let vertices = simple_ccw_polygon("tank outline", points)?;
                let n = vertices.len();
                // side k as given is side n−2−k (mod n) of the reversed (counter-clockwise) list
                let reversed = vertices[0] != points[0];
                let ccw_side = |k: usize| if reversed { (2 * n - 2 - k) % n } else { k };
                let mut outline = SectionOutline {
                    side_part: vec![1; n],
                    vertices,
                    part_names: builtin(),
                    exact_length: vec![None; 3],
                };
                outline.side_part = (0..n)
                    .map(|k| part_by_facing(outline.outward_normal(k)))
                    .collect();
                let mut claims = Vec::with_capacity(self.named_parts.len());
                for (name, range) in &self.named_parts {
                    let PartRange::Sides([first, last]) = *range else {
                        unreachable!("checked above: a polygon's parts are side ranges")
                    };
                    if first >= n || last >= n {
                        return Err(GeometryError::InvalidShape(format!(
                            "tank parts: part '{name}' names sides {first} to {last}, but the \
                             outline has sides 0 to {} (side k joins point k to point k+1, the \
                             last back to point 0)",
                            n - 1
                        )));
                    }
                    let count = if last >= first {
                        last - first + 1
                    } else {
                        n - first + last + 1
                    };
                    let mut claim = vec![false; n];
                    for m in 0..count {
                        claim[ccw_side((first + m) % n)] = true;
                    }
                    claims.push(claim);
                }
                let given_side = |k: usize| format!("side {}", ccw_side(k));
                self.assign_named_parts(&mut outline, &claims, given_side)?;
                outline.exact_length = vec![None; outline.part_names.len()];
                Ok(outline)
            }
            SectionShape::Circle { radius } => {
                let r = *radius;
                check_positive("tank radius", r)?;
                // a multiple of 8 sides puts vertices on the quarter boundaries (45°, 135°, …)
                let n = circle_segments(r, dx, sag).div_ceil(8) * 8;
                let mut angles: Vec<f64> = (0..n).map(|k| 2.0 * PI * k as f64 / n as f64).collect();
                // the ends of the named arcs are vertices too
                let mut arcs = Vec::with_capacity(self.named_parts.len());
                for (name, range) in &self.named_parts {
                    let PartRange::Arc([first, last]) = *range else {
                        unreachable!("checked above: a circle's parts are arcs")
                    };
                    if !(first.is_finite() && last.is_finite()) {
                        return Err(GeometryError::InvalidShape(format!(
                            "tank parts: part '{name}': the angles [{first}, {last}] must be \
                             finite numbers of degrees"
                        )));
                    }
                    let start = first.to_radians().rem_euclid(2.0 * PI);
                    let mut span = (last - first).to_radians().rem_euclid(2.0 * PI);
                    if span < 1e-12 {
                        if (last - first).abs() < 1e-9 {
                            return Err(GeometryError::InvalidShape(format!(
                                "tank parts: part '{name}': the arc from {first}° to {last}° \
                                 has no length (give two different angles, counter-clockwise \
                                 from +x)"
                            )));
                        }
                        span = 2.0 * PI;
                    }
                    arcs.push((start, span));
                    angles.push(start);
                    angles.push((start + span).rem_euclid(2.0 * PI));
                }
                angles.sort_by(f64::total_cmp);
                angles.dedup_by(|b, a| (*b - *a).abs() < 1e-9);
                if angles.len() > 1 && 2.0 * PI - angles[angles.len() - 1] < 1e-9 {
                    angles.pop();
                }
                let n = angles.len();
                let vertices = angles
                    .iter()
                    .map(|t| [r + r * t.cos(), r + r * t.sin()])
                    .collect();
                let arc_of = |k: usize| {
                    let end = if k + 1 < n {
                        angles[k + 1]
                    } else {
                        2.0 * PI + angles[0]
                    };
                    (angles[k], end)
                };
                let mut outline = SectionOutline {
                    vertices,
                    side_part: vec![1; n],
                    part_names: builtin(),
                    exact_length: Vec::new(),
                };
                outline.side_part = (0..n)
                    .map(|k| part_by_facing(outline.outward_normal(k)))
                    .collect();
                if arcs.is_empty() {
                    outline.exact_length =
                        vec![Some(0.5 * PI * r), Some(PI * r), Some(0.5 * PI * r)];
                    return Ok(outline);
                }
                let covers = |p: usize, k: usize| {
                    let (start, span) = arcs[p];
                    let (a, b) = arc_of(k);
                    (0.5 * (a + b) - start).rem_euclid(2.0 * PI) < span
                };
                let at_angle = |k: usize| {
                    let (a, b) = arc_of(k);
                    format!("the arc {:.3}° to {:.3}°", a.to_degrees(), b.to_degrees())
                };
                // each side stands for its arc, r·Δθ
                let side_exact: Vec<f64> = (0..n)
                    .map(|k| {
                        let (a, b) = arc_of(k);
                        r * (b - a)
                    })
                    .collect();
                self.name_parts_with_lengths(outline, covers, at_angle, &side_exact)
            }
        }
    }

    /// Puts the sides of `outline` each part named by the user covers in that part
    /// ([`SectionTank2::assign_named_parts`]; `covers(p, k)`: named part p covers side k,
    /// `describe(k)` names side k in errors), then sets each part's exact length to the sum of
    /// `side_exact` (m, the exact length each side stands for) over its sides.
    fn name_parts_with_lengths(
        &self,
        mut outline: SectionOutline,
        covers: impl Fn(usize, usize) -> bool,
        describe: impl Fn(usize) -> String,
        side_exact: &[f64],
    ) -> Result<SectionOutline, GeometryError> {
        let n = outline.vertices.len();
        let claims: Vec<Vec<bool>> = (0..self.named_parts.len())
            .map(|p| (0..n).map(|k| covers(p, k)).collect())
            .collect();
        self.assign_named_parts(&mut outline, &claims, describe)?;
        let mut total = vec![0.0; outline.part_names.len()];
        for (k, &p) in outline.side_part.iter().enumerate() {
            total[p as usize] += side_exact[k];
        }
        outline.exact_length = total.into_iter().map(Some).collect();
        Ok(outline)
    }

    /// Puts the sides each part named by the user claims (`claims[p][k]`: part p covers side
    /// k of `outline`) in that part, adding its name; errors for a side claimed twice, named
    /// by `describe(k)`, or a part that covers no side.
    fn assign_named_parts(
        &self,
        outline: &mut SectionOutline,
        claims: &[Vec<bool>],
        describe: impl Fn(usize) -> String,
    ) -> Result<(), GeometryError> {
        let n = outline.vertices.len();
        let mut named_by: Vec<Option<&str>> = vec![None; n];
        for ((name, _), claim) in self.named_parts.iter().zip(claims) {
            let part = match outline.part_names.iter().position(|p| p == name) {
                Some(p) => p,
                None => {
                    outline.part_names.push(name.clone());
                    outline.part_names.len() - 1
                }
            } as u16;
            if !claim.iter().any(|&c| c) {
                return Err(GeometryError::InvalidShape(format!(
                    "tank parts: part '{name}' covers no part of the outline"
                )));
            }
            for k in (0..n).filter(|&k| claim[k]) {
                if let Some(other) = named_by[k] {
                    return Err(GeometryError::InvalidShape(format!(
                        "tank parts: part '{name}' names {}, already named by part '{other}'",
                        describe(k)
                    )));
                }
                named_by[k] = Some(name);
                outline.side_part[k] = part;
            }
        }
        Ok(())
    }

    /// Builds the initial particles for spacing `dx` (m) on the lattice ((i+½)dx, (j+½)dx):
    ///
    /// * fluid: lattice points inside the outline and outside every solid, below the (tilted)
    ///   still level;
    /// * walls: lattice points outside the outline, or inside a solid, within `layers`·dx
    ///   (+10⁻⁶ dx) of that outline (a solid's only where its nearest surface point lies inside
    ///   the tank); a point that qualifies for both takes the nearer; layer = ⌈distance/dx⌉;
    ///   part and normal (out of the liquid) of the nearest side; at a vertex where two parts
    ///   meet, the part of the nearer side line, ties to roof over wall over bottom; at a
    ///   vertex of one part, the normal points from the vertex to the particle;
    /// * area (m per m of depth): each part's sides are sampled at ≤ dx/2, each sample's length
    ///   goes to the nearest innermost-layer particle of that part (a solid's: of those whose
    ///   normal is within 45° of the side's), and the areas of each part are scaled to add up
    ///   to its exact length ([`SectionOutline::part_lengths`]; a solid's: its exact
    ///   perimeter). With solids, only wetted samples count — the liquid side of the sample
    ///   inside the tank and outside every other solid — and each part's total is its exact
    ///   length times the wetted fraction of its samples.
    pub fn build(&self, dx: f64) -> Result<ParticleSetup<2>, GeometryError> {
        check_positive("fill depth", self.fill_depth)?;
        check_finite("initial tilt", self.initial_tilt)?;
        check_layers(self.layers)?;
        let outline = self.outline(dx)?;
        let (lo, hi) = outline.bounds();
        let height = hi[1] - lo[1];
        if self.fill_depth > height * (1.0 + 1e-12) {
            return Err(GeometryError::FillAboveTank {
                fill: self.fill_depth,
                height,
            });
        }
        let min_size = (hi[0] - lo[0]).min(height);
        if dx > min_size {
            return Err(GeometryError::SpacingTooLarge {
                dx,
                what: "smaller side of the bounding box",
                size: min_size,
            });
        }
        // rows counted from the lattice level at or below the lowest point (outlines may
        // reach below y = 0)
        let base = (lo[1] / dx).floor().min(0.0) * dx;
        let fill_level = base + lattice_rows_below(lo[1] + self.fill_depth - base, dx) * dx;
        let tilt = self.initial_tilt;
        if fill_level - tilt.abs() < lo[1] {
            return Err(GeometryError::TiltTooLarge {
                tilt,
                reason: format!(
                    "the tilted surface would dip below the lowest point of the tank (still level {fill_level} m)"
                ),
            });
        }
        if fill_level + tilt.abs() > hi[1] {
            return Err(GeometryError::TiltTooLarge {
                tilt,
                reason: format!(
                    "the tilted surface would rise above the tank top {} m (still level {fill_level} m)",
                    hi[1]
                ),
            });
        }
        let span = [lo[0], hi[0]];
        let tilt_shape = match self.initial_shape {
            crate::InitialSurface::Plane => TiltShape::Plane { span },
            crate::InitialSurface::FirstMode => TiltShape::Cosine { span },
        };

        let layers = self.layers as f64;
        let reach = layers * dx + 1e-6 * dx;
        let pad = reach + dx;
        let imin = [cell_of(lo[0] - pad, dx), cell_of(lo[1] - pad, dx)];
        let imax = [cell_of(hi[0] + pad, dx), cell_of(hi[1] + pad, dx)];
        let dims = [
            (imax[0] - imin[0] + 1) as usize,
            (imax[1] - imin[1] + 1) as usize,
        ];
        let estimate = dims[0] as u64 * dims[1] as u64;
        if estimate > 2 * MAX_PARTICLES {
            return Err(GeometryError::TooManyParticles {
                dx,
                estimate,
                limit: MAX_PARTICLES,
            });
        }
        let polyline = outline.polyline();
        let n_sides = outline.vertices.len();
        let normals: Vec<PVec2> = (0..n_sides).map(|k| outline.outward_normal(k)).collect();
        let point = |i: i64, j: i64| PVec2::new((i as f64 + 0.5) * dx, (j as f64 + 0.5) * dx);
        let to_na = |v: PVec2| Vector2::new(v.x, v.y);
        let tank_contains = |x: PVec2| {
            polyline
                .project_local_point_assuming_solid_interior_ccw(x)
                .0
                .is_inside
        };

        // the internal solids, each in the part of its name
        let mut part_names = outline.part_names.clone();
        let mut solids: Vec<SolidBoundary> = Vec::with_capacity(self.solids.len());
        for s in &self.solids {
            let (vertices, perimeter) = s.outline(dx)?;
            let part = match part_names.iter().position(|n| *n == s.name) {
                Some(p) => p,
                None => {
                    part_names.push(s.name.clone());
                    part_names.len() - 1
                }
            } as u16;
            solids.push(SolidBoundary::new(&s.name, vertices, part, perimeter));
        }

        let mut setup = ParticleSetup {
            spacing: dx,
            fluid_positions: Vec::new(),
            wall_positions: Vec::new(),
            wall_part: Vec::new(),
            wall_normal: Vec::new(),
            wall_area: Vec::new(),
            wall_layer: Vec::new(),
            part_names: part_names.clone(),
            interior_min: Vector2::new(lo[0], lo[1]),
            interior_max: Vector2::new(hi[0], hi[1]),
            fill_level,
            interior: Box::new(SectionRegion2 {
                polyline: polyline.clone(),
                solids: solids.iter().map(|s| s.polyline.clone()).collect(),
            }),
        };
        // innermost-layer wall particle at each lattice cell, for the area assignment
        let mut inner_grid = vec![u32::MAX; dims[0] * dims[1]];
        for j in imin[1]..=imax[1] {
            for i in imin[0]..=imax[0] {
                let x = point(i, j);
                let (proj, (side, location)) =
                    polyline.project_local_point_assuming_solid_interior_ccw(x);
                // inside a solid; the nearest solid surface inside the tank within reach
                let mut in_solid = false;
                let mut near_solid: Option<(f64, usize, u32, SegmentPointLocation, PVec2)> = None;
                for (si, b) in solids.iter().enumerate() {
                    if !b.near(x, reach) {
                        continue;
                    }
                    let (sp, (s_side, s_loc)) = b
                        .polyline
                        .project_local_point_assuming_solid_interior_ccw(x);
                    if !sp.is_inside {
                        continue;
                    }
                    in_solid = true;
                    let d = (x - sp.point).length();
                    if d <= reach && near_solid.is_none_or(|n| d < n.0) && tank_contains(sp.point) {
                        near_solid = Some((d, si, s_side, s_loc, sp.point));
                    }
                }
                if proj.is_inside && !in_solid {
                    if x.y < fill_level + tilt * tilt_shape.at(x.x, 0.0) {
                        setup.fluid_positions.push(to_na(x));
                    }
                    continue;
                }
                let tank_dist = if proj.is_inside {
                    f64::INFINITY
                } else {
                    (x - proj.point).length()
                };
                let (dist, part, normal) = match near_solid {
                    Some((d, si, s_side, s_loc, on)) if d < tank_dist || tank_dist > reach => {
                        let b = &solids[si];
                        let normal = match s_loc {
                            SegmentPointLocation::OnVertex(_) if d > 1e-6 * dx => (x - on) / d,
                            _ => b.normals[s_side as usize],
                        };
                        (d, b.part, normal)
                    }
                    _ => {
                        let dist = tank_dist;
                        if dist > reach {
                            continue;
                        }
                        let side = side as usize;
                        let (part, normal) = match location {
                            SegmentPointLocation::OnEdge(_) => {
                                (outline.side_part[side], normals[side])
                            }
                            SegmentPointLocation::OnVertex(end) => {
                                let vertex = (side + end as usize) % n_sides;
                                let sides = [(vertex + n_sides - 1) % n_sides, vertex];
                                let parts = sides.map(|s| outline.side_part[s]);
                                if parts[0] == parts[1] {
                                    let n = if dist > 1e-6 * dx {
                                        (x - proj.point) / dist
                                    } else {
                                        normals[side]
                                    };
                                    (parts[0], n)
                                } else {
                                    // the part of the nearer side line; ties to the higher priority
                                    let v = outline.vertices[vertex];
                                    let line = sides.map(|s| {
                                        ((x - PVec2::new(v[0], v[1])).dot(normals[s])).abs()
                                    });
                                    let tol = 1e-7 * dx;
                                    let first = line[0] < line[1] - tol
                                        || (line[0] <= line[1] + tol
                                            && part_priority(parts[0]) > part_priority(parts[1]));
                                    let s = if first { sides[0] } else { sides[1] };
                                    (outline.side_part[s], normals[s])
                                }
                            }
                        };
                        (dist, part, normal)
                    }
                };
                let layer = ((dist / dx - 1e-9).ceil() as i64).clamp(1, self.layers as i64) as u8;
                if layer == 1 {
                    let g = (j - imin[1]) as usize * dims[0] + (i - imin[0]) as usize;
                    inner_grid[g] = setup.wall_positions.len() as u32;
                }
                setup.wall_positions.push(to_na(x));
                setup.wall_part.push(part);
                setup.wall_normal.push(to_na(normal));
                setup.wall_layer.push(layer);
            }
        }
        if setup.fluid_positions.is_empty() {
            return Err(if dx > self.fill_depth || self.solids.is_empty() {
                GeometryError::SpacingAboveFill {
                    dx,
                    fill: self.fill_depth,
                }
            } else {
                GeometryError::NoLiquidRegion {
                    dx,
                    fill: self.fill_depth,
                }
            });
        }

        // areas: sample each side at ≤ dx/2, give each sample's length to the nearest
        // innermost particle of the side's part
        let wall_part = &setup.wall_part;
        let wall_normal = &setup.wall_normal;
        // `facing`: only particles whose normal is within 45° of it (a solid's corners: each
        // face's length goes to the particles that carry that face's normal)
        let nearest_inner = |s: PVec2, part: u16, facing: Option<PVec2>| -> Option<u32> {
            let c = [cell_of(s.x, dx), cell_of(s.y, dx)];
            for radius in [2i64, 4] {
                let mut best: Option<(f64, u32)> = None;
                for dj in -radius..=radius {
                    for di in -radius..=radius {
                        let (i, j) = (c[0] + di, c[1] + dj);
                        if i < imin[0] || i > imax[0] || j < imin[1] || j > imax[1] {
                            continue;
                        }
                        let w =
                            inner_grid[(j - imin[1]) as usize * dims[0] + (i - imin[0]) as usize];
                        if w == u32::MAX || wall_part[w as usize] != part {
                            continue;
                        }
                        if let Some(f) = facing {
                            let n = wall_normal[w as usize];
                            if n.x * f.x + n.y * f.y < FRAC_1_SQRT_2 {
                                continue;
                            }
                        }
                        let d2 = (point(i, j) - s).length_squared();
                        if best.is_none_or(|(bd, bw)| d2 < bd || (d2 == bd && w < bw)) {
                            best = Some((d2, w));
                        }
                    }
                }
                if let Some((_, w)) = best {
                    return Some(w);
                }
            }
            None
        };
        let in_other_solid = |s: PVec2, own: Option<usize>| {
            solids
                .iter()
                .enumerate()
                .any(|(k, b)| Some(k) != own && b.contains(s))
        };
        let n_parts = part_names.len();
        let mut wall_area = vec![0.0; setup.wall_positions.len()];
        let mut assigned = vec![0.0; n_parts];
        // the tank's sides: a sample covered by a solid (just inside the liquid) is not wetted
        let mut tank_full = vec![0.0; n_parts];
        let mut tank_wet = vec![0.0; n_parts];
        for (k, &normal) in normals.iter().enumerate() {
            let part = outline.side_part[k];
            let (a, b) = (outline.vertices[k], outline.vertices[(k + 1) % n_sides]);
            let (a, b) = (PVec2::new(a[0], a[1]), PVec2::new(b[0], b[1]));
            let length = (b - a).length();
            let pieces = (length / (0.5 * dx)).ceil().max(1.0) as usize;
            let piece = length / pieces as f64;
            for m in 0..pieces {
                let s = a + (b - a) * ((m as f64 + 0.5) / pieces as f64);
                tank_full[part as usize] += piece;
                if !solids.is_empty() && in_other_solid(s - normal * (1e-3 * dx), None) {
                    continue;
                }
                tank_wet[part as usize] += piece;
                if let Some(w) = nearest_inner(s, part, None) {
                    wall_area[w as usize] += piece;
                    assigned[part as usize] += piece;
                }
            }
        }
        let mut target = outline.part_lengths();
        target.resize(n_parts, 0.0);
        if !solids.is_empty() {
            for ((t, full), wet) in target.iter_mut().zip(&tank_full).zip(&tank_wet) {
                if *full > 0.0 {
                    *t *= wet / full;
                }
            }
        }
        // the solids' sides: wetted where just outside the solid lies inside the tank and
        // outside the other solids; the part's total is the exact perimeter's wetted share
        for (si, b) in solids.iter().enumerate() {
            let nv = b.vertices.len();
            let (mut full, mut wet, mut missed) = (0.0, 0.0, 0.0);
            for k in 0..nv {
                let (p, q) = (b.vertices[k], b.vertices[(k + 1) % nv]);
                let length = (q - p).length();
                let pieces = (length / (0.5 * dx)).ceil().max(1.0) as usize;
                let piece = length / pieces as f64;
                for m in 0..pieces {
                    let s = p + (q - p) * ((m as f64 + 0.5) / pieces as f64);
                    full += piece;
                    let liquid_side = s - b.normals[k] * (1e-3 * dx);
                    if !tank_contains(liquid_side) || in_other_solid(liquid_side, Some(si)) {
                        continue;
                    }
                    wet += piece;
                    let facing = nearest_inner(s, b.part, Some(b.normals[k]));
                    match facing.or_else(|| nearest_inner(s, b.part, None)) {
                        Some(w) => {
                            wall_area[w as usize] += piece;
                            assigned[b.part as usize] += piece;
                        }
                        None => missed += piece,
                    }
                }
            }
            if missed > 0.0 {
                return Err(GeometryError::InvalidShape(format!(
                    "solid '{}': {missed:.3} m of its wetted outline has no wall particle within \
                     4 dx inside it; the solid is thinner than 2 dx = {} m there (make it \
                     thicker or use a smaller dx)",
                    b.name,
                    2.0 * dx
                )));
            }
            if full > 0.0 {
                target[b.part as usize] += b.perimeter * wet / full;
            }
        }
        scale_areas_to_part_totals(&mut wall_area, &setup.wall_part, &assigned, &target);
        setup.wall_area = wall_area;
        Ok(setup)
    }
}

/// The interior points of a roof polyline `points` (m) given from one wall top to the other of
/// a section `width` wide with walls `wall_height` high, ordered from the right wall top
/// (width, wall_height) to the left one (0, wall_height).
fn roof_between_wall_tops(
    points: &[[f64; 2]],
    width: f64,
    wall_height: f64,
) -> Result<Vec<[f64; 2]>, GeometryError> {
    let (left, right) = ([0.0, wall_height], [width, wall_height]);
    let tol = 1e-9 * width.max(wall_height);
    let near = |p: &[f64; 2], q: [f64; 2]| (p[0] - q[0]).hypot(p[1] - q[1]) <= tol;
    let (Some(first), Some(last)) = (points.first(), points.last()) else {
        return Err(GeometryError::InvalidShape(
            "tank roof: the roof polyline has no points".into(),
        ));
    };
    let mut inner: Vec<[f64; 2]> = if near(first, right) && near(last, left) {
        points[1..points.len() - 1].to_vec()
    } else if near(first, left) && near(last, right) {
        points[1..points.len() - 1].iter().rev().copied().collect()
    } else {
        return Err(GeometryError::InvalidShape(format!(
            "tank roof: the roof polyline must run from one wall top to the other, \
             [0, {wall_height}] and [{width}, {wall_height}] (it runs from {first:?} to {last:?})"
        )));
    };
    inner.retain(|p| !(near(p, left) || near(p, right)));
    Ok(inner)
}

/// The interior of a [`SectionTank2`]: the region inside its closed outline and outside its
/// internal solids.
#[derive(Clone)]
pub struct SectionRegion2 {
    polyline: Polyline,
    solids: Vec<Polyline>,
}

/// Whether `point` lies inside the closed counter-clockwise `polyline`, and its distance to it.
fn inside_and_distance(polyline: &Polyline, point: &Vector2<f64>) -> (bool, f64) {
    let x = PVec2::new(point.x, point.y);
    let (proj, _) = polyline.project_local_point_assuming_solid_interior_ccw(x);
    (proj.is_inside, (x - proj.point).length())
}

/// Whether `point` lies inside the bounding box of `polyline`.
fn in_box(polyline: &Polyline, point: &Vector2<f64>) -> bool {
    let aabb = polyline.local_aabb();
    point.x >= aabb.mins.x
        && point.y >= aabb.mins.y
        && point.x <= aabb.maxs.x
        && point.y <= aabb.maxs.y
}

impl SectionRegion2 {
    /// Distance (m) from `point` to the surface of the internal solid it lies in, if any.
    fn depth_in_solid(&self, point: &Vector2<f64>) -> Option<f64> {
        self.solids
            .iter()
            .filter(|s| in_box(s, point))
            .map(|s| inside_and_distance(s, point))
            .find(|(inside, _)| *inside)
            .map(|(_, d)| d)
    }
}

impl TankInterior<2> for SectionRegion2 {
    fn contains(&self, point: &Vector2<f64>) -> bool {
        in_box(&self.polyline, point)
            && inside_and_distance(&self.polyline, point).0
            && self.depth_in_solid(point).is_none()
    }

    /// Distance to the tank outline outside it; inside a solid, the distance to the solid's
    /// surface.
    fn distance_outside(&self, point: &Vector2<f64>) -> f64 {
        match inside_and_distance(&self.polyline, point) {
            (true, _) => self.depth_in_solid(point).unwrap_or(0.0),
            (false, d) => d,
        }
    }
}

/// An internal solid ready for particles: its counter-clockwise outline, the normal of each
/// side pointing into the solid (out of the liquid), part and exact perimeter.
struct SolidBoundary {
    name: String,
    vertices: Vec<PVec2>,
    normals: Vec<PVec2>,
    polyline: Polyline,
    part: u16,
    perimeter: f64,
    lo: PVec2,
    hi: PVec2,
}

impl SolidBoundary {
    fn new(name: &str, vertices: Vec<[f64; 2]>, part: u16, perimeter: f64) -> Self {
        let (lo, hi) = bounding_box_2d(&vertices);
        let n = vertices.len();
        let v: Vec<PVec2> = vertices.iter().map(|p| PVec2::new(p[0], p[1])).collect();
        let normals = (0..n)
            .map(|k| {
                let (a, b) = (v[k], v[(k + 1) % n]);
                PVec2::new(a.y - b.y, b.x - a.x).normalize_or_zero()
            })
            .collect();
        let indices = (0..n as u32).map(|k| [k, (k + 1) % n as u32]).collect();
        SolidBoundary {
            name: name.to_string(),
            polyline: Polyline::new(v.clone(), Some(indices)),
            vertices: v,
            normals,
            part,
            perimeter,
            lo: PVec2::new(lo[0], lo[1]),
            hi: PVec2::new(hi[0], hi[1]),
        }
    }

    /// Whether `x` is within `margin` (m) of the solid's bounding box.
    fn near(&self, x: PVec2, margin: f64) -> bool {
        x.x >= self.lo.x - margin
            && x.y >= self.lo.y - margin
            && x.x <= self.hi.x + margin
            && x.y <= self.hi.y + margin
    }

    /// Whether `x` lies inside the solid.
    fn contains(&self, x: PVec2) -> bool {
        self.near(x, 0.0)
            && self
                .polyline
                .project_local_point_assuming_solid_interior_ccw(x)
                .0
                .is_inside
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Sum of the areas of each part (m per m of depth).
    fn part_sums(setup: &ParticleSetup<2>) -> [f64; 3] {
        let mut s = [0.0; 3];
        for (a, &p) in setup.wall_area.iter().zip(&setup.wall_part) {
            s[p as usize] += a;
        }
        s
    }

    /// Sum of the wall areas of part `name` (m per m of depth).
    pub(super) fn part_sum(setup: &ParticleSetup<2>, name: &str) -> f64 {
        let p = setup
            .part_names
            .iter()
            .position(|n| n == name)
            .expect("the part exists") as u16;
        setup
            .wall_area
            .iter()
            .zip(&setup.wall_part)
            .filter(|(_, &q)| q == p)
            .map(|(a, _)| a)
            .sum()
    }

    /// Relative difference |a − b| / b.
    pub(super) fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b
    }

    #[test]
    fn cone_roof_section_lengths_and_normals() {
        // 2 m wide, walls 1 m, apex 0.5 m above the wall tops: roof 2·√(1² + 0.5²)
        let tank = SectionTank2::new(
            SectionShape::RoofedRect {
                width: 2.0,
                wall_height: 1.0,
                roof: SectionRoof::Cone { apex_height: 0.5 },
            },
            0.6,
        );
        let setup = tank.build(0.05).unwrap();
        let exact = [2.0, 2.0, 2.0 * 1.25f64.sqrt()];
        let sums = part_sums(&setup);
        for p in 0..3 {
            assert!(
                rel(sums[p], exact[p]) < 1e-12,
                "part {p}: {} vs {}",
                sums[p],
                exact[p]
            );
        }
        // every roof particle faces up and out along the cone: n = (±0.5, 1)/√1.25
        let n_cone = (0.5f64 / 1.25f64.sqrt(), 1.0 / 1.25f64.sqrt());
        for (k, &p) in setup.wall_part.iter().enumerate() {
            let n = setup.wall_normal[k];
            assert!((n.norm() - 1.0).abs() < 1e-12);
            if p == 2 && setup.wall_layer[k] == 1 && (setup.wall_positions[k].x - 1.0).abs() > 0.1 {
                assert!((n.x.abs() - n_cone.0).abs() < 1e-9 && (n.y - n_cone.1).abs() < 1e-9);
            }
        }
        // fluid: 0.6 m deep = 12 rows of 40 columns
        assert_eq!(setup.fluid_positions.len(), 12 * 40);
        assert!((setup.fill_level - 0.6).abs() < 1e-12);
        // no wall particle inside, each within 3 dx of the outline
        for x in &setup.wall_positions {
            let d = setup.interior.distance_outside(x);
            assert!(d > 0.0 && d <= 3.0 * 0.05 + 1e-9);
        }
    }

    #[test]
    fn dome_roof_length_within_one_percent_of_the_arc() {
        // half-width 1 m, rise 0.4 m: a = (1 + 0.16)/0.8 = 1.45 m, roof 2·a·asin(1/a)
        let tank = SectionTank2::new(
            SectionShape::RoofedRect {
                width: 2.0,
                wall_height: 1.0,
                roof: SectionRoof::Dome { rise: 0.4 },
            },
            0.5,
        );
        let outline = tank.outline(0.05).unwrap();
        let a = 1.45f64;
        let arc = 2.0 * a * (1.0 / a).asin();
        // the polygon's chords are within the sag bound of the arc
        assert!(rel(outline.side_lengths()[2], arc) < 1e-4);
        let setup = tank.build(0.05).unwrap();
        let sums = part_sums(&setup);
        assert!(rel(sums[2], arc) < 0.01, "{} vs {arc}", sums[2]);
        assert!(rel(sums[0], 2.0) < 0.01 && rel(sums[1], 2.0) < 0.01);
    }

    #[test]
    fn circle_parts_and_fluid_area() {
        let r = 1.0;
        let dx = 0.025;
        let tank = SectionTank2::new(SectionShape::Circle { radius: r }, r);
        let setup = tank.build(dx).unwrap();
        let sums = part_sums(&setup);
        let exact = [0.5 * PI * r, PI * r, 0.5 * PI * r];
        for p in 0..3 {
            assert!(
                rel(sums[p], exact[p]) < 0.01,
                "part {p}: {} vs {}",
                sums[p],
                exact[p]
            );
        }
        // half full: the fluid particles stand for πR²/2 within 1 %
        let area = setup.fluid_positions.len() as f64 * dx * dx;
        assert!(rel(area, 0.5 * PI * r * r) < 0.01, "{area}");
        // the wall normals point away from the centre
        for (x, n) in setup.wall_positions.iter().zip(&setup.wall_normal) {
            let out = (x - Vector2::new(r, r)).normalize();
            assert!(out.dot(n) > 0.99);
        }
    }

    #[test]
    fn polygon_with_sloped_floor_any_orientation() {
        // clockwise trapezoid: floor sloping 0.2 m over 2 m, vertical walls, flat roof at 1.2 m
        let cw = vec![[0.0, 0.2], [0.0, 1.2], [2.0, 1.2], [2.0, 0.0]];
        let tank = SectionTank2::new(SectionShape::Polygon(cw.clone()), 0.6);
        let outline = tank.outline(0.05).unwrap();
        let floor = 2.0f64.hypot(0.2);
        let exact = [floor, 1.0 + 1.2, 2.0];
        let lengths = outline.part_lengths();
        for p in 0..3 {
            assert!(rel(lengths[p], exact[p]) < 1e-12);
        }
        let setup = tank.build(0.05).unwrap();
        let sums = part_sums(&setup);
        for p in 0..3 {
            assert!(rel(sums[p], exact[p]) < 1e-12, "part {p}");
        }
        let ccw: Vec<[f64; 2]> = cw.iter().rev().copied().collect();
        let other = SectionTank2::new(SectionShape::Polygon(ccw), 0.6)
            .build(0.05)
            .unwrap();
        assert_eq!(other.fluid_positions, setup.fluid_positions);
        assert_eq!(other.wall_positions, setup.wall_positions);
    }

    #[test]
    fn outline_below_the_origin_holds_its_depth() {
        // a 1 m square from y = −0.7 m, 0.5 m of liquid: still level −0.2 m, 10 rows × 20
        let square = vec![[-0.3, -0.7], [0.7, -0.7], [0.7, 0.3], [-0.3, 0.3]];
        let setup = SectionTank2::new(SectionShape::Polygon(square), 0.5)
            .build(0.05)
            .unwrap();
        assert!(
            (setup.fill_level + 0.2).abs() < 1e-9,
            "{}",
            setup.fill_level
        );
        assert_eq!(setup.fluid_positions.len(), 10 * 20);
    }

    #[test]
    fn self_intersecting_outline_names_the_sides() {
        let bow_tie = vec![[0.0, 0.0], [1.0, 1.0], [1.0, 0.0], [0.0, 1.0]];
        let err = SectionTank2::new(SectionShape::Polygon(bow_tie), 0.5)
            .check_shape()
            .unwrap_err()
            .to_string();
        assert!(err.contains("side 0") && err.contains("side 2"), "{err}");
        let folded = vec![[0.0, 0.0], [2.0, 0.0], [1.0, 0.0], [1.0, 1.0]];
        let err = SectionTank2::new(SectionShape::Polygon(folded), 0.5)
            .check_shape()
            .unwrap_err()
            .to_string();
        assert!(err.contains("fold back"), "{err}");
        let roof = SectionRoof::Outline(vec![[0.0, 1.0], [0.5, 1.5], [0.5, 2.0]]);
        let err = SectionTank2::new(
            SectionShape::RoofedRect {
                width: 1.0,
                wall_height: 1.0,
                roof,
            },
            0.5,
        )
        .check_shape()
        .unwrap_err()
        .to_string();
        assert!(err.contains("wall top"), "{err}");
    }

    #[test]
    fn polyline_roof_equals_its_length_and_bad_numbers_are_errors() {
        let roof = SectionRoof::Outline(vec![[1.0, 1.0], [0.7, 1.3], [0.3, 1.3], [0.0, 1.0]]);
        let tank = SectionTank2::new(
            SectionShape::RoofedRect {
                width: 1.0,
                wall_height: 1.0,
                roof,
            },
            0.5,
        );
        let setup = tank.build(0.02).unwrap();
        let exact = 2.0 * 0.3f64.hypot(0.3) + 0.4;
        assert!(rel(part_sums(&setup)[2], exact) < 1e-12);
        let circle =
            |r: f64, fill: f64| SectionTank2::new(SectionShape::Circle { radius: r }, fill);
        assert!(circle(-1.0, 0.5).build(0.05).is_err());
        assert!(circle(1.0, 2.5).build(0.05).is_err());
        assert!(circle(1.0, f64::NAN).build(0.05).is_err());
        assert!(circle(1.0, 0.5).with_initial_tilt(0.6).build(0.05).is_err());
    }
}

#[cfg(test)]
mod solid_tests {
    use super::tests::{part_sum, rel};
    use super::*;

    fn tank_2x1() -> SectionTank2 {
        SectionTank2::new(
            SectionShape::Polygon(vec![[0.0, 0.0], [2.0, 0.0], [2.0, 1.0], [0.0, 1.0]]),
            0.6,
        )
    }

    #[test]
    fn solids_lengths_add_up_to_their_perimeters() {
        let dx = 0.02;
        // a plate turned 30°, a column, a triangle, all inside the tank (some above the liquid:
        // the whole outline inside the tank is wetted surface)
        let triangle = vec![[1.5, 0.2], [1.8, 0.2], [1.65, 0.5]];
        let tank = tank_2x1()
            .with_solid(Solid2::plate("baffle", [0.5, 0.35], 0.4, 0.05, 30.0))
            .with_solid(Solid2::circle("column", [1.0, 0.3], 0.1))
            .with_solid(Solid2::polygon("wedge", triangle));
        let setup = tank.build(dx).unwrap();
        assert_eq!(
            setup.part_names,
            ["bottom", "wall", "roof", "baffle", "column", "wedge"]
        );
        let wedge = 0.3 + 2.0 * 0.15f64.hypot(0.3);
        for (name, exact) in [
            ("baffle", 2.0 * (0.4 + 0.05)),
            ("column", 2.0 * PI * 0.1),
            ("wedge", wedge),
        ] {
            let sum = part_sum(&setup, name);
            assert!(rel(sum, exact) < 0.01, "{name}: {sum} vs {exact}");
        }
        // the tank's own parts keep their lengths
        assert!(rel(part_sum(&setup, "bottom"), 2.0) < 1e-12);
        assert!(rel(part_sum(&setup, "wall"), 2.0) < 1e-12);
        // no fluid inside a solid or closer than dx/2·… to its surface than the lattice allows;
        // every solid wall particle lies inside its solid, normals point into it
        let column = setup.part_names.iter().position(|n| n == "column").unwrap() as u16;
        for x in &setup.fluid_positions {
            assert!((x - Vector2::new(1.0, 0.3)).norm() > 0.1);
            assert!(setup.interior.contains(x));
        }
        for (k, x) in setup.wall_positions.iter().enumerate() {
            if setup.wall_part[k] == column {
                let r = x - Vector2::new(1.0, 0.3);
                assert!(r.norm() < 0.1 && r.norm() >= 0.1 - 3.0 * dx - 1e-9);
                assert!(setup.wall_normal[k].dot(&(-r.normalize())) > 0.99);
            }
        }
        // the fluid area is the liquid's area less the submerged solids' (within the
        // lattice's staircase: 2 % here)
        let level = setup.fill_level;
        let submerged = PI * 0.1 * 0.1 + 0.5 * 0.3 * 0.3 + 0.4 * 0.05;
        let area = setup.fluid_positions.len() as f64 * dx * dx;
        assert!(rel(area, 2.0 * level - submerged) < 0.02, "{area}");
    }

    #[test]
    fn a_solid_through_the_tank_wall_is_wetted_inside_only() {
        // a plate on the floor, half of its thickness below it: the floor under it and the
        // plate's lower face are dry
        let dx = 0.01;
        let tank = tank_2x1().with_solid(Solid2::plate("plate", [1.0, 0.0], 0.4, 0.06, 0.0));
        let setup = tank.build(dx).unwrap();
        let plate = 0.4 + 2.0 * 0.03;
        assert!(rel(part_sum(&setup, "plate"), plate) < 0.01);
        // the wetted faces' area-weighted normals: the top face, 0.4 m facing down into the
        // plate, and the two end faces cancelling
        let p = setup.part_names.iter().position(|n| n == "plate").unwrap() as u16;
        let (mut nx, mut ny) = (0.0, 0.0);
        for k in 0..setup.wall_part.len() {
            if setup.wall_part[k] == p {
                nx += setup.wall_area[k] * setup.wall_normal[k].x;
                ny += setup.wall_area[k] * setup.wall_normal[k].y;
            }
        }
        assert!(nx.abs() < 1e-3 && rel(-ny, 0.4) < 0.01, "{nx} {ny}");
        assert!(rel(part_sum(&setup, "bottom"), 2.0 - 0.4) < 0.01);
    }

    #[test]
    fn thin_or_misnamed_solids_are_errors() {
        let thin = tank_2x1().with_solid(Solid2::plate("baffle", [1.0, 0.5], 0.4, 0.01, 0.0));
        let err = match thin.build(0.02) {
            Ok(_) => panic!("a plate thinner than 2 dx builds"),
            Err(e) => e.to_string(),
        };
        assert!(err.contains("thinner than 2 dx"), "{err}");
        let bad = tank_2x1().with_solid(Solid2::circle("my column", [1.0, 0.5], 0.1));
        assert!(bad.check_shape().is_err());
    }

    #[test]
    fn named_sides_of_a_polygon_sum_to_their_lengths() {
        // a tank with a sump: floor at 0.2 m with a 0.2 m deep, 0.4 m wide sump, sides given
        // clockwise (side k joins point k to point k+1)
        let outline = vec![
            [0.0, 0.2],
            [0.0, 1.0],
            [2.0, 1.0],
            [2.0, 0.2],
            [1.2, 0.2],
            [1.2, 0.0],
            [0.8, 0.0],
            [0.8, 0.2],
        ];
        let tank = SectionTank2::new(SectionShape::Polygon(outline.clone()), 0.5)
            .with_named_sides("sump", 4, 6)
            .with_named_sides("roof", 1, 1)
            .with_named_sides("shell", 7, 0);
        let o = tank.outline(0.02).unwrap();
        assert_eq!(o.part_names, ["bottom", "wall", "roof", "sump", "shell"]);
        let lengths = o.part_lengths();
        // sump 0.2 + 0.4 + 0.2; shell: floor 0.8 left and the left wall 0.8; bottom: the right
        // floor 0.8; wall: the right wall 0.8; roof 2
        let exact = [0.8, 0.8, 2.0, 0.8, 1.6];
        for p in 0..5 {
            assert!(rel(lengths[p], exact[p]) < 1e-12, "{p}: {}", lengths[p]);
        }
        let setup = tank.build(0.02).unwrap();
        for (p, name) in o.part_names.iter().enumerate() {
            let sum = part_sum(&setup, name);
            assert!(rel(sum, exact[p]) < 0.01, "{name}: {sum} vs {}", exact[p]);
        }
        let total: f64 = setup.wall_area.iter().sum();
        assert!(rel(total, exact.iter().sum()) < 0.01);
        // the counter-clockwise order names the same sides
        let ccw: Vec<[f64; 2]> = outline.iter().rev().copied().collect();
        let n = ccw.len();
        let flip = |k: usize| (2 * n - 2 - k) % n;
        let tank = SectionTank2::new(SectionShape::Polygon(ccw), 0.5)
            .with_named_sides("sump", flip(6), flip(4))
            .with_named_sides("roof", flip(1), flip(1))
            .with_named_sides("shell", flip(0), flip(7));
        assert_eq!(tank.outline(0.02).unwrap().part_lengths(), lengths);
        // overlapping or out-of-range ranges are errors
        let err = SectionTank2::new(SectionShape::Polygon(outline.clone()), 0.5)
            .with_named_sides("a", 0, 2)
            .with_named_sides("b", 2, 3)
            .check_shape()
            .unwrap_err()
            .to_string();
        assert!(err.contains("already named"), "{err}");
        let err = SectionTank2::new(SectionShape::Polygon(outline), 0.5)
            .with_named_sides("a", 0, 8)
            .check_shape()
            .unwrap_err()
            .to_string();
        assert!(err.contains("sides 0 to 7"), "{err}");
    }
}

#[cfg(test)]
mod named_part_tests {
    use super::tests::{part_sum, rel};
    use super::*;

    #[test]
    fn circle_arcs_sum_to_their_arc_lengths() {
        // R = 1 m: a manway from 80° to 100°, a sump wrapping past 0° from 350° to 10°
        // (= −10° to 10°), and the built-in quarters keep the rest of their arcs
        let r = 1.0;
        let dx = 0.02;
        let tank = SectionTank2::new(SectionShape::Circle { radius: r }, 1.2)
            .with_named_arc("manway", 80.0, 100.0)
            .with_named_arc("nozzle", 350.0, 10.0);
        let outline = tank.outline(dx).unwrap();
        assert_eq!(
            outline.part_names,
            ["bottom", "wall", "roof", "manway", "nozzle"]
        );
        let deg = PI / 180.0;
        // exact arcs: roof 90° − 20°, wall 180° − 20°, bottom 90°, manway 20°, nozzle 20°
        let exact = [90.0 * deg, 160.0 * deg, 70.0 * deg, 20.0 * deg, 20.0 * deg];
        let lengths = outline.part_lengths();
        for p in 0..5 {
            // the part lengths are the arcs r·Δθ of their sides: exact to roundoff
            assert!(rel(lengths[p], exact[p] * r) < 1e-12, "{p}: {}", lengths[p]);
        }
        let setup = tank.build(dx).unwrap();
        for (p, name) in outline.part_names.iter().enumerate() {
            // the particle areas add up to the part lengths (1 %: the requirement)
            let sum = part_sum(&setup, name);
            assert!(
                rel(sum, exact[p] * r) < 0.01,
                "{name}: {sum} vs {}",
                exact[p]
            );
        }
        // the manway's particles lie between 80° and 100° (within a lattice cell)
        let manway = 3u16;
        for (x, &part) in setup.wall_positions.iter().zip(&setup.wall_part) {
            if part == manway {
                let a = (x.y - r).atan2(x.x - r).to_degrees();
                assert!(a > 78.0 && a < 102.0, "{a}");
            }
        }
    }

    #[test]
    fn circle_arcs_are_checked() {
        let circle = || SectionTank2::new(SectionShape::Circle { radius: 1.0 }, 1.0);
        let err = circle()
            .with_named_arc("a", 10.0, 10.0)
            .check_shape()
            .unwrap_err()
            .to_string();
        assert!(err.contains("no length"), "{err}");
        let err = circle()
            .with_named_arc("a", 0.0, 90.0)
            .with_named_arc("b", 80.0, 120.0)
            .check_shape()
            .unwrap_err()
            .to_string();
        assert!(err.contains("already named by part 'a'"), "{err}");
        // a whole turn is the whole circle: 2πR
        let o = circle()
            .with_named_arc("shell", 0.0, 360.0)
            .outline(0.05)
            .unwrap();
        assert!(rel(o.part_lengths()[3], 2.0 * PI) < 1e-12);
        // side ranges are for polygons
        assert!(circle().with_named_sides("a", 0, 1).check_shape().is_err());
    }

    #[test]
    fn rectangle_pieces_sum_to_their_lengths() {
        let dx = 0.02;
        let (w, h) = (2.0, 1.0);
        let rect = |roof: SectionRoof| SectionShape::RoofedRect {
            width: w,
            wall_height: h,
            roof,
        };
        // cone rising 0.4 m: each slope √(1² + 0.4²)
        let slope = 1.0f64.hypot(0.4);
        let tank = SectionTank2::new(rect(SectionRoof::Cone { apex_height: 0.4 }), 0.6)
            .with_named_pieces("windward", &[RectPiece::LeftWall, RectPiece::RoofLeft])
            .with_named_pieces("floor", &[RectPiece::Floor]);
        let setup = tank.build(dx).unwrap();
        assert_eq!(
            setup.part_names,
            ["bottom", "wall", "roof", "windward", "floor"]
        );
        for (name, exact) in [
            ("windward", h + slope),
            ("floor", w),
            ("wall", h),
            ("roof", slope),
        ] {
            let sum = part_sum(&setup, name);
            assert!(rel(sum, exact) < 0.01, "{name}: {sum} vs {exact}");
        }
        // a dome's halves: each the arc a·asin(1/a) of half-width 1 m, rise 0.4 m
        let half_arc = dome_arc_length(1.0, 0.4);
        let tank = SectionTank2::new(rect(SectionRoof::Dome { rise: 0.4 }), 0.6)
            .with_named_pieces("lee_roof", &[RectPiece::RoofRight]);
        let o = tank.outline(dx).unwrap();
        let lengths = o.part_lengths();
        assert!(rel(lengths[3], half_arc) < 1e-9, "{}", lengths[3]);
        assert!(rel(lengths[2], half_arc) < 1e-9, "{}", lengths[2]);
        let setup = tank.build(dx).unwrap();
        assert!(rel(part_sum(&setup, "lee_roof"), half_arc) < 0.01);
        // a flat polyline roof split at mid-width where no vertex lies
        let flat = SectionRoof::Outline(vec![[2.0, 1.0], [0.0, 1.0]]);
        let tank = SectionTank2::new(rect(flat), 0.6)
            .with_named_pieces("left_half", &[RectPiece::RoofLeft]);
        let setup = tank.build(dx).unwrap();
        assert!(rel(part_sum(&setup, "left_half"), 1.0) < 0.01);
        assert!(rel(part_sum(&setup, "roof"), 1.0) < 0.01);
        // the same piece in two parts is an error
        let err = SectionTank2::new(rect(SectionRoof::Cone { apex_height: 0.4 }), 0.6)
            .with_named_pieces("a", &[RectPiece::Roof])
            .with_named_pieces("b", &[RectPiece::RoofLeft])
            .check_shape()
            .unwrap_err()
            .to_string();
        assert!(err.contains("already named by part 'a'"), "{err}");
    }

    #[test]
    fn rectangles_and_circles_without_parts_are_unchanged() {
        // no parts: the outline of the built-in parts alone, exact lengths in closed form
        let o = SectionTank2::new(SectionShape::Circle { radius: 1.0 }, 1.0)
            .outline(0.05)
            .unwrap();
        assert_eq!(
            o.exact_length,
            vec![Some(0.5 * PI), Some(PI), Some(0.5 * PI)]
        );
        assert_eq!(o.vertices.len() % 8, 0);
    }
}
