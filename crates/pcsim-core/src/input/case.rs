//! Case files: the TOML description of a catenary, its pantographs and a run.
//!
//! Every numeric field may be written plainly (`tension_n = 20000.0`) or with its provenance
//! (`tension_n = { value = 20000.0, source = "README §3.1 (c1)" }`). Presets use the second form on
//! every field. Unknown keys are errors. [`Case::from_toml_str`] parses (no file I/O: the caller
//! reads the file), and [`Case::validate`] checks values and names the offending field.

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

use crate::error::CaseError;
pub use crate::error::Warning;
pub use crate::input::bounds::{self, check_bound, inv, num, Bound};
pub use crate::input::irregularity::{IrregularityCase, PsdTable};
pub use crate::input::lateral::{
    AeroCase, Dof, IceCase, LateralCase, SectionCase, Spectrum, WindCase, WindProfile,
};
pub use crate::input::line::{LineCase, OverlapCase, SpanRun, TensionLengthCase};
pub use crate::model::statics::{Presag, PresagZero, G};
pub use crate::model::wire::Damping;

/// Provenance of each sourced field: dotted path → source text.
pub type Provenance = BTreeMap<String, String>;

/// Top-level case.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Case {
    #[serde(default)]
    /// Name and description.
    pub meta: Meta,
    /// The catenary (with `[line]`: what every tension length shares).
    pub catenary: CatenaryCase,
    /// A line of spans that need not repeat (`input::line`); without it the catenary is one
    /// tension length of `catenary.spans` equal spans.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub line: Option<LineCase>,
    /// The pantographs, leading first.
    pub pantographs: Vec<PantographCase>,
    #[serde(default)]
    /// The pantograph–wire contact.
    pub contact: ContactCase,
    /// The run.
    pub run: RunCase,
    /// Crosswind (needs `lateral` in `run.dofs`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wind: Option<WindCase>,
    /// Contact-wire irregularity: sources that add up.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub irregularity: Vec<IrregularityCase>,
    /// The dropper wire's S–N curve, for Miner's damage (`pcsim run --dropper-forces`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dropper_fatigue: Option<DropperFatigueCase>,
    /// Section insulators in the contact wire (issue 55, `input::hard_spots`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub section_insulator: Vec<crate::input::hard_spots::SectionInsulatorCase>,
    /// Neutral sections: dead lengths between section insulators.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub neutral_section: Vec<crate::input::hard_spots::NeutralSectionCase>,
}

/// The dropper wire's fatigue: a Basquin S–N curve in stress range,
/// `N(Δσ) = sn_cycles (sn_stress_range_mpa / Δσ)^sn_slope`, and the cross-section that turns a
/// tension range into a stress range (`analysis::fatigue`). pcsim has no default: each value
/// needs its source (a test of the dropper wire, its maker's data).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DropperFatigueCase {
    /// The dropper wire's load-bearing cross-section, mm².
    pub area_mm2: f64,
    /// The S–N curve's slope `m`.
    pub sn_slope: f64,
    /// The reference stress range, MPa.
    pub sn_stress_range_mpa: f64,
    /// Cycles to failure at the reference stress range.
    pub sn_cycles: f64,
}

/// Free-text description of a case.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Meta {
    #[serde(default)]
    /// Name of the case (shown in outputs).
    pub name: String,
    #[serde(default)]
    /// What the case is, in a sentence or two.
    pub description: String,
}

/// The catenary: geometry, wires, point elements and damping.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CatenaryCase {
    /// Number of spans in the model (the model length is `spans × span_m`). With `[line]`:
    /// omitted, or the line's number of spans (it is set from the line when omitted).
    #[serde(default)]
    pub spans: usize,
    /// Span length, m. With `[line]`: the span of the reference dropper layout.
    pub span_m: f64,
    /// Height of the messenger above the contact wire at the supports.
    pub encumbrance_m: f64,
    /// Pre-sag of the contact wire.
    pub presag: Presag,
    /// Damping of the wires' modes.
    pub damping: Damping,
    /// The contact wire.
    pub contact_wire: WireCase,
    /// The messenger wire.
    pub messenger: WireCase,
    /// The droppers.
    pub droppers: DropperCase,
    /// The messenger supports.
    pub messenger_support: SupportCase,
    /// The steady arms.
    pub steady_arm: ArmCase,
    /// Stitch wires at every support (stitched catenaries), or none.
    #[serde(default)]
    pub stitch_wire: Option<StitchCase>,
    /// Stagger and lateral registration (needed when `lateral` is modelled).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lateral: Option<LateralCase>,
    /// Radial ice on the wires.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ice: Option<IceCase>,
}

