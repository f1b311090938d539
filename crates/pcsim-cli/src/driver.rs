//! The one driver of every study (issue 52): a command fills the study's spec from its
//! arguments and hands it here. In order: the study's check (before anything is written), the
//! output directory (staged under its lock), the case as given, the progress line, the run, the
//! study's files, the manifest, the figures, the commit, the answer on the terminal, the report,
//! and the exit status: the outputs are always written, then a study whose answer lists failures
//! (events not accepted, runs not made) is refused with them (exit 2).

use anyhow::Result;
use pcsim_core::study::Study;
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
pub fn drive<S: Study>(study: &S, d: Drive<'_>, ctx: &Ctx) -> Result<S::Output> {
    let kind = S::KIND;
    study.check()?;
    let od = OutDir::begin(d.out)?;
    let dir = od.path();
    if let Some(t) = d.case_text {
        write_file(&dir.join("case.toml"), t)?;
    }
    let pb = Progress::new(
        kind.name(),
        study.work() as u64,
        ctx.progress,
        &format!(
            "{} [{{bar:40}}] {{pos}}/{{len}} {} {{elapsed_precise}} eta {{eta}}",
            kind.name(),
            d.unit
        ),
    );
    let output = study.run(&|| pb.inc());
    pb.finish();
    let output = output?;
    let files = study.files(&output);
    for f in &files {
        write_file(&dir.join(&f.name), &f.bytes)?;
    }
    write_manifest(dir, kind.name(), d.manifest)?;
    let answer = S::answer(&output);
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
    println!("wrote {}", written(d.out, &files));
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
    Ok(output)
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
