//! The effective vibration area (EVA): window energy around the pantograph (Eq. 21) and the window
//! length at which it converges (paper §2.4; README §2.5–2.7).

use crate::energy::{integrate, DensityGrid};
use crate::error::SimError;
use crate::model::Model;
use crate::solver::Solver;

/// Settings of an EVA evaluation.
#[derive(Debug, Clone, PartialEq)]
pub struct EvaSettings {
    /// Step Δd between neighbouring window lengths, m.
    pub step_m: f64,
    /// Largest window length evaluated, m (default: the model length, so that the fraction
    /// criterion always has an answer).
    pub max_window_m: Option<f64>,
    /// Paper's criterion: the step of E(d_e) between neighbours below this, J.
    pub tolerance_j: f64,
    /// Step-independent criterion: the window holding this fraction of the whole model's energy.
    pub fraction: f64,
    /// Snapshot when the leading pantograph passes this position (default: mid-model), m.
    pub snapshot_at_m: Option<f64>,
    /// Interval between samples for the maximum and the time average, s.
    pub sample_every_s: f64,
    /// Grid intervals per mode for the density.
    pub points_per_mode: usize,
}

impl Default for EvaSettings {
    fn default() -> Self {
        Self {
            step_m: 1.0,
            max_window_m: None,
            tolerance_j: 0.01,
            fraction: 0.99,
            snapshot_at_m: None,
            sample_every_s: 0.1,
            points_per_mode: 4,
        }
    }
}

/// Window energy `E(d) = ∫_{x_p − d/2}^{x_p + d/2} E(x) dx` (Eq. 21) for each `d`, from grid values
/// `density` at `x_j = j·dx` (linear between grid points; clipped to the model).
pub fn window_energy(density: &[f64], dx: f64, xp: f64, d: &[f64]) -> Vec<f64> {
    let n = density.len();
    let mut cum = vec![0.0; n];
    for j in 1..n {
        cum[j] = cum[j - 1] + 0.5 * dx * (density[j - 1] + density[j]);
    }
    let l = (n - 1) as f64 * dx;
    let at = |x: f64| -> f64 {
        let x = x.clamp(0.0, l);
        let j = ((x / dx).floor() as usize).min(n - 2);
        let t = x - j as f64 * dx;
        let slope = (density[j + 1] - density[j]) / dx;
        cum[j] + density[j] * t + 0.5 * slope * t * t
    };
    d.iter()
        .map(|&w| at(xp + 0.5 * w) - at(xp - 0.5 * w))
        .collect()
}

/// The paper's criterion (§2.4): the first `d_i` at which `E(d_{i+1}) − E(d_i) < tol`.
pub fn eva_by_step(d: &[f64], e: &[f64], tol_j: f64) -> Option<f64> {
    (0..e.len().saturating_sub(1))
        .find(|&i| e[i + 1] - e[i] < tol_j)
        .map(|i| d[i])
}

/// The step-independent criterion: the smallest `d` with `E(d) ≥ fraction · total` (linear
/// interpolation between grid values).
pub fn eva_by_fraction(d: &[f64], e: &[f64], total_j: f64, fraction: f64) -> Option<f64> {
    let target = fraction * total_j;
    let i = e.iter().position(|&v| v >= target)?;
    if i == 0 {
        return Some(d[0]);
    }
    let t = (target - e[i - 1]) / (e[i] - e[i - 1]);
    Some(d[i - 1] + t * (d[i] - d[i - 1]))
}

/// One way of sampling the energy (snapshot, maximum over the passage, or time average).
#[derive(Debug, Clone, PartialEq)]
pub struct EnergyView {
    /// Density at the relative positions `xi_m` (x − x_p), J/m.
    pub density_j_per_m: Vec<f64>,
    /// Window energy at `EvaOutput::window_m`, J.
    pub window_j: Vec<f64>,
    /// Energy of the whole model, J.
    pub total_j: f64,
    /// EVA length by the paper's step criterion, m.
    pub eva_step_m: Option<f64>,
    /// EVA length by the fraction criterion, m.
    pub eva_fraction_m: Option<f64>,
    /// Window energy at the step-criterion EVA ("converged total energy"), J.
    pub converged_j: Option<f64>,
}

impl EnergyView {
    fn new(density: Vec<f64>, window: Vec<f64>, total: f64, d: &[f64], s: &EvaSettings) -> Self {
        let eva_step_m = eva_by_step(d, &window, s.tolerance_j);
        let converged_j = eva_step_m
            .and_then(|e| d.iter().position(|&x| x == e))
            .map(|i| window[i]);
        Self {
            eva_fraction_m: eva_by_fraction(d, &window, total, s.fraction),
            density_j_per_m: density,
            window_j: window,
            total_j: total,
            eva_step_m,
            converged_j,
        }
    }
}

