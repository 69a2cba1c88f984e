//! The error type of this crate: every reader error names the file and the 1-based line.

use thiserror::Error;

/// What can go wrong reading or processing a ground-motion record.
///
/// `path` is the file as the caller gave it (or a label such as `<string>` for text parsed from
/// memory); `line` is 1-based.
#[derive(Debug, Error)]
pub enum MotionError {
    /// The file could not be opened or read.
    #[error("cannot read ground-motion file `{path}`: {source}; check that the path exists and is readable")]
    Io {
        /// The file as given.
        path: String,
        /// The operating-system error.
        #[source]
        source: std::io::Error,
    },
    /// A header line is not what the format requires.
    #[error("{path}:{line}: wrong header for a {format} file: expected {expected}, found `{found}`; check that the file really is in that format")]
    WrongHeader {
        /// The file as given.
        path: String,
        /// 1-based line number.
        line: usize,
        /// Format name (e.g. `PEER AT2`).
        format: &'static str,
        /// What the reader looked for.
        expected: String,
        /// The offending line (trimmed, shortened).
        found: String,
    },
    /// The file ends before the header is complete or before any data.
    #[error("{path}:{line}: short data: {message}; the file seems truncated")]
    ShortData {
        /// The file as given.
        path: String,
        /// 1-based line number of the last line read.
        line: usize,
        /// What was missing.
        message: String,
    },
    /// A token in the data section is not a number.
    #[error("{path}:{line}: `{token}` is not a number; remove or comment out (with `#`) the line, or fix the value")]
    NotANumber {
        /// The file as given.
        path: String,
        /// 1-based line number.
        line: usize,
        /// The offending token.
        token: String,
    },
    /// The number of values differs from the count the header announces.
    #[error("{path}:{line}: the header announces NPTS = {expected} values but the file has {found}{more}; fix NPTS or the data", more = if *found > *expected { " or more" } else { "" })]
    NptsMismatch {
        /// The file as given.
        path: String,
        /// 1-based line where the mismatch was found (first extra value, or end of file).
        line: usize,
        /// NPTS from the header.
        expected: usize,
        /// Values found (when too many: counted up to the first extra value).
        found: usize,
    },
    /// A time column value is not larger than the previous one.
    #[error("{path}:{line}: time {time_s} s is not after the previous time {previous_s} s; the time column must increase strictly (sort the rows or remove duplicates)")]
    NonMonotonicTime {
        /// The file as given.
        path: String,
        /// 1-based line number.
        line: usize,
        /// The time on this line, s.
        time_s: f64,
        /// The time on the previous data line, s.
        previous_s: f64,
    },
    /// The data section has a layout the reader does not accept (e.g. a wrong column count).
    #[error("{path}:{line}: {message}")]
    BadLayout {
        /// The file as given.
        path: String,
        /// 1-based line number.
        line: usize,
        /// What is wrong and how to fix it.
        message: String,
    },
    /// A processing step or reader option was given a value it cannot use.
    #[error("invalid argument: {0}")]
    InvalidArgument(String),
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, MotionError>;
