//! Monte Carlo studies (issue 13): realisations of a case whose random inputs (irregularity,
//! turbulence) take seeds offset by 0, 1, …, N−1, run in parallel on the sweep engine, and the
//! spread of their results. Each realisation runs single-threaded and deterministically, so the
//! study gives the same bytes with any number of jobs.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::{Deserialize, Serialize};

use crate::analysis::events::{count_events, run_errors, EventCount, RunError};
use crate::analysis::record::{simulate, RunOutput};
use crate::analysis::sweep::parallel_map;
use crate::compile::{Budget, Setup};
use crate::error::{CaseError, SimError};
use crate::input::case::Case;
use crate::model::irregularity::IrregularityReport;
use crate::model::wind::WindReport;
use crate::study::{Answer, Study, StudyFile, StudyKind};

/// Mean, standard deviation (N − 1) and a 95 % confidence interval of the mean (Student's t).
/// With one realisation the spread is undefined (`None`, `null` in JSON), never 0.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Spread {
    /// Number of realisations.
    pub n: usize,
    /// Mean over the realisations.
    pub mean: f64,
    /// Standard deviation (N − 1); `None` (undefined) for one realisation.
    pub std: Option<f64>,
    /// Lower end of the 95 % confidence interval of the mean; `None` for one realisation.
    pub ci95_low: Option<f64>,
    /// Upper end of the 95 % confidence interval of the mean; `None` for one realisation.
    pub ci95_high: Option<f64>,
    /// Smallest value.
    pub min: f64,
    /// Largest value.
    pub max: f64,
}

/// Two-sided 95 % quantile of Student's t with `dof` degrees of freedom (table to 30, then the
/// usual `1.96 + 2.4/dof` approximation, within 0.2 % of the exact value).
pub fn t95(dof: usize) -> f64 {
    const T: [f64; 30] = [
        12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160,
        2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056,
        2.052, 2.048, 2.045, 2.042,
    ];
    match dof {
        0 => f64::NAN,
        d if d <= 30 => T[d - 1],
        d => 1.96 + 2.4 / d as f64,
    }
}

impl Spread {
    /// The spread of `values` (finite values only; `None` when there are none).
    pub fn of(values: &[f64]) -> Option<Spread> {
        let v: Vec<f64> = values.iter().copied().filter(|x| x.is_finite()).collect();
        let n = v.len();
        if n == 0 {
            return None;
        }
        let mean = v.iter().sum::<f64>() / n as f64;
        let std = (n > 1)
            .then(|| (v.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / (n - 1) as f64).sqrt());
        let half = std.map(|s| t95(n - 1) * s / (n as f64).sqrt());
        Some(Spread {
            n,
            mean,
            std,
            ci95_low: half.map(|h| mean - h),
            ci95_high: half.map(|h| mean + h),
            min: v.iter().copied().fold(f64::INFINITY, f64::min),
            max: v.iter().copied().fold(f64::NEG_INFINITY, f64::max),
        })
    }
}

/// One realisation: its seed offset and its run.
#[derive(Debug, Clone, PartialEq)]
pub struct Realisation {
    /// Seed offset added to every seed of the case's random inputs.
    pub seed_offset: u64,
    /// The realisation's run.
    pub output: RunOutput,
}

/// Run realisations `0..n` of `case` on up to `jobs` threads, each within `budget`.
pub fn monte_carlo(
    case: &Case,
    n: usize,
    jobs: Option<usize>,
    budget: &Budget,
    on_done: &(dyn Fn() + Sync),
) -> Result<Vec<Realisation>, SimError> {
    let ks: Vec<u64> = (0..n as u64).collect();
    parallel_map(&ks, jobs, |&k| {
        let c = case.with_seed_offset(k);
        let setup = Setup::from_case_with(&c, budget)?;
        let output = simulate(&setup, &mut |_| true)?;
        on_done();
        Ok(Realisation {
            seed_offset: k,
            output,
        })
    })
    .into_iter()
    .collect()
}

