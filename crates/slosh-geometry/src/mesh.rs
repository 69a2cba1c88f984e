//! Triangle surface meshes: reading (OBJ, STL), writing (OBJ), closedness checks, and the
//! procedural meshes of the built-in tank shapes.

use std::collections::HashMap;
use std::f64::consts::PI;
use std::fmt::Write as _;
use std::path::Path;

use crate::error::GeometryError;

/// A triangle surface mesh with shared vertices (m).
///
/// A closed mesh describing a region is oriented with counter-clockwise triangles seen from
/// outside, i.e. face normals pointing out of the region (positive [`SurfaceMesh::signed_volume`]).
#[derive(Debug, Clone, Default, PartialEq)]
pub struct SurfaceMesh {
    /// Vertex positions (m).
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as indices into `vertices`.
    pub triangles: Vec<[u32; 3]>,
}

impl SurfaceMesh {
    /// Reads an OBJ (`.obj`) or STL (`.stl`, ASCII or binary) file, in metres.
    ///
    /// Polygons are split into triangle fans; vertices with identical coordinates are merged
    /// (STL stores each triangle's corners separately); degenerate triangles (a repeated vertex
    /// after merging) are dropped. Does not check closedness: see [`SurfaceMesh::check_closed`].
    pub fn read(path: &Path) -> Result<SurfaceMesh, GeometryError> {
        Ok(SurfaceMesh::read_grouped(path)?.0)
    }

    /// Parses the bytes of an OBJ or STL file, as [`SurfaceMesh::read`] does; `extension`
    /// (`obj` or `stl`, any case) chooses the format and `name` names the file in errors.
    pub fn parse(bytes: &[u8], extension: &str, name: &str) -> Result<SurfaceMesh, GeometryError> {
        Ok(SurfaceMesh::parse_grouped(bytes, extension, name)?.0)
    }

    /// Reads an OBJ or STL file as [`SurfaceMesh::read`] does, with the group of each
    /// triangle: the name of the OBJ `g` or `o` statement before it (the OBJ default group
    /// `default`, or a `g` without a name, is no group), or the name of the ASCII STL `solid`
    /// block holding it (none for a binary STL or an unnamed solid).
    pub fn read_grouped(path: &Path) -> Result<(SurfaceMesh, Vec<Option<String>>), GeometryError> {
        let name = path.display().to_string();
        let bytes = std::fs::read(path).map_err(|e| GeometryError::MeshRead {
            path: name.clone(),
            message: e.to_string(),
        })?;
        let ext = path.extension().and_then(|e| e.to_str()).unwrap_or("");
        SurfaceMesh::parse_grouped(&bytes, ext, &name)
    }

    /// [`SurfaceMesh::parse`] with the group of each triangle, as [`SurfaceMesh::read_grouped`].
    pub fn parse_grouped(
        bytes: &[u8],
        extension: &str,
        name: &str,
    ) -> Result<(SurfaceMesh, Vec<Option<String>>), GeometryError> {
        let name = name.to_string();
        let parsed = match extension.to_ascii_lowercase().as_str() {
            "obj" => parse_obj(bytes),
            "stl" => parse_stl(bytes),
            _ => Err("unknown file type: use a .obj or .stl file".into()),
        };
        let (mut mesh, groups) = parsed.map_err(|message| GeometryError::MeshRead {
            path: name.clone(),
            message,
        })?;
        let kept = mesh.merge_vertices_keeping();
        if mesh.triangles.is_empty() {
            return Err(GeometryError::MeshRead {
                path: name,
                message: "the file contains no triangles".into(),
            });
        }
        let groups = kept.into_iter().map(|k| groups[k].clone()).collect();
        Ok((mesh, groups))
    }

