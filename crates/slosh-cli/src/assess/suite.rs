//! Suite files: one ground motion per row, the columns parameters of the case script.
//!
//! - **CSV**: a header row naming the columns, then one row per motion. `#` starts a comment
//!   line; an empty cell leaves that parameter at the script's default for that motion.
//! - **RON**: a list of rows, each a struct or a map of column to value, e.g.
//!   `[(name: "elcentro", pga: 3.0), (name: "sine", motion: "sine", pga: 1.0)]`.
//!
//! The optional column `name` names the motion and its run folder; without it the folder is
//! made of the row's values, as `slosh sweep` names its cases.

use anyhow::{bail, Context, Result};
use slosh_script::{parse_set_value, ParamDecl, ParamValue};
use std::path::Path;

/// One row of a suite: a ground motion.
#[derive(Clone, Debug, PartialEq)]
pub struct SuiteRow {
    /// The motion's name (its run folder, `runs/<name>`).
    pub name: String,
    /// The parameter values of the row, converted to the types of the script's defaults.
    pub values: Vec<(String, ParamValue)>,
    /// Line of the row in the suite file (1-based).
    pub line: usize,
}

/// Reads a suite file (`.csv` or `.ron`) and checks its columns and values against the
/// parameters the case script declares. Errors name the file and line.
pub fn read_suite(path: &Path, declared: &[ParamDecl]) -> Result<Vec<SuiteRow>> {
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read the suite file {}", path.display()))?;
    let source = path.display().to_string();
    let raw = match path.extension().and_then(|e| e.to_str()) {
        Some(e) if e.eq_ignore_ascii_case("csv") => parse_csv(&text, &source)?,
        Some(e) if e.eq_ignore_ascii_case("ron") => parse_ron(&text, &source)?,
        _ => bail!(
            "{source}: a suite file must end in .csv or .ron (a table with one ground motion per row)"
        ),
    };
    typed_rows(raw, declared, &source)
}

/// A row as read, before its values are checked: (line, [(column, value)]).
type RawRow = (usize, Vec<(String, ParamValue)>);

fn parse_csv(text: &str, source: &str) -> Result<Vec<RawRow>> {
    let mut reader = csv::ReaderBuilder::new()
        .has_headers(true)
        .comment(Some(b'#'))
        .trim(csv::Trim::All)
        .from_reader(text.as_bytes());
    let header: Vec<String> = reader
        .headers()
        .map_err(|e| anyhow::anyhow!(csv_error(&e, source)))?
        .iter()
        .map(str::to_string)
        .collect();
    let header_line = text
        .lines()
        .position(|l| !l.trim().is_empty() && !l.trim_start().starts_with('#'))
        .map_or(1, |i| i + 1);
    if header.iter().all(String::is_empty) {
        bail!("{source}: the first row must name the columns, e.g. `name,record,pga`");
    }
    for (j, h) in header.iter().enumerate() {
        if h.is_empty() {
            bail!("{source}:{header_line}: column {} has no name", j + 1);
        }
        if header[..j].contains(h) {
            bail!("{source}:{header_line}: the column `{h}` appears twice");
        }
    }
    let mut rows = Vec::new();
    for record in reader.records() {
        let record = record.map_err(|e| anyhow::anyhow!(csv_error(&e, source)))?;
        let line = record.position().map_or(0, |p| p.line() as usize);
        let values = header
            .iter()
            .zip(record.iter())
            .filter(|(_, cell)| !cell.is_empty())
            .map(|(h, cell)| {
                let v = if h == "name" {
                    ParamValue::Str(cell.to_string())
                } else {
                    parse_set_value(cell)
                };
                (h.clone(), v)
            })
            .collect();
        rows.push((line, values));
    }
    Ok(rows)
}

/// A CSV error as `source:line: what` where the csv crate knows the line.
fn csv_error(e: &csv::Error, source: &str) -> String {
    match e.kind() {
        csv::ErrorKind::UnequalLengths {
            pos: Some(pos),
            expected_len,
            len,
        } => format!(
            "{source}:{}: {len} cells where the header has {expected_len}",
            pos.line()
        ),
        _ => match e.position() {
            Some(pos) => format!("{source}:{}: {e}", pos.line()),
            None => format!("{source}: {e}"),
        },
    }
}

