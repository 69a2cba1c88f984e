//! The errors a tank description can produce, worded for the user who wrote it.

use thiserror::Error;

/// Why a tank description could not be turned into particles.
///
/// Every message names the offending quantity with its value and unit, so a user can fix the
/// script or the mesh file without reading the source.
#[derive(Debug, Clone, PartialEq, Error)]
pub enum GeometryError {
    /// A length or other input is NaN or infinite.
    #[error("{what} must be a finite number (got {value})")]
    NotFinite {
        /// What the number is, e.g. "tank width".
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// A length that must be strictly positive is zero or negative.
    #[error("{what} must be > 0 (got {value})")]
    NotPositive {
        /// What the number is, e.g. "tank width".
        what: &'static str,
        /// The value given.
        value: f64,
    },
    /// The fill depth is above the top of the tank (m).
    #[error("fill depth {fill} m is above the tank height {height} m")]
    FillAboveTank {
        /// Fill depth given (m).
        fill: f64,
        /// Height available to the liquid (m).
        height: f64,
    },
    /// The particle spacing is larger than a tank dimension (m).
    #[error("dx {dx} m is larger than the tank ({what} {size} m)")]
    SpacingTooLarge {
        /// Particle spacing (m).
        dx: f64,
        /// Which dimension, e.g. "width".
        what: &'static str,
        /// That dimension (m).
        size: f64,
    },
    /// The particle spacing is larger than the fill depth, so no fluid particle would exist.
    #[error("dx {dx} m is larger than the fill depth {fill} m: no fluid particles would be created; use a smaller dx")]
    SpacingAboveFill {
        /// Particle spacing (m).
        dx: f64,
        /// Fill depth (m).
        fill: f64,
    },
    /// No lattice point below the fill level is inside the tank and outside every solid: the
    /// solids fill the liquid's place.
    #[error("no fluid particle fits: below the fill level (fill depth {fill} m) every lattice point at dx = {dx} m lies inside a solid; move or shrink the solids")]
    NoLiquidRegion {
        /// Particle spacing (m).
        dx: f64,
        /// Fill depth (m).
        fill: f64,
    },
    /// A tank dimension is not a whole number of particle spacings.
    #[error("{what} {size} m is not a whole number of particle spacings dx = {dx} m ({ratio:.4} spacings); choose a dx that divides it, e.g. dx = {suggestion} m")]
    NotMultipleOfSpacing {
        /// Which dimension, e.g. "tank width".
        what: &'static str,
        /// That dimension (m).
        size: f64,
        /// Particle spacing (m).
        dx: f64,
        /// size / dx.
        ratio: f64,
        /// A nearby spacing that divides the dimension (m).
        suggestion: f64,
    },
    /// The initial free-surface tilt is too large for the tank.
    #[error("initial tilt {tilt} m is too large: {reason}")]
    TiltTooLarge {
        /// Tilt given: surface elevation at the left wall (m).
        tilt: f64,
        /// Why, in words.
        reason: String,
    },
    /// The number of wall layers is out of range.
    #[error("number of wall layers must be between 1 and 10 (got {0})")]
    BadLayers(u8),
    /// The requested spacing would create an unreasonable number of particles.
    #[error(
        "dx = {dx} m would create about {estimate} particles (limit {limit}); use a larger dx"
    )]
    TooManyParticles {
        /// Particle spacing (m).
        dx: f64,
        /// Estimated particle count.
        estimate: u64,
        /// The limit.
        limit: u64,
    },
    /// A roof or internal-solid parameter is invalid.
    #[error("{0}")]
    InvalidShape(String),
    /// A mesh file could not be read or parsed.
    #[error("cannot read mesh file {path}: {message}")]
    MeshRead {
        /// The file.
        path: String,
        /// What went wrong (with line number where known).
        message: String,
    },
    /// A mesh has edges used by only one triangle (holes).
    #[error("mesh {path} is not watertight: {open_edges} open edge(s) (edges used by only one triangle), e.g. the edge from {example}; the mesh must be a closed surface")]
    MeshNotWatertight {
        /// The file (or a description of a generated mesh).
        path: String,
        /// Number of open edges.
        open_edges: usize,
        /// One open edge, as two vertex coordinates.
        example: String,
    },
    /// A mesh has edges shared by more than two triangles.
    #[error("mesh {path} is not manifold: {edges} edge(s) shared by more than two triangles, e.g. the edge from {example}")]
    MeshNonManifold {
        /// The file.
        path: String,
        /// Number of non-manifold edges.
        edges: usize,
        /// One such edge, as two vertex coordinates.
        example: String,
    },
    /// Neighbouring triangles of a mesh have opposite winding.
    #[error("mesh {path} is not consistently oriented: {edges} edge(s) where two neighbouring triangles have opposite winding, e.g. the edge from {example}; flip those triangles so all normals point out of the interior")]
    MeshInconsistentOrientation {
        /// The file.
        path: String,
        /// Number of badly oriented edges.
        edges: usize,
        /// One such edge, as two vertex coordinates.
        example: String,
    },
}

/// Checks that `value` is finite and > 0.
pub(crate) fn check_positive(what: &'static str, value: f64) -> Result<(), GeometryError> {
    check_finite(what, value)?;
    if value <= 0.0 {
        return Err(GeometryError::NotPositive { what, value });
    }
    Ok(())
}

/// Checks that `value` is finite.
pub(crate) fn check_finite(what: &'static str, value: f64) -> Result<(), GeometryError> {
    if !value.is_finite() {
        return Err(GeometryError::NotFinite { what, value });
    }
    Ok(())
}

/// Checks the number of wall layers.
pub(crate) fn check_layers(layers: u8) -> Result<(), GeometryError> {
    if !(1..=10).contains(&layers) {
        return Err(GeometryError::BadLayers(layers));
    }
    Ok(())
}

/// Largest number of particles a builder accepts before refusing (protects from typos in dx).
pub const MAX_PARTICLES: u64 = 50_000_000;
