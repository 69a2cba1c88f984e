//! Script parameters: `param(name, default)` declarations and `--set` overrides.

use serde::{Deserialize, Serialize};
use std::fmt;

/// The value of a script parameter.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub enum ParamValue {
    /// A real number.
    Float(f64),
    /// An integer.
    Int(i64),
    /// A flag.
    Bool(bool),
    /// A string (a name or a path).
    Str(String),
}

impl ParamValue {
    /// The type's name as users see it.
    pub fn type_name(&self) -> &'static str {
        match self {
            ParamValue::Float(_) => "number",
            ParamValue::Int(_) => "integer",
            ParamValue::Bool(_) => "true/false",
            ParamValue::Str(_) => "string",
        }
    }

    /// As an f64 when numeric.
    pub fn as_f64(&self) -> Option<f64> {
        match self {
            ParamValue::Float(x) => Some(*x),
            ParamValue::Int(i) => Some(*i as f64),
            _ => None,
        }
    }

    pub(crate) fn to_dynamic(&self) -> rhai::Dynamic {
        match self {
            ParamValue::Float(x) => (*x).into(),
            ParamValue::Int(i) => (*i).into(),
            ParamValue::Bool(b) => (*b).into(),
            ParamValue::Str(s) => s.clone().into(),
        }
    }

    pub(crate) fn from_dynamic(d: &rhai::Dynamic) -> Option<ParamValue> {
        if let Ok(x) = d.as_float() {
            Some(ParamValue::Float(x))
        } else if let Ok(i) = d.as_int() {
            Some(ParamValue::Int(i))
        } else if let Ok(b) = d.as_bool() {
            Some(ParamValue::Bool(b))
        } else if d.is_string() {
            Some(ParamValue::Str(d.clone().into_string().ok()?))
        } else {
            None
        }
    }

    /// Converts a `--set` value to the type of `default`, or explains why it cannot.
    pub fn coerce_to(&self, default: &ParamValue) -> Result<ParamValue, String> {
        if let ParamValue::Float(x) = self {
            if !x.is_finite() && !matches!(default, ParamValue::Str(_)) {
                return Err(format!("must be a finite number (got {x})"));
            }
        }
        match (default, self) {
            (ParamValue::Float(_), ParamValue::Float(_)) => Ok(self.clone()),
            (ParamValue::Float(_), ParamValue::Int(i)) => Ok(ParamValue::Float(*i as f64)),
            (ParamValue::Int(_), ParamValue::Int(_)) => Ok(self.clone()),
            (ParamValue::Bool(_), ParamValue::Bool(_)) => Ok(self.clone()),
            (ParamValue::Str(_), ParamValue::Str(_)) => Ok(self.clone()),
            // A string parameter accepts anything written on the command line as text.
            (ParamValue::Str(_), other) => Ok(ParamValue::Str(other.to_string())),
            _ => Err(format!(
                "expects a {} (default {default}), got {} '{self}'",
                default.type_name(),
                self.type_name()
            )),
        }
    }
}

impl fmt::Display for ParamValue {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            ParamValue::Float(x) => write!(f, "{x}"),
            ParamValue::Int(i) => write!(f, "{i}"),
            ParamValue::Bool(b) => write!(f, "{b}"),
            ParamValue::Str(s) => write!(f, "\"{s}\""),
        }
    }
}

/// Reads a `--set` value: a number or `true`/`false` when it looks like one, otherwise a
/// string (surrounding quotes optional).
pub fn parse_set_value(text: &str) -> ParamValue {
    let t = text.trim();
    if let Some(inner) = t
        .strip_prefix('"')
        .and_then(|s| s.strip_suffix('"'))
        .or_else(|| t.strip_prefix('\'').and_then(|s| s.strip_suffix('\'')))
    {
        return ParamValue::Str(inner.to_string());
    }
    match t {
        "true" => return ParamValue::Bool(true),
        "false" => return ParamValue::Bool(false),
        _ => {}
    }
    if let Ok(i) = t.parse::<i64>() {
        return ParamValue::Int(i);
    }
    match t.parse::<f64>() {
        Ok(x) => ParamValue::Float(x),
        Err(_) => ParamValue::Str(t.to_string()),
    }
}

