//! `pcsim assess DIR`: a run's statistics against the acceptance criteria (EN 50367, the TSI
//! Energy, EN 50119), each with its clause and source; `assessment.csv` and `assessment.json`
//! beside the run (issue 22, item 3). The criteria and the verdicts are the core's
//! (`input::criteria`, `analysis::assess`); this file reads the run's summary and prints.

use anyhow::{bail, Context, Result};
use clap::Args;
use std::path::{Path, PathBuf};

use pcsim_core::analysis::assess::{assess, AssessInput, Assessment, Verdict};
use pcsim_core::input::criteria::{self, System};

use crate::output::{add_to_manifest, read_complete_manifest, write_file_atomic};

#[derive(Args)]
pub struct AssessArgs {
    /// A run's output directory (`pcsim run … --out DIR`).
    dir: PathBuf,
    /// The line's supply system: ac, dc-3kv or dc-1.5kv (the criteria that depend on it are
    /// left out, and named, without it).
    #[arg(long, value_name = "SYSTEM")]
    system: Option<String>,
    /// Your own criteria (TOML, the format of data/acceptance-criteria.toml, status "user" and
    /// the source you read each limit in): added to the built-in ones, replacing those of the
    /// same id.
    #[arg(long, value_name = "FILE")]
    criteria: Option<PathBuf>,
    /// Exit with status 1 when a criterion is not met or the run had an error-level event (a
    /// dewirement, contact lost over 10 %); by default the status is 0 whenever the assessment
    /// is made.
    #[arg(long)]
    strict: bool,
}

/// The supply system named on the command line.
fn system_flag(s: Option<&str>) -> Result<Option<System>> {
    s.map(|s| System::parse_or_explain(s).map_err(|e| anyhow::anyhow!("--system {e}")))
        .transpose()
}

pub fn run(a: AssessArgs) -> Result<i32> {
    let system = system_flag(a.system.as_deref())?;
    let mut list = criteria::builtin();
    if let Some(f) = &a.criteria {
        let text = crate::common::read_input(f)
            .with_context(|| format!("--criteria: cannot read {}", f.display()))?;
        let user = criteria::user_file(&text)
            .map_err(|e| anyhow::anyhow!("--criteria {}: {e}", f.display()))?;
        list = criteria::merged(list, user);
    }
    let input = read_run(&a.dir)?;
    let result = assess(&input, &list, system);
    print(&result);
    let written = write(&a.dir, &result)?;
    for p in &written {
        println!("wrote {}", p.display());
    }
    // A report made before is made again, with the assessment in it.
    if read_complete_manifest(&a.dir)?.lists("report.html") {
        let p = crate::report::write(&a.dir)?;
        println!("wrote {}", p.display());
    }
    Ok(if a.strict && !result.passes() { 1 } else { 0 })
}

/// What the directory gives the assessment: a run's `summary.json`, or the current-collection
/// study's `wear.json` (its arcing), each as pcsim wrote it.
fn read_run(dir: &Path) -> Result<AssessInput> {
    use pcsim_core::study::StudyKind;
    let m = read_complete_manifest(dir)?;
    let (file, read): (&str, fn(&str) -> _) = match m.kind {
        StudyKind::Run => ("summary.json", AssessInput::from_summary_json),
        StudyKind::Wear => ("wear.json", AssessInput::from_wear_json),
        kind => bail!(
            "{} holds a `{kind}` study, not a run: pcsim assess takes the directory of `pcsim run` (or of `pcsim study wear`, for its arcing)",
            dir.display()
        ),
    };
    // The same check as the report's: a file edited after pcsim wrote it (its error events
    // deleted, a value changed) is not judged.
    let edited = crate::output::edited_files(dir, &m);
    if edited.iter().any(|f| f == file) {
        bail!(
            "{}: {file} is not the file pcsim wrote (its bytes differ from the hash in pcsim.json): assess judges only what pcsim computed; run it again",
            dir.display()
        );
    }
    let path = dir.join(file);
    let text = std::fs::read_to_string(&path)
        .with_context(|| format!("cannot read {}", path.display()))?;
    read(&text).map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))
}

