//! What an output directory's manifest (`pcsim.json`) holds (issue 52): the study that wrote
//! it, the pcsim version, whether it is complete, its files with their hashes, and what the
//! study adds (its fingerprint and shard, its case, its section). The CLI writes and reads it
//! back through [`ManifestRecord`] (no lookup by key); `pcsim schema manifest` prints its
//! schema.

use std::collections::BTreeMap;

use serde::{Deserialize, Serialize};

use crate::study::window_search::{SearchSettings, Tolerances};

/// A manifest. Every field has a default, so that a manifest missing a field reads (and the
/// reader says which is missing) and a wrong field is told by its key
/// ([`ManifestRecord::from_value`]).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default)]
pub struct ManifestRecord {
    /// The study that wrote the directory ([`crate::study::StudyKind::name`]).
    pub kind: String,
    /// The pcsim version that wrote it.
    pub pcsim_version: String,
    /// Whether the directory is complete (false: interrupted, failed, or being written).
    pub complete: bool,
    /// The command line that wrote it.
    pub command: String,
    /// The files of the directory, relative to it (none until it is complete).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub files: Option<Vec<String>>,
    /// Each file's FNV-1a 64 hash, hexadecimal (none: written before hashes were recorded).
    #[serde(rename = "fnv1a64", skip_serializing_if = "Option::is_none")]
    pub hashes: Option<BTreeMap<String, String>>,
    /// What the study adds.
    #[serde(flatten)]
    pub study: StudyManifest,
}

/// What a study adds to its manifest: each study fills the fields it has (absent fields are not
/// written).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default)]
pub struct StudyManifest {
    /// A sweep's or a design's fingerprint (its cases and settings).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fingerprint: Option<String>,
    /// A sweep's cases, all shards together.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cases: Option<usize>,
    /// A sweep's shard `[I, N]`: the I-th of N.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shard: Option<[usize; 2]>,
    /// The cases of this shard.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cases_in_shard: Option<Vec<usize>>,
    /// A merged sweep: the shards it was merged from.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub merged_from_shards: Option<usize>,
    /// What a sweep's columns mean.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub columns: Option<String>,
    /// A window sweep's tolerances, %.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerances_pct: Option<Tolerances>,
    /// A window sweep's search lattice.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub search_m: Option<SearchSettings>,
    /// A design's figures.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub figures: Option<Vec<String>>,
    /// The pantograph studied (a comparison's, a response's, a fit's).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pantograph: Option<String>,
    /// The measured file (a comparison's, a fit's).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub measured: Option<String>,
    /// The run directory compared.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub run: Option<String>,
    /// The compared run's case.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub case: Option<String>,
    /// The case's name (the real-time comparison's).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub case_name: Option<String>,
    /// The train speed, km/h.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub speed_kmh: Option<f64>,
    /// The analysis section, m.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub analysis_m: Option<[f64; 2]>,
    /// The flags that overrode the case.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub overrides: Option<Vec<String>>,
    /// A Monte Carlo study's realisations.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub realisations: Option<usize>,
}

impl ManifestRecord {
    /// Read a manifest's JSON `value`; a field of the wrong type is named by its key and value.
    pub fn from_value(value: serde_json::Value) -> Result<Self, String> {
        Self::deserialize(&value)
            .map_err(|e| Self::field_error(&value).unwrap_or_else(|| e.to_string()))
    }

    /// The first top-level field of `value` that does not read on its own: `` `key` is value:
    /// why``.
    fn field_error(value: &serde_json::Value) -> Option<String> {
        let serde_json::Value::Object(o) = value else {
            return Some(format!("is {value}, not an object"));
        };
        o.iter().find_map(|(k, v)| {
            let one = serde_json::json!({ k.as_str(): v });
            serde_json::from_value::<Self>(one)
                .err()
                .map(|e| format!("`{k}` is {v}: {e}"))
        })
    }
}
