//! Tests of the PNG/SVG plots: files exist with the right size and structure, and odd data
//! (NaN, constant, empty) never panics. The pictures themselves were checked by eye.

mod common;

use std::path::Path;

use slosh_io::{heatmap, line_plot, scatter_with_identity, Field2d, IoError, PlotSpec, Series};

/// Width and height from a PNG's IHDR chunk (after checking the signature).
fn png_size(path: &Path) -> (u32, u32) {
    let b = std::fs::read(path).unwrap();
    assert_eq!(&b[..8], b"\x89PNG\r\n\x1a\n", "PNG signature");
    assert_eq!(&b[12..16], b"IHDR");
    let w = u32::from_be_bytes(b[16..20].try_into().unwrap());
    let h = u32::from_be_bytes(b[20..24].try_into().unwrap());
    (w, h)
}

fn check_pair(base: &Path, title: &str) {
    let png = base.with_file_name(format!(
        "{}.png",
        base.file_name().unwrap().to_string_lossy()
    ));
    let svg = base.with_file_name(format!(
        "{}.svg",
        base.file_name().unwrap().to_string_lossy()
    ));
    assert_eq!(png_size(&png), (1000, 600));
    // A drawn chart with text compresses to well over 10 kB; a blank image to ~2-3 kB.
    assert!(
        std::fs::metadata(&png).unwrap().len() > 10_000,
        "PNG looks blank"
    );
    let s = std::fs::read_to_string(&svg).unwrap();
    assert!(s.starts_with("<svg") || s.starts_with("<?xml"));
    assert!(s.contains(title), "SVG contains the title");
    assert!(s.trim_end().ends_with("</svg>"));
    // Drawn into temporary siblings and renamed: none is left behind.
    let dir = base.parent().unwrap();
    let parts: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .filter_map(|e| e.ok())
        .map(|e| e.file_name().to_string_lossy().to_string())
        .filter(|n| n.contains(".part."))
        .collect();
    assert!(parts.is_empty(), "{parts:?}");
}

#[test]
fn line_plot_with_legend() {
    let dir = common::tmp_dir("plot-line");
    let t: Vec<f64> = (0..=1000).map(|i| i as f64 * 0.012).collect();
    let sph: Vec<f64> = t
        .iter()
        .map(|&t| 0.02 * (5.0 * t).sin() * (1.0 - (-t).exp()))
        .collect();
    let th: Vec<f64> = t.iter().map(|&t| 0.02 * (5.0 * t).sin()).collect();
    let probes: Vec<f64> = t.iter().step_by(50).copied().collect();
    let pv: Vec<f64> = probes.iter().map(|&t| 0.018 * (5.0 * t).sin()).collect();
    let base = dir.join("eta_left.v1");
    line_plot(
        &base,
        &PlotSpec::new("Free surface at the left wall", "t (s)", "η (m)"),
        &[
            Series::line("SPH", &t, &sph),
            Series::dashed("linear theory", &t, &th),
            Series::points("probe", &probes, &pv),
        ],
    )
    .unwrap();
    // The dot in the name is kept: the extension is appended, not substituted.
    check_pair(&base, "Free surface at the left wall");
}

#[test]
fn odd_data_does_not_panic() {
    let dir = common::tmp_dir("plot-odd");
    let spec = PlotSpec::new("odd", "x (m)", "y (m)");
    let xs = [0.0, 1.0, 2.0, 3.0, 4.0];
    let nan_ys = [1.0, f64::NAN, 3.0, f64::INFINITY, 2.0];
    let const_ys = [5.0; 5];
    let all_nan = [f64::NAN; 5];
    line_plot(
        dir.join("nan"),
        &spec,
        &[Series::line("with gaps", &xs, &nan_ys)],
    )
    .unwrap();
    line_plot(
        dir.join("const"),
        &spec,
        &[Series::line("constant", &xs, &const_ys)],
    )
    .unwrap();
    line_plot(
        dir.join("allnan"),
        &spec,
        &[Series::line("nothing", &xs, &all_nan)],
    )
    .unwrap();
    line_plot(dir.join("none"), &spec, &[]).unwrap();
    line_plot(
        dir.join("zero"),
        &spec,
        &[Series::points("", &[0.0], &[0.0])],
    )
    .unwrap();
    for n in ["nan", "const", "allnan", "none", "zero"] {
        assert_eq!(png_size(&dir.join(format!("{n}.png"))), (1000, 600));
    }
    let e = line_plot(dir.join("bad"), &spec, &[Series::line("x", &xs, &xs[..3])]).unwrap_err();
    assert!(matches!(e, IoError::InvalidData { .. }));
    assert!(e.to_string().contains("bad.png"));
}

#[test]
fn scatter_against_theory() {
    let dir = common::tmp_dir("plot-scatter");
    let theory = [0.5, 1.0, 1.5, 2.0, 2.5, 3.0];
    let sph = [0.52, 0.97, 1.58, 1.95, 2.6, 2.9];
    let base = dir.join("frequency_check");
    scatter_with_identity(
        &base,
        &PlotSpec::new(
            "Natural frequency: SPH vs theory",
            "theory ω (rad/s)",
            "SPH ω (rad/s)",
        ),
        &[Series::points("cases", &theory, &sph)],
    )
    .unwrap();
    check_pair(&base, "Natural frequency: SPH vs theory");
}

#[test]
fn heatmap_with_colour_bar() {
    let dir = common::tmp_dir("plot-heat");
    let ts: Vec<f64> = (0..400).map(|i| i as f64 * 0.025).collect();
    let xs: Vec<f64> = (0..40).map(|j| -0.975 + j as f64 * 0.05).collect();
    let mut p = Vec::new();
    for &t in &ts {
        for &x in &xs {
            let v: f64 = 2000.0
                * (3.0 * t).sin().max(0.0)
                * (-(x - 0.8 * (1.3 * t).sin()).powi(2) * 8.0).exp();
            p.push(if t > 4.0 && t < 4.2 { f64::NAN } else { v });
        }
    }
    let base = dir.join("roof_pressure_map");
    heatmap(
        &base,
        &PlotSpec::new("Roof pressure", "t (s)", "x (m)"),
        &Field2d {
            xs: &ts,
            ys: &xs,
            values: &p,
            value_label: "p (Pa)".into(),
        },
    )
    .unwrap();
    check_pair(&base, "Roof pressure");

    // Constant, single-cell and empty fields draw too; bad grids are errors.
    let f = |xs: &'static [f64], ys: &'static [f64], v: &'static [f64]| Field2d {
        xs,
        ys,
        values: v,
        value_label: "p (Pa)".into(),
    };
    heatmap(
        dir.join("const"),
        &PlotSpec::default(),
        &f(&[0.0, 1.0], &[0.0], &[3.0, 3.0]),
    )
    .unwrap();
    heatmap(
        dir.join("one"),
        &PlotSpec::default(),
        &f(&[2.0], &[0.0], &[f64::NAN]),
    )
    .unwrap();
    heatmap(dir.join("empty"), &PlotSpec::default(), &f(&[], &[], &[])).unwrap();
    assert!(heatmap(
        dir.join("bad"),
        &PlotSpec::default(),
        &f(&[0.0, 1.0], &[0.0], &[1.0])
    )
    .is_err());
    assert!(heatmap(
        dir.join("bad"),
        &PlotSpec::default(),
        &f(&[1.0, 0.0], &[0.0], &[1.0, 2.0])
    )
    .is_err());
}
