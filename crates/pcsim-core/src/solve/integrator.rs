//! Time integration of the coupled model (Eq. 18) in deviation coordinates.
//!
//! # Method
//! Central differences in velocity-Verlet form, with the wires' diagonal modal damping and the
//! implicit point terms (steady-arm masses, support dampers) taken implicitly:
//!
//! ```text
//! v½ = vₙ + Δt/2 aₙ,   uₙ₊₁ = uₙ + Δt v½,
//! (M + Δt/2 C) aₙ₊₁ = Q(uₙ₊₁, v½) − K uₙ₊₁ − C v½,   vₙ₊₁ = v½ + Δt/2 aₙ₊₁.
//! ```
//!
//! `Q` holds the point forces of the elements (`model::elements`), the pantographs' own springs
//! and the crosswind (`model::wind`).
//!
//! # Torsion: each mode implicitly
//! Torsional waves travel at √(G/ρ) ≈ 2.2 km/s in copper, so at the vertical mode density the
//! highest torsional mode would need Δt ≈ 0.4 ms explicitly. The torsional series is therefore
//! advanced per mode by the trapezoidal rule (a 2×2 map on each mode's `(q, q̇)`, computed once,
//! [`oscillator_flow`]), split around the point forces as a kick–map–kick step:
//!
//! ```text
//! v½ = vₙ + Δt/2 M⁻¹Qₙ,   (uₙ₊₁, v̂) = Φ(Δt)(uₙ, v½),   vₙ₊₁ = v̂ + Δt/2 M⁻¹Qₙ₊₁.
//! ```
//!
//! The diagonal modal part is then stable for any Δt; only the point couplings (eccentric
//! clamps, a few N·m/rad) limit the step. The exact flow of each mode was tried first and
//! rejected: it turns the high modes by `ω Δt` (up to about 5 rad), and the kicks then resonate
//! with the step (the impulse method's known instability). The trapezoidal map turns by less
//! than π. The vertical and lateral series keep the scheme above, so a vertical-only model is
//! unchanged. The wire mass matrix is diagonal plus the implicit point terms (`M = D + Φᵀ W Φ`),
//! solved exactly with the Woodbury identity ([`crate::solve::implicit`]). Every step does the
//! same fixed work: no iteration, no allocation. See ARCHITECTURE.md for why this scheme was
//! chosen over ode15s.//!
//! # Layers of the step
//! [`CompiledModel`] holds everything that does not depend on Δt (the slots, point groups,
//! moving points, monitors, probes, the energy view); [`Integrator`] adds the Δt operators (the
//! modal diagonal, the torsional flow, the implicit corrections, the pantographs' chains) and
//! steps in eight named stages.

use crate::error::CaseError;
use crate::model::dof::Direction;
use crate::model::elements::{Io, Weight};
use crate::model::pantograph::ChainOperators;
use crate::model::Model;
use crate::solve::compiled::{invalid, CompiledModel};
use crate::solve::implicit::{ImplicitPoints, ImplicitScratch};
use crate::solve::kernels::{self, Isa};
use crate::solve::limits::CoupledLimit;
use crate::solve::pantographs;
use crate::solve::plan::Plan;
use crate::solve::sampler::SamplerScratch;
use crate::solve::state::State;
use crate::solve::team::{self, Part, Team, Unit};
use crate::solve::workspace::{Lane, Workspace};

/// The stepper: the compiled model and the operators of one time step Δt, precomputed.
/// Immutable while stepping: [`Integrator::step`] takes the state and a [`Workspace`].
#[derive(Debug, Clone)]
pub struct Integrator {
    cm: CompiledModel,
    dt: f64,
    /// Stiffness, damping and `1/(M + Δt/2 C)` (and its negative) of every modal coordinate, by
    /// the layout (`k`, `c` are zero on the modes advanced by their flow).
    k: Vec<f64>,
    c: Vec<f64>,
    d_inv: Vec<f64>,
    neg_d_inv: Vec<f64>,
    /// Contiguous ranges of the modal vector: (start, end, advanced by its trapezoidal flow).
    segments: Vec<(usize, usize, bool)>,
    /// The one-step flow of every mode (used on the flow ranges).
    flow: Vec<[f64; 4]>,
    /// The implicit point terms with their Δt weights (Woodbury).
    implicit: Vec<ImplicitPoints>,
    /// Per pantograph: its chain's Δt operators (lumped pantographs).
    chains: Vec<Option<ChainOperators>>,
    /// The pantographs' static equilibrium, the initial state's.
    initial_py: Vec<f64>,
    /// Sampler scratch for every sampler of a step, and the implicit terms' largest sizes.
    scratch: SamplerScratch,
    max_imp: (usize, usize, usize),
    /// The coupled limit Δt was checked against.
    limit: Option<CoupledLimit>,
    /// The step's per-group work in parts, one per thread of a run (`solve::team`); one part
    /// covering everything for a single thread.
    parts: Vec<Part>,
}

