//! The time step against the explicit scheme's stability limit, in one place.
//!
//! The scheme (central differences, velocity-Verlet form, Eq. 18) is stable while `ω Δt < 2`
//! for the highest frequency `ω` of the part it treats explicitly. Damping taken as
//! `(M + Δt/2 C)` does not lower that limit (Newmark with γ = ½, β = 0). Two checks, both here:
//!
//! - **Local limits** ([`check_local`]): each node on the springs attached to it, each penalty
//!   contact on its pantograph head, each pantograph spring. Cheap, from the model alone, and
//!   each names the case field to change. The set-up runs them before anything is compiled.
//! - **The coupled limit** ([`coupled_limit`]): the highest frequency of the whole explicit
//!   system as compiled — the wires' modal stiffness (the torsional modes, advanced by their
//!   trapezoidal flow, excluded) with every dropper, support, registration, steady-arm mass,
//!   stitch, penalty contact and pantograph coupling them. A local limit misses it: a stiff
//!   support acts on the few centimetres of wire that the highest modes resolve at the point, and
//!   the droppers and contacts add up. It is found by power iteration on `M⁻¹K`, each product
//!   being the difference of two evaluations of the compiled step's accelerations about the
//!   static state (where the droppers are taut and the contact is closed: the stiffest the
//!   system gets). The mode found is then split into the strain energy of each part, and the
//!   largest share names the element that limits Δt.
//!
//! Between the two, a cheap lower bound of the coupled frequency ([`top_mode_bound`]): each
//! wire's highest mode alone, as the Rayleigh quotient's trial vector. A step that fails it is
//! refused at once; the power iteration, which converges from below and may stop short where the
//! top of the spectrum is dense, never reports less than it.
//!
//! [`check_stability`] runs them and issues the [`StableStep`] proof that the integrator is built
//! on. A Δt is accepted when `ω Δt ≤ 2 · MARGIN`.

use crate::error::{CaseError, ModelQuantity};
use crate::model::dof::Direction;
use crate::model::elements::{Attach, Io, Weight};
use crate::model::Model;
use crate::solve::compiled::{refused, CompiledModel};
use crate::solve::integrator::Integrator;
use crate::solve::plan::Plan;
use crate::solve::state::State;
use crate::solve::workspace::Workspace;

/// The share of the stability limit a time step may use: Δt ≤ `MARGIN` · 2/ω, i.e. ω·Δt ≤ 1.3.
///
/// Measured (docs/validation.md, "The time step against the coupled limit"): on `en50318-2002`
/// at 250 km/h the moving contact already drives the top modes unstable from ω·Δt ≈ 1.78 (σ
/// 35 N against 32.6 N, 1 % loss of contact), below the linear limit of 2; at 300 km/h σ leaves
/// 2 % of its converged value from ω·Δt ≈ 1.42. The accepted range keeps every preset within
/// 2 %.
pub const MARGIN: f64 = 0.65;

/// The time step of the probe integrator whose accelerations the power iteration differences:
/// small enough that `Δt/2 C` is negligible beside `M` (the limit is the undamped one).
const PROBE_DT_S: f64 = 1e-9;

/// Size of the perturbation about the static state (the vector's Euclidean norm, in modal
/// coordinates, m or rad): far below a dropper's slack (its static force over its stiffness,
/// about a millimetre) or the contact's opening, so the evaluations stay on one linear branch.
const PERTURBATION: f64 = 1e-7;

/// Power iterations: at most this many, and at least [`MIN_ITERATIONS`]; the estimate stops when
/// it has changed by less than [`TOLERANCE`] over the last [`MIN_ITERATIONS`] / 4 iterations.
const MAX_ITERATIONS: usize = 3000;
const MIN_ITERATIONS: usize = 60;
const TOLERANCE: f64 = 1e-5;

pub use crate::solve::limits::{CoupledLimit, StableStep};

