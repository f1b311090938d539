//! A run beside a measurement (issue 22, item 4): the measured contact force against position
//! (`input::measured`), filtered as the run's (0–20 Hz, zero phase, EN 50318), aligned to it by
//! cross-correlation over a stated search range, with the statistics side by side, the spectra
//! and the force averaged over the span's length.
//!
//! Both records are filtered whole, then cut to the analysis section (as the run's statistics).
//! A record sampled every `Δx` at speed `v` is sampled at `v/Δx` in time, so the time filters
//! apply to position records unchanged. The shift `d` is the one that maximises the correlation
//! coefficient of the filtered records over the section: measured position `x` is simulated
//! position `x + d`.

use crate::analysis::filter::{bandpass_zero_phase, lowpass_zero_phase};
use crate::analysis::stats::{BAND_SPLIT_HZ, CUTOFF_HZ};
use crate::error::CaseError;
use crate::input::bounds::inv;
use crate::input::measured::MeasuredForce;

/// The statistics of one record over the section (0–20 Hz force unless named otherwise), N.
#[derive(
    Debug, Clone, Copy, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema,
)]
pub struct ForceStats {
    /// Mean.
    pub mean_n: f64,
    /// Standard deviation.
    pub std_n: f64,
    /// Standard deviation of the 0–5 Hz force.
    pub std_0_5hz_n: f64,
    /// Standard deviation of the 5–20 Hz force.
    pub std_5_20hz_n: f64,
    /// Largest value.
    pub max_n: f64,
    /// Smallest value.
    pub min_n: f64,
    /// Mean + 3σ.
    pub stat_max_n: f64,
    /// Mean − 3σ.
    pub stat_min_n: f64,
    /// Samples.
    pub samples: usize,
}

impl ForceStats {
    fn of(f: &[f64], f05: &[f64], f520: &[f64]) -> Self {
        let ms = |x: &[f64]| {
            let n = x.len().max(1) as f64;
            let m = x.iter().sum::<f64>() / n;
            (
                m,
                (x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / n).sqrt(),
            )
        };
        let (mean_n, std_n) = ms(f);
        ForceStats {
            mean_n,
            std_n,
            std_0_5hz_n: ms(f05).1,
            std_5_20hz_n: ms(f520).1,
            max_n: f.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            min_n: f.iter().copied().fold(f64::INFINITY, f64::min),
            stat_max_n: mean_n + 3.0 * std_n,
            stat_min_n: mean_n - 3.0 * std_n,
            samples: f.len(),
        }
    }

    /// The rows of the side-by-side table: name and value.
    pub fn rows(&self) -> [(&'static str, f64); 8] {
        [
            ("mean_n", self.mean_n),
            ("std_n", self.std_n),
            ("std_0_5hz_n", self.std_0_5hz_n),
            ("std_5_20hz_n", self.std_5_20hz_n),
            ("max_n", self.max_n),
            ("min_n", self.min_n),
            ("stat_max_n", self.stat_max_n),
            ("stat_min_n", self.stat_min_n),
        ]
    }
}

/// What `compare` found.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct Comparison {
    /// The shift found: measured position `x` is simulated position `x + shift`, m.
    pub shift_m: f64,
    /// The shift in samples of the measurement.
    pub shift_samples: i64,
    /// The correlation coefficient of the filtered records at that shift.
    pub correlation: f64,
    /// The search range, ± m.
    pub search_m: f64,
    /// The section compared (simulated positions), m.
    pub section_m: [f64; 2],
    /// The run's statistics on the measurement's grid.
    pub simulated: ForceStats,
    /// The measurement's.
    pub measured: ForceStats,
    /// The grid: the measured positions, shifted, inside the section, m.
    pub position_m: Vec<f64>,
    /// The run's 0–20 Hz force on the grid, N.
    pub simulated_n: Vec<f64>,
    /// The measurement's 0–20 Hz force on the grid, N.
    pub measured_n: Vec<f64>,
    /// Spatial frequency (1/m) and the power spectral density of each, N²·m (Welch, Hann,
    /// half-overlapping segments), up to twice the 20 Hz cut-off's wavenumber `20 Hz / v`.
    pub spectrum: Vec<[f64; 3]>,
    /// Fraction of the span (0 at a support) and each record's mean over the spans, N.
    pub profile: Vec<[f64; 3]>,
    /// What makes the alignment doubtful: a correlation below [`MIN_CORRELATION`], or a shift at
    /// the edge of the search range (the best may lie beyond it). Empty when the alignment holds;
    /// `pcsim compare --strict` fails on any.
    pub warnings: Vec<String>,
}