/// One trapezoidal (Cayley) step over `t` of the damped oscillator `m q̈ + c q̇ + k q = 0` as a
/// matrix on `(q, q̇)`: `(I − t/2 A)⁻¹ (I + t/2 A)` with `A = [[0, 1], [−k/m, −c/m]]`. It turns
/// the phase plane by `2 atan(ω t / 2) < π` per step, whatever `ω t`, so the point forces kicked
/// around it cannot meet a resonance of the step (the exact flow, turning by `ω t`, does: with
/// torsional modes up to `ω Δt ≈ 5` the kick–flow–kick step blew up on the eccentric clamps).
pub fn oscillator_flow(m: f64, c: f64, k: f64, t: f64) -> [f64; 4] {
    let h = 0.5 * t;
    let w2 = k / m;
    let s2 = c / m; // 2σ
    let det = 1.0 + h * s2 + h * h * w2;
    [
        (1.0 + h * s2 - h * h * w2) / det,
        2.0 * h / det,
        -2.0 * h * w2 / det,
        (1.0 - h * s2 - h * h * w2) / det,
    ]
}

/// How a stage of [`Integrator::drive`] is run: the one driver's two strategies.
pub(crate) trait StageStrategy {
    /// Run `stage` of `integ`'s step.
    fn stage(&self, integ: &Integrator, stage: Stage, st: &mut State, ws: &mut Workspace);
}

/// Every stage on this thread ([`Integrator::step`]).
pub(crate) struct Serial;

impl StageStrategy for Serial {
    #[inline(always)]
    fn stage(&self, integ: &Integrator, stage: Stage, st: &mut State, ws: &mut Workspace) {
        integ.serial_stage(stage, st, ws);
    }
}

/// The per-group stages shared by a team of threads ([`Integrator::step_team`]).
pub(crate) struct TeamStages<'t, 'u>(&'t Team<'u>);

impl StageStrategy for TeamStages<'_, '_> {
    #[inline(always)]
    fn stage(&self, integ: &Integrator, stage: Stage, st: &mut State, ws: &mut Workspace) {
        integ.team_stage(self.0, stage, st, ws);
    }
}

/// The named stages of [`Integrator::step`], in order.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// 1: the half kick and the drift.
    Drift,
    /// 2: the wires' displacements and velocities at every point (the sampler).
    Gather,
    /// 3: droppers, supports, steady arms, stitches; the nodes.
    FixedPointForces,
    /// 4: `−K q − C v` and the point forces scattered onto the modes.
    ModalRhs,
    /// 5: steady loads and the crosswind.
    Wind,
    /// 6: the moving contact points and their rows.
    MovingPoints,
    /// 7: the implicit point terms (Woodbury).
    ImplicitSolve,
    /// 8: the pantographs.
    Pantographs,
}

impl Stage {
    /// Every stage, in the order a step runs them.
    pub const ALL: [Stage; 8] = [
        Stage::Drift,
        Stage::Gather,
        Stage::FixedPointForces,
        Stage::ModalRhs,
        Stage::Wind,
        Stage::MovingPoints,
        Stage::ImplicitSolve,
        Stage::Pantographs,
    ];

    /// Its name in the benches.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Drift => "drift",
            Stage::Gather => "gather",
            Stage::FixedPointForces => "fixed_point_forces",
            Stage::ModalRhs => "modal_rhs",
            Stage::Wind => "wind",
            Stage::MovingPoints => "moving_points",
            Stage::ImplicitSolve => "implicit_solve",
            Stage::Pantographs => "pantographs",
        }
    }
}

/// The modal operators of a step: the diagonal stiffness, damping and `M + Δt/2 C` of every
/// mode (Eqs. 9–14), the torsional modes' trapezoidal flow, and the runs of the layout advanced
/// by each law.
struct ModalOps {
    k: Vec<f64>,
    c: Vec<f64>,
    d_eff: Vec<f64>,
    flow: Vec<[f64; 4]>,
    segments: Vec<(usize, usize, bool)>,
}

impl ModalOps {
    fn new(cm: &CompiledModel, dt: f64) -> ModalOps {
        let model = &cm.model;
        let lay = &model.layout;
        // Modal operators. Torsional blocks are advanced by their trapezoidal flow: their
        // stiffness and damping leave the explicit right-hand side.
        let mut k = vec![0.0; lay.len];
        let mut c = vec![0.0; lay.len];
        let mut d_eff = vec![0.0; lay.len];
        let mut flow = vec![[1.0, 0.0, 0.0, 1.0]; lay.len];
        let mut segments: Vec<(usize, usize, bool)> = Vec::new();
        for b in 0..lay.blocks.len() {
            let s = model.series(b);
            let exact = lay.blocks[b].key.dir == Direction::Torsional;
            let r = lay.range(b);
            for (i, j) in r.clone().enumerate() {
                if exact {
                    flow[j] = oscillator_flow(s.mass[i], s.damping[i], s.stiffness[i], dt);
                    d_eff[j] = s.mass[i];
                } else {
                    k[j] = s.stiffness[i];
                    c[j] = s.damping[i];
                    d_eff[j] = s.mass[i] + 0.5 * dt * s.damping[i];
                }
            }
            segments.push((r.start, r.end, exact));
        }
        segments.sort_unstable_by_key(|sg| sg.0);
        segments.dedup_by(|next, prev| {
            let merge = prev.1 == next.0 && prev.2 == next.2;
            if merge {
                prev.1 = next.1;
            }
            merge
        });
        ModalOps {
            k,
            c,
            d_eff,
            flow,
            segments,
        }
    }
}

