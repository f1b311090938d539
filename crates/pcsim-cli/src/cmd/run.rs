//! `pcsim run`: one case, `summary.json`, `timeseries.csv` and (with `--plot`) the figures.

use anyhow::Result;
use clap::Args;
use std::path::PathBuf;

use crate::common::{apply, case_name, shown, Ctx, Override};
use crate::output::{write_run, Summary};
use pcsim_core::analysis::record::RunOutput;

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
    let mut overrides = Vec::new();
    if let Some(v) = &a.speed {
        overrides.push(Override::speed(v)?);
    }
    if let Some(t) = &a.tension {
        overrides.push(Override::tension(t)?);
    }
    if let Some(dt) = &a.dt {
        overrides.push(Override::dt(dt)?);
    }
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
    if a.verify && a.seeds.is_some() {
        anyhow::bail!(
            "--verify with --seeds: verify one realisation (run it alone), not the spread of many"
        );
    }
    if a.sensitivity && a.seeds.is_some() {
        anyhow::bail!(
            "--sensitivity with --seeds: vary the ranged values of one realisation (run it alone), not the spread of many"
        );
    }
    let sensitivity = a
        .sensitivity
        .then(|| -> Result<_> {
            let spec = pcsim_core::analysis::sensitivity::SensitivitySpec {
                samples: a.sensitivity_samples,
                seed: a.sensitivity_seed,
                max_runs: a.sensitivity_max_runs,
                allow_failed_runs: a.allow_failed_runs,
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
            let ranges = pcsim_core::Case::from_toml_str_with_ranges(&case_text)?.2;
            if ranges.is_empty() {
                anyhow::bail!("--sensitivity: the case gives no value a range (mark one as `{{ value = …, source = \"…\", range = [low, high], range_source = \"why\" }}`)");
            }
            Ok((spec, ranges))
        })
        .transpose()?;
    if a.seeds.is_some() && a.threads != 1 {
        anyhow::bail!("--threads {} with --seeds: the realisations run in parallel by --jobs; give one or the other", a.threads);
    }
    // The output directory is locked before the work starts: a second writer is refused at once.
    if a.seeds.is_some() {
        let n = crate::common::seeds_flag(a.seeds, &case)?;
        if a.dropper_forces {
            anyhow::bail!("--dropper-forces with --seeds {n}: the droppers' tensions are followed in one run, not gathered over realisations; run the realisation you want alone (its seeds are in montecarlo.csv) with --dropper-forces");
        }
        // The case refused before anything is written, naming the flags that may have caused it.
        crate::common::setup(&case, &overrides, ctx)?;
        let flags: Vec<String> = overrides.iter().map(|o| o.flag.clone()).collect();
        let study = pcsim_core::study::montecarlo::MonteCarloStudy {
            case: case.clone(),
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
                case_text: Some(&case_text),
                plot: a.plot || a.report,
                report: a.report,
                manifest: serde_json::json!({ "realisations": n, "overrides": flags }),
                unit: "realisations",
            },
            ctx,
        )?;
        return Ok(0);
    }
    let od = crate::output::OutDir::begin(&a.out)?;
    let droppers = a
        .dropper_forces
        .then(|| pcsim_core::analysis::record::DropperOptions {
            history: true,
            history_limit: crate::output::DROPPER_HISTORY_LIMIT,
            curve: case
                .dropper_fatigue
                .as_ref()
                .map(pcsim_core::analysis::fatigue::SnCurve::from),
        });
    let (out, wall, warnings) =
        crate::common::run_with_droppers(&case, &overrides, "run", ctx, false, droppers)?;
    for w in pcsim_core::analysis::report::run_verdicts(&out) {
        eprintln!("warning: {w}");
    }
    let flags = overrides.iter().map(|o| o.flag.clone()).collect();
    let mut summary = Summary::new(&case, &out, wall, flags, warnings);
    if a.verify {
        let pb =
            crate::progress::Progress::run("verify (refined and stiff-contact runs)", ctx.progress);
        let v = pcsim_core::analysis::verify::verify(&case, &out, &ctx.budget, a.jobs)?;
        pb.finish();
        summary.verification = Some(v);
    }
    if let Some((spec, ranges)) = &sensitivity {
        let fixed: Vec<String> = overrides.iter().map(|o| o.path.clone()).collect();
        let n = spec.runs_for(ranges.iter().filter(|r| !fixed.contains(&r.path)).count());
        let workers = pcsim_core::analysis::sweep::workers(a.jobs, n);
        eprintln!(
            "sensitivity: {n} runs (at most {}), about {:.0} s on {workers} workers at this run's speed",
            spec.max_runs,
            wall * n as f64 / workers as f64
        );
        let pb = crate::progress::Progress::new(
            "sensitivity",
            n as u64,
            ctx.progress,
            "sensitivity [{bar:40}] {pos}/{len} runs {elapsed_precise} eta {eta}",
        );
        let s = pcsim_core::analysis::sensitivity::sensitivity(
            &case,
            &out,
            ranges,
            &fixed,
            spec,
            a.allowed(),
            &ctx.budget,
            a.jobs,
            &|k, _| pb.set(k as u64),
        )
        .map_err(|e| {
            pcsim_core::study::specs::with_flags(
                e,
                &[("sensitivity.max_runs", "--sensitivity-max-runs")],
            )
        })?;
        pb.finish();
        summary.sensitivity = Some(s);
    }
    write_run(od.path(), &out, &summary)?;
    let dropper_note = crate::output::write_droppers(od.path(), &out)?;
    // The case as given (every value with its source), for the report.
    crate::output::write_file(&od.path().join("case.toml"), &case_text)?;
    let plot = a.plot || a.report;
    let files = if plot {
        // From the files just written: exactly what `pcsim plot DIR` draws.
        od.in_target(&crate::plot::redraw_kind(
            od.path(),
            pcsim_core::study::StudyKind::Run,
        )?)
    } else {
        Vec::new()
    };
    od.commit()?;
    if plot {
        crate::plot::report(&files);
    }
    if a.report {
        let p = crate::report::write(&a.out)?;
        println!("report: {}", p.display());
    }
    print_run(&case, &out, &summary, wall);
    if let Some(v) = &summary.verification {
        print_verification(v);
    }
    if let Some(s) = &summary.sensitivity {
        print_sensitivity(s);
    }
    println!(
        "wrote {} and {}",
        shown(&a.out, "summary.json"),
        shown(&a.out, "timeseries.csv")
    );
    if let Some(d) = &out.droppers {
        print_droppers(d, out.analysis_m, &a.out);
        if let Some(note) = dropper_note {
            println!("  {note}");
        }
    }
    // Error-level events: each kind is refused (exit 2) unless its flag accepts it.
    refuse_errors(&out, a.allowed())?;
    // A study that produced less than it was asked: refused (exit 2), its outputs written.
    if let Some(s) = &summary.sensitivity {
        s.check()
            .map_err(|e| anyhow::anyhow!("{e} (the outputs are written)"))?;
    }
    Ok(0)
}

