//! What a run reports: the summary (`summary.json` of the CLI, `Result.summary` in Python) and
//! the time-series columns (`timeseries.csv`, `Result.timeseries`), defined once here so that
//! every front end writes the same content.

use serde::Serialize;

use crate::analysis::events::run_errors;
use crate::analysis::record::RunOutput;
use crate::analysis::stats::{ContactStats, HardSpotStats, LateralStats, OverlapStats};
use crate::input::case::Case;
use crate::model::irregularity::IrregularityReport;
use crate::model::wind::WindReport;
use crate::solve::run::RunStatistics;

/// A time rounded to the nanosecond (so that 19.113 s reads as such).
pub fn round_ns(t: f64) -> f64 {
    (t * 1e9).round() / 1e9
}

/// `x` with `digits` significant digits (`0.00123`, `4.66`, `1230`), for the terminal: a small
/// value never prints as `0.00`.
pub fn significant(x: f64, digits: usize) -> String {
    if x == 0.0 || !x.is_finite() {
        return format!("{x}");
    }
    let magnitude = x.abs().log10().floor() as i64;
    let decimals = (digits as i64 - 1 - magnitude).max(0) as usize;
    format!("{x:.decimals$}")
}

/// The name a case reports itself with (`meta.name`, or `case`).
pub fn case_name(case: &Case) -> String {
    if case.meta.name.is_empty() {
        "case".to_string()
    } else {
        case.meta.name.clone()
    }
}

#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
/// One pantograph in `summary.json`: its name, statistics and lateral flags.
pub struct PantographSummary {
    /// The pantograph's name.
    pub name: String,
    /// EN 50318 statistics over the analysis section.
    pub stats: Option<ContactStats>,
    /// The contact point across the head (lateral motion modelled): flags and the wear
    /// histogram.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lateral: Option<LateralStats>,
    /// Its passage through each overlap of a line (issue 21).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub overlaps: Vec<OverlapStats>,
    /// Its passage over each section insulator and neutral section (issue 55).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub hard_spots: Vec<HardSpotStats>,
    /// Each collector strip's own contact (issue 43; `stats` above are their sum's).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub strips: Vec<StripSummary>,
}

#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
/// One collector strip in `summary.json`: its place on the head and its force's statistics.
pub struct StripSummary {
    /// Where its contact point is ahead of the pantograph's position, m.
    pub along_m: f64,
    /// EN 50318 statistics of its own force over the analysis section.
    pub stats: Option<ContactStats>,
}

