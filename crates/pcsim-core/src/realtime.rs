//! Real-time catenary: a moving window of catenary around the pantograph, stepped at a fixed rate
//! without allocating (paper §4.2, after Facchinetti & Bruni 2012).
//!
//! # Method
//! The window `[x0, x0 + W]` is a catenary model of its own, built with the same machinery as the
//! full model ([`Model::window`]): a sine series over `W` with the full model's mode density, and
//! the droppers, supports, arms and stitch elements that fall inside it. Its ends are pinned at the
//! static shape. `x0` is a whole number of spans, so the static shape in window coordinates is
//! always the same.
//!
//! When the pantograph passes `W/2 + Δ/2` (window coordinates) the window moves forward by
//! `Δ = m·S`, `m = max(1, ⌊W / 2S⌋)` whole spans, so the pantograph stays within `Δ/2` of the
//! centre. The new window's state is the old one projected onto the new sine basis over the
//! overlap; the part that enters starts at the static shape (zero deviation):
//!
//! ```text
//! q'_k = (2/W) ∫_0^{W−Δ} Σ_j q_j sin(κ_j (x + Δ)) sin(κ_k x) dx = Σ_j P_kj q_j,
//! ```
//!
//! with `P` in closed form, computed once (the shift is always the same). The same `P` maps the
//! velocities and accelerations; stitch-node states are carried over by position. A move is a
//! fixed `O(N²)` cost, so every step has a fixed bound on its work.
//!
//! # Where the error comes from
//! - the pinned window ends reflect the waves that would travel on (the main error when the
//!   window is shorter than the effective vibration area);
//! - the energy behind the window's rear end is dropped at every move, and the entering part is
//!   set to the static shape although the real wire there already moves (waves run ahead of the
//!   pantograph);
//! - the projection itself is exact for the modes kept, but the truncated series of a function
//!   cut off at the overlap's end carries a small Gibbs error.

use crate::case::{Case, PantographCase};
use crate::error::{CaseError, SimError};
use crate::model::Model;
use crate::solver::{Solver, State};
use crate::stats::{contact_stats, ContactStats};

/// How the real-time catenary is coupled to the pantograph.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Coupling {
    /// Software in the loop: pcsim's own pantograph model runs inside the window.
    Sil,
    /// Hardware in the loop: the measured contact force and pantograph position are inputs.
    Hil,
}

/// What one step returns.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct RealtimeOutput {
    pub time_s: f64,
    /// Pantograph position along the track, m.
    pub position_m: f64,
    /// Contact-wire height at the contact point (static shape + deviation), m.
    pub wire_height_m: f64,
    /// Contact-wire vertical velocity at the contact point, m/s.
    pub wire_velocity_m_s: f64,
    /// Contact force: computed (SIL) or the input (HIL), N.
    pub contact_force_n: f64,
}

/// The moving-window catenary with a fixed-step, allocation-free [`RealtimeCatenary::step`].
pub struct RealtimeCatenary {
    solver: Solver,
    st: State,
    coupling: Coupling,
    origin_m: f64,
    window_m: f64,
    shift_m: f64,
    trigger_m: f64,
    n: usize,
    proj: Vec<f64>,
    buf: Vec<f64>,
    stitch_from: Vec<Option<usize>>,
    sbuf: Vec<f64>,
    input: (f64, f64),
    moves: usize,
    /// The full model's run length and analysis section (track coordinates), for comparisons.
    full_duration_s: f64,
    analysis_m: [f64; 2],
}

/// `∫_0^A cos(ω x + φ) dx`.
fn int_cos(omega: f64, phi: f64, a: f64) -> f64 {
    if omega.abs() < 1e-12 {
        a * phi.cos()
    } else {
        ((omega * a + phi).sin() - phi.sin()) / omega
    }
}

