//! A run against the acceptance criteria (`pcsim assess`, and the report's section; issue 22,
//! item 3): each criterion of [`crate::input::criteria`] that applies to the run's speed, supply
//! system and pantographs gives one row with the value, the limit, the verdict, the clause and the
//! source. A criterion without a limit it can cite gives the value and says that the limit is
//! missing: the assessment never passes a run on a limit it does not hold.

use serde::{Deserialize, Serialize};

use crate::analysis::stats::ContactStats;
use crate::analysis::verify::Verification;
use crate::input::criteria::{Criterion, Kind, Quantity, System};

/// One pantograph's part of what is assessed.
#[derive(Debug, Clone, PartialEq)]
pub struct PantographInput {
    /// Its name.
    pub name: String,
    /// Its EN 50318 statistics (none: it did not cross the analysis section).
    pub stats: Option<ContactStats>,
    /// Half the width of its head, m (lateral motion modelled).
    pub head_half_width_m: Option<f64>,
    /// NQ, its share of time with an arc, % (the current-collection study's; none for a run).
    pub arcing_percent: Option<f64>,
    /// Its own speed where it differs from the input's, km/h (a train of the study's mix: the
    /// criteria's speed ranges and formulas take it).
    pub speed_kmh: Option<f64>,
}

/// What a run gives the assessment: its speed, its speed ratio and its pantographs.
#[derive(Debug, Clone, PartialEq)]
pub struct AssessInput {
    /// Train speed, km/h.
    pub speed_kmh: f64,
    /// The speed over the contact wire's wave speed (none: not recorded).
    pub speed_ratio: Option<f64>,
    /// The pantographs.
    pub pantographs: Vec<PantographInput>,
    /// The run's error-level events (`summary.json`'s `errors`: a dewirement, contact lost over
    /// the limit): a run that had one is not accepted, whatever its rows say.
    pub run_errors: Vec<String>,
    /// The run's verification (`pcsim run --verify`), when it has one: each row then says
    /// whether its value is converged and whether its verdict holds refined and with the
    /// stiffer contact.
    pub verification: Option<Verification>,
    /// What is assessed: a run (its force statistics), or the current-collection study (its
    /// arcing only).
    pub source: AssessSource,
}

/// What an assessment reads.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum AssessSource {
    /// A run's `summary.json`: the force statistics, the uplift, the speed ratio; no arcing.
    Run,
    /// The current-collection study's `wear.json` (issue 54): each train's pantographs' NQ.
    CurrentCollection,
}

#[derive(Deserialize)]
struct WearView {
    trains: Vec<TrainView>,
}

#[derive(Deserialize)]
struct TrainView {
    name: String,
    speed_kmh: f64,
    pantographs: Vec<WearPantographView>,
}

#[derive(Deserialize)]
struct WearPantographView {
    name: String,
    nq_percent: f64,
}

#[derive(Deserialize)]
struct SummaryView {
    speed_kmh: f64,
    speed_ratio: Option<f64>,
    pantographs: Vec<PantographView>,
    #[serde(default)]
    errors: Vec<String>,
    #[serde(default)]
    verification: Option<Verification>,
}

#[derive(Deserialize)]
struct PantographView {
    name: String,
    stats: Option<ContactStats>,
    lateral: Option<LateralView>,
}

#[derive(Deserialize)]
struct LateralView {
    head_half_width_m: Option<f64>,
}

impl AssessInput {
    /// What a run's `summary.json` ([`crate::analysis::report::RunSummary`]) gives the
    /// assessment: the one reading of it for every front end (the CLI's `assess`, the report,
    /// Python's `pcsim.assess`). An error names what is missing or malformed.
    pub fn from_summary_json(text: &str) -> Result<AssessInput, crate::error::CaseError> {
        let v: SummaryView = serde_json::from_str(text).map_err(|e| {
            crate::error::CaseError::Parse(format!("not a run's summary.json: {e}"))
        })?;
        Ok(AssessInput {
            speed_kmh: v.speed_kmh,
            speed_ratio: v.speed_ratio,
            run_errors: v.errors,
            verification: v.verification,
            pantographs: v
                .pantographs
                .into_iter()
                .map(|p| PantographInput {
                    name: p.name,
                    stats: p.stats,
                    head_half_width_m: p.lateral.and_then(|l| l.head_half_width_m),
                    arcing_percent: None,
                    speed_kmh: None,
                })
                .collect(),
            source: AssessSource::Run,
        })
    }

