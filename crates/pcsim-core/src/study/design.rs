//! The design search (issue 24): the settings of a catenary or a pantograph that minimise an
//! objective of the runs at several speeds, under constraints and the acceptance criteria. The
//! one owner of the contract: the CLI's `pcsim design` and Python's `pcsim.design` only read the
//! spec, hand over the journal and write what this module returns.
//!
//! - **The optimiser** is argmin's (a maintained crate, not a hand-written one): its particle
//!   swarm by default (bounded by construction, its population evaluated side by side, seeded
//!   through the spec's `budget.seed`), or its Nelder–Mead (one evaluation at a time, few of
//!   them on a smooth objective). Both search the unit cube; a variable is `min + u (max − min)`,
//!   rounded when it is an integer.
//! - **An evaluation** runs the base case with the variables set, once per speed (the runs of a
//!   batch side by side over [`parallel_map`], in order), and reads the statistics. Its cost is
//!   the objective when every constraint holds; otherwise [`INFEASIBLE_COST`] × (1 + the summed
//!   relative violation), so that every feasible design ranks before every infeasible one, and a
//!   run that fails costs [`FAILED_COST`].
//! - **The journal.** Every new evaluation is handed to the caller (design.csv) in the order the
//!   optimiser first asked for it. Each run is deterministic, so an evaluation is a function of
//!   the design values: a resumed search is given the journal's evaluations, asks the same
//!   points in the same order, takes them from the journal instead of running them, and ends
//!   with the uninterrupted search's result (tested). A journal written by another spec (its
//!   [`Design::fingerprint`] differs) is refused by the front end.
//! - **The answer.** The best feasible design, run again (the confirmation: its statistics must
//!   equal the journal's), the base design beside it, the objective at ± a step of each variable
//!   (the sensitivity), and each constraint's margin with whether it is active (violated within
//!   one step). No feasible design: the search says so and names the least violating one.

use std::collections::HashMap;
use std::sync::Mutex;
use std::time::Instant;

use argmin::core::{CostFunction, Error as ArgminError, Executor, State, TerminationReason};
use argmin::solver::neldermead::NelderMead;
use argmin::solver::particleswarm::ParticleSwarm;
use rand_xoshiro::rand_core::SeedableRng;
use serde::{Deserialize, Serialize};

use crate::analysis::assess::{assess, AssessInput, Verdict};
use crate::analysis::record::{simulate, RunOutput};
use crate::analysis::report::RunSummary;
use crate::analysis::stats::ContactStats;
use crate::analysis::sweep::parallel_map;
use crate::compile::{Budget as RunBudget, Setup};
use crate::error::{CaseError, SimError};
use crate::input::case::Case;
use crate::input::criteria::{self, Criterion, System};
use crate::input::design::{invalid, Constraint, DesignSpec, Method, Statistic, Term, Which};
use crate::input::overrides::{value_at, with_overrides, OverrideValue};

/// The cost of an infeasible design per unit of (1 + its relative violation): above every
/// objective a run's statistics give (newtons, millimetres, per cent).
pub const INFEASIBLE_COST: f64 = 1e20;
/// The cost of a design whose run failed (refused, blew up, no statistics).
pub const FAILED_COST: f64 = 1e30;

/// A statistic as read for a term or a constraint: which pantograph, and for `worst` whether the
/// largest or the smallest value is the worst.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Need {
    /// The statistic.
    pub statistic: Statistic,
    /// Its pantograph.
    pub which: Which,
    /// For `worst`: the largest value (else the smallest).
    pub high: bool,
}

impl Need {
    /// What an objective term reads (for `worst`, the largest value).
    fn of_term(t: &Term) -> Need {
        Need {
            statistic: t.statistic,
            which: t.pantograph,
            high: true,
        }
    }

    /// What a constraint's maximum (`high`) or minimum reads.
    fn of_limit(c: &Constraint, high: bool) -> Need {
        Need {
            statistic: c.statistic,
            which: c.pantograph,
            high,
        }
    }

    /// Its column name, without the speed: `std_n[max]`, `mean_n[0]`.
    pub fn label(&self) -> String {
        let w = match self.which {
            Which::Worst if self.high => "max".to_string(),
            Which::Worst => "min".to_string(),
            w => w.name(),
        };
        if self.statistic.per_run() {
            self.statistic.name().to_string()
        } else {
            format!("{}[{w}]", self.statistic.name())
        }
    }
}

/// A checked design search: the spec, the base case with its `set` values, the statistics it
/// reads, and the acceptance criteria it applies.
#[derive(Debug, Clone)]
pub struct Design {
    /// The spec.
    pub spec: DesignSpec,
    /// The base case (the spec's `set` values applied).
    pub base: Case,
    /// The statistics read, in column order.
    pub needs: Vec<Need>,
    criteria: Option<(Vec<Criterion>, Option<System>)>,
    run_budget: RunBudget,
    fingerprint: String,
}

/// One design's evaluation: its values, what its runs gave, and its cost.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Evaluation {
    /// Its index: the order in which the search first asked for it.
    pub index: usize,
    /// The search's phase: `search` or `sensitivity`.
    pub phase: String,
    /// The batch of the search it was asked in.
    pub batch: usize,
    /// The design variables' values, in the spec's order and units.
    pub x: Vec<f64>,
    /// Per speed (the spec's order), per [`Design::needs`]: the statistic (none: no value).
    pub values: Vec<Vec<Option<f64>>>,
    /// The objective (none: a run failed).
    pub objective: Option<f64>,
    /// The summed relative violation of the constraints (0: feasible).
    pub violation: f64,
    /// The constraints violated, each `label@speed`.
    pub violated: Vec<String>,
    /// What failed (none: every run gave its statistics).
    pub error: Option<String>,
    /// What the optimiser saw.
    pub cost: f64,
}

impl Evaluation {
    /// Every run gave its statistics and every constraint holds.
    pub fn feasible(&self) -> bool {
        self.error.is_none() && self.violation == 0.0
    }
}

/// Why a search stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum StopReason {
    /// The budget's evaluations were spent.
    Evaluations,
    /// The optimiser converged (Nelder–Mead: the simplex's costs agree; a corner plan: every
    /// corner was run).
    Converged,
    /// The budget's wall time was spent.
    WallTime,
    /// The caller stopped it (an interrupt).
    Interrupted,
}

/// One variable's sensitivity: the objective at ± its step from the best design.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Sensitivity {
    /// The variable's path.
    pub path: String,
    /// The step, in the variable's unit.
    pub step: f64,
    /// The best design's value.
    pub value: f64,
    /// `min` or `max` when the best design sits at that bound: the optimum may lie beyond the
    /// range searched.
    pub at_bound: Option<String>,
    /// The value below (none: the best sits at its lower bound).
    pub below: Option<f64>,
    /// The objective there, and whether that design is feasible.
    pub objective_below: Option<f64>,
    /// Feasible below.
    pub feasible_below: Option<bool>,
    /// The value above (none: at the upper bound).
    pub above: Option<f64>,
    /// The objective there.
    pub objective_above: Option<f64>,
    /// Feasible above.
    pub feasible_above: Option<bool>,
}

