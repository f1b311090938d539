//! The effective vibration area (EVA): window energy around the pantograph (Eq. 21) and the window
//! length at which it converges (paper §2.4; README §2.5–2.7).

use crate::analysis::energy::{integrate, DensityGrid};
use crate::analysis::record::{simulate_beside, RunOutput};
use crate::compile::budget::{check_len, Budget};
use crate::compile::Setup;
use crate::error::SimError;
use crate::model::PantographKind;
use crate::solve::run::{run, Observer};
use crate::solve::{CompiledModel, Integrator, State, Workspace};

/// What the vibration energy is measured about: the EVA is the energy of the catenary's
/// vibration caused by the pantograph, so a steady load's static deflection (ice, a mean wind)
/// and a turbulent wind's own vibration are not part of it.
enum Datum {
    /// No steady load: the design's static shape (modal zero).
    Design,
    /// Steady loads without a wind (ice): the static start state.
    Static(Box<State>),
    /// A wind: the same run without the pantographs (each a zero moving force), stepped beside
    /// the run through the same wind field; the energy is that of the difference of the two
    /// (the pantograph's part of the vibration).
    Twin(Box<(Integrator, State, Workspace)>),
}

impl Datum {
    /// The datum of `setup`'s run by `integ` from its initial state `st`.
    fn of(setup: &Setup, integ: &Integrator, st: &State) -> Result<Datum, SimError> {
        let m = integ.model();
        if m.wind.is_some() {
            let mut twin = m.clone();
            for p in &mut twin.pantographs {
                p.kind = PantographKind::MovingForce {
                    force_n: 0.0,
                    lateral_force_n: 0.0,
                };
            }
            let mut options = setup.options;
            options.threads = 1;
            let ti = Integrator::new(twin, &setup.plan, options)
                .map_err(crate::compile::in_case_terms)?;
            let ts = ti.initial_state(setup.plan.start_m);
            let tw = ti.workspace();
            return Ok(Datum::Twin(Box::new((ti, ts, tw))));
        }
        if integ.compiled().initial.is_some() {
            return Ok(Datum::Static(Box::new(st.clone())));
        }
        Ok(Datum::Design)
    }
}

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
    /// Positions across the snapshot's span at which the EVA is taken as well (issue 53, item
    /// 4: a snapshot's EVA depends on where in the span it is taken; 0: none), evenly spaced
    /// from the span's first support.
    pub span_positions: usize,
    /// Grid intervals per mode for the density.
    pub points_per_mode: usize,
    /// Memory limit of the energy arrays.
    pub budget: Budget,
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
            span_positions: 8,
            points_per_mode: 4,
            budget: Budget::default(),
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

/// Grid values `density` at `x_j = j·dx` at `x`, linear between points; zero outside the grid.
fn linear_at(density: &[f64], dx: f64, x: f64) -> f64 {
    let n = density.len();
    if n < 2 || x < 0.0 || x > (n - 1) as f64 * dx {
        return 0.0;
    }
    let j = ((x / dx).floor() as usize).min(n - 2);
    let t = x / dx - j as f64;
    density[j] + t * (density[j + 1] - density[j])
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
    /// The settings the run used.
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
    /// Track position at which the snapshot is taken (the leading pantograph passes it), m.
    pub snapshot_at_m: f64,
    /// Energy samples taken over the passage (for the max and mean views).
    pub samples: usize,
    /// Positions across the snapshot's span at which the EVA was taken too, m
    /// ([`EvaSettings::span_positions`]).
    pub span_positions_m: Vec<f64>,
    /// The EVA by the step criterion at each of them (none: not reached, or not passed).
    pub span_eva_step_m: Vec<Option<f64>>,
    /// The EVA by the fraction criterion at each of them.
    pub span_eva_fraction_m: Vec<Option<f64>>,
}

/// The positions across the span holding `x` (from its first support, the support at `x`
/// included) at which the EVA is taken as well: `n` evenly spaced (none for `n = 0`, or a
/// model without supports or span).
fn span_positions(model: &crate::model::Model, x: f64, n: usize) -> Vec<f64> {
    if n == 0 {
        return Vec::new();
    }
    let span = (model.supports_m.windows(2))
        .find(|w| w[0] <= x && x < w[1])
        .map(|w| (w[0], w[1]))
        .or_else(|| model.span_m.map(|l| (x, x + l)));
    let Some((a, b)) = span else {
        return Vec::new();
    };
    (0..n).map(|k| a + (b - a) * k as f64 / n as f64).collect()
}

