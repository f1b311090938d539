//! Hand-made models for analytic checks and the zoo ([`ModelBuilder`]). A case becomes a model in
//! the compile step (`compile::model`), not here.

use crate::model::basis::SineBasis;
use crate::model::dof::Direction;
use crate::model::elements::contact::{Contact, ContactLaw, Contacts};
use crate::model::elements::registration::{Registration, Registrations};
use crate::model::elements::section_insulator::{
    curvature_stiffness_n_per_m, SectionInsulator, SectionInsulators,
};
use crate::model::elements::steady_arm::{SteadyArm, SteadyArms};
use crate::model::elements::{Attach, PointElement};
use crate::model::pantograph::{Pantograph, PantographKind};
use crate::model::wind::WindLoad;
use crate::model::wire::{Damping, Section, Wire, WireRole};
use crate::model::{Model, StaticShape};

/// The plan of a hand-made run: speed (m/s), the leading pantograph's start, the duration and
/// the time step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BuilderRun {
    /// Train speed, m/s.
    pub speed_m_s: f64,
    /// The leading pantograph's start, m.
    pub start_m: f64,
    /// Duration of the run, s.
    pub duration_s: f64,
    /// Time step, s.
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
    dirs: Vec<Direction>,
    registrations: Vec<Registration>,
    insulators: Vec<SectionInsulator>,
    lateral_load_n_per_m: Option<f64>,
    vertical_load_n_per_m: f64,
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
            section: Section::vertical(mass_per_m, tension_n, ei_nm2),
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
            dirs: vec![Direction::Vertical],
            registrations: Vec::new(),
            insulators: Vec::new(),
            lateral_load_n_per_m: None,
            vertical_load_n_per_m: 0.0,
        }
    }

    /// Model lateral motion too (the lateral bending stiffness equals the vertical one).
    pub fn lateral(mut self) -> Self {
        if !self.dirs.contains(&Direction::Lateral) {
            self.dirs.push(Direction::Lateral);
        }
        self
    }

    /// Model torsion too, with torsional stiffness `G I_p` and polar mass moment `ρ I_p` per
    /// metre.
    pub fn torsion(mut self, gj_nm2: f64, polar_inertia_kg_m: f64) -> Self {
        self.section.gj_nm2 = gj_nm2;
        self.section.polar_inertia_kg_m = polar_inertia_kg_m;
        if !self.dirs.contains(&Direction::Torsional) {
            self.dirs.push(Direction::Torsional);
        }
        self
    }

    /// A lateral spring to ground (a registration) at `x_m` (needs [`Self::lateral`]).
    pub fn registration(mut self, x_m: f64, stiffness_n_per_m: f64) -> Self {
        self.registrations.push(Registration {
            at: Attach::Wire {
                wire: 0,
                dir: Direction::Lateral,
                x_m,
            },
            twist: Attach::Ground,
            eccentricity_m: 0.0,
            stiffness_n_per_m,
            mass_kg: 0.0,
            vertical_force_n: 0.0,
            torsional_stiffness_nm_per_rad: 0.0,
        });
        self
    }

    /// A steady uniform lateral load `q` (N/m) on the wire (needs [`Self::lateral`]); the
    /// initial state is its static deflection.
    pub fn uniform_lateral_load(mut self, q_n_per_m: f64) -> Self {
        self.lateral_load_n_per_m = Some(q_n_per_m);
        self
    }

    /// A steady uniform vertical load `q` (N/m, upward positive) that the static shape does not
    /// carry (as ice's weight, [`Wire::static_load_per_m`]); the initial state is its static
    /// deflection.
    pub fn uniform_vertical_load(mut self, q_n_per_m: f64) -> Self {
        self.vertical_load_n_per_m = q_n_per_m;
        self
    }

    /// The wire's damping law.
    pub fn damping(mut self, d: &Damping) -> Self {
        self.damping = d.clone();
        self
    }

    /// A second, uncoupled wire over the same basis (a messenger with no droppers), for checks
    /// that need more than one block.
    pub fn uncoupled_messenger(mut self, mass_per_m: f64, tension_n: f64, ei_nm2: f64) -> Self {
        self.messenger = Some(Section::vertical(mass_per_m, tension_n, ei_nm2));
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

    /// A section insulator in the vertical direction centred at `x_m`: `length_m` long, its
    /// mass at the centre, `added_ei_nm2` stiffer in bending than the wire
    /// ([`crate::model::elements::section_insulator`]).
    pub fn section_insulator(
        mut self,
        x_m: f64,
        length_m: f64,
        mass_kg: f64,
        added_ei_nm2: f64,
    ) -> Self {
        let at = |x_m| Attach::Wire {
            wire: 0,
            dir: Direction::Vertical,
            x_m,
        };
        self.insulators.push(SectionInsulator {
            at: [at(x_m - 0.5 * length_m), at(x_m), at(x_m + 0.5 * length_m)],
            mass_kg,
            curvature_n_per_m: curvature_stiffness_n_per_m(added_ei_nm2, length_m),
        });
        self
    }

    /// A constant upward force moving with the run's speed.
    pub fn moving_force(self, name: &str, force_n: f64) -> Self {
        self.moving_force_3d(name, force_n, 0.0)
    }

    /// A constant moving force with a lateral part too (applied when lateral motion is
    /// modelled, [`Self::lateral`]).
    pub fn moving_force_3d(mut self, name: &str, force_n: f64, lateral_force_n: f64) -> Self {
        self.pantographs.push(Pantograph {
            name: name.to_string(),
            offset_m: 0.0,
            kind: PantographKind::MovingForce {
                force_n,
                lateral_force_n,
            },
            head_half_width_m: None,
            working_half_width_m: None,
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
        let mut dirs = self.dirs.clone();
        dirs.sort();
        let mut wires = vec![Wire::new(
            "contact_wire",
            WireRole::Contact,
            0.0,
            basis.clone(),
            self.section,
            self.damping.clone(),
            &dirs,
        )
        .with_static_load(Direction::Vertical, self.vertical_load_n_per_m)];
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
        let np = self.pantographs.len();
        let lateral_probe = self.dirs.contains(&Direction::Lateral);
        let contacts = Contacts(
            (0..np)
                .map(|p| Contact {
                    pantograph: p,
                    head: 0,
                    along_m: 0.0,
                    wire: 0,
                    dir: Direction::Vertical,
                    law: ContactLaw::prescribed(Direction::Vertical, p, np),
                    eccentricity_m: 0.0,
                    twist: false,
                })
                .chain((0..np).filter(|_| lateral_probe).map(|p| Contact {
                    pantograph: p,
                    head: 0,
                    along_m: 0.0,
                    wire: 0,
                    dir: Direction::Lateral,
                    law: ContactLaw::prescribed(Direction::Lateral, p, np),
                    eccentricity_m: 0.0,
                    twist: false,
                }))
                .collect(),
        );
        let mut elements: Vec<Box<dyn PointElement>> = vec![Box::new(SteadyArms(self.arms))];
        if !self.registrations.is_empty() {
            elements.push(Box::new(Registrations(self.registrations)));
        }
        if !self.insulators.is_empty() {
            elements.push(Box::new(SectionInsulators(self.insulators)));
        }
        elements.push(Box::new(contacts));
        let mut model = Model::new(
            wires,
            vec![],
            elements,
            self.pantographs,
            StaticShape::Flat,
            None,
        );
        model.wind = self
            .lateral_load_n_per_m
            .map(|q| WindLoad::uniform_lateral(0, q));
        (model, self.run)
    }
}
