//! Building an integrator: the one place where compiling, the static start, the stability
//! proof and the Δt operators meet. `integrator.rs` knows only the proof's type
//! ([`crate::solve::limits::StableStep`]) and `stability.rs` probes the compiled step through an integrator of its
//! own, so neither imports the other's constructor: the imports point one way
//! (construct → stability → integrator).

use crate::error::CaseError;
use crate::model::Model;
use crate::solve::compiled::CompiledModel;
use crate::solve::integrator::Integrator;
use crate::solve::plan::{Options, Plan};
use crate::solve::stability::check_stability;

impl Integrator {
    /// Precompute everything a step needs: compile the model (and solve its static start under
    /// the steady loads, [`crate::solve::equilibrium`]), check that the time step is stable for
    /// its explicit parts, local and coupled ([`check_stability`]), and build the Δt operators
    /// on that proof (Eq. 18's scheme).
    pub fn new(model: Model, plan: &Plan, options: Options) -> Result<Self, CaseError> {
        let mut cm = CompiledModel::new(model, plan, options.isa)?;
        cm.initial = crate::solve::equilibrium::static_start(&cm)?;
        let stable = check_stability(&cm, plan, options.dt_s)?;
        Integrator::from_compiled(cm, plan, stable.dt_s())
            .map(|integ| integ.with_limit(stable.limit().clone(), options.threads))
    }
}
