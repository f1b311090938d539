//! The report (`pcsim report DIR`, `--report`): one self-contained `report.html` of an
//! output directory, its own module beside `plot/` (issue 52); a study's part is dispatched on
//! its kind (`StudyKind`, matched exhaustively) and opens with its typed answer. A run's
//! output directory (issue 22, item 1; runs first): the case with every value and its source,
//! the run's statistics and warnings, the passages through the overlaps, the droppers, every
//! figure inline (SVG, rebuilt from a whitelist: `svg_safe.rs`) with its caption, the versions
//! and the command line. No script, no network: the page needs nothing but itself, and its
//! Content-Security-Policy forbids scripts and every outside resource. A file changed after the
//! run (its hash is no longer the manifest's) is said at the top of the page.

use anyhow::{Context, Result};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::output::{add_to_manifest, read_complete_manifest};
use pcsim_core::analysis::report::{PantographSummary, RunSummary};
use pcsim_core::analysis::sensitivity::Sensitivity;
use pcsim_core::analysis::verify::Verification;
use pcsim_core::study::compare::{CompareOutput, CompareStudy};
use pcsim_core::study::design::DesignRecord;
use pcsim_core::study::montecarlo::{MonteCarloOutput, MonteCarloStudy};
use pcsim_core::study::realtime::{RealtimeOutput, RealtimeStudy};
use pcsim_core::study::{Answer, Study, StudyKind};

/// Escape text for HTML.
fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// The command line that wrote a directory, as its manifest recorded it.
fn command(m: &crate::output::Manifest) -> &str {
    Some(m.record.command.as_str())
        .filter(|c| !c.is_empty())
        .unwrap_or("(command line not recorded)")
}

