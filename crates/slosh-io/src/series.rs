//! CSV time series and tables.
//!
//! [`SeriesWriter`] writes a run's `series.csv`: one header row with the bare column names
//! (`t,accel_x,eta_left,...`, looked up by name by scripts and checks) and one row of numbers
//! per output interval, plus a sibling `<stem>_units.csv` with `column,unit` rows.
//! [`TableWriter`] is the same without units, for other tables; [`write_grid_csv`] writes a
//! field sampled on a (row × column) grid, such as a time × position pressure map.
//!
//! Numbers are written in Rust's shortest round-trip representation (the text parses back
//! to the identical `f64`), in plain decimal for ordinary magnitudes and in exponent form
//! (`1.5e-9`) for very small or large ones; non-finite values are written as `NaN`, `inf`,
//! `-inf`, which Python, NumPy, pandas and Rust all parse.

use std::cell::Cell;
use std::fs::File;
use std::io::Write;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crate::error::{create_fresh, ensure_parent, refuse_link, IoError, Result};

/// Formats `x` compactly and losslessly (shortest text that parses back to the same `f64`).
pub fn format_f64(x: f64) -> String {
    if x.is_nan() {
        "NaN".to_string()
    } else if x.is_infinite() {
        if x > 0.0 { "inf" } else { "-inf" }.to_string()
    } else if x == 0.0 || (1e-5..1e16).contains(&x.abs()) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// The file under a [`TableWriter`]: counts the bytes the system took and, after a failed
/// write (a full disk), refuses every later one, so that nothing reaches the file past the
/// point where the writer cut it back to its last whole row.
struct RowFile {
    file: File,
    written: u64,
    failed: Cell<bool>,
}

impl Write for RowFile {
    fn write(&mut self, buf: &[u8]) -> std::io::Result<usize> {
        if self.failed.get() {
            return Err(std::io::Error::other(
                "an earlier write to this file failed",
            ));
        }
        match self.file.write(buf) {
            Ok(n) => {
                self.written += n as u64;
                Ok(n)
            }
            // An interrupted call wrote nothing and is tried again by `write_all`.
            Err(e) if e.kind() == std::io::ErrorKind::Interrupted => Err(e),
            Err(e) => {
                self.failed.set(true);
                Err(e)
            }
        }
    }

    fn flush(&mut self) -> std::io::Result<()> {
        if self.failed.get() {
            return Err(std::io::Error::other(
                "an earlier write to this file failed",
            ));
        }
        self.file.flush()
    }
}

/// A CSV table of numbers with a header row of column names, flushed to disk regularly.
///
/// A failed write (a full disk) cuts the file back to its last whole row and ends the
/// writer: a table on disk never ends mid-row.
///
/// By default every row is flushed as soon as it is written, so that an aborted run leaves
/// all rows written so far on disk; [`TableWriter::set_flush_interval`] trades that for fewer
/// system calls. Dropping the writer flushes it too.
pub struct TableWriter {
    path: PathBuf,
    writer: csv::Writer<RowFile>,
    /// Bytes of the file known to be on disk, ending at a whole row.
    whole_rows_len: u64,
    /// For a table written whole: the file it becomes at [`TableWriter::finish`] (`path` is
    /// then its temporary `.part` sibling).
    finished_path: Option<PathBuf>,
    columns: Vec<String>,
    rows: usize,
    flush_interval: Duration,
    last_flush: Instant,
    fields: Vec<String>,
}

impl std::fmt::Debug for TableWriter {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("TableWriter")
            .field("path", &self.path)
            .field("columns", &self.columns)
            .field("rows", &self.rows)
            .finish_non_exhaustive()
    }
}

impl TableWriter {
    /// Creates (truncating) the CSV file at `path` (creating its folder) and writes the header;
    /// rows appear in the file as they are written (a time series a user may watch).
    ///
    /// Column names must be non-empty and distinct.
    pub fn create<S: AsRef<str>>(path: impl AsRef<Path>, header: &[S]) -> Result<Self> {
        Self::create_at(path.as_ref().to_path_buf(), header)
    }

