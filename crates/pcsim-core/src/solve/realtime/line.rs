//! A line's window: a model per window position ([`Frame`]), the positions along the supports
//! ([`line_origins`]), and the moves between them ([`Transfer`], [`LineMoves`]).

use super::projection::basis_projection;
use crate::error::CaseError;
use crate::model::StaticShape;
use crate::solve::integrator::Integrator;
use crate::solve::kernels::Isa;
use crate::solve::plan::Plan;
use crate::solve::state::State;
use crate::solve::workspace::Workspace;

/// One position of the window: its model (compiled), state and scratch.
#[derive(Debug, Clone)]
pub(super) struct Frame {
    pub(super) integ: Integrator,
    pub(super) st: State,
    pub(super) ws: Workspace,
    /// Track position of the window's start, m.
    pub(super) origin_m: f64,
}

impl Frame {
    /// The window `[origin, origin + window]` of `full_model`, at rest at its static shape.
    pub(super) fn new(
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
#[doc(hidden)] // public for the unit tests in tests/suite/unit
pub fn line_origins(
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

/// How a line's window carries its state from one position to the next, built once: each
/// block of the next position's model takes the same wire's block (same direction) projected
/// onto its basis ([`basis_projection`]), or starts at rest when the wire enters; nodes are
/// carried over by position; the pantograph's state, the time and the positions are kept.
/// Under steady loads (ice) each position has its own static start `s`: the deviation from it
/// is carried, `q' = P (q − s_from) + s_to`, and an entering wire or node starts at `s_to`.
#[derive(Debug, Clone)]
pub(super) struct Transfer {
    /// Per block of the next model: its offset and modes, and the source block's offset and
    /// modes with the projection (`None`: the wire enters the window).
    pub(super) blocks: Vec<(usize, usize, Option<Source>)>,
    /// For each node of the next model: the node it takes its state from.
    pub(super) node_from: Vec<Option<usize>>,
    /// How far the window moves, m.
    pub(super) shift_m: f64,
    /// The static starts of both positions (modal, nodes; empty without steady loads).
    pub(super) static_from: (Vec<f64>, Vec<f64>),
    pub(super) static_to: (Vec<f64>, Vec<f64>),
}

/// The full model's wire of window wire `i`.
pub(super) fn full_wire(m: &crate::model::Model, i: usize) -> usize {
    match &m.statics {
        StaticShape::Line(l) => l.full_wire.get(i).copied().unwrap_or(i),
        _ => i,
    }
}

/// A projection matrix, shared between the moves of equal geometry (on a tension length of
/// equal spans most moves are the same shift of the same bases).
pub(super) type Projection = std::sync::Arc<[f64]>;

/// Where a block of the next position takes its state from: the source block's offset and modes,
/// and the projection onto the block's basis.
pub(super) type Source = (usize, usize, Projection);

/// The projections made so far, by the geometry they depend on: the target basis's start
/// relative to the source's, both lengths (to 1 nm) and both mode counts.
pub(super) type Projections = std::collections::HashMap<(i64, i64, i64, usize, usize), Projection>;

impl Transfer {
    pub(super) fn new(from: &Frame, to: &Frame, made: &mut Projections) -> Self {
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
        let static_of = |f: &Frame| {
            f.integ
                .compiled()
                .static_start()
                .map_or((Vec::new(), Vec::new()), |s| {
                    (s.modal.clone(), s.nodes.clone())
                })
        };
        Transfer {
            blocks,
            node_from,
            shift_m: to.origin_m - from.origin_m,
            static_from: static_of(from),
            static_to: static_of(to),
        }
    }

    /// Carry `from` over into `to` (`h = Δt/2`): the modal coordinates and the half-kicked
    /// velocities `v + h a` are projected (`kernels::project2_rect`), the accelerations start at
    /// zero (as `State::project_group`). `buf` holds at least four times the most modes of a
    /// block. Allocation-free; the work is fixed (`Σ n_to · n_from`).
    pub(super) fn apply(&self, from: &State, to: &mut State, h: f64, isa: Isa, buf: &mut [f64]) {
        to.modal.a.fill(0.0);
        let (sf, st) = (&self.static_from, &self.static_to);
        for (ot, nt, src) in &self.blocks {
            let (ot, nt) = (*ot, *nt);
            let Some((of, nf, p)) = src else {
                match st.0.is_empty() {
                    true => to.modal.u[ot..ot + nt].fill(0.0),
                    false => to.modal.u[ot..ot + nt].copy_from_slice(&st.0[ot..ot + nt]),
                }
                to.modal.v[ot..ot + nt].fill(0.0);
                continue;
            };
            let (of, nf) = (*of, *nf);
            let (half, rest) = buf.split_at_mut(nf);
            let (dev, out) = rest.split_at_mut(nf);
            half.copy_from_slice(&from.modal.v[of..of + nf]);
            crate::solve::kernels::kick(isa, half, &from.modal.a[of..of + nf], h);
            dev.copy_from_slice(&from.modal.u[of..of + nf]);
            if !sf.0.is_empty() {
                for (d, s) in dev.iter_mut().zip(&sf.0[of..of + nf]) {
                    *d -= s;
                }
            }
            let out = &mut out[..2 * nt];
            crate::solve::kernels::project2_rect(isa, p, (nt, nf), dev, half, out);
            to.modal.u[ot..ot + nt].copy_from_slice(&out[..nt]);
            if !st.0.is_empty() {
                for (u, s) in to.modal.u[ot..ot + nt].iter_mut().zip(&st.0[ot..ot + nt]) {
                    *u += s;
                }
            }
            to.modal.v[ot..ot + nt].copy_from_slice(&out[nt..]);
        }
        let (nf, nt) = (&from.nodes, &mut to.nodes);
        let s_at = |s: &Vec<f64>, i: usize| s.get(i).copied().unwrap_or(0.0);
        for (i, f) in self.node_from.iter().enumerate() {
            nt.u[i] = f.map_or(s_at(&st.1, i), |j| {
                nf.u[j] - s_at(&sf.1, j) + s_at(&st.1, i)
            });
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
pub(super) struct LineMoves {
    pub(super) transfers: Vec<Transfer>,
    pub(super) trigger_m: Vec<f64>,
    /// Half the time step, s.
    pub(super) h: f64,
    /// Scratch of the projections (four times the most modes of a block).
    pub(super) buf: Vec<f64>,
}

impl LineMoves {
    pub(super) fn new(frames: &[Frame], origins: &[f64], window_m: f64, h: f64) -> Self {
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
            buf: vec![0.0; 4 * most],
        }
    }
}
