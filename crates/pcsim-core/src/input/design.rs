//! A design search's spec (`pcsim design SPEC.toml`, Python's `pcsim.design`; issue 24): the base
//! case, the design variables (any numeric case field by its override path, with bounds), the
//! speeds with their weights, the objective, the constraints, the acceptance criteria and the
//! budget. Parsed and checked here for its own shape; `study::design::Design::new` checks it
//! against the base case (every variable's path, every pantograph named) before any run.
//!
//! ```toml
//! [base]
//! preset = "stitched-2018-like"        # or file = "case.toml" (relative to the spec)
//! set = { "catenary.presag" = { kind = "parabolic", mid_span_m = 0.0, zero_at = "supports" } }
//!
//! [[variable]]
//! path = "catenary.contact_wire.tension_n"
//! min = 15000.0
//! max = 30000.0
//!
//! [[speed]]
//! kmh = 320.0
//! weight = 1.0                         # in the objective; 0: constraints only
//!
//! [[objective]]
//! statistic = "std_n"                  # of the 0–20 Hz contact force
//! pantograph = "worst"                 # leading, trailing, worst, or an index
//!
//! [[constraint]]
//! statistic = "stat_min_n"
//! min = 0.0
//!
//! [acceptance]
//! system = "ac"                        # every criterion with a limit must be met at every speed
//!
//! [budget]
//! evaluations = 60
//! seed = 1
//! ```

use serde::Deserialize;

use crate::error::CaseError;

/// The most evaluations a search takes (each is one run per speed).
pub const MAX_EVALUATIONS: usize = 100_000;

/// A statistic of a run that an objective or a constraint reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Statistic {
    /// Mean of the 0–20 Hz contact force, N.
    MeanN,
    /// Standard deviation of the 0–20 Hz contact force, N.
    StdN,
    /// σ of the 0–5 Hz band, N.
    #[serde(rename = "std_0_5hz_n")]
    Std05HzN,
    /// σ of the 5–20 Hz band, N.
    #[serde(rename = "std_5_20hz_n")]
    Std520HzN,
    /// Fm + 3σ, N.
    StatMaxN,
    /// Fm − 3σ, N.
    StatMinN,
    /// Largest 0–20 Hz force, N.
    ActualMaxN,
    /// Smallest 0–20 Hz force, N.
    ActualMinN,
    /// Range of the contact-wire height at the contact point, mm.
    ContactPointRangeMm,
    /// Largest uplift at a steady arm while the pantograph passes, mm.
    MaxUpliftAtSupportMm,
    /// Share of samples without contact, %.
    LossOfContactPercent,
    /// Largest lateral offset of the contact point, mm (lateral motion modelled).
    MaxLateralOffsetMm,
    /// Smallest margin of the contact point to the head's end, mm (lateral motion modelled).
    MinHeadMarginMm,
    /// Largest lateral blow-out of the contact wire, mm (lateral motion modelled).
    MaxContactWireBlowoutMm,
    /// Largest number of droppers slack at once (of the run, not of a pantograph).
    MaxSlackDroppers,
    /// Share of steps with a slack dropper, % (of the run).
    StepsWithSlackPercent,
    /// The train speed over the contact wire's wave speed (of the run).
    SpeedRatio,
}

impl Statistic {
    /// Every statistic, as a spec names it.
    pub const ALL: [Statistic; 17] = [
        Statistic::MeanN,
        Statistic::StdN,
        Statistic::Std05HzN,
        Statistic::Std520HzN,
        Statistic::StatMaxN,
        Statistic::StatMinN,
        Statistic::ActualMaxN,
        Statistic::ActualMinN,
        Statistic::ContactPointRangeMm,
        Statistic::MaxUpliftAtSupportMm,
        Statistic::LossOfContactPercent,
        Statistic::MaxLateralOffsetMm,
        Statistic::MinHeadMarginMm,
        Statistic::MaxContactWireBlowoutMm,
        Statistic::MaxSlackDroppers,
        Statistic::StepsWithSlackPercent,
        Statistic::SpeedRatio,
    ];

