//! The run: speed, start and end, the analysis section, the modes and the time step.

use super::*;

/// The time step, the number of modes, and where the run starts, ends and is analysed.
pub(super) fn run(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let r = &case.run;
    check_bound(w, "run.dt_s", r.dt_s, &bounds::DT)?;
    if !(r.perturb_uplift_rel.is_finite() && (0.0..=1e-3).contains(&r.perturb_uplift_rel)) {
        return Err(inv(
            "run.perturb_uplift_rel",
            r.perturb_uplift_rel,
            "must lie in [0, 1e-3]: a perturbation to put an error bar on threshold-sensitive statistics, not a change of the uplift",
        ));
    }
    modes(case, w)?;
    let l = case.length_m();
    let max_off = case
        .pantographs
        .iter()
        .map(|p| p.offset_m())
        .fold(0.0, f64::max);
    if r.start_m - max_off <= 0.0 || r.start_m >= l {
        return Err(inv(
            "run.start_m",
            r.start_m,
            &format!("every pantograph must start inside the model (0, {l}) m (rearmost offset {max_off} m)"),
        ));
    }
    if r.end_m <= r.start_m - max_off {
        return Err(inv(
            "run.end_m",
            r.end_m,
            "must lie ahead of the rearmost pantograph's start",
        ));
    }
    if r.end_m + max_off >= l {
        return Err(inv(
            "run.end_m",
            r.end_m,
            &format!("the leading pantograph would leave the model (length {l} m) before the rearmost reaches it"),
        ));
    }
    analysis_section(case, max_off, w)?;
    Ok(())
}

/// The modes per wire (`modes` or `modes_per_m`, one of them): at most 200 000, at least 2 per
/// span; warned about below 0.3 per metre.
fn modes(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let c = &case.catenary;
    let r = &case.run;
    match (r.modes, r.modes_per_m) {
        (Some(_), Some(_)) => {
            return Err(inv(
                "run.modes",
                "both modes and modes_per_m",
                "give only one of them",
            ))
        }
        (None, None) => return Err(inv("run.modes", "missing", "give `modes` or `modes_per_m`")),
        (Some(n), None) if n == 0 => return Err(inv("run.modes", n, "must be at least 1")),
        (None, Some(dn)) => pos("run.modes_per_m", dn)?,
        _ => {}
    }
    let l = case.length_m();
    let field = if r.modes.is_some() {
        "run.modes"
    } else {
        "run.modes_per_m"
    };
    let shown = |n: usize| match r.modes_per_m {
        Some(d) if r.modes.is_none() => format!("{d} ({n} modes over {l} m)"),
        _ => n.to_string(),
    };
    let raw = match (r.modes, r.modes_per_m) {
        (Some(n), _) => n as f64,
        (None, Some(d)) => d * l,
        _ => 0.0,
    };
    if raw > 200_000.0 {
        return Err(inv(
            field,
            shown(raw as usize),
            "more than 200000 modes per wire",
        ));
    }
    let n = case.n_modes();
    // The shortest wave of the series, 2L/N, must be shorter than a span, or the series
    // cannot even show the span-to-span shape of the catenary.
    if (n as f64) < 2.0 * c.spans as f64 {
        return Err(inv(
            field,
            shown(n),
            &format!(
                "fewer than 2 modes per span ({} spans): the series cannot represent the catenary; about 1 mode per metre converges (docs/validation.md)",
                c.spans
            ),
        ));
    }
    if (n as f64) / l < 0.3 {
        w.push(Warning(format!(
            "{field} = {}: {:.2} modes per metre resolve the wires only to about {:.0} Hz; statistics converge at about 1 per metre (docs/validation.md)",
            shown(n),
            n as f64 / l,
            n as f64 / l * 60.0
        )));
    }
    Ok(())
}

/// The analysis section: inside the model, crossed whole by every pantograph (`max_off` the
/// rearmost's offset), and beginning once the leading one has settled (one span after its
/// start) unless the start transient is allowed (then a warning).
fn analysis_section(case: &Case, max_off: f64, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let r = &case.run;
    let l = case.length_m();
    let [a, b] = r.analysis_m;
    if !(a >= 0.0 && b <= l && a < b) {
        return Err(inv(
            "run.analysis_m",
            format!("[{a}, {b}]"),
            &format!("must be an interval inside the model [0, {l}] m"),
        ));
    }
    if a < r.start_m - max_off || b > r.end_m {
        return Err(inv(
            "run.analysis_m",
            format!("[{a}, {b}]"),
            &format!("every pantograph must cross the whole section: it must lie within [start_m − offset, end_m] = [{}, {}] m", r.start_m - max_off, r.end_m),
        ));
    }
    // The start transient: every pantograph settles over one span after its start, and the
    // leading one starts last (the furthest along), at start_m.
    let settled = r.start_m + case.catenary.span_m;
    if a < settled {
        let what = format!(
            "starts before the leading pantograph has settled: the section must begin at least one span after its start, at run.start_m + span_m = {settled} m, or the start transient enters the statistics"
        );
        if r.allow_start_transient {
            w.push(Warning(format!(
                "run.analysis_m = [{a}, {b}] {what} (allowed by run.allow_start_transient)"
            )));
        } else {
            return Err(inv(
                "run.analysis_m",
                format!("[{a}, {b}]"),
                &format!("{what}; set run.allow_start_transient = true to keep it with a warning"),
            ));
        }
    }
    Ok(())
}