/// One constraint at one speed, at the best design.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct ConstraintStatus {
    /// `label@speed`, or `acceptance:ID[pantograph]@speed`.
    pub name: String,
    /// The value at the best design.
    pub value: Option<f64>,
    /// The limit.
    pub limit: Option<f64>,
    /// How far inside the limit, in the value's unit (negative: violated).
    pub margin: Option<f64>,
    /// Violated by a design one sensitivity step away.
    pub active: bool,
}

/// A design search as `design.json` holds it (and Python's `design()` returns; `pcsim schema
/// design`): written and read back through this type. No wall time, so the same search gives
/// the same bytes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct DesignRecord {
    /// `improved`, `no improvement found`, `interrupted` or `infeasible`
    /// ([`DesignResult::answer`]).
    pub answer: String,
    /// The search's fingerprint (its journal's).
    pub fingerprint: String,
    /// The optimiser (`particle-swarm`, `nelder-mead`).
    pub method: String,
    /// The optimiser's seed.
    pub seed: u64,
    /// Evaluations asked by the optimiser.
    pub evaluations_asked: usize,
    /// Why the search stopped.
    pub stop: StopReason,
    /// The design variables, in the spec's order.
    pub variables: Vec<VariableRecord>,
    /// The speeds, km/h.
    pub speeds_kmh: Vec<f64>,
    /// The statistics read per speed, in the order of [`Evaluation::values`].
    pub columns: Vec<String>,
    /// A feasible design was found (the best, or the base).
    pub feasible: bool,
    /// The design handed over (none: nothing beat the base, or nothing is feasible).
    pub best: Option<Evaluation>,
    /// The search's best feasible evaluation, recommended or not.
    pub best_evaluated: Option<Evaluation>,
    /// No feasible design: the least violating evaluation.
    pub least_violating: Option<Evaluation>,
    /// The base design's evaluation.
    pub base: Option<Evaluation>,
    /// The best design run again.
    pub confirmation: Option<Confirmation>,
    /// Each variable's sensitivity at the best design.
    pub sensitivity: Vec<Sensitivity>,
    /// Each constraint at the best design.
    pub constraints: Vec<ConstraintStatus>,
}

/// A design variable's range as design.json gives it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct VariableRecord {
    /// The case field, as an override path.
    pub path: String,
    /// Lower bound, in the field's unit.
    pub min: f64,
    /// Upper bound, in the field's unit.
    pub max: f64,
    /// A whole number.
    pub integer: bool,
}

/// The best design's confirmation run.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Confirmation {
    /// Its evaluation.
    pub evaluation: Evaluation,
    /// Whether its statistics equal the search's evaluation of the same design.
    pub same_as_search: bool,
}

/// The search's answer.
#[derive(Debug, Clone)]
pub struct DesignResult {
    /// Every evaluation, in the order first asked (the journal's rows, with those given).
    pub evaluations: Vec<Evaluation>,
    /// Evaluations asked by the optimiser (journal hits included): what the budget counts.
    pub asked: usize,
    /// Evaluations run in this call (the rest came from the journal).
    pub run_now: usize,
    /// Why the search stopped.
    pub stop: StopReason,
    /// The search's best feasible evaluation's index (none: no feasible design was found).
    pub best: Option<usize>,
    /// The design handed over: `best` when it beats the base design (a base that is feasible
    /// and costs no more is not beaten: "no improvement found"); none otherwise.
    pub recommended: Option<usize>,
    /// No feasible design: the least violating evaluation's index (none: every run failed).
    pub least_violating: Option<usize>,
    /// The best design run again, and whether its statistics equal the journal's.
    pub confirmation: Option<(Evaluation, bool)>,
    /// The base design's evaluation (none after an interrupt).
    pub base: Option<Evaluation>,
    /// The base design's runs, one per speed (none: a run failed).
    pub base_runs: Vec<Option<RunOutput>>,
    /// The best design's confirmation runs, one per speed.
    pub best_runs: Vec<Option<RunOutput>>,
    /// The sensitivity of each variable at the best design.
    pub sensitivity: Vec<Sensitivity>,
    /// Each constraint at the best design.
    pub constraints: Vec<ConstraintStatus>,
}

/// A pantograph's statistic `q` (none for the run's own statistics, or one the run has no
/// value of): the one lookup by name, [`crate::analysis::verify::statistic`].
fn stat_of(s: &ContactStats, q: Statistic) -> Option<f64> {
    if q.per_run() {
        return None;
    }
    crate::analysis::verify::statistic(s, q.name())
}

/// A statistic `need` of one run (none: the run has no value of it).
fn read(out: &RunOutput, need: &Need) -> Option<f64> {
    match need.statistic {
        Statistic::MaxSlackDroppers => return Some(out.max_slack_droppers as f64),
        Statistic::StepsWithSlackPercent => return Some(out.steps_with_slack_percent),
        Statistic::SpeedRatio => return out.contact_wire_wave_speed_m_s.map(|c| out.speed_m_s / c),
        _ => {}
    }
    let ps = &out.pantographs;
    let of = |i: usize| {
        ps.get(i)?
            .stats
            .as_ref()
            .and_then(|s| stat_of(s, need.statistic))
    };
    match need.which {
        Which::Leading => of(0),
        Which::Trailing => of(ps.len().checked_sub(1)?),
        Which::Index(i) => of(i),
        Which::Worst => {
            let v: Option<Vec<f64>> = (0..ps.len()).map(of).collect();
            let v = v?;
            if need.high {
                v.into_iter().reduce(f64::max)
            } else {
                v.into_iter().reduce(f64::min)
            }
        }
    }
}

/// An acceptance criterion with a verdict, of one run.
struct AcceptanceRow {
    /// `acceptance:ID[pantograph]`.
    name: String,
    value: Option<f64>,
    limit: Option<f64>,
    /// How far inside the limit (negative: violated).
    margin: Option<f64>,
    met: bool,
}

/// What one run at one speed gave.
struct SpeedRun {
    values: Vec<Option<f64>>,
    acceptance: Vec<AcceptanceRow>,
    run_errors: Vec<String>,
    output: RunOutput,
}

/// A violation relative to its limit (to the unit when the limit is 0).
fn relative(excess: f64, limit: f64) -> f64 {
    excess / if limit.abs() > 0.0 { limit.abs() } else { 1.0 }
}

