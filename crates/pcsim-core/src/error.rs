//! Error types of the core library.

use thiserror::Error;

/// A case that cannot be parsed or whose values are invalid.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum CaseError {
    /// TOML that does not parse, or does not describe a case.
    #[error("{0}")]
    Parse(String),
    #[error("invalid value for `{field}` = {value}: {reason}")]
    /// A value outside its bounds, or inconsistent with another.
    Invalid {
        /// The field, as its path in the case file.
        field: String,
        /// The value given.
        value: String,
        /// Why it is refused, with the bound.
        reason: String,
    },
    #[error("unknown preset `{0}` (see `pcsim presets`)")]
    /// A preset name that is not embedded.
    UnknownPreset(String),
    /// A case file that could not be read (the front end read it; the core words the error).
    #[error("cannot read case file '{path}': {reason}")]
    Read {
        /// The file.
        path: String,
        /// Why it could not be read.
        reason: String,
    },
    /// An error inside a case file, with the file it came from.
    #[error("in case file '{path}': {error}")]
    InFile {
        /// The file.
        path: String,
        /// What was wrong in it (in the message, not a second link of the error chain, so that a
        /// chain printed whole says it once).
        error: Box<CaseError>,
    },
    /// An error of one case of a sweep or a study, with the case it belongs to.
    #[error("{case}: {error}")]
    InCase {
        /// The case's name or index in a sweep.
        case: String,
        /// What was wrong in it.
        error: Box<CaseError>,
    },
}

/// A run that failed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SimError {
    #[error(transparent)]
    /// The case was refused.
    Case(#[from] CaseError),
    #[error("numerical blow-up at t = {time_s:.4} s (pantograph at x = {position_m:.2} m): {what}. Usual causes: a time step too large for a stiff element (run.dt_s, or a stiffness far above the typical values), or a geometry or load the pantograph cannot follow (pre-sag, uplift, tensions); the case's warnings name values far from the typical ones")]
    /// The run blew up: a non-finite or implausible value.
    BlowUp {
        /// Simulated time, s.
        time_s: f64,
        /// Track position of the leading pantograph, m.
        position_m: f64,
        /// What was found.
        what: String,
    },
    #[error("run cancelled")]
    /// The run was cancelled (Ctrl-C or the caller's progress callback).
    Cancelled,
}

/// A non-fatal remark about a case.
#[derive(Debug, Clone, PartialEq)]
pub struct Warning(pub String);

impl std::fmt::Display for Warning {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}
