//! A case becomes a model ([`Model::from_case`]); hand-made models for analytic checks and the
//! zoo come from [`ModelBuilder`]. This is where every element kind is registered.

use crate::error::CaseError;
use crate::input::case::{Case, Damping, PantographCase, Warning, WireCase, G};
use crate::model::basis::SineBasis;
use crate::model::dof::Direction;
use crate::model::elements::contact::{Contact, ContactLaw, Contacts};
use crate::model::elements::dropper::{Dropper, Droppers};
use crate::model::elements::steady_arm::{SteadyArm, SteadyArms};
use crate::model::elements::stitch::{Stitch, Stitches};
use crate::model::elements::support::{Support, Supports};
use crate::model::elements::{Attach, PointElement};
use crate::model::pantograph::{Lumped, Pantograph, PantographKind};
use crate::model::statics::StaticSolution;
use crate::model::wire::{Section, Wire, WireRole};
use crate::model::{Model, Node, StaticShape};

/// Index of the messenger and of the contact wire in a catenary model built from a case.
pub const MESSENGER: usize = 0;
pub const CONTACT: usize = 1;

fn section(mass_per_m_kg: f64, w: &WireCase) -> Section {
    Section {
        mass_per_m_kg,
        tension_n: w.tension_n,
        ei_vertical_nm2: w.ei_nm2,
        ei_lateral_nm2: w.ei_nm2,
        gj_nm2: 0.0,
        polar_inertia_kg_m: 0.0,
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

/// The pantographs of a case, and one contact per pantograph on the contact wire.
fn pantographs(case: &Case, contact_wire: usize) -> (Vec<Pantograph>, Contacts) {
    let mut contacts = Vec::new();
    let pans = case
        .pantographs
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let (name, offset_m, kind, law) = match p {
                PantographCase::Lumped {
                    name,
                    offset_m,
                    masses_kg,
                    stiffness_n_per_m,
                    damping_ns_per_m,
                    uplift_n,
                    aero_coeffs_kmh,
                } => (
                    name,
                    offset_m,
                    PantographKind::Lumped(Lumped {
                        masses_kg: masses_kg.clone(),
                        stiffness_n_per_m: stiffness_n_per_m.clone(),
                        damping_ns_per_m: damping_ns_per_m.clone(),
                        uplift_n: *uplift_n,
                        aero_coeffs_kmh: aero_coeffs_kmh.clone(),
                    }),
                    ContactLaw::Penalty {
                        stiffness_n_per_m: case.contact.stiffness_n_per_m,
                    },
                ),
                PantographCase::MovingForce {
                    name,
                    offset_m,
                    force_n,
                } => (
                    name,
                    offset_m,
                    PantographKind::MovingForce { force_n: *force_n },
                    ContactLaw::Prescribed,
                ),
            };
            contacts.push(Contact {
                pantograph: i,
                wire: contact_wire,
                dir: Direction::Vertical,
                law,
            });
            Pantograph {
                name: default_name(name, i),
                offset_m: *offset_m,
                kind,
            }
        })
        .collect();
    (pans, Contacts(contacts))
}

impl Model {
    /// Build the model of a case (validated first).
    ///
    /// Deviation from the paper: dropper clamp masses (and half of each dropper's own mass) are
    /// smeared into the wires' mass per metre instead of being point masses, as the reference
    /// README §5 allows (σ changes by ≤ 1 N); point masses treated explicitly would be unstable.
    /// Steady-arm masses stay point masses, solved exactly in the mass matrix.
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
        let vertical = [Direction::Vertical];
        let wires = vec![
            Wire::new(
                "messenger",
                WireRole::Messenger,
                0.0,
                basis.clone(),
                section(rho_m, &c.messenger),
                c.damping.clone(),
                &vertical,
            ),
            Wire::new(
                "contact_wire",
                WireRole::Contact,
                0.0,
                basis,
                section(rho_c, &c.contact_wire),
                c.damping.clone(),
                &vertical,
            ),
        ];
        let on = |wire: usize, x_m: f64| Attach::Wire {
            wire,
            dir: Direction::Vertical,
            x_m,
        };
        let mut droppers = Vec::new();
        let mut stitches = Vec::new();
        let mut nodes = Vec::new();
        let sup = &c.messenger_support;
        for s in 0..c.spans {
            for (i, &d) in c.droppers.positions_m.iter().enumerate() {
                let x = s as f64 * c.span_m + d;
                let top = match stat.stitch[i] {
                    Some(st) => {
                        let damping = match c.stitch_wire.as_ref().and_then(|w| w.damping_ns_per_m)
                        {
                            Some(cs) => cs,
                            None if sup.stiffness_n_per_m > 0.0 => {
                                sup.damping_ns_per_m / sup.stiffness_n_per_m * st.stiffness_n_per_m
                            }
                            None => 0.0,
                        };
                        nodes.push(Node {
                            x_m: x,
                            mass_kg: st.node_mass_kg,
                            dir: Direction::Vertical,
                        });
                        let node = Attach::Node(nodes.len() - 1);
                        stitches.push(Stitch {
                            wire: on(MESSENGER, x),
                            node,
                            stiffness_n_per_m: st.stiffness_n_per_m,
                            damping_ns_per_m: damping,
                        });
                        node
                    }
                    None => on(MESSENGER, x),
                };
                droppers.push(Dropper {
                    x_m: x,
                    stiffness_n_per_m: match (c.droppers.stiffness_n_per_m, c.droppers.ea_n) {
                        (Some(k), _) => k,
                        (None, Some(ea)) => ea / stat.dropper_length_m[i],
                        (None, None) => unreachable!("validated"),
                    },
                    preload_n: stat.dropper_force_contact_n[i],
                    top,
                    bottom: on(CONTACT, x),
                });
            }
        }
        let supports = (1..c.spans)
            .map(|s| Support {
                at: on(MESSENGER, s as f64 * c.span_m),
                stiffness_n_per_m: c.messenger_support.stiffness_n_per_m,
                damping_ns_per_m: c.messenger_support.damping_ns_per_m,
            })
            .collect();
        let arms = (1..c.spans)
            .map(|s| SteadyArm {
                at: on(CONTACT, s as f64 * c.span_m),
                mass_kg: c.steady_arm.mass_kg,
                stiffness_n_per_m: c.steady_arm.stiffness_n_per_m,
            })
            .collect();
        let (pans, contacts) = pantographs(case, CONTACT);
        // The registration of every element kind, in the order their forces are evaluated.
        let elements: Vec<Box<dyn PointElement>> = vec![
            Box::new(Droppers(droppers)),
            Box::new(Supports(supports)),
            Box::new(SteadyArms(arms)),
            Box::new(Stitches(stitches)),
            Box::new(contacts),
        ];
        let model = Model::new(
            wires,
            nodes,
            elements,
            pans,
            StaticShape::Catenary(Box::new(stat)),
            Some(c.span_m),
        );
        Ok((model, warnings))
    }
}

