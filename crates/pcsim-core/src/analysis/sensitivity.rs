//! A run's model uncertainty from the case's own marks (issue 42, item 2: `pcsim run
//! --sensitivity`). A value of the case may carry a range (`{ value, source, range = [low,
//! high], range_source }`, [`RangedValue`]); the study runs the case with each ranged value at
//! its low and at its high end, the others at the case's values (one at a time), and a seeded
//! sample of runs with every ranged value drawn uniformly from its range at once. Each EN 50318
//! statistic gets its band (the smallest and largest value over the case's own run and every run
//! of the study) and the values that move it most (the change from a value's low end to its high
//! end, largest first).
//!
//! A run that cannot be made (a value at its end that the case's checks refuse, a time step
//! the stiffer model cannot take) is not left out silently: it is listed in `failed` with its
//! reason and the bands say over how many runs they were taken. A run with an error-level event
//! (dewirement, contact loss over the limit) keeps its statistics in the band and is listed in
//! `events`: its statistics mix contact with flight.

use serde::{Deserialize, Serialize};

use crate::analysis::events::{run_errors, AllowedErrors};
use crate::analysis::record::{simulate, RunOutput};
use crate::analysis::verify::{statistic, VERDICT_STATISTICS};
use crate::compile::budget::Budget;
use crate::compile::Setup;
use crate::error::CaseError;
use crate::input::case::{Case, RangedValue};
use crate::input::overrides::{with_overrides, OverrideValue};
use crate::model::wind_field::SplitMix64;

/// The largest seeded sample a study draws (each sample is a run of the whole case).
pub const MAX_SAMPLES: usize = 1000;

/// What the study varies and how (`Default`: 8 sampled runs, seed 1, at most 200 runs, no
/// failed run accepted).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct SensitivitySpec {
    /// Runs with every ranged value drawn at once (0: one at a time only).
    pub samples: usize,
    /// The sample's seed.
    pub seed: u64,
    /// The most runs the study may make (two per ranged value, then the sample): a bound on its
    /// work, checked before any run.
    #[serde(default = "default_max_runs")]
    pub max_runs: usize,
    /// Accept runs that could not be made (then the bands are taken over fewer runs, said);
    /// without it such a study is a failure.
    #[serde(default)]
    pub allow_failed_runs: bool,
}

fn default_max_runs() -> usize {
    SensitivitySpec::default().max_runs
}

impl Default for SensitivitySpec {
    fn default() -> Self {
        Self {
            samples: 8,
            seed: 1,
            max_runs: 200,
            allow_failed_runs: false,
        }
    }
}

impl SensitivitySpec {
    /// Refuse a spec the study cannot honour, by its field.
    pub fn check(&self) -> Result<(), CaseError> {
        if self.samples > MAX_SAMPLES {
            return Err(crate::input::bounds::inv(
                "sensitivity.samples",
                self.samples,
                &format!("at most {MAX_SAMPLES} (each sample is a run of the whole case)"),
            ));
        }
        if self.max_runs == 0 {
            return Err(crate::input::bounds::inv(
                "sensitivity.max_runs",
                self.max_runs,
                "at least 1",
            ));
        }
        Ok(())
    }

    /// The runs a study of `n` ranged values makes: two per value, then the sample.
    pub fn runs_for(&self, n: usize) -> usize {
        2 * n + self.samples
    }
}

/// One run of the study: which values it set.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct StudyRun {
    /// `low`/`high` of one value (its path), or `sample k`.
    pub label: String,
    /// The values set, `(path, value)`.
    pub values: Vec<(String, f64)>,
}

/// How much one ranged value moves one statistic (one at a time).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Mover {
    /// The value's path.
    pub path: String,
    /// The statistic with the value at its low end (none: that run was not made).
    pub at_low: Option<f64>,
    /// The statistic with the value at its high end (none: that run was not made).
    pub at_high: Option<f64>,
    /// `at_high − at_low` (none: an end is missing).
    pub swing: Option<f64>,
    /// How far the statistic moved from the case's value, the larger of the two ends: what the
    /// ranking sorts by when an end is missing (a missing end never drops a value from it).
    pub moved: f64,
}

