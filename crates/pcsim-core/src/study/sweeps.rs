//! The sweeps of the studies, each one function with the resource budget, seeds and shards
//! (issue 18): the CLI, Python and the cluster recipes call these and only write their rows.
//!
//! - [`eva_sweep`]: EVA over a grid ([`EvaRow`] per case, with the case's [`EvaOutput`]);
//! - [`window_sweep`]: the accuracy-based window length over a grid ([`WindowRow`] per case, with
//!   the errors of every window tried and the energy curves);
//! - [`validation_runs`]: the runs of a validation plan, assembled into its report.

use crate::analysis::eva::{run_eva, simulate_with_eva, EvaOutput, EvaRow, EvaSettings};
use crate::analysis::record::{simulate, RunOutput};
use crate::analysis::sweep::{parallel_map, Job};
use crate::compile::Budget;
use crate::compile::Setup;
use crate::error::{CaseError, SimError};
use crate::study::validate::{ValidationPlan, ValidationReport};
use crate::study::window_search::{
    full_stats, search_windows, EnergyCurves, SearchResult, SearchSettings, Tolerances,
};

/// A sweep's error, with the case it belongs to.
fn in_case(index: usize, what: &str, e: impl std::fmt::Display) -> SimError {
    SimError::Case(CaseError::InCase {
        case: format!("case {index}{what}"),
        error: Box::new(CaseError::Parse(e.to_string())),
    })
}

/// One case of an EVA sweep.
#[derive(Debug, Clone)]
pub struct EvaCase {
    /// The grid point.
    pub job: Job,
    /// Energy distributions and EVA lengths of its run.
    pub output: EvaOutput,
    /// Its row of `eva.csv`.
    pub row: EvaRow,
}

/// EVA of every case of `jobs` (one shard of a grid, [`crate::study::specs::GridSpec::jobs`]) on up to `threads` threads
/// (`None`: every core), within `budget`; `done` is called after each case (progress). The rows
/// come in the order of `jobs`, the same bytes with any number of threads.
pub fn eva_sweep(
    jobs: &[Job],
    settings: &EvaSettings,
    budget: &Budget,
    threads: Option<usize>,
    done: &(dyn Fn() + Sync),
) -> Result<Vec<EvaCase>, SimError> {
    parallel_map(jobs, threads, |job| {
        crate::compile::require_contact(&job.case, "the EVA")
            .map_err(|e| in_case(job.index, "", e))?;
        let setup = Setup::from_case_with(&job.case, budget)?;
        let output =
            run_eva(&setup, settings, &mut |_| true).map_err(|e| in_case(job.index, "", e))?;
        let row = EvaRow {
            seed_offset: job.seed_offset,
            ..EvaRow::new(
                job.index,
                job.speed_kmh,
                job.tension_n / 1e3,
                &job.damping,
                &output,
            )
        };
        done();
        Ok(EvaCase {
            job: job.clone(),
            output,
            row,
        })
    })
    .into_iter()
    .collect()
}

