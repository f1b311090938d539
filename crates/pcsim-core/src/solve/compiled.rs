//! The compiled model (MuJoCo's `mjModel`): everything a step reads that does not depend on the
//! time step — the model, every attachment resolved to a [`Slot`], the point groups and their
//! sampler plans, the moving points, the monitors and blow-out probes, the crosswind's scatter,
//! the static deflection under the mean wind, and the energy view. The stepper
//! ([`crate::solve::Integrator`]) adds the Δt operators on top; analysis reads this, not the
//! stepper.
//!
//! # Slots
//! Every element attachment is resolved once to a [`Slot`]: an index into the workspace's
//! arrays. The displacement array holds, in order: the ground (index 0, always zero), the wire
//! points of each basis group (all blocks of the group, block-major), the nodes, the pantograph
//! heads and the moving contact points. The velocity array holds the ground, the velocity points
//! of each block that has some, the nodes, the heads and the moving points.

use crate::error::CaseError;
use crate::model::basis::SineBasis;
use crate::model::dof::Direction;
use crate::model::elements::{Attach, Io, Slot, Weight};
use crate::model::pantograph::PantographKind;
use crate::model::wind::WindLoad;
use crate::model::{Model, WireRole};
use crate::solve::implicit::ImplicitScratch;
use crate::solve::kernels::{self, Isa};
use crate::solve::plan::Plan;
use crate::solve::sampler::{PointSampler, SamplerScratch};
use crate::solve::state::State;
use crate::solve::workspace::ExternalInput;
use crate::solve::workspace::{ContactSample, Workspace, MAX_PLAUSIBLE_HEIGHT_M};

/// Wire points of one basis group, gathered for all its blocks at once.
#[derive(Debug, Clone)]
pub(crate) struct GroupPoints {
    pub(crate) sampler: PointSampler,
    /// Blocks in the group, their modes, and the group's place in the state.
    pub(crate) k: usize,
    pub(crate) n: usize,
    pub(crate) q_off: usize,
    /// First slot of the group in the displacement array.
    pub(crate) u_base: usize,
    pub(crate) npts: usize,
}

/// Velocity points of one block.
#[derive(Debug, Clone)]
pub(crate) struct VelocityPoints {
    pub(crate) sampler: PointSampler,
    pub(crate) n: usize,
    pub(crate) q_off: usize,
    pub(crate) v_base: usize,
    pub(crate) npts: usize,
}

/// A point under a pantograph.
#[derive(Debug, Clone)]
pub(crate) struct MovingPoint {
    pub(crate) wire: usize,
    pub(crate) dir: Direction,
    pub(crate) pantograph: usize,
    /// Its contact head among the head slots (a strip, or the pantograph's one head).
    pub(crate) head: usize,
    /// Where it is ahead of the pantograph's position, m.
    pub(crate) along_m: f64,
    pub(crate) basis: SineBasis,
    pub(crate) origin_m: f64,
    pub(crate) n: usize,
    pub(crate) q_off: usize,
    pub(crate) row_off: usize,
    /// False when an earlier moving point of the same pantograph, at the same place on it, on
    /// the same basis fills the row (the directions of one wire share their sines).
    pub(crate) fills_row: bool,
}

impl MovingPoint {
    /// Whether model coordinate `x` lies on the wire (between its ends).
    #[inline]
    pub(crate) fn covers(&self, x: f64) -> bool {
        x >= self.origin_m && x <= self.origin_m + self.basis.length_m()
    }
}

/// The contact wire's lateral position under a pantograph, read with the sine row of the
/// pantograph's vertical moving point.
#[derive(Debug, Clone)]
pub(crate) struct LateralProbe {
    pub(crate) pantograph: usize,
    pub(crate) moving: usize,
    pub(crate) wire: usize,
    pub(crate) lat_off: usize,
    pub(crate) tors_off: Option<usize>,
    pub(crate) n: usize,
    pub(crate) eccentricity_m: f64,
}

/// The crosswind's per-step work: one part per basis group that carries loaded wires (a
/// catenary's messenger and contact wire share one basis; a line's tension lengths each have
/// their own), each a scatter of the grid's pressures onto its wires, and the loaded blocks
/// with their coefficients.
#[derive(Debug, Clone)]
#[doc(hidden)] // public for the unit tests in tests/suite/unit
pub struct WindStep {
    pub parts: Vec<WindPart>,
}

/// The crosswind on one basis group: the grid points inside its wires' extent and its loaded
/// wires.
#[derive(Debug, Clone)]
#[doc(hidden)] // public for the unit tests in tests/suite/unit
pub struct WindPart {
    pub sampler: PointSampler,
    /// The loaded wires' slots in `WindLoad::wires` (one block of `n` modes each in `wind_q`).
    pub slots: Vec<usize>,
    /// The grid points inside the group's basis: indices into the wind field.
    pub grid: Vec<usize>,
    /// Loaded wires, modes, grid points.
    pub k: usize,
    pub n: usize,
    pub ng: usize,
    /// (local wire slot in this part's `wind_q`, block offset in the state, coefficient `d C`).
    pub blocks: Vec<(usize, usize, f64)>,
    /// The mean load's generalised force on every loaded wire: `P̄ ∫ sin(κ_k x) dx` with `P̄`
    /// the mean pressure at the group's first support, plus on a curved track the scatter of
    /// each grid point's own mean pressure less `P̄`.
    pub mean: Vec<f64>,
    /// Each grid point's mean pressure per loaded wire (`k·ng`; all `P̄` on a straight track):
    /// the step's fluctuation is taken about it.
    pub p_mean: Vec<f64>,
    /// Where this part's pressures (`k·ng`), forces (`k·n`) and interval forces (`3·k·n`)
    /// start in the workspace's `wind_p`, `wind_q` and `wind_c`.
    pub p_off: usize,
    pub q_off: usize,
    pub c_off: usize,
}

impl WindStep {
    /// The workspace's sizes of `wind_p`, `wind_q`, `wind_c`.
    pub(crate) fn sizes(&self) -> (usize, usize, usize) {
        self.parts.iter().fold((0, 0, 0), |(p, q, c), w| {
            (p + w.k * w.ng, q + w.k * w.n, c + 3 * w.k * w.n)
        })
    }
}

impl WindPart {
    /// The generalised forces of the crosswind over field interval `interval` as a quadratic in
    /// the interval's fraction, into `c = [A0 | A1 | A2]` (the mean in `A0`; this part's
    /// slices): the grid's pressure coefficients ([`WindLoad::pressure_quadratic`], the
    /// fluctuation about the mean in `A0`) scattered once each. `false` (and `c` not filled)
    /// when the normal wind changes sign at a grid point inside the interval.
    pub fn interval_forces(
        &self,
        wl: &WindLoad,
        interval: usize,
        p: &mut [f64],
        c: &mut [f64],
        scr: &mut SamplerScratch,
    ) -> bool {
        let kn = self.k * self.n;
        for order in 0..3 {
            for (s, &slot) in self.slots.iter().enumerate() {
                let p0 = &self.p_mean[s * self.ng..(s + 1) * self.ng];
                for (gi, &g) in self.grid.iter().enumerate() {
                    let (u0, u1) = wl.field.ends(g, interval);
                    let Some(q) = wl.pressure_quadratic_at(slot, g, u0, u1) else {
                        return false;
                    };
                    let v = if order == 0 { q[0] - p0[gi] } else { q[order] };
                    p[s * self.ng + gi] = v * wl.grid_m;
                }
            }
            let out = &mut c[order * kn..(order + 1) * kn];
            if order == 0 {
                out.copy_from_slice(&self.mean);
            } else {
                out.fill(0.0);
            }
            self.sampler.scatter_add(p, self.k, out, scr);
        }
        true
    }