#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize, schemars::JsonSchema)]
/// `summary.json` of a run: the case, the run's settings and statistics, the warnings and the verdicts. Built here for every front end.
pub struct RunSummary {
    /// The case's name (`meta.name`).
    pub case_name: String,
    /// Train speed, km/h.
    pub speed_kmh: f64,
    /// Contact-wire tension used, N.
    pub contact_wire_tension_n: f64,
    /// The slowest contact wire's wave speed √(T/ρA) with its clamps and droppers in ρA, km/h.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_wire_wave_speed_kmh: Option<f64>,
    /// The train speed over that wave speed (EN 50119 asks below 0.7; `pcsim assess`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed_ratio: Option<f64>,
    /// On a line of several tension lengths: the speed ratio of each tension length's contact
    /// wire, in track order (`speed_ratio` is the largest).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub speed_ratio_per_tension_length: Vec<f64>,
    /// Span length, m (none for a `[line]`: its supports are listed in `supports_m`).
    pub span_m: Option<f64>,
    /// The supports of a `[line]`, track positions, m (absent for a `[catenary]` of equal spans).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub supports_m: Vec<f64>,
    /// The overlaps of a `[line]`: first and last shared support of each, m.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub overlaps_m: Vec<[f64; 2]>,
    /// Simulated time, s.
    pub simulated_time_s: f64,
    /// Wall-clock time of the run, s.
    pub wall_time_s: f64,
    /// Analysis section (track coordinates), m.
    pub analysis_section_m: [f64; 2],
    /// Modes per wire and direction.
    pub modes_per_wire: usize,
    /// Time step, s.
    pub dt_s: f64,
    /// The kernels that ran: `portable` (the same bytes on every machine) or `x86-64-v3`.
    pub kernels: String,
    /// Largest number of droppers slack at once.
    pub max_slack_droppers: usize,
    /// Share of steps with at least one slack dropper, %.
    pub steps_with_slack_percent: f64,
    /// Counters of what the run loop saw.
    pub run_statistics: RunStatistics,
    /// The flags that overrode case values, as given.
    pub overrides: Vec<String>,
    /// Every warning of the case and the run, with the verdicts.
    pub warnings: Vec<String>,
    /// Error-level events of the run ([`run_errors`]): a dewirement. The CLI's `run` exits
    /// non-zero when there is one, unless `--allow-dewirement` is given.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub errors: Vec<String>,
    /// What each pantograph's `max_uplift_at_support_mm` is measured from: the design's static
    /// position, or under ice or a mean wind the loaded static position.
    pub uplift_datum: crate::analysis::record::UpliftDatum,
    /// Per pantograph: its statistics.
    pub pantographs: Vec<PantographSummary>,
    /// The crosswind (mean speed, spectrum, seed, turbulence intensity achieved).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wind: Option<WindReport>,
    /// The contact-wire irregularity's sources (kind, seed, RMS target and achieved).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub irregularity: Vec<IrregularityReport>,
    /// A curved track: radius, the head's offset on a canted curve, the chord's largest bow and
    /// the registrations' static (pull-off) forces.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub curve: Option<crate::model::lateral::CurveReport>,
    /// The coupled stability limit the time step was checked against: the highest frequency
    /// of the explicit system, the largest accepted Δt and the element that sets it.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stability: Option<crate::solve::CoupledLimit>,
    /// With `--verify`: each statistic beside the refined run's (twice the modes, half the step)
    /// and the stiffer contact's, and which are not converged to their tolerance.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub verification: Option<crate::analysis::verify::Verification>,
    /// With `--sensitivity`: each statistic's band over the case's ranged values and the values
    /// that move it most.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub sensitivity: Option<crate::analysis::sensitivity::Sensitivity>,
}

/// The run's verdicts, built here once for every front end: a contact wire that left the
/// pantograph head, or a contact point that left the strip's working range (lateral motion).
pub fn run_verdicts(out: &RunOutput) -> Vec<String> {
    let mut v = Vec::new();
    for p in &out.pantographs {
        if let Some(s) = p
            .stats
            .as_ref()
            .filter(|s| s.loss_of_contact_percent >= 100.0)
        {
            v.push(format!(
                "pantograph {}: it never touched the contact wire in the analysis section (contact lost {:.0} % of the time): its force statistics describe no contact; check its uplift (uplift_n) and aerodynamic force",
                p.name, s.loss_of_contact_percent
            ));
        }
        if let Some(l) = &p.lateral {
            let n = p.position_m.len().max(1);
            // A contact point beyond the head is an error-level event (`run_errors`).
            if l.samples_off_head == 0 && l.samples_outside_working_range > 0 {
                v.push(format!(
                    "pantograph {}: the contact point left the working range in {} samples ({:.2} % of the run; largest offset {:.0} mm)",
                    p.name,
                    l.samples_outside_working_range,
                    100.0 * l.samples_outside_working_range as f64 / n as f64,
                    l.max_lateral_offset_mm
                ));
            }
        }
    }
    v
}

