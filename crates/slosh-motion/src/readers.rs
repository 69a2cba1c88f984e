//! Readers for recorded ground motion: PEER NGA `.AT2`, K-NET / KiK-net ASCII, plain text.
//!
//! Every reader returns a [`Record`] in m/s² with uniform samples starting at time 0, with the
//! file's SHA-256 and header kept in [`RecordMeta`]. The `parse_*` functions take the file's
//! text (and a label used in error messages) for callers that already hold the bytes.

use crate::error::{MotionError, Result};
use crate::record::{AccelUnit, Record, RecordFormat, RecordMeta};
use sha2::{Digest, Sha256};
use std::path::Path;

/// SHA-256 of `bytes` as 64 lowercase hex characters.
pub fn sha256_hex(bytes: &[u8]) -> String {
    let digest = Sha256::digest(bytes);
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

/// The bytes of a data file, its error naming the path.
pub(crate) fn read_bytes(path: &Path) -> Result<Vec<u8>> {
    std::fs::read(path).map_err(|source| MotionError::Io {
        path: path.display().to_string(),
        source,
    })
}

/// Parses a number as written in record files: Fortran `D` exponents and a leading `.` accepted.
fn parse_number(token: &str) -> Option<f64> {
    let t = token.trim();
    let v = t.parse::<f64>().ok().or_else(|| {
        if t.contains(['d', 'D']) {
            t.replace(['d', 'D'], "e").parse::<f64>().ok()
        } else {
            None
        }
    })?;
    v.is_finite().then_some(v)
}

/// Longest excerpt of a file's line that an error message quotes, in characters.
const EXCERPT_CHARS: usize = 60;

/// A short, escaped excerpt of a line of a data file for error messages: at most
/// [`EXCERPT_CHARS`] characters, control and non-printing characters escaped, so that a
/// message never echoes more of a file than the start of the offending line.
pub(crate) fn excerpt(line: &str) -> String {
    let mut out = String::new();
    let mut count = 0;
    for c in line.trim().chars() {
        let escaped: String = if c == '`' || c.is_control() || !c.is_ascii() && c.is_whitespace() {
            c.escape_debug().collect()
        } else {
            c.to_string()
        };
        count += escaped.chars().count();
        if count > EXCERPT_CHARS {
            out.push('…');
            return out;
        }
        out.push_str(&escaped);
    }
    out
}

/// Shortest and longest sample intervals accepted for a ground-motion record, s (100 kHz to
/// 1 Hz sampling). Accelerographs sample at 50–1000 Hz; values outside these bounds come from
/// a wrong header or a time column in other units than seconds.
pub const SAMPLE_INTERVAL_RANGE_S: (f64, f64) = (1e-5, 1.0);

/// Checks that `dt_s` is a plausible sample interval; `npts` samples would last `npts·dt`.
fn check_sample_interval(dt_s: f64, npts: usize, source: &str, line: usize) -> Result<()> {
    let (lo, hi) = SAMPLE_INTERVAL_RANGE_S;
    if dt_s.is_finite() && (lo..=hi).contains(&dt_s) {
        return Ok(());
    }
    Err(MotionError::BadLayout {
        path: source.into(),
        line,
        message: format!(
            "sample interval {dt_s:e} s is not plausible for a ground-motion record \
             ({npts} samples would last {:e} s); a record is sampled every {lo:e} s to {hi} s: \
             fix the time step (DT, sampling frequency or time column, in seconds)",
            npts as f64 * dt_s
        ),
    })
}

/// Most samples a non-uniform plain-text record is resampled to, per row of the file and in
/// all: the smallest step sets the grid, and near-duplicate times would otherwise make a small
/// file allocate without bound.
const RESAMPLED_PER_ROW: usize = 1000;
const MAX_RESAMPLED: usize = 50_000_000;

/// The most whitespace-separated values `bytes` can hold (one character and one separator
/// each): no reader reserves room for more samples than this, whatever a header announces.
fn max_values_in(bytes: &[u8]) -> usize {
    bytes.len() / 2 + 1
}

// ---------------------------------------------------------------------------------------------
// PEER AT2
// ---------------------------------------------------------------------------------------------

/// Reads a PEER NGA `.AT2` file (values in g) into a record in m/s².
///
/// Layout: 4 header lines, the 4th giving the count and step, e.g. `NPTS=  1559, DT= .02000 SEC`
/// (also `NPTS= 1559 DT= 0.0200`, or the older `1559  0.0200  NPTS, DT`); then the values,
/// any number a line (usually 5 or 8). The number of values must equal NPTS.
pub fn read_at2(path: impl AsRef<Path>) -> Result<Record> {
    let path = path.as_ref();
    let bytes = read_bytes(path)?;
    parse_at2_bytes(&bytes, &path.display().to_string())
}

/// Parses the text of a PEER `.AT2` file; `source` names it in errors and metadata.
pub fn parse_at2(text: &str, source: &str) -> Result<Record> {
    parse_at2_bytes(text.as_bytes(), source)
}

fn parse_at2_bytes(bytes: &[u8], source: &str) -> Result<Record> {
    const FORMAT: &str = "PEER AT2";
    let text = String::from_utf8_lossy(bytes);
    let lines: Vec<&str> = text.lines().collect();
    if lines.len() < 4 {
        return Err(MotionError::ShortData {
            path: source.into(),
            line: lines.len(),
            message: format!(
                "a PEER AT2 file has 4 header lines, this one has only {} lines",
                lines.len()
            ),
        });
    }
    let (npts, dt_s) = parse_at2_npts_dt(lines[3]).ok_or_else(|| MotionError::WrongHeader {
        path: source.into(),
        line: 4,
        format: FORMAT,
        expected: "`NPTS= <count>, DT= <step> SEC` on line 4".into(),
        found: excerpt(lines[3]),
    })?;
    if npts > max_values_in(bytes) {
        return Err(MotionError::WrongHeader {
            path: source.into(),
            line: 4,
            format: FORMAT,
            expected: format!(
                "an NPTS no larger than the {} values a file of {} bytes can hold",
                max_values_in(bytes),
                bytes.len()
            ),
            found: excerpt(lines[3]),
        });
    }
    check_sample_interval(dt_s, npts, source, 4)?;
    // Line 3 names the units ("... IN UNITS OF G"); refuse a file that names other units.
    let units_line = lines[2].to_ascii_uppercase();
    let units_word = units_line
        .find("UNITS OF")
        .and_then(|at| units_line[at + 8..].split_whitespace().next());
    if units_word.is_some_and(|w| w.trim_end_matches(['.', ',']) != "G") {
        return Err(MotionError::WrongHeader {
            path: source.into(),
            line: 3,
            format: FORMAT,
            expected: "acceleration in units of g (e.g. `ACCELERATION TIME SERIES IN UNITS OF G`)"
                .into(),
            found: excerpt(lines[2]),
        });
    }
    let mut values = Vec::with_capacity(npts);
    for (k, line) in lines.iter().enumerate().skip(4) {
        let line_no = k + 1;
        for token in line.split_whitespace() {
            let v = parse_number(token).ok_or_else(|| MotionError::NotANumber {
                path: source.into(),
                line: line_no,
                token: excerpt(token),
            })?;
            if values.len() == npts {
                return Err(MotionError::NptsMismatch {
                    path: source.into(),
                    line: line_no,
                    expected: npts,
                    found: npts + 1,
                });
            }
            values.push(v);
        }
    }
    if values.len() != npts {
        return Err(MotionError::NptsMismatch {
            path: source.into(),
            line: lines.len(),
            expected: npts,
            found: values.len(),
        });
    }
    let factor = AccelUnit::G.to_m_s2();
    let accel: Vec<f64> = values.iter().map(|v| v * factor).collect();
    check_finite_samples(&accel, source)?;
    Ok(Record {
        dt_s,
        start_time_s: 0.0,
        accel_m_s2: accel,
        meta: RecordMeta {
            source_file: source.into(),
            format: RecordFormat::PeerAt2,
            original_units: AccelUnit::G,
            original_npts: npts,
            original_dt_s: dt_s,
            station: String::new(),
            header: lines[..4].join("\n"),
            sha256_hex: sha256_hex(bytes),
        },
        processing_log: vec![format!(
            "read PEER AT2 `{source}` ({npts} samples, dt {dt_s} s, g -> m/s2 x {factor})"
        )],
        warnings: Vec::new(),
    })
}

/// Extracts (NPTS, DT) from the 4th AT2 header line.
fn parse_at2_npts_dt(line: &str) -> Option<(usize, f64)> {
    let upper = line.to_ascii_uppercase();
    let value_after = |key: &str| -> Option<&str> {
        let at = upper.find(key)?;
        let rest = &line[at + key.len()..];
        let rest = rest.trim_start();
        let rest = rest.strip_prefix('=').or_else(|| rest.strip_prefix(':'))?;
        rest.split(|c: char| c.is_whitespace() || c == ',')
            .find(|s| !s.is_empty())
    };
    if let (Some(n), Some(d)) = (value_after("NPTS"), value_after("DT")) {
        let npts = n.parse::<usize>().ok()?;
        let dt = parse_number(d)?;
        return Some((npts, dt));
    }
    // Older layout: `  1559   0.0200   NPTS, DT`.
    if upper.contains("NPTS") && upper.contains("DT") {
        let mut nums = line.split([' ', ',', '\t']).filter(|s| !s.is_empty());
        let npts = nums.next()?.parse::<usize>().ok()?;
        let dt = parse_number(nums.next()?)?;
        return Some((npts, dt));
    }
    None
}

// ---------------------------------------------------------------------------------------------
// K-NET / KiK-net ASCII
// ---------------------------------------------------------------------------------------------

/// Reads a K-NET or KiK-net ASCII file (NIED) into a record in m/s².
///
/// Layout: 17 header lines, each a label in the first 18 columns and a value (`Origin Time`,
/// `Lat.`, `Lon.`/`Long.`, `Depth. (km)`, `Mag.`, `Station Code`, `Station Lat.`,
/// `Station Lon.`/`Station Long.`, `Station Height(m)`, `Record Time`, `Sampling Freq(Hz)`
/// (e.g. `100Hz`), `Duration Time(s)`, `Dir.`, `Scale Factor` (e.g. `7845(gal)/8223790`),
/// `Max. Acc. (gal)`, `Last Correction`, `Memo.`); then integer counts, 8 a line.
/// Acceleration in gal = count × numerator / denominator of the scale factor; the mean of the
/// whole record is subtracted (as NIED prescribes) and gal (cm/s²) is converted to m/s².
pub fn read_knet(path: impl AsRef<Path>) -> Result<Record> {
    let path = path.as_ref();
    let bytes = read_bytes(path)?;
    parse_knet_bytes(&bytes, &path.display().to_string())
}

/// Parses the text of a K-NET / KiK-net ASCII file; `source` names it in errors and metadata.
pub fn parse_knet(text: &str, source: &str) -> Result<Record> {
    parse_knet_bytes(text.as_bytes(), source)
}

/// The 17 K-NET header labels (alternatives separated by `|`), in order.
const KNET_LABELS: [&str; 17] = [
    "Origin Time",
    "Lat.",
    "Lon.|Long.",
    "Depth.",
    "Mag.",
    "Station Code",
    "Station Lat.",
    "Station Lon.|Station Long.",
    "Station Height",
    "Record Time",
    "Sampling Freq",
    "Duration Time",
    "Dir.",
    "Scale Factor",
    "Max. Acc.|Max Acc.",
    "Last Correction",
    "Memo.",
];

fn parse_knet_bytes(bytes: &[u8], source: &str) -> Result<Record> {
    const FORMAT: &str = "K-NET ASCII";
    let text = String::from_utf8_lossy(bytes);
    let lines: Vec<&str> = text.lines().collect();
    if lines.len() < 17 {
        return Err(MotionError::ShortData {
            path: source.into(),
            line: lines.len(),
            message: format!(
                "a K-NET ASCII file has 17 header lines, this one has only {} lines",
                lines.len()
            ),
        });
    }
    // Check each label and take the value: the text after the 18-column label field (or after
    // the label itself when the columns are not aligned).
    let mut values: Vec<String> = Vec::with_capacity(17);
    for (k, label) in KNET_LABELS.iter().enumerate() {
        let line = lines[k];
        let found = label.split('|').find(|alt| {
            line.to_ascii_lowercase()
                .starts_with(&alt.to_ascii_lowercase())
        });
        let Some(_) = found else {
            return Err(MotionError::WrongHeader {
                path: source.into(),
                line: k + 1,
                format: FORMAT,
                expected: format!("a line starting with `{}`", label.replace('|', "` or `")),
                found: excerpt(line),
            });
        };
        let value = if line.len() > 18 && line.is_char_boundary(18) {
            line[18..].trim()
        } else {
            ""
        };
        values.push(value.to_string());
    }
    let freq_text = values[10]
        .trim_end_matches(|c: char| c.is_ascii_alphabetic())
        .trim();
    let freq_hz = parse_number(freq_text)
        .filter(|f| *f > 0.0)
        .ok_or_else(|| MotionError::WrongHeader {
            path: source.into(),
            line: 11,
            format: FORMAT,
            expected: "a positive sampling frequency such as `100Hz`".into(),
            found: excerpt(lines[10]),
        })?;
    let scale = parse_knet_scale(&values[13]).ok_or_else(|| MotionError::WrongHeader {
        path: source.into(),
        line: 14,
        format: FORMAT,
        expected: "a scale factor such as `7845(gal)/8223790`".into(),
        found: excerpt(lines[13]),
    })?;
    let mut gal = Vec::new();
    for (k, line) in lines.iter().enumerate().skip(17) {
        for token in line.split_whitespace() {
            let count = token.parse::<i64>().map_err(|_| MotionError::NotANumber {
                path: source.into(),
                line: k + 1,
                token: excerpt(token),
            })?;
            gal.push(count as f64 * scale);
        }
    }
    if gal.is_empty() {
        return Err(MotionError::ShortData {
            path: source.into(),
            line: lines.len(),
            message: "the header is complete but no data values follow it".into(),
        });
    }
    let npts = gal.len();
    let dt_s = 1.0 / freq_hz;
    check_sample_interval(dt_s, npts, source, 11)?;
    let warnings: Vec<String> = knet_duration_warning(&values[11], npts, dt_s, source)
        .into_iter()
        .collect();
    let mean_gal = gal.iter().sum::<f64>() / npts as f64;
    let to_m_s2 = AccelUnit::Gal.to_m_s2();
    let accel: Vec<f64> = gal.iter().map(|a| (a - mean_gal) * to_m_s2).collect();
    check_finite_samples(&accel, source)?;
    Ok(Record {
        dt_s,
        start_time_s: 0.0,
        accel_m_s2: accel,
        meta: RecordMeta {
            source_file: source.into(),
            format: RecordFormat::KnetAscii,
            original_units: AccelUnit::Gal,
            original_npts: npts,
            original_dt_s: dt_s,
            station: values[5].clone(),
            header: lines[..17].join("\n"),
            sha256_hex: sha256_hex(bytes),
        },
        processing_log: vec![format!(
            "read K-NET ASCII `{source}` (station {}, dir {}, {npts} samples at {freq_hz} Hz, counts x {} = gal, mean {mean_gal:.6} gal removed, gal -> m/s2 x 0.01)",
            values[5], values[12], values[13]
        )],
        warnings,
    })
}

/// A warning when the K-NET header's `Duration Time` (s) disagrees with the `npts` samples
/// every `dt_s` the file holds (by more than one sample interval and 1 %): a file cut short
/// (or padded) would otherwise run silently with a motion that stops early.
fn knet_duration_warning(stated: &str, npts: usize, dt_s: f64, source: &str) -> Option<String> {
    let held_s = npts as f64 * dt_s;
    let Some(stated_s) = parse_number(stated) else {
        return Some(format!(
            "{source}:12: `Duration Time` `{}` is not a number of seconds; the record holds \
             {npts} samples = {held_s} s",
            excerpt(stated)
        ));
    };
    let tolerance_s = dt_s.max(0.01 * stated_s.abs());
    ((stated_s - held_s).abs() > tolerance_s).then(|| {
        format!(
            "{source}:12: the header states a duration of {stated_s} s but the file holds \
             {npts} samples at {} Hz = {held_s} s; the file may be cut short (the motion is \
             zero after {held_s} s): check the download or the header",
            1.0 / dt_s
        )
    })
}

/// `7845(gal)/8223790` → 7845/8223790 (gal per count).
fn parse_knet_scale(value: &str) -> Option<f64> {
    let (num, den) = value.split_once('/')?;
    let num = num.trim();
    let num = num.strip_suffix("(gal)").unwrap_or(num).trim();
    let num = parse_number(num)?;
    let den = parse_number(den.trim())?;
    (den != 0.0).then_some(num / den)
}

// ---------------------------------------------------------------------------------------------
// Plain text
// ---------------------------------------------------------------------------------------------

/// How to read a plain-text record.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlainTextOptions {
    /// Units of the acceleration column.
    pub units: AccelUnit,
    /// Sample interval, s, for a one-column file (ignored for two columns, which give time).
    pub dt_s: Option<f64>,
}

