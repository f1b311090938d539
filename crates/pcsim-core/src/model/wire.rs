//! Wires: a role, an extent along the track, section data, and one modal series per modelled
//! direction (Eqs. 1–14).
//!
//! The law of a tensioned Euler–Bernoulli beam lives in two functions: [`Wire::coefficients`]
//! gives the per-metre coefficients of the kinetic and strain energy of a direction (Eqs. 1–4),
//! and [`ModalSeries::tensioned_beam`] turns them into the diagonal modal matrices (Eqs. 11–14).
//! The energy density (Eq. 20, `analysis::energy`) uses the same coefficients, so the tension can
//! be followed from the case file (`catenary.contact_wire.tension_n`) through
//! [`Section::tension_n`] to both.

use serde::{Deserialize, Serialize};

use crate::model::basis::SineBasis;
use crate::model::dof::Direction;

/// Damping of the wires' own modes (paper §2.1 uses Rayleigh α = β = 0.02; README §2.2).
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Damping {
    /// `C = αM + βK` on each wire's modal matrices.
    Rayleigh {
        /// Mass factor α, 1/s.
        alpha: f64,
        /// Stiffness factor β, s.
        beta: f64,
    },
    /// The same damping ratio on every sine mode of each wire.
    Modal {
        /// Damping ratio ζ.
        ratio: f64,
    },
}

/// What a wire is in the catenary.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum WireRole {
    /// The messenger wire.
    Messenger,
    /// The contact wire.
    Contact,
    /// A stitch wire.
    Stitch,
}

/// Section data of a wire (SI units): what Eqs. 1–4 need in each direction.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Section {
    /// Mass per metre in the dynamics (ρA; clamps smeared in, see `model::build`), kg/m.
    pub mass_per_m_kg: f64,
    /// Tension T, N.
    pub tension_n: f64,
    /// Bending stiffness for vertical motion (the paper's E I_z), N·m².
    pub ei_vertical_nm2: f64,
    /// Bending stiffness for lateral motion (E I_y), N·m².
    pub ei_lateral_nm2: f64,
    /// Torsional stiffness G I_p, N·m².
    pub gj_nm2: f64,
    /// Polar mass moment per metre ρ(I_y + I_z), kg·m.
    pub polar_inertia_kg_m: f64,
}

impl Section {
    /// A section with the vertical data only (the lateral bending stiffness equal to the
    /// vertical one, no torsion).
    pub fn vertical(mass_per_m_kg: f64, tension_n: f64, ei_nm2: f64) -> Self {
        Section {
            mass_per_m_kg,
            tension_n,
            ei_vertical_nm2: ei_nm2,
            ei_lateral_nm2: ei_nm2,
            gj_nm2: 0.0,
            polar_inertia_kg_m: 0.0,
        }
    }
}

/// Per-metre coefficients of one direction of a wire in Eqs. 1–4: the kinetic energy density is
/// `½ mass·u̇²` and the strain energy density `½ slope·u'² + ½ bending·u''²`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Coefficients {
    /// ρA (y, z) or ρ(I_y + I_z) (φ).
    pub mass: f64,
    /// T (y, z) or G I_p (φ).
    pub slope: f64,
    /// E I_z (y), E I_y (z), 0 (φ).
    pub bending: f64,
}

/// Diagonal modal matrices of one direction of one wire (Eqs. 11–14): for a uniform wire in sine
/// coordinates `M`, `K` and the damping `C` are diagonal.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalSeries {
    /// Modal masses M_k (Eqs. 11, 13).
    pub mass: Vec<f64>,
    /// Modal stiffnesses K_k (Eqs. 12, 14).
    pub stiffness: Vec<f64>,
    /// Modal dampings C_k (Rayleigh `C = αM + βK` as in the paper, or a modal ratio).
    pub damping: Vec<f64>,
}

impl ModalSeries {
    /// The series of a tensioned Euler–Bernoulli beam (Eqs. 11–14): `M_k = L/2 · mass`,
    /// `K_k = L/2 (slope κ² + bending κ⁴)`, and `C = αM + βK` (Rayleigh, paper §2.1) or
    /// `C_k = 2ζ √(K_k M_k)` (modal).
    pub fn tensioned_beam(basis: &SineBasis, c: Coefficients, damping: &Damping) -> Self {
        let l = basis.length_m();
        let n = basis.n_modes();
        let mut mass = vec![0.0; n];
        let mut stiffness = vec![0.0; n];
        let mut damp = vec![0.0; n];
        for i in 0..n {
            let k = basis.wavenumber(i);
            mass[i] = 0.5 * l * c.mass;
            stiffness[i] = 0.5 * l * (c.slope * k * k + c.bending * k.powi(4));
            damp[i] = match damping {
                Damping::Rayleigh { alpha, beta } => alpha * mass[i] + beta * stiffness[i],
                Damping::Modal { ratio } => 2.0 * ratio * (stiffness[i] * mass[i]).sqrt(),
            };
        }
        Self {
            mass,
            stiffness,
            damping: damp,
        }
    }
}

/// The modal series of a wire, one slot per direction.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Series {
    /// Vertical series (`y` of Eqs. 1–8), if modelled.
    pub vertical: Option<ModalSeries>,
    /// Lateral series (`z` of Eqs. 1–8), if modelled.
    pub lateral: Option<ModalSeries>,
    /// Torsional series (`φ` of Eqs. 1–8), if modelled.
    pub torsional: Option<ModalSeries>,
}

