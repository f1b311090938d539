//! `pcsim design SPEC.toml`: the design search (issue 24). The search is the core's
//! (`study::design`); this file reads the spec and its base case, keeps the journal
//! (`--journal`, design.csv's rows appended batch by batch, so that a killed search resumes where
//! it stopped), and writes the answer: design.csv, design.json, best-case.toml, traces.csv and
//! the figures.

use anyhow::{bail, Context, Result};
use clap::Args;
use std::io::Write as _;
use std::path::{Path, PathBuf};
use std::time::Instant;

use pcsim_core::analysis::record::RunOutput;
use pcsim_core::study::design::{search, Design, DesignResult, Evaluation, Local};

use crate::common::Ctx;
use crate::output::{write_file, write_manifest, OutDir};
use crate::progress::Progress;

#[derive(Args)]
pub struct DesignArgs {
    /// The search's spec (TOML with the tables base, variable, speed, objective, constraint,
    /// acceptance and budget; see docs/design.md).
    spec: PathBuf,
    /// Output directory (written as a whole when the search ends).
    #[arg(long, default_value = "design")]
    out: PathBuf,
    /// The journal: every evaluation, appended batch by batch [default: OUT-journal.csv]. A
    /// journal of the same search is resumed (its evaluations are not run again); one of
    /// another search is refused (see --fresh).
    #[arg(long, value_name = "FILE")]
    journal: Option<PathBuf>,
    /// Start afresh: remove the journal of an earlier search first.
    #[arg(long)]
    fresh: bool,
    /// Worker threads for the runs, at least 1 [default: all cores]. The answer does not depend
    /// on it.
    #[arg(long)]
    jobs: Option<usize>,
    /// Do not draw the figures.
    #[arg(long)]
    no_plot: bool,
    /// Evaluate each batch elsewhere (a cluster): PROGRAM is run as `PROGRAM BATCH_DIR SPEC N`
    /// after the batch's N designs are written to BATCH_DIR/designs.csv, and must leave each
    /// design's journal row in BATCH_DIR/row-I.csv (`pcsim design SPEC --task BATCH_DIR
    /// --task-index I` writes it; scripts/slurm/design_batch.sh runs them as a Slurm job
    /// array).
    #[arg(long, value_name = "PROGRAM")]
    evaluate_with: Option<PathBuf>,
    /// Where --evaluate-with's batch directories go [default: OUT-batches].
    #[arg(long, value_name = "DIR")]
    batches: Option<PathBuf>,
    /// Evaluate one design of a batch (what a cluster task runs): design --task-index of
    /// BATCH_DIR/designs.csv, its journal row written to BATCH_DIR/row-I.csv.
    #[arg(long, value_name = "BATCH_DIR", requires = "task_index")]
    task: Option<PathBuf>,
    /// The design's index in --task's batch.
    #[arg(long, value_name = "I", requires = "task")]
    task_index: Option<usize>,
}

/// A batch evaluated by another program (a Slurm job array): the designs written to a batch
/// directory, the program run, each design's journal row read back (and checked by the core:
/// fingerprint, values).
struct CommandEvaluator {
    program: PathBuf,
    spec: PathBuf,
    dir: PathBuf,
    next: std::sync::Mutex<usize>,
}