impl PlainTextOptions {
    /// Options for a two-column (time, accel) file in `units`.
    pub fn two_column(units: AccelUnit) -> Self {
        PlainTextOptions { units, dt_s: None }
    }

    /// Options for a one-column file in `units` sampled every `dt_s` seconds.
    pub fn one_column(units: AccelUnit, dt_s: f64) -> Self {
        PlainTextOptions {
            units,
            dt_s: Some(dt_s),
        }
    }
}

/// Reads a plain-text record: CSV (`,` or `;`) or whitespace-separated columns.
///
/// * Two columns: time (s), acceleration. The time column must increase strictly. If the
///   steps are uniform (within 1e-6 relative) they are used as they are; otherwise the record is
///   resampled by linear interpolation onto a uniform grid with the smallest step found,
///   from the first to the last time (the log says so). The first time becomes time 0.
/// * One column: acceleration, sampled every `options.dt_s` (required).
///
/// Lines starting with `#` and empty lines are skipped, and so is one header line (a line
/// with a non-number) before the first data line. Values are converted from `options.units`.
pub fn read_plain_text(path: impl AsRef<Path>, options: &PlainTextOptions) -> Result<Record> {
    let path = path.as_ref();
    let bytes = read_bytes(path)?;
    parse_plain_text_bytes(&bytes, &path.display().to_string(), options)
}

