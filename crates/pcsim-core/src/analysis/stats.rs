//! EN 50318 contact-force statistics over the analysis section (README §4).

use serde::Serialize;

use crate::analysis::filter::{bandpass_zero_phase, lowpass_zero_phase};

/// Statistics of one pantograph's contact force over the analysis section.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct ContactStats {
    /// Mean of the 0–20 Hz force, N.
    pub mean_n: f64,
    /// Standard deviation of the 0–20 Hz force, N.
    pub std_n: f64,
    /// σ of the 0–5 Hz band, N.
    pub std_0_5hz_n: f64,
    /// σ of the 5–20 Hz band, N.
    pub std_5_20hz_n: f64,
    /// Fm + 3σ, N.
    pub stat_max_n: f64,
    /// Fm − 3σ, N.
    pub stat_min_n: f64,
    /// Largest 0–20 Hz force, N.
    pub actual_max_n: f64,
    /// Smallest 0–20 Hz force, N.
    pub actual_min_n: f64,
    /// Range (max − min) of the contact-wire height at the contact point (unfiltered), mm.
    pub contact_point_range_mm: f64,
    /// Largest upward displacement of the contact wire at a steady arm from its static position
    /// while this pantograph passes (supports inside the analysis section), mm.
    pub max_uplift_at_support_mm: f64,
    /// Share of samples with zero (unfiltered) contact force, %.
    pub loss_of_contact_percent: f64,
}

/// Low-pass cut-off for the statistics, Hz.
pub const CUTOFF_HZ: f64 = 20.0;
/// Boundary between the low and high bands, Hz.
pub const BAND_SPLIT_HZ: f64 = 5.0;

fn mean_std(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    let v = x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / n;
    (m, v.sqrt())
}

/// Compute the statistics. The whole record (`force_n`, sampled every `dt_s`) is filtered with
/// zero phase first, then cut to the samples whose `position_m` lies in `section` (README §5:
/// filter the whole record, then cut). The 0–5 Hz band is a 5 Hz low-pass; the 5–20 Hz band a
/// band-pass.
pub fn contact_stats(
    force_n: &[f64],
    position_m: &[f64],
    wire_height_m: &[f64],
    dt_s: f64,
    section: [f64; 2],
    max_uplift_at_support_m: f64,
) -> Option<ContactStats> {
    let fs = 1.0 / dt_s;
    let f20 = lowpass_zero_phase(force_n, fs, CUTOFF_HZ);
    let f5 = lowpass_zero_phase(force_n, fs, BAND_SPLIT_HZ);
    let f520 = bandpass_zero_phase(force_n, fs, BAND_SPLIT_HZ, CUTOFF_HZ);
    let idx: Vec<usize> = (0..force_n.len())
        .filter(|&i| position_m[i] >= section[0] && position_m[i] <= section[1])
        .collect();
    if idx.len() < 2 {
        return None;
    }
    let pick = |v: &[f64]| idx.iter().map(|&i| v[i]).collect::<Vec<_>>();
    let (s20, s5, s520) = (pick(&f20), pick(&f5), pick(&f520));
    let (mean, std) = mean_std(&s20);
    let (_, std5) = mean_std(&s5);
    let (_, std520) = mean_std(&s520);
    let h = pick(wire_height_m);
    let hmax = h.iter().cloned().fold(f64::MIN, f64::max);
    let hmin = h.iter().cloned().fold(f64::MAX, f64::min);
    let lost = idx.iter().filter(|&&i| force_n[i] <= 0.0).count();
    Some(ContactStats {
        mean_n: mean,
        std_n: std,
        std_0_5hz_n: std5,
        std_5_20hz_n: std520,
        stat_max_n: mean + 3.0 * std,
        stat_min_n: mean - 3.0 * std,
        actual_max_n: s20.iter().cloned().fold(f64::MIN, f64::max),
        actual_min_n: s20.iter().cloned().fold(f64::MAX, f64::min),
        contact_point_range_mm: (hmax - hmin) * 1e3,
        max_uplift_at_support_mm: max_uplift_at_support_m * 1e3,
        loss_of_contact_percent: 100.0 * lost as f64 / idx.len() as f64,
    })
}