impl Design {
    /// Check `spec` against its base case (`base`: the preset or file the spec names, read by the
    /// front end): the `set` values, every variable's path at both bounds, every pantograph
    /// named, the acceptance's supply system. Every error names the field and the value.
    pub fn new(spec: DesignSpec, base: Case) -> Result<Design, CaseError> {
        let set: Vec<(String, OverrideValue)> = spec
            .base
            .set
            .iter()
            .map(|(k, v)| (k.clone(), OverrideValue::Toml(v.clone())))
            .collect();
        let base = with_overrides(&base, &set).map_err(|e| CaseError::InCase {
            case: "design spec, base.set".into(),
            error: Box::new(e),
        })?;
        for (k, v) in spec.variables.iter().enumerate() {
            for (bound, x) in [("min", v.min), ("max", v.max)] {
                let value = if v.integer {
                    OverrideValue::Integer(x as i64)
                } else {
                    OverrideValue::Number(x)
                };
                with_overrides(&base, &[(v.path.clone(), value)]).map_err(|e| {
                    CaseError::InCase {
                        case: format!("design spec, variable[{k}] ({}) at its {bound} {x}", v.path),
                        error: Box::new(e),
                    }
                })?;
            }
        }
        for s in &spec.speeds {
            let mut c = base.clone();
            c.run.speed_kmh = s.kmh;
            c.validate().map_err(|e| CaseError::InCase {
                case: format!("design spec, speed {} km/h", s.kmh),
                error: Box::new(e),
            })?;
        }
        let n_panto = base.pantographs.len();
        let check_which = |field: String, w: Which| match w {
            Which::Index(i) if i >= n_panto => Err(invalid(
                field,
                i.to_string(),
                format!(
                    "the base case has {n_panto} pantograph(s), indices 0 to {}",
                    n_panto.saturating_sub(1)
                ),
            )),
            _ => Ok(()),
        };
        let mut needs: Vec<Need> = Vec::new();
        let mut add = |n: Need| {
            if !needs.contains(&n) {
                needs.push(n);
            }
        };
        for (k, t) in spec.objective.iter().enumerate() {
            check_which(format!("objective[{k}].pantograph"), t.pantograph)?;
            add(Need::of_term(t));
        }
        for (k, c) in spec.constraints.iter().enumerate() {
            check_which(format!("constraint[{k}].pantograph"), c.pantograph)?;
            for (_, high) in c.limits() {
                add(Need::of_limit(c, high));
            }
        }
        let criteria = match &spec.acceptance {
            None => None,
            Some(a) => {
                let system = a
                    .system
                    .as_deref()
                    .map(|s| {
                        System::parse_or_explain(s).map_err(|e| invalid("acceptance.system", s, e))
                    })
                    .transpose()?;
                Some((criteria::builtin(), system))
            }
        };
        // The fingerprint: everything that decides an evaluation and the search's path, not the
        // budget's size (a resumed search may be given more evaluations or time).
        let fp_text = format!(
            "{}\n{:?}\n{:?}\n{:?}\n{:?}\n{:?}\n{}\n{}\n{:?}\n{}",
            base.to_toml_string(),
            spec.variables,
            spec.speeds,
            spec.objective,
            spec.constraints,
            spec.acceptance,
            spec.budget.seed,
            spec.budget.method.name(),
            spec.budget.particles,
            crate::solve::Isa::detect().name(),
        );
        Ok(Design {
            fingerprint: crate::fingerprint::fnv1a64_hex(fp_text.as_bytes()),
            spec,
            base,
            needs,
            criteria,
            run_budget: RunBudget::default(),
        })
    }

    /// A spec's text and its base case: a preset, or a case file that `read` reads (the front
    /// end's bounded read, relative to the spec): the one loader of every front end.
    pub fn from_spec_text(
        text: &str,
        read: &dyn Fn(&str) -> std::io::Result<String>,
    ) -> Result<Design, CaseError> {
        let spec = DesignSpec::from_toml_str(text)?;
        let base = match (&spec.base.preset, &spec.base.file) {
            (Some(p), _) => crate::input::case_from_preset(p)?,
            (None, Some(f)) => crate::input::case_from_file(f, read(f))?,
            (None, None) => unreachable!("the spec's shape names its base"),
        };
        Design::new(spec, base)
    }

    /// The same search with the runs held to `budget` (the CLI's memory and step limits).
    pub fn with_run_budget(mut self, budget: RunBudget) -> Design {
        self.run_budget = budget;
        self
    }

    /// What decides the search (the base case, the spec but its budget's size, the kernels):
    /// a journal is resumed only by a search of the same fingerprint.
    pub fn fingerprint(&self) -> &str {
        &self.fingerprint
    }

    /// The base design's values (each variable as the base case has it, or the middle of its
    /// range when the case's value is not a number).
    pub fn base_x(&self) -> Vec<f64> {
        self.spec
            .variables
            .iter()
            .map(|v| match value_at(&self.base, &v.path) {
                Ok(toml::Value::Float(x)) => x,
                Ok(toml::Value::Integer(i)) => i as f64,
                _ => 0.5 * (v.min + v.max),
            })
            .collect()
    }

    /// The design values of a point `u` of the unit cube (clamped into it; integers rounded).
    pub fn x_of(&self, u: &[f64]) -> Vec<f64> {
        self.spec
            .variables
            .iter()
            .zip(u)
            .map(|(v, &u)| {
                let u = if u.is_finite() {
                    u.clamp(0.0, 1.0)
                } else {
                    0.5
                };
                let x = v.min + u * (v.max - v.min);
                if v.integer {
                    x.round().clamp(v.min, v.max)
                } else {
                    x.clamp(v.min, v.max)
                }
            })
            .collect()
    }

    fn u_of(&self, x: &[f64]) -> Vec<f64> {
        self.spec
            .variables
            .iter()
            .zip(x)
            .map(|(v, &x)| ((x - v.min) / (v.max - v.min)).clamp(0.0, 1.0))
            .collect()
    }

    /// The case of design `x` at speed `kmh`.
    pub fn case_at(&self, x: &[f64], kmh: f64) -> Result<Case, CaseError> {
        let mut o: Vec<(String, OverrideValue)> = self
            .spec
            .variables
            .iter()
            .zip(x)
            .map(|(v, &x)| {
                let value = if v.integer {
                    OverrideValue::Integer(x as i64)
                } else {
                    OverrideValue::Number(x)
                };
                (v.path.clone(), value)
            })
            .collect();
        o.push(("run.speed_kmh".into(), OverrideValue::Number(kmh)));
        with_overrides(&self.base, &o)
    }

