//! The assembled model: two wires in sine coordinates, point elements, pantographs and the run.
//!
//! Built from a [`Case`] by [`Model::from_case`], or piece by piece with [`ModelBuilder`] (the test
//! zoo uses the builder for single-wire analytic checks).

use crate::basis::SineBasis;
use crate::case::{Case, Damping, PantographCase, Warning, G};
use crate::error::CaseError;
use crate::statics::StaticSolution;

/// Diagonal modal matrices of one motion direction of one wire (Eqs. 11–14): for a uniform wire
/// in sine coordinates `M`, `K` and Rayleigh/modal `C` are diagonal.
#[derive(Debug, Clone, PartialEq)]
pub struct ModalSeries {
    pub mass: Vec<f64>,
    pub stiffness: Vec<f64>,
    pub damping: Vec<f64>,
}

impl ModalSeries {
    /// Vertical series of a tensioned Euler–Bernoulli beam (Eqs. 11–12):
    /// `M_k = ρA L/2`, `K_k = L/2 (EI κ⁴ + T κ²)`; damping per [`Damping`]
    /// (`C = αM + βK`, paper §2.1, or `C_k = 2ζ ω_k M_k`).
    pub fn tensioned_beam(
        basis: &SineBasis,
        mass_per_m: f64,
        tension_n: f64,
        ei_nm2: f64,
        damping: &Damping,
    ) -> Self {
        let l = basis.length_m();
        let n = basis.n_modes();
        let mut mass = vec![0.0; n];
        let mut stiffness = vec![0.0; n];
        let mut damp = vec![0.0; n];
        for i in 0..n {
            let k = basis.wavenumber(i);
            mass[i] = 0.5 * l * mass_per_m;
            stiffness[i] = 0.5 * l * (tension_n * k * k + ei_nm2 * k.powi(4));
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

/// One wire.
#[derive(Debug, Clone, PartialEq)]
pub struct Wire {
    /// Mass per metre used in the dynamics (clamps smeared in; see [`Model::from_case`]).
    pub mass_per_m_kg: f64,
    pub tension_n: f64,
    pub ei_nm2: f64,
    /// The damping law of the wire's modes.
    pub damping: Damping,
    /// Vertical motion. Lateral and torsional series would be further `ModalSeries` over the same
    /// basis (Eqs. 11–14); they are not excited in this model and not built.
    pub vertical: ModalSeries,
}

impl Wire {
    /// A wire over `basis` with its vertical series (Eqs. 11–12) and damping law.
    pub fn new(
        basis: &SineBasis,
        mass_per_m_kg: f64,
        tension_n: f64,
        ei_nm2: f64,
        damping: Damping,
    ) -> Self {
        let vertical =
            ModalSeries::tensioned_beam(basis, mass_per_m_kg, tension_n, ei_nm2, &damping);
        Self {
            mass_per_m_kg,
            tension_n,
            ei_nm2,
            damping,
            vertical,
        }
    }

    /// Transverse wave speed √(T/ρA), m/s.
    pub fn wave_speed(&self) -> f64 {
        (self.tension_n / self.mass_per_m_kg).sqrt()
    }
}

/// Tension-only dropper between the wires (Eq. 15 with preload, README §2.8).
#[derive(Debug, Clone, PartialEq)]
pub struct Dropper {
    pub x_m: f64,
    pub stiffness_n_per_m: f64,
    /// Static tension (at the contact-wire clamp), N.
    pub preload_n: f64,
    /// The stitch element this dropper hangs from (index into `Model::stitches`); `None` for a
    /// dropper on the messenger.
    pub stitch: Option<usize>,
}

/// A stitch element (paper §2.1: the stitch wire as spring-damping elements on the messenger):
/// a node of mass `mass_kg` joined to the messenger at `x_m` by a spring-damper, from which a
/// stitch dropper hangs. Stiffness from [`crate::statics::stitch_stiffness`].
#[derive(Debug, Clone, PartialEq)]
pub struct Stitch {
    pub x_m: f64,
    pub mass_kg: f64,
    pub stiffness_n_per_m: f64,
    pub damping_ns_per_m: f64,
}

/// Messenger support spring-damper to ground.
#[derive(Debug, Clone, PartialEq)]
pub struct Support {
    pub x_m: f64,
    pub stiffness_n_per_m: f64,
    pub damping_ns_per_m: f64,
}

/// Steady arm: lumped mass and vertical spring on the contact wire.
#[derive(Debug, Clone, PartialEq)]
pub struct Arm {
    pub x_m: f64,
    pub mass_kg: f64,
    pub stiffness_n_per_m: f64,
}

/// A pantograph model (Eq. 16) or a moving force.
#[derive(Debug, Clone, PartialEq)]
pub enum Pantograph {
    /// Head first; spring `i` joins mass `i` to `i+1`, the last joins the lowest mass to the roof.
    /// Coordinates are absolute heights with zero at the contact-wire height at the supports,
    /// where every spring is unstretched.
    Lumped {
        name: String,
        offset_m: f64,
        masses_kg: Vec<f64>,
        stiffness_n_per_m: Vec<f64>,
        damping_ns_per_m: Vec<f64>,
        /// Net static uplift on the lowest mass, N.
        uplift_n: f64,
        /// Aerodynamic force on the head at the run speed, N (Eq. 17 as a configurable polynomial;
        /// README §2.1).
        aero_n: f64,
    },
    /// A constant upward force on the contact wire.
    MovingForce {
        name: String,
        offset_m: f64,
        force_n: f64,
    },
    /// A force and position given from outside at every step (hardware in the loop; see
    /// [`crate::solver::Solver::set_external`]).
    External { name: String },
}

impl Pantograph {
    pub fn name(&self) -> &str {
        match self {
            Pantograph::Lumped { name, .. }
            | Pantograph::MovingForce { name, .. }
            | Pantograph::External { name } => name,
        }
    }
    pub fn offset_m(&self) -> f64 {
        match self {
            Pantograph::Lumped { offset_m, .. } | Pantograph::MovingForce { offset_m, .. } => {
                *offset_m
            }
            Pantograph::External { .. } => 0.0,
        }
    }
    /// Number of degrees of freedom.
    pub fn n_dof(&self) -> usize {
        match self {
            Pantograph::Lumped { masses_kg, .. } => masses_kg.len(),
            Pantograph::MovingForce { .. } | Pantograph::External { .. } => 0,
        }
    }
}

/// The static shape the dynamics deviate from.
#[derive(Debug, Clone, PartialEq)]
pub enum StaticShape {
    /// Straight wires at height 0 (analytic single-wire checks).
    Flat,
    Catenary(Box<StaticSolution>),
}

impl StaticShape {
    pub fn contact_height(&self, x: f64) -> f64 {
        match self {
            StaticShape::Flat => 0.0,
            StaticShape::Catenary(s) => s.contact_height(x),
        }
    }
}

/// The whole model and its run settings.
#[derive(Debug, Clone, PartialEq)]
pub struct Model {
    pub basis: SineBasis,
    /// Span length when the layout repeats every span (enables the fast point sampler).
    pub span_m: Option<f64>,
    pub messenger: Wire,
    pub contact: Wire,
    pub droppers: Vec<Dropper>,
    pub supports: Vec<Support>,
    pub arms: Vec<Arm>,
    pub stitches: Vec<Stitch>,
    pub statics: StaticShape,
    pub pantographs: Vec<Pantograph>,
    pub contact_stiffness_n_per_m: f64,
    pub speed_m_s: f64,
    /// Leading pantograph position at t = 0.
    pub start_m: f64,
    /// Simulated duration, s.
    pub duration_s: f64,
    pub analysis_m: [f64; 2],
    pub dt_s: f64,
}

impl Model {
    /// Position of pantograph `p` at time `t`.
    pub fn pantograph_position(&self, p: usize, t: f64) -> f64 {
        self.start_m - self.pantographs[p].offset_m() + self.speed_m_s * t
    }

    /// Build the model of a validated case.
    ///
    /// Deviation from the paper: dropper clamp masses (and half of each dropper's own mass) are
    /// smeared into the wires' mass per metre instead of being point masses, as README §5 allows
    /// (σ changes by ≤ 1 N); point masses treated explicitly would be unstable. Steady-arm masses
    /// stay point masses, solved exactly in the mass matrix (see [`crate::solver`]).
    pub fn from_case(case: &Case) -> Result<(Model, Vec<Warning>), CaseError> {
        let warnings = case.validate()?;
        let c = &case.catenary;
        let stat = StaticSolution::solve(c);
        for (i, len) in stat.dropper_length_m.iter().enumerate() {
            if !len.is_finite() || *len <= 0.05 {
                return Err(CaseError::Invalid {
                    field: "catenary.encumbrance_m".into(),
                    value: c.encumbrance_m.to_string(),
                    reason: format!("the static messenger sags onto the contact wire: dropper {} would be {:.3} m long", i + 1, len),
                });
            }
        }
        let l = case.length_m();
        let basis = SineBasis::new(l, case.n_modes());
        let nd = c.droppers.positions_m.len() as f64;
        let mean_len = stat.dropper_length_m.iter().sum::<f64>() / nd;
        let half_dropper = 0.5 * c.droppers.mass_per_m_kg * mean_len;
        let rho_c = c.contact_wire.mass_per_m_kg
            + nd * (c.droppers.clamp_mass_contact_kg + half_dropper) / c.span_m;
        // Stitch droppers' upper clamps are the stitch nodes (own degrees of freedom).
        let n_on_messenger = nd - c.stitch_wire.as_ref().map_or(0, |st| st.droppers.len()) as f64;
        let rho_m = c.messenger.mass_per_m_kg
            + (n_on_messenger * c.droppers.clamp_mass_messenger_kg + nd * half_dropper) / c.span_m;
        let wire = |rho: f64, w: &crate::case::WireCase| {
            Wire::new(&basis, rho, w.tension_n, w.ei_nm2, c.damping.clone())
        };
        let mut droppers = Vec::new();
        let mut stitches = Vec::new();
        let sup = &c.messenger_support;
        for s in 0..c.spans {
            for (i, &d) in c.droppers.positions_m.iter().enumerate() {
                let x = s as f64 * c.span_m + d;
                let stitch = stat.stitch[i].map(|st| {
                    let damping = match c.stitch_wire.as_ref().and_then(|w| w.damping_ns_per_m) {
                        Some(cs) => cs,
                        None if sup.stiffness_n_per_m > 0.0 => {
                            sup.damping_ns_per_m / sup.stiffness_n_per_m * st.stiffness_n_per_m
                        }
                        None => 0.0,
                    };
                    stitches.push(Stitch {
                        x_m: x,
                        mass_kg: st.node_mass_kg,
                        stiffness_n_per_m: st.stiffness_n_per_m,
                        damping_ns_per_m: damping,
                    });
                    stitches.len() - 1
                });
                droppers.push(Dropper {
                    stitch,
                    x_m: x,
                    stiffness_n_per_m: match (c.droppers.stiffness_n_per_m, c.droppers.ea_n) {
                        (Some(k), _) => k,
                        (None, Some(ea)) => ea / stat.dropper_length_m[i],
                        (None, None) => unreachable!("validated"),
                    },
                    preload_n: stat.dropper_force_contact_n[i],
                });
            }
        }
        let supports = (1..c.spans)
            .map(|s| Support {
                x_m: s as f64 * c.span_m,
                stiffness_n_per_m: c.messenger_support.stiffness_n_per_m,
                damping_ns_per_m: c.messenger_support.damping_ns_per_m,
            })
            .collect();
        let arms = (1..c.spans)
            .map(|s| Arm {
                x_m: s as f64 * c.span_m,
                mass_kg: c.steady_arm.mass_kg,
                stiffness_n_per_m: c.steady_arm.stiffness_n_per_m,
            })
            .collect();
        let v_kmh = case.run.speed_kmh;
        let pantographs = case
            .pantographs
            .iter()
            .enumerate()
            .map(|(i, p)| match p {
                PantographCase::Lumped {
                    name,
                    offset_m,
                    masses_kg,
                    stiffness_n_per_m,
                    damping_ns_per_m,
                    uplift_n,
                    aero_coeffs_kmh,
                } => Pantograph::Lumped {
                    name: default_name(name, i),
                    offset_m: *offset_m,
                    masses_kg: masses_kg.clone(),
                    stiffness_n_per_m: stiffness_n_per_m.clone(),
                    damping_ns_per_m: damping_ns_per_m.clone(),
                    uplift_n: *uplift_n,
                    aero_n: aero_coeffs_kmh
                        .iter()
                        .rev()
                        .fold(0.0, |acc, ci| acc * v_kmh + ci),
                },
                PantographCase::MovingForce {
                    name,
                    offset_m,
                    force_n,
                } => Pantograph::MovingForce {
                    name: default_name(name, i),
                    offset_m: *offset_m,
                    force_n: *force_n,
                },
            })
            .collect::<Vec<_>>();
        // Explicit stability of the wire modes themselves (central differences: ω Δt < 2).
        for (name, w) in [
            ("contact_wire", &c.contact_wire),
            ("messenger", &c.messenger),
        ] {
            let rho = if name == "messenger" { rho_m } else { rho_c };
            let f = basis.max_frequency_hz(w.tension_n, w.ei_nm2, rho);
            let omega_dt = 2.0 * std::f64::consts::PI * f * case.run.dt_s;
            if omega_dt > 1.8 {
                return Err(CaseError::Invalid {
                    field: "run.dt_s".into(),
                    value: case.run.dt_s.to_string(),
                    reason: format!(
                        "too large for the highest {name} mode ({f:.0} Hz): the explicit scheme needs Δt < {:.2e} s (with margin)",
                        1.8 / (2.0 * std::f64::consts::PI * f)
                    ),
                });
            }
        }
        // Explicit stability of the stitch nodes.
        for st in stat.stitch.iter().flatten() {
            let k = st.stiffness_n_per_m
                + c.droppers
                    .stiffness_n_per_m
                    .unwrap_or(0.0)
                    .max(c.droppers.ea_n.map_or(0.0, |ea| {
                        ea / stat
                            .dropper_length_m
                            .iter()
                            .cloned()
                            .fold(f64::MAX, f64::min)
                    }));
            if (k / st.node_mass_kg).sqrt() * case.run.dt_s > 1.8 {
                return Err(CaseError::Invalid {
                    field: "run.dt_s".into(),
                    value: case.run.dt_s.to_string(),
                    reason: format!(
                        "too large for the stitch nodes ({} kg on {k:.0} N/m): explicit stability",
                        st.node_mass_kg
                    ),
                });
            }
        }
        // Explicit stability of the penalty contact and the pantograph springs (ω Δt below a
        // margin; the wire's own participating mass only lowers these frequencies).
        let dt = case.run.dt_s;
        for (i, p) in case.pantographs.iter().enumerate() {
            if let PantographCase::Lumped {
                masses_kg,
                stiffness_n_per_m,
                ..
            } = p
            {
                let kn = case.contact.stiffness_n_per_m;
                if (kn / masses_kg[0]).sqrt() * dt > 1.0 {
                    return Err(CaseError::Invalid {
                        field: "contact.stiffness_n_per_m".into(),
                        value: kn.to_string(),
                        reason: format!(
                            "too stiff for run.dt_s = {dt} s with a {} kg head: need √(k/m)·Δt < 1, i.e. Δt < {:.2e} s",
                            masses_kg[0],
                            (masses_kg[0] / kn).sqrt()
                        ),
                    });
                }
                for j in 0..masses_kg.len() {
                    let m_inv = 1.0 / masses_kg[j] + masses_kg.get(j + 1).map_or(0.0, |m| 1.0 / m);
                    if (stiffness_n_per_m[j] * m_inv).sqrt() * dt > 1.8 {
                        return Err(CaseError::Invalid {
                            field: format!("pantographs[{i}].stiffness_n_per_m[{j}]"),
                            value: stiffness_n_per_m[j].to_string(),
                            reason: format!("too stiff for run.dt_s = {dt} s (explicit stability)"),
                        });
                    }
                }
            }
        }
        let v = case.speed_m_s();
        let max_off = pantographs.iter().map(|p| p.offset_m()).fold(0.0, f64::max);
        let duration_s = (case.run.end_m - (case.run.start_m - max_off)) / v;
        let model = Model {
            basis: basis.clone(),
            span_m: Some(c.span_m),
            messenger: wire(rho_m, &c.messenger),
            contact: wire(rho_c, &c.contact_wire),
            droppers,
            supports,
            arms,
            stitches,
            statics: StaticShape::Catenary(Box::new(stat)),
            pantographs,
            contact_stiffness_n_per_m: case.contact.stiffness_n_per_m,
            speed_m_s: v,
            start_m: case.run.start_m,
            duration_s,
            analysis_m: case.run.analysis_m,
            dt_s: case.run.dt_s,
        };
        Ok((model, warnings))
    }
}

fn default_name(name: &str, i: usize) -> String {
    if !name.is_empty() {
        name.to_string()
    } else if i == 0 {
        "leading".to_string()
    } else {
        format!("pantograph-{}", i + 1)
    }
}

/// Builder for hand-made models (analytic checks, the test zoo).
#[derive(Debug, Clone)]
pub struct ModelBuilder {
    model: Model,
}

impl ModelBuilder {
    /// A single contact wire of length `length_m` with `n_modes` modes, flat static shape, a
    /// decoupled (idle) messenger, no point elements and no pantograph.
    pub fn single_wire(
        length_m: f64,
        n_modes: usize,
        mass_per_m: f64,
        tension_n: f64,
        ei_nm2: f64,
    ) -> Self {
        let basis = SineBasis::new(length_m, n_modes);
        let w = Wire::new(
            &basis,
            mass_per_m,
            tension_n,
            ei_nm2,
            Damping::Modal { ratio: 0.0 },
        );
        Self {
            model: Model {
                basis,
                span_m: None,
                messenger: w.clone(),
                contact: w,
                droppers: vec![],
                supports: vec![],
                arms: vec![],
                stitches: vec![],
                statics: StaticShape::Flat,
                pantographs: vec![],
                contact_stiffness_n_per_m: 50_000.0,
                speed_m_s: 0.0,
                start_m: 0.5 * length_m,
                duration_s: 1.0,
                analysis_m: [0.0, length_m],
                dt_s: 1e-3,
            },
        }
    }

    /// Wire damping for both wires.
    pub fn damping(mut self, d: &Damping) -> Self {
        let m = &mut self.model;
        for w in [&mut m.messenger, &mut m.contact] {
            *w = Wire::new(&m.basis, w.mass_per_m_kg, w.tension_n, w.ei_nm2, d.clone());
        }
        self
    }

    pub fn arm(mut self, a: Arm) -> Self {
        self.model.arms.push(a);
        self
    }

    pub fn pantograph(mut self, p: Pantograph) -> Self {
        self.model.pantographs.push(p);
        self
    }

    /// Speed (m/s), start position, duration and time step.
    pub fn run(mut self, speed_m_s: f64, start_m: f64, duration_s: f64, dt_s: f64) -> Self {
        let m = &mut self.model;
        m.speed_m_s = speed_m_s;
        m.start_m = start_m;
        m.duration_s = duration_s;
        m.dt_s = dt_s;
        self
    }

    pub fn build(self) -> Model {
        self.model
    }
}

/// Total static weight and support forces of a catenary model, for the balance check (N).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticBalance {
    /// Wire, clamp and dropper weights.
    pub weight_n: f64,
    /// Messenger supports plus steady arms (all supports, including both ends).
    pub support_n: f64,
}

/// Vertical static balance of the whole modelled catenary of `case`: every support (messenger
/// support, steady arm; the end supports carry half a span) against every weight.
pub fn static_balance(case: &Case) -> StaticBalance {
    let c = &case.catenary;
    let s = StaticSolution::solve(c);
    let l = case.length_m();
    let n = c.spans as f64;
    let dropper_w: f64 = s
        .dropper_length_m
        .iter()
        .map(|len| len * c.droppers.mass_per_m_kg * G)
        .sum();
    // Upper clamps: on the messenger, or the stitch clamp plus half a stitch wire per stitch dropper.
    let clamps: f64 = (0..c.droppers.positions_m.len())
        .map(|i| {
            let upper = match c.stitch_wire.as_ref().filter(|st| st.droppers.contains(&i)) {
                Some(st) => st.clamp_mass_kg + 0.5 * st.mass_per_m_kg * st.length_m,
                None => c.droppers.clamp_mass_messenger_kg,
            };
            (c.droppers.clamp_mass_contact_kg + upper) * G
        })
        .sum();
    let weight = (c.contact_wire.mass_per_m_kg + c.messenger.mass_per_m_kg) * G * l
        + n * (dropper_w + clamps);
    // Support forces from the kinks of the solved shapes at a support (not from load sums): the
    // messenger's kink is the messenger-support force; the steady arm carries the contact wire's
    // kink when it holds the design height (zero in a stitched catenary). Interior supports carry
    // one span's load and the two end supports half each: n spans in all.
    let sup = s.messenger.node_forces()[0];
    let support = n * (s.arm_force_n + sup);
    StaticBalance {
        weight_n: weight,
        support_n: support,
    }
}

impl Model {
    /// A window `[origin, origin + length]` of this (full) model, with its own sine basis of
    /// `n_modes` modes and the point elements that fall strictly inside it, in window coordinates
    /// (x − origin). `origin` should be a whole number of spans so that the span-periodic static
    /// shape reads the same in window coordinates. With `external`, the pantographs become
    /// [`Pantograph::External`] (HIL); otherwise they are kept, positions shifted (SIL).
    pub fn window(&self, origin_m: f64, length_m: f64, n_modes: usize, external: bool) -> Model {
        let basis = SineBasis::new(length_m, n_modes);
        let inside = |x: f64| x > origin_m + 1e-9 && x < origin_m + length_m - 1e-9;
        let mut stitch_map = vec![None; self.stitches.len()];
        let mut stitches = Vec::new();
        for (i, s) in self.stitches.iter().enumerate() {
            if inside(s.x_m) {
                stitch_map[i] = Some(stitches.len());
                stitches.push(Stitch {
                    x_m: s.x_m - origin_m,
                    ..s.clone()
                });
            }
        }
        let droppers = self
            .droppers
            .iter()
            .filter(|d| inside(d.x_m))
            .map(|d| Dropper {
                x_m: d.x_m - origin_m,
                stitch: d.stitch.and_then(|j| stitch_map[j]),
                ..d.clone()
            })
            .collect();
        let supports = self
            .supports
            .iter()
            .filter(|s| inside(s.x_m))
            .map(|s| Support {
                x_m: s.x_m - origin_m,
                ..s.clone()
            })
            .collect();
        let arms = self
            .arms
            .iter()
            .filter(|a| inside(a.x_m))
            .map(|a| Arm {
                x_m: a.x_m - origin_m,
                ..a.clone()
            })
            .collect();
        let rebase = |w: &Wire| {
            Wire::new(
                &basis,
                w.mass_per_m_kg,
                w.tension_n,
                w.ei_nm2,
                w.damping.clone(),
            )
        };
        let (messenger, contact) = (rebase(&self.messenger), rebase(&self.contact));
        let pantographs = if external {
            self.pantographs
                .iter()
                .map(|p| Pantograph::External {
                    name: p.name().to_string(),
                })
                .collect()
        } else {
            self.pantographs.clone()
        };
        Model {
            basis,
            // The point sampler uses the periodic path only when the window is whole spans.
            span_m: self.span_m,
            messenger,
            contact,
            droppers,
            supports,
            arms,
            stitches,
            statics: self.statics.clone(),
            pantographs,
            contact_stiffness_n_per_m: self.contact_stiffness_n_per_m,
            speed_m_s: self.speed_m_s,
            start_m: self.start_m - origin_m,
            duration_s: self.duration_s,
            analysis_m: [self.analysis_m[0] - origin_m, self.analysis_m[1] - origin_m],
            dt_s: self.dt_s,
        }
    }
}
