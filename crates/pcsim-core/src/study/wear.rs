//! Current collection (issue 54): the electrical contact and its arcs, the wear of the contact
//! wire and of the collector strips, the contact point's lateral sweep across the head, and
//! their life over a traffic mix. A study of a spec file (`kind = "wear"`,
//! `presets/studies/wear-2018-like.toml`), through the one driver of the study contract.
//!
//! The dynamics are pcsim's (the paper's Eqs. 1–19: the contact force, its loss, the contact
//! gap, the contact point across the head); this file adds the laws of current collection,
//! each one function:
//! - Archard's law of sliding wear, `V = K F s / H` ([`archard_volume_m3`]);
//! - the electrical wear while current passes the contact, linear in the charge
//!   ([`electrical_volume_m3`]), and Holm's constriction resistance of the contact,
//!   `R = (ρ₁ + ρ₂) / (4a)`, `a = √(F / (π H))` ([`contact_resistance_ohm`]), for the Joule heat;
//! - the arc at a loss of contact: it strikes when the contact opens under current, burns at
//!   its arc voltage while the gap stays below a gap that grows with the current, and goes out
//!   beyond it ([`extinction_gap_m`]); the arc's erosion is linear in its energy
//!   ([`arc_volume_m3`]); NQ is the share of time with an arc (EN 50317's definition);
//! - the lateral sweep: the contact point's net lateral travel across a span over the time to
//!   pass it (`2 s v / L` on a straight zig-zag of stagger ±s), against Derosa et al.'s
//!   (Wear 486–487, 2021) lower limit of 330 mm/s;
//! - the worn contact wire as a round section cut flat ([`worn_depth_m`]).
//!
//! Every coefficient comes from the spec, each with its source or a `guess` mark, and travels
//! into `wear.json`.

use serde::{Deserialize, Serialize};
use std::fmt::Write as _;

use crate::analysis::record::{simulate, PantographTrace, RunOutput};
use crate::analysis::sweep::parallel_map;
use crate::compile::Setup;
use crate::error::{CaseError, SimError};
use crate::input::bounds::inv;
use crate::input::overrides::{with_overrides, OverrideValue};
use crate::input::Case;
use crate::study::contract::{
    Answer, CaseLabel, Figure, FigureSeries, Study, StudyFile, StudyKind,
};
use crate::study::CaseLoader;

/// The embedded default spec: the 2018-like stitched line in 3D under a mix of three trains.
pub const DEFAULT_SPEC: &str = include_str!("../../../../presets/studies/wear-2018-like.toml");

/// Most bins of the wear profile along the line: the bound on its memory.
pub const MAX_BINS: usize = 1_000_000;

/// Most runs one study makes (trains × realisations): the bound on the work.
pub const MAX_RUNS: usize = 256;

/// The density of a copper contact wire, kg/m³: its section from its mass per metre when the
/// case gives no diameter (Cu-ETP, EN 50149's material; handbook value).
const COPPER_DENSITY_KG_M3: f64 = 8890.0;

/// A value with its source (`{ value, source }`), as everywhere in pcsim.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Sourced {
    /// The value, in the unit its field's name carries.
    pub value: f64,
    /// Where it comes from, or `guess: why`.
    pub source: String,
    /// A remark.
    #[serde(default, skip_serializing_if = "String::is_empty")]
    pub note: String,
}

/// One train of the traffic mix.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Train {
    /// Its name.
    pub name: String,
    /// Its speed, km/h.
    pub speed_kmh: Sourced,
    /// The current each of its pantographs draws, A.
    pub current_a: Sourced,
    /// Passages a day.
    pub passages_per_day: Sourced,
    /// The current along the line instead of `current_a`: `[position_m, current_a]` points,
    /// linear between them, constant beyond the ends.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub current_profile: Vec<[f64; 2]>,
}

/// The laws' coefficients (SI).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WearLaw {
    /// Archard's dimensionless wear coefficient of the contact wire.
    pub wire_archard_k: Sourced,
    /// The contact wire's hardness, Pa.
    pub wire_hardness_pa: Sourced,
    /// Archard's coefficient of the strip.
    pub strip_archard_k: Sourced,
    /// The strip's hardness, Pa.
    pub strip_hardness_pa: Sourced,
    /// The contact wire's electrical wear per charge passed in contact, m³/C.
    pub wire_electrical_m3_per_c: Sourced,
    /// The strip's, m³/C.
    pub strip_electrical_m3_per_c: Sourced,
    /// The contact wire's arc erosion per arc energy, m³/J.
    pub wire_arc_m3_per_j: Sourced,
    /// The strip's, m³/J.
    pub strip_arc_m3_per_j: Sourced,
    /// The two bodies' resistivities together (Holm's ρ₁ + ρ₂), Ω·m.
    pub resistivity_sum_ohm_m: Sourced,
    /// The hardness of the softer body, which yields at the contact spot, Pa.
    pub contact_hardness_pa: Sourced,
    /// The arc voltage, V.
    pub arc_voltage_v: Sourced,
    /// The gap beyond which an arc goes out, per ampere, m/A.
    pub arc_gap_m_per_a: Sourced,
}

/// The limits the life is counted to.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WearLimits {
    /// The contact wire's loss of section at renewal, % of its section.
    pub wire_area_loss_percent: Sourced,
    /// The strip's wear allowance (its height that may wear), m.
    pub strip_wear_allowance_m: Sourced,
    /// The strip's width along the track, m.
    pub strip_width_m: Sourced,
    /// The lowest lateral sweep speed recommended, m/s.
    pub sweep_min_m_s: Sourced,
}

/// A current-collection study's spec file (`pcsim schema wear-spec`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WearSpec {
    /// `"wear"`.
    pub kind: String,
    /// The case: a preset's name, or a case file beside the spec.
    pub case: String,
    /// The life counted, years.
    pub years: Sourced,
    /// Realisations of each train over the case's seeds (1 for a case without random input).
    #[serde(default = "one")]
    pub realisations: usize,
    /// The bins of the wear profile along the line, m.
    pub bin_m: Sourced,
    /// Accept runs whose contact was lost over more than 10 % of the section (an error-level
    /// event of a run: refused otherwise, as everywhere).
    #[serde(default)]
    pub allow_contact_loss: bool,
    /// Accept runs where the contact wire left a head.
    #[serde(default)]
    pub allow_dewirement: bool,
    /// The traffic mix.
    pub trains: Vec<Train>,
    /// The laws' coefficients.
    pub law: WearLaw,
    /// The limits.
    pub limits: WearLimits,
}

fn one() -> usize {
    1
}