impl Mover {
    /// Its rank's key: `|swing|` with both ends, else the one end's move from the case's value.
    fn key(&self) -> f64 {
        self.swing.map_or(self.moved, f64::abs)
    }
}

/// One statistic's band.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct StatisticBand {
    /// Its name (as in `summary.json`'s `stats`).
    pub statistic: String,
    /// Its unit.
    pub unit: String,
    /// The case's own value.
    pub value: f64,
    /// The smallest value over the case's run and the study's runs.
    pub low: f64,
    /// The largest.
    pub high: f64,
    /// The ranged values by how much they move it, the largest `|swing|` first.
    pub movers: Vec<Mover>,
}

/// One pantograph's bands.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct PantographBands {
    /// Its name.
    pub name: String,
    /// Its statistics, in [`VERDICT_STATISTICS`]' order (those its own run has a value of).
    pub statistics: Vec<StatisticBand>,
}

/// The study (`summary.json`'s `sensitivity`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Sensitivity {
    /// The spec (the sample's size and seed).
    pub spec: SensitivitySpec,
    /// The ranged values varied.
    pub parameters: Vec<RangedValue>,
    /// Ranged values not varied, with the reason (a flag set them).
    pub not_varied: Vec<String>,
    /// Every run of the study, in order: each value low then high, then the sample.
    pub runs: Vec<StudyRun>,
    /// Runs that could not be made, with the reason.
    pub failed: Vec<String>,
    /// Runs with an error-level event, with the event.
    pub events: Vec<String>,
    /// What makes the study a failure (the failed runs unless `spec.allow_failed_runs`, the
    /// events the user did not accept): empty for a study a front end may report with exit 0.
    #[serde(default)]
    pub failures: Vec<String>,
    /// Per pantograph that crossed the analysis section in the case's own run.
    pub pantographs: Vec<PantographBands>,
}

impl Sensitivity {
    /// An error when the study produced less than it was asked ([`Sensitivity::failures`]):
    /// the count, the first reason and the flags that accept them. Every front end refuses
    /// such a study with it (after writing its outputs).
    pub fn check(&self) -> Result<(), CaseError> {
        let Some(first) = self.failures.first() else {
            return Ok(());
        };
        Err(crate::input::bounds::inv(
            "sensitivity",
            format!("{} of {} runs", self.failures.len(), self.runs.len()),
            &format!(
                "not made or with an event not accepted; the first: {first}. Accept runs that could not be made with --allow-failed-runs (Python: allow_failed_runs=True), events with their --allow flag"
            ),
        ))
    }

    /// The band of pantograph `name`'s statistic `statistic`.
    pub fn band(&self, pantograph: &str, statistic: &str) -> Option<&StatisticBand> {
        self.pantographs
            .iter()
            .find(|p| p.name == pantograph)?
            .statistics
            .iter()
            .find(|s| s.statistic == statistic)
    }
}

/// The study's runs: each parameter at its low then its high end, the others at the case's
/// values; then `spec.samples` runs with every parameter drawn uniformly in its range from a
/// SplitMix64 stream seeded with `spec.seed` (run-major, parameters in their order).
pub fn study_runs(parameters: &[RangedValue], spec: &SensitivitySpec) -> Vec<StudyRun> {
    let mut runs = Vec::new();
    for p in parameters {
        for (end, x) in [("low", p.low), ("high", p.high)] {
            runs.push(StudyRun {
                label: format!("{} {end}", p.path),
                values: vec![(p.path.clone(), x)],
            });
        }
    }
    let mut rng = SplitMix64::new(spec.seed);
    for k in 0..spec.samples {
        let values = parameters
            .iter()
            .map(|p| {
                let u = rng.uniform();
                let x = if p.integer {
                    // Whole numbers from low to high, each equally likely.
                    (p.low + ((p.high - p.low + 1.0) * u).floor()).min(p.high)
                } else {
                    p.low + (p.high - p.low) * u
                };
                (p.path.clone(), x)
            })
            .collect();
        runs.push(StudyRun {
            label: format!("sample {k}"),
            values,
        });
    }
    runs
}