/// The implicit point terms (Woodbury, `solve/implicit.rs`) with their Δt weights, over the
/// modal diagonal `d_eff`.
fn implicit_terms(
    cm: &CompiledModel,
    dt: f64,
    d_eff: &[f64],
) -> Result<Vec<ImplicitPoints>, CaseError> {
    let model = &cm.model;
    let lay = &model.layout;
    let isa = cm.isa;
    // Implicit point terms: a mass as it is, a damper as `Δt/2 c`.
    let mut implicit = Vec::with_capacity(cm.implicit.len());
    for grp in &cm.implicit {
        let b = grp.blocks.start;
        let weights: Vec<Vec<f64>> = grp
            .weights
            .iter()
            .map(|ws| {
                ws.iter()
                    .map(|w| match *w {
                        Weight::Mass(m) => m,
                        Weight::Damper(cd) => 0.5 * dt * cd,
                    })
                    .collect()
            })
            .collect();
        let ds: Vec<&[f64]> = grp.blocks.clone().map(|k| &d_eff[lay.range(k)]).collect();
        let imp = ImplicitPoints::new(
            lay.basis(b),
            model.span_m,
            isa,
            lay.blocks[b].offset,
            &grp.xs,
            &weights,
            &ds,
        )
        .map_err(|err| {
            invalid(
                &format!(
                    "implicit point terms of {}",
                    model.wires[lay.blocks[b].key.wire].name
                ),
                format!("row {}, pivot {:e}", err.row, err.pivot),
                "the capacitance matrix of the point masses and dampers is not positive definite (a mass or damper that is not positive?)".into(),
            )
        })?;
        implicit.push(imp);
    }

    Ok(implicit)
}

impl Integrator {
    /// The integrator with the coupled limit its Δt was checked against, on `threads` threads
    /// ([`Integrator::new`], in `construct.rs`).
    pub(crate) fn with_limit(mut self, limit: CoupledLimit, threads: usize) -> Self {
        self.limit = Some(limit);
        self.parts = self.partition(threads);
        self
    }

    /// The coupled stability limit this integrator's Δt was checked against (`None` for the
    /// stability check's own probe).
    pub fn stability(&self) -> Option<&CoupledLimit> {
        self.limit.as_ref()
    }

    /// The Δt operators over a compiled model: the modal diagonal `M + Δt/2 C` (Eqs. 9–14), the
    /// torsional modes' trapezoidal flow, the implicit point terms with their Δt weights, and the
    /// pantographs' chains (Eq. 16) with their static equilibrium.
    pub(crate) fn from_compiled(
        cm: CompiledModel,
        plan: &Plan,
        dt: f64,
    ) -> Result<Self, CaseError> {
        let modal = ModalOps::new(&cm, dt);
        let implicit = implicit_terms(&cm, dt, &modal.d_eff)?;
        let (chains, initial_py) = pantographs::chains_at_rest(&cm, plan, dt)?;
        let ModalOps {
            k,
            c,
            d_eff,
            flow,
            segments,
        } = modal;
        let scratch = implicit
            .iter()
            .map(|i| i.sampler().scratch())
            .fold(cm.scratch.clone(), |a, b| a.max(b));
        let max_imp = implicit
            .iter()
            .map(|i| (i.n_blocks(), i.n_points(), i.sampler().n_modes()))
            .fold((0, 0, 0), |a, x| (a.0.max(x.0), a.1.max(x.1), a.2.max(x.2)));
        let mut integ = Integrator {
            dt,
            d_inv: d_eff.iter().map(|d| 1.0 / d).collect(),
            neg_d_inv: d_eff.iter().map(|d| -1.0 / d).collect(),
            k,
            c,
            segments,
            flow,
            implicit,
            chains,
            initial_py,
            scratch,
            max_imp,
            limit: None,
            parts: Vec::new(),
            cm,
        };
        // One part until `Integrator::new` splits it for `Options::threads`.
        integ.parts = integ.partition(1);
        Ok(integ)
    }

    /// The step's per-group work split for `threads` threads ([`team::partition`]).
    fn partition(&self, threads: usize) -> Vec<Part> {
        let cm = &self.cm;
        let groups: Vec<Unit> = (cm.groups.iter())
            .map(|g| Unit {
                q: g.q_off..g.q_off + g.k * g.n,
                u: g.u_base..g.u_base + g.k * g.npts,
            })
            .collect();
        let vels: Vec<(usize, std::ops::Range<usize>)> = (cm.vels.iter())
            .map(|v| (v.q_off, v.v_base..v.v_base + v.npts))
            .collect();
        let implicit: Vec<std::ops::Range<usize>> =
            self.implicit.iter().map(|i| i.modal_range()).collect();
        team::partition(
            threads,
            self.cm.model.layout.len,
            &groups,
            &vels,
            &implicit,
            cm.n_u,
            cm.n_v,
        )
    }

    /// Number of threads a run of this integrator uses (its parts; `Options::threads` asked
    /// for at most that many).
    pub fn threads(&self) -> usize {
        self.parts.len()
    }

    /// The compiled model (Δt-free): what analysis reads.
    pub fn compiled(&self) -> &CompiledModel {
        &self.cm
    }

    /// The model being integrated.
    pub fn model(&self) -> &Model {
        &self.cm.model
    }

    /// Fixed time step, s.
    pub fn dt_s(&self) -> f64 {
        self.dt
    }

