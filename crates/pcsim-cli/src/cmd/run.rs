//! `pcsim run`: one case, `summary.json`, `timeseries.csv` and (with `--plot`) the figures.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

use crate::common::{apply, Ctx, Override};
use pcsim_core::analysis::fatigue::SnCurve;
use pcsim_core::analysis::record::DropperOptions;
use pcsim_core::analysis::sensitivity::SensitivitySpec;
use pcsim_core::study::run::{RunSpec, RunStudy};

#[derive(Args)]
pub struct RunArgs {
    /// Case file (TOML). Give this or --preset.
    case: Option<PathBuf>,
    /// Embedded preset name (see `pcsim presets`).
    #[arg(long)]
    preset: Option<String>,
    /// Override the train speed: km/h, or with a unit (250km/h, 69m/s).
    #[arg(long, value_name = "KM/H")]
    speed: Option<String>,
    /// Override the contact-wire tension: kN, or with a unit (20kN, 20000N).
    #[arg(long, value_name = "KN")]
    tension: Option<String>,
    /// Override the time step: s, or with a unit (0.5ms).
    #[arg(long, value_name = "S")]
    dt: Option<String>,
    /// Output directory (written as a whole: a directory of an earlier run is replaced).
    #[arg(long, default_value = "out/run")]
    out: PathBuf,
    /// Also draw the figures (SVG and PNG) into the output directory.
    #[arg(long)]
    plot: bool,
    /// Add a contact-wire irregularity profile from a CSV file (`position_m,deviation_m`, m; a
    /// header line first), on top of the case's own sources.
    #[arg(long, value_name = "FILE")]
    irregularity: Option<PathBuf>,
    /// Monte Carlo: N realisations of the case's random inputs (seeds offset by 0..N), run in
    /// parallel; writes montecarlo.csv, montecarlo.json and histograms instead of one run.
    #[arg(long, value_name = "N")]
    seeds: Option<usize>,
    /// Exit 0 even when a pantograph dewired (the contact wire left its head): the run's outputs
    /// are written either way, with the event in summary.json's `errors`.
    #[arg(long)]
    allow_dewirement: bool,
    /// Exit 0 even when a pantograph lost contact over more than 10 % of the analysis section:
    /// the outputs are written either way, with the event in summary.json's `errors`.
    #[arg(long)]
    allow_contact_loss: bool,
    /// Worker threads for --seeds, at least 1 [default: all cores].
    #[arg(long)]
    jobs: Option<usize>,
    /// Threads of this one run: its per-group work (gather, scatter, implicit solve) is split
    /// between the model's basis groups, so a long line of several tension lengths runs sooner;
    /// the output bytes are the same [default: 1]. A model of one basis group runs on one.
    #[arg(long, default_value_t = 1)]
    threads: usize,
    /// Follow every dropper's tension: droppers.csv (extremes, slack steps, rainflow cycles, and
    /// Miner's damage when the case has a dropper_fatigue S–N curve), dropper_forces.csv (each
    /// dropper's tension at every step, when it holds at most 10 million numbers), and with
    /// --plot the figure along the line.
    #[arg(long)]
    dropper_forces: bool,
    /// Also write report.html: the case with its sources, the statistics, every figure
    /// (implies --plot).
    #[arg(long)]
    report: bool,
    /// Verify the numbers: run the case again refined (twice the modes, half the time step) and
    /// with the contact twice as stiff (a model check); summary.json gains `verification`, each
    /// statistic beside both with its change, and the statistics not converged to their
    /// tolerance are listed (the two runs share --jobs).
    #[arg(long)]
    verify: bool,
    /// The model uncertainty from the case's own marks: every value the case gives a range
    /// (`{ value, source, range = [low, high], range_source }`) run at its low and its high end,
    /// one at a time, then --sensitivity-samples runs with all of them drawn at once;
    /// summary.json gains `sensitivity`, each statistic's band and the values that move it
    /// most (the runs share --jobs).
    #[arg(long)]
    sensitivity: bool,
    /// Runs of --sensitivity's seeded sample (0: one at a time only).
    #[arg(long, value_name = "N", requires = "sensitivity", default_value_t = pcsim_core::analysis::sensitivity::SensitivitySpec::default().samples)]
    sensitivity_samples: usize,
    /// Seed of --sensitivity's sample (in summary.json's `sensitivity.spec`).
    #[arg(long, value_name = "SEED", requires = "sensitivity", default_value_t = pcsim_core::analysis::sensitivity::SensitivitySpec::default().seed)]
    sensitivity_seed: u64,
    /// The most runs --sensitivity may make (two per ranged value, then the sample), checked
    /// before any run.
    #[arg(long, value_name = "N", requires = "sensitivity", default_value_t = pcsim_core::analysis::sensitivity::SensitivitySpec::default().max_runs)]
    sensitivity_max_runs: usize,
    /// Exit 0 even when runs of --sensitivity could not be made (the bands are then taken over
    /// fewer runs, said); without it such a study exits 2, its outputs written.
    #[arg(long, requires = "sensitivity")]
    allow_failed_runs: bool,
}

impl RunArgs {
    /// The error-level events accepted by flag.
    fn allowed(&self) -> pcsim_core::analysis::events::AllowedErrors {
        pcsim_core::analysis::events::AllowedErrors {
            dewirement: self.allow_dewirement,
            contact_loss: self.allow_contact_loss,
        }
    }
}

