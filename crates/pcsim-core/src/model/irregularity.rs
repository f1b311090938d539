//! Contact-wire irregularity (issue 13): the vertical deviation `r(x)` of the contact wire from
//! its design height, sampled once on a fine grid. The pantograph sees the wire at
//! `y_static(x) + r(x) + w(x)` (`Model::static_height`); the droppers keep their lengths and
//! the static forces are those of the design (the irregularity is a given geometric deviation,
//! not a load case: it does not enter the dropper lengths).
//!
//! Random profiles use spectral representation along the line: `r(x) = Σ A_k cos(2π Ω_k x + φ_k)`
//! over the spatial frequencies `Ω_k = k / (N dx)` whose wavelength lies in the band, with
//! `A_k = √(2 c S(Ω_k) ΔΩ)`, `c` chosen so that `Σ A_k²/2` is the target RMS², and uniform
//! random phases from SplitMix64 (one FFT).

use rustfft::num_complex::Complex;
use rustfft::FftPlanner;

use crate::model::wind_field::SplitMix64;
use serde::{Deserialize, Serialize};

/// One source of irregularity, as the model takes it (the compile step fills it from the case's
/// `[[irregularity]]`).
#[derive(Debug, Clone, PartialEq)]
pub enum IrregularitySource {
    /// Deviation (m, upward positive) at positions (m, increasing), linear in between.
    Table {
        /// Positions, m (model coordinates, increasing).
        position_m: Vec<f64>,
        /// Deviations at the positions, m (upward positive).
        deviation_m: Vec<f64>,
        /// Where the table came from (a file name), for the outputs.
        source_file: String,
    },
    /// A random profile with the one-sided PSD `S(λ) ∝ λ^exponent` (or a table) in a band,
    /// scaled to `rms_m`, seeded.
    Psd {
        /// RMS of the profile, m.
        rms_m: f64,
        /// Shortest wavelength of the band, m.
        min_wavelength_m: f64,
        /// Longest wavelength of the band, m.
        max_wavelength_m: f64,
        /// `S ∝ λ^exponent` in the band (ignored with `table`).
        exponent: f64,
        /// The PSD's shape as a table, instead of the power law.
        table: Option<PsdTable>,
        /// Seed of the random phases.
        seed: u64,
    },
    /// Random height errors at the droppers, the same in every span, seeded.
    Droppers {
        /// RMS of the dropper-height errors, m.
        rms_m: f64,
        /// Seed of the random pattern.
        seed: u64,
    },
}

impl IrregularitySource {
    /// The seed of a random source.
    pub fn seed(&self) -> Option<u64> {
        match self {
            IrregularitySource::Psd { seed, .. } | IrregularitySource::Droppers { seed, .. } => {
                Some(*seed)
            }
            IrregularitySource::Table { .. } => None,
        }
    }
}

/// A PSD shape over wavelength.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PsdTable {
    /// Wavelengths, m (increasing).
    pub wavelength_m: Vec<f64>,
    /// Relative PSD values at the wavelengths (log-log interpolation).
    pub psd: Vec<f64>,
}

/// What the outputs say about one source.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct IrregularityReport {
    /// The source's kind (`table`, `psd`, `droppers`).
    pub kind: String,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    /// Seed of a random source.
    pub seed: Option<u64>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    /// RMS asked for, m.
    pub rms_target_m: Option<f64>,
    /// RMS of this source over the model, m.
    pub rms_achieved_m: f64,
    #[serde(default, skip_serializing_if = "String::is_empty")]
    /// The file a table came from.
    pub source_file: String,
}

/// The summed profile on a uniform grid.
#[derive(Debug, Clone, PartialEq)]
pub struct IrregularityProfile {
    /// Position of sample 0 (model coordinates), m.
    pub x0_m: f64,
    /// Grid spacing, m.
    pub dx_m: f64,
    /// The summed deviation at each grid point, m.
    pub r_m: Vec<f64>,
    /// What each source contributed.
    pub reports: Vec<IrregularityReport>,
}

