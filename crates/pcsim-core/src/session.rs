//! The real-time session: the one owner of the real-time step contract (issue 18). The FMU
//! (FMI 2.0 and 3.0), the C API, Python's `RealtimeCatenary` and `pcsim hil` only translate it.
//!
//! # The contract of a step
//! 1. **Input** (hardware in the loop): finite; the position inside the modelled catenary and
//!    inside the window (not behind it, not ahead of it); no faster than the plausible speed
//!    since the last accepted input (the first input is not timed); the force within
//!    ±[`force_limit_n`] of the case. A refused input is not stepped: the catenary is unchanged.
//! 2. **Save, step, check, roll back.** The state is saved, the step (or the `n` internal steps
//!    of a communication step) is taken, and the result must be sound: every number finite and
//!    the contact-wire sample within [`MAX_WIRE_DEVIATION_M`] of its design height. An unsound
//!    step is rolled back to the saved state.
//! 3. **A typed status**: `Ok` with the output, or a [`Refusal`] whose [`Refusal::code`] is the
//!    same word in every front end.
//!
//! The window carries the case's leading pantograph only: the constructor drops the others.
//! Positions are track positions (m, the model's coordinates); `pcsim hil` and the FMU give them
//! from the case's start and add it.
//!
//! # State format
//! [`RealtimeSession::state_bytes`] writes one versioned form for every front end:
//! `PCSIMRTS`, the format version, the configuration's fingerprint ([`fnv1a64`] of the pcsim
//! version, the case, the window, the step and the coupling), the payload's length, the payload
//! (the window's state, the steps taken, the last output, four host values), and an FNV-1a
//! checksum of everything before it. A state from another format version or configuration, a
//! truncated one, or one with a flipped byte is refused with the reason.

use crate::error::CaseError;
use crate::fingerprint::fnv1a64;
use crate::input::case::{Case, PantographCase};
use crate::solve::realtime::{RealtimeCatenary, Snapshot};
use crate::solve::state::ByteReader;
use crate::solve::workspace::MAX_PLAUSIBLE_HEIGHT_M;

pub use crate::solve::realtime::{
    force_limit_n, Coupling, InputError, RealtimeOutput, DEFAULT_MAX_SPEED_KMH,
};

/// A step is sound while the contact-wire sample lies within this distance of its design height,
/// m (and every number is finite).
pub const MAX_WIRE_DEVIATION_M: f64 = MAX_PLAUSIBLE_HEIGHT_M;

/// Why a step was not taken, or was taken and rolled back.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Refusal {
    /// The input was refused; nothing was stepped.
    Input(InputError),
    /// The step was taken, gave an unsound state and was rolled back.
    RolledBack {
        /// The contact-wire sample's deviation from its design height, m (NaN if not finite).
        deviation_m: f64,
    },
}

impl Refusal {
    /// A stable name of the reason, the same in every front end: the input's
    /// ([`InputError::code`]) or `rolled_back`.
    pub fn code(&self) -> &'static str {
        match self {
            Refusal::Input(e) => e.code(),
            Refusal::RolledBack { .. } => "rolled_back",
        }
    }
}

impl std::fmt::Display for Refusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Refusal::Input(e) => write!(f, "input refused ({}): {e}; the step was not taken", e.code()),
            Refusal::RolledBack { deviation_m } => write!(
                f,
                "rolled back (rolled_back): the state became non-finite or implausible (contact wire {deviation_m:.3e} m from its design height; the bound is {MAX_WIRE_DEVIATION_M} m)"
            ),
        }
    }
}

/// A saved session state: everything a step reads and writes, and host values that travel with
/// it. Allocate once with [`RealtimeSession::state`]; [`RealtimeSession::save_into`] and
/// [`RealtimeSession::restore`] then copy without allocating.
#[derive(Debug, Clone)]
pub struct SessionState {
    snap: Snapshot,
    steps: u64,
    last: RealtimeOutput,
    accepted: bool,
    /// Values a front end keeps with the state (the FMU: its start time, its two inputs and
    /// whether it was terminated). The core neither reads nor changes them.
    pub host: [f64; 4],
    fingerprint: u64,
}

/// The serialised state's magic and format version.
const MAGIC: &[u8; 8] = b"PCSIMRTS";
const VERSION: u64 = 2;

/// The real-time session: the moving-window catenary behind the one step contract.
#[derive(Debug, Clone)]
pub struct RealtimeSession {
    cat: RealtimeCatenary,
    snap: Snapshot,
    steps: u64,
    last: RealtimeOutput,
    /// Whether an input has been accepted (the first is not timed).
    accepted: bool,
    fingerprint: u64,
}