fn value(x: Option<f64>) -> String {
    x.map_or("—".into(), |v| {
        if v.abs() >= 100.0 {
            format!("{v:.1}")
        } else {
            format!("{v:.3}")
        }
    })
}

fn print(r: &Assessment) {
    println!(
        "assessment at {} km/h, supply system {}",
        r.speed_kmh,
        r.system.as_deref().unwrap_or("not given (--system)")
    );
    for e in &r.run_errors {
        println!("  ERROR of the run: {e}");
    }
    // The pantograph column as wide as its longest name (a study's `TRAIN at V km/h, NAME`).
    let w = (r.rows.iter())
        .filter_map(|row| row.pantograph.as_ref().map(|p| p.chars().count()))
        .fold(10, usize::max);
    println!(
        "  {:<22} {:<w$} {:>10} {:>12} {:<16} {:<15}",
        "criterion", "pantograph", "value", "limit", "verdict", "status"
    );
    for row in &r.rows {
        let verdict = match (row.verdict, row.deviation_percent) {
            (Verdict::Deviation, Some(d)) => format!("{d:+.1} % of target"),
            (v, _) => v.text().to_string(),
        };
        println!(
            "  {:<22} {:<w$} {:>10} {:>12} {:<16} {:<15}",
            row.id,
            row.pantograph.as_deref().unwrap_or("(run)"),
            value(row.value),
            value(row.limit),
            verdict,
            row.status
        );
    }
    if r.rows.iter().any(|row| row.verification.is_some()) {
        println!("verification (the run's --verify: twice the modes and half the step; the contact twice as stiff):");
        println!(
            "  {:<22} {:<10} {:>10} {:>9} {:<16} {:>10} {:<16}",
            "criterion",
            "pantograph",
            "refined",
            "change",
            "verdict refined",
            "stiff k",
            "verdict stiff k"
        );
        for row in &r.rows {
            if let Some(k) = &row.verification {
                println!(
                    "  {:<22} {:<10} {:>10} {:>8.2}%{} {:<16} {:>10} {:<16}",
                    row.id,
                    row.pantograph.as_deref().unwrap_or("(run)"),
                    value(Some(k.refined)),
                    k.change_percent,
                    if k.converged { " " } else { "!" },
                    k.refined_verdict.text(),
                    value(Some(k.stiff_contact)),
                    k.stiff_contact_verdict.text()
                );
            }
        }
        for n in &r.not_established {
            println!("  NOT ESTABLISHED: {n}");
        }
    }
    println!("clauses and sources:");
    let mut seen = Vec::new();
    for row in &r.rows {
        if seen.contains(&&row.id) {
            continue;
        }
        seen.push(&row.id);
        println!(
            "  {}: {} [{}: {}]",
            row.id, row.clause, row.status, row.source
        );
    }
    for s in &r.skipped {
        println!("  not applied: {s}");
    }
    println!("{}", r.conclusion());
}

/// `assessment.json` (the whole assessment) and `assessment.csv` (one row per criterion and
/// pantograph), listed in the directory's manifest.
fn write(dir: &Path, r: &Assessment) -> Result<Vec<PathBuf>> {
    let json = dir.join("assessment.json");
    write_file_atomic(&json, serde_json::to_string_pretty(r)? + "\n")?;
    let csv_path = dir.join("assessment.csv");
    let mut w = csv::Writer::from_writer(Vec::new());
    w.write_record([
        "id",
        "pantograph",
        "quantity",
        "unit",
        "value",
        "kind",
        "limit",
        "limit_formula",
        "deviation_percent",
        "verdict",
        "status",
        "clause",
        "source",
    ])?;
    let opt = |x: Option<f64>| x.map_or(String::new(), |v| format!("{v}"));
    for row in &r.rows {
        w.write_record([
            row.id.as_str(),
            row.pantograph.as_deref().unwrap_or(""),
            &row.quantity,
            &row.unit,
            &opt(row.value),
            &row.kind,
            &opt(row.limit),
            &row.limit_formula,
            &opt(row.deviation_percent),
            row.verdict.text(),
            &row.status,
            &row.clause,
            &row.source,
        ])?;
    }
    write_file_atomic(&csv_path, w.into_inner()?)?;
    let files = vec![json, csv_path];
    add_to_manifest(dir, &files)?;
    Ok(files)
}