    /// What the current-collection study's `wear.json` (`study::wear::WearOutput`) gives the
    /// assessment: each train's pantographs (named `TRAIN at V km/h, PANTOGRAPH`) with their NQ
    /// and their train's speed (the input's is the fastest train's). An error names what is
    /// missing or malformed.
    pub fn from_wear_json(text: &str) -> Result<AssessInput, crate::error::CaseError> {
        let v: WearView = serde_json::from_str(text).map_err(|e| {
            crate::error::CaseError::Parse(format!(
                "not a current-collection study's wear.json: {e}"
            ))
        })?;
        Ok(AssessInput {
            speed_kmh: (v.trains.iter()).fold(0.0, |a, t| a.max(t.speed_kmh)),
            speed_ratio: None,
            run_errors: Vec::new(),
            verification: None,
            pantographs: (v.trains.iter())
                .flat_map(|t| {
                    t.pantographs.iter().map(|p| PantographInput {
                        name: format!("{} at {:.0} km/h, {}", t.name, t.speed_kmh, p.name),
                        stats: None,
                        head_half_width_m: None,
                        arcing_percent: Some(p.nq_percent),
                        speed_kmh: Some(t.speed_kmh),
                    })
                })
                .collect(),
            source: AssessSource::CurrentCollection,
        })
    }
}

/// Why criterion `c` has nothing to judge in what `source` gives (`None`: it has).
fn not_given(c: &Criterion, source: AssessSource) -> Option<String> {
    match (source, c.quantity == Quantity::Arcing) {
        (AssessSource::Run, true) => Some(format!(
            "{}: arcing is the current-collection study's (pcsim study wear): assess its directory",
            c.id
        )),
        (AssessSource::CurrentCollection, false) => Some(format!(
            "{}: the current-collection study gives the arcing only: assess a run for {}",
            c.id,
            c.quantity.name()
        )),
        _ => None,
    }
}

/// A row's verdict.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum Verdict {
    /// Within the limit.
    Met,
    /// Beyond it.
    NotMet,
    /// A target without a tolerance: the deviation is given, not a verdict.
    Deviation,
    /// No limit that pcsim can cite: the value is given.
    NoLimit,
    /// The run has no value of the quantity (a pantograph that did not cross the section, or a
    /// lateral quantity without lateral motion).
    NoValue,
}

impl Verdict {
    /// As printed.
    pub fn text(self) -> &'static str {
        match self {
            Verdict::Met => "met",
            Verdict::NotMet => "NOT MET",
            Verdict::Deviation => "deviation only",
            Verdict::NoLimit => "no limit held",
            Verdict::NoValue => "no value",
        }
    }
}

/// One criterion applied to one pantograph (or to the run).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Row {
    /// The criterion's id.
    pub id: String,
    /// The pantograph (none: a quantity of the run).
    pub pantograph: Option<String>,
    /// The quantity's name.
    pub quantity: String,
    /// Its unit.
    pub unit: String,
    /// The run's value.
    pub value: Option<f64>,
    /// The limit at this run's speed (and pantograph).
    pub limit: Option<f64>,
    /// The limit as a formula.
    pub limit_formula: String,
    /// `max`, `min`, `target` or `report`.
    pub kind: String,
    /// For a target: (value − target) / target, %.
    pub deviation_percent: Option<f64>,
    /// The verdict.
    pub verdict: Verdict,
    /// The clause.
    pub clause: String,
    /// Where the limit was read (or why there is none).
    pub source: String,
    /// `quoted`, `limit-not-held`, `not-public` or `user`.
    pub status: String,
    /// What a reader should know besides.
    pub note: String,
    /// With a verified run: the value refined and with the stiffer contact, and whether the
    /// verdict holds in both.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub verification: Option<RowCheck>,
}

