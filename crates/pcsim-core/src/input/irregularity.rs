//! Contact-wire irregularity (issue 13): a vertical deviation of the contact wire from its design
//! height, added to the height the pantograph sees. Three sources, which add up:
//! a profile given point by point (a measurement or a design, `pcsim run --irregularity FILE.csv`
//! fills it from a CSV file), a random profile from a one-sided PSD over wavelength, and
//! periodic dropper errors.

use serde::{Deserialize, Serialize};

use super::bounds::inv;
use crate::error::CaseError;
pub use crate::model::irregularity::PsdTable;

/// One source of irregularity (`[[irregularity]]`).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum IrregularityCase {
    /// A profile: deviation (m, upward positive) at positions (m, model coordinates, increasing),
    /// linear in between and zero outside.
    Table {
        /// Positions, m (model coordinates, increasing).
        position_m: Vec<f64>,
        /// Deviations at the positions, m (upward positive).
        deviation_m: Vec<f64>,
        /// Where the table came from (a file name), for the outputs.
        #[serde(default, skip_serializing_if = "String::is_empty")]
        source_file: String,
    },
    /// A random profile with the one-sided PSD `S(λ) ∝ λ^exponent` over wavelength (or a table),
    /// limited to `[min_wavelength_m, max_wavelength_m]`, scaled to `rms_m`, seeded.
    Psd {
        /// RMS of the profile, m.
        rms_m: f64,
        /// Shortest wavelength of the band, m.
        min_wavelength_m: f64,
        /// Longest wavelength of the band, m.
        max_wavelength_m: f64,
        /// `S ∝ λ^exponent` in the band (per unit spatial frequency); ignored with `table`.
        #[serde(default)]
        exponent: f64,
        /// The PSD's shape as a table: wavelengths (m, increasing) and relative values (log-log
        /// interpolation), instead of the power law.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        table: Option<PsdTable>,
        /// Seed of the random phases (written to the outputs).
        seed: u64,
    },
    /// Height errors at the droppers, the same pattern in every span (a dropper-length error
    /// repeated at each span), random with `rms_m`, seeded, linear between droppers and zero at
    /// the supports.
    Droppers {
        /// RMS of the dropper-height errors, m.
        rms_m: f64,
        /// Seed of the random pattern.
        seed: u64,
    },
}

impl IrregularityCase {
    /// A profile from CSV text: a header line, then `position_m,deviation_m` rows (m). The
    /// caller reads the file (the core does no I/O); `source` names it in errors and outputs.
    pub fn from_csv(text: &str, source: &str) -> Result<Self, CaseError> {
        let text = crate::input::without_bom(text);
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
