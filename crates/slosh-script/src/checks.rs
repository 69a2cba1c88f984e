//! Checks of a loaded case that catch a run that would silently do nothing: a misspelled or
//! mis-declared `ground_accel` or `post`, no excitation at all, and ground-motion records that
//! end before the excitation does.

use crate::error::ScriptError;
use crate::motion_api::MotionInfo;
use crate::spec::RunSpec;
use rhai::AST;
use std::path::Path;

/// A script function slosh calls by name, with the one parameter it passes.
pub(crate) struct HostCalled {
    /// Function name.
    pub name: &'static str,
    /// The parameter as the docs write it (`t`, `run`).
    pub parameter: &'static str,
    /// What the function is for, as a sentence ending.
    pub purpose: &'static str,
}

/// The excitation, called every step with the time since the excitation started.
pub(crate) const GROUND_ACCEL: HostCalled = HostCalled {
    name: "ground_accel",
    parameter: "t",
    purpose: "slosh calls it every step for the ground acceleration; without it the tank is \
              not shaken",
};

/// The tank's rotation, called every step.
pub(crate) const GROUND_ROTATION: HostCalled = HostCalled {
    name: "ground_rotation",
    parameter: "t",
    purpose: "slosh calls it every step for the tank's angle about its pivot; without it the \
              tank does not turn",
};

/// The post-processing, called once after the run.
pub(crate) const POST: HostCalled = HostCalled {
    name: "post",
    parameter: "run",
    purpose: "slosh calls it once after the run; without it nothing is post-processed",
};

/// Largest edit distance (insertions, deletions, substitutions, swaps of neighbours) at which
/// a function's name is taken for a misspelling of a function slosh calls.
const SIMILAR_NAME_DISTANCE: usize = 2;

/// Shortest share of the excitation a record must cover; below it the record is refused.
pub(crate) const MIN_RECORD_COVERAGE: f64 = 0.1;

/// True when the script defines `expected` with its one parameter. Refuses a script that
/// instead defines it with another number of parameters, or defines a function of a similar
/// name that the script itself never calls (a misspelling: slosh would never call it either).
pub(crate) fn defines(
    file: &Path,
    source: &str,
    ast: &AST,
    expected: &HostCalled,
) -> Result<bool, ScriptError> {
    let functions: Vec<(String, Vec<String>)> = ast
        .iter_functions()
        .map(|f| {
            let params = f.params.iter().map(|p| p.to_string()).collect();
            (f.name.to_string(), params)
        })
        .collect();
    if functions
        .iter()
        .any(|(name, params)| name == expected.name && params.len() == 1)
    {
        return Ok(true);
    }
    let wrong = functions.iter().find(|(name, _)| {
        name == expected.name
            || (edit_distance(&name.to_lowercase(), expected.name) <= SIMILAR_NAME_DISTANCE
                && !is_called(source, name))
    });
    let Some((name, params)) = wrong else {
        return Ok(false);
    };
    let what = if name == expected.name {
        format!(
            "defines {name}({}) with {} parameters",
            params.join(", "),
            params.len()
        )
    } else {
        format!("defines {name}({}) (and never calls it)", params.join(", "))
    };
    let message = format!(
        "the script {what} but no fn {}({}): {}. Name it and give it one parameter: \
         fn {}({}) {{ ... }}",
        expected.name, expected.parameter, expected.purpose, expected.name, expected.parameter
    );
    Err(match definition_position(source, name) {
        Some(pos) => ScriptError::at(file, pos, message),
        None => ScriptError::case(file, message),
    })
}

/// Warnings and errors for the ground-motion records a script read, against the run's
/// excitation time (duration − settle): the reader's own warnings; a record that ends before
/// the excitation does (zero acceleration after its end) is a warning, and an error when it
/// covers less than [`MIN_RECORD_COVERAGE`] of the excitation.
pub(crate) fn record_coverage(
    file: &Path,
    motions: &[MotionInfo],
    run: &RunSpec,
) -> Result<Vec<String>, ScriptError> {
    let excitation_s = run.duration - run.settle;
    let mut warnings = Vec::new();
    for m in motions {
        warnings.extend(m.warnings.iter().cloned());
        let covered_s = m.end_time_s.min(excitation_s) - m.start_time_s.max(0.0);
        if excitation_s <= 0.0 || m.end_time_s >= excitation_s {
            continue;
        }
        let ends = format!(
            "the record \"{}\" ends at t = {} s of the excitation, which lasts {excitation_s} s \
             (duration {} s − settle {} s)",
            m.file, m.end_time_s, run.duration, run.settle
        );
        if covered_s < MIN_RECORD_COVERAGE * excitation_s {
            return Err(ScriptError::case(
                file,
                format!(
                    "{ends}: it covers {:.1} % of it, less than {:.0} %; use a longer record \
                     or shorten the run (run duration ≤ settle + {} s)",
                    100.0 * covered_s.max(0.0) / excitation_s,
                    100.0 * MIN_RECORD_COVERAGE,
                    m.end_time_s
                ),
            ));
        }
        let after = if m.format == crate::motion_api::ROTATION_TABLE {
            "the tank rests at the record's last angle"
        } else {
            "the ground acceleration is zero"
        };
        warnings.push(format!(
            "{ends}: {after} for the last {} s; shorten the run (duration ≤ settle + {} s) or \
             use a longer record",
            excitation_s - m.end_time_s,
            m.end_time_s
        ));
    }
    Ok(warnings)
}