    fn run_one(&self, x: &[f64], speed: usize) -> Result<SpeedRun, SimError> {
        let kmh = self.spec.speeds[speed].kmh;
        let case = self.case_at(x, kmh)?;
        let setup = Setup::from_case_with(&case, &self.run_budget)?;
        let output = simulate(&setup, &mut |_| true)?;
        let values = self.needs.iter().map(|n| read(&output, n)).collect();
        let summary = RunSummary::new(&case, &output, 0.0, Vec::new(), Vec::new());
        let run_errors = summary.errors.clone();
        let mut acceptance = Vec::new();
        if let Some((list, system)) = &self.criteria {
            let text =
                serde_json::to_string(&summary).map_err(|e| CaseError::Parse(e.to_string()))?;
            let input = AssessInput::from_summary_json(&text)?;
            for r in assess(&input, list, *system).rows {
                if matches!(r.verdict, Verdict::Met | Verdict::NotMet) {
                    let who = r.pantograph.map_or(String::new(), |p| format!("[{p}]"));
                    let margin = match (r.value, r.limit, r.kind.as_str()) {
                        (Some(v), Some(l), "max") => Some(l - v),
                        (Some(v), Some(l), "min") => Some(v - l),
                        _ => None,
                    };
                    acceptance.push(AcceptanceRow {
                        name: format!("acceptance:{}{who}", r.id),
                        value: r.value,
                        limit: r.limit,
                        margin,
                        met: r.verdict == Verdict::Met,
                    });
                }
            }
        }
        Ok(SpeedRun {
            values,
            acceptance,
            run_errors,
            output,
        })
    }

    /// Assemble an evaluation from its runs (one per speed).
    fn assemble(&self, x: Vec<f64>, runs: &[Result<SpeedRun, SimError>]) -> Evaluation {
        let mut values = Vec::new();
        let mut error = None;
        let mut violation = 0.0;
        let mut violated = Vec::new();
        let mut objective = 0.0;
        for (sp, run) in self.spec.speeds.iter().zip(runs) {
            let r = match run {
                Ok(r) => r,
                Err(e) => {
                    error.get_or_insert_with(|| format!("at {} km/h: {e}", sp.kmh));
                    values.push(vec![None; self.needs.len()]);
                    continue;
                }
            };
            values.push(r.values.clone());
            let value = |n: &Need| r.values[self.needs.iter().position(|m| m == n).expect("need")];
            for t in &self.spec.objective {
                let n = Need::of_term(t);
                match value(&n) {
                    Some(v) => {
                        let v = t.target.map_or(v, |target| (v - target).abs());
                        objective += sp.weight * t.weight * v;
                    }
                    None => {
                        error.get_or_insert_with(|| {
                            format!("at {} km/h: the run has no value of {}", sp.kmh, n.label())
                        });
                    }
                }
            }
            for c in self
                .spec
                .constraints
                .iter()
                .filter(|c| c.applies_at(sp.kmh))
            {
                for (limit, high) in c.limits() {
                    let n = Need::of_limit(c, high);
                    match value(&n) {
                        Some(v) => {
                            let rel = relative(if high { v - limit } else { limit - v }, limit);
                            if rel > 0.0 {
                                violation += rel;
                                violated.push(format!("{}@{}", c.label(), sp.kmh));
                            }
                        }
                        None => {
                            error.get_or_insert_with(|| {
                                format!("at {} km/h: the run has no value of {}", sp.kmh, n.label())
                            });
                        }
                    }
                }
            }
            for a in r.acceptance.iter().filter(|a| !a.met) {
                let (v, l) = (a.value.unwrap_or(0.0), a.limit.unwrap_or(0.0));
                violation += relative((v - l).abs(), l).max(f64::MIN_POSITIVE);
                violated.push(format!("{}@{}", a.name, sp.kmh));
            }
            for e in &r.run_errors {
                violation += 1.0;
                violated.push(format!("run error@{}: {e}", sp.kmh));
            }
        }
        let objective = if error.is_none() && objective.is_finite() {
            Some(objective)
        } else {
            error.get_or_insert_with(|| "the objective is not finite".into());
            None
        };
        let cost = match objective {
            None => FAILED_COST,
            Some(f) if violation == 0.0 => f,
            // Below a failed run's cost whatever the violation (and finite).
            Some(_) => (INFEASIBLE_COST * (1.0 + violation)).min(0.5 * FAILED_COST),
        };
        Evaluation {
            index: 0,
            phase: String::new(),
            batch: 0,
            x,
            values,
            objective,
            violation,
            violated,
            error,
            cost,
        }
    }

    /// Evaluate the designs `xs` (each at every speed; the runs side by side on `jobs` workers,
    /// in order), with their runs.
    fn evaluate_many(
        &self,
        xs: &[Vec<f64>],
        jobs: Option<usize>,
    ) -> Vec<(Evaluation, Vec<Option<SpeedRun>>)> {
        let ns = self.spec.speeds.len();
        let items: Vec<(usize, usize)> = (0..xs.len())
            .flat_map(|i| (0..ns).map(move |s| (i, s)))
            .collect();
        let mut runs = parallel_map(&items, jobs, |&(i, s)| self.run_one(&xs[i], s)).into_iter();
        xs.iter()
            .map(|x| {
                let r: Vec<_> = runs.by_ref().take(ns).collect();
                let e = self.assemble(x.clone(), &r);
                (e, r.into_iter().map(Result::ok).collect())
            })
            .collect()
    }

    /// Evaluate one design (every speed), with its runs.
    pub fn evaluate(&self, x: &[f64], jobs: Option<usize>) -> (Evaluation, Vec<Option<RunOutput>>) {
        let (e, runs) = self
            .evaluate_many(&[x.to_vec()], jobs)
            .pop()
            .expect("one design");
        (e, runs.into_iter().map(|r| r.map(|r| r.output)).collect())
    }

    /// The journal's columns (design.csv's header).
    pub fn journal_header(&self) -> Vec<String> {
        let mut h: Vec<String> = ["evaluation", "phase", "batch"].map(String::from).to_vec();
        h.extend(self.spec.variables.iter().map(|v| v.path.clone()));
        h.extend(["cost", "objective", "feasible", "violation"].map(String::from));
        for s in &self.spec.speeds {
            for n in &self.needs {
                h.push(format!("{}@{}", n.label(), s.kmh));
            }
        }
        h.extend(["violated", "error", "seed", "fingerprint", "row_checksum"].map(String::from));
        h
    }

    /// The checksum of a journal row's fields (every column before `row_checksum`): FNV-1a 64 of
    /// the fields joined by the unit separator. A row edited by hand or damaged on disk no longer
    /// matches it, and is refused ([`Design::journal_read`]) rather than trusted.
    fn row_checksum(fields: &[String]) -> String {
        crate::fingerprint::fnv1a64_hex(fields.join("\u{1f}").as_bytes())
    }

