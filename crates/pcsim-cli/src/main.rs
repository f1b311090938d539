//! `pcsim`: the command-line tool over `pcsim-core`. Each command parses its arguments, calls the
//! core and writes files; none of them re-implements the core's orchestration.
// No production function over 100 lines (clippy.toml's threshold; issue 52): a long function
// is split into named parts. Tests are exempt (a scenario reads best whole).
#![cfg_attr(not(test), deny(clippy::too_many_lines))]

mod cmd;
mod common;
mod driver;
mod output;
mod plot;
mod progress;
mod report;
mod svg_safe;
mod sweep_dir;

use clap::{Parser, Subcommand};

use crate::common::Ctx;
use crate::progress::ProgressMode;

/// Pantograph–catenary dynamic interaction simulator (modal superposition, EN 50318 statistics).
#[derive(Parser)]
#[command(name = "pcsim", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// No progress output (the same as --progress none).
    #[arg(long, global = true)]
    quiet: bool,
    /// Progress on stderr: a bar on a terminal, a plain line every 5 s otherwise (auto), or
    /// always a bar, always plain lines, or nothing.
    #[arg(long, global = true, value_enum, default_value = "auto")]
    progress: ProgressMode,
    /// Most time steps one run may take before it is refused [default: 20000000].
    #[arg(long, global = true, value_name = "N")]
    max_steps: Option<u64>,
    /// Most memory one run may need before it is refused, GiB [default: 4].
    #[arg(long, global = true, value_name = "GIB")]
    max_memory_gb: Option<f64>,
    /// Largest input file read (a case, a profile, a HIL input, a shard's manifest), MB
    /// [default: 256].
    #[arg(long, global = true, value_name = "MB")]
    max_input_mb: Option<f64>,
    /// Use the portable kernels (plain multiply and add) instead of AVX2+FMA: the same bytes on
    /// every x86-64 machine, about 25 % slower. The same as PCSIM_PORTABLE=1.
    #[arg(long, global = true)]
    portable: bool,
}

#[derive(Subcommand)]
enum Command {
    /// Run one case and write summary.json and timeseries.csv.
    Run(cmd::run::RunArgs),
    /// Run a validation (default: en50318-2002 at 250 and 300 km/h) and print the table.
    Validate(cmd::validate::ValidateArgs),
    /// List the embedded presets, or print one (`presets show NAME`).
    Presets(cmd::presets::PresetsArgs),
    /// The JSON Schema of a case file (`schema case`, for an editor) or of an output
    /// (`schema summary`, `schema montecarlo`).
    Schema(cmd::schema::SchemaArgs),
    /// Benchmark: wall time against simulated time on one core.
    Bench(cmd::bench::BenchArgs),
    /// Redraw the plots of a finished run from its output directory.
    Plot(cmd::plot::PlotArgs),
    /// Energy distribution and effective vibration area over speeds, tensions and dampings;
    /// `eva merge DIR…` joins shards.
    Eva(cmd::eva::EvaArgs),
    /// The real-time (moving-window) catenary against the full model, for several window lengths.
    Realtime(cmd::realtime::RealtimeArgs),
    /// FMI 2.0 FMU of the real-time catenary: `fmu build --out DIR`, `fmu xml`.
    Fmu(cmd::fmu::FmuArgs),
    /// Replay a contact-force/position file through the real-time catenary (HIL, Rust reference).
    Hil(cmd::hil::HilArgs),
    /// How long must the real-time window be? The shortest window that matches the full model
    /// within tolerances, over speeds and tensions, beside the energy-based lengths; `window
    /// merge DIR…` joins shards.
    Window(cmd::window::WindowArgs),
    /// A run's contact force beside a measured one: the same 0–20 Hz filter, aligned by
    /// cross-correlation, statistics side by side, spectra and the force over the span.
    Compare(cmd::compare::CompareArgs),
    /// One self-contained report.html of a run's output directory (the case and its sources,
    /// statistics, warnings, overlaps, droppers, every figure).
    Report(cmd::report::ReportArgs),
    /// A run against the acceptance criteria (EN 50367, TSI Energy, EN 50119), each with its
    /// clause and source; a criterion whose limit pcsim cannot cite gives the value only.
    Assess(cmd::assess::AssessArgs),
    /// Design search: the catenary or pantograph settings that minimise an objective of the runs
    /// at several speeds, under constraints and the acceptance criteria (SPEC.toml), with a
    /// journal that a killed search resumes from.
    Design(cmd::design::DesignArgs),
    /// A pantograph's frequency response at the head (`pantograph frf CASE`), and a lumped
    /// chain fitted to a measured one (`pantograph fit FRF.csv CASE`).
    Pantograph(cmd::pantograph::PantographArgs),
    /// A study written as a spec file (TOML, its `kind` naming the study), or a study's embedded
    /// default spec by its name; `pcsim schema` lists each such study's output and spec.
    Study(cmd::study::StudyArgs),
}

/// Restore the default SIGPIPE action so that `pcsim … | head` ends quietly instead of panicking
/// on a closed stdout (Rust ignores SIGPIPE by default).
#[cfg(unix)]
fn default_sigpipe() {
    extern "C" {
        fn signal(signum: i32, handler: usize) -> usize;
    }
    const SIGPIPE: i32 = 13;
    const SIG_DFL: usize = 0;
    // SAFETY: resetting a signal to its default action, before any other thread exists.
    unsafe {
        signal(SIGPIPE, SIG_DFL);
    }
}

