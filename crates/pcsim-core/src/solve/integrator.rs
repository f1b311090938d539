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
use crate::model::{Model, WireRole};
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
    /// False when an earlier moving point of the same pantograph on the same basis fills the
    /// row (the directions of one wire share their sines).
    fills_row: bool,
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
    /// The true modal stiffness and damping (`k`, `c` above are zero on the exactly advanced
    /// modes).
    k_true: Vec<f64>,
    c_true: Vec<f64>,
    /// Contiguous ranges of the modal vector: (start, end, advanced by its exact flow).
    segments: Vec<(usize, usize, bool)>,
    /// The one-step flow of every mode (used on the exact ranges).
    flow: Vec<[f64; 4]>,
    /// Per pantograph: the contact wire's lateral (and torsional) coordinates under it.
    pan_lateral: Vec<Option<LateralProbe>>,
    /// Blow-out probes: displacement slots of the contact wire's lateral deviation, positions.
    probes: Vec<usize>,
    probe_x: Vec<f64>,
    wind: Option<WindStep>,
    /// The lateral springs of the static state, resolved to displacement slots.
    static_springs: Vec<(Vec<(usize, f64)>, f64)>,
    /// Static deflection under the mean wind (modal coordinates), the initial state's.
    initial_modal: Option<Vec<f64>>,
}

/// The contact wire's lateral position under a pantograph, read with the sine row of the
/// pantograph's vertical moving point.
#[derive(Debug, Clone)]
struct LateralProbe {
    moving: usize,
    wire: usize,
    lat_off: usize,
    tors_off: Option<usize>,
    n: usize,
    eccentricity_m: f64,
}