/// A row's value under the run's verification (`pcsim run --verify`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct RowCheck {
    /// The refined run's value (twice the modes, half the step).
    pub refined: f64,
    /// Its change, % of the statistic's scale.
    pub change_percent: f64,
    /// Whether that change is within the statistic's tolerance.
    pub converged: bool,
    /// The verdict with the refined value, against the same limit.
    pub refined_verdict: Verdict,
    /// The value with the contact twice as stiff (the model check).
    pub stiff_contact: f64,
    /// The verdict with it.
    pub stiff_contact_verdict: Verdict,
}

/// A run's assessment.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Assessment {
    /// The supply system it was assessed for (none: not given, so the criteria that depend on
    /// it are left out and named in `skipped`).
    pub system: Option<String>,
    /// Train speed, km/h.
    pub speed_kmh: f64,
    /// One row per criterion and pantograph.
    pub rows: Vec<Row>,
    /// Criteria that do not apply, each with the reason.
    pub skipped: Vec<String>,
    /// Rows met.
    pub met: usize,
    /// Rows not met.
    pub not_met: usize,
    /// Rows without a verdict (no limit held, a target without tolerance, or no value).
    pub without_verdict: usize,
    /// The run's error-level events (a dewirement, contact lost over the limit): with any, the
    /// run is not accepted, whatever its rows say (`pcsim assess --strict` fails).
    pub run_errors: Vec<String>,
    /// With a verified run: the rows whose value is not converged, or whose verdict changes
    /// refined or with the stiffer contact, as sentences.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub not_established: Vec<String>,
}

impl Assessment {
    /// One line that says what the assessment established, and what it did not.
    pub fn conclusion(&self) -> String {
        let open = if self.without_verdict > 0 {
            format!(
                "; {} without a verdict (no limit pcsim can cite, a target without tolerance, or no value): this is not an acceptance",
                self.without_verdict
            )
        } else {
            String::new()
        };
        let errors = if self.run_errors.is_empty() {
            String::new()
        } else {
            format!(
                "; the run had {} error-level event(s) (listed first): it is not accepted",
                self.run_errors.len()
            )
        };
        let doubt = if self.not_established.is_empty() {
            String::new()
        } else {
            format!(
                "; {} row(s) not established by the verification (a value not converged, or a verdict that changes refined or with the stiffer contact)",
                self.not_established.len()
            )
        };
        format!(
            "{} criteria rows met, {} not met{open}{errors}{doubt}",
            self.met, self.not_met
        )
    }

    /// Whether the run is accepted on what was assessed: every row with a verdict met and no
    /// error-level event (rows without a verdict are said by [`Assessment::conclusion`]).
    pub fn passes(&self) -> bool {
        self.not_met == 0 && self.run_errors.is_empty()
    }
}

/// The name in `summary.json`'s `stats` of a quantity the verification checks.
fn statistic_name(q: Quantity) -> Option<&'static str> {
    Some(match q {
        Quantity::MeanForce => "mean_n",
        Quantity::Std => "std_n",
        Quantity::StatMin => "stat_min_n",
        Quantity::StatMax => "stat_max_n",
        Quantity::ActualMax => "actual_max_n",
        Quantity::ActualMin => "actual_min_n",
        Quantity::UpliftAtSupport => "max_uplift_at_support_mm",
        _ => return None,
    })
}