/// Check `dt` against the local limits and the coupled limit of the compiled model: the proof
/// that an integrator at `dt` is stable, or an error naming the time step (or the stiff part), the
/// limit with its margin and the element that sets it.
pub fn check_stability(cm: &CompiledModel, plan: &Plan, dt: f64) -> Result<StableStep, CaseError> {
    check_local(cm.model(), dt)?;
    check_top_modes(cm, dt)?;
    let lim = coupled_limit(cm, plan)?;
    if dt > lim.dt_max_s {
        let f = lim.omega_rad_s / (2.0 * std::f64::consts::PI);
        return Err(refused(
            ModelQuantity::TimeStep,
            dt,
            format!(
                "too large for the coupled system: its fastest mode is at {f:.0} Hz (ω = {:.0} rad/s), set by {}. The explicit scheme is unstable from ω·Δt = 2 (Δt = {:.3e} s) and loses accuracy before: pcsim accepts ω·Δt ≤ {:.1} (σ within 2 % of the converged value, docs/validation.md), i.e. Δt ≤ {:.3e} s",
                lim.omega_rad_s,
                lim.limiting,
                2.0 / lim.omega_rad_s,
                2.0 * MARGIN,
                lim.dt_max_s
            ),
        ));
    }
    Ok(StableStep::new(dt, lim))
}

/// The local explicit limits (central differences: ω Δt < 2, with the margin): every node on its
/// springs, every penalty contact on its pantograph head, every pantograph spring. Errors name
/// the model's quantity to change (`compile/` names its case field).
pub fn check_local(model: &Model, dt: f64) -> Result<(), CaseError> {
    let limit = 2.0 * MARGIN;
    let dt_field = |reason: String| refused(ModelQuantity::TimeStep, dt, reason);
    // A block's highest mode is not checked here: the coupled limit holds it, with the elements
    // that raise it.
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
        if (k / n.mass_kg).sqrt() * dt > limit {
            return Err(dt_field(format!(
                "too large for node {j} at x = {:.2} m ({} kg on {k:.0} N/m, a stitch node): explicit stability",
                n.x_m, n.mass_kg
            )));
        }
    }
    // Penalty contacts and pantograph springs.
    crate::solve::pantographs::within_step(model, dt, limit)
}

/// A lower bound of the coupled system's highest `ω²`, from the model alone, before the power
/// iteration: each explicit block's highest mode alone as the trial vector of the Rayleigh
/// quotient `xᵀKx / xᵀMx` — its modal stiffness (the point springs only add to it) over its
/// modal mass plus every point mass on its wire (a sine's square is at most 1). The largest, with
/// its block.
pub fn top_mode_bound(cm: &CompiledModel) -> Option<(f64, usize)> {
    let m = cm.model();
    let mut point_mass_kg = vec![0.0; m.wires.len()];
    for e in &m.elements {
        for i in 0..e.len() {
            if let Some((a, Weight::Mass(mass))) = e.implicit(i) {
                if let Attach::Wire { wire, .. } = e.attachment(i, a) {
                    point_mass_kg[wire] += mass;
                }
            }
        }
    }
    (0..m.layout.blocks.len())
        .filter(|&b| m.layout.blocks[b].key.dir != Direction::Torsional)
        .filter_map(|b| {
            let s = m.series(b);
            let top = s.mass.len().checked_sub(1)?;
            let w = m.layout.blocks[b].key.wire;
            Some((s.stiffness[top] / (s.mass[top] + point_mass_kg[w]), b))
        })
        .max_by(|a, b| a.0.total_cmp(&b.0))
}