    /// The generalised forces at time `t` by one scatter of the step's own pressures (the law
    /// at the field's value at `t`), the mean included, into `q` (this part's slices).
    pub fn step_forces(
        &self,
        wl: &WindLoad,
        t: f64,
        p: &mut [f64],
        q: &mut [f64],
        scr: &mut SamplerScratch,
    ) {
        for (s, &slot) in self.slots.iter().enumerate() {
            let p0 = &self.p_mean[s * self.ng..(s + 1) * self.ng];
            for (gi, &g) in self.grid.iter().enumerate() {
                p[s * self.ng + gi] =
                    (wl.pressure_at(slot, g, wl.field.at(g, t)) - p0[gi]) * wl.grid_m;
            }
        }
        q.copy_from_slice(&self.mean);
        self.sampler.scatter_add(p, self.k, q, scr);
    }

    /// Add each loaded block's share `coef · q_wire` of the forces `q` (this part's) to the
    /// modal vector `a`.
    #[inline]
    pub(crate) fn add_to(&self, isa: Isa, q: &[f64], a: &mut [f64]) {
        for &(slot, off, coef) in &self.blocks {
            kernels::axpy(
                isa,
                coef,
                &q[slot * self.n..(slot + 1) * self.n],
                &mut a[off..off + self.n],
            );
        }
    }
}

/// The implicit point terms (steady-arm masses, support dampers) of consecutive blocks of one
/// basis group whose points sit at the same positions: corrected together. Δt-free: a damper's
/// weight `Δt/2 · c` is formed by the stepper.
#[derive(Debug, Clone)]
pub(crate) struct ImplicitGroup {
    /// The blocks, contiguous in the state.
    pub(crate) blocks: std::ops::Range<usize>,
    /// Positions of the points (the group's coordinates), m.
    pub(crate) xs: Vec<f64>,
    /// Per block: the weight of every point.
    pub(crate) weights: Vec<Vec<Weight>>,
}

pub(crate) const TOL_X: f64 = 1e-9;

fn index_of(pts: &mut Vec<f64>, x: f64) -> usize {
    match pts.iter().position(|&p| (p - x).abs() < TOL_X) {
        Some(i) => i,
        None => {
            pts.push(x);
            pts.len() - 1
        }
    }
}

/// The static start state under the steady loads and how it was found
/// (`equilibrium.rs`'s `static_start`, set by `Integrator::new` in `construct.rs`).
#[derive(Debug, Clone, PartialEq)]
pub struct StaticStart {
    /// Modal coordinates (by the layout).
    pub modal: Vec<f64>,
    /// Node displacements.
    pub nodes: Vec<f64>,
    /// Newton steps taken.
    pub newton_steps: usize,
    /// Conjugate-gradient iterations in all.
    pub cg_iterations: usize,
    /// The residual's norm against the steady loads' (N against N).
    pub relative_residual: f64,
}

/// A quantity of the model refused, in the model's terms (`compile/` names the case field).
pub(crate) fn refused(
    what: crate::error::ModelQuantity,
    value: impl std::fmt::Display,
    reason: String,
) -> CaseError {
    CaseError::Model {
        what,
        value: value.to_string(),
        reason,
    }
}

pub(crate) fn invalid(field: &str, value: impl std::fmt::Display, reason: String) -> CaseError {
    CaseError::Invalid {
        field: field.to_string(),
        value: value.to_string(),
        reason,
    }
}

/// The compiled model: the model with every attachment resolved, the point groups with their
/// sampler plans, the moving points, monitors and probes, the crosswind's scatter, the run's
/// kinematics (speed, pantograph offsets) and the static state under the mean wind. It holds no
/// Δt: the stepper ([`crate::solve::Integrator`]) owns the operators of one time step.
#[derive(Debug, Clone)]
pub struct CompiledModel {
    pub(crate) model: Model,
    #[doc(hidden)]
    pub isa: Isa,
    pub(crate) speed_m_s: f64,
    pub(crate) speed_kmh: f64,
    /// Per pantograph: its distance behind the leading one, m.
    pub(crate) offsets: Vec<f64>,
    pub(crate) groups: Vec<GroupPoints>,
    pub(crate) vels: Vec<VelocityPoints>,
    /// Per element kind (index into `model.elements`): its slots in a step and in an energy
    /// evaluation.
    pub(crate) slots: Vec<Vec<Slot>>,
    pub(crate) energy_slots: Vec<Vec<Slot>>,
    /// Element kinds without / with moving attachments (the latter act after the scatter).
    pub(crate) fixed: Vec<usize>,
    pub(crate) moving_kinds: Vec<usize>,
    pub(crate) moving: Vec<MovingPoint>,
    pub(crate) node_u0: usize,
    pub(crate) node_v0: usize,
    pub(crate) head_u0: usize,
    /// Per pantograph: its first contact head among the head slots (`head_u0 + head_base[p] +
    /// s` is strip `s`'s running face).
    pub(crate) head_base: Vec<usize>,
    pub(crate) moving_u0: usize,
    pub(crate) n_u: usize,
    pub(crate) n_v: usize,
    pub(crate) rows_len: usize,
    /// The implicit point terms, grouped for their corrections.
    pub(crate) implicit: Vec<ImplicitGroup>,
    pub(crate) pan_off: Vec<usize>,
    /// Per pantograph: its first moving point (for the samples, and the lateral probe).
    pub(crate) pan_point: Vec<Option<usize>>,
    /// Per pantograph with more than one contact wire (a line's overlaps): its vertical moving
    /// points, one per contact wire; empty otherwise.
    pub(crate) pan_points: Vec<Vec<usize>>,
    /// Displacement slots of the monitored attachments, and their positions.
    pub(crate) monitors: Vec<usize>,
    pub(crate) monitor_x: Vec<f64>,
    /// The largest sampler scratch of the groups, velocity points and wind.
    pub(crate) scratch: SamplerScratch,
    pub(crate) max_pdof: usize,
    /// The true modal stiffness and damping of every coordinate (by the layout).
    pub(crate) k_true: Vec<f64>,
    pub(crate) c_true: Vec<f64>,
    /// The contact wires' lateral (and torsional) coordinates under the pantographs: one probe
    /// per vertical contact whose wire moves laterally (a line's every contact wire), in order.
    pub(crate) pan_lateral: Vec<LateralProbe>,
    /// Blow-out probes: displacement slots of the contact wire's lateral deviation, positions.
    pub(crate) probes: Vec<usize>,
    pub(crate) probe_x: Vec<f64>,
    #[doc(hidden)]
    pub wind: Option<WindStep>,
    /// The wires' steady loads that the design does not carry (the ice's weight), projected on
    /// their modes: (offset in the modal vector, load per mode).
    pub(crate) steady_loads: Vec<(usize, Vec<f64>)>,
    /// The static state under the steady loads (modal coordinates, node displacements), the
    /// initial state's; `None` when there are none (the design shape is the equilibrium).
    pub(crate) initial: Option<StaticStart>,
    /// The blow-up bound of the contact wire's deviation from its design height, m.
    pub(crate) max_deviation_m: f64,
}

