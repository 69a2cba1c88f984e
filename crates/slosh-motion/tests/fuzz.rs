//! Fuzzing the record readers (PEER AT2, K-NET ASCII, plain text) with proptest: random bytes
//! and random files of the right shape (headers with any count, step and scale, data lines of
//! numbers and garbage). No input may panic, and no reader may make an allocation larger than
//! a fixed multiple of the file's size (a header count must not size a buffer).

mod fuzz_support;

use fuzz_support::{
    allocation_follows_input, cases, fuzz, largest_allocation_of, LargestAllocation,
};
use proptest::prelude::*;
use slosh_motion::*;

#[global_allocator]
static ALLOCATOR: LargestAllocation = LargestAllocation;

/// Bytes of allocation allowed per input byte: lines (16 B each), values (8 B each), rows of
/// plain text (≈ 56 B each), grown by doubling; plain-text resampling adds up to 1000 samples a row.
const PER_BYTE: usize = 8192;
const SLACK: usize = 1 << 20;

/// A number as record files write it, or something that is almost one.
fn number_token() -> impl Strategy<Value = String> {
    prop_oneof![
        any::<f64>().prop_map(|x| format!("{x}")),
        any::<f64>().prop_map(|x| format!("{x:e}")),
        (-1e6f64..1e6).prop_map(|x| format!("{x:.5}")),
        any::<i64>().prop_map(|i| i.to_string()),
        (-999i32..999, -320i32..320).prop_map(|(m, e)| format!("{m}D{e}")),
        Just(".02".to_string()),
        Just("nan".to_string()),
        Just("-inf".to_string()),
        Just("1e-300".to_string()),
        Just("2305843009213693952".to_string()),
        "[ -~]{0,12}",
    ]
}

/// Lines of tokens separated by spaces, tabs, commas or semicolons.
fn data_lines() -> impl Strategy<Value = String> {
    prop::collection::vec(
        (
            prop::collection::vec(number_token(), 0..9),
            prop_oneof![Just(" "), Just("\t"), Just(","), Just(";"), Just("  ")],
        ),
        0..40,
    )
    .prop_map(|lines| {
        lines
            .into_iter()
            .map(|(tokens, sep)| tokens.join(sep))
            .collect::<Vec<_>>()
            .join("\n")
    })
}

fn at2_file() -> impl Strategy<Value = String> {
    let npts = prop_oneof![
        (0usize..200).prop_map(|n| n.to_string()),
        any::<u64>().prop_map(|n| n.to_string()),
        Just("1000000000000000".to_string()),
        Just("2305843009213693952".to_string()),
        "[ -~]{0,8}",
    ];
    let units = prop_oneof![
        Just("ACCELERATION TIME SERIES IN UNITS OF G".to_string()),
        Just("UNITS OF CM/S2".to_string()),
        "[ -~]{0,40}",
    ];
    let line4 = prop_oneof![
        (npts.clone(), number_token()).prop_map(|(n, d)| format!("NPTS= {n}, DT= {d} SEC")),
        (npts, number_token()).prop_map(|(n, d)| format!("  {n}  {d}  NPTS, DT")),
        "[ -~]{0,40}",
    ];
    ("[ -~]{0,30}", units, line4, data_lines()).prop_map(|(title, units, line4, data)| {
        format!("{title}\nsecond\n{units}\n{line4}\n{data}\n")
    })
}