/// A time step that already fails against [`top_mode_bound`] is refused at once, naming the wire
/// (the power iteration would find a frequency at least as high, after many applications of a
/// model that may be large: a case with far too many modes is refused in milliseconds).
fn check_top_modes(cm: &CompiledModel, dt: f64) -> Result<(), CaseError> {
    let Some((w2, b)) = top_mode_bound(cm) else {
        return Ok(());
    };
    let omega = w2.sqrt();
    if omega * dt <= 2.0 * MARGIN {
        return Ok(());
    }
    let m = cm.model();
    let key = m.layout.blocks[b].key;
    Err(refused(
        ModelQuantity::TimeStep,
        dt,
        format!(
            "too large for the coupled system: its fastest mode is at least at {:.0} Hz (ω ≥ {omega:.0} rad/s), set by the {} wire's own {} stiffness (its highest mode alone, with every point mass on the wire; more modes per span raise it). pcsim accepts ω·Δt ≤ {:.1} (docs/validation.md), so Δt must be below {:.3e} s at least (the coupled check then gives the exact limit)",
            omega / (2.0 * std::f64::consts::PI),
            m.wires[key.wire].name,
            key.dir.name(),
            2.0 * MARGIN,
            2.0 * MARGIN / omega
        ),
    ))
}

/// The coupled system's highest frequency by power iteration on `M⁻¹K` about the static state
/// (see the module's notes), and the part of the model that sets it. Deterministic: the start
/// vector comes from a fixed sequence.
pub fn coupled_limit(cm: &CompiledModel, plan: &Plan) -> Result<CoupledLimit, CaseError> {
    let probe = Integrator::from_compiled(cm.clone(), plan, PROBE_DT_S)?;
    let mut ws = probe.workspace();
    let rest = probe.initial_state(plan.start_m);
    let mut st = rest.clone();
    let (nm, nn, np) = (
        rest.modal.u.len(),
        rest.nodes.u.len(),
        rest.pantographs.u.len(),
    );
    let n = nm + nn + np;
    // A fixed pseudo-random start vector (xorshift): it has a component on every mode.
    let mut x = vec![0.0; n];
    let mut r: u64 = 0x9E37_79B9_7F4A_7C15;
    for xi in &mut x {
        r ^= r << 13;
        r ^= r >> 7;
        r ^= r << 17;
        *xi = (r >> 11) as f64 / (1u64 << 53) as f64 - 0.5;
    }
    normalise(&mut x);
    let mut y = vec![0.0; n];
    let mut minus = vec![0.0; n];
    let mut history = Vec::with_capacity(MAX_ITERATIONS);
    let mut lambda = 0.0;
    for it in 0..MAX_ITERATIONS {
        apply(
            &probe, &rest, &mut st, &mut ws, &x, &mut y, &mut minus, None,
        );
        lambda = norm(&y);
        if !lambda.is_finite() {
            return Err(refused(
                ModelQuantity::TimeStep,
                "(stability check)",
                "the coupled stability check met a non-finite acceleration about the static state"
                    .into(),
            ));
        }
        if lambda == 0.0 {
            break;
        }
        history.push(lambda);
        for (xi, yi) in x.iter_mut().zip(&y) {
            *xi = yi / lambda;
        }
        let w = MIN_ITERATIONS / 4;
        if it + 1 >= MIN_ITERATIONS && (history[it] - history[it - w]).abs() <= TOLERANCE * lambda {
            break;
        }
    }
    // The power iteration converges from below: where it stopped short of a wire's highest mode
    // alone (a dense top of the spectrum), that mode's bound is the better estimate.
    if let Some((w2, b)) = top_mode_bound(cm).filter(|&(w2, _)| w2 > lambda) {
        let key = cm.model().layout.blocks[b].key;
        return Ok(CoupledLimit {
            omega_rad_s: w2.sqrt(),
            dt_max_s: 2.0 * MARGIN / w2.sqrt(),
            limiting: format!(
                "the {} wire's own {} stiffness (its highest mode alone: the power iteration stopped below it after {} iterations)",
                cm.model().wires[key.wire].name,
                key.dir.name(),
                history.len()
            ),
            iterations: history.len(),
        });
    }
    let omega = lambda.sqrt();
    let limiting = if omega > 0.0 {
        let mut shares = Vec::new();
        apply(
            &probe,
            &rest,
            &mut st,
            &mut ws,
            &x,
            &mut y,
            &mut minus,
            Some(&mut shares),
        );
        describe(cm, shares)
    } else {
        "nothing (the model has no stiffness)".to_string()
    };
    Ok(CoupledLimit {
        omega_rad_s: omega,
        dt_max_s: if omega > 0.0 {
            2.0 * MARGIN / omega
        } else {
            f64::INFINITY
        },
        limiting,
        iterations: history.len(),
    })
}

