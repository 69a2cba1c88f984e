//! What a case script declares: tank, numerics, run control, gauges; read from Rhai maps.

use rhai::{Dynamic, Map};
use serde::Serialize;
use slosh_core::{
    ArtificialSoundSpeed, Backend, BoundaryMethod, DensityDiffusion, DensityMethod, Integrator,
    KernelKind, NeighbourBackend, PairScheme, SoundSpeedRule, SphParams, ViscousOperator,
    WallPressureMethod,
};
use slosh_geometry::{
    bounding_box_2d, CylinderLattice, InitialSurface, InternalSolid, RectPiece, Roof, SectionRoof,
    SectionShape, SectionTank2, Solid2, Solid2Shape, SolidShape, TankMesh,
};
use std::collections::BTreeSet;

/// Reads the keys of a Rhai map, remembering which were used so that unknown keys (typos)
/// can be reported.
pub(crate) struct MapReader<'a> {
    what: &'static str,
    map: &'a Map,
    used: BTreeSet<String>,
}

impl<'a> MapReader<'a> {
    pub(crate) fn new(what: &'static str, map: &'a Map) -> Self {
        MapReader {
            what,
            map,
            used: BTreeSet::new(),
        }
    }

    pub(crate) fn get(&mut self, key: &str) -> Option<&'a Dynamic> {
        self.used.insert(key.to_string());
        self.map.get(key)
    }

    pub(crate) fn f64_or(&mut self, key: &str, default: f64) -> Result<f64, String> {
        Ok(self.opt_f64(key)?.unwrap_or(default))
    }

    /// A finite number, or `None` when the key is absent (a NaN or an infinity computed by
    /// the script is an error here, before it becomes a size or a time).
    pub(crate) fn opt_f64(&mut self, key: &str) -> Result<Option<f64>, String> {
        match self.get(key) {
            None => Ok(None),
            Some(d) => match dynamic_to_f64(d) {
                Some(x) if x.is_finite() => Ok(Some(x)),
                Some(x) => Err(format!(
                    "{}: '{key}' must be a finite number (got {x}; check the script's \
                     arithmetic)",
                    self.what
                )),
                None => Err(format!("{}: '{key}' must be a number (got {d})", self.what)),
            },
        }
    }

    pub(crate) fn bool_or(&mut self, key: &str, default: bool) -> Result<bool, String> {
        match self.get(key) {
            None => Ok(default),
            Some(d) => d
                .as_bool()
                .map_err(|_| format!("{}: '{key}' must be true or false (got {d})", self.what)),
        }
    }

    pub(crate) fn str_or(&mut self, key: &str, default: &str) -> Result<String, String> {
        match self.get(key) {
            None => Ok(default.to_string()),
            Some(d) if d.is_string() => Ok(d.clone().into_string().unwrap_or_default()),
            Some(d) => Err(format!("{}: '{key}' must be a string (got {d})", self.what)),
        }
    }

    /// Reads `key` as one of `choices` (`default` when the key is absent): each choice is
    /// the names it answers to (the first is the one an error lists) and what it stands
    /// for. A name that is none of them stops with the names the key accepts.
    pub(crate) fn choice_or<T: Clone>(
        &mut self,
        key: &str,
        default: &str,
        choices: &[(&[&str], T)],
    ) -> Result<T, String> {
        let name = self.str_or(key, default)?;
        match choices
            .iter()
            .find(|(names, _)| names.contains(&name.as_str()))
        {
            Some((_, value)) => Ok(value.clone()),
            None => {
                let listed: Vec<String> = choices
                    .iter()
                    .filter_map(|(names, _)| names.first().map(|n| format!("\"{n}\"")))
                    .collect();
                let names = match listed.split_last() {
                    Some((last, rest)) if !rest.is_empty() => {
                        format!("{} or {last}", rest.join(", "))
                    }
                    _ => listed.concat(),
                };
                Err(format!(
                    "{}: unknown {key} \"{name}\" (use {names})",
                    self.what
                ))
            }
        }
    }

    pub(crate) fn usize_or(&mut self, key: &str, default: usize) -> Result<usize, String> {
        match self.get(key) {
            None => Ok(default),
            Some(d) => match dynamic_to_f64(d) {
                Some(x) if x >= 0.0 && x.fract() == 0.0 => Ok(x as usize),
                _ => Err(format!(
                    "{}: '{key}' must be a whole number ≥ 0 (got {d})",
                    self.what
                )),
            },
        }
    }

    /// A list of numbers, or `None` when the key is absent.
    pub(crate) fn opt_numbers(&mut self, key: &str) -> Result<Option<Vec<f64>>, String> {
        let what = self.what;
        let Some(d) = self.get(key) else {
            return Ok(None);
        };
        let list = d
            .clone()
            .into_array()
            .map_err(|_| format!("{what}: '{key}' must be a list of numbers (got {d})"))?;
        list.iter()
            .map(|x| {
                dynamic_to_f64(x)
                    .ok_or_else(|| format!("{what}: '{key}' must be a list of numbers (got {x})"))
            })
            .collect::<Result<Vec<f64>, String>>()
            .map(Some)
    }

    /// A list of [x, y] points (m), or `None` when the key is absent.
    pub(crate) fn opt_points(&mut self, key: &str) -> Result<Option<Vec<[f64; 2]>>, String> {
        let what = self.what;
        self.get(key)
            .map(|d| points_from_dynamic(d).map_err(|m| format!("{what}: '{key}' {m}")))
            .transpose()
    }

    /// Error when the map holds keys that were never asked for.
    pub(crate) fn finish(self) -> Result<(), String> {
        let unknown: Vec<&str> = self
            .map
            .keys()
            .map(|k| k.as_str())
            .filter(|k| !self.used.contains(*k))
            .collect();
        if unknown.is_empty() {
            Ok(())
        } else {
            let known: Vec<&str> = self.used.iter().map(|s| s.as_str()).collect();
            Err(format!(
                "{}: unknown key(s) {}; known keys: {}",
                self.what,
                unknown.join(", "),
                known.join(", ")
            ))
        }
    }
}

/// Reads a Rhai array of [x, y] number pairs.
fn points_from_dynamic(d: &Dynamic) -> Result<Vec<[f64; 2]>, String> {
    let list = d
        .as_array_ref()
        .map_err(|_| format!("must be a list of [x, y] points (got {d})"))?;
    list.iter()
        .enumerate()
        .map(|(k, p)| {
            let pair = p.as_array_ref().ok().and_then(|a| {
                (a.len() == 2)
                    .then(|| Some([dynamic_to_f64(&a[0])?, dynamic_to_f64(&a[1])?]))
                    .flatten()
            });
            pair.ok_or_else(|| format!("point {k} must be [x, y] with two numbers (got {p})"))
        })
        .collect()
}

pub(crate) fn dynamic_to_f64(d: &Dynamic) -> Option<f64> {
    d.as_float()
        .ok()
        .or_else(|| d.as_int().ok().map(|i| i as f64))
}

/// The tank a script describes.
#[derive(Clone, Debug, Serialize)]
pub enum TankSpec {
    /// 2D rectangular tank section (per metre of depth).
    Rect {
        /// Inner width 2l (m).
        width: f64,
        /// Tank (shell) height (m).
        height: f64,
        /// Still liquid depth H (m).
        depth: f64,
        /// A roof (closed tank) or none (open).
        roof: bool,
        /// The roof's shape when it is not flat (absent: flat at `height`).
        #[serde(skip_serializing_if = "Option::is_none")]
        roof_shape: Option<SectionRoofSpec>,
        /// `"offset"` or `"paper"`.
        layout: String,
        /// Initial free-surface elevation at the left wall (m).
        tilt: f64,
        /// Shape of the tilted surface: `"plane"` or `"mode1"` (first sloshing mode).
        tilt_shape: String,
        /// Fixed solids inside the tank (baffles, columns); a closed (roofed) section only.
        #[serde(skip_serializing_if = "Vec::is_empty")]
        solids: Vec<Solid2>,
        /// Parts named by the user on a roofed rectangle: name and the pieces it covers
        /// (`floor`, `left_wall`, `right_wall`, `roof`, `roof_left`, `roof_right`).
        #[serde(skip_serializing_if = "Vec::is_empty")]
        parts: Vec<(String, Vec<String>)>,
    },
    /// 2D section of any closed outline (per metre of depth): a polygon or a circle.
    Section {
        /// The outline.
        outline: SectionOutlineSpec,
        /// Still liquid depth above the lowest point of the outline (m).
        depth: f64,
        /// Initial free-surface elevation at the leftmost point (m).
        tilt: f64,
        /// Shape of the tilted surface: `"plane"` or `"mode1"` (first sloshing mode).
        tilt_shape: String,
        /// Fixed solids inside the tank (baffles, columns).
        #[serde(skip_serializing_if = "Vec::is_empty")]
        solids: Vec<Solid2>,
        /// Parts named by the user on a polygon: name and the first and last side (side k
        /// joins point k to point k+1 of the outline as given).
        #[serde(skip_serializing_if = "Vec::is_empty")]
        parts: Vec<(String, [usize; 2])>,
        /// Parts named by the user on a circle: name and the first and last angle of its arc
        /// (degrees from +x, counter-clockwise).
        #[serde(skip_serializing_if = "Vec::is_empty")]
        arc_parts: Vec<(String, [f64; 2])>,
    },
    /// 3D upright cylinder, axis vertical through x = y = 0.
    Cylinder {
        /// Inner radius R (m).
        radius: f64,
        /// Shell height (m).
        height: f64,
        /// Still liquid depth (m).
        depth: f64,
        /// `"none"`, `"flat"`, `"cone"`, `"dome"`, or a mesh path.
        roof: String,
        /// Rise of a cone apex or dome crown above the shell top (m).
        roof_rise: f64,
        /// Initial free-surface elevation at x = −R (m).
        tilt: f64,
        /// Shape of the tilted surface: `"plane"` or `"mode1"` (first sloshing mode).
        tilt_shape: String,
        /// Internal solids (columns, rings, blocks).
        #[serde(skip_serializing_if = "Vec::is_empty")]
        solids: Vec<InternalSolid>,
        /// Layout of the liquid and shell particles: `"cubic"` (the lattice of every tank) or
        /// `"polar"` (rings about the axis, fitted to the shell; a script's default where it
        /// applies). Absent from a written case: cubic.
        #[serde(skip_serializing_if = "is_cubic")]
        lattice: String,
    },
    /// 3D rectangular box tank.
    Box {
        /// Inner length along x (m).
        length: f64,
        /// Inner breadth along y (m).
        breadth: f64,
        /// Height (m).
        height: f64,
        /// Still liquid depth (m).
        depth: f64,
        /// Flat roof at `height`.
        roof: bool,
        /// Initial free-surface elevation at x = 0 (m).
        tilt: f64,
        /// Shape of the tilted surface: `"plane"` or `"mode1"` (first sloshing mode).
        tilt_shape: String,
        /// Internal solids (columns, rings, blocks).
        #[serde(skip_serializing_if = "Vec::is_empty")]
        solids: Vec<InternalSolid>,
    },
    /// 3D tank of any shape: a closed OBJ/STL mesh of the whole interior, raised so that its
    /// lowest point is at z = 0.
    Mesh {
        /// The mesh file as the script gives it (looked up below the script's folder).
        mesh: String,
        /// Still liquid depth above the mesh's lowest point (m).
        depth: f64,
        /// Initial free-surface elevation at the mesh's smallest x (m).
        tilt: f64,
        /// Shape of the tilted surface: `"plane"` or `"mode1"` (cos(π ξ) across x).
        tilt_shape: String,
        /// Internal solids (columns, rings, blocks).
        #[serde(skip_serializing_if = "Vec::is_empty")]
        solids: Vec<InternalSolid>,
        /// What the file holds (read when the script calls `tank`).
        extent: MeshExtent,
    },
    /// 3D spherical tank, centre on the vertical axis at z = radius.
    Sphere {
        /// Inner radius R (m).
        radius: f64,
        /// Still liquid depth above the lowest point (m).
        depth: f64,
        /// Initial free-surface elevation at x = −R (m).
        tilt: f64,
        /// Shape of the tilted surface: `"plane"` or `"mode1"` (first sloshing mode).
        tilt_shape: String,
    },
}