/// The study: its spec and the case it names.
#[derive(Debug, Clone, PartialEq)]
pub struct WearStudy {
    /// The spec as read.
    pub spec: WearSpec,
    /// The case.
    pub case: Case,
}

/// Archard's law of sliding wear: the volume worn, m³, by a force `force_n` over a sliding
/// distance `sliding_m` with the dimensionless coefficient `k` against hardness `hardness_pa`.
pub fn archard_volume_m3(k: f64, hardness_pa: f64, force_n: f64, sliding_m: f64) -> f64 {
    k * force_n.max(0.0) * sliding_m / hardness_pa
}

/// The electrical wear of a contact carrying `current_a` for `time_s`: linear in the charge,
/// `m3_per_c · |I| · t`, m³.
pub fn electrical_volume_m3(m3_per_c: f64, current_a: f64, time_s: f64) -> f64 {
    m3_per_c * current_a.abs() * time_s
}

/// An arc's erosion, linear in its energy, m³.
pub fn arc_volume_m3(m3_per_j: f64, energy_j: f64) -> f64 {
    m3_per_j * energy_j
}

/// Holm's constriction resistance of one contact spot pressed by `force_n`: `R = (ρ₁ + ρ₂) /
/// (4a)` with the spot's radius `a = √(F / (π H))` (plastic contact), Ω; infinite without force.
pub fn contact_resistance_ohm(resistivity_sum_ohm_m: f64, hardness_pa: f64, force_n: f64) -> f64 {
    if force_n <= 0.0 {
        return f64::INFINITY;
    }
    let a = (force_n / (std::f64::consts::PI * hardness_pa)).sqrt();
    resistivity_sum_ohm_m / (4.0 * a)
}

/// The gap beyond which an arc of `current_a` goes out, m.
pub fn extinction_gap_m(gap_m_per_a: f64, current_a: f64) -> f64 {
    gap_m_per_a * current_a.abs()
}

/// The depth of a round wire of radius `radius_m` worn flat over an area `area_m2` of its
/// section (the circular segment's height), m; the whole diameter beyond the section.
pub fn worn_depth_m(area_m2: f64, radius_m: f64) -> f64 {
    let segment = |h: f64| {
        let d = radius_m - h;
        radius_m * radius_m * (d / radius_m).clamp(-1.0, 1.0).acos()
            - d * (2.0 * radius_m * h - h * h).max(0.0).sqrt()
    };
    if area_m2 <= 0.0 {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0, 2.0 * radius_m);
    if segment(hi) <= area_m2 {
        return hi;
    }
    for _ in 0..100 {
        let mid = 0.5 * (lo + hi);
        if segment(mid) < area_m2 {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

/// The current at `x_m` of a train: its profile's, linear between points, or its constant.
pub fn current_at(train: &Train, x_m: f64) -> f64 {
    let p = &train.current_profile;
    match p.len() {
        0 => train.current_a.value,
        1 => p[0][1],
        _ => {
            let i = p.partition_point(|q| q[0] <= x_m);
            if i == 0 {
                p[0][1]
            } else if i == p.len() {
                p[p.len() - 1][1]
            } else {
                let (a, b) = (p[i - 1], p[i]);
                a[1] + (b[1] - a[1]) * (x_m - a[0]) / (b[0] - a[0])
            }
        }
    }
}

/// The train with no current over the dead lengths `dead_m` (a line's neutral sections, issue
/// 55: the current stops over each): its current as a profile, zero from each dead length's
/// start to its end, its own value up to a millimetre before and after.
pub fn without_current_over(train: &Train, dead_m: &[[f64; 2]]) -> Train {
    if dead_m.is_empty() {
        return train.clone();
    }
    let eps = 1e-3;
    let dead = |x: f64| dead_m.iter().any(|d| x >= d[0] && x <= d[1]);
    let mut points: Vec<[f64; 2]> = (train.current_profile.iter())
        .filter(|q| !dead(q[0]))
        .copied()
        .collect();
    for &[a, b] in dead_m {
        points.push([a - eps, current_at(train, a - eps)]);
        points.push([a, 0.0]);
        points.push([b, 0.0]);
        points.push([b + eps, current_at(train, b + eps)]);
    }
    points.sort_by(|p, q| p[0].total_cmp(&q[0]));
    Train {
        current_profile: points,
        ..train.clone()
    }
}

/// One arc.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct ArcEvent {
    /// Where it struck, m.
    pub start_m: f64,
    /// How long it burnt, s.
    pub duration_s: f64,
    /// Its energy, J.
    pub energy_j: f64,
    /// The realisation it happened in.
    pub realisation: usize,
}

/// What one pantograph's passage did (one run), over the analysis section.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Passage {
    /// The contact wire's wear per bin of the section, m³ (every term).
    pub wire_m3: Vec<f64>,
    /// The contact wire's wear by term, m³: mechanical, electrical, arc.
    pub wire_terms_m3: [f64; 3],
    /// The strip's wear per lateral bin ([`Bins::strip`]), m³ (empty without lateral motion).
    pub strip_m3: Vec<f64>,
    /// The strip's wear by term, m³.
    pub strip_terms_m3: [f64; 3],
    /// The arcs.
    pub arcs: Vec<ArcEvent>,
    /// Time with an arc, s.
    pub arc_time_s: f64,
    /// Time with the contact lost, s.
    pub loss_time_s: f64,
    /// Time in the section, s.
    pub section_time_s: f64,
    /// The Joule heat in the contact resistance, J.
    pub joule_j: f64,
}

/// The bins a passage is counted in: along the section, and across the head.
#[derive(Debug, Clone, PartialEq)]
pub struct Bins {
    /// The analysis section, m.
    pub section_m: [f64; 2],
    /// The bin along the line, m.
    pub bin_m: f64,
    /// The head's half-width, m (the strip's bins span it).
    pub half_width_m: f64,
    /// Bins across the head.
    pub strip: usize,
}

impl Bins {
    fn along(&self) -> usize {
        (((self.section_m[1] - self.section_m[0]) / self.bin_m).ceil() as usize).max(1)
    }
    fn at(&self, x_m: f64) -> Option<usize> {
        (x_m >= self.section_m[0] && x_m <= self.section_m[1])
            .then(|| (((x_m - self.section_m[0]) / self.bin_m) as usize).min(self.along() - 1))
    }
    fn across(&self, y_m: f64) -> usize {
        let u = (y_m + self.half_width_m) / (2.0 * self.half_width_m);
        ((u * self.strip as f64).floor().max(0.0) as usize).min(self.strip - 1)
    }
    /// The centre of strip bin `k` from the head's centre, m.
    pub fn strip_centre_m(&self, k: usize) -> f64 {
        -self.half_width_m + (k as f64 + 0.5) * 2.0 * self.half_width_m / self.strip as f64
    }
}

/// The arc of a passage, as it burns step by step.
#[derive(Default)]
struct Burning {
    arc: Option<ArcEvent>,
    /// The contact opened and its arc went out: none strikes again before contact returns.
    out: bool,
}

/// One pantograph's passage through the section (`tr`, a run at `speed_m_s` with steps of
/// `dt_s`), counted in `bins` under `law` with the train's current: the wear of the wire along
/// the line and of the strip across the head, the arcs, NQ's times, the Joule heat.
pub fn passage(
    tr: &PantographTrace,
    dt_s: f64,
    speed_m_s: f64,
    train: &Train,
    law: &WearLaw,
    bins: &Bins,
    realisation: usize,
) -> Passage {
    let lateral = !tr.lateral_m.is_empty();
    let mut p = Passage {
        wire_m3: vec![0.0; bins.along()],
        strip_m3: if lateral {
            vec![0.0; bins.strip]
        } else {
            Vec::new()
        },
        ..Passage::default()
    };
    let mut burning = Burning::default();
    for k in 0..tr.position_m.len() {
        let x = tr.position_m[k];
        let Some(b) = bins.at(x) else {
            finish_arc(&mut p, &mut burning);
            continue;
        };
        let (f, i) = (tr.force_n[k], current_at(train, x));
        let gap = tr.gap_m.get(k).copied().unwrap_or(0.0);
        let s = lateral.then(|| bins.across(tr.lateral_m[k]));
        p.section_time_s += dt_s;
        let (wire, strip) = if f > 0.0 {
            finish_arc(&mut p, &mut burning);
            burning.out = false;
            p.joule_j += i
                * i
                * contact_resistance_ohm(
                    law.resistivity_sum_ohm_m.value,
                    law.contact_hardness_pa.value,
                    f,
                )
                * dt_s;
            let slide = speed_m_s * dt_s;
            let m = [
                archard_volume_m3(
                    law.wire_archard_k.value,
                    law.wire_hardness_pa.value,
                    f,
                    slide,
                ),
                archard_volume_m3(
                    law.strip_archard_k.value,
                    law.strip_hardness_pa.value,
                    f,
                    slide,
                ),
            ];
            let e = [
                electrical_volume_m3(law.wire_electrical_m3_per_c.value, i, dt_s),
                electrical_volume_m3(law.strip_electrical_m3_per_c.value, i, dt_s),
            ];
            p.wire_terms_m3[0] += m[0];
            p.wire_terms_m3[1] += e[0];
            p.strip_terms_m3[0] += m[1];
            p.strip_terms_m3[1] += e[1];
            (m[0] + e[0], m[1] + e[1])
        } else {
            p.loss_time_s += dt_s;
            let burns = !burning.out
                && i.abs() > 0.0
                && gap <= extinction_gap_m(law.arc_gap_m_per_a.value, i);
            if !burns {
                burning.out = burning.arc.is_some() || burning.out || i.abs() > 0.0;
                finish_arc(&mut p, &mut burning);
                continue;
            }
            let energy = law.arc_voltage_v.value * i.abs() * dt_s;
            let arc = burning.arc.get_or_insert(ArcEvent {
                start_m: x,
                duration_s: 0.0,
                energy_j: 0.0,
                realisation,
            });
            arc.duration_s += dt_s;
            arc.energy_j += energy;
            p.arc_time_s += dt_s;
            let a = [
                arc_volume_m3(law.wire_arc_m3_per_j.value, energy),
                arc_volume_m3(law.strip_arc_m3_per_j.value, energy),
            ];
            p.wire_terms_m3[2] += a[0];
            p.strip_terms_m3[2] += a[1];
            (a[0], a[1])
        };
        p.wire_m3[b] += wire;
        if let Some(s) = s {
            p.strip_m3[s] += strip;
        }
    }
    finish_arc(&mut p, &mut burning);
    p
}

fn finish_arc(p: &mut Passage, burning: &mut Burning) {
    if let Some(a) = burning.arc.take() {
        p.arcs.push(a);
    }
}

/// The lateral sweep over one span.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct SpanSweep {
    /// The span's start, m.
    pub start_m: f64,
    /// Its end, m.
    pub end_m: f64,
    /// The contact point's net lateral travel across it over the time to pass it, m/s.
    pub speed_m_s: f64,
}