fn stat(s: &ContactStats, q: Quantity) -> Option<f64> {
    match q {
        Quantity::MeanForce => Some(s.mean_n),
        Quantity::Std => Some(s.std_n),
        Quantity::StatMin => Some(s.stat_min_n),
        Quantity::StatMax => Some(s.stat_max_n),
        Quantity::ActualMax => Some(s.actual_max_n),
        Quantity::ActualMin => Some(s.actual_min_n),
        Quantity::UpliftAtSupport => Some(s.max_uplift_at_support_mm),
        Quantity::LossOfContact => Some(s.loss_of_contact_percent),
        Quantity::LateralOffset => s.max_lateral_offset_mm,
        Quantity::SpeedRatio | Quantity::Arcing => None,
    }
}

/// Why criterion `c` does not apply to a run at `v` km/h on `system` (`None`: it applies): a
/// criterion of other supply systems, or of the system when none is given, or of other speeds
/// (not checked without a speed).
fn not_applicable(c: &Criterion, system: Option<System>, v: Option<f64>) -> Option<String> {
    if !c.systems.is_empty() {
        match system {
            None => {
                return Some(format!(
                    "{}: applies to {} only, and the supply system was not given (--system)",
                    c.id,
                    c.systems
                        .iter()
                        .map(|s| s.name())
                        .collect::<Vec<_>>()
                        .join(", ")
                ))
            }
            Some(s) if !c.systems.contains(&s) => {
                return Some(format!("{}: does not apply to {}", c.id, s.name()))
            }
            _ => {}
        }
    }
    match (c.speed_kmh, v) {
        (Some([lo, hi]), Some(v)) if !(v > lo && v <= hi) => Some(format!(
            "{}: applies above {lo} and up to {hi} km/h, not at {v} km/h",
            c.id
        )),
        _ => None,
    }
}

/// The run `input` against `criteria` for the supply system `system` (none: the criteria that
/// depend on the system are skipped, and said so). The verdict of each row: `max` is met at or
/// below the limit, `min` at or above it, a `target` within its tolerance (without one, the
/// deviation only); a criterion without a limit gives the value alone.
pub fn assess(input: &AssessInput, criteria: &[Criterion], system: Option<System>) -> Assessment {
    let v = input.speed_kmh;
    let mut rows = Vec::new();
    let mut skipped = Vec::new();
    // A study's trains each at their own speed: a criterion's speed range is theirs.
    let per_train = input.pantographs.iter().any(|p| p.speed_kmh.is_some());
    for c in criteria {
        // The speed range is checked per train below when the trains have their own.
        let why = not_given(c, input.source)
            .or_else(|| not_applicable(c, system, (!per_train).then_some(v)));
        if let Some(why) = why {
            skipped.push(why);
            continue;
        }
        if c.quantity.per_run() {
            rows.push(row(c, None, input.speed_ratio, v, &|_| None));
            continue;
        }
        let mut any = false;
        for p in &input.pantographs {
            if let Some(w) = c.head_width_mm {
                // The head's width, to the millimetre.
                match p.head_half_width_m {
                    Some(h) if (2e3 * h - w).abs() < 0.5 => {}
                    _ => continue,
                }
            }
            let pv = p.speed_kmh.unwrap_or(v);
            if let Some(why) = not_applicable(c, system, p.speed_kmh) {
                skipped.push(format!("{why} ({})", p.name));
                continue;
            }
            any = true;
            let value = match c.quantity {
                Quantity::Arcing => p.arcing_percent,
                q => p.stats.as_ref().and_then(|s| stat(s, q)),
            };
            let of = |q: Quantity| p.stats.as_ref().and_then(|s| stat(s, q));
            let mut r = row(c, Some(p.name.clone()), value, pv, &of);
            let check = (input.verification.as_ref())
                .zip(statistic_name(c.quantity))
                .and_then(|(ver, name)| ver.check(&p.name, name));
            if let Some(k) = check {
                // Against the same limit; without one, no verdict either way.
                let verdict = |x: f64| r.limit.map_or(Verdict::NoLimit, |l| judge(c.kind, x, l).0);
                r.verification = Some(RowCheck {
                    refined: k.refined,
                    change_percent: k.change_percent,
                    converged: k.converged,
                    refined_verdict: verdict(k.refined),
                    stiff_contact: k.stiff_contact,
                    stiff_contact_verdict: verdict(k.stiff_contact),
                });
            }
            rows.push(r);
        }
        if !any && c.head_width_mm.is_some() {
            skipped.push(format!(
                "{}: no pantograph has a {} mm head with lateral motion modelled",
                c.id,
                c.head_width_mm.unwrap_or_default()
            ));
        }
    }
    let count = |f: &dyn Fn(Verdict) -> bool| rows.iter().filter(|r| f(r.verdict)).count();
    let met = count(&|x| x == Verdict::Met);
    let not_met = count(&|x| x == Verdict::NotMet);
    let not_established = rows
        .iter()
        .filter_map(|r| {
            let k = r.verification.as_ref()?;
            let who = r.pantograph.as_deref().unwrap_or("the run");
            if !k.converged {
                Some(format!(
                    "{} ({who}): {} not converged ({:+.2} % refined); verdict refined: {}",
                    r.id,
                    r.quantity,
                    k.change_percent,
                    k.refined_verdict.text()
                ))
            } else if k.refined_verdict != r.verdict || k.stiff_contact_verdict != r.verdict {
                Some(format!(
                    "{} ({who}): {} is {} but {} refined and {} with the contact twice as stiff",
                    r.id,
                    r.quantity,
                    r.verdict.text(),
                    k.refined_verdict.text(),
                    k.stiff_contact_verdict.text()
                ))
            } else {
                None
            }
        })
        .collect();
    Assessment {
        not_established,
        system: system.map(|s| s.name().to_string()),
        speed_kmh: v,
        met,
        not_met,
        without_verdict: rows.len() - met - not_met,
        rows,
        skipped,
        run_errors: input.run_errors.clone(),
    }
}