/// The projection `P_kj` of a shift by `d` on a sine basis over `w` (row-major `n × n`).
pub fn shift_projection(w: f64, n: usize, d: f64) -> Vec<f64> {
    let kap = |i: usize| (i + 1) as f64 * std::f64::consts::PI / w;
    let a = (w - d).max(0.0);
    let mut p = vec![0.0; n * n];
    for k in 0..n {
        for j in 0..n {
            let (kj, kk) = (kap(j), kap(k));
            let phi = kj * d;
            p[k * n + j] = (int_cos(kj - kk, phi, a) - int_cos(kj + kk, phi, a)) / w;
        }
    }
    p
}

impl RealtimeCatenary {
    /// Build the window model of `case` with window length `window_m` (at the full model's mode
    /// density), placed around the leading pantograph's start.
    pub fn new(case: &Case, window_m: f64, coupling: Coupling) -> Result<Self, CaseError> {
        let (full, _) = Model::from_case(case)?;
        let span = case.catenary.span_m;
        let l = full.basis.length_m();
        if !(window_m.is_finite() && window_m >= 0.5 * span && window_m < l) {
            return Err(CaseError::Invalid {
                field: "window_m".into(),
                value: window_m.to_string(),
                reason: format!("the window must be at least half a span ({} m) and shorter than the model ({l} m)", 0.5 * span),
            });
        }
        let density = full.basis.n_modes() as f64 / l;
        let n = ((density * window_m).round() as usize).max(1);
        let m = ((window_m / (2.0 * span)).floor() as usize).max(1);
        let shift_m = m as f64 * span;
        let trigger_m = (0.5 * window_m + 0.5 * shift_m).min(window_m);
        let x_start = full.pantograph_position(0, 0.0);
        let origin_m = span * ((x_start - 0.5 * window_m).max(0.0) / span).floor();
        let model = full.window(origin_m, window_m, n, coupling == Coupling::Hil);
        // Stitch nodes after a move: the node at local x comes from the old node at x + Δ.
        let xs: Vec<f64> = model.stitches.iter().map(|s| s.x_m).collect();
        let stitch_from = xs
            .iter()
            .map(|&x| xs.iter().position(|&y| (y - (x + shift_m)).abs() < 1e-6))
            .collect();
        let solver = Solver::new(model);
        let st = solver.initial_state();
        Ok(Self {
            proj: shift_projection(window_m, n, shift_m),
            buf: vec![0.0; 6 * n],
            sbuf: vec![0.0; xs.len()],
            stitch_from,
            solver,
            st,
            coupling,
            origin_m,
            window_m,
            shift_m,
            trigger_m,
            n,
            input: (x_start, 0.0),
            moves: 0,
            full_duration_s: full.duration_s,
            analysis_m: full.analysis_m,
        })
    }

    /// Fixed time step, s.
    pub fn dt_s(&self) -> f64 {
        self.solver.model().dt_s
    }

    /// Window length, m.
    pub fn window_m(&self) -> f64 {
        self.window_m
    }

    /// Modes per wire in the window.
    pub fn n_modes(&self) -> usize {
        self.n
    }

    /// Global position of the window's start, m.
    pub fn origin_m(&self) -> f64 {
        self.origin_m
    }

    /// Number of window moves so far.
    pub fn moves(&self) -> usize {
        self.moves
    }

    /// HIL input for the next step: the measured contact force (N, pushing the wire up) and the
    /// pantograph position along the track (m).
    pub fn set_input(&mut self, contact_force_n: f64, position_m: f64) {
        self.input = (position_m, contact_force_n);
    }

    /// Advance one fixed step. Allocation-free; the work is bounded (a window move adds a fixed
    /// `O(N²)` projection).
    pub fn step(&mut self) -> RealtimeOutput {
        if self.coupling == Coupling::Hil {
            let (x, f) = self.input;
            self.solver.set_external(0, x - self.origin_m, f);
        }
        self.solver.step(&mut self.st);
        let s = self.solver.samples()[0];
        let out = RealtimeOutput {
            time_s: self.st.t,
            position_m: s.position_m + self.origin_m,
            wire_height_m: s.wire_height_m,
            wire_velocity_m_s: s.wire_velocity_m_s,
            contact_force_n: s.force_n,
        };
        if s.position_m > self.trigger_m {
            self.shift();
        }
        out
    }