/// A `--set` argument that is not `NAME=VALUE`.
#[derive(Clone, Debug, PartialEq, Eq, thiserror::Error)]
#[error("--set {argument}: {problem}")]
pub struct SetArgumentError {
    /// The argument as given.
    pub argument: String,
    /// What is wrong with it, and how to write it.
    pub problem: String,
}

/// Reads `--set NAME=VALUE` arguments (without the `--set`) into the overrides of a case,
/// in order, each value as [`parse_set_value`] reads it. Whether the names are parameters
/// of the script is checked when the case is loaded.
pub fn parse_sets(sets: &[String]) -> Result<crate::CaseOptions, SetArgumentError> {
    let mut options = crate::CaseOptions::default();
    for s in sets {
        let Some((name, value)) = s.split_once('=') else {
            return Err(SetArgumentError {
                argument: s.clone(),
                problem: "expected NAME=VALUE, e.g. --set duration=6".into(),
            });
        };
        let name = name.trim();
        if name.is_empty() {
            return Err(SetArgumentError {
                argument: s.clone(),
                problem: "the parameter name is empty".into(),
            });
        }
        options
            .overrides
            .push((name.to_string(), parse_set_value(value)));
    }
    Ok(options)
}

/// A parameter the script declared.
#[derive(Clone, Debug, Serialize)]
pub struct ParamDecl {
    /// Name.
    pub name: String,
    /// The script's default.
    pub default: ParamValue,
    /// The value used (the default or the `--set` override).
    pub value: ParamValue,
    /// True when `--set` changed it.
    pub overridden: bool,
    /// Unit, from the parameter's documentation (e.g. `m`, `rad/s`); `None` when it has none.
    pub unit: Option<String>,
    /// What the parameter is, from the third argument of `param` or the trailing `//`
    /// comment of its line; `None` when the script says nothing.
    pub description: Option<String>,
}

/// The text after `//` on a line of script source, outside string literals.
pub fn trailing_comment(line: &str) -> Option<&str> {
    let bytes = line.as_bytes();
    let mut quote: Option<u8> = None;
    let mut i = 0;
    while i < bytes.len() {
        let b = bytes[i];
        match quote {
            Some(_) if b == b'\\' => i += 1,
            Some(q) if b == q => quote = None,
            Some(_) => {}
            None if b == b'"' || b == b'`' || b == b'\'' => quote = Some(b),
            None if b == b'/' && bytes.get(i + 1) == Some(&b'/') => {
                let text = line[i + 2..].trim();
                return (!text.is_empty()).then_some(text);
            }
            None => {}
        }
        i += 1;
    }
    None
}

/// Splits a parameter's documentation into its unit and its description: the unit is the
/// first parenthesised group that reads as a unit symbol (`(m)`, `(rad/s)`, `(m/s²)`,
/// `(Pa)`); it is taken out of the description.
pub fn split_unit(doc: &str) -> (Option<String>, String) {
    let mut search_from = 0;
    while let Some(open) = doc[search_from..].find('(').map(|k| k + search_from) {
        let Some(close) = doc[open..].find(')').map(|k| k + open) else {
            break;
        };
        let inner = &doc[open + 1..close];
        if looks_like_unit(inner) {
            let before = doc[..open].trim_end();
            let after = &doc[close + 1..];
            let description = format!("{before}{after}").trim().to_string();
            return (Some(inner.to_string()), description);
        }
        search_from = close + 1;
    }
    (None, doc.trim().to_string())
}