impl IrregularityProfile {
    /// Deviation at `x` (model coordinates), m: linear between samples, zero outside.
    #[inline]
    pub fn at(&self, x: f64) -> f64 {
        let s = (x - self.x0_m) / self.dx_m;
        if s.is_nan() || s < 0.0 {
            return 0.0;
        }
        let i = s.floor() as usize;
        if i + 1 >= self.r_m.len() {
            return 0.0;
        }
        let t = s - i as f64;
        self.r_m[i] + t * (self.r_m[i + 1] - self.r_m[i])
    }

    /// Add `f(x)` (m, upward positive; track coordinates) at every grid point: a given
    /// deviation that is not a source of its own (a section insulator's runners).
    pub fn add(&mut self, f: impl Fn(f64) -> f64) {
        for (k, r) in self.r_m.iter_mut().enumerate() {
            *r += f(self.x0_m + k as f64 * self.dx_m);
        }
    }

    /// RMS of the profile over `[0, length_m]`, m.
    pub fn rms_over(&self, length_m: f64) -> f64 {
        rms_of(|x| self.at(x), length_m, self.dx_m)
    }

    /// Build the sum of `sources` over a model of `length_m` with spans of `span_m` and droppers
    /// at `dropper_positions_m` within each span.
    pub fn build(
        sources: &[IrregularitySource],
        length_m: f64,
        span_m: f64,
        dropper_positions_m: &[f64],
    ) -> Self {
        let mut dx: f64 = 0.1;
        for s in sources {
            if let IrregularitySource::Psd {
                min_wavelength_m, ..
            } = s
            {
                dx = dx.min(min_wavelength_m / 16.0);
            }
        }
        let n = (length_m / dx).ceil() as usize + 2;
        let mut r = vec![0.0; n];
        let mut reports = Vec::new();
        for s in sources {
            let part: Vec<f64> = match s {
                IrregularitySource::Table {
                    position_m,
                    deviation_m,
                    ..
                } => (0..n)
                    .map(|k| table_at(position_m, deviation_m, k as f64 * dx))
                    .collect(),
                IrregularitySource::Psd {
                    rms_m,
                    min_wavelength_m,
                    max_wavelength_m,
                    exponent,
                    table,
                    seed,
                } => psd_profile(
                    n,
                    dx,
                    *rms_m,
                    (*min_wavelength_m, *max_wavelength_m),
                    *exponent,
                    table.as_ref(),
                    *seed,
                ),
                IrregularitySource::Droppers { rms_m, seed } => {
                    dropper_profile(n, dx, span_m, dropper_positions_m, *rms_m, *seed)
                }
            };
            let single = IrregularityProfile {
                x0_m: 0.0,
                dx_m: dx,
                r_m: part.clone(),
                reports: Vec::new(),
            };
            reports.push(IrregularityReport {
                kind: match s {
                    IrregularitySource::Table { .. } => "table",
                    IrregularitySource::Psd { .. } => "psd",
                    IrregularitySource::Droppers { .. } => "droppers",
                }
                .into(),
                seed: s.seed(),
                rms_target_m: match s {
                    IrregularitySource::Psd { rms_m, .. }
                    | IrregularitySource::Droppers { rms_m, .. } => Some(*rms_m),
                    IrregularitySource::Table { .. } => None,
                },
                rms_achieved_m: single.rms_over(length_m),
                source_file: match s {
                    IrregularitySource::Table { source_file, .. } => source_file.clone(),
                    _ => String::new(),
                },
            });
            for (a, b) in r.iter_mut().zip(part) {
                *a += b;
            }
        }
        IrregularityProfile {
            x0_m: 0.0,
            dx_m: dx,
            r_m: r,
            reports,
        }
    }
}

fn rms_of(f: impl Fn(f64) -> f64, length_m: f64, dx: f64) -> f64 {
    let n = (length_m / dx).floor() as usize;
    if n == 0 {
        return 0.0;
    }
    let s: f64 = (0..n).map(|k| f((k as f64 + 0.5) * dx).powi(2)).sum();
    (s / n as f64).sqrt()
}