/// The plan of a hand-made run: speed (m/s), the leading pantograph's start, the duration and
/// the time step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BuilderRun {
    pub speed_m_s: f64,
    pub start_m: f64,
    pub duration_s: f64,
    pub dt_s: f64,
}

/// Builder for hand-made models (analytic checks, the zoo): one contact wire, a flat static
/// shape, point masses on springs, moving forces.
#[derive(Debug, Clone)]
pub struct ModelBuilder {
    length_m: f64,
    n_modes: usize,
    section: Section,
    messenger: Option<Section>,
    damping: Damping,
    arms: Vec<SteadyArm>,
    pantographs: Vec<Pantograph>,
    run: BuilderRun,
}

impl ModelBuilder {
    /// A single contact wire of length `length_m` with `n_modes` vertical modes, no damping, a
    /// flat static shape, no point elements and no pantograph.
    pub fn single_wire(
        length_m: f64,
        n_modes: usize,
        mass_per_m: f64,
        tension_n: f64,
        ei_nm2: f64,
    ) -> Self {
        Self {
            length_m,
            n_modes,
            section: Section {
                mass_per_m_kg: mass_per_m,
                tension_n,
                ei_vertical_nm2: ei_nm2,
                ei_lateral_nm2: ei_nm2,
                gj_nm2: 0.0,
                polar_inertia_kg_m: 0.0,
            },
            messenger: None,
            damping: Damping::Modal { ratio: 0.0 },
            arms: Vec::new(),
            pantographs: Vec::new(),
            run: BuilderRun {
                speed_m_s: 0.0,
                start_m: 0.5 * length_m,
                duration_s: 1.0,
                dt_s: 1e-3,
            },
        }
    }

    /// The wire's damping law.
    pub fn damping(mut self, d: &Damping) -> Self {
        self.damping = d.clone();
        self
    }

    /// A second, uncoupled wire over the same basis (a messenger with no droppers), for checks
    /// that need more than one block.
    pub fn uncoupled_messenger(mut self, mass_per_m: f64, tension_n: f64, ei_nm2: f64) -> Self {
        self.messenger = Some(Section {
            mass_per_m_kg: mass_per_m,
            tension_n,
            ei_vertical_nm2: ei_nm2,
            ei_lateral_nm2: ei_nm2,
            gj_nm2: 0.0,
            polar_inertia_kg_m: 0.0,
        });
        self
    }

    /// A point mass on a spring to ground at `x_m` (a steady arm).
    pub fn point_mass(mut self, x_m: f64, mass_kg: f64, stiffness_n_per_m: f64) -> Self {
        self.arms.push(SteadyArm {
            at: Attach::Wire {
                wire: 0,
                dir: Direction::Vertical,
                x_m,
            },
            mass_kg,
            stiffness_n_per_m,
        });
        self
    }

    /// A constant upward force moving with the run's speed.
    pub fn moving_force(mut self, name: &str, force_n: f64) -> Self {
        self.pantographs.push(Pantograph {
            name: name.to_string(),
            offset_m: 0.0,
            kind: PantographKind::MovingForce { force_n },
        });
        self
    }

    /// Speed (m/s), start position, duration and time step.
    pub fn run(mut self, speed_m_s: f64, start_m: f64, duration_s: f64, dt_s: f64) -> Self {
        self.run = BuilderRun {
            speed_m_s,
            start_m,
            duration_s,
            dt_s,
        };
        self
    }

    /// The model and its run.
    pub fn build(self) -> (Model, BuilderRun) {
        let basis = SineBasis::new(self.length_m, self.n_modes);
        let mut wires = vec![Wire::new(
            "contact_wire",
            WireRole::Contact,
            0.0,
            basis.clone(),
            self.section,
            self.damping.clone(),
            &[Direction::Vertical],
        )];
        if let Some(m) = self.messenger {
            wires.push(Wire::new(
                "messenger",
                WireRole::Messenger,
                0.0,
                basis,
                m,
                self.damping,
                &[Direction::Vertical],
            ));
        }
        let contacts = Contacts(
            (0..self.pantographs.len())
                .map(|p| Contact {
                    pantograph: p,
                    wire: 0,
                    dir: Direction::Vertical,
                    law: ContactLaw::Prescribed,
                })
                .collect(),
        );
        let elements: Vec<Box<dyn PointElement>> =
            vec![Box::new(SteadyArms(self.arms)), Box::new(contacts)];
        (
            Model::new(
                wires,
                vec![],
                elements,
                self.pantographs,
                StaticShape::Flat,
                None,
            ),
            self.run,
        )
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