impl RealtimeSession {
    /// The session of `case`'s leading pantograph in a window of `window_m` (m), coupled as
    /// `coupling`, with the plausible speed [`DEFAULT_MAX_SPEED_KMH`].
    pub fn new(case: &Case, window_m: f64, coupling: Coupling) -> Result<Self, CaseError> {
        Self::with_budget(case, window_m, coupling, &crate::compile::Budget::default())
    }

    /// [`Self::new`] with the full model compiled within `budget` (the CLI's `--max-steps`,
    /// `--max-memory-gb`).
    pub fn with_budget(
        case: &Case,
        window_m: f64,
        coupling: Coupling,
        budget: &crate::compile::Budget,
    ) -> Result<Self, CaseError> {
        let case = crate::compile::window_case(case)?;
        let cat = crate::compile::realtime_window_with(&case, window_m, coupling, budget)?;
        let fingerprint = fnv1a64(
            format!(
                "{}|{}|{:e}|{:e}|{:?}",
                env!("CARGO_PKG_VERSION"),
                case.to_toml_string(),
                window_m,
                cat.dt_s(),
                coupling
            )
            .as_bytes(),
        );
        let snap = cat.snapshot();
        let x = cat.start_position_m();
        let static_force = match case.pantographs.first() {
            Some(PantographCase::Lumped { .. }) | None => 0.0,
            Some(PantographCase::MovingForce { force_n, .. }) => *force_n,
        };
        let last = RealtimeOutput {
            time_s: 0.0,
            position_m: if coupling == Coupling::Sil {
                cat.sil_position_m()
            } else {
                x
            },
            wire_height_m: cat.static_height_at(x),
            wire_velocity_m_s: 0.0,
            contact_force_n: static_force,
            lateral_m: cat.static_lateral_at(x),
        };
        Ok(Self {
            cat,
            snap,
            steps: 0,
            last,
            accepted: false,
            fingerprint,
        })
    }

    /// The plausible speed of hardware-in-the-loop positions, km/h (finite and > 0).
    pub fn set_max_speed_kmh(&mut self, v: f64) -> Result<(), CaseError> {
        if !(v.is_finite() && v > 0.0) {
            return Err(CaseError::Invalid {
                field: "max_speed_kmh".into(),
                value: v.to_string(),
                reason: "must be a finite speed > 0".into(),
            });
        }
        self.cat.set_max_speed_kmh(v);
        Ok(())
    }

    /// Replace the bound on the input contact force, N (finite and > 0; the default is
    /// [`force_limit_n`] of the case).
    pub fn set_force_limit_n(&mut self, v: f64) -> Result<(), CaseError> {
        if !(v.is_finite() && v > 0.0) {
            return Err(CaseError::Invalid {
                field: "force_limit_n".into(),
                value: v.to_string(),
                reason: "must be a finite force > 0".into(),
            });
        }
        self.cat.set_force_limit_n(v);
        Ok(())
    }

    /// Check a HIL input (part 1 of the contract) without taking it; `elapsed_s` is the time since
    /// the last accepted input (ignored for the first).
    pub fn check_input(
        &self,
        contact_force_n: f64,
        position_m: f64,
        elapsed_s: f64,
    ) -> Result<(), InputError> {
        let elapsed = if self.accepted {
            elapsed_s
        } else {
            f64::INFINITY
        };
        self.cat.check_input(contact_force_n, position_m, elapsed)
    }

    /// Give the first input before any step (the FMU's initial values): checked as a step's
    /// input, then held. It changes nothing in a SIL session.
    pub fn set_initial_input(
        &mut self,
        contact_force_n: f64,
        position_m: f64,
    ) -> Result<(), Refusal> {
        if self.cat.coupling() == Coupling::Hil {
            self.check_input(contact_force_n, position_m, f64::INFINITY)
                .map_err(Refusal::Input)?;
            self.cat.set_input(contact_force_n, position_m);
            self.accepted = true;
            self.last.position_m = position_m;
            self.last.contact_force_n = contact_force_n;
            self.last.wire_height_m = self.cat.static_height_at(position_m);
            self.last.lateral_m = self.cat.static_lateral_at(position_m);
        }
        Ok(())
    }