impl pcsim_core::study::design::Evaluator for CommandEvaluator {
    fn evaluate(
        &self,
        d: &Design,
        xs: &[Vec<f64>],
    ) -> std::result::Result<Vec<Evaluation>, String> {
        let k = {
            let mut n = self.next.lock().map_err(|e| e.to_string())?;
            *n += 1;
            *n - 1
        };
        let run = || -> Result<Vec<Evaluation>> {
            let dir = self.dir.join(format!("batch-{k}"));
            let _ = std::fs::remove_dir_all(&dir);
            std::fs::create_dir_all(&dir)
                .with_context(|| format!("cannot create {}", dir.display()))?;
            // The program and its tasks may run elsewhere (Slurm's --chdir): an absolute path.
            let dir = std::fs::canonicalize(&dir)?;
            let mut text = csv_line(
                &d.spec
                    .variables
                    .iter()
                    .map(|v| v.path.clone())
                    .collect::<Vec<_>>(),
            )?;
            for x in xs {
                text.extend(csv_line(
                    &x.iter().map(|v| format!("{v:?}")).collect::<Vec<_>>(),
                )?);
            }
            std::fs::write(dir.join("designs.csv"), text)?;
            let status = std::process::Command::new(&self.program)
                .arg(&dir)
                .arg(&self.spec)
                .arg(xs.len().to_string())
                .status()
                .with_context(|| format!("cannot run {}", self.program.display()))?;
            if !status.success() {
                bail!(
                    "{} {} failed ({status})",
                    self.program.display(),
                    dir.display()
                );
            }
            (0..xs.len())
                .map(|i| {
                    let p = dir.join(format!("row-{i}.csv"));
                    let t = crate::common::read_input(&p)
                        .with_context(|| format!("cannot read {}", p.display()))?;
                    let mut r = csv::ReaderBuilder::new().from_reader(t.as_bytes());
                    let got: Vec<String> = r.headers()?.iter().map(String::from).collect();
                    let row = r
                        .records()
                        .next()
                        .with_context(|| format!("{}: no row", p.display()))??;
                    let row: Vec<String> = row.iter().map(String::from).collect();
                    d.journal_read(&got, &row)
                        .map_err(|e| anyhow::anyhow!("{}: {e}", p.display()))
                })
                .collect()
        };
        run().map_err(|e| format!("{e:#}"))
    }
}

/// `--task DIR --task-index I`: one design of a batch, its journal row written beside it.
fn task(d: &Design, dir: &Path, i: usize) -> Result<i32> {
    let p = dir.join("designs.csv");
    let t =
        crate::common::read_input(&p).with_context(|| format!("cannot read {}", p.display()))?;
    let mut r = csv::ReaderBuilder::new().from_reader(t.as_bytes());
    let row = r
        .records()
        .nth(i)
        .with_context(|| format!("--task-index {i}: {} has no design {i}", p.display()))??;
    let x = row
        .iter()
        .map(|v| {
            v.parse::<f64>()
                .with_context(|| format!("{}: `{v}` is not a number", p.display()))
        })
        .collect::<Result<Vec<f64>>>()?;
    if x.len() != d.spec.variables.len() {
        bail!(
            "{}: design {i} has {} values for {} variables",
            p.display(),
            x.len(),
            d.spec.variables.len()
        );
    }
    let (e, _) = d.evaluate(&x, Some(1));
    let mut text = csv_line(&d.journal_header())?;
    text.extend(csv_line(&d.journal_row(&e))?);
    crate::output::write_file_atomic(&dir.join(format!("row-{i}.csv")), text)?;
    Ok(0)
}

/// The spec and its base case, checked.
fn load(path: &Path, ctx: &Ctx) -> Result<Design> {
    let text = crate::common::read_input(path)
        .with_context(|| format!("cannot read the design spec {}", path.display()))?;
    let dir = path.parent().unwrap_or(Path::new(".")).to_path_buf();
    let read = |f: &str| crate::common::read_input(&dir.join(f));
    let d = Design::from_spec_text(&text, &read)
        .map_err(|e| anyhow::anyhow!("{}: {e}", path.display()))?;
    Ok(d.with_run_budget(ctx.budget))
}

/// The journal's evaluations, if it exists (a row torn by a kill is dropped and the file cut
/// back to its last whole row).
fn read_journal(path: &Path, d: &Design) -> Result<Vec<Evaluation>> {
    if !path.exists() {
        return Ok(Vec::new());
    }
    let mut text = crate::common::read_input(path)
        .with_context(|| format!("cannot read the journal {}", path.display()))?;
    if !text.is_empty() && !text.ends_with('\n') {
        let keep = text.rfind('\n').map_or(0, |i| i + 1);
        eprintln!(
            "note: {}: its last row was cut short (a killed search): dropped",
            path.display()
        );
        text.truncate(keep);
        std::fs::write(path, &text).with_context(|| format!("cannot write {}", path.display()))?;
    }
    let mut r = csv::ReaderBuilder::new()
        .has_headers(false)
        .flexible(true)
        .from_reader(text.as_bytes());
    let mut rows = r.records();
    let Some(header) = rows.next() else {
        return Ok(Vec::new());
    };
    let header: Vec<String> = header?.iter().map(String::from).collect();
    let mut out = Vec::new();
    for (k, row) in rows.enumerate() {
        let row: Vec<String> = row?.iter().map(String::from).collect();
        out.push(d.journal_read(&header, &row).map_err(|e| {
            anyhow::anyhow!(
                "the journal {} (row {}): {e}; give --fresh to start the search afresh, or another --journal",
                path.display(),
                k + 1
            )
        })?);
    }
    Ok(out)
}