/// A stitch wire at each support, modelled as the paper does (§2.1): spring-damping elements on
/// the messenger at the stitch droppers, from which those droppers hang.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StitchCase {
    /// Length of the stitch wire, centred on the support.
    pub length_m: f64,
    /// Tension of the stitch wire, N.
    pub tension_n: f64,
    /// Mass per length of the stitch wire, kg/m.
    pub mass_per_m_kg: f64,
    /// Mass of each stitch-dropper clamp on the stitch wire.
    pub clamp_mass_kg: f64,
    /// Indices (into `droppers.positions_m`) of the droppers that hang from stitch wires.
    pub droppers: Vec<usize>,
    /// Damping of each stitch element; by default the messenger support's damping ratio c/k is
    /// applied to the stitch stiffness.
    #[serde(default)]
    pub damping_ns_per_m: Option<f64>,
}

/// One wire's properties.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WireCase {
    /// Mass per length, kg/m.
    pub mass_per_m_kg: f64,
    /// Tension, N.
    pub tension_n: f64,
    /// Bending stiffness EI, N·m².
    pub ei_nm2: f64,
    /// Diameter, lateral and torsional data and aerodynamic coefficients (lateral and torsional
    /// motion, wind, ice).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub section: Option<SectionCase>,
}

/// Droppers: positions within a span (same in every span) and properties.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DropperCase {
    /// Positions from the span's start, m.
    pub positions_m: Vec<f64>,
    /// Stiffness in tension (zero in compression; Eq. 15). Give this or `ea_n`.
    #[serde(default)]
    pub stiffness_n_per_m: Option<f64>,
    /// Axial stiffness EA; each dropper then has `k = EA / length` with its static length.
    #[serde(default)]
    pub ea_n: Option<f64>,
    /// Mass of the clamp on the messenger, kg.
    pub clamp_mass_messenger_kg: f64,
    /// Mass of the clamp on the contact wire, kg.
    pub clamp_mass_contact_kg: f64,
    #[serde(default)]
    /// Dropper mass per length, kg/m (shared by its two ends).
    pub mass_per_m_kg: f64,
}

/// Messenger support: a spring-damper to ground at each mast.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SupportCase {
    /// Vertical stiffness, N/m.
    pub stiffness_n_per_m: f64,
    #[serde(default)]
    /// Vertical damping, N·s/m.
    pub damping_ns_per_m: f64,
}

/// Steady (registration) arm: a lumped mass with a vertical spring at each mast.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ArmCase {
    /// Mass, kg.
    pub mass_kg: f64,
    /// Vertical stiffness, N/m.
    pub stiffness_n_per_m: f64,
    /// Whether the arm holds the contact wire at its design height at the support and carries
    /// the static force there (simple catenaries). When false (stitched catenaries) the contact
    /// wire hangs from the droppers only and the arm carries no static load.
    #[serde(default = "yes")]
    pub static_support: bool,
}

fn yes() -> bool {
    true
}

