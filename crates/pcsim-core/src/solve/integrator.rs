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
//! `Q` holds the point forces of the elements (`model::elements`) and the pantographs' own
//! springs. The wire mass matrix is diagonal plus the implicit point terms (`M = D + Φᵀ W Φ`),
//! solved exactly with the Woodbury identity ([`crate::solve::implicit`]). Every step does the
//! same fixed work: no iteration, no allocation. See ARCHITECTURE.md for why this scheme was
//! chosen over ode15s.
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
use crate::model::pantograph::{ChainOperators, PantographKind};
use crate::model::Model;
use crate::solve::implicit::{ImplicitPoints, ImplicitScratch};
use crate::solve::kernels::{self, Isa};
use crate::solve::plan::{Options, Plan};
use crate::solve::sampler::{PointSampler, SamplerScratch};
use crate::solve::state::State;
use crate::solve::workspace::{ContactSample, Workspace};

/// Wire points of one basis group, gathered for all its blocks at once.
#[derive(Debug, Clone)]
struct GroupPoints {
    sampler: PointSampler,
    /// Blocks in the group, their modes, and the group's place in the state.
    k: usize,
    n: usize,
    q_off: usize,
    /// First slot of the group in the displacement array.
    u_base: usize,
    npts: usize,
}

/// Velocity points of one block.
#[derive(Debug, Clone)]
struct VelocityPoints {
    sampler: PointSampler,
    n: usize,
    q_off: usize,
    v_base: usize,
    npts: usize,
}

/// A point under a pantograph.
#[derive(Debug, Clone)]
struct MovingPoint {
    wire: usize,
    dir: Direction,
    pantograph: usize,
    basis: SineBasis,
    origin_m: f64,
    n: usize,
    q_off: usize,
    row_off: usize,
}

/// The stepper: the model and every operator a step needs, precomputed. Immutable while
/// stepping: [`Integrator::step`] takes the state and a [`Workspace`].
#[derive(Debug, Clone)]
pub struct Integrator {
    model: Model,
    dt: f64,
    isa: Isa,
    speed_m_s: f64,
    speed_kmh: f64,
    /// Per pantograph: its distance behind the leading one, m.
    offsets: Vec<f64>,
    /// Stiffness, damping and `1/(M + Δt/2 C)` (and its negative) of every modal coordinate, by
    /// the layout.
    k: Vec<f64>,
    c: Vec<f64>,
    d_inv: Vec<f64>,
    neg_d_inv: Vec<f64>,
    groups: Vec<GroupPoints>,
    vels: Vec<VelocityPoints>,
    /// Per element kind (index into `model.elements`): its slots in a step and in an energy
    /// evaluation.
    slots: Vec<Vec<Slot>>,
    energy_slots: Vec<Vec<Slot>>,
    /// Element kinds without / with moving attachments (the latter act after the scatter).
    fixed: Vec<usize>,
    moving_kinds: Vec<usize>,
    moving: Vec<MovingPoint>,
    node_u0: usize,
    node_v0: usize,
    head_u0: usize,
    moving_u0: usize,
    n_u: usize,
    n_v: usize,
    rows_len: usize,
    implicit: Vec<ImplicitPoints>,
    chains: Vec<Option<ChainOperators>>,
    pan_off: Vec<usize>,
    /// Per pantograph: its moving point (for the samples).
    pan_point: Vec<Option<usize>>,
    initial_py: Vec<f64>,
    /// Displacement slots of the monitored attachments, and their positions.
    monitors: Vec<usize>,
    monitor_x: Vec<f64>,
    max_period_scratch: SamplerScratch,
    max_pdof: usize,
    /// Largest (blocks, points, modes) of the implicit terms, for their scratch.
    max_imp: (usize, usize, usize),
}

const TOL_X: f64 = 1e-9;

fn index_of(pts: &mut Vec<f64>, x: f64) -> usize {
    match pts.iter().position(|&p| (p - x).abs() < TOL_X) {
        Some(i) => i,
        None => {
            pts.push(x);
            pts.len() - 1
        }
    }
}