    /// An evaluation as a journal row (numbers in their shortest exact form, so that a row read
    /// back gives the same bits).
    pub fn journal_row(&self, e: &Evaluation) -> Vec<String> {
        let num = |x: Option<f64>| x.map_or(String::new(), |x| format!("{x:?}"));
        let mut r = vec![e.index.to_string(), e.phase.clone(), e.batch.to_string()];
        r.extend(e.x.iter().map(|x| num(Some(*x))));
        r.push(num(Some(e.cost)));
        r.push(num(e.objective));
        r.push(e.feasible().to_string());
        r.push(num(Some(e.violation)));
        for v in &e.values {
            r.extend(v.iter().map(|x| num(*x)));
        }
        r.push(serde_json::to_string(&e.violated).expect("strings serialise"));
        r.push(e.error.clone().unwrap_or_default());
        r.push(self.spec.budget.seed.to_string());
        r.push(self.fingerprint.clone());
        let sum = Self::row_checksum(&r);
        r.push(sum);
        r
    }

    /// A journal row read back (`header` and `row` as [`Design::journal_header`] and
    /// [`Design::journal_row`] wrote them). An error names the row and the column: a journal of
    /// another spec, or one edited by hand, is refused.
    pub fn journal_read(&self, header: &[String], row: &[String]) -> Result<Evaluation, CaseError> {
        let want = self.journal_header();
        if header != want.as_slice() {
            return Err(invalid(
                "journal header",
                header.join(","),
                format!("not this spec's columns ({})", want.join(",")),
            ));
        }
        if row.len() != want.len() {
            return Err(invalid(
                "journal row",
                row.join(","),
                format!("{} columns, the header has {}", row.len(), want.len()),
            ));
        }
        let last = want.len() - 1;
        if row[last] != Self::row_checksum(&row[..last]) {
            return Err(invalid(
                "journal row",
                row[..last.min(4)].join(","),
                "its checksum does not match its values: the row was edited by hand or damaged on disk, so its evaluation cannot be trusted".to_string(),
            ));
        }
        let at = |k: usize| row[k].as_str();
        let bad = |k: usize, why: &str| {
            invalid(
                format!("journal column {}", want[k]),
                at(k),
                why.to_string(),
            )
        };
        let fp = at(want.len() - 2);
        if fp != self.fingerprint {
            return Err(invalid(
                "journal fingerprint",
                fp,
                format!(
                    "written by another search (this spec's fingerprint is {}: its base case, variables, speeds, objective, constraints, seed, method or the kernels differ)",
                    self.fingerprint
                ),
            ));
        }
        let num = |k: usize| -> Result<f64, CaseError> {
            at(k).parse::<f64>().map_err(|_| bad(k, "not a number"))
        };
        let opt = |k: usize| -> Result<Option<f64>, CaseError> {
            if at(k).is_empty() {
                Ok(None)
            } else {
                num(k).map(Some)
            }
        };
        let nv = self.spec.variables.len();
        let index = at(0).parse().map_err(|_| bad(0, "not a whole number"))?;
        let batch = at(2).parse().map_err(|_| bad(2, "not a whole number"))?;
        let x = (0..nv).map(|k| num(3 + k)).collect::<Result<Vec<_>, _>>()?;
        let c = 3 + nv;
        let (cost, objective, violation) = (num(c)?, opt(c + 1)?, num(c + 3)?);
        let mut values = Vec::new();
        let mut k = c + 4;
        for _ in &self.spec.speeds {
            let mut v = Vec::new();
            for _ in &self.needs {
                v.push(opt(k)?);
                k += 1;
            }
            values.push(v);
        }
        let violated: Vec<String> =
            serde_json::from_str(at(k)).map_err(|_| bad(k, "not a JSON list of names"))?;
        let error = (!at(k + 1).is_empty()).then(|| at(k + 1).to_string());
        Ok(Evaluation {
            index,
            phase: at(1).to_string(),
            batch,
            x,
            values,
            objective,
            violation,
            violated,
            error,
            cost,
        })
    }
}

/// Who runs a batch of designs: this machine's pool ([`Local`]), or a front end's engine (Dask
/// workers, a Slurm job array) that hands back each design's journal row
/// ([`Design::journal_row`], read with [`Design::journal_read`]: the fingerprint and the design
/// values are checked, so a row of another search or another design is refused).
pub trait Evaluator: Sync {
    /// The evaluations of `xs`, in order (their `index`, `phase` and `batch` are set by the
    /// search). An error stops the search; the journal keeps every batch before it.
    fn evaluate(&self, design: &Design, xs: &[Vec<f64>]) -> Result<Vec<Evaluation>, String>;
}

/// This machine: the runs of a batch side by side on `jobs` workers (`None`: every core).
#[derive(Debug, Clone, Copy)]
pub struct Local {
    /// Workers.
    pub jobs: Option<usize>,
}

impl Evaluator for Local {
    fn evaluate(&self, design: &Design, xs: &[Vec<f64>]) -> Result<Vec<Evaluation>, String> {
        Ok(design
            .evaluate_many(xs, self.jobs)
            .into_iter()
            .map(|(e, _)| e)
            .collect())
    }
}

/// Why the optimiser was stopped from inside its cost function (argmin carries it as an error).
#[derive(Debug)]
enum Halt {
    /// The search stops here (budget, wall time, interrupt).
    Stop(StopReason),
    /// The evaluator failed: the search ends with this error.
    Failed(String),
}

impl std::fmt::Display for Halt {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Halt::Stop(s) => write!(f, "the search stops: {s:?}"),
            Halt::Failed(e) => write!(f, "{e}"),
        }
    }
}

impl std::error::Error for Halt {}

/// The search's book-keeping: the journal (every evaluation by its design values' bits), the
/// budget, and the caller's callback.
struct Book<'a> {
    evaluations: Vec<Evaluation>,
    by_x: HashMap<Vec<u64>, usize>,
    asked: usize,
    run_now: usize,
    batch: usize,
    started: Instant,
    stop: Option<StopReason>,
    on_batch: &'a mut (dyn FnMut(&[Evaluation]) -> bool + Send),
}

/// The optimiser's view: a cost per point of the unit cube.
struct Problem<'a> {
    design: &'a Design,
    evaluator: &'a dyn Evaluator,
    /// Points outside the cube (Nelder–Mead) cost their clamped point's cost plus a penalty.
    penalise_outside: bool,
    book: Mutex<Book<'a>>,
}