/// A pantograph, or a constant moving force (for analytic moving-load checks).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum PantographCase {
    /// N lumped masses, head first (Eq. 16). Spring/damper `i` joins mass `i` to mass `i+1`; the
    /// last joins the lowest mass to the roof.
    Lumped {
        #[serde(default)]
        /// Name (shown in outputs).
        name: String,
        /// Distance behind the leading pantograph, m (0 for the leading one).
        #[serde(default)]
        offset_m: f64,
        /// Masses, head first, kg.
        masses_kg: Vec<f64>,
        /// Springs, one per mass, N/m.
        stiffness_n_per_m: Vec<f64>,
        /// Dampers, one per mass, N·s/m.
        damping_ns_per_m: Vec<f64>,
        /// Net static uplift on the lowest mass (gravity included), N.
        uplift_n: f64,
        /// The static uplift as a function of the head's working height (issue 43, item 2): a
        /// frame's static force changes with the height it works at, so a lowered contact wire
        /// (structures, overlaps) changes it. Its value at height 0 is `uplift_n`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        uplift_by_height: Option<UpliftByHeight>,
        /// Aerodynamic force on the head, `Σ c_i v^i` with `v` in km/h, N. Deviation from Eq. 17
        /// (`F = 0.0097 V²`, no unit for V, 478 N at 222 km/h): a configurable polynomial whose
        /// coefficients each preset states with their source (README §2.1).
        #[serde(default)]
        aero_coeffs_kmh: Vec<f64>,
        /// Half the length of the head (contact strip and horns), m: the wire beyond it has left
        /// the head.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        head_half_width_m: Option<f64>,
        /// Half the working range of the strip, m.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        working_half_width_m: Option<f64>,
        /// Collector strips on the head (issue 43, item 1): each a mass on its own spring and
        /// damper to the head, whose mass (`masses_kg[0]`) is then the head's frame, with its
        /// own contact point along the track. None: the head mass carries the contact.
        #[serde(default, skip_serializing_if = "Vec::is_empty")]
        strips: Vec<StripCase>,
    },
    /// A constant upward force moving along the contact wire.
    MovingForce {
        #[serde(default)]
        /// Name (shown in outputs).
        name: String,
        #[serde(default)]
        /// Distance behind the leading pantograph, m.
        offset_m: f64,
        /// Upward force, N.
        force_n: f64,
        /// Lateral force on the contact wire (positive along the model's lateral axis), N: a
        /// probe of the lateral motion, applied where it is modelled (issue 20).
        #[serde(default)]
        lateral_force_n: f64,
    },
}

/// A lumped pantograph's static uplift at each working height of its head (linear between the
/// points, constant beyond the ends).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct UpliftByHeight {
    /// Heights of the head, m, increasing: from the contact wire's height at the supports
    /// (the model's zero), upward positive.
    pub height_m: Vec<f64>,
    /// The static uplift at each, N (gravity included, as `uplift_n`).
    pub uplift_n: Vec<f64>,
}

/// A collector strip of a lumped pantograph (`[[pantographs.strips]]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StripCase {
    /// The strip's mass, kg.
    pub mass_kg: f64,
    /// Its suspension's stiffness to the head's frame, N/m.
    pub stiffness_n_per_m: f64,
    /// Its suspension's damping, N·s/m.
    pub damping_ns_per_m: f64,
    /// Where its contact point is along the track, ahead of the pantograph's position, m.
    pub along_m: f64,
    /// Its running face's height above the other strips' at rest, m (negative: lower, as a
    /// strip worn more than its neighbour).
    #[serde(default)]
    pub height_offset_m: f64,
    /// The penalty stiffness of its contact, N/m (default: `[contact] stiffness_n_per_m`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_stiffness_n_per_m: Option<f64>,
}

impl PantographCase {
    /// The name as given (may be empty).
    pub fn name(&self) -> &str {
        match self {
            PantographCase::Lumped { name, .. } | PantographCase::MovingForce { name, .. } => name,
        }
    }

    /// The name the outputs use for pantograph `i` (its CSV columns, figures): its own, or
    /// `p{i}` without one.
    pub fn output_name(&self, i: usize) -> String {
        if self.name().is_empty() {
            format!("p{i}")
        } else {
            self.name().to_string()
        }
    }

    /// Distance behind the leading pantograph.
    pub fn offset_m(&self) -> f64 {
        match self {
            PantographCase::Lumped { offset_m, .. }
            | PantographCase::MovingForce { offset_m, .. } => *offset_m,
        }
    }
}

/// Pantograph–wire contact (Eq. 19).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ContactCase {
    /// Penalty stiffness of the contact (Eq. 19), N/m.
    pub stiffness_n_per_m: f64,
}

impl Default for ContactCase {
    fn default() -> Self {
        Self {
            stiffness_n_per_m: 50_000.0,
        }
    }
}

