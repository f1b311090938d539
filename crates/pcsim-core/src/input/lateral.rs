//! The three-dimensional part of a case (issue 12): which directions are modelled (the paper's
//! Eqs. 1–14 in y, z and φ), the wires' lateral and torsional section data, stagger and lateral
//! registration, crosswind and ice. Every block is optional; a case without them is the vertical
//! model it always was (`run.dofs = ["vertical"]`).

use serde::{Deserialize, Serialize};

use super::case::{check_bound, inv, Bound, Case, PantographCase, Warning};
use crate::error::CaseError;

/// A modelled direction of motion, as the case file names it.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq, PartialOrd, Ord, Hash)]
#[serde(rename_all = "snake_case")]
pub enum Dof {
    Vertical,
    Lateral,
    Torsional,
}

/// The default of `run.dofs`: the vertical model.
pub fn vertical_only() -> Vec<Dof> {
    vec![Dof::Vertical]
}

/// Whether `dofs` is the default (then it is not written out).
pub fn is_vertical_only(dofs: &[Dof]) -> bool {
    dofs == [Dof::Vertical]
}

/// Section data beyond the vertical ones (`catenary.<wire>.section`): what Eqs. 1–4 need for
/// lateral and torsional motion, and the diameter for drag and ice.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SectionCase {
    /// Outer diameter (for a grooved contact wire: its height), m.
    pub diameter_m: f64,
    /// Bending stiffness for lateral motion E I_y, N·m² (default: the wire's `ei_nm2`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ei_lateral_nm2: Option<f64>,
    /// Torsional stiffness G I_p, N·m² (needed when `torsional` is modelled).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gj_nm2: Option<f64>,
    /// Polar mass moment per metre ρ(I_y + I_z), kg·m (needed when `torsional` is modelled).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub polar_inertia_kg_m: Option<f64>,
    /// Quasi-steady aerodynamic coefficients against the angle of attack (needed with wind).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub aero: Option<AeroCase>,
}

/// Drag, lift and moment coefficients over the angle of attack (per unit length, on the
/// diameter: `F_D = ½ρ d C_D V²`, `F_L = ½ρ d C_L V²`, `M = ½ρ d² C_M V²`).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct AeroCase {
    /// Angles of attack, degrees, increasing (the relative wind's angle above horizontal).
    pub attack_deg: Vec<f64>,
    pub drag: Vec<f64>,
    pub lift: Vec<f64>,
    pub moment: Vec<f64>,
}

impl AeroCase {
    /// `(C_D, C_L, C_M)` at `alpha_deg`, linear between the table's points (held beyond).
    pub fn at(&self, alpha_deg: f64) -> (f64, f64, f64) {
        let a = &self.attack_deg;
        let n = a.len();
        let lerp = |c: &[f64]| -> f64 {
            if alpha_deg <= a[0] {
                return c[0];
            }
            if alpha_deg >= a[n - 1] {
                return c[n - 1];
            }
            let i = a.partition_point(|&x| x <= alpha_deg).clamp(1, n - 1);
            let t = (alpha_deg - a[i - 1]) / (a[i] - a[i - 1]);
            c[i - 1] + t * (c[i] - c[i - 1])
        };
        (lerp(&self.drag), lerp(&self.lift), lerp(&self.moment))
    }

    /// `(dC_D/dα, dC_L/dα)` per radian at 0 (central difference over the table's neighbours).
    pub fn slopes_at_zero(&self) -> (f64, f64) {
        let h = 1.0;
        let (d1, l1, _) = self.at(h);
        let (d0, l0, _) = self.at(-h);
        let per_rad = 180.0 / (2.0 * h * std::f64::consts::PI);
        ((d1 - d0) * per_rad, (l1 - l0) * per_rad)
    }
}