fn knet_file() -> impl Strategy<Value = String> {
    let labels = [
        "Origin Time",
        "Lat.",
        "Lon.",
        "Depth. (km)",
        "Mag.",
        "Station Code",
        "Station Lat.",
        "Station Lon.",
        "Station Height(m)",
        "Record Time",
        "Sampling Freq(Hz)",
        "Duration Time(s)",
        "Dir.",
        "Scale Factor",
        "Max. Acc. (gal)",
        "Last Correction",
        "Memo.",
    ];
    let freq = prop_oneof![
        Just("100Hz".to_string()),
        number_token().prop_map(|x| format!("{x}Hz")),
    ];
    let scale = prop_oneof![
        Just("7845(gal)/8223790".to_string()),
        (number_token(), number_token()).prop_map(|(a, b)| format!("{a}(gal)/{b}")),
        "[ -~]{0,20}",
    ];
    let counts = prop::collection::vec(
        prop_oneof![any::<i64>().prop_map(|i| i.to_string()), number_token()],
        0..200,
    );
    (
        freq,
        number_token(),
        scale,
        counts,
        0usize..17,
        "[ -~]{0,20}",
    )
        .prop_map(move |(freq, duration, scale, counts, broken, junk)| {
            let mut s = String::new();
            for (k, label) in labels.iter().enumerate() {
                let value = match k {
                    10 => freq.clone(),
                    11 => duration.clone(),
                    13 => scale.clone(),
                    _ => "x".to_string(),
                };
                let label = if k == broken && junk.len() > 15 {
                    junk.as_str()
                } else {
                    label
                };
                s.push_str(&format!("{label:<18}{value}\n"));
            }
            for chunk in counts.chunks(8) {
                s.push_str(&chunk.join(" "));
                s.push('\n');
            }
            s
        })
}

fn plain_options() -> impl Strategy<Value = PlainTextOptions> {
    let dt = prop_oneof![
        Just(None),
        any::<f64>().prop_map(Some),
        (1e-4f64..0.1).prop_map(Some)
    ];
    let units = prop_oneof![
        Just(AccelUnit::G),
        Just(AccelUnit::Gal),
        Just(AccelUnit::MetersPerSecondSquared)
    ];
    (units, dt).prop_map(|(units, dt_s)| PlainTextOptions { units, dt_s })
}

/// Any bytes, read as lossy UTF-8 like the readers do with a file.
fn random_text() -> impl Strategy<Value = String> {
    prop::collection::vec(any::<u8>(), 0..600)
        .prop_map(|b| String::from_utf8_lossy(&b).into_owned())
}

/// Parses with `parse`, failing on an allocation out of proportion to the text; on success,
/// the record must be usable (its samples finite, at() callable).
fn check(
    text: &str,
    parse: impl FnOnce(&str) -> Result<Record>,
) -> std::result::Result<(), String> {
    let (result, largest) = largest_allocation_of(|| parse(text));
    allocation_follows_input(largest, text.len(), PER_BYTE, SLACK)?;
    if let Ok(record) = result {
        if record.accel_m_s2.iter().any(|a| !a.is_finite()) || !record.dt_s.is_finite() {
            return Err(format!(
                "a non-finite sample or step was accepted: {record:?}"
            ));
        }
        let _ = record.at(record.end_time_s() * 0.5);
    }
    Ok(())
}

#[test]
fn fuzz_at2_reader() {
    let n = cases(10_000);
    fuzz("AT2 (shaped)", n, at2_file(), |text| {
        check(&text, |t| parse_at2(t, "f.at2"))
    });
    fuzz("AT2 (random bytes)", n, random_text(), |text| {
        check(&text, |t| parse_at2(t, "f.at2"))
    });
}

#[test]
fn fuzz_knet_reader() {
    let n = cases(10_000);
    fuzz("K-NET (shaped)", n, knet_file(), |text| {
        check(&text, |t| parse_knet(t, "f.NS"))
    });
    fuzz("K-NET (random bytes)", n, random_text(), |text| {
        check(&text, |t| parse_knet(t, "f.NS"))
    });
}

#[test]
fn fuzz_plain_text_reader() {
    let n = cases(10_000);
    fuzz(
        "CSV (shaped)",
        n,
        (data_lines(), plain_options()),
        |(text, options)| check(&text, |t| parse_plain_text(t, "f.csv", &options)),
    );
    fuzz(
        "CSV (random bytes)",
        n,
        (random_text(), plain_options()),
        |(text, options)| check(&text, |t| parse_plain_text(t, "f.csv", &options)),
    );
}
