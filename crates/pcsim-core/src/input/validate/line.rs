//! A `[line]`: its tension lengths, the overlaps between them, and the working contact wire's
//! gradient along the supports.

use super::*;

/// A `[line]`: its tension lengths (spans, dropper layouts, heights at the supports, the wires
/// they override), the overlaps between them, and what a line does not carry yet.
pub(super) fn line(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let Some(line) = &case.line else {
        return Ok(());
    };
    let c = &case.catenary;
    let ntl = line.tension_lengths.len();
    if ntl == 0 {
        return Err(inv(
            "line.tension_lengths",
            "[]",
            "give at least one [[line.tension_lengths]]",
        ));
    }
    if ntl > 64 {
        return Err(inv(
            "line.tension_lengths",
            format!("{ntl} tension lengths"),
            "more than 64 tension lengths (about 90 km) is not a line this tool runs in one model",
        ));
    }
    line_physics(case, line)?;
    line_lateral(case, line, w)?;
    for (k, t) in line.tension_lengths.iter().enumerate() {
        tension_length(case, k, t, w)?;
    }
    if line.overlaps.len() != ntl - 1 {
        return Err(inv(
            "line.overlaps",
            format!("{} overlaps", line.overlaps.len()),
            &format!(
                "need one [[line.overlaps]] between each two consecutive tension lengths ({})",
                ntl - 1
            ),
        ));
    }
    for k in 0..line.overlaps.len() {
        overlap(line, k, w)?;
    }
    if c.spans != line.n_spans() {
        return Err(inv(
            "catenary.spans",
            c.spans,
            &format!(
                "the line has {} spans: omit catenary.spans with [line], or give {}",
                line.n_spans(),
                line.n_spans()
            ),
        ));
    }
    working_gradients(line, w)
}

/// Overlap `k` of a line: its shared spans are the same spans in both tension lengths, its
/// rise and separation in range, and it does not meet the next overlap.
fn overlap(line: &LineCase, k: usize, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let o = &line.overlaps[k];
    let f = |key: &str| format!("line.overlaps[{k}].{key}");
    let (a, b) = (
        line.tension_lengths[k].span_lengths_m(),
        line.tension_lengths[k + 1].span_lengths_m(),
    );
    if o.spans == 0 || o.spans > a.len() || o.spans > b.len() {
        return Err(inv(
            &f("spans"),
            o.spans,
            &format!(
                "an overlap shares 1 to min({}, {}) spans (the two tension lengths' spans)",
                a.len(),
                b.len()
            ),
        ));
    }
    for i in 0..o.spans {
        let (la, lb) = (a[a.len() - o.spans + i], b[i]);
        if (la - lb).abs() > 1e-3 {
            return Err(inv(
                &f("spans"),
                o.spans,
                &format!(
                    "shared span {} is {la} m in tension length {k} but {lb} m in tension length {}: an overlap's spans are the same spans",
                    i + 1,
                    k + 1
                ),
            ));
        }
    }
    check_bound(w, &f("rise_m"), o.rise_m, &bounds::OVERLAP_RISE)?;
    check_bound(
        w,
        &f("separation_m"),
        o.separation_m,
        &bounds::OVERLAP_SEPARATION,
    )?;
    if k + 1 < line.overlaps.len() {
        let next = &line.overlaps[k + 1];
        if o.spans + next.spans > b.len() {
            return Err(inv(
                &f("spans"),
                o.spans,
                &format!(
                    "tension length {} has {} spans: its two overlaps ({} and {} spans) may not meet",
                    k + 1,
                    b.len(),
                    o.spans,
                    next.spans
                ),
            ));
        }
    }
    Ok(())
}