/// Energy distributions and EVA lengths of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct EvaOutput {
    pub settings: EvaSettings,
    /// Relative positions x − x_p of the densities, m.
    pub xi_m: Vec<f64>,
    /// Window lengths d_e, m.
    pub window_m: Vec<f64>,
    /// Snapshot when the leading pantograph passes `snapshot_at_m`.
    pub snapshot: EnergyView,
    /// Maximum over the passage through the analysis section (pointwise in x − x_p and in d_e).
    pub max: EnergyView,
    /// Time average over the passage.
    pub mean: EnergyView,
    pub snapshot_at_m: f64,
    pub samples: usize,
}

/// Run `model` and evaluate the energy distribution around the leading pantograph.
pub fn run_eva(
    model: Model,
    s: &EvaSettings,
    progress: &mut dyn FnMut(f64) -> bool,
) -> Result<EvaOutput, SimError> {
    let l = model.basis.length_m();
    let snap_x = s.snapshot_at_m.unwrap_or(0.5 * l);
    let dt = model.dt_s;
    let n_steps = (model.duration_s / dt).ceil() as usize;
    let every = ((s.sample_every_s / dt).round() as usize).max(1);
    let mut grid = DensityGrid::new(&model, s.points_per_mode);
    let dx = grid.dx();
    let max_window = s.max_window_m.unwrap_or(l).min(2.0 * l);
    let half = (0.5 * max_window / dx).round() as isize;
    let xi: Vec<f64> = (-half..=half).map(|i| i as f64 * dx).collect();
    let nd = (max_window / s.step_m).floor() as usize;
    let d: Vec<f64> = (1..=nd).map(|i| i as f64 * s.step_m).collect();
    let analysis = model.analysis_m;
    let mut solver = Solver::new(model);
    let mut st = solver.initial_state();
    let mut dens = vec![0.0; grid.n_points()];
    let relative = |dens: &[f64], xp: f64| -> Vec<f64> {
        let jp = (xp / dx).round() as isize;
        (-half..=half)
            .map(|i| {
                let k = jp + i;
                if k < 0 {
                    0.0
                } else {
                    dens.get(k as usize).copied().unwrap_or(0.0)
                }
            })
            .collect()
    };
    let mut snapshot = None;
    let mut max_d = vec![0.0f64; xi.len()];
    let mut sum_d = vec![0.0f64; xi.len()];
    let mut max_w = vec![0.0f64; d.len()];
    let mut sum_w = vec![0.0f64; d.len()];
    let (mut max_total, mut sum_total) = (0.0f64, 0.0f64);
    let mut samples = 0usize;
    let mut prev_x = solver.model().pantograph_position(0, 0.0);
    for step in 1..=n_steps {
        solver.step(&mut st);
        let xp = solver.model().pantograph_position(0, st.t);
        if !xp.is_finite() || st.qc.iter().take(1).any(|v| !v.is_finite()) {
            return Err(SimError::BlowUp {
                time_s: st.t,
                position_m: xp,
                what: "non-finite state".into(),
            });
        }
        let c = solver.samples()[0];
        if !c.is_sound() {
            return Err(SimError::BlowUp {
                time_s: st.t,
                position_m: xp,
                what: format!(
                    "contact force {} N, wire height {} m",
                    c.force_n, c.wire_height_m
                ),
            });
        }
        let snap_now = snapshot.is_none() && prev_x < snap_x && xp >= snap_x;
        let in_passage = xp >= analysis[0] && xp <= analysis[1] && step % every == 0;
        if snap_now || in_passage {
            grid.density(solver.model(), &st, &mut dens);
            let total = integrate(&dens, dx);
            let w = window_energy(&dens, dx, xp, &d);
            if snap_now {
                snapshot = Some(EnergyView::new(
                    relative(&dens, xp),
                    w.clone(),
                    total,
                    &d,
                    s,
                ));
            }
            if in_passage {
                let rel = relative(&dens, xp);
                for i in 0..xi.len() {
                    max_d[i] = max_d[i].max(rel[i]);
                    sum_d[i] += rel[i];
                }
                for i in 0..d.len() {
                    max_w[i] = max_w[i].max(w[i]);
                    sum_w[i] += w[i];
                }
                max_total = max_total.max(total);
                sum_total += total;
                samples += 1;
            }
        }
        prev_x = xp;
        if step % 256 == 0 && !progress(step as f64 / n_steps as f64) {
            return Err(SimError::Cancelled);
        }
    }
    progress(1.0);
    let snapshot = snapshot.ok_or_else(|| {
        SimError::Case(crate::error::CaseError::Invalid {
            field: "eva.snapshot_at_m".into(),
            value: snap_x.to_string(),
            reason: "the leading pantograph never passes this position during the run".into(),
        })
    })?;
    let ns = samples.max(1) as f64;
    let mean_d: Vec<f64> = sum_d.iter().map(|v| v / ns).collect();
    let mean_w: Vec<f64> = sum_w.iter().map(|v| v / ns).collect();
    Ok(EvaOutput {
        max: EnergyView::new(max_d, max_w, max_total, &d, s),
        mean: EnergyView::new(mean_d, mean_w, sum_total / ns, &d, s),
        snapshot,
        settings: s.clone(),
        xi_m: xi,
        window_m: d,
        snapshot_at_m: snap_x,
        samples,
    })
}