/// The contact point's lateral sweep per span of the section (`supports_m`, track order): its
/// net travel across the head from the span's first sample to its last, over the time between
/// them (vibration about the path does not count as sweep). Spans not wholly inside the section
/// are left out.
pub fn sweep(
    tr: &PantographTrace,
    dt_s: f64,
    supports_m: &[f64],
    section_m: [f64; 2],
) -> Vec<SpanSweep> {
    let mut out = Vec::new();
    if tr.lateral_m.is_empty() {
        return out;
    }
    for w in supports_m.windows(2) {
        let (a, b) = (w[0], w[1]);
        if a < section_m[0] || b > section_m[1] {
            continue;
        }
        let first = tr.position_m.iter().position(|&x| x >= a);
        let last = tr.position_m.iter().rposition(|&x| x <= b);
        if let (Some(i), Some(j)) = (first, last) {
            if j > i {
                let speed = (tr.lateral_m[j] - tr.lateral_m[i]).abs() / ((j - i) as f64 * dt_s);
                out.push(SpanSweep {
                    start_m: a,
                    end_m: b,
                    speed_m_s: speed,
                });
            }
        }
    }
    out
}

/// The lateral sweep of a train (its leading pantograph) and its figure of merit.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct SweepOutput {
    /// Per span.
    pub spans: Vec<SpanSweep>,
    /// The share of the spans' length swept slower than the limit, %: the stagger layout's
    /// figure of merit for this train (0 is best).
    pub share_below_limit_percent: f64,
    /// The slowest span's speed, m/s.
    pub least_m_s: f64,
}

/// A strip's wear across the head.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct StripOutput {
    /// The bins' centres from the head's centre, m.
    pub lateral_m: Vec<f64>,
    /// The strip's wear depth per 1000 km of this train's service, by bin, mm.
    pub depth_mm_per_1000_km: Vec<f64>,
    /// Where it wears most, m.
    pub worst_lateral_m: f64,
    /// Its life in this train's service, km (the allowance over the deepest bin's rate; none
    /// when it does not wear).
    pub life_km: Option<f64>,
}