    /// `x_c ← P x_c` for the six modal vectors at once: each row of `P` is read once (the move
    /// is the longest step, so this bounds the worst-case latency).
    fn project_all(p: &[f64], n: usize, st: &mut State, buf: &mut [f64]) {
        let xs: [&[f64]; 6] = [&st.qm, &st.vm, &st.am, &st.qc, &st.vc, &st.ac];
        let chunks = n / 4;
        for k in 0..n {
            let row = &p[k * n..(k + 1) * n];
            // Four lanes per vector (explicit partial sums, so the loop vectorises without
            // reassociating floating-point sums behind our back).
            let mut acc = [[0.0f64; 4]; 6];
            for c in 0..chunks {
                let r = &row[4 * c..4 * c + 4];
                for (a, x) in acc.iter_mut().zip(xs.iter()) {
                    let x = &x[4 * c..4 * c + 4];
                    for l in 0..4 {
                        a[l] += r[l] * x[l];
                    }
                }
            }
            for (v, (a, x)) in acc.iter().zip(xs.iter()).enumerate() {
                let mut sum = (a[0] + a[1]) + (a[2] + a[3]);
                for j in 4 * chunks..n {
                    sum += row[j] * x[j];
                }
                buf[6 * k + v] = sum;
            }
        }
        for k in 0..n {
            st.qm[k] = buf[6 * k];
            st.vm[k] = buf[6 * k + 1];
            st.am[k] = buf[6 * k + 2];
            st.qc[k] = buf[6 * k + 3];
            st.vc[k] = buf[6 * k + 4];
            st.ac[k] = buf[6 * k + 5];
        }
    }

    /// Move the window forward by the fixed shift and carry the state over.
    fn shift(&mut self) {
        let n = self.n;
        Self::project_all(&self.proj, n, &mut self.st, &mut self.buf);
        let st = &mut self.st;
        for v in [&mut st.sz, &mut st.sv, &mut st.sa] {
            for (i, from) in self.stitch_from.iter().enumerate() {
                self.sbuf[i] = from.map_or(0.0, |j| v[j]);
            }
            v.copy_from_slice(&self.sbuf);
        }
        self.solver.shift_origin(self.shift_m);
        self.origin_m += self.shift_m;
        self.moves += 1;
    }
}

/// A saved state of a [`RealtimeCatenary`], for rolling a step back. Allocate once with
/// [`RealtimeCatenary::snapshot`], then [`RealtimeCatenary::save`] and
/// [`RealtimeCatenary::restore`] copy without allocating.
#[derive(Debug, Clone)]
pub struct Snapshot {
    st: State,
    origin_m: f64,
    moves: usize,
    start_m: f64,
    input: (f64, f64),
}

impl RealtimeCatenary {
    /// A snapshot buffer holding the current state.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            st: self.st.clone(),
            origin_m: self.origin_m,
            moves: self.moves,
            start_m: self.solver.model().start_m,
            input: self.input,
        }
    }

    /// Copy the current state into `s` (no allocation).
    pub fn save(&self, s: &mut Snapshot) {
        copy_state(&self.st, &mut s.st);
        s.origin_m = self.origin_m;
        s.moves = self.moves;
        s.start_m = self.solver.model().start_m;
        s.input = self.input;
    }

    /// Return to the state saved in `s` (no allocation).
    pub fn restore(&mut self, s: &Snapshot) {
        copy_state(&s.st, &mut self.st);
        self.origin_m = s.origin_m;
        self.moves = s.moves;
        let d = self.solver.model().start_m - s.start_m;
        self.solver.shift_origin(d);
        self.input = s.input;
    }

    /// Static contact-wire height at a track position, m (the wire before any step).
    pub fn static_height_at(&self, x_m: f64) -> f64 {
        self.solver
            .model()
            .statics
            .contact_height(x_m - self.origin_m)
    }

    /// Track position of pantograph 0 in SIL mode at the current time, m.
    pub fn sil_position_m(&self) -> f64 {
        self.solver.model().pantograph_position(0, self.st.t) + self.origin_m
    }

    /// True when the modal state is finite and the wire heights plausible (|deviation| < 2 m).
    pub fn state_is_sound(&self) -> bool {
        let ok = |v: &[f64]| v.iter().all(|x| x.is_finite());
        let st = &self.st;
        ok(&st.qm)
            && ok(&st.vm)
            && ok(&st.qc)
            && ok(&st.vc)
            && ok(&st.sz)
            && st.py.iter().all(|p| ok(p))
            && self.solver.samples().iter().all(|s| s.is_sound())
    }
}