/// The crosswind's per-step work: a scatter of the grid's pressures onto every loaded wire, and
/// the loaded blocks with their coefficients.
#[derive(Debug, Clone)]
struct WindStep {
    sampler: PointSampler,
    /// Loaded wires (one block of `n` modes each in `wind_q`), grid points.
    k: usize,
    n: usize,
    ng: usize,
    /// (wire slot in `wind_q`, block offset in the state, coefficient `d C`).
    blocks: Vec<(usize, usize, f64)>,
    /// The mean load's generalised "pressure" of every loaded wire, `P̄ ∫ sin(κ_k x) dx`.
    mean: Vec<f64>,
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
        // Blow-out probes: the contact wire's lateral deviation at droppers and mid-spans.
        let contact_wire = model.wire_index(WireRole::Contact);
        let probe_at: Vec<Attach> = match (&model.lateral, contact_wire) {
            (Some(lg), Some(cw)) if lay.find(cw, Direction::Lateral).is_some() => lg
                .probes_m
                .iter()
                .map(|&x_m| Attach::Wire {
                    wire: cw,
                    dir: Direction::Lateral,
                    x_m,
                })
                .collect(),
            _ => Vec::new(),
        };
        for m in monitors_at.iter().chain(&probe_at) {
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
                            let basis = lay.basis(b).clone();
                            let origin_m = lay.groups[bl.group].origin_m;
                            let shared = moving.iter().find(|o: &&MovingPoint| {
                                o.fills_row
                                    && o.pantograph == pantograph
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
                                basis,
                                origin_m,
                                n: bl.n_modes,
                                q_off: bl.offset,
                                row_off,
                                fills_row,
                            });
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
        let contact_ecc = model
            .lateral
            .as_ref()
            .map_or(0.0, |l| l.contact_point_eccentricity_m);
        let pan_lateral: Vec<Option<LateralProbe>> = pan_point
            .iter()
            .map(|pm| {
                let mi = (*pm)?;
                let mp = &moving[mi];
                if mp.dir != Direction::Vertical {
                    return None;
                }
                let lb = lay.find(mp.wire, Direction::Lateral)?;
                Some(LateralProbe {
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
            .collect();
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
        let mut probes = Vec::with_capacity(probe_at.len());
        let mut probe_x = Vec::with_capacity(probe_at.len());
        for p in &probe_at {
            if let Attach::Wire { wire, dir, x_m } = *p {
                probes.push(wire_slot(wire, dir, x_m, false).u as usize);
                probe_x.push(x_m);
            }
        }
        // The lateral springs of the static state (for the static deflection under wind).
        let mut springs = Vec::new();
        for e in &model.elements {
            e.static_springs(&mut springs);
        }
        let mut static_springs = Vec::with_capacity(springs.len());
        for sp in &springs {
            let mut terms = Vec::with_capacity(sp.terms.len());
            for &(a, w) in &sp.terms {
                match a {
                    Attach::Wire { wire, dir, x_m } => {
                        block_of(wire, dir)?;
                        terms.push((wire_slot(wire, dir, x_m, false).u as usize, w));
                    }
                    Attach::Ground => {}
                    _ => return Err(invalid(
                        "model",
                        format!("{a:?}"),
                        "a lateral spring of the static state attaches to a node or a pantograph"
                            .into(),
                    )),
                }
            }
            static_springs.push((terms, sp.stiffness_n_per_m));
        }

        // Modal operators. Torsional blocks are advanced by their exact flow: their stiffness
        // and damping leave the explicit right-hand side.
        let mut k = vec![0.0; lay.len];
        let mut c = vec![0.0; lay.len];
        let mut k_true = vec![0.0; lay.len];
        let mut c_true = vec![0.0; lay.len];
        let mut d_eff = vec![0.0; lay.len];
        let mut flow = vec![[1.0, 0.0, 0.0, 1.0]; lay.len];
        let mut segments: Vec<(usize, usize, bool)> = Vec::new();
        for b in 0..lay.blocks.len() {
            let s = model.series(b);
            let exact = lay.blocks[b].key.dir == Direction::Torsional;
            let r = lay.range(b);
            for (i, j) in r.clone().enumerate() {
                k_true[j] = s.stiffness[i];
                c_true[j] = s.damping[i];
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
                            model.static_height(mp.wire, mp.dir, x, model.track_origin_m)
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
        // Crosswind: one scatter of the grid's pressures onto every loaded wire (they share one
        // sine basis), then each loaded block takes its coefficient's share.
        let wind = match &model.wind {
            None => None,
            Some(wl) => {
                let first = wl
                    .wires
                    .first()
                    .ok_or_else(|| invalid("wind", "no wire", "the wind loads no wire".into()))?;
                let b0 = block_of(first.wire, Direction::Vertical)?;
                let g0 = lay.blocks[b0].group;
                let basis = lay.basis(b0).clone();
                let origin = lay.groups[g0].origin_m;
                let mut blocks = Vec::new();
                for (slot, ww) in wl.wires.iter().enumerate() {
                    let bv = block_of(ww.wire, Direction::Vertical)?;
                    if lay.blocks[bv].group != g0 {
                        return Err(invalid(
                            "wind",
                            &model.wires[ww.wire].name,
                            "every wire under wind must share one sine basis".into(),
                        ));
                    }
                    for (dir, coef) in [
                        (Direction::Vertical, ww.vertical_m),
                        (Direction::Lateral, ww.lateral_m),
                        (Direction::Torsional, ww.torsional_m2),
                    ] {
                        if let (Some(b), true) = (lay.find(ww.wire, dir), coef != 0.0) {
                            blocks.push((slot, lay.blocks[b].offset, coef));
                        }
                    }
                }
                let n = basis.n_modes();
                let k = wl.wires.len();
                let xs: Vec<f64> = wl.field.x_m.iter().map(|x| x - origin).collect();
                let mut mean = vec![0.0; k * n];
                for slot in 0..k {
                    let p0 = wl.mean_pressure(slot);
                    for j in 0..n {
                        let odd = if j % 2 == 0 { 2.0 } else { 0.0 };
                        mean[slot * n + j] = p0 * odd / basis.wavenumber(j);
                    }
                }
                Some(WindStep {
                    sampler: PointSampler::new(&basis, &xs, model.span_m, isa),
                    k,
                    n,
                    ng: xs.len(),
                    blocks,
                    mean,
                })
            }
        };
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
            .chain(wind.iter().map(|w| w.sampler.scratch()))
            .fold(
                PointSampler::new(&SineBasis::new(1.0, 1), &[], None, isa).scratch(),
                |a, b| a.max(b),
            );
        let max_imp = implicit
            .iter()
            .map(|i| (i.n_blocks(), i.n_points(), i.sampler().n_modes()))
            .fold((0, 0, 0), |a, x| (a.0.max(x.0), a.1.max(x.1), a.2.max(x.2)));
        Ok::<Integrator, CaseError>(Integrator {
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
            k_true,
            c_true,
            segments,
            flow,
            pan_lateral,
            probes,
            probe_x,
            wind,
            static_springs,
            initial_modal: None,
            model,
        })
        .and_then(|mut integ: Integrator| {
            integ.initial_modal = integ.static_wind_deflection()?;
            Ok(integ)
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
            wind_p: vec![0.0; self.wind.as_ref().map_or(0, |w| w.k * w.ng)],
            wind_q: vec![0.0; self.wind.as_ref().map_or(0, |w| w.k * w.n)],
        }
    }

    /// The static state: zero deviation, wires at rest, each pantograph in static equilibrium
    /// against the rigid static wire at its start position.
    pub fn initial_state(&self, start_m: f64) -> State {
        let mut st = State::at_rest(&self.model, start_m);
        st.pantographs.u.copy_from_slice(&self.initial_py);
        if let Some(q) = &self.initial_modal {
            st.modal.u.copy_from_slice(q);
        }
        st
    }

    /// The static deflection of the lateral and torsional series under the mean wind (the
    /// drag and the moment), with the linear springs of the static state
    /// ([`crate::model::elements::StaticSpring`]): `(K + Σ k g gᵀ) q = Q̄`, solved by conjugate
    /// gradients preconditioned with the modal stiffness, with the step's own gather and
    /// scatter. The pendulums are linearised about the still-air state (`f0/L`); their
    /// second-order vertical stretch `k δ²/2L` is left to the dynamics. `None` without wind.
    fn static_wind_deflection(&self) -> Result<Option<Vec<f64>>, CaseError> {
        let Some(w) = &self.wind else {
            return Ok(None);
        };
        let lay = &self.model.layout;
        let n_all = lay.len;
        let mut mask = vec![false; n_all];
        for b in 0..lay.blocks.len() {
            if lay.blocks[b].key.dir != Direction::Vertical {
                mask[lay.range(b)].fill(true);
            }
        }
        let mut rhs = vec![0.0; n_all];
        for &(slot, off, coef) in &w.blocks {
            if mask[off] {
                for j in 0..w.n {
                    rhs[off + j] += coef * w.mean[slot * w.n + j];
                }
            }
        }
        let bnorm = rhs.iter().map(|x| x * x).sum::<f64>().sqrt();
        if bnorm == 0.0 {
            return Ok(None);
        }
        let mut ws = self.workspace();
        let apply = |x: &[f64], y: &mut [f64], ws: &mut Workspace| {
            for g in &self.groups {
                g.sampler.gather(
                    &x[g.q_off..g.q_off + g.k * g.n],
                    g.k,
                    &mut ws.u[g.u_base..g.u_base + g.k * g.npts],
                    &mut ws.scr,
                );
            }
            ws.f.fill(0.0);
            for (terms, kk) in &self.static_springs {
                let d: f64 = terms.iter().map(|&(sl, wt)| wt * ws.u[sl]).sum();
                for &(sl, wt) in terms {
                    ws.f[sl] += kk * d * wt;
                }
            }
            for (yi, (xi, ki)) in y.iter_mut().zip(x.iter().zip(&self.k_true)) {
                *yi = ki * xi;
            }
            for g in &self.groups {
                g.sampler.scatter_add(
                    &ws.f[g.u_base..g.u_base + g.k * g.npts],
                    g.k,
                    &mut y[g.q_off..g.q_off + g.k * g.n],
                    &mut ws.scr,
                );
            }
            for (yi, m) in y.iter_mut().zip(&mask) {
                if !m {
                    *yi = 0.0;
                }
            }
        };
        let precond = |r: &[f64], z: &mut [f64]| {
            for ((zi, ri), (ki, m)) in z.iter_mut().zip(r).zip(self.k_true.iter().zip(&mask)) {
                *zi = if *m && *ki > 0.0 { ri / ki } else { 0.0 };
            }
        };
        let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
        let mut x = vec![0.0; n_all];
        let mut r = rhs.clone();
        let mut z = vec![0.0; n_all];
        precond(&r, &mut z);
        let mut p = z.clone();
        let mut ap = vec![0.0; n_all];
        let mut rz = dot(&r, &z);
        let max_iter = 20 * n_all.max(100);
        for _ in 0..max_iter {
            apply(&p, &mut ap, &mut ws);
            let pap = dot(&p, &ap);
            if pap.is_nan() || pap <= 0.0 {
                break;
            }
            let alpha = rz / pap;
            for i in 0..n_all {
                x[i] += alpha * p[i];
                r[i] -= alpha * ap[i];
            }
            if dot(&r, &r).sqrt() <= 1e-12 * bnorm {
                return Ok(Some(x));
            }
            precond(&r, &mut z);
            let rz_new = dot(&r, &z);
            let beta = rz_new / rz;
            rz = rz_new;
            for i in 0..n_all {
                p[i] = z[i] + beta * p[i];
            }
        }
        Err(invalid(
            "wind",
            "the static deflection",
            format!(
                "the static lateral solve under the mean wind did not converge (residual {:.2e} of the load): a lateral spring of zero or negative stiffness?",
                dot(&r, &r).sqrt() / bnorm
            ),
        ))
    }

    /// Power of the crosswind on the wires at the state (after a step: the step's load and
    /// the state's velocities), W.
    pub fn wind_power(&self, st: &State, ws: &Workspace) -> f64 {
        let Some(w) = &self.wind else {
            return 0.0;
        };
        w.blocks
            .iter()
            .map(|&(slot, off, coef)| {
                coef * kernels::dot(
                    self.isa,
                    &ws.wind_q[slot * w.n..(slot + 1) * w.n],
                    &st.modal.v[off..off + w.n],
                )
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
    fn moving_x(&self, st: &State, external: &[(f64, f64)], mp: &MovingPoint) -> f64 {
        let p = mp.pantograph;
        match self.model.pantographs[p].kind {
            PantographKind::External => external[p].0,
            _ => self.position(st, p),
        }
    }

    /// The sine row of the moving point `mp` at `x` (filled here unless an earlier point of
    /// the same pantograph on the same basis filled it).
    #[inline]
    fn moving_row<'w>(&self, rows: &'w mut [f64], mp: &MovingPoint, x: f64) -> &'w [f64] {
        let row = &mut rows[mp.row_off..mp.row_off + mp.n];
        if mp.fills_row {
            mp.basis.fill_sines(x - mp.origin_m, row);
        }
        row
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

    /// Advance `st` by one fixed step Δt (Eq. 18), in eight named stages, as MuJoCo's
    /// `mj_step`: drift, gather, fixed point forces, modal right-hand side, wind, moving points,
    /// implicit solve and kick, pantographs. Allocation-free; the work is the same every step.
    pub fn step(&self, st: &mut State, ws: &mut Workspace) {
        self.drift(st);
        self.gather(st, ws);
        self.fixed_point_forces(st, ws);
        self.modal_rhs(st, ws);
        self.wind(st, ws);
        self.moving_points(st, ws);
        self.implicit_solve(st, ws);
        self.pantographs(st, ws);
    }

    /// Stage 1, drift: the half kick and the drift of the modal coordinates (the exact flow of the
    /// torsional modes), of the pantograph and node coordinates; the time advances by Δt.
    #[inline(always)]
    fn drift(&self, st: &mut State) {
        let dt = self.dt;
        let h = 0.5 * dt;
        let isa = self.isa;
        for &(a, b, exact) in &self.segments {
            let (q, v, acc) = (
                &mut st.modal.u[a..b],
                &mut st.modal.v[a..b],
                &st.modal.a[a..b],
            );
            if exact {
                kernels::kick(isa, v, acc, h);
                kernels::flow(isa, q, v, &self.flow[a..b]);
            } else {
                kernels::kick_drift(isa, q, v, acc, h, dt);
            }
        }
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
    }

    /// Stage 3, fixed point forces: droppers (Eq. 15), supports, steady arms, stitches and
    /// registrations at their slots; the nodes' accelerations and half kick.
    #[inline(always)]
    fn fixed_point_forces(&self, st: &mut State, ws: &mut Workspace) {
        let h = 0.5 * self.dt;
        let m = &self.model;
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
    }

    /// Stage 4, modal right-hand side: `−K q − C v` of every mode (Eqs. 9–14) plus the point forces
    /// scattered onto the modes (Eq. 18).
    #[inline(always)]
    fn modal_rhs(&self, st: &mut State, ws: &mut Workspace) {
        let isa = self.isa;
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
    }

    /// Stage 5, wind: the crosswind's fluctuating pressures on the grid, scattered onto the loaded
    /// wires (the mean is projected exactly, once).
    #[inline(always)]
    fn wind(&self, st: &mut State, ws: &mut Workspace) {
        let m = &self.model;
        let isa = self.isa;
        // Crosswind: the grid's pressures (fluctuation about the mean, which is projected
        // exactly), one scatter onto every loaded wire, each block its share.
        if let (Some(w), Some(wl)) = (&self.wind, &m.wind) {
            for slot in 0..w.k {
                let p0 = wl.mean_pressure(slot);
                for g in 0..w.ng {
                    ws.wind_p[slot * w.ng + g] =
                        (wl.pressure(slot, wl.field.at(g, st.t)) - p0) * wl.grid_m;
                }
            }
            ws.wind_q.copy_from_slice(&w.mean);
            w.sampler
                .scatter_add(&ws.wind_p, w.k, &mut ws.wind_q, &mut ws.scr);
            for &(slot, off, coef) in &w.blocks {
                kernels::axpy(
                    isa,
                    coef,
                    &ws.wind_q[slot * w.n..(slot + 1) * w.n],
                    &mut st.modal.a[off..off + w.n],
                );
            }
        }
    }

    /// Stage 6, moving points: each pantograph's contact row and wire height, the contact force
    /// (Eq. 19) and its scatter, and the contact samples (height, lateral position).
    #[inline(always)]
    fn moving_points(&self, st: &mut State, ws: &mut Workspace) {
        let m = &self.model;
        let isa = self.isa;
        // Moving points (contacts, Eq. 19): rows, heights, forces.
        for (mi, mp) in self.moving.iter().enumerate() {
            let x = self.moving_x(st, &ws.external, mp);
            let row = self.moving_row(&mut ws.rows, mp, x);
            ws.u[self.moving_u0 + mi] = m.static_height(mp.wire, mp.dir, x, st.track_origin_m)
                + kernels::dot(isa, &st.modal.u[mp.q_off..mp.q_off + mp.n], row);
            ws.samples[mp.pantograph].position_m = x;
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
        for (p, lp) in self.pan_lateral.iter().enumerate() {
            if let Some(lp) = lp {
                let mp = &self.moving[lp.moving];
                let row = &ws.rows[mp.row_off..mp.row_off + mp.n];
                let x = ws.samples[p].position_m;
                let mut z = m.static_height(lp.wire, Direction::Lateral, x, st.track_origin_m)
                    + kernels::dot(isa, &st.modal.u[lp.lat_off..lp.lat_off + lp.n], row);
                if let Some(t) = lp.tors_off {
                    z -= lp.eccentricity_m * kernels::dot(isa, &st.modal.u[t..t + lp.n], row);
                }
                ws.samples[p].lateral_m = z;
            }
        }
    }

    /// Stage 7, implicit solve and kick: the diagonal modal solve `(M + Δt/2 C)⁻¹`, the Woodbury
    /// correction of the implicit point masses and dampers, and the second half kick.
    #[inline(always)]
    fn implicit_solve(&self, st: &mut State, ws: &mut Workspace) {
        let h = 0.5 * self.dt;
        let isa = self.isa;
        // Solve for the accelerations and finish the velocities.
        kernels::scale(isa, &mut st.modal.a, &self.d_inv);
        for imp in &self.implicit {
            imp.correct(&mut st.modal.a, &self.neg_d_inv, &mut ws.scr, &mut ws.imp);
        }
        kernels::kick(isa, &mut st.modal.v, &st.modal.a, h);
    }

    /// Stage 8, pantographs: the wire velocity at the contact and each lumped pantograph's
    /// accelerations and half kick (Eq. 16).
    #[inline(always)]
    fn pantographs(&self, st: &mut State, ws: &mut Workspace) {
        let h = 0.5 * self.dt;
        let isa = self.isa;
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
            if let PantographKind::Lumped(_) = pan.kind {
                let o = self.pan_off[p];
                ws.eu[self.head_u0 + p] = st.pantographs.u[o];
                ws.ev[self.head_u0 + p] = st.pantographs.v[o];
            }
        }
        for (mi, mp) in self.moving.iter().enumerate() {
            let x = self.moving_x(st, &ws.external, mp);
            let row = self.moving_row(&mut ws.rows, mp, x);
            ws.eu[self.moving_u0 + mi] = m.static_height(mp.wire, mp.dir, x, st.track_origin_m)
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

    /// Modal damping of every coordinate (by the layout), aerodynamic damping included.
    pub(crate) fn modal_damping(&self) -> &[f64] {
        &self.c_true
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
        if model.layout.blocks[b].key.dir == Direction::Torsional {
            continue; // advanced by its exact flow: stable for any Δt
        }
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
