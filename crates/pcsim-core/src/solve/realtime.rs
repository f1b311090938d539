//! Real-time catenary: a moving window of catenary around the pantograph, stepped at a fixed rate
//! without allocating (paper §4.2, after Facchinetti & Bruni 2012).
//!
//! # Method
//! The window `[x0, x0 + W]` is a catenary model of its own, built with the same machinery as the
//! full model (`Model::window`): a sine series over `W` with the full model's mode density, and
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
//! velocities and accelerations; node states (stitch nodes) are carried over by position. The
//! move is the [`WindowMover`], an observer of the one run loop. A move is a
//! fixed `O(N²)` cost, so every step has a fixed bound on its work.
//!
//! # On a line
//! A line's spans need not repeat and its tension lengths end, so each window position is a
//! model of its own (`Model::window` gives each wire's part inside the window its own basis, and
//! leaves out the wires that do not reach in), built with its compiled operators before the
//! first step. The positions start at supports: the next is the furthest support within half a
//! window ahead, and the move fires at `W/2 + Δ/2` as above. A move carries each wire's state
//! onto the next position's basis of the same wire by the projection of one sine basis onto
//! another over their common part ([`basis_projection`], closed form, shared between moves of
//! the same geometry); a wire that enters starts at its static shape. Every contact wire inside
//! the window is carried, so the pantograph passes an overlap as in the full model. The move's
//! work is fixed (`Σ n_to · n_from` per wire) and allocation-free.
//!
//! # Where the error comes from
//! - the pinned window ends reflect the waves that would travel on (the main error when the
//!   window is shorter than the effective vibration area);
//! - the energy behind the window's rear end is dropped at every move, and the entering part is
//!   set to the static shape although the real wire there already moves (waves run ahead of the
//!   pantograph);
//! - the projection itself is exact for the modes kept, but the truncated series of a function
//!   cut off at the overlap's end carries a small Gibbs error.

use crate::error::{CaseError, SimError};
use crate::model::{StaticShape, WireRole};
use crate::solve::compiled::CompiledModel;
use crate::solve::integrator::Integrator;
use crate::solve::kernels::Isa;
use crate::solve::plan::Plan;
use crate::solve::run::Observer;
use crate::solve::state::State;
use crate::solve::workspace::ExternalInput;
use crate::solve::workspace::Workspace;

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
    /// Simulated time, s.
    pub time_s: f64,
    /// Pantograph position along the track, m.
    pub position_m: f64,
    /// Contact-wire height at the contact point (static shape + deviation), m.
    pub wire_height_m: f64,
    /// Contact-wire vertical velocity at the contact point, m/s.
    pub wire_velocity_m_s: f64,
    /// Contact force: computed (SIL) or the input (HIL), N.
    pub contact_force_n: f64,
    /// Lateral position of the contact point from the track's centre line, m (0 without
    /// lateral motion).
    pub lateral_m: f64,
}

/// `∫_0^A cos(ω x + φ) dx`.
fn int_cos(omega: f64, phi: f64, a: f64) -> f64 {
    if omega.abs() < 1e-12 {
        a * phi.cos()
    } else {
        ((omega * a + phi).sin() - phi.sin()) / omega
    }
}

