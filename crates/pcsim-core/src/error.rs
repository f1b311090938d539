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
    /// A quantity of the model the engine refuses, named in the model's terms (`solve/` and
    /// `model/` never read the file format); `compile/` maps it to the case field that sets it
    /// ([`crate::compile::in_case_terms`]).
    #[error("invalid {what} = {value}: {reason}")]
    Model {
        /// What is refused, in the model's terms.
        what: ModelQuantity,
        /// Its value.
        value: String,
        /// Why, with the bound.
        reason: String,
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

/// A quantity of the model, as the engine names it in an error.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ModelQuantity {
    /// The time step Δt, s.
    TimeStep,
    /// The train speed, km/h.
    Speed,
    /// The penalty contact's stiffness, N/m.
    ContactStiffness,
    /// The masses of pantograph `0` (its index in the model).
    PantographMasses(usize),
    /// The stiffnesses of pantograph `.0`, or its `.1`-th one.
    PantographStiffness(usize, Option<usize>),
    /// Collector strip `.1` of pantograph `.0`: its contact's stiffness (`.2`), or its
    /// suspension's.
    StripStiffness(usize, usize, bool),
    /// The pantographs of a model (their number).
    Pantographs,
    /// The steady loads of the static start state (the mean wind, the ice's weight).
    SteadyLoads,
    /// The contact wire's static lateral position: the stagger and the track's curve.
    StaticLateralPosition,
    /// The static force against the head's height of pantograph `0`.
    PantographUpliftTable(usize),
}

impl std::fmt::Display for ModelQuantity {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            ModelQuantity::TimeStep => write!(f, "time step Δt [s]"),
            ModelQuantity::Speed => write!(f, "train speed [km/h]"),
            ModelQuantity::ContactStiffness => write!(f, "contact stiffness [N/m]"),
            ModelQuantity::PantographMasses(p) => write!(f, "masses of pantograph {p} [kg]"),
            ModelQuantity::PantographStiffness(p, None) => {
                write!(f, "stiffnesses of pantograph {p} [N/m]")
            }
            ModelQuantity::PantographStiffness(p, Some(j)) => {
                write!(f, "stiffness {j} of pantograph {p} [N/m]")
            }
            ModelQuantity::StripStiffness(p, s, true) => {
                write!(f, "contact stiffness of strip {s} of pantograph {p} [N/m]")
            }
            ModelQuantity::StripStiffness(p, s, false) => {
                write!(f, "stiffness of strip {s} of pantograph {p} [N/m]")
            }
            ModelQuantity::Pantographs => write!(f, "pantographs"),
            ModelQuantity::SteadyLoads => write!(f, "static start state under the steady loads"),
            ModelQuantity::StaticLateralPosition => {
                write!(f, "the contact wire's static lateral position [m]")
            }
            ModelQuantity::PantographUpliftTable(p) => {
                write!(f, "static force against height of pantograph {p} [N]")
            }
        }
    }
}

impl ModelQuantity {
    /// The case field that sets it (its path in the case file): how `compile/` names it.
    pub fn case_path(self) -> String {
        match self {
            ModelQuantity::TimeStep => "run.dt_s".into(),
            ModelQuantity::Speed => "run.speed_kmh".into(),
            ModelQuantity::ContactStiffness => "contact.stiffness_n_per_m".into(),
            ModelQuantity::PantographMasses(p) => format!("pantographs[{p}].masses_kg"),
            ModelQuantity::PantographStiffness(p, None) => {
                format!("pantographs[{p}].stiffness_n_per_m")
            }
            ModelQuantity::PantographStiffness(p, Some(j)) => {
                format!("pantographs[{p}].stiffness_n_per_m[{j}]")
            }
            ModelQuantity::StripStiffness(p, s, true) => {
                format!("pantographs[{p}].strips[{s}].contact_stiffness_n_per_m")
            }
            ModelQuantity::StripStiffness(p, s, false) => {
                format!("pantographs[{p}].strips[{s}].stiffness_n_per_m")
            }
            ModelQuantity::Pantographs => "pantographs".into(),
            ModelQuantity::SteadyLoads => "wind / catenary.ice".into(),
            ModelQuantity::StaticLateralPosition => {
                "catenary.lateral (stagger, track_radius_m)".into()
            }
            ModelQuantity::PantographUpliftTable(p) => format!("pantographs[{p}].uplift_by_height"),
        }
    }
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