/// Each pantograph's first moving point, and its vertical contact points when it has two or more
/// (a head of collector strips; one contact point needs no list).
#[allow(clippy::type_complexity)]
fn pantograph_points(np: usize, moving: &[MovingPoint]) -> (Vec<Option<usize>>, Vec<Vec<usize>>) {
    let mut pan_point = vec![None; np];
    for (m, mp) in moving.iter().enumerate() {
        if pan_point[mp.pantograph].is_none() {
            pan_point[mp.pantograph] = Some(m);
        }
    }
    let mut pan_points = vec![Vec::new(); np];
    for (m, mp) in moving.iter().enumerate() {
        if mp.dir == Direction::Vertical {
            pan_points[mp.pantograph].push(m);
        }
    }
    for pts in &mut pan_points {
        if pts.len() < 2 {
            pts.clear();
        }
    }
    (pan_point, pan_points)
}

impl CompiledModel {
    /// Resolve every attachment of `model` and plan its point groups, for a run at
    /// `plan`'s speed with the kernels of `isa`, in named steps: collect the points, lay out the
    /// slots, resolve the elements, the pantographs' probes, the monitors and blow-out probes, the
    /// static springs, the implicit groups and the crosswind's scatter; then the static
    /// deflection under the mean wind. Errors name the model part that cannot be compiled (an
    /// attachment to a direction that is not modelled, a lateral spring on a node, a static wind
    /// deflection that does not converge).
    pub fn new(model: Model, plan: &Plan, isa: Isa) -> Result<Self, CaseError> {
        let points = Points::collect(&model)?;
        let sl = SlotLayout::new(&model, &points, isa);
        let el = resolve_elements(&model, &points, &sl)?;
        let np = model.pantographs.len();
        let (pan_point, pan_points) = pantograph_points(np, &el.moving);
        let pan_lateral = lateral_probes(&model, &el.moving);
        let wire_slots = |at: &[Attach]| -> (Vec<usize>, Vec<f64>) {
            at.iter()
                .filter_map(|m| match *m {
                    Attach::Wire { wire, dir, x_m } => {
                        Some((sl.wire_slot(&points, wire, dir, x_m, false).u as usize, x_m))
                    }
                    _ => None,
                })
                .unzip()
        };
        let (monitors, monitor_x) = wire_slots(&points.monitors_at);
        let (probes, probe_x) = wire_slots(&points.probe_at);
        let lay = &model.layout;
        let (mut k_true, mut c_true) = (vec![0.0; lay.len], vec![0.0; lay.len]);
        for b in 0..lay.blocks.len() {
            let s = model.series(b);
            for (i, j) in lay.range(b).enumerate() {
                k_true[j] = s.stiffness[i];
                c_true[j] = s.damping[i];
            }
        }
        let implicit = implicit_groups(&model)?;
        let mut pan_off = Vec::with_capacity(np);
        let mut off = 0;
        for pan in &model.pantographs {
            pan_off.push(off);
            off += pan.n_dof();
        }
        let wind = wind_step(&model, isa)?;
        let max_pdof = model
            .pantographs
            .iter()
            .map(|p| p.n_dof())
            .max()
            .unwrap_or(0);
        let scratch = sl
            .groups
            .iter()
            .map(|g| g.sampler.scratch())
            .chain(sl.vels.iter().map(|v| v.sampler.scratch()))
            .chain(
                wind.iter()
                    .flat_map(|w| &w.parts)
                    .map(|p| p.sampler.scratch()),
            )
            .fold(
                PointSampler::new(&SineBasis::new(1.0, 1), &[], None, isa).scratch(),
                |a, b| a.max(b),
            );
        let cm = CompiledModel {
            offsets: model.pantographs.iter().map(|p| p.offset_m).collect(),
            isa,
            speed_m_s: plan.speed_m_s,
            speed_kmh: plan.speed_kmh,
            groups: sl.groups,
            vels: sl.vels,
            slots: el.slots,
            energy_slots: el.energy_slots,
            fixed: el.fixed,
            moving_kinds: el.moving_kinds,
            moving: el.moving,
            node_u0: sl.node_u0,
            node_v0: sl.node_v0,
            head_u0: sl.head_u0,
            head_base: sl.head_base,
            moving_u0: sl.moving_u0,
            n_u: sl.n_u,
            n_v: sl.n_v,
            rows_len: el.rows_len,
            implicit,
            pan_off,
            pan_point,
            pan_points,
            monitors,
            monitor_x,
            scratch,
            max_pdof,
            k_true,
            c_true,
            pan_lateral,
            probes,
            probe_x,
            wind,
            steady_loads: steady_loads(&model),
            initial: None,
            max_deviation_m: system_height_m(&model).unwrap_or(MAX_PLAUSIBLE_HEIGHT_M),
            model,
        };
        Ok(cm)
    }

    /// The model.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// How far the contact wire may stray from its design height before a run is treated as
    /// blown up, m: the system height (the messenger's design height above the contact wire's,
    /// largest along the model, at the supports), which no contact wire passes without having
    /// gone through its messenger; [`MAX_PLAUSIBLE_HEIGHT_M`] when the model has no messenger.
    pub fn max_wire_deviation_m(&self) -> f64 {
        self.max_deviation_m
    }

    /// Instruction set of the hot loops.
    pub fn isa(&self) -> Isa {
        self.isa
    }

    /// Train speed, m/s.
    pub fn speed_m_s(&self) -> f64 {
        self.speed_m_s
    }

    /// Train speed, km/h.
    pub fn speed_kmh(&self) -> f64 {
        self.speed_kmh
    }

