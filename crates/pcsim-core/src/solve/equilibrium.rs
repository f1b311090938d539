//! The static start state under the steady loads: the coupled, nonlinear equilibrium of the
//! compiled model.
//!
//! The design's static shape (`model::statics`, paper §2.1) is the equilibrium of the wires
//! under their own weight, and the dynamics deviate from it (Eqs. 9–14 in deviation
//! coordinates). Two loads are not in it:
//! - the **mean crosswind**'s drag, lift and moment (`model::wind`);
//! - the **ice**'s weight: the dropper lengths are those of the ice-free design, so ice lowers
//!   the wires ([`crate::model::Wire::static_load_per_m`]).
//!
//! A run that started from the design shape under them would oscillate about the loaded shape
//! for its whole length (the torsional modes are barely damped). So the start state is the
//! equilibrium of every direction together, with the elements' own force laws (the dropper's
//! pendulum and eccentric clamp, which couple the lateral and torsional deflection to the
//! vertical; slack droppers; stitches and their nodes): the residual
//! `CompiledModel::static_residual` is driven to zero by Newton's method. Each Newton step
//! solves the tangent system by conjugate gradients, preconditioned with the modal stiffness
//! (and each node's own stiffness); the tangent is applied as a difference of two residuals.
//! With the modal stiffness as the preconditioner the preconditioned tangent is the identity plus
//! a term of the rank of the point elements, so the iterations are bounded by the number of
//! point attachments, not by the condition number.
//!
//! The start state is then a fixed point of the step (the kick–flow–kick of the torsional modes
//! included: a constant force `Q = k q` is kicked in and out around the trapezoidal flow with no
//! net motion), so a steady load gives a run that stays at rest.

use crate::error::{CaseError, ModelQuantity};
use crate::solve::compiled::{refused, CompiledModel};
use crate::solve::implicit::ImplicitScratch;
use crate::solve::Workspace;

pub use crate::solve::compiled::StaticStart;

/// The residual the Newton iteration stops at, relative to the steady loads'.
pub const RESIDUAL_TOLERANCE: f64 = 1e-10;
/// At most this many Newton steps.
const MAX_NEWTON: usize = 30;
/// The displacement step of the tangent's difference, m (or rad).
const FD_STEP: f64 = 1e-7;

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn norm(a: &[f64]) -> f64 {
    dot(a, a).sqrt()
}

/// The preconditioner's diagonal at zero deviation, where the residual is `r`: the modal
/// stiffness, and each node's own stiffness (nodes attach to wires only, never to another node,
/// so one probe of all the nodes at once gives each diagonal).
fn preconditioner_diagonal(cm: &CompiledModel, ws: &mut Workspace, r: &[f64]) -> Vec<f64> {
    let nm = cm.model.layout.len;
    let n = r.len();
    let mut diag = vec![0.0; n];
    diag[..nm].copy_from_slice(&cm.k_true);
    if n > nm {
        let mut xp = vec![0.0; n];
        let mut rp = vec![0.0; n];
        for v in &mut xp[nm..] {
            *v = FD_STEP;
        }
        cm.static_residual(&xp, ws, &mut rp);
        for j in nm..n {
            diag[j] = (r[j] - rp[j]) / FD_STEP;
        }
    }
    diag
}

/// The static start state of `cm` under its steady loads, or `None` when it has none (the
/// design shape is then the equilibrium, and the start state is zero deviation). Errors when
/// the equilibrium is not found: a load the structure cannot carry, or a soft part.
pub fn static_start(cm: &CompiledModel) -> Result<Option<StaticStart>, CaseError> {
    if !cm.has_steady_loads() {
        return Ok(None);
    }
    let nm = cm.model.layout.len;
    let nn = cm.model.nodes.len();
    let n = nm + nn;
    let mut ws = cm.workspace_with(cm.scratch.clone(), ImplicitScratch::new(0, 0, 0));
    let mut x = vec![0.0; n];
    let mut r = vec![0.0; n];
    cm.static_residual(&x, &mut ws, &mut r);
    let load = norm(&r);
    if load == 0.0 {
        return Ok(None);
    }
    let diag = preconditioner_diagonal(cm, &mut ws, &r);
    let precond = |res: &[f64], z: &mut [f64]| {
        for ((zi, ri), di) in z.iter_mut().zip(res).zip(&diag) {
            *zi = if *di > 0.0 { ri / di } else { 0.0 };
        }
    };
    let (mut p, mut z, mut ap, mut xp, mut rp, mut dx) = (
        vec![0.0; n],
        vec![0.0; n],
        vec![0.0; n],
        vec![0.0; n],
        vec![0.0; n],
        vec![0.0; n],
    );
    let mut cg_total = 0;
    let max_cg = 4 * n + 100;
    for newton in 0..MAX_NEWTON {
        let res = norm(&r);
        if !res.is_finite() {
            break;
        }
        if res <= RESIDUAL_TOLERANCE * load {
            return Ok(Some(StaticStart {
                modal: x[..nm].to_vec(),
                nodes: x[nm..].to_vec(),
                newton_steps: newton,
                cg_iterations: cg_total,
                relative_residual: res / load,
            }));
        }
        // Solve J dx = r, with J v = (r(x) − r(x + h v))/h (the tangent stiffness).
        dx.fill(0.0);
        let mut rr = r.clone();
        precond(&rr, &mut z);
        p.copy_from_slice(&z);
        let mut rz = dot(&rr, &z);
        let target = 1e-3 * RESIDUAL_TOLERANCE * load;
        for _ in 0..max_cg {
            cg_total += 1;
            let pn = p.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            if pn == 0.0 {
                break;
            }
            let h = FD_STEP / pn;
            for i in 0..n {
                xp[i] = x[i] + h * p[i];
            }
            cm.static_residual(&xp, &mut ws, &mut rp);
            for i in 0..n {
                ap[i] = (r[i] - rp[i]) / h;
            }
            let pap = dot(&p, &ap);
            if !pap.is_finite() || pap <= 0.0 {
                break;
            }
            let alpha = rz / pap;
            for i in 0..n {
                dx[i] += alpha * p[i];
                rr[i] -= alpha * ap[i];
            }
            if norm(&rr) <= target.max(1e-6 * res) {
                break;
            }
            precond(&rr, &mut z);
            let rz_new = dot(&rr, &z);
            let beta = rz_new / rz;
            rz = rz_new;
            for i in 0..n {
                p[i] = z[i] + beta * p[i];
            }
        }
        for i in 0..n {
            x[i] += dx[i];
        }
        cm.static_residual(&x, &mut ws, &mut r);
    }
    Err(refused(
        ModelQuantity::SteadyLoads,
        "the static start state",
        format!(
            "the equilibrium under the steady loads (the mean crosswind, the ice's weight) was not found: residual {:.2e} of the load after {MAX_NEWTON} Newton steps; a load the catenary cannot carry, or a part with no stiffness?",
            norm(&r) / load
        ),
    ))
}
