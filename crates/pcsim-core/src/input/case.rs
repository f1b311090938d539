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
pub use crate::input::irregularity::{IrregularityCase, PsdTable};
pub use crate::input::lateral::{
    AeroCase, Dof, IceCase, LateralCase, SectionCase, Spectrum, WindCase, WindProfile,
};
pub use crate::model::statics::{Presag, PresagZero, G};
pub use crate::model::wire::Damping;

/// Provenance of each sourced field: dotted path → source text.
pub type Provenance = BTreeMap<String, String>;

/// Top-level case.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Case {
    #[serde(default)]
    pub meta: Meta,
    pub catenary: CatenaryCase,
    pub pantographs: Vec<PantographCase>,
    #[serde(default)]
    pub contact: ContactCase,
    pub run: RunCase,
    /// Crosswind (needs `lateral` in `run.dofs`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub wind: Option<WindCase>,
    /// Contact-wire irregularity: sources that add up.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub irregularity: Vec<IrregularityCase>,
}

/// Free-text description of a case.
#[derive(Debug, Clone, Default, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct Meta {
    #[serde(default)]
    pub name: String,
    #[serde(default)]
    pub description: String,
}

/// The catenary: geometry, wires, point elements and damping.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct CatenaryCase {
    /// Number of spans in the model (the model length is `spans × span_m`).
    pub spans: usize,
    pub span_m: f64,
    /// Height of the messenger above the contact wire at the supports.
    pub encumbrance_m: f64,
    pub presag: Presag,
    pub damping: Damping,
    pub contact_wire: WireCase,
    pub messenger: WireCase,
    pub droppers: DropperCase,
    pub messenger_support: SupportCase,
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
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct StitchCase {
    /// Length of the stitch wire, centred on the support.
    pub length_m: f64,
    pub tension_n: f64,
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
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct WireCase {
    pub mass_per_m_kg: f64,
    pub tension_n: f64,
    pub ei_nm2: f64,
    /// Diameter, lateral and torsional data and aerodynamic coefficients (lateral and torsional
    /// motion, wind, ice).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub section: Option<SectionCase>,
}

/// Droppers: positions within a span (same in every span) and properties.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct DropperCase {
    pub positions_m: Vec<f64>,
    /// Stiffness in tension (zero in compression; Eq. 15). Give this or `ea_n`.
    #[serde(default)]
    pub stiffness_n_per_m: Option<f64>,
    /// Axial stiffness EA; each dropper then has `k = EA / length` with its static length.
    #[serde(default)]
    pub ea_n: Option<f64>,
    pub clamp_mass_messenger_kg: f64,
    pub clamp_mass_contact_kg: f64,
    #[serde(default)]
    pub mass_per_m_kg: f64,
}

/// Messenger support: a spring-damper to ground at each mast.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SupportCase {
    pub stiffness_n_per_m: f64,
    #[serde(default)]
    pub damping_ns_per_m: f64,
}

/// Steady (registration) arm: a lumped mass with a vertical spring at each mast.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ArmCase {
    pub mass_kg: f64,
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
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum PantographCase {
    /// N lumped masses, head first (Eq. 16). Spring/damper `i` joins mass `i` to mass `i+1`; the
    /// last joins the lowest mass to the roof.
    Lumped {
        #[serde(default)]
        name: String,
        /// Distance behind the leading pantograph, m (0 for the leading one).
        #[serde(default)]
        offset_m: f64,
        masses_kg: Vec<f64>,
        stiffness_n_per_m: Vec<f64>,
        damping_ns_per_m: Vec<f64>,
        /// Net static uplift on the lowest mass (gravity included), N.
        uplift_n: f64,
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
    },
    /// A constant upward force moving along the contact wire.
    MovingForce {
        #[serde(default)]
        name: String,
        #[serde(default)]
        offset_m: f64,
        force_n: f64,
    },
}

