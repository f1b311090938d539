//! What several commands share: the global options, reading a case, overrides of case values by
//! flags (with their units), and running a case with progress.

use anyhow::{bail, Context, Result};
use pcsim_core::analysis::record::RunOutput;
use pcsim_core::compile::Budget;
use pcsim_core::input::overrides::{with_overrides, OverrideValue};
use pcsim_core::input::units::{parse_quantity, Dimension};
use pcsim_core::{Case, Setup};
use std::path::{Path, PathBuf};
use std::time::Instant;

use crate::progress::{Progress, ProgressMode};

/// The global options of every command.
#[derive(Debug, Clone, Copy)]
pub struct Ctx {
    pub progress: ProgressMode,
    pub budget: Budget,
    /// Threads of one run (`run --threads`, `bench --threads`); 1 elsewhere.
    pub threads: usize,
}

/// The largest input file read, bytes (`--max-input-mb`; set once at start-up).
static MAX_INPUT_BYTES: std::sync::atomic::AtomicU64 =
    std::sync::atomic::AtomicU64::new(pcsim_core::input::MAX_INPUT_BYTES);

/// Set the largest input file read (the global `--max-input-mb`).
pub fn set_max_input_bytes(n: u64) {
    MAX_INPUT_BYTES.store(n, std::sync::atomic::Ordering::Relaxed);
}

/// Open and read `path` as text within the input limit (`--max-input-mb`), the core's one
/// bounded read: `/dev/zero` or a huge file is refused with the limit and the flag to raise it.
pub fn read_input(path: &Path) -> std::io::Result<String> {
    let limit = MAX_INPUT_BYTES.load(std::sync::atomic::Ordering::Relaxed);
    let f = std::fs::File::open(path)?;
    if f.metadata()?.is_dir() {
        return Err(std::io::Error::other("is a directory"));
    }
    pcsim_core::input::read_text_limited(f, limit).map_err(|e| {
        if e.kind() == std::io::ErrorKind::InvalidData && e.to_string().contains("limit") {
            std::io::Error::other(format!(
                "{e} ({} MB; raise it with --max-input-mb)",
                limit >> 20
            ))
        } else {
            e
        }
    })
}

/// [`read_input`] for a file of a kind `what` (`a manifest`), with a limit of its own, naming
/// the file on error.
pub fn read_text_limited(path: &Path, limit: u64, what: &str) -> Result<String> {
    let f = std::fs::File::open(path).with_context(|| format!("cannot read {}", path.display()))?;
    pcsim_core::input::read_text_limited(f, limit)
        .with_context(|| format!("cannot read {} ({what})", path.display()))
}

/// Load a case from a file or a preset.
pub fn load_case(path: Option<&PathBuf>, preset: Option<&str>) -> Result<Case> {
    Ok(load_case_with_text(path, preset)?.0)
}

/// [`load_case`], and the text the case was read from (the file's, or the preset's), every value
/// with its source.
pub fn load_case_with_text(path: Option<&PathBuf>, preset: Option<&str>) -> Result<(Case, String)> {
    match (path, preset) {
        (Some(p), None) => {
            let text = read_input(p);
            let kept = text.as_ref().cloned().unwrap_or_default();
            let case = pcsim_core::input::case_from_file(&p.display().to_string(), text)?;
            Ok((case, kept))
        }
        (None, Some(name)) => Ok((
            pcsim_core::input::case_from_preset(name)?,
            pcsim_core::presets::find(name)?.toml.to_string(),
        )),
        (Some(_), Some(_)) => bail!("give a case file or --preset, not both"),
        (None, None) => bail!("give a case file or --preset NAME (see `pcsim presets`)"),
    }
}

pub use pcsim_core::analysis::report::case_name;

/// An override of a case value by a flag.
#[derive(Debug, Clone)]
pub struct Override {
    /// The flag as given, e.g. `--tension 20000`.
    pub flag: String,
    /// How it was read, e.g. `20000 kN` (a hint follows where a bare number was taken in the
    /// flag's default unit).
    pub reading: String,
    /// The case field and its value in the field's unit.
    pub path: String,
    pub value: f64,
}

impl Override {
    /// `--speed`: a train speed, km/h unless a unit is given.
    pub fn speed(text: &str) -> Result<Override> {
        let q = parse_quantity(text, Dimension::Speed, 1.0)
            .map_err(|e| anyhow::anyhow!("--speed {e}"))?;
        Ok(Override {
            flag: format!("--speed {text}"),
            reading: format!("{} km/h", q.value),
            path: "run.speed_kmh".into(),
            value: q.value,
        })
    }