/// The projection `P_kj` of a shift by `d` on a sine basis over `w` (row-major `n × n`), by its
/// defining integrals: `P_kj = (2/W) ∫_0^{W−d} sin(κ_k x) sin(κ_j (x + d)) dx`. The reference
/// for [`shift_projection`].
pub fn shift_projection_by_integrals(w: f64, n: usize, d: f64) -> Vec<f64> {
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

/// The projection `P_kj` of a shift by `d` on a sine basis over `w` (row-major `n × n`), in its
/// closed Toeplitz + Hankel form (mode numbers `j, k ≥ 1`, `s_m = sin(mπd/W)`,
/// `σ_m = (−1)^m`):
///
/// ```text
/// P_kj = (σ_j σ_k s_k − s_j) / ((j − k) π) + (σ_j σ_k s_k + s_j) / ((j + k) π),   j ≠ k,
/// P_kk = (1 − d/W) cos(kπd/W) + s_k / (kπ).
/// ```
///
/// Tested against [`shift_projection_by_integrals`]. It needs one sine and one cosine per mode
/// instead of four per entry.
pub fn shift_projection(w: f64, n: usize, d: f64) -> Vec<f64> {
    use std::f64::consts::PI;
    let th = |m: usize| m as f64 * PI * d / w;
    let s: Vec<f64> = (0..=n).map(|m| th(m).sin()).collect();
    let sg = |m: usize| if m % 2 == 0 { 1.0 } else { -1.0 };
    let mut p = vec![0.0; n * n];
    for k in 1..=n {
        for j in 1..=n {
            let v = if j == k {
                (1.0 - d / w) * th(k).cos() + s[k] / (k as f64 * PI)
            } else {
                let ss = sg(j) * sg(k) * s[k];
                (ss - s[j]) / ((j as f64 - k as f64) * PI) + (ss + s[j]) / ((j + k) as f64 * PI)
            };
            p[(k - 1) * n + (j - 1)] = v;
        }
    }
    p
}

/// The observer that moves the window forward by its fixed shift when the leading pantograph
/// passes the trigger, and carries the state over (allocation-free, fixed work).
#[derive(Debug, Clone)]
pub struct WindowMover {
    shift_m: f64,
    trigger_m: f64,
    proj: Vec<f64>,
    buf: Vec<f64>,
    /// For each node after a move: the node it takes its state from.
    node_from: Vec<Option<usize>>,
    nbuf: Vec<f64>,
    moves: u64,
    /// The window's time step, s (the carried-over state is taken at the half step).
    dt_s: f64,
}

impl WindowMover {
    /// A mover for `model` (a window of length `window_m` with `n` modes per block, stepped at
    /// `dt_s`), shifting by `shift_m` once the leading pantograph passes `trigger_m` (window
    /// coordinates).
    pub fn new(
        model: &crate::model::Model,
        dt_s: f64,
        window_m: f64,
        n: usize,
        shift_m: f64,
        trigger_m: f64,
    ) -> Self {
        let xs: Vec<f64> = model.nodes.iter().map(|s| s.x_m).collect();
        let node_from = xs
            .iter()
            .map(|&x| xs.iter().position(|&y| (y - (x + shift_m)).abs() < 1e-6))
            .collect();
        let nv = 4 * model
            .layout
            .groups
            .iter()
            .map(|g| g.blocks.len())
            .max()
            .unwrap_or(0);
        WindowMover {
            shift_m,
            trigger_m,
            proj: shift_projection(window_m, n, shift_m),
            buf: vec![0.0; nv * n],
            node_from,
            nbuf: vec![0.0; xs.len()],
            moves: 0,
            dt_s,
        }
    }

    /// Move the window forward by the fixed shift and carry the state over (`h = Δt/2`).
    pub fn shift(
        &mut self,
        model: &crate::model::Model,
        st: &mut State,
        h: f64,
        isa: crate::solve::kernels::Isa,
    ) {
        for g in 0..model.layout.groups.len() {
            st.project_group(model, g, &self.proj, h, isa, &mut self.buf);
        }
        let nd = &mut st.nodes;
        for v in [&mut nd.u, &mut nd.v, &mut nd.a] {
            for (i, from) in self.node_from.iter().enumerate() {
                self.nbuf[i] = from.map_or(0.0, |j| v[j]);
            }
            v.copy_from_slice(&self.nbuf);
        }
        st.x0_m -= self.shift_m;
        st.track_origin_m += self.shift_m;
        self.moves += 1;
    }
}

impl Observer for WindowMover {
    fn observe(
        &mut self,
        cm: &CompiledModel,
        st: &mut State,
        ws: &Workspace,
    ) -> Result<(), SimError> {
        if ws.samples()[0].position_m > self.trigger_m {
            self.shift(cm.model(), st, 0.5 * self.dt_s, cm.isa());
        }
        Ok(())
    }

    fn moves(&self) -> u64 {
        self.moves
    }
}

/// A hardware-in-the-loop input that the window cannot take.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum InputError {
    /// Not a finite number.
    NotFinite {
        /// What was not finite.
        what: &'static str,
        /// Its value.
        value: f64,
    },
    /// The contact force lies outside the bound stated for the case (see
    /// `session::RealtimeSession::force_limit_n`).
    ForceOutOfBound {
        /// The force given, N.
        force_n: f64,
        /// The bound, N.
        limit_n: f64,
    },
    /// The position lies ahead of the window's far end (the wire there is not modelled).
    AheadOfWindow {
        /// The position given, m.
        position_m: f64,
        /// The window's far end, m.
        window_end_m: f64,
    },
    /// The position lies outside the modelled catenary.
    OutsideModel {
        /// The position given, m.
        position_m: f64,
        /// The model's length, m.
        length_m: f64,
    },
    /// The position lies behind the window (it only moves forward).
    BehindWindow {
        /// The position given, m.
        position_m: f64,
        /// The window's start, m.
        window_start_m: f64,
    },
    /// The position moved faster than the plausible speed since the last step.
    TooFast {
        /// The position given, m.
        position_m: f64,
        /// The previous step's position, m.
        previous_m: f64,
        /// The speed the jump implies, km/h.
        speed_kmh: f64,
        /// The plausible limit, km/h.
        limit_kmh: f64,
    },
}

impl InputError {
    /// A stable name of the reason, the same in every front end (`not_finite`,
    /// `force_out_of_bound`, `outside_model`, `behind_window`, `ahead_of_window`, `too_fast`).
    pub fn code(&self) -> &'static str {
        match self {
            InputError::NotFinite { .. } => "not_finite",
            InputError::ForceOutOfBound { .. } => "force_out_of_bound",
            InputError::OutsideModel { .. } => "outside_model",
            InputError::BehindWindow { .. } => "behind_window",
            InputError::AheadOfWindow { .. } => "ahead_of_window",
            InputError::TooFast { .. } => "too_fast",
        }
    }
}

impl std::fmt::Display for InputError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            InputError::NotFinite { what, value } => write!(f, "{what} = {value} is not finite"),
            InputError::ForceOutOfBound { force_n, limit_n } => write!(
                f,
                "contact force {force_n:e} N lies outside the bound ±{limit_n} N stated for this case"
            ),
            InputError::AheadOfWindow {
                position_m,
                window_end_m,
            } => write!(
                f,
                "pantograph position {position_m} m lies ahead of the window, which ends at {window_end_m} m"
            ),
            InputError::OutsideModel {
                position_m,
                length_m,
            } => write!(
                f,
                "pantograph position {position_m} m lies outside the modelled catenary [0, {length_m}] m"
            ),
            InputError::BehindWindow {
                position_m,
                window_start_m,
            } => write!(
                f,
                "pantograph position {position_m} m lies behind the window, which starts at {window_start_m} m and only moves forward"
            ),
            InputError::TooFast {
                position_m,
                previous_m,
                speed_kmh,
                limit_kmh,
            } => write!(
                f,
                "pantograph position jumped from {previous_m} m to {position_m} m in one step ({speed_kmh:.0} km/h, above the plausible {limit_kmh:.0} km/h)"
            ),
        }
    }
}