/// A number as a table shows it.
fn num(v: &serde_json::Value) -> String {
    match v {
        serde_json::Value::Number(n) => match n.as_f64() {
            Some(x) if x.fract() != 0.0 && x.abs() < 1e6 => format!("{x:.3}"),
            _ => n.to_string(),
        },
        serde_json::Value::Null => "—".into(),
        serde_json::Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// A number of a typed output as a table shows it (none, or not finite: "—"), the same text
/// as [`num`] gives the number written to JSON.
fn numf(x: Option<f64>) -> String {
    num(&serde_json::json!(x))
}

/// A table of `head` columns and `rows`.
fn table(out: &mut String, caption: &str, head: &[&str], rows: &[Vec<String>]) {
    let _ = write!(out, "<table><caption>{}</caption><thead><tr>", esc(caption));
    for h in head {
        let _ = write!(out, "<th>{}</th>", esc(h));
    }
    out.push_str("</tr></thead><tbody>");
    for r in rows {
        out.push_str("<tr>");
        for c in r {
            let _ = write!(out, "<td>{}</td>", esc(c));
        }
        out.push_str("</tr>");
    }
    out.push_str("</tbody></table>\n");
}

/// The caption of a figure, from its file's stem.
fn caption(stem: &str) -> String {
    if let Some(p) = stem.strip_prefix("contact_force_") {
        format!("Contact force of the {p} pantograph along the track: raw and 0–20 Hz (min–max per pixel column); supports dashed, analysis section and overlaps shaded.")
    } else if stem == "contact_height" {
        "Contact-point height above the contact wire's design height at the supports, each pantograph.".into()
    } else if let Some(p) = stem.strip_prefix("lateral_") {
        format!("Lateral position of the contact point on the {p} pantograph's head.")
    } else if let Some(p) = stem.strip_prefix("wear_") {
        format!("Where the contact point runs on the {p} pantograph's strip.")
    } else if stem == "eva_window_energy" {
        "Window energy E(d_e) (Eq. 21) against the window length, with the two EVA criteria marked (the step criterion and 99 % of the total).".into()
    } else if stem == "eva_length_vs_speed" {
        "EVA length against speed by both criteria.".into()
    } else if let Some(k) = stem.strip_prefix("eva_density_") {
        format!(
            "Vibration-energy density (Eq. 20) along the catenary, {}.",
            k.replace('_', ", ")
        )
    } else if stem == "window_length" {
        "The real-time window's length by accuracy against the full model, beside the energy-based lengths; values above the axis are named in the note.".into()
    } else if stem.starts_with("window_errors") {
        "The window's σ error against the full model, by window length.".into()
    } else if let Some(k) = stem.strip_prefix("compare_") {
        format!("The run beside the measurement: {k} (0–20 Hz, aligned).")
    } else if stem == "design_progress" {
        "The design search: the objective of each feasible design over the evaluations, and the best so far.".into()
    } else if let Some(v) = stem.strip_prefix("design_force_") {
        format!("Contact force at {v} km/h along the analysis section: the best design against the base design, each pantograph.")
    } else if stem == "droppers" {
        "Every dropper along the line: Miner's damage of the passage (or, without an S–N curve, its largest tension range); overlaps shaded.".into()
    } else {
        stem.replace('_', " ")
    }
}

/// Write `report.html` into the run's directory `dir` and list it in the manifest.
pub fn write(dir: &Path) -> Result<PathBuf> {
    let m = read_complete_manifest(dir)?;
    if m.kind != StudyKind::Run {
        return write_study(dir, &m);
    }
    let summary_text = std::fs::read_to_string(dir.join("summary.json"))
        .with_context(|| format!("cannot read {}", dir.join("summary.json").display()))?;
    // Read back through the type that wrote it (issue 52: no lookup by key).
    let summary: RunSummary =
        serde_json::from_str(&summary_text).context("summary.json is not a run's summary")?;
    let name = summary.case_name.as_str();
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">{CSP}<title>pcsim report: {}</title>\n<style>{}</style></head><body>\n",
        esc(name),
        STYLE
    );
    let _ = write!(
        h,
        "<h1>{} at {} km/h</h1>\n<p class=\"meta\">pcsim {} · kernels {} · <code>{}</code></p>\n",
        esc(name),
        n(&summary.speed_kmh),
        esc(&m.version),
        esc(&summary.kernels),
        esc(command(&m))
    );
    edited_box(&mut h, dir, &m);
    // The run's error-level events, above everything else.
    errors_box(&mut h, &summary.errors);
    warnings_section(&mut h, &summary.warnings);
    // The answer first (issue 42, item 6): the statistics, the verdicts and their evidence;
    // then the figures; then the tables of the set-up and the details.
    statistics_section(&mut h, &summary.pantographs);
    assessment(&mut h, dir, &summary_text)?;
    if let Some(v) = &summary.verification {
        verification_section(&mut h, v);
    }
    if let Some(s) = &summary.sensitivity {
        sensitivity_section(&mut h, s);
    }
    figures(&mut h, dir, &m.files)?;
    run_section(&mut h, &summary);
    overlaps_section(&mut h, &summary.pantographs);
    hard_spots_section(&mut h, &summary.pantographs);
    droppers_section(&mut h, dir, summary.analysis_section_m);
    provenance(&mut h, dir, &summary.overrides)?;
    finish(dir, h)
}

/// A typed value as a table shows it ([`num`] of its JSON form: the bytes the report gave when it
/// read summary.json by key).
fn n<T: serde::Serialize + ?Sized>(x: &T) -> String {
    num(&serde_json::to_value(x).unwrap_or_default())
}

/// The run's warnings (above the answer: they qualify it).
fn warnings_section(h: &mut String, warnings: &[String]) {
    if warnings.is_empty() {
        h.push_str("<p>No warnings.</p>\n");
    } else {
        h.push_str("<h3>Warnings</h3><ul>");
        for w in warnings {
            let _ = write!(h, "<li>{}</li>", esc(w));
        }
        h.push_str("</ul>\n");
    }
}

/// The run's set-up and counters.
fn run_section(h: &mut String, s: &RunSummary) {
    let rows = vec![
        vec!["simulated_time_s".to_string(), n(&s.simulated_time_s)],
        vec!["analysis_section_m".to_string(), n(&s.analysis_section_m)],
        vec!["modes_per_wire".to_string(), n(&s.modes_per_wire)],
        vec!["dt_s".to_string(), n(&s.dt_s)],
        vec!["max_slack_droppers".to_string(), n(&s.max_slack_droppers)],
        vec![
            "steps_with_slack_percent".to_string(),
            n(&s.steps_with_slack_percent),
        ],
        vec![
            "contact_wire_tension_n".to_string(),
            n(&s.contact_wire_tension_n),
        ],
    ];
    h.push_str("<h2>The run</h2>\n");
    table(h, "Set-up and run", &["quantity", "value"], &rows);
}

/// The EN 50318 statistics, one column per pantograph.
fn statistics_section(h: &mut String, pans: &[PantographSummary]) {
    h.push_str("<h2 id=\"answer\">EN 50318 statistics (0–20 Hz contact force over the analysis section)</h2>\n");
    // Each statistic's row, in the order of the type's fields as written.
    let as_map = |st: &Option<pcsim_core::analysis::stats::ContactStats>| match st
        .as_ref()
        .map(serde_json::to_value)
    {
        Some(Ok(serde_json::Value::Object(o))) => o,
        _ => serde_json::Map::new(),
    };
    // A column per pantograph, then one per collector strip of it (its own force's statistics;
    // the pantograph's are their sum's).
    let mut cols: Vec<(String, serde_json::Map<String, serde_json::Value>)> = Vec::new();
    for p in pans {
        cols.push((p.name.clone(), as_map(&p.stats)));
        for (k, st) in p.strips.iter().enumerate() {
            cols.push((
                format!("{}, strip {} ({:+.2} m)", p.name, k + 1, st.along_m),
                as_map(&st.stats),
            ));
        }
    }
    let mut keys: Vec<String> = Vec::new();
    for p in pans {
        for k in as_map(&p.stats).keys() {
            if !keys.contains(k) {
                keys.push(k.clone());
            }
        }
    }
    let mut head = vec!["quantity"];
    head.extend(cols.iter().map(|(n, _)| n.as_str()));
    let null = serde_json::Value::Null;
    let rows: Vec<Vec<String>> = keys
        .iter()
        .map(|k| {
            std::iter::once(k.clone())
                .chain(cols.iter().map(|(_, st)| num(st.get(k).unwrap_or(&null))))
                .collect()
        })
        .collect();
    table(h, "Statistics per pantograph", &head, &rows);
}

/// The run's verification (`--verify`): each statistic beside its refined and stiff-contact
/// values, the statistics not converged first.
fn verification_section(h: &mut String, v: &Verification) {
    h.push_str("<h2>Verification: the numbers against a refined run and a stiffer contact</h2>\n");
    let _ = writeln!(
        h,
        "<p>Refined: {} modes per wire at Δt {} s (the run: {} at {} s). Model check: the contact {} N/m at Δt {} s (the run's {} N/m). A statistic is converged when the refinement moves it by no more than its tolerance.</p>",
        n(&v.refined.modes_per_wire),
        n(&v.refined.dt_s),
        n(&v.run.modes_per_wire),
        n(&v.run.dt_s),
        n(&v.stiff_contact.contact_stiffness_n_per_m),
        n(&v.stiff_contact.dt_s),
        n(&v.run.contact_stiffness_n_per_m),
    );
    if v.not_converged.is_empty() {
        h.push_str("<p>Every statistic is converged to its tolerance.</p>\n");
    } else {
        h.push_str(
            "<div class=\"warn\"><p><strong>Not converged to their tolerance:</strong></p><ul>",
        );
        for x in &v.not_converged {
            let _ = write!(h, "<li>{}</li>", esc(x));
        }
        h.push_str("</ul></div>\n");
    }
    let mut rows = Vec::new();
    for p in &v.pantographs {
        for s in &p.statistics {
            let pct = |x: f64| format!("{x:+.2} %");
            rows.push(vec![
                p.name.clone(),
                format!("{} [{}]", s.statistic, s.unit),
                n(&s.value),
                n(&s.refined),
                pct(s.change_percent),
                format!("{} %", n(&s.tolerance_percent)),
                if s.converged { "yes" } else { "NO" }.into(),
                n(&s.stiff_contact),
                pct(s.stiff_contact_change_percent),
            ]);
        }
    }
    table(
        h,
        "Each statistic, refined and with the contact twice as stiff",
        &[
            "pantograph",
            "statistic",
            "value",
            "refined",
            "change",
            "tolerance",
            "converged",
            "stiff contact",
            "change",
        ],
        &rows,
    );
}

/// The run's sensitivity (`--sensitivity`): each statistic's band over the case's ranged values
/// and the values that move it most, the ranges with their reasons, and the runs not made.
fn sensitivity_section(h: &mut String, s: &Sensitivity) {
    h.push_str("<h2>Sensitivity: the statistics over the case's ranged values</h2>\n");
    let _ = writeln!(
        h,
        "<p>{} ranged values, each run at its low and its high end (the others at the case's values), then {} runs with all of them drawn at once (seed {}). The band is the smallest and largest value over the case's run and every run of the study; the figure <code>sensitivity_*.svg</code> shows what moves σ.</p>",
        s.parameters.len(),
        n(&s.spec.samples),
        n(&s.spec.seed),
    );
    let lists = [
        ("Runs that could not be made", &s.failed),
        ("Runs with an error-level event", &s.events),
        ("Not varied", &s.not_varied),
    ];
    for (what, items) in lists {
        if !items.is_empty() {
            let _ = write!(h, "<div class=\"warn\"><p><strong>{what}:</strong></p><ul>");
            for x in items {
                let _ = write!(h, "<li>{}</li>", esc(x));
            }
            h.push_str("</ul></div>\n");
        }
    }
    let mut rows = Vec::new();
    for p in &s.pantographs {
        for b in &p.statistics {
            let movers: Vec<String> = (b.movers.iter().take(3))
                .map(|m| format!("{} ({:+.3})", m.path, m.swing.unwrap_or(f64::NAN)))
                .collect();
            rows.push(vec![
                p.name.clone(),
                format!("{} [{}]", b.statistic, b.unit),
                n(&b.value),
                n(&b.low),
                n(&b.high),
                movers.join("; "),
            ]);
        }
    }
    table(
        h,
        "Each statistic's band and the values that move it most (low end to high end)",
        &[
            "pantograph",
            "statistic",
            "value",
            "band low",
            "band high",
            "moved most by",
        ],
        &rows,
    );
    let prow: Vec<Vec<String>> = (s.parameters.iter())
        .map(|p| {
            vec![
                p.path.clone(),
                n(&p.value),
                format!("{} – {}", n(&p.low), n(&p.high)),
                n(&p.source),
                n(&p.range_source),
            ]
        })
        .collect();
    table(
        h,
        "The ranged values",
        &["value", "case", "range", "source", "why this range"],
        &prow,
    );
}

/// Each pantograph's passage over each hard spot of a line (section insulators, neutral
/// sections).
fn hard_spots_section(h: &mut String, pans: &[PantographSummary]) {
    let rows: Vec<Vec<String>> = (pans.iter())
        .flat_map(|p| {
            p.hard_spots.iter().map(|o| {
                vec![
                    p.name.clone(),
                    match o.kind {
                        pcsim_core::model::HardSpotKind::SectionInsulator => "section insulator",
                        pcsim_core::model::HardSpotKind::NeutralSection => "neutral section",
                    }
                    .to_string(),
                    format!("{}–{}", n(&o.section_m[0]), n(&o.section_m[1])),
                    n(&o.max_force_n),
                    n(&o.min_force_n),
                    n(&o.loss_of_contact_percent),
                    n(&o.max_uplift_mm),
                ]
            })
        })
        .collect();
    if !rows.is_empty() {
        h.push_str("<h2>Passages over the hard spots</h2>\n");
        table(
            h,
            "Each pantograph over each section insulator and neutral section (raw force)",
            &[
                "pantograph",
                "what",
                "where [m]",
                "max [N]",
                "min [N]",
                "loss [%]",
                "uplift [mm]",
            ],
            &rows,
        );
    }
}

/// Each pantograph's passage through each overlap of a line.
fn overlaps_section(h: &mut String, pans: &[PantographSummary]) {
    let mut orows = Vec::new();
    for p in pans {
        for o in &p.overlaps {
            orows.push(vec![
                p.name.clone(),
                format!("{}–{}", n(&o.section_m[0]), n(&o.section_m[1])),
                n(&o.max_force_n),
                n(&o.min_force_n),
                n(&o.loss_of_contact_percent),
                match o.transfer_m {
                    Some([a, b]) => format!("{}–{}", n(&a), n(&b)),
                    None => "—".into(),
                },
                n(&o.min_clearance_mm),
                n(&o.max_uplift_at_support_mm),
            ]);
        }
    }
    if !orows.is_empty() {
        h.push_str("<h2>Passages through the overlaps</h2>\n");
        table(
            h,
            "Each pantograph in each overlap",
            &[
                "pantograph",
                "overlap [m]",
                "max [N]",
                "min [N]",
                "loss [%]",
                "transfer [m]",
                "idle wire's clearance [mm]",
                "uplift [mm]",
            ],
            &orows,
        );
    }
}

/// The ten worst droppers inside the analysis section `section` (from droppers.csv, when
/// written).
fn droppers_section(h: &mut String, dir: &Path, section: [f64; 2]) {
    // Droppers: the worst inside the analysis section, as the terminal lists them (outside it the
    // pantographs start and stop: those droppers carry the run's transients, not a passage).
    if let Ok(text) = std::fs::read_to_string(dir.join("droppers.csv")) {
        let mut r = csv::Reader::from_reader(text.as_bytes());
        let mut rows: Vec<Vec<String>> = r
            .records()
            .filter_map(|x| x.ok())
            .map(|x| x.iter().map(str::to_owned).collect::<Vec<_>>())
            .filter(|r| {
                r.get(1)
                    .and_then(|v| v.parse::<f64>().ok())
                    .is_some_and(|x| x >= section[0] && x <= section[1])
            })
            .collect();
        let key = |r: &Vec<String>| -> f64 {
            r.get(9)
                .and_then(|v| v.parse().ok())
                .or_else(|| r.get(8).and_then(|v| v.parse().ok()))
                .unwrap_or(0.0)
        };
        rows.sort_by(|a, b| key(b).total_cmp(&key(a)));
        rows.truncate(10);
        h.push_str("<h2>Droppers</h2>\n");
        table(
            h,
            &format!(
                "The ten worst droppers inside the analysis section {}–{} m (by damage, else by the largest tension range; every dropper in droppers.csv)",
                n(&section[0]),
                n(&section[1])
            ),
            &["#", "x [m]", "wire", "preload [N]", "min [N]", "max [N]", "slack steps", "cycles", "largest range [N]", "damage"],
            &rows,
        );
    }
}

/// The page's Content-Security-Policy: no script, no outside resource of any kind; only its own
/// inline style (and inline SVG, which is part of the page).
const CSP: &str = "<meta http-equiv=\"Content-Security-Policy\" content=\"default-src 'none'; script-src 'none'; object-src 'none'; base-uri 'none'; form-action 'none'; style-src 'unsafe-inline'\">";

/// Files changed after pcsim wrote them (their hashes differ from the manifest's), said at the top
/// of the page: what the page shows of them is what they hold now, not what the run wrote.
fn edited_box(h: &mut String, dir: &Path, m: &crate::output::Manifest) {
    let edited = crate::output::edited_files(dir, m);
    if edited.is_empty() {
        return;
    }
    h.push_str("<section class=\"errors\" id=\"edited\"><h2>Files changed after the run</h2><ul>");
    for f in &edited {
        let _ = write!(h, "<li><code>{}</code></li>", esc(f));
    }
    h.push_str("</ul><p>Their bytes are no longer those pcsim wrote (the manifest records each file's hash): this page shows them as they are now, which is not what the run wrote. Run the case again for a report of it.</p></section>\n");
}

/// The error-level events of a run or a study (a dewirement, contact lost over the limit), in a
/// box of their own at the top of the page: its numbers describe a run that is not acceptable as
/// it is.
fn errors_box(h: &mut String, errors: &[String]) {
    if errors.is_empty() {
        return;
    }
    h.push_str("<section class=\"errors\" id=\"errors\"><h2>Errors of the run</h2><ul>");
    for e in errors {
        let _ = write!(h, "<li>{}</li>", esc(e));
    }
    h.push_str("</ul><p>The statistics below come from this run; they describe it with these events, and the run is not accepted as it is.</p></section>\n");
}

/// The error-level events of a study's directory: a Monte Carlo study's answer's failures and
/// warnings (its montecarlo.json read back through its type).
fn study_errors(dir: &Path, kind: StudyKind) -> Result<Vec<String>> {
    match kind {
        StudyKind::MonteCarlo => {
            let a =
                MonteCarloStudy::answer(&typed::<MonteCarloOutput>(&dir.join("montecarlo.json"))?);
            Ok(a.failures.into_iter().chain(a.warnings).collect())
        }
        // A doubtful alignment (compare.json read back through its type; none before it).
        StudyKind::Compare if dir.join("compare.json").is_file() => {
            Ok(CompareStudy::answer(&typed::<CompareOutput>(&dir.join("compare.json"))?).warnings)
        }
        StudyKind::Run
        | StudyKind::Eva
        | StudyKind::Window
        | StudyKind::Realtime
        | StudyKind::Compare
        | StudyKind::Design
        | StudyKind::PantographFrf
        | StudyKind::PantographFit
        | StudyKind::Wear => Ok(Vec::new()),
    }
}

/// An output file read back through the type that wrote it (the error names the file).
fn typed<T: serde::de::DeserializeOwned>(p: &Path) -> Result<T> {
    let text =
        std::fs::read_to_string(p).with_context(|| format!("cannot read {}", p.display()))?;
    serde_json::from_str(&text).with_context(|| format!("{} is not pcsim's output", p.display()))
}

/// A study's typed answer (its headline, its values, what it does not establish).
fn answer_section(h: &mut String, a: &Answer) {
    let _ = writeln!(h, "<h2 id=\"answer\">The answer: {}</h2>", esc(&a.headline));
    let rows: Vec<Vec<String>> = (a.rows.iter())
        .map(|(w, v)| vec![w.trim().to_string(), v.clone()])
        .collect();
    table(h, "the answer", &["", "value"], &rows);
}

/// The run against the acceptance criteria: the assessment `pcsim assess` wrote into the
/// directory (with its supply system and the user's criteria), else the built-in criteria
/// without a supply system (from `summary`, the run's summary.json as read).
fn assessment(h: &mut String, dir: &Path, summary: &str) -> Result<()> {
    use pcsim_core::analysis::assess::{assess, AssessInput, Assessment};
    h.push_str("<h2>Acceptance criteria</h2>\n");
    let path = dir.join("assessment.json");
    let a: Assessment = match std::fs::read_to_string(&path) {
        Ok(text) => serde_json::from_str(&text)
            .with_context(|| format!("{} is not an assessment pcsim wrote", path.display()))?,
        Err(_) => {
            let input = AssessInput::from_summary_json(summary)
                .map_err(|e| anyhow::anyhow!("summary.json: {e}"))?;
            h.push_str("<p>Assessed here with the built-in criteria and no supply system: <code>pcsim assess DIR --system …</code> assesses the criteria that depend on it, and adds your own with <code>--criteria</code>.</p>\n");
            assess(&input, &pcsim_core::input::criteria::builtin(), None)
        }
    };
    let _ = writeln!(
        h,
        "<p>Supply system: {}. A criterion whose limit pcsim cannot cite from a public text has no limit here: its row gives the run's value only, and the run is not accepted on it.</p>",
        esc(a.system.as_deref().unwrap_or("not given"))
    );
    let rows: Vec<Vec<String>> = a.rows.iter().map(assessment_row).collect();
    table(
        h,
        "Each criterion, per pantograph",
        &[
            "criterion",
            "pantograph",
            "value",
            "limit",
            "verdict",
            "status",
            "clause",
            "source",
        ],
        &rows,
    );
    if !a.skipped.is_empty() {
        h.push_str("<p>Not applied:</p><ul>");
        for s in &a.skipped {
            let _ = write!(h, "<li>{}</li>", esc(s));
        }
        h.push_str("</ul>\n");
    }
    let n_err = a.run_errors.len();
    let _ = writeln!(
        h,
        "<p><strong>{} met, {} not met, {} without a verdict{}.</strong></p>",
        a.met,
        a.not_met,
        a.without_verdict,
        if n_err > 0 {
            format!("; the run had {n_err} error-level event(s) (at the top of the page): it is not accepted")
        } else {
            String::new()
        }
    );
    Ok(())
}

/// One assessment row as the report's table shows it.
fn assessment_row(r: &pcsim_core::analysis::assess::Row) -> Vec<String> {
    use pcsim_core::analysis::assess::Verdict;
    let verdict = match (r.verdict, r.deviation_percent) {
        (Verdict::Deviation, Some(d)) => format!("{d:+.1} % of the target"),
        (v, _) => num(&serde_json::json!(v)).replace('-', " "),
    };
    vec![
        r.id.clone(),
        r.pantograph.clone().unwrap_or_else(|| "(run)".into()),
        format!("{} {}", numf(r.value), r.unit),
        match r.limit {
            None => "—".to_string(),
            Some(l) => format!("{} ({})", numf(Some(l)), r.limit_formula),
        },
        verdict,
        r.status.clone(),
        r.clause.clone(),
        r.source.clone(),
    ]
}

/// The case as given (`case.toml`), every value with its source; `overrides` are the flags that
/// changed it for this run.
fn provenance(h: &mut String, dir: &Path, overrides: &[String]) -> Result<()> {
    h.push_str("<h2>The case: every value and its source</h2>\n");
    let Ok(text) = std::fs::read_to_string(dir.join("case.toml")) else {
        h.push_str("<p>This directory has no case.toml (made by an older pcsim, or by a command that does not write it): see the case file or preset it was made from.</p>\n");
        return Ok(());
    };
    if let Ok(m) = crate::output::read_complete_manifest(dir) {
        if crate::output::edited_files(dir, &m)
            .iter()
            .any(|f| f == "case.toml")
        {
            h.push_str("<p class=\"edited\"><strong>case.toml was changed after the run</strong> (its hash is not the manifest's): the table shows the file as it is now, not the case that was run.</p>\n");
        }
    }
    let (case, prov) =
        pcsim_core::Case::from_toml_str(&text).map_err(|e| anyhow::anyhow!("case.toml: {e}"))?;
    let value: toml::Value =
        toml::from_str(&case.to_toml_string()).context("the case does not write back as TOML")?;
    let mut rows = Vec::new();
    flatten("", &value, &mut rows);
    let rows: Vec<Vec<String>> = rows
        .into_iter()
        .map(|(p, v)| {
            let src = prov
                .get(&p)
                .cloned()
                .unwrap_or_else(|| "— (no source given)".into());
            vec![p, v, src]
        })
        .collect();
    if !overrides.is_empty() {
        let _ = writeln!(
            h,
            "<p>Overridden on the command line: {} (the table shows the case as given).</p>",
            esc(&overrides.join(", "))
        );
    }
    table(h, "Provenance", &["field", "value", "source"], &rows);
    Ok(())
}

/// Close the page, write it and list it in the manifest.
fn finish(dir: &Path, mut h: String) -> Result<PathBuf> {
    h.push_str("</body></html>\n");
    let path = dir.join("report.html");
    // Through a temporary file and a rename: a full disk leaves the previous report (or none),
    // never a truncated one, and no temporary file.
    crate::output::write_file_atomic(&path, h)?;
    add_to_manifest(dir, std::slice::from_ref(&path))?;
    Ok(path)
}

/// Every SVG figure of the directory, inline, with its caption.
fn figures(h: &mut String, dir: &Path, files: &[String]) -> Result<()> {
    h.push_str("<h2>Figures</h2>\n");
    let mut n_fig = 0;
    for f in files.iter().filter(|f| f.ends_with(".svg")) {
        let text = std::fs::read_to_string(dir.join(f))
            .with_context(|| format!("cannot read {}", dir.join(f).display()))?;
        // Never copied verbatim: rebuilt from the whitelist of drawing elements.
        let svg = crate::svg_safe::sanitize(&text).with_context(|| f.clone())?;
        let stem = f.trim_end_matches(".svg");
        let _ = writeln!(
            h,
            "<figure id=\"{}\">{}<figcaption>{}</figcaption></figure>",
            esc(stem),
            svg,
            esc(&caption(stem))
        );
        n_fig += 1;
    }
    if n_fig == 0 {
        h.push_str("<p>No figures: the directory was written without them (<code>pcsim plot DIR</code> draws them).</p>\n");
    }
    Ok(())
}

/// The most rows of a study's table shown in the report (every row is in its CSV).
const MAX_ROWS: usize = 200;

/// The report of a study's directory (eva, window, realtime, Monte Carlo, compare): its manifest's
/// description, each of its top-level tables, every figure.
fn write_study(dir: &Path, m: &crate::output::Manifest) -> Result<PathBuf> {
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">{CSP}<title>pcsim report: {} {}</title>\n<style>{}</style></head><body>\n",
        esc(m.kind.name()),
        esc(&dir.display().to_string()),
        STYLE
    );
    let _ = write!(
        h,
        "<h1>pcsim {}: {}</h1>\n<p class=\"meta\">pcsim {} · <code>{}</code></p>\n",
        esc(m.kind.name()),
        esc(&dir.display().to_string()),
        esc(&m.version),
        esc(command(m))
    );
    edited_box(&mut h, dir, m);
    errors_box(&mut h, &study_errors(dir, m.kind)?);
    // The answer first (issue 42, item 6), then the figures, then the tables.
    study_answer(&mut h, dir, m.kind)?;
    figures(&mut h, dir, &m.files)?;
    // The current-collection study's arcing against the criteria, once `pcsim assess` wrote it.
    if m.kind == StudyKind::Wear && m.lists("assessment.json") {
        assessment(&mut h, dir, "")?;
    }
    // The manifest's record as written, each entry a row.
    let record = serde_json::to_value(&m.record)?;
    let described: Vec<Vec<String>> = record
        .as_object()
        .map(|o| {
            o.iter()
                .filter(|(k, _)| {
                    !matches!(k.as_str(), "files" | "complete" | "kind" | "pcsim_version")
                })
                .map(|(k, v)| vec![k.clone(), num(v)])
                .collect()
        })
        .unwrap_or_default();
    if !described.is_empty() {
        table(
            &mut h,
            "What the directory holds",
            &["item", "value"],
            &described,
        );
    }
    for f in m.files.iter().filter(|f| {
        // A design's force traces are its figures' data, not a table to read.
        f.ends_with(".csv")
            && !f.contains('/')
            && !(m.kind == StudyKind::Design && *f == "traces.csv")
    }) {
        let text = std::fs::read_to_string(dir.join(f))
            .with_context(|| format!("cannot read {}", dir.join(f).display()))?;
        // Parsed as CSV (a design's journal quotes fields with commas).
        let mut r = csv::ReaderBuilder::new()
            .flexible(true)
            .from_reader(text.as_bytes());
        let head: Vec<String> = r.headers()?.iter().map(String::from).collect();
        let head: Vec<&str> = head.iter().map(String::as_str).collect();
        let rows: Vec<Vec<String>> = r
            .records()
            .take(MAX_ROWS)
            .map(|x| Ok(x?.iter().map(String::from).collect()))
            .collect::<Result<_>>()?;
        let total = text.lines().count().saturating_sub(1);
        let cap = if total > MAX_ROWS {
            format!("{f} (the first {MAX_ROWS} of {total} rows)")
        } else {
            f.clone()
        };
        let _ = writeln!(h, "<h2>{}</h2>", esc(f));
        table(&mut h, &cap, &head, &rows);
    }
    // The study's base case: the grid's flags (speeds, tensions, …) vary it, as the command says.
    provenance(&mut h, dir, &[])?;
    finish(dir, h)
}