/// The energy sampler: an observer that evaluates the energy density around the leading
/// pantograph at the snapshot and at regular times of its passage through the analysis section.
struct EnergySampler<'a> {
    s: &'a EvaSettings,
    /// What the energy is measured about.
    datum: Datum,
    /// One density grid per basis group (a line's tension lengths), with its densities.
    grids: Vec<DensityGrid>,
    dens: Vec<Vec<f64>>,
    /// Spacing of the relative positions `x − x_p` (the finest grid's).
    dx: f64,
    half: isize,
    d: Vec<f64>,
    snap_x: f64,
    every: usize,
    analysis: [f64; 2],
    step: usize,
    prev_x: f64,
    snapshot: Option<EnergyView>,
    /// The positions across the snapshot's span, and the EVA by each criterion at each
    /// (none: not passed yet).
    span_x: Vec<f64>,
    span_eva: Vec<Option<(Option<f64>, Option<f64>)>>,
    max_d: Vec<f64>,
    sum_d: Vec<f64>,
    max_w: Vec<f64>,
    sum_w: Vec<f64>,
    max_total: f64,
    sum_total: f64,
    samples: usize,
}

impl EnergySampler<'_> {
    /// The density at the relative positions x − x_p: on one grid, its points nearest to them;
    /// on a line, the sum of every tension length's density there (linear between its points).
    fn relative(&self, xp: f64) -> Vec<f64> {
        if let [dens] = &self.dens[..] {
            let jp = (xp / self.dx).round() as isize;
            return (-self.half..=self.half)
                .map(|i| {
                    let k = jp + i;
                    if k < 0 {
                        0.0
                    } else {
                        dens.get(k as usize).copied().unwrap_or(0.0)
                    }
                })
                .collect();
        }
        (-self.half..=self.half)
            .map(|i| {
                let x = xp + i as f64 * self.dx;
                self.grids
                    .iter()
                    .zip(&self.dens)
                    .map(|(g, d)| linear_at(d, g.dx(), x - g.origin_m()))
                    .sum()
            })
            .collect()
    }

    /// The whole model's energy, J: every grid's integral.
    fn total(&self) -> f64 {
        (self.grids.iter().zip(&self.dens)).fold(0.0, |t, (g, d)| t + integrate(d, g.dx()))
    }

    /// The window energies about `xp` (Eq. 21): every grid's part of each window, each wire on
    /// its own extent.
    fn windows(&self, xp: f64) -> Vec<f64> {
        let mut w = vec![0.0; self.d.len()];
        for (g, d) in self.grids.iter().zip(&self.dens) {
            let part = window_energy(d, g.dx(), xp - g.origin_m(), &self.d);
            for (a, b) in w.iter_mut().zip(part) {
                *a += b;
            }
        }
        w
    }
}