    /// Instruction set of the hot loops.
    pub fn isa(&self) -> Isa {
        self.cm.isa
    }

    /// Train speed, m/s.
    pub fn speed_m_s(&self) -> f64 {
        self.cm.speed_m_s
    }

    /// Train speed, km/h.
    pub fn speed_kmh(&self) -> f64 {
        self.cm.speed_kmh
    }

    /// A workspace sized for this integrator (the only allocation; steps allocate nothing).
    pub fn workspace(&self) -> Workspace {
        let imp = || ImplicitScratch::new(self.max_imp.0, self.max_imp.1, self.max_imp.2);
        let mut ws = self.cm.workspace_with(self.scratch.clone(), imp());
        if self.parts.len() > 1 {
            ws.lanes = (0..self.parts.len())
                .map(|_| (self.scratch.clone(), imp()))
                .collect();
        }
        ws
    }

    /// The static state: the wires at rest in their static shape (the design's, or its
    /// equilibrium under the steady loads, [`crate::solve::equilibrium`]), each pantograph in
    /// static equilibrium against the static wire at its start position.
    ///
    /// Under steady loads the state also carries its accelerations, so that the first half kick
    /// holds the steady force: the torsional modes' stored acceleration is `M⁻¹Q = ω² q`, not
    /// zero, and without it the first step would miss half the mean moment's kick and the twist
    /// would oscillate about its static value with an amplitude ∝ Δt. (Without steady loads the
    /// start keeps zero accelerations, as the byte goldens were made.)
    pub fn initial_state(&self, start_m: f64) -> State {
        let mut st = State::at_rest(&self.cm.model, start_m);
        st.pantographs.u.copy_from_slice(&self.initial_py);
        if let Some(s0) = &self.cm.initial {
            st.modal.u.copy_from_slice(&s0.modal);
            st.nodes.u.copy_from_slice(&s0.nodes);
            let mut ws = self.workspace();
            self.accelerations(&mut st, &mut ws);
            st.modal.v.fill(0.0);
            st.nodes.v.fill(0.0);
            st.pantographs.v.fill(0.0);
        }
        st
    }

    /// The wire's deviation at every monitored point (the registration points) in state `st`,
    /// m, by monitor index ([`CompiledModel::monitor`]): in the static state, the datum that
    /// uplift is measured from (under ice or a mean wind the wires' static position is not the
    /// design's). Allocates a workspace: not for the step.
    pub fn monitors_at(&self, st: &State) -> Vec<f64> {
        let mut st = st.clone();
        let mut ws = self.workspace();
        self.gather(&mut st, &mut ws);
        (0..self.cm.monitor_positions().len())
            .map(|k| self.cm.monitor(&ws, k))
            .collect()
    }

    /// The slot displacements gathered at state `st` (what the point elements see), for a
    /// law evaluated once at a state (the droppers' static tensions under steady loads).
    /// Allocates a workspace: not for the step.
    pub fn gathered_at(&self, st: &State) -> Workspace {
        let mut st = st.clone();
        let mut ws = self.workspace();
        self.gather(&mut st, &mut ws);
        ws
    }

    /// Position of pantograph `p` at the state's time (model coordinates), m.
    #[inline]
    pub fn position(&self, st: &State, p: usize) -> f64 {
        self.cm.position(st, p)
    }

    /// The degrees of freedom of pantograph `p` in the pantograph arrays of the state.
    pub fn pantograph_dofs(&self, p: usize) -> std::ops::Range<usize> {
        self.cm.pantograph_dofs(p)
    }

    /// Advance `st` by one fixed step Δt (Eq. 18), in eight named stages, as MuJoCo's
    /// `mj_step`: drift, gather, fixed point forces, modal right-hand side, wind, moving points,
    /// implicit solve and kick, pantographs ([`Stage::ALL`], run by the one driver, `drive`).
    /// Allocation-free; the work is the same every step.
    pub fn step(&self, st: &mut State, ws: &mut Workspace) {
        self.drive(&Serial, &Stage::ALL, st, ws);
    }

    /// The one driver of the stages: `stages` (a run of [`Stage::ALL`], in its order), each by
    /// `how` (one thread, or a team: [`Serial`], [`TeamStages`]). Every way of stepping goes
    /// through it, so the order is written once.
    #[inline(always)]
    fn drive<H: StageStrategy>(
        &self,
        how: &H,
        stages: &[Stage],
        st: &mut State,
        ws: &mut Workspace,
    ) {
        for &s in stages {
            how.stage(self, s, st, ws);
        }
    }

    /// One stage of [`Integrator::step`] alone, for the benches that time and count each stage
    /// (`benches/step.rs`, docs/performance.md). The stages run in [`Stage::ALL`]'s order in a
    /// step; one called alone works on whatever `st` and `ws` hold.
    #[inline(never)]
    pub fn step_stage(&self, stage: Stage, st: &mut State, ws: &mut Workspace) {
        Serial.stage(self, stage, st, ws);
    }

    /// One stage on this thread.
    #[inline(always)]
    fn serial_stage(&self, stage: Stage, st: &mut State, ws: &mut Workspace) {
        match stage {
            Stage::Drift => self.drift(st),
            Stage::Gather => self.gather(st, ws),
            Stage::FixedPointForces => self.fixed_point_forces(st, ws),
            Stage::ModalRhs => self.modal_rhs(st, ws),
            Stage::Wind => self.wind(st, ws),
            Stage::MovingPoints => self.moving_points(st, ws),
            Stage::ImplicitSolve => self.implicit_solve(st, ws),
            Stage::Pantographs => self.pantographs(st, ws),
        }
    }

