//! VTK XML PolyData (`.vtp`) particle frames and the ParaView `.pvd` time index.
//!
//! Encoding: every `DataArray` is written **inline** with `format="binary"`: base64 (standard
//! alphabet, `=` padding) of a little-endian `UInt64` byte count followed by the raw
//! little-endian values, encoded as one stream exactly as VTK's own writer does for
//! uncompressed data (`header_type="UInt64"`, `byte_order="LittleEndian"`). This keeps the
//! file well-formed XML (readable by any XML parser, unlike raw appended data) at a third
//! more bytes than raw binary, and it is fast to write. Particles are written as vertices
//! (`<Verts>` with `connectivity` 0..n and `offsets` 1..=n) so ParaView renders them without
//! a glyph filter.
//!
//! Frame files and the index are written to a temporary sibling and renamed into place, so
//! an aborted run never leaves a truncated frame, and `frames.pvd` (rewritten after each
//! frame) always lists exactly the frames on disk.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::base64::encode_into;
use crate::error::{write_atomic, IoError, Result};
use crate::series::format_f64;

/// The values of one per-point array.
#[derive(Debug, Clone, Copy)]
pub enum ArrayData<'a> {
    /// One `f64` per point (written as `Float64`, 1 component), e.g. pressure, density.
    Scalar(&'a [f64]),
    /// Three `f64` per point (written as `Float64`, 3 components), e.g. velocity; 2D runs pad
    /// the third component with 0.
    Vector3(&'a [[f64; 3]]),
    /// One `i32` per point (written as `Int32`), e.g. particle kind or part id.
    Int32(&'a [i32]),
}

/// A named per-point array of a `.vtp` frame.
#[derive(Debug, Clone, Copy)]
pub struct PointArray<'a> {
    /// The array's name as ParaView shows it (e.g. `"pressure"`).
    pub name: &'a str,
    /// The values, one entry per point.
    pub data: ArrayData<'a>,
}

impl<'a> PointArray<'a> {
    /// A scalar `f64` array.
    pub fn scalar(name: &'a str, data: &'a [f64]) -> Self {
        Self {
            name,
            data: ArrayData::Scalar(data),
        }
    }

    /// A 3-component `f64` array.
    pub fn vector3(name: &'a str, data: &'a [[f64; 3]]) -> Self {
        Self {
            name,
            data: ArrayData::Vector3(data),
        }
    }

    /// An `i32` array.
    pub fn int32(name: &'a str, data: &'a [i32]) -> Self {
        Self {
            name,
            data: ArrayData::Int32(data),
        }
    }

    /// The number of points (tuples) the array holds.
    pub fn len(&self) -> usize {
        match self.data {
            ArrayData::Scalar(d) => d.len(),
            ArrayData::Vector3(d) => d.len(),
            ArrayData::Int32(d) => d.len(),
        }
    }

    /// Whether the array holds no points.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }
}

/// Escapes the characters that may not appear verbatim in an XML attribute value.
fn xml_escape(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    for c in s.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            _ => out.push(c),
        }
    }
    out
}

/// Appends one binary `DataArray` element: `bytes` are the raw little-endian values.
fn push_data_array(
    xml: &mut String,
    indent: &str,
    vtk_type: &str,
    name: Option<&str>,
    components: usize,
    bytes: &[u8],
) {
    let _ = write!(xml, "{indent}<DataArray type=\"{vtk_type}\"");
    if let Some(n) = name {
        let _ = write!(xml, " Name=\"{}\"", xml_escape(n));
    }
    let _ = write!(
        xml,
        " NumberOfComponents=\"{components}\" format=\"binary\">"
    );
    let mut block = Vec::with_capacity(8 + bytes.len());
    block.extend_from_slice(&(bytes.len() as u64).to_le_bytes());
    block.extend_from_slice(bytes);
    encode_into(&block, xml);
    xml.push_str("</DataArray>\n");
}