impl Observer for EnergySampler<'_> {
    fn observe(
        &mut self,
        cm: &CompiledModel,
        st: &mut State,
        _ws: &Workspace,
    ) -> Result<(), SimError> {
        self.step += 1;
        if let Datum::Twin(t) = &mut self.datum {
            // The twin takes the same step through the same wind field.
            let (ti, ts, tw) = &mut **t;
            ti.step(ts, tw);
        }
        let xp = cm.position(st, 0);
        let snap_now = self.snapshot.is_none() && self.prev_x < self.snap_x && xp >= self.snap_x;
        let in_passage =
            xp >= self.analysis[0] && xp <= self.analysis[1] && self.step % self.every == 0;
        let prev_x = self.prev_x;
        let passes = |x: f64| prev_x < x && xp >= x;
        let span_now =
            (self.span_x.iter().zip(&self.span_eva)).any(|(&x, e)| e.is_none() && passes(x));
        if snap_now || in_passage || span_now {
            let reference = match &self.datum {
                Datum::Design => None,
                Datum::Static(s0) => Some(&**s0),
                Datum::Twin(t) => Some(&t.1),
            };
            for (g, d) in self.grids.iter_mut().zip(&mut self.dens) {
                g.density_about(cm.model(), st, reference, d);
            }
            let total = self.total();
            let w = self.windows(xp);
            if snap_now {
                self.snapshot = Some(EnergyView::new(
                    self.relative(xp),
                    w.clone(),
                    total,
                    &self.d,
                    self.s,
                ));
            }
            for (&x, e) in self.span_x.iter().zip(&mut self.span_eva) {
                if e.is_none() && passes(x) {
                    *e = Some((
                        eva_by_step(&self.d, &w, self.s.tolerance_j),
                        eva_by_fraction(&self.d, &w, total, self.s.fraction),
                    ));
                }
            }
            if in_passage {
                let rel = self.relative(xp);
                for i in 0..rel.len() {
                    self.max_d[i] = self.max_d[i].max(rel[i]);
                    self.sum_d[i] += rel[i];
                }
                for i in 0..self.d.len() {
                    self.max_w[i] = self.max_w[i].max(w[i]);
                    self.sum_w[i] += w[i];
                }
                self.max_total = self.max_total.max(total);
                self.sum_total += total;
                self.samples += 1;
            }
        }
        self.prev_x = xp;
        Ok(())
    }

    fn finished(&self) -> bool {
        // The pantograph moves forward: past the section and the span, no sample is taken again.
        self.snapshot.is_some()
            && self.prev_x > self.analysis[1]
            && self.span_x.last().is_none_or(|&x| self.prev_x >= x)
    }
}

impl<'a> EnergySampler<'a> {
    /// The sampler of `setup`'s run by `integ` under settings `s`, from the initial state `st`.
    /// Checks the energy arrays against the budget.
    fn new(
        setup: &Setup,
        s: &'a EvaSettings,
        integ: &Integrator,
        st: &State,
    ) -> Result<Self, SimError> {
        let x0_m = integ.position(st, 0);
        let l = setup.model.length_m();
        let dt = setup.options.dt_s;
        // Bounded memory: the window lengths (every Δd up to the largest window, eight arrays)
        // and the density grid (points per mode × modes, about twenty arrays).
        let max_window = s.max_window_m.unwrap_or(l).min(2.0 * l);
        check_len(
            &s.budget,
            "eva.step_m (--step)",
            s.step_m,
            8.0 * max_window / s.step_m,
        )?;
        check_len(
            &s.budget,
            "eva.points_per_mode",
            s.points_per_mode,
            20.0 * (s.points_per_mode.max(2) * setup.model.n_modes()) as f64,
        )?;
        let grids = DensityGrid::per_group(&setup.model, s.points_per_mode)?;
        let dx = grids.iter().map(|g| g.dx()).fold(f64::INFINITY, f64::min);
        let half = (0.5 * max_window / dx).round() as isize;
        let n_xi = (2 * half + 1) as usize;
        let nd = (max_window / s.step_m).floor() as usize;
        let d: Vec<f64> = (1..=nd).map(|i| i as f64 * s.step_m).collect();
        let snap_x = s.snapshot_at_m.unwrap_or(0.5 * l);
        let span_x = span_positions(&setup.model, snap_x, s.span_positions);
        Ok(EnergySampler {
            s,
            datum: Datum::of(setup, integ, st)?,
            dens: grids.iter().map(|g| vec![0.0; g.n_points()]).collect(),
            grids,
            dx,
            half,
            snap_x,
            span_eva: vec![None; span_x.len()],
            span_x,
            every: ((s.sample_every_s / dt).round() as usize).max(1),
            analysis: setup.plan.analysis_m,
            step: 0,
            prev_x: x0_m,
            snapshot: None,
            max_d: vec![0.0; n_xi],
            sum_d: vec![0.0; n_xi],
            max_w: vec![0.0; d.len()],
            sum_w: vec![0.0; d.len()],
            max_total: 0.0,
            sum_total: 0.0,
            samples: 0,
            d,
        })
    }