/// The columns `cols` (name, heading) of `dir/file`, each row's values as written (none when the
/// file or a column is missing).
fn csv_columns(dir: &Path, file: &str, cols: &[(&str, &str)]) -> Result<Option<Vec<Vec<String>>>> {
    let p = dir.join(file);
    if !p.exists() {
        return Ok(None);
    }
    let mut r =
        csv::Reader::from_path(&p).with_context(|| format!("cannot read {}", p.display()))?;
    let head: Vec<String> = r.headers()?.iter().map(String::from).collect();
    let Some(idx) = cols
        .iter()
        .map(|(c, _)| head.iter().position(|h| h == c))
        .collect::<Option<Vec<usize>>>()
    else {
        return Ok(None);
    };
    let mut rows = Vec::new();
    for rec in r.records().take(MAX_ROWS) {
        let rec = rec?;
        rows.push(
            idx.iter()
                .map(|&i| rec.get(i).unwrap_or("").to_string())
                .collect(),
        );
    }
    Ok(Some(rows))
}

/// The answer of a study driven through the contract (`answer.json`, any kind, read back
/// through [`Answer`]), else of one that writes its output as a typed JSON (compare.json,
/// realtime.json, read back through its type); `None` for the others, and for a directory
/// written before them.
fn typed_answer(dir: &Path, kind: StudyKind) -> Result<Option<Answer>> {
    let answer = dir.join("answer.json");
    if answer.is_file() {
        return Ok(Some(typed::<Answer>(&answer)?));
    }
    let (compare, realtime) = (dir.join("compare.json"), dir.join("realtime.json"));
    Ok(match kind {
        StudyKind::Compare if compare.is_file() => {
            Some(CompareStudy::answer(&typed::<CompareOutput>(&compare)?))
        }
        StudyKind::Realtime if realtime.is_file() => {
            Some(RealtimeStudy::answer(&typed::<RealtimeOutput>(&realtime)?))
        }
        _ => None,
    })
}