fn parse_ron(text: &str, source: &str) -> Result<Vec<RawRow>> {
    let value: ron::Value = ron::from_str(text).map_err(|e| {
        anyhow::anyhow!(
            "{source}:{}:{}: {} (a suite in RON is a list of rows, e.g. [(name: \"a\", pga: 3.0)])",
            e.span.start.line,
            e.span.start.col,
            e.code
        )
    })?;
    let ron::Value::Seq(items) = value else {
        bail!("{source}:1: a suite in RON is a list of rows, e.g. [(name: \"a\", pga: 3.0), (name: \"b\", pga: 4.0)]");
    };
    let lines = element_lines(text);
    let mut rows = Vec::new();
    for (k, item) in items.into_iter().enumerate() {
        let line = lines.get(k).copied().unwrap_or(1);
        let ron::Value::Map(map) = item else {
            bail!(
                "{source}:{line}: row {} is not a struct or map of column: value",
                k + 1
            );
        };
        let mut values = Vec::new();
        for (key, v) in map.iter() {
            let ron::Value::String(column) = key else {
                bail!("{source}:{line}: a column name must be a word or a string");
            };
            let value = match v {
                ron::Value::String(s) => ParamValue::Str(s.clone()),
                ron::Value::Bool(b) => ParamValue::Bool(*b),
                ron::Value::Number(n @ (ron::Number::F32(_) | ron::Number::F64(_))) => {
                    ParamValue::Float(n.into_f64())
                }
                ron::Value::Number(n) => ParamValue::Int(n.into_f64() as i64),
                other => bail!(
                    "{source}:{line}: column `{column}`: {other:?} is not a number, true/false or a string"
                ),
            };
            values.push((column.clone(), value));
        }
        rows.push((line, values));
    }
    Ok(rows)
}

/// The 1-based line on which each element of the top-level list of a RON text starts.
fn element_lines(text: &str) -> Vec<usize> {
    let mut lines = Vec::new();
    let (mut depth, mut line) = (0usize, 1usize);
    let mut expecting = false;
    let mut chars = text.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '\n' => line += 1,
            '/' if chars.peek() == Some(&'/') => {
                for c in chars.by_ref() {
                    if c == '\n' {
                        line += 1;
                        break;
                    }
                }
                continue;
            }
            c if c.is_whitespace() => {}
            _ => {
                if depth == 1 && expecting && c != ',' && c != ']' {
                    lines.push(line);
                    expecting = false;
                }
                match c {
                    '"' => {
                        let mut escaped = false;
                        for c in chars.by_ref() {
                            match c {
                                '\n' => line += 1,
                                '\\' if !escaped => {
                                    escaped = true;
                                    continue;
                                }
                                '"' if !escaped => break,
                                _ => {}
                            }
                            escaped = false;
                        }
                    }
                    '[' | '(' | '{' => {
                        depth += 1;
                        if depth == 1 {
                            expecting = true;
                        }
                    }
                    ']' | ')' | '}' => depth = depth.saturating_sub(1),
                    ',' if depth == 1 => expecting = true,
                    _ => {}
                }
            }
        }
    }
    lines
}

