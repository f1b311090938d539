//! Validation of a case, in one place (issue 18): [`Case::validate`] runs the sections below in a
//! fixed order (the first error found is the one reported, as the hardening tests pin), each
//! against the one table of bounds (`input::bounds`). The case's types know nothing of it, so
//! validation imports them and nothing imports validation: no circle.

use crate::error::{CaseError, Warning};
use crate::input::bounds::{self, check_bound, inv, Bound};
use crate::input::case::*;
use crate::input::irregularity::IrregularityCase;
use crate::input::lateral::*;
use crate::input::line::{LineCase, TensionLengthCase, OVERRIDES};

/// A positive finite number, or an error naming the field.
fn pos(field: &str, v: f64) -> Result<(), CaseError> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(inv(field, v, "must be a finite number > 0"))
    }
}

impl Case {
    /// Check every value; return warnings, or an error naming the field and its value.
    ///
    /// Every number has plausibility bounds: outside the hard bounds it is physically
    /// meaningless (an error), outside the soft bounds merely unusual (a warning naming the
    /// field and the typical range). See [`bounds`].
    pub fn validate(&self) -> Result<Vec<Warning>, CaseError> {
        let mut w = Vec::new();
        finite_all(self)?;
        line(self, &mut w)?;
        geometry_and_wires(self, &mut w)?;
        droppers(self, &mut w)?;
        presag(self, &mut w)?;
        damping(self, &mut w)?;
        supports_and_arms(self, &mut w)?;
        stitch_wire(self, &mut w)?;
        contact_and_pantographs(self, &mut w)?;
        dropper_fatigue(self, &mut w)?;
        run(self, &mut w)?;
        lateral_dofs(self, &mut w)?;
        lateral_sections(self, &mut w)?;
        lateral_geometry(self, &mut w)?;
        ice(self, &mut w)?;
        wind(self, &mut w)?;
        pantograph_heads(self, &mut w)?;
        irregularity(self, &mut w)?;
        Ok(w)
    }
}