/// Parses plain-text record content; `source` names it in errors and metadata.
pub fn parse_plain_text(text: &str, source: &str, options: &PlainTextOptions) -> Result<Record> {
    parse_plain_text_bytes(text.as_bytes(), source, options)
}

/// The numbers of a plain-text table: comment lines (`#`) and one header line naming the
/// columns kept as its header, every data line with the same number of columns.
pub(crate) struct NumericTable {
    /// Comment and header lines.
    pub header_lines: Vec<String>,
    /// (1-based line, values) of each data line.
    pub rows: Vec<(usize, Vec<f64>)>,
    /// Columns of every data line.
    pub columns: usize,
    /// The last line read (1-based).
    pub last_line: usize,
}

/// Reads the numbers of a plain-text table of at most `max_columns` columns (comma, semicolon
/// or white space between values); `layout` says what the columns are, for the error of a
/// line with more.
pub(crate) fn numeric_table(
    text: &str,
    source: &str,
    max_columns: usize,
    layout: &str,
) -> Result<NumericTable> {
    // A byte-order mark (spreadsheets write one before UTF-8 CSV) is not part of the first
    // value: left in, it would make the first data line read as a header.
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut header_lines: Vec<String> = Vec::new();
    let mut rows: Vec<(usize, Vec<f64>)> = Vec::new();
    let mut columns: Option<usize> = None;
    let mut header_skipped = false;
    let mut last_line = 0;
    for (k, raw) in text.lines().enumerate() {
        let line_no = k + 1;
        last_line = line_no;
        let line = raw.trim();
        if line.is_empty() {
            continue;
        }
        if line.starts_with('#') {
            header_lines.push(line.to_string());
            continue;
        }
        let tokens: Vec<&str> = line
            .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
            .filter(|s| !s.is_empty())
            .collect();
        let parsed: Vec<Option<f64>> = tokens.iter().map(|t| parse_number(t)).collect();
        if let Some(bad) = parsed.iter().position(Option::is_none) {
            // A header names its columns; a line whose only non-numbers are numbers that are
            // not finite (`nan`, `inf`) is a data line with a bad value, never a header.
            let names_columns = tokens
                .iter()
                .zip(&parsed)
                .any(|(t, p)| p.is_none() && t.parse::<f64>().is_err());
            if rows.is_empty() && !header_skipped && names_columns {
                header_skipped = true;
                header_lines.push(line.to_string());
                continue;
            }
            return Err(MotionError::NotANumber {
                path: source.into(),
                line: line_no,
                token: excerpt(tokens[bad]),
            });
        }
        let row: Vec<f64> = parsed.into_iter().flatten().collect();
        match columns {
            None => {
                if row.len() > max_columns {
                    return Err(MotionError::BadLayout {
                        path: source.into(),
                        line: line_no,
                        message: format!("found {} columns; {layout}", row.len()),
                    });
                }
                columns = Some(row.len());
            }
            Some(c) if c != row.len() => {
                return Err(MotionError::BadLayout {
                    path: source.into(),
                    line: line_no,
                    message: format!(
                        "found {} columns where earlier lines have {c}; every data line needs the same number of columns",
                        row.len()
                    ),
                });
            }
            _ => {}
        }
        rows.push((line_no, row));
    }
    let Some(columns) = columns else {
        return Err(MotionError::ShortData {
            path: source.into(),
            line: last_line,
            message: "no data lines found (only comments, a header or empty lines)".into(),
        });
    };
    Ok(NumericTable {
        header_lines,
        rows,
        columns,
        last_line,
    })
}

