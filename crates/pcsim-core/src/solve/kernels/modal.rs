//! The modal parts of a step: the kick and drift, the right-hand side, the scaled kick, the
//! crosswind's quadratic and the torsional modes' flow.

use super::*;

// ---------------------------------------------------------------------------------------------
// The modal parts of a step.

#[inline(always)]
fn kick_drift_body<const F: bool>(q: &mut [f64], v: &mut [f64], a: &[f64], h: f64, dt: f64) {
    for ((qi, vi), ai) in q.iter_mut().zip(v.iter_mut()).zip(a) {
        *vi = mad::<F>(h, *ai, *vi);
        *qi = mad::<F>(dt, *vi, *qi);
    }
}

kernel! {
    /// `v += h a; q += Δt v` (the first half of a velocity-Verlet step).
    pub fn kick_drift(q: &mut [f64], v: &mut [f64], a: &[f64], h: f64, dt: f64) = kick_drift_body;
}

#[inline(always)]
fn modal_rhs_body<const F: bool>(a: &mut [f64], q: &[f64], v: &[f64], k: &[f64], c: &[f64]) {
    for ((((ai, qi), vi), ki), ci) in a.iter_mut().zip(q).zip(v).zip(k).zip(c) {
        *ai = mad::<F>(-ki, *qi, -ci * vi);
    }
}

kernel! {
    /// `a = −K q − C v` (diagonal modal stiffness and damping).
    pub fn modal_rhs(a: &mut [f64], q: &[f64], v: &[f64], k: &[f64], c: &[f64]) = modal_rhs_body;
}

#[inline(always)]
fn scale_kick_body<const F: bool>(a: &mut [f64], d_inv: &[f64]) {
    for (ai, di) in a.iter_mut().zip(d_inv) {
        *ai *= di;
    }
}

kernel! {
    /// `a ⊙= d⁻¹`.
    pub fn scale(a: &mut [f64], d_inv: &[f64]) = scale_kick_body;
}

#[inline(always)]
fn kick_body<const F: bool>(v: &mut [f64], a: &[f64], h: f64) {
    for (vi, ai) in v.iter_mut().zip(a) {
        *vi = mad::<F>(h, *ai, *vi);
    }
}

kernel! {
    /// `v += h a`.
    pub fn kick(v: &mut [f64], a: &[f64], h: f64) = kick_body;
}

#[inline(always)]
fn quadratic_body<const F: bool>(out: &mut [f64], c0: &[f64], c1: &[f64], c2: &[f64], tau: f64) {
    for (((o, a), b), c) in out.iter_mut().zip(c0).zip(c1).zip(c2) {
        *o = mad::<F>(tau, mad::<F>(tau, *c, *b), *a);
    }
}

kernel! {
    /// `out = c0 + τ (c1 + τ c2)` (a quadratic in `τ` per value: the crosswind's generalised
    /// forces inside one interval of its field).
    pub fn quadratic(out: &mut [f64], c0: &[f64], c1: &[f64], c2: &[f64], tau: f64) = quadratic_body;
}

#[inline(always)]
fn flow_body<const F: bool>(q: &mut [f64], v: &mut [f64], m: &[[f64; 4]]) {
    for ((qi, vi), c) in q.iter_mut().zip(v.iter_mut()).zip(m) {
        let (q0, v0) = (*qi, *vi);
        *qi = mad::<F>(c[0], q0, c[1] * v0);
        *vi = mad::<F>(c[2], q0, c[3] * v0);
    }
}

kernel! {
    /// `(q, v) ← Φ (q, v)` per mode with `Φ = [[m0, m1], [m2, m3]]`: the exact flow of each
    /// damped modal oscillator over one step (the torsional series, see `integrator`).
    pub fn flow(q: &mut [f64], v: &mut [f64], m: &[[f64; 4]]) = flow_body;
}