    /// Its name in a spec (and in `summary.json`).
    pub fn name(self) -> &'static str {
        match self {
            Statistic::MeanN => "mean_n",
            Statistic::StdN => "std_n",
            Statistic::Std05HzN => "std_0_5hz_n",
            Statistic::Std520HzN => "std_5_20hz_n",
            Statistic::StatMaxN => "stat_max_n",
            Statistic::StatMinN => "stat_min_n",
            Statistic::ActualMaxN => "actual_max_n",
            Statistic::ActualMinN => "actual_min_n",
            Statistic::ContactPointRangeMm => "contact_point_range_mm",
            Statistic::MaxUpliftAtSupportMm => "max_uplift_at_support_mm",
            Statistic::LossOfContactPercent => "loss_of_contact_percent",
            Statistic::MaxLateralOffsetMm => "max_lateral_offset_mm",
            Statistic::MinHeadMarginMm => "min_head_margin_mm",
            Statistic::MaxContactWireBlowoutMm => "max_contact_wire_blowout_mm",
            Statistic::MaxSlackDroppers => "max_slack_droppers",
            Statistic::StepsWithSlackPercent => "steps_with_slack_percent",
            Statistic::SpeedRatio => "speed_ratio",
        }
    }

    /// Whether it is a statistic of the run rather than of one pantograph.
    pub fn per_run(self) -> bool {
        matches!(
            self,
            Statistic::MaxSlackDroppers | Statistic::StepsWithSlackPercent | Statistic::SpeedRatio
        )
    }
}

/// Which pantograph a statistic is read from.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Which {
    /// The first pantograph.
    Leading,
    /// The last pantograph.
    Trailing,
    /// The pantograph with this index (0: the first).
    Index(usize),
    /// The worst of all: the largest value in an objective and against a maximum, the smallest
    /// against a minimum.
    Worst,
}

impl Which {
    fn parse(s: &str) -> Option<Which> {
        Some(match s {
            "leading" => Which::Leading,
            "trailing" => Which::Trailing,
            "worst" => Which::Worst,
            _ => Which::Index(s.parse().ok()?),
        })
    }

    /// As a spec writes it.
    pub fn name(self) -> String {
        match self {
            Which::Leading => "leading".into(),
            Which::Trailing => "trailing".into(),
            Which::Worst => "worst".into(),
            Which::Index(i) => i.to_string(),
        }
    }
}

/// Where the base case comes from.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BaseSpec {
    /// An embedded preset's name.
    #[serde(default)]
    pub preset: Option<String>,
    /// A case file, relative to the spec (the front end reads it).
    #[serde(default)]
    pub file: Option<String>,
    /// Values set on the base before the search, by override path (any TOML value: a table
    /// replaces a table, so `catenary.presag` can become a parabola).
    #[serde(default)]
    pub set: toml::Table,
}

/// A design variable.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Variable {
    /// The case field, as an override path (its unit is the field's).
    pub path: String,
    /// Lower bound, in the field's unit.
    pub min: f64,
    /// Upper bound, in the field's unit.
    pub max: f64,
    /// A whole number (a count of spans, of modes).
    #[serde(default)]
    pub integer: bool,
    /// The step of the sensitivity study, in the field's unit (default: 5 % of the range; at
    /// least 1 for an integer).
    #[serde(default)]
    pub step: Option<f64>,
}

impl Variable {
    /// The sensitivity step.
    pub fn sensitivity_step(&self) -> f64 {
        let s = self.step.unwrap_or(0.05 * (self.max - self.min));
        if self.integer {
            s.round().max(1.0)
        } else {
            s
        }
    }
}

/// A speed the design is run at.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SpeedPoint {
    /// Train speed, km/h.
    pub kmh: f64,
    /// Its weight in the objective (0: the constraints only).
    #[serde(default = "one")]
    pub weight: f64,
}