/// What a tank mesh file holds: its size and parts.
#[derive(Clone, Debug, Default, PartialEq, Serialize)]
pub struct MeshExtent {
    /// Lowest corner of its bounding box (m; lowest point at z = 0).
    pub min: [f64; 3],
    /// Highest corner of its bounding box (m).
    pub max: [f64; 3],
    /// Lowest corner of a `roof` triangle (m): the freeboard's top; `None` without a roof.
    pub roof_base: Option<f64>,
    /// Each part (`bottom`, `wall`, `roof`, then the other groups) with its mesh area (m²).
    pub parts: Vec<(String, f64)>,
}

/// Reads a 3D tank's `solids`: `#{ name, shape: "column", centre: [x, y], radius, bottom,
/// top }`, `#{ name, shape: "ring", inner_radius, outer_radius, bottom, top }` (centred on
/// the z axis) or `#{ name, shape: "block", min: [x, y, z], max: [x, y, z] }` (m).
fn read_solids_3d(r: &mut MapReader) -> Result<Vec<InternalSolid>, String> {
    let Some(list) = r.get("solids") else {
        return Ok(Vec::new());
    };
    let list = list.as_array_ref().map_err(|_| {
        format!("tank: 'solids' must be a list of maps #{{ name, shape, … }} (got {list})")
    })?;
    let mut solids = Vec::with_capacity(list.len());
    for (k, d) in list.iter().enumerate() {
        let at = |m: String| format!("tank: solids[{k}]: {m}");
        let map = d.read_lock::<Map>().ok_or_else(|| {
            format!("tank: solids[{k}] must be a map #{{ name, shape, … }} (got {d})")
        })?;
        let mut r = MapReader::new("tank solid", &map);
        let name = r.str_or("name", "")?;
        if name.is_empty() {
            return Err(at(
                "needs a 'name', the part its loads are reported under".into()
            ));
        }
        let shape = r.str_or("shape", "")?;
        let number = |r: &mut MapReader, key: &str| -> Result<f64, String> {
            r.opt_f64(key)?
                .ok_or_else(|| at(format!("a {shape} needs '{key}' (m)")))
        };
        let vector = |r: &mut MapReader, key: &str, n: usize| -> Result<Vec<f64>, String> {
            let d = r.get(key).ok_or_else(|| {
                at(format!(
                    "a {shape} needs '{key}', [{}] (m)",
                    ["x", "y", "z"][..n].join(", ")
                ))
            })?;
            crate::engine::dynamic_to_vec(d)
                .filter(|v| v.len() == n)
                .ok_or_else(|| at(format!("'{key}' must be a list of {n} numbers (got {d})")))
        };
        let solid = match shape.as_str() {
            "column" => {
                let c = vector(&mut r, "centre", 2)?;
                InternalSolid::column(
                    &name,
                    [c[0], c[1]],
                    number(&mut r, "radius")?,
                    number(&mut r, "bottom")?,
                    number(&mut r, "top")?,
                )
            }
            "ring" => InternalSolid::ring(
                &name,
                number(&mut r, "inner_radius")?,
                number(&mut r, "outer_radius")?,
                number(&mut r, "bottom")?,
                number(&mut r, "top")?,
            ),
            "block" => {
                let lo = vector(&mut r, "min", 3)?;
                let hi = vector(&mut r, "max", 3)?;
                InternalSolid::block(&name, [lo[0], lo[1], lo[2]], [hi[0], hi[1], hi[2]])
            }
            other => {
                return Err(at(format!(
                "unknown shape \"{other}\" for a 3D tank (use \"column\", \"ring\" or \"block\")"
            )))
            }
        };
        r.finish().map_err(at)?;
        solids.push(solid);
    }
    Ok(solids)
}

/// What an internal solid of a 3D tank is, in words.
fn describe_solid_3d(s: &InternalSolid) -> String {
    match &s.shape {
        SolidShape::Column {
            centre,
            radius,
            bottom,
            top,
        } => format!(
            "internal column of radius {radius} m at ({}, {}) m, z {bottom} to {top} m",
            centre[0], centre[1]
        ),
        SolidShape::Ring {
            inner_radius,
            outer_radius,
            bottom,
            top,
        } => format!(
            "internal ring of radii {inner_radius} to {outer_radius} m about the z axis, z \
             {bottom} to {top} m"
        ),
        SolidShape::Block { min, max } => format!(
            "internal block from ({}, {}, {}) to ({}, {}, {}) m",
            min[0], min[1], min[2], max[0], max[1], max[2]
        ),
    }
}

/// Reads one `#{ name, shape, … }` map of a 2D tank's `solids` list (lengths in m, angles in
/// degrees): `shape: "plate"` (`centre`, `length`, `thickness`, `angle` from +x), `"circle"`
/// (`centre`, `radius`) or `"polygon"` (`outline`, a list of [x, y] points).
fn solid_from_map(k: usize, map: &Map) -> Result<Solid2, String> {
    let mut r = MapReader::new("tank solid", map);
    let at = |m: String| format!("tank: solids[{k}]: {m}");
    let name = r.str_or("name", "")?;
    if name.is_empty() {
        return Err(at(
            "needs a 'name', the part its loads are reported under".into()
        ));
    }
    let centre = |r: &mut MapReader| -> Result<[f64; 2], String> {
        match r.get("centre") {
            None => Err(at("needs 'centre', [x, y] (m)".into())),
            Some(d) => {
                let p = points_from_dynamic(&Dynamic::from(vec![d.clone()]))
                    .map_err(|_| at(format!("'centre' must be [x, y] (got {d})")))?;
                Ok(p[0])
            }
        }
    };
    let shape =
        match r.str_or("shape", "")?.as_str() {
            "plate" => Solid2Shape::Plate {
                centre: centre(&mut r)?,
                length: r
                    .opt_f64("length")?
                    .ok_or_else(|| at("a plate needs 'length' (m)".into()))?,
                thickness: r
                    .opt_f64("thickness")?
                    .ok_or_else(|| at("a plate needs 'thickness' (m)".into()))?,
                angle_deg: r.f64_or("angle", 0.0)?,
            },
            "circle" => Solid2Shape::Circle {
                centre: centre(&mut r)?,
                radius: r
                    .opt_f64("radius")?
                    .ok_or_else(|| at("a circle needs 'radius' (m)".into()))?,
            },
            "polygon" => Solid2Shape::Polygon(r.opt_points("outline")?.ok_or_else(|| {
                at("a polygon needs 'outline', a list of [x, y] points (m)".into())
            })?),
            other => {
                return Err(at(format!(
                    "unknown shape \"{other}\" (use \"plate\", \"circle\" or \"polygon\")"
                )))
            }
        };
    r.finish().map_err(at)?;
    Ok(Solid2 { name, shape })
}

/// Reads a tank's `solids`: a list of solid maps (empty when absent).
fn read_solids(r: &mut MapReader) -> Result<Vec<Solid2>, String> {
    let Some(list) = r.get("solids") else {
        return Ok(Vec::new());
    };
    let list = list.as_array_ref().map_err(|_| {
        format!("tank: 'solids' must be a list of maps #{{ name, shape, … }} (got {list})")
    })?;
    list.iter()
        .enumerate()
        .map(|(k, d)| {
            let map = d.read_lock::<Map>().ok_or_else(|| {
                format!("tank: solids[{k}] must be a map #{{ name, shape, … }} (got {d})")
            })?;
            solid_from_map(k, &map)
        })
        .collect()
}

/// Reads a polygon's `parts`: a map from part name to [first side, last side].
fn read_parts(r: &mut MapReader) -> Result<Vec<(String, [usize; 2])>, String> {
    let Some(d) = r.get("parts") else {
        return Ok(Vec::new());
    };
    let map = d.read_lock::<Map>().ok_or_else(|| {
        format!("tank: 'parts' must be a map from part name to [first side, last side] (got {d})")
    })?;
    let side = |v: &Dynamic| {
        dynamic_to_f64(v)
            .filter(|x| *x >= 0.0 && x.fract() == 0.0)
            .map(|x| x as usize)
    };
    map.iter()
        .map(|(name, range)| {
            let pair = range.as_array_ref().ok().and_then(|a| {
                (a.len() == 2)
                    .then(|| Some([side(&a[0])?, side(&a[1])?]))
                    .flatten()
            });
            pair.map(|p| (name.to_string(), p)).ok_or_else(|| {
                format!(
                    "tank: parts.{name} must be [first side, last side], two whole numbers ≥ 0 \
                     (side k joins point k to point k+1 of the outline; got {range})"
                )
            })
        })
        .collect()
}