/// The correlation coefficient below which the alignment is not trusted (a guess, stated: below
/// 0.5 the two filtered records share less than a quarter of their variance, so the shift that
/// maximises it says little about where the measurement was taken).
pub const MIN_CORRELATION: f64 = 0.5;

/// The most sample comparisons the alignment's search may make (shifts × samples: a few
/// seconds).
pub const MAX_SEARCH_WORK: f64 = 2e9;

/// Linear interpolation of `y` sampled at `x0 + k·dx` at `x` (`None` outside).
fn at(y: &[f64], x0: f64, dx: f64, x: f64) -> Option<f64> {
    let last = (y.len() - 1) as f64;
    let s = (x - x0) / dx;
    // A rounding beyond an end is the end.
    if !(s >= -1e-9 && s <= last + 1e-9) {
        return None;
    }
    let s = s.clamp(0.0, last);
    let k = (s.floor() as usize).min(y.len().saturating_sub(2));
    let t = s - k as f64;
    Some(y[k] * (1.0 - t) + y[k + 1] * t)
}

/// One record's three filtered versions: 0–20 Hz, 0–5 Hz, 5–20 Hz, sampled every `dx` at `v`.
fn bands(f: &[f64], dx: f64, v: f64) -> [Vec<f64>; 3] {
    let fs = v / dx;
    [
        lowpass_zero_phase(f, fs, CUTOFF_HZ),
        lowpass_zero_phase(f, fs, BAND_SPLIT_HZ),
        bandpass_zero_phase(f, fs, BAND_SPLIT_HZ, CUTOFF_HZ),
    ]
}

/// Compare the run's contact force (`sim_x`, `sim_f`: one pantograph, positions at a uniform
/// step) with a measurement, over `section` (simulated positions), searching the shift within
/// ± `search_m`; `speed_m_s` turns the filters' frequencies into wavelengths, `supports_m` (the
/// run's supports, sorted) gives the spans of the profile. Errors name what does not fit.
pub fn compare(
    (sim_x, sim_f): (&[f64], &[f64]),
    meas: &MeasuredForce,
    speed_m_s: f64,
    section: [f64; 2],
    search_m: f64,
    supports_m: &[f64],
) -> Result<Comparison, CaseError> {
    let n = sim_x.len();
    check_inputs((sim_x, sim_f), meas, speed_m_s, search_m)?;
    let dxs = (sim_x[n - 1] - sim_x[0]) / (n - 1) as f64;
    let dxm = meas.spacing_m;
    let k_max = (search_m / dxm).round() as i64;
    let [s20, s05, s520] = bands(sim_f, dxs, speed_m_s);
    let [m20, m05, m520] = bands(&meas.force_n, dxm, speed_m_s);
    let xm = &meas.position_m;
    // Pearson's coefficient of the two filtered records over the section at shift k·Δx.
    let s20r = &s20;
    let pairs = |k: i64| {
        let d = k as f64 * dxm;
        xm.iter().enumerate().filter_map(move |(i, &x)| {
            let xs = x + d;
            if xs < section[0] || xs > section[1] {
                return None;
            }
            at(s20r, sim_x[0], dxs, xs).map(|s| (xs, s, i))
        })
    };
    let min_pairs = crate::input::measured::MIN_SAMPLES;
    let best = best_shift(k_max, min_pairs, &m20, &pairs);
    let Some((k, r)) = best else {
        return Err(inv(
            "measured positions",
            format!("{} to {} m", xm[0], xm[xm.len() - 1]),
            &format!(
                "within ± {search_m} m of shift they never cover {min_pairs} samples of the run's section {} to {} m: the record and the run are of different places (or widen --search)",
                section[0], section[1]
            ),
        ));
    };
    let d = k as f64 * dxm;
    let grid: Vec<(f64, f64, usize)> = pairs(k).collect();
    let position_m: Vec<f64> = grid.iter().map(|g| g.0).collect();
    let simulated_n: Vec<f64> = grid.iter().map(|g| g.1).collect();
    let measured_n: Vec<f64> = grid.iter().map(|g| m20[g.2]).collect();
    // The run's bands at the grid (inside its record, as the 0–20 Hz force was); the
    // measurement's at its own samples.
    let sim_at = |y: &[f64]| -> Vec<f64> {
        (position_m.iter())
            .map(|&x| at(y, sim_x[0], dxs, x).unwrap_or(0.0))
            .collect()
    };
    let sim_b = [sim_at(&s05), sim_at(&s520)];
    let mea_b = [
        grid.iter().map(|g| m05[g.2]).collect::<Vec<f64>>(),
        grid.iter().map(|g| m520[g.2]).collect::<Vec<f64>>(),
    ];
    let simulated = ForceStats::of(&simulated_n, &sim_b[0], &sim_b[1]);
    let measured = ForceStats::of(&measured_n, &mea_b[0], &mea_b[1]);
    for (who, st) in [("the run", &simulated), ("the measurement", &measured)] {
        if let Some((name, v)) = st.rows().into_iter().find(|(_, v)| !v.is_finite()) {
            return Err(inv(
                "statistics",
                format!("{name} = {v}"),
                &format!("{who}'s statistics over the section are not finite numbers: its forces are beyond what a sum of squares can hold"),
            ));
        }
    }
    let mut warnings = Vec::new();
    if r < MIN_CORRELATION {
        warnings.push(format!(
            "the best correlation of the two records is {r:.3}, below {MIN_CORRELATION}: the alignment is not trustworthy (a record of another place, another run, or of no force at all)"
        ));
    }
    if k_max > 0 && k.abs() == k_max {
        warnings.push(format!(
            "the best shift, {d:+.2} m, is at the edge of the search range (± {search_m} m): the true alignment may lie beyond it (widen --search)"
        ));
    }
    Ok(Comparison {
        shift_m: d,
        shift_samples: k,
        correlation: r,
        search_m,
        section_m: section,
        simulated,
        measured,
        // Up to an octave above the 20 Hz cut-off (beyond it both are the filter's floor).
        spectrum: welch_pair(&simulated_n, &measured_n, dxm)
            .into_iter()
            .filter(|r| r[0] <= 2.0 * CUTOFF_HZ / speed_m_s)
            .collect(),
        profile: span_profile(&position_m, &simulated_n, &measured_n, supports_m),
        position_m,
        simulated_n,
        measured_n,
        warnings,
    })
}