#[cfg(not(unix))]
fn default_sigpipe() {}

/// The global options, checked.
fn context(cli: &Cli) -> anyhow::Result<Ctx> {
    if cli.portable && !pcsim_core::solve::Isa::force_portable() {
        anyhow::bail!("--portable: the kernels were chosen before the flag was read");
    }
    // The core's one conversion and check of the limits, named by flag.
    let budget =
        pcsim_core::study::specs::budget_of(cli.max_steps, cli.max_memory_gb).map_err(|e| {
            pcsim_core::study::specs::with_flags(
                e,
                &[
                    ("max_steps", "--max-steps"),
                    ("max_memory_gb", "--max-memory-gb"),
                ],
            )
        })?;
    if let Some(mb) = cli.max_input_mb {
        if !(0.001..=1e6).contains(&mb) {
            anyhow::bail!("--max-input-mb {mb}: must be a number of MB in [0.001, 1e6]");
        }
        crate::common::set_max_input_bytes((mb * (1u64 << 20) as f64) as u64);
    }
    Ok(Ctx {
        progress: if cli.quiet {
            ProgressMode::None
        } else {
            cli.progress
        },
        budget,
        threads: 1,
    })
}

fn main() {
    default_sigpipe();
    let cli = Cli::parse();
    let res = context(&cli).and_then(|ctx| match cli.command {
        Command::Run(a) => cmd::run::run(a, &ctx),
        Command::Validate(a) => cmd::validate::validate(a, &ctx),
        Command::Presets(a) => cmd::presets::presets(a),
        Command::Schema(a) => cmd::schema::schema_cmd(a),
        Command::Bench(a) => cmd::bench::bench(a, &ctx),
        Command::Plot(a) => cmd::plot::plot(a),
        Command::Eva(a) => cmd::eva::eva(a, &ctx),
        Command::Realtime(a) => cmd::realtime::realtime(a, &ctx),
        Command::Study(a) => cmd::study::study(a, &ctx),
        Command::Fmu(a) => cmd::fmu::fmu(a),
        Command::Hil(a) => cmd::hil::hil(a, &ctx),
        Command::Window(a) => cmd::window::window(a, &ctx),
        Command::Compare(a) => cmd::compare::compare(a, &ctx),
        Command::Report(a) => cmd::report::report(a),
        Command::Assess(a) => cmd::assess::run(a),
        Command::Design(a) => cmd::design::design(a, &ctx),
        Command::Pantograph(a) => cmd::pantograph::pantograph(a, &ctx),
    });
    match res {
        Ok(code) => std::process::exit(code),
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::exit(2);
        }
    }
}

/// The flags' defaults are the core specs' `Default` (issue 52): clap takes them from the spec
/// where it can (`default_value_t = Spec::default().field`), and a default written as text with
/// its unit (`--mean-tol 1%`) is read here through the flag's own parser and compared.
#[cfg(test)]
mod spec_defaults {
    use super::Cli;
    use clap::CommandFactory;

    fn default_of(sub: &str, arg: &str) -> String {
        let cmd = Cli::command();
        let a = (cmd.find_subcommand(sub).expect(sub).get_arguments())
            .find(|a| a.get_id() == arg)
            .unwrap_or_else(|| panic!("{sub} --{arg}"))
            .clone();
        let d = a.get_default_values();
        assert_eq!(d.len(), 1, "{sub} --{arg}");
        d[0].to_string_lossy().into_owned()
    }

    #[test]
    fn every_study_flags_default_is_its_specs() {
        let num = |sub: &str, arg: &str| default_of(sub, arg).parse::<f64>().unwrap();
        let e = pcsim_core::analysis::eva::EvaSettings::default();
        assert_eq!(num("eva", "step"), e.step_m);
        assert_eq!(num("eva", "tol"), e.tolerance_j);
        assert_eq!(num("eva", "fraction"), e.fraction);
        assert_eq!(num("eva", "span_positions"), e.span_positions as f64);
        let w = pcsim_core::study::specs::WindowSweepSpec::default();
        let pct = |arg: &str| crate::cmd::window::pct(arg, &default_of("window", arg)).unwrap();
        assert_eq!(pct("mean_tol"), w.tolerances.mean_pct);
        assert_eq!(pct("sigma_tol"), w.tolerances.sigma_pct);
        assert_eq!(pct("max_tol"), w.tolerances.max_pct);
        let m = |arg: &str| crate::cmd::window::metres(arg, &default_of("window", arg)).unwrap();
        assert_eq!(m("coarse"), w.coarse_m);
        assert_eq!(m("resolution"), w.resolution_m);
        let s = pcsim_core::analysis::sensitivity::SensitivitySpec::default();
        assert_eq!(num("run", "sensitivity_samples"), s.samples as f64);
        assert_eq!(num("run", "sensitivity_seed"), s.seed as f64);
        assert_eq!(num("run", "sensitivity_max_runs"), s.max_runs as f64);
    }
}