/// Checks the columns against the script's parameters, converts the values to the types of
/// the defaults and names the rows.
fn typed_rows(raw: Vec<RawRow>, declared: &[ParamDecl], source: &str) -> Result<Vec<SuiteRow>> {
    if raw.is_empty() {
        bail!("{source}: the suite has no rows; write one row per ground motion");
    }
    let known = || {
        declared
            .iter()
            .map(|p| format!("  {} = {}", p.name, p.default))
            .collect::<Vec<_>>()
            .join("\n")
    };
    let mut rows: Vec<SuiteRow> = Vec::with_capacity(raw.len());
    for (line, cells) in raw {
        let mut name = None;
        let mut values = Vec::new();
        for (column, value) in cells {
            if column == "name" {
                let text = match value {
                    ParamValue::Str(s) => s,
                    other => other.to_string(),
                };
                name = Some(text);
                continue;
            }
            let Some(decl) = declared.iter().find(|p| p.name == column) else {
                bail!(
                    "{source}:{line}: column `{column}` is not a parameter of the case script \
                     (or `name`); its parameters are:\n{}",
                    known()
                );
            };
            let value = value
                .coerce_to(&decl.default)
                .map_err(|e| anyhow::anyhow!("{source}:{line}: column `{column}`: {e}"))?;
            values.push((column, value));
        }
        // In the script's order, whatever the order of the file's columns or map keys.
        values.sort_by_key(|(n, _)| declared.iter().position(|p| &p.name == n));
        let name = match name {
            Some(n) if !n.trim().is_empty() => crate::sweep::folder_safe(n.trim()),
            _ => crate::sweep::case_folder_name(&values),
        };
        crate::sweep::check_folder_name(&name)
            .map_err(|e| anyhow::anyhow!("{source}:{line}: {e:#}"))?;
        if let Some(other) = rows.iter().find(|r| r.name == name) {
            bail!(
                "{source}:{line}: the motion name `{name}` is also the name of the row on line {}; \
                 give each row its own `name`",
                other.line
            );
        }
        rows.push(SuiteRow { name, values, line });
    }
    Ok(rows)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn decl(name: &str, default: ParamValue) -> ParamDecl {
        ParamDecl {
            name: name.into(),
            value: default.clone(),
            default,
            overridden: false,
            unit: None,
            description: None,
        }
    }

    fn declared() -> Vec<ParamDecl> {
        vec![
            decl("record", ParamValue::Str("data/a.at2".into())),
            decl("pga", ParamValue::Float(3.0)),
        ]
    }

    fn write(name: &str, text: &str) -> std::path::PathBuf {
        let dir = std::env::temp_dir().join("slosh-suite-tests");
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join(name);
        std::fs::write(&path, text).unwrap();
        path
    }

    #[test]
    fn csv_and_ron_give_the_same_rows() {
        let csv = write(
            "a.csv",
            "# site suite\nname,record,pga\nec,data/a.at2,2\nbig one,,4.5\n",
        );
        let ron = write(
            "a.ron",
            "// site suite\n[\n  (name: \"ec\", record: \"data/a.at2\", pga: 2),\n  {\"name\": \"big one\",\n   \"pga\": 4.5},\n]\n",
        );
        let a = read_suite(&csv, &declared()).unwrap();
        let b = read_suite(&ron, &declared()).unwrap();
        assert_eq!(a.len(), 2);
        assert_eq!(a[0].name, "ec");
        assert_eq!(a[1].name, "big_one");
        assert_eq!(a[0].values[1], ("pga".into(), ParamValue::Float(2.0)));
        assert_eq!(a[1].values, vec![("pga".into(), ParamValue::Float(4.5))]);
        assert_eq!((a[0].line, a[1].line), (3, 4));
        assert_eq!((b[0].line, b[1].line), (3, 4));
        for (x, y) in a.iter().zip(&b) {
            assert_eq!((&x.name, &x.values), (&y.name, &y.values));
        }
    }

    #[test]
    fn bad_suites_name_the_line_and_the_problem() {
        for (file, text, words) in [
            (
                "u.csv",
                "name,pgaa\na,1\n",
                "u.csv:2: column `pgaa` is not a parameter",
            ),
            (
                "t.csv",
                "pga\n1\nstrong\n",
                "t.csv:3: column `pga`: expects a number",
            ),
            (
                "d.csv",
                "name,pga\na,1\na,2\n",
                "d.csv:3: the motion name `a`",
            ),
            (
                "l.csv",
                "name,pga\na,1,2\n",
                "l.csv:2: 3 cells where the header has 2",
            ),
            ("e.csv", "name,pga\n", "no rows"),
            ("s.ron", "[(pga: 1.0),\n (pga: )]", "s.ron:2:"),
            (
                "m.ron",
                "[(pga: 1.0),\n 3]",
                "m.ron:2: row 2 is not a struct",
            ),
            ("x.txt", "pga\n1\n", ".csv or .ron"),
        ] {
            let e = format!(
                "{:#}",
                read_suite(&write(file, text), &declared()).unwrap_err()
            );
            assert!(e.contains(words), "{file}: {e}");
        }
        let e = format!(
            "{:#}",
            read_suite(&write("k.csv", "pgaa\n1\n"), &declared()).unwrap_err()
        );
        assert!(
            e.contains("record = \"data/a.at2\"") && e.contains("pga = 3"),
            "{e}"
        );
    }
}