/// The run: speed, where the pantographs go, the analysis section and the discretisation.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RunCase {
    /// Train speed, km/h.
    pub speed_kmh: f64,
    /// Position of the leading pantograph at t = 0.
    pub start_m: f64,
    /// The run ends when the rearmost pantograph reaches this position.
    pub end_m: f64,
    /// Statistics are taken while a pantograph is inside `[start, end]`.
    pub analysis_m: [f64; 2],
    /// Modes per wire; give this or `modes_per_m`.
    #[serde(default)]
    pub modes: Option<usize>,
    #[serde(default)]
    /// Modes per metre of wire (the number of modes scales with the model's length).
    pub modes_per_m: Option<f64>,
    /// Time step, s.
    pub dt_s: f64,
    /// The directions modelled for every wire (Eqs. 5–8): `["vertical"]` (default),
    /// `["vertical", "lateral"]` or all three.
    #[serde(
        default = "crate::input::lateral::vertical_only",
        skip_serializing_if = "crate::input::lateral::is_vertical_only"
    )]
    pub dofs: Vec<Dof>,
    /// Let the analysis section begin less than one span after the leading pantograph's start
    /// (its start transient then enters the statistics): a warning instead of an error.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub allow_start_transient: bool,
    /// A tiny seeded perturbation of every lumped pantograph's uplift, relative (0: none): the
    /// uplift is multiplied by `1 + perturb_uplift_rel · (2u − 1)`, `u` uniform from
    /// `perturb_seed`. With `--seeds N` each realisation draws its own `u` (the seed offset by
    /// the realisation), so the spread of the statistics puts an error bar on the quantities that
    /// hang on a threshold (the actual maximum and minimum when droppers go slack; issue 20).
    #[serde(default, skip_serializing_if = "is_zero")]
    pub perturb_uplift_rel: f64,
    /// The seed of the perturbation (see `perturb_uplift_rel`).
    #[serde(default, skip_serializing_if = "is_zero_u64")]
    pub perturb_seed: u64,
    /// The pantograph the real-time window follows (the rig's): `"leading"` (the default),
    /// `"trailing"` (the last), a pantograph's name or its index. The window, the window
    /// studies and the full run they are compared with carry that pantograph alone
    /// (`compile::window_case`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub window_pantograph: Option<String>,
}

fn is_zero(x: &f64) -> bool {
    *x == 0.0
}

fn is_zero_u64(x: &u64) -> bool {
    *x == 0
}

impl RunCase {
    /// The factor on every lumped pantograph's uplift (1 without a perturbation): `1 + rel ·
    /// (2u − 1)` with `u` uniform in [0, 1) from `perturb_seed` (splitmix64).
    pub fn uplift_factor(&self) -> f64 {
        if self.perturb_uplift_rel == 0.0 {
            return 1.0;
        }
        let mut z = self.perturb_seed.wrapping_add(0x9E37_79B9_7F4A_7C15);
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^= z >> 31;
        let u = (z >> 11) as f64 / (1u64 << 53) as f64;
        1.0 + self.perturb_uplift_rel * (2.0 * u - 1.0)
    }
}

/// The field of `pantographs[i]` (named by `path`) whose value has the wrong type: each field of
/// the pantograph's table is read alone as its variant's type (`None` when all read, or the path
/// is not a pantograph's).
fn pantograph_field_at_fault(pantographs: &toml::Value, path: &str) -> Option<String> {
    let i: usize = path
        .strip_prefix("pantographs[")?
        .strip_suffix(']')?
        .parse()
        .ok()?;
    let table = pantographs.as_array()?.get(i)?.as_table()?;
    fn reads<T: serde::de::DeserializeOwned>(v: &toml::Value) -> bool {
        v.clone().try_into::<T>().is_ok()
    }
    for (key, v) in table {
        let ok = match key.as_str() {
            "kind" | "name" => reads::<String>(v),
            "masses_kg" | "stiffness_n_per_m" | "damping_ns_per_m" | "aero_coeffs_kmh" => {
                reads::<Vec<f64>>(v)
            }
            "offset_m" | "uplift_n" | "force_n" | "head_half_width_m" | "working_half_width_m" => {
                reads::<f64>(v)
            }
            _ => true,
        };
        if !ok {
            return Some(key.clone());
        }
    }
    None
}

impl Case {
    /// Parse a case from TOML text. Sourced fields (`{ value, source }`) are unwrapped and their
    /// sources returned; unknown keys are errors that name the key.
    pub fn from_toml_str(text: &str) -> Result<(Case, Provenance), CaseError> {
        Self::from_toml_str_with_ranges(text).map(|(c, p, _)| (c, p))
    }

