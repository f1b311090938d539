//! The JSON Schemas of a case file and of the studies' outputs (`pcsim schema`, issue 52): an
//! editor (taplo, VS Code's Even Better TOML) completes and checks a case with the first, a
//! downstream tool parses `summary.json`, `montecarlo.json`, `assessment.json`, `design.json`,
//! `fit.json`, `compare.json` or `pcsim.json` with the others, without guessing.
//!
//! The schemas are derived from the very types that read a case and write an output (serde and
//! schemars read the same attributes), so they cannot drift from the code. A case's value may be
//! written plain or sourced (`{ value, source, note, range, range_source }`, stripped by
//! [`crate::input::case`] before the case is read): the case's schema allows both at every field.

use serde_json::{json, Map, Value};

/// The outputs whose schema `pcsim schema` prints, by name.
pub const SCHEMAS: &[(&str, &str)] = &[
    ("case", "a case file (TOML), every value plain or sourced"),
    ("summary", "a run's summary.json"),
    ("montecarlo", "a Monte Carlo study's montecarlo.json"),
    (
        "assessment",
        "an assessment's assessment.json (pcsim assess)",
    ),
    ("design", "a design search's design.json"),
    ("fit", "a pantograph fit's fit.json"),
    ("frf", "a pantograph response's frf.json"),
    ("compare", "a comparison's compare.json"),
    ("realtime", "a real-time window study's realtime.json"),
    ("manifest", "an output directory's manifest, pcsim.json"),
    (
        "answer",
        "a study's answer.json (what its report and terminal open with)",
    ),
    ("figures", "a study's figures.json (its figures as data)"),
];

/// Every schema `pcsim schema` prints, by name: [`SCHEMAS`], then each spec-file study's
/// output (`NAME`) and spec (`NAME-spec`) from its row of [`crate::study::SPEC_STUDIES`].
pub fn names() -> Vec<(String, String)> {
    let mut v: Vec<(String, String)> = SCHEMAS
        .iter()
        .map(|(n, w)| (n.to_string(), w.to_string()))
        .collect();
    for s in crate::study::SPEC_STUDIES {
        let n = s.kind.name();
        v.push((n.into(), format!("a {n} study's {n}.json ({})", s.what)));
        v.push((
            format!("{n}-spec"),
            format!("a {n} study's spec file (TOML)"),
        ));
    }
    v
}

/// The schema named `name` (one of [`names`]), or `None`.
pub fn schema(name: &str) -> Option<Value> {
    match name {
        "case" => Some(case_schema()),
        "summary" => Some(output_schema::<crate::analysis::report::RunSummary>()),
        "montecarlo" => Some(output_schema::<crate::study::montecarlo::MonteCarloOutput>()),
        "assessment" => Some(output_schema::<crate::analysis::assess::Assessment>()),
        "design" => Some(output_schema::<crate::study::design::DesignRecord>()),
        "fit" => Some(output_schema::<crate::study::frf::FitRecord>()),
        "frf" => Some(output_schema::<crate::study::frf::FrfOutput>()),
        "compare" => Some(output_schema::<crate::study::compare::CompareOutput>()),
        "realtime" => Some(output_schema::<crate::study::realtime::RealtimeOutput>()),
        "manifest" => Some(output_schema::<crate::study::manifest::ManifestRecord>()),
        "answer" => Some(output_schema::<crate::study::Answer>()),
        "figures" => Some(output_schema::<Vec<crate::study::Figure>>()),
        _ => {
            let (kind, spec) = match name.strip_suffix("-spec") {
                Some(k) => (k, true),
                None => (name, false),
            };
            let row = crate::study::spec_study(kind)?;
            Some(if spec {
                (row.spec_schema)()
            } else {
                (row.output_schema)()
            })
        }
    }
}

fn output_schema<T: schemars::JsonSchema>() -> Value {
    schemars::schema_for!(T).to_value()
}

/// The case file's schema: [`crate::input::Case`]'s, with every property and list element
/// allowed in its sourced form too.
pub fn case_schema() -> Value {
    let mut v = schemars::schema_for!(crate::input::Case).to_value();
    sourced_everywhere(&mut v);
    if let Value::Object(m) = &mut v {
        m.insert(
            "description".into(),
            json!("A pcsim case file (TOML). Any value may be given plain or sourced: { value, source, note, range, range_source }."),
        );
    }
    v
}

/// Wrap each property's and each list element's schema as `anyOf [plain, sourced]`, once per
/// schema node (the sourced form holds the plain schema, which is not wrapped again).
fn sourced_everywhere(v: &mut Value) {
    match v {
        Value::Object(m) => {
            // First the children, then this node's own properties and items.
            for (k, child) in m.iter_mut() {
                if k != "properties" && k != "items" {
                    sourced_everywhere(child);
                }
            }
            if let Some(Value::Object(props)) = m.get_mut("properties") {
                for p in props.values_mut() {
                    sourced_everywhere(p);
                    *p = plain_or_sourced(std::mem::take(p));
                }
            }
            if let Some(items) = m.get_mut("items") {
                sourced_everywhere(items);
                if items.is_object() {
                    *items = plain_or_sourced(std::mem::take(items));
                }
            }
        }
        Value::Array(a) => a.iter_mut().for_each(sourced_everywhere),
        _ => {}
    }
}

/// `anyOf [plain, { value: plain, source, note, range, range_source }]`.
fn plain_or_sourced(plain: Value) -> Value {
    let mut props = Map::new();
    props.insert("value".into(), plain.clone());
    props.insert(
        "source".into(),
        json!({"type": "string", "description": "where the value comes from (`guess: …` when nowhere)"}),
    );
    props.insert("note".into(), json!({"type": "string"}));
    props.insert(
        "range".into(),
        json!({"type": "array", "description": "[low, high], or one [low, high] per element of a list (pcsim run --sensitivity)"}),
    );
    props.insert("range_source".into(), json!({"type": "string"}));
    json!({
        "anyOf": [
            plain,
            {
                "type": "object",
                "required": ["value"],
                "properties": props,
                "additionalProperties": false
            }
        ]
    })
}