    /// `--tension`: the contact-wire tension, kN unless a unit is given.
    pub fn tension(text: &str) -> Result<Override> {
        let q = parse_quantity(text, Dimension::Force, 1e3)
            .map_err(|e| anyhow::anyhow!("--tension {e}"))?;
        let reading = if q.explicit_unit {
            format!("{} N", q.value)
        } else {
            format!(
                "{} kN = {} N; a bare number is in kN, write {text}N for newtons",
                q.value / 1e3,
                q.value
            )
        };
        Ok(Override {
            flag: format!("--tension {text}"),
            reading,
            path: "catenary.contact_wire.tension_n".into(),
            value: q.value,
        })
    }

    /// `--dt`: the time step, s unless a unit is given.
    pub fn dt(text: &str) -> Result<Override> {
        let q =
            parse_quantity(text, Dimension::Time, 1.0).map_err(|e| anyhow::anyhow!("--dt {e}"))?;
        Ok(Override {
            flag: format!("--dt {text}"),
            reading: format!("{} s", q.value),
            path: "run.dt_s".into(),
            value: q.value,
        })
    }
}

/// `--pantograph`: the pantograph a real-time window follows, as the case's
/// `run.window_pantograph` (the core resolves it and refuses one the case does not have).
pub fn window_pantograph(mut case: Case, flag: Option<&str>) -> Case {
    if let Some(p) = flag {
        case.run.window_pantograph = Some(p.to_string());
    }
    case
}

/// A length flag (window lengths), m unless a unit is given.
pub fn length(flag: &str, text: &str) -> Result<f64> {
    Ok(parse_quantity(text, Dimension::Length, 1.0)
        .map_err(|e| anyhow::anyhow!("{flag} {e}"))?
        .value)
}

/// Check `--jobs` (at least 1) and say when it is capped at the core's limit
/// (`analysis::sweep::max_jobs`: 4 workers per core).
pub fn jobs_flag(jobs: Option<usize>) -> Result<()> {
    if jobs == Some(0) {
        bail!("--jobs 0: give at least 1 worker (leave it out to use every core)");
    }
    let cap = pcsim_core::analysis::sweep::max_jobs();
    if let Some(n) = jobs.filter(|&n| n > cap) {
        eprintln!(
            "note: --jobs {n}: capped at {cap} workers ({} per core on this machine)",
            pcsim_core::analysis::sweep::MAX_JOBS_PER_CORE
        );
    }
    Ok(())
}

/// `--threads N` of one run, by the core's rules: 1 to 16, capped at this machine's cores with a
/// note (`team::usable_threads`), and, when `busy_fallback`, fewer when the cores are busy with
/// other work, measured over 0.2 s before the run (`team::idle_cores`, `team::threads_for_idle`),
/// with a note that says why. Without `busy_fallback` (a benchmark) a busy machine is only warned
/// about.
pub fn threads_flag(threads: usize, busy_fallback: bool) -> Result<usize> {
    use pcsim_core::solve::team;
    let n = team::usable_threads(threads).map_err(|e| anyhow::anyhow!("--threads {e}"))?;
    if n < threads {
        eprintln!("note: --threads {threads}: capped at this machine's {n} core(s)");
    }
    if n == 1 {
        return Ok(n);
    }
    let (m, why) =
        team::threads_for_idle(n, team::idle_cores(std::time::Duration::from_millis(200)));
    match why {
        Some(why) if busy_fallback => {
            eprintln!("note: --threads {threads}: {why}");
            Ok(m)
        }
        Some(why) => {
            eprintln!(
                "warning: --threads {threads}: {why} (not applied here: the benchmark runs on {n})"
            );
            Ok(n)
        }
        None => Ok(n),
    }
}

/// The sweep flags shared by `eva` and `window`: speeds (km/h unless a unit is given), contact-
/// wire tensions (kN unless a unit is given), and the shard. Errors name the flag.
pub fn sweep_flags(
    speed: &[String],
    tension: &[String],
    jobs: Option<usize>,
    shard: Option<&str>,
) -> Result<(Vec<f64>, Vec<f64>, pcsim_core::analysis::sweep::Shard)> {
    use pcsim_core::analysis::sweep::Shard;
    jobs_flag(jobs)?;
    let shard = match shard {
        None => Shard::ALL,
        Some(s) => Shard::parse(s)?,
    };
    let list = |flag: &str, values: &[String], dim: Dimension, default_scale: f64| {
        values
            .iter()
            .map(|s| {
                Ok(parse_quantity(s, dim, default_scale)
                    .map_err(|e| anyhow::anyhow!("{flag} {e}"))?
                    .value)
            })
            .collect::<Result<Vec<f64>>>()
    };
    Ok((
        list("--speed", speed, Dimension::Speed, 1.0)?,
        list("--tension", tension, Dimension::Force, 1e3)?,
        shard,
    ))
}