    /// [`Integrator::step`] with the per-group work of stages 1–2, 4 and 7 shared by a team of
    /// threads, one part each ([`crate::solve::team`]): the same operations on every value, so
    /// the same bytes as [`Integrator::step`]. The workspace must come from this integrator.
    pub fn step_team(&self, team: &Team, st: &mut State, ws: &mut Workspace) {
        let n = self.parts.len();
        if n <= 1 || team.threads() < n || ws.lanes.len() < n {
            return self.step(st, ws);
        }
        self.drive(&TeamStages(team), &Stage::ALL, st, ws);
    }

    /// One stage with a team: the per-group stages part by part on the team's threads (the
    /// drift and the gather of a part in one fork: a part's gather reads only its own drifted
    /// coordinates), the others on this thread as [`Integrator::serial_stage`].
    fn team_stage(&self, team: &Team, stage: Stage, st: &mut State, ws: &mut Workspace) {
        let n = self.parts.len();
        match stage {
            Stage::Drift => {
                // Stages 1 and 2 of the parts' modal coordinates, then the rest's drift.
                let m = &mut st.modal;
                let lanes = Lane::split(&self.parts, m, &mut ws.u, &mut ws.vel, &mut ws.lanes);
                team.fork(n, &|i| {
                    let Some(l) = Lane::take(&lanes, i) else {
                        return;
                    };
                    let p = &self.parts[i];
                    self.drift_modal(p, &mut *l.q, &mut *l.v, &*l.a);
                    self.gather_part(p, &*l.q, &*l.v, &mut *l.u, &mut *l.vel, &mut l.scr.0);
                });
                self.drift_rest(st);
            }
            // The parts' gather ran with their drift: the rest's.
            Stage::Gather => self.gather_rest(st, ws),
            Stage::ModalRhs => {
                let m = &mut st.modal;
                let f = &ws.f;
                let lanes = Lane::split(&self.parts, m, &mut ws.u, &mut ws.vel, &mut ws.lanes);
                team.fork(n, &|i| {
                    let Some(l) = Lane::take(&lanes, i) else {
                        return;
                    };
                    self.modal_rhs_part(&self.parts[i], l.a, l.q, l.v, f, &mut l.scr.0);
                });
            }
            Stage::ImplicitSolve => {
                let m = &mut st.modal;
                let lanes = Lane::split(&self.parts, m, &mut ws.u, &mut ws.vel, &mut ws.lanes);
                team.fork(n, &|i| {
                    let Some(l) = Lane::take(&lanes, i) else {
                        return;
                    };
                    let (scr, imp) = (&mut l.scr.0, &mut l.scr.1);
                    self.implicit_part(&self.parts[i], l.a, l.v, scr, imp);
                });
            }
            Stage::FixedPointForces | Stage::Wind | Stage::MovingPoints | Stage::Pantographs => {
                self.serial_stage(stage, st, ws)
            }
        }
    }

    /// Stages 2–8 of [`Integrator::step`] ([`Integrator::drive`] from the gather): the
    /// accelerations at `st` (the velocities are half-kicked on the way; callers that only want
    /// the accelerations reset them). The coupled stability check differences it without the
    /// drift ([`crate::solve::stability`]).
    #[inline(always)]
    pub(crate) fn accelerations(&self, st: &mut State, ws: &mut Workspace) {
        self.drive(&Serial, &Stage::ALL[1..], st, ws);
    }

    /// Stage 1, drift: the half kick and the drift of the modal coordinates (the exact flow of the
    /// torsional modes), of the pantograph and node coordinates; the time advances by Δt.
    #[inline(always)]
    fn drift(&self, st: &mut State) {
        for p in &self.parts {
            let m = &mut st.modal;
            let (q, v, a) = (
                &mut m.u[p.q.clone()],
                &mut m.v[p.q.clone()],
                &m.a[p.q.clone()],
            );
            self.drift_modal(p, q, v, a);
        }
        self.drift_rest(st);
    }

    /// Stage 1 on part `p`'s modal coordinates (`q`, `v`, `a` start at `p.q.start`).
    #[inline(always)]
    fn drift_modal(&self, p: &Part, q: &mut [f64], v: &mut [f64], a: &[f64]) {
        let dt = self.dt;
        let h = 0.5 * dt;
        let isa = self.cm.isa;
        let base = p.q.start;
        for &(s, e, exact) in &self.segments {
            let (s, e) = (s.max(p.q.start), e.min(p.q.end));
            if s >= e {
                continue;
            }
            let r = s - base..e - base;
            let (q, v, acc) = (&mut q[r.clone()], &mut v[r.clone()], &a[r]);
            if exact {
                kernels::kick(isa, v, acc, h);
                kernels::flow(isa, q, v, &self.flow[s..e]);
            } else {
                kernels::kick_drift(isa, q, v, acc, h, dt);
            }
        }
    }