    /// The energy views of the run observed.
    fn finish(mut self) -> Result<EvaOutput, SimError> {
        let snap_x = self.snap_x;
        let snapshot = self.snapshot.take().ok_or_else(|| {
            SimError::Case(crate::error::CaseError::Invalid {
                field: "eva.snapshot_at_m".into(),
                value: snap_x.to_string(),
                reason: "the leading pantograph never passes this position during the run".into(),
            })
        })?;
        let s = self.s;
        let xi: Vec<f64> = (-self.half..=self.half)
            .map(|i| i as f64 * self.dx)
            .collect();
        let ns = self.samples.max(1) as f64;
        let mean_d: Vec<f64> = self.sum_d.iter().map(|v| v / ns).collect();
        let mean_w: Vec<f64> = self.sum_w.iter().map(|v| v / ns).collect();
        let d = self.d;
        let (span_eva_step_m, span_eva_fraction_m) = (self.span_eva.iter())
            .map(|e| e.unwrap_or((None, None)))
            .unzip();
        Ok(EvaOutput {
            max: EnergyView::new(self.max_d, self.max_w, self.max_total, &d, s),
            mean: EnergyView::new(mean_d, mean_w, self.sum_total / ns, &d, s),
            snapshot,
            settings: s.clone(),
            xi_m: xi,
            window_m: d,
            snapshot_at_m: snap_x,
            samples: self.samples,
            span_positions_m: self.span_x,
            span_eva_step_m,
            span_eva_fraction_m,
        })
    }
}

/// Run a set-up and evaluate the energy distribution around the leading pantograph (Eqs. 20–21).
/// The run stops once the snapshot is taken and the pantograph has left the analysis section:
/// nothing after it is observed.
pub fn run_eva(
    setup: &Setup,
    s: &EvaSettings,
    progress: &mut dyn FnMut(f64) -> bool,
) -> Result<EvaOutput, SimError> {
    let integ = setup.integrator()?;
    let mut st = integ.initial_state(setup.plan.start_m);
    let mut ws = integ.workspace();
    let mut sampler = EnergySampler::new(setup, s, &integ, &st)?;
    run(
        &integ,
        &mut st,
        &mut ws,
        setup.n_steps(),
        &mut [&mut sampler],
        progress,
    )?;
    sampler.finish()
}

/// [`simulate`](crate::analysis::record::simulate) and [`run_eva`] of the same set-up in one
/// run (the recorder and the energy sampler observe the same steps): the same outputs as the two
/// runs.
pub fn simulate_with_eva(
    setup: &Setup,
    s: &EvaSettings,
    progress: &mut dyn FnMut(f64) -> bool,
) -> Result<(RunOutput, EvaOutput), SimError> {
    let (out, sampler) = simulate_beside(
        setup,
        None,
        |integ, st| EnergySampler::new(setup, s, integ, st),
        progress,
    )?;
    Ok((out, sampler.finish()?))
}

/// One row of an EVA sweep (`eva.csv`): the case, the settings and every EVA variant.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct EvaRow {
    /// Case index in the grid.
    pub index: usize,
    /// Train speed, km/h.
    pub speed_kmh: f64,
    /// Contact-wire tension, kN.
    pub tension_kn: f64,
    /// Damping of the case, as written in the grid.
    pub damping: String,
    /// Window increment Δd of the step criterion, m.
    pub step_m: f64,
    /// Energy gain below which the step criterion stops, J.
    pub tolerance_j: f64,
    /// Share of the total energy the fraction criterion asks for.
    pub fraction: f64,
    /// EVA of the snapshot by the paper's step criterion, m (`None`: not reached).
    pub eva_step_m: Option<f64>,
    /// EVA of the snapshot by the fraction criterion, m.
    pub eva_fraction_m: Option<f64>,
    /// Window energy of the snapshot at its step-criterion EVA, J.
    pub converged_energy_j: Option<f64>,
    /// Energy of the whole model at the snapshot, J.
    pub total_energy_j: f64,
    /// EVA of the maximum over the passage by the step criterion, m.
    pub eva_step_max_m: Option<f64>,
    /// EVA of the maximum over the passage by the fraction criterion, m.
    pub eva_fraction_max_m: Option<f64>,
    /// EVA of the time average by the step criterion, m.
    pub eva_step_mean_m: Option<f64>,
    /// EVA of the time average by the fraction criterion, m.
    pub eva_fraction_mean_m: Option<f64>,
    /// Seed offset of the realisation (Monte Carlo over the case's random inputs; 0 for one).
    pub seed_offset: u64,
    /// The smallest EVA by the step criterion over the snapshot's span
    /// ([`EvaSettings::span_positions`] positions), m.
    pub eva_step_span_min_m: Option<f64>,
    /// The largest, m (none where a position has no value: the band's upper end unseen).
    pub eva_step_span_max_m: Option<f64>,
    /// The smallest EVA by the fraction criterion over the span, m.
    pub eva_fraction_span_min_m: Option<f64>,
    /// The largest, m.
    pub eva_fraction_span_max_m: Option<f64>,
}

