//! What a hardware-in-the-loop input may be, and why one is refused ([`InputError`]).

/// A hardware-in-the-loop input that the window cannot take.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InputError {
    /// Not a finite number.
    NotFinite {
        /// What was not finite.
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// The contact force lies outside the bound stated for the case (see
    /// `session::RealtimeSession::force_limit_n`).
    ForceOutOfBound {
        /// The force given, N.
        force_n: f64,
        /// The bound, N.
        limit_n: f64,
    },
    /// The position lies ahead of the window's far end (the wire there is not modelled).
    AheadOfWindow {
        /// The position given, m.
        position_m: f64,
        /// The window's far end, m.
        window_end_m: f64,
    },
    /// The position lies outside the modelled catenary.
    OutsideModel {
        /// The position given, m.
        position_m: f64,
        /// The model's length, m.
        length_m: f64,
    },
    /// The position lies behind the window (it only moves forward).
    BehindWindow {
        /// The position given, m.
        position_m: f64,
        /// The window's start, m.
        window_start_m: f64,
    },
    /// The position moved faster than the plausible speed since the last step.
    TooFast {
        /// The position given, m.
        position_m: f64,
        /// The previous step's position, m.
        previous_m: f64,
        /// The speed the jump implies, km/h.
        speed_kmh: f64,
        /// The plausible limit, km/h.
        limit_kmh: f64,
    },
}

impl InputError {
    /// A stable name of the reason, the same in every front end (`not_finite`,
    /// `force_out_of_bound`, `outside_model`, `behind_window`, `ahead_of_window`, `too_fast`).
    pub fn code(&self) -> &'static str {
        match self {
            InputError::NotFinite { .. } => "not_finite",
            InputError::ForceOutOfBound { .. } => "force_out_of_bound",
            InputError::OutsideModel { .. } => "outside_model",
            InputError::BehindWindow { .. } => "behind_window",
            InputError::AheadOfWindow { .. } => "ahead_of_window",
            InputError::TooFast { .. } => "too_fast",
        }
    }
}

impl std::fmt::Display for InputError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            InputError::NotFinite { what, value } => write!(f, "{what} = {value} is not finite"),
            InputError::ForceOutOfBound { force_n, limit_n } => write!(
                f,
                "contact force {force_n:e} N lies outside the bound ±{limit_n} N stated for this case"
            ),
            InputError::AheadOfWindow {
                position_m,
                window_end_m,
            } => write!(
                f,
                "pantograph position {position_m} m lies ahead of the window, which ends at {window_end_m} m"
            ),
            InputError::OutsideModel {
                position_m,
                length_m,
            } => write!(
                f,
                "pantograph position {position_m} m lies outside the modelled catenary [0, {length_m}] m"
            ),
            InputError::BehindWindow {
                position_m,
                window_start_m,
            } => write!(
                f,
                "pantograph position {position_m} m lies behind the window, which starts at {window_start_m} m and only moves forward"
            ),
            InputError::TooFast {
                position_m,
                previous_m,
                speed_kmh,
                limit_kmh,
            } => write!(
                f,
                "pantograph position jumped from {previous_m} m to {position_m} m in one step ({speed_kmh:.0} km/h, above the plausible {limit_kmh:.0} km/h)"
            ),
        }
    }
}
