//! The FMU instance, independent of the FMI version: phases, the standard's rules for setting and
//! getting values, and the `do_step` contract.

use pcsim_core::presets;
use pcsim_core::solve::realtime::{Coupling, RealtimeCatenary, RealtimeOutput, Snapshot};

use crate::vars::{self, Causality, Kind};

/// Status of a call (FMI numbering).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Status {
    Ok = 0,
    Warning = 1,
    Discard = 2,
    Error = 3,
    Fatal = 4,
}

/// Life-cycle phase.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    Instantiated,
    Initialization,
    Stepping,
    Terminated,
    /// After a fatal error: every call but free is refused.
    Failed,
}

/// A result with the reason for the host's log.
pub type Res<T = ()> = Result<T, (Status, String)>;

fn err<T>(msg: impl Into<String>) -> Res<T> {
    Err((Status::Error, msg.into()))
}

/// A saved FMU state (`fmi2GetFMUstate`, `fmi3GetFMUState`): everything `do_step` reads and
/// writes, so that a restored instance continues bit for bit, and the fingerprint of the
/// configuration it belongs to.
#[derive(Debug, Clone)]
pub struct FmuState {
    snap: Snapshot,
    steps: u64,
    start_time: f64,
    force_in: f64,
    position_in: f64,
    out: RealtimeOutput,
    terminated: bool,
    fingerprint: u64,
}

/// The serialised form: a magic, a version, the configuration's fingerprint, then the state.
const STATE_MAGIC: &[u8; 8] = b"PCSIMFMU";
const STATE_VERSION: u64 = 1;