/// The smallest and the largest of the values (none: no value; the largest is none too where
/// one position has no value, a criterion not reached within the largest window or a position
/// the run did not pass, so that the band never claims an upper end it did not see).
fn spread(v: &[Option<f64>]) -> (Option<f64>, Option<f64>) {
    let given = || v.iter().flatten().copied();
    let hi = given()
        .reduce(f64::max)
        .filter(|_| v.iter().all(Option::is_some));
    (given().reduce(f64::min), hi)
}

impl EvaRow {
    /// The CSV header of `eva.csv`.
    pub const HEADER: &'static str = "index,speed_kmh,tension_kn,damping,step_m,tolerance_j,fraction,eva_step_m,eva_fraction_m,converged_energy_j,total_energy_j,eva_step_max_m,eva_fraction_max_m,eva_step_mean_m,eva_fraction_mean_m,seed_offset,eva_step_span_min_m,eva_step_span_max_m,eva_fraction_span_min_m,eva_fraction_span_max_m";

    /// The row of case `index` of a sweep.
    pub fn new(
        index: usize,
        speed_kmh: f64,
        tension_kn: f64,
        damping: &str,
        o: &EvaOutput,
    ) -> Self {
        let s = &o.settings;
        let (step_lo, step_hi) = spread(&o.span_eva_step_m);
        let (fraction_lo, fraction_hi) = spread(&o.span_eva_fraction_m);
        EvaRow {
            index,
            speed_kmh,
            tension_kn,
            damping: damping.to_string(),
            step_m: s.step_m,
            tolerance_j: s.tolerance_j,
            fraction: s.fraction,
            eva_step_m: o.snapshot.eva_step_m,
            eva_fraction_m: o.snapshot.eva_fraction_m,
            converged_energy_j: o.snapshot.converged_j,
            total_energy_j: o.snapshot.total_j,
            eva_step_max_m: o.max.eva_step_m,
            eva_fraction_max_m: o.max.eva_fraction_m,
            eva_step_mean_m: o.mean.eva_step_m,
            eva_fraction_mean_m: o.mean.eva_fraction_m,
            seed_offset: 0,
            eva_step_span_min_m: step_lo,
            eva_step_span_max_m: step_hi,
            eva_fraction_span_min_m: fraction_lo,
            eva_fraction_span_max_m: fraction_hi,
        }
    }

    /// The CSV line (lengths to 1 mm, energies to 1 µJ; an empty cell where a criterion was not
    /// reached).
    pub fn to_csv(&self) -> String {
        let opt = |v: Option<f64>| v.map(|x| format!("{x:.3}")).unwrap_or_default();
        format!(
            "{},{},{},{},{},{},{},{},{},{},{:.6},{},{},{},{},{},{},{},{},{}",
            self.index,
            self.speed_kmh,
            self.tension_kn,
            self.damping,
            self.step_m,
            self.tolerance_j,
            self.fraction,
            opt(self.eva_step_m),
            opt(self.eva_fraction_m),
            self.converged_energy_j
                .map(|x| format!("{x:.6}"))
                .unwrap_or_default(),
            self.total_energy_j,
            opt(self.eva_step_max_m),
            opt(self.eva_fraction_max_m),
            opt(self.eva_step_mean_m),
            opt(self.eva_fraction_mean_m),
            self.seed_offset,
            opt(self.eva_step_span_min_m),
            opt(self.eva_step_span_max_m),
            opt(self.eva_fraction_span_min_m),
            opt(self.eva_fraction_span_max_m),
        )
    }
}
