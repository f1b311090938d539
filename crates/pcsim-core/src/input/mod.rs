//! What a user gives: case files (TOML with provenance), the embedded presets, and the
//! validation targets. The bottom layer: it imports nothing else from the crate.

pub mod case;
pub mod irregularity;
pub mod lateral;
pub mod overrides;
pub mod presets;
pub mod targets;
pub mod units;

pub use case::{Case, Provenance, Warning, G};