fn norm(x: &[f64]) -> f64 {
    x.iter().map(|v| v * v).sum::<f64>().sqrt()
}

fn normalise(x: &mut [f64]) {
    let s = norm(x);
    for v in x {
        *v /= s;
    }
}

/// One part of the model and its strain energy in the limiting mode.
enum Part {
    Block(usize),
    Element { e: usize, instance: usize },
    Pantograph(usize),
}

/// `y = −M⁻¹K x` by central differences of the accelerations about `rest` (`minus`: scratch of
/// `y`'s length); with `shares`, also the strain energy `½ xᵀK x` of every part (blocks,
/// element kinds, pantograph chains).
#[allow(clippy::too_many_arguments)]
fn apply(
    probe: &Integrator,
    rest: &State,
    st: &mut State,
    ws: &mut Workspace,
    x: &[f64],
    y: &mut [f64],
    minus: &mut [f64],
    shares: Option<&mut Vec<(Part, f64)>>,
) {
    let cm = probe.compiled();
    let (nm, nn) = (rest.modal.u.len(), rest.nodes.u.len());
    let eval = |sign: f64, st: &mut State, ws: &mut Workspace, out: &mut [f64]| {
        let e = sign * PERTURBATION;
        st.t = rest.t;
        for (u, (u0, xi)) in st.modal.u.iter_mut().zip(rest.modal.u.iter().zip(x)) {
            *u = u0 + e * xi;
        }
        for (u, (u0, xi)) in st.nodes.u.iter_mut().zip(rest.nodes.u.iter().zip(&x[nm..])) {
            *u = u0 + e * xi;
        }
        for (u, (u0, xi)) in st
            .pantographs
            .u
            .iter_mut()
            .zip(rest.pantographs.u.iter().zip(&x[nm + nn..]))
        {
            *u = u0 + e * xi;
        }
        st.modal.v.fill(0.0);
        st.nodes.v.fill(0.0);
        st.pantographs.v.fill(0.0);
        probe.accelerations(st, ws);
        out[..nm].copy_from_slice(&st.modal.a);
        out[nm..nm + nn].copy_from_slice(&st.nodes.a);
        out[nm + nn..].copy_from_slice(&st.pantographs.a);
    };
    eval(1.0, st, ws, y);
    let (u_plus, f_plus) = shares
        .as_ref()
        .map(|_| (ws.u.clone(), element_forces(cm, ws)))
        .unzip();
    eval(-1.0, st, ws, minus);
    for (a, b) in y.iter_mut().zip(minus.iter()) {
        *a = (*a - b) / (2.0 * PERTURBATION);
    }
    let Some(out) = shares else {
        return;
    };
    let (u_plus, f_plus) = (u_plus.unwrap_or_default(), f_plus.unwrap_or_default());
    let f_minus = element_forces(cm, ws);
    let m = cm.model();
    // The wires' own stiffness (explicit blocks only).
    for b in 0..m.layout.blocks.len() {
        if m.layout.blocks[b].key.dir == Direction::Torsional {
            continue;
        }
        let e: f64 = m
            .layout
            .range(b)
            .map(|j| 0.5 * cm.k_true[j] * x[j] * x[j])
            .sum();
        out.push((Part::Block(b), e));
    }
    // Each element kind, with its instance of largest share.
    let d = 2.0 * PERTURBATION;
    for (e, el) in m.elements.iter().enumerate() {
        let slots = cm.slots(e);
        let (fp, fm) = (&f_plus[e], &f_minus[e]);
        let slot_energy = |s: usize| -0.5 * (u_plus[s] - ws.u[s]) / d * (fp[s] - fm[s]) / d;
        let mut seen = vec![false; ws.u.len()];
        let mut total = 0.0;
        let (mut best, mut best_e) = (0, f64::NEG_INFINITY);
        for i in 0..el.len() {
            let mut ei = 0.0;
            for a in 0..el.arity() {
                let s = slots[i * el.arity() + a].u as usize;
                let es = slot_energy(s);
                ei += es;
                if !seen[s] {
                    seen[s] = true;
                    total += es;
                }
            }
            if ei > best_e {
                (best, best_e) = (i, ei);
            }
        }
        out.push((Part::Element { e, instance: best }, total));
    }
    // The pantographs' own springs.
    for p in 0..m.pantographs.len() {
        let r = cm.pantograph_dofs(p);
        let xs = &x[nm + nn + r.start..nm + nn + r.end];
        if let Some(spring) = crate::solve::pantographs::spring_energy(m, p, xs) {
            out.push((Part::Pantograph(p), spring));
        }
    }
}