impl PantographCase {
    /// Distance behind the leading pantograph.
    pub fn offset_m(&self) -> f64 {
        match self {
            PantographCase::Lumped { offset_m, .. }
            | PantographCase::MovingForce { offset_m, .. } => *offset_m,
        }
    }
}

/// Pantograph–wire contact (Eq. 19).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct ContactCase {
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
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct RunCase {
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
    pub modes_per_m: Option<f64>,
    pub dt_s: f64,
    /// The directions modelled for every wire (Eqs. 5–8): `["vertical"]` (default),
    /// `["vertical", "lateral"]` or all three.
    #[serde(
        default = "crate::input::lateral::vertical_only",
        skip_serializing_if = "crate::input::lateral::is_vertical_only"
    )]
    pub dofs: Vec<Dof>,
}

impl Case {
    /// Parse a case from TOML text. Sourced fields (`{ value, source }`) are unwrapped and their
    /// sources returned; unknown keys are errors that name the key.
    pub fn from_toml_str(text: &str) -> Result<(Case, Provenance), CaseError> {
        let mut value: toml::Value =
            toml::from_str(text).map_err(|e| CaseError::Parse(parse_message(text, &e)))?;
        let mut prov = Provenance::new();
        strip_sources(&mut value, String::new(), &mut prov)?;
        let case: Case = serde_path_to_error::deserialize(value).map_err(|e| {
            let path = e.path().to_string();
            CaseError::Parse(format!("at `{}`: {}", path, e.into_inner()))
        })?;
        Ok((case, prov))
    }

    /// The case as TOML (plain values).
    pub fn to_toml_string(&self) -> String {
        toml::to_string_pretty(self).unwrap_or_default()
    }

    /// Model length, m.
    pub fn length_m(&self) -> f64 {
        self.catenary.spans as f64 * self.catenary.span_m
    }

    /// The case of realisation `k` of a Monte Carlo study: every seed (irregularity, wind)
    /// offset by `k`.
    pub fn with_seed_offset(&self, k: u64) -> Case {
        let mut c = self.clone();
        for ir in &mut c.irregularity {
            *ir = ir.with_seed_offset(k);
        }
        if let Some(w) = c.wind.as_mut() {
            w.seed = w.seed.wrapping_add(k);
        }
        c
    }

    /// Whether the case has a seeded random input (a Monte Carlo study varies it).
    pub fn is_random(&self) -> bool {
        self.irregularity.iter().any(|i| i.seed().is_some())
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

    /// Check every value; return warnings, or an error naming the field and its value.
    ///
    /// Every number has plausibility bounds: outside the hard bounds it is physically
    /// meaningless (an error), outside the soft bounds merely unusual (a warning naming the
    /// field and the typical range). See [`bounds`].
    pub fn validate(&self) -> Result<Vec<Warning>, CaseError> {
        let mut w = Vec::new();
        finite_all(self)?;
        validate::geometry_and_wires(self, &mut w)?;
        validate::droppers(self, &mut w)?;
        validate::presag(self, &mut w)?;
        validate::damping(self, &mut w)?;
        validate::supports_and_arms(self, &mut w)?;
        validate::stitch_wire(self, &mut w)?;
        validate::contact_and_pantographs(self, &mut w)?;
        validate::run(self, &mut w)?;
        crate::input::lateral::validate(self, &mut w)?;
        crate::input::irregularity::validate(self, &mut w)?;
        Ok(w)
    }
}

/// Plausibility bounds of a quantity: outside `hard` it is an error (physically meaningless),
/// outside `soft` a warning (legal but unusual). A hard lower bound of 0 excludes 0 when
/// `soft.0 > 0`.
#[derive(Debug, Clone, Copy)]
pub struct Bound {
    pub hard: (f64, f64),
    pub soft: (f64, f64),
    pub unit: &'static str,
    pub typical: &'static str,
}

/// The plausibility bounds of the case's quantities (SI units as the field names say).
pub mod bounds {
    use super::Bound;

