//! `pcsim pantograph frf` (a case's pantograph: its frequency response at the head) and `pcsim
//! pantograph fit` (a lumped chain fitted to a measured response). The computing is the core's
//! (`study/frf.rs`): the response is a study of the contract (`FrfStudy`, through the driver);
//! this file reads the arguments (and writes the fit's files).

use anyhow::{Context, Result};
use clap::{Args, Subcommand, ValueEnum};
use std::path::{Path, PathBuf};

use crate::output::{write_file, write_manifest, OutDir};
use pcsim_core::study::frf::{fit_with, FitSpec, FrfStudy, Quantity, Response};

#[derive(Args)]
pub struct PantographArgs {
    #[command(subcommand)]
    action: Action,
}

#[derive(Subcommand)]
enum Action {
    /// The frequency response at the head of a case's pantograph: frf.csv (frequency,
    /// magnitude with its unit, phase) and the figures of magnitude and phase.
    Frf(FrfArgs),
    /// Fit the case's pantograph (its masses, springs and dampers; the case's values as the start,
    /// each bounded to a factor of 4 around it) to a measured response (CSV: frequency_hz,
    /// magnitude_m_per_n or magnitude_kg, phase_deg): fit.json (each value with its uncertainty,
    /// the residual) and fitted-pantograph.toml (the case block, the measurement as its source).
    Fit(FitArgs),
}

#[derive(Clone, Copy, ValueEnum)]
enum Kind {
    /// Force over acceleration at the head, kg.
    ApparentMass,
    /// Displacement over force at the head, m/N.
    Receptance,
}

#[derive(Args)]
struct Which {
    /// Case file (TOML). Give this or --preset.
    case: Option<PathBuf>,
    /// Embedded preset name.
    #[arg(long)]
    preset: Option<String>,
    /// The pantograph: leading, trailing, a name or an index [default: leading].
    #[arg(long)]
    pantograph: Option<String>,
    /// Output directory.
    #[arg(long, default_value = "out/pantograph")]
    out: PathBuf,
}

#[derive(Args)]
struct FrfArgs {
    #[command(flatten)]
    which: Which,
    /// What the response gives.
    #[arg(long, value_enum, default_value = "apparent-mass")]
    quantity: Kind,
    /// Lowest frequency, Hz.
    #[arg(long, value_name = "HZ", default_value_t = 0.1)]
    from_hz: f64,
    /// Highest frequency, Hz.
    #[arg(long, value_name = "HZ", default_value_t = 20.0)]
    to_hz: f64,
    /// Frequencies, evenly spaced on a logarithmic scale.
    #[arg(long, default_value_t = 200)]
    points: usize,
}

#[derive(Args)]
struct FitArgs {
    /// The measured response (CSV; the units in the header).
    measured: PathBuf,
    #[command(flatten)]
    which: Which,
    /// Starts of the least-squares method: the case's values, then seeded draws inside the
    /// bounds.
    #[arg(long, default_value_t = FitSpec::default().starts)]
    starts: usize,
    /// The draws' seed.
    #[arg(long, default_value_t = FitSpec::default().seed)]
    seed: u64,
    /// The largest RMS misfit accepted, %: above it the fit fails (exit status 1, no case
    /// block written).
    #[arg(long, value_name = "PERCENT", default_value_t = 100.0 * FitSpec::default().max_residual_rms)]
    max_residual_percent: f64,
}

pub fn pantograph(a: PantographArgs, ctx: &crate::common::Ctx) -> Result<i32> {
    match a.action {
        Action::Frf(a) => frf(a, ctx),
        Action::Fit(a) => fit_cmd(a, ctx),
    }
}

fn chain(w: &Which) -> Result<(String, pcsim_core::model::pantograph::Lumped)> {
    let case = crate::common::load_case(w.case.as_ref(), w.preset.as_deref())?;
    Ok(pcsim_core::compile::lumped_pantograph(
        &case,
        w.pantograph.as_deref(),
    )?)
}

/// Magnitude and phase against frequency, one line per response.
fn figures(dir: &Path, stem: &str, title: &str, responses: &[&Response]) -> Result<Vec<PathBuf>> {
    use crate::plot::{figure, Figure, Line};
    let unit = match responses[0].quantity {
        Quantity::Receptance => "receptance |X/F| [m/N]",
        Quantity::ApparentMass => "apparent mass |F/A| [kg]",
    };
    let lines = |f: &dyn Fn(f64, f64) -> f64| -> Vec<Line> {
        responses
            .iter()
            .map(|r| {
                Line::new(
                    r.source.clone(),
                    r.frequency_hz
                        .iter()
                        .zip(&r.value)
                        .map(|(&x, h)| (x, f(h.re, h.im)))
                        .collect(),
                )
            })
            .collect()
    };
    let mut files = figure(
        &dir.join(format!("{stem}_magnitude")),
        &Figure {
            title: &format!("{title}: magnitude"),
            x_label: "frequency [Hz]",
            y_label: unit,
            lines: lines(&|re, im| re.hypot(im)),
            log_y: true,
            vmarks: Vec::new(),
            hmarks: Vec::new(),
        },
    )?;
    files.extend(figure(
        &dir.join(format!("{stem}_phase")),
        &Figure {
            title: &format!("{title}: phase"),
            x_label: "frequency [Hz]",
            y_label: "phase [°]",
            lines: lines(&|re, im| im.atan2(re).to_degrees()),
            log_y: false,
            vmarks: Vec::new(),
            hmarks: Vec::new(),
        },
    )?);
    Ok(files)
}