impl Problem<'_> {
    /// The costs of a batch of points: those in the journal taken from it, the rest run side by
    /// side (within the budget) and handed to the caller in order.
    fn costs(&self, us: &[&Vec<f64>], phase: &str) -> Result<Vec<f64>, ArgminError> {
        let mut book = self.book.lock().expect("the book is not poisoned");
        let d = self.design;
        let left = d.spec.budget.evaluations.saturating_sub(book.asked);
        let take = if phase == "search" {
            us.len().min(left)
        } else {
            us.len()
        };
        if take == 0 {
            book.stop.get_or_insert(StopReason::Evaluations);
            return Err(Halt::Stop(StopReason::Evaluations).into());
        }
        let xs: Vec<Vec<f64>> = us[..take].iter().map(|u| d.x_of(u)).collect();
        let mut new: Vec<Vec<f64>> = Vec::new();
        for x in &xs {
            if !book.by_x.contains_key(&bits(x)) && !new.contains(x) {
                new.push(x.clone());
            }
        }
        if !new.is_empty() {
            // A stop (an interrupt, the wall time) holds only where the search has work left
            // to run: points in the journal are always answered (argmin's Nelder–Mead cannot
            // take an error while it evaluates its first simplex, which is in the journal by
            // then), and the sensitivity belongs to the answer.
            if let (Some(s), "search") = (book.stop, phase) {
                return Err(Halt::Stop(s).into());
            }
            // The first batch always runs: a search stopped by its wall time answers from
            // something.
            if let Some(w) = d
                .spec
                .budget
                .wall_s
                .filter(|_| book.batch > 0 && phase == "search")
            {
                if book.started.elapsed().as_secs_f64() > w {
                    book.stop = Some(StopReason::WallTime);
                    return Err(Halt::Stop(StopReason::WallTime).into());
                }
            }
            let batch = book.batch;
            let mut fresh = Vec::new();
            let got = self
                .evaluator
                .evaluate(d, &new)
                .and_then(|got| {
                    if got.len() == new.len() && got.iter().zip(&new).all(|(e, x)| bits(&e.x) == bits(x)) {
                        Ok(got)
                    } else {
                        Err(format!(
                            "the evaluator answered {} evaluation(s) for the {} design(s) asked, or other designs",
                            got.len(),
                            new.len()
                        ))
                    }
                })
                .map_err(Halt::Failed)?;
            for mut e in got {
                e.index = book.evaluations.len();
                e.phase = phase.to_string();
                e.batch = batch;
                book.by_x.insert(bits(&e.x), e.index);
                fresh.push(e.clone());
                book.evaluations.push(e);
            }
            book.run_now += fresh.len();
            if !(book.on_batch)(&fresh) {
                book.stop = Some(StopReason::Interrupted);
            }
        }
        if phase == "search" {
            book.asked += take;
        }
        // Counted whether it ran or came from the journal: a resumed search numbers its
        // batches as the uninterrupted one.
        book.batch += 1;
        let costs: Vec<f64> = us[..take]
            .iter()
            .zip(&xs)
            .map(|(u, x)| {
                let c = book.evaluations[book.by_x[&bits(x)]].cost;
                if self.penalise_outside && u.iter().any(|u| !(0.0..=1.0).contains(u)) {
                    let out: f64 = u
                        .iter()
                        .map(|&u| (u - u.clamp(0.0, 1.0)).powi(2))
                        .sum::<f64>()
                        .sqrt();
                    c + (1.0 + c.abs()) * out
                } else {
                    c
                }
            })
            .collect();
        if take < us.len() {
            book.stop.get_or_insert(StopReason::Evaluations);
            return Err(Halt::Stop(StopReason::Evaluations).into());
        }
        Ok(costs)
    }
}

/// The key of a design in the journal: its values' bits.
fn bits(x: &[f64]) -> Vec<u64> {
    x.iter().map(|v| v.to_bits()).collect()
}

/// What argmin's executor owns: a view of the problem, which outlives the executor (an error
/// ends the executor and would take an owned problem with it).
struct View<'p, 'a>(&'p Problem<'a>);

impl CostFunction for View<'_, '_> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, u: &Vec<f64>) -> Result<f64, ArgminError> {
        Ok(self.0.costs(&[u], "search")?[0])
    }

    fn bulk_cost<P>(&self, params: &[P]) -> Result<Vec<f64>, ArgminError>
    where
        P: std::borrow::Borrow<Vec<f64>> + argmin::core::SyncAlias,
        f64: argmin::core::SendAlias,
        Self: argmin::core::SyncAlias,
    {
        let us: Vec<&Vec<f64>> = params.iter().map(|p| p.borrow()).collect();
        self.0.costs(&us, "search")
    }
}

/// Run the spec's optimiser over `problem` within its budget: why it stopped.
fn run_optimiser(problem: &Problem<'_>) -> Result<StopReason, CaseError> {
    let design = problem.design;
    let b = &design.spec.budget;
    let n = design.spec.variables.len();
    let outcome: Result<bool, ArgminError> = match b.method {
        Method::ParticleSwarm => {
            let p = b
                .particles
                .unwrap_or((4 * n).max(6))
                .min(b.evaluations)
                .max(2);
            let iters = (b.evaluations.saturating_sub(p) / p) as u64;
            let rng = rand_xoshiro::Xoshiro256PlusPlus::seed_from_u64(b.seed);
            let solver =
                ParticleSwarm::new((vec![0.0; n], vec![1.0; n]), p).with_rng_generator(rng);
            Executor::new(View(problem), solver)
                .configure(|s| s.max_iters(iters))
                .run()
                .map(|_| false)
        }
        Method::NelderMead => {
            // From the base design, one quarter of each range along each axis.
            let u0 = design.u_of(&design.base_x());
            let mut simplex = vec![u0.clone()];
            for i in 0..n {
                let mut u = u0.clone();
                u[i] += if u[i] + 0.25 <= 1.0 { 0.25 } else { -0.25 };
                simplex.push(u);
            }
            // The first simplex runs as one batch (argmin's Nelder–Mead asks its points one by
            // one, then finds them in the journal); they are counted once.
            let refs: Vec<&Vec<f64>> = simplex.iter().collect();
            let first = problem.costs(&refs, "search");
            let stopped = problem.book.lock().expect("book").stop;
            match (first, stopped) {
                (Err(e), _) => Err(e),
                (Ok(_), Some(s)) => Err(Halt::Stop(s).into()),
                (Ok(_), None) => {
                    problem.book.lock().expect("book").asked -= simplex.len();
                    let solver = NelderMead::new(simplex)
                        .with_sd_tolerance(1e-9)
                        .map_err(|e| invalid("budget.method", "nelder-mead", e.to_string()))?;
                    Executor::new(View(problem), solver)
                        .configure(|s| s.max_iters(u64::MAX))
                        .run()
                        .map(|r| {
                            matches!(
                                r.state().get_termination_reason(),
                                Some(TerminationReason::SolverConverged)
                            )
                        })
                }
            }
        }
        Method::Corners => {
            // Corner k takes variable i at its upper bound when bit i of k is set: one batch,
            // in that order (the journal's), and the plan is then complete.
            let corners: Vec<Vec<f64>> = (0..1usize << n)
                .map(|k| (0..n).map(|i| ((k >> i) & 1) as f64).collect())
                .collect();
            let refs: Vec<&Vec<f64>> = corners.iter().collect();
            problem.costs(&refs, "search").map(|_| true)
        }
    };
    match outcome {
        Ok(converged) => Ok(problem
            .book
            .lock()
            .expect("book")
            .stop
            .unwrap_or(if converged {
                StopReason::Converged
            } else {
                StopReason::Evaluations
            })),
        Err(e) => match e.downcast_ref::<Halt>() {
            Some(Halt::Stop(s)) => Ok(*s),
            Some(Halt::Failed(f)) => Err(invalid("design search", "the evaluator", f)),
            None => Err(invalid("design search", "the optimiser", e.to_string())),
        },
    }
}

