//! `pcsim validate`: a validation's runs side by side, and the table of value against range.

use anyhow::{Context, Result};
use clap::Args;
use pcsim_core::study::sweeps::validation_runs;
use pcsim_core::study::validate::{ValidationPlan, VALIDATIONS};
use pcsim_core::CaseError;
use std::path::PathBuf;

use crate::common::{run_with_progress, Ctx};

#[derive(Args)]
pub struct ValidateArgs {
    /// Validation to run (en50318-2002, the default, or seed-table1), or a case file (.toml) to
    /// run against a validation's targets instead of its preset: the en50318-2002 ranges, or
    /// those of --targets.
    #[arg(value_name = "NAME|CASE")]
    name: Option<String>,
    /// Ranges from your own targets file instead (the format of data/validation-targets.toml:
    /// one table naming its preset; `[]` where a range is not known, reported as missing; a
    /// template for the EN 50318:2018 structure: data/targets-en50318-2018-template.toml).
    /// With a case file, the case runs instead of the file's preset.
    #[arg(long, value_name = "FILE")]
    targets: Option<PathBuf>,
    /// Print JSON instead of a table.
    #[arg(long)]
    json: bool,
    /// Exit with status 1 when a row fails (by default the exit status is 0 whenever the runs
    /// complete: rows out of reach with public data are expected, see docs/validation.md).
    #[arg(long)]
    strict: bool,
    /// Verify each run: again refined (twice the modes, half the time step) and with the contact
    /// twice as stiff (`pcsim run --verify`); each row gains its value and verdict under both,
    /// and the rows whose verdict the refinement changes, or whose value is not converged to its
    /// tolerance, are listed as not established.
    #[arg(long)]
    verify: bool,
}

/// The default validation.
const DEFAULT: &str = "en50318-2002";

/// What the positional argument names: a validation pcsim knows, or a case file.
fn case_path(name: &str) -> Option<PathBuf> {
    let known = VALIDATIONS.iter().any(|v| v.name == name);
    let path = PathBuf::from(name);
    (!known && (name.ends_with(".toml") || path.is_file())).then_some(path)
}

/// The plan: a validation, a targets file, either on a user's case.
fn plan_of(a: &ValidateArgs) -> Result<ValidationPlan> {
    let case = a.name.as_deref().and_then(case_path);
    let plan = match (&a.targets, a.name.as_deref(), case.is_some()) {
        (Some(path), None, _) | (Some(path), Some(_), true) => {
            let text = crate::common::read_input(path)
                .with_context(|| format!("cannot read {}", path.display()))?;
            let on = match &case {
                Some(c) => Some((
                    crate::common::load_case(Some(c), None)?,
                    c.display().to_string(),
                )),
                None => None,
            };
            return ValidationPlan::from_targets_on(
                &text,
                &path.display().to_string(),
                on.as_ref().map(|(c, l)| (c.clone(), l.as_str())),
            )
            .with_context(|| format!("in {}", path.display()));
        }
        (Some(_), Some(name), false) => anyhow::bail!(
            "give a validation name ({name}) or --targets, not both (a case file may go with --targets)"
        ),
        (None, Some(name), false) => ValidationPlan::new(name)
            .context("the argument is a validation's name or a case file (.toml)")?,
        (None, _, _) => ValidationPlan::new(DEFAULT)?,
    };
    Ok(match case {
        Some(path) => {
            let case = crate::common::load_case(Some(&path), None)?;
            plan.on_case(case, &path.display().to_string())?
        }
        None => plan,
    })
}