fn copy_state(from: &State, to: &mut State) {
    to.t = from.t;
    for (a, b) in [
        (&from.qm, &mut to.qm),
        (&from.vm, &mut to.vm),
        (&from.am, &mut to.am),
        (&from.qc, &mut to.qc),
        (&from.vc, &mut to.vc),
        (&from.ac, &mut to.ac),
        (&from.sz, &mut to.sz),
        (&from.sv, &mut to.sv),
        (&from.sa, &mut to.sa),
    ] {
        b.copy_from_slice(a);
    }
    for (a, b) in from.py.iter().zip(to.py.iter_mut()) {
        b.copy_from_slice(a);
    }
    for (a, b) in from.pv.iter().zip(to.pv.iter_mut()) {
        b.copy_from_slice(a);
    }
    for (a, b) in from.pa.iter().zip(to.pa.iter_mut()) {
        b.copy_from_slice(a);
    }
}

/// Result of a window run in SIL mode.
#[derive(Debug, Clone, PartialEq)]
pub struct WindowRun {
    pub window_m: f64,
    pub n_modes: usize,
    pub moves: usize,
    pub time_s: Vec<f64>,
    pub position_m: Vec<f64>,
    pub force_n: Vec<f64>,
    pub stats: Option<ContactStats>,
}

/// Run `case` with the window model in SIL mode over the same time as the full model, and take
/// the EN 50318 statistics of the leading pantograph over the case's analysis section.
pub fn run_window_sil(case: &Case, window_m: f64) -> Result<WindowRun, SimError> {
    if !matches!(
        case.pantographs.first(),
        Some(PantographCase::Lumped { .. })
    ) {
        return Err(SimError::Case(CaseError::Invalid {
            field: "pantographs[0].kind".into(),
            value: "moving_force".into(),
            reason: "SIL needs a lumped pantograph".into(),
        }));
    }
    let mut rt = RealtimeCatenary::new(case, window_m, Coupling::Sil)?;
    let dt = rt.dt_s();
    let n_steps = (rt.full_duration_s / dt).ceil() as usize;
    let (mut t, mut x, mut f, mut h) = (
        Vec::with_capacity(n_steps),
        Vec::with_capacity(n_steps),
        Vec::with_capacity(n_steps),
        Vec::with_capacity(n_steps),
    );
    for _ in 0..n_steps {
        let o = rt.step();
        if !rt.solver.samples()[0].is_sound() {
            return Err(SimError::BlowUp {
                time_s: o.time_s,
                position_m: o.position_m,
                what: format!("window {window_m} m: contact force {} N", o.contact_force_n),
            });
        }
        t.push(o.time_s);
        x.push(o.position_m);
        f.push(o.contact_force_n);
        h.push(o.wire_height_m);
    }
    let stats = contact_stats(&f, &x, &h, dt, rt.analysis_m, 0.0);
    Ok(WindowRun {
        window_m,
        n_modes: rt.n_modes(),
        moves: rt.moves(),
        time_s: t,
        position_m: x,
        force_n: f,
        stats,
    })
}
