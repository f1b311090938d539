//! The solver's side of a pantograph (issue 52, item 5): everything the stepper and the
//! stability check do with a pantograph's kind, in one place. A lumped chain's Δt operators and
//! its rest on the static wire (a head of collector strips, a static force by the head's
//! height), its contact heads' displacements, the loads a moving force or a rig prescribes, the
//! chain's half kick (Eq. 16), and its limits on Δt. The integrator and the stability check call
//! these and match no kind: a new kind of pantograph is `model/pantograph.rs` and this file.

use crate::error::{CaseError, ModelQuantity};
use crate::model::dof::Direction;
use crate::model::pantograph::{ChainOperators, Lumped, PantographKind};
use crate::model::Model;
use crate::solve::compiled::{contact_stiffness, contact_stiffness_on, refused, CompiledModel};
use crate::solve::plan::Plan;
use crate::solve::state::State;
use crate::solve::workspace::Workspace;

/// Each pantograph's chain operators (Eq. 16) at Δt, and the chains' static equilibrium against
/// the static wire at the start.
pub(crate) fn chains_at_rest(
    cm: &CompiledModel,
    plan: &Plan,
    dt: f64,
) -> Result<(Vec<Option<ChainOperators>>, Vec<f64>), CaseError> {
    let model = &cm.model;
    // Pantographs.
    let np = model.pantographs.len();
    let mut chains = Vec::with_capacity(np);
    let mut initial_py = Vec::new();
    for (p, pan) in model.pantographs.iter().enumerate() {
        match &pan.kind {
            PantographKind::Lumped(l) => {
                let ops = l.operators(dt, plan.speed_kmh).ok_or_else(|| {
                    refused(
                        ModelQuantity::PantographMasses(p),
                        format!("{:?}", l.masses_kg),
                        "the pantograph's mass matrix M + Δt/2 C is singular".into(),
                    )
                })?;
                let x = plan.start_m - pan.offset_m + plan.speed_m_s * 0.0;
                let no_equilibrium = || no_static_equilibrium(p, l);
                if !l.strips.is_empty() {
                    let y = strips_at_rest(cm, p, l, &ops, x).ok_or_else(no_equilibrium)?;
                    initial_py.extend(y);
                    chains.push(Some(ops));
                    continue;
                }
                let (kn, h) = match cm.pan_point[p] {
                    Some(m) if cm.pan_points[p].is_empty() => {
                        (contact_stiffness(model, p), cm.start_height(m, x))
                    }
                    // Several contact wires: the head rests on the lowest of those present
                    // at the start, and on every other at that height (their penalty
                    // springs in parallel).
                    Some(_) => {
                        let present: Vec<(usize, f64)> = cm.pan_points[p]
                            .iter()
                            .filter(|&&k| cm.moving[k].covers(x))
                            .map(|&k| (k, cm.start_height(k, x)))
                            .collect();
                        let low = present
                            .iter()
                            .map(|&(_, h)| h)
                            .fold(f64::INFINITY, f64::min);
                        let kn: f64 = present
                            .iter()
                            .filter(|&&(_, h)| h <= low + 1e-9)
                            .map(|&(k, _)| contact_stiffness_on(model, p, Some(cm.moving[k].wire)))
                            .sum();
                        if low.is_finite() {
                            (kn, low)
                        } else {
                            (contact_stiffness(model, p), 0.0)
                        }
                    }
                    None => (contact_stiffness(model, p), 0.0),
                };
                let y = ops.static_equilibrium(kn, h).ok_or_else(no_equilibrium)?;
                initial_py.extend(y);
                chains.push(Some(ops));
            }
            _ => chains.push(None),
        }
    }
    Ok((chains, initial_py))
}