/// One position of the window: its model (compiled), state and scratch.
#[derive(Debug, Clone)]
struct Frame {
    integ: Integrator,
    st: State,
    ws: Workspace,
    /// Track position of the window's start, m.
    origin_m: f64,
}

impl Frame {
    /// The window `[origin, origin + window]` of `full_model`, at rest at its static shape.
    fn new(
        full_model: &crate::model::Model,
        full_plan: &Plan,
        options: crate::solve::Options,
        origin_m: f64,
        window_m: f64,
        n: usize,
        hil: bool,
    ) -> Result<Self, CaseError> {
        let model = full_model.window(origin_m, window_m, n, hil);
        let plan = Plan {
            start_m: full_plan.start_m - origin_m,
            ..full_plan.clone()
        };
        let integ = Integrator::new(model, &plan, options)?;
        let mut st = integ.initial_state(plan.start_m);
        st.track_origin_m = origin_m;
        let ws = integ.workspace();
        Ok(Frame {
            integ,
            st,
            ws,
            origin_m,
        })
    }
}

/// The window's positions on a line, track coordinates of their starts: from the last support
/// at or behind half a window before the start, each next one the furthest support within half
/// a window ahead (at least the next support), until the window reaches the line's end. The
/// window moves by one or more whole spans, as on a span-periodic catenary, but the spans need
/// not be equal, so each position is a model of its own.
fn line_origins(
    full_model: &crate::model::Model,
    window_m: f64,
    x_start_m: f64,
) -> Result<Vec<f64>, CaseError> {
    let l = full_model.length_m();
    let mut sup = full_model.supports_m.clone();
    sup.sort_by(f64::total_cmp);
    sup.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
    let longest = sup.windows(2).map(|w| w[1] - w[0]).fold(0.0, f64::max);
    if !(window_m.is_finite() && window_m > longest && window_m < l) {
        return Err(CaseError::Invalid {
            field: "window_m".into(),
            value: window_m.to_string(),
            reason: format!(
                "on a line the window must be longer than its longest span ({longest} m), so that it moves by whole spans, and shorter than the line ({l} m)"
            ),
        });
    }
    let behind = (x_start_m - 0.5 * window_m).max(0.0);
    let mut origins = vec![sup.iter().copied().rfind(|&s| s <= behind).unwrap_or(0.0)];
    while let Some(&o) = origins.last() {
        if o + window_m >= l - 1e-9 {
            break;
        }
        let next = sup
            .iter()
            .copied()
            .rfind(|&s| s > o + 1e-6 && s <= o + 0.5 * window_m)
            .or_else(|| sup.iter().copied().find(|&s| s > o + 1e-6));
        match next {
            Some(x) => origins.push(x),
            None => break,
        }
        if origins.len() > MAX_LINE_POSITIONS {
            return Err(CaseError::Invalid {
                field: "window_m".into(),
                value: window_m.to_string(),
                reason: format!(
                    "over this {l} m line the window would take more than {MAX_LINE_POSITIONS} positions, each a model of its own built before the first step (about 0.5 MB and 40 M instructions each at 240 m): use a longer window or a shorter line"
                ),
            });
        }
    }
    Ok(origins)
}

/// The most positions a line's window may take (its models are all built before the first
/// step: memory and set-up grow with them).
pub const MAX_LINE_POSITIONS: usize = 2000;

/// `∫_0^A cos(ω x + φ) dx = 2 cos(φ + ωA/2) sin(ωA/2) / ω`, in a form without cancellation
/// when ω is small (the wires' bases on a line differ a little in length).
fn int_cos_stable(omega: f64, phi: f64, a: f64) -> f64 {
    let half = 0.5 * omega * a;
    let sinc = if half.abs() < 1e-8 {
        1.0 - half * half / 6.0
    } else {
        half.sin() / half
    };
    a * (phi + half).cos() * sinc
}

/// The projection of a wire's modes from one sine basis onto another over the part they share
/// (row-major `n_to × n_from`): the bases cover `[a_from, a_from + l_from]` and
/// `[a_to, a_to + l_to]` (track coordinates), and
/// `P_kj = (2/l_to) ∫ sin(κ_j (x − a_from)) sin(κ'_k (x − a_to)) dx` over their common part.
/// On equal bases shifted by `d` it is [`shift_projection`].
pub fn basis_projection(
    (a_from, l_from, n_from): (f64, f64, usize),
    (a_to, l_to, n_to): (f64, f64, usize),
) -> Vec<f64> {
    use std::f64::consts::PI;
    let x0 = a_from.max(a_to);
    let len = ((a_from + l_from).min(a_to + l_to) - x0).max(0.0);
    let mut p = vec![0.0; n_to * n_from];
    for k in 0..n_to {
        let kk = (k + 1) as f64 * PI / l_to;
        let pk = kk * (x0 - a_to);
        for j in 0..n_from {
            let kj = (j + 1) as f64 * PI / l_from;
            let pj = kj * (x0 - a_from);
            p[k * n_from + j] = (int_cos_stable(kj - kk, pj - pk, len)
                - int_cos_stable(kj + kk, pj + pk, len))
                / l_to;
        }
    }
    p
}

