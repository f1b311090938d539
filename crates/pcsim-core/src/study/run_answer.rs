//! A run's answer, row by row (what the terminal prints and the report opens with): each
//! pantograph's statistics and lateral motion, the irregularity and the wind, the verification,
//! the sensitivity and the droppers that suffer most. Formatting only; the run is `run.rs`.

use crate::analysis::fatigue::DropperFatigue;
use crate::analysis::record::{DropperRun, RunOutput};
use crate::analysis::report::RunSummary;
use crate::analysis::sensitivity::Sensitivity;
use crate::analysis::verify::Verification;

/// The rows of an answer: `(what, value)`.
type Rows = Vec<(String, String)>;

/// Each pantograph's statistics (its strips' and its lateral motion's), the irregularity and
/// the wind.
pub(crate) fn statistics(s: &RunSummary, rows: &mut Rows) {
    for p in &s.pantographs {
        let name = format!("{:<10}", p.name);
        match &p.stats {
            Some(t) => rows.push((
                name.clone(),
                format!(
                    "Fm {:6.1} N  σ {:5.1} N  (0-5 Hz {:4.1}, 5-20 Hz {:4.1})  max {:6.1}  min {:6.1}  uplift@support {:5.1} mm  loss {:.2} %",
                    t.mean_n, t.std_n, t.std_0_5hz_n, t.std_5_20hz_n, t.actual_max_n, t.actual_min_n, t.max_uplift_at_support_mm, t.loss_of_contact_percent
                ),
            )),
            None => rows.push((name.clone(), "did not cross the analysis section".into())),
        }
        for (k, st) in p.strips.iter().enumerate() {
            if let Some(t) = &st.stats {
                rows.push((
                    format!("{:<10}", ""),
                    format!(
                        "strip {} ({:+.2} m): Fm {:6.1} N  σ {:5.1} N  max {:6.1}  min {:6.1}  loss {:.2} %",
                        k + 1, st.along_m, t.mean_n, t.std_n, t.actual_max_n, t.actual_min_n, t.loss_of_contact_percent
                    ),
                ));
            }
        }
        if let Some(t) = &p.stats {
            if let (Some(lat), Some(bo)) = (t.max_lateral_offset_mm, t.max_contact_wire_blowout_mm)
            {
                let margin = t
                    .min_head_margin_mm
                    .map_or(String::new(), |m| format!("  head margin {m:.0} mm"));
                rows.push((
                    format!("{:<10}", ""),
                    format!(
                        "lateral: max offset {lat:.0} mm{margin}  contact-wire blow-out {bo:.0} mm"
                    ),
                ));
            }
        }
    }
    for r in &s.irregularity {
        rows.push((
            "irregularity".into(),
            format!(
                "{}{}: RMS {:.2} mm{}",
                r.kind,
                r.seed.map_or(String::new(), |s| format!(" (seed {s})")),
                r.rms_achieved_m * 1e3,
                r.rms_target_m
                    .map_or(String::new(), |t| format!(" (target {:.2} mm)", t * 1e3))
            ),
        ));
    }
    if let Some(w) = &s.wind {
        rows.push((
            "wind".into(),
            format!(
                "{:.1} m/s at {} m, {} spectrum, seed {}, turbulence intensity {:.3} (target {:.3})",
                w.mean_speed_m_s,
                w.reference_height_m,
                w.spectrum,
                w.seed,
                w.turbulence_intensity_achieved,
                w.turbulence_intensity_target
            ),
        ));
    }
}

/// The verification: each statistic beside its refined and stiff-contact values, and the
/// statistics not converged to their tolerance.
pub(crate) fn verification(v: &Verification, rows: &mut Rows) {
    rows.push((
        "verification:".into(),
        format!(
            "refined {} modes/wire, Δt {} s; contact {} N/m (model check: every contact, a strip's own too, twice as stiff: {} N/m at Δt {} s)",
            v.refined.modes_per_wire,
            v.refined.dt_s,
            v.run.contact_stiffness_n_per_m,
            v.stiff_contact.contact_stiffness_n_per_m,
            v.stiff_contact.dt_s
        ),
    ));
    for p in &v.pantographs {
        rows.push((
            format!("{:<10}", p.name),
            format!(
                "{:<26} {:>10} {:>10} {:>8} {:>6}   {:>10} {:>8}",
                "statistic", "value", "refined", "change", "tol", "stiff k", "change"
            ),
        ));
        for s in &p.statistics {
            rows.push((
                format!("{:<10}", ""),
                format!(
                    "{:<26} {:>10.3} {:>10.3} {:>7.2}% {:>5}%{} {:>10.3} {:>7.2}%",
                    format!("{} [{}]", s.statistic, s.unit),
                    s.value,
                    s.refined,
                    s.change_percent,
                    s.tolerance_percent,
                    if s.converged { " " } else { "!" },
                    s.stiff_contact,
                    s.stiff_contact_change_percent
                ),
            ));
        }
        // Issue 53, item 2: each statistic with its numerical error, estimated as its change to
        // the refined run (twice the modes, half the step).
        let errors: Vec<String> = p
            .statistics
            .iter()
            .map(|s| {
                format!(
                    "{} {:.2} ± {:.2} {}",
                    s.statistic.trim_end_matches("_n").trim_end_matches("_mm"),
                    s.value,
                    (s.refined - s.value).abs(),
                    s.unit
                )
            })
            .collect();
        rows.push((
            format!("{:<10}", ""),
            format!("numerical (the change refined): {}", errors.join(", ")),
        ));
    }
    if v.not_converged.is_empty() {
        rows.push((
            "verification:".into(),
            "every statistic converged to its tolerance (! marks one that is not)".into(),
        ));
    }
    for n in &v.not_converged {
        rows.push(("NOT CONVERGED:".into(), n.clone()));
    }
}

