//! Lateral and torsional motion: the directions, the sections, stagger and registration, ice
//! and the crosswind.

use super::*;

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
            Some(a) => aero(a, &f, w)?,
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

/// A wire's aerodynamic table (`section.aero`): increasing angles through 0°, one coefficient
/// per angle of each kind, a positive drag at 0°. `f` names a field of the section.
fn aero(
    a: &crate::input::lateral::AeroCase,
    f: &dyn Fn(&str) -> String,
    w: &mut Vec<Warning>,
) -> Result<(), CaseError> {
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
            curve(case, l, w)?;
            // The stagger's usual range is about the pantograph's centre line: on a canted
            // curve that is the track's, moved toward the curve's centre.
            let off = l.head_offset_m();
            // The value as given against the hard bound; on a canted curve the usual range
            // (a warning only) from the head's centre.
            let stagger = |w: &mut Vec<Warning>, field: &str, s: f64| {
                if off == 0.0 {
                    return check_bound(w, field, s, &bounds::STAGGER);
                }
                check_bound(&mut Vec::new(), field, s, &bounds::STAGGER)?;
                let usual = bounds::Bound {
                    hard: (f64::NEG_INFINITY, f64::INFINITY),
                    ..bounds::STAGGER
                };
                check_bound(
                    w,
                    &format!("{field} (from the head's centre, {off:.3} m off the track's on the canted curve)"),
                    s - off,
                    &usual,
                )
            };
            match (&l.stagger_m, &l.stagger_list_m) {
                (Some(s), None) => {
                    // Alternating: on a canted curve +s and −s lie at different distances from
                    // the head's centre.
                    stagger(w, "catenary.lateral.stagger_m", *s)?;
                    if off != 0.0 {
                        stagger(w, "catenary.lateral.stagger_m", -*s)?;
                    }
                }
                (None, Some(list)) => {
                    if list.is_empty() {
                        return Err(inv(
                            "catenary.lateral.stagger_list_m",
                            "[]",
                            "give at least one stagger",
                        ));
                    }
                    for (i, s) in list.iter().enumerate() {
                        stagger(w, &format!("catenary.lateral.stagger_list_m[{i}]"), *s)?;
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
            registration(l, w)?;
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

/// The lateral registration's stiffnesses, masses, eccentricities and contact-wire height, each
/// within its bounds.
fn registration(l: &LateralCase, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let f = |k: &str| format!("catenary.lateral.{k}");
    check_bound(
        w,
        &f("steady_arm_stiffness_n_per_m"),
        l.steady_arm_stiffness_n_per_m,
        &bounds::LAT_STIFF,
    )?;
    check_bound(
        w,
        &f("steady_arm_mass_kg"),
        l.steady_arm_mass_kg,
        &bounds::ARM_MASS,
    )?;
    check_bound(
        w,
        &f("messenger_support_stiffness_n_per_m"),
        l.messenger_support_stiffness_n_per_m,
        &bounds::LAT_STIFF,
    )?;
    for (k, v) in [
        (
            "dropper_clamp_eccentricity_m",
            l.dropper_clamp_eccentricity_m,
        ),
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
    Ok(())
}

/// A curved track: its radius against the span (the chord's bow is second order in `s/R`), its
/// cant only with a radius.
fn curve(case: &Case, l: &LateralCase, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let (c, f) = (&case.catenary, |k: &str| format!("catenary.lateral.{k}"));
    if let Some(r) = l.track_radius_m {
        if !r.is_finite() {
            return Err(inv(&f("track_radius_m"), num(r), "must be a finite number"));
        }
        check_bound(w, &f("track_radius_m"), r.abs(), &bounds::TRACK_RADIUS)?;
        if c.span_m > 0.2 * r.abs() {
            return Err(inv(
                &f("track_radius_m"),
                num(r),
                &format!(
                    "a span of {} m on a radius of {} m: the chord's bow is taken to second order in span/radius, valid up to a span of a fifth of the radius",
                    c.span_m,
                    r.abs()
                ),
            ));
        }
    }
    check_bound(w, &f("cant_m"), l.cant_m, &bounds::CANT)?;
    if l.cant_m != 0.0 && l.track_radius_m.is_none() {
        return Err(inv(
            &f("cant_m"),
            num(l.cant_m),
            "a cant needs a curve: give catenary.lateral.track_radius_m (a straight track has no cant)",
        ));
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
