//! The studies: each one file that owns its spec (with its defaults and checks), its
//! fingerprint, its jobs, its run, its typed output and the answer its report opens with
//! (issue 52). The front ends (CLI, Python) fill a spec and call the study; they re-derive
//! nothing.
//!
//! | file | the study |
//! |---|---|
//! | `contract.rs` | the contract every study fills: [`StudyKind`], [`Study`], [`Answer`], [`StudyFile`] |
//! | `run.rs`, `run_answer.rs` | one run with its evidence (verify, sensitivity, droppers), its files and its answer |
//! | `compare.rs` | a run beside a recording car's measured force: the tables, compare.json, the answer |
//! | `montecarlo.rs` | realisations over seeds and their spread |
//! | `specs.rs` | the sweeps' specs: grids, EVA, window, Monte Carlo |
//! | `sweeps.rs` | the EVA sweep, the window sweep, the validation runs, as typed rows |
//! | `realtime.rs` | the real-time window against the full model; `pcsim realtime` as a study (realtime.csv, timeseries.csv, realtime.json, the answer) |
//! | `window_search.rs` | the accuracy-based window length and the energy criteria's fit |
//! | `validate.rs` | which cases, which targets, the validation table |
//! | `design.rs` | the design search: an optimiser over case fields, the journal, the answer |
//! | `manifest.rs` | what an output directory's manifest holds (written and read through one type) |
//! | `schema.rs` | the JSON Schemas of a case file and of the outputs (`pcsim schema`) |
//! | `frf.rs` | a pantograph's frequency response at the head, and a chain fitted to a measured one |
//! | `wear.rs` | current collection: arcing, wear of the wire and the strips, the lateral sweep, their life over a traffic mix (a spec-file study) |

pub mod compare;
pub mod contract;
pub mod design;
pub mod frf;
pub mod manifest;
pub mod montecarlo;
pub mod realtime;
pub mod run;
pub mod run_answer;
pub mod schema;
pub mod specs;
pub mod sweeps;
pub mod validate;
pub mod wear;
pub mod window_search;

pub use contract::{Answer, AnyStudy, Figure, FigureSeries, Ran, Study, StudyFile, StudyKind};

use crate::error::CaseError;
use crate::input::Case;

/// How a front end hands a spec's `case` over: a preset's name or a file it reads (the core
/// opens no file), as the case and its text.
pub type CaseLoader<'a> = dyn Fn(&str) -> Result<(Case, String), CaseError> + 'a;

/// The case a spec names, by the one rule of every front end: the file of that name beside the
/// spec (`file`: its path as shown and what the front end's read gave, when such a file
/// exists), else the embedded preset of that name; with its text as given.
pub fn case_named(
    name: &str,
    file: Option<(String, std::io::Result<String>)>,
) -> Result<(Case, String), CaseError> {
    match file {
        Some((path, read)) => {
            let text = read.as_ref().cloned().unwrap_or_default();
            Ok((crate::input::case_from_file(&path, read)?, text))
        }
        None => Ok((
            crate::input::case_from_preset(name)?,
            crate::input::presets::find(name)?.toml.to_string(),
        )),
    }
}

/// A spec's text and the front end's case loader made into its study.
pub type BuildStudy = fn(&str, &CaseLoader<'_>) -> Result<Box<dyn AnyStudy>, CaseError>;

/// A study written as a spec file (`kind = "…"` and its own tables): one row of
/// [`SPEC_STUDIES`] is all a front end needs to run it (`pcsim study SPEC`, Python's
/// `pcsim.study`), print its schemas (`pcsim schema NAME`, `pcsim schema NAME-spec`) and offer
/// its embedded default (MuJoCo's plugin table: a new study is one row).
pub struct SpecStudy {
    /// Its kind (its `kind` key in a spec, its output directory's kind).
    pub kind: StudyKind,
    /// What it studies, one line.
    pub what: &'static str,
    /// The embedded spec `pcsim study NAME` runs.
    pub default_spec: &'static str,
    /// Read a spec (every error names its field and value), its case through the loader.
    pub build: BuildStudy,
    /// The JSON Schema of its spec file.
    pub spec_schema: fn() -> serde_json::Value,
    /// The JSON Schema of its typed output.
    pub output_schema: fn() -> serde_json::Value,
}

/// The studies a spec file names, one row each.
pub const SPEC_STUDIES: &[SpecStudy] = &[SpecStudy {
    kind: StudyKind::Wear,
    what: "current collection: arcing, wear of the contact wire and the strips, the lateral sweep, their life over a traffic mix",
    default_spec: wear::DEFAULT_SPEC,
    build: wear::build,
    spec_schema: wear::spec_schema,
    output_schema: wear::output_schema,
}];

/// The row of the study named `name` (its kind's name), or `None`.
pub fn spec_study(name: &str) -> Option<&'static SpecStudy> {
    SPEC_STUDIES.iter().find(|s| s.kind.name() == name)
}

/// Read a spec file's text into its study: its `kind` picks the row of [`SPEC_STUDIES`].
pub fn from_spec(text: &str, load: &CaseLoader<'_>) -> Result<Box<dyn AnyStudy>, CaseError> {
    let v: toml::Value = toml::from_str(text).map_err(|e| CaseError::Parse(e.to_string()))?;
    let names = || {
        SPEC_STUDIES
            .iter()
            .map(|s| s.kind.name())
            .collect::<Vec<_>>()
            .join(", ")
    };
    let kind = v
        .get("kind")
        .and_then(|k| k.as_str())
        .ok_or_else(|| CaseError::Invalid {
            field: "kind".into(),
            value: v.get("kind").map(|k| k.to_string()).unwrap_or_default(),
            reason: format!("a study spec names its kind: one of {}", names()),
        })?;
    let row = spec_study(kind).ok_or_else(|| CaseError::Invalid {
        field: "kind".into(),
        value: kind.into(),
        reason: format!("not a study of a spec file: one of {}", names()),
    })?;
    (row.build)(text, load)
}
