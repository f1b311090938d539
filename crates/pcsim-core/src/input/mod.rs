//! What a user gives: case files (TOML with provenance), the embedded presets, and the
//! validation targets. The bottom layer: it imports nothing else from the crate.

pub mod bounds;
pub mod case;
pub mod irregularity;
pub mod lateral;
pub mod overrides;
pub mod presets;
pub mod targets;
pub mod units;
mod validate;

pub use case::{Case, Provenance, Warning, G};

/// The one case loader of every front end (CLI, C API, Python, FMU), with one error wording. The
/// core does no I/O: the front end reads the file and hands over what the read gave.
pub fn case_from_file(path: &str, read: std::io::Result<String>) -> Result<Case, crate::CaseError> {
    let text = read.map_err(|e| crate::CaseError::Read {
        path: path.to_string(),
        reason: e.to_string(),
    })?;
    Case::from_toml_str(&text)
        .map(|(c, _)| c)
        .map_err(|e| crate::CaseError::InFile {
            path: path.to_string(),
            source: Box::new(e),
        })
}

/// An embedded preset by name (the same wording for an unknown name everywhere).
pub fn case_from_preset(name: &str) -> Result<Case, crate::CaseError> {
    Ok(presets::load(name)?.0)
}