/// The statistics a Monte Carlo summary reports per pantograph, by name (with
/// [`LATERAL_STATS`] where the lateral motion is modelled: [`statistics_of`]).
pub const MC_STATS: [&str; 6] = [
    "mean_n",
    "std_n",
    "actual_max_n",
    "actual_min_n",
    "loss_of_contact_percent",
    "max_uplift_at_support_mm",
];

/// The lateral statistics that decide a dewirement's verdict: the contact point's largest offset,
/// the head's smallest margin and the contact wire's largest blow-out (issue 51: a study in wind
/// reports them beside the vertical ones).
pub const LATERAL_STATS: [&str; 3] = [
    "max_lateral_offset_mm",
    "min_head_margin_mm",
    "max_contact_wire_blowout_mm",
];

/// The statistics a study of `runs` reports: [`MC_STATS`], then each of [`LATERAL_STATS`] that
/// some run has a value of.
pub fn statistics_of<'a>(
    runs: impl IntoIterator<Item = &'a RunOutput> + Clone,
) -> Vec<&'static str> {
    let has = |name: &str| {
        runs.clone().into_iter().any(|o| {
            (o.pantographs.iter())
                .filter_map(|p| p.stats.as_ref())
                .any(|s| crate::analysis::verify::statistic(s, name).is_some())
        })
    };
    MC_STATS
        .iter()
        .copied()
        .chain(LATERAL_STATS.iter().copied().filter(|n| has(n)))
        .collect()
}

/// The value of statistic `name` of pantograph `p` of a run (NaN when the pantograph did not
/// cross the analysis section, or the run has no value of it): the one lookup,
/// [`crate::analysis::verify::statistic`].
pub fn stat_of(out: &RunOutput, p: usize, name: &str) -> f64 {
    out.pantographs
        .get(p)
        .and_then(|t| t.stats.as_ref())
        .and_then(|s| crate::analysis::verify::statistic(s, name))
        .unwrap_or(f64::NAN)
}

/// The Monte Carlo study of one case (`pcsim run --seeds N`, Python's `run_seeds`): its spec
/// (the realisations and the events accepted), the case, and where it runs.
#[derive(Debug, Clone)]
pub struct MonteCarloStudy {
    /// The case (its random inputs' seeds are offset by 0..n).
    pub case: Case,
    /// The realisations and the error-level events accepted.
    pub spec: crate::study::specs::MonteCarloSpec,
    /// The flags that overrode the case's values, as given (written with the output).
    pub overrides: Vec<String>,
    /// Each run's limits.
    pub budget: Budget,
    /// Worker threads (`None`: every core); the output does not depend on them.
    pub jobs: Option<usize>,
}

/// One realisation in the output: its seed offset, the seeds it took, the irregularity's
/// achieved RMS, its error-level events and each pantograph's statistics (by
/// [`MonteCarloOutput::statistics_names`], NaN where it has none).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RealisationRow {
    /// Seed offset.
    pub seed_offset: u64,
    /// The seeds of its random inputs (`irregularity[0]=7`, `wind=…`).
    pub seeds: Vec<String>,
    /// The irregularity's achieved RMS over its sources, m.
    pub irregularity_rms_m: f64,
    /// Its error-level events' kinds.
    pub errors: Vec<String>,
    /// Per pantograph, per statistic: the value (`None`: none).
    pub values: Vec<Vec<Option<f64>>>,
}