/// The comparison's inputs: a run's record, a finite search range, a measurement fine enough for
/// the 0–20 Hz filter at the speed, and a search whose work is bounded ([`MAX_SEARCH_WORK`]).
pub(crate) fn check_inputs(
    (sim_x, sim_f): (&[f64], &[f64]),
    meas: &MeasuredForce,
    speed_m_s: f64,
    search_m: f64,
) -> Result<(), CaseError> {
    let n = sim_x.len();
    if n < 2 || sim_f.len() != n {
        return Err(inv(
            "run",
            format!("{n} samples"),
            "the run has no force record to compare",
        ));
    }
    if !(search_m.is_finite() && search_m >= 0.0) {
        return Err(inv(
            "--search",
            search_m,
            "the search range must be a finite length ≥ 0 m",
        ));
    }
    let dxm = meas.spacing_m;
    // The filter needs the 20 Hz band below the measurement's Nyquist frequency.
    if speed_m_s / dxm < 2.0 * CUTOFF_HZ * 1.05 {
        return Err(inv(
            "measured spacing",
            format!("{dxm} m"),
            &format!(
                "at {:.1} km/h a spacing of {dxm} m samples {:.1} Hz, too coarse for the 0–20 Hz filter: it needs less than {:.3} m",
                speed_m_s * 3.6,
                speed_m_s / dxm,
                speed_m_s / (2.0 * CUTOFF_HZ * 1.05)
            ),
        ));
    }
    // Each shift tried costs a pass over the record: bound the work (in floating point: a wide
    // search must not overflow an integer before it is refused).
    let shifts = 2.0 * (search_m / dxm).round() + 1.0;
    if shifts * meas.position_m.len() as f64 > MAX_SEARCH_WORK {
        return Err(inv(
            "--search",
            format!("{search_m} m"),
            &format!(
                "± {search_m} m at the measurement's {dxm} m spacing is {shifts:e} shifts over {} samples, more than {MAX_SEARCH_WORK:e} comparisons: narrow the search",
                meas.position_m.len()
            ),
        ));
    }
    Ok(())
}