/// One pantograph of a train, per passage (the mean over the realisations).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct PantographWear {
    /// Its name.
    pub name: String,
    /// NQ: the share of time in the section with an arc, %.
    pub nq_percent: f64,
    /// The share of time with the contact lost, %.
    pub loss_percent: f64,
    /// Arcs per passage.
    pub arcs_per_passage: f64,
    /// Arc energy per passage, J.
    pub arc_energy_j: f64,
    /// Joule heat in the contact per passage, J.
    pub joule_j: f64,
    /// The contact wire's wear per passage by term (mechanical, electrical, arc), mm³.
    pub wire_terms_mm3: [f64; 3],
    /// The strip's wear per passage by term, mm³.
    pub strip_terms_mm3: [f64; 3],
    /// The strip across the head (`None` when the case models no lateral motion).
    pub strip: Option<StripOutput>,
    /// Every arc of every realisation.
    pub arc_events: Vec<ArcEvent>,
}

/// One train of the mix.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct TrainWear {
    /// Its name.
    pub name: String,
    /// Speed, km/h.
    pub speed_kmh: f64,
    /// Current per pantograph (its constant, or its profile's mean over the section), A.
    pub current_a: f64,
    /// Passages a day.
    pub passages_per_day: f64,
    /// Its pantographs.
    pub pantographs: Vec<PantographWear>,
    /// Its leading pantograph's sweep (`None` without lateral motion).
    pub sweep: Option<SweepOutput>,
    /// The error-level events of its runs (`realisation k: message`), and whether the spec
    /// accepted them.
    pub errors: Vec<String>,
    /// Whether every one of them is accepted by the spec.
    pub errors_allowed: bool,
}

/// The contact wire's life under the mix.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct WireLife {
    /// The bins' centres along the line, m.
    pub position_m: Vec<f64>,
    /// Wear a day, mm³ per m of wire.
    pub daily_mm3_per_m: Vec<f64>,
    /// The section lost after the years counted, mm².
    pub area_loss_mm2: Vec<f64>,
    /// The depth worn after the years counted, mm.
    pub depth_mm: Vec<f64>,
    /// The wire's section, mm².
    pub section_mm2: f64,
    /// The section that may be lost, mm².
    pub limit_mm2: f64,
    /// Years until the first bin reaches the limit (none without wear).
    pub years_to_limit: Option<f64>,
    /// That bin's centre, m.
    pub worst_position_m: f64,
    /// The spans that wear first, fastest first (at most 3).
    pub worst_spans: Vec<SpanLife>,
}

/// A span's contact wire under the mix.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct SpanLife {
    /// The span's start, m.
    pub start_m: f64,
    /// Its end, m.
    pub end_m: f64,
    /// Years until its most worn bin reaches the limit (none without wear).
    pub years_to_limit: Option<f64>,
}

/// A law coefficient or limit as used, with its source.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Provenance {
    /// Its field.
    pub field: String,
    /// Its value (SI, the field's unit).
    pub value: f64,
    /// Its source.
    pub source: String,
}

/// What a current-collection study gives (`wear.json`; `pcsim schema wear`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct WearOutput {
    /// The case's name.
    pub case_name: String,
    /// The analysis section, m.
    pub section_m: [f64; 2],
    /// Years counted.
    pub years: f64,
    /// Realisations per train.
    pub realisations: usize,
    /// The seed offsets of the realisations (added to every seed of the case's random inputs,
    /// which case.toml gives).
    pub seed_offsets: Vec<u64>,
    /// Whether the case models lateral motion (the strips' wear and the sweep need it).
    pub lateral: bool,
    /// Per train.
    pub trains: Vec<TrainWear>,
    /// The contact wire's life.
    pub wire: WireLife,
    /// Every coefficient and limit used, with its source.
    pub provenance: Vec<Provenance>,
}

impl WearSpec {
    /// Parse a spec: every error names its field.
    pub fn from_toml_str(text: &str) -> Result<WearSpec, CaseError> {
        let de = toml::Deserializer::new(text);
        serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            CaseError::Parse(format!("wear spec, at `{path}`: {}", e.inner().message()))
        })
    }

    /// Every coefficient and limit by its field.
    pub fn sourced(&self) -> Vec<(String, &Sourced)> {
        let l = &self.law;
        let m = &self.limits;
        let mut v: Vec<(String, &Sourced)> = vec![
            ("years".into(), &self.years),
            ("bin_m".into(), &self.bin_m),
            ("law.wire_archard_k".into(), &l.wire_archard_k),
            ("law.wire_hardness_pa".into(), &l.wire_hardness_pa),
            ("law.strip_archard_k".into(), &l.strip_archard_k),
            ("law.strip_hardness_pa".into(), &l.strip_hardness_pa),
            (
                "law.wire_electrical_m3_per_c".into(),
                &l.wire_electrical_m3_per_c,
            ),
            (
                "law.strip_electrical_m3_per_c".into(),
                &l.strip_electrical_m3_per_c,
            ),
            ("law.wire_arc_m3_per_j".into(), &l.wire_arc_m3_per_j),
            ("law.strip_arc_m3_per_j".into(), &l.strip_arc_m3_per_j),
            ("law.resistivity_sum_ohm_m".into(), &l.resistivity_sum_ohm_m),
            ("law.contact_hardness_pa".into(), &l.contact_hardness_pa),
            ("law.arc_voltage_v".into(), &l.arc_voltage_v),
            ("law.arc_gap_m_per_a".into(), &l.arc_gap_m_per_a),
            (
                "limits.wire_area_loss_percent".into(),
                &m.wire_area_loss_percent,
            ),
            (
                "limits.strip_wear_allowance_m".into(),
                &m.strip_wear_allowance_m,
            ),
            ("limits.strip_width_m".into(), &m.strip_width_m),
            ("limits.sweep_min_m_s".into(), &m.sweep_min_m_s),
        ];
        for (k, t) in self.trains.iter().enumerate() {
            v.push((format!("trains[{k}].speed_kmh"), &t.speed_kmh));
            v.push((format!("trains[{k}].current_a"), &t.current_a));
            v.push((format!("trains[{k}].passages_per_day"), &t.passages_per_day));
        }
        v
    }

    /// Refuse what the study cannot honour, by its field.
    pub fn check(&self, case: &Case) -> Result<(), CaseError> {
        if self.kind != "wear" {
            return Err(inv("kind", &self.kind, "a wear spec's kind is \"wear\""));
        }
        for (field, s) in self.sourced() {
            if !s.value.is_finite() || s.value < 0.0 {
                return Err(inv(&field, s.value, "must be a finite number ≥ 0"));
            }
            if s.source.trim().is_empty() {
                return Err(inv(&field, s.value, "give its source, or `guess: why`"));
            }
        }
        let positive = [
            ("years", self.years.value),
            ("bin_m", self.bin_m.value),
            ("law.wire_hardness_pa", self.law.wire_hardness_pa.value),
            ("law.strip_hardness_pa", self.law.strip_hardness_pa.value),
            (
                "law.contact_hardness_pa",
                self.law.contact_hardness_pa.value,
            ),
            (
                "limits.wire_area_loss_percent",
                self.limits.wire_area_loss_percent.value,
            ),
            (
                "limits.strip_wear_allowance_m",
                self.limits.strip_wear_allowance_m.value,
            ),
            ("limits.strip_width_m", self.limits.strip_width_m.value),
        ];
        for (field, v) in positive {
            if v <= 0.0 {
                return Err(inv(field, v, "must be > 0"));
            }
        }
        if self.limits.wire_area_loss_percent.value >= 100.0 {
            return Err(inv(
                "limits.wire_area_loss_percent",
                self.limits.wire_area_loss_percent.value,
                "a loss of section below 100 %",
            ));
        }
        let [x0, x1] = case.run.analysis_m;
        if (x1 - x0) / self.bin_m.value > MAX_BINS as f64 {
            return Err(inv(
                "bin_m",
                self.bin_m.value,
                &format!(
                    "the {:.0} m section in bins this short makes more than {MAX_BINS}",
                    x1 - x0
                ),
            ));
        }
        if self.trains.is_empty() {
            return Err(inv("trains", "[]", "give at least one train"));
        }
        for (k, t) in self.trains.iter().enumerate() {
            if t.speed_kmh.value <= 0.0 {
                return Err(inv(
                    &format!("trains[{k}].speed_kmh"),
                    t.speed_kmh.value,
                    "must be > 0",
                ));
            }
            let sorted = t.current_profile.windows(2).all(|w| w[1][0] > w[0][0]);
            let finite = t.current_profile.iter().flatten().all(|v| v.is_finite());
            if !sorted || !finite {
                return Err(inv(
                    &format!("trains[{k}].current_profile"),
                    format!("{:?}", t.current_profile),
                    "finite [position_m, current_a] points in increasing position",
                ));
            }
        }
        if self.realisations != 1 {
            if let Err(why) = crate::analysis::sweep::check_seeds(Some(self.realisations), case) {
                return Err(inv("realisations", self.realisations, &why));
            }
        }
        let runs = self.trains.len() * self.realisations;
        if runs > MAX_RUNS {
            return Err(inv(
                "realisations",
                self.realisations,
                &format!("{runs} runs (trains × realisations): at most {MAX_RUNS}"),
            ));
        }
        crate::compile::require_contact(case, "the current-collection study")
    }
}