/// True when `name(` appears in `source` other than in its own definition (`fn name(`).
fn is_called(source: &str, name: &str) -> bool {
    word_positions(source, name).any(|at| {
        let before = source[..at].trim_end();
        let after = source[at + name.len()..].trim_start();
        after.starts_with('(') && !ends_with_word(before, "fn")
    })
}

/// The position (line, column) of `fn name` in `source`.
fn definition_position(source: &str, name: &str) -> Option<rhai::Position> {
    let at =
        word_positions(source, name).find(|&at| ends_with_word(source[..at].trim_end(), "fn"))?;
    let before = &source[..at];
    let line = before.matches('\n').count() + 1;
    let column = before[before.rfind('\n').map_or(0, |i| i + 1)..]
        .chars()
        .count()
        + 1;
    let line = u16::try_from(line).ok()?;
    let column = u16::try_from(column).ok()?;
    Some(rhai::Position::new(line, column))
}

/// Byte offsets where `word` occurs in `text` as a whole identifier.
fn word_positions<'a>(text: &'a str, word: &'a str) -> impl Iterator<Item = usize> + 'a {
    let is_ident = |c: char| c.is_alphanumeric() || c == '_';
    text.match_indices(word)
        .map(|(at, _)| at)
        .filter(move |&at| {
            let before = text[..at].chars().next_back();
            let after = text[at + word.len()..].chars().next();
            !before.is_some_and(is_ident) && !after.is_some_and(is_ident)
        })
}

fn ends_with_word(text: &str, word: &str) -> bool {
    text.strip_suffix(word).is_some_and(|rest| {
        !rest
            .chars()
            .next_back()
            .is_some_and(|c| c.is_alphanumeric() || c == '_')
    })
}

/// Optimal-string-alignment distance: insertions, deletions, substitutions and swaps of two
/// neighbouring characters each count 1 (`pots` is 1 from `post`).
fn edit_distance(a: &str, b: &str) -> usize {
    let a: Vec<char> = a.chars().collect();
    let b: Vec<char> = b.chars().collect();
    if a.len().abs_diff(b.len()) > SIMILAR_NAME_DISTANCE {
        return usize::MAX;
    }
    let mut d = vec![vec![0usize; b.len() + 1]; a.len() + 1];
    for (i, row) in d.iter_mut().enumerate() {
        row[0] = i;
    }
    for (j, cell) in d[0].iter_mut().enumerate() {
        *cell = j;
    }
    for i in 1..=a.len() {
        for j in 1..=b.len() {
            let cost = usize::from(a[i - 1] != b[j - 1]);
            let mut best = (d[i - 1][j] + 1)
                .min(d[i][j - 1] + 1)
                .min(d[i - 1][j - 1] + cost);
            if i > 1 && j > 1 && a[i - 1] == b[j - 2] && a[i - 2] == b[j - 1] {
                best = best.min(d[i - 2][j - 2] + 1);
            }
            d[i][j] = best;
        }
    }
    d[a.len()][b.len()]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn distances() {
        assert_eq!(edit_distance("post", "post"), 0);
        assert_eq!(edit_distance("pots", "post"), 1);
        assert_eq!(edit_distance("ground_acel", "ground_accel"), 1);
        assert_eq!(edit_distance("groundaccel", "ground_accel"), 1);
        assert_eq!(edit_distance("grnd_accel", "ground_accel"), 2);
        assert!(edit_distance("accel", "ground_accel") > 2);
    }

    #[test]
    fn calls_and_definitions() {
        let src = "fn cost(x) { x }\nlet y = cost (2);\n  fn pots(run) { 1 }\n";
        assert!(is_called(src, "cost"));
        assert!(!is_called(src, "pots"));
        let pos = definition_position(src, "pots").unwrap();
        assert_eq!((pos.line(), pos.position()), (Some(3), Some(6)));
    }
}