fn one() -> f64 {
    1.0
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct TermRaw {
    statistic: String,
    #[serde(default)]
    pantograph: Option<toml::Value>,
    #[serde(default = "one")]
    weight: f64,
    #[serde(default)]
    target: Option<f64>,
}

/// One term of the objective: `weight × value` (or `weight × |value − target|`), summed over the
/// speeds with their weights.
#[derive(Debug, Clone, PartialEq)]
pub struct Term {
    /// The statistic.
    pub statistic: Statistic,
    /// Its pantograph.
    pub pantograph: Which,
    /// Its weight (negative: maximised).
    pub weight: f64,
    /// A target: the term is the distance to it.
    pub target: Option<f64>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct ConstraintRaw {
    statistic: String,
    #[serde(default)]
    pantograph: Option<toml::Value>,
    #[serde(default)]
    max: Option<f64>,
    #[serde(default)]
    min: Option<f64>,
    #[serde(default)]
    speeds_kmh: Option<Vec<f64>>,
}

/// A constraint: a statistic against a limit at every speed (or at those listed).
#[derive(Debug, Clone, PartialEq)]
pub struct Constraint {
    /// The statistic.
    pub statistic: Statistic,
    /// Its pantograph.
    pub pantograph: Which,
    /// Upper limit.
    pub max: Option<f64>,
    /// Lower limit.
    pub min: Option<f64>,
    /// The speeds it applies at (empty: every speed of the spec).
    pub speeds_kmh: Vec<f64>,
}

impl Constraint {
    /// Its limits: `(limit, true)` for the maximum, `(limit, false)` for the minimum.
    pub fn limits(&self) -> impl Iterator<Item = (f64, bool)> {
        self.max
            .map(|m| (m, true))
            .into_iter()
            .chain(self.min.map(|m| (m, false)))
    }

    /// Whether it holds at speed `kmh` (every speed when it lists none).
    pub fn applies_at(&self, kmh: f64) -> bool {
        self.speeds_kmh.is_empty() || self.speeds_kmh.contains(&kmh)
    }

    /// Its name in the outputs: `stat_min_n[worst]>=0`.
    pub fn label(&self) -> String {
        let mut s = format!("{}[{}]", self.statistic.name(), self.pantograph.name());
        if let Some(m) = self.min {
            s += &format!(">={m}");
        }
        if let Some(m) = self.max {
            s += &format!("<={m}");
        }
        s
    }
}

/// The acceptance criteria as constraints.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AcceptanceSpec {
    /// The supply system (`ac`, `dc-3kv`, `dc-1.5kv`; none: the criteria that depend on it are
    /// left out).
    #[serde(default)]
    pub system: Option<String>,
}

/// The optimiser.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// Particle swarm (argmin): a population evaluated side by side, bounds by construction.
    ParticleSwarm,
    /// Nelder–Mead (argmin): one evaluation at a time, few of them on a smooth objective.
    NelderMead,
    /// Every corner of the variables' box, 2ⁿ designs side by side, no optimiser: the envelope
    /// of a response that is monotone in each variable over the box (bounds from corner runs,
    /// issue 53, item 6), with the best corner as the answer.
    Corners,
}

/// Most variables a corner plan takes (2¹² = 4 096 designs).
pub const MAX_CORNER_VARIABLES: usize = 12;

impl Method {
    /// As a spec names it.
    pub fn name(self) -> &'static str {
        match self {
            Method::ParticleSwarm => "particle-swarm",
            Method::NelderMead => "nelder-mead",
            Method::Corners => "corners",
        }
    }
}

/// What the search may spend.
#[derive(Debug, Clone, PartialEq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Budget {
    /// Evaluations of the search (each one run per speed), at most.
    pub evaluations: usize,
    /// Wall time of the search, s (none: no limit). A search stopped by it says so.
    #[serde(default)]
    pub wall_s: Option<f64>,
    /// The optimiser's seed (the case's own random inputs keep their seeds: every candidate
    /// meets the same realisation).
    #[serde(default)]
    pub seed: u64,
    /// The optimiser.
    #[serde(default = "default_method")]
    pub method: Method,
    /// Particles of the swarm (default: 4 × the variables, at least 6).
    #[serde(default)]
    pub particles: Option<usize>,
}

fn default_method() -> Method {
    Method::ParticleSwarm
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct SpecRaw {
    base: BaseSpec,
    #[serde(rename = "variable")]
    variables: Vec<Variable>,
    #[serde(rename = "speed")]
    speeds: Vec<SpeedPoint>,
    objective: Vec<TermRaw>,
    #[serde(default, rename = "constraint")]
    constraints: Vec<ConstraintRaw>,
    #[serde(default)]
    acceptance: Option<AcceptanceSpec>,
    budget: Budget,
}

/// A design search's spec, checked for its own shape.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignSpec {
    /// The base case.
    pub base: BaseSpec,
    /// The design variables.
    pub variables: Vec<Variable>,
    /// The speeds.
    pub speeds: Vec<SpeedPoint>,
    /// The objective's terms.
    pub objective: Vec<Term>,
    /// The constraints.
    pub constraints: Vec<Constraint>,
    /// The acceptance criteria as constraints (none: not applied).
    pub acceptance: Option<AcceptanceSpec>,
    /// The budget.
    pub budget: Budget,
}

/// An invalid value (the design search's errors, here and in `study::design`).
pub(crate) fn invalid(
    field: impl Into<String>,
    value: impl Into<String>,
    reason: impl Into<String>,
) -> CaseError {
    CaseError::Invalid {
        field: field.into(),
        value: value.into(),
        reason: reason.into(),
    }
}