/// The sensitivity: each statistic's band and the value that moves it most.
pub(crate) fn sensitivity(s: &Sensitivity, rows: &mut Rows) {
    rows.push((
        "sensitivity:".into(),
        format!(
            "{} ranged values, {} runs one at a time and {} sampled (seed {})",
            s.parameters.len(),
            2 * s.parameters.len(),
            s.spec.samples,
            s.spec.seed
        ),
    ));
    for p in &s.pantographs {
        rows.push((
            format!("{:<10}", p.name),
            format!(
                "{:<26} {:>10} {:>21}   most moved by",
                "statistic", "value", "band"
            ),
        ));
        for b in &p.statistics {
            let top = b
                .movers
                .first()
                .map_or(String::from("-"), |m| match m.swing {
                    Some(w) => format!("{} ({w:+.3} {})", m.path, b.unit),
                    None => format!("{} (one end only: moved {:.3} {})", m.path, m.moved, b.unit),
                });
            rows.push((
                format!("{:<10}", ""),
                format!(
                    "{:<26} {:>10.3} [{:>9.3}, {:>9.3}]   {top}",
                    format!("{} [{}]", b.statistic, b.unit),
                    b.value,
                    b.low,
                    b.high
                ),
            ));
        }
    }
    for n in &s.not_varied {
        rows.push(("not varied:".into(), n.clone()));
    }
    for e in &s.events {
        rows.push(("EVENT:".into(), e.clone()));
    }
    for f in &s.failed {
        rows.push(("NOT RUN:".into(), f.clone()));
    }
}

/// The droppers inside the analysis section that suffer most: by Miner's damage when the case
/// gives an S–N curve, else by their largest tension range (outside it the pantographs start and
/// stop: those droppers carry the run's transients, not a passage); and why the history was not
/// kept, when it was not.
pub(crate) fn droppers(
    d: &DropperRun,
    out: &RunOutput,
    rows: &mut Rows,
    warnings: &mut Vec<String>,
) {
    let section = out.analysis_m;
    let mut worst: Vec<&DropperFatigue> = (d.droppers.iter())
        .filter(|f| f.x_m >= section[0] && f.x_m <= section[1])
        .collect();
    let key = |f: &DropperFatigue| f.damage.unwrap_or(f.max_range_n);
    worst.sort_by(|a, b| key(b).total_cmp(&key(a)));
    let by = if d.curve.is_some() {
        "Miner's damage of this passage"
    } else {
        "largest tension range (no [dropper_fatigue] S–N curve in the case: no damage)"
    };
    rows.push((
        "droppers:".into(),
        format!(
            "{} followed; the worst inside the analysis section {section:?} m by {by}:",
            d.droppers.len()
        ),
    ));
    rows.push((
        format!("{:>9}", "x [m]"),
        format!(
            "{:<22} {:>8} {:>8} {:>8} {:>6} {:>7} {:>9} {:>10}",
            "wire", "F0 [N]", "min [N]", "max [N]", "slack", "cycles", "ΔFmax [N]", "damage"
        ),
    ));
    for f in worst.iter().take(10) {
        rows.push((
            format!("{:>9.2}", f.x_m),
            format!(
                "{:<22} {:>8.1} {:>8.1} {:>8.1} {:>6} {:>7} {:>9.1} {:>10}",
                f.wire,
                f.preload_n,
                f.min_n,
                f.max_n,
                f.slack_steps,
                f.cycles,
                f.max_range_n,
                f.damage.map_or("—".to_string(), |v| format!("{v:.3e}"))
            ),
        ));
    }
    if d.history.is_none() {
        let n = d.droppers.len();
        warnings.push(format!(
            "dropper_forces.csv not written: {n} droppers × {} steps = {} numbers, more than the limit of {}; droppers.csv has each dropper's extremes, slack steps and cycles",
            out.time_s.len(),
            n * out.time_s.len(),
            d.history_limit
        ));
    }
}
