//! Validation against published acceptance ranges (`data/validation-targets.toml`, embedded).

use serde::Serialize;

use crate::error::CaseError;
use crate::stats::ContactStats;

/// The validation targets, copied from the reference data with their provenance.
pub const TARGETS_TOML: &str = include_str!("../../../data/validation-targets.toml");

/// One row of a validation table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Row {
    pub quantity: String,
    pub value: f64,
    pub range: [f64; 2],
    pub pass: bool,
    /// The seed paper's own value, where the targets give one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub paper_value: Option<f64>,
    /// Whether the paper's value lies in the range.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub paper_pass: Option<bool>,
}

/// A speed case of a validation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CaseRows {
    pub speed_kmh: f64,
    /// "leading" or "trailing" where the targets distinguish pantographs.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pantograph: Option<String>,
    pub rows: Vec<Row>,
}

/// Quantities in the order they are reported, with the `ContactStats` field each maps to.
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

/// The value of quantity `q` in `s`.
pub fn stat_value(s: &ContactStats, q: &str) -> Option<f64> {
    Some(match q {
        "mean" => s.mean_n,
        "std" => s.std_n,
        "std_0_5hz" => s.std_0_5hz_n,
        "std_5_20hz" => s.std_5_20hz_n,
        "stat_max" => s.stat_max_n,
        "stat_min" => s.stat_min_n,
        "actual_max" => s.actual_max_n,
        "actual_min" => s.actual_min_n,
        "contact_point_range_mm" => s.contact_point_range_mm,
        "max_uplift_at_support_mm" => s.max_uplift_at_support_mm,
        "loss_of_contact_percent" => s.loss_of_contact_percent,
        _ => return None,
    })
}

/// A target case: its speed and the ranges it gives, in [`QUANTITIES`] order.
#[derive(Debug, Clone, PartialEq)]
pub struct TargetCase {
    pub key: String,
    pub speed_kmh: f64,
    /// From the key's suffix (`v275_leading` → "leading").
    pub pantograph: Option<String>,
    pub ranges: Vec<(String, [f64; 2])>,
    /// `paper_value` entries, by quantity.
    pub paper: Vec<(String, f64)>,
}

/// Read the target cases of a table (e.g. `en50318_2002`) from the embedded targets.
pub fn target_cases(table: &str) -> Result<Vec<TargetCase>, CaseError> {
    let v: toml::Value =
        toml::from_str(TARGETS_TOML).map_err(|e| CaseError::Parse(e.to_string()))?;
    let t = v
        .get(table)
        .and_then(|t| t.as_table())
        .ok_or_else(|| CaseError::Parse(format!("validation targets have no table `{table}`")))?;
    let mut out = Vec::new();
    for (key, c) in t {
        let Some(c) = c.as_table() else { continue };
        let Some(speed) = c
            .get("speed_kmh")
            .and_then(|s| s.as_float().or(s.as_integer().map(|i| i as f64)))
        else {
            continue;
        };
        let mut ranges = Vec::new();
        for q in QUANTITIES {
            if let Some(r) = c.get(*q).and_then(|r| r.as_array()) {
                let f: Vec<f64> = r
                    .iter()
                    .filter_map(|x| x.as_float().or(x.as_integer().map(|i| i as f64)))
                    .collect();
                if f.len() == 2 {
                    ranges.push((q.to_string(), [f[0], f[1]]));
                }
            }
        }
        let num = |x: &toml::Value| x.as_float().or(x.as_integer().map(|i| i as f64));
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
        });
    }
    Ok(out)
}

/// Compare statistics with a target case. Values are compared after rounding to the ranges'
/// own precision (0.1 N/mm/%); a single-value range such as `[169, 169]` gets ±0.5.
pub fn compare(stats: &ContactStats, target: &TargetCase) -> CaseRows {
    let rows = target
        .ranges
        .iter()
        .filter_map(|(q, r)| {
            let v = stat_value(stats, q)?;
            let inside = |v: f64| {
                let (lo, hi) = if r[0] == r[1] && r[0] != 0.0 {
                    (r[0] - 0.5, r[1] + 0.5)
                } else {
                    (r[0].min(r[1]), r[0].max(r[1]))
                };
                let vr = (v * 10.0).round() / 10.0;
                vr >= lo && vr <= hi
            };
            let paper_value = target.paper.iter().find(|(k, _)| k == q).map(|(_, v)| *v);
            Some(Row {
                quantity: q.clone(),
                value: v,
                range: *r,
                pass: inside(v),
                paper_value,
                paper_pass: paper_value.map(inside),
            })
        })
        .collect();
    CaseRows {
        speed_kmh: target.speed_kmh,
        pantograph: target.pantograph.clone(),
        rows,
    }
}