/// Reads a circle's `parts`: a map from part name to [first angle, last angle] (degrees from
/// +x, counter-clockwise; wrapping past 0° allowed).
fn read_arc_parts(r: &mut MapReader) -> Result<Vec<(String, [f64; 2])>, String> {
    let Some(d) = r.get("parts") else {
        return Ok(Vec::new());
    };
    let map = d.read_lock::<Map>().ok_or_else(|| {
        format!(
            "tank: 'parts' of a circle must be a map from part name to [first angle, last \
             angle] in degrees (got {d})"
        )
    })?;
    map.iter()
        .map(|(name, range)| {
            let pair = range.as_array_ref().ok().and_then(|a| {
                (a.len() == 2)
                    .then(|| Some([dynamic_to_f64(&a[0])?, dynamic_to_f64(&a[1])?]))
                    .flatten()
            });
            pair.filter(|p| p[0].is_finite() && p[1].is_finite())
                .map(|p| (name.to_string(), p))
                .ok_or_else(|| {
                    format!(
                        "tank: parts.{name} must be [first angle, last angle], two numbers of \
                         degrees counter-clockwise from +x (e.g. [80.0, 100.0]; got {range})"
                    )
                })
        })
        .collect()
}

/// Reads a rectangle's `parts`: a map from part name to a piece name or a list of them
/// ([`RectPiece::from_name`]).
fn read_piece_parts(r: &mut MapReader) -> Result<Vec<(String, Vec<String>)>, String> {
    let Some(d) = r.get("parts") else {
        return Ok(Vec::new());
    };
    let bad = |name: &str, got: &Dynamic| {
        format!(
            "tank: parts.{name} of a rectangle must be a piece or a list of pieces, from {}              (got {got})",
            RectPiece::NAMES
        )
    };
    let map = d.read_lock::<Map>().ok_or_else(|| {
        format!(
            "tank: 'parts' of a rectangle must be a map from part name to pieces, from {}              (got {d})",
            RectPiece::NAMES
        )
    })?;
    map.iter()
        .map(|(name, value)| {
            let names: Vec<String> = if let Ok(s) = value.clone().into_string() {
                vec![s]
            } else if let Ok(a) = value.as_array_ref() {
                a.iter()
                    .map(|v| v.clone().into_string().map_err(|_| bad(name, value)))
                    .collect::<Result<_, _>>()?
            } else {
                return Err(bad(name, value));
            };
            if names.is_empty() {
                return Err(bad(name, value));
            }
            for piece in &names {
                if RectPiece::from_name(piece).is_none() {
                    return Err(format!(
                        "tank: parts.{name}: unknown piece \"{piece}\" (use {})",
                        RectPiece::NAMES
                    ));
                }
            }
            Ok((name.to_string(), names))
        })
        .collect()
}

/// A 2D section's roof other than flat or none.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub enum SectionRoofSpec {
    /// Straight from the wall tops to an apex `rise` (m) above them at mid-width.
    Cone {
        /// Apex height above the wall tops (m).
        rise: f64,
    },
    /// Circular arc through the wall tops, `rise` (m) above them at mid-width.
    Dome {
        /// Crown height above the wall tops (m).
        rise: f64,
    },
    /// Polyline of [x, y] points (m) from one wall top to the other.
    Outline(Vec<[f64; 2]>),
}

/// The outline of a 2D [`TankSpec::Section`].
#[derive(Clone, Debug, PartialEq, Serialize)]
pub enum SectionOutlineSpec {
    /// Closed polygon of [x, y] vertices (m), any orientation.
    Polygon(Vec<[f64; 2]>),
    /// Circle of `radius` (m), centre (radius, radius): a horizontal cylindrical tank.
    Circle {
        /// Inner radius (m).
        radius: f64,
    },
}

impl SectionOutlineSpec {
    /// Lowest and highest corner of the outline's bounding box (m).
    pub fn bounds(&self) -> ([f64; 2], [f64; 2]) {
        match self {
            SectionOutlineSpec::Circle { radius } => ([0.0, 0.0], [2.0 * radius, 2.0 * radius]),
            SectionOutlineSpec::Polygon(points) => bounding_box_2d(points),
        }
    }
}

/// Reads a 2D section's `roof`: true/false, "flat", "none"/"open", "cone" or "dome" (rising
/// `roof_rise` m), or a list of [x, y] points from wall top to wall top. Returns whether there
/// is a roof and its shape when not flat.
fn section_roof(r: &mut MapReader) -> Result<(bool, Option<SectionRoofSpec>), String> {
    let rise = r.f64_or("roof_rise", 0.1)?;
    let Some(roof) = r.get("roof") else {
        return Ok((true, None));
    };
    if let Ok(closed) = roof.as_bool() {
        return Ok((closed, None));
    }
    if roof.is_array() {
        let points = r.opt_points("roof")?.unwrap_or_default();
        return Ok((true, Some(SectionRoofSpec::Outline(points))));
    }
    let name = roof.clone().into_string().unwrap_or_default();
    match name.trim().to_ascii_lowercase().as_str() {
        "flat" => Ok((true, None)),
        "none" | "open" => Ok((false, None)),
        "cone" => Ok((true, Some(SectionRoofSpec::Cone { rise }))),
        "dome" => Ok((true, Some(SectionRoofSpec::Dome { rise }))),
        _ => Err(format!(
            "tank: unknown roof {} for a 2D section (use true, false, \"flat\", \"none\", \"cone\", \"dome\" \
             or a list of [x, y] points from one wall top to the other)",
            if roof.is_string() { format!("\"{name}\"") } else { roof.to_string() }
        )),
    }
}

impl Default for TankSpec {
    /// The paper's §3.1 section: 1.0 m wide, 1.0 m high, 0.5 m of water, closed, flat surface.
    fn default() -> Self {
        TankSpec::Rect {
            width: 1.0,
            height: 1.0,
            depth: 0.5,
            roof: true,
            roof_shape: None,
            layout: "offset".into(),
            tilt: 0.0,
            tilt_shape: "plane".into(),
            solids: Vec::new(),
            parts: Vec::new(),
        }
    }
}

/// True for a cylinder's default lattice (left out of the written case).
fn is_cubic(lattice: &str) -> bool {
    lattice == "cubic"
}

/// Reads a cylinder's `lattice`, "cubic" or "polar". Left out, it is "polar" (liquid and shell
/// on rings fitted to the shell, which damps the first mode least; `docs/tanks.md`, *The polar lattice*) where
/// that lattice applies — a built-in roof and no internal solids — and "cubic" otherwise.
fn cylinder_lattice(
    r: &mut MapReader,
    roof: &str,
    solids: &[InternalSolid],
) -> Result<String, String> {
    let polar_applies = Roof::from_name(roof, 0.0)
        .is_some_and(|roof| CylinderLattice::polar_fits(&roof, !solids.is_empty()));
    let default = if polar_applies { "polar" } else { "cubic" };
    r.choice_or(
        "lattice",
        default,
        &[(&["cubic"], "cubic"), (&["polar"], "polar")],
    )
    .map(str::to_string)
}

/// Reads `tilt_shape` ("plane" by default, or "mode1").
fn tilt_shape(r: &mut MapReader) -> Result<String, String> {
    r.choice_or(
        "tilt_shape",
        "plane",
        &[(&["plane"], "plane"), (&["mode1"], "mode1")],
    )
    .map(str::to_string)
}

impl TankSpec {
    /// Still liquid depth (m).
    pub fn depth(&self) -> f64 {
        match self {
            TankSpec::Rect { depth, .. }
            | TankSpec::Section { depth, .. }
            | TankSpec::Cylinder { depth, .. }
            | TankSpec::Box { depth, .. }
            | TankSpec::Sphere { depth, .. }
            | TankSpec::Mesh { depth, .. } => *depth,
        }
    }

    /// Largest horizontal inner size (m): a section's width, a box's length or breadth, a
    /// cylinder's diameter.
    pub fn horizontal_size(&self) -> f64 {
        match self {
            TankSpec::Rect { width, .. } => *width,
            TankSpec::Section { outline, .. } => {
                let (lo, hi) = outline.bounds();
                hi[0] - lo[0]
            }
            TankSpec::Box {
                length, breadth, ..
            } => length.max(*breadth),
            TankSpec::Cylinder { radius, .. } | TankSpec::Sphere { radius, .. } => 2.0 * radius,
            TankSpec::Mesh { extent, .. } => {
                (extent.max[0] - extent.min[0]).max(extent.max[1] - extent.min[1])
            }
        }
    }

    /// Reads and checks a mesh tank's file through `sandbox` (the script's folders) and
    /// records its size and parts; nothing for the other tanks.
    pub fn read_mesh(&mut self, sandbox: &crate::ReadSandbox) -> Result<(), String> {
        let TankSpec::Mesh { mesh, extent, .. } = self else {
            return Ok(());
        };
        let path = sandbox
            .resolve(mesh)
            .map_err(|e| format!("tank: mesh {e}"))?;
        let read = TankMesh::read(&path).map_err(|e| format!("tank: {e}"))?;
        let (min, max) = read.bounds();
        let roof_base = read
            .triangle_part
            .iter()
            .zip(&read.surface.triangles)
            .filter(|(p, _)| **p == 2)
            .flat_map(|(_, t)| t.map(|i| read.surface.vertices[i as usize][2]))
            .reduce(f64::min);
        *extent = MeshExtent {
            min,
            max,
            roof_base,
            parts: read
                .part_names
                .iter()
                .cloned()
                .zip(read.part_areas())
                .collect(),
        };
        Ok(())
    }

    /// Space dimension of the tank (2 or 3).
    pub fn dim(&self) -> usize {
        match self {
            TankSpec::Rect { .. } | TankSpec::Section { .. } => 2,
            _ => 3,
        }
    }