pub fn validate(a: ValidateArgs, ctx: &Ctx) -> Result<i32> {
    let plan = plan_of(&a)?;
    // Each run is single-threaded and deterministic; the runs go side by side.
    let (runs, mut report) = validation_runs(&plan, Some(plan.cases.len().max(1)), &|case| {
        let label = format!("{} km/h", case.run.speed_kmh);
        run_with_progress(case, &[], &label, ctx)
            .map(|r| r.0)
            .map_err(|e| CaseError::Parse(format!("{e:#}")).into())
    })?;
    if a.verify {
        let pb =
            crate::progress::Progress::run("verify (refined and stiff-contact runs)", ctx.progress);
        let outs: Vec<_> = runs.iter().map(|(o, _)| o.clone()).collect();
        plan.verify(
            &outs,
            &mut report,
            &ctx.budget,
            Some(plan.cases.len().max(1)),
        )?;
        pb.finish();
    }
    if a.json {
        println!("{}", serde_json::to_string_pretty(&report)?);
    } else {
        println!(
            "{}, on {} (ranges from {})",
            plan.title, plan.runs_on, plan.ranges_from
        );
        for (c, &k) in report.cases.iter().zip(&plan.run_of_target) {
            let (out, wall) = &runs[k];
            let who = who(c);
            println!(
                "\n{} km/h{who}  ({:.1} s simulated in {wall:.1} s)",
                c.speed_kmh,
                out.simulated_time_s()
            );
            print_rows(c);
        }
        let missing: usize = report.cases.iter().map(|c| c.missing.len()).sum();
        if missing > 0 {
            println!(
                "\n{missing} ranges are missing from {}: pcsim does not invent them; fill them in from your copy of the standard.",
                plan.ranges_from
            );
        }
        let rows = report.cases.iter().flat_map(|c| &c.rows);
        let n = rows.clone().count();
        let p = rows.clone().filter(|r| r.pass).count();
        let pp = rows.clone().filter(|r| r.paper_pass == Some(true)).count();
        if rows.clone().any(|r| r.paper_value.is_some()) {
            println!("\n{p} of {n} rows pass (the paper's own values: {pp} of {n}). See docs/validation.md for the reasons.");
        } else {
            println!("\n{p} of {n} rows pass. Rows out of reach with the public data are explained in docs/validation.md.");
        }
        if a.verify {
            print_verification(&report);
        }
        if !a.strict {
            println!(
                "(exit status 0: the runs completed; add --strict for status 1 when a row fails)"
            );
        }
    }
    Ok(if a.strict && !report.all_pass { 1 } else { 0 })
}

/// A case's rows: the value (and the paper's, when the targets give it) against its range.
fn print_rows(c: &pcsim_core::study::validate::CaseRows) {
    let paper = c.rows.iter().any(|r| r.paper_value.is_some());
    if paper {
        println!(
            "  {:<26} {:>8} {:>6}  {:>8} {:>6}  {:>14} unit",
            "quantity", "pcsim", "", "paper", "", "range"
        );
    } else {
        println!(
            "  {:<26} {:>8} {:>6}  {:>14} unit",
            "quantity", "value", "result", "range"
        );
    }
    for r in &c.rows {
        let range = format!("[{}, {}]", r.range[0], r.range[1]);
        match (r.paper_value, r.paper_pass) {
            (Some(pv), Some(pp)) => println!(
                "  {:<26} {:>8.1} {:>6}  {:>8.1} {:>6}  {:>14} {}",
                r.quantity,
                r.value,
                mark(r.pass),
                pv,
                mark(pp),
                range,
                r.unit
            ),
            _ => println!(
                "  {:<26} {:>8.1} {:>6}  {:>14} {}",
                r.quantity,
                r.value,
                mark(r.pass),
                range,
                r.unit
            ),
        }
    }
    for u in &c.missing {
        println!(
            "  {:<26} {:>8.1} {:>6}  {:>14} {}",
            u.quantity, u.value, "-", "no range given", u.unit
        );
    }
}

/// The rows under the verification: each value refined and with the stiffer contact, with
/// their verdicts, and the rows not established.
fn print_verification(report: &pcsim_core::study::validate::ValidationReport) {
    if let Some(v) = report.verification.first() {
        println!(
            "\nverification: refined {} modes/wire, Δt {} s; model check: contact {} N/m at Δt {} s",
            v.refined.modes_per_wire,
            v.refined.dt_s,
            v.stiff_contact.contact_stiffness_n_per_m,
            v.stiff_contact.dt_s
        );
    }
    for c in &report.cases {
        let who = who(c);
        println!(
            "  {} km/h{who}\n  {:<26} {:>8} {:>6}  {:>8} {:>6}  {:>10} {:>6}  established",
            c.speed_kmh, "quantity", "value", "", "refined", "", "stiff k", ""
        );
        for r in &c.rows {
            if let Some(v) = &r.verification {
                println!(
                    "  {:<26} {:>8.2} {:>6}  {:>8.2} {:>6}  {:>10.2} {:>6}  {}",
                    r.quantity,
                    r.value,
                    mark(r.pass),
                    v.refined,
                    mark(v.refined_pass),
                    v.stiff_contact,
                    mark(v.stiff_contact_pass),
                    if v.established { "yes" } else { "NO" }
                );
            }
        }
    }
    if report.not_established.is_empty() {
        println!("  every verdict is established by the verification");
    }
    for n in &report.not_established {
        println!("  NOT ESTABLISHED: {n}");
    }
}

/// A case's pantograph as the table heads it (`, trailing pantograph`; empty for one).
fn who(c: &pcsim_core::study::validate::CaseRows) -> String {
    c.pantograph
        .as_deref()
        .map(|p| format!(", {p} pantograph"))
        .unwrap_or_default()
}

/// A verdict as the table prints it.
fn mark(pass: bool) -> &'static str {
    if pass {
        "pass"
    } else {
        "FAIL"
    }
}