fn fnv1a64(data: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in data {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    h
}

/// One FMU instance. No global state: two instances share nothing.
pub struct Instance {
    pub name: String,
    phase: Phase,
    case: String,
    irregularity_file: String,
    window_m: f64,
    step_s: f64,
    sil: bool,
    force_in: f64,
    position_in: f64,
    rt: Option<RealtimeCatenary>,
    snap: Option<Snapshot>,
    start_time: f64,
    steps: u64,
    x_start: f64,
    out: RealtimeOutput,
    /// The configuration's fingerprint (set when the model is built).
    fingerprint: u64,
}

impl Instance {
    pub fn new(name: &str) -> Self {
        Self {
            name: name.to_string(),
            phase: Phase::Instantiated,
            case: vars::DEFAULT_CASE.to_string(),
            irregularity_file: String::new(),
            window_m: vars::DEFAULT_WINDOW_M,
            step_s: vars::DEFAULT_STEP_S,
            sil: false,
            force_in: 0.0,
            position_in: 0.0,
            rt: None,
            snap: None,
            start_time: 0.0,
            steps: 0,
            x_start: 0.0,
            out: RealtimeOutput::default(),
            fingerprint: 0,
        }
    }

    /// The state, for `fmi2GetFMUstate` / `fmi3GetFMUState` (after initialisation).
    pub fn get_state(&self) -> Res<FmuState> {
        self.usable()?;
        let rt = self.rt.as_ref().ok_or((
            Status::Error,
            "the FMU state exists only after initialisation".to_string(),
        ))?;
        Ok(FmuState {
            snap: rt.snapshot(),
            steps: self.steps,
            start_time: self.start_time,
            force_in: self.force_in,
            position_in: self.position_in,
            out: self.out,
            terminated: self.phase == Phase::Terminated,
            fingerprint: self.fingerprint,
        })
    }

    /// Copy the state into `s` without allocating (a `fmi*GetFMUState` on an existing state).
    pub fn get_state_into(&self, s: &mut FmuState) -> Res {
        self.usable()?;
        let rt = self.rt.as_ref().ok_or((
            Status::Error,
            "the FMU state exists only after initialisation".to_string(),
        ))?;
        if s.fingerprint != self.fingerprint {
            *s = self.get_state()?;
            return Ok(());
        }
        rt.save(&mut s.snap);
        s.steps = self.steps;
        s.start_time = self.start_time;
        s.force_in = self.force_in;
        s.position_in = self.position_in;
        s.out = self.out;
        s.terminated = self.phase == Phase::Terminated;
        Ok(())
    }

    /// Return to a saved state of this configuration.
    pub fn set_state(&mut self, s: &FmuState) -> Res {
        self.usable()?;
        if s.fingerprint != self.fingerprint {
            return err("the FMU state belongs to another configuration (case, window, step, coupling or pcsim version)");
        }
        let rt = self.rt.as_mut().ok_or((
            Status::Error,
            "set the FMU state after initialisation".to_string(),
        ))?;
        rt.restore(&s.snap);
        self.steps = s.steps;
        self.start_time = s.start_time;
        self.force_in = s.force_in;
        self.position_in = s.position_in;
        self.out = s.out;
        self.phase = if s.terminated {
            Phase::Terminated
        } else {
            Phase::Stepping
        };
        Ok(())
    }

    /// The serialised state: `PCSIMFMU`, the format version, the fingerprint, then the numbers.
    pub fn serialize_state(s: &FmuState) -> Vec<u8> {
        let mut b = Vec::new();
        b.extend_from_slice(STATE_MAGIC);
        b.extend_from_slice(&STATE_VERSION.to_le_bytes());
        b.extend_from_slice(&s.fingerprint.to_le_bytes());
        s.snap.write_bytes(&mut b);
        b.extend_from_slice(&s.steps.to_le_bytes());
        for x in [
            s.start_time,
            s.force_in,
            s.position_in,
            s.out.time_s,
            s.out.position_m,
            s.out.wire_height_m,
            s.out.wire_velocity_m_s,
            s.out.contact_force_n,
            s.out.lateral_m,
        ] {
            b.extend_from_slice(&x.to_le_bytes());
        }
        b.push(s.terminated as u8);
        b
    }

    /// A state read back from [`Self::serialize_state`]'s bytes: refused with an error when it
    /// was written by another format version, for another configuration, or is damaged.
    pub fn deserialize_state(&self, bytes: &[u8]) -> Res<FmuState> {
        use pcsim_core::solve::state::ByteReader;
        self.usable()?;
        let rt = self.rt.as_ref().ok_or((
            Status::Error,
            "de-serialise an FMU state after initialisation (the model must exist)".to_string(),
        ))?;
        let bad = |m: String| (Status::Error, format!("serialised FMU state refused: {m}"));
        let mut r = ByteReader::new(bytes);
        if r.bytes(8).map_err(bad)? != STATE_MAGIC {
            return Err(bad("not a pcsim FMU state".into()));
        }
        let v = r.u64().map_err(bad)?;
        if v != STATE_VERSION {
            return Err(bad(format!(
                "format version {v}, this FMU reads version {STATE_VERSION}"
            )));
        }
        let fp = r.u64().map_err(bad)?;
        if fp != self.fingerprint {
            return Err(bad(
                "it belongs to another configuration (case, window, step, coupling or pcsim version)".into(),
            ));
        }
        let snap = rt.snapshot_from_bytes(&mut r).map_err(bad)?;
        let steps = r.u64().map_err(bad)?;
        let mut f = [0.0; 9];
        for x in f.iter_mut() {
            *x = r.f64().map_err(bad)?;
        }
        let terminated = r.bytes(1).map_err(bad)?[0] != 0;
        if !r.is_done() {
            return Err(bad("trailing bytes".into()));
        }
        Ok(FmuState {
            snap,
            steps,
            start_time: f[0],
            force_in: f[1],
            position_in: f[2],
            out: RealtimeOutput {
                time_s: f[3],
                position_m: f[4],
                wire_height_m: f[5],
                wire_velocity_m_s: f[6],
                contact_force_n: f[7],
                lateral_m: f[8],
            },
            terminated,
            fingerprint: fp,
        })
    }

    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// Mark the instance unusable (after a panic inside it).
    pub fn fail(&mut self) {
        self.phase = Phase::Failed;
    }

    /// Current FMU time, s.
    pub fn time(&self) -> f64 {
        self.start_time + self.steps as f64 * self.step_s
    }

    fn usable(&self) -> Res {
        match self.phase {
            Phase::Failed => err("the instance failed earlier; free it"),
            _ => Ok(()),
        }
    }

    fn var(vr: u32, kind: Kind) -> Res<&'static vars::Var> {
        vars::find(vr, kind).ok_or_else(|| {
            (
                Status::Error,
                format!("no {kind:?} variable with value reference {vr}"),
            )
        })
    }

    fn check_param_settable(&self, name: &str) -> Res {
        match self.phase {
            Phase::Instantiated | Phase::Initialization => Ok(()),
            _ => err(format!(
                "`{name}` is a fixed parameter: it cannot be set after initialisation"
            )),
        }
    }

    pub fn setup_experiment(&mut self, start_time: f64) -> Res {
        self.usable()?;
        if self.phase != Phase::Instantiated {
            return err("fmi2SetupExperiment is allowed only after instantiation");
        }
        if !start_time.is_finite() {
            return err(format!("start time {start_time} is not finite"));
        }
        self.start_time = start_time;
        Ok(())
    }

    pub fn enter_initialization(&mut self) -> Res {
        self.usable()?;
        if self.phase != Phase::Instantiated {
            return err("fmi2EnterInitializationMode is allowed only after instantiation");
        }
        self.phase = Phase::Initialization;
        Ok(())
    }

    /// Build the window model from the parameters.
    pub fn exit_initialization(&mut self) -> Res {
        self.usable()?;
        if self.phase != Phase::Initialization {
            return err("fmi2ExitInitializationMode is allowed only in initialization mode");
        }
        let (mut case, _) = presets::load(&self.case)
            .map_err(|e| (Status::Error, format!("parameter `case`: {e}")))?;
        case.pantographs.truncate(1);
        case.run.dt_s = self.step_s;
        if !self.irregularity_file.is_empty() {
            let text = std::fs::read_to_string(&self.irregularity_file).map_err(|e| {
                (
                    Status::Error,
                    format!(
                        "parameter `irregularity_file` = {:?}: cannot read it: {e}",
                        self.irregularity_file
                    ),
                )
            })?;
            let ir =
                pcsim_core::input::case::IrregularityCase::from_csv(&text, &self.irregularity_file)
                    .map_err(|e| (Status::Error, format!("parameter `irregularity_file`: {e}")))?;
            case.irregularity.push(ir);
        }
        let coupling = if self.sil {
            Coupling::Sil
        } else {
            Coupling::Hil
        };
        let mut rt = RealtimeCatenary::new(&case, self.window_m, coupling)
            .map_err(|e| (Status::Error, format!("cannot build the model: {e}")))?;
        self.fingerprint = fnv1a64(
            format!(
                "{}|{}|{:e}|{:e}|{}|{}",
                env!("CARGO_PKG_VERSION"),
                case.to_toml_string(),
                self.window_m,
                self.step_s,
                self.sil,
                self.case
            )
            .as_bytes(),
        );
        self.x_start = case.run.start_m;
        if !self.sil {
            let x = self.x_start + self.position_in;
            rt.check_input(self.force_in, x, f64::INFINITY)
                .map_err(|e| {
                    (
                        Status::Error,
                        format!(
                            "initial input refused: {e} (pantograph_position = {} m from the case's start)",
                            self.position_in
                        ),
                    )
                })?;
            rt.set_input(self.force_in, x);
        }
        let x = if self.sil {
            rt.sil_position_m()
        } else {
            self.x_start + self.position_in
        };
        self.out = RealtimeOutput {
            time_s: 0.0,
            position_m: x,
            wire_height_m: rt.static_height_at(x),
            wire_velocity_m_s: 0.0,
            contact_force_n: self.force_in,
            lateral_m: rt.static_lateral_at(x),
        };
        self.snap = Some(rt.snapshot());
        self.rt = Some(rt);
        self.steps = 0;
        self.phase = Phase::Stepping;
        Ok(())
    }

    pub fn terminate(&mut self) -> Res {
        self.usable()?;
        match self.phase {
            Phase::Stepping | Phase::Initialization => {
                self.phase = Phase::Terminated;
                Ok(())
            }
            _ => err("fmi2Terminate is allowed only after initialisation"),
        }
    }

    pub fn reset(&mut self) -> Res {
        self.usable()?;
        let name = std::mem::take(&mut self.name);
        *self = Instance::new(&name);
        Ok(())
    }

    pub fn set_real(&mut self, vr: u32, v: f64) -> Res {
        self.usable()?;
        if self.phase == Phase::Terminated {
            return err("cannot set values after fmi2Terminate");
        }
        let var = Self::var(vr, Kind::Real)?;
        match var.causality {
            Causality::Output => {
                return err(format!("`{}` is an output and cannot be set", var.name))
            }
            Causality::Parameter => self.check_param_settable(var.name)?,
            Causality::Input => {}
        }
        if !v.is_finite() {
            return err(format!("`{}` = {v}: not a finite number", var.name));
        }
        match vr {
            vars::VR_CONTACT_FORCE => self.force_in = v,
            vars::VR_PANTOGRAPH_POSITION => self.position_in = v,
            vars::VR_WINDOW_LENGTH => {
                if v <= 0.0 {
                    return err(format!("`window_length` = {v}: must be > 0"));
                }
                self.window_m = v
            }
            vars::VR_STEP_SIZE => {
                if v <= 0.0 || v > 0.01 {
                    return err(format!("`step_size` = {v}: must lie in (0, 0.01] s"));
                }
                self.step_s = v
            }
            _ => return err(format!("value reference {vr} cannot be set")),
        }
        Ok(())
    }

    fn check_readable(&self, var: &vars::Var) -> Res {
        self.usable()?;
        match (self.phase, var.causality) {
            (Phase::Instantiated, _) => err(format!(
                "`{}` cannot be read before initialisation (fmi2EnterInitializationMode)",
                var.name
            )),
            (Phase::Initialization, Causality::Output) => err(format!(
                "output `{}` is calculated at fmi2ExitInitializationMode",
                var.name
            )),
            _ => Ok(()),
        }
    }

    pub fn get_real(&self, vr: u32) -> Res<f64> {
        let var = Self::var(vr, Kind::Real)?;
        self.check_readable(var)?;
        Ok(match vr {
            vars::VR_CONTACT_FORCE => self.force_in,
            vars::VR_PANTOGRAPH_POSITION => self.position_in,
            vars::VR_WIRE_HEIGHT => self.out.wire_height_m,
            vars::VR_WIRE_VELOCITY => self.out.wire_velocity_m_s,
            vars::VR_PANTOGRAPH_CONTACT_FORCE => self.out.contact_force_n,
            vars::VR_CONTACT_LATERAL => self.out.lateral_m,
            vars::VR_WINDOW_LENGTH => self.window_m,
            vars::VR_STEP_SIZE => self.step_s,
            _ => return err(format!("value reference {vr} cannot be read")),
        })
    }

    pub fn set_boolean(&mut self, vr: u32, v: bool) -> Res {
        self.usable()?;
        let var = Self::var(vr, Kind::Boolean)?;
        self.check_param_settable(var.name)?;
        self.sil = v;
        Ok(())
    }

    pub fn get_boolean(&self, vr: u32) -> Res<bool> {
        let var = Self::var(vr, Kind::Boolean)?;
        self.check_readable(var)?;
        Ok(self.sil)
    }

    pub fn set_string(&mut self, vr: u32, v: &str) -> Res {
        self.usable()?;
        let var = Self::var(vr, Kind::String)?;
        self.check_param_settable(var.name)?;
        if vr == vars::VR_IRREGULARITY_FILE {
            self.irregularity_file = v.to_string();
            return Ok(());
        }
        presets::find(v).map_err(|e| (Status::Error, format!("`case` = {v:?}: {e}")))?;
        self.case = v.to_string();
        Ok(())
    }

    pub fn get_string(&self, vr: u32) -> Res<&str> {
        let var = Self::var(vr, Kind::String)?;
        self.check_readable(var)?;
        Ok(if vr == vars::VR_IRREGULARITY_FILE {
            &self.irregularity_file
        } else {
            &self.case
        })
    }

    /// Advance from `t` by `h`: `t` must be the FMU's time, `h` finite, > 0 and a whole number of
    /// internal steps (at most [`vars::MAX_INTERNAL_STEPS`]). Inputs are held over the step.
    ///
    /// Discard (logged, nothing computed, the FMU unchanged) when the HIL position lies outside
    /// the modelled catenary, behind the window, or moved faster than the plausible speed since
    /// the last step; or when the state becomes non-finite or implausible (the wire more than 2 m
    /// from its design height), in which case the step is rolled back.
    pub fn do_step(&mut self, t: f64, h: f64) -> Res<Status> {
        self.usable()?;
        match self.phase {
            Phase::Stepping => {}
            Phase::Terminated => return err("fmi2DoStep after fmi2Terminate"),
            _ => return err("fmi2DoStep before fmi2ExitInitializationMode"),
        }
        let now = self.time();
        if !t.is_finite() || (t - now).abs() > 1e-9 * now.abs().max(1.0) {
            return err(format!(
                "communication point {t} s is not the FMU's time {now} s"
            ));
        }
        if !h.is_finite() || h <= 0.0 {
            return err(format!("communication step {h} s must be finite and > 0"));
        }
        let n = (h / self.step_s).round();
        if n < 1.0 || (n * self.step_s - h).abs() > 1e-9 * h.max(self.step_s) {
            return err(format!(
                "communication step {h} s is not a whole number of internal steps of {} s",
                self.step_s
            ));
        }
        if n as u64 > vars::MAX_INTERNAL_STEPS {
            return err(format!(
                "communication step {h} s needs {n} internal steps; the cap is {}",
                vars::MAX_INTERNAL_STEPS
            ));
        }
        let (rt, snap) = match (&mut self.rt, &mut self.snap) {
            (Some(r), Some(s)) => (r, s),
            _ => return Err((Status::Fatal, "model missing after initialisation".into())),
        };
        let x = self.x_start + self.position_in;
        if !self.sil {
            if let Err(e) = rt.check_input(self.force_in, x, h) {
                return Err((
                    Status::Discard,
                    format!(
                        "input refused at t = {now} s: {e} (pantograph_position = {} m from the case's start); the step was not taken",
                        self.position_in
                    ),
                ));
            }
        }
        rt.save(snap);
        let mut last = self.out;
        for _ in 0..n as u64 {
            rt.set_input(self.force_in, x);
            last = rt.step();
        }
        if !(rt.state_is_sound()
            && last.wire_height_m.is_finite()
            && last.wire_velocity_m_s.is_finite()
            && last.contact_force_n.is_finite())
        {
            rt.restore(snap);
            return Err((
                Status::Discard,
                format!("the state became non-finite or implausible during the step from t = {now} s (the wire more than 2 m from its design height); rolled back"),
            ));
        }
        self.out = last;
        self.steps += n as u64;
        Ok(Status::Ok)
    }
}