    /// Writes the mesh as a Wavefront OBJ file (vertices in m, 1-based faces), with `comment`
    /// lines at the top.
    pub fn write_obj(&self, path: &Path, comment: &str) -> std::io::Result<()> {
        let mut out = self.obj_head(comment);
        for t in &self.triangles {
            let _ = writeln!(out, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        std::fs::write(path, out)
    }

    /// Writes the mesh as a Wavefront OBJ file as [`SurfaceMesh::write_obj`] does, each run of
    /// triangles of one group after a `g <name>` line (`groups`: one entry per triangle; `None`
    /// writes `g default`, the OBJ default group).
    pub fn write_obj_grouped(
        &self,
        path: &Path,
        comment: &str,
        groups: &[Option<String>],
    ) -> std::io::Result<()> {
        let mut out = self.obj_head(comment);
        let mut current: Option<Option<&String>> = None;
        for (k, t) in self.triangles.iter().enumerate() {
            let g = groups.get(k).and_then(|g| g.as_ref());
            if current != Some(g) {
                let _ = writeln!(out, "g {}", g.map_or("default", |s| s.as_str()));
                current = Some(g);
            }
            let _ = writeln!(out, "f {} {} {}", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        std::fs::write(path, out)
    }

    /// The start of an OBJ file: `comment` as `#` lines, then the `v` lines of the vertices.
    fn obj_head(&self, comment: &str) -> String {
        let mut out = String::new();
        for line in comment.lines() {
            let _ = writeln!(out, "# {line}");
        }
        for v in &self.vertices {
            let _ = writeln!(
                out,
                "v {} {} {}",
                fmt_coord(v[0]),
                fmt_coord(v[1]),
                fmt_coord(v[2])
            );
        }
        out
    }

    /// Merges vertices with bit-identical coordinates and drops triangles that become degenerate.
    pub fn merge_duplicate_vertices(&mut self) {
        self.merge_vertices_keeping();
    }

    /// [`SurfaceMesh::merge_duplicate_vertices`], returning the former index of each kept
    /// triangle.
    fn merge_vertices_keeping(&mut self) -> Vec<usize> {
        let mut map: HashMap<[u64; 3], u32> = HashMap::with_capacity(self.vertices.len());
        let mut new_vertices = Vec::with_capacity(self.vertices.len());
        let mut remap = Vec::with_capacity(self.vertices.len());
        for v in &self.vertices {
            let key = v.map(|c| if c == 0.0 { 0u64 } else { c.to_bits() });
            let id = *map.entry(key).or_insert_with(|| {
                new_vertices.push(*v);
                (new_vertices.len() - 1) as u32
            });
            remap.push(id);
        }
        self.vertices = new_vertices;
        let mut triangles = Vec::with_capacity(self.triangles.len());
        let mut kept = Vec::with_capacity(self.triangles.len());
        for (k, t) in self.triangles.iter().enumerate() {
            let t = t.map(|i| remap[i as usize]);
            if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                triangles.push(t);
                kept.push(k);
            }
        }
        self.triangles = triangles;
        kept
    }

    /// Checks the mesh is a closed (watertight), manifold, consistently oriented surface;
    /// errors name `source` (the file) and give the count and one example of each defect.
    pub fn check_closed(&self, source: &str) -> Result<(), GeometryError> {
        // undirected edge -> (uses along min->max, uses along max->min)
        let mut edges: HashMap<(u32, u32), (u32, u32)> = HashMap::new();
        for t in &self.triangles {
            for k in 0..3 {
                let (a, b) = (t[k], t[(k + 1) % 3]);
                let e = edges.entry((a.min(b), a.max(b))).or_insert((0, 0));
                if a < b {
                    e.0 += 1;
                } else {
                    e.1 += 1;
                }
            }
        }
        let describe = |(a, b): (u32, u32)| {
            let p = self.vertices[a as usize];
            let q = self.vertices[b as usize];
            format!(
                "({}, {}, {}) to ({}, {}, {})",
                p[0], p[1], p[2], q[0], q[1], q[2]
            )
        };
        let mut open = Vec::new();
        let mut non_manifold = Vec::new();
        let mut flipped = Vec::new();
        for (&key, &(fwd, bwd)) in &edges {
            match fwd + bwd {
                1 => open.push(key),
                2 if fwd != 1 => flipped.push(key),
                2 => {}
                _ => non_manifold.push(key),
            }
        }
        for list in [&mut open, &mut non_manifold, &mut flipped] {
            list.sort_unstable();
        }
        if !open.is_empty() {
            return Err(GeometryError::MeshNotWatertight {
                path: source.to_string(),
                open_edges: open.len(),
                example: describe(open[0]),
            });
        }
        if !non_manifold.is_empty() {
            return Err(GeometryError::MeshNonManifold {
                path: source.to_string(),
                edges: non_manifold.len(),
                example: describe(non_manifold[0]),
            });
        }
        if !flipped.is_empty() {
            return Err(GeometryError::MeshInconsistentOrientation {
                path: source.to_string(),
                edges: flipped.len(),
                example: describe(flipped[0]),
            });
        }
        Ok(())
    }

    /// Volume enclosed by a closed mesh (m³), positive when the normals point outwards.
    pub fn signed_volume(&self) -> f64 {
        self.triangles
            .iter()
            .map(|t| {
                let [a, b, c] = t.map(|i| self.vertices[i as usize]);
                dot(a, cross(b, c)) / 6.0
            })
            .sum()
    }

    /// Total surface area (m²).
    pub fn area(&self) -> f64 {
        (0..self.triangles.len())
            .map(|k| self.triangle_area(k))
            .sum()
    }

    /// Area of triangle `k` (m²).
    pub fn triangle_area(&self, k: usize) -> f64 {
        let [a, b, c] = self.triangles[k].map(|i| self.vertices[i as usize]);
        0.5 * norm(cross(sub(b, a), sub(c, a)))
    }

    /// Reverses the winding of every triangle (flips all normals).
    pub fn flip(&mut self) {
        for t in &mut self.triangles {
            t.swap(1, 2);
        }
    }

    /// Flips the mesh if needed so that its normals point out of the enclosed region.
    pub fn orient_outwards(&mut self) {
        if self.signed_volume() < 0.0 {
            self.flip();
        }
    }

    /// Axis-aligned bounding box (min, max) of the vertices (m).
    pub fn bounds(&self) -> ([f64; 3], [f64; 3]) {
        let mut lo = [f64::INFINITY; 3];
        let mut hi = [f64::NEG_INFINITY; 3];
        for v in &self.vertices {
            for k in 0..3 {
                lo[k] = lo[k].min(v[k]);
                hi[k] = hi[k].max(v[k]);
            }
        }
        (lo, hi)
    }

    /// Moves the mesh by `offset` (m).
    pub fn translate(&mut self, offset: [f64; 3]) {
        for v in &mut self.vertices {
            for k in 0..3 {
                v[k] += offset[k];
            }
        }
    }
}

fn fmt_coord(c: f64) -> String {
    let s = format!("{c:.9}");
    let s = s.trim_end_matches('0').trim_end_matches('.');
    if s == "-0" {
        "0".to_string()
    } else {
        s.to_string()
    }
}

/// Longest excerpt of a mesh file that an error message quotes, in characters.
const EXCERPT_CHARS: usize = 60;

/// A short, escaped excerpt of a token of a mesh file for error messages (as the record
/// readers quote a line): at most [`EXCERPT_CHARS`] characters, control characters escaped.
fn excerpt(token: &str) -> String {
    let escaped: String = token.chars().flat_map(char::escape_debug).collect();
    match escaped.char_indices().nth(EXCERPT_CHARS) {
        Some((at, _)) => format!("{}…", &escaped[..at]),
        None => escaped,
    }
}

/// The group a name statement (`g`, `o`, `solid`) opens: the rest of the line, or none when
/// it is empty or the OBJ default group `default`.
fn group_name<'a>(tokens: impl Iterator<Item = &'a str>) -> Option<String> {
    let name = tokens.collect::<Vec<_>>().join(" ");
    (!name.is_empty() && name != "default").then_some(name)
}

/// The coordinate `tok` of a text mesh file on line `line_no` (1-based): a finite number.
fn coordinate(tok: &str, line_no: usize) -> Result<f64, String> {
    tok.parse::<f64>()
        .ok()
        .filter(|x| x.is_finite())
        .ok_or_else(|| format!("line {line_no}: bad coordinate '{}'", excerpt(tok)))
}

fn parse_obj(bytes: &[u8]) -> Result<(SurfaceMesh, Vec<Option<String>>), String> {
    let text =
        std::str::from_utf8(bytes).map_err(|_| "the OBJ file is not UTF-8 text".to_string())?;
    let mut mesh = SurfaceMesh::default();
    let mut groups = Vec::new();
    let mut group: Option<String> = None;
    for (line_no, line) in text.lines().enumerate() {
        let line_no = line_no + 1;
        let mut tokens = line.split_whitespace();
        match tokens.next() {
            Some("g") | Some("o") => group = group_name(tokens),
            Some("v") => {
                let mut v = [0.0; 3];
                for c in &mut v {
                    let tok = tokens.next().ok_or_else(|| {
                        format!("line {line_no}: a vertex needs three coordinates")
                    })?;
                    *c = coordinate(tok, line_no)?;
                }
                mesh.vertices.push(v);
            }
            Some("f") => {
                let n = mesh.vertices.len() as i64;
                let mut ids = Vec::new();
                for tok in tokens {
                    let first = tok.split('/').next().unwrap_or("");
                    let i: i64 = first.parse().map_err(|_| {
                        format!("line {line_no}: bad face index '{}'", excerpt(tok))
                    })?;
                    let idx = if i > 0 { i - 1 } else { n + i };
                    if i == 0 || idx < 0 || idx >= n {
                        return Err(format!(
                            "line {line_no}: face index {i} refers to no vertex (the file has {n} vertices so far)"
                        ));
                    }
                    ids.push(idx as u32);
                }
                if ids.len() < 3 {
                    return Err(format!(
                        "line {line_no}: a face needs at least three vertices"
                    ));
                }
                for k in 1..ids.len() - 1 {
                    mesh.triangles.push([ids[0], ids[k], ids[k + 1]]);
                    groups.push(group.clone());
                }
            }
            _ => {}
        }
    }
    Ok((mesh, groups))
}

fn parse_stl(bytes: &[u8]) -> Result<(SurfaceMesh, Vec<Option<String>>), String> {
    let is_binary = bytes.len() >= 84 && {
        let n = u32::from_le_bytes([bytes[80], bytes[81], bytes[82], bytes[83]]) as usize;
        bytes.len() == 84 + 50 * n
    };
    let mut mesh = SurfaceMesh::default();
    if is_binary {
        let n = (bytes.len() - 84) / 50;
        for f in 0..n {
            let base = 84 + 50 * f + 12;
            let mut tri = [0u32; 3];
            for (k, t) in tri.iter_mut().enumerate() {
                let mut v = [0.0; 3];
                for (c, val) in v.iter_mut().enumerate() {
                    let o = base + 12 * k + 4 * c;
                    let x =
                        f32::from_le_bytes([bytes[o], bytes[o + 1], bytes[o + 2], bytes[o + 3]]);
                    if !x.is_finite() {
                        return Err(format!("facet {f}: non-finite coordinate"));
                    }
                    *val = x as f64;
                }
                mesh.vertices.push(v);
                *t = (mesh.vertices.len() - 1) as u32;
            }
            mesh.triangles.push(tri);
        }
        let groups = vec![None; mesh.triangles.len()];
        return Ok((mesh, groups));
    }
    let text = std::str::from_utf8(bytes).map_err(|_| {
        "neither a binary STL (size does not match the facet count) nor ASCII text".to_string()
    })?;
    let mut corners = Vec::new();
    let mut groups = Vec::new();
    let mut group: Option<String> = None;
    for (line_no, line) in text.lines().enumerate() {
        let mut tokens = line.split_whitespace();
        match tokens.next() {
            Some("solid") => group = group_name(tokens),
            Some("endsolid") => group = None,
            Some("vertex") => {
                let mut v = [0.0; 3];
                for c in &mut v {
                    *c = coordinate(tokens.next().unwrap_or(""), line_no + 1)?;
                }
                corners.push(v);
            }
            Some("endloop") => {
                if corners.len() != 3 {
                    return Err(format!(
                        "line {}: a facet must have exactly three vertices (found {})",
                        line_no + 1,
                        corners.len()
                    ));
                }
                let base = mesh.vertices.len() as u32;
                mesh.vertices.append(&mut corners);
                mesh.triangles.push([base, base + 1, base + 2]);
                groups.push(group.clone());
            }
            _ => {}
        }
    }
    Ok((mesh, groups))
}

pub(crate) fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}
pub(crate) fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}
pub(crate) fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}
pub(crate) fn norm(a: [f64; 3]) -> f64 {
    dot(a, a).sqrt()
}