/// The shift `k` (in the measurement's samples, within ± `k_max`) that maximises Pearson's
/// coefficient of the two filtered records over the section, with the coefficient; `pairs(k)`
/// gives the run's value and the measurement's index of each sample inside the section at that
/// shift. Shifts with fewer than `min_pairs` samples are not taken. `None`: no shift has enough.
fn best_shift<I: Iterator<Item = (f64, f64, usize)>>(
    k_max: i64,
    min_pairs: usize,
    m20: &[f64],
    pairs: &dyn Fn(i64) -> I,
) -> Option<(i64, f64)> {
    let mut best: Option<(i64, f64)> = None;
    for k in -k_max..=k_max {
        let (mut c, mut ss, mut sm, mut sss, mut smm, mut ssm) = (0usize, 0.0, 0.0, 0.0, 0.0, 0.0);
        for (_, s, i) in pairs(k) {
            let m = m20[i];
            c += 1;
            ss += s;
            sm += m;
            sss += s * s;
            smm += m * m;
            ssm += s * m;
        }
        if c < min_pairs {
            continue;
        }
        let cf = c as f64;
        let cov = ssm - ss * sm / cf;
        let vs = sss - ss * ss / cf;
        let vm = smm - sm * sm / cf;
        let r = if vs > 0.0 && vm > 0.0 {
            cov / (vs * vm).sqrt()
        } else {
            0.0
        };
        if best.is_none_or(|(_, rb)| r > rb) {
            best = Some((k, r));
        }
    }
    best
}

/// Welch's power spectral density of two records sampled every `dx` (m): Hann windows of the
/// largest power of two up to a quarter of the record (at least 64), half-overlapping; one-sided,
/// N²·m against spatial frequency, 1/m.
fn welch_pair(a: &[f64], b: &[f64], dx: f64) -> Vec<[f64; 3]> {
    use rustfft::num_complex::Complex;
    let n = a.len().min(b.len());
    let mut seg = 64usize;
    while seg * 2 <= n / 4 {
        seg *= 2;
    }
    if n < seg {
        return Vec::new();
    }
    let fft = rustfft::FftPlanner::<f64>::new().plan_fft_forward(seg);
    let w: Vec<f64> = (0..seg)
        .map(|i| 0.5 - 0.5 * (2.0 * std::f64::consts::PI * i as f64 / seg as f64).cos())
        .collect();
    let wss: f64 = w.iter().map(|v| v * v).sum();
    let psd = |x: &[f64]| {
        let mean = x[..n].iter().sum::<f64>() / n as f64;
        let mut acc = vec![0.0; seg / 2 + 1];
        let mut count = 0;
        let mut start = 0;
        let mut buf = vec![Complex::new(0.0, 0.0); seg];
        while start + seg <= n {
            for i in 0..seg {
                buf[i] = Complex::new((x[start + i] - mean) * w[i], 0.0);
            }
            fft.process(&mut buf);
            for (k, a) in acc.iter_mut().enumerate() {
                let one_sided = if k == 0 || k == seg / 2 { 1.0 } else { 2.0 };
                *a += one_sided * buf[k].norm_sqr() * dx / wss;
            }
            count += 1;
            start += seg / 2;
        }
        acc.iter().map(|v| v / count as f64).collect::<Vec<f64>>()
    };
    let (pa, pb) = (psd(a), psd(b));
    (1..pa.len())
        .map(|k| [k as f64 / (seg as f64 * dx), pa[k], pb[k]])
        .collect()
}

/// Each record averaged over the position within its span (50 bins of the span's length; the
/// spans need not be equal).
fn span_profile(x: &[f64], a: &[f64], b: &[f64], supports_m: &[f64]) -> Vec<[f64; 3]> {
    const BINS: usize = 50;
    let mut acc = vec![(0.0, 0.0, 0usize); BINS];
    for ((&xi, &ai), &bi) in x.iter().zip(a).zip(b) {
        let j = supports_m.partition_point(|&s| s <= xi);
        if j == 0 || j >= supports_m.len() {
            continue;
        }
        let (s0, s1) = (supports_m[j - 1], supports_m[j]);
        let frac = (xi - s0) / (s1 - s0);
        let bin = ((frac * BINS as f64) as usize).min(BINS - 1);
        acc[bin].0 += ai;
        acc[bin].1 += bi;
        acc[bin].2 += 1;
    }
    acc.iter()
        .enumerate()
        .filter(|(_, c)| c.2 > 0)
        .map(|(i, c)| {
            [
                (i as f64 + 0.5) / BINS as f64,
                c.0 / c.2 as f64,
                c.1 / c.2 as f64,
            ]
        })
        .collect()
}