fn parse_plain_text_bytes(
    bytes: &[u8],
    source: &str,
    options: &PlainTextOptions,
) -> Result<Record> {
    let text = String::from_utf8_lossy(bytes);
    let NumericTable {
        header_lines,
        rows,
        columns,
        last_line,
    } = numeric_table(
        &text,
        source,
        2,
        "a plain-text record has 2 columns (time s, acceleration) or 1 (acceleration, with dt \
         given)",
    )?;
    let factor = options.units.to_m_s2();
    let mut log = Vec::new();
    let (dt_s, accel, original_dt_s) = if columns == 1 {
        let dt_s = options
            .dt_s
            .filter(|d| d.is_finite() && *d > 0.0)
            .ok_or_else(|| MotionError::BadLayout {
                path: source.into(),
                line: rows[0].0,
                message:
                    "a one-column record needs the sample interval: give dt (s) when reading it"
                        .into(),
            })?;
        let accel: Vec<f64> = rows.iter().map(|(_, r)| r[0] * factor).collect();
        log.push(format!(
            "read plain text `{source}` (1 column, {} samples, dt {dt_s} s given, {} -> m/s2 x {factor})",
            accel.len(),
            options.units
        ));
        (dt_s, accel, dt_s)
    } else {
        if rows.len() < 2 {
            return Err(MotionError::ShortData {
                path: source.into(),
                line: last_line,
                message: "a two-column record needs at least 2 data lines to define its time step"
                    .into(),
            });
        }
        let mut min_step = f64::INFINITY;
        for w in rows.windows(2) {
            let (t0, t1) = (w[0].1[0], w[1].1[0]);
            if t1 <= t0 {
                return Err(MotionError::NonMonotonicTime {
                    path: source.into(),
                    line: w[1].0,
                    time_s: t1,
                    previous_s: t0,
                });
            }
            min_step = min_step.min(t1 - t0);
        }
        let t_first = rows[0].1[0];
        let t_last = rows[rows.len() - 1].1[0];
        let mean_step = (t_last - t_first) / (rows.len() - 1) as f64;
        let uniform = rows
            .windows(2)
            .all(|w| ((w[1].1[0] - w[0].1[0]) - mean_step).abs() <= 1e-6 * mean_step);
        let accel: Vec<f64>;
        let dt_s;
        if uniform {
            dt_s = mean_step;
            accel = rows.iter().map(|(_, r)| r[1] * factor).collect();
            log.push(format!(
                "read plain text `{source}` (2 columns, {} samples, uniform dt {dt_s} s, {} -> m/s2 x {factor})",
                accel.len(),
                options.units
            ));
        } else {
            dt_s = min_step;
            let n_new = ((t_last - t_first) / dt_s + 1e-9).floor() as usize + 1;
            check_sample_interval(dt_s, n_new, source, rows[0].0)?;
            let most = (RESAMPLED_PER_ROW * rows.len()).min(MAX_RESAMPLED);
            if n_new > most {
                return Err(MotionError::InvalidArgument(format!(
                    "{source}: the smallest time step {dt_s} s would make {n_new} samples from {} rows (at most {most}); remove near-duplicate time rows",
                    rows.len()
                )));
            }
            let mut out = Vec::with_capacity(n_new);
            let mut j = 0;
            for i in 0..n_new {
                let t = (t_first + i as f64 * dt_s).min(t_last);
                while j + 2 < rows.len() && rows[j + 1].1[0] < t {
                    j += 1;
                }
                let (ta, aa) = (rows[j].1[0], rows[j].1[1]);
                let (tb, ab) = (rows[j + 1].1[0], rows[j + 1].1[1]);
                let w = ((t - ta) / (tb - ta)).clamp(0.0, 1.0);
                out.push((aa + w * (ab - aa)) * factor);
            }
            accel = out;
            log.push(format!(
                "read plain text `{source}` (2 columns, {} rows, non-uniform time: resampled linearly to the smallest step {dt_s} s -> {} samples, {} -> m/s2 x {factor})",
                rows.len(),
                accel.len(),
                options.units
            ));
        }
        if t_first != 0.0 {
            log.push(format!(
                "time column starts at {t_first} s; record re-zeroed to start at 0"
            ));
        }
        (dt_s, accel, dt_s)
    };
    check_sample_interval(dt_s, accel.len(), source, rows[0].0)?;
    check_finite_samples(&accel, source)?;
    Ok(Record {
        dt_s,
        start_time_s: 0.0,
        meta: RecordMeta {
            source_file: source.into(),
            format: RecordFormat::PlainText,
            original_units: options.units,
            original_npts: rows.len(),
            original_dt_s,
            station: String::new(),
            header: header_lines.join("\n"),
            sha256_hex: sha256_hex(bytes),
        },
        accel_m_s2: accel,
        processing_log: log,
        warnings: Vec::new(),
    })
}