/// One row of a window sweep (`window.csv`): the accuracy-based length beside the energy-based
/// EVA lengths.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct WindowRow {
    /// Case index in the grid.
    pub index: usize,
    /// Seed offset of the realisation.
    pub seed_offset: u64,
    /// Train speed, km/h.
    pub speed_kmh: f64,
    /// Contact-wire tension, kN.
    pub tension_kn: f64,
    /// Damping, as written in the grid.
    pub damping: String,
    /// The accuracy-based window length, m (`None`: not reached within the longest window).
    pub length_m: Option<f64>,
    /// The errors of that window against the full model, % (when no window matches, the
    /// longest window's: what fails, by how much).
    pub mean_err_pct: Option<f64>,
    /// Error of σ against the full model, %.
    pub sigma_err_pct: Option<f64>,
    /// Error of the maximum against the full model, %.
    pub max_err_pct: Option<f64>,
    /// Windows run by the search.
    pub windows_run: usize,
    /// EVA of the snapshot by the step criterion, m.
    pub eva_step_m: Option<f64>,
    /// EVA of the snapshot by the fraction criterion, m.
    pub eva_fraction_m: Option<f64>,
    /// EVA of the maximum by the step criterion, m.
    pub eva_step_max_m: Option<f64>,
    /// EVA of the maximum by the fraction criterion, m.
    pub eva_fraction_max_m: Option<f64>,
    /// EVA of the time average by the step criterion, m.
    pub eva_step_mean_m: Option<f64>,
    /// EVA of the time average by the fraction criterion, m.
    pub eva_fraction_mean_m: Option<f64>,
    /// The energies the fraction criteria refer to, J.
    pub snapshot_total_j: f64,
    /// Total energy of the maximum view, J.
    pub max_total_j: f64,
    /// Total energy of the time-average view, J.
    pub mean_total_j: f64,
    /// The claim's lattice: every window at the resolution from `length_m` up to this length
    /// was run and matches (above it, the coarse windows only; the longest window for a full
    /// scan), m.
    pub fine_checked_to_m: Option<f64>,
}

impl WindowRow {
    /// The header of `window.csv`.
    pub const HEADER: &'static str = "index,seed_offset,speed_kmh,tension_kn,damping,length_m,mean_err_pct,sigma_err_pct,max_err_pct,windows_run,eva_step_m,eva_fraction_m,eva_step_max_m,eva_fraction_max_m,eva_step_mean_m,eva_fraction_mean_m,snapshot_total_j,max_total_j,mean_total_j,fine_checked_to_m";

    /// The row in `window.csv`'s form (an empty cell for `None`).
    pub fn to_csv(&self) -> String {
        let opt = |v: Option<f64>| v.map(|x| format!("{x:.3}")).unwrap_or_default();
        format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{},{:.9e},{:.9e},{:.9e},{}",
            self.index,
            self.seed_offset,
            self.speed_kmh,
            self.tension_kn,
            self.damping,
            opt(self.length_m),
            opt(self.mean_err_pct),
            opt(self.sigma_err_pct),
            opt(self.max_err_pct),
            self.windows_run,
            opt(self.eva_step_m),
            opt(self.eva_fraction_m),
            opt(self.eva_step_max_m),
            opt(self.eva_fraction_max_m),
            opt(self.eva_step_mean_m),
            opt(self.eva_fraction_mean_m),
            self.snapshot_total_j,
            self.max_total_j,
            self.mean_total_j,
            opt(self.fine_checked_to_m)
        )
    }
}

/// One case of a window sweep.
#[derive(Debug, Clone)]
pub struct WindowCase {
    /// The grid point.
    pub job: Job,
    /// Every window the search ran, with its errors.
    pub search: SearchResult,
    /// The window energies the criteria read.
    pub curves: EnergyCurves,
    /// Its row of `window.csv`.
    pub row: WindowRow,
}