fn frf(a: FrfArgs, ctx: &crate::common::Ctx) -> Result<i32> {
    let (name, pantograph) = chain(&a.which)?;
    let quantity = match a.quantity {
        Kind::ApparentMass => Quantity::ApparentMass,
        Kind::Receptance => Quantity::Receptance,
    };
    let frequency_hz = Response::log_grid(a.from_hz, a.to_hz, a.points).map_err(|e| {
        pcsim_core::study::specs::with_flags(
            e,
            &[
                ("from_hz", "--from-hz"),
                ("to_hz", "--to-hz"),
                ("points", "--points"),
            ],
        )
    })?;
    let manifest = crate::output::StudyManifest {
        pantograph: Some(name.clone()),
        ..Default::default()
    };
    let study = FrfStudy {
        name,
        pantograph,
        quantity,
        frequency_hz,
    };
    crate::driver::drive(
        &study,
        crate::driver::Drive {
            out: &a.which.out,
            case_text: None,
            spec_text: None,
            plot: true,
            report: false,
            manifest,
            unit: "responses",
        },
        ctx,
    )?;
    Ok(0)
}

fn fit_cmd(a: FitArgs, ctx: &crate::common::Ctx) -> Result<i32> {
    let (name, start) = chain(&a.which)?;
    let text = crate::common::read_input(&a.measured)
        .with_context(|| format!("cannot read {}", a.measured.display()))?;
    let label = a.measured.file_name().map_or_else(
        || a.measured.display().to_string(),
        |n| n.to_string_lossy().into_owned(),
    );
    let measured = Response::from_csv(&text, &label)?;
    let spec = FitSpec {
        starts: a.starts,
        seed: a.seed,
        max_residual_rms: a.max_residual_percent / 100.0,
    };
    spec.check().map_err(|e| {
        pcsim_core::study::specs::with_flags(
            e,
            &[
                ("fit.starts", "--starts"),
                ("fit.max_residual_rms", "--max-residual-percent"),
            ],
        )
    })?;
    let pb = crate::progress::Progress::new(
        "fit",
        spec.starts as u64,
        ctx.progress,
        "fit [{bar:40}] {pos}/{len} starts {elapsed_precise} eta {eta}",
    );
    let r = fit_with(&start, &measured, &spec, &mut |k, _| pb.set(k as u64))?;
    pb.finish();
    let failure = r.check(&start, &measured).err();
    let od = OutDir::begin(&a.which.out)?;
    write_file(
        &od.path().join("fit.json"),
        serde_json::to_string_pretty(&r.record)? + "\n",
    )?;
    if failure.is_none() {
        let block = r.case_block(&name, &label);
        write_file(&od.path().join("fitted-pantograph.toml"), &block)?;
    }
    let mut fitted = Response::of_model(&r.pantograph, measured.quantity, &measured.frequency_hz)?;
    fitted.source = "fitted".into();
    write_manifest(
        od.path(),
        "pantograph-fit",
        crate::output::StudyManifest {
            pantograph: Some(name.clone()),
            measured: Some(a.measured.display().to_string()),
            ..Default::default()
        },
    )?;
    figures(
        od.path(),
        "fit",
        &format!("pantograph {name} fitted to {label}"),
        &[&measured, &fitted],
    )?;
    od.commit()?;
    println!(
        "pantograph {name} fitted to {label}: residual {:.2} % RMS (from {:.2} % at the start), {} evaluations",
        100.0 * r.record.residual_rms,
        100.0 * r.record.start_residual_rms,
        r.record.evaluations
    );
    for q in &r.record.parameters {
        println!(
            "  {:<22} {:>12.5} ± {:<10.3} (start {}){}",
            q.name,
            q.value,
            q.std,
            q.start,
            if q.at_bound {
                "  AT ITS BOUND: widen the start or check the measurement"
            } else {
                ""
            }
        );
    }
    if let Some(e) = failure {
        println!("wrote {}", a.which.out.join("fit.json").display());
        println!("FIT FAILED: {e}");
        return Ok(1);
    }
    println!(
        "wrote {} and {}",
        a.which.out.join("fit.json").display(),
        a.which.out.join("fitted-pantograph.toml").display()
    );
    Ok(0)
}
