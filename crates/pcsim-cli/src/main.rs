//! `pcsim`: the command-line tool over `pcsim-core`.

mod commands;
mod eva_cmd;
mod fmu_cmd;
mod output;
mod plots;
mod progress;
mod realtime_cmd;

use clap::{Parser, Subcommand};

/// Pantograph–catenary dynamic interaction simulator (modal superposition, EN 50318 statistics).
#[derive(Parser)]
#[command(name = "pcsim", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
    /// No progress bar.
    #[arg(long, global = true)]
    quiet: bool,
}

#[derive(Subcommand)]
enum Command {
    /// Run one case and write summary.json and timeseries.csv.
    Run(commands::RunArgs),
    /// Run a validation (default: en50318-2002 at 250 and 300 km/h) and print the table.
    Validate(commands::ValidateArgs),
    /// List the embedded presets, or print one (`presets show NAME`).
    Presets(commands::PresetsArgs),
    /// Benchmark: wall time against simulated time on one core.
    Bench(commands::BenchArgs),
    /// Redraw the plots of a finished run from its output directory.
    Plot(commands::PlotArgs),
    /// Energy distribution and effective vibration area over speeds, tensions and dampings;
    /// `eva merge DIR…` joins shards.
    Eva(eva_cmd::EvaArgs),
    /// The real-time (moving-window) catenary against the full model, for several window lengths.
    Realtime(realtime_cmd::RealtimeArgs),
    /// FMI 2.0 FMU of the real-time catenary: `fmu build --out DIR`, `fmu xml`.
    Fmu(fmu_cmd::FmuArgs),
    /// Replay a contact-force/position file through the real-time catenary (HIL, Rust reference).
    Hil(fmu_cmd::HilArgs),
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

fn main() {
    default_sigpipe();
    let cli = Cli::parse();
    let res = match cli.command {
        Command::Run(a) => commands::run(a, cli.quiet),
        Command::Validate(a) => commands::validate(a, cli.quiet),
        Command::Presets(a) => commands::presets(a),
        Command::Bench(a) => commands::bench(a, cli.quiet),
        Command::Plot(a) => commands::plot(a),
        Command::Eva(a) => eva_cmd::eva(a, cli.quiet),
        Command::Realtime(a) => realtime_cmd::realtime(a, cli.quiet),
        Command::Fmu(a) => fmu_cmd::fmu(a),
        Command::Hil(a) => fmu_cmd::hil(a),
    };
    match res {
        Ok(code) => std::process::exit(code),
        Err(e) => {
            eprintln!("error: {e:#}");
            std::process::exit(2);
        }
    }
}
