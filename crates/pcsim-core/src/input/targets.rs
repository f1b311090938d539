//! Validation targets (`data/validation-targets.toml`, embedded): acceptance ranges and the seed
//! paper's own values, each table with its source.

use crate::error::CaseError;

/// The validation targets, copied from the reference data with their provenance.
pub const TARGETS_TOML: &str = include_str!("../../../../data/validation-targets.toml");

/// Quantities in the order they are reported (the EN 50318 statistics of `ContactStats`).
pub const QUANTITIES: &[&str] = &[
    "mean",
    "std",
    "std_0_5hz",
    "std_5_20hz",
    "stat_max",
    "stat_min",
    "actual_max",
    "actual_min",
    "contact_point_range_mm",
    "max_uplift_at_support_mm",
    "loss_of_contact_percent",
];

/// A target case: its speed and the ranges it gives, in [`QUANTITIES`] order.
#[derive(Debug, Clone, PartialEq)]
pub struct TargetCase {
    /// Key in the targets table (e.g. `v275_leading`).
    pub key: String,
    /// Train speed, km/h.
    pub speed_kmh: f64,
    /// From the key's suffix (`v275_leading` → "leading").
    pub pantograph: Option<String>,
    /// Ranges [low, high] by quantity.
    pub ranges: Vec<(String, [f64; 2])>,
    /// `paper_value` entries, by quantity.
    pub paper: Vec<(String, f64)>,
    /// Quantities the table names without a range (`mean = []`: a template not yet filled).
    pub missing: Vec<String>,
}

fn num(x: &toml::Value) -> Option<f64> {
    x.as_float().or(x.as_integer().map(|i| i as f64))
}

/// Read the target cases of a table (e.g. `en50318_2002`) from the embedded targets.
pub fn target_cases(table: &str) -> Result<Vec<TargetCase>, CaseError> {
    target_cases_in(TARGETS_TOML, table)
}

/// A user's targets file (`pcsim validate --targets FILE`), in the format of the embedded
/// targets: one table with the preset it runs, `source`, and its cases `vNNN[_leading|_trailing]`
/// with `speed_kmh` and a range `[low, high]` per quantity (or `[]` where the range is not known
/// yet: reported as missing, never invented).
#[derive(Debug, Clone, PartialEq)]
pub struct TargetsFile {
    /// The table's name.
    pub table: String,
    /// The preset it runs (`preset = "…"`; none: the targets run only on a case a user gives).
    pub preset: Option<String>,
    /// Where its ranges come from (`source = "…"`).
    pub source: String,
    /// Its cases.
    pub cases: Vec<TargetCase>,
}

/// Read a user's targets file (see [`TargetsFile`]); errors name the key at fault.
pub fn targets_file(text: &str) -> Result<TargetsFile, CaseError> {
    let bad = |field: &str, value: &str, reason: &str| CaseError::Invalid {
        field: field.into(),
        value: value.into(),
        reason: reason.into(),
    };
    let v: toml::Value = toml::from_str(text).map_err(|e| CaseError::Parse(e.to_string()))?;
    let tables: Vec<&String> = v
        .as_table()
        .map(|t| {
            t.iter()
                .filter(|(_, x)| x.is_table())
                .map(|(k, _)| k)
                .collect()
        })
        .unwrap_or_default();
    let [table] = tables[..] else {
        return Err(bad(
            "targets",
            &format!("{} tables", tables.len()),
            "a targets file holds one table (e.g. [en50318_2018_simple]) with its cases",
        ));
    };
    let t = &v[table.as_str()];
    let text_of = |key: &str| t.get(key).and_then(|x| x.as_str()).map(str::to_string);
    let preset = text_of("preset");
    let cases = target_cases_in(text, table)?;
    if cases.is_empty() {
        return Err(bad(
            table,
            "no cases",
            "give at least one case table with speed_kmh (e.g. [TABLE.v275_leading])",
        ));
    }
    Ok(TargetsFile {
        table: table.clone(),
        preset,
        source: text_of("source").unwrap_or_default(),
        cases,
    })
}

/// Read the target cases of table `table` of targets text `text`.
pub fn target_cases_in(text: &str, table: &str) -> Result<Vec<TargetCase>, CaseError> {
    let v: toml::Value = toml::from_str(text).map_err(|e| CaseError::Parse(e.to_string()))?;
    let t = v
        .get(table)
        .and_then(|t| t.as_table())
        .ok_or_else(|| CaseError::Parse(format!("validation targets have no table `{table}`")))?;
    let mut out = Vec::new();
    for (key, c) in t {
        let Some(c) = c.as_table() else { continue };
        let Some(speed) = c.get("speed_kmh").and_then(num) else {
            continue;
        };
        let mut ranges = Vec::new();
        let mut missing = Vec::new();
        for q in QUANTITIES {
            if let Some(r) = c.get(*q).and_then(|r| r.as_array()) {
                let f: Vec<f64> = r.iter().filter_map(num).collect();
                match f[..] {
                    [lo, hi] if lo.is_finite() && hi.is_finite() => {
                        ranges.push((q.to_string(), [lo, hi]))
                    }
                    [] if r.is_empty() => missing.push(q.to_string()),
                    _ => {
                        return Err(CaseError::Invalid {
                            field: format!("{table}.{key}.{q}"),
                            value: format!("{r:?}"),
                            reason: "a range is [low, high], or [] where it is not known".into(),
                        })
                    }
                }
            }
        }
        if let Some(k) = c
            .keys()
            .find(|k| !QUANTITIES.contains(&k.as_str()) && *k != "speed_kmh" && *k != "paper_value")
        {
            return Err(CaseError::Invalid {
                field: format!("{table}.{key}.{k}"),
                value: "given".into(),
                reason: format!("not a quantity pcsim reports ({})", QUANTITIES.join(", ")),
            });
        }
        let paper = c
            .get("paper_value")
            .and_then(|p| p.as_table())
            .map(|p| {
                p.iter()
                    .filter_map(|(k, v)| num(v).map(|v| (k.clone(), v)))
                    .collect()
            })
            .unwrap_or_default();
        let pantograph = ["leading", "trailing"]
            .iter()
            .find(|p| key.ends_with(*p))
            .map(|p| p.to_string());
        out.push(TargetCase {
            key: key.clone(),
            speed_kmh: speed,
            pantograph,
            ranges,
            paper,
            missing,
        });
    }
    Ok(out)
}

/// A number of a table of the targets (e.g. `paper_realtime.measured_mean_n`).
pub fn target_value(table: &str, key: &str) -> Option<f64> {
    let v: toml::Value = toml::from_str(TARGETS_TOML).ok()?;
    v.get(table)?.get(key).and_then(num)
}
