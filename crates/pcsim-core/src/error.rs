//! Error types of the core library.

use thiserror::Error;

/// A case that cannot be parsed or whose values are invalid.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum CaseError {
    #[error("case file: {0}")]
    Parse(String),
    #[error("invalid value for `{field}` = {value}: {reason}")]
    Invalid {
        field: String,
        value: String,
        reason: String,
    },
    #[error("unknown preset `{0}` (see `pcsim presets`)")]
    UnknownPreset(String),
    /// An error of one case of a sweep or a study, with the case it belongs to.
    #[error("{case}: {source}")]
    InCase {
        case: String,
        source: Box<CaseError>,
    },
}

/// A run that failed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SimError {
    #[error(transparent)]
    Case(#[from] CaseError),
    #[error("numerical blow-up at t = {time_s:.4} s (leading pantograph at x = {position_m:.2} m): {what}; reduce run.dt_s or check stiffness values")]
    BlowUp {
        time_s: f64,
        position_m: f64,
        what: String,
    },
    #[error("run cancelled")]
    Cancelled,
}