/// The contact wire's section, m²: its diameter's circle, else its mass over copper's density.
fn wire_section_m2(case: &Case) -> f64 {
    let w = &case.catenary.contact_wire;
    match &w.section {
        Some(s) => std::f64::consts::PI * s.diameter_m * s.diameter_m / 4.0,
        None => w.mass_per_m_kg / COPPER_DENSITY_KG_M3,
    }
}

/// One train's run in one realisation: its output and the line's supports.
struct TrainRun {
    out: RunOutput,
    supports_m: Vec<f64>,
}

/// Train number `t` of the spec in realisation `k`: a speed the case refuses is named as the
/// train's (`trains[t].speed_kmh`).
fn run_train(case: &Case, train: &Train, t: usize, k: usize) -> Result<TrainRun, SimError> {
    let c = with_overrides(
        &case.with_seed_offset(k as u64),
        &[(
            "run.speed_kmh".into(),
            OverrideValue::Number(train.speed_kmh.value),
        )],
    )
    .map_err(|e| match e {
        CaseError::Invalid { value, reason, .. } => CaseError::Invalid {
            field: format!("trains[{t}].speed_kmh"),
            value,
            reason,
        },
        e => e,
    })?;
    let setup = Setup::from_case(&c)?;
    let supports_m = setup.model.supports_m.clone();
    let out = simulate(&setup, &mut |_| true)?;
    Ok(TrainRun { out, supports_m })
}

impl WearStudy {
    fn bins(&self, half_width_m: f64) -> Bins {
        Bins {
            section_m: self.case.run.analysis_m,
            bin_m: self.spec.bin_m.value,
            half_width_m,
            strip: 60,
        }
    }

    /// A train's realisations reduced to its pantographs' means per passage.
    fn train_wear(
        &self,
        train: &Train,
        runs: &[TrainRun],
    ) -> Result<(TrainWear, Vec<f64>), SimError> {
        let n = runs.len() as f64;
        let first = &runs[0].out;
        let mut wire = vec![0.0; self.bins(1.0).along()];
        let mut pantographs = Vec::new();
        let dead: Vec<[f64; 2]> = (self.case.neutral_section.iter())
            .map(|n| [n.start_m, n.end_m])
            .collect();
        let train = &without_current_over(train, &dead);
        for (p, tr0) in first.pantographs.iter().enumerate() {
            let hw = tr0.head_half_width_m.unwrap_or(0.8);
            let bins = self.bins(hw);
            let mut acc = Passage::default();
            let mut events = Vec::new();
            for (k, r) in runs.iter().enumerate() {
                let tr = &r.out.pantographs[p];
                if tr.stats.is_none() {
                    return Err(SimError::Case(inv(
                        "case.run.analysis_m",
                        format!("{:?}", self.case.run.analysis_m),
                        &format!("pantograph {} did not cross the analysis section", tr.name),
                    )));
                }
                let ps = passage(
                    tr,
                    r.out.dt_s,
                    r.out.speed_m_s,
                    train,
                    &self.spec.law,
                    &bins,
                    k,
                );
                add_passage(&mut acc, &ps);
                events.extend(ps.arcs);
            }
            for (w, a) in wire.iter_mut().zip(&acc.wire_m3) {
                *w += a / n;
            }
            pantographs.push(self.pantograph_wear(tr0, &acc, events, n, &bins));
        }
        let allowed = crate::analysis::events::AllowedErrors {
            dewirement: self.spec.allow_dewirement,
            contact_loss: self.spec.allow_contact_loss,
        };
        let mut errors = Vec::new();
        let mut errors_allowed = true;
        for (k, r) in runs.iter().enumerate() {
            let es = crate::analysis::events::run_errors(&r.out);
            errors_allowed &= allowed.first_refused(&es).is_none();
            errors.extend(es.iter().map(|e| format!("realisation {k}: {}", e.message)));
        }
        let sweep = first.pantographs.first().and_then(|tr| {
            let spans = sweep(
                tr,
                first.dt_s,
                &runs[0].supports_m,
                self.case.run.analysis_m,
            );
            sweep_output(spans, self.spec.limits.sweep_min_m_s.value)
        });
        let [a, b] = self.case.run.analysis_m;
        let current = if train.current_profile.is_empty() {
            train.current_a.value
        } else {
            let m = 200;
            (0..m).fold(0.0, |c, j| {
                c + current_at(train, a + (b - a) * (j as f64 + 0.5) / m as f64)
            }) / m as f64
        };
        Ok((
            TrainWear {
                name: train.name.clone(),
                speed_kmh: train.speed_kmh.value,
                current_a: current,
                passages_per_day: train.passages_per_day.value,
                pantographs,
                sweep,
                errors,
                errors_allowed,
            },
            wire,
        ))
    }