/// Reject NaN and infinities anywhere in the case, naming the field.
fn finite_all(case: &Case) -> Result<(), CaseError> {
    let v = toml::Value::try_from(case).map_err(|e| CaseError::Parse(e.to_string()))?;
    fn walk(v: &toml::Value, path: &str) -> Result<(), CaseError> {
        match v {
            toml::Value::Float(f) if !f.is_finite() => Err(inv(path, f, "must be finite")),
            toml::Value::Table(t) => {
                for (k, x) in t {
                    let p = if path.is_empty() {
                        k.clone()
                    } else {
                        format!("{path}.{k}")
                    };
                    walk(x, &p)?;
                }
                Ok(())
            }
            toml::Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    walk(x, &format!("{path}[{i}]"))?;
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }
    walk(&v, "")
}

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
    for (field, given) in [
        (
            "run.dofs",
            case.run.dofs.iter().any(|d| *d != Dof::Vertical),
        ),
        ("catenary.lateral", c.lateral.is_some()),
        ("catenary.ice", c.ice.is_some()),
        ("wind", case.wind.is_some()),
        ("irregularity", !case.irregularity.is_empty()),
    ] {
        if given {
            return Err(inv(
                field,
                "given",
                "a [line] is vertical only in this version, without ice, wind or irregularity: use [catenary] for those",
            ));
        }
    }
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
    for (k, o) in line.overlaps.iter().enumerate() {
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

/// The working contact wire's design gradient between consecutive supports of a line: the
/// height the pantograph runs at, at each support, is the lowest of the contact wires there (an
/// overlap's rise added at each wire's anchor). A gradient above
/// [`bounds::CONTACT_GRADIENT`]'s hard bound is a geometry error naming the support where the
/// height changes; above its soft bound, a warning.
fn working_gradients(line: &LineCase, w: &mut Vec<Warning>) -> Result<(), CaseError> {
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
fn tension_length(
    case: &Case,
    k: usize,
    t: &TensionLengthCase,
    w: &mut Vec<Warning>,
) -> Result<(), CaseError> {
    let base = &case.catenary;
    let c = t.catenary(base);
    let f = |key: &str| format!("line.tension_lengths[{k}].{key}");
    // The catenary's own checks on what this tension length overrides, named as its fields.
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
        for Warning(text) in scratch {
            if let Some(key) = OVERRIDES
                .iter()
                .find(|key| t.overrides(key) && text.contains(&format!("catenary.{key}")))
            {
                w.push(Warning(text.replace(&format!("catenary.{key}"), &f(key))));
            }
        }
    }
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

/// The number and length of spans, the system height and the wires.
pub(super) fn geometry_and_wires(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let c = &case.catenary;
    if c.spans < 2 {
        return Err(inv("catenary.spans", c.spans, "need at least 2 spans"));
    }
    if c.spans > 5000 {
        return Err(inv(
            "catenary.spans",
            c.spans,
            "more than 5000 spans (300 km at 60 m) is not a catenary model this tool can run",
        ));
    }
    if c.spans > 200 {
        w.push(Warning(format!(
            "catenary.spans = {}: unusually many spans (typical: 10–60); the run's cost grows with the length",
            c.spans
        )));
    }
    check_bound(w, "catenary.span_m", c.span_m, &bounds::SPAN)?;
    check_bound(
        w,
        "catenary.encumbrance_m",
        c.encumbrance_m,
        &bounds::ENCUMBRANCE,
    )?;
    for (name, wire) in [
        ("contact_wire", &c.contact_wire),
        ("messenger", &c.messenger),
    ] {
        let f = |k: &str| format!("catenary.{name}.{k}");
        check_bound(
            w,
            &f("mass_per_m_kg"),
            wire.mass_per_m_kg,
            &bounds::WIRE_MASS,
        )?;
        check_bound(w, &f("tension_n"), wire.tension_n, &bounds::TENSION)?;
        check_bound(w, &f("ei_nm2"), wire.ei_nm2, &bounds::EI)?;
    }
    Ok(())
}

/// The droppers: positions within the span, stiffness, clamp masses.
pub(super) fn droppers(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let c = &case.catenary;
    let d = &c.droppers;
    if d.positions_m.is_empty() {
        return Err(inv(
            "catenary.droppers.positions_m",
            "[]",
            "need at least one dropper per span",
        ));
    }
    let mut prev = 0.0;
    for (i, &x) in d.positions_m.iter().enumerate() {
        if x <= 0.0 || x >= c.span_m {
            return Err(inv(
                &format!("catenary.droppers.positions_m[{i}]"),
                x,
                &format!("dropper lies outside its span (0, {}) m", c.span_m),
            ));
        }
        if x <= prev && i > 0 {
            return Err(inv(
                &format!("catenary.droppers.positions_m[{i}]"),
                x,
                "positions must increase",
            ));
        }
        prev = x;
    }
    match (d.stiffness_n_per_m, d.ea_n) {
        (Some(k), None) => check_bound(
            w,
            "catenary.droppers.stiffness_n_per_m",
            k,
            &bounds::DROPPER_STIFFNESS,
        )?,
        (None, Some(ea)) => check_bound(w, "catenary.droppers.ea_n", ea, &bounds::DROPPER_EA)?,
        _ => {
            return Err(inv(
                "catenary.droppers.stiffness_n_per_m",
                "both or neither of stiffness_n_per_m and ea_n",
                "give exactly one of them",
            ))
        }
    }
    check_bound(
        w,
        "catenary.droppers.clamp_mass_messenger_kg",
        d.clamp_mass_messenger_kg,
        &bounds::CLAMP_MASS,
    )?;
    check_bound(
        w,
        "catenary.droppers.clamp_mass_contact_kg",
        d.clamp_mass_contact_kg,
        &bounds::CLAMP_MASS,
    )?;
    check_bound(
        w,
        "catenary.droppers.mass_per_m_kg",
        d.mass_per_m_kg,
        &bounds::DROPPER_MASS,
    )?;
    Ok(())
}

/// The contact wire's pre-sag.
pub(super) fn presag(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let c = &case.catenary;
    let d = &c.droppers;
    // Pre-sag: beyond span/100 (0.6 m on 60 m) no pantograph follows the wire; typical
    // designs stay below span/500.
    let presag_bound = Bound {
        hard: (-c.span_m / 100.0, c.span_m / 100.0),
        soft: (0.0, c.span_m / 500.0),
        unit: "m",
        typical: "0 to span/500 (downward positive)",
    };
    match &c.presag {
        Presag::Parabolic { mid_span_m, .. } => {
            check_bound(w, "catenary.presag.mid_span_m", *mid_span_m, &presag_bound)?;
        }
        Presag::Table { values_m } => {
            if values_m.len() != d.positions_m.len() {
                return Err(inv(
                    "catenary.presag.values_m",
                    format!("{} values", values_m.len()),
                    &format!("need one value per dropper ({})", d.positions_m.len()),
                ));
            }
            for (i, v) in values_m.iter().enumerate() {
                check_bound(
                    w,
                    &format!("catenary.presag.values_m[{i}]"),
                    *v,
                    &presag_bound,
                )?;
            }
        }
    }
    Ok(())
}

/// The wires' damping law.
pub(super) fn damping(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let c = &case.catenary;
    match &c.damping {
        Damping::Rayleigh { alpha, beta } => {
            check_bound(w, "catenary.damping.alpha", *alpha, &bounds::RAYLEIGH_ALPHA)?;
            check_bound(w, "catenary.damping.beta", *beta, &bounds::RAYLEIGH_BETA)?;
        }
        Damping::Modal { ratio } => {
            check_bound(w, "catenary.damping.ratio", *ratio, &bounds::MODAL_RATIO)?;
        }
    }
    Ok(())
}

/// Messenger supports and steady arms.
pub(super) fn supports_and_arms(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let c = &case.catenary;
    check_bound(
        w,
        "catenary.messenger_support.stiffness_n_per_m",
        c.messenger_support.stiffness_n_per_m,
        &bounds::SUPPORT_STIFFNESS,
    )?;
    check_bound(
        w,
        "catenary.messenger_support.damping_ns_per_m",
        c.messenger_support.damping_ns_per_m,
        &bounds::SUPPORT_DAMPING,
    )?;
    check_bound(
        w,
        "catenary.steady_arm.mass_kg",
        c.steady_arm.mass_kg,
        &bounds::ARM_MASS,
    )?;
    check_bound(
        w,
        "catenary.steady_arm.stiffness_n_per_m",
        c.steady_arm.stiffness_n_per_m,
        &bounds::SUPPORT_STIFFNESS,
    )?;
    Ok(())
}

/// The stitch wire, where there is one.
pub(super) fn stitch_wire(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let c = &case.catenary;
    let d = &c.droppers;
    if let Some(st) = &c.stitch_wire {
        check_bound(
            w,
            "catenary.stitch_wire.length_m",
            st.length_m,
            &bounds::STITCH_LENGTH,
        )?;
        check_bound(
            w,
            "catenary.stitch_wire.tension_n",
            st.tension_n,
            &bounds::STITCH_TENSION,
        )?;
        check_bound(
            w,
            "catenary.stitch_wire.mass_per_m_kg",
            st.mass_per_m_kg,
            &bounds::DROPPER_MASS,
        )?;
        check_bound(
            w,
            "catenary.stitch_wire.clamp_mass_kg",
            st.clamp_mass_kg,
            &bounds::CLAMP_MASS,
        )?;
        if let Some(cs) = st.damping_ns_per_m {
            check_bound(
                w,
                "catenary.stitch_wire.damping_ns_per_m",
                cs,
                &bounds::SUPPORT_DAMPING,
            )?;
        }
        if st.length_m >= c.span_m {
            return Err(inv(
                "catenary.stitch_wire.length_m",
                st.length_m,
                "must be shorter than the span",
            ));
        }
        if st.droppers.is_empty() {
            return Err(inv(
                "catenary.stitch_wire.droppers",
                "[]",
                "name the droppers that hang from the stitch wire",
            ));
        }
        for (j, &i) in st.droppers.iter().enumerate() {
            let field = format!("catenary.stitch_wire.droppers[{j}]");
            let Some(&x) = d.positions_m.get(i) else {
                return Err(inv(
                    &field,
                    i,
                    &format!("no such dropper (there are {})", d.positions_m.len()),
                ));
            };
            let to_support = x.min(c.span_m - x);
            if to_support >= 0.5 * st.length_m - 1e-9 {
                return Err(inv(
                    &field,
                    i,
                    &format!(
                        "dropper at {x} m is not under a stitch wire (±{} m around the support)",
                        0.5 * st.length_m
                    ),
                ));
            }
        }
        if c.steady_arm.static_support {
            w.push(Warning(
                "stitched catenary with catenary.steady_arm.static_support = true: the arm, not the stitch droppers, holds the contact wire at the support".into(),
            ));
        }
    }
    Ok(())
}

/// The dropper wire's S–N curve.
fn dropper_fatigue(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let Some(f) = &case.dropper_fatigue else {
        return Ok(());
    };
    check_bound(
        w,
        "dropper_fatigue.area_mm2",
        f.area_mm2,
        &bounds::DROPPER_AREA,
    )?;
    check_bound(w, "dropper_fatigue.sn_slope", f.sn_slope, &bounds::SN_SLOPE)?;
    check_bound(
        w,
        "dropper_fatigue.sn_stress_range_mpa",
        f.sn_stress_range_mpa,
        &bounds::SN_STRESS_RANGE,
    )?;
    check_bound(
        w,
        "dropper_fatigue.sn_cycles",
        f.sn_cycles,
        &bounds::SN_CYCLES,
    )
}

/// The contact stiffness and the pantographs.
pub(super) fn contact_and_pantographs(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    check_bound(
        w,
        "contact.stiffness_n_per_m",
        case.contact.stiffness_n_per_m,
        &bounds::CONTACT_STIFFNESS,
    )?;

    let r = &case.run;
    check_bound(w, "run.speed_kmh", r.speed_kmh, &bounds::SPEED)?;
    // The speed is checked against the wave speed of the built model (one definition, with the
    // clamps smeared in): see `solve::Plan::check`.
    if case.pantographs.is_empty() {
        return Err(inv("pantographs", "[]", "need at least one pantograph"));
    }
    for (i, p) in case.pantographs.iter().enumerate() {
        let base = format!("pantographs[{i}]");
        // The name heads the pantograph's columns in timeseries.csv and names its figures: one
        // per pantograph, and nothing a CSV header or a file name would split.
        let name = p.output_name(i);
        if let Some(c) = name
            .chars()
            .find(|c| c.is_control() || matches!(c, ',' | '"' | '/' | '\\'))
        {
            return Err(inv(
                &format!("{base}.name"),
                format!("{:?}", p.name()),
                &format!("holds {c:?}: a name heads CSV columns and names files (letters, digits, spaces, - and _)"),
            ));
        }
        if let Some(j) = (0..i).find(|&j| case.pantographs[j].output_name(j) == name) {
            return Err(inv(
                &format!("{base}.name"),
                format!("{name:?}"),
                &format!("pantographs[{j}] has the same name: each pantograph's columns and figures need their own name"),
            ));
        }
        check_bound(
            w,
            &format!("{base}.offset_m"),
            p.offset_m(),
            &bounds::OFFSET,
        )?;
        match p {
            PantographCase::Lumped { .. } => lumped_pantograph(w, &base, p, r.speed_kmh)?,
            PantographCase::MovingForce {
                force_n,
                lateral_force_n,
                ..
            } => {
                check_bound(
                    w,
                    &format!("{base}.force_n"),
                    *force_n,
                    &bounds::MOVING_FORCE,
                )?;
                check_bound(
                    w,
                    &format!("{base}.lateral_force_n"),
                    *lateral_force_n,
                    &bounds::MOVING_LATERAL_FORCE,
                )?;
            }
        }
    }
    Ok(())
}

/// A lumped pantograph (Eq. 16): its masses, springs and dampers (one each per mass), static
/// uplift and aerodynamic polynomial (its force at the run's speed).
fn lumped_pantograph(
    w: &mut Vec<Warning>,
    base: &str,
    p: &PantographCase,
    speed_kmh: f64,
) -> Result<(), CaseError> {
    let PantographCase::Lumped {
        masses_kg,
        stiffness_n_per_m,
        damping_ns_per_m,
        uplift_n,
        aero_coeffs_kmh,
        ..
    } = p
    else {
        return Ok(());
    };
    if masses_kg.is_empty() {
        return Err(inv(
            &format!("{base}.masses_kg"),
            "[]",
            "need at least one mass",
        ));
    }
    if masses_kg.len() > 20 {
        return Err(inv(
            &format!("{base}.masses_kg"),
            format!("{} masses", masses_kg.len()),
            "a lumped pantograph has a handful of masses (at most 20)",
        ));
    }
    for (j, &m) in masses_kg.iter().enumerate() {
        check_bound(
            w,
            &format!("{base}.masses_kg[{j}]"),
            m,
            &bounds::PANTOGRAPH_MASS,
        )?;
    }
    for (field, v, b) in [
        (
            "stiffness_n_per_m",
            stiffness_n_per_m,
            &bounds::PANTOGRAPH_STIFFNESS,
        ),
        (
            "damping_ns_per_m",
            damping_ns_per_m,
            &bounds::PANTOGRAPH_DAMPING,
        ),
    ] {
        if v.len() != masses_kg.len() {
            return Err(inv(
                &format!("{base}.{field}"),
                format!("{} values", v.len()),
                &format!("need one value per mass ({})", masses_kg.len()),
            ));
        }
        for (j, &x) in v.iter().enumerate() {
            check_bound(w, &format!("{base}.{field}[{j}]"), x, b)?;
        }
    }
    check_bound(w, &format!("{base}.uplift_n"), *uplift_n, &bounds::UPLIFT)?;
    if aero_coeffs_kmh.len() > 8 {
        return Err(inv(
            &format!("{base}.aero_coeffs_kmh"),
            format!("{} coefficients", aero_coeffs_kmh.len()),
            "a polynomial of degree at most 7",
        ));
    }
    let v = speed_kmh;
    let aero = crate::model::pantograph::aero_force_n(aero_coeffs_kmh, v);
    check_bound(
        w,
        &format!("{base}.aero_coeffs_kmh (the force at {v} km/h, N)"),
        aero,
        &bounds::AERO,
    )?;
    Ok(())
}

/// The time step, the number of modes, and where the run starts, ends and is analysed.
pub(super) fn run(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let c = &case.catenary;
    let r = &case.run;
    check_bound(w, "run.dt_s", r.dt_s, &bounds::DT)?;
    if !(r.perturb_uplift_rel.is_finite() && (0.0..=1e-3).contains(&r.perturb_uplift_rel)) {
        return Err(inv(
            "run.perturb_uplift_rel",
            r.perturb_uplift_rel,
            "must lie in [0, 1e-3]: a perturbation to put an error bar on threshold-sensitive statistics, not a change of the uplift",
        ));
    }
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

/// The modelled directions.
pub(super) fn lateral_dofs(case: &Case, _w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let dofs = &case.run.dofs;
    if !dofs.contains(&Dof::Vertical) {
        return Err(inv(
            "run.dofs",
            format!("{dofs:?}"),
            "must include \"vertical\": the pantograph touches the wire vertically",
        ));
    }
    for (i, d) in dofs.iter().enumerate() {
        if dofs[..i].contains(d) {
            return Err(inv(
                "run.dofs",
                format!("{dofs:?}"),
                "a direction is listed twice",
            ));
        }
    }
    let lateral = dofs.contains(&Dof::Lateral);
    let torsional = dofs.contains(&Dof::Torsional);
    if torsional && !lateral {
        return Err(inv(
            "run.dofs",
            format!("{dofs:?}"),
            "torsion is coupled through lateral forces at eccentric clamps: model \"lateral\" too",
        ));
    }
    Ok(())
}

/// The wires' lateral and torsional section data.
pub(super) fn lateral_sections(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let lateral = case.run.dofs.contains(&Dof::Lateral);
    let torsional = case.run.dofs.contains(&Dof::Torsional);
    let per_m = case.n_modes() as f64 / case.length_m();
    let need = bounds::LATERAL_MODES_PER_M_FOR_1_PCT;
    if lateral && per_m < need {
        w.push(Warning(format!(
            "run.modes gives {per_m:.2} modes per metre: the lateral blow-off converges within 1 % from {need} per metre (at 0.67 per metre it is 1.6 % low; docs/validation.md, the mode-density study)"
        )));
    }
    let need = bounds::ICE_MODES_PER_M_FOR_1_PCT;
    if case.catenary.ice.is_some() && per_m < need {
        w.push(Warning(format!(
            "catenary.ice with {per_m:.2} modes per metre: the ice's sag converges within 1 % from {need} per metre (at 1 per metre it is about 1.5 % short at mid-span; docs/validation.md, the ice sag)"
        )));
    }
    let c = &case.catenary;
    for (name, wire) in [
        ("contact_wire", &c.contact_wire),
        ("messenger", &c.messenger),
    ] {
        let f = |k: &str| format!("catenary.{name}.section.{k}");
        let needs = lateral || case.wind.is_some() || c.ice.is_some();
        let Some(s) = &wire.section else {
            if needs {
                return Err(inv(
                    &format!("catenary.{name}.section"),
                    "missing",
                    "lateral motion, wind and ice need the wire's section (diameter_m, and gj_nm2 and polar_inertia_kg_m for torsion)",
                ));
            }
            continue;
        };
        check_bound(w, &f("diameter_m"), s.diameter_m, &bounds::DIAMETER)?;
        if let Some(ei) = s.ei_lateral_nm2 {
            check_bound(w, &f("ei_lateral_nm2"), ei, &bounds::EI)?;
        }
        match (s.gj_nm2, s.polar_inertia_kg_m) {
            (Some(gj), Some(ip)) => {
                check_bound(w, &f("gj_nm2"), gj, &bounds::GJ)?;
                check_bound(w, &f("polar_inertia_kg_m"), ip, &bounds::POLAR)?;
            }
            _ if torsional => {
                return Err(inv(
                    &f(if s.gj_nm2.is_none() {
                        "gj_nm2"
                    } else {
                        "polar_inertia_kg_m"
                    }),
                    "missing",
                    "torsional motion needs gj_nm2 and polar_inertia_kg_m",
                ))
            }
            _ => {}
        }
        match &s.aero {
            Some(a) => {
                let n = a.attack_deg.len();
                if n < 2 {
                    return Err(inv(
                        &f("aero.attack_deg"),
                        format!("{n} angles"),
                        "need at least two angles",
                    ));
                }
                for i in 1..n {
                    if a.attack_deg[i] <= a.attack_deg[i - 1] {
                        return Err(inv(
                            &f(&format!("aero.attack_deg[{i}]")),
                            a.attack_deg[i],
                            "angles must increase",
                        ));
                    }
                }
                if a.attack_deg[0] > 0.0 || a.attack_deg[n - 1] < 0.0 {
                    return Err(inv(
                        &f("aero.attack_deg"),
                        format!("{:?}", a.attack_deg),
                        "the table must include 0° (the mean wind is horizontal)",
                    ));
                }
                for (k, v) in [("drag", &a.drag), ("lift", &a.lift), ("moment", &a.moment)] {
                    if v.len() != n {
                        return Err(inv(
                            &f(&format!("aero.{k}")),
                            format!("{} values", v.len()),
                            &format!("need one value per angle ({n})"),
                        ));
                    }
                    for (i, x) in v.iter().enumerate() {
                        check_bound(w, &f(&format!("aero.{k}[{i}]")), *x, &bounds::COEFF)?;
                    }
                }
                if a.at(0.0).0 <= 0.0 {
                    return Err(inv(
                        &f("aero.drag"),
                        a.at(0.0).0,
                        "the drag coefficient at 0° must be positive",
                    ));
                }
            }
            None if case.wind.is_some() => {
                return Err(inv(
                    &f("aero"),
                    "missing",
                    "wind needs the wire's aerodynamic coefficients",
                ))
            }
            None => {}
        }
    }
    Ok(())
}

/// Stagger, registrations and the lateral geometry.
pub(super) fn lateral_geometry(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let lateral = case.run.dofs.contains(&Dof::Lateral);
    let c = &case.catenary;
    match &c.lateral {
        Some(l) => {
            if !lateral {
                w.push(Warning(
                    "catenary.lateral is given but run.dofs has no \"lateral\": stagger and lateral registration are ignored".into(),
                ));
            }
            match (&l.stagger_m, &l.stagger_list_m) {
                (Some(s), None) => check_bound(w, "catenary.lateral.stagger_m", *s, &bounds::STAGGER)?,
                (None, Some(list)) => {
                    if list.is_empty() {
                        return Err(inv(
                            "catenary.lateral.stagger_list_m",
                            "[]",
                            "give at least one stagger",
                        ));
                    }
                    for (i, s) in list.iter().enumerate() {
                        check_bound(
                            w,
                            &format!("catenary.lateral.stagger_list_m[{i}]"),
                            *s,
                            &bounds::STAGGER,
                        )?;
                    }
                }
                (None, None) => {}
                (Some(_), Some(_)) => {
                    return Err(inv(
                        "catenary.lateral.stagger_m",
                        "both stagger_m and stagger_list_m",
                        "give only one of them",
                    ))
                }
            }
            let f = |k: &str| format!("catenary.lateral.{k}");
            check_bound(
                w,
                &f("steady_arm_stiffness_n_per_m"),
                l.steady_arm_stiffness_n_per_m,
                &bounds::LAT_STIFF,
            )?;
            check_bound(w, &f("steady_arm_mass_kg"), l.steady_arm_mass_kg, &bounds::ARM_MASS)?;
            check_bound(
                w,
                &f("messenger_support_stiffness_n_per_m"),
                l.messenger_support_stiffness_n_per_m,
                &bounds::LAT_STIFF,
            )?;
            for (k, v) in [
                ("dropper_clamp_eccentricity_m", l.dropper_clamp_eccentricity_m),
                (
                    "steady_arm_clamp_eccentricity_m",
                    l.steady_arm_clamp_eccentricity_m,
                ),
                (
                    "contact_point_eccentricity_m",
                    l.contact_point_eccentricity_m,
                ),
            ] {
                check_bound(w, &f(k), v, &bounds::ECC)?;
            }
            check_bound(
                w,
                &f("steady_arm_torsional_stiffness_nm_per_rad"),
                l.steady_arm_torsional_stiffness_nm_per_rad,
                &bounds::TORS_STIFF,
            )?;
            check_bound(
                w,
                &f("contact_wire_height_m"),
                l.contact_wire_height_m,
                &bounds::WIRE_HEIGHT,
            )?;
        }
        None if lateral => {
            return Err(inv(
                "catenary.lateral",
                "missing",
                "lateral motion needs the lateral registration (steady-arm and messenger-support stiffness, contact-wire height, stagger)",
            ))
        }
        None => {}
    }
    Ok(())
}

/// Ice on the wires.
pub(super) fn ice(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let c = &case.catenary;
    if let Some(ice) = &c.ice {
        check_bound(
            w,
            "catenary.ice.density_kg_m3",
            ice.density_kg_m3,
            &bounds::ICE_DENSITY,
        )?;
        check_bound(
            w,
            "catenary.ice.contact_wire_m",
            ice.contact_wire_m,
            &bounds::ICE,
        )?;
        check_bound(w, "catenary.ice.messenger_m", ice.messenger_m, &bounds::ICE)?;
    }
    Ok(())
}

/// The crosswind.
pub(super) fn wind(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let lateral = case.run.dofs.contains(&Dof::Lateral);
    let c = &case.catenary;
    if let Some(wd) = &case.wind {
        if !lateral {
            return Err(inv(
                "wind",
                "given",
                "wind acts laterally: add \"lateral\" to run.dofs",
            ));
        }
        let f = |k: &str| format!("wind.{k}");
        check_bound(w, &f("mean_speed_m_s"), wd.mean_speed_m_s, &bounds::WIND)?;
        check_bound(
            w,
            &f("reference_height_m"),
            wd.reference_height_m,
            &bounds::REF_HEIGHT,
        )?;
        match &wd.profile {
            WindProfile::Log { roughness_m } => {
                check_bound(w, &f("profile.roughness_m"), *roughness_m, &bounds::ROUGH)?;
                if *roughness_m <= 0.0 {
                    return Err(inv(&f("profile.roughness_m"), roughness_m, "must be > 0"));
                }
                let lh = c.lateral.as_ref().map_or(5.0, |l| l.contact_wire_height_m);
                if lh <= *roughness_m || wd.reference_height_m <= *roughness_m {
                    return Err(inv(
                        &f("profile.roughness_m"),
                        roughness_m,
                        "the log law needs heights above the roughness length",
                    ));
                }
            }
            WindProfile::Power { exponent } => {
                check_bound(w, &f("profile.exponent"), *exponent, &bounds::EXPONENT)?
            }
        }
        check_bound(w, &f("yaw_deg"), wd.yaw_deg, &bounds::YAW)?;
        check_bound(
            w,
            &f("turbulence_intensity"),
            wd.turbulence_intensity,
            &bounds::TI,
        )?;
        if let Spectrum::Kaimal { integral_length_m } = wd.spectrum {
            check_bound(
                w,
                &f("spectrum.integral_length_m"),
                integral_length_m,
                &bounds::LENGTH_SCALE,
            )?;
            if integral_length_m <= 0.0 {
                return Err(inv(
                    &f("spectrum.integral_length_m"),
                    integral_length_m,
                    "must be > 0",
                ));
            }
        }
        check_bound(w, &f("coherence_decay"), wd.coherence_decay, &bounds::DECAY)?;
        check_bound(
            w,
            &f("air_density_kg_m3"),
            wd.air_density_kg_m3,
            &bounds::AIR,
        )?;
        check_bound(w, &f("grid_m"), wd.grid_m, &bounds::GRID)?;
        if wd.grid_m <= 0.0 {
            return Err(inv(&f("grid_m"), wd.grid_m, "must be > 0"));
        }
        check_bound(w, &f("dt_s"), wd.dt_s, &bounds::WIND_DT)?;
        if wd.dt_s <= 0.0 {
            return Err(inv(&f("dt_s"), wd.dt_s, "must be > 0"));
        }
        if wd.dt_s < case.run.dt_s {
            return Err(inv(
                &f("dt_s"),
                wd.dt_s,
                "must not be shorter than run.dt_s (the wind is interpolated between its samples)",
            ));
        }
        if wd.turbulence_intensity > 0.0 && matches!(wd.spectrum, Spectrum::None) {
            return Err(inv(
                &f("spectrum"),
                "none",
                "a turbulence intensity above 0 needs a spectrum (kaimal or davenport)",
            ));
        }
    }
    Ok(())
}

/// The pantograph heads' widths.
pub(super) fn pantograph_heads(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    for (i, p) in case.pantographs.iter().enumerate() {
        if let PantographCase::Lumped {
            head_half_width_m,
            working_half_width_m,
            ..
        } = p
        {
            if let Some(h) = head_half_width_m {
                check_bound(
                    w,
                    &format!("pantographs[{i}].head_half_width_m"),
                    *h,
                    &bounds::HALF_WIDTH,
                )?;
                if *h <= 0.0 {
                    return Err(inv(
                        &format!("pantographs[{i}].head_half_width_m"),
                        h,
                        "must be > 0",
                    ));
                }
            }
            if let Some(wr) = working_half_width_m {
                check_bound(
                    w,
                    &format!("pantographs[{i}].working_half_width_m"),
                    *wr,
                    &bounds::HALF_WIDTH,
                )?;
                if let Some(h) = head_half_width_m {
                    if wr > h {
                        return Err(inv(
                            &format!("pantographs[{i}].working_half_width_m"),
                            wr,
                            &format!("must not exceed the head's half-width ({h} m)"),
                        ));
                    }
                }
            }
        }
    }
    Ok(())
}

/// Check the irregularity sources of `case`.
pub(super) fn irregularity(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    for (i, ir) in case.irregularity.iter().enumerate() {
        let f = |k: &str| format!("irregularity[{i}].{k}");
        match ir {
            IrregularityCase::Table {
                position_m,
                deviation_m,
                ..
            } => irregularity_table(w, &f, position_m, deviation_m)?,
            IrregularityCase::Psd { .. } => irregularity_psd(case, w, &f, ir)?,
            IrregularityCase::Droppers { rms_m, .. } => {
                check_bound(w, &f("rms_m"), *rms_m, &bounds::IRREGULARITY_RMS)?;
            }
        }
    }
    Ok(())
}

/// A measured profile: at least two points, increasing positions, one deviation each.
fn irregularity_table(
    w: &mut Vec<Warning>,
    f: &dyn Fn(&str) -> String,
    position_m: &[f64],
    deviation_m: &[f64],
) -> Result<(), CaseError> {
    if position_m.len() < 2 {
        return Err(inv(
            &f("position_m"),
            format!("{} points", position_m.len()),
            "a profile needs at least two points",
        ));
    }
    if deviation_m.len() != position_m.len() {
        return Err(inv(
            &f("deviation_m"),
            format!("{} values", deviation_m.len()),
            &format!("need one deviation per position ({})", position_m.len()),
        ));
    }
    for k in 1..position_m.len() {
        if position_m[k] <= position_m[k - 1] {
            return Err(inv(
                &f(&format!("position_m[{k}]")),
                position_m[k],
                "positions must increase",
            ));
        }
    }
    for (k, d) in deviation_m.iter().enumerate() {
        check_bound(
            w,
            &f(&format!("deviation_m[{k}]")),
            *d,
            &bounds::IRREGULARITY_DEVIATION,
        )?;
    }
    Ok(())
}

/// A profile drawn from a PSD: the rms, the wavelength band, the exponent or the table.
fn irregularity_psd(
    case: &Case,
    w: &mut Vec<Warning>,
    f: &dyn Fn(&str) -> String,
    ir: &IrregularityCase,
) -> Result<(), CaseError> {
    let IrregularityCase::Psd {
        rms_m,
        min_wavelength_m,
        max_wavelength_m,
        exponent,
        table,
        ..
    } = ir
    else {
        return Ok(());
    };
    check_bound(w, &f("rms_m"), *rms_m, &bounds::IRREGULARITY_RMS)?;
    check_bound(
        w,
        &f("min_wavelength_m"),
        *min_wavelength_m,
        &bounds::IRREGULARITY_WAVELENGTH,
    )?;
    check_bound(
        w,
        &f("max_wavelength_m"),
        *max_wavelength_m,
        &bounds::IRREGULARITY_WAVELENGTH,
    )?;
    if !(*min_wavelength_m > 0.0 && max_wavelength_m > min_wavelength_m) {
        return Err(inv(
            &f("max_wavelength_m"),
            max_wavelength_m,
            &format!("the band needs 0 < min_wavelength_m ({min_wavelength_m}) < max_wavelength_m"),
        ));
    }
    if !(exponent.is_finite() && exponent.abs() <= 10.0) {
        return Err(inv(&f("exponent"), exponent, "must lie within ±10"));
    }
    if *max_wavelength_m > case.length_m() {
        w.push(Warning(format!(
            "{} = {max_wavelength_m} m is longer than the model ({} m): those wavelengths are cut",
            f("max_wavelength_m"),
            case.length_m()
        )));
    }
    if let Some(t) = table {
        if t.wavelength_m.len() < 2 || t.psd.len() != t.wavelength_m.len() {
            return Err(inv(
                &f("table"),
                format!(
                    "{} wavelengths, {} values",
                    t.wavelength_m.len(),
                    t.psd.len()
                ),
                "need at least two wavelengths and one PSD value per wavelength",
            ));
        }
        for k in 0..t.wavelength_m.len() {
            if t.wavelength_m[k] <= 0.0 || (k > 0 && t.wavelength_m[k] <= t.wavelength_m[k - 1]) {
                return Err(inv(
                    &f(&format!("table.wavelength_m[{k}]")),
                    t.wavelength_m[k],
                    "wavelengths must be positive and increase",
                ));
            }
            if !(t.psd[k] > 0.0 && t.psd[k].is_finite()) {
                return Err(inv(
                    &f(&format!("table.psd[{k}]")),
                    t.psd[k],
                    "PSD values must be finite and > 0",
                ));
            }
        }
    }
    Ok(())
}