/// A study's answer, first in its report (issue 42, item 6): the EVA per case, the window
/// length, the real-time window against the full model, the run beside the measurement side by
/// side, the Monte Carlo mean with its 95 % interval.
fn study_answer(h: &mut String, dir: &Path, kind: StudyKind) -> Result<()> {
    // A Monte Carlo study's answer comes with its table of each statistic's interval.
    if kind == StudyKind::MonteCarlo {
        return montecarlo_answer(h, dir);
    }
    if let Some(a) = typed_answer(dir, kind)? {
        answer_section(h, &a);
        return Ok(());
    }
    let (title, file, cols): (&str, &str, &[(&str, &str)]) = match kind {
        StudyKind::Eva => (
            "The answer: the effective vibration area of each case",
            "eva.csv",
            &[
                ("speed_kmh", "km/h"),
                ("tension_kn", "kN"),
                ("damping", "damping"),
                ("eva_step_m", "EVA, the paper's step criterion [m]"),
                ("eva_step_span_min_m", "step, least over a span [m]"),
                ("eva_step_span_max_m", "step, largest over a span [m]"),
                ("eva_fraction_m", "EVA, the fraction of the energy [m]"),
                ("eva_fraction_span_min_m", "fraction, least over a span [m]"),
                (
                    "eva_fraction_span_max_m",
                    "fraction, largest over a span [m]",
                ),
                ("converged_energy_j", "converged energy [J]"),
                ("total_energy_j", "whole model [J]"),
            ],
        ),
        StudyKind::Window => (
            "The answer: the shortest window that matches the full model",
            "window.csv",
            &[
                ("speed_kmh", "km/h"),
                ("tension_kn", "kN"),
                ("damping", "damping"),
                ("length_m", "window length [m]"),
                ("mean_err_pct", "Δ mean [%]"),
                ("sigma_err_pct", "Δ σ [%]"),
                ("max_err_pct", "Δ max [%]"),
                ("fine_checked_to_m", "every window checked up to [m]"),
            ],
        ),
        // A real-time study written before realtime.json: its table.
        StudyKind::Realtime => (
            "The answer: the real-time window against the full model",
            "realtime.csv",
            &[
                ("window_m", "window [m]"),
                ("mean_n", "mean [N]"),
                ("std_n", "σ [N]"),
                ("mean_error_percent", "Δ mean [%]"),
                ("std_error_percent", "Δ σ [%]"),
                ("max_error_percent", "Δ max [%]"),
                ("full_mean_n", "full model, this pantograph alone: mean [N]"),
                ("full_std_n", "full model, this pantograph alone: σ [N]"),
            ],
        ),
        // A comparison written before compare.json: its table.
        StudyKind::Compare => (
            "The answer: the run beside the measurement",
            "compare_stats.csv",
            &[
                ("quantity", "quantity"),
                ("run", "run"),
                ("measured", "measured"),
                ("difference", "difference"),
            ],
        ),
        StudyKind::MonteCarlo => return montecarlo_answer(h, dir),
        StudyKind::PantographFit => return fit_answer(h, dir),
        StudyKind::Design => return design_section(h, dir),
        // Its answer is answer.json's (above).
        StudyKind::Run | StudyKind::Wear => return Ok(()),
        StudyKind::PantographFrf => (
            "The answer: the pantograph's response at the head",
            "frf.csv",
            &[
                ("frequency_hz", "frequency [Hz]"),
                ("magnitude_kg", "apparent mass [kg]"),
                ("phase_deg", "phase [°]"),
            ],
        ),
    };
    // A file written before its columns over a span (issue 53, item 4): the table without them.
    let older: Vec<(&str, &str)> = cols
        .iter()
        .filter(|(c, _)| !c.contains("_span_"))
        .copied()
        .collect();
    let found = match csv_columns(dir, file, cols)? {
        Some(rows) => Some((rows, cols)),
        None => csv_columns(dir, file, &older)?.map(|rows| (rows, &older[..])),
    };
    if let Some((rows, cols)) = found {
        let _ = writeln!(h, "<h2 id=\"answer\">{}</h2>", esc(title));
        let head: Vec<&str> = cols.iter().map(|(_, l)| *l).collect();
        table(h, file, &head, &rows);
    }
    Ok(())
}

