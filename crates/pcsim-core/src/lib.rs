//! # pcsim-core
//!
//! Pantograph–catenary dynamic interaction by modal superposition, after "Study on the Length of
//! the Effective Vibration Area of the Catenary in a Pantograph–Catenary Interaction System"
//! (MDPI, 2024). The physics, the solver and the analysis; no file, terminal or network I/O.
//!
//! Flow: a [`case::Case`] (TOML) → [`model::Model`] (modal matrices, point elements, pantographs)
//! → [`solver::Solver`] steps a [`solver::State`] → [`sim::RunOutput`] with
//! [`stats::ContactStats`] → [`validation`] against EN 50318 ranges.

// Index loops read like the equations they implement.
#![allow(clippy::needless_range_loop)]

pub mod basis;
pub mod case;
pub mod energy;
pub mod error;
pub mod eva;
pub mod filter;
pub mod model;
pub mod presets;
pub mod realtime;
pub mod sampler;
pub mod sim;
pub mod solver;
pub mod statics;
pub mod stats;
pub mod validation;
#[cfg(feature = "zoo")]
pub mod zoo;

pub use case::Case;
pub use error::{CaseError, SimError};
pub use model::Model;
pub use sim::{run_case, simulate, RunOutput, RunStatistics};