    /// One fixed step Δt with the contact force (N, pushing the wire up) and the pantograph's
    /// track position (m); a SIL session ignores both. Allocation-free.
    pub fn step(
        &mut self,
        contact_force_n: f64,
        position_m: f64,
    ) -> Result<RealtimeOutput, Refusal> {
        let dt = self.cat.dt_s();
        self.advance(contact_force_n, position_m, 1, dt)
    }

    /// `n_steps` fixed steps holding the input (an FMU's communication step of `elapsed_s`), under
    /// the whole contract: checked, saved, stepped, checked for soundness, rolled back.
    /// Allocation-free.
    pub fn advance(
        &mut self,
        contact_force_n: f64,
        position_m: f64,
        n_steps: u64,
        elapsed_s: f64,
    ) -> Result<RealtimeOutput, Refusal> {
        let hil = self.cat.coupling() == Coupling::Hil;
        if hil {
            self.check_input(contact_force_n, position_m, elapsed_s)
                .map_err(Refusal::Input)?;
        }
        self.cat.save(&mut self.snap);
        let mut out = self.last;
        for _ in 0..n_steps {
            if hil {
                self.cat.set_input(contact_force_n, position_m);
            }
            out = self.cat.step();
        }
        let deviation_m = out.wire_height_m - self.cat.static_height_at(out.position_m);
        let sound = self.cat.state_is_sound()
            && [
                out.wire_height_m,
                out.wire_velocity_m_s,
                out.contact_force_n,
                out.lateral_m,
                deviation_m,
            ]
            .iter()
            .all(|v| v.is_finite())
            && deviation_m.abs() <= MAX_WIRE_DEVIATION_M;
        if !sound {
            self.cat.restore(&self.snap);
            return Err(Refusal::RolledBack {
                deviation_m: if deviation_m.is_finite() {
                    deviation_m
                } else {
                    f64::NAN
                },
            });
        }
        if hil {
            self.accepted = true;
        }
        self.steps += n_steps;
        self.last = out;
        Ok(out)
    }

    /// The last step's output (before any step: the static wire at the start position).
    pub fn output(&self) -> RealtimeOutput {
        self.last
    }

    /// Steps taken (rolled-back and refused steps do not count).
    pub fn steps(&self) -> u64 {
        self.steps
    }

    /// The fixed time step, s.
    pub fn dt_s(&self) -> f64 {
        self.cat.dt_s()
    }

    /// The window length, m.
    pub fn window_m(&self) -> f64 {
        self.cat.window_m()
    }

    /// Modes per wire in the window.
    pub fn n_modes(&self) -> usize {
        self.cat.n_modes()
    }

    /// Window moves so far.
    pub fn moves(&self) -> usize {
        self.cat.moves()
    }

    /// The case's start: the leading pantograph's track position at t = 0, m.
    pub fn start_position_m(&self) -> f64 {
        self.cat.start_position_m()
    }

    /// The bound on the input contact force, N ([`force_limit_n`]).
    pub fn force_limit_n(&self) -> f64 {
        self.cat.force_limit_n()
    }

    /// The full model's length, m.
    pub fn model_length_m(&self) -> f64 {
        self.cat.model_length_m()
    }

    /// The configuration's fingerprint (in every saved state).
    pub fn fingerprint(&self) -> u64 {
        self.fingerprint
    }

    /// A saved state holding the current one (allocates).
    pub fn state(&self, host: [f64; 4]) -> SessionState {
        SessionState {
            snap: self.cat.snapshot(),
            steps: self.steps,
            last: self.last,
            accepted: self.accepted,
            host,
            fingerprint: self.fingerprint,
        }
    }

    /// Copy the current state into `s` (no allocation when `s` belongs to this session).
    pub fn save_into(&self, s: &mut SessionState, host: [f64; 4]) {
        if s.fingerprint != self.fingerprint {
            *s = self.state(host);
            return;
        }
        self.cat.save(&mut s.snap);
        s.steps = self.steps;
        s.last = self.last;
        s.accepted = self.accepted;
        s.host = host;
    }

    /// Return to a saved state of this configuration (no allocation); else an error and the
    /// session is unchanged.
    pub fn restore(&mut self, s: &SessionState) -> Result<(), String> {
        if s.fingerprint != self.fingerprint {
            return Err("the state belongs to another configuration (case, window, step, coupling or pcsim version)".into());
        }
        self.cat.restore(&s.snap);
        self.steps = s.steps;
        self.last = s.last;
        self.accepted = s.accepted;
        Ok(())
    }

