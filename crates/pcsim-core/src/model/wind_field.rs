//! Turbulent wind along the line by spectral representation (weighted amplitude wave
//! superposition, Shinozuka & Deodatis 1991/1996), FFT-accelerated and seeded.
//!
//! The along-wind fluctuation at points `x_j` on the line is
//!
//! ```text
//! u_j(t) = Re Σ_l A_l Z_j(l) e^{2πi f_l t},   A_l = √(2 S(f_l) Δf),
//! Z_0 = e^{iΦ_0l},   Z_j = ρ_j Z_{j−1} + √(1 − ρ_j²) e^{iΦ_jl},   ρ_j = exp(−C f_l |x_j − x_{j−1}| / U)
//! ```
//!
//! with independent uniform phases `Φ`. The recursion is the Cholesky factor of Davenport's
//! coherence matrix `exp(−C f |x_j − x_k| / U)` applied to the random phasors (the factor of an
//! exponential correlation is bidiagonal in this form), so the field has the target spectrum at
//! every point and Davenport's coherence between any two, at `O(points · frequencies)` plus one
//! FFT per point. `S` is one-sided; the frequencies exclude 0 and Nyquist, so the variance
//! achieved is the target's integral over `(Δf, f_Nyquist)`, reported as the turbulence
//! intensity achieved.
//!
//! The random numbers are SplitMix64 (Steele, Lea & Flood 2014), written here (eight lines) so
//! that a seed gives the same field in every build: a generator from a crate may change its
//! stream between versions.

use std::f64::consts::PI;

use rustfft::num_complex::Complex;
use rustfft::FftPlanner;

/// The turbulence spectrum `S(f)` of the along-wind component (one-sided, m²/s² per Hz).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum SpectrumModel {
    /// `f S/σ² = 4 y / (1 + 6 y)^{5/3}`, `y = f L / U` (the IEC 61400-1 form; `L = 8.1 Λ`,
    /// `Λ = 0.7 z` below 60 m: reference README §3.6).
    Kaimal {
        /// Integral length scale Λ, m.
        integral_length_m: f64,
        /// Mean speed, m/s.
        mean_m_s: f64,
    },
    /// `f S/σ² = (2/3) x² / (1 + x²)^{4/3}`, `x = 1200 f / U_ref` (Davenport 1961: the form
    /// `f S/(κ U10²) = 4 x²/(1 + x²)^{4/3}` of the reference README §3.6 normalised by its
    /// variance `σ² = 6 κ U10²`, so that the turbulence intensity is the case's).
    Davenport {
        /// Davenport's reference speed U_ref, m/s.
        reference_m_s: f64,
    },
}

impl SpectrumModel {
    /// `S(f) / σ²`, 1/Hz.
    pub fn normalised(&self, f: f64) -> f64 {
        match *self {
            SpectrumModel::Kaimal {
                integral_length_m,
                mean_m_s,
            } => {
                let a = integral_length_m / mean_m_s;
                4.0 * a / (1.0 + 6.0 * f * a).powf(5.0 / 3.0)
            }
            SpectrumModel::Davenport { reference_m_s } => {
                let x = 1200.0 * f / reference_m_s;
                (2.0 / 3.0) * x * x / (f * (1.0 + x * x).powf(4.0 / 3.0))
            }
        }
    }

    /// A short name for outputs.
    pub fn name(&self) -> &'static str {
        match self {
            SpectrumModel::Kaimal { .. } => "kaimal",
            SpectrumModel::Davenport { .. } => "davenport",
        }
    }
}

/// Davenport's root-coherence between two points `dx` apart at frequency `f`.
pub fn davenport_coherence(decay: f64, f: f64, dx: f64, mean_m_s: f64) -> f64 {
    (-decay * f * dx.abs() / mean_m_s).exp()
}

/// SplitMix64: a seeded stream of 64-bit numbers.
#[derive(Debug, Clone)]
pub struct SplitMix64(u64);

impl SplitMix64 {
    /// A stream starting from `seed`.
    pub fn new(seed: u64) -> Self {
        Self(seed)
    }
    /// The next number of the stream.
    pub fn next_u64(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }
    /// Uniform in `[0, 1)` (53 bits).
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 / (1u64 << 53) as f64
    }
}

/// What to generate: the spectrum, the standard deviation, the mean speed (for the coherence)
/// and Davenport's decay constant.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FieldSpec {
    /// The spectrum.
    pub spectrum: SpectrumModel,
    /// Standard deviation of the fluctuation, m/s.
    pub sigma_m_s: f64,
    /// Mean speed, m/s (for the coherence).
    pub mean_m_s: f64,
    /// Davenport's coherence decay constant C.
    pub coherence_decay: f64,
}

