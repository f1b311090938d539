//! EN 50318 contact-force statistics over the analysis section (README §4).

use serde::{Deserialize, Serialize};

use crate::analysis::filter::{bandpass_zero_phase, lowpass_zero_phase};

/// Statistics of one pantograph's contact force over the analysis section.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
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
    /// Largest distance of the contact point from the track's centre line over the analysis
    /// section, mm (lateral motion modelled).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_lateral_offset_mm: Option<f64>,
    /// Smallest margin from the contact point to the end of the head (`head_half_width_m −
    /// |lateral|`) over the analysis section, mm (lateral motion and a head width given).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_head_margin_mm: Option<f64>,
    /// Largest lateral deflection of the contact wire from its still-air static position at the
    /// droppers and mid-spans of the analysis section over the run, mm (lateral motion).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub max_contact_wire_blowout_mm: Option<f64>,
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
        max_lateral_offset_mm: None,
        min_head_margin_mm: None,
        max_contact_wire_blowout_mm: None,
    })
}

/// What the contact point did across the head over the analysis section (issue 12).
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct LateralStats {
    /// Largest `|lateral|`, mm.
    pub max_lateral_offset_mm: f64,
    /// Smallest `head_half_width − |lateral|`, mm (head width given).
    pub min_head_margin_mm: Option<f64>,
    /// Samples with the contact point beyond the working range (`working_half_width_m`).
    pub samples_outside_working_range: usize,
    /// Samples with the contact point beyond the head: the wire has left the pantograph.
    pub samples_off_head: usize,
    /// The pantograph's half-widths used, m.
    pub head_half_width_m: Option<f64>,
    /// The working range's half-width used, m (when given).
    pub working_half_width_m: Option<f64>,
    /// Histogram of the lateral position (the strip's wear pattern).
    pub histogram: LateralHistogram,
}

/// A histogram of the contact point's lateral position.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct LateralHistogram {
    /// Left edge of the first bin, mm (from the head's centre: the track's centre line, moved
    /// toward a canted curve's centre; positive to the same side as positive stagger).
    pub from_mm: f64,
    /// Bin width, mm.
    pub bin_mm: f64,
    /// Samples per bin; samples beyond the range go to the end bins.
    pub counts: Vec<usize>,
}

/// Bin width of the lateral histogram, mm.
pub const LATERAL_BIN_MM: f64 = 10.0;

/// The lateral statistics of one pantograph over `section` (positions in track coordinates).
pub fn lateral_stats(
    lateral_m: &[f64],
    position_m: &[f64],
    section: [f64; 2],
    head_half_width_m: Option<f64>,
    working_half_width_m: Option<f64>,
) -> Option<LateralStats> {
    let idx: Vec<usize> = (0..lateral_m.len())
        .filter(|&i| position_m[i] >= section[0] && position_m[i] <= section[1])
        .collect();
    if idx.is_empty() {
        return None;
    }
    let max_abs = idx.iter().map(|&i| lateral_m[i].abs()).fold(0.0, f64::max);
    let half = head_half_width_m.unwrap_or(1.0);
    let nbins = (2.0 * half * 1e3 / LATERAL_BIN_MM).ceil().max(1.0) as usize;
    let from_mm = -half * 1e3;
    let mut counts = vec![0usize; nbins];
    for &i in &idx {
        let b = ((lateral_m[i] * 1e3 - from_mm) / LATERAL_BIN_MM).floor();
        let b = b.clamp(0.0, (nbins - 1) as f64) as usize;
        counts[b] += 1;
    }
    let count_beyond = |w: Option<f64>| {
        w.map_or(0, |w| {
            idx.iter().filter(|&&i| lateral_m[i].abs() > w).count()
        })
    };
    Some(LateralStats {
        max_lateral_offset_mm: max_abs * 1e3,
        min_head_margin_mm: head_half_width_m.map(|h| (h - max_abs) * 1e3),
        samples_outside_working_range: count_beyond(working_half_width_m),
        samples_off_head: count_beyond(head_half_width_m),
        head_half_width_m,
        working_half_width_m,
        histogram: LateralHistogram {
            from_mm,
            bin_mm: LATERAL_BIN_MM,
            counts,
        },
    })
}

/// One pantograph's passage through one overlap of a line (issue 21): the raw contact force
/// (the sum over the wires) while the pantograph is between the overlap's first and last shared
/// supports.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct OverlapStats {
    /// The overlap: its first and last shared support, track coordinates, m.
    pub section_m: [f64; 2],
    /// Largest raw contact force inside it, N.
    pub max_force_n: f64,
    /// Smallest raw contact force inside it, N.
    pub min_force_n: f64,
    /// Share of its samples with no contact force, %.
    pub loss_of_contact_percent: f64,
    /// Where both contact wires carried force: the first and last such position, m (none when
    /// the pantograph never touched both at once).
    pub transfer_m: Option<[f64; 2]>,
    /// The out-of-running wire's clearance: the smallest height of a wire carrying no force
    /// above the wire the pantograph runs on, inside the overlap but outside the transfer
    /// region, mm (none when there is no such sample).
    pub min_clearance_mm: Option<f64>,
    /// Largest uplift of a steady arm at the overlap's supports while the pantograph passed, mm.
    pub max_uplift_at_support_mm: f64,
    /// Samples inside it.
    pub samples: usize,
}