/// A pantograph fit's answer: each fitted value with its uncertainty and start, the residual
/// (fit.json).
fn fit_answer(h: &mut String, dir: &Path) -> Result<()> {
    let p = dir.join("fit.json");
    if !p.exists() {
        return Ok(());
    }
    let v: pcsim_core::study::frf::FitRecord = typed(&p)?;
    let _ = writeln!(
        h,
        "<h2 id=\"answer\">The answer: the pantograph fitted to {} (residual {} RMS, from {} at the start)</h2>",
        esc(&v.source),
        numf(Some(v.residual_rms)),
        numf(Some(v.start_residual_rms))
    );
    let rows: Vec<Vec<String>> = (v.parameters.iter())
        .map(|q| {
            vec![
                q.name.clone(),
                numf(Some(q.value)),
                numf(Some(q.std)),
                numf(Some(q.start)),
                if q.at_bound {
                    "at its bound".into()
                } else {
                    String::new()
                },
            ]
        })
        .collect();
    table(
        h,
        "fit.json",
        &["parameter", "fitted", "± (1 σ)", "start", ""],
        &rows,
    );
    Ok(())
}

/// A Monte Carlo study's answer (montecarlo.json read back through its type): the answer the
/// terminal gave, then each statistic's mean over the realisations with its 95 % confidence
/// interval (Student's t), the spread and the extremes.
fn montecarlo_answer(h: &mut String, dir: &Path) -> Result<()> {
    let o: MonteCarloOutput = typed(&dir.join("montecarlo.json"))?;
    answer_section(h, &MonteCarloStudy::answer(&o));
    let opt = |x: Option<f64>| x.map_or("—".into(), |v| format!("{v}"));
    let mut rows = Vec::new();
    for (pan, stats) in &o.statistics {
        for (name, s) in stats {
            let Some(s) = s else { continue };
            rows.push(vec![
                pan.clone(),
                name.clone(),
                format!("{}", s.mean),
                format!("{} – {}", opt(s.ci95_low), opt(s.ci95_high)),
                opt(s.std),
                format!("{} – {}", s.min, s.max),
                s.n.to_string(),
            ]);
        }
    }
    table(
        h,
        "montecarlo.json",
        &[
            "pantograph",
            "statistic",
            "mean",
            "95 % interval of the mean",
            "σ over the realisations",
            "min – max",
            "n",
        ],
        &rows,
    );
    Ok(())
}