/// What a line carries beyond the vertical model: lateral and torsional motion (checked in
/// [`line_lateral`]), ice on every tension length's own wires (each overriding wire with its
/// section), a crosswind on every tension length's wires (an overriding wire's section and
/// coefficients checked with its other fields), a profile of irregularity along the track.
fn line_physics(case: &Case, line: &LineCase) -> Result<(), CaseError> {
    let c = &case.catenary;
    // A profile along the track applies on a line; the dropper pattern repeats per span.
    for (i, ir) in case.irregularity.iter().enumerate() {
        if matches!(ir, IrregularityCase::Droppers { .. }) {
            return Err(inv(
                &format!("irregularity[{i}].kind"),
                "droppers",
                "the dropper-height pattern repeats in every span of a [catenary]; a [line]'s spans and dropper layouts differ: give a measured table or a psd profile along the track",
            ));
        }
    }
    // Ice sits on each tension length's own wires: a wire a tension length overrides needs its
    // section (the ice's mass and inertia follow from the diameter).
    if c.ice.is_some() {
        for (k, t) in line.tension_lengths.iter().enumerate() {
            for (name, w) in [
                ("messenger", &t.messenger),
                ("contact_wire", &t.contact_wire),
            ] {
                if w.as_ref().is_some_and(|w| w.section.is_none()) {
                    return Err(inv(
                        &format!("line.tension_lengths[{k}].{name}.section"),
                        "missing",
                        "catenary.ice needs the section (diameter_m) of every wire a tension length overrides",
                    ));
                }
            }
        }
    }
    Ok(())
}

/// The working contact wire's design gradient between consecutive supports of a line: the
/// height the pantograph runs at, at each support, is the lowest of the contact wires there (an
/// overlap's rise added at each wire's anchor). A gradient above
/// [`bounds::CONTACT_GRADIENT`]'s hard bound is a geometry error naming the support where the
/// height changes; above its soft bound, a warning.
pub(super) fn working_gradients(line: &LineCase, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    // (track position, working height, tension length, support index within it)
    let mut at: Vec<(f64, f64, usize, usize)> = Vec::new();
    let ntl = line.tension_lengths.len();
    for (k, t) in line.tension_lengths.iter().enumerate() {
        let xs = line.tension_length_supports_m(k);
        for (j, &x) in xs.iter().enumerate() {
            let mut h = t.contact_height_m.get(j).copied().unwrap_or(0.0);
            if j == 0 && k > 0 {
                h += line.overlaps.get(k - 1).map_or(0.0, |o| o.rise_m);
            }
            if j + 1 == xs.len() && k + 1 < ntl {
                h += line.overlaps.get(k).map_or(0.0, |o| o.rise_m);
            }
            match at.iter_mut().find(|a| (a.0 - x).abs() < 1e-3) {
                Some(a) if h < a.1 => *a = (x, h, k, j),
                Some(_) => {}
                None => at.push((x, h, k, j)),
            }
        }
    }
    at.sort_by(|a, b| a.0.total_cmp(&b.0));
    let b = &bounds::CONTACT_GRADIENT;
    let mut worst: Option<(f64, usize)> = None;
    for i in 1..at.len() {
        let (x0, h0, ..) = at[i - 1];
        let (x1, h1, k, j) = at[i];
        let g = (h1 - h0) / (x1 - x0);
        let field = format!("line.tension_lengths[{k}].contact_height_m[{j}]");
        if g.abs() > b.hard.1 {
            return Err(inv(
                &field,
                format!("{h1} m"),
                &format!(
                    "the working contact wire changes height by {:+.3} m between the supports at {x0:.1} m and {x1:.1} m (tension length {}, support {j}): a gradient of {:.2} % (1:{:.0}), steeper than {:.1} % (1:{:.0}), {}; a pantograph cannot follow it (the run would blow up, not measure anything)",
                    h1 - h0,
                    k + 1,
                    100.0 * g.abs(),
                    1.0 / g.abs(),
                    100.0 * b.hard.1,
                    1.0 / b.hard.1,
                    b.typical
                ),
            ));
        }
        if g.abs() > b.soft.1 && worst.is_none_or(|(v, _)| g.abs() > v) {
            worst = Some((g.abs(), i));
        }
    }
    if let Some((g, i)) = worst {
        let (x0, x1, k, j) = (at[i - 1].0, at[i].0, at[i].2, at[i].3);
        w.push(Warning(format!(
            "line.tension_lengths[{k}].contact_height_m[{j}]: the working contact wire's gradient reaches {:.2} % (1:{:.0}) between the supports at {x0:.1} m and {x1:.1} m: unusual (typical: {})",
            100.0 * g,
            1.0 / g,
            b.typical
        )));
    }
    Ok(())
}

