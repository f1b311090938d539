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

use crate::error::CaseError;
use crate::model::{StaticShape, WireRole};
use crate::solve::integrator::Integrator;
use crate::solve::plan::Plan;
use crate::solve::run::Observer;
use crate::solve::state::State;
use crate::solve::workspace::ExternalInput;
use crate::solve::workspace::Workspace;

mod line;
mod mover;
mod projection;
mod refusal;
mod snapshot;

#[doc(hidden)] // public for the unit tests in tests/suite/unit
pub use line::line_origins;
pub use line::MAX_LINE_POSITIONS;
pub use mover::WindowMover;
pub use projection::{basis_projection, shift_projection, shift_projection_by_integrals};
pub use refusal::InputError;
pub use snapshot::Snapshot;

use line::{Frame, LineMoves};

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
            return Err(CaseError::Model {
                what: crate::error::ModelQuantity::Pantographs,
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
            )
            .with_static_start(frame.integ.compiled().static_start());
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

impl RealtimeCatenary {
    /// Static lateral position (stagger) of the contact wire at a track position, m.
    pub fn static_lateral_at(&self, x_m: f64) -> f64 {
        let m = self.frames[self.cur].integ.model();
        match (&m.lateral, m.wire_index(WireRole::Contact)) {
            (Some(l), Some(w)) => l.stagger_at(w, x_m),
            _ => 0.0,
        }
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
    /// system height of its design height, [`crate::solve::CompiledModel::max_wire_deviation_m`]).
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