fn csv_line(fields: &[String]) -> Result<Vec<u8>> {
    let mut w = csv::WriterBuilder::new().from_writer(Vec::new());
    w.write_record(fields)?;
    w.into_inner().map_err(|e| anyhow::anyhow!("{e}"))
}

/// `OUT-suffix` beside the output directory `out` (the journal and the batches live outside it:
/// the output is replaced whole when a search ends).
fn beside(out: &Path, suffix: &str) -> PathBuf {
    let name = out.file_name().unwrap_or_default().to_string_lossy();
    out.with_file_name(format!("{name}-{suffix}"))
}

/// The journal of an earlier run of the search (empty: a new journal with its header), and the
/// journal open for appending.
fn open_journal(journal_path: &Path, d: &Design) -> Result<(Vec<Evaluation>, std::fs::File)> {
    let journal = read_journal(journal_path, d)?;
    if !journal.is_empty() {
        println!(
            "resuming from {} evaluation(s) in {}",
            journal.len(),
            journal_path.display()
        );
    }
    let mut file = std::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(journal_path)
        .with_context(|| format!("cannot open the journal {}", journal_path.display()))?;
    if journal.is_empty() {
        file.set_len(0)?;
        file.write_all(&csv_line(&d.journal_header())?)?;
    }
    Ok((journal, file))
}

/// The search's directory: its outputs, its case and spec, its figures and its manifest.
fn write_directory(
    a: &DesignArgs,
    d: &Design,
    result: &DesignResult,
    journal_path: &Path,
    out: &Path,
) -> Result<Vec<PathBuf>> {
    write_outputs(out, d, result, journal_path)?;
    write_file(&out.join("case.toml"), base_text(&a.spec, d)?)?;
    std::fs::copy(&a.spec, out.join("spec.toml"))
        .with_context(|| format!("cannot copy {}", a.spec.display()))?;
    let mut files = Vec::new();
    if !a.no_plot {
        files = crate::plot::design::redraw(out)?;
    }
    write_manifest(
        out,
        "design",
        crate::output::StudyManifest {
            fingerprint: Some(d.fingerprint().to_string()),
            figures: Some(
                (files.iter().filter_map(|f| f.file_name()))
                    .map(|f| f.to_string_lossy().to_string())
                    .collect(),
            ),
            ..Default::default()
        },
    )?;
    Ok(files)
}

pub fn design(a: DesignArgs, ctx: &Ctx) -> Result<i32> {
    crate::common::jobs_flag(a.jobs)?;
    let d = load(&a.spec, ctx)?;
    if let (Some(dir), Some(i)) = (&a.task, a.task_index) {
        return task(&d, dir, i);
    }
    let journal_path = a
        .journal
        .clone()
        .unwrap_or_else(|| beside(&a.out, "journal.csv"));
    // The output directory is locked for the whole search (a second search into it is refused),
    // before the journal is touched.
    let od = OutDir::begin(&a.out)?;
    if a.fresh && journal_path.exists() {
        std::fs::remove_file(&journal_path)
            .with_context(|| format!("cannot remove {}", journal_path.display()))?;
    }
    let (journal, mut file) = open_journal(&journal_path, &d)?;
    let b = &d.spec.budget;
    let pb = Progress::new(
        "design",
        b.evaluations as u64,
        ctx.progress,
        "design [{bar:40}] {pos}/{len} evaluations {elapsed_precise} eta {eta}",
    );
    let t0 = Instant::now();
    let mut write_error: Option<anyhow::Error> = None;
    let local = Local { jobs: a.jobs };
    let remote = match &a.evaluate_with {
        None => None,
        Some(program) => Some(CommandEvaluator {
            program: program.clone(),
            spec: std::fs::canonicalize(&a.spec)
                .with_context(|| format!("cannot find {}", a.spec.display()))?,
            dir: a
                .batches
                .clone()
                .unwrap_or_else(|| beside(&a.out, "batches")),
            next: std::sync::Mutex::new(0),
        }),
    };
    let evaluator: &dyn pcsim_core::study::design::Evaluator = match &remote {
        Some(r) => r,
        None => &local,
    };
    let result = search(&d, journal, evaluator, a.jobs, &mut |fresh| {
        for e in fresh {
            let line = csv_line(&d.journal_row(e)).and_then(|l| Ok(file.write_all(&l)?));
            if let Err(err) = line {
                write_error.get_or_insert(err);
            }
            if e.phase == "search" {
                pb.inc();
            }
        }
        // Each batch reaches the disk before the next one runs.
        let _ = file.sync_data();
        write_error.is_none()
    })
    .map_err(|e| anyhow::anyhow!("{}: {e}", a.spec.display()))?;
    pb.finish();
    if let Some(e) = write_error {
        return Err(e.context(format!(
            "cannot append to the journal {}",
            journal_path.display()
        )));
    }
    let wall = t0.elapsed().as_secs_f64();
    print(&d, &result, wall);
    let files = write_directory(&a, &d, &result, &journal_path, od.path())?;
    let shown = od.in_target(&files);
    od.commit()?;
    let unconfirmed = result.confirmation_error(&d);
    println!(
        "wrote {}/design.csv, design.json, traces.csv{}",
        a.out.display(),
        if result.recommended.is_some() && unconfirmed.is_none() {
            ", best-case.toml"
        } else {
            ""
        }
    );
    if !shown.is_empty() {
        crate::plot::report(&shown);
    }
    if let Some(e) = unconfirmed {
        anyhow::bail!("{e}");
    }
    Ok(if result.recommended.is_some() { 0 } else { 1 })
}