    /// Stage 1 outside the parts: the pantographs and nodes; the time.
    #[inline(always)]
    fn drift_rest(&self, st: &mut State) {
        let dt = self.dt;
        let h = 0.5 * dt;
        let pd = &mut st.pantographs;
        for i in 0..pd.u.len() {
            pd.v[i] += h * pd.a[i];
            pd.u[i] += dt * pd.v[i];
        }
        let nd = &mut st.nodes;
        for j in 0..nd.u.len() {
            nd.v[j] += h * nd.a[j];
            nd.u[j] += dt * nd.v[j];
        }
        st.t += dt;
    }

    /// Stage 2, gather: the wires' displacement and velocity at every point (the sampler, the hot
    /// spot) and the nodes' own; the force accumulators are cleared.
    #[inline(always)]
    fn gather(&self, st: &mut State, ws: &mut Workspace) {
        for p in &self.parts {
            let m = &st.modal;
            self.gather_part(
                p,
                &m.u[p.q.clone()],
                &m.v[p.q.clone()],
                &mut ws.u[p.u.clone()],
                &mut ws.vel[p.v.clone()],
                &mut ws.scr,
            );
        }
        self.gather_rest(st, ws);
    }

    /// Stage 2 on part `p`: its point groups' displacements and its velocity points (`q`, `v`
    /// start at `p.q.start`, `u` at `p.u.start`, `vel` at `p.v.start`).
    #[inline(always)]
    fn gather_part(
        &self,
        p: &Part,
        q: &[f64],
        v: &[f64],
        u: &mut [f64],
        vel: &mut [f64],
        scr: &mut SamplerScratch,
    ) {
        let (qb, ub, vb) = (p.q.start, p.u.start, p.v.start);
        for g in &self.cm.groups[p.groups.clone()] {
            let (q0, u0) = (g.q_off - qb, g.u_base - ub);
            g.sampler.gather(
                &q[q0..q0 + g.k * g.n],
                g.k,
                &mut u[u0..u0 + g.k * g.npts],
                scr,
            );
        }
        for vp in &self.cm.vels[p.vels.clone()] {
            let (q0, v0) = (vp.q_off - qb, vp.v_base - vb);
            vp.sampler
                .gather(&v[q0..q0 + vp.n], 1, &mut vel[v0..v0 + vp.npts], scr);
        }
    }

    /// Stage 2 outside the parts: the force accumulators cleared, the nodes' own displacements
    /// and velocities.
    #[inline(always)]
    fn gather_rest(&self, st: &State, ws: &mut Workspace) {
        ws.f.fill(0.0);
        let nn = st.nodes.u.len();
        ws.u[self.cm.node_u0..self.cm.node_u0 + nn].copy_from_slice(&st.nodes.u);
        ws.vel[self.cm.node_v0..self.cm.node_v0 + nn].copy_from_slice(&st.nodes.v);
    }

    /// Stage 3, fixed point forces: droppers (Eq. 15), supports, steady arms, stitches and
    /// registrations at their slots; the nodes' accelerations and half kick.
    #[inline(always)]
    fn fixed_point_forces(&self, st: &mut State, ws: &mut Workspace) {
        let h = 0.5 * self.dt;
        let m = &self.cm.model;
        ws.slack = self.cm.fixed_forces(ws);
        for (j, node) in m.nodes.iter().enumerate() {
            st.nodes.a[j] = ws.f[self.cm.node_u0 + j] / node.mass_kg;
            st.nodes.v[j] += h * st.nodes.a[j];
        }
    }

    /// Stage 4, modal right-hand side: `−K q − C v` of every mode (Eqs. 9–14) plus the point forces
    /// scattered onto the modes (Eq. 18).
    #[inline(always)]
    fn modal_rhs(&self, st: &mut State, ws: &mut Workspace) {
        for p in &self.parts {
            let m = &mut st.modal;
            let q = p.q.clone();
            self.modal_rhs_part(
                p,
                &mut m.a[q.clone()],
                &m.u[q.clone()],
                &m.v[q],
                &ws.f,
                &mut ws.scr,
            );
        }
    }

    /// Stage 4 on part `p` (`a`, `q`, `v` start at `p.q.start`; `f` is every slot's force).
    #[inline(always)]
    fn modal_rhs_part(
        &self,
        p: &Part,
        a: &mut [f64],
        q: &[f64],
        v: &[f64],
        f: &[f64],
        scr: &mut SamplerScratch,
    ) {
        // Right-hand sides, stored in the acceleration array.
        let r = p.q.clone();
        kernels::modal_rhs(self.cm.isa, a, q, v, &self.k[r.clone()], &self.c[r]);
        for g in &self.cm.groups[p.groups.clone()] {
            let q0 = g.q_off - p.q.start;
            g.sampler.scatter_add(
                &f[g.u_base..g.u_base + g.k * g.npts],
                g.k,
                &mut a[q0..q0 + g.k * g.n],
                scr,
            );
        }
    }