/// Stagger and lateral registration (`catenary.lateral`).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LateralCase {
    /// Stagger of the contact wire at the supports, alternating `+s, −s, …` from the first
    /// support, m. Give this or `stagger_list_m`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stagger_m: Option<f64>,
    /// Stagger at each support in turn (the list repeats), m.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stagger_list_m: Option<Vec<f64>>,
    /// Lateral stiffness of the steady arm at the registration point, N/m.
    pub steady_arm_stiffness_n_per_m: f64,
    /// Mass of the steady arm in lateral motion, kg.
    #[serde(default)]
    pub steady_arm_mass_kg: f64,
    /// Lateral stiffness of the messenger's support (cantilever), N/m.
    pub messenger_support_stiffness_n_per_m: f64,
    /// Height of the dropper clamp on the contact wire above the wire's axis, m.
    #[serde(default)]
    pub dropper_clamp_eccentricity_m: f64,
    /// Height of the steady arm's clamp above the contact wire's axis, m.
    #[serde(default)]
    pub steady_arm_clamp_eccentricity_m: f64,
    /// The steady arm clamp's resistance to the contact wire's rotation, N·m/rad.
    #[serde(default)]
    pub steady_arm_torsional_stiffness_nm_per_rad: f64,
    /// Depth of the contact point (the wire's running face) below its axis, m.
    #[serde(default)]
    pub contact_point_eccentricity_m: f64,
    /// Height of the contact wire above the rail (for the wind profile), m.
    pub contact_wire_height_m: f64,
}

impl LateralCase {
    /// Stagger at support `i`, m.
    pub fn stagger_at(&self, i: usize) -> f64 {
        match (&self.stagger_list_m, self.stagger_m) {
            (Some(l), _) if !l.is_empty() => l[i % l.len()],
            (_, Some(s)) => {
                if i % 2 == 0 {
                    s
                } else {
                    -s
                }
            }
            _ => 0.0,
        }
    }
}

/// Radial ice on the wires (`catenary.ice`): the static-load plus wind-on-iced-wire case of the
/// design codes. The ice adds its mass and widens the wire for drag.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct IceCase {
    pub density_kg_m3: f64,
    /// Radial thickness on the contact wire, m.
    pub contact_wire_m: f64,
    /// Radial thickness on the messenger, m.
    pub messenger_m: f64,
}

/// The mean-wind profile with height.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum WindProfile {
    /// `U(z) = U_ref ln(z/z0) / ln(z_ref/z0)`.
    Log { roughness_m: f64 },
    /// `U(z) = U_ref (z/z_ref)^α`.
    Power { exponent: f64 },
}

/// The turbulence spectrum of the along-wind component.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Spectrum {
    /// Kaimal (IEC form): `f S/σ² = 4 y / (1 + 6 y)^{5/3}`, `y = f L/U`, with the Kaimal length
    /// `L = 8.1 Λ` (`Λ = 0.7 z` below 60 m).
    Kaimal { integral_length_m: f64 },
    /// Davenport: `f S/σ² = (2/3) x² / (1 + x²)^{4/3}`, `x = 1200 f / U_ref`.
    Davenport,
    /// Mean wind only.
    None,
}

/// Crosswind (`[wind]`).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct WindCase {
    /// Mean speed at the reference height, m/s.
    pub mean_speed_m_s: f64,
    pub reference_height_m: f64,
    pub profile: WindProfile,
    /// Angle between the wind and the track, degrees (90: square to the track).
    pub yaw_deg: f64,
    /// σ_u / U at the reference height.
    pub turbulence_intensity: f64,
    pub spectrum: Spectrum,
    /// Davenport's decay constant `C` of the coherence `exp(−C f Δx / U)` along the line.
    pub coherence_decay: f64,
    /// Seed of the turbulence (written to summary.json).
    pub seed: u64,
    pub air_density_kg_m3: f64,
    /// Spacing of the wind grid along the line, m (a divisor of the span keeps it periodic).
    pub grid_m: f64,
    /// Time step of the generated wind, s (linear in between).
    pub dt_s: f64,
}