/// Tension length `k` of a line.
pub(super) fn tension_length(
    case: &Case,
    k: usize,
    t: &TensionLengthCase,
    w: &mut Vec<Warning>,
) -> Result<(), CaseError> {
    let c = t.catenary(&case.catenary);
    let f = |key: &str| format!("line.tension_lengths[{k}].{key}");
    overridden_sections(case, k, t, &c, w)?;
    let n = t.n_spans();
    if t.spans_m.is_empty() == t.span_runs.is_empty() {
        return Err(inv(
            &f("spans_m"),
            if t.spans_m.is_empty() {
                "neither"
            } else {
                "both"
            },
            "give the spans one by one (spans_m) or as runs (span_runs), one of them",
        ));
    }
    if !(2..=5000).contains(&n) {
        return Err(inv(
            &f("spans_m"),
            format!("{n} spans"),
            "need 2 to 5000 spans in a tension length",
        ));
    }
    for (j, r) in t.span_runs.iter().enumerate() {
        if r.count == 0 {
            return Err(inv(&f(&format!("span_runs[{j}].count")), 0, "must be ≥ 1"));
        }
        check_bound(
            w,
            &f(&format!("span_runs[{j}].length_m")),
            r.length_m,
            &bounds::SPAN,
        )?;
    }
    for (j, &s) in t.spans_m.iter().enumerate() {
        check_bound(w, &f(&format!("spans_m[{j}]")), s, &bounds::SPAN)?;
    }
    let lengths = t.span_lengths_m();
    if !t.droppers_m.is_empty() && t.droppers_m.len() != n {
        return Err(inv(
            &f("droppers_m"),
            format!("{} layouts", t.droppers_m.len()),
            &format!("need one dropper layout per span ({n}), or none (the catenary's, scaled)"),
        ));
    }
    dropper_layouts(k, t, &c, &lengths)?;
    for (key, v) in [
        ("contact_height_m", &t.contact_height_m),
        ("encumbrance_m", &t.encumbrance_m),
    ] {
        if !v.is_empty() && v.len() != n + 1 {
            return Err(inv(
                &f(key),
                format!("{} values", v.len()),
                &format!("need one value per support ({}), or none", n + 1),
            ));
        }
    }
    for (j, &h) in t.contact_height_m.iter().enumerate() {
        check_bound(
            w,
            &f(&format!("contact_height_m[{j}]")),
            h,
            &bounds::CONTACT_HEIGHT_CHANGE,
        )?;
    }
    for (j, &e) in t.encumbrance_m.iter().enumerate() {
        check_bound(
            w,
            &f(&format!("encumbrance_m[{j}]")),
            e,
            &bounds::ENCUMBRANCE,
        )?;
    }
    stitch_layouts(k, t, &c, &lengths)?;
    Ok(())
}

/// The catenary's own checks on what tension length `k` overrides (its wires, droppers,
/// supports, arms), named as its fields; their warnings renamed too.
fn overridden_sections(
    case: &Case,
    k: usize,
    t: &TensionLengthCase,
    c: &CatenaryCase,
    w: &mut Vec<Warning>,
) -> Result<(), CaseError> {
    let f = |key: &str| format!("line.tension_lengths[{k}].{key}");
    if OVERRIDES.iter().any(|key| t.overrides(key)) {
        let mut alone = case.clone();
        alone.line = None;
        alone.catenary = c.clone();
        let rename = |e: CaseError| match e {
            CaseError::Invalid {
                field,
                value,
                reason,
            } => {
                let key = OVERRIDES
                    .iter()
                    .find(|key| t.overrides(key) && field.starts_with(&format!("catenary.{key}")));
                CaseError::Invalid {
                    field: match key {
                        Some(key) => field.replacen(&format!("catenary.{key}"), &f(key), 1),
                        None => field,
                    },
                    value,
                    reason,
                }
            }
            other => other,
        };
        let mut scratch = Vec::new();
        geometry_and_wires(&alone, &mut scratch).map_err(rename)?;
        droppers(&alone, &mut scratch).map_err(rename)?;
        supports_and_arms(&alone, &mut scratch).map_err(rename)?;
        stitch_wire(&alone, &mut scratch).map_err(rename)?;
        // The lateral model, the wind and the ice read an overriding wire's section.
        lateral_sections(&alone, &mut scratch).map_err(rename)?;
        for Warning(text) in scratch {
            if let Some(key) = OVERRIDES
                .iter()
                .find(|key| t.overrides(key) && text.contains(&format!("catenary.{key}")))
            {
                w.push(Warning(text.replace(&format!("catenary.{key}"), &f(key))));
            }
        }
    }
    Ok(())
}

