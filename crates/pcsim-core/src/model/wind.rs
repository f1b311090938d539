//! Crosswind on the wires (issue 12, the paper's "future work"): quasi-steady loads per unit
//! length from the wind normal to the track.
//!
//! With the normal wind `U_n + u'_n(x, t)` (mean from the height profile, turbulence from
//! `wind_field`) and a wire of diameter `d` (ice included) the loads per unit length are
//!
//! ```text
//! lateral  F_z = ½ρ d C_D(0) (U_n + u'_n)|U_n + u'_n| − c_z ż,        c_z = ρ d C_D(0) U_n
//! vertical F_y = ½ρ d C_L(0) (U_n + u'_n)|U_n + u'_n| − c_y ẏ,        c_y = ½ρ d U_n (C_L'(0) + C_D(0))
//! moment   M   = ½ρ d² C_M(0) (U_n + u'_n)|U_n + u'_n| − c_φ φ̇,      c_φ = ½ρ d² R U_n C_M'(0)
//! ```
//!
//! The wire's own motion enters through the relative velocity, linearised about the mean wind:
//! the lateral aerodynamic damping `c_z` and the vertical one `c_y` (Den Hartog's: negative when
//! `C_L' + C_D < 0`, galloping). The torsional one is the quasi-steady theory's (Blevins, *Flow-
//! Induced Vibration*, torsional galloping): a section turning at `φ̇` meets the wind at an angle
//! changed by `R φ̇/U`, `R` the characteristic radius, here the wire's radius `d/2` (a round
//! section's own length: guess), so the moment changes by `½ρ U² d² C_M' R φ̇/U`; negative when
//! `C_M' < 0` (torsional galloping). All three are uniform along the wire, so in sine coordinates
//! they are diagonal: they add `c L/2` to each mode's damping and cost nothing per step — the
//! series is loaded by projection, not point by point. The fluctuating part is applied on a grid
//! of points (one scatter per step for all wires); the mean part is projected exactly once. The
//! dependence of the coefficients on the wire's rotation (an aerodynamic torsional stiffness
//! `½ρ U² d² C_M'`) is left out (documented in docs/validation.md).

use crate::model::wind_field::{SpectrumModel, WindField};

/// The wind on one wire.
#[derive(Debug, Clone, PartialEq)]
pub struct WireWind {
    /// Index of the wire in `Model::wires`.
    pub wire: usize,
    /// Height above the rail, m.
    pub height_m: f64,
    /// Mean wind normal to the track at the wire's height, m/s (on a curve, at the first
    /// support).
    pub mean_normal_m_s: f64,
    /// Mean wind at the wire's height along the wind, m/s (a curve's normal part is
    /// `WindLoad::normal_by_grid` times it).
    pub mean_along_m_s: f64,
    /// Per-length load coefficients on `½ρ V|V|`: lateral `d C_D`, vertical `d C_L`, torsional
    /// `d² C_M` (ice included in `d`).
    pub lateral_m: f64,
    /// Vertical load coefficient `d C_L`, m, times the side of the normal wind (`±1`, at the
    /// first support): the lift of a section symmetric about its vertical plane is even in the
    /// wind's side (`½ρ V² d C_L`), the drag and the moment are odd.
    pub vertical_m: f64,
    /// Torsional load coefficient `d² C_M`, m².
    pub torsional_m2: f64,
    /// Linearised aerodynamic damping per metre, lateral and vertical, N·s/m².
    pub damping_lateral: f64,
    /// Vertical aerodynamic damping per metre, N·s/m².
    pub damping_vertical: f64,
    /// Torsional aerodynamic damping per metre, N·m·s/m.
    pub damping_torsional: f64,
}