/// The run on the terminal: its speed and cost, each pantograph's statistics (and lateral
/// motion), the irregularity and the wind.
fn print_run(case: &pcsim_core::Case, out: &RunOutput, summary: &Summary, wall: f64) {
    println!(
        "{} at {} km/h: {} s simulated in {:.2} s wall ({:.1}x real time), {} modes/wire",
        case_name(case),
        case.run.speed_kmh,
        summary.simulated_time_s,
        wall,
        out.simulated_time_s() / wall,
        out.n_modes
    );
    for p in &out.pantographs {
        match &p.stats {
            Some(s) => println!(
                "  {:<10} Fm {:6.1} N  σ {:5.1} N  (0-5 Hz {:4.1}, 5-20 Hz {:4.1})  max {:6.1}  min {:6.1}  uplift@support {:5.1} mm  loss {:.2} %",
                p.name, s.mean_n, s.std_n, s.std_0_5hz_n, s.std_5_20hz_n, s.actual_max_n, s.actual_min_n, s.max_uplift_at_support_mm, s.loss_of_contact_percent
            ),
            None => println!("  {:<10} did not cross the analysis section", p.name),
        }
        for (k, st) in p.strips.iter().enumerate() {
            if let Some(s) = &st.stats {
                println!(
                    "  {:<10} strip {} ({:+.2} m): Fm {:6.1} N  σ {:5.1} N  max {:6.1}  min {:6.1}  loss {:.2} %",
                    "", k + 1, st.along_m, s.mean_n, s.std_n, s.actual_max_n, s.actual_min_n, s.loss_of_contact_percent
                );
            }
        }
        if let Some(s) = &p.stats {
            if let (Some(lat), Some(bo)) = (s.max_lateral_offset_mm, s.max_contact_wire_blowout_mm)
            {
                let margin = s
                    .min_head_margin_mm
                    .map_or(String::new(), |m| format!("  head margin {m:.0} mm"));
                println!(
                    "  {:<10} lateral: max offset {lat:.0} mm{margin}  contact-wire blow-out {bo:.0} mm",
                    ""
                );
            }
        }
    }
    for r in &out.irregularity {
        println!(
            "  irregularity {}{}: RMS {:.2} mm{}",
            r.kind,
            r.seed.map_or(String::new(), |s| format!(" (seed {s})")),
            r.rms_achieved_m * 1e3,
            r.rms_target_m
                .map_or(String::new(), |t| format!(" (target {:.2} mm)", t * 1e3))
        );
    }
    if let Some(w) = &out.wind {
        println!(
            "  wind {:.1} m/s at {} m, {} spectrum, seed {}, turbulence intensity {:.3} (target {:.3})",
            w.mean_speed_m_s,
            w.reference_height_m,
            w.spectrum,
            w.seed,
            w.turbulence_intensity_achieved,
            w.turbulence_intensity_target
        );
    }
}