    /// A workspace for this model with the stepper's scratch (the only allocation; steps
    /// allocate nothing).
    pub(crate) fn workspace_with(&self, scr: SamplerScratch, imp: ImplicitScratch) -> Workspace {
        let np = self.model.pantographs.len();
        let wind_sizes = self.wind.as_ref().map_or((0, 0, 0), |w| w.sizes());
        Workspace {
            u: vec![0.0; self.n_u],
            vel: vec![0.0; self.n_v],
            f: vec![0.0; self.n_u],
            rows: vec![0.0; self.rows_len],
            scr,
            imp,
            lanes: Vec::new(),
            prhs: vec![0.0; self.max_pdof],
            loads: vec![0.0; 2 * np],
            external: vec![ExternalInput::default(); np],
            off_head: vec![false; self.n_u],
            moving_lateral: vec![(0.0, None); self.moving.len()],
            moving_static: vec![(0.0, 0.0); self.moving.len()],
            absent: vec![false; self.n_u],
            sample_point: self.pan_point.iter().map(|p| p.unwrap_or(0)).collect(),
            samples: vec![ContactSample::default(); np],
            slack: 0,
            eu: vec![0.0; self.n_u],
            ev: vec![0.0; self.n_u],
            ef: vec![0.0; self.n_u],
            wind_p: vec![0.0; wind_sizes.0],
            wind_q: vec![0.0; wind_sizes.1],
            wind_interval: None,
            wind_quadratic: vec![false; self.wind.as_ref().map_or(0, |w| w.parts.len())],
            wind_c: vec![0.0; wind_sizes.2],
        }
    }

    /// The static start state under the steady loads and how it was found (`None` without
    /// steady loads: the design shape is the start).
    pub fn static_start(&self) -> Option<&StaticStart> {
        self.initial.as_ref()
    }

    /// Whether any steady load acts (the mean crosswind, the ice's weight): then the design
    /// shape is not the equilibrium and the start state is solved.
    pub(crate) fn has_steady_loads(&self) -> bool {
        !self.steady_loads.is_empty()
            || self
                .wind
                .as_ref()
                .is_some_and(|w| w.parts.iter().any(|p| !p.blocks.is_empty()))
    }

    /// The static residual at the modal coordinates and node displacements `x` (modal vector,
    /// then the nodes), every velocity zero: the fixed elements' point forces (Eq. 15 and the
    /// supports, steady arms, stitches and registrations, by their own force laws) scattered on
    /// the modes, minus the modal stiffness `K q` (Eqs. 9–14, every direction), plus the steady
    /// loads (the mean crosswind, the ice's weight); then the nodes' net forces. Contacts and
    /// pantographs are left out. Zero at a static equilibrium of the wires.
    pub(crate) fn static_residual(&self, x: &[f64], ws: &mut Workspace, r: &mut [f64]) {
        let nm = self.model.layout.len;
        let (q, un) = x.split_at(nm);
        self.gather_points(q, ws);
        ws.u[self.node_u0..self.node_u0 + un.len()].copy_from_slice(un);
        ws.f.fill(0.0);
        self.fixed_forces(ws);
        let (rq, rn) = r.split_at_mut(nm);
        for ((ri, qi), ki) in rq.iter_mut().zip(q).zip(&self.k_true) {
            *ri = -ki * qi;
        }
        self.scatter_points(ws, rq);
        self.add_steady_loads(rq);
        for part in self.wind.iter().flat_map(|w| &w.parts) {
            part.add_to(self.isa, &part.mean, rq);
        }
        rn.copy_from_slice(&ws.f[self.node_u0..self.node_u0 + rn.len()]);
    }

    /// The wires' displacement at every point of the point groups from the modal coordinates
    /// `q` (the sampler's gather, the hot spot), into `ws.u`.
    #[inline(always)]
    pub(crate) fn gather_points(&self, q: &[f64], ws: &mut Workspace) {
        for g in &self.groups {
            g.sampler.gather(
                &q[g.q_off..g.q_off + g.k * g.n],
                g.k,
                &mut ws.u[g.u_base..g.u_base + g.k * g.npts],
                &mut ws.scr,
            );
        }
    }

    /// The fixed elements' point forces (droppers, Eq. 15; supports, steady arms, stitches,
    /// registrations), each by its own law, added into `ws.f` at the displacements and
    /// velocities of `ws`; returns the number of slack droppers.
    #[inline(always)]
    pub(crate) fn fixed_forces(&self, ws: &mut Workspace) -> usize {
        let mut io = Io {
            u: &ws.u,
            v: &ws.vel,
            f: &mut ws.f,
            loads: &ws.loads,
            off_head: &ws.off_head,
            absent: &ws.absent,
            slack: 0,
        };
        for &e in &self.fixed {
            self.model.elements[e].add_forces(&self.slots[e], &mut io);
        }
        io.slack
    }

    /// The point forces of `ws.f` scattered onto the modes of the point groups (Eq. 18's
    /// generalised forces), added into `rhs`.
    #[inline(always)]
    pub(crate) fn scatter_points(&self, ws: &mut Workspace, rhs: &mut [f64]) {
        for g in &self.groups {
            g.sampler.scatter_add(
                &ws.f[g.u_base..g.u_base + g.k * g.npts],
                g.k,
                &mut rhs[g.q_off..g.q_off + g.k * g.n],
                &mut ws.scr,
            );
        }
    }

    /// Add the wires' steady loads (the ice's weight) to the modal right-hand side `rhs`.
    #[inline]
    pub(crate) fn add_steady_loads(&self, rhs: &mut [f64]) {
        for (off, load) in &self.steady_loads {
            for (a, l) in rhs[*off..*off + load.len()].iter_mut().zip(load) {
                *a += l;
            }
        }
    }

    /// Power of the crosswind on the wires at the state (after a step: the step's load and
    /// the state's velocities), W.
    pub fn wind_power(&self, st: &State, ws: &Workspace) -> f64 {
        let Some(w) = &self.wind else {
            return 0.0;
        };
        w.parts
            .iter()
            .flat_map(|p| {
                p.blocks.iter().map(move |&(slot, off, coef)| {
                    let q = &ws.wind_q[p.q_off + slot * p.n..p.q_off + (slot + 1) * p.n];
                    coef * kernels::dot(self.isa, q, &st.modal.v[off..off + p.n])
                })
            })
            .sum()
    }

    /// Positions (model coordinates) of the blow-out probes of the contact wire's lateral
    /// deviation, m.
    pub fn probe_positions(&self) -> &[f64] {
        &self.probe_x
    }

    /// Lateral deviation of the contact wire at probe `k` after the last step, m.
    #[inline]
    pub fn probe(&self, ws: &Workspace, k: usize) -> f64 {
        ws.u[self.probes[k]]
    }

    /// Position of pantograph `p` at the state's time (model coordinates), m.
    #[inline]
    pub fn position(&self, st: &State, p: usize) -> f64 {
        st.x0_m - self.offsets[p] + self.speed_m_s * st.t
    }

    /// Where the moving point `mp` is this step, model coordinates, m: an external
    /// pantograph's input position, else its pantograph's own position.
    #[inline]
    pub(crate) fn moving_x(&self, st: &State, external: &[ExternalInput], mp: &MovingPoint) -> f64 {
        let p = mp.pantograph;
        match self.model.pantographs[p].kind {
            PantographKind::External => external[p].position_m,
            // A strip's place on the head (0 for a head without strips: the bytes unchanged).
            _ if mp.along_m != 0.0 => self.position(st, p) + mp.along_m,
            _ => self.position(st, p),
        }
    }