/// Number of facets around the axis for a circle of radius `radius` (m) so that the chord
/// sagitta stays below `sag` (m) and the facets are no wider than `max_edge` (m).
pub fn circle_segments(radius: f64, max_edge: f64, sag: f64) -> usize {
    let by_sag = if sag < radius {
        (PI / (1.0 - sag / radius).acos()).ceil()
    } else {
        3.0
    };
    let by_edge = (2.0 * PI * radius / max_edge).ceil();
    (by_sag.max(by_edge).max(24.0) as usize).min(100_000)
}

/// The closed surface swept by revolving a polyline `profile` of (r, z) points (m) about the
/// z axis with `segments` facets around, then oriented outwards.
///
/// Profile points with r = 0 become single vertices on the axis. When `closed_loop` is true
/// the last point connects back to the first (a ring-like solid); otherwise the profile must
/// start and end on the axis. Consecutive points are joined by straight segments, subdivided
/// so no segment is longer than `max_edge` (m).
pub fn revolve_profile(
    profile: &[[f64; 2]],
    closed_loop: bool,
    segments: usize,
    max_edge: f64,
) -> SurfaceMesh {
    // subdivide the profile
    let mut pts: Vec<[f64; 2]> = Vec::new();
    let n_seg = if closed_loop {
        profile.len()
    } else {
        profile.len() - 1
    };
    for s in 0..n_seg {
        let a = profile[s];
        let b = profile[(s + 1) % profile.len()];
        let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
        let n = ((len / max_edge).ceil() as usize).max(1);
        for k in 0..n {
            let t = k as f64 / n as f64;
            let r = if k == 0 {
                a[0]
            } else {
                a[0] + t * (b[0] - a[0])
            };
            let z = if k == 0 {
                a[1]
            } else {
                a[1] + t * (b[1] - a[1])
            };
            pts.push([r, z]);
        }
    }
    if !closed_loop {
        pts.push(*profile.last().expect("profile not empty"));
    }
    let mut mesh = SurfaceMesh::default();
    let sin_cos: Vec<(f64, f64)> = (0..segments)
        .map(|k| (2.0 * PI * k as f64 / segments as f64).sin_cos())
        .collect();
    // vertex ids per profile point: either one (axis) or a ring
    let mut rings: Vec<Vec<u32>> = Vec::with_capacity(pts.len());
    for p in &pts {
        if p[0] <= 1e-12 {
            mesh.vertices.push([0.0, 0.0, p[1]]);
            rings.push(vec![(mesh.vertices.len() - 1) as u32]);
        } else {
            let start = mesh.vertices.len() as u32;
            for &(s, c) in &sin_cos {
                mesh.vertices.push([p[0] * c, p[0] * s, p[1]]);
            }
            rings.push((start..start + segments as u32).collect());
        }
    }
    let n_links = if closed_loop {
        pts.len()
    } else {
        pts.len() - 1
    };
    for s in 0..n_links {
        let a = &rings[s];
        let b = &rings[(s + 1) % pts.len()];
        match (a.len(), b.len()) {
            (1, 1) => {}
            (1, _) => {
                for k in 0..segments {
                    mesh.triangles.push([a[0], b[(k + 1) % segments], b[k]]);
                }
            }
            (_, 1) => {
                for k in 0..segments {
                    mesh.triangles.push([a[k], a[(k + 1) % segments], b[0]]);
                }
            }
            _ => {
                for k in 0..segments {
                    let k1 = (k + 1) % segments;
                    mesh.triangles.push([a[k], a[k1], b[k1]]);
                    mesh.triangles.push([a[k], b[k1], b[k]]);
                }
            }
        }
    }
    mesh.orient_outwards();
    mesh
}