fn fmt(x: Option<f64>) -> String {
    x.map_or("—".into(), |x| format!("{x:.4}"))
}

/// The answer of a search without a best design: the base design is feasible (no improvement),
/// or nothing is (the least violating design, or the first error).
fn print_no_best(r: &DesignResult, names: &[&str]) {
    let searched = r.evaluations.iter().filter(|e| e.phase == "search").count();
    if let Some(b) = r.base.as_ref().filter(|b| b.feasible()) {
        println!(
            "NO IMPROVEMENT FOUND: none of the {searched} designs searched meets the constraints, the base design does (objective {}); no design is recommended and no best-case.toml is written.",
            fmt(b.objective)
        );
        return;
    }
    println!(
        "INFEASIBLE: none of the {searched} designs evaluated meets the constraints{}; there is no best design.",
        match r.stop {
            pcsim_core::study::design::StopReason::WallTime => " (the search stopped at its wall time: more time may find one)",
            _ => "",
        }
    );
    if let Some(li) = r.least_violating {
        let e = &r.evaluations[li];
        println!("  the least violating (evaluation {li}):");
        for (n, x) in names.iter().zip(&e.x) {
            println!("    {n} = {x}");
        }
        println!("    violated: {}", e.violated.join("; "));
    } else {
        println!(
            "  every run failed; the first error: {}",
            r.evaluations
                .first()
                .and_then(|e| e.error.clone())
                .unwrap_or_default()
        );
    }
}