/// The forces of every element kind alone at the workspace's displacements, by slot.
fn element_forces(cm: &CompiledModel, ws: &Workspace) -> Vec<Vec<f64>> {
    let m = cm.model();
    (0..m.elements.len())
        .map(|e| {
            let mut f = vec![0.0; ws.u.len()];
            let mut io = Io {
                u: &ws.u,
                v: &ws.vel,
                f: &mut f,
                loads: &ws.loads,
                off_head: &ws.off_head,
                absent: &ws.absent,
                slack: 0,
            };
            m.elements[e].add_forces(cm.slots(e), &mut io);
            f
        })
        .collect()
}

/// The part with the largest share of the limiting mode's strain energy, in words.
fn describe(cm: &CompiledModel, shares: Vec<(Part, f64)>) -> String {
    let m = cm.model();
    let total: f64 = shares.iter().map(|s| s.1.max(0.0)).sum();
    let Some((part, e)) = shares.into_iter().max_by(|a, b| a.1.total_cmp(&b.1)) else {
        return "the wires".into();
    };
    let pct = if total > 0.0 { 100.0 * e / total } else { 0.0 };
    match part {
        Part::Block(b) => {
            let key = m.layout.blocks[b].key;
            format!(
                "the {} wire's own {} stiffness (tension and bending of its highest modes, {pct:.0} % of the mode's strain energy; more modes per span raise it)",
                m.wires[key.wire].name,
                key.dir.name()
            )
        }
        Part::Element { e, instance } => {
            let el = &m.elements[e];
            let at = match el.attachment(instance, 0) {
                Attach::Wire { wire, x_m, .. } => format!(
                    "on the {} at x = {:.2} m",
                    m.wires[wire].name,
                    x_m - m.track_origin_m
                ),
                Attach::Node(j) => format!("at node {j} (x = {:.2} m)", m.nodes[j].x_m),
                Attach::Head { pantograph: p, .. } | Attach::Moving { pantograph: p, .. } => {
                    format!("under pantograph {}", m.pantographs[p].name)
                }
                Attach::Ground => String::new(),
            };
            format!(
                "the {} elements ({pct:.0} % of the mode's strain energy; the largest share at {} {instance} {at}, stiffness {:.3e} N/m)",
                el.kind(),
                el.kind(),
                el.stiffness(instance)
            )
        }
        Part::Pantograph(p) => format!(
            "the springs of pantograph {} ({pct:.0} % of the mode's strain energy)",
            m.pantographs[p].name
        ),
    }
}