/// The objective one sensitivity step below and above the best design `bi`, per variable, from
/// the evaluations of the plan (`neighbours`: the evaluation of each step, two per variable).
fn sensitivities(
    design: &Design,
    evaluations: &[Evaluation],
    bi: usize,
    neighbours: &[Option<usize>],
) -> Vec<Sensitivity> {
    let bx = &evaluations[bi].x;
    let mut sensitivity = Vec::new();
    for (k, v) in design.spec.variables.iter().enumerate() {
        let at = |j: usize| neighbours[2 * k + j].map(|i| &evaluations[i]);
        let (lo, hi) = (at(0), at(1));
        sensitivity.push(Sensitivity {
            path: v.path.clone(),
            step: v.sensitivity_step(),
            value: bx[k],
            at_bound: if bx[k] <= v.min {
                Some("min".into())
            } else if bx[k] >= v.max {
                Some("max".into())
            } else {
                None
            },
            below: lo.map(|e| e.x[k]),
            objective_below: lo.and_then(|e| e.objective),
            feasible_below: lo.map(|e| e.feasible()),
            above: hi.map(|e| e.x[k]),
            objective_above: hi.and_then(|e| e.objective),
            feasible_above: hi.map(|e| e.feasible()),
        });
    }
    sensitivity
}

/// Whether `best` is worth handing over against the base design: the base must have been run
/// (not after an interrupt) and be infeasible or cost strictly more. A search never recommends
/// what it did not beat.
fn beats_base(best: &Evaluation, base: Option<&Evaluation>) -> bool {
    match base {
        None => false,
        Some(b) => !b.feasible() || best.cost < b.cost,
    }
}

/// The evaluation that violates the constraints least (an infeasible search's answer).
fn least_violating(evaluations: &[Evaluation]) -> Option<usize> {
    evaluations
        .iter()
        .filter(|e| e.error.is_none())
        .min_by(|a, b| {
            a.violation
                .total_cmp(&b.violation)
                .then(a.index.cmp(&b.index))
        })
        .map(|e| e.index)
}

/// The sensitivity: ± a step of each variable from the best design `best` (none: no runs),
/// journaled so that a resumed search finds them in the journal too. Each planned point in the
/// search's unit coordinates, `None` where the step would leave the variable's range.
fn sensitivity_runs(
    problem: &Problem<'_>,
    best: Option<usize>,
) -> Result<Vec<Option<Vec<f64>>>, CaseError> {
    let mut plan: Vec<Option<Vec<f64>>> = Vec::new();
    if let Some(bi) = best {
        let design = problem.design;
        let bx = problem.book.lock().expect("book").evaluations[bi].x.clone();
        for (k, v) in design.spec.variables.iter().enumerate() {
            for dir in [-1.0, 1.0] {
                let mut x = bx.clone();
                x[k] = (bx[k] + dir * v.sensitivity_step()).clamp(v.min, v.max);
                plan.push((x[k] != bx[k]).then(|| design.u_of(&x)));
            }
        }
        let refs: Vec<&Vec<f64>> = plan.iter().flatten().collect();
        if !refs.is_empty() {
            problem
                .costs(&refs, "sensitivity")
                .map_err(|e| invalid("design search", "sensitivity", e.to_string()))?;
        }
    }
    Ok(plan)
}

/// Run the design search: the optimiser within the budget, then the best design's confirmation,
/// the base design, the sensitivity and the constraints' status.
///
/// `journal`: the evaluations of an earlier, interrupted run of the same search (read back with
/// [`Design::journal_read`]); they are not run again. `on_batch` receives every new evaluation,
/// batch by batch in order (the front end appends them to design.csv); returning `false` stops
/// the search after that batch (an interrupt), with the answer from what was evaluated.
/// `evaluator` runs the search's batches ([`Local`]: this machine); the base design and the
/// confirmation run here on `jobs` workers (`None`: every core). The answer depends on neither.
pub fn search(
    design: &Design,
    journal: Vec<Evaluation>,
    evaluator: &dyn Evaluator,
    jobs: Option<usize>,
    on_batch: &mut (dyn FnMut(&[Evaluation]) -> bool + Send),
) -> Result<DesignResult, CaseError> {
    let n = design.spec.variables.len();
    let mut by_x = HashMap::new();
    for (k, e) in journal.iter().enumerate() {
        if e.index != k || e.x.len() != n {
            return Err(invalid(
                "journal",
                format!("row {k}"),
                format!("evaluation {} out of order", e.index),
            ));
        }
        by_x.insert(bits(&e.x), k);
    }
    let b = &design.spec.budget;
    let problem = Problem {
        design,
        evaluator,
        penalise_outside: b.method == Method::NelderMead,
        book: Mutex::new(Book {
            evaluations: journal,
            by_x,
            asked: 0,
            run_now: 0,
            batch: 0,
            started: Instant::now(),
            stop: None,
            on_batch,
        }),
    };
    let stop = run_optimiser(&problem)?;
    let best = {
        let book = problem.book.lock().expect("book");
        book.evaluations
            .iter()
            // The search's own evaluations: a journal of a finished search also holds its
            // sensitivity's, which a resumed search must not take as its own.
            .filter(|e| e.feasible() && e.phase == "search")
            .min_by(|a, b| a.cost.total_cmp(&b.cost).then(a.index.cmp(&b.index)))
            .map(|e| e.index)
    };
    let interrupted = stop == StopReason::Interrupted;
    let plan = sensitivity_runs(&problem, best.filter(|_| !interrupted))?;
    let book = problem.book.into_inner().expect("book");
    let evaluations = book.evaluations;
    let neighbours: Vec<Option<usize>> = plan
        .iter()
        .map(|u| u.as_ref().map(|u| book.by_x[&bits(&design.x_of(u))]))
        .collect();
    let sensitivity = match (best, interrupted) {
        (Some(bi), false) => sensitivities(design, &evaluations, bi, &neighbours),
        _ => Vec::new(),
    };
    let least_violating = if best.is_none() {
        least_violating(&evaluations)
    } else {
        None
    };
    // The base design, and the best one run again (not after an interrupt: the journal holds
    // the search, and a resumed search gives the answer).
    let (base, base_runs) = if interrupted {
        (None, Vec::new())
    } else {
        let (e, r) = design.evaluate(&design.base_x(), jobs);
        (Some(e), r)
    };
    let (confirmation, best_runs, constraints) = match (best, interrupted) {
        (Some(bi), false) => {
            let (c, runs) = design
                .evaluate_many(std::slice::from_ref(&evaluations[bi].x), jobs)
                .pop()
                .expect("one design");
            let j = &evaluations[bi];
            let same = c.values == j.values && c.objective == j.objective && c.cost == j.cost;
            let status = constraint_status(design, &evaluations, bi, &neighbours, &runs);
            let outputs = runs.into_iter().map(|r| r.map(|r| r.output)).collect();
            (Some((c, same)), outputs, status)
        }
        _ => (None, Vec::new(), Vec::new()),
    };
    let recommended = best.filter(|&bi| beats_base(&evaluations[bi], base.as_ref()));
    Ok(DesignResult {
        asked: book.asked,
        run_now: book.run_now,
        evaluations,
        stop,
        best,
        recommended,
        least_violating,
        confirmation,
        base,
        base_runs,
        best_runs,
        sensitivity,
        constraints,
    })
}