/// Tension length `k`'s dropper layouts: one per span or none, at least one dropper each, as many
/// as the reference layout where a stitch wire or a pre-sag table refers to it, increasing inside
/// the span.
fn dropper_layouts(
    k: usize,
    t: &TensionLengthCase,
    c: &CatenaryCase,
    lengths: &[f64],
) -> Result<(), CaseError> {
    let f = |key: &str| format!("line.tension_lengths[{k}].{key}");
    let n_ref = c.droppers.positions_m.len();
    for (j, d) in t.droppers_m.iter().enumerate() {
        let field = f(&format!("droppers_m[{j}]"));
        if d.is_empty() {
            return Err(inv(&field, "[]", "need at least one dropper per span"));
        }
        let needs_ref_count = c.stitch_wire.is_some() || matches!(c.presag, Presag::Table { .. });
        if needs_ref_count && d.len() != n_ref {
            return Err(inv(
                &field,
                format!("{} droppers", d.len()),
                &format!("the stitch wire's dropper indices and a pre-sag table refer to catenary.droppers.positions_m: give {n_ref} droppers in every span"),
            ));
        }
        let mut prev = 0.0;
        for (i, &x) in d.iter().enumerate() {
            if x <= prev || x >= lengths[j] {
                return Err(inv(
                    &format!("{field}[{i}]"),
                    x,
                    &format!(
                        "positions must increase inside the span (0, {}) m",
                        lengths[j]
                    ),
                ));
            }
            prev = x;
        }
    }
    Ok(())
}

/// Every span of tension length `k` longer than the stitch wire, and its stitch droppers under it.
fn stitch_layouts(
    k: usize,
    t: &TensionLengthCase,
    c: &CatenaryCase,
    lengths: &[f64],
) -> Result<(), CaseError> {
    let f = |key: &str| format!("line.tension_lengths[{k}].{key}");
    if let Some(st) = &c.stitch_wire {
        for (j, &len) in lengths.iter().enumerate() {
            if st.length_m >= len {
                return Err(inv(
                    &f(&format!("spans_m[{j}]")),
                    len,
                    &format!(
                        "the stitch wire ({} m) must be shorter than every span",
                        st.length_m
                    ),
                ));
            }
            let d = t.droppers_of_span(j, len, &c.droppers.positions_m, c.span_m);
            for &i in &st.droppers {
                if let Some(&x) = d.get(i) {
                    if x.min(len - x) >= 0.5 * st.length_m - 1e-9 {
                        return Err(inv(
                            &f(&format!("droppers_m[{j}]")),
                            x,
                            &format!("stitch dropper {i} of span {j} is not under a stitch wire (±{} m around the support)", 0.5 * st.length_m),
                        ));
                    }
                }
            }
        }
    }
    Ok(())
}