    fn pantograph_wear(
        &self,
        tr: &PantographTrace,
        acc: &Passage,
        arc_events: Vec<ArcEvent>,
        n: f64,
        bins: &Bins,
    ) -> PantographWear {
        let pct = |t: f64| {
            if acc.section_time_s > 0.0 {
                100.0 * t / acc.section_time_s
            } else {
                0.0
            }
        };
        let strip = (!acc.strip_m3.is_empty()).then(|| {
            let km = (bins.section_m[1] - bins.section_m[0]) / 1e3;
            let area = (2.0 * bins.half_width_m / bins.strip as f64)
                * self.spec.limits.strip_width_m.value;
            let depth: Vec<f64> = acc
                .strip_m3
                .iter()
                .map(|v| v / n / area / km * 1e3 * 1e3)
                .collect();
            let (worst, &deepest) = depth
                .iter()
                .enumerate()
                .max_by(|a, b| a.1.total_cmp(b.1))
                .unwrap_or((0, &0.0));
            StripOutput {
                lateral_m: (0..bins.strip).map(|k| bins.strip_centre_m(k)).collect(),
                depth_mm_per_1000_km: depth.clone(),
                worst_lateral_m: bins.strip_centre_m(worst),
                life_km: (deepest > 0.0)
                    .then(|| self.spec.limits.strip_wear_allowance_m.value * 1e3 / deepest * 1e3),
            }
        });
        PantographWear {
            name: tr.name.clone(),
            nq_percent: pct(acc.arc_time_s),
            loss_percent: pct(acc.loss_time_s),
            arcs_per_passage: arc_events.len() as f64 / n,
            arc_energy_j: arc_events.iter().fold(0.0, |e, a| e + a.energy_j) / n,
            joule_j: acc.joule_j / n,
            wire_terms_mm3: acc.wire_terms_m3.map(|v| v / n * 1e9),
            strip_terms_mm3: acc.strip_terms_m3.map(|v| v / n * 1e9),
            strip,
            arc_events,
        }
    }

    /// The contact wire's life under the mix: the daily wear per bin (`daily_m3` per bin), the
    /// section lost and the depth after the years counted, the years to the limit.
    fn wire_life(&self, daily_m3: &[f64], supports_m: &[f64]) -> WireLife {
        let bin = self.spec.bin_m.value;
        let a0 = self.case.run.analysis_m[0];
        let section = wire_section_m2(&self.case);
        let limit = section * self.spec.limits.wire_area_loss_percent.value / 100.0;
        let radius = (section / std::f64::consts::PI).sqrt();
        let years = self.spec.years.value;
        let per_m: Vec<f64> = daily_m3.iter().map(|v| v / bin).collect();
        let area: Vec<f64> = per_m.iter().map(|d| d * 365.25 * years).collect();
        let to_limit = |d: f64| (d > 0.0).then(|| limit / (d * 365.25));
        let (worst, &most) = per_m
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .unwrap_or((0, &0.0));
        let centre = |k: usize| a0 + (k as f64 + 0.5) * bin;
        let mut spans: Vec<SpanLife> = supports_m
            .windows(2)
            .filter_map(|w| {
                let m = (0..per_m.len())
                    .filter(|&k| centre(k) >= w[0] && centre(k) < w[1])
                    .map(|k| per_m[k])
                    .fold(f64::NEG_INFINITY, f64::max);
                (m > f64::NEG_INFINITY).then(|| SpanLife {
                    start_m: w[0],
                    end_m: w[1],
                    years_to_limit: to_limit(m),
                })
            })
            .collect();
        let key = |s: &SpanLife| s.years_to_limit.unwrap_or(f64::INFINITY);
        spans.sort_by(|a, b| key(a).total_cmp(&key(b)));
        spans.truncate(3);
        WireLife {
            position_m: (0..per_m.len()).map(centre).collect(),
            daily_mm3_per_m: per_m.iter().map(|d| d * 1e9).collect(),
            area_loss_mm2: area.iter().map(|a| a * 1e6).collect(),
            depth_mm: area
                .iter()
                .map(|&a| worn_depth_m(a, radius) * 1e3)
                .collect(),
            section_mm2: section * 1e6,
            limit_mm2: limit * 1e6,
            years_to_limit: to_limit(most),
            worst_position_m: centre(worst),
            worst_spans: spans,
        }
    }
}

fn add_passage(acc: &mut Passage, p: &Passage) {
    let add = |a: &mut Vec<f64>, b: &[f64]| {
        if a.is_empty() {
            a.resize(b.len(), 0.0);
        }
        for (x, y) in a.iter_mut().zip(b) {
            *x += y;
        }
    };
    add(&mut acc.wire_m3, &p.wire_m3);
    add(&mut acc.strip_m3, &p.strip_m3);
    for k in 0..3 {
        acc.wire_terms_m3[k] += p.wire_terms_m3[k];
        acc.strip_terms_m3[k] += p.strip_terms_m3[k];
    }
    acc.arc_time_s += p.arc_time_s;
    acc.loss_time_s += p.loss_time_s;
    acc.section_time_s += p.section_time_s;
    acc.joule_j += p.joule_j;
}

/// The sweep's figure of merit: the share of the spans' length slower than `limit_m_s`.
pub fn sweep_output(spans: Vec<SpanSweep>, limit_m_s: f64) -> Option<SweepOutput> {
    if spans.is_empty() {
        return None;
    }
    // Folds from +0 (an empty float sum is −0).
    let total = spans.iter().fold(0.0, |t, s| t + s.end_m - s.start_m);
    let slow = (spans.iter().filter(|s| s.speed_m_s < limit_m_s))
        .fold(0.0, |t, s| t + s.end_m - s.start_m);
    let least = spans
        .iter()
        .map(|s| s.speed_m_s)
        .fold(f64::INFINITY, f64::min);
    Some(SweepOutput {
        spans,
        share_below_limit_percent: 100.0 * slow / total,
        least_m_s: least,
    })
}

