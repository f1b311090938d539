//! Monte Carlo studies (issue 13): realisations of a case whose random inputs (irregularity,
//! turbulence) take seeds offset by 0, 1, …, N−1, run in parallel on the sweep engine, and the
//! spread of their results. Each realisation runs single-threaded and deterministically, so the
//! study gives the same bytes with any number of jobs.

use serde::Serialize;

use crate::analysis::record::{simulate, RunOutput};
use crate::analysis::sweep::parallel_map;
use crate::compile::{Budget, Setup};
use crate::error::SimError;
use crate::input::case::Case;

/// Mean, standard deviation (N − 1) and a 95 % confidence interval of the mean (Student's t).
/// With one realisation the spread is undefined (`None`, `null` in JSON), never 0.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
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
