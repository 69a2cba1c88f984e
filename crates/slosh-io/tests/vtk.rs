//! Tests of the `.vtp`/`.pvd` writers: the files are parsed back with a tiny XML scanner and
//! base64 decoder written here (independent of the writer's code).

mod common;

use std::collections::BTreeMap;

use slosh_io::{write_vtp, FrameSeries, IoError, PointArray, PvdIndex};

/// One XML element: name, attributes and text content (for leaf elements).
#[derive(Debug)]
struct Elem {
    name: String,
    attrs: BTreeMap<String, String>,
    text: String,
    children: Vec<Elem>,
}

impl Elem {
    fn child(&self, name: &str) -> &Elem {
        self.children
            .iter()
            .find(|c| c.name == name)
            .unwrap_or_else(|| panic!("<{}> has no <{name}>", self.name))
    }
    fn attr(&self, a: &str) -> &str {
        self.attrs
            .get(a)
            .unwrap_or_else(|| panic!("<{}> has no attribute {a}", self.name))
    }
}

/// A minimal XML parser: enough for the well-formed files written by slosh-io (no CDATA,
/// no comments, entities only in attribute values). Panics on anything malformed.
fn parse_xml(s: &str) -> Elem {
    let s = s.trim_start();
    let s = if s.starts_with("<?") {
        &s[s.find("?>").unwrap() + 2..]
    } else {
        s
    };
    let mut pos = 0;
    let root = parse_elem(s, &mut pos);
    assert!(
        s[pos..].trim().is_empty(),
        "trailing content after the root element"
    );
    root
}

fn unescape(s: &str) -> String {
    s.replace("&lt;", "<")
        .replace("&gt;", ">")
        .replace("&quot;", "\"")
        .replace("&apos;", "'")
        .replace("&amp;", "&")
}

fn parse_elem(s: &str, pos: &mut usize) -> Elem {
    while s.as_bytes()[*pos].is_ascii_whitespace() {
        *pos += 1;
    }
    assert_eq!(&s[*pos..*pos + 1], "<");
    let end = *pos + s[*pos..].find('>').unwrap();
    let tag = &s[*pos + 1..end];
    let self_closing = tag.ends_with('/');
    let tag = tag.trim_end_matches('/');
    let mut parts = tag.splitn(2, char::is_whitespace);
    let name = parts.next().unwrap().to_string();
    let mut attrs = BTreeMap::new();
    let mut rest = parts.next().unwrap_or("").trim();
    while !rest.is_empty() {
        let eq = rest.find("=\"").unwrap();
        let key = rest[..eq].trim().to_string();
        let vend = eq + 2 + rest[eq + 2..].find('"').unwrap();
        attrs.insert(key, unescape(&rest[eq + 2..vend]));
        rest = rest[vend + 1..].trim();
    }
    *pos = end + 1;
    let mut e = Elem {
        name,
        attrs,
        text: String::new(),
        children: Vec::new(),
    };
    if self_closing {
        return e;
    }
    loop {
        let next = *pos + s[*pos..].find('<').unwrap();
        e.text.push_str(&s[*pos..next]);
        *pos = next;
        if s[*pos..].starts_with("</") {
            let close = *pos + s[*pos..].find('>').unwrap();
            assert_eq!(&s[*pos + 2..close], e.name, "mismatched closing tag");
            *pos = close + 1;
            return e;
        }
        e.children.push(parse_elem(s, pos));
    }
}

fn b64_decode(s: &str) -> Vec<u8> {
    let val = |c: u8| -> u32 {
        match c {
            b'A'..=b'Z' => (c - b'A') as u32,
            b'a'..=b'z' => (c - b'a') as u32 + 26,
            b'0'..=b'9' => (c - b'0') as u32 + 52,
            b'+' => 62,
            b'/' => 63,
            _ => panic!("bad base64 char {c}"),
        }
    };
    let bytes: Vec<u8> = s.bytes().filter(|b| !b.is_ascii_whitespace()).collect();
    assert_eq!(bytes.len() % 4, 0, "base64 length");
    let mut out = Vec::new();
    for q in bytes.chunks(4) {
        let pad = q.iter().filter(|&&c| c == b'=').count();
        let n = q
            .iter()
            .map(|&c| if c == b'=' { 0 } else { val(c) })
            .fold(0u32, |acc, v| (acc << 6) | v);
        let b = [(n >> 16) as u8, (n >> 8) as u8, n as u8];
        out.extend_from_slice(&b[..3 - pad]);
    }
    out
}

/// Decodes a binary DataArray: a UInt64 byte count, then that many bytes (checked).
fn payload(e: &Elem) -> Vec<u8> {
    assert_eq!(e.attr("format"), "binary");
    let raw = b64_decode(&e.text);
    let n = u64::from_le_bytes(raw[..8].try_into().unwrap()) as usize;
    assert_eq!(raw.len(), 8 + n, "header byte count matches the data");
    raw[8..].to_vec()
}

fn as_f64(b: &[u8]) -> Vec<f64> {
    b.chunks_exact(8)
        .map(|c| f64::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

fn as_i32(b: &[u8]) -> Vec<i32> {
    b.chunks_exact(4)
        .map(|c| i32::from_le_bytes(c.try_into().unwrap()))
        .collect()
}

fn array<'e>(parent: &'e Elem, name: &str) -> &'e Elem {
    parent
        .children
        .iter()
        .find(|c| c.name == "DataArray" && c.attrs.get("Name").map(String::as_str) == Some(name))
        .unwrap_or_else(|| panic!("no DataArray {name}"))
}