/// Build the study from a spec's text, its case through the front end's loader (a row of
/// [`crate::study::SPEC_STUDIES`]).
pub fn build(
    text: &str,
    load: &CaseLoader<'_>,
) -> Result<Box<dyn crate::study::AnyStudy>, CaseError> {
    let spec = WearSpec::from_toml_str(text)?;
    let (case, _) = load(&spec.case).map_err(|e| match e {
        CaseError::UnknownPreset(_) => inv(
            "case",
            &spec.case,
            "neither a case file beside the spec nor a preset (see `pcsim presets`)",
        ),
        e => e,
    })?;
    Ok(Box::new(WearStudy { spec, case }))
}

/// The JSON Schema of a spec file.
pub fn spec_schema() -> serde_json::Value {
    schemars::schema_for!(WearSpec).to_value()
}

/// The JSON Schema of `wear.json`.
pub fn output_schema() -> serde_json::Value {
    schemars::schema_for!(WearOutput).to_value()
}

impl Study for WearStudy {
    const KIND: StudyKind = StudyKind::Wear;
    type Output = WearOutput;

    fn check(&self) -> Result<(), CaseError> {
        self.spec.check(&self.case)
    }

    fn work(&self) -> usize {
        self.spec.trains.len() * self.spec.realisations
    }

    fn case_label(&self) -> Option<CaseLabel> {
        Some((
            crate::analysis::report::case_name(&self.case),
            self.case.run.speed_kmh,
            self.case.run.analysis_m,
        ))
    }

    fn run(&self, done: &(dyn Fn() + Sync)) -> Result<WearOutput, SimError> {
        let r = self.spec.realisations;
        let jobs: Vec<(usize, usize)> = (0..self.spec.trains.len())
            .flat_map(|t| (0..r).map(move |k| (t, k)))
            .collect();
        let runs: Vec<TrainRun> = parallel_map(&jobs, None, |&(t, k)| {
            let run = run_train(&self.case, &self.spec.trains[t], t, k);
            done();
            run
        })
        .into_iter()
        .collect::<Result<_, _>>()?;
        let mut trains = Vec::new();
        let mut daily = vec![0.0; self.bins(1.0).along()];
        for (t, train) in self.spec.trains.iter().enumerate() {
            let (tw, wire) = self.train_wear(train, &runs[t * r..(t + 1) * r])?;
            for (d, w) in daily.iter_mut().zip(&wire) {
                *d += w * train.passages_per_day.value;
            }
            trains.push(tw);
        }
        let lateral = runs[0]
            .out
            .pantographs
            .iter()
            .any(|p| !p.lateral_m.is_empty());
        Ok(WearOutput {
            case_name: crate::analysis::report::case_name(&self.case),
            section_m: self.case.run.analysis_m,
            years: self.spec.years.value,
            realisations: r,
            seed_offsets: (0..r as u64).collect(),
            lateral,
            trains,
            wire: self.wire_life(&daily, &runs[0].supports_m),
            provenance: (self.spec.sourced().into_iter())
                .map(|(field, s)| Provenance {
                    field,
                    value: s.value,
                    source: s.source.clone(),
                })
                .collect(),
        })
    }

    fn files(&self, o: &WearOutput) -> Vec<StudyFile> {
        vec![
            StudyFile::text("wear.csv", wear_csv(o)),
            StudyFile::text("arcing.csv", arcing_csv(o)),
            StudyFile::text("strips.csv", strips_csv(o)),
            StudyFile::text("sweep.csv", sweep_csv(o)),
            StudyFile::text(
                "wear.json",
                serde_json::to_string_pretty(o).unwrap_or_default() + "\n",
            ),
        ]
    }

    fn answer(o: &WearOutput) -> Answer {
        answer(o)
    }

    fn figures(&self, o: &WearOutput) -> Vec<Figure> {
        figures(o, self.spec.limits.sweep_min_m_s.value)
    }
}

fn wear_csv(o: &WearOutput) -> String {
    let w = &o.wire;
    let mut s = String::from("position_m,daily_mm3_per_m,area_loss_mm2,depth_mm\n");
    for k in 0..w.position_m.len() {
        let _ = writeln!(
            s,
            "{:.3},{:.6e},{:.6e},{:.6e}",
            w.position_m[k], w.daily_mm3_per_m[k], w.area_loss_mm2[k], w.depth_mm[k]
        );
    }
    s
}

fn arcing_csv(o: &WearOutput) -> String {
    let mut s = String::from("train,pantograph,realisation,start_m,duration_ms,energy_j\n");
    for t in &o.trains {
        for p in &t.pantographs {
            for a in &p.arc_events {
                let _ = writeln!(
                    s,
                    "{},{},{},{:.3},{:.3},{:.4}",
                    t.name,
                    p.name,
                    a.realisation,
                    a.start_m,
                    a.duration_s * 1e3,
                    a.energy_j
                );
            }
        }
    }
    s
}

fn strips_csv(o: &WearOutput) -> String {
    let mut s = String::from("train,pantograph,lateral_m,depth_mm_per_1000_km\n");
    for t in &o.trains {
        for p in &t.pantographs {
            if let Some(st) = &p.strip {
                for (y, d) in st.lateral_m.iter().zip(&st.depth_mm_per_1000_km) {
                    let _ = writeln!(s, "{},{},{:.4},{:.6e}", t.name, p.name, y, d);
                }
            }
        }
    }
    s
}

fn sweep_csv(o: &WearOutput) -> String {
    let mut s = String::from("train,span_start_m,span_end_m,sweep_m_s\n");
    for t in &o.trains {
        for sp in t.sweep.iter().flat_map(|s| &s.spans) {
            let _ = writeln!(
                s,
                "{},{:.3},{:.3},{:.5}",
                t.name, sp.start_m, sp.end_m, sp.speed_m_s
            );
        }
    }
    s
}

fn years(y: Option<f64>) -> String {
    match y {
        Some(y) => format!("{y:.1} years"),
        None => "never (no wear)".into(),
    }
}

fn km(l: Option<f64>) -> String {
    match l {
        Some(l) => format!("{l:.0} km"),
        None => "unbounded (no wear)".into(),
    }
}