/// A line's lateral layout: each tension length's own stagger (one value per support, within
/// the stagger's bounds, its usual range judged from the head's centre on a canted curve), each
/// run of spans' curve (a finite radius within its bounds and at least five spans long, a cant
/// only with a radius), the default curve of `catenary.lateral` against every span it covers,
/// and an overlap's shared spans on one curve in both tension lengths. What only the lateral
/// model reads is refused without it, so that nothing given is silently ignored.
fn line_lateral(case: &Case, line: &LineCase, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let lat = case
        .catenary
        .lateral
        .as_ref()
        .filter(|_| case.run.dofs.contains(&Dof::Lateral));
    let default = lat.map_or((None, 0.0), |l| (l.track_radius_m, l.cant_m));
    let needs = "is read by the lateral model: give [catenary.lateral] and \"lateral\" in run.dofs";
    let mut curves: Vec<Vec<(Option<f64>, f64)>> = Vec::new();
    for (k, tl) in line.tension_lengths.iter().enumerate() {
        let tf = |name: &str| format!("line.tension_lengths[{k}].{name}");
        for (i, run) in tl.span_runs.iter().enumerate() {
            let f = |name: &str| tf(&format!("span_runs[{i}].{name}"));
            if let Some(r) = run.track_radius_m {
                if lat.is_none() {
                    return Err(inv(&f("track_radius_m"), num(r), needs));
                }
                if !r.is_finite() {
                    return Err(inv(&f("track_radius_m"), num(r), "must be a finite number"));
                }
                check_bound(w, &f("track_radius_m"), r.abs(), &bounds::TRACK_RADIUS)?;
            }
            if let Some(cant) = run.cant_m {
                if lat.is_none() {
                    return Err(inv(&f("cant_m"), num(cant), needs));
                }
                check_bound(w, &f("cant_m"), cant, &bounds::CANT)?;
                if cant != 0.0 && run.track_radius_m.or(default.0).is_none() {
                    return Err(inv(
                        &f("cant_m"),
                        num(cant),
                        "a cant needs a curve: give this run's track_radius_m or catenary.lateral.track_radius_m (a straight track has no cant)",
                    ));
                }
            }
        }
        // Every span against the radius it lies on (the run's own, or catenary.lateral's).
        let c = tl.span_curves(default);
        for (j, (s, (r, _))) in tl.span_lengths_m().iter().zip(&c).enumerate() {
            if let Some(r) = *r {
                if *s > 0.2 * r.abs() {
                    let own = tl
                        .run_of_span(j)
                        .filter(|&i| tl.span_runs[i].track_radius_m.is_some());
                    let field = own.map_or("catenary.lateral.track_radius_m".to_string(), |i| {
                        tf(&format!("span_runs[{i}].track_radius_m"))
                    });
                    return Err(inv(
                        &field,
                        num(r),
                        &format!(
                            "span {j} of tension length {k} is {s} m long on a radius of {} m: the chord's bow is taken to second order in span/radius, valid up to a span of a fifth of the radius",
                            r.abs()
                        ),
                    ));
                }
            }
        }
        if !tl.stagger_m.is_empty() {
            let Some(l) = lat else {
                return Err(inv(&tf("stagger_m"), "given", needs));
            };
            let n = tl.n_spans() + 1;
            if tl.stagger_m.len() != n {
                return Err(inv(
                    &tf("stagger_m"),
                    format!("{} values", tl.stagger_m.len()),
                    &format!("give one stagger per support of the tension length: {n} values"),
                ));
            }
            for (j, &y) in tl.stagger_m.iter().enumerate() {
                let field = tf(&format!("stagger_m[{j}]"));
                check_bound(&mut Vec::new(), &field, y, &bounds::STAGGER)?;
                // The usual range from the head's centre: a canted curve's span beside it.
                let (r, cant) = c[j.min(c.len().saturating_sub(1))];
                let off = crate::input::lateral::head_offset_m(r, cant, l.contact_wire_height_m);
                let usual = bounds::Bound {
                    hard: (f64::NEG_INFINITY, f64::INFINITY),
                    ..bounds::STAGGER
                };
                check_bound(w, &field, y - off, &usual)?;
            }
        }
        curves.push(c);
    }
    overlaps_on_one_track(line, &curves)
}

/// An overlap's shared spans lie on one track: one curve in both tension lengths (`curves`: each
/// tension length's (radius, cant) per span). An overlap list that does not fit the tension
/// lengths is refused after this, by count and by span: only the overlaps that fit are compared.
fn overlaps_on_one_track(
    line: &LineCase,
    curves: &[Vec<(Option<f64>, f64)>],
) -> Result<(), CaseError> {
    // An overlap's shared spans lie on one track: one curve in both tension lengths.
    // (An overlap list that does not fit the tension lengths is refused after this, by count
    // and by span: only the overlaps that fit are compared here.)
    for (k, o) in line.overlaps.iter().enumerate() {
        let (Some(a), Some(b)) = (curves.get(k), curves.get(k + 1)) else {
            break;
        };
        let Some(first) = a.len().checked_sub(o.spans) else {
            continue;
        };
        for j in 0..o.spans.min(b.len()) {
            let (ca, cb) = (a[first + j], b[j]);
            if ca != cb {
                return Err(inv(
                    &format!("line.tension_lengths[{}].span_runs", k + 1),
                    format!("{}, cant {} m", radius_text(cb.0), cb.1),
                    &format!(
                        "span {j} of overlap {k} is shared with tension length {k}, which puts it on {}, cant {} m: an overlap's spans lie on one track",
                        radius_text(ca.0), ca.1
                    ),
                ));
            }
        }
    }
    Ok(())
}

/// A run's radius as a sentence names it: `radius 4000 m`, or `straight track`.
fn radius_text(r: Option<f64>) -> String {
    r.map_or_else(|| "straight track".into(), |r| format!("radius {r} m"))
}