/// How a line's window carries its state from one position to the next, built once: each
/// block of the next position's model takes the same wire's block (same direction) projected
/// onto its basis ([`basis_projection`]), or starts at rest when the wire enters; nodes are
/// carried over by position; the pantograph's state, the time and the positions are kept.
#[derive(Debug, Clone)]
struct Transfer {
    /// Per block of the next model: its offset and modes, and the source block's offset and
    /// modes with the projection (`None`: the wire enters the window).
    blocks: Vec<(usize, usize, Option<Source>)>,
    /// For each node of the next model: the node it takes its state from.
    node_from: Vec<Option<usize>>,
    /// How far the window moves, m.
    shift_m: f64,
}

/// The full model's wire of window wire `i`.
fn full_wire(m: &crate::model::Model, i: usize) -> usize {
    match &m.statics {
        StaticShape::Line(l) => l.full_wire.get(i).copied().unwrap_or(i),
        _ => i,
    }
}

/// A projection matrix, shared between the moves of equal geometry (on a tension length of
/// equal spans most moves are the same shift of the same bases).
type Projection = std::sync::Arc<[f64]>;

/// Where a block of the next position takes its state from: the source block's offset and modes,
/// and the projection onto the block's basis.
type Source = (usize, usize, Projection);

/// The projections made so far, by the geometry they depend on: the target basis's start
/// relative to the source's, both lengths (to 1 nm) and both mode counts.
type Projections = std::collections::HashMap<(i64, i64, i64, usize, usize), Projection>;

impl Transfer {
    fn new(from: &Frame, to: &Frame, made: &mut Projections) -> Self {
        let (mf, mt) = (from.integ.model(), to.integ.model());
        let span = |m: &crate::model::Model, o: f64, b: usize| {
            let blk = &m.layout.blocks[b];
            let w = &m.wires[blk.key.wire];
            (o + w.origin_m, w.basis.length_m(), blk.n_modes)
        };
        let blocks = (0..mt.layout.blocks.len())
            .map(|b| {
                let bt = &mt.layout.blocks[b];
                let key = (full_wire(mt, bt.key.wire), bt.key.dir);
                let src = (0..mf.layout.blocks.len()).find(|&j| {
                    let bf = &mf.layout.blocks[j];
                    (full_wire(mf, bf.key.wire), bf.key.dir) == key
                });
                let src = src.map(|j| {
                    let (f, t) = (span(mf, from.origin_m, j), span(mt, to.origin_m, b));
                    let nm = |x: f64| (x * 1e9).round() as i64;
                    let key = (nm(t.0 - f.0), nm(f.1), nm(t.1), f.2, t.2);
                    let p = made
                        .entry(key)
                        .or_insert_with(|| basis_projection(f, t).into())
                        .clone();
                    (mf.layout.blocks[j].offset, mf.layout.blocks[j].n_modes, p)
                });
                (bt.offset, bt.n_modes, src)
            })
            .collect();
        let node_from = mt
            .nodes
            .iter()
            .map(|nt| {
                let x = nt.x_m + to.origin_m;
                mf.nodes
                    .iter()
                    .position(|nf| nf.dir == nt.dir && (nf.x_m + from.origin_m - x).abs() < 1e-6)
            })
            .collect();
        Transfer {
            blocks,
            node_from,
            shift_m: to.origin_m - from.origin_m,
        }
    }

    /// Carry `from` over into `to` (`h = Δt/2`): the modal coordinates and the half-kicked
    /// velocities `v + h a` are projected (`kernels::project2_rect`), the accelerations start at
    /// zero (as `State::project_group`). `buf` holds at least three times the most modes of a
    /// block. Allocation-free; the work is fixed (`Σ n_to · n_from`).
    fn apply(&self, from: &State, to: &mut State, h: f64, isa: Isa, buf: &mut [f64]) {
        to.modal.a.fill(0.0);
        for (ot, nt, src) in &self.blocks {
            let (ot, nt) = (*ot, *nt);
            let Some((of, nf, p)) = src else {
                to.modal.u[ot..ot + nt].fill(0.0);
                to.modal.v[ot..ot + nt].fill(0.0);
                continue;
            };
            let (of, nf) = (*of, *nf);
            let (half, out) = buf.split_at_mut(nf);
            half.copy_from_slice(&from.modal.v[of..of + nf]);
            crate::solve::kernels::kick(isa, half, &from.modal.a[of..of + nf], h);
            let out = &mut out[..2 * nt];
            crate::solve::kernels::project2_rect(
                isa,
                p,
                (nt, nf),
                &from.modal.u[of..of + nf],
                half,
                out,
            );
            to.modal.u[ot..ot + nt].copy_from_slice(&out[..nt]);
            to.modal.v[ot..ot + nt].copy_from_slice(&out[nt..]);
        }
        let (nf, nt) = (&from.nodes, &mut to.nodes);
        for (i, f) in self.node_from.iter().enumerate() {
            nt.u[i] = f.map_or(0.0, |j| nf.u[j]);
            nt.v[i] = f.map_or(0.0, |j| nf.v[j]);
            nt.a[i] = f.map_or(0.0, |j| nf.a[j]);
        }
        to.pantographs.u.copy_from_slice(&from.pantographs.u);
        to.pantographs.v.copy_from_slice(&from.pantographs.v);
        to.pantographs.a.copy_from_slice(&from.pantographs.a);
        to.t = from.t;
        to.x0_m = from.x0_m - self.shift_m;
        to.track_origin_m = from.track_origin_m + self.shift_m;
    }
}