/// The verification on the terminal: each statistic beside its refined and stiff-contact
/// values, and the statistics not converged to their tolerance.
pub fn print_verification(v: &pcsim_core::analysis::verify::Verification) {
    println!(
        "verification: refined {} modes/wire, Δt {} s; contact {} N/m (model check: every contact, a strip's own too, twice as stiff: {} N/m at Δt {} s)",
        v.refined.modes_per_wire,
        v.refined.dt_s,
        v.run.contact_stiffness_n_per_m,
        v.stiff_contact.contact_stiffness_n_per_m,
        v.stiff_contact.dt_s
    );
    for p in &v.pantographs {
        println!(
            "  {:<10} {:<26} {:>10} {:>10} {:>8} {:>6}   {:>10} {:>8}",
            p.name, "statistic", "value", "refined", "change", "tol", "stiff k", "change"
        );
        for s in &p.statistics {
            println!(
                "  {:<10} {:<26} {:>10.3} {:>10.3} {:>7.2}% {:>5}%{} {:>10.3} {:>7.2}%",
                "",
                format!("{} [{}]", s.statistic, s.unit),
                s.value,
                s.refined,
                s.change_percent,
                s.tolerance_percent,
                if s.converged { " " } else { "!" },
                s.stiff_contact,
                s.stiff_contact_change_percent
            );
        }
    }
    if v.not_converged.is_empty() {
        println!("  every statistic converged to its tolerance (! marks one that is not)");
    }
    for n in &v.not_converged {
        println!("  NOT CONVERGED: {n}");
    }
}

