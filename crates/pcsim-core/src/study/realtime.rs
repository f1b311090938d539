//! Studies built from several runs: the real-time window against the full model (paper §4.2,
//! Figs. 8–9).

use crate::analysis::record::{simulate, Recorder, RunOutput};
use crate::analysis::stats::{contact_stats, ContactStats};
use crate::analysis::sweep::parallel_map;
use crate::compile::Setup;
use crate::error::{CaseError, SimError};
use crate::input::case::{Case, PantographCase};
use crate::solve::realtime::Coupling;
use crate::solve::run::run;

/// Result of a window run in SIL mode.
#[derive(Debug, Clone, PartialEq)]
pub struct WindowRun {
    /// Window length, m.
    pub window_m: f64,
    /// Modes per wire and direction in the window.
    pub n_modes: usize,
    /// Window moves made.
    pub moves: usize,
    /// Time of every step, s.
    pub time_s: Vec<f64>,
    /// Pantograph position (track coordinates), m.
    pub position_m: Vec<f64>,
    /// Contact force, N.
    pub force_n: Vec<f64>,
    /// EN 50318 statistics over the analysis section.
    pub stats: Option<ContactStats>,
}

/// Run `case` with the window model in SIL mode over the same time as the full model (the one
/// run loop, with the EN 50318 recorder and the window mover as observers), and take the
/// statistics of the leading pantograph over the case's analysis section.
pub fn run_window_sil(case: &Case, window_m: f64) -> Result<WindowRun, SimError> {
    if !matches!(
        case.pantographs.first(),
        Some(PantographCase::Lumped { .. })
    ) {
        return Err(SimError::Case(CaseError::Invalid {
            field: "pantographs[0].kind".into(),
            value: "moving_force".into(),
            reason: "SIL needs a lumped pantograph".into(),
        }));
    }
    let mut rt = crate::compile::realtime_window(case, window_m, Coupling::Sil)?;
    let (duration_s, analysis_m) = rt.full_run();
    let n_steps = (duration_s / rt.dt_s()).ceil() as usize;
    let n_modes = rt.n_modes();
    if rt.is_line() {
        return run_window_line(&mut rt, window_m, n_steps, analysis_m);
    }
    let Some((integ, st, ws, mover)) = rt.parts_mut() else {
        unreachable!("a span-periodic window moves over one model");
    };
    let mut rec = Recorder::new(integ.compiled(), integ.dt_s(), n_steps, analysis_m);
    let rs = run(integ, st, ws, n_steps, &mut [&mut rec, mover], &mut |_| {
        true
    })
    .map_err(|e| match e {
        SimError::BlowUp {
            time_s,
            position_m,
            what,
        } => SimError::BlowUp {
            time_s,
            position_m,
            what: format!("window {window_m} m: {what}"),
        },
        other => other,
    })?;
    let mut out = rec.finish(integ.compiled(), rs);
    let p = out.pantographs.swap_remove(0);
    Ok(WindowRun {
        window_m,
        n_modes,
        moves: rs.window_moves as usize,
        time_s: out.time_s,
        position_m: p.position_m,
        force_n: p.force_n,
        stats: p.stats,
    })
}

/// [`run_window_sil`] on a line, whose window moves between a model per position: stepped by
/// [`crate::solve::realtime::RealtimeCatenary::step`], the statistics from the same
/// [`contact_stats`]. The window's uplift at the supports is not recorded here (its field reads
/// 0): the study compares the contact force.
fn run_window_line(
    rt: &mut crate::solve::realtime::RealtimeCatenary,
    window_m: f64,
    n_steps: usize,
    analysis_m: [f64; 2],
) -> Result<WindowRun, SimError> {
    let (mut time_s, mut position_m, mut force_n, mut height_m) = (
        Vec::with_capacity(n_steps),
        Vec::with_capacity(n_steps),
        Vec::with_capacity(n_steps),
        Vec::with_capacity(n_steps),
    );
    for _ in 0..n_steps {
        let o = rt.step();
        if let Some(what) = rt.fault() {
            return Err(SimError::BlowUp {
                time_s: o.time_s,
                position_m: o.position_m,
                what: format!("window {window_m} m: {what}"),
            });
        }
        time_s.push(o.time_s);
        position_m.push(o.position_m);
        force_n.push(o.contact_force_n);
        height_m.push(o.wire_height_m);
    }
    let stats = contact_stats(&force_n, &position_m, &height_m, rt.dt_s(), analysis_m, 0.0);
    Ok(WindowRun {
        window_m,
        n_modes: rt.n_modes(),
        moves: rt.moves(),
        time_s,
        position_m,
        force_n,
        stats,
    })
}

/// The window study: the full model and the window model at each length, leading pantograph.
#[derive(Debug, Clone, PartialEq)]
pub struct WindowStudy {
    /// The full model's run.
    pub full: RunOutput,
    /// The window's run at each length.
    pub windows: Vec<WindowRun>,
}

impl WindowStudy {
    /// Relative errors (%) of the window's mean, σ and maximum of the 0–20 Hz force against the
    /// full model, per window (`None` where a run did not cross the analysis section): the one
    /// law of the window's accuracy, [`crate::study::window_search::WindowErrors::of`], the
    /// window sweep's too.
    pub fn errors_percent(&self) -> Vec<Option<crate::study::window_search::WindowErrors>> {
        let Some(fs) = self.full.pantographs[0].stats else {
            return vec![None; self.windows.len()];
        };
        self.windows
            .iter()
            .map(|r| {
                r.stats
                    .map(|s| crate::study::window_search::WindowErrors::of(r.window_m, &s, &fs))
            })
            .collect()
    }
}

/// Run the full model of `case` (leading pantograph only), then the window model at every length
/// in `windows_m` side by side on up to `jobs` threads.
pub fn window_study(
    case: &Case,
    windows_m: &[f64],
    jobs: Option<usize>,
    progress: &mut dyn FnMut(f64) -> bool,
) -> Result<WindowStudy, SimError> {
    let single = crate::compile::window_case(case)?;
    crate::compile::require_contact(&single, "the real-time window study")?;
    let full = simulate(&Setup::from_case(&single)?, progress)?;
    let windows = parallel_map(windows_m, jobs, |&w| run_window_sil(&single, w))
        .into_iter()
        .collect::<Result<_, _>>()?;
    Ok(WindowStudy { full, windows })
}
