//! The run driver: steps a [`Solver`] over the run, records what the pantographs see, checks for
//! blow-up, and computes the EN 50318 statistics.
//!
//! Blow-up: a non-finite value, a contact force above 1 MN or a contact-wire height more than 2 m
//! from the design height (no catenary moves that far) stops the run with the time and place.

use crate::case::Case;
use crate::error::SimError;
use crate::filter::lowpass_zero_phase;
use crate::model::Model;
use crate::solver::Solver;
use crate::stats::{contact_stats, ContactStats, CUTOFF_HZ};

/// Time histories of one pantograph.
#[derive(Debug, Clone, PartialEq)]
pub struct PantographTrace {
    pub name: String,
    pub position_m: Vec<f64>,
    /// Raw contact force, N.
    pub force_n: Vec<f64>,
    /// Contact force low-pass filtered at 20 Hz with zero phase, N.
    pub force_filtered_n: Vec<f64>,
    /// Contact-wire height at the contact point, m.
    pub wire_height_m: Vec<f64>,
    /// See [`ContactStats::max_uplift_at_support_mm`], m.
    pub max_uplift_at_support_m: f64,
    pub stats: Option<ContactStats>,
}

/// Everything a run produced.
#[derive(Debug, Clone, PartialEq)]
pub struct RunOutput {
    pub speed_m_s: f64,
    pub dt_s: f64,
    pub time_s: Vec<f64>,
    pub analysis_m: [f64; 2],
    pub pantographs: Vec<PantographTrace>,
    /// Largest number of droppers slack at once.
    pub max_slack_droppers: usize,
    /// Share of steps with at least one slack dropper, %.
    pub steps_with_slack_percent: f64,
    pub n_modes: usize,
    /// Counters of what the run loop saw (snapshot-tested on the zoo).
    pub run_statistics: RunStatistics,
}

/// What a run loop counted: the solver's statistics, snapshot-tested on the zoo so that a silent
/// change of the algorithm shows in review.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
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
    /// modal coordinates).
    pub blow_up_checks: u64,
}

impl RunOutput {
    /// Simulated time, s.
    pub fn simulated_time_s(&self) -> f64 {
        self.time_s.last().copied().unwrap_or(0.0)
    }
}

/// Run a case (validates it first).
pub fn run_case(case: &Case, progress: &mut dyn FnMut(f64) -> bool) -> Result<RunOutput, SimError> {
    let (model, _) = Model::from_case(case)?;
    simulate(model, progress)
}

/// Simulate `model` for its duration. `progress(fraction)` is called every few hundred steps;
/// returning `false` cancels the run.
pub fn simulate(
    model: Model,
    progress: &mut dyn FnMut(f64) -> bool,
) -> Result<RunOutput, SimError> {
    let n_steps = (model.duration_s / model.dt_s).ceil() as usize;
    let np = model.pantographs.len();
    let mut solver = Solver::new(model);
    let mut st = solver.initial_state();
    let m = solver.model().clone();
    let mut time = Vec::with_capacity(n_steps);
    let mut pos = vec![Vec::with_capacity(n_steps); np];
    let mut force = vec![Vec::with_capacity(n_steps); np];
    let mut height = vec![Vec::with_capacity(n_steps); np];
    let mut uplift = vec![0.0f64; np];
    let mut max_slack = 0;
    let mut steps_slack = 0usize;
    let mut rs = RunStatistics::default();
    for step in 0..n_steps {
        solver.step(&mut st);
        time.push(st.t);
        let slack = solver.slack_droppers();
        max_slack = max_slack.max(slack);
        steps_slack += (slack > 0) as usize;
        rs.steps += 1;
        rs.blow_up_checks += 1;
        if solver
            .samples()
            .iter()
            .zip(&m.pantographs)
            .any(|(s, p)| matches!(p, crate::model::Pantograph::Lumped { .. }) && s.force_n <= 0.0)
        {
            rs.steps_with_contact_loss += 1;
        }
        for (p, s) in solver.samples().iter().enumerate() {
            if !s.is_sound() {
                return Err(SimError::BlowUp {
                    time_s: st.t,
                    position_m: s.position_m,
                    what: format!(
                        "contact force {} N, wire height {} m at pantograph {}",
                        s.force_n, s.wire_height_m, p
                    ),
                });
            }
            pos[p].push(s.position_m);
            force[p].push(s.force_n);
            height[p].push(s.wire_height_m);
            if let Some(span) = m.span_m {
                let j = (s.position_m / span).round();
                let xs = j * span;
                let ji = j as usize;
                if ji >= 1 && ji <= m.arms.len() && xs >= m.analysis_m[0] && xs <= m.analysis_m[1] {
                    uplift[p] = uplift[p].max(solver.arm_displacements()[ji - 1]);
                }
            }
        }
        if step % 256 == 0 {
            rs.blow_up_checks += 1;
            let norm: f64 = st.qc.iter().chain(&st.qm).map(|v| v * v).sum();
            if !norm.is_finite() || st.py.iter().flatten().any(|v| !v.is_finite()) {
                return Err(SimError::BlowUp {
                    time_s: st.t,
                    position_m: m.pantograph_position(0, st.t),
                    what: "non-finite modal coordinates".into(),
                });
            }
            if !progress(step as f64 / n_steps as f64) {
                return Err(SimError::Cancelled);
            }
        }
    }
    progress(1.0);
    let fs = 1.0 / m.dt_s;
    let pantographs = (0..np)
        .map(|p| {
            let filtered = lowpass_zero_phase(&force[p], fs, CUTOFF_HZ);
            let stats = contact_stats(
                &force[p],
                &pos[p],
                &height[p],
                m.dt_s,
                m.analysis_m,
                uplift[p],
            );
            PantographTrace {
                name: m.pantographs[p].name().to_string(),
                position_m: std::mem::take(&mut pos[p]),
                force_n: std::mem::take(&mut force[p]),
                force_filtered_n: filtered,
                wire_height_m: std::mem::take(&mut height[p]),
                max_uplift_at_support_m: uplift[p],
                stats,
            }
        })
        .collect();
    Ok(RunOutput {
        speed_m_s: m.speed_m_s,
        dt_s: m.dt_s,
        time_s: time,
        analysis_m: m.analysis_m,
        pantographs,
        max_slack_droppers: max_slack,
        steps_with_slack_percent: 100.0 * steps_slack as f64 / n_steps.max(1) as f64,
        n_modes: m.basis.n_modes(),
        run_statistics: RunStatistics {
            steps_with_slack_dropper: steps_slack as u64,
            max_slack_droppers: max_slack as u64,
            ..rs
        },
    })
}