/// The crosswind of a model.
#[derive(Debug, Clone, PartialEq)]
pub struct WindLoad {
    /// Air density, kg/m³.
    pub air_density_kg_m3: f64,
    /// `sin(yaw)`: the part of the wind (and its fluctuation) normal to the track, signed
    /// (positive: toward positive stagger).
    pub normal_fraction: f64,
    /// The wind on every loaded wire.
    pub wires: Vec<WireWind>,
    /// On a curved track, the part of the wind normal to the track at each grid point,
    /// `sin(ψ − θ(x))` with `ψ` the yaw at the first support and `θ(x)` the track's turn
    /// since it; empty on a straight track (`normal_fraction` everywhere).
    pub normal_by_grid: Vec<f64>,
    /// Along-wind fluctuation on the grid (model coordinates).
    pub field: WindField,
    /// Length of line each grid point stands for, m.
    pub grid_m: f64,
    /// What summary.json reports.
    pub report: WindReport,
}

/// The wind's description in the outputs.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct WindReport {
    /// Mean speed at the reference height, m/s.
    pub mean_speed_m_s: f64,
    /// Reference height, m.
    pub reference_height_m: f64,
    /// Angle between the wind and the track, °.
    pub yaw_deg: f64,
    /// The turbulence spectrum's name.
    pub spectrum: String,
    /// Seed of the turbulence.
    pub seed: u64,
    /// The turbulence intensity the case asked for.
    pub turbulence_intensity_target: f64,
    /// σ of the generated fluctuation over the run, divided by the mean at the reference height.
    pub turbulence_intensity_achieved: f64,
}

impl WindLoad {
    /// `½ρ V|V|` for the normal wind `V = U_n + u'_n` on wire `w` with the along-wind fluctuation
    /// `u'`, N/m² (the common factor of the three loads).
    #[inline]
    pub fn pressure(&self, w: usize, u_prime: f64) -> f64 {
        let v = self.wires[w].mean_normal_m_s + self.normal_fraction * u_prime;
        0.5 * self.air_density_kg_m3 * v * v.abs()
    }

    /// The mean of [`Self::pressure`] at `u' = 0`.
    pub fn mean_pressure(&self, w: usize) -> f64 {
        self.pressure(w, 0.0)
    }

    /// [`Self::pressure`] along a fluctuation linear in `τ ∈ [0, 1]` from `u0` to `u1` (the
    /// field between two of its samples), as `[c0, c1, c2]` with `p(τ) = c0 + c1 τ + c2 τ²`:
    /// while the normal wind `V = V0 + τ ΔV` keeps its sign `s`,
    /// `½ρ V|V| = s ½ρ (V0² + 2 V0 ΔV τ + ΔV² τ²)`, the same law expanded (equal to it in exact
    /// arithmetic). `None` when `V` changes sign inside the interval (the law is not one
    /// quadratic there).
    pub fn pressure_quadratic(&self, w: usize, u0: f64, u1: f64) -> Option<[f64; 3]> {
        let v0 = self.wires[w].mean_normal_m_s + self.normal_fraction * u0;
        let v1 = self.wires[w].mean_normal_m_s + self.normal_fraction * u1;
        Self::quadratic(self.air_density_kg_m3, v0, v1)
    }

    /// `½ρ V|V|` along a normal wind linear from `v0` to `v1`, as a quadratic in the fraction
    /// (see [`Self::pressure_quadratic`]).
    fn quadratic(rho: f64, v0: f64, v1: f64) -> Option<[f64; 3]> {
        if v0 * v1 < 0.0 {
            return None;
        }
        let dv = v1 - v0;
        let half_rho = if v0 < 0.0 || (v0 == 0.0 && v1 < 0.0) {
            -0.5 * rho
        } else {
            0.5 * rho
        };
        Some([
            half_rho * v0 * v0,
            half_rho * 2.0 * v0 * dv,
            half_rho * dv * dv,
        ])
    }

    /// [`Self::pressure`] at grid point `g`: on a curved track the normal wind there,
    /// `V = sin(ψ − θ(x_g)) (U + u')`, the same law; on a straight track `pressure(w, u')`.
    #[inline]
    pub fn pressure_at(&self, w: usize, g: usize, u_prime: f64) -> f64 {
        match self.normal_by_grid.get(g) {
            None => self.pressure(w, u_prime),
            Some(&s) => {
                let v = s * (self.wires[w].mean_along_m_s + u_prime);
                0.5 * self.air_density_kg_m3 * v * v.abs()
            }
        }
    }