/// A note naming the overrides, for errors they may have caused.
pub fn override_note(overrides: &[Override]) -> String {
    overrides
        .iter()
        .map(|o| format!("{} (read as {})", o.flag, o.reading))
        .collect::<Vec<_>>()
        .join(", ")
}

/// The case with the overrides applied (and validated); an error names the overrides.
pub fn apply(case: &Case, overrides: &[Override]) -> Result<Case> {
    if overrides.is_empty() {
        return Ok(case.clone());
    }
    let ov: Vec<(String, OverrideValue)> = overrides
        .iter()
        .map(|o| (o.path.clone(), OverrideValue::Number(o.value)))
        .collect();
    with_overrides(case, &ov).with_context(|| format!("with {}", override_note(overrides)))
}

/// Validate a case and build its set-up within the budget; errors name the overrides that may
/// have caused them.
pub fn setup(case: &Case, overrides: &[Override], ctx: &Ctx) -> Result<Setup> {
    let s = Setup::from_case_with(case, &ctx.budget).map(|mut s| {
        s.options.threads = ctx.threads;
        s
    });
    if overrides.is_empty() {
        Ok(s?)
    } else {
        s.with_context(|| format!("with {}", override_note(overrides)))
    }
}

/// Validate and run a case with progress; print its warnings. Returns the output, the wall time
/// and the warnings.
pub fn run_with_progress(
    case: &Case,
    overrides: &[Override],
    label: &str,
    ctx: &Ctx,
) -> Result<(RunOutput, f64, Vec<String>)> {
    run_with_progress_quietly(case, overrides, label, ctx, false)
}

/// [`run_with_progress`], printing the set-up warnings unless `quiet_warnings` (a repeated run).
pub fn run_with_progress_quietly(
    case: &Case,
    overrides: &[Override],
    label: &str,
    ctx: &Ctx,
    quiet_warnings: bool,
) -> Result<(RunOutput, f64, Vec<String>)> {
    run_with_droppers(case, overrides, label, ctx, quiet_warnings, None)
}

/// [`run_with_progress_quietly`], following every dropper's tension as `droppers` asks.
pub fn run_with_droppers(
    case: &Case,
    overrides: &[Override],
    label: &str,
    ctx: &Ctx,
    quiet_warnings: bool,
    droppers: Option<pcsim_core::analysis::record::DropperOptions>,
) -> Result<(RunOutput, f64, Vec<String>)> {
    let setup = setup(case, overrides, ctx)?;
    let warnings: Vec<String> = setup.warnings.iter().map(|w| w.to_string()).collect();
    if !quiet_warnings {
        for w in &warnings {
            eprintln!("warning: {w}");
        }
    }
    let pb = Progress::run(label, ctx.progress);
    let t0 = Instant::now();
    let out = pcsim_core::analysis::record::simulate_with(&setup, droppers, &mut |f| {
        pb.set((f * 1000.0) as u64);
        true
    })
    .map_err(anyhow::Error::from);
    pb.finish();
    let out = if overrides.is_empty() {
        out?
    } else {
        out.with_context(|| format!("with {}", override_note(overrides)))?
    };
    Ok((out, t0.elapsed().as_secs_f64(), warnings))
}

/// A file inside an output directory, for messages (no doubled separator).
pub fn shown(dir: &Path, file: &str) -> String {
    dir.join(file).display().to_string()
}

/// The number of realisations of `--seeds N` (1 without the flag): at least 1, at most
/// 100 000, and only for a case with a seeded random input.
pub fn seeds_flag(seeds: Option<usize>, case: &Case) -> Result<usize> {
    pcsim_core::analysis::sweep::check_seeds(seeds, case)
        .map_err(|e| anyhow::anyhow!("--seeds {}: {e}", seeds.unwrap_or(1)))
}

/// Read a contact-wire irregularity profile from a CSV file: a header line, then `position_m,
/// deviation_m` rows (model coordinates, m; deviation upward positive, m).
pub fn read_irregularity_csv(path: &Path) -> Result<pcsim_core::input::case::IrregularityCase> {
    let text = read_input(path)
        .with_context(|| format!("--irregularity: cannot read {}", path.display()))?;
    pcsim_core::input::case::IrregularityCase::from_csv(&text, &path.display().to_string())
        .map_err(|e| anyhow::anyhow!("--irregularity: {e}"))
}
