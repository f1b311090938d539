//! The contact wire's irregularity sources.

use super::*;

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
pub(super) fn irregularity_table(
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
pub(super) fn irregularity_psd(
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