/// The closed surface of the box [min, max] (m), each face split into squares no wider than
/// `max_edge` (m), oriented outwards.
pub fn box_mesh(min: [f64; 3], max: [f64; 3], max_edge: f64) -> SurfaceMesh {
    let n: [usize; 3] =
        std::array::from_fn(|k| (((max[k] - min[k]) / max_edge).ceil() as usize).max(1));
    let coord = |axis: usize, i: usize| {
        if i == n[axis] {
            max[axis]
        } else {
            min[axis] + (max[axis] - min[axis]) * i as f64 / n[axis] as f64
        }
    };
    let mut mesh = SurfaceMesh::default();
    for axis in 0..3 {
        let (u, v) = ((axis + 1) % 3, (axis + 2) % 3);
        for side in [0, n[axis]] {
            let base = mesh.vertices.len() as u32;
            for j in 0..=n[v] {
                for i in 0..=n[u] {
                    let mut p = [0.0; 3];
                    p[axis] = coord(axis, side);
                    p[u] = coord(u, i);
                    p[v] = coord(v, j);
                    mesh.vertices.push(p);
                }
            }
            let row = (n[u] + 1) as u32;
            for j in 0..n[v] as u32 {
                for i in 0..n[u] as u32 {
                    let a = base + j * row + i;
                    let (b, c, d) = (a + 1, a + row + 1, a + row);
                    if side == 0 {
                        mesh.triangles.push([a, c, b]);
                        mesh.triangles.push([a, d, c]);
                    } else {
                        mesh.triangles.push([a, b, c]);
                        mesh.triangles.push([a, c, d]);
                    }
                }
            }
        }
    }
    mesh.merge_duplicate_vertices();
    mesh.orient_outwards();
    mesh
}