#[test]
fn vtp_parses_back_to_the_same_numbers() {
    let dir = common::tmp_dir("vtp");
    let path = dir.join("frame.vtp");
    // 5 points (lengths 1..5 exercise every base64 padding case across the arrays).
    let points: Vec<[f64; 3]> = (0..5)
        .map(|i| [0.1 * i as f64, -1.5e-7 * i as f64, 1e10 + i as f64])
        .collect();
    let pressure = [1.0, f64::NAN, -3.25, 1e300, 5e-324];
    let velocity: Vec<[f64; 3]> = (0..5).map(|i| [i as f64, -(i as f64), 0.5]).collect();
    let kind = [0, 1, 2, -7, i32::MAX];
    write_vtp(
        &path,
        &points,
        &[
            PointArray::scalar("pressure", &pressure),
            PointArray::vector3("velocity", &velocity),
            PointArray::int32("kind", &kind),
        ],
    )
    .unwrap();

    let text = std::fs::read_to_string(&path).unwrap();
    let root = parse_xml(&text);
    assert_eq!(root.name, "VTKFile");
    assert_eq!(root.attr("type"), "PolyData");
    assert_eq!(root.attr("byte_order"), "LittleEndian");
    assert_eq!(root.attr("header_type"), "UInt64");
    let piece = root.child("PolyData").child("Piece");
    assert_eq!(piece.attr("NumberOfPoints"), "5");
    assert_eq!(piece.attr("NumberOfVerts"), "5");

    // Bit-exact: the data are raw f64/i32, so nothing may change (NaN compared as NaN).
    let pts = piece.child("Points").child("DataArray");
    assert_eq!(pts.attr("NumberOfComponents"), "3");
    assert_eq!(pts.attr("type"), "Float64");
    let flat: Vec<f64> = points.iter().flatten().copied().collect();
    assert_eq!(as_f64(&payload(pts)), flat);

    let pd = piece.child("PointData");
    let p = as_f64(&payload(array(pd, "pressure")));
    assert_eq!(p.len(), 5);
    for (a, b) in p.iter().zip(&pressure) {
        assert!(a.to_bits() == b.to_bits());
    }
    let v = array(pd, "velocity");
    assert_eq!(v.attr("NumberOfComponents"), "3");
    let vflat: Vec<f64> = velocity.iter().flatten().copied().collect();
    assert_eq!(as_f64(&payload(v)), vflat);
    let k = array(pd, "kind");
    assert_eq!(k.attr("type"), "Int32");
    assert_eq!(as_i32(&payload(k)), kind);

    let verts = piece.child("Verts");
    assert_eq!(
        as_i32(&payload(array(verts, "connectivity"))),
        [0, 1, 2, 3, 4]
    );
    assert_eq!(as_i32(&payload(array(verts, "offsets"))), [1, 2, 3, 4, 5]);
}

#[test]
fn empty_frame_is_valid() {
    let dir = common::tmp_dir("vtp-empty");
    let path = dir.join("empty.vtp");
    write_vtp(&path, &[], &[PointArray::scalar("p", &[])]).unwrap();
    let root = parse_xml(&std::fs::read_to_string(&path).unwrap());
    let piece = root.child("PolyData").child("Piece");
    assert_eq!(piece.attr("NumberOfPoints"), "0");
    assert!(payload(piece.child("Points").child("DataArray")).is_empty());
}

#[test]
fn inconsistent_arrays_are_errors() {
    let dir = common::tmp_dir("vtp-bad");
    let path = dir.join("bad.vtp");
    let pts = [[0.0; 3]; 3];
    let e = write_vtp(&path, &pts, &[PointArray::scalar("p", &[1.0, 2.0])]).unwrap_err();
    assert!(matches!(e, IoError::InvalidData { .. }));
    assert!(
        e.to_string().contains("bad.vtp") && e.to_string().contains("`p`"),
        "{e}"
    );
    let d = [1.0; 3];
    let e = write_vtp(
        &path,
        &pts,
        &[PointArray::scalar("p", &d), PointArray::scalar("p", &d)],
    )
    .unwrap_err();
    assert!(e.to_string().contains("twice"));
    assert!(!path.exists(), "nothing written on error");
}

#[test]
fn pvd_is_rewritten_after_each_frame() {
    let dir = common::tmp_dir("pvd");
    let frames_dir = dir.join("frames");
    let mut frames = FrameSeries::new(&frames_dir);
    let pts = [[0.0, 1.0, 0.0], [1.0, 2.0, 0.0]];
    let rho = [1000.0, 1001.0];
    for (i, t) in [0.0, 0.05, 0.1].into_iter().enumerate() {
        let p = frames
            .write_frame(t, &pts, &[PointArray::scalar("density", &rho)])
            .unwrap();
        assert_eq!(p, frames_dir.join(format!("frame_{i:06}.vtp")));
        // After every frame the index on disk lists exactly the frames written so far.
        let root = parse_xml(&std::fs::read_to_string(frames_dir.join("frames.pvd")).unwrap());
        assert_eq!(root.attr("type"), "Collection");
        let sets = &root.child("Collection").children;
        assert_eq!(sets.len(), i + 1);
        let last = &sets[i];
        assert_eq!(last.name, "DataSet");
        assert_eq!(last.attr("timestep").parse::<f64>().unwrap(), t);
        assert_eq!(last.attr("file"), format!("frame_{i:06}.vtp"));
        assert!(frames_dir.join(last.attr("file")).exists());
    }
    assert_eq!(frames.index().entries().len(), 3);

    let mut idx = PvdIndex::new(dir.join("x.pvd"));
    assert!(idx.add(f64::NAN, "a.vtp").is_err());
    idx.add(1.0, "a&b.vtp").unwrap();
    let root = parse_xml(&std::fs::read_to_string(dir.join("x.pvd")).unwrap());
    assert_eq!(root.child("Collection").children[0].attr("file"), "a&b.vtp");
}
