//! `pcsim run --seeds N`: a Monte Carlo study of one case over the seeds of its random inputs
//! (the core's `study::montecarlo`): `montecarlo.csv` (one row per realisation),
//! `montecarlo.json` (the spread of each statistic: mean, standard deviation, 95 % confidence
//! interval of the mean) and histograms of σ and of the minimum force.

use anyhow::Result;
use pcsim_core::analysis::events::{count_events, run_errors, EventCount, RunError};
use pcsim_core::study::montecarlo::Realisation;
use pcsim_core::study::montecarlo::{monte_carlo, stat_of, statistics_of, Spread};
use pcsim_core::study::specs::MonteCarloSpec;
use pcsim_core::Case;
use std::fmt::Write as _;
use std::path::Path;

use crate::common::{shown, Ctx, Override};
use crate::output::{write_file, write_manifest};
use crate::progress::Progress;

/// A Monte Carlo study as the command line gives it.
pub struct Study<'a> {
    /// The case.
    pub case: &'a Case,
    /// Its text as given (written as `case.toml`).
    pub case_text: &'a str,
    /// The flags that overrode case values.
    pub overrides: &'a [Override],
    /// The study: its realisations and the error-level events accepted by flag
    /// (`--allow-contact-loss`, `--allow-dewirement`).
    pub spec: MonteCarloSpec,
    /// Worker threads.
    pub jobs: Option<usize>,
}

/// Run the study into `out`; `(plot, report)`: draw the figures, write `report.html`. Exits 2
/// (after writing every output) when a realisation had an error-level event that no flag
/// accepts, naming how many realisations had which event.
pub fn run_seeds(
    st: Study<'_>,
    out: &Path,
    (plot, report): (bool, bool),
    ctx: &Ctx,
) -> Result<i32> {
    let Study {
        case,
        case_text,
        overrides,
        spec,
        jobs,
    } = st;
    let n = spec
        .check(case)
        .map_err(|e| anyhow::anyhow!("--seeds {}: {e}", spec.realisations))?;
    let allowed = spec.allowed;
    crate::common::setup(case, overrides, ctx)?;
    let od = crate::output::OutDir::begin(out)?;
    let target = out;
    let out = od.path();
    // The case as given (every value with its source), for the report.
    write_file(&out.join("case.toml"), case_text)?;
    let pb = Progress::new(
        "montecarlo",
        n as u64,
        ctx.progress,
        "montecarlo [{bar:40}] {pos}/{len} realisations {elapsed_precise} eta {eta}",
    );
    let real = monte_carlo(case, n, jobs, &ctx.budget, &|| pb.inc())?;
    pb.finish();
    let names: Vec<String> = real[0]
        .output
        .pantographs
        .iter()
        .map(|p| p.name.clone())
        .collect();
    // The error-level events of each realisation, counted per kind.
    let per_run: Vec<_> = real.iter().map(|r| run_errors(&r.output)).collect();
    let events = count_events(&per_run, allowed);
    let csv = realisation_rows(case, &real, &per_run, &names);
    write_file(&out.join("montecarlo.csv"), csv)?;
    let stats = spreads(&real, &names)?;
    let summary = serde_json::json!({
        "case_name": crate::common::case_name(case),
        "speed_kmh": case.run.speed_kmh,
        "realisations": n,
        "seed_offsets": [0, n - 1],
        "overrides": overrides.iter().map(|o| o.flag.clone()).collect::<Vec<_>>(),
        "irregularity": real[0].output.irregularity,
        "wind": real[0].output.wind,
        "statistics": stats,
        "errors": events,
        "note": "spread over the realisations: mean, standard deviation (N-1), 95 % confidence interval of the mean (Student's t), min, max",
    });
    write_file(
        &out.join("montecarlo.json"),
        serde_json::to_string_pretty(&summary)? + "\n",
    )?;
    write_manifest(
        out,
        "montecarlo",
        serde_json::json!({
            "realisations": n,
            "overrides": overrides.iter().map(|o| o.flag.clone()).collect::<Vec<_>>(),
        }),
    )?;
    println!(
        "{}: {n} realisations at {} km/h",
        crate::common::case_name(case),
        case.run.speed_kmh
    );
    print_spreads(&real, &names);
    let files = if plot {
        od.in_target(&crate::plot::redraw_kind(out, "montecarlo")?)
    } else {
        Vec::new()
    };
    od.commit()?;
    println!(
        "wrote {} and {}",
        shown(target, "montecarlo.csv"),
        shown(target, "montecarlo.json")
    );
    if plot {
        crate::plot::report(&files);
    }
    if report {
        let p = crate::cmd::report::write(target)?;
        println!("report: {}", p.display());
    }
    refuse_events(&events, n)
}