    /// Creates a table that appears only whole: it is written to `<path>.part` and renamed to
    /// `path` by [`TableWriter::finish`], so a reader never sees it half-written.
    pub fn create_whole<S: AsRef<str>>(path: impl AsRef<Path>, header: &[S]) -> Result<Self> {
        let path = path.as_ref().to_path_buf();
        let mut part = path.clone().into_os_string();
        part.push(".part");
        let mut table = Self::create_at(PathBuf::from(part), header)?;
        table.finished_path = Some(path);
        Ok(table)
    }

    fn create_at<S: AsRef<str>>(path: PathBuf, header: &[S]) -> Result<Self> {
        let columns: Vec<String> = header.iter().map(|s| s.as_ref().to_string()).collect();
        if columns.is_empty() {
            return Err(IoError::invalid(&path, "a table needs at least one column"));
        }
        for (i, c) in columns.iter().enumerate() {
            if c.trim().is_empty() {
                return Err(IoError::invalid(
                    &path,
                    format!("column {i} has an empty name"),
                ));
            }
            if columns[..i].contains(c) {
                return Err(IoError::invalid(
                    &path,
                    format!("column name `{c}` appears twice"),
                ));
            }
        }
        ensure_parent(&path)?;
        let file: File = create_fresh(&path).map_err(|e| IoError::io(&path, e))?;
        let mut writer = csv::WriterBuilder::new().from_writer(RowFile {
            file,
            written: 0,
            failed: Cell::new(false),
        });
        writer
            .write_record(&columns)
            .map_err(|e| csv_err(&path, e))?;
        writer.flush().map_err(|e| IoError::io(&path, e))?;
        Ok(Self {
            path,
            whole_rows_len: writer.get_ref().written,
            writer,
            finished_path: None,
            fields: Vec::with_capacity(columns.len()),
            columns,
            rows: 0,
            flush_interval: Duration::ZERO,
            last_flush: Instant::now(),
        })
    }

    /// Sets how often buffered rows are flushed: `Duration::ZERO` (the default) flushes after
    /// every row; a longer interval flushes on the first row written after it has elapsed.
    pub fn set_flush_interval(&mut self, interval: Duration) {
        self.flush_interval = interval;
    }

    /// Appends one row; `values.len()` must equal the number of columns.
    pub fn write_row(&mut self, values: &[f64]) -> Result<()> {
        if values.len() != self.columns.len() {
            return Err(IoError::invalid(
                &self.path,
                format!(
                    "row has {} values but the table has {} columns",
                    values.len(),
                    self.columns.len()
                ),
            ));
        }
        self.fields.clear();
        self.fields.extend(values.iter().map(|&v| format_f64(v)));
        if let Err(e) = self.writer.write_record(&self.fields) {
            self.cut_to_whole_rows();
            return Err(csv_err(&self.path, e));
        }
        self.after_row()
    }

    /// Appends one row of text fields (quoted as CSV requires); the length must match too.
    pub fn write_text_row<S: AsRef<str>>(&mut self, fields: &[S]) -> Result<()> {
        if fields.len() != self.columns.len() {
            return Err(IoError::invalid(
                &self.path,
                format!(
                    "row has {} fields but the table has {} columns",
                    fields.len(),
                    self.columns.len()
                ),
            ));
        }
        if let Err(e) = self.writer.write_record(fields.iter().map(|s| s.as_ref())) {
            self.cut_to_whole_rows();
            return Err(csv_err(&self.path, e));
        }
        self.after_row()
    }

    fn after_row(&mut self) -> Result<()> {
        self.rows += 1;
        if self.flush_interval.is_zero() || self.last_flush.elapsed() >= self.flush_interval {
            self.flush()?;
        }
        Ok(())
    }