    /// [`Case::from_toml_str`], with the ranges the case gives its values
    /// (`{ value, source, range = [low, high], range_source }`, issue 42: the model uncertainty
    /// that `pcsim run --sensitivity` varies). A range's form is checked here (two finite
    /// numbers, low below high), so every loader refuses a bad one by its field, and so is each
    /// end: the case must pass its checks with the value at either end
    /// ([`crate::input::overrides::check_range_ends`]); a value edited out of its range loads,
    /// and the sensitivity study refuses it ([`RangedValue::check`]).
    pub fn from_toml_str_with_ranges(
        text: &str,
    ) -> Result<(Case, Provenance, Vec<RangedValue>), CaseError> {
        let mut value: toml::Value =
            toml::from_str(text).map_err(|e| CaseError::Parse(parse_message(text, &e)))?;
        let mut prov = Provenance::new();
        let mut ranges = Vec::new();
        strip_sources(&mut value, String::new(), &mut prov, &mut ranges)?;
        let pantographs = value.get("pantographs").cloned();
        let case: Case = serde_path_to_error::deserialize(value).map_err(|e| {
            let mut path = e.path().to_string();
            // toml's own location ("in `pantographs`") follows on later lines: the path says it.
            let inner = e.into_inner().to_string();
            let first = inner.lines().next().unwrap_or_default();
            // A tagged pantograph is read whole, so serde's path stops at `pantographs[i]`: for a
            // value of the wrong type, find the field itself.
            if first.starts_with("invalid ") {
                if let Some(field) = pantographs
                    .as_ref()
                    .and_then(|p| pantograph_field_at_fault(p, &path))
                {
                    path = format!("{path}.{field}");
                }
            }
            CaseError::Parse(format!("at `{path}`: {first}"))
        })?;
        let mut case = case;
        if let Some(line) = &case.line {
            // `catenary.spans` is the line's, when omitted.
            let n = line.n_spans();
            match case.catenary.spans {
                0 => case.catenary.spans = n,
                k if k != n => {
                    return Err(inv(
                        "catenary.spans",
                        k,
                        &format!(
                            "the line has {n} spans: omit catenary.spans with [line], or give {n}"
                        ),
                    ))
                }
                _ => {}
            }
        }
        crate::input::overrides::check_range_ends(&case, &ranges)?;
        Ok((case, prov, ranges))
    }

    /// The case as TOML (plain values).
    pub fn to_toml_string(&self) -> String {
        toml::to_string_pretty(self).unwrap_or_default()
    }

    /// Model length, m.
    pub fn length_m(&self) -> f64 {
        match &self.line {
            Some(l) => l.length_m(),
            None => self.catenary.spans as f64 * self.catenary.span_m,
        }
    }

    /// The case of realisation `k` of a Monte Carlo study: every seed (irregularity, wind,
    /// perturbation) offset by `k`.
    pub fn with_seed_offset(&self, k: u64) -> Case {
        let mut c = self.clone();
        for ir in &mut c.irregularity {
            *ir = ir.with_seed_offset(k);
        }
        if let Some(w) = c.wind.as_mut() {
            w.seed = w.seed.wrapping_add(k);
        }
        c.run.perturb_seed = c.run.perturb_seed.wrapping_add(k);
        c
    }

    /// Whether the case has a seeded random input (a Monte Carlo study varies it).
    pub fn is_random(&self) -> bool {
        self.run.perturb_uplift_rel != 0.0
            || self.irregularity.iter().any(|i| i.seed().is_some())
            || self
                .wind
                .as_ref()
                .is_some_and(|w| w.turbulence_intensity > 0.0)
    }

    /// Train speed in m/s.
    pub fn speed_m_s(&self) -> f64 {
        self.run.speed_kmh / 3.6
    }

    /// Modes per wire after resolving `modes` / `modes_per_m`.
    pub fn n_modes(&self) -> usize {
        match (self.run.modes, self.run.modes_per_m) {
            (Some(n), _) => n,
            (None, Some(d)) => (d * self.length_m()).round().max(1.0) as usize,
            (None, None) => 0,
        }
    }
}

/// A TOML error as one line: where, what, and the line it is on. TOML's own message can be empty
/// (a key with `=` and no value): then say what is missing.
fn parse_message(text: &str, e: &toml::de::Error) -> String {
    let msg = e.message().trim().replace('\n', "; ");
    let msg = if msg.is_empty() {
        "a value is missing or incomplete here (e.g. `key =` with nothing after it)".to_string()
    } else {
        msg
    };
    match e.span() {
        Some(sp) => {
            let start = sp.start.min(text.len());
            let line_no = text[..start].matches('\n').count() + 1;
            let line_start = text[..start].rfind('\n').map_or(0, |i| i + 1);
            let col = text[line_start..start].chars().count() + 1;
            let line = text[line_start..].lines().next().unwrap_or("").trim_end();
            format!("TOML error at line {line_no}, column {col}: {msg}: `{line}`")
        }
        None => format!("TOML error: {msg}"),
    }
}