/// `montecarlo.csv`: one row per realisation, its seeds, the irregularity's achieved RMS, its
/// error-level events and every pantograph's statistics.
fn realisation_rows(
    case: &Case,
    real: &[Realisation],
    per_run: &[Vec<RunError>],
    names: &[String],
) -> String {
    let stats = statistics_of(real.iter().map(|r| &r.output));
    let mut csv = String::from("realisation,seed_offset,seeds,irregularity_rms_m,errors");
    for nm in names {
        for s in &stats {
            let _ = write!(csv, ",{nm}_{s}");
        }
    }
    csv.push('\n');
    for (k, r) in real.iter().enumerate() {
        let c = case.with_seed_offset(r.seed_offset);
        let mut seeds: Vec<String> = c
            .irregularity
            .iter()
            .enumerate()
            .filter_map(|(i, ir)| ir.seed().map(|s| format!("irregularity[{i}]={s}")))
            .collect();
        if let Some(w) = &c.wind {
            seeds.push(format!("wind={}", w.seed));
        }
        if c.run.perturb_uplift_rel != 0.0 {
            seeds.push(format!("perturb={}", c.run.perturb_seed));
        }
        let rms: f64 = r
            .output
            .irregularity
            .iter()
            .map(|x| x.rms_achieved_m.powi(2))
            .sum::<f64>()
            .sqrt();
        let kinds: Vec<&str> = per_run[k].iter().map(|e| e.kind.name()).collect();
        let _ = write!(
            csv,
            "{},{},{},{:.6e},{}",
            r.seed_offset,
            r.seed_offset,
            seeds.join(" "),
            rms,
            kinds.join(" ")
        );
        for p in 0..names.len() {
            for s in &stats {
                let v = stat_of(&r.output, p, s);
                if v.is_finite() {
                    let _ = write!(csv, ",{v:.6}");
                } else {
                    csv.push(',');
                }
            }
        }
        csv.push('\n');
    }
    csv
}

/// The spread of each statistic over the realisations, per pantograph.
fn spreads(
    real: &[Realisation],
    names: &[String],
) -> Result<serde_json::Map<String, serde_json::Value>> {
    let mut stats = serde_json::Map::new();
    let names_of = statistics_of(real.iter().map(|r| &r.output));
    for (p, nm) in names.iter().enumerate() {
        let mut m = serde_json::Map::new();
        for s in &names_of {
            let v: Vec<f64> = real.iter().map(|r| stat_of(&r.output, p, s)).collect();
            m.insert(s.to_string(), serde_json::to_value(Spread::of(&v))?);
        }
        stats.insert(nm.clone(), serde_json::Value::Object(m));
    }
    Ok(stats)
}

/// The spread of σ, the minimum and the loss of contact on the terminal.
fn print_spreads(real: &[Realisation], names: &[String]) {
    for (p, nm) in names.iter().enumerate() {
        for s in [
            "std_n",
            "actual_min_n",
            "loss_of_contact_percent",
            "max_lateral_offset_mm",
            "max_contact_wire_blowout_mm",
        ] {
            let v: Vec<f64> = real.iter().map(|r| stat_of(&r.output, p, s)).collect();
            if let Some(sp) = Spread::of(&v) {
                match (sp.std, sp.ci95_low, sp.ci95_high) {
                    (Some(sd), Some(lo), Some(hi)) => println!(
                        "  {nm:<10} {s:<28} mean {:8.3}  std {sd:7.3}  95 % CI [{lo:.3}, {hi:.3}]  range [{:.3}, {:.3}]",
                        sp.mean, sp.min, sp.max
                    ),
                    _ => println!(
                        "  {nm:<10} {s:<28} mean {:8.3}  std and 95 % CI undefined (one realisation)",
                        sp.mean
                    ),
                }
            }
        }
    }
}

/// The study's error-level events on standard error: an error (exit 2, the outputs written)
/// unless its flag accepts it, as for one run.
fn refuse_events(events: &[EventCount], n: usize) -> Result<i32> {
    let mut refused = None;
    for e in events {
        let line = format!(
            "{} of {n} realisations: {} (the first, realisation {}: {})",
            e.runs.len(),
            e.kind.replace('_', " "),
            e.runs[0],
            e.first_message
        );
        let flag = crate::common::allow_flag(e.of);
        if e.allowed {
            eprintln!("warning: {line} (allowed by {flag})");
        } else {
            eprintln!("error: {line}");
            refused.get_or_insert(flag);
        }
    }
    if let Some(flag) = refused {
        anyhow::bail!("the study's realisations had error-level events (above; montecarlo.json's `errors`, montecarlo.csv's `errors` column): the outputs are written; give {flag} to accept them");
    }
    Ok(0)
}