fn invalid(field: &str, value: impl std::fmt::Display, reason: String) -> CaseError {
    CaseError::Invalid {
        field: field.to_string(),
        value: value.to_string(),
        reason,
    }
}

impl Integrator {
    /// Precompute everything a step needs, after checking that the time step is stable for the
    /// model's explicit parts.
    pub fn new(model: Model, plan: &Plan, options: Options) -> Result<Self, CaseError> {
        let dt = options.dt_s;
        let isa = options.isa;
        check_stability(&model, dt)?;
        let lay = model.layout.clone();
        let block_of = |wire: usize, dir: Direction| -> Result<usize, CaseError> {
            lay.find(wire, dir).ok_or_else(|| {
                invalid(
                    "model",
                    format!("wire {wire}, {}", dir.name()),
                    "an element attaches to a direction that is not modelled".into(),
                )
            })
        };

        // Displacement points per basis group, velocity points per block, in element order.
        let ng = lay.groups.len();
        let mut gpts: Vec<Vec<f64>> = vec![Vec::new(); ng];
        let mut vpts: Vec<Vec<f64>> = vec![Vec::new(); lay.blocks.len()];
        let mut n_moving = 0;
        for e in &model.elements {
            for i in 0..e.len() {
                for a in 0..e.arity() {
                    match e.attachment(i, a) {
                        Attach::Wire { wire, dir, x_m } => {
                            let b = block_of(wire, dir)?;
                            let g = lay.blocks[b].group;
                            index_of(&mut gpts[g], x_m - lay.groups[g].origin_m);
                            if e.needs_velocity(a) {
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
        for m in &monitors_at {
            if let Attach::Wire { wire, dir, x_m } = *m {
                let b = block_of(wire, dir)?;
                let g = lay.blocks[b].group;
                index_of(&mut gpts[g], x_m - lay.groups[g].origin_m);
            }
        }
        let mut n_u = 1;
        let mut groups = Vec::with_capacity(ng);
        for (g, grp) in lay.groups.iter().enumerate() {
            let sampler = PointSampler::new(&grp.basis, &gpts[g], model.span_m, isa);
            let k = grp.blocks.len();
            let npts = gpts[g].len();
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
        for (b, xs) in vpts.iter().enumerate() {
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
        let np = model.pantographs.len();
        let (node_u0, node_v0) = (n_u, n_v);
        let (head_u0, head_v0) = (n_u + nn, n_v + nn);
        let (moving_u0, moving_v0) = (head_u0 + np, head_v0 + np);
        n_u = moving_u0 + n_moving;
        n_v = moving_v0 + n_moving;

        // Resolve every attachment.
        let wire_slot = |wire: usize, dir: Direction, x: f64, vel: bool| -> Slot {
            let b = lay.find(wire, dir).expect("checked above");
            let g = lay.blocks[b].group;
            let xl = x - lay.groups[g].origin_m;
            let gp = &groups[g];
            let j = gpts[g]
                .iter()
                .position(|&p| (p - xl).abs() < TOL_X)
                .expect("collected above");
            let kb = lay.groups[g].blocks.iter().position(|&x| x == b).unwrap();
            let v = if vel {
                let vp = &vels[vel_of_block[b].expect("collected above")];
                let jv = vpts[b]
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
        };
        let mut slots = Vec::with_capacity(model.elements.len());
        let mut energy_slots = Vec::with_capacity(model.elements.len());
        let mut moving = Vec::with_capacity(n_moving);
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
                            wire_slot(wire, dir, x_m, e.needs_velocity(a))
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
                                u: (node_u0 + j) as u32,
                                v: (node_v0 + j) as u32,
                            }
                        }
                        Attach::Ground => Slot::default(),
                        Attach::Head(p) => Slot {
                            u: (head_u0 + p) as u32,
                            v: (head_v0 + p) as u32,
                        },
                        Attach::Moving {
                            wire,
                            dir,
                            pantograph,
                        } => {
                            has_moving = true;
                            let b = block_of(wire, dir)?;
                            let bl = &lay.blocks[b];
                            let m = moving.len();
                            moving.push(MovingPoint {
                                wire,
                                dir,
                                pantograph,
                                basis: lay.basis(b).clone(),
                                origin_m: lay.groups[bl.group].origin_m,
                                n: bl.n_modes,
                                q_off: bl.offset,
                                row_off: rows_len,
                            });
                            rows_len += bl.n_modes;
                            Slot {
                                u: (moving_u0 + m) as u32,
                                v: (moving_v0 + m) as u32,
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
        let mut pan_point = vec![None; np];
        for (m, mp) in moving.iter().enumerate() {
            if pan_point[mp.pantograph].is_none() {
                pan_point[mp.pantograph] = Some(m);
            }
        }
        let monitors: Vec<usize> = monitors_at
            .iter()
            .filter_map(|m| match *m {
                Attach::Wire { wire, dir, x_m } => {
                    Some(wire_slot(wire, dir, x_m, false).u as usize)
                }
                _ => None,
            })
            .collect();
        let monitor_x: Vec<f64> = monitors_at
            .iter()
            .filter_map(|m| match *m {
                Attach::Wire { x_m, .. } => Some(x_m),
                _ => None,
            })
            .collect();

        // Modal operators.
        let mut k = vec![0.0; lay.len];
        let mut c = vec![0.0; lay.len];
        let mut d_eff = vec![0.0; lay.len];
        for b in 0..lay.blocks.len() {
            let s = model.series(b);
            for (i, j) in lay.range(b).enumerate() {
                k[j] = s.stiffness[i];
                c[j] = s.damping[i];
                d_eff[j] = s.mass[i] + 0.5 * dt * s.damping[i];
            }
        }
        // Implicit point terms per block, in element order.
        let mut imp_pts: Vec<Vec<(f64, f64)>> = vec![Vec::new(); lay.blocks.len()];
        for e in &model.elements {
            for i in 0..e.len() {
                if let Some((a, w)) = e.implicit(i) {
                    if let Attach::Wire { wire, dir, x_m } = e.attachment(i, a) {
                        let b = block_of(wire, dir)?;
                        let x = x_m - lay.groups[lay.blocks[b].group].origin_m;
                        let w = match w {
                            Weight::Mass(m) => m,
                            Weight::Damper(cd) => 0.5 * dt * cd,
                        };
                        imp_pts[b].push((x, w));
                    }
                }
            }
        }
        // Blocks of one basis group whose implicit points sit at the same positions are
        // corrected together (contiguous in the state, in order); the others alone.
        let mut implicit = Vec::new();
        let mut b = 0;
        while b < lay.blocks.len() {
            if imp_pts[b].is_empty() {
                b += 1;
                continue;
            }
            let same = |x: &Vec<(f64, f64)>, y: &Vec<(f64, f64)>| {
                x.len() == y.len() && x.iter().zip(y).all(|(p, q)| (p.0 - q.0).abs() < TOL_X)
            };
            let mut e = b + 1;
            while e < lay.blocks.len()
                && lay.blocks[e].group == lay.blocks[b].group
                && lay.blocks[e].offset == lay.blocks[e - 1].offset + lay.blocks[e - 1].n_modes
                && same(&imp_pts[b], &imp_pts[e])
            {
                e += 1;
            }
            let xs: Vec<f64> = imp_pts[b].iter().map(|p| p.0).collect();
            let weights: Vec<Vec<f64>> = (b..e)
                .map(|k| imp_pts[k].iter().map(|p| p.1).collect())
                .collect();
            let ds: Vec<&[f64]> = (b..e).map(|k| &d_eff[lay.range(k)]).collect();
            let imp = ImplicitPoints::new(
                lay.basis(b),
                model.span_m,
                isa,
                lay.blocks[b].offset,
                &xs,
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
            b = e;
        }

        // Pantographs.
        let mut chains = Vec::with_capacity(np);
        let mut pan_off = Vec::with_capacity(np);
        let mut initial_py = Vec::new();
        let mut off = 0;
        for (p, pan) in model.pantographs.iter().enumerate() {
            pan_off.push(off);
            off += pan.n_dof();
            match &pan.kind {
                PantographKind::Lumped(l) => {
                    let ops = l.operators(dt, plan.speed_kmh).ok_or_else(|| {
                        invalid(
                            &format!("pantographs[{p}].masses_kg"),
                            format!("{:?}", l.masses_kg),
                            "the pantograph's mass matrix M + Δt/2 C is singular".into(),
                        )
                    })?;
                    let x = plan.start_m - pan.offset_m + plan.speed_m_s * 0.0;
                    let kn = contact_stiffness(&model, p);
                    let h = match pan_point[p] {
                        Some(m) => {
                            let mp = &moving[m];
                            model.static_height(mp.wire, mp.dir, x)
                        }
                        None => 0.0,
                    };
                    let y = ops.static_equilibrium(kn, h).ok_or_else(|| {
                        invalid(
                            &format!("pantographs[{p}].stiffness_n_per_m"),
                            format!("{:?}", l.stiffness_n_per_m),
                            "the pantograph has no static equilibrium (a spring of zero stiffness?)".into(),
                        )
                    })?;
                    initial_py.extend(y);
                    chains.push(Some(ops));
                }
                _ => chains.push(None),
            }
        }
        let max_pdof = model
            .pantographs
            .iter()
            .map(|p| p.n_dof())
            .max()
            .unwrap_or(0);
        let scratch = groups
            .iter()
            .map(|g| g.sampler.scratch())
            .chain(vels.iter().map(|v| v.sampler.scratch()))
            .chain(implicit.iter().map(|i| i.sampler().scratch()))
            .fold(
                PointSampler::new(&SineBasis::new(1.0, 1), &[], None, isa).scratch(),
                |a, b| a.max(b),
            );
        let max_imp = implicit
            .iter()
            .map(|i| (i.n_blocks(), i.n_points(), i.sampler().n_modes()))
            .fold((0, 0, 0), |a, x| (a.0.max(x.0), a.1.max(x.1), a.2.max(x.2)));
        Ok(Integrator {
            offsets: model.pantographs.iter().map(|p| p.offset_m).collect(),
            dt,
            isa,
            speed_m_s: plan.speed_m_s,
            speed_kmh: plan.speed_kmh,
            d_inv: d_eff.iter().map(|d| 1.0 / d).collect(),
            neg_d_inv: d_eff.iter().map(|d| -1.0 / d).collect(),
            k,
            c,
            groups,
            vels,
            slots,
            energy_slots,
            fixed,
            moving_kinds,
            moving,
            node_u0,
            node_v0,
            head_u0,
            moving_u0,
            n_u,
            n_v,
            rows_len,
            implicit,
            chains,
            pan_off,
            pan_point,
            initial_py,
            monitors,
            monitor_x,
            max_period_scratch: scratch,
            max_pdof,
            max_imp,
            model,
        })
    }

    /// The model being integrated.
    pub fn model(&self) -> &Model {
        &self.model
    }

    /// Fixed time step, s.
    pub fn dt_s(&self) -> f64 {
        self.dt
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

    /// A workspace sized for this integrator (the only allocation; steps allocate nothing).
    pub fn workspace(&self) -> Workspace {
        let np = self.model.pantographs.len();
        Workspace {
            u: vec![0.0; self.n_u],
            vel: vec![0.0; self.n_v],
            f: vec![0.0; self.n_u],
            rows: vec![0.0; self.rows_len],
            scr: self.max_period_scratch.clone(),
            imp: ImplicitScratch::new(self.max_imp.0, self.max_imp.1, self.max_imp.2),
            prhs: vec![0.0; self.max_pdof],
            loads: vec![0.0; np],
            external: vec![(0.0, 0.0); np],
            samples: vec![ContactSample::default(); np],
            slack: 0,
            eu: vec![0.0; self.n_u],
            ev: vec![0.0; self.n_u],
            ef: vec![0.0; self.n_u],
        }
    }

    /// The static state: zero deviation, wires at rest, each pantograph in static equilibrium
    /// against the rigid static wire at its start position.
    pub fn initial_state(&self, start_m: f64) -> State {
        let mut st = State::at_rest(&self.model, start_m);
        st.pantographs.u.copy_from_slice(&self.initial_py);
        st
    }

    /// Position of pantograph `p` at the state's time (model coordinates), m.
    #[inline]
    pub fn position(&self, st: &State, p: usize) -> f64 {
        st.x0_m - self.offsets[p] + self.speed_m_s * st.t
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

    /// Advance `st` by one fixed step Δt. Allocation-free; the work is the same every step.
    pub fn step(&self, st: &mut State, ws: &mut Workspace) {
        let dt = self.dt;
        let h = 0.5 * dt;
        let m = &self.model;
        let isa = self.isa;
        kernels::kick_drift(isa, &mut st.modal.u, &mut st.modal.v, &st.modal.a, h, dt);
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

        // Point displacements and velocities.
        for g in &self.groups {
            g.sampler.gather(
                &st.modal.u[g.q_off..g.q_off + g.k * g.n],
                g.k,
                &mut ws.u[g.u_base..g.u_base + g.k * g.npts],
                &mut ws.scr,
            );
        }
        ws.f.fill(0.0);
        for vp in &self.vels {
            vp.sampler.gather(
                &st.modal.v[vp.q_off..vp.q_off + vp.n],
                1,
                &mut ws.vel[vp.v_base..vp.v_base + vp.npts],
                &mut ws.scr,
            );
        }
        let nn = st.nodes.u.len();
        ws.u[self.node_u0..self.node_u0 + nn].copy_from_slice(&st.nodes.u);
        ws.vel[self.node_v0..self.node_v0 + nn].copy_from_slice(&st.nodes.v);

        // Point forces of the fixed elements.
        let mut io = Io {
            u: &ws.u,
            v: &ws.vel,
            f: &mut ws.f,
            loads: &ws.loads,
            slack: 0,
        };
        for &e in &self.fixed {
            m.elements[e].add_forces(&self.slots[e], &mut io);
        }
        ws.slack = io.slack;
        for (j, node) in m.nodes.iter().enumerate() {
            st.nodes.a[j] = ws.f[self.node_u0 + j] / node.mass_kg;
            st.nodes.v[j] += h * st.nodes.a[j];
        }

        // Right-hand sides, stored in the acceleration array.
        kernels::modal_rhs(
            isa,
            &mut st.modal.a,
            &st.modal.u,
            &st.modal.v,
            &self.k,
            &self.c,
        );
        for g in &self.groups {
            g.sampler.scatter_add(
                &ws.f[g.u_base..g.u_base + g.k * g.npts],
                g.k,
                &mut st.modal.a[g.q_off..g.q_off + g.k * g.n],
                &mut ws.scr,
            );
        }

        // Moving points (contacts, Eq. 19): rows, heights, forces.
        for (mi, mp) in self.moving.iter().enumerate() {
            let p = mp.pantograph;
            let x = match m.pantographs[p].kind {
                PantographKind::External => ws.external[p].0,
                _ => self.position(st, p),
            };
            let row = &mut ws.rows[mp.row_off..mp.row_off + mp.n];
            mp.basis.fill_sines(x - mp.origin_m, row);
            ws.u[self.moving_u0 + mi] = m.static_height(mp.wire, mp.dir, x)
                + kernels::dot(isa, &st.modal.u[mp.q_off..mp.q_off + mp.n], row);
            ws.samples[p].position_m = x;
        }
        for (p, pan) in m.pantographs.iter().enumerate() {
            ws.u[self.head_u0 + p] = match pan.kind {
                PantographKind::Lumped(_) => st.pantographs.u[self.pan_off[p]],
                _ => 0.0,
            };
            ws.loads[p] = match pan.kind {
                PantographKind::MovingForce { force_n } => force_n,
                PantographKind::External => ws.external[p].1,
                PantographKind::Lumped(_) => 0.0,
            };
        }
        let mut io = Io {
            u: &ws.u,
            v: &ws.vel,
            f: &mut ws.f,
            loads: &ws.loads,
            slack: 0,
        };
        for &e in &self.moving_kinds {
            m.elements[e].add_forces(&self.slots[e], &mut io);
        }
        for (mi, mp) in self.moving.iter().enumerate() {
            let f = ws.f[self.moving_u0 + mi];
            kernels::axpy(
                isa,
                f,
                &ws.rows[mp.row_off..mp.row_off + mp.n],
                &mut st.modal.a[mp.q_off..mp.q_off + mp.n],
            );
        }
        for (p, pm) in self.pan_point.iter().enumerate() {
            if let Some(mi) = *pm {
                ws.samples[p].force_n = ws.f[self.moving_u0 + mi];
                ws.samples[p].wire_height_m = ws.u[self.moving_u0 + mi];
                ws.samples[p].wire_velocity_m_s = 0.0;
            }
        }

        // Solve for the accelerations and finish the velocities.
        kernels::scale(isa, &mut st.modal.a, &self.d_inv);
        for imp in &self.implicit {
            imp.correct(&mut st.modal.a, &self.neg_d_inv, &mut ws.scr, &mut ws.imp);
        }
        kernels::kick(isa, &mut st.modal.v, &st.modal.a, h);
        for (p, pm) in self.pan_point.iter().enumerate() {
            if let Some(mi) = *pm {
                let mp = &self.moving[mi];
                ws.samples[p].wire_velocity_m_s = kernels::dot(
                    isa,
                    &st.modal.v[mp.q_off..mp.q_off + mp.n],
                    &ws.rows[mp.row_off..mp.row_off + mp.n],
                );
            }
            if let Some(ops) = &self.chains[p] {
                let r = self.pantograph_dofs(p);
                let n = ops.n;
                let f_head = ws.f[self.head_u0 + p];
                let pd = &mut st.pantographs;
                ops.accelerations(
                    &pd.u[r.clone()],
                    &pd.v[r.clone()],
                    f_head,
                    &mut ws.prhs[..n],
                    &mut pd.a[r.clone()],
                );
                for i in r {
                    pd.v[i] += h * pd.a[i];
                }
            }
        }
    }

    /// Fill the energy arrays of `ws` at the state: displacement and velocity at every slot (in
    /// the displacement layout). Used by `analysis::energy`; allocates nothing (the step's rows
    /// are reused as scratch).
    pub(crate) fn fill_energy_io(&self, st: &State, ws: &mut Workspace) {
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
            if let PantographKind::Lumped(_) = pan.kind {
                let o = self.pan_off[p];
                ws.eu[self.head_u0 + p] = st.pantographs.u[o];
                ws.ev[self.head_u0 + p] = st.pantographs.v[o];
            }
        }
        for (mi, mp) in self.moving.iter().enumerate() {
            let p = mp.pantograph;
            let x = match m.pantographs[p].kind {
                PantographKind::External => ws.external[p].0,
                _ => self.position(st, p),
            };
            let row = &mut ws.rows[mp.row_off..mp.row_off + mp.n];
            mp.basis.fill_sines(x - mp.origin_m, row);
            ws.eu[self.moving_u0 + mi] = m.static_height(mp.wire, mp.dir, x)
                + kernels::dot(self.isa, &st.modal.u[mp.q_off..mp.q_off + mp.n], row);
            ws.ev[self.moving_u0 + mi] =
                kernels::dot(self.isa, &st.modal.v[mp.q_off..mp.q_off + mp.n], row);
        }
    }

    /// The slots of element kind `e` for an energy evaluation (velocities in the displacement
    /// layout).
    pub(crate) fn energy_slots(&self, e: usize) -> &[Slot] {
        &self.energy_slots[e]
    }

    /// Modal damping of every coordinate (by the layout).
    pub(crate) fn modal_damping(&self) -> &[f64] {
        &self.c
    }
}

/// The penalty stiffness of pantograph `p`'s contact (0 if it has none).
fn contact_stiffness(model: &Model, p: usize) -> f64 {
    use crate::model::elements::contact::{ContactLaw, Contacts};
    model
        .element::<Contacts>()
        .and_then(|c| c.0.iter().find(|c| c.pantograph == p))
        .map_or(0.0, |c| match c.law {
            ContactLaw::Penalty { stiffness_n_per_m } => stiffness_n_per_m,
            ContactLaw::Prescribed => 0.0,
        })
}

/// The explicit parts of the scheme must be stable at Δt (central differences: ω Δt < 2, with a
/// margin): the highest mode of every block, every node on its springs, every penalty contact on
/// its pantograph head, every pantograph spring. Errors name the case field to change.
pub fn check_stability(model: &Model, dt: f64) -> Result<(), CaseError> {
    use std::f64::consts::PI;
    let dt_field = |reason: String| invalid("run.dt_s", dt, reason);
    // Every block's highest mode.
    for b in 0..model.layout.blocks.len() {
        let s = model.series(b);
        let Some(last) = s.stiffness.len().checked_sub(1) else {
            continue;
        };
        let f = (s.stiffness[last] / s.mass[last]).sqrt() / (2.0 * PI);
        if 2.0 * PI * f * dt > 1.8 {
            let key = model.layout.blocks[b].key;
            let name = &model.wires[key.wire].name;
            let dir = key.dir.name();
            return Err(dt_field(format!(
                "too large for the highest {name} {dir} mode ({f:.0} Hz): the explicit scheme needs Δt < {:.2e} s (with margin)",
                1.8 / (2.0 * PI * f)
            )));
        }
    }
    // Nodes on the springs attached to them.
    let mut node_k = vec![0.0; model.nodes.len()];
    for e in &model.elements {
        for i in 0..e.len() {
            for a in 0..e.arity() {
                if let Attach::Node(j) = e.attachment(i, a) {
                    if let Some(k) = node_k.get_mut(j) {
                        *k += e.stiffness(i);
                    }
                }
            }
        }
    }
    for (j, (n, k)) in model.nodes.iter().zip(&node_k).enumerate() {
        if (k / n.mass_kg).sqrt() * dt > 1.8 {
            return Err(dt_field(format!(
                "too large for node {j} at x = {:.2} m ({} kg on {k:.0} N/m, a stitch node): explicit stability",
                n.x_m, n.mass_kg
            )));
        }
    }
    // Penalty contacts and pantograph springs.
    for (p, pan) in model.pantographs.iter().enumerate() {
        if let PantographKind::Lumped(l) = &pan.kind {
            let kn = contact_stiffness(model, p);
            let m0 = l.masses_kg[0];
            if (kn / m0).sqrt() * dt > 1.0 {
                return Err(invalid(
                    "contact.stiffness_n_per_m",
                    kn,
                    format!(
                        "too stiff for run.dt_s = {dt} s with a {m0} kg head: need √(k/m)·Δt < 1, i.e. Δt < {:.2e} s",
                        (m0 / kn).sqrt()
                    ),
                ));
            }
            for j in 0..l.masses_kg.len() {
                let m_inv = 1.0 / l.masses_kg[j] + l.masses_kg.get(j + 1).map_or(0.0, |m| 1.0 / m);
                if (l.stiffness_n_per_m[j] * m_inv).sqrt() * dt > 1.8 {
                    return Err(invalid(
                        &format!("pantographs[{p}].stiffness_n_per_m[{j}]"),
                        l.stiffness_n_per_m[j],
                        format!("too stiff for run.dt_s = {dt} s (explicit stability)"),
                    ));
                }
            }
        }
    }
    Ok(())
}