    /// Stage 5, steady loads and wind: the wires' steady loads (the ice's weight), and the
    /// crosswind's fluctuating pressures on the grid, scattered onto the loaded wires (the mean is
    /// projected exactly, once).
    #[inline(always)]
    fn wind(&self, st: &mut State, ws: &mut Workspace) {
        let m = &self.cm.model;
        let isa = self.cm.isa;
        self.cm.add_steady_loads(&mut st.modal.a);
        // Crosswind: the grid's pressures (fluctuation about the mean, which is projected
        // exactly) onto every loaded wire, each block its share. The field is linear in time
        // between its samples, so inside one of its intervals the pressures are a quadratic in
        // the interval's fraction: three scatters when a step enters an interval, and each
        // step the quadratic's value; where the normal wind changes sign inside the interval,
        // one scatter per step.
        if let (Some(w), Some(wl)) = (&self.cm.wind, &m.wind) {
            let (interval, tau) = wl.field.interval(st.t);
            let enter = ws.wind_interval != Some(interval);
            ws.wind_interval = Some(interval);
            for (i, part) in w.parts.iter().enumerate() {
                let (kn, kg) = (part.k * part.n, part.k * part.ng);
                let p = &mut ws.wind_p[part.p_off..part.p_off + kg];
                let c = &mut ws.wind_c[part.c_off..part.c_off + 3 * kn];
                let q = &mut ws.wind_q[part.q_off..part.q_off + kn];
                if enter {
                    ws.wind_quadratic[i] = part.interval_forces(wl, interval, p, c, &mut ws.scr);
                }
                if ws.wind_quadratic[i] {
                    let (c0, rest) = c.split_at(kn);
                    let (c1, c2) = rest.split_at(kn);
                    kernels::quadratic(isa, q, c0, c1, c2, tau);
                } else {
                    part.step_forces(wl, st.t, p, q, &mut ws.scr);
                }
                part.add_to(isa, q, &mut st.modal.a);
            }
        }
    }

    /// Stage 6, moving points: each pantograph's contact row and wire height, the contact point's
    /// lateral position (on the head or not), the contact force (Eq. 19) and its scatter, and the
    /// contact samples.
    #[inline(always)]
    fn moving_points(&self, st: &mut State, ws: &mut Workspace) {
        self.moving_heights(st, ws);
        self.moving_lateral(st, ws);
        pantographs::heads_and_loads(&self.cm, st, ws);
        self.contact_forces(st, ws);
        self.contact_samples(ws);
    }

    /// Moving points (contacts, Eq. 19): their rows and the wire's height under each.
    #[inline(always)]
    fn moving_heights(&self, st: &mut State, ws: &mut Workspace) {
        let m = &self.cm.model;
        for (mi, mp) in self.cm.moving.iter().enumerate() {
            let x = self.cm.moving_x(st, &ws.external, mp);
            let absent = !mp.covers(x);
            ws.absent[self.cm.moving_u0 + mi] = absent;
            let h = m.static_height(mp.wire, mp.dir, x, st.track_origin_m);
            ws.moving_static[mi].0 = h;
            // A point beyond its wire's ends (a pantograph outside that tension length) has no
            // contact and no force: its row and the wire's deviation there are not needed.
            ws.u[self.cm.moving_u0 + mi] = if absent {
                h
            } else {
                h + self.cm.moving_deviation(&mut ws.rows, mp, x, &st.modal.u)
            };
            ws.samples[mp.pantograph].position_m = x;
        }
    }

    /// The contact points' lateral positions, before the contact forces: beyond the head there
    /// is no contact (the wire has left the pantograph).
    #[inline(always)]
    fn moving_lateral(&self, st: &mut State, ws: &mut Workspace) {
        let m = &self.cm.model;
        let isa = self.cm.isa;
        for lp in &self.cm.pan_lateral {
            let p = lp.pantograph;
            let slot = self.cm.moving_u0 + lp.moving;
            let mp = &self.cm.moving[lp.moving];
            let x = ws.samples[p].position_m;
            let mut z = m.static_height(lp.wire, Direction::Lateral, x, st.track_origin_m);
            ws.moving_static[lp.moving].1 = z;
            let single = self.cm.pan_points[p].is_empty();
            if ws.absent[slot] {
                // Beyond the wire's ends: no row, no deviation (and no contact).
                ws.moving_lateral[lp.moving] = (z, None);
                ws.off_head[slot] = false;
                if single {
                    ws.samples[p].lateral_m = z;
                    ws.samples[p].static_lateral_m = z;
                }
                continue;
            }
            let row = &ws.rows[mp.row_off..mp.row_off + mp.n];
            z += kernels::dot(isa, &st.modal.u[lp.lat_off..lp.lat_off + lp.n], row);
            let mut twist = None;
            if let Some(t) = lp.tors_off {
                let phi = kernels::dot(isa, &st.modal.u[t..t + lp.n], row);
                z -= lp.eccentricity_m * phi;
                twist = Some(phi);
            }
            ws.moving_lateral[lp.moving] = (z, twist);
            if single {
                ws.samples[p].lateral_m = z;
                ws.samples[p].static_lateral_m = ws.moving_static[lp.moving].1;
                if let Some(phi) = twist {
                    ws.samples[p].twist_rad = phi;
                }
            }
            // On the head: from its centre, which a canted curve moves off the track's.
            let on_head =
                z - (m.lateral.as_ref()).map_or(0.0, |l| l.head_offset_at(x + st.track_origin_m));
            ws.off_head[slot] = m.pantographs[p]
                .head_half_width_m
                .is_some_and(|hw| on_head.abs() > hw);
        }
    }