/// The case of one study run: `case` with the run's values set (checked as any case is).
pub fn run_case(case: &Case, run: &StudyRun) -> Result<Case, CaseError> {
    let overrides: Vec<(String, OverrideValue)> = run
        .values
        .iter()
        .map(|(p, x)| (p.clone(), OverrideValue::Number(*x)))
        .collect();
    with_overrides(case, &overrides)
}

/// The study of `case`, whose own run gave `out`: `ranges` are the case's ranged values, `fixed`
/// the paths a flag set (not varied), `allowed` the error-level events the user accepts. Before
/// any run: the spec, each value within its range, the number of runs against
/// `spec.max_runs`, and the case at every range end built (a time step the stiffer end cannot
/// take is refused then, naming the end). The runs share `jobs` threads (the answer does not
/// depend on them); `progress(done, total)` is called as each ends.
#[allow(clippy::too_many_arguments)]
pub fn sensitivity(
    case: &Case,
    out: &RunOutput,
    ranges: &[RangedValue],
    fixed: &[String],
    spec: &SensitivitySpec,
    allowed: AllowedErrors,
    budget: &Budget,
    jobs: Option<usize>,
    progress: &(dyn Fn(usize, usize) + Sync),
) -> Result<Sensitivity, CaseError> {
    spec.check()?;
    for r in ranges {
        r.check()?;
    }
    let (parameters, not_varied): (Vec<RangedValue>, Vec<RangedValue>) = ranges
        .iter()
        .cloned()
        .partition(|r| !fixed.contains(&r.path));
    let not_varied = not_varied
        .iter()
        .map(|r| format!("{}: set by a flag, not varied", r.path))
        .collect();
    if parameters.is_empty() {
        return Err(crate::input::bounds::inv(
            "sensitivity",
            "no ranged value",
            "the case gives no value a range to vary: mark one as `{ value = …, source = \"…\", range = [low, high], range_source = \"why\" }`",
        ));
    }
    let n_runs = spec.runs_for(parameters.len());
    if n_runs > spec.max_runs {
        return Err(crate::input::bounds::inv(
            "sensitivity.max_runs",
            spec.max_runs,
            &format!(
                "the study would make {n_runs} runs ({} ranged values at both ends, {} sampled), each a run of the whole case: raise the bound (--sensitivity-max-runs) or range fewer values",
                parameters.len(),
                spec.samples
            ),
        ));
    }
    let runs = study_runs(&parameters, spec);
    preflight(case, &runs[..2 * parameters.len()], budget, jobs)?;
    let done = std::sync::atomic::AtomicUsize::new(0);
    let outputs = crate::analysis::sweep::parallel_map(&runs, jobs, |r| {
        let o = (|| {
            let c = run_case(case, r).map_err(|e| e.to_string())?;
            let setup = Setup::from_case_with(&c, budget).map_err(|e| e.to_string())?;
            simulate(&setup, &mut |_| true).map_err(|e| e.to_string())
        })();
        progress(
            done.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1,
            runs.len(),
        );
        o
    });
    Ok(assemble(
        out, parameters, not_varied, runs, &outputs, spec, allowed,
    ))
}

