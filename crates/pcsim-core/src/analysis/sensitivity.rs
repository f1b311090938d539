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

use crate::analysis::record::{simulate, RunOutput};
use crate::analysis::report::run_errors;
use crate::analysis::verify::{statistic, STATISTICS};
use crate::compile::budget::Budget;
use crate::compile::Setup;
use crate::error::CaseError;
use crate::input::case::{Case, RangedValue};
use crate::input::overrides::{with_overrides, OverrideValue};
use crate::model::wind_field::SplitMix64;

/// The largest seeded sample a study draws (each sample is a run of the whole case).
pub const MAX_SAMPLES: usize = 1000;

/// What the study varies and how: the sample's size and seed (`Default`: 8 runs, seed 1).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub struct SensitivitySpec {
    /// Runs with every ranged value drawn at once (0: one at a time only).
    pub samples: usize,
    /// The sample's seed.
    pub seed: u64,
}

impl Default for SensitivitySpec {
    fn default() -> Self {
        Self {
            samples: 8,
            seed: 1,
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
        Ok(())
    }
}

/// One run of the study: which values it set.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct StudyRun {
    /// `low`/`high` of one value (its path), or `sample k`.
    pub label: String,
    /// The values set, `(path, value)`.
    pub values: Vec<(String, f64)>,
}

/// How much one ranged value moves one statistic (one at a time).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Mover {
    /// The value's path.
    pub path: String,
    /// The statistic with the value at its low end.
    pub at_low: f64,
    /// The statistic with the value at its high end.
    pub at_high: f64,
    /// `at_high − at_low`.
    pub swing: f64,
}

/// One statistic's band.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct PantographBands {
    /// Its name.
    pub name: String,
    /// Its statistics, in [`STATISTICS`]' order.
    pub statistics: Vec<StatisticBand>,
}

/// The study (`summary.json`'s `sensitivity`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
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
    /// Per pantograph that crossed the analysis section in the case's own run.
    pub pantographs: Vec<PantographBands>,
}

impl Sensitivity {
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
            .map(|p| (p.path.clone(), p.low + (p.high - p.low) * rng.uniform()))
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
/// the paths a flag set (not varied). The runs share `jobs` threads; the answer does not depend
/// on them.
pub fn sensitivity(
    case: &Case,
    out: &RunOutput,
    ranges: &[RangedValue],
    fixed: &[String],
    spec: &SensitivitySpec,
    budget: &Budget,
    jobs: Option<usize>,
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
    let runs = study_runs(&parameters, spec);
    let outputs = crate::analysis::sweep::parallel_map(&runs, jobs, |r| {
        let c = run_case(case, r).map_err(|e| e.to_string())?;
        let setup = Setup::from_case_with(&c, budget).map_err(|e| e.to_string())?;
        simulate(&setup, &mut |_| true).map_err(|e| e.to_string())
    });
    let mut failed = Vec::new();
    let mut events = Vec::new();
    for (r, o) in runs.iter().zip(&outputs) {
        match o {
            Err(e) => failed.push(format!("{}: {e}", r.label)),
            Ok(o) => events.extend(
                run_errors(o)
                    .into_iter()
                    .map(|e| format!("{}: {}", r.label, e.message)),
            ),
        }
    }
    let pantographs = bands(out, &parameters, &outputs);
    Ok(Sensitivity {
        spec: *spec,
        parameters,
        not_varied,
        runs,
        failed,
        events,
        pantographs,
    })
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
        let statistics = STATISTICS
            .iter()
            .map(|(name, unit)| {
                let at = |k: usize| {
                    all[k]
                        .as_ref()
                        .and_then(|s| statistic(s, name))
                        .filter(|x| x.is_finite())
                };
                let value = statistic(s, name).expect("listed");
                let (mut low, mut high) = (value, value);
                for x in (0..all.len()).filter_map(at) {
                    low = low.min(x);
                    high = high.max(x);
                }
                let mut movers: Vec<Mover> = parameters
                    .iter()
                    .enumerate()
                    .filter_map(|(j, q)| {
                        let (a, b) = (at(2 * j)?, at(2 * j + 1)?);
                        Some(Mover {
                            path: q.path.clone(),
                            at_low: a,
                            at_high: b,
                            swing: b - a,
                        })
                    })
                    .collect();
                movers.sort_by(|a, b| {
                    b.swing
                        .abs()
                        .total_cmp(&a.swing.abs())
                        .then_with(|| a.path.cmp(&b.path))
                });
                StatisticBand {
                    statistic: (*name).into(),
                    unit: (*unit).into(),
                    value,
                    low,
                    high,
                    movers,
                }
            })
            .collect();
        pantographs.push(PantographBands {
            name: p.name.clone(),
            statistics,
        });
    }
    pantographs
}