    /// `Σ q_k row_k`, the deviation of the moving point `mp` at `x` (Eq. 5; `q`: the modal
    /// coordinates, its block at `mp.q_off`), with its sine row filled in the same pass
    /// (`kernels::fill_sines_dot`: the bytes of `kernels::fill_sines`, then `kernels::dot`),
    /// unless an earlier point of the same pantograph on the same basis filled it.
    #[inline]
    pub(crate) fn moving_deviation(
        &self,
        rows: &mut [f64],
        mp: &MovingPoint,
        x: f64,
        q: &[f64],
    ) -> f64 {
        let row = &mut rows[mp.row_off..mp.row_off + mp.n];
        let q = &q[mp.q_off..mp.q_off + mp.n];
        if mp.fills_row {
            kernels::fill_sines_dot(self.isa, mp.basis.theta(x - mp.origin_m), row, q)
        } else {
            kernels::dot(self.isa, q, row)
        }
    }

    /// The height of moving point `m`'s wire at `x` (model coordinates) in the start state: the
    /// design's static height plus the static start's deviation under the steady loads, m.
    pub(crate) fn start_height(&self, m: usize, x: f64) -> f64 {
        let mp = &self.moving[m];
        let h = self
            .model
            .static_height(mp.wire, mp.dir, x, self.model.track_origin_m);
        match &self.initial {
            Some(s0) => {
                let mut row = vec![0.0; mp.n];
                mp.basis.fill_sines(x - mp.origin_m, &mut row);
                h + row
                    .iter()
                    .zip(&s0.modal[mp.q_off..mp.q_off + mp.n])
                    .map(|(a, b)| a * b)
                    .sum::<f64>()
            }
            None => h,
        }
    }

    /// Pantograph `p`'s contact points when it has more than one contact wire (a line's
    /// overlaps), one per contact wire; empty otherwise.
    pub fn contact_points(&self, p: usize) -> &[usize] {
        &self.pan_points[p]
    }

    /// The wire of moving point `m`.
    pub fn moving_wire(&self, m: usize) -> usize {
        self.moving[m].wire
    }

    /// Moving point `m` in the last step: its force on its wire (N), its wire's height under
    /// the pantograph (m), and whether the wire reaches there.
    pub fn moving_sample(&self, ws: &Workspace, m: usize) -> (f64, f64, bool) {
        let i = self.moving_u0 + m;
        (ws.f[i], ws.u[i], !ws.absent[i])
    }

    /// The contact force on collector strip `s` of pantograph `p` in the last step (on every
    /// contact wire together), N: the reaction on its running face.
    #[inline]
    pub fn head_force(&self, ws: &Workspace, p: usize, s: usize) -> f64 {
        0.0 - ws.f[self.head_u0 + self.head_base[p] + s]
    }

    /// The contact gap of pantograph `p` in the last step, m: over its vertical contact points
    /// on a wire that is present and on the head, the least height of the wire above the running
    /// face under it (negative while they press: the penalty's penetration, Eq. 19); 0 for a
    /// pantograph without a head (a prescribed force), infinite when no wire is over the head.
    pub fn contact_gap(&self, ws: &Workspace, p: usize) -> f64 {
        if !matches!(self.model.pantographs[p].kind, PantographKind::Lumped(_)) {
            return 0.0;
        }
        let mut gap = f64::INFINITY;
        for (mi, mp) in self.moving.iter().enumerate() {
            if mp.pantograph != p || mp.dir != Direction::Vertical {
                continue;
            }
            let i = self.moving_u0 + mi;
            if ws.absent[i] || ws.off_head[i] {
                continue;
            }
            let h = self.head_u0 + self.head_base[p] + mp.head;
            gap = gap.min(ws.u[i] - ws.u[h]);
        }
        gap
    }

    /// The degrees of freedom of pantograph `p` in the pantograph arrays of the state.
    pub fn pantograph_dofs(&self, p: usize) -> std::ops::Range<usize> {
        let o = self.pan_off[p];
        o..o + self.model.pantographs[p].n_dof()
    }

    /// Positions of the monitored attachments (the steady arms' registration points), model
    /// coordinates, m.
    pub fn monitor_positions(&self) -> &[f64] {
        &self.monitor_x
    }

    /// Deviation at monitored point `k` after the last step, m.
    #[inline]
    pub fn monitor(&self, ws: &Workspace, k: usize) -> f64 {
        ws.u[self.monitors[k]]
    }

    /// The element kind of type `T` and its slots in a step (read with
    /// [`Self::displacements`]).
    pub fn element<T: 'static>(&self) -> Option<(&T, &[Slot])> {
        self.model.elements.iter().enumerate().find_map(|(i, e)| {
            e.as_any()
                .downcast_ref::<T>()
                .map(|t| (t, &self.slots[i][..]))
        })
    }

    /// The slots of element kind `e` (index into `model.elements`) in a step.
    pub fn slots(&self, e: usize) -> &[Slot] {
        &self.slots[e]
    }

    /// The displacement array of the last step (read with [`Self::slots`]).
    pub fn displacements<'a>(&self, ws: &'a Workspace) -> &'a [f64] {
        &ws.u
    }

    /// The point elements' view of the state for their energy and dissipation: displacement
    /// and velocity at every slot (in the displacement layout), in the energy arrays of `ws`.
    /// Used by `analysis::energy`; allocates nothing (the step's rows are reused as scratch).
    pub(crate) fn energy_io<'w>(&self, st: &State, ws: &'w mut Workspace) -> Io<'w> {
        self.fill_energy_io(st, ws);
        Io {
            u: &ws.eu,
            v: &ws.ev,
            f: &mut ws.ef,
            loads: &ws.loads,
            off_head: &ws.off_head,
            absent: &ws.absent,
            slack: 0,
        }
    }

    fn fill_energy_io(&self, st: &State, ws: &mut Workspace) {
        let m = &self.model;
        ws.eu.fill(0.0);
        ws.ev.fill(0.0);
        ws.ef.fill(0.0);
        for g in &self.groups {
            let r = g.q_off..g.q_off + g.k * g.n;
            let o = g.u_base..g.u_base + g.k * g.npts;
            g.sampler.gather(
                &st.modal.u[r.clone()],
                g.k,
                &mut ws.eu[o.clone()],
                &mut ws.scr,
            );
            g.sampler
                .gather(&st.modal.v[r], g.k, &mut ws.ev[o], &mut ws.scr);
        }
        let nn = st.nodes.u.len();
        ws.eu[self.node_u0..self.node_u0 + nn].copy_from_slice(&st.nodes.u);
        ws.ev[self.node_u0..self.node_u0 + nn].copy_from_slice(&st.nodes.v);
        for (p, pan) in m.pantographs.iter().enumerate() {
            if let PantographKind::Lumped(l) = &pan.kind {
                let (o, h) = (self.pan_off[p], self.head_u0 + self.head_base[p]);
                if l.strips.is_empty() {
                    ws.eu[h] = st.pantographs.u[o];
                    ws.ev[h] = st.pantographs.v[o];
                }
                for (s, strip) in l.strips.iter().enumerate() {
                    ws.eu[h + s] = st.pantographs.u[o + s] + strip.height_offset_m;
                    ws.ev[h + s] = st.pantographs.v[o + s];
                }
            }
        }
        for (mi, mp) in self.moving.iter().enumerate() {
            let x = self.moving_x(st, &ws.external, mp);
            ws.absent[self.moving_u0 + mi] = !mp.covers(x);
            ws.eu[self.moving_u0 + mi] = m.static_height(mp.wire, mp.dir, x, st.track_origin_m)
                + self.moving_deviation(&mut ws.rows, mp, x, &st.modal.u);
            let row = &ws.rows[mp.row_off..mp.row_off + mp.n];
            ws.ev[self.moving_u0 + mi] =
                kernels::dot(self.isa, &st.modal.v[mp.q_off..mp.q_off + mp.n], row);
        }
    }

    /// The slots of element kind `e` for an energy evaluation (velocities in the displacement
    /// layout).
    pub(crate) fn energy_slots(&self, e: usize) -> &[Slot] {
        &self.energy_slots[e]
    }

    /// Modal damping of every coordinate (by the layout), aerodynamic damping included.
    pub(crate) fn modal_damping(&self) -> &[f64] {
        &self.c_true
    }
}