    /// Writes all buffered rows to the file.
    pub fn flush(&mut self) -> Result<()> {
        self.last_flush = Instant::now();
        match self.writer.flush() {
            Ok(()) => {
                self.whole_rows_len = self.writer.get_ref().written;
                Ok(())
            }
            Err(e) => {
                self.cut_to_whole_rows();
                Err(IoError::io(&self.path, e))
            }
        }
    }

    /// After a failed write: the file is cut back to its last whole row on disk, and no later
    /// write (nor the flush when the writer is dropped) reaches it.
    fn cut_to_whole_rows(&mut self) {
        let file = self.writer.get_ref();
        file.failed.set(true);
        // Freeing the partial row's bytes needs no space; if even that fails, the row stays
        // cut (a reader of the file sees one short last line).
        let _ = file.file.set_len(self.whole_rows_len);
    }

    /// Writes the buffered rows and, for a table made by [`TableWriter::create_whole`],
    /// renames it into place (a table that cannot be finished removes its `.part` file).
    pub fn finish(mut self) -> Result<()> {
        self.flush()?;
        if let Some(done) = self.finished_path.clone() {
            refuse_link(&done)?;
            std::fs::rename(&self.path, &done).map_err(|e| IoError::io(&done, e))?;
            self.finished_path = None;
        }
        Ok(())
    }

    /// The file being written.
    pub fn path(&self) -> &Path {
        &self.path
    }

    /// The column names, in order.
    pub fn columns(&self) -> &[String] {
        &self.columns
    }

    /// How many data rows have been written (header not counted).
    pub fn rows_written(&self) -> usize {
        self.rows
    }
}

impl Drop for TableWriter {
    /// A table meant to appear only whole that was not finished (a failed write, an error
    /// of its producer) removes its own `.part` file.
    fn drop(&mut self) {
        if self.finished_path.is_some() {
            self.writer.get_ref().failed.set(true);
            let _ = std::fs::remove_file(&self.path);
        }
    }
}

fn csv_err(path: &Path, source: csv::Error) -> IoError {
    IoError::Csv {
        path: path.to_path_buf(),
        reason: source,
    }
}

/// The path of the units file that goes with a series file: `dir/series.csv` →
/// `dir/series_units.csv`.
pub fn units_path_for(path: &Path) -> PathBuf {
    let stem = path
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "series".to_string());
    path.with_file_name(format!("{stem}_units.csv"))
}

/// The time-series writer of a run (`series.csv` + `series_units.csv`).
///
/// The header row of the main file holds the bare column names; the units live in the units
/// file (`column,unit` rows, in column order).
#[derive(Debug)]
pub struct SeriesWriter {
    table: TableWriter,
    units: Vec<String>,
    units_path: PathBuf,
}

impl SeriesWriter {
    /// Creates `path` with the header row of column names and writes the units file beside
    /// it. `columns` are (name, unit) pairs, e.g. `("t", "s")`, `("eta_left", "m")`; use an
    /// empty unit (or `"1"`) for dimensionless columns.
    pub fn create<N: AsRef<str>, U: AsRef<str>>(
        path: impl AsRef<Path>,
        columns: &[(N, U)],
    ) -> Result<Self> {
        let path = path.as_ref();
        let names: Vec<&str> = columns.iter().map(|(n, _)| n.as_ref()).collect();
        let units: Vec<String> = columns
            .iter()
            .map(|(_, u)| u.as_ref().to_string())
            .collect();
        let table = TableWriter::create(path, &names)?;
        let units_path = units_path_for(path);
        let mut uw = TableWriter::create(&units_path, &["column", "unit"])?;
        for (n, u) in names.iter().zip(&units) {
            uw.write_text_row(&[*n, u.as_str()])?;
        }
        uw.flush()?;
        Ok(Self {
            table,
            units,
            units_path,
        })
    }

    /// Appends one row (one value per column, in column order). Flushed per the table's
    /// flush policy (every row by default).
    pub fn write_row(&mut self, values: &[f64]) -> Result<()> {
        self.table.write_row(values)
    }

    /// Writes all buffered rows to the file.
    pub fn flush(&mut self) -> Result<()> {
        self.table.flush()
    }