/// A line's window moves: from each position to the next when the pantograph passes the
/// position's trigger (window coordinates, `W/2 + Δ/2` with `Δ` the move, as the
/// [`WindowMover`]'s), by its [`Transfer`].
#[derive(Debug, Clone)]
struct LineMoves {
    transfers: Vec<Transfer>,
    trigger_m: Vec<f64>,
    /// Half the time step, s.
    h: f64,
    /// Scratch of the projections (three times the most modes of a block).
    buf: Vec<f64>,
}

impl LineMoves {
    fn new(frames: &[Frame], origins: &[f64], window_m: f64, h: f64) -> Self {
        let mut made = Projections::new();
        let transfers = frames
            .windows(2)
            .map(|f| Transfer::new(&f[0], &f[1], &mut made))
            .collect();
        let trigger_m = (0..frames.len())
            .map(|k| match origins.get(k + 1) {
                Some(&next) => (0.5 * window_m + 0.5 * (next - origins[k])).min(window_m),
                None => f64::INFINITY,
            })
            .collect();
        let most = (frames.iter())
            .flat_map(|f| f.integ.model().layout.blocks.iter().map(|b| b.n_modes))
            .max()
            .unwrap_or(0);
        LineMoves {
            transfers,
            trigger_m,
            h,
            buf: vec![0.0; 3 * most],
        }
    }
}

/// The plausible speed limit of a hardware-in-the-loop pantograph position, km/h (the fastest
/// trains run at 350–400 km/h; records are near 575 km/h).
pub const DEFAULT_MAX_SPEED_KMH: f64 = 600.0;

/// The moving-window catenary with a fixed-step, allocation-free [`RealtimeCatenary::step`].
#[derive(Debug, Clone)]
pub struct RealtimeCatenary {
    /// The window's positions: one for a span-periodic catenary (the window moves over the same
    /// model), one per position on a line (`LineMoves`).
    frames: Vec<Frame>,
    /// The current position, an index into `frames`.
    cur: usize,
    mover: WindowMover,
    /// A line's moves from each position to the next (`None`: a span-periodic catenary).
    line: Option<LineMoves>,
    coupling: Coupling,
    window_m: f64,
    n: usize,
    input: ExternalInput,
    /// The full model's run length and analysis section (track coordinates), for comparisons.
    full_duration_s: f64,
    analysis_m: [f64; 2],
    /// The full model's length (track coordinates), m.
    length_m: f64,
    /// Track position of the leading pantograph at the start (the case's), m.
    start_m: f64,
    max_speed_kmh: f64,
    /// The largest contact force a HIL input may have, N ([`force_limit_n`]).
    force_limit_n: f64,
}

/// The bound on a hardware-in-the-loop contact force, N: 20 times the leading pantograph's static
/// force (its uplift, or a moving force's value), and at least 20 × 50 N. EN 50367 limits the
/// mean force to about 200 N and the statistical maximum to 350–400 N at 320 km/h; a measured
/// force above this bound is a sensor or unit error, never a contact force, and stepping it would
/// throw the wire metres (1e6 N: 12 km).
pub fn force_limit_n(static_force_n: f64) -> f64 {
    20.0 * static_force_n.abs().max(50.0)
}

impl RealtimeCatenary {
    /// The window model, `window_m` long (at the full model's mode density), placed around the
    /// leading pantograph's start (the compile step's `compile::realtime_window` builds it from a
    /// case). `full_model`,
    /// `full_plan` and `options` are the full model's; `span_m` its span; `static_force_n` the
    /// leading pantograph's static force (the bound on HIL forces, [`force_limit_n`]).
    #[allow(clippy::too_many_arguments)]
    pub fn new(
        full_model: &crate::model::Model,
        full_plan: &Plan,
        options: crate::solve::Options,
        span_m: f64,
        static_force_n: f64,
        window_m: f64,
        coupling: Coupling,
    ) -> Result<Self, CaseError> {
        if full_model.pantographs.len() != 1 {
            return Err(CaseError::Invalid {
                field: "pantographs".into(),
                value: format!("{} pantographs", full_model.pantographs.len()),
                reason: "the real-time window carries one pantograph, the rig's (compile::window_case keeps the leading one)".into(),
            });
        }
        let static_force = static_force_n;
        let span = span_m;
        let l = full_model.length_m();
        let line = matches!(full_model.statics, StaticShape::Line(_));
        let lead_offset = full_model.pantographs.first().map_or(0.0, |p| p.offset_m);
        let x_start = full_plan.start_m - lead_offset + full_plan.speed_m_s * 0.0;
        // The contact wire's mode density (a line's wires each cover one tension length).
        let density = full_model
            .wire_index(WireRole::Contact)
            .map_or(full_model.n_modes() as f64 / l, |w| {
                full_model.n_modes() as f64 / full_model.wires[w].basis.length_m()
            });
        let n = ((density * window_m).round() as usize).max(1);
        let hil = coupling == Coupling::Hil;
        let (frames, mover, line) = if line {
            let origins = line_origins(full_model, window_m, x_start)?;
            let frames = origins
                .iter()
                .map(|&o| Frame::new(full_model, full_plan, options, o, window_m, n, hil))
                .collect::<Result<Vec<_>, _>>()?;
            if let Some(f) = frames
                .iter()
                .find(|f| f.integ.dt_s() != frames[0].integ.dt_s())
            {
                return Err(CaseError::Invalid {
                    field: "window_m".into(),
                    value: window_m.to_string(),
                    reason: format!(
                        "the window at {} m needs a time step of {} s, the first one {} s: one real-time step must serve every position",
                        f.st.track_origin_m,
                        f.integ.dt_s(),
                        frames[0].integ.dt_s()
                    ),
                });
            }
            let moves = LineMoves::new(&frames, &origins, window_m, 0.5 * options.dt_s);
            // The periodic mover never fires on a line (its trigger lies beyond the window).
            let mover = WindowMover::new(
                frames[0].integ.model(),
                options.dt_s,
                window_m,
                1,
                0.0,
                f64::INFINITY,
            );
            (frames, mover, Some(moves))
        } else {
            if !(window_m.is_finite() && window_m >= 0.5 * span && window_m < l) {
                return Err(CaseError::Invalid {
                    field: "window_m".into(),
                    value: window_m.to_string(),
                    reason: format!("the window must be at least half a span ({} m) and shorter than the model ({l} m)", 0.5 * span),
                });
            }
            let m = ((window_m / (2.0 * span)).floor() as usize).max(1);
            let shift_m = m as f64 * span;
            let trigger_m = (0.5 * window_m + 0.5 * shift_m).min(window_m);
            let origin_m = span * ((x_start - 0.5 * window_m).max(0.0) / span).floor();
            let frame = Frame::new(full_model, full_plan, options, origin_m, window_m, n, hil)?;
            let mover = WindowMover::new(
                frame.integ.model(),
                options.dt_s,
                window_m,
                n,
                shift_m,
                trigger_m,
            );
            (vec![frame], mover, None)
        };
        Ok(Self {
            frames,
            cur: 0,
            mover,
            line,
            coupling,
            window_m,
            n,
            input: ExternalInput {
                position_m: x_start,
                force_n: 0.0,
            },
            start_m: x_start,
            full_duration_s: full_plan.duration_s,
            analysis_m: full_plan.analysis_m,
            length_m: l,
            max_speed_kmh: DEFAULT_MAX_SPEED_KMH,
            force_limit_n: force_limit_n(static_force),
        })
    }