/// What a Monte Carlo study gives (`montecarlo.json`, with the rows of `montecarlo.csv`),
/// written and read back through this type.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct MonteCarloOutput {
    /// The case's name.
    pub case_name: String,
    /// Error-level events over the realisations, counted per kind.
    pub errors: Vec<EventCount>,
    /// The first realisation's irregularity sources.
    pub irregularity: Vec<IrregularityReport>,
    /// What the spreads are.
    pub note: String,
    /// The flags that overrode the case's values.
    pub overrides: Vec<String>,
    /// Number of realisations.
    pub realisations: usize,
    /// The first and last seed offset.
    pub seed_offsets: [usize; 2],
    /// Train speed, km/h.
    pub speed_kmh: f64,
    /// Per pantograph, per statistic: its spread over the realisations.
    pub statistics: BTreeMap<String, BTreeMap<String, Option<Spread>>>,
    /// The first realisation's wind.
    pub wind: Option<WindReport>,
    /// The pantographs, in the case's order (montecarlo.csv's column groups).
    #[serde(skip)]
    pub pantographs: Vec<String>,
    /// The statistics of montecarlo.csv's columns, in order.
    #[serde(skip)]
    pub statistics_names: Vec<String>,
    /// The realisations (montecarlo.csv).
    #[serde(skip)]
    pub rows: Vec<RealisationRow>,
}

/// The note montecarlo.json carries.
const NOTE: &str = "spread over the realisations: mean, standard deviation (N-1), 95 % confidence interval of the mean (Student's t), min, max";

impl MonteCarloStudy {
    /// The row of realisation `r` (its events `events`) with the statistics `names`.
    fn row(&self, r: &Realisation, events: &[RunError], names: &[&str]) -> RealisationRow {
        let c = self.case.with_seed_offset(r.seed_offset);
        let mut seeds: Vec<String> = (c.irregularity.iter().enumerate())
            .filter_map(|(i, ir)| ir.seed().map(|s| format!("irregularity[{i}]={s}")))
            .collect();
        if let Some(w) = &c.wind {
            seeds.push(format!("wind={}", w.seed));
        }
        if c.run.perturb_uplift_rel != 0.0 {
            seeds.push(format!("perturb={}", c.run.perturb_seed));
        }
        let rms = (r.output.irregularity.iter())
            .map(|x| x.rms_achieved_m.powi(2))
            .sum::<f64>()
            .sqrt();
        let values = (0..r.output.pantographs.len())
            .map(|p| {
                (names.iter())
                    .map(|s| Some(stat_of(&r.output, p, s)).filter(|v| v.is_finite()))
                    .collect()
            })
            .collect();
        RealisationRow {
            seed_offset: r.seed_offset,
            seeds,
            irregularity_rms_m: rms,
            errors: events.iter().map(|e| e.kind.name().to_string()).collect(),
            values,
        }
    }
}

impl Study for MonteCarloStudy {
    const KIND: StudyKind = StudyKind::MonteCarlo;
    type Output = MonteCarloOutput;

    fn check(&self) -> Result<(), CaseError> {
        self.spec.check(&self.case).map(drop)
    }

    fn work(&self) -> usize {
        self.spec.realisations
    }

    fn run(&self, done: &(dyn Fn() + Sync)) -> Result<MonteCarloOutput, SimError> {
        let n = self.spec.check(&self.case)?;
        let real = monte_carlo(&self.case, n, self.jobs, &self.budget, done)?;
        let per_run: Vec<Vec<RunError>> = real.iter().map(|r| run_errors(&r.output)).collect();
        let names = statistics_of(real.iter().map(|r| &r.output));
        let pantographs: Vec<String> = (real[0].output.pantographs.iter())
            .map(|p| p.name.clone())
            .collect();
        let mut statistics = BTreeMap::new();
        for (p, nm) in pantographs.iter().enumerate() {
            let m = (names.iter())
                .map(|s| {
                    let v: Vec<f64> = real.iter().map(|r| stat_of(&r.output, p, s)).collect();
                    (s.to_string(), Spread::of(&v))
                })
                .collect();
            statistics.insert(nm.clone(), m);
        }
        Ok(MonteCarloOutput {
            case_name: crate::analysis::report::case_name(&self.case),
            errors: count_events(&per_run, self.spec.allowed),
            irregularity: real[0].output.irregularity.clone(),
            note: NOTE.into(),
            overrides: self.overrides.clone(),
            realisations: n,
            seed_offsets: [0, n - 1],
            speed_kmh: self.case.run.speed_kmh,
            statistics,
            wind: real[0].output.wind.clone(),
            rows: (real.iter().zip(&per_run))
                .map(|(r, e)| self.row(r, e, &names))
                .collect(),
            pantographs,
            statistics_names: names.iter().map(|s| s.to_string()).collect(),
        })
    }

