//! Acceptance criteria (`data/acceptance-criteria.toml`, embedded; a user's file in the same
//! format): what `pcsim assess` checks a run against, each criterion with its clause, its source
//! and whether its limit was read in a public text (issue 22, item 3). A criterion without a
//! limit it can cite has none: the assessment reports the value and says so.

use serde::Deserialize;

use crate::error::CaseError;

/// The built-in criteria, embedded (every limit quoted from a named public source).
pub const CRITERIA_TOML: &str = include_str!("../../../../data/acceptance-criteria.toml");

/// A supply system, which selects the criteria that depend on it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum System {
    /// AC lines (25 kV 50 Hz, 15 kV 16.7 Hz).
    Ac,
    /// DC 3 kV.
    Dc3kV,
    /// DC 1.5 kV.
    Dc1500V,
}

impl System {
    /// Every system, in the order they are listed.
    pub const ALL: [System; 3] = [System::Ac, System::Dc3kV, System::Dc1500V];

    /// Its name in files and on the command line.
    pub fn name(self) -> &'static str {
        match self {
            System::Ac => "ac",
            System::Dc3kV => "dc-3kv",
            System::Dc1500V => "dc-1.5kv",
        }
    }

    /// The system named `s` (see [`System::name`]).
    pub fn parse(s: &str) -> Option<System> {
        System::ALL.into_iter().find(|x| x.name() == s)
    }

    /// [`System::parse`], or the one wording of an unknown name for every front end
    /// (`"ac25: not a supply system pcsim knows (ac, dc-3kv, dc-1.5kv)"`; the front end puts
    /// its flag or argument before it).
    pub fn parse_or_explain(s: &str) -> Result<System, String> {
        System::parse(s).ok_or_else(|| {
            format!(
                "{s}: not a supply system pcsim knows ({})",
                System::ALL.map(System::name).join(", ")
            )
        })
    }
}

/// A quantity a criterion checks: one of a pantograph's EN 50318 statistics, or the run's speed
/// ratio.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Quantity {
    /// Mean of the 0–20 Hz contact force, N.
    MeanForce,
    /// Its standard deviation, N.
    Std,
    /// Fm − 3σ, N.
    StatMin,
    /// Fm + 3σ, N.
    StatMax,
    /// Largest 0–20 Hz force, N.
    ActualMax,
    /// Smallest 0–20 Hz force, N.
    ActualMin,
    /// Largest uplift at a steady arm, mm.
    UpliftAtSupport,
    /// Share of time without contact, %.
    LossOfContact,
    /// Train speed over the contact wire's wave speed (one per run).
    SpeedRatio,
    /// Largest distance of the contact point from the track centre, mm (lateral motion).
    LateralOffset,
    /// NQ: the share of time with an arc, % (the current-collection study's, issue 54).
    Arcing,
}

impl Quantity {
    /// Every quantity, in the order they are listed.
    pub const ALL: [Quantity; 11] = [
        Quantity::MeanForce,
        Quantity::Std,
        Quantity::StatMin,
        Quantity::StatMax,
        Quantity::ActualMax,
        Quantity::ActualMin,
        Quantity::UpliftAtSupport,
        Quantity::LossOfContact,
        Quantity::SpeedRatio,
        Quantity::LateralOffset,
        Quantity::Arcing,
    ];