    /// The contact forces (Eq. 19, each moving element by its own law) and their scatter onto
    /// the modes through each point's row.
    #[inline(always)]
    fn contact_forces(&self, st: &mut State, ws: &mut Workspace) {
        let m = &self.cm.model;
        let isa = self.cm.isa;
        let mut io = Io {
            u: &ws.u,
            v: &ws.vel,
            f: &mut ws.f,
            loads: &ws.loads,
            off_head: &ws.off_head,
            absent: &ws.absent,
            slack: 0,
        };
        for &e in &self.cm.moving_kinds {
            m.elements[e].add_forces(&self.cm.slots[e], &mut io);
        }
        for (mi, mp) in self.cm.moving.iter().enumerate() {
            if ws.absent[self.cm.moving_u0 + mi] {
                continue; // no force (its row was not filled)
            }
            let f = ws.f[self.cm.moving_u0 + mi];
            kernels::axpy(
                isa,
                f,
                &ws.rows[mp.row_off..mp.row_off + mp.n],
                &mut st.modal.a[mp.q_off..mp.q_off + mp.n],
            );
        }
    }

    /// Each pantograph's contact sample: its force, and the height (and lateral position) of
    /// the wire it meets.
    #[inline(always)]
    fn contact_samples(&self, ws: &mut Workspace) {
        for (p, pm) in self.cm.pan_point.iter().enumerate() {
            if let Some(mi) = *pm {
                let pts = &self.cm.pan_points[p];
                if pts.is_empty() {
                    ws.samples[p].force_n = ws.f[self.cm.moving_u0 + mi];
                    ws.samples[p].wire_height_m = ws.u[self.cm.moving_u0 + mi];
                    ws.samples[p].static_height_m = ws.moving_static[mi].0;
                } else {
                    // Several contact wires: the force is theirs together; the height is the
                    // lowest wire's among those present (the one the head meets first).
                    let u0 = self.cm.moving_u0;
                    ws.samples[p].force_n = pts.iter().map(|&k| ws.f[u0 + k]).sum();
                    let mut best = mi;
                    let mut low = f64::INFINITY;
                    for &k in pts {
                        if !ws.absent[u0 + k] && ws.u[u0 + k] < low {
                            low = ws.u[u0 + k];
                            best = k;
                        }
                    }
                    ws.sample_point[p] = best;
                    ws.samples[p].wire_height_m = ws.u[u0 + best];
                    ws.samples[p].static_height_m = ws.moving_static[best].0;
                    // Its lateral position (and rotation) where the wire moves laterally.
                    if self.cm.pan_lateral.iter().any(|lp| lp.moving == best) {
                        let (z, twist) = ws.moving_lateral[best];
                        ws.samples[p].lateral_m = z;
                        ws.samples[p].static_lateral_m = ws.moving_static[best].1;
                        if let Some(phi) = twist {
                            ws.samples[p].twist_rad = phi;
                        }
                    }
                }
                ws.samples[p].wire_velocity_m_s = 0.0;
            }
        }
    }

    /// Stage 7, implicit solve and kick: the diagonal modal solve `(M + Δt/2 C)⁻¹`, the Woodbury
    /// correction of the implicit point masses and dampers, and the second half kick.
    #[inline(always)]
    fn implicit_solve(&self, st: &mut State, ws: &mut Workspace) {
        for p in &self.parts {
            let m = &mut st.modal;
            let q = p.q.clone();
            let (a, v) = (&mut m.a[q.clone()], &mut m.v[q]);
            self.implicit_part(p, a, v, &mut ws.scr, &mut ws.imp);
        }
    }

    /// Stage 7 on part `p` (`a`, `v` start at `p.q.start`).
    #[inline(always)]
    fn implicit_part(
        &self,
        p: &Part,
        a: &mut [f64],
        v: &mut [f64],
        scr: &mut SamplerScratch,
        imp: &mut ImplicitScratch,
    ) {
        let h = 0.5 * self.dt;
        let isa = self.cm.isa;
        // Solve for the accelerations and finish the velocities.
        kernels::scale(isa, a, &self.d_inv[p.q.clone()]);
        for ip in &self.implicit[p.implicit.clone()] {
            ip.correct(a, p.q.start, &self.neg_d_inv, scr, imp);
        }
        kernels::kick(isa, v, a, h);
    }

    /// Stage 8, pantographs: the wire velocity at the contact and each lumped pantograph's
    /// accelerations and half kick (Eq. 16).
    #[inline(always)]
    fn pantographs(&self, st: &mut State, ws: &mut Workspace) {
        let h = 0.5 * self.dt;
        let isa = self.cm.isa;
        for (p, pm) in self.cm.pan_point.iter().enumerate() {
            if let Some(mi) = *pm {
                let mi = if self.cm.pan_points[p].is_empty() {
                    mi
                } else {
                    ws.sample_point[p]
                };
                let mp = &self.cm.moving[mi];
                // No wire under the pantograph: its row was not filled, the velocity is zero.
                ws.samples[p].wire_velocity_m_s = if ws.absent[self.cm.moving_u0 + mi] {
                    0.0
                } else {
                    kernels::dot(
                        isa,
                        &st.modal.v[mp.q_off..mp.q_off + mp.n],
                        &ws.rows[mp.row_off..mp.row_off + mp.n],
                    )
                };
            }
            if let Some(ops) = &self.chains[p] {
                pantographs::half_kick(ops, &self.cm, p, h, st, ws);
            }
        }
    }
}
