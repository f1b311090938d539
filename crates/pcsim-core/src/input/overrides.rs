//! Overrides of case values by dotted path (`run.speed_kmh`, `catenary.contact_wire.tension_n`,
//! `pantographs[1].offset_m`). The path names the field, so it carries the field's unit; the
//! value is in that unit. Used by sweeps and the Python bindings.

use crate::error::CaseError;
use crate::input::case::Case;

/// A value to put at a path.
#[derive(Debug, Clone, PartialEq)]
pub enum OverrideValue {
    /// A number.
    Number(f64),
    /// An integer.
    Integer(i64),
    /// A boolean.
    Bool(bool),
    /// A string.
    Text(String),
    /// A list of numbers (`run.analysis_m`, `catenary.droppers.positions_m`).
    Numbers(Vec<f64>),
    /// Any TOML value (a table replaces a table: `catenary.presag` as a parabola).
    Toml(toml::Value),
}

impl From<f64> for OverrideValue {
    fn from(v: f64) -> Self {
        OverrideValue::Number(v)
    }
}

impl From<OverrideValue> for toml::Value {
    fn from(v: OverrideValue) -> Self {
        match v {
            OverrideValue::Number(x) => toml::Value::Float(x),
            OverrideValue::Integer(i) => toml::Value::Integer(i),
            OverrideValue::Bool(b) => toml::Value::Boolean(b),
            OverrideValue::Text(s) => toml::Value::String(s),
            OverrideValue::Numbers(v) => {
                toml::Value::Array(v.into_iter().map(toml::Value::Float).collect())
            }
            OverrideValue::Toml(v) => v,
        }
    }
}

/// One step of a path: a table key or an array index.
enum Step<'a> {
    Key(&'a str),
    Index(usize),
}

fn parse_path(path: &str) -> Result<Vec<Step<'_>>, CaseError> {
    let bad = |reason: &str| CaseError::Invalid {
        field: path.to_string(),
        value: String::new(),
        reason: reason.to_string(),
    };
    let mut steps = Vec::new();
    for part in path.split('.') {
        let (key, mut rest) = match part.find('[') {
            Some(i) => (&part[..i], &part[i..]),
            None => (part, ""),
        };
        if key.is_empty() {
            return Err(bad("empty name in the path"));
        }
        steps.push(Step::Key(key));
        while let Some(r) = rest.strip_prefix('[') {
            let end = r.find(']').ok_or_else(|| bad("unclosed `[` in the path"))?;
            let i: usize = r[..end]
                .parse()
                .map_err(|_| bad("an index must be a whole number"))?;
            steps.push(Step::Index(i));
            rest = &r[end + 1..];
        }
        if !rest.is_empty() {
            return Err(bad("unexpected text after `]`"));
        }
    }
    Ok(steps)
}

/// The value at `path` in `case` (in the field's unit), by the same path rules as
/// [`with_overrides`]. An error names the path and what is missing.
pub fn value_at(case: &Case, path: &str) -> Result<toml::Value, CaseError> {
    let root = toml::Value::try_from(case).map_err(|e| CaseError::Parse(e.to_string()))?;
    let missing = |what: String| CaseError::Parse(format!("`{path}`: {what}"));
    let mut at = &root;
    for step in parse_path(path)? {
        at = match step {
            Step::Key(k) => at
                .get(k)
                .ok_or_else(|| missing(format!("the case has no `{k}`")))?,
            Step::Index(i) => at
                .get(i)
                .ok_or_else(|| missing(format!("index {i} is out of range")))?,
        };
    }
    Ok(at.clone())
}

/// A copy of `case` with every `(path, value)` set, validated. An unknown path, a value of the
/// wrong type or an invalid result is an error that names the path and the value.
pub fn with_overrides(
    case: &Case,
    overrides: &[(String, OverrideValue)],
) -> Result<Case, CaseError> {
    let mut root = toml::Value::try_from(case).map_err(|e| CaseError::Parse(e.to_string()))?;
    for (path, value) in overrides {
        let steps = parse_path(path)?;
        let mut at = &mut root;
        for (k, step) in steps.iter().enumerate() {
            let last = k + 1 == steps.len();
            at = match (step, at) {
                (Step::Key(key), toml::Value::Table(t)) => {
                    if !t.contains_key(*key) {
                        if last {
                            // An optional field the case leaves out (or a misspelt one: the case's
                            // own parsing names it).
                            t.insert(key.to_string(), toml::Value::Boolean(false));
                        } else {
                            return Err(CaseError::Invalid {
                                field: path.clone(),
                                value: format!("{value:?}"),
                                reason: format!("the case has no `{key}` here"),
                            });
                        }
                    }
                    t.get_mut(*key).expect("present")
                }
                (Step::Index(i), toml::Value::Array(a)) => {
                    let n = a.len();
                    a.get_mut(*i).ok_or_else(|| CaseError::Invalid {
                        field: path.clone(),
                        value: format!("{value:?}"),
                        reason: format!("index {i} out of range (there are {n})"),
                    })?
                }
                _ => {
                    return Err(CaseError::Invalid {
                        field: path.clone(),
                        value: format!("{value:?}"),
                        reason: "the path does not lead to a value of the case".into(),
                    })
                }
            };
        }
        *at = match (&*at, value) {
            // A whole number for a field that holds one (`catenary.spans`, `run.modes`): a
            // study's draws and ranges are numbers, the case's field an integer.
            (toml::Value::Integer(_), OverrideValue::Number(x)) => {
                if x.fract() != 0.0 || !x.is_finite() || x.abs() > 9.0e15 {
                    return Err(CaseError::Invalid {
                        field: path.clone(),
                        value: format!("{x}"),
                        reason: "the field holds a whole number".into(),
                    });
                }
                toml::Value::Integer(*x as i64)
            }
            _ => value.clone().into(),
        };
    }
    let text = toml::to_string(&root).map_err(|e| CaseError::Parse(e.to_string()))?;
    let (out, _) = Case::from_toml_str(&text).map_err(|e| match e {
        CaseError::Parse(m) => CaseError::Parse(format!(
            "after the overrides {}: {m}",
            overrides
                .iter()
                .map(|(p, v)| format!("{p} = {v:?}"))
                .collect::<Vec<_>>()
                .join(", ")
        )),
        other => other,
    })?;
    out.validate()?;
    Ok(out)
}

/// Each ranged value at its low and at its high end, the case checked as any case is (issue 51:
/// a range end that can never run, a speed of 0 or a start outside the model, is refused when
/// the case is read, not when a study reaches it). The error names the value's range, the end
/// and the case's reason. A case that does not validate itself is left to its own check.
pub fn check_range_ends(
    case: &Case,
    ranges: &[crate::input::RangedValue],
) -> Result<(), CaseError> {
    if ranges.is_empty() || case.validate().is_err() {
        return Ok(());
    }
    for r in ranges {
        for (end, x) in [("low", r.low), ("high", r.high)] {
            if let Err(e) = with_overrides(case, &[(r.path.clone(), OverrideValue::Number(x))]) {
                return Err(CaseError::Invalid {
                    field: format!("{}.range", r.path),
                    value: format!("[{}, {}]", r.low, r.high),
                    reason: format!("the case cannot run at its {end} end ({x}): {e}"),
                });
            }
        }
    }
    Ok(())
}