/// Why pantograph `p` has no static equilibrium, in the model's terms: with a static force that
/// depends on the head's height, a table steeper than the chain's springs (the fixed point on
/// the head's height diverges: the table's steepest slope is named); else a spring of zero
/// stiffness.
fn no_static_equilibrium(p: usize, l: &Lumped) -> CaseError {
    match &l.uplift_by_height {
        Some(t) => {
            let steepest = (t.height_m.windows(2).zip(t.uplift_n.windows(2)))
                .map(|(h, f)| ((f[1] - f[0]) / (h[1] - h[0])).abs())
                .fold(0.0, f64::max);
            let series = 1.0
                / (l.stiffness_n_per_m.iter())
                    .filter(|k| **k > 0.0)
                    .map(|k| 1.0 / k)
                    .sum::<f64>();
            refused(
                ModelQuantity::PantographUpliftTable(p),
                format!("a slope of {steepest:.4e} N/m"),
                format!(
                    "the pantograph has no static equilibrium on the wire: its static force changes with the head's height by up to {steepest:.4e} N per metre, against springs of {series:.4e} N/m in series, so the head's height found for one force asks another; a frame's force varies by a few newtons over its working range"
                ),
            )
        }
        None => refused(
            ModelQuantity::PantographStiffness(p, None),
            format!("{:?}", l.stiffness_n_per_m),
            "the pantograph has no static equilibrium (a spring of zero stiffness?)".into(),
        ),
    }
}

/// The static equilibrium of pantograph `p`'s head of strips at position `x` on the static
/// wire: each strip on the lowest wire present under its own contact point (on every wire at
/// that height, their penalty springs in parallel), [`ChainOperators::static_equilibrium_strips`].
fn strips_at_rest(
    cm: &CompiledModel,
    p: usize,
    l: &Lumped,
    ops: &ChainOperators,
    x: f64,
) -> Option<Vec<f64>> {
    let ns = l.strips.len();
    let (mut kn, mut h) = (vec![0.0; ns], vec![0.0; ns]);
    for (s, strip) in l.strips.iter().enumerate() {
        let xs = x + strip.along_m;
        let head = cm.head_base[p] + s;
        let present: Vec<f64> = (cm.moving.iter().enumerate())
            .filter(|(_, mp)| mp.head == head && mp.dir == Direction::Vertical && mp.covers(xs))
            .map(|(k, _)| cm.start_height(k, xs))
            .collect();
        let low = present.iter().copied().fold(f64::INFINITY, f64::min);
        if low.is_finite() {
            h[s] = low;
            let at_low = present.iter().filter(|&&hh| hh <= low + 1e-9).count();
            kn[s] = at_low as f64 * strip.contact_stiffness_n_per_m;
        }
    }
    let offsets: Vec<f64> = l.strips.iter().map(|s| s.height_offset_m).collect();
    ops.static_equilibrium_strips(&kn, &h, &offsets)
}

/// Each pantograph's contact heads' displacements (a lumped head's, or each strip's running
/// face) and the loads it prescribes (a moving force's, a rig's measured force): stage 6.
#[inline(always)]
pub(crate) fn heads_and_loads(cm: &CompiledModel, st: &State, ws: &mut Workspace) {
    let m = &cm.model;
    for (p, pan) in m.pantographs.iter().enumerate() {
        let h = cm.head_u0 + cm.head_base[p];
        match &pan.kind {
            PantographKind::Lumped(l) if l.strips.is_empty() => {
                ws.u[h] = st.pantographs.u[cm.pan_off[p]];
            }
            // Each strip's running face: the strip's height and its offset.
            PantographKind::Lumped(l) => {
                let o = cm.pan_off[p];
                for (s, strip) in l.strips.iter().enumerate() {
                    ws.u[h + s] = st.pantographs.u[o + s] + strip.height_offset_m;
                }
            }
            _ => ws.u[h] = 0.0,
        }
        let np = m.pantographs.len();
        ws.loads[np + p] = match pan.kind {
            PantographKind::MovingForce {
                lateral_force_n, ..
            } => lateral_force_n,
            _ => 0.0,
        };
        ws.loads[p] = match pan.kind {
            PantographKind::MovingForce { force_n, .. } => force_n,
            PantographKind::External => ws.external[p].force_n,
            PantographKind::Lumped(_) => 0.0,
        };
    }
}