/// Replace every `{ value = …, source = "…" }` table by its value, recording the source (and
/// the value's range, when it gives one).
fn strip_sources(
    v: &mut toml::Value,
    path: String,
    prov: &mut Provenance,
    ranges: &mut Vec<RangedValue>,
) -> Result<(), CaseError> {
    match v {
        toml::Value::Table(t) => {
            // `{ value = …, source = "…" }`, or `{ value = … }` alone (a value without its source
            // yet; `note` may accompany either, `range` and `range_source` give its range).
            // No field of a case is named `value`: a table with one is a sourced value, and a
            // key beside it that a sourced value does not have is misspelt (`sorce`).
            let is_sourced = t.contains_key("value");
            if let Some(k) = t.keys().find(|k| {
                is_sourced
                    && !matches!(
                        k.as_str(),
                        "value" | "source" | "note" | "range" | "range_source"
                    )
            }) {
                return Err(inv(
                    &format!("{path}.{k}"),
                    "an unknown key",
                    "a sourced value has the keys value, source, note, range and range_source",
                ));
            }
            if is_sourced {
                ranges.extend(ranged_values(&path, t)?);
                match t.get("source") {
                    Some(toml::Value::String(s)) => {
                        prov.insert(path.clone(), s.clone());
                    }
                    Some(_) => {
                        return Err(inv(
                            &format!("{path}.source"),
                            "non-string",
                            "source must be a string",
                        ))
                    }
                    None => {}
                }
                let inner = t.remove("value").expect("checked");
                *v = inner;
                return Ok(());
            }
            for (k, x) in t.iter_mut() {
                let p = if path.is_empty() {
                    k.clone()
                } else {
                    format!("{path}.{k}")
                };
                strip_sources(x, p, prov, ranges)?;
            }
            Ok(())
        }
        toml::Value::Array(a) => {
            for (i, x) in a.iter_mut().enumerate() {
                strip_sources(x, format!("{path}[{i}]"), prov, ranges)?;
            }
            Ok(())
        }
        _ => Ok(()),
    }
}

/// A value of the case with the range it may take (issue 42, item 2): where it is, the value,
/// the range's ends, the value's source and the range's reason. A list's range is given per
/// element (`range = [[low, high], …]`) and gives one ranged value per element (`path[i]`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct RangedValue {
    /// The value's path in the case (`catenary.steady_arm.mass_kg`, `pantographs[0].masses_kg[1]`),
    /// in the field's unit.
    pub path: String,
    /// The case's value.
    pub value: f64,
    /// The range's low end.
    pub low: f64,
    /// The range's high end.
    pub high: f64,
    /// The value's source (`guess: …` when it has none).
    pub source: Option<String>,
    /// Why the range is what it is (`range_source`).
    pub range_source: Option<String>,
    /// The field holds a whole number (`catenary.spans`): its ends are whole and a study draws
    /// whole numbers.
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub integer: bool,
}

impl RangedValue {
    /// Refuse a value outside its own range (edited since the range was given), by its field.
    pub fn check(&self) -> Result<(), CaseError> {
        if (self.low..=self.high).contains(&self.value) {
            Ok(())
        } else {
            Err(inv(
                &format!("{}.range", self.path),
                format!("[{}, {}]", self.low, self.high),
                &format!(
                    "the value {} is outside its range: widen the range, or remove it",
                    self.value
                ),
            ))
        }
    }

    /// Whether the value is a guess (its source starts with `guess`, or it has none).
    pub fn is_guess(&self) -> bool {
        self.source
            .as_deref()
            .is_none_or(|s| s.trim_start().starts_with("guess"))
    }
}