    /// Its name in files (the name of the statistic in `summary.json`).
    pub fn name(self) -> &'static str {
        match self {
            Quantity::MeanForce => "mean_force_n",
            Quantity::Std => "std_n",
            Quantity::StatMin => "stat_min_n",
            Quantity::StatMax => "stat_max_n",
            Quantity::ActualMax => "actual_max_n",
            Quantity::ActualMin => "actual_min_n",
            Quantity::UpliftAtSupport => "max_uplift_at_support_mm",
            Quantity::LossOfContact => "loss_of_contact_percent",
            Quantity::SpeedRatio => "speed_ratio",
            Quantity::LateralOffset => "max_lateral_offset_mm",
            Quantity::Arcing => "arcing_percent",
        }
    }

    /// Its unit as printed.
    pub fn unit(self) -> &'static str {
        match self {
            Quantity::UpliftAtSupport | Quantity::LateralOffset => "mm",
            Quantity::LossOfContact | Quantity::Arcing => "%",
            Quantity::SpeedRatio => "",
            _ => "N",
        }
    }

    /// Whether the run has one value of it (else one per pantograph).
    pub fn per_run(self) -> bool {
        self == Quantity::SpeedRatio
    }

    fn parse(s: &str) -> Option<Quantity> {
        Quantity::ALL.into_iter().find(|q| q.name() == s)
    }
}

/// How a criterion judges its quantity.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Kind {
    /// Met when the value is at most the limit.
    Max,
    /// Met when the value is at least the limit.
    Min,
    /// The deviation from the limit; a verdict only within a tolerance, % of the limit.
    Target {
        /// The tolerance, % of the target (none: deviation only).
        tolerance_percent: Option<f64>,
    },
    /// No limit: the value is reported.
    Report,
}

/// A criterion's limit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Limit {
    /// No limit (a criterion of kind [`Kind::Report`]).
    None,
    /// A fixed value, in the quantity's unit.
    Constant(f64),
    /// `c0 + c1 v + c2 v²`, v in km/h.
    SpeedPolynomialKmh([f64; 3]),
    /// `factor` times the same pantograph's value of `quantity`.
    FactorOf {
        /// The quantity it is a multiple of.
        quantity: Quantity,
        /// The multiple.
        factor: f64,
    },
}

/// Whether a criterion's limit was read in a public text.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Status {
    /// Read in the public source it names.
    Quoted,
    /// The clause is public, but its limit was not read in a text this project holds.
    LimitNotHeld,
    /// Its text is sold, not public.
    NotPublic,
    /// Given by the user, with the source they name.
    User,
}

impl Status {
    /// Its name in files.
    pub fn name(self) -> &'static str {
        match self {
            Status::Quoted => "quoted",
            Status::LimitNotHeld => "limit-not-held",
            Status::NotPublic => "not-public",
            Status::User => "user",
        }
    }
}

/// One acceptance criterion.
#[derive(Debug, Clone, PartialEq)]
pub struct Criterion {
    /// Unique name.
    pub id: String,
    /// What it checks.
    pub quantity: Quantity,
    /// How.
    pub kind: Kind,
    /// Against what.
    pub limit: Limit,
    /// The supply systems it applies to (empty: every one).
    pub systems: Vec<System>,
    /// The speeds it applies to, km/h: `low < v <= high` (none: every speed).
    pub speed_kmh: Option<[f64; 2]>,
    /// The pantograph head width it applies to, mm (lateral criteria).
    pub head_width_mm: Option<f64>,
    /// The clause, as its text names it.
    pub clause: String,
    /// Where the limit was read (or why there is none).
    pub source: String,
    /// Whether the limit was read in a public text.
    pub status: Status,
    /// What a reader should know besides.
    pub note: String,
}

impl Criterion {
    /// The limit at speed `speed_kmh`, given the same pantograph's value of any quantity
    /// (`value_of`); `None` without a limit, or when the quantity it is a multiple of is missing.
    pub fn limit_at(
        &self,
        speed_kmh: f64,
        value_of: &dyn Fn(Quantity) -> Option<f64>,
    ) -> Option<f64> {
        match self.limit {
            Limit::None => None,
            Limit::Constant(c) => Some(c),
            Limit::SpeedPolynomialKmh([c0, c1, c2]) => {
                Some(c0 + c1 * speed_kmh + c2 * speed_kmh * speed_kmh)
            }
            Limit::FactorOf { quantity, factor } => value_of(quantity).map(|v| factor * v),
        }
    }

