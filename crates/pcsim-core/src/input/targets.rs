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
}

fn num(x: &toml::Value) -> Option<f64> {
    x.as_float().or(x.as_integer().map(|i| i as f64))
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
        let Some(speed) = c.get("speed_kmh").and_then(num) else {
            continue;
        };
        let mut ranges = Vec::new();
        for q in QUANTITIES {
            if let Some(r) = c.get(*q).and_then(|r| r.as_array()) {
                let f: Vec<f64> = r.iter().filter_map(num).collect();
                if f.len() == 2 {
                    ranges.push((q.to_string(), [f[0], f[1]]));
                }
            }
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
        });
    }
    Ok(out)
}

/// A number of a table of the targets (e.g. `paper_realtime.measured_mean_n`).
pub fn target_value(table: &str, key: &str) -> Option<f64> {
    let v: toml::Value = toml::from_str(TARGETS_TOML).ok()?;
    v.get(table)?.get(key).and_then(num)
}