impl DesignResult {
    /// The search's answer in one phrase: `improved` (a recommended design beats the base),
    /// `no improvement found` (the base design is feasible and nothing evaluated beats it),
    /// `infeasible` (no design evaluated, the base included, meets the constraints) or
    /// `interrupted`.
    pub fn answer(&self) -> &'static str {
        if self.recommended.is_some() {
            "improved"
        } else if self.stop == StopReason::Interrupted {
            "interrupted"
        } else if self.base.as_ref().is_some_and(|b| b.feasible()) {
            "no improvement found"
        } else {
            "infeasible"
        }
    }

    /// An error when the best design's confirmation run differs from its evaluation in the
    /// search (a journal row that does not reproduce: evaluated by another build or machine, or
    /// changed): then there is no best design to hand over (the CLI writes no `best-case.toml`
    /// and exits non-zero; Python raises).
    pub fn confirmation_error(&self, d: &Design) -> Option<String> {
        let (c, same) = self.confirmation.as_ref()?;
        if *same {
            return None;
        }
        let j = &self.evaluations[self.best?];
        Some(format!(
            "the best design (evaluation {}, {}) did not reproduce: run again it gives objective {:?} and {:?}, the search's evaluation {:?} and {:?} (columns {}); its journal row was not made by this build on this machine, or was changed. No best design is handed over: run the search afresh (--fresh)",
            j.index,
            d.spec
                .variables
                .iter()
                .zip(&j.x)
                .map(|(v, x)| format!("{} = {x}", v.path))
                .collect::<Vec<_>>()
                .join(", "),
            c.objective,
            c.values,
            j.objective,
            j.values,
            d.needs.iter().map(|n| n.label()).collect::<Vec<_>>().join(", ")
        ))
    }

    /// The answer as every front end writes it (the CLI's design.json, Python's
    /// `pcsim.design(...)`).
    pub fn record(&self, d: &Design) -> DesignRecord {
        let best = self.best.map(|i| &self.evaluations[i]);
        let at = |i: Option<usize>| i.map(|i| self.evaluations[i].clone());
        DesignRecord {
            answer: self.answer().into(),
            fingerprint: d.fingerprint().to_string(),
            method: d.spec.budget.method.name().into(),
            seed: d.spec.budget.seed,
            evaluations_asked: self.asked,
            stop: self.stop,
            variables: (d.spec.variables.iter())
                .map(|v| VariableRecord {
                    path: v.path.clone(),
                    min: v.min,
                    max: v.max,
                    integer: v.integer,
                })
                .collect(),
            speeds_kmh: d.spec.speeds.iter().map(|s| s.kmh).collect(),
            columns: d.needs.iter().map(|n| n.label()).collect(),
            feasible: best.is_some() || self.base.as_ref().is_some_and(Evaluation::feasible),
            best: at(self.recommended),
            best_evaluated: best.cloned(),
            least_violating: at(self.least_violating),
            base: self.base.clone(),
            confirmation: (self.confirmation.as_ref()).map(|(e, same)| Confirmation {
                evaluation: e.clone(),
                same_as_search: *same,
            }),
            sensitivity: self.sensitivity.clone(),
            constraints: self.constraints.clone(),
        }
    }

    /// [`Self::record`] as JSON, its keys sorted (the bytes design.json has always had).
    pub fn to_json(&self, d: &Design) -> serde_json::Value {
        serde_json::to_value(self.record(d)).expect("a design record is JSON")
    }
}

/// Each constraint (and acceptance row with a verdict, from the confirmation `runs`) at the best
/// design: value, limit, margin, and whether a design one sensitivity step away violates it.
fn constraint_status(
    design: &Design,
    evaluations: &[Evaluation],
    best: usize,
    neighbours: &[Option<usize>],
    runs: &[Option<SpeedRun>],
) -> Vec<ConstraintStatus> {
    let e = &evaluations[best];
    let near: Vec<&Evaluation> = neighbours
        .iter()
        .flatten()
        .map(|&i| &evaluations[i])
        .collect();
    let active = |name: &String| near.iter().any(|x| x.violated.contains(name));
    let mut out = Vec::new();
    for (s, sp) in design.spec.speeds.iter().enumerate() {
        for c in design
            .spec
            .constraints
            .iter()
            .filter(|c| c.applies_at(sp.kmh))
        {
            let name = format!("{}@{}", c.label(), sp.kmh);
            for (limit, high) in c.limits() {
                let n = Need::of_limit(c, high);
                let k = design.needs.iter().position(|m| *m == n).expect("need");
                let value = e.values[s][k];
                out.push(ConstraintStatus {
                    name: name.clone(),
                    value,
                    limit: Some(limit),
                    margin: value.map(|v| if high { limit - v } else { v - limit }),
                    active: active(&name),
                });
            }
        }
        for a in runs
            .get(s)
            .into_iter()
            .flatten()
            .flat_map(|r| &r.acceptance)
        {
            let name = format!("{}@{}", a.name, sp.kmh);
            out.push(ConstraintStatus {
                active: active(&name),
                name,
                value: a.value,
                limit: a.limit,
                margin: a.margin,
            });
        }
    }
    out
}