    /// The wall parts whose loads are reported (`bottom`, `wall`, `roof`, then the parts named
    /// by the user and the internal solids), each with what it is on this tank.
    pub fn part_descriptions(&self) -> Vec<(String, String)> {
        let mut parts: Vec<(String, String)> = self
            .built_in_part_descriptions()
            .into_iter()
            .map(|(n, w)| (n.to_string(), w))
            .collect();
        let (named, solids): (Vec<(String, String)>, &[Solid2]) = match self {
            TankSpec::Section {
                parts,
                arc_parts,
                solids,
                ..
            } => (
                parts
                    .iter()
                    .map(|(n, [first, last])| {
                        (n.clone(), format!("outline sides {first} to {last}"))
                    })
                    .chain(arc_parts.iter().map(|(n, [first, last])| {
                        (n.clone(), format!("the arc from {first}° to {last}°"))
                    }))
                    .collect(),
                solids,
            ),
            TankSpec::Rect { parts, solids, .. } => (
                parts
                    .iter()
                    .map(|(n, pieces)| (n.clone(), pieces.join(" + ")))
                    .collect(),
                solids,
            ),
            _ => (Vec::new(), &[]),
        };
        if !named.is_empty() {
            for (name, what) in parts.iter_mut() {
                if !named.iter().any(|(n, _)| n == name) {
                    what.push_str(" (of the sides not named in 'parts')");
                }
            }
        }
        let mut describe =
            |name: &str, what: String| match parts.iter_mut().find(|(n, _)| n == name) {
                Some((_, w)) => {
                    w.push_str("; ");
                    w.push_str(&what);
                }
                None => parts.push((name.to_string(), what)),
            };
        for (name, what) in named {
            describe(&name, what);
        }
        let solids_3d: &[InternalSolid] = match self {
            TankSpec::Cylinder { solids, .. }
            | TankSpec::Box { solids, .. }
            | TankSpec::Mesh { solids, .. } => solids,
            _ => &[],
        };
        if let TankSpec::Mesh { extent, .. } = self {
            for (name, area) in extent.parts.iter().skip(3) {
                describe(name, format!("mesh group \"{name}\", {area:.4} m²"));
            }
        }
        for s in solids_3d {
            describe(&s.name, describe_solid_3d(s));
        }
        for s in solids {
            let what = match &s.shape {
                Solid2Shape::Plate {
                    centre,
                    length,
                    thickness,
                    angle_deg,
                } => format!(
                    "internal plate {length} × {thickness} m at ({}, {}) m, {angle_deg}° from x",
                    centre[0], centre[1]
                ),
                Solid2Shape::Circle { centre, radius } => format!(
                    "internal circle of radius {radius} m at ({}, {}) m",
                    centre[0], centre[1]
                ),
                Solid2Shape::Polygon(points) => {
                    format!("internal polygon of {} points", points.len())
                }
            };
            describe(&s.name, what);
        }
        parts
    }

    /// The built-in parts `bottom`, `wall`, `roof` with what each is on this tank.
    fn built_in_part_descriptions(&self) -> Vec<(&'static str, String)> {
        let none = || "none (open tank)".to_string();
        let by_facing = |down: &str, side: &str, up: &str| {
            vec![
                ("bottom", down.to_string()),
                ("wall", side.to_string()),
                ("roof", up.to_string()),
            ]
        };
        match self {
            TankSpec::Rect {
                roof, roof_shape, ..
            } => {
                let roof = match (roof, roof_shape) {
                    (false, _) => none(),
                    (true, None) => "the flat roof".into(),
                    (true, Some(SectionRoofSpec::Cone { .. })) => {
                        "the cone roof's two slopes".into()
                    }
                    (true, Some(SectionRoofSpec::Dome { .. })) => "the dome roof's arc".into(),
                    (true, Some(SectionRoofSpec::Outline(_))) => "the roof polyline".into(),
                };
                vec![
                    ("bottom", "the floor".into()),
                    ("wall", "the two side walls".into()),
                    ("roof", roof),
                ]
            }
            TankSpec::Section {
                outline: SectionOutlineSpec::Circle { .. },
                ..
            } => by_facing(
                "the lower quarter of the circle",
                "the two side quarters",
                "the upper quarter",
            ),
            TankSpec::Section { .. } => by_facing(
                "sides facing within 45° of straight down",
                "the other sides",
                "sides facing within 45° of straight up",
            ),
            TankSpec::Cylinder { roof, .. } => vec![
                ("bottom", "the floor".into()),
                ("wall", "the cylindrical shell".into()),
                (
                    "roof",
                    if roof == "none" || roof == "open" {
                        none()
                    } else {
                        format!("the {roof} roof")
                    },
                ),
            ],
            TankSpec::Sphere { .. } => by_facing(
                "the cap within 45° of the lowest point",
                "the zone between latitudes −45° and 45°",
                "the cap within 45° of the highest point",
            ),
            TankSpec::Mesh { extent, .. } => {
                let area = |k: usize| extent.parts.get(k).map_or(0.0, |p| p.1);
                vec![
                    (
                        "bottom",
                        format!(
                            "mesh group \"bottom\" and untagged triangles facing within 45° of \
                             straight down, {:.4} m²",
                            area(0)
                        ),
                    ),
                    (
                        "wall",
                        format!(
                            "mesh group \"wall\" and the other untagged triangles, {:.4} m²",
                            area(1)
                        ),
                    ),
                    (
                        "roof",
                        format!(
                            "mesh group \"roof\" and untagged triangles facing within 45° of \
                             straight up, {:.4} m²",
                            area(2)
                        ),
                    ),
                ]
            }
            TankSpec::Box { roof, .. } => vec![
                ("bottom", "the floor".into()),
                ("wall", "the four side walls".into()),
                (
                    "roof",
                    if *roof {
                        "the flat roof".into()
                    } else {
                        none()
                    },
                ),
            ],
        }
    }

    /// The 2D tank built by [`SectionTank2`]: a rectangle with a cone, dome or polyline roof,
    /// a polygon or a circle; `None` for the flat-roofed or open rectangle (built by
    /// `RectTank2`) and the 3D tanks. Errors for a roof shape with the paper layout.
    pub fn section_tank(&self) -> Result<Option<SectionTank2>, String> {
        // a flat-roofed rectangle with solids: the roof as a straight polyline
        let flat;
        let (shape, depth, tilt, tilt_shape, solids) = match self {
            TankSpec::Rect {
                roof: false,
                solids,
                ..
            } if !solids.is_empty() => {
                return Err(
                    "tank: internal solids need a closed 2D section: give the rectangle a roof \
                     (roof: \"flat\", \"cone\", …) or use shape \"polygon\""
                        .into(),
                )
            }
            TankSpec::Rect {
                roof: false, parts, ..
            } if !parts.is_empty() => {
                return Err(
                    "tank: parts of a rectangle need a closed 2D section: give the rectangle a \
                     roof (roof: \"flat\", \"cone\", …) or use shape \"polygon\" with parts \
                     by side"
                        .into(),
                )
            }
            TankSpec::Rect {
                width,
                height,
                depth,
                roof: true,
                roof_shape,
                layout,
                tilt,
                tilt_shape,
                solids,
                parts: _,
            } if roof_shape.is_some() || !solids.is_empty() || self.has_named_parts() => {
                let roof = match roof_shape {
                    Some(roof) => roof,
                    None => {
                        flat = SectionRoofSpec::Outline(vec![[*width, *height], [0.0, *height]]);
                        &flat
                    }
                };
                if layout != "offset" {
                    return Err(format!(
                        "tank: layout \"{layout}\" is for flat or open roofs without solids; a \
                         cone, dome or polyline roof, internal solids or parts use the offset \
                         layout"
                    ));
                }
                let roof = match roof {
                    SectionRoofSpec::Cone { rise } => SectionRoof::Cone { apex_height: *rise },
                    SectionRoofSpec::Dome { rise } => SectionRoof::Dome { rise: *rise },
                    SectionRoofSpec::Outline(points) => SectionRoof::Outline(points.clone()),
                };
                let shape = SectionShape::RoofedRect {
                    width: *width,
                    wall_height: *height,
                    roof,
                };
                (shape, depth, tilt, tilt_shape, solids)
            }
            TankSpec::Section {
                outline,
                depth,
                tilt,
                tilt_shape,
                solids,
                ..
            } => {
                let shape = match outline {
                    SectionOutlineSpec::Polygon(points) => SectionShape::Polygon(points.clone()),
                    SectionOutlineSpec::Circle { radius } => {
                        SectionShape::Circle { radius: *radius }
                    }
                };
                (shape, depth, tilt, tilt_shape, solids)
            }
            _ => return Ok(None),
        };
        let mut tank = SectionTank2::new(shape, *depth)
            .with_initial_tilt(*tilt)
            .with_initial_shape(InitialSurface::from_name(tilt_shape).unwrap_or_default());
        for s in solids {
            tank = tank.with_solid(s.clone());
        }
        match self {
            TankSpec::Section {
                parts, arc_parts, ..
            } => {
                for (name, [first, last]) in parts {
                    tank = tank.with_named_sides(name, *first, *last);
                }
                for (name, [first, last]) in arc_parts {
                    tank = tank.with_named_arc(name, *first, *last);
                }
            }
            TankSpec::Rect { parts, .. } => {
                for (name, pieces) in parts {
                    let pieces: Vec<RectPiece> = pieces
                        .iter()
                        .filter_map(|p| RectPiece::from_name(p))
                        .collect();
                    tank = tank.with_named_pieces(name, &pieces);
                }
            }
            _ => {}
        }
        Ok(Some(tank))
    }

    /// Whether the user named parts of the tank's outline (`parts`).
    fn has_named_parts(&self) -> bool {
        match self {
            TankSpec::Rect { parts, .. } => !parts.is_empty(),
            TankSpec::Section {
                parts, arc_parts, ..
            } => !parts.is_empty() || !arc_parts.is_empty(),
            _ => false,
        }
    }

    /// Parses and checks a `tank(#{…})` map: unknown keys, and the outline or roof of a 2D
    /// section (simple, closed, from wall top to wall top).
    pub(crate) fn from_map_checked(map: &Map) -> Result<TankSpec, String> {
        let spec = TankSpec::from_map(map)?;
        if let Some(section) = spec.section_tank()? {
            section.check_shape().map_err(|e| e.to_string())?;
        }
        Ok(spec)
    }