/// The ranged values of one sourced table (`{ value, source, range, range_source }`) at `path`:
/// none without `range`; a number's range is `[low, high]`, a list's one `[low, high]` per element.
fn ranged_values(path: &str, t: &toml::value::Table) -> Result<Vec<RangedValue>, CaseError> {
    let Some(range) = t.get("range") else {
        if t.contains_key("range_source") {
            return Err(inv(
                &format!("{path}.range_source"),
                "given",
                "a range_source without a range: give `range = [low, high]` too",
            ));
        }
        return Ok(Vec::new());
    };
    let field = format!("{path}.range");
    let text = |k: &str| -> Result<Option<String>, CaseError> {
        match t.get(k) {
            None => Ok(None),
            Some(toml::Value::String(s)) => Ok(Some(s.clone())),
            Some(_) => Err(inv(
                &format!("{path}.{k}"),
                "non-string",
                "must be a string",
            )),
        }
    };
    let (source, range_source) = (text("source")?, text("range_source")?);
    let number = |v: &toml::Value| match v {
        toml::Value::Float(x) => Some(*x),
        toml::Value::Integer(i) => Some(*i as f64),
        _ => None,
    };
    let pair = |r: &toml::Value, at: &str| -> Result<(f64, f64), CaseError> {
        let bad = |why: &str| inv(at, r.to_string(), why);
        let a = r
            .as_array()
            .filter(|a| a.len() == 2)
            .ok_or_else(|| bad("a range is two numbers, [low, high]"))?;
        let (Some(lo), Some(hi)) = (number(&a[0]), number(&a[1])) else {
            return Err(bad("a range is two numbers, [low, high]"));
        };
        if !(lo.is_finite() && hi.is_finite() && lo < hi) {
            return Err(bad(
                "a range's ends are finite, the low one below the high one",
            ));
        }
        Ok((lo, hi))
    };
    let one =
        |p: String, v: &toml::Value, r: &toml::Value, at: &str| -> Result<RangedValue, CaseError> {
            let x = number(v)
                .ok_or_else(|| inv(&field, range.to_string(), "only numbers take a range"))?;
            let (low, high) = pair(r, at)?;
            let integer = matches!(v, toml::Value::Integer(_));
            if integer && (low.fract() != 0.0 || high.fract() != 0.0) {
                return Err(inv(
                    at,
                    r.to_string(),
                    &format!("{p} holds a whole number: its range's ends are whole numbers"),
                ));
            }
            Ok(RangedValue {
                path: p,
                value: x,
                low,
                high,
                source: source.clone(),
                range_source: range_source.clone(),
                integer,
            })
        };
    match t.get("value") {
        Some(toml::Value::Array(xs)) => {
            let rs = range
                .as_array()
                .filter(|rs| rs.len() == xs.len())
                .ok_or_else(|| {
                    inv(
                        &field,
                        range.to_string(),
                        &format!(
                            "a list's range is one [low, high] per element ({} of them)",
                            xs.len()
                        ),
                    )
                })?;
            xs.iter()
                .zip(rs)
                .enumerate()
                .map(|(i, (x, r))| one(format!("{path}[{i}]"), x, r, &format!("{field}[{i}]")))
                .collect()
        }
        Some(v) => Ok(vec![one(path.to_string(), v, range, &field)?]),
        None => Ok(Vec::new()),
    }
}

/// Every numeric leaf of a TOML case text that carries no source mark (paths), for the preset
/// provenance test.
pub fn unsourced_fields(text: &str) -> Result<Vec<String>, CaseError> {
    let v: toml::Value = toml::from_str(text).map_err(|e| CaseError::Parse(e.to_string()))?;
    let mut out = Vec::new();
    fn walk(v: &toml::Value, path: &str, out: &mut Vec<String>) {
        match v {
            toml::Value::Table(t) => {
                if t.contains_key("value") && t.contains_key("source") {
                    return;
                }
                for (k, x) in t {
                    let p = if path.is_empty() {
                        k.clone()
                    } else {
                        format!("{path}.{k}")
                    };
                    walk(x, &p, out);
                }
            }
            toml::Value::Array(a) => {
                if a.iter().all(|x| x.is_table()) {
                    for (i, x) in a.iter().enumerate() {
                        walk(x, &format!("{path}[{i}]"), out);
                    }
                } else {
                    out.push(path.to_string());
                }
            }
            toml::Value::Integer(_) | toml::Value::Float(_) | toml::Value::Boolean(_) => {
                out.push(path.to_string())
            }
            _ => {}
        }
    }
    walk(&v, "", &mut out);
    Ok(out)
}
