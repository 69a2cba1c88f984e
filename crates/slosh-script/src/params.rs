//! Script parameters: `param(name, default)` declarations and `--set` overrides.

use serde::Serialize;
use std::fmt;

/// The value of a script parameter.
#[derive(Clone, Debug, PartialEq, Serialize)]
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
}

#[cfg(test)]
mod tests {
    use super::*;

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
}
