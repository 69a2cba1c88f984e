//! Script errors, located at file:line:column where the script is at fault.

use std::path::Path;
use thiserror::Error;

/// An error in a case script or in what it asked for.
#[derive(Debug, Error)]
pub enum ScriptError {
    /// A syntax or runtime error at a place in the script.
    #[error("{file}:{line}:{column}: {message}")]
    At {
        /// Script file.
        file: String,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// What is wrong.
        message: String,
    },
    /// An error without a place in the script (e.g. unknown `--set` name).
    #[error("{file}: {message}")]
    Case {
        /// Script file.
        file: String,
        /// What is wrong.
        message: String,
    },
    /// The script file cannot be read.
    #[error("cannot read the case script {file}: {source}")]
    Io {
        /// Script file.
        file: String,
        /// The I/O error.
        source: std::io::Error,
    },
}

impl ScriptError {
    pub(crate) fn at(file: &Path, pos: rhai::Position, message: impl Into<String>) -> Self {
        let message = message.into();
        match (pos.line(), pos.position()) {
            (Some(line), column) => ScriptError::At {
                file: file.display().to_string(),
                line,
                column: column.unwrap_or(1),
                message,
            },
            _ => ScriptError::Case {
                file: file.display().to_string(),
                message,
            },
        }
    }

    pub(crate) fn case(file: &Path, message: impl Into<String>) -> Self {
        ScriptError::Case {
            file: file.display().to_string(),
            message: message.into(),
        }
    }

    /// Turns a Rhai evaluation error into a located script error, with the innermost
    /// position (inside a function when the error is raised there).
    pub(crate) fn from_eval(file: &Path, err: &rhai::EvalAltResult) -> Self {
        let mut inner = err;
        // Unwrap "error in function call" layers to the real cause and place.
        while let rhai::EvalAltResult::ErrorInFunctionCall(_, _, cause, _) = inner {
            inner = cause;
        }
        let message = match inner {
            rhai::EvalAltResult::ErrorRuntime(value, _) => value.to_string(),
            rhai::EvalAltResult::ErrorTerminated(reason, _) => reason.to_string(),
            other => {
                let text = other.to_string();
                // Rhai appends " (line L, position C)"; the location is already given.
                match text.rfind(" (line ") {
                    Some(i) => text[..i].to_string(),
                    None => text,
                }
            }
        };
        let pos = if inner.position().is_none() {
            err.position()
        } else {
            inner.position()
        };
        ScriptError::at(file, pos, message)
    }
}
