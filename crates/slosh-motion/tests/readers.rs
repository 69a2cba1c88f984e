//! Reader tests: PEER AT2, K-NET ASCII, plain text, and their errors.

mod common;

use common::{elcentro_path, temp_file};
use slosh_motion::*;

const G: f64 = GRAVITY_M_S2;

#[test]
fn elcentro_at2_header_and_peak() {
    // Tolerance: the file has 5 decimals in g, so the peak must match -0.31882 g to rounding (1e-12).
    let r = read_at2(elcentro_path()).expect("read El Centro");
    assert_eq!(r.len(), 1559);
    assert_eq!(r.meta.original_npts, 1559);
    assert!((r.dt_s - 0.02).abs() < 1e-15);
    assert_eq!(r.meta.format, RecordFormat::PeerAt2);
    assert_eq!(r.meta.original_units, AccelUnit::G);
    assert_eq!(r.meta.sha256_hex.len(), 64);
    let (t, a) = r.peak().unwrap();
    assert!((t - 2.02).abs() < 1e-12, "peak time {t}");
    assert!((a / G - (-0.31882)).abs() < 1e-12, "peak {} g", a / G);
    assert!((r.end_time_s() - 1558.0 * 0.02).abs() < 1e-9);
    assert!(r.processing_log[0].contains("PEER AT2"));
}

#[test]
fn at2_header_variants_and_count_check() {
    // Tolerance exact (1e-15): values are parsed decimal literals times g.
    let body = "  0.1 0.2 0.3 0.4 0.5\n -0.1 -0.2\n";
    for line4 in [
        "NPTS=  7, DT= .01000 SEC",
        "NPTS= 7 DT= 0.0100",
        "   7   0.0100   NPTS, DT",
    ] {
        let text =
            format!("title\nsecond\nACCELERATION TIME SERIES IN UNITS OF G\n{line4}\n{body}");
        let r = parse_at2(&text, "mem.at2").unwrap_or_else(|e| panic!("{line4}: {e}"));
        assert_eq!(r.len(), 7);
        assert!((r.dt_s - 0.01).abs() < 1e-15);
        assert!((r.accel_m_s2[6] - (-0.2 * G)).abs() < 1e-15);
    }
    // Too few values: NPTS mismatch naming the last line.
    let short = "a\nb\nUNITS OF G\nNPTS= 8, DT= 0.01\n1 2 3\n4 5\n";
    let e = parse_at2(short, "short.at2").unwrap_err();
    assert!(
        matches!(
            e,
            MotionError::NptsMismatch {
                expected: 8,
                found: 5,
                line: 6,
                ..
            }
        ),
        "{e}"
    );
    assert!(e.to_string().contains("short.at2:6"), "{e}");
    // Too many: named at the line of the first extra value.
    let long = "a\nb\nUNITS OF G\nNPTS= 3, DT= 0.01\n1 2\n3 4\n";
    let e = parse_at2(long, "long.at2").unwrap_err();
    assert!(
        matches!(e, MotionError::NptsMismatch { line: 6, .. }),
        "{e}"
    );
    // Bad header line 4.
    let e = parse_at2("a\nb\nc\nnothing here\n1\n", "bad.at2").unwrap_err();
    assert!(matches!(e, MotionError::WrongHeader { line: 4, .. }), "{e}");
    // Non-number.
    let e = parse_at2("a\nb\nc\nNPTS= 3, DT= 0.01\n1 x 3\n", "nan.at2").unwrap_err();
    assert!(matches!(e, MotionError::NotANumber { line: 5, .. }), "{e}");
    assert!(
        e.to_string().contains("nan.at2:5") && e.to_string().contains("`x`"),
        "{e}"
    );
    // Truncated header.
    let e = parse_at2("a\nb\n", "trunc.at2").unwrap_err();
    assert!(matches!(e, MotionError::ShortData { .. }), "{e}");
}

