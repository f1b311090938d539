//! The contact and the pantographs: their names, masses, springs and dampers, uplift and
//! aerodynamic force, and their heads.

use super::*;

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
        // Figures are named by the name's letters, digits, - and _ (others become _), and a
        // file system may fold case: two names alike in that form would write one file.
        if let Some(j) =
            (0..i).find(|&j| file_key(&case.pantographs[j].output_name(j)) == file_key(&name))
        {
            return Err(inv(
                &format!("{base}.name"),
                format!("{name:?}"),
                &format!(
                    "pantographs[{j}] is named {:?}: in a file name (letters, digits, - and _ kept, others as _, case folded) both are {:?}, and their figures would overwrite each other",
                    case.pantographs[j].output_name(j),
                    file_key(&name)
                ),
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
pub(super) fn lumped_pantograph(
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
        uplift_by_height,
        aero_coeffs_kmh,
        strips,
        ..
    } = p
    else {
        return Ok(());
    };
    if let Some(t) = uplift_by_height {
        uplift_table(w, base, t, *uplift_n)?;
    }
    collector_strips(w, base, strips)?;
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

/// A head's collector strips: at most 8, each a mass on a spring of positive stiffness (a
/// strip on no spring has no static position), a damper, its place on the head and its running
/// face's height within their bounds, and its contact's own stiffness if given.
fn collector_strips(
    w: &mut Vec<Warning>,
    base: &str,
    strips: &[crate::input::case::StripCase],
) -> Result<(), CaseError> {
    if strips.len() > 8 {
        return Err(inv(
            &format!("{base}.strips"),
            format!("{} strips", strips.len()),
            "a head carries a few collector strips (at most 8)",
        ));
    }
    for (j, s) in strips.iter().enumerate() {
        let f = |k: &str| format!("{base}.strips[{j}].{k}");
        check_bound(w, &f("mass_kg"), s.mass_kg, &bounds::PANTOGRAPH_MASS)?;
        check_bound(
            w,
            &f("stiffness_n_per_m"),
            s.stiffness_n_per_m,
            &bounds::PANTOGRAPH_STIFFNESS,
        )?;
        if s.stiffness_n_per_m <= 0.0 {
            return Err(inv(
                &f("stiffness_n_per_m"),
                s.stiffness_n_per_m,
                "a strip rests on its spring: give it a positive stiffness",
            ));
        }
        check_bound(
            w,
            &f("damping_ns_per_m"),
            s.damping_ns_per_m,
            &bounds::PANTOGRAPH_DAMPING,
        )?;
        check_bound(w, &f("along_m"), s.along_m, &bounds::STRIP_ALONG)?;
        check_bound(
            w,
            &f("height_offset_m"),
            s.height_offset_m,
            &bounds::STRIP_HEIGHT_OFFSET,
        )?;
        if let Some(k) = s.contact_stiffness_n_per_m {
            check_bound(
                w,
                &f("contact_stiffness_n_per_m"),
                k,
                &bounds::CONTACT_STIFFNESS,
            )?;
        }
    }
    Ok(())
}

/// A static uplift against the head's height: at least two points, heights finite and
/// increasing, each uplift within the uplift's bounds, and the uplift at height 0 the case's
/// `uplift_n` (within 0.01 N: the two say the same thing, and must not disagree).
fn uplift_table(
    w: &mut Vec<Warning>,
    base: &str,
    t: &crate::input::case::UpliftByHeight,
    uplift_n: f64,
) -> Result<(), CaseError> {
    let field = format!("{base}.uplift_by_height");
    if t.height_m.len() < 2 || t.height_m.len() != t.uplift_n.len() {
        return Err(inv(
            &field,
            format!("{} heights, {} forces", t.height_m.len(), t.uplift_n.len()),
            "give at least two points, as many forces (uplift_n) as heights (height_m)",
        ));
    }
    for (j, h) in t.height_m.iter().enumerate() {
        if !(h.is_finite() && h.abs() <= 5.0) {
            return Err(inv(
                &format!("{field}.height_m[{j}]"),
                h,
                "a head height in m, within ±5 m of the contact wire's height at the supports",
            ));
        }
        if j > 0 && *h <= t.height_m[j - 1] {
            return Err(inv(
                &format!("{field}.height_m[{j}]"),
                h,
                "the heights increase from point to point",
            ));
        }
    }
    for (j, f) in t.uplift_n.iter().enumerate() {
        check_bound(w, &format!("{field}.uplift_n[{j}]"), *f, &bounds::UPLIFT)?;
    }
    let table = crate::model::pantograph::UpliftTable {
        height_m: t.height_m.clone(),
        uplift_n: t.uplift_n.clone(),
    };
    let at0 = table.at(0.0);
    if (at0 - uplift_n).abs() > 0.01 {
        return Err(inv(
            &field,
            format!("{at0} N at height 0"),
            &format!(
                "the table's uplift at height 0 is the pantograph's uplift_n ({uplift_n} N): make them agree"
            ),
        ));
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

/// A name as it becomes part of a file's name (the CLI's figures: letters, digits, `-` and `_`
/// kept, every other character `_`), case folded (a file system may not tell `A` from `a`).
fn file_key(name: &str) -> String {
    name.chars()
        .map(|c| {
            if c.is_ascii_alphanumeric() || c == '-' || c == '_' {
                c.to_ascii_lowercase()
            } else {
                '_'
            }
        })
        .collect()
}
