//! The proof a time step was checked against the coupled system ([`StableStep`]) and the limit it
//! records ([`CoupledLimit`]): the types the integrator carries, kept apart from the check
//! (`stability.rs`) so that the integrator and the check import one way.

/// A time step that [`crate::solve::stability::check_stability`] accepted for one compiled model: the proof the
/// integrator is built on.
#[derive(Debug, Clone, PartialEq)]
pub struct StableStep {
    dt_s: f64,
    limit: CoupledLimit,
}

impl StableStep {
    /// The proof for `dt_s` against `limit` (issued by [`crate::solve::stability::check_stability`]).
    pub(crate) fn new(dt_s: f64, limit: CoupledLimit) -> Self {
        StableStep { dt_s, limit }
    }

    /// The time step that was checked, s.
    pub fn dt_s(&self) -> f64 {
        self.dt_s
    }

    /// The coupled limit it was checked against.
    pub fn limit(&self) -> &CoupledLimit {
        &self.limit
    }
}

/// The highest frequency of the coupled explicit system and what limits it (reported in a run's
/// `summary.json` as `stability`).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct CoupledLimit {
    /// The highest circular frequency found, rad/s.
    pub omega_rad_s: f64,
    /// The largest accepted time step, `MARGIN · 2/ω` ([`crate::solve::stability::MARGIN`]), s.
    pub dt_max_s: f64,
    /// The part of the model holding the largest share of that mode's strain energy, in words
    /// ("the droppers (61 % …)").
    pub limiting: String,
    /// Power iterations made.
    pub iterations: usize,
}