    fn files(&self, o: &MonteCarloOutput) -> Vec<StudyFile> {
        let mut csv = String::from("realisation,seed_offset,seeds,irregularity_rms_m,errors");
        for nm in &o.pantographs {
            for s in &o.statistics_names {
                let _ = write!(csv, ",{nm}_{s}");
            }
        }
        csv.push('\n');
        for r in &o.rows {
            let _ = write!(
                csv,
                "{},{},{},{:.6e},{}",
                r.seed_offset,
                r.seed_offset,
                r.seeds.join(" "),
                r.irregularity_rms_m,
                r.errors.join(" ")
            );
            for v in r.values.iter().flatten() {
                match v {
                    Some(v) => {
                        let _ = write!(csv, ",{v:.6}");
                    }
                    None => csv.push(','),
                }
            }
            csv.push('\n');
        }
        // Written through a JSON value: every object's keys in order, as before the contract.
        let json = serde_json::to_value(o)
            .and_then(|v| serde_json::to_string_pretty(&v))
            .unwrap_or_default();
        vec![
            StudyFile::text("montecarlo.csv", csv),
            StudyFile::text("montecarlo.json", json + "\n"),
        ]
    }

    fn answer(o: &MonteCarloOutput) -> Answer {
        let mut rows = Vec::new();
        // By the statistics' own keys: the answer of an output read back is the written one's.
        for (nm, stats) in &o.statistics {
            for s in [
                "std_n",
                "actual_min_n",
                "loss_of_contact_percent",
                "max_lateral_offset_mm",
                "max_contact_wire_blowout_mm",
            ] {
                let Some(sp) = stats.get(s).and_then(|x| *x) else {
                    continue;
                };
                let value = match (sp.std, sp.ci95_low, sp.ci95_high) {
                    (Some(sd), Some(lo), Some(hi)) => format!(
                        "mean {:8.3}  std {sd:7.3}  95 % CI [{lo:.3}, {hi:.3}]  range [{:.3}, {:.3}]",
                        sp.mean, sp.min, sp.max
                    ),
                    _ => format!(
                        "mean {:8.3}  std and 95 % CI undefined (one realisation)",
                        sp.mean
                    ),
                };
                rows.push((format!("{nm:<10} {s:<28}"), value));
            }
        }
        let n = o.realisations;
        let line = |e: &EventCount| event_line(e, n);
        Answer {
            headline: format!(
                "{}: {n} realisations at {} km/h, each statistic's mean with its 95 % interval",
                o.case_name, o.speed_kmh
            ),
            rows,
            warnings: (o.errors.iter())
                .filter(|e| e.allowed)
                .map(|e| format!("{} (allowed by {})", line(e), e.kind.flag()))
                .collect(),
            failures: (o.errors.iter())
                .filter(|e| !e.allowed)
                .map(|e| {
                    format!(
                        "{} (montecarlo.json's `errors`, montecarlo.csv's `errors` column): give {} to accept it",
                        line(e),
                        e.kind.flag()
                    )
                })
                .collect(),
        }
    }
}

/// How many realisations had one kind of event, with the first one's message.
pub fn event_line(e: &EventCount, n: usize) -> String {
    format!(
        "{} of {n} realisations: {} (the first, realisation {}: {})",
        e.runs.len(),
        e.kind.name().replace('_', " "),
        e.runs[0],
        e.first_message
    )
}
