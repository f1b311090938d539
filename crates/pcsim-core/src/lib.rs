//! # pcsim-core
//!
//! Pantograph–catenary dynamic interaction by modal superposition, after "Study on the Length of
//! the Effective Vibration Area of the Catenary in a Pantograph–Catenary Interaction System"
//! (MDPI, 2024). The physics, the solver and the analysis; no file, terminal or network I/O.
//!
//! Layers, each importing only from the ones above it in this list (`tests/suite/layers.rs`):
//! - [`model`]: wires and their modal series, point elements, pantographs, statics — the problem;
//! - [`solve`]: plan and options, state, workspace, integrator, the run loop, the real-time window;
//! - [`input`]: cases (TOML with provenance), presets, validation targets (reusing the model's
//!   vocabulary);
//! - [`compile`]: a case becomes a set-up (the only reader of cases for the engine);
//! - [`analysis`]: what a run means: filters, EN 50318 statistics, energy, EVA, fatigue, a run
//!   against criteria and beside a measurement, a run's own evidence;
//! - [`session`]: the real-time session, the one owner of the real-time step contract;
//! - [`study`]: the studies over many runs, one file each, each the owner of its spec, run,
//!   typed output and answer.
//!
//! Flow: a [`Case`] → [`compile::Setup`] (model, plan, options) → [`solve::Integrator`] steps a
//! [`solve::State`] with a [`solve::Workspace`] in [`solve::run()`] → observers such as the EN 50318
//! recorder ([`analysis::record::simulate`]) → [`study::validate`].

// Index loops read like the equations they implement.
#![allow(clippy::needless_range_loop)]
// Every public item says what it is (issue 18); CI denies warnings.
#![warn(missing_docs)]
// Every unsafe block says why it is sound (a `SAFETY:` comment), as in the FFI crates.
#![deny(clippy::undocumented_unsafe_blocks)]
// No production function over 100 lines (clippy.toml's threshold; issue 52): a long function
// is split into named parts. Tests are exempt (a scenario reads best whole).
#![cfg_attr(not(test), deny(clippy::too_many_lines))]

pub mod analysis;
pub mod compile;
pub mod error;
pub mod fingerprint;
pub mod input;
pub mod linalg;
pub mod model;
pub mod session;
pub mod solve;
pub mod study;
#[cfg(feature = "zoo")]
pub mod zoo;

pub use analysis::record::{run_case, simulate, RunOutput};
pub use compile::{Budget, Setup};
pub use error::{CaseError, SimError};
pub use input::{presets, Case};
pub use model::Model;
pub use solve::RunStatistics;
