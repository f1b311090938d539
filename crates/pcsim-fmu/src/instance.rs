//! The FMU instance, independent of the FMI version: phases, the standard's rules for setting and
//! getting values, and the `do_step` contract.

use std::path::{Path, PathBuf};

use pcsim_core::input::case::Case;
use pcsim_core::presets;
use pcsim_core::session::{Coupling, RealtimeOutput, RealtimeSession, SessionState};

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

/// Whether the `case` parameter names a case file rather than a preset.
fn is_case_file(v: &str) -> bool {
    Path::new(v).extension().is_some_and(|e| e == "toml")
}

fn err<T>(msg: impl Into<String>) -> Res<T> {
    Err((Status::Error, msg.into()))
}

/// A saved FMU state (`fmi2GetFMUstate`, `fmi3GetFMUState`): the core session's state, in its one
/// versioned form, with the FMU's own values (start time, the two inputs, terminated) in its host
/// slots, so that a restored instance continues bit for bit.
pub type FmuState = SessionState;

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
    rt: Option<RealtimeSession>,
    start_time: f64,
    /// Track position of the case's start, m (`position_from_start` is from it).
    x_start: f64,
    /// The FMU's unpacked `resources/` folder, where the host gave it.
    resources: Option<PathBuf>,
}

/// The folder of a resource location as the host gives it: FMI 2.0's URI (`file:///…`,
/// `file://localhost/…`, `file:/…`, percent-encoded) or FMI 3.0's path. `None` for anything
/// else, or a folder that does not exist.
pub fn resource_dir(location: &str) -> Option<PathBuf> {
    let path = match location.strip_prefix("file:") {
        Some(rest) => {
            let rest = rest
                .strip_prefix("//localhost")
                .or_else(|| rest.strip_prefix("//"))
                .unwrap_or(rest);
            percent_decode(rest)?
        }
        None => location.to_string(),
    };
    let dir = PathBuf::from(path);
    dir.is_dir().then_some(dir)
}

