//! The method: a model and a plan become an [`Integrator`] that steps a [`State`] with a
//! [`Workspace`], in the one [`run()`] loop, or in the real-time window. Nothing here reads a case:
//! the compile step (the `compile` module) turns a case into the model, the plan and the options.
//!
//! | file | what it holds |
//! |---|---|
//! | `plan.rs` | the run's plan (speed, start, duration, analysis section) and the options (Δt) |
//! | `state.rs` | the state: modal blocks, nodes, pantographs, time, the model's place on the track |
//! | `workspace.rs` | scratch sized once, the step's samples, external inputs |
//! | `sampler.rs` | point sines × modal coordinates over any number of blocks (the hot spot) |
//! | `nufft.rs` | point sines at arbitrary positions: the non-uniform fast sine transform (gridding, one FFT per two blocks) |
//! | `implicit.rs` | implicit point masses and dampers (Woodbury) |
//! | `compiled.rs` | the compiled model: slots, point groups, moving points, monitors, probes, the energy view (no Δt) |
//! | `equilibrium.rs` | the static start state under the steady loads (mean crosswind, ice): Newton on the compiled residual |
//! | `integrator.rs` | the stepper: the Δt operators, the step (Eq. 18) in eight named stages |
//! | `pantographs.rs` | the solver's side of a pantograph: its chain's operators and rest, its heads, its prescribed loads, its half kick, its limits on Δt |
//! | `stability.rs` | Δt against the local limits and the coupled system's highest frequency (power iteration) |
//! | `construct.rs` | `Integrator::new`: compile, static start, the stability proof, the Δt operators |
//! | `run.rs` | the run loop with observers, blow-up checks, run statistics |
//! | `team.rs` | one run on several threads: the step's per-group work in parts, a spinning fork–join team |
//! | `realtime.rs` | the moving-window catenary for HIL |

pub mod compiled;
pub mod construct;
pub mod equilibrium;
pub mod implicit;
pub mod integrator;
pub mod kernels;
pub mod limits;
pub mod nufft;
pub mod pantographs;
pub mod plan;
pub mod realtime;
pub mod run;
pub mod sampler;
pub mod stability;
pub mod state;
pub mod team;
pub mod workspace;

pub use compiled::CompiledModel;
pub use integrator::{Integrator, Stage};
pub use kernels::Isa;
pub use plan::{Options, Plan};
pub use run::{run, Observer, RunStatistics};
pub use stability::{CoupledLimit, StableStep};
pub use state::State;
pub use workspace::{ContactSample, ExternalInput, Workspace};