const B_DIAMETER: Bound = Bound {
    hard: (0.0, 0.2),
    soft: (0.004, 0.04),
    unit: "m",
    typical: "0.008–0.02 m",
};
const B_GJ: Bound = Bound {
    hard: (0.0, 1.0e6),
    soft: (1.0, 5000.0),
    unit: "N·m²",
    typical: "20–400 N·m²",
};
const B_POLAR: Bound = Bound {
    hard: (0.0, 1.0),
    soft: (1.0e-7, 1.0e-3),
    unit: "kg·m",
    typical: "1e-5–1e-4 kg·m",
};
const B_COEFF: Bound = Bound {
    hard: (-10.0, 10.0),
    soft: (-3.0, 3.0),
    unit: "",
    typical: "C_D 0.8–1.3, C_L and C_M within ±0.5",
};
const B_STAGGER: Bound = Bound {
    hard: (-2.0, 2.0),
    soft: (-0.45, 0.45),
    unit: "m",
    typical: "±0.2–0.4 m",
};
const B_LAT_STIFF: Bound = Bound {
    hard: (0.0, 1.0e11),
    soft: (0.0, 1.0e8),
    unit: "N/m",
    typical: "1e4–1e6 N/m",
};
const B_TORS_STIFF: Bound = Bound {
    hard: (0.0, 1.0e6),
    soft: (0.0, 500.0),
    unit: "N·m/rad",
    typical: "0–100 N·m/rad",
};
const B_ARM_MASS: Bound = Bound {
    hard: (0.0, 1000.0),
    soft: (0.0, 10.0),
    unit: "kg",
    typical: "0.5–3 kg",
};
const B_ECC: Bound = Bound {
    hard: (-0.5, 0.5),
    soft: (-0.05, 0.05),
    unit: "m",
    typical: "0–0.02 m",
};
const B_HEIGHT: Bound = Bound {
    hard: (0.5, 100.0),
    soft: (3.0, 10.0),
    unit: "m",
    typical: "4.9–6.5 m",
};
const B_ICE_DENSITY: Bound = Bound {
    hard: (0.0, 1000.0),
    soft: (100.0, 917.0),
    unit: "kg/m³",
    typical: "300 (rime) – 900 (glaze) kg/m³",
};
const B_ICE: Bound = Bound {
    hard: (0.0, 0.5),
    soft: (0.0, 0.05),
    unit: "m",
    typical: "0–0.03 m radial",
};
const B_WIND: Bound = Bound {
    hard: (0.0, 120.0),
    soft: (0.0, 45.0),
    unit: "m/s",
    typical: "0–40 m/s",
};
const B_REF_HEIGHT: Bound = Bound {
    hard: (0.1, 1000.0),
    soft: (2.0, 100.0),
    unit: "m",
    typical: "10 m",
};
const B_ROUGH: Bound = Bound {
    hard: (0.0, 10.0),
    soft: (1.0e-4, 2.0),
    unit: "m",
    typical: "0.003–1 m",
};
const B_EXPONENT: Bound = Bound {
    hard: (0.0, 1.0),
    soft: (0.05, 0.5),
    unit: "",
    typical: "0.1–0.3",
};
const B_YAW: Bound = Bound {
    hard: (-360.0, 360.0),
    soft: (-180.0, 180.0),
    unit: "°",
    typical: "90° (square to the track)",
};
const B_TI: Bound = Bound {
    hard: (0.0, 1.0),
    soft: (0.0, 0.4),
    unit: "",
    typical: "0.05–0.25",
};
const B_LENGTH_SCALE: Bound = Bound {
    hard: (0.0, 10_000.0),
    soft: (5.0, 500.0),
    unit: "m",
    typical: "30–300 m",
};
const B_DECAY: Bound = Bound {
    hard: (0.0, 1000.0),
    soft: (2.0, 30.0),
    unit: "",
    typical: "7–16",
};
const B_AIR: Bound = Bound {
    hard: (0.0, 10.0),
    soft: (0.9, 1.5),
    unit: "kg/m³",
    typical: "1.225 kg/m³",
};
const B_GRID: Bound = Bound {
    hard: (0.0, 1000.0),
    soft: (0.5, 20.0),
    unit: "m",
    typical: "2–10 m",
};
const B_WIND_DT: Bound = Bound {
    hard: (0.0, 1.0),
    soft: (0.002, 0.1),
    unit: "s",
    typical: "0.01–0.05 s",
};
const B_HALF_WIDTH: Bound = Bound {
    hard: (0.0, 2.0),
    soft: (0.3, 1.2),
    unit: "m",
    typical: "0.8 m (1600 mm head), 0.975 m (1950 mm)",
};