fn statistic(field: &str, s: &str) -> Result<Statistic, CaseError> {
    Statistic::ALL
        .into_iter()
        .find(|x| x.name() == s)
        .ok_or_else(|| {
            invalid(
                field,
                format!("\"{s}\""),
                format!(
                    "no such statistic; use one of {}",
                    Statistic::ALL.map(|x| x.name()).join(", ")
                ),
            )
        })
}

fn which(field: &str, v: Option<&toml::Value>) -> Result<Which, CaseError> {
    let bad = |v: &dyn std::fmt::Display| {
        invalid(
            field,
            v.to_string(),
            "use leading, trailing, worst or a pantograph's index (0, 1, …)",
        )
    };
    match v {
        None => Ok(Which::Worst),
        Some(toml::Value::String(s)) => Which::parse(s).ok_or_else(|| bad(&format!("\"{s}\""))),
        Some(toml::Value::Integer(i)) if *i >= 0 => Ok(Which::Index(*i as usize)),
        Some(other) => Err(bad(other)),
    }
}

fn finite(field: String, x: f64) -> Result<f64, CaseError> {
    if x.is_finite() {
        Ok(x)
    } else {
        Err(invalid(field, x.to_string(), "must be a finite number"))
    }
}

impl DesignSpec {
    /// Parse a spec. Every error names the field and the value.
    pub fn from_toml_str(text: &str) -> Result<DesignSpec, CaseError> {
        let de = toml::Deserializer::new(text);
        let raw: SpecRaw = serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            CaseError::Parse(format!("design spec, at `{path}`: {}", e.inner().message()))
        })?;
        let mut objective = Vec::new();
        for (k, t) in raw.objective.iter().enumerate() {
            let f = format!("objective[{k}]");
            objective.push(Term {
                statistic: statistic(&format!("{f}.statistic"), &t.statistic)?,
                pantograph: which(&format!("{f}.pantograph"), t.pantograph.as_ref())?,
                weight: finite(format!("{f}.weight"), t.weight)?,
                target: t
                    .target
                    .map(|x| finite(format!("{f}.target"), x))
                    .transpose()?,
            });
        }
        let mut constraints = Vec::new();
        for (k, c) in raw.constraints.iter().enumerate() {
            let f = format!("constraint[{k}]");
            if c.max.is_none() && c.min.is_none() {
                return Err(invalid(
                    f,
                    &c.statistic,
                    "a constraint needs `max`, `min` or both",
                ));
            }
            constraints.push(Constraint {
                statistic: statistic(&format!("{f}.statistic"), &c.statistic)?,
                pantograph: which(&format!("{f}.pantograph"), c.pantograph.as_ref())?,
                max: c.max.map(|x| finite(format!("{f}.max"), x)).transpose()?,
                min: c.min.map(|x| finite(format!("{f}.min"), x)).transpose()?,
                speeds_kmh: c.speeds_kmh.clone().unwrap_or_default(),
            });
        }
        let spec = DesignSpec {
            base: raw.base,
            variables: raw.variables,
            speeds: raw.speeds,
            objective,
            constraints,
            acceptance: raw.acceptance,
            budget: raw.budget,
        };
        spec.check_shape()?;
        Ok(spec)
    }

    /// The checks that need no case.
    fn check_shape(&self) -> Result<(), CaseError> {
        match (&self.base.preset, &self.base.file) {
            (Some(_), Some(_)) => {
                return Err(invalid(
                    "base",
                    "preset and file",
                    "give one of `preset` and `file`",
                ))
            }
            (None, None) => return Err(invalid("base", "", "give `preset` or `file`")),
            _ => {}
        }
        self.check_variables()?;
        self.check_speeds_and_objective()?;
        self.check_constraints()?;
        self.check_budget()
    }

    /// The variables: finite bounds in order (whole numbers for an integer), a step inside them,
    /// no speed and no path twice.
    fn check_variables(&self) -> Result<(), CaseError> {
        if self.variables.is_empty() {
            return Err(invalid(
                "variable",
                "[]",
                "a search needs at least one [[variable]]",
            ));
        }
        for (k, v) in self.variables.iter().enumerate() {
            let f = |n: &str| format!("variable[{k}].{n} ({})", v.path);
            finite(f("min"), v.min)?;
            finite(f("max"), v.max)?;
            if v.min >= v.max {
                return Err(invalid(
                    f("max"),
                    v.max.to_string(),
                    format!("must be above min = {}", v.min),
                ));
            }
            if v.integer && (v.min.fract() != 0.0 || v.max.fract() != 0.0) {
                return Err(invalid(
                    f("min"),
                    format!("{}..{}", v.min, v.max),
                    "an integer variable's bounds are whole numbers",
                ));
            }
            if let Some(s) = v.step {
                if !(s.is_finite() && s > 0.0 && s <= v.max - v.min) {
                    return Err(invalid(
                        f("step"),
                        s.to_string(),
                        "must be positive and at most max − min",
                    ));
                }
            }
            if v.path == "run.speed_kmh" {
                return Err(invalid(
                    f("path"),
                    &v.path,
                    "the speeds are the spec's [[speed]] list, not a variable",
                ));
            }
            if self.variables[..k].iter().any(|w| w.path == v.path) {
                return Err(invalid(f("path"), &v.path, "the path is a variable twice"));
            }
        }
        Ok(())
    }

    /// The speeds (positive, with weights ≥ 0) and the objective's terms, some weight other than 0.
    fn check_speeds_and_objective(&self) -> Result<(), CaseError> {
        if self.speeds.is_empty() {
            return Err(invalid(
                "speed",
                "[]",
                "a search needs at least one [[speed]]",
            ));
        }
        for (k, s) in self.speeds.iter().enumerate() {
            if !(s.kmh.is_finite() && s.kmh > 0.0) {
                return Err(invalid(
                    format!("speed[{k}].kmh"),
                    s.kmh.to_string(),
                    "must be positive",
                ));
            }
            if !(s.weight.is_finite() && s.weight >= 0.0) {
                return Err(invalid(
                    format!("speed[{k}].weight"),
                    s.weight.to_string(),
                    "must be finite and ≥ 0",
                ));
            }
        }
        if self.objective.is_empty() {
            return Err(invalid(
                "objective",
                "[]",
                "a search needs at least one [[objective]] term",
            ));
        }
        if self.speeds.iter().all(|s| s.weight == 0.0)
            || self.objective.iter().all(|t| t.weight == 0.0)
        {
            return Err(invalid(
                "objective",
                "weights all 0",
                "at least one speed and one objective term need a weight other than 0",
            ));
        }
        Ok(())
    }

    /// Each constraint at the spec's speeds, with a range some value can meet.
    fn check_constraints(&self) -> Result<(), CaseError> {
        for (k, c) in self.constraints.iter().enumerate() {
            for v in &c.speeds_kmh {
                if !self.speeds.iter().any(|s| s.kmh == *v) {
                    return Err(invalid(
                        format!("constraint[{k}].speeds_kmh"),
                        v.to_string(),
                        "not one of the spec's [[speed]] values",
                    ));
                }
            }
            if let (Some(lo), Some(hi)) = (c.min, c.max) {
                if lo > hi {
                    return Err(invalid(
                        format!("constraint[{k}].min"),
                        lo.to_string(),
                        format!("above its max = {hi}: no value can meet it"),
                    ));
                }
            }
        }
        Ok(())
    }

    /// The budget: its evaluations, wall time, the first simplex and the swarm.
    fn check_budget(&self) -> Result<(), CaseError> {
        let b = &self.budget;
        if b.evaluations == 0 || b.evaluations > MAX_EVALUATIONS {
            return Err(invalid(
                "budget.evaluations",
                b.evaluations.to_string(),
                format!("must be 1 to {MAX_EVALUATIONS}"),
            ));
        }
        if let Some(w) = b.wall_s {
            if !(w.is_finite() && w > 0.0) {
                return Err(invalid(
                    "budget.wall_s",
                    w.to_string(),
                    "must be a positive number of seconds",
                ));
            }
        }
        if b.method == Method::NelderMead && b.evaluations <= self.variables.len() {
            return Err(invalid(
                "budget.evaluations",
                b.evaluations.to_string(),
                format!(
                    "Nelder–Mead needs at least the {} evaluations of its first simplex",
                    self.variables.len() + 1
                ),
            ));
        }
        if b.method == Method::Corners {
            let n = self.variables.len();
            if n > MAX_CORNER_VARIABLES {
                return Err(invalid(
                    "budget.method",
                    "corners",
                    format!(
                        "{n} variables have 2^{n} corners: at most {MAX_CORNER_VARIABLES} variables"
                    ),
                ));
            }
            if b.evaluations < 1 << n {
                return Err(invalid(
                    "budget.evaluations",
                    b.evaluations.to_string(),
                    format!(
                        "the corners of {n} variables need {} evaluations",
                        1usize << n
                    ),
                ));
            }
        }
        if let Some(p) = b.particles {
            if !(2..=1000).contains(&p) {
                return Err(invalid(
                    "budget.particles",
                    p.to_string(),
                    "must be 2 to 1000",
                ));
            }
        }
        Ok(())
    }
}