/// The accuracy-based window length of every case of `jobs` (one shard of a grid of a
/// one-pantograph case), with the EVA lengths beside it; as [`eva_sweep`]. The tolerances and the
/// search are checked here, for every front end ([`Tolerances::check`],
/// [`SearchSettings::check_for`] against the model's length).
pub fn window_sweep(
    jobs: &[Job],
    search: &SearchSettings,
    tol: &Tolerances,
    budget: &Budget,
    threads: Option<usize>,
    done: &(dyn Fn() + Sync),
) -> Result<Vec<WindowCase>, SimError> {
    tol.check()?;
    if let Some(j) = jobs.first() {
        search.check_for(j.case.length_m())?;
    }
    let eva_settings = EvaSettings {
        budget: *budget,
        ..EvaSettings::default()
    };
    parallel_map(jobs, threads, |job| {
        // The window carries one pantograph; its energies are the one-pantograph run's, taken
        // in the same run as the full model's statistics (the same steps, so the outputs of
        // two runs, one recording and one sampling the energy).
        let case = crate::compile::window_case(&job.case).map_err(|e| in_case(job.index, "", e))?;
        crate::compile::require_contact(&case, "the window-length search")
            .map_err(|e| in_case(job.index, "", e))?;
        let setup = Setup::from_case_with(&case, budget).map_err(|e| in_case(job.index, "", e))?;
        let (full, eva) = simulate_with_eva(&setup, &eva_settings, &mut |_| true)
            .map_err(|e| in_case(job.index, "", e))?;
        let fs = full_stats(&case, &full).map_err(|e| in_case(job.index, "", e))?;
        let r = search_windows(&case, &fs, search, tol).map_err(|e| in_case(job.index, "", e))?;
        let curves = EnergyCurves::of(&eva);
        // The errors of the window found; when none matches, of the longest window run (what
        // fails, by how much).
        let at = match r.length_m {
            Some(l) => r.evaluated.iter().find(|e| (e.window_m - l).abs() < 1e-9),
            None => r
                .evaluated
                .iter()
                .max_by(|a, b| a.window_m.total_cmp(&b.window_m)),
        };
        let row = WindowRow {
            index: job.index,
            seed_offset: job.seed_offset,
            speed_kmh: job.speed_kmh,
            tension_kn: job.tension_n / 1e3,
            damping: job.damping.clone(),
            length_m: r.length_m,
            mean_err_pct: at.map(|e| e.mean_pct),
            sigma_err_pct: at.map(|e| e.sigma_pct),
            max_err_pct: at.map(|e| e.max_pct),
            windows_run: r.evaluated.len(),
            eva_step_m: eva.snapshot.eva_step_m,
            eva_fraction_m: eva.snapshot.eva_fraction_m,
            eva_step_max_m: eva.max.eva_step_m,
            eva_fraction_max_m: eva.max.eva_fraction_m,
            eva_step_mean_m: eva.mean.eva_step_m,
            eva_fraction_mean_m: eva.mean.eva_fraction_m,
            snapshot_total_j: curves.snapshot_total_j,
            max_total_j: curves.max_total_j,
            mean_total_j: curves.mean_total_j,
            fine_checked_to_m: r.fine_checked_to_m,
        };
        done();
        Ok(WindowCase {
            job: job.clone(),
            search: r,
            curves,
            row,
        })
    })
    .into_iter()
    .collect()
}

/// The runs of a validation plan on up to `threads` threads, each timed, assembled into its
/// report (`pcsim validate --json`). `run` runs one case ([`run_quietly`], or the CLI's run
/// with progress); the outputs come with their wall times, s, in the plan's order.
#[allow(clippy::type_complexity)]
pub fn validation_runs(
    plan: &ValidationPlan,
    threads: Option<usize>,
    run: &(dyn Fn(&crate::input::case::Case) -> Result<RunOutput, SimError> + Sync),
) -> Result<(Vec<(RunOutput, f64)>, ValidationReport), SimError> {
    // No contact, no numbers: a validation of a pantograph that never touches is refused.
    for c in &plan.cases {
        crate::compile::require_contact(c, "the validation")?;
    }
    let runs: Vec<(RunOutput, f64)> = parallel_map(&plan.cases, threads, |c| {
        let t0 = std::time::Instant::now();
        run(c).map(|o| (o, t0.elapsed().as_secs_f64()))
    })
    .into_iter()
    .collect::<Result<_, _>>()?;
    let outputs: Vec<RunOutput> = runs.iter().map(|r| r.0.clone()).collect();
    let report = plan.assemble(&outputs)?;
    Ok((runs, report))
}

/// One case run within `budget`, with no progress.
pub fn run_quietly(
    case: &crate::input::case::Case,
    budget: &Budget,
) -> Result<RunOutput, SimError> {
    let setup = Setup::from_case_with(case, budget)?;
    simulate(&setup, &mut |_| true)
}
