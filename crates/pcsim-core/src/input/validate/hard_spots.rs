//! The line's hard spots: section insulators and neutral sections.

use super::*;
use crate::input::hard_spots::tension_length_under;

/// Check the section insulators and the neutral sections of `case`.
pub(super) fn hard_spots(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    for (i, si) in case.section_insulator.iter().enumerate() {
        let f = |k: &str| format!("section_insulator[{i}].{k}");
        check_bound(w, &f("length_m"), si.length_m, &bounds::INSULATOR_LENGTH)?;
        check_bound(w, &f("mass_kg"), si.mass_kg, &bounds::INSULATOR_MASS)?;
        check_bound(w, &f("ei_nm2"), si.ei_nm2, &bounds::INSULATOR_EI)?;
        check_bound(w, &f("prelift_m"), si.prelift_m, &bounds::INSULATOR_PRELIFT)?;
        if !(0.0..=0.5 * si.length_m).contains(&si.ramp_m) {
            return Err(inv(
                &f("ramp_m"),
                si.ramp_m,
                &format!(
                    "the runners' lead-on lies within the insulator: between 0 and half its length ({} m)",
                    0.5 * si.length_m
                ),
            ));
        }
        let k = tension_length_under(case, si.extent_m())
            .map_err(|reason| inv(&f("position_m"), si.position_m, &reason))?;
        let wire_ei = match &case.line {
            Some(l) => {
                (l.tension_lengths[k].catenary(&case.catenary))
                    .contact_wire
                    .ei_nm2
            }
            None => case.catenary.contact_wire.ei_nm2,
        };
        if si.ei_nm2 < wire_ei {
            return Err(inv(
                &f("ei_nm2"),
                si.ei_nm2,
                &format!(
                    "softer than the contact wire it is inserted in ({wire_ei} N·m²): the model adds the insulator's bending stiffness over the wire's, and a negative difference is a negative stiffness"
                ),
            ));
        }
        if let Some(j) = (case.section_insulator[..i].iter())
            .position(|o| si.extent_m()[0] < o.extent_m()[1] && o.extent_m()[0] < si.extent_m()[1])
        {
            return Err(inv(
                &f("position_m"),
                si.position_m,
                &format!("it overlaps section_insulator[{j}]"),
            ));
        }
    }
    for (i, ns) in case.neutral_section.iter().enumerate() {
        let f = |k: &str| format!("neutral_section[{i}].{k}");
        let (lo, hi) = bounds::NEUTRAL_SECTION_LENGTH.hard;
        if !(lo..=hi).contains(&(ns.end_m - ns.start_m)) {
            return Err(inv(
                &f("end_m"),
                ns.end_m,
                &format!(
                    "the dead length end_m − start_m ({} m) must lie between {lo} and {hi} m",
                    ns.end_m - ns.start_m
                ),
            ));
        }
        let on = |x: f64| {
            (case.section_insulator.iter())
                .position(|s| x >= s.extent_m()[0] && x <= s.extent_m()[1])
        };
        let (a, b) = (on(ns.start_m), on(ns.end_m));
        for (k, x, at) in [("start_m", ns.start_m, a), ("end_m", ns.end_m, b)] {
            if at.is_none() {
                return Err(inv(
                    &f(k),
                    x,
                    "a neutral section's dead length ends on a section insulator: no [[section_insulator]] covers this position",
                ));
            }
        }
        if a == b {
            return Err(inv(
                &f("end_m"),
                ns.end_m,
                "the dead length starts and ends on the same insulator: a neutral section lies between two",
            ));
        }
    }
    Ok(())
}