fn f64_bytes<'b>(values: impl Iterator<Item = &'b f64>, n: usize) -> Vec<u8> {
    let mut b = Vec::with_capacity(8 * n);
    for v in values {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b
}

fn i32_bytes(values: impl Iterator<Item = i32>, n: usize) -> Vec<u8> {
    let mut b = Vec::with_capacity(4 * n);
    for v in values {
        b.extend_from_slice(&v.to_le_bytes());
    }
    b
}

/// Builds the text of a `.vtp` file (see [`write_vtp`]); `path` only names errors.
fn vtp_text(path: &Path, points: &[[f64; 3]], arrays: &[PointArray]) -> Result<String> {
    let n = points.len();
    if n > i32::MAX as usize {
        return Err(IoError::invalid(
            path,
            format!("{n} points exceed the Int32 vertex connectivity used by this writer"),
        ));
    }
    for (i, a) in arrays.iter().enumerate() {
        if a.name.trim().is_empty() {
            return Err(IoError::invalid(
                path,
                format!("point array {i} has an empty name"),
            ));
        }
        if arrays[..i].iter().any(|b| b.name == a.name) {
            return Err(IoError::invalid(
                path,
                format!("point array name `{}` appears twice", a.name),
            ));
        }
        if a.len() != n {
            return Err(IoError::invalid(
                path,
                format!(
                    "point array `{}` has {} values for {n} points",
                    a.name,
                    a.len()
                ),
            ));
        }
    }

    // Roughly 4/3 of the binary size plus tags.
    let payload: usize = 24 * n + 8 * n + arrays.iter().map(|a| 24 * a.len()).sum::<usize>();
    let mut xml = String::with_capacity(payload * 4 / 3 + 1024);
    xml.push_str("<?xml version=\"1.0\"?>\n");
    xml.push_str(
        "<VTKFile type=\"PolyData\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n",
    );
    xml.push_str("  <PolyData>\n");
    let _ = writeln!(
        xml,
        "    <Piece NumberOfPoints=\"{n}\" NumberOfVerts=\"{n}\" NumberOfLines=\"0\" NumberOfStrips=\"0\" NumberOfPolys=\"0\">"
    );

    xml.push_str("      <PointData>\n");
    for a in arrays {
        let ind = "        ";
        match a.data {
            ArrayData::Scalar(d) => push_data_array(
                &mut xml,
                ind,
                "Float64",
                Some(a.name),
                1,
                &f64_bytes(d.iter(), n),
            ),
            ArrayData::Vector3(d) => push_data_array(
                &mut xml,
                ind,
                "Float64",
                Some(a.name),
                3,
                &f64_bytes(d.iter().flatten(), 3 * n),
            ),
            ArrayData::Int32(d) => push_data_array(
                &mut xml,
                ind,
                "Int32",
                Some(a.name),
                1,
                &i32_bytes(d.iter().copied(), n),
            ),
        }
    }
    xml.push_str("      </PointData>\n");

    xml.push_str("      <Points>\n");
    push_data_array(
        &mut xml,
        "        ",
        "Float64",
        Some("Points"),
        3,
        &f64_bytes(points.iter().flatten(), 3 * n),
    );
    xml.push_str("      </Points>\n");

    xml.push_str("      <Verts>\n");
    // n <= i32::MAX was checked above, so these casts are exact.
    push_data_array(
        &mut xml,
        "        ",
        "Int32",
        Some("connectivity"),
        1,
        &i32_bytes((0..n).map(|i| i as i32), n),
    );
    push_data_array(
        &mut xml,
        "        ",
        "Int32",
        Some("offsets"),
        1,
        &i32_bytes((1..=n).map(|i| i as i32), n),
    );
    xml.push_str("      </Verts>\n");
    xml.push_str("    </Piece>\n  </PolyData>\n</VTKFile>\n");
    Ok(xml)
}

/// Writes one particle frame as a VTK XML PolyData file (`.vtp`, inline base64 binary; see
/// the module docs). Every array must hold one entry per point and have a distinct,
/// non-empty name. 2D runs pass points with z = 0.
pub fn write_vtp(path: impl AsRef<Path>, points: &[[f64; 3]], arrays: &[PointArray]) -> Result<()> {
    let path = path.as_ref();
    let xml = vtp_text(path, points, arrays)?;
    write_atomic(path, xml.as_bytes())
}

/// A ParaView collection (`.pvd`) listing frames with their times.
///
/// [`PvdIndex::add`] rewrites the whole file after each frame, so the index on disk is valid
/// whenever a run stops.
#[derive(Debug, Clone)]
pub struct PvdIndex {
    path: PathBuf,
    entries: Vec<(f64, String)>,
}

impl PvdIndex {
    /// An empty index that will be written to `path` (e.g. `out/case/frames/frames.pvd`).
    pub fn new(path: impl AsRef<Path>) -> Self {
        Self {
            path: path.as_ref().to_path_buf(),
            entries: Vec::new(),
        }
    }

    /// Records a frame at simulation time `time` (s, finite) stored in `file`, a path
    /// relative to the index's folder (e.g. `"frame_000012.vtp"`), and rewrites the index.
    pub fn add(&mut self, time: f64, file: impl Into<String>) -> Result<()> {
        if !time.is_finite() {
            return Err(IoError::invalid(
                &self.path,
                format!("frame time {time} is not finite"),
            ));
        }
        self.entries.push((time, file.into()));
        self.write()
    }

    /// Writes the index file with the frames recorded so far.
    pub fn write(&self) -> Result<()> {
        let mut xml = String::with_capacity(128 + 80 * self.entries.len());
        xml.push_str("<?xml version=\"1.0\"?>\n");
        xml.push_str("<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n");
        xml.push_str("  <Collection>\n");
        for (t, f) in &self.entries {
            let _ = writeln!(
                xml,
                "    <DataSet timestep=\"{}\" group=\"\" part=\"0\" file=\"{}\"/>",
                format_f64(*t),
                xml_escape(f)
            );
        }
        xml.push_str("  </Collection>\n</VTKFile>\n");
        write_atomic(&self.path, xml.as_bytes())
    }

    /// The (time, relative file name) entries recorded so far, in order.
    pub fn entries(&self) -> &[(f64, String)] {
        &self.entries
    }

    /// The index file.
    pub fn path(&self) -> &Path {
        &self.path
    }
}

/// A folder of numbered frames plus its index: `DIR/frame_000000.vtp`, ... and
/// `DIR/frames.pvd`.
#[derive(Debug, Clone)]
pub struct FrameSeries {
    dir: PathBuf,
    index: PvdIndex,
}

impl FrameSeries {
    /// Frames will go into `dir` (created on the first frame), the index into
    /// `dir/frames.pvd`.
    pub fn new(dir: impl AsRef<Path>) -> Self {
        let dir = dir.as_ref().to_path_buf();
        let index = PvdIndex::new(dir.join("frames.pvd"));
        Self { dir, index }
    }

    /// A series that continues one whose index held `entries` (time, file): the next frame
    /// is numbered after them, and the index lists them first.
    pub fn continuing(dir: impl AsRef<Path>, entries: &[(f64, String)]) -> Self {
        let mut series = Self::new(dir);
        series.index.entries = entries.to_vec();
        series
    }

    /// Writes the next frame (`frame_NNNNNN.vtp`, numbered from 0) at time `time` (s) and
    /// rewrites the index; returns the frame's path.
    pub fn write_frame(
        &mut self,
        time: f64,
        points: &[[f64; 3]],
        arrays: &[PointArray],
    ) -> Result<PathBuf> {
        let name = format!("frame_{:06}.vtp", self.index.entries().len());
        let path = self.dir.join(&name);
        write_vtp(&path, points, arrays)?;
        self.index.add(time, name)?;
        Ok(path)
    }

    /// The index of the frames written so far.
    pub fn index(&self) -> &PvdIndex {
        &self.index
    }

    /// The frames folder.
    pub fn dir(&self) -> &Path {
        &self.dir
    }
}