    /// Whether the window runs on a line (a model per position, `step` moves between them); the
    /// span-periodic window moves over one model, so the one run loop can step it with the
    /// [`WindowMover`] ([`Self::parts_mut`]).
    pub fn is_line(&self) -> bool {
        self.line.is_some()
    }

    /// The window's positions along the track (their origins), m: one for a span-periodic
    /// catenary, whose window moves over one model.
    pub fn positions_m(&self) -> Vec<f64> {
        self.frames.iter().map(|f| f.origin_m).collect()
    }

    /// The window's model (one pantograph).
    pub fn model(&self) -> &crate::model::Model {
        self.frames[self.cur].integ.model()
    }

    /// How the window is coupled to the pantograph.
    pub fn coupling(&self) -> Coupling {
        self.coupling
    }

    /// The plausible speed limit of hardware-in-the-loop positions, km/h.
    pub fn set_max_speed_kmh(&mut self, v: f64) {
        self.max_speed_kmh = v;
    }

    /// Replace the bound on a HIL contact force, N.
    pub fn set_force_limit_n(&mut self, v: f64) {
        self.force_limit_n = v;
    }

    /// The largest contact force a HIL input may have, N.
    pub fn force_limit_n(&self) -> f64 {
        self.force_limit_n
    }

    /// The full model's length, m: the positions a HIL input may take lie in `[0, length]`.
    pub fn model_length_m(&self) -> f64 {
        self.length_m
    }

    /// Check a HIL input before [`Self::set_input`]: finite, inside the modelled catenary and the
    /// window, the force within [`Self::force_limit_n`], and no faster than the plausible speed since the last input, which was
    /// `elapsed_s` ago (one step, or one communication step of an FMU). A refused input leaves the
    /// catenary unchanged.
    pub fn check_input(
        &self,
        contact_force_n: f64,
        position_m: f64,
        elapsed_s: f64,
    ) -> Result<(), InputError> {
        if !contact_force_n.is_finite() {
            return Err(InputError::NotFinite {
                what: "contact force",
                value: contact_force_n,
            });
        }
        if !position_m.is_finite() {
            return Err(InputError::NotFinite {
                what: "pantograph position",
                value: position_m,
            });
        }
        if !(0.0..=self.length_m).contains(&position_m) {
            return Err(InputError::OutsideModel {
                position_m,
                length_m: self.length_m,
            });
        }
        if position_m < self.frames[self.cur].st.track_origin_m {
            return Err(InputError::BehindWindow {
                position_m,
                window_start_m: self.frames[self.cur].st.track_origin_m,
            });
        }
        let window_end_m = self.frames[self.cur].st.track_origin_m + self.window_m;
        if position_m > window_end_m {
            return Err(InputError::AheadOfWindow {
                position_m,
                window_end_m,
            });
        }
        if contact_force_n.abs() > self.force_limit_n {
            return Err(InputError::ForceOutOfBound {
                force_n: contact_force_n,
                limit_n: self.force_limit_n,
            });
        }
        let previous_m = self.input.position_m;
        let speed_kmh = (position_m - previous_m).abs()
            / elapsed_s.max(self.frames[self.cur].integ.dt_s())
            * 3.6;
        // A little slack for rounding: the limit applies to the step's displacement.
        if speed_kmh > self.max_speed_kmh * (1.0 + 1e-9) + 1e-6 {
            return Err(InputError::TooFast {
                position_m,
                previous_m,
                speed_kmh,
                limit_kmh: self.max_speed_kmh,
            });
        }
        Ok(())
    }