/// The study from its runs' `outputs` (in [`study_runs`]' order): the runs not made and the
/// events, what makes it a failure, and each pantograph's bands.
#[doc(hidden)] // public for the unit tests in tests/suite/unit
pub fn assemble(
    out: &RunOutput,
    parameters: Vec<RangedValue>,
    not_varied: Vec<String>,
    runs: Vec<StudyRun>,
    outputs: &[Result<RunOutput, String>],
    spec: &SensitivitySpec,
    allowed: AllowedErrors,
) -> Sensitivity {
    let mut failed = Vec::new();
    let mut events = Vec::new();
    let mut failures = Vec::new();
    for (r, o) in runs.iter().zip(outputs) {
        match o {
            Err(e) => {
                failed.push(format!("{}: {e}", r.label));
                if !spec.allow_failed_runs {
                    failures.push(format!("{}: not made: {e}", r.label));
                }
            }
            Ok(o) => {
                for e in run_errors(o) {
                    let m = format!("{}: {}", r.label, e.message);
                    if !allowed.allows(e.kind) {
                        failures.push(m.clone());
                    }
                    events.push(m);
                }
            }
        }
    }
    let pantographs = bands(out, &parameters, outputs);
    Sensitivity {
        spec: *spec,
        parameters,
        not_varied,
        runs,
        failed,
        events,
        failures,
        pantographs,
    }
}

/// The case at every range end built before any run (statics, the time step against the
/// coupled system's limit): an end that cannot run is refused by its range, not found after
/// the others have run.
fn preflight(
    case: &Case,
    ends: &[StudyRun],
    budget: &Budget,
    jobs: Option<usize>,
) -> Result<(), CaseError> {
    let checks = crate::analysis::sweep::parallel_map(ends, jobs, |r| {
        run_case(case, r)
            .and_then(|c| Setup::from_case_with(&c, budget).map(drop))
            .err()
    });
    match ends.iter().zip(checks).find_map(|(r, e)| e.map(|e| (r, e))) {
        None => Ok(()),
        Some((r, e)) => {
            let (path, x) = &r.values[0];
            Err(crate::input::bounds::inv(
                &format!("{path}.range"),
                x,
                &format!(
                    "the case cannot run at this end ({}): {e}",
                    r.label.rsplit(' ').next().unwrap_or("")
                ),
            ))
        }
    }
}

/// Each pantograph's bands over the case's run `out` and the study's `outputs` (in
/// [`study_runs`]' order).
fn bands(
    out: &RunOutput,
    parameters: &[RangedValue],
    outputs: &[Result<RunOutput, String>],
) -> Vec<PantographBands> {
    let stats_of = |o: &Result<RunOutput, String>, i: usize| {
        o.as_ref()
            .ok()
            .and_then(|o| o.pantographs.get(i))
            .and_then(|p| p.stats)
    };
    let mut pantographs = Vec::new();
    for (i, p) in out.pantographs.iter().enumerate() {
        let Some(s) = &p.stats else { continue };
        let all: Vec<_> = outputs.iter().map(|o| stats_of(o, i)).collect();
        let statistics = VERDICT_STATISTICS
            .iter()
            .filter_map(|(name, unit)| {
                let at = |k: usize| {
                    all[k]
                        .as_ref()
                        .and_then(|s| statistic(s, name))
                        .filter(|x| x.is_finite())
                };
                let value = statistic(s, name)?;
                let (mut low, mut high) = (value, value);
                for x in (0..all.len()).filter_map(at) {
                    low = low.min(x);
                    high = high.max(x);
                }
                let mut movers: Vec<Mover> = parameters
                    .iter()
                    .enumerate()
                    .filter_map(|(j, q)| {
                        let (a, b) = (at(2 * j), at(2 * j + 1));
                        let moved = [a, b]
                            .iter()
                            .flatten()
                            .map(|x| (x - value).abs())
                            .reduce(f64::max)?;
                        Some(Mover {
                            path: q.path.clone(),
                            at_low: a,
                            at_high: b,
                            swing: a.zip(b).map(|(a, b)| b - a),
                            moved,
                        })
                    })
                    .collect();
                movers.sort_by(|a, b| {
                    b.key()
                        .total_cmp(&a.key())
                        .then_with(|| a.path.cmp(&b.path))
                });
                Some(StatisticBand {
                    statistic: (*name).into(),
                    unit: (*unit).into(),
                    value,
                    low,
                    high,
                    movers,
                })
            })
            .collect();
        pantographs.push(PantographBands {
            name: p.name.clone(),
            statistics,
        });
    }
    pantographs
}