impl RunSummary {
    /// The summary of a run: `warnings` are the set-up's, and the run's verdicts
    /// ([`run_verdicts`]) follow them.
    pub fn new(
        case: &Case,
        out: &RunOutput,
        wall_time_s: f64,
        overrides: Vec<String>,
        warnings: Vec<String>,
    ) -> Self {
        RunSummary {
            case_name: case_name(case),
            speed_kmh: case.run.speed_kmh,
            contact_wire_tension_n: case.catenary.contact_wire.tension_n,
            contact_wire_wave_speed_kmh: out.contact_wire_wave_speed_m_s.map(|c| c * 3.6),
            speed_ratio: out.contact_wire_wave_speed_m_s.map(|c| out.speed_m_s / c),
            speed_ratio_per_tension_length: if out.contact_wire_wave_speeds_m_s.len() > 1 {
                out.contact_wire_wave_speeds_m_s
                    .iter()
                    .map(|c| out.speed_m_s / c)
                    .collect()
            } else {
                Vec::new()
            },
            span_m: case.line.is_none().then_some(case.catenary.span_m),
            supports_m: case.line.as_ref().map_or(Vec::new(), |l| l.supports_m()),
            overlaps_m: case
                .line
                .as_ref()
                .map_or(Vec::new(), |l| l.overlap_sections_m()),
            simulated_time_s: round_ns(out.simulated_time_s()),
            wall_time_s: (wall_time_s * 1e3).round() / 1e3,
            analysis_section_m: out.analysis_m,
            modes_per_wire: out.n_modes,
            dt_s: out.dt_s,
            kernels: crate::solve::Isa::detect().name().into(),
            max_slack_droppers: out.max_slack_droppers,
            steps_with_slack_percent: out.steps_with_slack_percent,
            run_statistics: out.run_statistics,
            overrides,
            warnings: warnings.into_iter().chain(run_verdicts(out)).collect(),
            errors: run_errors(out).into_iter().map(|e| e.message).collect(),
            uplift_datum: out.uplift_datum,
            pantographs: out
                .pantographs
                .iter()
                .map(|p| PantographSummary {
                    name: p.name.clone(),
                    stats: p.stats,
                    lateral: p.lateral.clone(),
                    overlaps: p.overlaps.clone(),
                    hard_spots: p.hard_spots.clone(),
                    strips: (p.strips.iter())
                        .map(|s| StripSummary {
                            along_m: s.along_m,
                            stats: s.stats,
                        })
                        .collect(),
                })
                .collect(),
            wind: out.wind.clone(),
            irregularity: out.irregularity.clone(),
            curve: out.curve.clone(),
            stability: out.stability.clone(),
            verification: None,
            sensitivity: None,
        }
    }
}

/// One column of the time series: its name, its values and the decimals it is written with.
#[derive(Debug, Clone, PartialEq)]
pub struct Column {
    /// Column name with its unit (the CSV header).
    pub name: String,
    /// One value per recorded step.
    pub values: Vec<f64>,
    /// Decimals it is written with.
    pub decimals: usize,
}

/// The time-series columns of a run: the time, then per pantograph its position, raw and
/// 20 Hz-filtered contact force, contact-wire height, and with lateral motion the contact
/// point's lateral position and head margin.
pub fn timeseries_columns(out: &RunOutput) -> Vec<Column> {
    let col = |name: String, values: Vec<f64>, decimals: usize| Column {
        name,
        values,
        decimals,
    };
    let mut cols = vec![col("time_s".into(), out.time_s.clone(), 6)];
    for (i, p) in out.pantographs.iter().enumerate() {
        let tag = if p.name.is_empty() {
            format!("p{i}")
        } else {
            p.name.clone()
        };
        cols.push(col(format!("{tag}_position_m"), p.position_m.clone(), 4));
        cols.push(col(format!("{tag}_force_n"), p.force_n.clone(), 4));
        cols.push(col(
            format!("{tag}_force_filtered_n"),
            p.force_filtered_n.clone(),
            4,
        ));
        cols.push(col(format!("{tag}_height_m"), p.wire_height_m.clone(), 6));
        if !p.lateral_m.is_empty() {
            cols.push(col(format!("{tag}_lateral_m"), p.lateral_m.clone(), 6));
            if let Some(h) = p.head_half_width_m {
                // From the head's centre, which a canted curve moves off the track's (each
                // section of the curve its own).
                let off = |x: f64| out.curve.as_ref().map_or(0.0, |c| c.head_offset_at(x));
                cols.push(col(
                    format!("{tag}_head_margin_m"),
                    (p.lateral_m.iter().zip(&p.position_m))
                        .map(|(z, &x)| h - (z - off(x)).abs())
                        .collect(),
                    6,
                ));
            }
        }
        if !p.twist_rad.is_empty() {
            cols.push(col(format!("{tag}_twist_rad"), p.twist_rad.clone(), 9));
        }
        for (wire, f) in &p.wire_forces {
            cols.push(col(format!("{tag}_force_on_{wire}_n"), f.clone(), 4));
        }
        for (k, s) in p.strips.iter().enumerate() {
            cols.push(col(
                format!("{tag}_strip{}_force_n", k + 1),
                s.force_n.clone(),
                4,
            ));
        }
    }
    cols
}