/// `%XX` escapes decoded (a malformed escape or a result that is not UTF-8: `None`).
fn percent_decode(s: &str) -> Option<String> {
    let b = s.as_bytes();
    let mut out = Vec::with_capacity(b.len());
    let mut i = 0;
    while i < b.len() {
        if b[i] == b'%' {
            let hex = std::str::from_utf8(b.get(i + 1..i + 3)?).ok()?;
            out.push(u8::from_str_radix(hex, 16).ok()?);
            i += 3;
        } else {
            out.push(b[i]);
            i += 1;
        }
    }
    String::from_utf8(out).ok()
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
            start_time: 0.0,
            x_start: 0.0,
            resources: None,
        }
    }

    /// The instance of an FMU unpacked at `resources` (the host's resource folder): with a
    /// bundled case ([`vars::BUNDLED_CASE`]) there, that case is the `case` parameter's value,
    /// as the model description's start value says.
    pub fn with_resources(mut self, resources: Option<PathBuf>) -> Self {
        if let Some(dir) = &resources {
            if dir.join(vars::BUNDLED_CASE).is_file() {
                self.case = vars::BUNDLED_CASE.to_string();
            }
        }
        self.resources = resources;
        self
    }

    /// The case the `case` parameter names: a preset, or a case file (in the resources first).
    fn load_case(&self) -> Res<Case> {
        if !is_case_file(&self.case) {
            return presets::load(&self.case)
                .map(|(c, _)| c)
                .map_err(|e| (Status::Error, format!("parameter `case`: {e}")));
        }
        let path = match &self.resources {
            Some(dir) if dir.join(&self.case).is_file() => dir.join(&self.case),
            _ => PathBuf::from(&self.case),
        };
        let text = std::fs::File::open(&path).and_then(|f| {
            pcsim_core::input::read_text_limited(f, pcsim_core::input::MAX_INPUT_BYTES)
        });
        pcsim_core::input::case_from_file(&path.display().to_string(), text).map_err(|e| {
            (
                Status::Error,
                format!("parameter `case` = {:?}: {e}", self.case),
            )
        })
    }

    fn session(&self) -> Res<&RealtimeSession> {
        self.usable()?;
        self.rt.as_ref().ok_or((
            Status::Error,
            "the FMU state exists only after initialisation".to_string(),
        ))
    }

    /// The FMU's own values kept in the state's host slots.
    fn host(&self) -> [f64; 4] {
        [
            self.start_time,
            self.force_in,
            self.position_in,
            (self.phase == Phase::Terminated) as u8 as f64,
        ]
    }

    /// The state, for `fmi2GetFMUstate` / `fmi3GetFMUState` (after initialisation).
    pub fn get_state(&self) -> Res<FmuState> {
        Ok(self.session()?.state(self.host()))
    }

    /// Copy the state into `s` without allocating (a `fmi*GetFMUState` on an existing state).
    pub fn get_state_into(&self, s: &mut FmuState) -> Res {
        self.session()?.save_into(s, self.host());
        Ok(())
    }

    /// Return to a saved state of this configuration.
    pub fn set_state(&mut self, s: &FmuState) -> Res {
        self.usable()?;
        let rt = self.rt.as_mut().ok_or((
            Status::Error,
            "set the FMU state after initialisation".to_string(),
        ))?;
        rt.restore(s).map_err(|e| (Status::Error, e))?;
        let [start, force, position, terminated] = s.host;
        self.start_time = start;
        self.force_in = force;
        self.position_in = position;
        self.phase = if terminated != 0.0 {
            Phase::Terminated
        } else {
            Phase::Stepping
        };
        Ok(())
    }

    /// The serialised state: the core session's one versioned form.
    pub fn serialize_state(s: &FmuState) -> Vec<u8> {
        RealtimeSession::state_bytes(s)
    }

    /// A state read back from [`Self::serialize_state`]'s bytes: refused with an error when it
    /// was written by another format version, for another configuration, or is damaged.
    pub fn deserialize_state(&self, bytes: &[u8]) -> Res<FmuState> {
        let rt = self.session().map_err(|_| {
            (
                Status::Error,
                "de-serialise an FMU state after initialisation (the model must exist)".to_string(),
            )
        })?;
        rt.state_from_bytes(bytes)
            .map_err(|m| (Status::Error, format!("serialised FMU {m}")))
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
        self.start_time + self.rt.as_ref().map_or(0, |r| r.steps()) as f64 * self.step_s
    }

    /// The last output (the static wire before the first step).
    fn out(&self) -> RealtimeOutput {
        self.rt
            .as_ref()
            .map_or_else(RealtimeOutput::default, |r| r.output())
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
        let mut case = self.load_case()?;
        case.run.dt_s = self.step_s;
        if !self.irregularity_file.is_empty() {
            let text = std::fs::File::open(&self.irregularity_file)
                .and_then(|f| {
                    pcsim_core::input::read_text_limited(f, pcsim_core::input::MAX_INPUT_BYTES)
                })
                .map_err(|e| {
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
        let mut rt = RealtimeSession::new(&case, self.window_m, coupling)
            .map_err(|e| (Status::Error, format!("cannot build the model: {e}")))?;
        self.x_start = rt.start_position_m();
        rt.set_initial_input(self.force_in, self.x_start + self.position_in)
            .map_err(|e| {
                (
                    Status::Error,
                    format!(
                        "initial {e} (position_from_start = {} m from the case's start)",
                        self.position_in
                    ),
                )
            })?;
        self.rt = Some(rt);
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
        let resources = self.resources.take();
        *self = Instance::new(&name).with_resources(resources);
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
            // The step contract's reason code (`not_finite`), as the other front ends report it.
            return err(format!(
                "input refused (not_finite): `{}` = {v} is not a finite number",
                var.name
            ));
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
            vars::VR_WIRE_HEIGHT => self.out().wire_height_m,
            vars::VR_WIRE_VELOCITY => self.out().wire_velocity_m_s,
            vars::VR_PANTOGRAPH_CONTACT_FORCE => self.out().contact_force_n,
            vars::VR_CONTACT_LATERAL => self.out().lateral_m,
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
        if !is_case_file(v) {
            presets::find(v).map_err(|e| {
                (
                    Status::Error,
                    format!("`case` = {v:?}: {e} (or give a case file, .toml)"),
                )
            })?;
        }
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
    /// The step contract is the core session's (`pcsim_core::session`): Discard (logged with the
    /// reason's code, the FMU unchanged) when the HIL input is refused (not finite, the force
    /// beyond the case's bound, the position outside the model or the window, or faster than the
    /// plausible speed), or when the step gave an unsound state and was rolled back.
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
        let x = self.x_start + self.position_in;
        let Some(rt) = self.rt.as_mut() else {
            return Err((Status::Fatal, "model missing after initialisation".into()));
        };
        match rt.advance(self.force_in, x, n as u64, h) {
            Ok(_) => Ok(Status::Ok),
            Err(e) => Err((
                Status::Discard,
                format!(
                    "step from t = {now} s: {e} (position_from_start = {} m from the case's start)",
                    self.position_in
                ),
            )),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The host's resource location, as FMI 2.0's URI (with and without a host, percent
    /// escapes) or FMI 3.0's path; anything else, or a missing folder, is no folder.
    #[test]
    fn resource_locations_of_both_standards_name_the_folder() {
        let d = std::env::temp_dir().join(format!("pcsim fmu res {}", std::process::id()));
        std::fs::create_dir_all(&d).unwrap();
        let p = d.display().to_string();
        let esc = p.replace(' ', "%20");
        for loc in [
            format!("file://{esc}"),
            format!("file://localhost{esc}"),
            format!("file:{esc}"),
            format!("{p}/"),
        ] {
            assert_eq!(resource_dir(&loc).as_deref(), Some(d.as_path()), "{loc}");
        }
        assert_eq!(resource_dir("file:///no/such/folder"), None);
        assert_eq!(resource_dir("file:///bad%zz"), None);
        // A bundled case becomes the `case` parameter's value; without one, the default.
        assert_eq!(
            Instance::new("a").with_resources(Some(d.clone())).case,
            vars::DEFAULT_CASE
        );
        std::fs::write(d.join(vars::BUNDLED_CASE), "not read yet").unwrap();
        let i = Instance::new("a").with_resources(Some(d.clone()));
        assert_eq!(i.case, vars::BUNDLED_CASE);
        // Read at initialisation: a bad bundled case is an error naming the parameter.
        let e = i.load_case().unwrap_err();
        assert!(e.1.contains("parameter `case`"), "{}", e.1);
        let _ = std::fs::remove_dir_all(&d);
    }
}