    pub(crate) fn from_map(map: &Map) -> Result<TankSpec, String> {
        let mut r = MapReader::new("tank", map);
        let shape = r.str_or("shape", "rect")?;
        let spec = match shape.as_str() {
            "rect" | "rectangle" => {
                let (roof, roof_shape) = section_roof(&mut r)?;
                TankSpec::Rect {
                    width: r.f64_or("width", 1.0)?,
                    height: r.f64_or("height", 1.0)?,
                    depth: r.f64_or("depth", 0.5)?,
                    roof,
                    roof_shape,
                    layout: r.str_or("layout", "offset")?,
                    tilt: r.f64_or("tilt", 0.0)?,
                    tilt_shape: tilt_shape(&mut r)?,
                    solids: read_solids(&mut r)?,
                    parts: read_piece_parts(&mut r)?,
                }
            }
            "polygon" => TankSpec::Section {
                outline: SectionOutlineSpec::Polygon(r.opt_points("outline")?.ok_or(
                    "tank: a polygon needs 'outline', a list of [x, y] points (m) around the interior",
                )?),
                depth: r.f64_or("depth", 0.5)?,
                tilt: r.f64_or("tilt", 0.0)?,
                tilt_shape: tilt_shape(&mut r)?,
                solids: read_solids(&mut r)?,
                parts: read_parts(&mut r)?,
                arc_parts: Vec::new(),
            },
            "circle" => TankSpec::Section {
                outline: SectionOutlineSpec::Circle {
                    radius: r.f64_or("radius", 0.5)?,
                },
                depth: r.f64_or("depth", 0.5)?,
                tilt: r.f64_or("tilt", 0.0)?,
                tilt_shape: tilt_shape(&mut r)?,
                solids: read_solids(&mut r)?,
                parts: Vec::new(),
                arc_parts: read_arc_parts(&mut r)?,
            },
            "cylinder" => {
                let (radius, height, depth) = (
                    r.f64_or("radius", 0.5)?,
                    r.f64_or("height", 0.6)?,
                    r.f64_or("depth", 0.5)?,
                );
                let (roof, roof_rise) = (r.str_or("roof", "flat")?, r.f64_or("roof_rise", 0.1)?);
                let (tilt, tilt_shape) = (r.f64_or("tilt", 0.0)?, tilt_shape(&mut r)?);
                let solids = read_solids_3d(&mut r)?;
                let lattice = cylinder_lattice(&mut r, &roof, &solids)?;
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
                }
            }
            "box" => TankSpec::Box {
                length: r.f64_or("length", 1.0)?,
                breadth: r.f64_or("breadth", 0.1)?,
                height: r.f64_or("height", 1.0)?,
                depth: r.f64_or("depth", 0.5)?,
                roof: r.bool_or("roof", true)?,
                tilt: r.f64_or("tilt", 0.0)?,
                tilt_shape: tilt_shape(&mut r)?,
                solids: read_solids_3d(&mut r)?,
            },
            "sphere" => TankSpec::Sphere {
                radius: r.f64_or("radius", 0.5)?,
                depth: r.f64_or("depth", 0.5)?,
                tilt: r.f64_or("tilt", 0.0)?,
                tilt_shape: tilt_shape(&mut r)?,
            },
            "mesh" => {
                let mesh = r.str_or("mesh", "")?;
                let lower = mesh.to_ascii_lowercase();
                if !(lower.ends_with(".obj") || lower.ends_with(".stl")) {
                    return Err(format!(
                        "tank: a mesh tank needs 'mesh', an .obj or .stl file of the whole \
                         interior next to the script (got \"{mesh}\")"
                    ));
                }
                TankSpec::Mesh {
                    mesh,
                    depth: r.f64_or("depth", 0.5)?,
                    tilt: r.f64_or("tilt", 0.0)?,
                    tilt_shape: tilt_shape(&mut r)?,
                    solids: read_solids_3d(&mut r)?,
                    extent: MeshExtent::default(),
                }
            }
            other => {
                return Err(format!(
                    "tank: unknown shape \"{other}\" (use \"rect\", \"polygon\", \"circle\", \"cylinder\", \"box\", \"sphere\" or \"mesh\")"
                ))
            }
        };
        r.finish()?;
        Ok(spec)
    }
}

/// Run control: times and output intervals.
#[derive(Clone, Debug, Serialize)]
pub struct RunSpec {
    /// Settling time with gravity only before the excitation starts (s).
    pub settle: f64,
    /// Total simulated time, settling included (s).
    pub duration: f64,
    /// Interval of the rows of `series.csv` (s).
    pub output_interval: f64,
    /// Interval of particle frames (s); 0 = no frames.
    pub frame_interval: f64,
    /// Cut-off of the low-pass filter of the `*_lp` load columns (Hz); `None` = ten times
    /// the tank's first sloshing frequency.
    pub load_filter_hz: Option<f64>,
    /// Damping ratio ζ_r of the roof oscillator of the roof load spectrum (1).
    pub roof_damping: f64,
    /// Roof periods T_r at which `summary.ron` gives the equivalent static roof load (s).
    pub roof_periods: Vec<f64>,
    /// The unit axis `fn ground_rotation(t)` turns the tank about, `[x, y, z]`; `None`: y (a
    /// positive angle lowers the +x wall; a 2D tank turns about y only).
    pub rotation_axis: Option<[f64; 3]>,
    /// The pivot the tank turns about, in the tank's coordinates (`[x, z]` in 2D, `[x, y, z]`
    /// in 3D, m); `None`: the centre of the tank's base.
    pub rotation_pivot: Option<Vec<f64>>,
}

/// Reads `rotation_axis`: `"x"`, `"y"`, `"z"` or a list of three numbers (made unit).
fn rotation_axis(r: &mut MapReader) -> Result<Option<[f64; 3]>, String> {
    let Some(d) = r.get("rotation_axis") else {
        return Ok(None);
    };
    if d.is_string() {
        let name = d.clone().into_string().unwrap_or_default();
        return match name.as_str() {
            "x" => Ok(Some([1.0, 0.0, 0.0])),
            "y" => Ok(Some([0.0, 1.0, 0.0])),
            "z" => Ok(Some([0.0, 0.0, 1.0])),
            _ => Err(format!(
                "run: unknown rotation_axis \"{name}\" (use \"x\", \"y\", \"z\" or [nx, ny, nz])"
            )),
        };
    }
    let v = r.opt_numbers("rotation_axis")?.unwrap_or_default();
    let norm = v.iter().map(|a| a * a).sum::<f64>().sqrt();
    if v.len() != 3 || !(norm.is_finite() && norm > 0.0) {
        return Err(format!(
            "run: rotation_axis must be \"x\", \"y\", \"z\" or three numbers not all zero \
             (got {d})"
        ));
    }
    Ok(Some([v[0] / norm, v[1] / norm, v[2] / norm]))
}

impl RunSpec {
    pub(crate) fn from_map(map: &Map) -> Result<RunSpec, String> {
        let mut r = MapReader::new("run", map);
        let spec = RunSpec {
            settle: r.f64_or("settle", 2.0)?,
            duration: r.f64_or("duration", 12.0)?,
            output_interval: r.f64_or("output_interval", 0.01)?,
            frame_interval: r.f64_or("frame_interval", 0.0)?,
            load_filter_hz: r.opt_f64("load_filter_hz")?,
            roof_damping: r.f64_or("roof_damping", DEFAULT_ROOF_DAMPING)?,
            roof_periods: r
                .opt_numbers("roof_periods")?
                .unwrap_or_else(|| DEFAULT_ROOF_PERIODS.to_vec()),
            rotation_axis: rotation_axis(&mut r)?,
            rotation_pivot: r.opt_numbers("rotation_pivot")?,
        };
        r.finish()?;
        if !(spec.roof_damping.is_finite() && (0.0..1.0).contains(&spec.roof_damping)) {
            return Err(format!(
                "run: roof_damping must be a damping ratio ≥ 0 and < 1 (got {}); 0.02 is 2 % of \
                 critical",
                spec.roof_damping
            ));
        }
        if spec.roof_periods.len() > MAX_ROOF_PERIODS {
            return Err(format!(
                "run: roof_periods lists {} periods; at most {MAX_ROOF_PERIODS}",
                spec.roof_periods.len()
            ));
        }
        let tags: Vec<String> = spec
            .roof_periods
            .iter()
            .map(|&t| slosh_run::roof_load::period_tag(t))
            .collect();
        if let Some(k) = (1..tags.len()).find(|&k| tags[..k].contains(&tags[k])) {
            return Err(format!(
                "run: roof_periods lists {} s twice",
                spec.roof_periods[k]
            ));
        }
        if let Some(t) = spec
            .roof_periods
            .iter()
            .find(|t| !(t.is_finite() && **t >= 1e-4 && **t <= 100.0))
        {
            return Err(format!(
                "run: roof_periods must be natural periods of the roof between 0.0001 and 100 s \
                 (got {t})"
            ));
        }
        if !(spec.duration.is_finite() && spec.duration > 0.0) {
            return Err(format!(
                "run: duration must be > 0 s (got {})",
                spec.duration
            ));
        }
        if !(spec.settle.is_finite() && spec.settle >= 0.0) {
            return Err(format!("run: settle must be ≥ 0 s (got {})", spec.settle));
        }
        if !(spec.output_interval.is_finite() && spec.output_interval > 0.0) {
            return Err(format!(
                "run: output_interval must be > 0 s (got {})",
                spec.output_interval
            ));
        }
        if !(spec.frame_interval.is_finite() && spec.frame_interval >= 0.0) {
            return Err(format!(
                "run: frame_interval must be ≥ 0 s (got {})",
                spec.frame_interval
            ));
        }
        if let Some(f) = spec.load_filter_hz {
            if !(f.is_finite() && f > 0.0) {
                return Err(format!(
                    "run: load_filter_hz must be a cut-off frequency > 0 Hz (got {f}); leave it \
                     out for ten times the first sloshing frequency"
                ));
            }
        }
        Ok(spec)
    }
}

impl Default for RunSpec {
    fn default() -> Self {
        RunSpec {
            settle: 2.0,
            duration: 12.0,
            output_interval: 0.01,
            frame_interval: 0.0,
            load_filter_hz: None,
            roof_damping: DEFAULT_ROOF_DAMPING,
            roof_periods: DEFAULT_ROOF_PERIODS.to_vec(),
            rotation_axis: None,
            rotation_pivot: None,
        }
    }
}

/// Most roof periods a script may list (each is one column per impact and per sweep row).
pub const MAX_ROOF_PERIODS: usize = 32;

pub use slosh_run::roof_load::{DEFAULT_ROOF_DAMPING, DEFAULT_ROOF_PERIODS};
/// A pressure sensor on the roof, as the run loop measures it.
pub use slosh_run::PressureSensor as PressureSensorSpec;

/// An extra wave gauge: the free-surface elevation on a vertical line.
#[derive(Clone, Debug, Serialize)]
pub struct GaugeSpec {
    /// Column name in `series.csv` (`eta_<name>`).
    pub name: String,
    /// Horizontal coordinates (x in 2D; x, y in 3D), m.
    pub horizontal: Vec<f64>,
}

/// How fine the particles are, as the script says it.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum Resolution {
    /// Lattice spacing dx (m).
    Spacing(f64),
    /// Particles across the still depth: dx = depth / n.
    PerDepth(f64),
    /// Particles across a cylinder's radius: dx = R / n.
    PerRadius(f64),
}