/// One pantograph's passage over a hard spot of a line (issue 55: a section insulator, a
/// neutral section): the raw contact force and the contact wire's uplift at the contact point
/// while the pantograph is over it.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct HardSpotStats {
    /// What it is.
    pub kind: crate::model::HardSpotKind,
    /// Its extent along the track, m.
    pub section_m: [f64; 2],
    /// Largest raw contact force over it, N.
    pub max_force_n: f64,
    /// Smallest raw contact force over it, N.
    pub min_force_n: f64,
    /// Share of its samples with no contact force, %.
    pub loss_of_contact_percent: f64,
    /// Largest rise of the contact wire at the contact point above its static height (the
    /// runners' included) over it, mm.
    pub max_uplift_mm: f64,
    /// Samples over it.
    pub samples: usize,
}

/// The passage over `section_m` of a pantograph at positions `x` (track coordinates) with
/// raw forces `force_n` and the contact wire's rise above its static height `rise_m` at each
/// sample; `None` when it never was over it.
pub fn hard_spot_stats(
    kind: crate::model::HardSpotKind,
    section_m: [f64; 2],
    x: &[f64],
    force_n: &[f64],
    rise_m: impl Fn(usize) -> f64,
) -> Option<HardSpotStats> {
    let inside: Vec<usize> = (0..x.len())
        .filter(|&i| x[i] >= section_m[0] && x[i] <= section_m[1])
        .collect();
    if inside.is_empty() {
        return None;
    }
    let f = |i: &usize| force_n[*i];
    Some(HardSpotStats {
        kind,
        section_m,
        max_force_n: inside.iter().map(f).fold(f64::NEG_INFINITY, f64::max),
        min_force_n: inside.iter().map(f).fold(f64::INFINITY, f64::min),
        loss_of_contact_percent: 100.0
            * inside.iter().filter(|&i| force_n[*i] <= 0.0).count() as f64
            / inside.len() as f64,
        max_uplift_mm: 1e3
            * inside
                .iter()
                .map(|&i| rise_m(i))
                .fold(f64::NEG_INFINITY, f64::max),
        samples: inside.len(),
    })
}

impl OverlapStats {
    /// An overlap not yet passed.
    pub fn new(section_m: [f64; 2]) -> Self {
        OverlapStats {
            section_m,
            max_force_n: f64::NEG_INFINITY,
            min_force_n: f64::INFINITY,
            loss_of_contact_percent: 0.0,
            transfer_m: None,
            min_clearance_mm: None,
            max_uplift_at_support_mm: 0.0,
            samples: 0,
        }
    }

    /// Whether track position `x` lies inside the overlap.
    pub fn contains(&self, x: f64) -> bool {
        x >= self.section_m[0] && x <= self.section_m[1]
    }

    /// Add a sample at `x` of total force `force_n`, with `touching` wires carrying force.
    pub fn add(&mut self, x: f64, force_n: f64, touching: usize) {
        self.samples += 1;
        self.max_force_n = self.max_force_n.max(force_n);
        self.min_force_n = self.min_force_n.min(force_n);
        if force_n <= 0.0 {
            // Counted as a count until `finish`.
            self.loss_of_contact_percent += 1.0;
        }
        if touching >= 2 {
            self.transfer_m = Some(match self.transfer_m {
                Some([a, b]) => [a.min(x), b.max(x)],
                None => [x, x],
            });
        }
    }

    /// The statistics of the passage (`None` when the pantograph never entered the overlap),
    /// with the clearance from the positions `x` of the run and, per sample, the gap `gap_m` of
    /// the nearest idle wire above the contact point (infinite when none).
    pub fn finish(mut self, x: &[f64], gap_m: &[f64]) -> Option<Self> {
        if self.samples == 0 {
            return None;
        }
        self.loss_of_contact_percent *= 100.0 / self.samples as f64;
        let outside = |xi: f64| self.transfer_m.is_none_or(|[a, b]| xi < a || xi > b);
        let c = x
            .iter()
            .zip(gap_m)
            .filter(|&(&xi, g)| self.contains(xi) && outside(xi) && g.is_finite())
            .map(|(_, &g)| g)
            .fold(f64::INFINITY, f64::min);
        self.min_clearance_mm = c.is_finite().then_some(c * 1e3);
        Some(self)
    }
}