    /// The mean of [`Self::pressure_at`] at grid point `g` (`u' = 0`).
    pub fn mean_pressure_at(&self, w: usize, g: usize) -> f64 {
        self.pressure_at(w, g, 0.0)
    }

    /// [`Self::pressure_quadratic`] at grid point `g` (on a curved track, with the normal
    /// wind of that point).
    pub fn pressure_quadratic_at(&self, w: usize, g: usize, u0: f64, u1: f64) -> Option<[f64; 3]> {
        match self.normal_by_grid.get(g) {
            None => self.pressure_quadratic(w, u0, u1),
            Some(&s) => {
                let a = self.wires[w].mean_along_m_s;
                Self::quadratic(self.air_density_kg_m3, s * (a + u0), s * (a + u1))
            }
        }
    }

    /// The same load in a window starting at `origin_m` (grid points inside it only).
    pub fn window(&self, origin_m: f64, length_m: f64) -> Self {
        let keep: Vec<usize> = (0..self.field.x_m.len())
            .filter(|&j| {
                let x = self.field.x_m[j];
                x > origin_m && x < origin_m + length_m
            })
            .collect();
        let mut u = Vec::with_capacity(keep.len() * self.field.n_t);
        for &j in &keep {
            u.extend_from_slice(self.field.series(j));
        }
        Self {
            normal_by_grid: (keep.iter())
                .filter_map(|&j| self.normal_by_grid.get(j).copied())
                .collect(),
            field: WindField {
                x_m: keep.iter().map(|&j| self.field.x_m[j] - origin_m).collect(),
                u,
                ..self.field.clone()
            },
            ..self.clone()
        }
    }
}

impl WindLoad {
    /// A steady uniform lateral load `q` (N/m) on wire `wire`, with no turbulence and no
    /// aerodynamic damping: the analytic checks' load.
    pub fn uniform_lateral(wire: usize, q_n_per_m: f64) -> Self {
        Self {
            air_density_kg_m3: 2.0,
            normal_fraction: 1.0,
            wires: vec![WireWind {
                wire,
                height_m: 0.0,
                mean_normal_m_s: q_n_per_m.signum() * q_n_per_m.abs().sqrt(),
                mean_along_m_s: q_n_per_m.signum() * q_n_per_m.abs().sqrt(),
                lateral_m: 1.0,
                vertical_m: 0.0,
                torsional_m2: 0.0,
                damping_lateral: 0.0,
                damping_vertical: 0.0,
                damping_torsional: 0.0,
            }],
            normal_by_grid: Vec::new(),
            field: WindField::calm(&[], 1.0),
            grid_m: 1.0,
            report: WindReport {
                mean_speed_m_s: 0.0,
                reference_height_m: 0.0,
                yaw_deg: 90.0,
                spectrum: "none".into(),
                seed: 0,
                turbulence_intensity_target: 0.0,
                turbulence_intensity_achieved: 0.0,
            },
        }
    }
}

/// Mean wind speed at height `z` from the reference speed (log or power law).
pub fn mean_at_height(u_ref: f64, z_ref: f64, z: f64, profile: &Profile) -> f64 {
    match *profile {
        Profile::Log { roughness_m } => u_ref * (z / roughness_m).ln() / (z_ref / roughness_m).ln(),
        Profile::Power { exponent } => u_ref * (z / z_ref).powf(exponent),
    }
}

/// The mean-wind profile (the model side of the case's `[wind] profile`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Profile {
    /// A logarithmic profile with the roughness length, m.
    Log {
        /// Terrain roughness length z0, m.
        roughness_m: f64,
    },
    /// A power-law profile with the exponent α.
    Power {
        /// Exponent α.
        exponent: f64,
    },
}

/// The spectrum to generate, or none (mean wind only).
pub type Turbulence = Option<SpectrumModel>;
