//! Tests of the CSV writers and the RON summary writer.

mod common;

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};
use slosh_io::{
    format_f64, read_ron, read_table, write_grid_csv, write_ron, IoError, SeriesWriter, TableWriter,
};

#[test]
fn series_header_units_and_lossless_rows() {
    let dir = common::tmp_dir("series");
    let path = dir.join("series.csv");
    let cols = [
        ("t", "s"),
        ("accel_x", "m/s^2"),
        ("eta_left", "m"),
        ("n_fluid", ""),
    ];
    let mut w = SeriesWriter::create(&path, &cols).unwrap();
    let rows = [
        [0.0, 0.0, 0.0, 1200.0],
        [0.01, -1.234_567_890_123_456_7e-3, 3.3e-12, 1200.0],
        [0.1 + 0.2, 9.81, f64::NAN, f64::INFINITY],
        [1e17, -2.5e-300, 5e-324, -0.0],
    ];
    for r in &rows {
        w.write_row(r).unwrap();
    }
    assert_eq!(w.rows_written(), 4);
    assert_eq!(w.column_index("eta_left"), Some(2));

    // Rows must be on disk while the writer is still alive (flushed every row by default),
    // so an aborted run keeps them: read before dropping the writer.
    let text = std::fs::read_to_string(&path).unwrap();
    assert_eq!(text.lines().next().unwrap(), "t,accel_x,eta_left,n_fluid");
    assert_eq!(text.lines().count(), 5);

    // Exact equality: the format is the shortest round-trip representation, so every
    // finite value must parse back bit-for-bit; NaN stays NaN.
    let table = read_table(&path).unwrap();
    assert_eq!(table.columns, ["t", "accel_x", "eta_left", "n_fluid"]);
    for (got, want) in table.rows.iter().zip(&rows) {
        for (g, w) in got.iter().zip(want) {
            if w.is_nan() {
                assert!(g.is_nan());
            } else {
                assert_eq!(g.to_bits(), w.to_bits(), "{g} vs {w}");
            }
        }
    }
    assert_eq!(table.column("t").unwrap()[1], 0.01);

    let units = std::fs::read_to_string(dir.join("series_units.csv")).unwrap();
    assert_eq!(
        units,
        "column,unit\nt,s\naccel_x,m/s^2\neta_left,m\nn_fluid,\n"
    );
    drop(w);
}

#[test]
fn compact_number_format() {
    // Ordinary magnitudes in plain decimal, extreme ones in exponent form; all lossless.
    assert_eq!(format_f64(0.0), "0");
    assert_eq!(format_f64(0.3), "0.3");
    assert_eq!(format_f64(1200.0), "1200");
    assert_eq!(format_f64(-9.81), "-9.81");
    assert_eq!(format_f64(2.5e-9), "2.5e-9");
    assert_eq!(format_f64(3e20), "3e20");
    assert_eq!(format_f64(f64::NEG_INFINITY), "-inf");
    for k in -320..308 {
        for m in [1.0, 1.234_567_890_123_45, 7.000_000_000_000_001] {
            let x = m * 10f64.powi(k);
            assert_eq!(format_f64(x).parse::<f64>().unwrap().to_bits(), x.to_bits());
            assert!(format_f64(x).len() <= 24, "{}", format_f64(x));
        }
    }
}

#[test]
fn timed_flush_still_flushes_on_demand_and_drop() {
    let dir = common::tmp_dir("timed");
    let path = dir.join("table.csv");
    let mut w = TableWriter::create(&path, &["a", "b"]).unwrap();
    w.set_flush_interval(std::time::Duration::from_secs(3600));
    w.write_row(&[1.0, 2.0]).unwrap();
    w.flush().unwrap();
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "a,b\n1,2\n");
    w.write_row(&[3.0, 4.0]).unwrap();
    drop(w);
    assert_eq!(std::fs::read_to_string(&path).unwrap(), "a,b\n1,2\n3,4\n");
}

#[test]
fn bad_shapes_are_errors_naming_the_file() {
    let dir = common::tmp_dir("bad");
    let path = dir.join("series.csv");
    let mut w = SeriesWriter::create(&path, &[("t", "s"), ("x", "m")]).unwrap();
    let e = w.write_row(&[1.0]).unwrap_err();
    assert!(matches!(e, IoError::InvalidData { .. }));
    assert_eq!(e.path(), path);
    assert!(e.to_string().contains("series.csv"), "{e}");

    let e = SeriesWriter::create(dir.join("dup.csv"), &[("t", "s"), ("t", "s")]).unwrap_err();
    assert!(e.to_string().contains("twice"), "{e}");

    // A folder where the file should be: an I/O error naming that path.
    std::fs::create_dir_all(dir.join("taken.csv")).unwrap();
    let e = TableWriter::create(dir.join("taken.csv"), &["a"]).unwrap_err();
    assert!(matches!(e, IoError::Io { .. }));
    assert!(e.to_string().contains("taken.csv"));
}

#[test]
fn grid_csv_layout() {
    let dir = common::tmp_dir("grid");
    let path = dir.join("maps/roof_pressure.csv");
    let ts = [0.0, 0.5];
    let xs = [0.25, 0.75, 1.25];
    let p = [1.0, 2.0, 3.0, 4.0, 5.0, 6.5];
    write_grid_csv(&path, "t", &ts, &xs, &p).unwrap();
    assert_eq!(
        std::fs::read_to_string(&path).unwrap(),
        "t,0.25,0.75,1.25\n0,1,2,3\n0.5,4,5,6.5\n"
    );
    assert!(write_grid_csv(&path, "t", &ts, &xs, &p[..5]).is_err());
}

#[derive(Debug, PartialEq, Serialize, Deserialize)]
struct Summary {
    dim: u32,
    sim_time: f64,
    max_roof_p: f64,
    params: BTreeMap<String, f64>,
    version: String,
}

#[test]
fn ron_round_trip() {
    let dir = common::tmp_dir("ron");
    let path = dir.join("summary.ron");
    let s = Summary {
        dim: 2,
        sim_time: 12.0,
        max_roof_p: 1_234.567_890_123,
        params: [("amplitude".to_string(), 0.01), ("omega".to_string(), 5.5)]
            .into_iter()
            .collect(),
        version: "0.1.0".into(),
    };
    write_ron(&path, &s).unwrap();
    let text = std::fs::read_to_string(&path).unwrap();
    assert!(text.contains("max_roof_p: 1234.567890123"), "{text}");
    assert!(
        text.lines().count() > 5,
        "pretty-printed over several lines:\n{text}"
    );
    let back: Summary = read_ron(&path).unwrap();
    assert_eq!(back, s);
    // Written via a temporary file that must not be left behind.
    assert!(!dir.join("summary.ron.tmp").exists());

    std::fs::write(dir.join("broken.ron"), "(dim: ").unwrap();
    let e = read_ron::<Summary>(dir.join("broken.ron")).unwrap_err();
    assert!(matches!(e, IoError::RonParse { .. }));
    assert!(e.to_string().contains("broken.ron"));
}
