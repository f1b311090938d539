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
pub mod window_search;

pub use contract::{Answer, Study, StudyFile, StudyKind};