    const fn b(
        hard: (f64, f64),
        soft: (f64, f64),
        unit: &'static str,
        typical: &'static str,
    ) -> Bound {
        Bound {
            hard,
            soft,
            unit,
            typical,
        }
    }

    pub const SPAN: Bound = b((1.0, 1000.0), (20.0, 100.0), "m", "27–70 m");
    pub const ENCUMBRANCE: Bound = b((0.05, 20.0), (0.3, 3.5), "m", "0.3–2 m");
    pub const WIRE_MASS: Bound = b((0.01, 100.0), (0.1, 5.0), "kg/m", "0.3–2 kg/m");
    pub const TENSION: Bound = b((100.0, 1.0e6), (1000.0, 60_000.0), "N", "5–40 kN");
    pub const EI: Bound = b((0.0, 1.0e6), (0.0, 5000.0), "N·m²", "10–300 N·m²");
    pub const DROPPER_STIFFNESS: Bound = b((0.0, 1.0e10), (1.0e3, 1.0e7), "N/m", "1e4–1e6 N/m");
    pub const DROPPER_EA: Bound = b((0.0, 1.0e11), (1.0e3, 1.0e8), "N", "1e5–1e7 N");
    pub const CLAMP_MASS: Bound = b((0.0, 100.0), (0.0, 5.0), "kg", "0.1–0.5 kg");
    pub const DROPPER_MASS: Bound = b((0.0, 20.0), (0.0, 2.0), "kg/m", "0.05–0.5 kg/m");
    pub const RAYLEIGH_ALPHA: Bound = b((0.0, 1.0e4), (0.0, 10.0), "1/s", "0–1 1/s");
    pub const RAYLEIGH_BETA: Bound = b((0.0, 10.0), (0.0, 0.1), "s", "0–0.02 s");
    pub const MODAL_RATIO: Bound = b((0.0, 0.999_999), (0.0, 0.2), "", "0–0.05");
    pub const SUPPORT_STIFFNESS: Bound = b((0.0, 1.0e11), (0.0, 1.0e8), "N/m", "1e2–1e6 N/m");
    pub const SUPPORT_DAMPING: Bound = b((0.0, 1.0e8), (0.0, 1.0e5), "N·s/m", "0–2000 N·s/m");
    pub const ARM_MASS: Bound = b((0.0, 1000.0), (0.0, 10.0), "kg", "0.5–3 kg");
    pub const STITCH_LENGTH: Bound = b((0.1, 1000.0), (5.0, 30.0), "m", "12–25 m");
    pub const STITCH_TENSION: Bound = b((10.0, 1.0e6), (300.0, 10_000.0), "N", "1–5 kN");
    pub const CONTACT_STIFFNESS: Bound = b((100.0, 1.0e9), (1.0e4, 5.0e5), "N/m", "5e4 N/m");
    pub const SPEED: Bound = b((0.0, 1000.0), (10.0, 400.0), "km/h", "50–350 km/h");
    pub const OFFSET: Bound = b((0.0, 1.0e5), (0.0, 500.0), "m", "0–400 m");
    pub const PANTOGRAPH_MASS: Bound = b((0.01, 1.0e4), (0.5, 100.0), "kg", "3–20 kg");
    pub const PANTOGRAPH_STIFFNESS: Bound = b((0.0, 1.0e9), (0.0, 1.0e6), "N/m", "0–2e4 N/m");
    pub const PANTOGRAPH_DAMPING: Bound = b((0.0, 1.0e7), (0.0, 1.0e4), "N·s/m", "0–200 N·s/m");
    pub const UPLIFT: Bound = b((-1.0e4, 1.0e4), (20.0, 500.0), "N", "50–150 N");
    pub const AERO: Bound = b((-1.0e4, 1.0e4), (-50.0, 300.0), "N", "0–100 N");
    pub const MOVING_FORCE: Bound = b((-1.0e5, 1.0e5), (-1000.0, 1000.0), "N", "50–300 N");
    pub const DT: Bound = b((0.0, 0.01), (1.0e-5, 2.0e-3), "s", "0.2–1 ms");
}

/// Check `v` of `field` against `b`: an error outside the hard bounds, a warning outside the
/// soft ones.
pub(crate) fn check_bound(
    w: &mut Vec<Warning>,
    field: &str,
    v: f64,
    b: &Bound,
) -> Result<(), CaseError> {
    check(w, field, v, b)
}

fn check(w: &mut Vec<Warning>, field: &str, v: f64, b: &Bound) -> Result<(), CaseError> {
    let (lo, hi) = b.hard;
    let unit = if b.unit.is_empty() {
        String::new()
    } else {
        format!(" {}", b.unit)
    };
    // A hard lower bound of 0 with a positive soft one excludes 0 itself.
    let strict_zero = lo == 0.0 && b.soft.0 > 0.0;
    let low_ok = if strict_zero { v > 0.0 } else { v >= lo };
    if !v.is_finite() || !low_ok {
        let rel = if strict_zero {
            "> 0".to_string()
        } else if lo == 0.0 {
            "≥ 0".to_string()
        } else {
            format!("≥ {}{unit}", num(lo))
        };
        return Err(inv(
            field,
            num(v),
            &format!("must be a finite number {rel}"),
        ));
    }
    if v > hi {
        return Err(inv(
            field,
            num(v),
            &format!(
                "physically meaningless above {}{unit} (typical: {})",
                num(hi),
                b.typical
            ),
        ));
    }
    if v < b.soft.0 || v > b.soft.1 {
        w.push(Warning(format!(
            "{field} = {}{unit} is unusual (typical: {}); check the value and its unit",
            num(v),
            b.typical
        )));
    }
    Ok(())
}

/// A number for a message: plain where that is short, in exponent form where it is tiny or huge.
pub fn num(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e7).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
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

pub(crate) fn inv(field: &str, value: impl std::fmt::Display, reason: &str) -> CaseError {
    CaseError::Invalid {
        field: field.to_string(),
        value: value.to_string(),
        reason: reason.to_string(),
    }
}

fn pos(field: &str, v: f64) -> Result<(), CaseError> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(inv(field, v, "must be a finite number > 0"))
    }
}