impl Series {
    /// The series of a direction, if modelled.
    pub fn get(&self, dir: Direction) -> Option<&ModalSeries> {
        match dir {
            Direction::Vertical => self.vertical.as_ref(),
            Direction::Lateral => self.lateral.as_ref(),
            Direction::Torsional => self.torsional.as_ref(),
        }
    }
}

/// One wire of the catenary.
#[derive(Debug, Clone, PartialEq)]
pub struct Wire {
    /// Name (shown in outputs).
    pub name: String,
    /// What the wire is.
    pub role: WireRole,
    /// Model coordinate of the wire's start, m.
    pub origin_m: f64,
    /// The sine basis over the wire's extent `[origin, origin + length]`.
    pub basis: SineBasis,
    /// The cross-section's data.
    pub section: Section,
    /// The damping law of the wire's modes.
    pub damping: Damping,
    /// The modal series per direction.
    pub series: Series,
    /// Damping per metre added uniformly in each direction (vertical, lateral, torsional), such
    /// as the linearised aerodynamic damping of a crosswind (`model::wind`), N·s/m² (N·m·s/m).
    pub added_damping_per_m: [f64; 3],
    /// A steady uniform load per metre in each direction (vertical, lateral, torsional) that the
    /// design's static shape does not carry: the ice's weight (downward, so negative), N/m
    /// (N·m/m). The static start state is solved under it (`solve::equilibrium`) and
    /// every step applies it.
    pub static_load_per_m: [f64; 3],
}

impl Wire {
    /// A wire with the given directions modelled, each a tensioned-beam series over `basis`.
    pub fn new(
        name: &str,
        role: WireRole,
        origin_m: f64,
        basis: SineBasis,
        section: Section,
        damping: Damping,
        dirs: &[Direction],
    ) -> Self {
        let mut w = Wire {
            name: name.to_string(),
            role,
            origin_m,
            basis,
            section,
            damping,
            series: Series::default(),
            added_damping_per_m: [0.0; 3],
            static_load_per_m: [0.0; 3],
        };
        for &d in dirs {
            let s = ModalSeries::tensioned_beam(&w.basis, w.coefficients(d), &w.damping);
            match d {
                Direction::Vertical => w.series.vertical = Some(s),
                Direction::Lateral => w.series.lateral = Some(s),
                Direction::Torsional => w.series.torsional = Some(s),
            }
        }
        w
    }

    /// The same wire over another basis (a window), with the same section, damping law,
    /// added damping and directions.
    pub fn rebased(&self, origin_m: f64, basis: SineBasis) -> Self {
        let dirs: Vec<Direction> = Direction::ALL
            .into_iter()
            .filter(|&d| self.series.get(d).is_some())
            .collect();
        let mut w = Wire::new(
            &self.name,
            self.role,
            origin_m,
            basis,
            self.section.clone(),
            self.damping.clone(),
            &dirs,
        );
        for (i, d) in Direction::ALL.into_iter().enumerate() {
            w = w.with_added_damping(d, self.added_damping_per_m[i]);
        }
        w.static_load_per_m = self.static_load_per_m;
        w
    }

    /// Add a steady uniform load `f` per metre in direction `dir` that the static design does not
    /// carry (see [`Wire::static_load_per_m`]), N/m.
    pub fn with_static_load(mut self, dir: Direction, f_per_m: f64) -> Self {
        let i = Direction::ALL.iter().position(|&d| d == dir).unwrap_or(0);
        self.static_load_per_m[i] += f_per_m;
        self
    }

    /// Add a uniform damping `c` per metre in direction `dir`: in sine coordinates it is
    /// diagonal, `c L/2` on every mode (the modes are orthogonal with `∫ sin² = L/2`).
    pub fn with_added_damping(mut self, dir: Direction, c_per_m: f64) -> Self {
        if c_per_m == 0.0 {
            return self;
        }
        let i = Direction::ALL.iter().position(|&d| d == dir).unwrap_or(0);
        self.added_damping_per_m[i] += c_per_m;
        let half_l = 0.5 * self.basis.length_m();
        let s = match dir {
            Direction::Vertical => self.series.vertical.as_mut(),
            Direction::Lateral => self.series.lateral.as_mut(),
            Direction::Torsional => self.series.torsional.as_mut(),
        };
        if let Some(s) = s {
            for c in &mut s.damping {
                *c += c_per_m * half_l;
            }
        }
        self
    }

    /// Per-metre energy coefficients of direction `dir` (Eqs. 1–4; the paper's Eq. 12 pairs E I_z
    /// with y and E I_y with z).
    pub fn coefficients(&self, dir: Direction) -> Coefficients {
        let s = &self.section;
        match dir {
            Direction::Vertical => Coefficients {
                mass: s.mass_per_m_kg,
                slope: s.tension_n,
                bending: s.ei_vertical_nm2,
            },
            Direction::Lateral => Coefficients {
                mass: s.mass_per_m_kg,
                slope: s.tension_n,
                bending: s.ei_lateral_nm2,
            },
            Direction::Torsional => Coefficients {
                mass: s.polar_inertia_kg_m,
                slope: s.gj_nm2,
                bending: 0.0,
            },
        }
    }

    /// Transverse wave speed √(T/ρA) with the dynamic mass per metre, m/s: the one definition
    /// used for the speed check and the speed ratio.
    pub fn wave_speed(&self) -> f64 {
        (self.section.tension_n / self.section.mass_per_m_kg).sqrt()
    }
}