/// Stage 8 for pantograph `p`'s chain: its accelerations under the wire's force on its contact
/// heads (its strips, or its one head) and the half kick `v += Δt/2 · a` (Eq. 16); `h` is Δt/2.
#[inline(always)]
pub(crate) fn half_kick(
    ops: &ChainOperators,
    cm: &CompiledModel,
    p: usize,
    h: f64,
    st: &mut State,
    ws: &mut Workspace,
) {
    let r = cm.pantograph_dofs(p);
    let n = ops.n;
    let h0 = cm.head_u0 + cm.head_base[p];
    let f_head = &ws.f[h0..h0 + ops.frame.max(1)];
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

/// Each pantograph's penalty contact and springs against the step Δt (`limit` the share of the
/// explicit limit a spring may use): a head's (or each strip's) contact `√(k/m)·Δt < 1`, each
/// spring of the chain and of a strip's suspension within the explicit limit.
pub(crate) fn within_step(model: &Model, dt: f64, limit: f64) -> Result<(), CaseError> {
    for (p, pan) in model.pantographs.iter().enumerate() {
        if let PantographKind::Lumped(l) = &pan.kind {
            strips_within_step(p, l, dt, limit)?;
            let kn = contact_stiffness(model, p);
            let m0 = l.masses_kg[0];
            if l.strips.is_empty() && (kn / m0).sqrt() * dt > 1.0 {
                return Err(refused(
                    ModelQuantity::ContactStiffness,
                    kn,
                    format!(
                        "too stiff for Δt = {dt} s with a {m0} kg head: need √(k/m)·Δt < 1, i.e. Δt < {:.2e} s",
                        (m0 / kn).sqrt()
                    ),
                ));
            }
            for j in 0..l.masses_kg.len() {
                let m_inv = 1.0 / l.masses_kg[j] + l.masses_kg.get(j + 1).map_or(0.0, |m| 1.0 / m);
                if (l.stiffness_n_per_m[j] * m_inv).sqrt() * dt > limit {
                    return Err(refused(
                        ModelQuantity::PantographStiffness(p, Some(j)),
                        l.stiffness_n_per_m[j],
                        format!("too stiff for Δt = {dt} s (explicit stability)"),
                    ));
                }
            }
        }
    }
    Ok(())
}

/// A head of collector strips against the step: each strip's own contact on its mass
/// (`√(k_c/m)·Δt < 1`, as a head's) and its suspension between it and the frame.
fn strips_within_step(p: usize, l: &Lumped, dt: f64, limit: f64) -> Result<(), CaseError> {
    let frame = l.masses_kg[0];
    for (s, st) in l.strips.iter().enumerate() {
        let kn = st.contact_stiffness_n_per_m;
        if (kn / st.mass_kg).sqrt() * dt > 1.0 {
            return Err(refused(
                ModelQuantity::StripStiffness(p, s, true),
                kn,
                format!(
                    "too stiff for Δt = {dt} s with a {} kg strip: need √(k/m)·Δt < 1, i.e. Δt < {:.2e} s",
                    st.mass_kg,
                    (st.mass_kg / kn).sqrt()
                ),
            ));
        }
        let m_inv = 1.0 / st.mass_kg + 1.0 / frame;
        if (st.stiffness_n_per_m * m_inv).sqrt() * dt > limit {
            return Err(refused(
                ModelQuantity::StripStiffness(p, s, false),
                st.stiffness_n_per_m,
                format!("too stiff for Δt = {dt} s (explicit stability)"),
            ));
        }
    }
    Ok(())
}

/// The potential energy in pantograph `p`'s own springs at its displacements `xs` (none: a
/// pantograph without a chain).
pub(crate) fn spring_energy(model: &Model, p: usize, xs: &[f64]) -> Option<f64> {
    match &model.pantographs[p].kind {
        PantographKind::Lumped(l) => Some(l.energy_all(xs, &vec![0.0; xs.len()], 0.0).1),
        _ => None,
    }
}
