//! Contact-wire irregularity (issue 13): a vertical deviation of the contact wire from its design
//! height, added to the height the pantograph sees. Three sources, which add up:
//! a profile given point by point (a measurement or a design, `pcsim run --irregularity FILE.csv`
//! fills it from a CSV file), a random profile from a one-sided PSD over wavelength, and
//! periodic dropper errors.

use serde::{Deserialize, Serialize};

use super::case::{check_bound, inv, Bound, Case, Warning};
use crate::error::CaseError;
pub use crate::model::irregularity::PsdTable;

/// One source of irregularity (`[[irregularity]]`).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum IrregularityCase {
    /// A profile: deviation (m, upward positive) at positions (m, model coordinates, increasing),
    /// linear in between and zero outside.
    Table {
        position_m: Vec<f64>,
        deviation_m: Vec<f64>,
        /// Where the table came from (a file name), for the outputs.
        #[serde(default, skip_serializing_if = "String::is_empty")]
        source_file: String,
    },
    /// A random profile with the one-sided PSD `S(λ) ∝ λ^exponent` over wavelength (or a table),
    /// limited to `[min_wavelength_m, max_wavelength_m]`, scaled to `rms_m`, seeded.
    Psd {
        rms_m: f64,
        min_wavelength_m: f64,
        max_wavelength_m: f64,
        /// `S ∝ λ^exponent` in the band (per unit spatial frequency); ignored with `table`.
        #[serde(default)]
        exponent: f64,
        /// The PSD's shape as a table: wavelengths (m, increasing) and relative values (log-log
        /// interpolation), instead of the power law.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        table: Option<PsdTable>,
        seed: u64,
    },
    /// Height errors at the droppers, the same pattern in every span (a dropper-length error
    /// repeated at each span), random with `rms_m`, seeded, linear between droppers and zero at
    /// the supports.
    Droppers { rms_m: f64, seed: u64 },
}

impl IrregularityCase {
    /// A profile from CSV text: a header line, then `position_m,deviation_m` rows (m). The
    /// caller reads the file (the core does no I/O); `source` names it in errors and outputs.
    pub fn from_csv(text: &str, source: &str) -> Result<Self, CaseError> {
        let mut xs = Vec::new();
        let mut ys = Vec::new();
        for (i, line) in text.lines().enumerate().skip(1) {
            if line.trim().is_empty() {
                continue;
            }
            let f: Vec<&str> = line.split(',').map(str::trim).collect();
            let num = |k: usize| -> Result<f64, CaseError> {
                f.get(k)
                    .and_then(|s| s.parse::<f64>().ok())
                    .filter(|v| v.is_finite())
                    .ok_or_else(|| {
                        inv(
                            source,
                            format!("line {}: `{line}`", i + 1),
                            "each row must be `position_m,deviation_m` (finite numbers, m)",
                        )
                    })
            };
            xs.push(num(0)?);
            ys.push(num(1)?);
        }
        Ok(IrregularityCase::Table {
            position_m: xs,
            deviation_m: ys,
            source_file: source.to_string(),
        })
    }

    /// The seed of a random source.
    pub fn seed(&self) -> Option<u64> {
        match self {
            IrregularityCase::Psd { seed, .. } | IrregularityCase::Droppers { seed, .. } => {
                Some(*seed)
            }
            IrregularityCase::Table { .. } => None,
        }
    }

    /// The same source with its seed offset by `k` (realisation `k` of a Monte Carlo study).
    pub fn with_seed_offset(&self, k: u64) -> Self {
        let mut c = self.clone();
        match &mut c {
            IrregularityCase::Psd { seed, .. } | IrregularityCase::Droppers { seed, .. } => {
                *seed = seed.wrapping_add(k)
            }
            IrregularityCase::Table { .. } => {}
        }
        c
    }
}

const B_RMS: Bound = Bound {
    hard: (0.0, 0.5),
    soft: (0.0, 0.03),
    unit: "m",
    typical: "0–20 mm",
};
const B_WAVE: Bound = Bound {
    hard: (0.0, 1.0e5),
    soft: (0.1, 1000.0),
    unit: "m",
    typical: "1–200 m",
};
const B_DEV: Bound = Bound {
    hard: (-1.0, 1.0),
    soft: (-0.1, 0.1),
    unit: "m",
    typical: "within ±30 mm",
};

/// Check the irregularity sources of `case`.
pub fn validate(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    for (i, ir) in case.irregularity.iter().enumerate() {
        let f = |k: &str| format!("irregularity[{i}].{k}");
        match ir {
            IrregularityCase::Table {
                position_m,
                deviation_m,
                ..
            } => {
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
                    check_bound(w, &f(&format!("deviation_m[{k}]")), *d, &B_DEV)?;
                }
            }
            IrregularityCase::Psd {
                rms_m,
                min_wavelength_m,
                max_wavelength_m,
                exponent,
                table,
                ..
            } => {
                check_bound(w, &f("rms_m"), *rms_m, &B_RMS)?;
                check_bound(w, &f("min_wavelength_m"), *min_wavelength_m, &B_WAVE)?;
                check_bound(w, &f("max_wavelength_m"), *max_wavelength_m, &B_WAVE)?;
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
                        if t.wavelength_m[k] <= 0.0
                            || (k > 0 && t.wavelength_m[k] <= t.wavelength_m[k - 1])
                        {
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
            }
            IrregularityCase::Droppers { rms_m, .. } => {
                check_bound(w, &f("rms_m"), *rms_m, &B_RMS)?;
            }
        }
    }
    Ok(())
}
