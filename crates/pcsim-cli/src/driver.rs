//! The one driver of every study (issue 52): a command fills the study's spec from its
//! arguments and hands it here. In order: the study's check (before anything is written), the
//! output directory (staged under its lock), the case as given, the progress line, the run, the
//! study's files, its answer (`answer.json`) and declared figures (`figures.json`), the manifest, the figures, the commit, the answer on the terminal, the report,
//! and the exit status: the outputs are always written, then a study whose answer lists failures
//! (events not accepted, runs not made) is refused with them (exit 2).

use anyhow::Result;
use pcsim_core::error::{CaseError, SimError};
use pcsim_core::study::{AnyStudy, Ran, Study, StudyKind};
use std::path::Path;

use crate::common::Ctx;
use crate::output::{write_file, write_manifest, OutDir};
use crate::progress::Progress;

/// What a command adds to a study's drive.
pub struct Drive<'a> {
    /// The output directory.
    pub out: &'a Path,
    /// The case as given (every value with its source), written as `case.toml`.
    pub case_text: Option<&'a str>,
    /// A spec-file study's spec as given, written as `study.toml` (beside the case it names,
    /// written as `case.toml`).
    pub spec_text: Option<&'a str>,
    /// Draw the figures.
    pub plot: bool,
    /// Write `report.html` (implies the figures).
    pub report: bool,
    /// The manifest's own fields beside its kind (a sweep's fingerprint, the flags given).
    pub manifest: crate::output::StudyManifest,
    /// What a unit of work is called on the progress line (`realisations`).
    pub unit: &'a str,
}

/// Drive `study` into `d.out`: returns its output (for the command's own lines).
pub fn drive<S: Study + Sync>(study: &S, d: Drive<'_>, ctx: &Ctx) -> Result<S::Output> {
    let mut kept = None;
    let mut run = |done: &(dyn Fn() + Sync)| {
        let output = study.run(done)?;
        let ran = Ran::of(study, &output);
        kept = Some(output);
        Ok(ran)
    };
    let (kind, work) = (S::KIND, study.work());
    drive_parts(kind, study.check(), work, &mut run, d, ctx)?;
    kept.ok_or_else(|| anyhow::anyhow!("the {kind} study gave no output"))
}

/// Drive a study whose output type is erased (a spec file's, [`pcsim_core::study::from_spec`]):
/// the same stages as [`drive`].
pub fn drive_any(study: &dyn AnyStudy, d: Drive<'_>, ctx: &Ctx) -> Result<Ran> {
    let mut run = |done: &(dyn Fn() + Sync)| study.run_erased(done);
    drive_parts(study.kind(), study.check(), study.work(), &mut run, d, ctx)
}

/// A study's run, its output turned into its files, answer and figures.
type RunParts<'a> = dyn FnMut(&(dyn Fn() + Sync)) -> Result<Ran, SimError> + 'a;

/// The driver's stages, in order, for any study.
fn drive_parts(
    kind: StudyKind,
    check: Result<(), CaseError>,
    work: usize,
    run: &mut RunParts<'_>,
    d: Drive<'_>,
    ctx: &Ctx,
) -> Result<Ran> {
    check?;
    let od = OutDir::begin(d.out)?;
    let dir = od.path();
    if let Some(t) = d.case_text {
        write_file(&dir.join("case.toml"), t)?;
    }
    if let Some(t) = d.spec_text {
        write_file(&dir.join("study.toml"), t)?;
    }
    let pb = Progress::new(
        kind.name(),
        work as u64,
        ctx.progress,
        &format!(
            "{} [{{bar:40}}] {{pos}}/{{len}} {} {{elapsed_precise}} eta {{eta}}",
            kind.name(),
            d.unit
        ),
    );
    let ran = run(&|| pb.inc());
    pb.finish();
    let ran = ran?;
    for f in &ran.files {
        write_file(&dir.join(&f.name), &f.bytes)?;
    }
    write_file(
        &dir.join("answer.json"),
        serde_json::to_string_pretty(&ran.answer)? + "\n",
    )?;
    if !ran.figures.is_empty() {
        write_file(
            &dir.join("figures.json"),
            serde_json::to_string(&ran.figures)? + "\n",
        )?;
    }
    write_manifest(dir, kind.name(), d.manifest)?;
    let answer = &ran.answer;
    println!("{}", answer.headline);
    for (what, value) in &answer.rows {
        println!("  {what} {value}");
    }
    let figures = if d.plot || d.report {
        od.in_target(&crate::plot::redraw_kind(dir, kind)?)
    } else {
        Vec::new()
    };
    od.commit()?;
    println!("wrote {}", written(d.out, &ran.files));
    if !figures.is_empty() {
        crate::plot::report(&figures);
    }
    if d.report {
        println!("report: {}", crate::report::write(d.out)?.display());
    }
    for w in &answer.warnings {
        eprintln!("warning: {w}");
    }
    for f in &answer.failures {
        eprintln!("error: {f}");
    }
    if let Some(first) = answer.failures.first() {
        anyhow::bail!(
            "the {} study is refused: {first} (its outputs are written)",
            kind.name()
        );
    }
    Ok(ran)
}

/// The files written, as the terminal names them (`out/a.csv and out/b.json`).
fn written(out: &Path, files: &[pcsim_core::study::StudyFile]) -> String {
    let names: Vec<String> = files
        .iter()
        .map(|f| crate::common::shown(out, &f.name))
        .collect();
    match names.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        Some((last, _)) => last.clone(),
        None => String::new(),
    }
}