/// Check the three-dimensional part of `case`, adding warnings to `w`.
pub fn validate(case: &Case, w: &mut Vec<Warning>) -> Result<(), CaseError> {
    let dofs = &case.run.dofs;
    if !dofs.contains(&Dof::Vertical) {
        return Err(inv(
            "run.dofs",
            format!("{dofs:?}"),
            "must include \"vertical\": the pantograph touches the wire vertically",
        ));
    }
    for (i, d) in dofs.iter().enumerate() {
        if dofs[..i].contains(d) {
            return Err(inv(
                "run.dofs",
                format!("{dofs:?}"),
                "a direction is listed twice",
            ));
        }
    }
    let lateral = dofs.contains(&Dof::Lateral);
    let torsional = dofs.contains(&Dof::Torsional);
    let c = &case.catenary;
    if torsional && !lateral {
        return Err(inv(
            "run.dofs",
            format!("{dofs:?}"),
            "torsion is coupled through lateral forces at eccentric clamps: model \"lateral\" too",
        ));
    }
    for (name, wire) in [
        ("contact_wire", &c.contact_wire),
        ("messenger", &c.messenger),
    ] {
        let f = |k: &str| format!("catenary.{name}.section.{k}");
        let needs = lateral || case.wind.is_some() || c.ice.is_some();
        let Some(s) = &wire.section else {
            if needs {
                return Err(inv(
                    &format!("catenary.{name}.section"),
                    "missing",
                    "lateral motion, wind and ice need the wire's section (diameter_m, and gj_nm2 and polar_inertia_kg_m for torsion)",
                ));
            }
            continue;
        };
        check_bound(w, &f("diameter_m"), s.diameter_m, &B_DIAMETER)?;
        if let Some(ei) = s.ei_lateral_nm2 {
            check_bound(w, &f("ei_lateral_nm2"), ei, &super::case::bounds::EI)?;
        }
        match (s.gj_nm2, s.polar_inertia_kg_m) {
            (Some(gj), Some(ip)) => {
                check_bound(w, &f("gj_nm2"), gj, &B_GJ)?;
                check_bound(w, &f("polar_inertia_kg_m"), ip, &B_POLAR)?;
            }
            _ if torsional => {
                return Err(inv(
                    &f(if s.gj_nm2.is_none() {
                        "gj_nm2"
                    } else {
                        "polar_inertia_kg_m"
                    }),
                    "missing",
                    "torsional motion needs gj_nm2 and polar_inertia_kg_m",
                ))
            }
            _ => {}
        }
        match &s.aero {
            Some(a) => {
                let n = a.attack_deg.len();
                if n < 2 {
                    return Err(inv(
                        &f("aero.attack_deg"),
                        format!("{n} angles"),
                        "need at least two angles",
                    ));
                }
                for i in 1..n {
                    if a.attack_deg[i] <= a.attack_deg[i - 1] {
                        return Err(inv(
                            &f(&format!("aero.attack_deg[{i}]")),
                            a.attack_deg[i],
                            "angles must increase",
                        ));
                    }
                }
                if a.attack_deg[0] > 0.0 || a.attack_deg[n - 1] < 0.0 {
                    return Err(inv(
                        &f("aero.attack_deg"),
                        format!("{:?}", a.attack_deg),
                        "the table must include 0° (the mean wind is horizontal)",
                    ));
                }
                for (k, v) in [("drag", &a.drag), ("lift", &a.lift), ("moment", &a.moment)] {
                    if v.len() != n {
                        return Err(inv(
                            &f(&format!("aero.{k}")),
                            format!("{} values", v.len()),
                            &format!("need one value per angle ({n})"),
                        ));
                    }
                    for (i, x) in v.iter().enumerate() {
                        check_bound(w, &f(&format!("aero.{k}[{i}]")), *x, &B_COEFF)?;
                    }
                }
                if a.at(0.0).0 <= 0.0 {
                    return Err(inv(
                        &f("aero.drag"),
                        a.at(0.0).0,
                        "the drag coefficient at 0° must be positive",
                    ));
                }
            }
            None if case.wind.is_some() => {
                return Err(inv(
                    &f("aero"),
                    "missing",
                    "wind needs the wire's aerodynamic coefficients",
                ))
            }
            None => {}
        }
    }
    match &c.lateral {
        Some(l) => {
            if !lateral {
                w.push(Warning(
                    "catenary.lateral is given but run.dofs has no \"lateral\": stagger and lateral registration are ignored".into(),
                ));
            }
            match (&l.stagger_m, &l.stagger_list_m) {
                (Some(s), None) => check_bound(w, "catenary.lateral.stagger_m", *s, &B_STAGGER)?,
                (None, Some(list)) => {
                    if list.is_empty() {
                        return Err(inv(
                            "catenary.lateral.stagger_list_m",
                            "[]",
                            "give at least one stagger",
                        ));
                    }
                    for (i, s) in list.iter().enumerate() {
                        check_bound(
                            w,
                            &format!("catenary.lateral.stagger_list_m[{i}]"),
                            *s,
                            &B_STAGGER,
                        )?;
                    }
                }
                (None, None) => {}
                (Some(_), Some(_)) => {
                    return Err(inv(
                        "catenary.lateral.stagger_m",
                        "both stagger_m and stagger_list_m",
                        "give only one of them",
                    ))
                }
            }
            let f = |k: &str| format!("catenary.lateral.{k}");
            check_bound(
                w,
                &f("steady_arm_stiffness_n_per_m"),
                l.steady_arm_stiffness_n_per_m,
                &B_LAT_STIFF,
            )?;
            check_bound(w, &f("steady_arm_mass_kg"), l.steady_arm_mass_kg, &B_ARM_MASS)?;
            check_bound(
                w,
                &f("messenger_support_stiffness_n_per_m"),
                l.messenger_support_stiffness_n_per_m,
                &B_LAT_STIFF,
            )?;
            for (k, v) in [
                ("dropper_clamp_eccentricity_m", l.dropper_clamp_eccentricity_m),
                (
                    "steady_arm_clamp_eccentricity_m",
                    l.steady_arm_clamp_eccentricity_m,
                ),
                (
                    "contact_point_eccentricity_m",
                    l.contact_point_eccentricity_m,
                ),
            ] {
                check_bound(w, &f(k), v, &B_ECC)?;
            }
            check_bound(
                w,
                &f("steady_arm_torsional_stiffness_nm_per_rad"),
                l.steady_arm_torsional_stiffness_nm_per_rad,
                &B_TORS_STIFF,
            )?;
            check_bound(
                w,
                &f("contact_wire_height_m"),
                l.contact_wire_height_m,
                &B_HEIGHT,
            )?;
        }
        None if lateral => {
            return Err(inv(
                "catenary.lateral",
                "missing",
                "lateral motion needs the lateral registration (steady-arm and messenger-support stiffness, contact-wire height, stagger)",
            ))
        }
        None => {}
    }
    if let Some(ice) = &c.ice {
        check_bound(
            w,
            "catenary.ice.density_kg_m3",
            ice.density_kg_m3,
            &B_ICE_DENSITY,
        )?;
        check_bound(w, "catenary.ice.contact_wire_m", ice.contact_wire_m, &B_ICE)?;
        check_bound(w, "catenary.ice.messenger_m", ice.messenger_m, &B_ICE)?;
    }
    if let Some(wd) = &case.wind {
        if !lateral {
            return Err(inv(
                "wind",
                "given",
                "wind acts laterally: add \"lateral\" to run.dofs",
            ));
        }
        let f = |k: &str| format!("wind.{k}");
        check_bound(w, &f("mean_speed_m_s"), wd.mean_speed_m_s, &B_WIND)?;
        check_bound(
            w,
            &f("reference_height_m"),
            wd.reference_height_m,
            &B_REF_HEIGHT,
        )?;
        match &wd.profile {
            WindProfile::Log { roughness_m } => {
                check_bound(w, &f("profile.roughness_m"), *roughness_m, &B_ROUGH)?;
                if *roughness_m <= 0.0 {
                    return Err(inv(&f("profile.roughness_m"), roughness_m, "must be > 0"));
                }
                let lh = c.lateral.as_ref().map_or(5.0, |l| l.contact_wire_height_m);
                if lh <= *roughness_m || wd.reference_height_m <= *roughness_m {
                    return Err(inv(
                        &f("profile.roughness_m"),
                        roughness_m,
                        "the log law needs heights above the roughness length",
                    ));
                }
            }
            WindProfile::Power { exponent } => {
                check_bound(w, &f("profile.exponent"), *exponent, &B_EXPONENT)?
            }
        }
        check_bound(w, &f("yaw_deg"), wd.yaw_deg, &B_YAW)?;
        check_bound(
            w,
            &f("turbulence_intensity"),
            wd.turbulence_intensity,
            &B_TI,
        )?;
        if let Spectrum::Kaimal { integral_length_m } = wd.spectrum {
            check_bound(
                w,
                &f("spectrum.integral_length_m"),
                integral_length_m,
                &B_LENGTH_SCALE,
            )?;
            if integral_length_m <= 0.0 {
                return Err(inv(
                    &f("spectrum.integral_length_m"),
                    integral_length_m,
                    "must be > 0",
                ));
            }
        }
        check_bound(w, &f("coherence_decay"), wd.coherence_decay, &B_DECAY)?;
        check_bound(w, &f("air_density_kg_m3"), wd.air_density_kg_m3, &B_AIR)?;
        check_bound(w, &f("grid_m"), wd.grid_m, &B_GRID)?;
        if wd.grid_m <= 0.0 {
            return Err(inv(&f("grid_m"), wd.grid_m, "must be > 0"));
        }
        check_bound(w, &f("dt_s"), wd.dt_s, &B_WIND_DT)?;
        if wd.dt_s <= 0.0 {
            return Err(inv(&f("dt_s"), wd.dt_s, "must be > 0"));
        }
        if wd.dt_s < case.run.dt_s {
            return Err(inv(
                &f("dt_s"),
                wd.dt_s,
                "must not be shorter than run.dt_s (the wind is interpolated between its samples)",
            ));
        }
        if wd.turbulence_intensity > 0.0 && matches!(wd.spectrum, Spectrum::None) {
            return Err(inv(
                &f("spectrum"),
                "none",
                "a turbulence intensity above 0 needs a spectrum (kaimal or davenport)",
            ));
        }
    }
    for (i, p) in case.pantographs.iter().enumerate() {
        if let PantographCase::Lumped {
            head_half_width_m,
            working_half_width_m,
            ..
        } = p
        {
            if let Some(h) = head_half_width_m {
                check_bound(
                    w,
                    &format!("pantographs[{i}].head_half_width_m"),
                    *h,
                    &B_HALF_WIDTH,
                )?;
                if *h <= 0.0 {
                    return Err(inv(
                        &format!("pantographs[{i}].head_half_width_m"),
                        h,
                        "must be > 0",
                    ));
                }
            }
            if let Some(wr) = working_half_width_m {
                check_bound(
                    w,
                    &format!("pantographs[{i}].working_half_width_m"),
                    *wr,
                    &B_HALF_WIDTH,
                )?;
                if let Some(h) = head_half_width_m {
                    if wr > h {
                        return Err(inv(
                            &format!("pantographs[{i}].working_half_width_m"),
                            wr,
                            &format!("must not exceed the head's half-width ({h} m)"),
                        ));
                    }
                }
            }
        }
    }
    Ok(())
}