/// A K-NET ASCII file written by hand after NIED's published layout (label in columns 1-18).
fn knet_text(counts: &[i64]) -> String {
    let mut s = String::new();
    for (label, value) in [
        ("Origin Time", "2011/03/11 14:46:00"),
        ("Lat.", "38.103"),
        ("Lon.", "142.860"),
        ("Depth. (km)", "24"),
        ("Mag.", "9.0"),
        ("Station Code", "MYG004"),
        ("Station Lat.", "37.6973"),
        ("Station Lon.", "141.0108"),
        ("Station Height(m)", "85"),
        ("Record Time", "2011/03/11 14:46:15"),
        ("Sampling Freq(Hz)", "100Hz"),
        ("Duration Time(s)", "300"),
        ("Dir.", "N-S"),
        ("Scale Factor", "7845(gal)/8223790"),
        ("Max. Acc. (gal)", "2699.943"),
        ("Last Correction", "2011/03/11 14:46:00"),
        ("Memo.", ""),
    ] {
        s.push_str(&format!("{label:<18}{value}\n"));
    }
    for chunk in counts.chunks(8) {
        for c in chunk {
            s.push_str(&format!("{c:>9}"));
        }
        s.push('\n');
    }
    s
}

#[test]
fn knet_counts_scale_and_mean_removal() {
    // Tolerance 1e-12 m/s²: (count − mean)·7845/8223790 gal × 0.01 computed in double precision.
    let counts: Vec<i64> = (0..20).map(|i| 1000 * (i % 5) - 1500 + i).collect();
    let path = temp_file("knet", "NS", &knet_text(&counts));
    let r = read_knet(&path).expect("read K-NET");
    assert_eq!(r.len(), 20);
    assert!((r.dt_s - 0.01).abs() < 1e-15);
    assert_eq!(r.meta.station, "MYG004");
    assert_eq!(r.meta.format, RecordFormat::KnetAscii);
    let scale = 7845.0 / 8_223_790.0;
    let mean = counts.iter().sum::<i64>() as f64 / 20.0;
    for (i, &c) in counts.iter().enumerate() {
        let expect = (c as f64 - mean) * scale * 0.01;
        assert!((r.accel_m_s2[i] - expect).abs() < 1e-12, "sample {i}");
    }
    let mean_after: f64 = r.accel_m_s2.iter().sum::<f64>() / 20.0;
    assert!(mean_after.abs() < 1e-15);
    // read_record detects the format from the first line.
    let auto = read_record(&path, &PlainTextOptions::two_column(AccelUnit::Gal)).unwrap();
    assert_eq!(auto.accel_m_s2, r.accel_m_s2);
}

#[test]
fn knet_errors_name_file_and_line() {
    // Exact: error variants and line numbers.
    let good = knet_text(&[1, 2, 3]);
    let bad_scale = good.replace("7845(gal)/8223790", "7845 gal");
    let e = parse_knet(&bad_scale, "x.NS").unwrap_err();
    assert!(
        matches!(e, MotionError::WrongHeader { line: 14, .. }),
        "{e}"
    );
    let bad_label = good.replacen("Sampling Freq(Hz)", "Sampling Rate    ", 1);
    let e = parse_knet(&bad_label, "x.NS").unwrap_err();
    assert!(
        matches!(e, MotionError::WrongHeader { line: 11, .. }),
        "{e}"
    );
    let bad_value = format!("{good}   12   abc\n");
    let e = parse_knet(&bad_value, "x.NS").unwrap_err();
    assert!(matches!(e, MotionError::NotANumber { line: 19, .. }), "{e}");
    let no_data = knet_text(&[]);
    let e = parse_knet(&no_data, "x.NS").unwrap_err();
    assert!(matches!(e, MotionError::ShortData { .. }), "{e}");
}

#[test]
fn plain_text_two_column_csv_with_header_and_comments() {
    // Tolerance 1e-12: uniform steps, values are decimal literals times 0.01 (gal → m/s²).
    let text = "# station test\n# units gal\ntime,accel\n0.0,1.0\n0.01,2.0\n0.02,-3.0\n0.03,4.0\n";
    let path = temp_file("plain", "csv", text);
    let r = read_plain_text(&path, &PlainTextOptions::two_column(AccelUnit::Gal)).unwrap();
    assert_eq!(r.len(), 4);
    assert!((r.dt_s - 0.01).abs() < 1e-12);
    assert!((r.accel_m_s2[2] - (-0.03)).abs() < 1e-12);
    assert!(r.meta.header.contains("time,accel"));
    assert_eq!(r.meta.format, RecordFormat::PlainText);
}