    /// The state in the one serialised form (see the module's documentation).
    pub fn state_bytes(s: &SessionState) -> Vec<u8> {
        let mut payload = Vec::new();
        s.snap.write_bytes(&mut payload);
        payload.extend_from_slice(&s.steps.to_le_bytes());
        let o = &s.last;
        for x in [
            o.time_s,
            o.position_m,
            o.wire_height_m,
            o.wire_velocity_m_s,
            o.contact_force_n,
            o.lateral_m,
        ]
        .into_iter()
        .chain(s.host)
        {
            payload.extend_from_slice(&x.to_le_bytes());
        }
        payload.push(s.accepted as u8);
        let mut b = Vec::with_capacity(payload.len() + 40);
        b.extend_from_slice(MAGIC);
        b.extend_from_slice(&VERSION.to_le_bytes());
        b.extend_from_slice(&s.fingerprint.to_le_bytes());
        b.extend_from_slice(&(payload.len() as u64).to_le_bytes());
        b.extend_from_slice(&payload);
        let sum = fnv1a64(&b);
        b.extend_from_slice(&sum.to_le_bytes());
        b
    }

    /// The size of [`Self::state_bytes`] for this session, bytes: on a line, the largest over
    /// the window's positions (a buffer of this size holds a state saved anywhere).
    pub fn state_size(&self) -> usize {
        let (now, most) = self.cat.snapshot_len();
        Self::state_bytes(&self.state([0.0; 4])).len() - now + most
    }

    /// A state read back from [`Self::state_bytes`]: refused, with the reason, when it was
    /// written by another format version or for another configuration, or is truncated, damaged
    /// (checksum) or holds non-finite numbers.
    pub fn state_from_bytes(&self, bytes: &[u8]) -> Result<SessionState, String> {
        let bad = |m: &str| format!("state refused: {m}");
        if bytes.len() < 40 {
            return Err(bad("truncated (shorter than its header)"));
        }
        let mut r = ByteReader::new(bytes);
        if r.bytes(8).map_err(|e| bad(&e))? != MAGIC {
            return Err(bad("not a pcsim real-time state"));
        }
        let v = r.u64().map_err(|e| bad(&e))?;
        if v != VERSION {
            return Err(bad(&format!(
                "format version {v}; this pcsim reads version {VERSION}"
            )));
        }
        let fp = r.u64().map_err(|e| bad(&e))?;
        if fp != self.fingerprint {
            return Err(bad(
                "it belongs to another configuration (case, window, step, coupling or pcsim version)",
            ));
        }
        let n = r.u64().map_err(|e| bad(&e))?;
        let have = bytes.len() as u64 - 40;
        if n > have {
            return Err(bad(&format!(
                "truncated: the payload should be {n} bytes, {have} are there"
            )));
        }
        if n < have && bytes.len() > self.state_size() {
            return Err(bad(&format!(
                "the payload is {n} bytes and {} more follow it: more than this session's largest state ({} bytes)",
                have - n,
                self.state_size()
            )));
        }
        // A buffer of the session's largest state size may hold a shorter state (a line's
        // windows differ in size): the state is the header's length, the rest of the buffer is
        // not read.
        let bytes = &bytes[..40 + n as usize];
        let body = bytes.len() - 8;
        let sum = u64::from_le_bytes(bytes[body..].try_into().expect("8 bytes"));
        if fnv1a64(&bytes[..body]) != sum {
            return Err(bad("damaged (its checksum does not match)"));
        }
        let mut r = ByteReader::new(&bytes[32..body]);
        let mut s = self.state([0.0; 4]);
        s.snap = self.cat.snapshot_from_bytes(&mut r).map_err(|e| bad(&e))?;
        s.steps = r.u64().map_err(|e| bad(&e))?;
        let mut f = [0.0; 10];
        for x in f.iter_mut() {
            *x = r.f64().map_err(|e| bad(&e))?;
        }
        if f.iter().any(|x| !x.is_finite()) {
            return Err(bad("it holds non-finite numbers"));
        }
        s.last = RealtimeOutput {
            time_s: f[0],
            position_m: f[1],
            wire_height_m: f[2],
            wire_velocity_m_s: f[3],
            contact_force_n: f[4],
            lateral_m: f[5],
        };
        s.host = [f[6], f[7], f[8], f[9]];
        s.accepted = r.bytes(1).map_err(|e| bad(&e))?[0] != 0;
        if !r.is_done() {
            return Err(bad("trailing bytes"));
        }
        Ok(s)
    }
}