fn row(
    c: &Criterion,
    pantograph: Option<String>,
    value: Option<f64>,
    speed_kmh: f64,
    of: &dyn Fn(Quantity) -> Option<f64>,
) -> Row {
    let limit = c.limit_at(speed_kmh, of);
    let (verdict, deviation_percent) = match (value, limit) {
        (None, _) => (Verdict::NoValue, None),
        (Some(_), None) => (Verdict::NoLimit, None),
        (Some(x), Some(l)) => judge(c.kind, x, l),
    };
    Row {
        id: c.id.clone(),
        pantograph,
        quantity: c.quantity.name().into(),
        unit: c.quantity.unit().into(),
        value,
        limit,
        limit_formula: c.limit_text(),
        kind: match c.kind {
            Kind::Max => "max",
            Kind::Min => "min",
            Kind::Target { .. } => "target",
            Kind::Report => "report",
        }
        .into(),
        deviation_percent,
        verdict,
        clause: c.clause.clone(),
        source: c.source.clone(),
        status: c.status.name().into(),
        note: c.note.clone(),
        verification: None,
    }
}

/// The verdict of value `x` against limit `l` of a criterion of kind `kind`, and for a target
/// the deviation, %.
fn judge(kind: Kind, x: f64, l: f64) -> (Verdict, Option<f64>) {
    match kind {
        Kind::Max if x <= l => (Verdict::Met, None),
        Kind::Max => (Verdict::NotMet, None),
        Kind::Min if x >= l => (Verdict::Met, None),
        Kind::Min => (Verdict::NotMet, None),
        // A target of zero (a user's formula at this speed) has no relative deviation.
        Kind::Target { .. } if l == 0.0 => (Verdict::NoLimit, None),
        Kind::Target { tolerance_percent } => {
            let d = 100.0 * (x - l) / l;
            let v = match tolerance_percent {
                Some(t) if d.abs() <= t => Verdict::Met,
                Some(_) => Verdict::NotMet,
                None => Verdict::Deviation,
            };
            (v, Some(d))
        }
        Kind::Report => (Verdict::NoLimit, None),
    }
}
