//! The one run loop: steps an integrator, checks for blow-up, counts what it sees, and hands
//! every step to its observers (the EN 50318 recorder, the energy sampler, the window mover).
//!
//! Blow-up: a non-finite value, a contact force above 1 MN or a contact wire further from its
//! design height than the system height (it would have passed the messenger;
//! [`CompiledModel::max_wire_deviation_m`]) stops the run with the time and place. Growth from a
//! time step too large for the coupled system is refused before the run
//! ([`crate::solve::stability`]).

use serde::Serialize;

use crate::error::SimError;
use crate::model::PantographKind;
use crate::solve::compiled::CompiledModel;
use crate::solve::integrator::Integrator;
use crate::solve::state::State;
use crate::solve::team::with_team;
use crate::solve::workspace::Workspace;

/// What a run loop counted: the solver's statistics, snapshot-tested on the zoo so that a silent
/// change of the algorithm shows in review.
#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, serde::Deserialize, schemars::JsonSchema,
)]
pub struct RunStatistics {
    /// Time steps taken.
    pub steps: u64,
    /// Steps with at least one slack dropper.
    pub steps_with_slack_dropper: u64,
    /// The most droppers slack at once.
    pub max_slack_droppers: u64,
    /// Steps in which at least one pantograph lost contact (zero contact force).
    pub steps_with_contact_loss: u64,
    /// Moves of a real-time window (0 for a full-model run).
    pub window_moves: u64,
    /// Blow-up checks made (one per step on the contact samples, one every 256 steps on the
    /// whole state).
    pub blow_up_checks: u64,
}

/// Something that watches a run, step by step, through the compiled model (never the stepper). It may change the state (a moving window
/// carries it over to its new place).
pub trait Observer {
    /// Called after every step that passed the blow-up check.
    fn observe(
        &mut self,
        cm: &CompiledModel,
        st: &mut State,
        ws: &Workspace,
    ) -> Result<(), SimError>;

    /// Window moves made so far (for the run statistics).
    fn moves(&self) -> u64 {
        0
    }

    /// Whether this observer has seen all it needs: the run loop stops early once every one of
    /// its observers says so (a recorder of the whole run never does; the energy sampler does
    /// once the pantograph has left its analysis section).
    fn finished(&self) -> bool {
        false
    }
}

/// How often the whole state is checked and progress reported, steps.
pub const CHECK_EVERY: usize = 256;

/// Step `n_steps` times, or until every observer is [`Observer::finished`] (none is given: all
/// the steps). `progress(fraction)` is called every [`CHECK_EVERY`] steps; returning `false`
/// cancels the run. An integrator built for several threads
/// ([`Integrator::threads`], `Options::threads`) steps with a team of that many
/// ([`crate::solve::team`]): the same bytes, sooner on a long line.
pub fn run(
    integ: &Integrator,
    st: &mut State,
    ws: &mut Workspace,
    n_steps: usize,
    observers: &mut [&mut dyn Observer],
    progress: &mut dyn FnMut(f64) -> bool,
) -> Result<RunStatistics, SimError> {
    // One thread: the team has no helper, and `step_team` is `step`.
    with_team(integ.threads(), |team| {
        let mut rs = RunStatistics::default();
        let pans = &integ.model().pantographs;
        let max_h = integ.compiled().max_wire_deviation_m();
        for step in 0..n_steps {
            integ.step_team(team, st, ws);
            rs.steps += 1;
            let slack = ws.slack_droppers() as u64;
            rs.max_slack_droppers = rs.max_slack_droppers.max(slack);
            rs.steps_with_slack_dropper += (slack > 0) as u64;
            if ws
                .samples()
                .iter()
                .zip(pans)
                .any(|(s, p)| matches!(p.kind, PantographKind::Lumped(_)) && s.force_n <= 0.0)
            {
                rs.steps_with_contact_loss += 1;
            }
            rs.blow_up_checks += 1;
            for (p, s) in ws.samples().iter().enumerate() {
                if !s.is_sound(max_h) {
                    return Err(SimError::BlowUp {
                        time_s: st.t,
                        position_m: s.position_m + st.track_origin_m,
                        what: s.fault(p, max_h).unwrap_or_default(),
                    });
                }
            }
            for o in observers.iter_mut() {
                o.observe(integ.compiled(), st, ws)?;
            }
            let finished = !observers.is_empty() && observers.iter().all(|o| o.finished());
            if step % CHECK_EVERY == 0 || finished {
                rs.blow_up_checks += 1;
                if !st.is_finite() {
                    return Err(SimError::BlowUp {
                        time_s: st.t,
                        position_m: integ.position(st, 0) + st.track_origin_m,
                        what: "non-finite state".into(),
                    });
                }
                if !progress(step as f64 / n_steps as f64) {
                    return Err(SimError::Cancelled);
                }
            }
            if finished {
                break;
            }
        }
        progress(1.0);
        rs.window_moves = observers.iter().map(|o| o.moves()).sum();
        Ok(rs)
    })
}