#[test]
fn plain_text_one_column_and_whitespace() {
    // Tolerance 1e-12: values times g.
    let r = parse_plain_text(
        "# one column in g\n0.1\n0.2\n\n0.3\n",
        "one.txt",
        &PlainTextOptions::one_column(AccelUnit::G, 0.005),
    )
    .unwrap();
    assert_eq!(r.len(), 3);
    assert!((r.dt_s - 0.005).abs() < 1e-15);
    assert!((r.accel_m_s2[2] - 0.3 * G).abs() < 1e-12);
    // Without dt a one-column file is refused with a message saying what to give.
    let e = parse_plain_text(
        "0.1\n0.2\n",
        "one.txt",
        &PlainTextOptions::two_column(AccelUnit::G),
    )
    .unwrap_err();
    assert!(e.to_string().contains("dt"), "{e}");
}

#[test]
fn plain_text_nonuniform_is_resampled_to_smallest_step() {
    // Tolerance 1e-12: linear data a = 2t is reproduced exactly by linear resampling.
    let text = "0.0 0.0\n0.1 0.2\n0.15 0.3\n0.35 0.7\n0.4 0.8\n";
    let r = parse_plain_text(
        text,
        "nu.txt",
        &PlainTextOptions::two_column(AccelUnit::MetersPerSecondSquared),
    )
    .unwrap();
    assert!((r.dt_s - 0.05).abs() < 1e-12, "dt {}", r.dt_s);
    assert_eq!(r.len(), 9);
    for (i, a) in r.accel_m_s2.iter().enumerate() {
        assert!((a - 2.0 * 0.05 * i as f64).abs() < 1e-12, "sample {i}: {a}");
    }
    assert!(r.processing_log.iter().any(|l| l.contains("resampled")));
}

#[test]
fn plain_text_errors() {
    // Exact: error variants and 1-based line numbers.
    let opts = PlainTextOptions::two_column(AccelUnit::G);
    let e = parse_plain_text("t a\n0 1\n0.02 1\n0.01 1\n", "m.txt", &opts).unwrap_err();
    assert!(
        matches!(e, MotionError::NonMonotonicTime { line: 4, .. }),
        "{e}"
    );
    assert!(e.to_string().starts_with("m.txt:4:"), "{e}");
    let e = parse_plain_text("0 1\n0.01 zz\n", "n.txt", &opts).unwrap_err();
    assert!(matches!(e, MotionError::NotANumber { line: 2, .. }), "{e}");
    let e = parse_plain_text("0 1\n0.01 2 3\n", "c.txt", &opts).unwrap_err();
    assert!(matches!(e, MotionError::BadLayout { line: 2, .. }), "{e}");
    let e = parse_plain_text("# nothing\n", "e.txt", &opts).unwrap_err();
    assert!(matches!(e, MotionError::ShortData { .. }), "{e}");
    let e = read_plain_text("/nonexistent/slosh/file.csv", &opts).unwrap_err();
    assert!(matches!(e, MotionError::Io { .. }), "{e}");
}

#[test]
fn sha256_of_known_string() {
    // Exact: the standard SHA-256 test vector for "abc".
    assert_eq!(
        sha256_hex(b"abc"),
        "ba7816bf8f01cfea414140de5dae2223b00361a396177a9cb410ff61f20015ad"
    );
}

/// A byte-order mark before the first value (spreadsheets write one) and a first data row with
/// a value that is not finite must not turn the first data row into a skipped header: the BOM
/// is dropped, and `0,nan` is refused with its line. Exact: the samples are decimal literals.
#[test]
fn a_bom_or_a_nan_never_makes_the_first_row_a_header() {
    let options = PlainTextOptions::two_column(AccelUnit::MetersPerSecondSquared);
    let with_bom = "\u{feff}0,1.5\n0.01,2.5\n0.02,3.5\n";
    let r = parse_plain_text(with_bom, "bom.csv", &options).unwrap();
    assert_eq!(r.len(), 3, "the first row was skipped");
    assert_eq!(r.accel_m_s2[0], 1.5);
    let with_header = "\u{feff}t,a\n0,1.5\n0.01,2.5\n";
    assert_eq!(
        parse_plain_text(with_header, "h.csv", &options)
            .unwrap()
            .len(),
        2
    );
    for first in ["0,nan", "0,inf", "0,-Infinity"] {
        let text = format!("{first}\n0.01,2.5\n0.02,3.5\n");
        let err = parse_plain_text(&text, "nan.csv", &options).unwrap_err();
        assert!(err.to_string().contains("nan.csv:1:"), "{first}: {err}");
    }
}