/// The largest design height of the messenger above the contact wire along the model (the system
/// height at the supports), sampled every metre, m; `None` without a messenger and a contact wire.
fn system_height_m(model: &Model) -> Option<f64> {
    let has = |r: WireRole| model.wires.iter().any(|w| w.role == r);
    if !(has(WireRole::Messenger) && has(WireRole::Contact)) {
        return None;
    }
    let n = model.length_m().ceil().max(1.0) as usize;
    let h = (0..=n)
        .map(|i| {
            model
                .statics
                .system_height(i as f64)
                .unwrap_or(f64::NEG_INFINITY)
        })
        .fold(f64::NEG_INFINITY, f64::max);
    (h.is_finite() && h > 0.0).then_some(h)
}

/// The block of `wire` in direction `dir`, or an error: an element attaches to a direction that
/// is not modelled.
fn block_of(model: &Model, wire: usize, dir: Direction) -> Result<usize, CaseError> {
    model.layout.find(wire, dir).ok_or_else(|| {
        invalid(
            "model",
            format!("wire {wire}, {}", dir.name()),
            "an element attaches to a direction that is not modelled".into(),
        )
    })
}

/// Step 1: the points a step reads, in element order — displacement points per basis group,
/// velocity points per block (group coordinates), the moving points' count, the monitors and
/// the blow-out probes.
struct Points {
    gpts: Vec<Vec<f64>>,
    vpts: Vec<Vec<f64>>,
    n_moving: usize,
    monitors_at: Vec<Attach>,
    probe_at: Vec<Attach>,
}

impl Points {
    fn collect(model: &Model) -> Result<Points, CaseError> {
        let lay = &model.layout;
        let mut gpts: Vec<Vec<f64>> = vec![Vec::new(); lay.groups.len()];
        let mut vpts: Vec<Vec<f64>> = vec![Vec::new(); lay.blocks.len()];
        let mut n_moving = 0;
        for e in &model.elements {
            for i in 0..e.len() {
                for a in 0..e.arity() {
                    match e.attachment(i, a) {
                        Attach::Wire { wire, dir, x_m } => {
                            let b = block_of(model, wire, dir)?;
                            let g = lay.blocks[b].group;
                            index_of(&mut gpts[g], x_m - lay.groups[g].origin_m);
                            if e.needs_velocity(i, a) {
                                index_of(&mut vpts[b], x_m - lay.groups[g].origin_m);
                            }
                        }
                        Attach::Moving { .. } => n_moving += 1,
                        _ => {}
                    }
                }
            }
        }
        let monitors_at: Vec<Attach> = model.elements.iter().flat_map(|e| e.monitors()).collect();
        // Blow-out probes: each contact wire's lateral deviation at droppers and mid-spans.
        let probe_at: Vec<Attach> = match &model.lateral {
            Some(lg) => (lg.probes_m.iter())
                .filter(|&&(wire, _)| lay.find(wire, Direction::Lateral).is_some())
                .map(|&(wire, x_m)| Attach::Wire {
                    wire,
                    dir: Direction::Lateral,
                    x_m,
                })
                .collect(),
            None => Vec::new(),
        };
        for m in monitors_at.iter().chain(&probe_at) {
            if let Attach::Wire { wire, dir, x_m } = *m {
                let b = block_of(model, wire, dir)?;
                let g = lay.blocks[b].group;
                index_of(&mut gpts[g], x_m - lay.groups[g].origin_m);
            }
        }
        Ok(Points {
            gpts,
            vpts,
            n_moving,
            monitors_at,
            probe_at,
        })
    }
}

/// Step 2: the slot layout — the point groups and velocity points with their sampler plans, and
/// where the nodes, the pantograph heads and the moving points sit in the workspace's arrays.
struct SlotLayout<'m> {
    lay: &'m crate::model::dof::Layout,
    groups: Vec<GroupPoints>,
    vels: Vec<VelocityPoints>,
    vel_of_block: Vec<Option<usize>>,
    node_u0: usize,
    node_v0: usize,
    head_u0: usize,
    head_v0: usize,
    /// Per pantograph: its first contact head among the head slots.
    head_base: Vec<usize>,
    moving_u0: usize,
    moving_v0: usize,
    n_u: usize,
    n_v: usize,
}

