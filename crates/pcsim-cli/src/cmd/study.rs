//! `pcsim study SPEC`: a study written as a spec file (its `kind` names it), or the embedded
//! default spec of a study named instead of a file. The command reads the file, hands
//! the core a case loader (a preset's name, or a case file beside the spec) and drives the study
//! the core's table builds ([`pcsim_core::study::from_spec`]); it knows no study by name.

use anyhow::{bail, Result};
use clap::Args;
use pcsim_core::error::CaseError;
use pcsim_core::study::{from_spec, spec_study, SPEC_STUDIES};
use std::cell::RefCell;
use std::path::{Path, PathBuf};

use crate::common::Ctx;

#[derive(Args)]
pub struct StudyArgs {
    /// A study's spec file (TOML; its `kind` names the study), or a study's name to run its
    /// embedded default spec (`pcsim schema` lists the studies as NAME-spec).
    spec: String,
    /// Output directory [default: out/KIND].
    #[arg(long)]
    out: Option<PathBuf>,
    /// No figures.
    #[arg(long)]
    no_plot: bool,
    /// Write report.html too.
    #[arg(long)]
    report: bool,
    /// Print the spec it would run (the embedded default's text) and stop.
    #[arg(long)]
    show: bool,
}

/// The spec's text and the folder its case files are read from.
fn spec_text(spec: &str) -> Result<(String, PathBuf)> {
    let p = Path::new(spec);
    if p.is_file() {
        let text = crate::common::read_input(p)
            .map_err(|e| anyhow::anyhow!("cannot read {}: {e}", p.display()))?;
        let dir = p.parent().map(Path::to_path_buf).unwrap_or_default();
        return Ok((text, dir));
    }
    match spec_study(spec) {
        Some(row) => Ok((row.default_spec.to_string(), PathBuf::from("."))),
        None => {
            let names: Vec<&str> = SPEC_STUDIES.iter().map(|s| s.kind.name()).collect();
            bail!(
                "{spec}: neither a spec file nor a study's name (one of: {})",
                names.join(", ")
            )
        }
    }
}

pub fn study(a: StudyArgs, ctx: &Ctx) -> Result<i32> {
    let (text, dir) = spec_text(&a.spec)?;
    if a.show {
        print!("{text}");
        return Ok(0);
    }
    let case_text = RefCell::new(None::<String>);
    let load = |name: &str| -> Result<(pcsim_core::input::Case, String), CaseError> {
        let path = dir.join(name);
        let file = (path.is_file())
            .then(|| (path.display().to_string(), crate::common::read_input(&path)));
        let (case, t) = pcsim_core::study::case_named(name, file)?;
        *case_text.borrow_mut() = Some(t.clone());
        Ok((case, t))
    };
    let study = from_spec(&text, &load)?;
    let kind = study.kind();
    let out = a
        .out
        .unwrap_or_else(|| PathBuf::from("out").join(kind.name()));
    let mut manifest = crate::output::StudyManifest::default();
    if let Some((name, speed, section)) = study.case_label() {
        manifest.case_name = Some(name);
        manifest.speed_kmh = Some(speed);
        manifest.analysis_m = Some(section);
    }
    let case_text = case_text.borrow().clone();
    crate::driver::drive_any(
        study.as_ref(),
        crate::driver::Drive {
            out: &out,
            case_text: case_text.as_deref(),
            spec_text: Some(&text),
            plot: !a.no_plot,
            report: a.report,
            manifest,
            unit: "runs",
        },
        ctx,
    )?;
    Ok(0)
}