// ---------------------------------------------------------------------------------------------
// Format detection
// ---------------------------------------------------------------------------------------------

/// Reads a record, choosing the reader from the content and name: a first line starting with
/// `Origin Time` is K-NET ASCII; a name ending in `.at2` (any case) is PEER AT2; anything else
/// is plain text read with `plain_options`.
pub fn read_record(path: impl AsRef<Path>, plain_options: &PlainTextOptions) -> Result<Record> {
    let path = path.as_ref();
    let bytes = read_bytes(path)?;
    let source = path.display().to_string();
    let is_at2 = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("at2"));
    if bytes.starts_with(b"Origin Time") {
        parse_knet_bytes(&bytes, &source)
    } else if is_at2 {
        parse_at2_bytes(&bytes, &source)
    } else {
        parse_plain_text_bytes(&bytes, &source, plain_options)
    }
}

/// Refuses a record whose accelerations are not all finite after its units and scale factor
/// were applied (a scale factor such as `1(gal)/1e-300`, or values near the largest number).
fn check_finite_samples(accel: &[f64], source: &str) -> Result<()> {
    match accel.iter().position(|a| !a.is_finite()) {
        None => Ok(()),
        Some(k) => Err(MotionError::InvalidArgument(format!(
            "{source}: sample {} is not finite after the units and scale factor were applied \
             ({}); check the scale factor and the values",
            k + 1,
            accel[k]
        ))),
    }
}