    /// Fixed time step, s.
    pub fn dt_s(&self) -> f64 {
        self.frames[self.cur].integ.dt_s()
    }

    /// Window length, m.
    pub fn window_m(&self) -> f64 {
        self.window_m
    }

    /// Modes per wire in the window.
    pub fn n_modes(&self) -> usize {
        self.n
    }

    /// Track position of the leading pantograph at the start (the first HIL input's), m.
    pub fn start_position_m(&self) -> f64 {
        self.start_m
    }

    /// Global position of the window's start, m.
    pub fn origin_m(&self) -> f64 {
        self.frames[self.cur].st.track_origin_m
    }

    /// Number of window moves so far (on a line: the index of the current position).
    pub fn moves(&self) -> usize {
        match self.line {
            Some(_) => self.cur,
            None => self.mover.moves as usize,
        }
    }

    /// The full model's duration and analysis section (track coordinates).
    pub fn full_run(&self) -> (f64, [f64; 2]) {
        (self.full_duration_s, self.analysis_m)
    }

    /// The integrator, the state, the workspace and the mover, for the run loop: a
    /// span-periodic window, which moves over one model. `None` on a line (its window moves
    /// between models: step it with [`Self::step`]).
    pub fn parts_mut(
        &mut self,
    ) -> Option<(&Integrator, &mut State, &mut Workspace, &mut WindowMover)> {
        if self.line.is_some() {
            return None;
        }
        let f = &mut self.frames[self.cur];
        Some((&f.integ, &mut f.st, &mut f.ws, &mut self.mover))
    }

    /// HIL input for the next step: the measured contact force (N, pushing the wire up) and the
    /// pantograph position along the track (m).
    pub fn set_input(&mut self, contact_force_n: f64, position_m: f64) {
        self.input = ExternalInput {
            position_m,
            force_n: contact_force_n,
        };
    }

    /// Advance one fixed step. Allocation-free; the work is bounded (a window move adds a fixed
    /// `O(N²)` projection).
    pub fn step(&mut self) -> RealtimeOutput {
        let f = &mut self.frames[self.cur];
        if self.coupling == Coupling::Hil {
            // The input in track coordinates, the workspace's in the window's model coordinates.
            f.ws.set_external(
                0,
                ExternalInput {
                    position_m: self.input.position_m - f.st.track_origin_m,
                    ..self.input
                },
            );
        }
        f.integ.step(&mut f.st, &mut f.ws);
        let s = f.ws.samples()[0];
        let out = RealtimeOutput {
            time_s: f.st.t,
            position_m: s.position_m + f.st.track_origin_m,
            wire_height_m: s.wire_height_m,
            wire_velocity_m_s: s.wire_velocity_m_s,
            contact_force_n: s.force_n,
            lateral_m: s.lateral_m,
        };
        match &mut self.line {
            Some(lm) => {
                if s.position_m > lm.trigger_m[self.cur] {
                    // The next position exists: the last one's trigger is infinite.
                    let isa = f.integ.compiled().isa();
                    let (done, next) = self.frames.split_at_mut(self.cur + 1);
                    let t = &lm.transfers[self.cur];
                    t.apply(&done[self.cur].st, &mut next[0].st, lm.h, isa, &mut lm.buf);
                    self.cur += 1;
                }
            }
            None => {
                // The mover never fails.
                let _ = self.mover.observe(f.integ.compiled(), &mut f.st, &f.ws);
            }
        }
        out
    }
}

/// A saved state of a [`RealtimeCatenary`], for rolling a step back. Allocate once with
/// [`RealtimeCatenary::snapshot`], then [`RealtimeCatenary::save`] and
/// [`RealtimeCatenary::restore`] copy without allocating.
#[derive(Debug, Clone)]
pub struct Snapshot {
    /// The state of each of the window's positions (one on a span-periodic catenary); the
    /// current one's is saved.
    st: Vec<State>,
    /// The current position.
    cur: usize,
    moves: u64,
    input: ExternalInput,
}

impl Snapshot {
    /// Append the snapshot to `out` (on a line, the position first; the state, the window
    /// moves, the last input).
    pub fn write_bytes(&self, out: &mut Vec<u8>) {
        if self.st.len() > 1 {
            out.extend_from_slice(&(self.cur as u64).to_le_bytes());
        }
        self.st[self.cur].write_bytes(out);
        out.extend_from_slice(&self.moves.to_le_bytes());
        out.extend_from_slice(&self.input.position_m.to_le_bytes());
        out.extend_from_slice(&self.input.force_n.to_le_bytes());
    }
}

impl RealtimeCatenary {
    /// A snapshot buffer holding the current state.
    pub fn snapshot(&self) -> Snapshot {
        Snapshot {
            st: self.frames.iter().map(|f| f.st.clone()).collect(),
            cur: self.cur,
            moves: self.moves() as u64,
            input: self.input,
        }
    }

    /// Copy the current state into `s` (no allocation).
    pub fn save(&self, s: &mut Snapshot) {
        s.st[self.cur].copy_from(&self.frames[self.cur].st);
        s.cur = self.cur;
        s.moves = self.moves() as u64;
        s.input = self.input;
    }

    /// Return to the state saved in `s` (no allocation), at its position on a line.
    pub fn restore(&mut self, s: &Snapshot) {
        self.cur = s.cur;
        self.frames[self.cur].st.copy_from(&s.st[s.cur]);
        self.mover.moves = s.moves;
        self.input = s.input;
    }