/// The headline: where and when the wire reaches its limit, the worst NQ, the shortest strip
/// life.
fn headline(o: &WearOutput) -> String {
    let w = &o.wire;
    let worst_nq = (o.trains.iter())
        .flat_map(|t| t.pantographs.iter().map(move |p| (t, p)))
        .max_by(|a, b| a.1.nq_percent.total_cmp(&b.1.nq_percent));
    let strip_life = (o.trains.iter())
        .flat_map(|t| {
            t.pantographs
                .iter()
                .filter_map(move |p| p.strip.as_ref().map(|s| (t, p, s)))
        })
        .min_by(|a, b| {
            let l = |s: &StripOutput| s.life_km.unwrap_or(f64::INFINITY);
            l(a.2).total_cmp(&l(b.2))
        });
    let span = w
        .worst_spans
        .first()
        .map(|s| format!(" (span {:.0}–{:.0} m)", s.start_m, s.end_m))
        .unwrap_or_default();
    let mut headline = format!(
        "{}: the contact wire reaches its wear limit ({:.0} % of {:.0} mm²) first at {:.0} m{span} after {}",
        o.case_name,
        100.0 * w.limit_mm2 / w.section_mm2,
        w.section_mm2,
        w.worst_position_m,
        years(w.years_to_limit)
    );
    if worst_nq.is_some_and(|(_, p)| p.nq_percent == 0.0) {
        headline.push_str("; no arc (NQ 0 % for every train)");
    } else if let Some((t, p)) = worst_nq {
        let _ = write!(
            headline,
            "; the worst NQ is {:.3} % ({}, {})",
            p.nq_percent, t.name, p.name
        );
    }
    if let Some((t, p, s)) = strip_life {
        let _ = write!(
            headline,
            "; the shortest strip life {} ({}, {})",
            km(s.life_km),
            t.name,
            p.name
        );
    }
    headline
}

/// The answer's rows: the wire's depth and life, the spans that wear first, each train's
/// pantographs and sweep.
fn rows(o: &WearOutput) -> Vec<(String, String)> {
    let w = &o.wire;
    let mut rows = vec![
        (
            format!("wire depth after {} years [mm]", o.years),
            format!(
                "{:.3} (largest)",
                w.depth_mm.iter().fold(0.0f64, |a, &b| a.max(b))
            ),
        ),
        ("years to the wire's limit".into(), years(w.years_to_limit)),
        (
            "NQ's limit".into(),
            "no limit held: EN 50367 and the TSI set one, whose clause pcsim cannot cite from its reference data".into(),
        ),
    ];
    for s in &w.worst_spans {
        rows.push((
            format!("span {:.0}–{:.0} m", s.start_m, s.end_m),
            years(s.years_to_limit),
        ));
    }
    for t in &o.trains {
        for p in &t.pantographs {
            let mut v = format!(
                "NQ {:.3} %, {:.1} arcs/passage, {:.1} J; loss {:.3} %; wire {:.2}/{:.2}/{:.2} mm³ (mech/elec/arc)",
                p.nq_percent, p.arcs_per_passage, p.arc_energy_j, p.loss_percent,
                p.wire_terms_mm3[0], p.wire_terms_mm3[1], p.wire_terms_mm3[2]
            );
            if let Some(s) = &p.strip {
                let _ = write!(
                    v,
                    "; strip life {} (worst at {:+.2} m)",
                    km(s.life_km),
                    s.worst_lateral_m
                );
            }
            rows.push((
                format!("{} at {:.0} km/h, {}", t.name, t.speed_kmh, p.name),
                v,
            ));
        }
        if let Some(s) = &t.sweep {
            rows.push((
                format!("{} sweep below limit [%]", t.name),
                format!(
                    "{:.1} (slowest span {:.3} m/s)",
                    s.share_below_limit_percent, s.least_m_s
                ),
            ));
        }
    }
    rows
}

/// The events and the limits of the answer: `(warnings, failures)`.
fn notes(o: &WearOutput) -> (Vec<String>, Vec<String>) {
    let mut warnings = Vec::new();
    let mut failures = Vec::new();
    for t in &o.trains {
        for e in &t.errors {
            let line = format!("{} at {:.0} km/h, {e}", t.name, t.speed_kmh);
            if t.errors_allowed {
                warnings.push(line);
            } else {
                failures
                    .push(line + " (the spec's allow_contact_loss / allow_dewirement accept it)");
            }
        }
    }
    if !o.lateral {
        warnings.push("the case models no lateral motion: the strips' wear across the head and the lateral sweep need the contact point's path (catenary.lateral), so they are not given".into());
    }
    let guesses = o
        .provenance
        .iter()
        .filter(|p| p.source.starts_with("guess"))
        .count();
    if guesses > 0 {
        warnings.push(format!(
            "{guesses} of the {} coefficients and limits are guesses (wear.json's provenance): the life is as good as they are",
            o.provenance.len()
        ));
    }
    (warnings, failures)
}

fn answer(o: &WearOutput) -> Answer {
    let (warnings, failures) = notes(o);
    Answer {
        headline: headline(o),
        rows: rows(o),
        warnings,
        failures,
    }
}

fn figures(o: &WearOutput, limit_m_s: f64) -> Vec<Figure> {
    let w = &o.wire;
    let mut out = vec![Figure {
        name: "wear_profile".into(),
        title: format!(
            "{}: the contact wire's wear after {} years",
            o.case_name, o.years
        ),
        x_label: "position along the line [m]".into(),
        y_label: "depth worn [mm]".into(),
        series: vec![FigureSeries {
            label: "depth".into(),
            x: w.position_m.clone(),
            y: w.depth_mm.clone(),
            dots: false,
        }],
        log_y: false,
    }];
    let strips: Vec<FigureSeries> = (o.trains.iter())
        .flat_map(|t| {
            t.pantographs.iter().filter_map(move |p| {
                p.strip.as_ref().map(|s| FigureSeries {
                    label: format!("{}, {}", t.name, p.name),
                    x: s.lateral_m.clone(),
                    y: s.depth_mm_per_1000_km.clone(),
                    dots: false,
                })
            })
        })
        .collect();
    if !strips.is_empty() {
        out.push(Figure {
            name: "strip_wear".into(),
            title: format!("{}: strip wear across the head", o.case_name),
            x_label: "across the head from its centre [m]".into(),
            y_label: "depth per 1000 km [mm]".into(),
            series: strips,
            log_y: false,
        });
    }
    let mut sweeps: Vec<FigureSeries> = (o.trains.iter())
        .filter_map(|t| {
            t.sweep.as_ref().map(|s| FigureSeries {
                label: format!("{} at {:.0} km/h", t.name, t.speed_kmh),
                x: s.spans
                    .iter()
                    .map(|sp| 0.5 * (sp.start_m + sp.end_m))
                    .collect(),
                y: s.spans.iter().map(|sp| sp.speed_m_s).collect(),
                dots: true,
            })
        })
        .collect();
    if !sweeps.is_empty() {
        sweeps.push(FigureSeries {
            label: format!("limit {limit_m_s} m/s"),
            x: o.section_m.to_vec(),
            y: vec![limit_m_s; 2],
            dots: false,
        });
        out.push(Figure {
            name: "sweep_speed".into(),
            title: format!(
                "{}: the contact point's lateral sweep per span",
                o.case_name
            ),
            x_label: "span centre [m]".into(),
            y_label: "sweep speed [m/s]".into(),
            series: sweeps,
            log_y: false,
        });
    }
    out
}