impl Resolution {
    /// The lattice spacing (m) for `tank`.
    pub fn spacing_for(&self, tank: &TankSpec) -> Result<f64, String> {
        let n_ok = |n: f64, key: &str| {
            if n.is_finite() && n >= 1.0 {
                Ok(n)
            } else {
                Err(format!("numerics: {key} must be a number ≥ 1 (got {n})"))
            }
        };
        match *self {
            Resolution::Spacing(dx) => Ok(dx),
            Resolution::PerDepth(n) => Ok(tank.depth() / n_ok(n, "particles_per_depth")?),
            Resolution::PerRadius(n) => match tank {
                TankSpec::Cylinder { radius, .. } => Ok(radius / n_ok(n, "particles_per_radius")?),
                _ => Err("numerics: particles_per_radius is for cylinders; use \
                          particles_per_depth or dx for this tank"
                    .into()),
            },
        }
    }
}

/// Reads `numerics(#{...})` into solver parameters, starting from the scheme preset.
/// Returns the parameters, the scheme name and the resolution.
pub(crate) fn numerics_from_map(map: &Map) -> Result<(SphParams, String, Resolution), String> {
    let mut r = MapReader::new("numerics", map);
    let scheme = r.choice_or(
        "scheme",
        "paper",
        &[(&["paper"], "paper"), (&["modern"], "modern")],
    )?;
    let mut p = if scheme == "modern" {
        SphParams::modern()
    } else {
        SphParams::paper()
    };
    let scheme = scheme.to_string();
    let resolution = match (
        r.opt_f64("dx")?,
        r.opt_f64("particles_per_depth")?,
        r.opt_f64("particles_per_radius")?,
    ) {
        (None, None, None) => Resolution::Spacing(0.02),
        (Some(dx), None, None) => Resolution::Spacing(dx),
        (None, Some(n), None) => Resolution::PerDepth(n),
        (None, None, Some(n)) => Resolution::PerRadius(n),
        _ => {
            return Err(
                "numerics: give one of dx, particles_per_depth and particles_per_radius".into(),
            )
        }
    };
    p.smoothing_ratio = r.f64_or("h_over_dx", p.smoothing_ratio)?;
    p.kernel = r.choice_or(
        "kernel",
        kernel_name(p.kernel),
        &[
            (&["cubic_spline", "cubic"], KernelKind::CubicSpline),
            (&["wendland_c2", "wendland"], KernelKind::WendlandC2),
        ],
    )?;
    p.rest_density = r.f64_or("rest_density", p.rest_density)?;
    p.dynamic_viscosity = r.f64_or("viscosity", p.dynamic_viscosity)?;
    read_sound_speed(&mut r, &mut p)?;
    p.eos_gamma = r.f64_or("eos_gamma", p.eos_gamma)?;
    p.av_alpha = r.f64_or("av_alpha", p.av_alpha)?;
    p.av_beta = r.f64_or("av_beta", p.av_beta)?;
    p.av_eta = r.f64_or("av_eta", p.av_eta)?;
    if let Some(c) = r.opt_f64("av_sound_speed")? {
        if !(c.is_finite() && c >= 0.0) {
            return Err(format!(
                "numerics: av_sound_speed must be a speed ≥ 0 m/s (0 = Eq. 17), got {c}"
            ));
        }
        p.av_sound_speed = if c > 0.0 {
            ArtificialSoundSpeed::Fixed(c)
        } else {
            ArtificialSoundSpeed::Eq17
        };
    }
    p.free_surface_threshold = r.f64_or("free_surface_threshold", p.free_surface_threshold)?;
    p.clamp_negative_pressure = r.bool_or("clamp_negative_pressure", p.clamp_negative_pressure)?;
    p.wall_separation = r.bool_or("wall_separation", p.wall_separation)?;
    p.gravity = r.f64_or("gravity", p.gravity)?;
    if !(p.gravity.is_finite() && p.gravity > 0.0) {
        // The still level, the sound speed from the tank, the settling and every closed form
        // are built on g > 0 (the vertical axis points up, gravity down).
        return Err(format!(
            "numerics: gravity is the magnitude of g, downwards, and must be a positive number \
             of m/s² (e.g. 9.81), got {}",
            p.gravity
        ));
    }
    p.cfl_number = r.f64_or("cfl_number", p.cfl_number)?;
    let dt = r.f64_or("dt", p.fixed_dt.unwrap_or(0.0))?;
    p.fixed_dt = if dt > 0.0 { Some(dt) } else { None };
    if dt < 0.0 || !dt.is_finite() {
        return Err(format!(
            "numerics: dt must be ≥ 0 s (0 = CFL-variable), got {dt}"
        ));
    }
    p.allow_unstable_dt = r.bool_or("allow_unstable_dt", p.allow_unstable_dt)?;
    p.neighbour_backend = r.choice_or(
        "neighbour_search",
        "grid",
        &[
            (&["grid", "cell_grid"], NeighbourBackend::CellGrid),
            (&["kdtree", "kd_tree"], NeighbourBackend::KdTree),
        ],
    )?;
    p.reorder_interval = r.usize_or("reorder_interval", p.reorder_interval)?;
    p.wall_pressure = r.choice_or(
        "wall_pressure",
        wall_pressure_name(p.wall_pressure),
        &[
            (&["nearest_fluid"], WallPressureMethod::NearestFluid),
            (
                &["kernel_extrapolation"],
                WallPressureMethod::KernelExtrapolation,
            ),
            (&["wall_particle"], WallPressureMethod::WallParticle),
        ],
    )?;
    p.density = r.choice_or(
        "density",
        density_name(p.density),
        &[
            (&["summation"], DensityMethod::Summation),
            (&["continuity"], DensityMethod::Continuity),
        ],
    )?;
    let (diffusion_default, delta_default) = match p.density_diffusion {
        DensityDiffusion::None => ("none", 0.1),
        DensityDiffusion::MolteniColagrossi { delta } => ("molteni_colagrossi", delta),
        DensityDiffusion::Fourtakas { delta } => ("fourtakas", delta),
    };
    let delta = r.f64_or("delta", delta_default)?;
    if !(delta.is_finite() && delta >= 0.0) {
        return Err(format!(
            "numerics: delta must be a number ≥ 0 (got {delta})"
        ));
    }
    p.density_diffusion = r.choice_or(
        "density_diffusion",
        diffusion_default,
        &[
            (&["none"], DensityDiffusion::None),
            (
                &["molteni_colagrossi", "molteni"],
                DensityDiffusion::MolteniColagrossi { delta },
            ),
            (&["fourtakas"], DensityDiffusion::Fourtakas { delta }),
        ],
    )?;
    p.boundary = r.choice_or(
        "boundary",
        boundary_name(p.boundary),
        &[
            (&["dynamic"], BoundaryMethod::Dynamic),
            (&["adami"], BoundaryMethod::Adami),
        ],
    )?;
    p.wall_no_slip = r.bool_or("wall_no_slip", p.wall_no_slip)?;
    p.integrator = r.choice_or(
        "integrator",
        integrator_name(p.integrator),
        &[
            (&["leapfrog", "leap_frog"], Integrator::LeapFrog),
            (&["symplectic"], Integrator::Symplectic),
        ],
    )?;
    let shifting = r.f64_or("shifting", p.shifting.unwrap_or(0.0))?;
    if !(shifting.is_finite() && shifting >= 0.0) {
        return Err(format!(
            "numerics: shifting must be a coefficient ≥ 0 (0 = off), got {shifting}"
        ));
    }
    p.shifting = if shifting > 0.0 { Some(shifting) } else { None };
    p.pair_scheme = r.choice_or(
        "pair_scheme",
        pair_scheme_name(p.pair_scheme),
        &[
            (&["standard"], PairScheme::Standard),
            (&["riemann"], PairScheme::Riemann),
        ],
    )?;
    // The single-sum operator is a term of the standard pair against Adami walls: a script
    // that picks the Riemann pair or dynamic walls without naming the operator gets the
    // strain-rate one, which goes with every pair and wall.
    let operator_default =
        if p.pair_scheme == PairScheme::Standard && p.boundary == BoundaryMethod::Adami {
            p.viscous_operator
        } else {
            ViscousOperator::StrainRate
        };
    p.viscous_operator = r.choice_or(
        "viscous_operator",
        viscous_operator_name(operator_default),
        &[
            (&["strain_rate"], ViscousOperator::StrainRate),
            (&["monaghan_cleary"], ViscousOperator::MonaghanCleary),
        ],
    )?;
    let backend = r.str_or("backend", "cpu")?;
    p.backend = Backend::from_name(&backend).ok_or_else(|| {
        format!("numerics: unknown backend \"{backend}\" (use \"cpu\", \"gpu\" or \"gpu_f32\")")
    })?;
    p.pressure_smoothing_eps = r.f64_or("smoothing_eps", p.pressure_smoothing_eps)?;
    p.smoothing_steps = r.usize_or("smoothing_steps", p.smoothing_steps)?;
    r.finish()?;
    Ok((p, scheme, resolution))
}

/// Reads the EOS stiffness keys: `eos_b` (B, Pa), `sound_speed` (c0, m/s) or
/// `sound_speed_coefficient` (k of c0 = max(k √(g H_ref), 10 U_ref)); at most one of them.
/// Without any, c0 follows the tank with k = 10. `allow_compressible` lifts the refusal of a
/// stiffness that squeezes the still liquid by more than 3 %.
fn read_sound_speed(r: &mut MapReader, p: &mut SphParams) -> Result<(), String> {
    let eos_b = r.opt_f64("eos_b")?;
    let c0 = r.opt_f64("sound_speed")?;
    let k = r.opt_f64("sound_speed_coefficient")?;
    p.sound_speed = match (eos_b, c0, k) {
        (None, None, None) => p.sound_speed,
        (Some(b), None, None) => {
            if !(b.is_finite() && b > 0.0) {
                return Err(format!(
                    "numerics: eos_b must be a positive number of Pa (got {b})"
                ));
            }
            p.eos_stiffness = b;
            SoundSpeedRule::Stiffness
        }
        (None, Some(c), None) => {
            if !(c.is_finite() && c > 0.0) {
                return Err(format!(
                    "numerics: sound_speed must be a positive number of m/s (got {c})"
                ));
            }
            SoundSpeedRule::Fixed(c)
        }
        (None, None, Some(k)) => {
            if !(k.is_finite() && k > 0.0) {
                return Err(format!(
                    "numerics: sound_speed_coefficient must be a positive number (got {k})"
                ));
            }
            SoundSpeedRule::FromCase {
                coefficient: k,
                flow_speed: 0.0,
            }
        }
        _ => {
            return Err("numerics: give at most one of eos_b, sound_speed and \
                        sound_speed_coefficient (they all set the EOS stiffness)"
                .into())
        }
    };
    p.allow_compressible = r.bool_or("allow_compressible", p.allow_compressible)?;
    Ok(())
}

