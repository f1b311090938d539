//! The catenary's own sections: its geometry and wires, droppers, pre-sag, damping, supports and
//! arms, stitch wires, and the droppers' S–N curve.

use super::*;

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
pub(super) fn dropper_fatigue(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
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