/// A design's sensitivity (the objective a step below and above the best design) and its
/// constraints' status, from design.json.
fn design_sensitivity_and_constraints(h: &mut String, v: &DesignRecord) {
    let sens: Vec<Vec<String>> = (v.sensitivity.iter())
        .map(|s| {
            vec![
                s.path.clone(),
                numf(Some(s.step)),
                numf(s.objective_below),
                numf(s.objective_above),
                (s.at_bound.as_ref()).map_or(String::new(), |b| format!("at its {b} bound")),
            ]
        })
        .collect();
    table(
        h,
        "Sensitivity: the objective one step below and above the best design",
        &[
            "variable",
            "step",
            "objective below",
            "objective above",
            "note",
        ],
        &sens,
    );
    let cons: Vec<Vec<String>> = (v.constraints.iter())
        .map(|c| {
            vec![
                c.name.clone(),
                numf(c.value),
                numf(c.limit),
                numf(c.margin),
                if c.active { "active" } else { "inactive" }.to_string(),
            ]
        })
        .collect();
    if !cons.is_empty() {
        table(
            h,
            "Constraints at the best design (active: violated one step away)",
            &["constraint", "value", "limit", "margin", ""],
            &cons,
        );
    }
}

/// A design search's answer (its design.json, the core's `DesignRecord`): the best design, the
/// sensitivity, the constraints.
fn design_section(h: &mut String, dir: &Path) -> Result<()> {
    let v: DesignRecord = typed(&dir.join("design.json"))?;
    let _ = writeln!(h, "<h2 id=\"answer\">The answer</h2>");
    let best = match &v.best_evaluated {
        Some(b) if v.answer != "infeasible" => b,
        _ => {
            let _ = writeln!(
                h,
                "<p><b>Infeasible</b>: none of the designs evaluated meets the constraints; there is no best design. The least violating: {}.</p>",
                esc(&serde_json::json!(v.least_violating.as_ref().map(|e| &e.violated)).to_string())
            );
            return Ok(());
        }
    };
    let base = v.base.as_ref();
    let base_objective = numf(base.and_then(|b| b.objective));
    let improved = v.best.is_some();
    if !improved {
        let _ = writeln!(
            h,
            "<p><b>No improvement found</b>: no design evaluated beats the base design (objective {base_objective}); the best evaluated (evaluation {}) has objective {}. No design is recommended: keep the base, or search a wider range or with more evaluations.</p>",
            best.index,
            numf(best.objective),
        );
    }
    let mut rows: Vec<Vec<String>> = (v.variables.iter().enumerate())
        .map(|(k, p)| {
            let base_x = base.and_then(|b| b.x.get(k).copied());
            vec![p.path.clone(), numf(best.x.get(k).copied()), numf(base_x)]
        })
        .collect();
    rows.push(vec![
        "objective".into(),
        numf(best.objective),
        base_objective,
    ]);
    let base_feasible = base.is_some_and(pcsim_core::study::design::Evaluation::feasible);
    rows.push(vec![
        "feasible".into(),
        "yes".into(),
        if base_feasible { "yes" } else { "no" }.into(),
    ]);
    table(
        h,
        &format!(
            "The best design {}(evaluation {}; confirmation run {})",
            if improved {
                ""
            } else {
                "evaluated, not recommended "
            },
            best.index,
            if v.confirmation.as_ref().is_some_and(|c| c.same_as_search) {
                "equal to the search's"
            } else {
                "DIFFERENT from the search's"
            }
        ),
        &["", "best", "base"],
        &rows,
    );
    design_sensitivity_and_constraints(h, &v);
    Ok(())
}

