//! The window's move on a span-periodic catenary: the [`WindowMover`], an observer of the one run
//! loop that shifts the window by whole spans and projects its state.

use super::projection::shift_projection;
use crate::error::SimError;
use crate::solve::compiled::CompiledModel;
use crate::solve::run::Observer;
use crate::solve::state::State;
use crate::solve::workspace::Workspace;

/// The observer that moves the window forward by its fixed shift when the leading pantograph
/// passes the trigger, and carries the state over (allocation-free, fixed work).
#[derive(Debug, Clone)]
pub struct WindowMover {
    pub(super) shift_m: f64,
    pub(super) trigger_m: f64,
    pub(super) proj: Vec<f64>,
    pub(super) buf: Vec<f64>,
    /// For each node after a move: the node it takes its state from.
    pub(super) node_from: Vec<Option<usize>>,
    pub(super) nbuf: Vec<f64>,
    pub(super) moves: u64,
    /// The window's time step, s (the carried-over state is taken at the half step).
    pub(super) dt_s: f64,
    /// The window's static start under its steady loads (ice), modal coordinates and node
    /// displacements; empty without steady loads (the design shape is the equilibrium).
    pub(super) static_modal: Vec<f64>,
    pub(super) static_nodes: Vec<f64>,
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
            static_modal: Vec::new(),
            static_nodes: Vec::new(),
        }
    }

    /// The mover of a window whose static start under its steady loads (ice) is `s`: a move
    /// carries the deviation from it, `q' = P (q − s) + s` (the window's model is the same at
    /// every position, so is `s`), and the wire that enters the window starts at its loaded
    /// static shape, not at the design's.
    pub fn with_static_start(mut self, s: Option<&crate::solve::compiled::StaticStart>) -> Self {
        if let Some(s) = s {
            self.static_modal = s.modal.clone();
            self.static_nodes = s.nodes.clone();
        }
        self
    }

    /// Move the window forward by the fixed shift and carry the state over (`h = Δt/2`).
    pub fn shift(
        &mut self,
        model: &crate::model::Model,
        st: &mut State,
        h: f64,
        isa: crate::solve::kernels::Isa,
    ) {
        let loaded = !self.static_modal.is_empty();
        if loaded {
            for (u, s) in st.modal.u.iter_mut().zip(&self.static_modal) {
                *u -= s;
            }
        }
        for g in 0..model.layout.groups.len() {
            st.project_group(model, g, &self.proj, h, isa, &mut self.buf);
        }
        if loaded {
            for (u, s) in st.modal.u.iter_mut().zip(&self.static_modal) {
                *u += s;
            }
        }
        let nd = &mut st.nodes;
        let s_at = |i: usize| self.static_nodes.get(i).copied().unwrap_or(0.0);
        for (i, from) in self.node_from.iter().enumerate() {
            self.nbuf[i] = from.map_or(s_at(i), |j| nd.u[j] - s_at(j) + s_at(i));
        }
        nd.u.copy_from_slice(&self.nbuf);
        for v in [&mut nd.v, &mut nd.a] {
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