    /// The limit as a formula, for a table (e.g. `0.00097 v² + 70`).
    pub fn limit_text(&self) -> String {
        match self.limit {
            Limit::None => "—".into(),
            Limit::Constant(c) => format!("{c}"),
            Limit::SpeedPolynomialKmh([c0, c1, c2]) => {
                let mut t = Vec::new();
                if c2 != 0.0 {
                    t.push(format!("{c2} v²"));
                }
                if c1 != 0.0 {
                    t.push(format!("{c1} v"));
                }
                if c0 != 0.0 || t.is_empty() {
                    t.push(format!("{c0}"));
                }
                format!("{} (v in km/h)", t.join(" + "))
            }
            Limit::FactorOf { quantity, factor } => format!("{factor} × {}", quantity.name()),
        }
    }
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FileRaw {
    #[serde(default)]
    criterion: Vec<CriterionRaw>,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct FactorRaw {
    quantity: String,
    factor: f64,
}

#[derive(Deserialize)]
#[serde(deny_unknown_fields)]
struct CriterionRaw {
    id: String,
    quantity: String,
    kind: String,
    limit: Option<f64>,
    formula_kmh: Option<Vec<f64>>,
    factor_of: Option<FactorRaw>,
    tolerance_percent: Option<f64>,
    #[serde(default)]
    systems: Vec<String>,
    speed_kmh: Option<[f64; 2]>,
    head_width_mm: Option<f64>,
    clause: String,
    source: String,
    status: String,
    #[serde(default)]
    note: String,
}

/// The built-in criteria (see [`CRITERIA_TOML`]).
pub fn builtin() -> Vec<Criterion> {
    // The embedded file is checked by the tests: it always parses.
    parse(CRITERIA_TOML, false).unwrap_or_default()
}

/// A user's criteria file: the format of [`CRITERIA_TOML`], every criterion with status
/// `user` and its own clause and source. Errors name the criterion and the field.
pub fn user_file(text: &str) -> Result<Vec<Criterion>, CaseError> {
    parse(text, true)
}

/// `base` with `extra` laid over it: a criterion of `extra` replaces the one of `base` with the
/// same id, and the others are added after.
pub fn merged(base: Vec<Criterion>, extra: Vec<Criterion>) -> Vec<Criterion> {
    let mut out = base;
    for c in extra {
        match out.iter_mut().find(|b| b.id == c.id) {
            Some(b) => *b = c,
            None => out.push(c),
        }
    }
    out
}

#[doc(hidden)] // public for the unit tests in tests/suite/unit
pub fn parse(text: &str, user: bool) -> Result<Vec<Criterion>, CaseError> {
    let raw: FileRaw = toml::from_str(text).map_err(|e| CaseError::Parse(e.to_string()))?;
    if raw.criterion.is_empty() {
        return Err(CaseError::Parse(
            "no [[criterion]] in the criteria file".into(),
        ));
    }
    let mut out: Vec<Criterion> = Vec::new();
    for (i, r) in raw.criterion.into_iter().enumerate() {
        let c = criterion(i, r, user)?;
        if out.iter().any(|o| o.id == c.id) {
            return Err(CaseError::Invalid {
                field: format!("criterion[{i}].id"),
                value: format!("\"{}\"", c.id),
                reason: "another criterion of the file has this id".into(),
            });
        }
        out.push(c);
    }
    Ok(out)
}

/// The fields of criterion `i` of a file, for the errors that name them.
struct At(usize);

impl At {
    fn bad(&self, field: &str, value: String, reason: &str) -> CaseError {
        CaseError::Invalid {
            field: format!("criterion[{}].{field}", self.0),
            value,
            reason: reason.into(),
        }
    }

    fn finite(&self, field: &str, v: f64) -> Result<f64, CaseError> {
        if v.is_finite() {
            Ok(v)
        } else {
            Err(self.bad(field, v.to_string(), "not a finite number"))
        }
    }
}

fn criterion(i: usize, r: CriterionRaw, user: bool) -> Result<Criterion, CaseError> {
    let at = At(i);
    if r.id.trim().is_empty() {
        return Err(at.bad("id", "\"\"".into(), "a criterion needs a name"));
    }
    let quantity = Quantity::parse(&r.quantity).ok_or_else(|| {
        at.bad(
            "quantity",
            format!("\"{}\"", r.quantity),
            &format!(
                "not a quantity pcsim assesses (one of {})",
                Quantity::ALL.map(Quantity::name).join(", ")
            ),
        )
    })?;
    let status = criterion_status(&at, &r, user)?;
    let limit = criterion_limit(&at, &r, quantity)?;
    let kind = criterion_kind(&at, &r)?;
    check_kind_limit_status(&at, &r, (kind, limit, status))?;
    let systems = criterion_scope(&at, &r, quantity)?;
    Ok(Criterion {
        id: r.id,
        quantity,
        kind,
        limit,
        systems,
        speed_kmh: r.speed_kmh,
        head_width_mm: r.head_width_mm,
        clause: r.clause,
        source: r.source,
        status,
        note: r.note,
    })
}

/// The criterion's status (a user's is `user`), and its clause and source, which every
/// criterion names.
fn criterion_status(at: &At, r: &CriterionRaw, user: bool) -> Result<Status, CaseError> {
    let status = match r.status.as_str() {
        "quoted" => Status::Quoted,
        "limit-not-held" => Status::LimitNotHeld,
        "not-public" => Status::NotPublic,
        "user" => Status::User,
        s => {
            return Err(at.bad(
                "status",
                format!("\"{s}\""),
                "one of quoted, limit-not-held, not-public, user",
            ))
        }
    };
    if user && status != Status::User {
        return Err(at.bad(
            "status",
            format!("\"{}\"", r.status),
            "a user's criterion has status \"user\" (only the embedded criteria say what pcsim quoted)",
        ));
    }
    for (field, text) in [("clause", &r.clause), ("source", &r.source)] {
        if text.trim().is_empty() {
            return Err(at.bad(
                field,
                "\"\"".into(),
                "every criterion names its clause and the source its limit was read in",
            ));
        }
    }
    Ok(status)
}

/// The criterion's limit: a constant, a polynomial in km/h (exactly three coefficients), a
/// multiple of another quantity of the same pantograph, or none; at most one of them.
fn criterion_limit(at: &At, r: &CriterionRaw, quantity: Quantity) -> Result<Limit, CaseError> {
    let given = [
        r.limit.is_some(),
        r.formula_kmh.is_some(),
        r.factor_of.is_some(),
    ]
    .iter()
    .filter(|x| **x)
    .count();
    if given > 1 {
        return Err(at.bad(
            "limit",
            "(several)".into(),
            "give one of limit, formula_kmh and factor_of",
        ));
    }
    Ok(if let Some(v) = r.limit {
        Limit::Constant(at.finite("limit", v)?)
    } else if let Some(p) = &r.formula_kmh {
        // Exactly three coefficients: a fourth is never dropped in silence.
        let Ok(p) = <[f64; 3]>::try_from(p.as_slice()) else {
            return Err(at.bad(
                "formula_kmh",
                format!("{p:?}"),
                "give exactly three coefficients [a, b, c] of a + b·v + c·v² (v in km/h)",
            ));
        };
        for (k, c) in p.iter().enumerate() {
            at.finite(&format!("formula_kmh[{k}]"), *c)?;
        }
        Limit::SpeedPolynomialKmh(p)
    } else if let Some(f) = &r.factor_of {
        let q = Quantity::parse(&f.quantity)
            .filter(|q| !q.per_run())
            .ok_or_else(|| {
                at.bad(
                    "factor_of.quantity",
                    format!("\"{}\"", f.quantity),
                    "not a pantograph's quantity pcsim assesses",
                )
            })?;
        if quantity.per_run() {
            return Err(at.bad(
                "factor_of",
                format!("{{ quantity = \"{}\" }}", f.quantity),
                "a run's quantity (speed_ratio) cannot be a multiple of a pantograph's",
            ));
        }
        Limit::FactorOf {
            quantity: q,
            factor: at.finite("factor_of.factor", f.factor)?,
        }
    } else {
        Limit::None
    })
}

/// The criterion's kind (a target with its tolerance, which only a target has).
fn criterion_kind(at: &At, r: &CriterionRaw) -> Result<Kind, CaseError> {
    let kind = match r.kind.as_str() {
        "max" => Kind::Max,
        "min" => Kind::Min,
        "target" => Kind::Target {
            tolerance_percent: match r.tolerance_percent {
                Some(t) if !(t.is_finite() && t > 0.0) => {
                    return Err(at.bad("tolerance_percent", t.to_string(), "must be above 0"))
                }
                t => t,
            },
        },
        "report" => Kind::Report,
        s => {
            return Err(at.bad(
                "kind",
                format!("\"{s}\""),
                "one of max, min, target, report",
            ))
        }
    };
    if r.tolerance_percent.is_some() && !matches!(kind, Kind::Target { .. }) {
        return Err(at.bad(
            "tolerance_percent",
            format!("{}", r.tolerance_percent.unwrap_or_default()),
            "only a target has a tolerance",
        ));
    }
    Ok(kind)
}

/// A report has no limit and every other kind one; a limit is written only with a source that
/// holds it, and a quoted criterion has the limit it quotes.
fn check_kind_limit_status(
    at: &At,
    r: &CriterionRaw,
    (kind, limit, status): (Kind, Limit, Status),
) -> Result<(), CaseError> {
    match (kind, limit) {
        (Kind::Report, Limit::None) => {}
        (Kind::Report, _) => {
            return Err(at.bad(
                "kind",
                "\"report\"".into(),
                "a criterion with a limit is max, min or target",
            ))
        }
        (_, Limit::None) => {
            return Err(at.bad(
                "limit",
                "(none)".into(),
                &format!(
                    "a {} criterion needs limit, formula_kmh or factor_of",
                    r.kind
                ),
            ))
        }
        _ => {}
    }
    if matches!(status, Status::LimitNotHeld | Status::NotPublic) && limit != Limit::None {
        return Err(at.bad(
            "status",
            format!("\"{}\"", r.status),
            "a criterion whose limit was not read in a public text has no limit",
        ));
    }
    if status == Status::Quoted && limit == Limit::None {
        return Err(at.bad(
            "status",
            "\"quoted\"".into(),
            "a quoted criterion has the limit it quotes",
        ));
    }
    Ok(())
}

/// Where the criterion applies: its supply systems, its speed range and the head width of a
/// lateral criterion.
fn criterion_scope(
    at: &At,
    r: &CriterionRaw,
    quantity: Quantity,
) -> Result<Vec<System>, CaseError> {
    let mut systems = Vec::new();
    for (k, s) in r.systems.iter().enumerate() {
        systems.push(System::parse(s).ok_or_else(|| {
            at.bad(
                &format!("systems[{k}]"),
                format!("\"{s}\""),
                "one of ac, dc-3kv, dc-1.5kv",
            )
        })?);
    }
    if let Some([lo, hi]) = r.speed_kmh {
        if !(lo.is_finite() && hi.is_finite() && lo >= 0.0 && hi > lo) {
            return Err(at.bad(
                "speed_kmh",
                format!("[{lo}, {hi}]"),
                "a range [low, high] of km/h with 0 <= low < high",
            ));
        }
    }
    if let Some(w) = r.head_width_mm {
        if !(w.is_finite() && w > 0.0) {
            return Err(at.bad("head_width_mm", w.to_string(), "must be above 0"));
        }
        if quantity != Quantity::LateralOffset {
            return Err(at.bad(
                "head_width_mm",
                w.to_string(),
                "only a lateral criterion (max_lateral_offset_mm) depends on the head",
            ));
        }
    }
    Ok(systems)
}