/// Every leaf of a TOML value as (dotted path, value).
fn flatten(prefix: &str, v: &toml::Value, out: &mut Vec<(String, String)>) {
    match v {
        toml::Value::Table(t) => {
            for (k, x) in t {
                let p = if prefix.is_empty() {
                    k.clone()
                } else {
                    format!("{prefix}.{k}")
                };
                flatten(&p, x, out);
            }
        }
        toml::Value::Array(a) if a.iter().any(|x| x.is_table()) => {
            for (i, x) in a.iter().enumerate() {
                flatten(&format!("{prefix}[{i}]"), x, out);
            }
        }
        other => out.push((prefix.to_string(), other.to_string())),
    }
}

/// The page's own style (no external sheet).
const STYLE: &str = "body{font-family:sans-serif;max-width:1250px;margin:2em auto;color:#222}\
h1{font-size:1.6em}h2{margin-top:1.6em;border-bottom:1px solid #ccc}\
.meta{color:#555}code{background:#f3f3f3;padding:0 .2em}\
table{border-collapse:collapse;margin:.8em 0}caption{text-align:left;font-weight:bold;margin-bottom:.3em}\
th,td{border:1px solid #bbb;padding:.2em .5em;font-size:.9em}th{background:#eee}\
td:nth-child(n+2){font-variant-numeric:tabular-nums}\
.errors{border:2px solid #b00;background:#fff0f0;padding:0 1em;margin:1em 0}.errors h2{color:#b00;border:none}\
.warn{border:2px solid #b60;background:#fff8ec;padding:0 1em;margin:1em 0}\
figure{margin:1.2em 0}figure svg{width:100%;height:auto}figcaption{color:#444;font-size:.9em}";