fn print(d: &Design, r: &DesignResult, wall: f64) {
    println!(
        "design search: {} evaluations asked ({} run now, the rest from the journal), stopped: {:?}, {:.1} s wall",
        r.asked, r.run_now, r.stop, wall
    );
    let names: Vec<&str> = d.spec.variables.iter().map(|v| v.path.as_str()).collect();
    let Some(bi) = r.best else {
        print_no_best(r, &names);
        return;
    };
    let e = &r.evaluations[bi];
    if r.recommended.is_none() {
        println!(
            "NO IMPROVEMENT FOUND: none of the designs evaluated beats the base design (objective {}); no design is recommended and no best-case.toml is written (search a wider range or with more evaluations).",
            r.base.as_ref().map_or("—".into(), |b| fmt(b.objective))
        );
    }
    println!(
        "{} (evaluation {bi}), objective {}:",
        if r.recommended.is_some() {
            "best design"
        } else {
            "the best evaluated, not recommended"
        },
        fmt(e.objective)
    );
    for (n, x) in names.iter().zip(&e.x) {
        println!("  {n} = {x}");
    }
    if let Some(b) = &r.base {
        println!(
            "  the base design: objective {}{}",
            fmt(b.objective),
            if b.feasible() { "" } else { " (infeasible)" }
        );
    }
    if let Some((_, same)) = &r.confirmation {
        println!(
            "  confirmation run: {}",
            if *same {
                "the same statistics as the search's"
            } else {
                "DIFFERENT from the search's (a bug: please report it)"
            }
        );
    }
    for (s, sp) in d.spec.speeds.iter().enumerate() {
        let cols: Vec<String> = d
            .needs
            .iter()
            .zip(&e.values[s])
            .map(|(n, v)| format!("{} {}", n.label(), fmt(*v)))
            .collect();
        println!("  at {} km/h: {}", sp.kmh, cols.join(", "));
    }
    println!("sensitivity (objective at ± the step):");
    for s in &r.sensitivity {
        println!(
            "  {} ± {}: {} → {}, {} → {}",
            s.path,
            s.step,
            s.below.map_or("at bound".into(), |x| x.to_string()),
            fmt(s.objective_below),
            s.above.map_or("at bound".into(), |x| x.to_string()),
            fmt(s.objective_above),
        );
        let better = |o: Option<f64>, f: Option<bool>| {
            f == Some(true) && o.zip(e.objective).is_some_and(|(o, b)| o < b)
        };
        if better(s.objective_below, s.feasible_below)
            || better(s.objective_above, s.feasible_above)
        {
            println!("    a step away is better: the search has not converged in this variable (give it more evaluations)");
        }
        if let Some(b) = &s.at_bound {
            println!("    at its {b} bound: the optimum may lie beyond the range searched");
        }
    }
    if !r.constraints.is_empty() {
        println!("constraints at the best design:");
        for c in &r.constraints {
            println!(
                "  {:<44} value {:>10}  limit {:>10}  margin {:>10}  {}",
                c.name,
                fmt(c.value),
                fmt(c.limit),
                fmt(c.margin),
                if c.active { "ACTIVE" } else { "inactive" }
            );
        }
    }
}

/// The force traces of the base and the best design over the analysis section, every speed and
/// pantograph: `design,speed_kmh,pantograph,position_m,force_n`.
fn traces(d: &Design, r: &DesignResult) -> String {
    let mut s = String::from("design,speed_kmh,pantograph,position_m,force_n\n");
    let mut add = |name: &str, runs: &[Option<RunOutput>]| {
        for (sp, run) in d.spec.speeds.iter().zip(runs) {
            let Some(run) = run else { continue };
            let [a, b] = run.analysis_m;
            for p in &run.pantographs {
                for (x, f) in p.position_m.iter().zip(&p.force_n) {
                    if (a..=b).contains(x) {
                        s += &format!("{name},{},{},{x},{f}\n", sp.kmh, p.name);
                    }
                }
            }
        }
    };
    add("base", &r.base_runs);
    add("best", &r.best_runs);
    s
}

/// The base case as given (every value with its source), for the report's provenance: the
/// preset's text or the file's (the spec's `set` values are in design.json's fingerprint and
/// the spec).
fn base_text(spec: &Path, d: &Design) -> Result<String> {
    match (&d.spec.base.preset, &d.spec.base.file) {
        (Some(p), _) => Ok(pcsim_core::presets::find(p)?.toml.to_string()),
        (None, Some(f)) => {
            let p = spec.parent().unwrap_or(Path::new(".")).join(f);
            crate::common::read_input(&p).with_context(|| format!("cannot read {}", p.display()))
        }
        (None, None) => unreachable!("the spec names its base"),
    }
}

fn write_outputs(out: &Path, d: &Design, r: &DesignResult, journal: &Path) -> Result<()> {
    std::fs::copy(journal, out.join("design.csv"))
        .with_context(|| format!("cannot copy {}", journal.display()))?;
    let best = r.recommended.map(|i| &r.evaluations[i]);
    let v = r.to_json(d);
    write_file(
        &out.join("design.json"),
        serde_json::to_string_pretty(&v)? + "\n",
    )?;
    write_file(&out.join("traces.csv"), traces(d, r))?;
    if let Some(e) = best.filter(|_| r.confirmation_error(d).is_none()) {
        let case = d
            .case_at(&e.x, d.base.run.speed_kmh)
            .map_err(|e| anyhow::anyhow!("the best design's case: {e}"))?;
        let mut text = String::from(
            "# The best design of a pcsim design search (design.json); the base case with\n",
        );
        for (v, x) in d.spec.variables.iter().zip(&e.x) {
            text += &format!("# {} = {x}\n", v.path);
        }
        text += &case.to_toml_string();
        write_file(&out.join("best-case.toml"), text)?;
    }
    Ok(())
}