    /// The length of [`Snapshot::write_bytes`] at the current position and the largest over
    /// the window's positions (they differ on a line, whose positions carry different wires),
    /// bytes (allocates).
    pub fn snapshot_len(&self) -> (usize, usize) {
        let s = self.snapshot();
        let mut buf = Vec::new();
        s.write_bytes(&mut buf);
        let header = buf.len() - {
            let mut b = Vec::new();
            s.st[s.cur].write_bytes(&mut b);
            b.len()
        };
        let most = (s.st.iter())
            .map(|st| {
                let mut b = Vec::new();
                st.write_bytes(&mut b);
                b.len()
            })
            .max()
            .unwrap_or(0);
        (buf.len(), header + most)
    }

    /// A snapshot read from bytes written by [`Snapshot::write_bytes`] for this window (the same
    /// case, window length and step); an error says what does not match.
    pub fn snapshot_from_bytes(
        &self,
        r: &mut crate::solve::state::ByteReader,
    ) -> Result<Snapshot, String> {
        let mut s = self.snapshot();
        if self.line.is_some() {
            let k = r.u64()?;
            if k >= self.frames.len() as u64 {
                return Err(format!(
                    "the window's position {k} does not exist: the line has {} positions",
                    self.frames.len()
                ));
            }
            s.cur = k as usize;
        }
        let st = &mut s.st[s.cur];
        st.read_bytes(r)?;
        s.moves = r.u64()?;
        s.input = ExternalInput {
            position_m: r.f64()?,
            force_n: r.f64()?,
        };
        if self.line.is_some() && s.moves != s.cur as u64 {
            return Err(format!(
                "the window's moves ({}) do not match its position ({}) on the line",
                s.moves, s.cur
            ));
        }
        let st = &s.st[s.cur];
        if !(st.is_finite()
            && st.x0_m.is_finite()
            && st.track_origin_m.is_finite()
            && s.input.position_m.is_finite()
            && s.input.force_n.is_finite())
        {
            return Err("the serialised state holds non-finite numbers".into());
        }
        Ok(s)
    }

    /// Static lateral position (stagger) of the contact wire at a track position, m.
    pub fn static_lateral_at(&self, x_m: f64) -> f64 {
        self.frames[self.cur]
            .integ
            .model()
            .lateral
            .as_ref()
            .map_or(0.0, |l| l.stagger_at(x_m))
    }

    /// Static contact-wire height at track position `x_m` (irregularity included), m.
    pub fn static_height_at(&self, x_m: f64) -> f64 {
        let m = self.frames[self.cur].integ.model();
        match m.wire_index(WireRole::Contact) {
            Some(w) => m.static_height(
                w,
                crate::model::Direction::Vertical,
                x_m - self.frames[self.cur].st.track_origin_m,
                self.frames[self.cur].st.track_origin_m,
            ),
            None => 0.0,
        }
    }

    /// Track position of pantograph 0 in SIL mode at the current time, m.
    pub fn sil_position_m(&self) -> f64 {
        self.frames[self.cur]
            .integ
            .position(&self.frames[self.cur].st, 0)
            + self.frames[self.cur].st.track_origin_m
    }

    /// What is wrong with the state after the last step, if anything: a non-finite state, or
    /// the sample's fault ([`Self::state_is_sound`]).
    pub fn fault(&self) -> Option<String> {
        let f = &self.frames[self.cur];
        let h = f.integ.compiled().max_wire_deviation_m();
        if !f.st.is_finite() {
            return Some("non-finite state".into());
        }
        (f.ws.samples().iter().enumerate()).find_map(|(p, s)| s.fault(p, h))
    }

    /// True when the state is finite and the last step's samples plausible (the wire within the
    /// system height of its design height, [`CompiledModel::max_wire_deviation_m`]).
    pub fn state_is_sound(&self) -> bool {
        let h = self.frames[self.cur]
            .integ
            .compiled()
            .max_wire_deviation_m();
        self.frames[self.cur].st.is_finite()
            && self.frames[self.cur]
                .ws
                .samples()
                .iter()
                .all(|s| s.is_sound(h))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::ModelBuilder;

    /// A line's window takes its positions at supports, each next one the furthest within half a
    /// window ahead; a window that would take more than [`MAX_LINE_POSITIONS`] positions is
    /// refused, naming the window (the models are all built before the first step).
    #[test]
    fn a_lines_window_positions_and_their_bound() {
        let line = |spans: usize| {
            let (mut m, _) =
                ModelBuilder::single_wire(60.0 * spans as f64, 4, 1.35, 20_000.0, 0.0).build();
            m.supports_m = (0..=spans).map(|k| 60.0 * k as f64).collect();
            m
        };
        // 240 m: moves of two 60 m spans (the furthest support within 120 m), from the support
        // at or behind the start less half a window, until the window reaches the end.
        let o = line_origins(&line(20), 240.0, 400.0).unwrap();
        assert_eq!(o.first(), Some(&240.0));
        assert!(o.windows(2).all(|w| w[1] - w[0] == 120.0), "{o:?}");
        assert!(o.last().unwrap() + 240.0 >= 1200.0);
        // A window no longer than a span cannot move by whole spans.
        let e = line_origins(&line(20), 60.0, 400.0)
            .unwrap_err()
            .to_string();
        assert!(e.contains("window_m") && e.contains("longest span"), "{e}");
        // 4 001 positions would be needed here.
        let e = line_origins(&line(4100), 100.0, 0.0)
            .unwrap_err()
            .to_string();
        assert!(
            e.contains("window_m") && e.contains("2000 positions"),
            "{e}"
        );
    }
}
