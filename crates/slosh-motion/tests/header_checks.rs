//! Headers that disagree with their data: absurd counts and steps are refused with a message,
//! a stated duration the data does not fill is a warning, and no message quotes more than a
//! short excerpt of the file.

mod common;

use common::temp_file;
use slosh_motion::*;

fn at2_text(line4: &str, body: &str) -> String {
    format!("title\nsecond\nACCELERATION TIME SERIES IN UNITS OF G\n{line4}\n{body}")
}

#[test]
fn at2_npts_beyond_the_file_size_is_an_error_not_an_abort() {
    for npts in [
        "1000000000000000",
        "2305843009213693952",
        "18446744073709551615",
    ] {
        let text = at2_text(&format!("NPTS= {npts}, DT= 0.01 SEC"), "0.1 0.2 0.3\n");
        let e = parse_at2(&text, "huge.at2").unwrap_err();
        let message = e.to_string();
        assert!(
            matches!(e, MotionError::WrongHeader { line: 4, .. }),
            "{message}"
        );
        assert!(
            message.contains("huge.at2:4") && message.contains("NPTS"),
            "{message}"
        );
    }
}

#[test]
fn at2_absurd_dt_is_an_error_naming_the_step() {
    for dt in ["1e-300", "0", "-0.01", "5000", "1e300"] {
        let text = at2_text(&format!("NPTS= 3, DT= {dt} SEC"), "0.1 0.2 0.3\n");
        let e = parse_at2(&text, "dt.at2").unwrap_err();
        let message = e.to_string();
        assert!(message.contains("dt.at2:4"), "DT {dt}: {message}");
        assert!(message.contains("sample interval"), "DT {dt}: {message}");
    }
    for dt in ["nan", "inf"] {
        let text = at2_text(&format!("NPTS= 3, DT= {dt} SEC"), "0.1 0.2 0.3\n");
        assert!(parse_at2(&text, "dt.at2").is_err(), "DT {dt}");
    }
}

fn knet_text(duration_s: &str, counts: usize) -> String {
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
        ("Duration Time(s)", duration_s),
        ("Dir.", "N-S"),
        ("Scale Factor", "7845(gal)/8223790"),
        ("Max. Acc. (gal)", "2699.943"),
        ("Last Correction", "2011/03/11 14:46:00"),
        ("Memo.", ""),
    ] {
        s.push_str(&format!("{label:<18}{value}\n"));
    }
    for i in 0..counts {
        s.push_str(&format!("{:>9}", (i % 7) as i64 * 100 - 300));
        if i % 8 == 7 {
            s.push('\n');
        }
    }
    s.push('\n');
    s
}

#[test]
fn knet_file_cut_short_of_its_duration_time_is_a_warning() {
    // 1 s of data (100 samples at 100 Hz) where the header states 300 s.
    let path = temp_file("knet-cut", "NS", &knet_text("300", 100));
    let r = read_knet(&path).expect("a cut file is still read");
    assert_eq!(r.len(), 100);
    assert_eq!(r.warnings.len(), 1, "{:?}", r.warnings);
    let w = &r.warnings[0];
    assert!(w.contains("300 s") && w.contains("1 s"), "{w}");
    // The full record: no warning.
    let full = parse_knet(&knet_text("300", 30_000), "full.NS").unwrap();
    assert!(full.warnings.is_empty(), "{:?}", full.warnings);
}

#[test]
fn knet_absurd_sampling_frequency_is_an_error() {
    let text = knet_text("1", 100).replace("100Hz", "1e300Hz");
    let e = parse_knet(&text, "f.NS").unwrap_err();
    assert!(e.to_string().contains("f.NS:11"), "{e}");
}

/// Found by the fuzz target: a scale factor with a tiny denominator turns counts into
/// infinite accelerations, which must be refused, not handed to the solver as NaN.
#[test]
fn knet_scale_factor_giving_infinite_accelerations_is_an_error() {
    let text =
        knet_text("1", 100).replace("7845(gal)/8223790", ".02(gal)/1e-300") + "99999999999\n";
    let e = parse_knet(&text, "f.NS").unwrap_err();
    assert!(e.to_string().contains("not finite"), "{e}");
    let e = parse_at2(
        &at2_text("NPTS=    2, DT= .01000 SEC", "1e308 1e308\n"),
        "big.at2",
    )
    .unwrap_err();
    assert!(e.to_string().contains("not finite"), "{e}");
}

#[test]
fn plain_text_time_column_not_in_seconds_is_an_error() {
    let opts = PlainTextOptions::two_column(AccelUnit::G);
    let e = parse_plain_text("0 1\n10 2\n20 3\n", "ms.csv", &opts).unwrap_err();
    assert!(e.to_string().contains("sample interval"), "{e}");
    let e = parse_plain_text(
        "0.1\n0.2\n",
        "one.txt",
        &PlainTextOptions::one_column(AccelUnit::G, 1e-300),
    )
    .unwrap_err();
    assert!(e.to_string().contains("sample interval"), "{e}");
}

#[test]
fn parse_errors_quote_only_a_short_escaped_excerpt() {
    let secret = format!("root:x:0:0:{}\u{1b}[31m:/bin/bash", "s".repeat(500));
    let cases = [
        parse_at2(
            &at2_text("NPTS= 1, DT= 0.01", &format!("{secret}\n")),
            "a.at2",
        ),
        parse_at2(&format!("a\nb\nc\n{secret}\n"), "b.at2"),
        parse_plain_text(
            &format!("0 1\n{secret} 1\n"),
            "c.csv",
            &PlainTextOptions::two_column(AccelUnit::G),
        ),
        parse_knet(&format!("{secret}\n").repeat(20), "d.NS"),
    ];
    for result in cases {
        let message = result.unwrap_err().to_string();
        assert!(!message.contains(&"s".repeat(61)), "{message}");
        assert!(!message.contains('\u{1b}'), "{message}");
        assert!(message.len() < 400, "{message}");
    }
}