    /// See [`TableWriter::set_flush_interval`].
    pub fn set_flush_interval(&mut self, interval: Duration) {
        self.table.set_flush_interval(interval);
    }

    /// The column names, in order.
    pub fn columns(&self) -> &[String] {
        self.table.columns()
    }

    /// The units, in column order.
    pub fn units(&self) -> &[String] {
        &self.units
    }

    /// The position of the column called `name`.
    pub fn column_index(&self, name: &str) -> Option<usize> {
        self.table.columns().iter().position(|c| c == name)
    }

    /// The series file.
    pub fn path(&self) -> &Path {
        self.table.path()
    }

    /// The units file written beside it.
    pub fn units_path(&self) -> &Path {
        &self.units_path
    }

    /// How many data rows have been written.
    pub fn rows_written(&self) -> usize {
        self.table.rows_written()
    }
}

/// Writes a field sampled on a grid as a wide CSV table: the header is `row_name` followed by
/// the column coordinates (as numbers, e.g. `t,0.05,0.15,0.25`), then one row per row
/// coordinate: the coordinate followed by its values. `values` is row-major:
/// `values[i * col_coords.len() + j]` belongs to `(row_coords[i], col_coords[j])`.
pub fn write_grid_csv(
    path: impl AsRef<Path>,
    row_name: &str,
    row_coords: &[f64],
    col_coords: &[f64],
    values: &[f64],
) -> Result<()> {
    let path = path.as_ref();
    if values.len() != row_coords.len() * col_coords.len() {
        return Err(IoError::invalid(
            path,
            format!(
                "grid has {} × {} points but {} values",
                row_coords.len(),
                col_coords.len(),
                values.len()
            ),
        ));
    }
    let mut header = vec![row_name.to_string()];
    header.extend(col_coords.iter().map(|&c| format_f64(c)));
    let mut w = TableWriter::create_whole(path, &header)?;
    w.set_flush_interval(Duration::MAX);
    let mut row = Vec::with_capacity(col_coords.len() + 1);
    for (i, &r) in row_coords.iter().enumerate() {
        row.clear();
        row.push(r);
        row.extend_from_slice(&values[i * col_coords.len()..(i + 1) * col_coords.len()]);
        w.write_row(&row)?;
    }
    w.finish()
}

/// A numeric CSV table read back into memory (see [`read_table`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Table {
    /// The header row.
    pub columns: Vec<String>,
    /// The data rows, each as long as `columns`.
    pub rows: Vec<Vec<f64>>,
}

impl Table {
    /// The values of the column called `name`, top to bottom.
    pub fn column(&self, name: &str) -> Option<Vec<f64>> {
        let j = self.columns.iter().position(|c| c == name)?;
        Some(self.rows.iter().map(|r| r[j]).collect())
    }
}

/// Reads a numeric CSV table with a header row (such as `series.csv`) back into memory.
/// A field that does not parse as a number is an error naming the row and column.
pub fn read_table(path: impl AsRef<Path>) -> Result<Table> {
    let path = path.as_ref();
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .from_path(path)
        .map_err(|e| csv_err(path, e))?;
    let columns: Vec<String> = reader
        .headers()
        .map_err(|e| csv_err(path, e))?
        .iter()
        .map(str::to_string)
        .collect();
    let mut rows = Vec::new();
    for (i, rec) in reader.records().enumerate() {
        let rec = rec.map_err(|e| csv_err(path, e))?;
        let row = rec
            .iter()
            .enumerate()
            .map(|(j, f)| {
                f.trim().parse::<f64>().map_err(|_| {
                    IoError::invalid(
                        path,
                        format!(
                            "data row {} column `{}`: `{f}` is not a number",
                            i + 1,
                            columns.get(j).map(String::as_str).unwrap_or("?")
                        ),
                    )
                })
            })
            .collect::<Result<Vec<f64>>>()?;
        rows.push(row);
    }
    Ok(Table { columns, rows })
}