/// A unit symbol: short, no spaces, made of letters, digits and `/ ² ³ · ^ - *`, and not a
/// bare number.
fn looks_like_unit(text: &str) -> bool {
    let allowed = |c: char| c.is_alphabetic() || c.is_ascii_digit() || "/²³·^-*%".contains(c);
    !text.is_empty()
        && text.chars().count() <= 10
        && text.chars().all(allowed)
        && text.chars().any(|c| c.is_alphabetic() || c == '%')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn set_arguments_become_overrides_in_order() {
        let sets = ["duration=3".to_string(), " roof = \"cone\"".to_string()];
        let options = parse_sets(&sets).unwrap();
        assert_eq!(
            options.overrides,
            vec![
                ("duration".to_string(), ParamValue::Int(3)),
                ("roof".to_string(), ParamValue::Str("cone".into())),
            ]
        );
        let err = parse_sets(&["duration".to_string()]).unwrap_err();
        assert_eq!(
            err.to_string(),
            "--set duration: expected NAME=VALUE, e.g. --set duration=6"
        );
        let err = parse_sets(&["=3".to_string()]).unwrap_err();
        assert_eq!(err.to_string(), "--set =3: the parameter name is empty");
    }

    #[test]
    fn set_values_are_typed_like_the_design_says() {
        assert_eq!(parse_set_value("0.6"), ParamValue::Float(0.6));
        assert_eq!(parse_set_value("20"), ParamValue::Int(20));
        assert_eq!(parse_set_value("true"), ParamValue::Bool(true));
        assert_eq!(parse_set_value("cone"), ParamValue::Str("cone".into()));
        assert_eq!(parse_set_value("\"cone\""), ParamValue::Str("cone".into()));
        assert_eq!(
            parse_set_value("1e-3").coerce_to(&ParamValue::Float(0.0)),
            Ok(ParamValue::Float(1e-3))
        );
        assert_eq!(
            parse_set_value("3").coerce_to(&ParamValue::Float(0.0)),
            Ok(ParamValue::Float(3.0))
        );
        assert!(parse_set_value("abc")
            .coerce_to(&ParamValue::Float(1.0))
            .is_err());
        assert!(parse_set_value("2.5")
            .coerce_to(&ParamValue::Int(1))
            .is_err());
    }

    #[test]
    fn non_finite_numbers_are_refused_for_numeric_parameters() {
        for text in ["inf", "-inf", "nan", "NaN", "infinity"] {
            let err = parse_set_value(text)
                .coerce_to(&ParamValue::Float(1.0))
                .unwrap_err();
            assert!(err.contains("must be a finite number"), "{text}: {err}");
        }
        assert_eq!(
            parse_set_value("inf").coerce_to(&ParamValue::Str("a".into())),
            Ok(ParamValue::Str("inf".into()))
        );
    }

    #[test]
    fn trailing_comments_skip_strings() {
        assert_eq!(
            trailing_comment(r#"let w = param("width", 1.0);   // inner width (m)"#),
            Some("inner width (m)")
        );
        assert_eq!(
            trailing_comment(r#"let u = param("url", "http://x");"#),
            None
        );
        assert_eq!(trailing_comment("let a = 1; //"), None);
    }

    #[test]
    fn the_unit_is_the_first_unit_like_group() {
        assert_eq!(
            split_unit("inner tank width 2l (m)"),
            (Some("m".into()), "inner tank width 2l".into())
        );
        assert_eq!(
            split_unit("fixed time step (s), ≤ the CFL bound; 0 = CFL-variable"),
            (
                Some("s".into()),
                "fixed time step, ≤ the CFL bound; 0 = CFL-variable".into()
            )
        );
        assert_eq!(
            split_unit("\"offset\" (exact block) or \"paper\" (1,974 particles)"),
            (
                None,
                "\"offset\" (exact block) or \"paper\" (1,974 particles)".into()
            )
        );
        assert_eq!(
            split_unit("excitation circular frequency ω (rad/s)").0,
            Some("rad/s".into())
        );
    }
}