fn density_name(d: DensityMethod) -> &'static str {
    match d {
        DensityMethod::Summation => "summation",
        DensityMethod::Continuity => "continuity",
    }
}

fn boundary_name(b: BoundaryMethod) -> &'static str {
    match b {
        BoundaryMethod::Dynamic => "dynamic",
        BoundaryMethod::Adami => "adami",
    }
}

fn pair_scheme_name(s: PairScheme) -> &'static str {
    match s {
        PairScheme::Standard => "standard",
        PairScheme::Riemann => "riemann",
    }
}

fn viscous_operator_name(v: ViscousOperator) -> &'static str {
    match v {
        ViscousOperator::StrainRate => "strain_rate",
        ViscousOperator::MonaghanCleary => "monaghan_cleary",
    }
}

fn integrator_name(i: Integrator) -> &'static str {
    match i {
        Integrator::LeapFrog => "leapfrog",
        Integrator::Symplectic => "symplectic",
    }
}

fn kernel_name(k: KernelKind) -> &'static str {
    match k {
        KernelKind::CubicSpline => "cubic_spline",
        KernelKind::WendlandC2 => "wendland_c2",
    }
}

fn wall_pressure_name(m: WallPressureMethod) -> &'static str {
    match m {
        WallPressureMethod::NearestFluid => "nearest_fluid",
        WallPressureMethod::KernelExtrapolation => "kernel_extrapolation",
        WallPressureMethod::WallParticle => "wall_particle",
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use slosh_geometry::PartRange;

    fn numerics(pairs: &[(&str, Dynamic)]) -> Result<(SphParams, String, Resolution), String> {
        let mut map = Map::new();
        for (k, v) in pairs {
            map.insert((*k).into(), v.clone());
        }
        numerics_from_map(&map)
    }

    #[test]
    fn a_name_outside_the_choices_is_refused_with_the_choices() {
        let err = numerics(&[("kernel", "gaussian".into())]).unwrap_err();
        assert_eq!(
            err,
            "numerics: unknown kernel \"gaussian\" (use \"cubic_spline\" or \"wendland_c2\")"
        );
        let err = numerics(&[("wall_pressure", "mirror".into())]).unwrap_err();
        assert_eq!(
            err,
            "numerics: unknown wall_pressure \"mirror\" (use \"nearest_fluid\", \
             \"kernel_extrapolation\" or \"wall_particle\")"
        );
        // Another name of a choice is accepted; a choice's value is what it stands for.
        let (p, _, _) = numerics(&[
            ("kernel", "wendland".into()),
            ("density_diffusion", "molteni".into()),
            ("delta", 0.05.into()),
        ])
        .unwrap();
        assert_eq!(p.kernel, KernelKind::WendlandC2);
        assert_eq!(
            p.density_diffusion,
            DensityDiffusion::MolteniColagrossi { delta: 0.05 }
        );
        let err = numerics(&[("scheme", "dualsphysics".into())]).unwrap_err();
        assert!(err.contains("(use \"paper\" or \"modern\")"), "{err}");
    }

    /// A cylinder's lattice left out is the polar one where it applies (built-in roof, no
    /// solids) and the cubic one for a mesh roof or solids; one named is kept.
    #[test]
    fn a_cylinder_takes_the_polar_lattice_where_it_applies() {
        let lattice = |extra: &[(&str, Dynamic)]| {
            let mut map = Map::new();
            map.insert("shape".into(), "cylinder".into());
            for (k, v) in extra {
                map.insert((*k).into(), v.clone());
            }
            match TankSpec::from_map(&map).unwrap() {
                TankSpec::Cylinder { lattice, .. } => lattice,
                other => panic!("not a cylinder: {other:?}"),
            }
        };
        assert_eq!(lattice(&[]), "polar");
        for roof in ["none", "flat", "cone", "dome"] {
            assert_eq!(lattice(&[("roof", roof.into())]), "polar", "{roof}");
        }
        assert_eq!(lattice(&[("roof", "roof.obj".into())]), "cubic");
        let mut column = Map::new();
        for (k, v) in [
            ("name", Dynamic::from("column")),
            ("shape", "column".into()),
            (
                "centre",
                Dynamic::from(vec![Dynamic::from(0.0), Dynamic::from(0.0)]),
            ),
            ("radius", 0.05.into()),
            ("bottom", 0.0.into()),
            ("top", 0.6.into()),
        ] {
            column.insert(k.into(), v);
        }
        let solids = Dynamic::from(vec![Dynamic::from(column)]);
        assert_eq!(lattice(&[("solids", solids)]), "cubic");
        assert_eq!(lattice(&[("lattice", "cubic".into())]), "cubic");
        assert_eq!(lattice(&[("lattice", "polar".into())]), "polar");
    }

    #[test]
    fn modern_scheme_keys() {
        let (p, scheme, _) = numerics(&[("scheme", "modern".into())]).unwrap();
        assert_eq!(scheme, "modern");
        assert_eq!(p.density, DensityMethod::Continuity);
        assert_eq!(
            p.density_diffusion,
            DensityDiffusion::Fourtakas { delta: 0.1 }
        );
        assert_eq!(p.boundary, BoundaryMethod::Adami);
        assert_eq!(p.integrator, Integrator::Symplectic);
        assert_eq!(p.kernel, KernelKind::WendlandC2);
        assert_eq!(p.smoothing_ratio, 2.0);
        assert_eq!(p.viscous_operator, ViscousOperator::MonaghanCleary);
        assert!(!p.clamp_negative_pressure);
        assert_eq!(p.shifting, None);
        // Switched back part by part.
        let (p, _, _) = numerics(&[
            ("scheme", "modern".into()),
            ("density", "summation".into()),
            ("density_diffusion", "molteni_colagrossi".into()),
            ("delta", Dynamic::from(0.05)),
            ("boundary", "dynamic".into()),
            ("integrator", "leapfrog".into()),
            ("shifting", Dynamic::from(2.0)),
        ])
        .unwrap();
        assert_eq!(p.density, DensityMethod::Summation);
        assert_eq!(
            p.density_diffusion,
            DensityDiffusion::MolteniColagrossi { delta: 0.05 }
        );
        assert_eq!(p.boundary, BoundaryMethod::Dynamic);
        assert_eq!(p.integrator, Integrator::LeapFrog);
        assert_eq!(p.shifting, Some(2.0));
        assert_eq!(p.pair_scheme, PairScheme::Standard);
        // Dynamic walls take the strain-rate operator, which goes with them.
        assert_eq!(p.viscous_operator, ViscousOperator::StrainRate);
        let (p, _, _) = numerics(&[
            ("scheme", "modern".into()),
            ("pair_scheme", "riemann".into()),
        ])
        .unwrap();
        assert_eq!(p.pair_scheme, PairScheme::Riemann);
        assert_eq!(p.viscous_operator, ViscousOperator::StrainRate);
        let (p, _, _) = numerics(&[
            ("scheme", "modern".into()),
            ("viscous_operator", "strain_rate".into()),
        ])
        .unwrap();
        assert_eq!(p.viscous_operator, ViscousOperator::StrainRate);
        // The paper scheme is SphParams::default().
        let (p, _, _) = numerics(&[]).unwrap();
        assert!(!p.uses_modern_step());
    }

    #[test]
    fn sound_speed_and_resolution_keys() {
        let (p, _, r) = numerics(&[]).unwrap();
        assert_eq!(p.sound_speed, SoundSpeedRule::DEFAULT);
        assert_eq!(r, Resolution::Spacing(0.02));
        let (p, _, _) = numerics(&[("eos_b", Dynamic::from(1.013e5))]).unwrap();
        assert_eq!(p.sound_speed, SoundSpeedRule::Stiffness);
        assert_eq!(p.eos_stiffness, 1.013e5);
        let (p, _, _) = numerics(&[("sound_speed", Dynamic::from(50.0))]).unwrap();
        assert_eq!(p.sound_speed, SoundSpeedRule::Fixed(50.0));
        let (p, _, r) = numerics(&[
            ("sound_speed_coefficient", Dynamic::from(15.0)),
            ("particles_per_depth", Dynamic::from(20_i64)),
        ])
        .unwrap();
        assert_eq!(
            p.sound_speed,
            SoundSpeedRule::FromCase {
                coefficient: 15.0,
                flow_speed: 0.0
            }
        );
        assert_eq!(r, Resolution::PerDepth(20.0));
        for bad in [
            vec![
                ("eos_b", Dynamic::from(1e5)),
                ("sound_speed", Dynamic::from(20.0)),
            ],
            vec![
                ("dx", Dynamic::from(0.1)),
                ("particles_per_radius", Dynamic::from(10.0)),
            ],
            vec![("eos_b", Dynamic::from(-1.0))],
            vec![("sound_speed_coefficient", Dynamic::from(0.0))],
        ] {
            assert!(numerics(&bad).is_err(), "{bad:?}");
        }
        let cylinder = TankSpec::Cylinder {
            radius: 12.0,
            height: 16.0,
            depth: 13.0,
            roof: "cone".into(),
            roof_rise: 1.5,
            tilt: 0.0,
            tilt_shape: "plane".into(),
            solids: Vec::new(),
            lattice: "cubic".into(),
        };
        assert_eq!(Resolution::PerRadius(24.0).spacing_for(&cylinder), Ok(0.5));
        assert_eq!(Resolution::PerDepth(26.0).spacing_for(&cylinder), Ok(0.5));
        let rect = TankSpec::Rect {
            roof_shape: None,
            width: 1.0,
            height: 1.0,
            depth: 0.5,
            roof: true,
            layout: "offset".into(),
            tilt: 0.0,
            tilt_shape: "plane".into(),
            solids: Vec::new(),
            parts: Vec::new(),
        };
        assert!(Resolution::PerRadius(10.0).spacing_for(&rect).is_err());
    }

    #[test]
    fn solids_and_named_parts_are_read() {
        let map = |pairs: Vec<(&str, Dynamic)>| -> Map {
            pairs.into_iter().map(|(k, v)| (k.into(), v)).collect()
        };
        let point = |x: f64, y: f64| Dynamic::from(vec![Dynamic::from(x), Dynamic::from(y)]);
        let square = Dynamic::from(vec![
            point(0.0, 0.0),
            point(1.0, 0.0),
            point(1.0, 1.0),
            point(0.0, 1.0),
        ]);
        let plate = Dynamic::from(map(vec![
            ("name", Dynamic::from("baffle")),
            ("shape", Dynamic::from("plate")),
            ("centre", point(0.5, 0.3)),
            ("length", Dynamic::from(0.4)),
            ("thickness", Dynamic::from(0.05)),
            ("angle", Dynamic::from(30_i64)),
        ]));
        let column = Dynamic::from(map(vec![
            ("name", Dynamic::from("column")),
            ("shape", Dynamic::from("circle")),
            ("centre", point(0.2, 0.2)),
            ("radius", Dynamic::from(0.05)),
        ]));
        let parts = Dynamic::from(map(vec![(
            "floor",
            Dynamic::from(vec![Dynamic::from(0_i64), Dynamic::from(0_i64)]),
        )]));
        let spec = TankSpec::from_map_checked(&map(vec![
            ("shape", Dynamic::from("polygon")),
            ("outline", square.clone()),
            ("depth", Dynamic::from(0.5)),
            ("solids", Dynamic::from(vec![plate.clone(), column])),
            ("parts", parts),
        ]))
        .unwrap();
        let tank = spec.section_tank().unwrap().unwrap();
        assert_eq!(
            tank.solids,
            vec![
                Solid2::plate("baffle", [0.5, 0.3], 0.4, 0.05, 30.0),
                Solid2::circle("column", [0.2, 0.2], 0.05)
            ]
        );
        assert_eq!(
            tank.named_parts,
            vec![("floor".to_string(), PartRange::Sides([0, 0]))]
        );
        let names: Vec<String> = spec.part_descriptions().into_iter().map(|p| p.0).collect();
        assert_eq!(
            names,
            ["bottom", "wall", "roof", "floor", "baffle", "column"]
        );
        // a flat-roofed rectangle with a solid is built as a section; an open one is refused
        let rect =
            TankSpec::from_map_checked(&map(vec![("solids", Dynamic::from(vec![plate.clone()]))]))
                .unwrap();
        assert!(rect.section_tank().unwrap().is_some());
        let err = TankSpec::from_map_checked(&map(vec![
            ("roof", Dynamic::from(false)),
            ("solids", Dynamic::from(vec![plate])),
        ]))
        .unwrap_err();
        assert!(err.contains("closed 2D section"), "{err}");
        // unknown solid shapes, missing keys and bad side ranges are named
        let cone = Dynamic::from(map(vec![
            ("name", Dynamic::from("x")),
            ("shape", Dynamic::from("cone")),
        ]));
        let err = TankSpec::from_map_checked(&map(vec![("solids", Dynamic::from(vec![cone]))]))
            .unwrap_err();
        assert!(err.contains("solids[0]") && err.contains("plate"), "{err}");
        let bad_parts = Dynamic::from(map(vec![("sump", Dynamic::from(3_i64))]));
        let err = TankSpec::from_map_checked(&map(vec![
            ("shape", Dynamic::from("polygon")),
            ("outline", square),
            ("parts", bad_parts),
        ]))
        .unwrap_err();
        assert!(err.contains("parts.sump"), "{err}");
    }

    #[test]
    fn section_roofs_and_outlines_are_read() {
        let tank = |pairs: Vec<(&str, Dynamic)>| {
            let map: Map = pairs.into_iter().map(|(k, v)| (k.into(), v)).collect();
            TankSpec::from_map_checked(&map)
        };
        let point = |x: f64, y: f64| Dynamic::from(vec![Dynamic::from(x), Dynamic::from(y)]);
        // true/false and "flat"/"none" keep the rectangle of RectTank2
        for (roof, closed) in [
            (Dynamic::from(true), true),
            (Dynamic::from(false), false),
            (Dynamic::from("flat"), true),
            (Dynamic::from("none"), false),
        ] {
            let t = tank(vec![("roof", roof)]).unwrap();
            assert!(matches!(t, TankSpec::Rect { roof, roof_shape: None, .. } if roof == closed));
            assert!(t.section_tank().unwrap().is_none());
        }
        let cone = tank(vec![
            ("roof", Dynamic::from("cone")),
            ("roof_rise", Dynamic::from(0.2)),
        ])
        .unwrap();
        let section = cone.section_tank().unwrap().unwrap();
        assert_eq!(
            section.shape,
            SectionShape::RoofedRect {
                width: 1.0,
                wall_height: 1.0,
                roof: SectionRoof::Cone { apex_height: 0.2 }
            }
        );
        let polyline = vec![point(0.0, 1.0), point(0.5, 1.2), point(1.0, 1.0)];
        let t = tank(vec![("roof", Dynamic::from(polyline))]).unwrap();
        assert!(matches!(
            t,
            TankSpec::Rect { roof_shape: Some(SectionRoofSpec::Outline(ref p)), .. } if p.len() == 3
        ));
        let circle = tank(vec![
            ("shape", Dynamic::from("circle")),
            ("radius", Dynamic::from(2.0)),
        ])
        .unwrap();
        assert_eq!(circle.dim(), 2);
        assert_eq!(circle.horizontal_size(), 4.0);
        let sphere = tank(vec![
            ("shape", Dynamic::from("sphere")),
            ("radius", Dynamic::from(2.0)),
        ])
        .unwrap();
        assert_eq!((sphere.dim(), sphere.horizontal_size()), (3, 4.0));
        assert!(sphere.section_tank().unwrap().is_none());
        // a self-intersecting outline is refused naming its sides
        let bow_tie = vec![
            point(0.0, 0.0),
            point(1.0, 1.0),
            point(1.0, 0.0),
            point(0.0, 1.0),
        ];
        let err = tank(vec![
            ("shape", Dynamic::from("polygon")),
            ("outline", Dynamic::from(bow_tie)),
        ])
        .unwrap_err();
        assert!(err.contains("side 0") && err.contains("side 2"), "{err}");
        let err = tank(vec![("shape", Dynamic::from("polygon"))]).unwrap_err();
        assert!(err.contains("outline"), "{err}");
        let err = tank(vec![("roof", Dynamic::from("pyramid"))]).unwrap_err();
        assert!(err.contains("\"pyramid\""), "{err}");
        let bad_point = vec![point(0.0, 1.0), Dynamic::from(3.0), point(1.0, 1.0)];
        let err = tank(vec![("roof", Dynamic::from(bad_point))]).unwrap_err();
        assert!(err.contains("point 1"), "{err}");
    }

    #[test]
    fn backends_are_read() {
        for (name, backend) in [
            ("cpu", Backend::Cpu),
            ("gpu", Backend::Gpu),
            ("gpu_f32", Backend::GpuF32),
        ] {
            let (p, _, _) = numerics(&[("backend", name.into())]).unwrap();
            assert_eq!(p.backend, backend);
        }
        let (p, _, _) = numerics(&[]).unwrap();
        assert_eq!(p.backend, Backend::Cpu);
    }

    #[test]
    fn unknown_values_are_reported() {
        for (key, value, hint) in [
            ("density", "sum", "continuity"),
            ("density_diffusion", "delta", "fourtakas"),
            ("boundary", "mirror", "adami"),
            ("integrator", "euler", "symplectic"),
            ("pair_scheme", "godunov", "riemann"),
            ("viscous_operator", "morris", "monaghan_cleary"),
            ("backend", "cuda", "gpu_f32"),
        ] {
            let err = numerics(&[(key, value.into())]).unwrap_err();
            assert!(err.contains(value) && err.contains(hint), "{err}");
        }
        let err = numerics(&[("delta", Dynamic::from(-1.0))]).unwrap_err();
        assert!(err.contains("delta"), "{err}");
        let err = numerics(&[("shifting", Dynamic::from(-1.0))]).unwrap_err();
        assert!(err.contains("shifting"), "{err}");
    }

    #[test]
    fn circle_and_rectangle_parts_are_read_and_checked() {
        let map = |pairs: Vec<(&str, Dynamic)>| -> Map {
            pairs.into_iter().map(|(k, v)| (k.into(), v)).collect()
        };
        let pair = |a: f64, b: f64| Dynamic::from(vec![Dynamic::from(a), Dynamic::from(b)]);
        let circle = TankSpec::from_map_checked(&map(vec![
            ("shape", Dynamic::from("circle")),
            ("radius", Dynamic::from(1.0)),
            ("depth", Dynamic::from(1.5)),
            (
                "parts",
                Dynamic::from(map(vec![("manway", pair(80.0, 100.0))])),
            ),
        ]))
        .unwrap();
        let tank = circle.section_tank().unwrap().unwrap();
        assert_eq!(
            tank.named_parts,
            vec![("manway".to_string(), PartRange::Arc([80.0, 100.0]))]
        );
        let names: Vec<String> = circle
            .part_descriptions()
            .into_iter()
            .map(|p| p.0)
            .collect();
        assert_eq!(names, ["bottom", "wall", "roof", "manway"]);
        // overlapping arcs are refused at the tank(…) call
        let err = TankSpec::from_map_checked(&map(vec![
            ("shape", Dynamic::from("circle")),
            (
                "parts",
                Dynamic::from(map(vec![("a", pair(0.0, 90.0)), ("b", pair(45.0, 135.0))])),
            ),
        ]))
        .unwrap_err();
        assert!(err.contains("already named"), "{err}");
        // a cone-roofed rectangle: a piece or a list of pieces
        let pieces = Dynamic::from(vec![Dynamic::from("left_wall"), Dynamic::from("roof_left")]);
        let rect = TankSpec::from_map_checked(&map(vec![
            ("roof", Dynamic::from("cone")),
            (
                "parts",
                Dynamic::from(map(vec![
                    ("windward", pieces),
                    ("lee_roof", Dynamic::from("roof_right")),
                ])),
            ),
        ]))
        .unwrap();
        let tank = rect.section_tank().unwrap().unwrap();
        assert_eq!(tank.named_parts.len(), 2);
        // a flat rectangle with parts is built as a section; without, as before
        let flat = TankSpec::from_map_checked(&map(vec![(
            "parts",
            Dynamic::from(map(vec![("lid", Dynamic::from("roof"))])),
        )]))
        .unwrap();
        assert!(flat.section_tank().unwrap().is_some());
        assert!(TankSpec::default().section_tank().unwrap().is_none());
        // unknown pieces are named with the list of known ones
        let err = TankSpec::from_map_checked(&map(vec![(
            "parts",
            Dynamic::from(map(vec![("lid", Dynamic::from("ceiling"))])),
        )]))
        .unwrap_err();
        assert!(
            err.contains("ceiling") && err.contains("roof_left"),
            "{err}"
        );
    }
}
