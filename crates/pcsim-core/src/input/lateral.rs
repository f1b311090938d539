//! The three-dimensional part of a case (issue 12): which directions are modelled (the paper's
//! Eqs. 1–14 in y, z and φ), the wires' lateral and torsional section data, stagger and lateral
//! registration, crosswind and ice. Every block is optional; a case without them is the vertical
//! model it always was (`run.dofs = ["vertical"]`).

use serde::{Deserialize, Serialize};

/// A modelled direction of motion, as the case file names it.
#[derive(
    Debug,
    Clone,
    Copy,
    Serialize,
    Deserialize,
    PartialEq,
    Eq,
    PartialOrd,
    Ord,
    Hash,
    schemars::JsonSchema,
)]
#[serde(rename_all = "snake_case")]
pub enum Dof {
    /// Vertical motion (`y` of Eqs. 1–8).
    Vertical,
    /// Lateral motion (`z` of Eqs. 1–8).
    Lateral,
    /// Torsional motion (`φ` of Eqs. 1–8).
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
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
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
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AeroCase {
    /// Angles of attack, degrees, increasing (the relative wind's angle above horizontal).
    pub attack_deg: Vec<f64>,
    /// Drag coefficients C_D at the angles.
    pub drag: Vec<f64>,
    /// Lift coefficients C_L at the angles.
    pub lift: Vec<f64>,
    /// Moment coefficients C_M at the angles.
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

    /// `(dC_D/dα, dC_L/dα, dC_M/dα)` per radian at 0 (central difference over the table's
    /// neighbours).
    pub fn slopes_at_zero(&self) -> (f64, f64, f64) {
        let h = 1.0;
        let (d1, l1, m1) = self.at(h);
        let (d0, l0, m0) = self.at(-h);
        let per_rad = 180.0 / (2.0 * h * std::f64::consts::PI);
        (
            (d1 - d0) * per_rad,
            (l1 - l0) * per_rad,
            (m1 - m0) * per_rad,
        )
    }
}

/// Stagger and lateral registration (`catenary.lateral`).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
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
    /// Depth below the axis of a contact point fixed to the wire's section (a worn, flat running
    /// face), m: it rises by ½eφ², moves sideways by eφ and takes the moment F·e·φ as the wire
    /// turns. 0 (the default) for a round running face, whose lowest point stays under the axis
    /// whatever the rotation (issue 20).
    #[serde(default)]
    pub contact_point_eccentricity_m: f64,
    /// Height of the contact wire above the rail (for the wind profile, and the pantograph's
    /// shift on a canted track), m.
    pub contact_wire_height_m: f64,
    /// Radius of the track's horizontal curve, m, signed: positive when the curve's centre lies
    /// on the side of positive stagger. The wires run straight between their registrations, so
    /// that relative to the curved track they bow toward the centre by `x(s − x)/(2R)` in a span
    /// `s`, and each registration holds the tension's change of direction (the pull-off force).
    /// Not given: straight track.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub track_radius_m: Option<f64>,
    /// Cant (superelevation) of a curved track, m of height between rails 1.5 m apart (standard
    /// gauge's rail centres), the outer rail raised: the vehicle leans toward the curve's centre
    /// and its pantograph head moves that way by `contact_wire_height_m · cant_m / 1.5`. Stagger
    /// stays measured from the track's centre line.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub cant_m: f64,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// Distance between the rails' centres of standard gauge (1 435 mm between the running edges,
/// about 1 500 mm between the rail heads' centres), m: the base of the cant.
pub const CANT_BASE_M: f64 = 1.5;

/// How far the pantograph's head stands from the track's centre line toward the curve's centre
/// on a track of radius `radius_m` (signed; `None`: straight) canted by `cant_m`, for a contact
/// wire `contact_wire_height_m` above the rails, m: `sign(R) h cant / 1.5` (0 on straight or
/// uncanted track).
pub fn head_offset_m(radius_m: Option<f64>, cant_m: f64, contact_wire_height_m: f64) -> f64 {
    match radius_m {
        Some(r) => r.signum() * contact_wire_height_m * cant_m / CANT_BASE_M,
        None => 0.0,
    }
}

impl LateralCase {
    /// How far the pantograph's head stands from the track's centre line toward the curve's
    /// centre on a canted track, m (0 on straight or uncanted track).
    pub fn head_offset_m(&self) -> f64 {
        head_offset_m(self.track_radius_m, self.cant_m, self.contact_wire_height_m)
    }

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
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct IceCase {
    /// Density of the ice, kg/m³.
    pub density_kg_m3: f64,
    /// Radial thickness on the contact wire, m.
    pub contact_wire_m: f64,
    /// Radial thickness on the messenger, m.
    pub messenger_m: f64,
}

/// The mean-wind profile with height.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum WindProfile {
    /// `U(z) = U_ref ln(z/z0) / ln(z_ref/z0)`.
    Log {
        /// Terrain roughness length z0, m.
        roughness_m: f64,
    },
    /// `U(z) = U_ref (z/z_ref)^α`.
    Power {
        /// Exponent α.
        exponent: f64,
    },
}

/// The turbulence spectrum of the along-wind component.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Spectrum {
    /// Kaimal (IEC form): `f S/σ² = 4 y / (1 + 6 y)^{5/3}`, `y = f L/U`, with the Kaimal length
    /// `L = 8.1 Λ` (`Λ = 0.7 z` below 60 m).
    Kaimal {
        /// Integral length scale Λ, m.
        integral_length_m: f64,
    },
    /// Davenport: `f S/σ² = (2/3) x² / (1 + x²)^{4/3}`, `x = 1200 f / U_ref`.
    Davenport,
    /// Mean wind only.
    None,
}

/// Crosswind (`[wind]`).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct WindCase {
    /// Mean speed at the reference height, m/s.
    pub mean_speed_m_s: f64,
    /// Reference height of the mean speed, m.
    pub reference_height_m: f64,
    /// The mean-wind profile with height.
    pub profile: WindProfile,
    /// Angle between the wind and the track, degrees (90: square to the track, blowing toward
    /// positive stagger; −90: toward negative stagger; on a curve, at the first support).
    pub yaw_deg: f64,
    /// σ_u / U at the reference height.
    pub turbulence_intensity: f64,
    /// The turbulence spectrum.
    pub spectrum: Spectrum,
    /// Davenport's decay constant `C` of the coherence `exp(−C f Δx / U)` along the line.
    pub coherence_decay: f64,
    /// Seed of the turbulence (written to summary.json).
    pub seed: u64,
    /// Air density, kg/m³.
    pub air_density_kg_m3: f64,
    /// Spacing of the wind grid along the line, m (a divisor of the span keeps it periodic).
    pub grid_m: f64,
    /// Time step of the generated wind, s (linear in between).
    pub dt_s: f64,
}