/// A generated field: the along-wind fluctuation at each point, sampled every `dt_s`.
#[derive(Debug, Clone, PartialEq)]
pub struct WindField {
    /// Points along the line (model coordinates, increasing), m.
    pub x_m: Vec<f64>,
    /// Sampling interval, s.
    pub dt_s: f64,
    /// Samples per point (a power of two); the field is periodic with `n_t · dt_s`.
    pub n_t: usize,
    /// `u[j · n_t + n]`: fluctuation at point `j`, time `n · dt`, m/s.
    pub u: Vec<f64>,
}

impl WindField {
    /// Generate the field at `x_m` for a duration of at least `duration_s`.
    pub fn generate(x_m: &[f64], spec: &FieldSpec, dt_s: f64, duration_s: f64, seed: u64) -> Self {
        let FieldSpec {
            spectrum,
            sigma_m_s,
            mean_m_s,
            coherence_decay: decay,
        } = *spec;
        let n_t = ((duration_s / dt_s).ceil() as usize + 2)
            .next_power_of_two()
            .max(16);
        let np = x_m.len();
        let df = 1.0 / (n_t as f64 * dt_s);
        let nf = n_t / 2;
        // Spectra of every point: bins 1 .. nf−1.
        let mut bins = vec![Complex::new(0.0, 0.0); np * n_t];
        let mut rng = SplitMix64::new(seed);
        for l in 1..nf {
            let f = l as f64 * df;
            let a = (2.0 * sigma_m_s * sigma_m_s * spectrum.normalised(f) * df).sqrt();
            let mut z = Complex::new(0.0, 0.0);
            for j in 0..np {
                let ph = Complex::from_polar(1.0, 2.0 * PI * rng.uniform());
                z = if j == 0 {
                    ph
                } else {
                    let rho = davenport_coherence(decay, f, x_m[j] - x_m[j - 1], mean_m_s);
                    z * rho + ph * (1.0 - rho * rho).max(0.0).sqrt()
                };
                bins[j * n_t + l] = z * a;
            }
        }
        let fft = FftPlanner::new().plan_fft_inverse(n_t);
        let mut scratch = vec![Complex::new(0.0, 0.0); fft.get_inplace_scratch_len()];
        let mut u = vec![0.0; np * n_t];
        for j in 0..np {
            let buf = &mut bins[j * n_t..(j + 1) * n_t];
            fft.process_with_scratch(buf, &mut scratch);
            for (o, c) in u[j * n_t..(j + 1) * n_t].iter_mut().zip(buf.iter()) {
                *o = c.re;
            }
        }
        Self {
            x_m: x_m.to_vec(),
            dt_s,
            n_t,
            u,
        }
    }

    /// A field of zeros (mean wind only).
    pub fn calm(x_m: &[f64], dt_s: f64) -> Self {
        Self {
            x_m: x_m.to_vec(),
            dt_s,
            n_t: 16,
            u: vec![0.0; x_m.len() * 16],
        }
    }

    /// The samples of point `j`.
    pub fn series(&self, j: usize) -> &[f64] {
        &self.u[j * self.n_t..(j + 1) * self.n_t]
    }

    /// Fluctuation at point `j` and time `t` (linear between samples, periodic), m/s.
    #[inline]
    pub fn at(&self, j: usize, t: f64) -> f64 {
        let (i, frac) = self.interval(t);
        let (u0, u1) = self.ends(j, i);
        u0 + frac * (u1 - u0)
    }

    /// The interval of samples holding time `t` (its index, counted from `t = 0` without the
    /// period's wrap) and `t`'s fraction of it in `[0, 1)`.
    #[inline]
    pub fn interval(&self, t: f64) -> (usize, f64) {
        let s = (t / self.dt_s).max(0.0);
        let i = s.floor();
        (i as usize, s - i)
    }

    /// The fluctuation at point `j` at the start and the end of interval `i` (periodic), m/s.
    #[inline]
    pub fn ends(&self, j: usize, i: usize) -> (f64, f64) {
        let i = i % self.n_t;
        let row = self.series(j);
        (row[i], row[(i + 1) % self.n_t])
    }

    /// Standard deviation of the fluctuation over the first `duration_s` at every point, m/s.
    pub fn std_over(&self, duration_s: f64) -> f64 {
        let n = ((duration_s / self.dt_s).ceil() as usize).clamp(1, self.n_t);
        let (mut s, mut s2, mut cnt) = (0.0, 0.0, 0.0);
        for j in 0..self.x_m.len() {
            for &v in &self.series(j)[..n] {
                s += v;
                s2 += v * v;
                cnt += 1.0;
            }
        }
        if cnt < 2.0 {
            return 0.0;
        }
        let m = s / cnt;
        ((s2 / cnt - m * m).max(0.0)).sqrt()
    }
}