/// The sensitivity on the terminal: each statistic's band and the value that moves it most.
pub fn print_sensitivity(s: &pcsim_core::analysis::sensitivity::Sensitivity) {
    println!(
        "sensitivity: {} ranged values, {} runs one at a time and {} sampled (seed {})",
        s.parameters.len(),
        2 * s.parameters.len(),
        s.spec.samples,
        s.spec.seed
    );
    for p in &s.pantographs {
        println!(
            "  {:<10} {:<26} {:>10} {:>21}   most moved by",
            p.name, "statistic", "value", "band"
        );
        for b in &p.statistics {
            let top = b
                .movers
                .first()
                .map_or(String::from("-"), |m| match m.swing {
                    Some(w) => format!("{} ({w:+.3} {})", m.path, b.unit),
                    None => format!("{} (one end only: moved {:.3} {})", m.path, m.moved, b.unit),
                });
            println!(
                "  {:<10} {:<26} {:>10.3} [{:>9.3}, {:>9.3}]   {top}",
                "",
                format!("{} [{}]", b.statistic, b.unit),
                b.value,
                b.low,
                b.high
            );
        }
    }
    for n in &s.not_varied {
        println!("  not varied: {n}");
    }
    for e in &s.events {
        println!("  EVENT: {e}");
    }
    for f in &s.failed {
        println!("  NOT RUN: {f}");
    }
}

/// A run's error-level events: a warning for those accepted by flag, an error (exit 2, the
/// outputs written) for the first that is not.
fn refuse_errors(
    out: &RunOutput,
    allowed: pcsim_core::analysis::events::AllowedErrors,
) -> Result<()> {
    let errors = pcsim_core::analysis::events::run_errors(out);
    for e in errors.iter().filter(|e| allowed.allows(e.kind)) {
        eprintln!("warning: {} (allowed by {})", e.message, e.kind.flag());
    }
    if let Some(e) = allowed.first_refused(&errors) {
        anyhow::bail!(
            "{} (the outputs are written; give {} to accept the run)",
            e.message,
            e.kind.flag()
        );
    }
    Ok(())
}

/// The droppers inside the analysis section that suffer most: by Miner's damage when the case
/// gives an S–N curve, else by their largest tension range. (Outside it the pantographs start
/// and stop: those droppers carry the run's transients, not a passage.)
fn print_droppers(
    d: &pcsim_core::analysis::record::DropperRun,
    section: [f64; 2],
    out: &std::path::Path,
) {
    let mut worst: Vec<&pcsim_core::analysis::fatigue::DropperFatigue> = d
        .droppers
        .iter()
        .filter(|f| f.x_m >= section[0] && f.x_m <= section[1])
        .collect();
    let key = |f: &pcsim_core::analysis::fatigue::DropperFatigue| f.damage.unwrap_or(f.max_range_n);
    worst.sort_by(|a, b| key(b).total_cmp(&key(a)));
    let by = if d.curve.is_some() {
        "Miner's damage of this passage"
    } else {
        "largest tension range (no [dropper_fatigue] S–N curve in the case: no damage)"
    };
    println!(
        "  droppers: {} followed; the worst inside the analysis section {section:?} m by {by}:",
        d.droppers.len()
    );
    println!(
        "  {:>9} {:<22} {:>8} {:>8} {:>8} {:>6} {:>7} {:>9} {:>10}",
        "x [m]", "wire", "F0 [N]", "min [N]", "max [N]", "slack", "cycles", "ΔFmax [N]", "damage"
    );
    for f in worst.iter().take(10) {
        println!(
            "  {:>9.2} {:<22} {:>8.1} {:>8.1} {:>8.1} {:>6} {:>7} {:>9.1} {:>10}",
            f.x_m,
            f.wire,
            f.preload_n,
            f.min_n,
            f.max_n,
            f.slack_steps,
            f.cycles,
            f.max_range_n,
            f.damage.map_or("—".to_string(), |v| format!("{v:.3e}"))
        );
    }
    println!("  every dropper: {}", shown(out, "droppers.csv"));
}
