//! The method: a case's model and plan become an [`Integrator`] that steps a [`State`] with a
//! [`Workspace`], in the one [`run()`] loop, or in the real-time window.
//!
//! | file | what it holds |
//! |---|---|
//! | `plan.rs` | the run's plan (speed, start, duration, analysis section) and the options (Δt) |
//! | `state.rs` | the state: modal blocks, nodes, pantographs, time, the model's place on the track |
//! | `workspace.rs` | scratch sized once, the step's samples, external inputs |
//! | `sampler.rs` | point sines × modal coordinates over any number of blocks (the hot spot) |
//! | `implicit.rs` | implicit point masses and dampers (Woodbury) |
//! | `integrator.rs` | the step (Eq. 18), the stability checks |
//! | `run.rs` | the run loop with observers, blow-up checks, run statistics |
//! | `realtime.rs` | the moving-window catenary for HIL |

pub mod budget;
pub mod implicit;
pub mod integrator;
pub mod kernels;
pub mod plan;
pub mod realtime;
pub mod run;
pub mod sampler;
pub mod state;
pub mod workspace;

pub use budget::{Budget, Estimate};
pub use integrator::Integrator;
pub use kernels::Isa;
pub use plan::{Options, Plan};
pub use run::{run, Observer, RunStatistics};
pub use state::State;
pub use workspace::{ContactSample, Workspace};

use crate::error::CaseError;
use crate::input::case::{Case, Warning};
use crate::model::build::BuilderRun;
use crate::model::Model;

/// What a case becomes: the model (the problem), the plan of the run and the integrator's
/// options, with the warnings found on the way.
#[derive(Debug, Clone)]
pub struct Setup {
    pub model: Model,
    pub plan: Plan,
    pub options: Options,
    pub warnings: Vec<Warning>,
}

impl Setup {
    /// Validate a case and build its model, plan and options, within the default [`Budget`].
    pub fn from_case(case: &Case) -> Result<Setup, CaseError> {
        Self::from_case_with(case, &Budget::default())
    }

    /// [`Setup::from_case`] within a given budget: the run's steps and memory are estimated
    /// from the case before anything is built, and refused with an error naming the cause when
    /// they exceed it.
    pub fn from_case_with(case: &Case, budget: &Budget) -> Result<Setup, CaseError> {
        case.validate()?;
        budget.check(case)?;
        let (model, mut warnings) = Model::from_case(case)?;
        let plan = Plan::from_case(case);
        warnings.extend(plan.check(&model)?);
        let options = Options::new(case.run.dt_s);
        integrator::check_stability(&model, options.dt_s)?;
        Ok(Setup {
            model,
            plan,
            options,
            warnings,
        })
    }

    /// A hand-made model and its run (`model::ModelBuilder`).
    pub fn from_builder((model, run): (Model, BuilderRun)) -> Setup {
        let length = model.length_m();
        Setup {
            model,
            plan: Plan {
                speed_kmh: run.speed_m_s * 3.6,
                speed_m_s: run.speed_m_s,
                start_m: run.start_m,
                duration_s: run.duration_s,
                analysis_m: [0.0, length],
            },
            options: Options::new(run.dt_s),
            warnings: Vec::new(),
        }
    }

    /// The integrator of this set-up.
    pub fn integrator(&self) -> Result<Integrator, CaseError> {
        Integrator::new(self.model.clone(), &self.plan, self.options)
    }

    /// Number of steps of the run.
    pub fn n_steps(&self) -> usize {
        self.plan.n_steps(self.options.dt_s)
    }
}

/// An integrator with its state and workspace: the convenient way to step a set-up by hand.
#[derive(Debug, Clone)]
pub struct Stepper {
    pub integ: Integrator,
    pub state: State,
    pub ws: Workspace,
}

impl Stepper {
    /// A stepper at the initial (static) state of the set-up.
    pub fn new(setup: &Setup) -> Result<Stepper, CaseError> {
        let integ = setup.integrator()?;
        let state = integ.initial_state(setup.plan.start_m);
        let ws = integ.workspace();
        Ok(Stepper { integ, state, ws })
    }

    /// One step.
    pub fn step(&mut self) {
        self.integ.step(&mut self.state, &mut self.ws);
    }

    /// The model.
    pub fn model(&self) -> &Model {
        self.integ.model()
    }

    /// Contact samples of the last step.
    pub fn samples(&self) -> &[ContactSample] {
        self.ws.samples()
    }
}