/// Linear in a table, zero outside.
fn table_at(x: &[f64], y: &[f64], at: f64) -> f64 {
    let n = x.len();
    if n < 2 || at < x[0] || at > x[n - 1] {
        return 0.0;
    }
    let i = x.partition_point(|&v| v <= at).clamp(1, n - 1);
    let t = (at - x[i - 1]) / (x[i] - x[i - 1]);
    y[i - 1] + t * (y[i] - y[i - 1])
}

/// The PSD's shape at wavelength `lam`: `λ^exponent`, or the table (log-log).
pub fn psd_shape(lam: f64, exponent: f64, table: Option<&PsdTable>) -> f64 {
    match table {
        None => lam.powf(exponent),
        Some(t) => {
            let (w, p) = (&t.wavelength_m, &t.psd);
            let n = w.len();
            if lam <= w[0] {
                return p[0];
            }
            if lam >= w[n - 1] {
                return p[n - 1];
            }
            let i = w.partition_point(|&v| v <= lam).clamp(1, n - 1);
            let t = (lam.ln() - w[i - 1].ln()) / (w[i].ln() - w[i - 1].ln());
            (p[i - 1].ln() + t * (p[i].ln() - p[i - 1].ln())).exp()
        }
    }
}

/// The spatial-frequency bins of a random profile on `n` samples of `dx` (FFT period `N dx`,
/// `N` the next power of two) whose wavelengths lie in `band`, with their amplitudes scaled to
/// `rms`: `(bin, amplitude)`.
pub fn psd_amplitudes(
    n: usize,
    dx: f64,
    rms: f64,
    band: (f64, f64),
    exponent: f64,
    table: Option<&PsdTable>,
) -> (usize, Vec<(usize, f64)>) {
    let nn = n.next_power_of_two();
    let d_omega = 1.0 / (nn as f64 * dx);
    let mut bins = Vec::new();
    for k in 1..nn / 2 {
        let lam = 1.0 / (k as f64 * d_omega);
        if lam >= band.0 && lam <= band.1 {
            bins.push((k, psd_shape(lam, exponent, table) * d_omega));
        }
    }
    let var: f64 = bins.iter().map(|b| b.1).sum();
    let c = if var > 0.0 { rms * rms / var } else { 0.0 };
    (
        nn,
        bins.into_iter()
            .map(|(k, sd)| (k, (2.0 * c * sd).sqrt()))
            .collect(),
    )
}

fn psd_profile(
    n: usize,
    dx: f64,
    rms: f64,
    band: (f64, f64),
    exponent: f64,
    table: Option<&PsdTable>,
    seed: u64,
) -> Vec<f64> {
    let (nn, amps) = psd_amplitudes(n, dx, rms, band, exponent, table);
    let mut rng = SplitMix64::new(seed);
    let mut buf = vec![Complex::new(0.0, 0.0); nn];
    for (k, a) in amps {
        buf[k] = Complex::from_polar(a, 2.0 * std::f64::consts::PI * rng.uniform());
    }
    FftPlanner::new().plan_fft_inverse(nn).process(&mut buf);
    buf.iter().take(n).map(|c| c.re).collect()
}

fn dropper_profile(
    n: usize,
    dx: f64,
    span_m: f64,
    droppers: &[f64],
    rms: f64,
    seed: u64,
) -> Vec<f64> {
    let mut rng = SplitMix64::new(seed);
    // Standard normal values (Box–Muller), scaled so that their RMS is exactly `rms`.
    let mut e: Vec<f64> = (0..droppers.len())
        .map(|_| {
            let (u1, u2) = (rng.uniform().max(1e-300), rng.uniform());
            (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
        })
        .collect();
    let q = (e.iter().map(|v| v * v).sum::<f64>() / e.len().max(1) as f64).sqrt();
    if q > 0.0 {
        for v in &mut e {
            *v *= rms / q;
        }
    }
    let mut xs = vec![0.0];
    xs.extend_from_slice(droppers);
    xs.push(span_m);
    let mut ys = vec![0.0];
    ys.extend_from_slice(&e);
    ys.push(0.0);
    (0..n)
        .map(|k| {
            let x = k as f64 * dx;
            let d = x - span_m * (x / span_m).floor();
            table_at(&xs, &ys, d)
        })
        .collect()
}