pub fn run(a: RunArgs, ctx: &Ctx) -> Result<i32> {
    let (base, case_text) =
        crate::common::load_case_with_text(a.case.as_ref(), a.preset.as_deref())?;
    let overrides = a.overrides()?;
    let mut case = apply(&base, &overrides)?;
    if let Some(f) = &a.irregularity {
        case.irregularity
            .push(crate::common::read_irregularity_csv(f)?);
        case.validate()
            .map_err(|e| anyhow::anyhow!("{e} (with --irregularity {})", f.display()))?;
    }
    crate::common::jobs_flag(a.jobs)?;
    let ctx = &Ctx {
        threads: crate::common::threads_flag(a.threads, true)?,
        ..*ctx
    };
    a.refuse_conflicts()?;
    let flags: Vec<String> = overrides.iter().map(|o| o.flag.clone()).collect();
    if a.seeds.is_some() {
        return seeds(&a, case, &case_text, &overrides, ctx);
    }
    let study = RunStudy {
        ranges: if a.sensitivity {
            pcsim_core::Case::from_toml_str_with_ranges(&case_text)?.2
        } else {
            Vec::new()
        },
        fixed: overrides.iter().map(|o| o.path.clone()).collect(),
        overrides: flags.clone(),
        spec: RunSpec {
            verify: a.verify,
            sensitivity: a.sensitivity.then_some(SensitivitySpec {
                samples: a.sensitivity_samples,
                seed: a.sensitivity_seed,
                max_runs: a.sensitivity_max_runs,
                allow_failed_runs: a.allow_failed_runs,
            }),
            allowed: a.allowed(),
            droppers: a.dropper_forces.then(|| DropperOptions {
                history: true,
                history_limit: pcsim_core::study::run::DROPPER_HISTORY_LIMIT,
                curve: case.dropper_fatigue.as_ref().map(SnCurve::from),
            }),
            threads: ctx.threads,
        },
        case,
        budget: ctx.budget,
        jobs: a.jobs,
    };
    // Refused by its flag's name before anything is written (and by the flags that may have
    // caused it).
    let with_flags = |e: anyhow::Error| {
        if overrides.is_empty() {
            e
        } else {
            e.context(format!("with {}", crate::common::override_note(&overrides)))
        }
    };
    pcsim_core::study::Study::check(&study)
        .map_err(|e| pcsim_core::study::specs::with_flags(e, &[("sensitivity", "--sensitivity")]))
        .map_err(|e| with_flags(e.into()))?;
    let drive = crate::driver::Drive {
        out: &a.out,
        case_text: Some(&case_text),
        spec_text: None,
        plot: a.plot || a.report,
        report: a.report,
        manifest: crate::output::StudyManifest {
            overrides: Some(flags),
            ..Default::default()
        },
        unit: "‰",
    };
    crate::driver::drive(&study, drive, ctx).map_err(with_flags)?;
    Ok(0)
}

impl RunArgs {
    /// The flags that override a case value, each with its unit read.
    fn overrides(&self) -> Result<Vec<Override>> {
        let mut o = Vec::new();
        if let Some(v) = &self.speed {
            o.push(Override::speed(v)?);
        }
        if let Some(t) = &self.tension {
            o.push(Override::tension(t)?);
        }
        if let Some(dt) = &self.dt {
            o.push(Override::dt(dt)?);
        }
        Ok(o)
    }

    /// Flags that cannot go together, refused by name before anything runs.
    fn refuse_conflicts(&self) -> Result<()> {
        if self.verify && self.seeds.is_some() {
            anyhow::bail!(
                "--verify with --seeds: verify one realisation (run it alone), not the spread of many"
            );
        }
        if self.sensitivity && self.seeds.is_some() {
            anyhow::bail!(
                "--sensitivity with --seeds: vary the ranged values of one realisation (run it alone), not the spread of many"
            );
        }
        if self.seeds.is_some() && self.threads != 1 {
            anyhow::bail!("--threads {} with --seeds: the realisations run in parallel by --jobs; give one or the other", self.threads);
        }
        if self.dropper_forces && self.seeds.is_some() {
            anyhow::bail!("--dropper-forces with --seeds {}: the droppers' tensions are followed in one run, not gathered over realisations; run the realisation you want alone (its seeds are in montecarlo.csv) with --dropper-forces", self.seeds.unwrap_or(0));
        }
        let spec = SensitivitySpec {
            samples: self.sensitivity_samples,
            seed: self.sensitivity_seed,
            max_runs: self.sensitivity_max_runs,
            allow_failed_runs: self.allow_failed_runs,
        };
        spec.check().map_err(|e| {
            pcsim_core::study::specs::with_flags(
                e,
                &[
                    ("sensitivity.samples", "--sensitivity-samples"),
                    ("sensitivity.max_runs", "--sensitivity-max-runs"),
                ],
            )
        })?;
        Ok(())
    }
}

/// `--seeds N`: the Monte Carlo study of the case.
fn seeds(
    a: &RunArgs,
    case: pcsim_core::Case,
    case_text: &str,
    overrides: &[Override],
    ctx: &Ctx,
) -> Result<i32> {
    let n = crate::common::seeds_flag(a.seeds, &case)?;
    // The case refused before anything is written, naming the flags that may have caused it.
    crate::common::setup(&case, overrides, ctx)?;
    let flags: Vec<String> = overrides.iter().map(|o| o.flag.clone()).collect();
    let study = pcsim_core::study::montecarlo::MonteCarloStudy {
        case,
        spec: pcsim_core::study::specs::MonteCarloSpec {
            realisations: n,
            allowed: a.allowed(),
        },
        overrides: flags.clone(),
        budget: ctx.budget,
        jobs: a.jobs,
    };
    crate::driver::drive(
        &study,
        crate::driver::Drive {
            out: &a.out,
            case_text: Some(case_text),
            spec_text: None,
            plot: a.plot || a.report,
            report: a.report,
            manifest: crate::output::StudyManifest {
                realisations: Some(n),
                overrides: Some(flags),
                ..Default::default()
            },
            unit: "realisations",
        },
        ctx,
    )?;
    Ok(0)
}