impl<'m> SlotLayout<'m> {
    fn new(model: &'m Model, points: &Points, isa: Isa) -> SlotLayout<'m> {
        let lay = &model.layout;
        let mut n_u = 1;
        let mut groups = Vec::with_capacity(lay.groups.len());
        for (g, grp) in lay.groups.iter().enumerate() {
            let sampler = PointSampler::new(&grp.basis, &points.gpts[g], model.span_m, isa);
            let k = grp.blocks.len();
            let npts = points.gpts[g].len();
            groups.push(GroupPoints {
                sampler,
                k,
                n: grp.basis.n_modes(),
                q_off: grp.offset,
                u_base: n_u,
                npts,
            });
            n_u += k * npts;
        }
        let mut n_v = 1;
        let mut vels = Vec::new();
        let mut vel_of_block = vec![None; lay.blocks.len()];
        for (b, xs) in points.vpts.iter().enumerate() {
            if xs.is_empty() {
                continue;
            }
            let bl = &lay.blocks[b];
            vel_of_block[b] = Some(vels.len());
            vels.push(VelocityPoints {
                sampler: PointSampler::new(lay.basis(b), xs, model.span_m, isa),
                n: bl.n_modes,
                q_off: bl.offset,
                v_base: n_v,
                npts: xs.len(),
            });
            n_v += xs.len();
        }
        let nn = model.nodes.len();
        // One head slot per contact head: a pantograph's strips, or its one head.
        let mut head_base = Vec::with_capacity(model.pantographs.len());
        let mut nh = 0;
        for p in &model.pantographs {
            head_base.push(nh);
            nh += p.n_heads();
        }
        let (node_u0, node_v0) = (n_u, n_v);
        let (head_u0, head_v0) = (n_u + nn, n_v + nn);
        let (moving_u0, moving_v0) = (head_u0 + nh, head_v0 + nh);
        SlotLayout {
            lay,
            groups,
            vels,
            vel_of_block,
            node_u0,
            node_v0,
            head_u0,
            head_v0,
            head_base,
            moving_u0,
            moving_v0,
            n_u: moving_u0 + points.n_moving,
            n_v: moving_v0 + points.n_moving,
        }
    }

    /// The slot of a wire point that [`Points::collect`] collected (with its velocity slot when
    /// `vel`).
    fn wire_slot(&self, points: &Points, wire: usize, dir: Direction, x: f64, vel: bool) -> Slot {
        let lay = self.lay;
        let b = lay.find(wire, dir).expect("checked when collected");
        let g = lay.blocks[b].group;
        let xl = x - lay.groups[g].origin_m;
        let gp = &self.groups[g];
        let j = points.gpts[g]
            .iter()
            .position(|&p| (p - xl).abs() < TOL_X)
            .expect("collected above");
        let kb = lay.groups[g].blocks.iter().position(|&x| x == b).unwrap();
        let v = if vel {
            let vp = &self.vels[self.vel_of_block[b].expect("collected above")];
            let jv = points.vpts[b]
                .iter()
                .position(|&p| (p - xl).abs() < TOL_X)
                .expect("collected above");
            (vp.v_base + jv) as u32
        } else {
            0
        };
        Slot {
            u: (gp.u_base + kb * gp.npts + j) as u32,
            v,
        }
    }
}

/// Step 3's result: every element kind's slots (in a step and in an energy evaluation), the
/// moving points, and which kinds act before and after the scatter.
struct Elements {
    slots: Vec<Vec<Slot>>,
    energy_slots: Vec<Vec<Slot>>,
    moving: Vec<MovingPoint>,
    fixed: Vec<usize>,
    moving_kinds: Vec<usize>,
    rows_len: usize,
}

/// Step 3: resolve every attachment of every element to its slot; a moving point shares the
/// sine row of an earlier point of the same pantograph on the same basis.
fn resolve_elements(
    model: &Model,
    points: &Points,
    sl: &SlotLayout<'_>,
) -> Result<Elements, CaseError> {
    let lay = &model.layout;
    let nn = model.nodes.len();
    let mut slots = Vec::with_capacity(model.elements.len());
    let mut energy_slots = Vec::with_capacity(model.elements.len());
    let mut moving: Vec<MovingPoint> = Vec::with_capacity(points.n_moving);
    let mut fixed = Vec::new();
    let mut moving_kinds = Vec::new();
    let mut rows_len = 0;
    for (ei, e) in model.elements.iter().enumerate() {
        let mut s = Vec::with_capacity(e.len() * e.arity());
        let mut has_moving = false;
        for i in 0..e.len() {
            for a in 0..e.arity() {
                let slot = match e.attachment(i, a) {
                    Attach::Wire { wire, dir, x_m } => {
                        sl.wire_slot(points, wire, dir, x_m, e.needs_velocity(i, a))
                    }
                    Attach::Node(j) => {
                        if j >= nn {
                            return Err(invalid(
                                "model",
                                j,
                                format!("{} attaches to a node that does not exist", e.kind()),
                            ));
                        }
                        Slot {
                            u: (sl.node_u0 + j) as u32,
                            v: (sl.node_v0 + j) as u32,
                        }
                    }
                    Attach::Ground => Slot::default(),
                    Attach::Head { pantograph, head } => Slot {
                        u: (sl.head_u0 + sl.head_base[pantograph] + head) as u32,
                        v: (sl.head_v0 + sl.head_base[pantograph] + head) as u32,
                    },
                    Attach::Moving {
                        wire,
                        dir,
                        pantograph,
                        head,
                        along_m,
                    } => {
                        has_moving = true;
                        let b = block_of(model, wire, dir)?;
                        let bl = &lay.blocks[b];
                        let m = moving.len();
                        let basis = lay.basis(b).clone();
                        let origin_m = lay.groups[bl.group].origin_m;
                        let shared = moving.iter().find(|o| {
                            o.fills_row
                                && o.pantograph == pantograph
                                && o.along_m == along_m
                                && o.basis == basis
                                && o.origin_m == origin_m
                        });
                        let (row_off, fills_row) = match shared {
                            Some(o) => (o.row_off, false),
                            None => (rows_len, true),
                        };
                        if fills_row {
                            rows_len += bl.n_modes;
                        }
                        moving.push(MovingPoint {
                            wire,
                            dir,
                            pantograph,
                            head: sl.head_base[pantograph] + head,
                            along_m,
                            basis,
                            origin_m,
                            n: bl.n_modes,
                            q_off: bl.offset,
                            row_off,
                            fills_row,
                        });
                        Slot {
                            u: (sl.moving_u0 + m) as u32,
                            v: (sl.moving_v0 + m) as u32,
                        }
                    }
                };
                s.push(slot);
            }
        }
        energy_slots.push(s.iter().map(|x| Slot { u: x.u, v: x.u }).collect());
        slots.push(s);
        if has_moving {
            moving_kinds.push(ei);
        } else {
            fixed.push(ei);
        }
    }
    Ok(Elements {
        slots,
        energy_slots,
        moving,
        fixed,
        moving_kinds,
        rows_len,
    })
}

/// Step 4: the contact wires' lateral (and torsional) coordinates under the pantographs, one
/// probe per vertical moving point whose wire moves laterally, read with its sine row.
fn lateral_probes(model: &Model, moving: &[MovingPoint]) -> Vec<LateralProbe> {
    let lay = &model.layout;
    let contact_ecc = model
        .lateral
        .as_ref()
        .map_or(0.0, |l| l.contact_point_eccentricity_m);
    (moving.iter().enumerate())
        .filter(|(_, mp)| mp.dir == Direction::Vertical)
        .filter_map(|(mi, mp)| {
            let lb = lay.find(mp.wire, Direction::Lateral)?;
            Some(LateralProbe {
                pantograph: mp.pantograph,
                moving: mi,
                wire: mp.wire,
                lat_off: lay.blocks[lb].offset,
                tors_off: lay
                    .find(mp.wire, Direction::Torsional)
                    .map(|t| lay.blocks[t].offset),
                n: mp.n,
                eccentricity_m: contact_ecc,
            })
        })
        .collect()
}

/// Step 5: the wires' steady loads per modelled direction, projected exactly on their sine
/// modes: `∫ f sin(k x) dx = f (1 − cos k L)/k` (`2 f/k` on the odd modes, 0 on the even).
fn steady_loads(model: &Model) -> Vec<(usize, Vec<f64>)> {
    let lay = &model.layout;
    let mut out = Vec::new();
    for b in 0..lay.blocks.len() {
        let key = lay.blocks[b].key;
        let i = Direction::ALL
            .iter()
            .position(|&d| d == key.dir)
            .unwrap_or(0);
        let f = model.wires[key.wire].static_load_per_m[i];
        if f == 0.0 {
            continue;
        }
        let basis = lay.basis(b);
        let load = (0..basis.n_modes())
            .map(|j| {
                if j % 2 == 0 {
                    2.0 * f / basis.wavenumber(j)
                } else {
                    0.0
                }
            })
            .collect();
        out.push((lay.blocks[b].offset, load));
    }
    out
}

/// Step 6: the implicit point terms per block, in element order; blocks of one basis group whose
/// implicit points sit at the same positions are corrected together (contiguous in the state,
/// in order), the others alone.
fn implicit_groups(model: &Model) -> Result<Vec<ImplicitGroup>, CaseError> {
    let lay = &model.layout;
    let mut imp_pts: Vec<Vec<(f64, Weight)>> = vec![Vec::new(); lay.blocks.len()];
    for e in &model.elements {
        for i in 0..e.len() {
            if let Some((a, w)) = e.implicit(i) {
                if let Attach::Wire { wire, dir, x_m } = e.attachment(i, a) {
                    let b = block_of(model, wire, dir)?;
                    let x = x_m - lay.groups[lay.blocks[b].group].origin_m;
                    imp_pts[b].push((x, w));
                }
            }
        }
    }
    let same = |x: &Vec<(f64, Weight)>, y: &Vec<(f64, Weight)>| {
        x.len() == y.len() && x.iter().zip(y).all(|(p, q)| (p.0 - q.0).abs() < TOL_X)
    };
    let mut implicit = Vec::new();
    let mut b = 0;
    while b < lay.blocks.len() {
        if imp_pts[b].is_empty() {
            b += 1;
            continue;
        }
        let mut e = b + 1;
        while e < lay.blocks.len()
            && lay.blocks[e].group == lay.blocks[b].group
            && lay.blocks[e].offset == lay.blocks[e - 1].offset + lay.blocks[e - 1].n_modes
            && same(&imp_pts[b], &imp_pts[e])
        {
            e += 1;
        }
        implicit.push(ImplicitGroup {
            blocks: b..e,
            xs: imp_pts[b].iter().map(|p| p.0).collect(),
            weights: (b..e)
                .map(|k| imp_pts[k].iter().map(|p| p.1).collect())
                .collect(),
        });
        b = e;
    }
    Ok(implicit)
}

/// Step 7: the crosswind's scatter — per basis group that carries loaded wires, one scatter of
/// the grid's pressures inside the group's extent onto its wires, then each loaded block takes
/// its coefficient's share; the mean load projected exactly, once (each wire covers its whole
/// basis, so the uniform mean's projection is `P̄ (1 − cos κ L)/κ`). A catenary's wires share
/// one group, so it has one part; a line has one per tension length, whose grid points are
/// those over its wires (an overlap's points load both tension lengths' wires).
fn wind_step(model: &Model, isa: Isa) -> Result<Option<WindStep>, CaseError> {
    let Some(wl) = &model.wind else {
        return Ok(None);
    };
    let lay = &model.layout;
    if wl.wires.is_empty() {
        return Err(invalid("wind", "no wire", "the wind loads no wire".into()));
    }
    // The loaded wires by basis group, in the order of their first loaded wire.
    let mut groups: Vec<(usize, Vec<usize>)> = Vec::new();
    for (slot, ww) in wl.wires.iter().enumerate() {
        let g = lay.blocks[block_of(model, ww.wire, Direction::Vertical)?].group;
        match groups.iter_mut().find(|(h, _)| *h == g) {
            Some((_, slots)) => slots.push(slot),
            None => groups.push((g, vec![slot])),
        }
    }
    let (mut p_off, mut q_off, mut c_off) = (0, 0, 0);
    let mut parts = Vec::with_capacity(groups.len());
    for (g, slots) in groups {
        let b0 = block_of(model, wl.wires[slots[0]].wire, Direction::Vertical)?;
        let basis = lay.basis(b0).clone();
        let origin = lay.groups[g].origin_m;
        let length = basis.length_m();
        let mut blocks = Vec::new();
        for (s, &slot) in slots.iter().enumerate() {
            let ww = &wl.wires[slot];
            for (dir, coef) in [
                (Direction::Vertical, ww.vertical_m),
                (Direction::Lateral, ww.lateral_m),
                (Direction::Torsional, ww.torsional_m2),
            ] {
                if let (Some(b), true) = (lay.find(ww.wire, dir), coef != 0.0) {
                    blocks.push((s, lay.blocks[b].offset, coef));
                }
            }
        }
        let grid: Vec<usize> = (0..wl.field.x_m.len())
            .filter(|&j| {
                let x = wl.field.x_m[j] - origin;
                x > 0.0 && x < length
            })
            .collect();
        let xs: Vec<f64> = grid.iter().map(|&j| wl.field.x_m[j] - origin).collect();
        let n = basis.n_modes();
        let k = slots.len();
        let mut mean = vec![0.0; k * n];
        for (s, &slot) in slots.iter().enumerate() {
            let p0 = wl.mean_pressure(slot);
            for j in 0..n {
                let odd = if j % 2 == 0 { 2.0 } else { 0.0 };
                mean[s * n + j] = p0 * odd / basis.wavenumber(j);
            }
        }
        let ng = xs.len();
        let sampler = PointSampler::new(&basis, &xs, model.span_m, isa);
        let mut p_mean = Vec::with_capacity(k * ng);
        for &slot in &slots {
            p_mean.extend(grid.iter().map(|&g| wl.mean_pressure_at(slot, g)));
        }
        if !wl.normal_by_grid.is_empty() {
            // A curve: each grid point's own mean less the uniform part already projected.
            let mut dp = p_mean.clone();
            for (s, &slot) in slots.iter().enumerate() {
                let p0 = wl.mean_pressure(slot);
                for v in &mut dp[s * ng..(s + 1) * ng] {
                    *v = (*v - p0) * wl.grid_m;
                }
            }
            sampler.scatter_add(&dp, k, &mut mean, &mut sampler.scratch());
        }
        parts.push(WindPart {
            sampler,
            slots,
            grid,
            k,
            n,
            ng,
            blocks,
            mean,
            p_mean,
            p_off,
            q_off,
            c_off,
        });
        p_off += k * ng;
        q_off += k * n;
        c_off += 3 * k * n;
    }
    Ok(Some(WindStep { parts }))
}

/// The penalty stiffness of pantograph `p`'s contact (0 if it has none).
pub(crate) fn contact_stiffness(model: &Model, p: usize) -> f64 {
    contact_stiffness_on(model, p, None)
}

/// The penalty stiffness of pantograph `p`'s contact with `wire` (its first contact when
/// `None`), N/m; 0 for a prescribed load.
pub(crate) fn contact_stiffness_on(model: &Model, p: usize, wire: Option<usize>) -> f64 {
    use crate::model::elements::contact::{ContactLaw, Contacts};
    model
        .element::<Contacts>()
        .and_then(|c| {
            c.0.iter()
                .find(|c| c.pantograph == p && wire.is_none_or(|w| w == c.wire))
        })
        .map_or(0.0, |c| match c.law {
            ContactLaw::Penalty { stiffness_n_per_m } => stiffness_n_per_m,
            ContactLaw::Prescribed { .. } => 0.0,
        })
}