/// Reject NaN and infinities anywhere in the case, naming the field.
fn finite_all(case: &Case) -> Result<(), CaseError> {
    let v = toml::Value::try_from(case).map_err(|e| CaseError::Parse(e.to_string()))?;
    fn walk(v: &toml::Value, path: &str) -> Result<(), CaseError> {
        match v {
            toml::Value::Float(f) if !f.is_finite() => Err(inv(path, f, "must be finite")),
            toml::Value::Table(t) => {
                for (k, x) in t {
                    let p = if path.is_empty() {
                        k.clone()
                    } else {
                        format!("{path}.{k}")
                    };
                    walk(x, &p)?;
                }
                Ok(())
            }
            toml::Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    walk(x, &format!("{path}[{i}]"))?;
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }
    walk(&v, "")
}

/// Replace every `{ value = …, source = "…" }` table by its value, recording the source.
fn strip_sources(
    v: &mut toml::Value,
    path: String,
    prov: &mut Provenance,
) -> Result<(), CaseError> {
    match v {
        toml::Value::Table(t) => {
            // `{ value = …, source = "…" }`, or `{ value = … }` alone (a value without its source
            // yet; `note` may accompany either).
            let is_sourced = t.contains_key("value")
                && t.keys()
                    .all(|k| k == "value" || k == "source" || k == "note");
            if is_sourced {
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
                strip_sources(x, p, prov)?;
            }
            Ok(())
        }
        toml::Value::Array(a) => {
            for (i, x) in a.iter_mut().enumerate() {
                strip_sources(x, format!("{path}[{i}]"), prov)?;
            }
            Ok(())
        }
        _ => Ok(()),
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

/// The sections of [`Case::validate`], in the order they are checked (the first error found is the
/// one reported, as the hardening tests pin).
mod validate {
    use super::*;

    /// The number and length of spans, the system height and the wires.
    pub(super) fn geometry_and_wires(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
        let c = &case.catenary;
        if c.spans < 2 {
            return Err(inv("catenary.spans", c.spans, "need at least 2 spans"));
        }
        if c.spans > 5000 {
            return Err(inv(
                "catenary.spans",
                c.spans,
                "more than 5000 spans (300 km at 60 m) is not a catenary model this tool can run",
            ));
        }
        if c.spans > 200 {
            w.push(Warning(format!(
                "catenary.spans = {}: unusually many spans (typical: 10–60); the run's cost grows with the length",
                c.spans
            )));
        }
        check(w, "catenary.span_m", c.span_m, &bounds::SPAN)?;
        check(
            w,
            "catenary.encumbrance_m",
            c.encumbrance_m,
            &bounds::ENCUMBRANCE,
        )?;
        for (name, wire) in [
            ("contact_wire", &c.contact_wire),
            ("messenger", &c.messenger),
        ] {
            let f = |k: &str| format!("catenary.{name}.{k}");
            check(
                w,
                &f("mass_per_m_kg"),
                wire.mass_per_m_kg,
                &bounds::WIRE_MASS,
            )?;
            check(w, &f("tension_n"), wire.tension_n, &bounds::TENSION)?;
            check(w, &f("ei_nm2"), wire.ei_nm2, &bounds::EI)?;
        }
        Ok(())
    }

    /// The droppers: positions within the span, stiffness, clamp masses.
    pub(super) fn droppers(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
        let c = &case.catenary;
        let d = &c.droppers;
        if d.positions_m.is_empty() {
            return Err(inv(
                "catenary.droppers.positions_m",
                "[]",
                "need at least one dropper per span",
            ));
        }
        let mut prev = 0.0;
        for (i, &x) in d.positions_m.iter().enumerate() {
            if x <= 0.0 || x >= c.span_m {
                return Err(inv(
                    &format!("catenary.droppers.positions_m[{i}]"),
                    x,
                    &format!("dropper lies outside its span (0, {}) m", c.span_m),
                ));
            }
            if x <= prev && i > 0 {
                return Err(inv(
                    &format!("catenary.droppers.positions_m[{i}]"),
                    x,
                    "positions must increase",
                ));
            }
            prev = x;
        }
        match (d.stiffness_n_per_m, d.ea_n) {
            (Some(k), None) => check(
                w,
                "catenary.droppers.stiffness_n_per_m",
                k,
                &bounds::DROPPER_STIFFNESS,
            )?,
            (None, Some(ea)) => check(w, "catenary.droppers.ea_n", ea, &bounds::DROPPER_EA)?,
            _ => {
                return Err(inv(
                    "catenary.droppers.stiffness_n_per_m",
                    "both or neither of stiffness_n_per_m and ea_n",
                    "give exactly one of them",
                ))
            }
        }
        check(
            w,
            "catenary.droppers.clamp_mass_messenger_kg",
            d.clamp_mass_messenger_kg,
            &bounds::CLAMP_MASS,
        )?;
        check(
            w,
            "catenary.droppers.clamp_mass_contact_kg",
            d.clamp_mass_contact_kg,
            &bounds::CLAMP_MASS,
        )?;
        check(
            w,
            "catenary.droppers.mass_per_m_kg",
            d.mass_per_m_kg,
            &bounds::DROPPER_MASS,
        )?;
        Ok(())
    }

    /// The contact wire's pre-sag.
    pub(super) fn presag(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
        let c = &case.catenary;
        let d = &c.droppers;
        // Pre-sag: beyond span/100 (0.6 m on 60 m) no pantograph follows the wire; typical
        // designs stay below span/500.
        let presag_bound = Bound {
            hard: (-c.span_m / 100.0, c.span_m / 100.0),
            soft: (0.0, c.span_m / 500.0),
            unit: "m",
            typical: "0 to span/500 (downward positive)",
        };
        match &c.presag {
            Presag::Parabolic { mid_span_m, .. } => {
                check(w, "catenary.presag.mid_span_m", *mid_span_m, &presag_bound)?;
            }
            Presag::Table { values_m } => {
                if values_m.len() != d.positions_m.len() {
                    return Err(inv(
                        "catenary.presag.values_m",
                        format!("{} values", values_m.len()),
                        &format!("need one value per dropper ({})", d.positions_m.len()),
                    ));
                }
                for (i, v) in values_m.iter().enumerate() {
                    check(
                        w,
                        &format!("catenary.presag.values_m[{i}]"),
                        *v,
                        &presag_bound,
                    )?;
                }
            }
        }
        Ok(())
    }

    /// The wires' damping law.
    pub(super) fn damping(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
        let c = &case.catenary;
        match &c.damping {
            Damping::Rayleigh { alpha, beta } => {
                check(w, "catenary.damping.alpha", *alpha, &bounds::RAYLEIGH_ALPHA)?;
                check(w, "catenary.damping.beta", *beta, &bounds::RAYLEIGH_BETA)?;
            }
            Damping::Modal { ratio } => {
                check(w, "catenary.damping.ratio", *ratio, &bounds::MODAL_RATIO)?;
            }
        }
        Ok(())
    }

    /// Messenger supports and steady arms.
    pub(super) fn supports_and_arms(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
        let c = &case.catenary;
        check(
            w,
            "catenary.messenger_support.stiffness_n_per_m",
            c.messenger_support.stiffness_n_per_m,
            &bounds::SUPPORT_STIFFNESS,
        )?;
        check(
            w,
            "catenary.messenger_support.damping_ns_per_m",
            c.messenger_support.damping_ns_per_m,
            &bounds::SUPPORT_DAMPING,
        )?;
        check(
            w,
            "catenary.steady_arm.mass_kg",
            c.steady_arm.mass_kg,
            &bounds::ARM_MASS,
        )?;
        check(
            w,
            "catenary.steady_arm.stiffness_n_per_m",
            c.steady_arm.stiffness_n_per_m,
            &bounds::SUPPORT_STIFFNESS,
        )?;
        Ok(())
    }

    /// The stitch wire, where there is one.
    pub(super) fn stitch_wire(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
        let c = &case.catenary;
        let d = &c.droppers;
        if let Some(st) = &c.stitch_wire {
            check(
                w,
                "catenary.stitch_wire.length_m",
                st.length_m,
                &bounds::STITCH_LENGTH,
            )?;
            check(
                w,
                "catenary.stitch_wire.tension_n",
                st.tension_n,
                &bounds::STITCH_TENSION,
            )?;
            check(
                w,
                "catenary.stitch_wire.mass_per_m_kg",
                st.mass_per_m_kg,
                &bounds::DROPPER_MASS,
            )?;
            check(
                w,
                "catenary.stitch_wire.clamp_mass_kg",
                st.clamp_mass_kg,
                &bounds::CLAMP_MASS,
            )?;
            if let Some(cs) = st.damping_ns_per_m {
                check(
                    w,
                    "catenary.stitch_wire.damping_ns_per_m",
                    cs,
                    &bounds::SUPPORT_DAMPING,
                )?;
            }
            if st.length_m >= c.span_m {
                return Err(inv(
                    "catenary.stitch_wire.length_m",
                    st.length_m,
                    "must be shorter than the span",
                ));
            }
            if st.droppers.is_empty() {
                return Err(inv(
                    "catenary.stitch_wire.droppers",
                    "[]",
                    "name the droppers that hang from the stitch wire",
                ));
            }
            for (j, &i) in st.droppers.iter().enumerate() {
                let field = format!("catenary.stitch_wire.droppers[{j}]");
                let Some(&x) = d.positions_m.get(i) else {
                    return Err(inv(
                        &field,
                        i,
                        &format!("no such dropper (there are {})", d.positions_m.len()),
                    ));
                };
                let to_support = x.min(c.span_m - x);
                if to_support >= 0.5 * st.length_m - 1e-9 {
                    return Err(inv(
                        &field,
                        i,
                        &format!("dropper at {x} m is not under a stitch wire (±{} m around the support)", 0.5 * st.length_m),
                    ));
                }
            }
            if c.steady_arm.static_support {
                w.push(Warning(
                    "stitched catenary with catenary.steady_arm.static_support = true: the arm, not the stitch droppers, holds the contact wire at the support".into(),
                ));
            }
        }
        Ok(())
    }

    /// The contact stiffness and the pantographs.
    pub(super) fn contact_and_pantographs(
        case: &Case,
        w: &mut Vec<Warning>,
    ) -> Result<(), CaseError> {
        check(
            w,
            "contact.stiffness_n_per_m",
            case.contact.stiffness_n_per_m,
            &bounds::CONTACT_STIFFNESS,
        )?;

        let r = &case.run;
        check(w, "run.speed_kmh", r.speed_kmh, &bounds::SPEED)?;
        // The speed is checked against the wave speed of the built model (one definition, with the
        // clamps smeared in): see `solve::Plan::check`.
        if case.pantographs.is_empty() {
            return Err(inv("pantographs", "[]", "need at least one pantograph"));
        }
        for (i, p) in case.pantographs.iter().enumerate() {
            let base = format!("pantographs[{i}]");
            check(
                w,
                &format!("{base}.offset_m"),
                p.offset_m(),
                &bounds::OFFSET,
            )?;
            match p {
                PantographCase::Lumped {
                    masses_kg,
                    stiffness_n_per_m,
                    damping_ns_per_m,
                    uplift_n,
                    aero_coeffs_kmh,
                    ..
                } => {
                    if masses_kg.is_empty() {
                        return Err(inv(
                            &format!("{base}.masses_kg"),
                            "[]",
                            "need at least one mass",
                        ));
                    }
                    if masses_kg.len() > 20 {
                        return Err(inv(
                            &format!("{base}.masses_kg"),
                            format!("{} masses", masses_kg.len()),
                            "a lumped pantograph has a handful of masses (at most 20)",
                        ));
                    }
                    for (j, &m) in masses_kg.iter().enumerate() {
                        check(
                            w,
                            &format!("{base}.masses_kg[{j}]"),
                            m,
                            &bounds::PANTOGRAPH_MASS,
                        )?;
                    }
                    for (field, v, b) in [
                        (
                            "stiffness_n_per_m",
                            stiffness_n_per_m,
                            &bounds::PANTOGRAPH_STIFFNESS,
                        ),
                        (
                            "damping_ns_per_m",
                            damping_ns_per_m,
                            &bounds::PANTOGRAPH_DAMPING,
                        ),
                    ] {
                        if v.len() != masses_kg.len() {
                            return Err(inv(
                                &format!("{base}.{field}"),
                                format!("{} values", v.len()),
                                &format!("need one value per mass ({})", masses_kg.len()),
                            ));
                        }
                        for (j, &x) in v.iter().enumerate() {
                            check(w, &format!("{base}.{field}[{j}]"), x, b)?;
                        }
                    }
                    check(w, &format!("{base}.uplift_n"), *uplift_n, &bounds::UPLIFT)?;
                    if aero_coeffs_kmh.len() > 8 {
                        return Err(inv(
                            &format!("{base}.aero_coeffs_kmh"),
                            format!("{} coefficients", aero_coeffs_kmh.len()),
                            "a polynomial of degree at most 7",
                        ));
                    }
                    let v = r.speed_kmh;
                    let aero = aero_coeffs_kmh
                        .iter()
                        .rev()
                        .fold(0.0, |acc, ci| acc * v + ci);
                    check(
                        w,
                        &format!("{base}.aero_coeffs_kmh (the force at {v} km/h, N)"),
                        aero,
                        &bounds::AERO,
                    )?;
                }
                PantographCase::MovingForce { force_n, .. } => {
                    check(
                        w,
                        &format!("{base}.force_n"),
                        *force_n,
                        &bounds::MOVING_FORCE,
                    )?;
                }
            }
        }
        Ok(())
    }

    /// The time step, the number of modes, and where the run starts, ends and is analysed.
    pub(super) fn run(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
        let c = &case.catenary;
        let r = &case.run;
        check(w, "run.dt_s", r.dt_s, &bounds::DT)?;
        match (r.modes, r.modes_per_m) {
            (Some(_), Some(_)) => {
                return Err(inv(
                    "run.modes",
                    "both modes and modes_per_m",
                    "give only one of them",
                ))
            }
            (None, None) => {
                return Err(inv("run.modes", "missing", "give `modes` or `modes_per_m`"))
            }
            (Some(n), None) if n == 0 => return Err(inv("run.modes", n, "must be at least 1")),
            (None, Some(dn)) => pos("run.modes_per_m", dn)?,
            _ => {}
        }
        let l = case.length_m();
        let field = if r.modes.is_some() {
            "run.modes"
        } else {
            "run.modes_per_m"
        };
        let shown = |n: usize| match r.modes_per_m {
            Some(d) if r.modes.is_none() => format!("{d} ({n} modes over {l} m)"),
            _ => n.to_string(),
        };
        let raw = match (r.modes, r.modes_per_m) {
            (Some(n), _) => n as f64,
            (None, Some(d)) => d * l,
            _ => 0.0,
        };
        if raw > 200_000.0 {
            return Err(inv(
                field,
                shown(raw as usize),
                "more than 200000 modes per wire",
            ));
        }
        let n = case.n_modes();
        // The shortest wave of the series, 2L/N, must be shorter than a span, or the series
        // cannot even show the span-to-span shape of the catenary.
        if (n as f64) < 2.0 * c.spans as f64 {
            return Err(inv(
                field,
                shown(n),
                &format!(
                    "fewer than 2 modes per span ({} spans): the series cannot represent the catenary; about 1 mode per metre converges (docs/validation.md)",
                    c.spans
                ),
            ));
        }
        if (n as f64) / l < 0.3 {
            w.push(Warning(format!(
                "{field} = {}: {:.2} modes per metre resolve the wires only to about {:.0} Hz; statistics converge at about 1 per metre (docs/validation.md)",
                shown(n),
                n as f64 / l,
                n as f64 / l * 60.0
            )));
        }
        let max_off = case
            .pantographs
            .iter()
            .map(|p| p.offset_m())
            .fold(0.0, f64::max);
        if r.start_m - max_off <= 0.0 || r.start_m >= l {
            return Err(inv(
                "run.start_m",
                r.start_m,
                &format!("every pantograph must start inside the model (0, {l}) m (rearmost offset {max_off} m)"),
            ));
        }
        if r.end_m <= r.start_m - max_off {
            return Err(inv(
                "run.end_m",
                r.end_m,
                "must lie ahead of the rearmost pantograph's start",
            ));
        }
        if r.end_m + max_off >= l {
            return Err(inv(
                "run.end_m",
                r.end_m,
                &format!("the leading pantograph would leave the model (length {l} m) before the rearmost reaches it"),
            ));
        }
        let [a, b] = r.analysis_m;
        if !(a >= 0.0 && b <= l && a < b) {
            return Err(inv(
                "run.analysis_m",
                format!("[{a}, {b}]"),
                &format!("must be an interval inside the model [0, {l}] m"),
            ));
        }
        if a < r.start_m - max_off || b > r.end_m {
            return Err(inv(
                "run.analysis_m",
                format!("[{a}, {b}]"),
                &format!("every pantograph must cross the whole section: it must lie within [start_m − offset, end_m] = [{}, {}] m", r.start_m - max_off, r.end_m),
            ));
        }
        Ok(())
    }
}
