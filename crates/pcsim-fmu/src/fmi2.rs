//! The FMI 2.0 co-simulation C ABI: 34 entry points over [`crate::instance::Instance`].
//!
//! Every entry point runs under `catch_unwind` (a panic gives `fmi2Fatal` and marks the instance
//! failed; the host survives). Component pointers are checked against a registry of live
//! instances, so NULL, foreign, freed and doubly freed pointers give `fmi2Error` (a repeated free
//! is a no-op). Strings returned to the host stay valid until the next call on that instance.

#![allow(
    non_snake_case,
    clippy::missing_safety_doc,
    clippy::not_unsafe_ptr_arg_deref
)]

use std::ffi::{c_char, c_int, c_uint, c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Mutex;

use crate::instance::{Instance, Phase, Res, Status};

type Fmi2Status = c_int;
type Fmi2Component = *mut c_void;
type Fmi2ValueReference = c_uint;
type Fmi2String = *const c_char;
type Fmi2Boolean = c_int;
type Logger =
    unsafe extern "C" fn(*mut c_void, Fmi2String, Fmi2Status, Fmi2String, Fmi2String, ...);

/// `fmi2CallbackFunctions`.
#[repr(C)]
pub struct CallbackFunctions {
    logger: Option<Logger>,
    allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    step_finished: Option<unsafe extern "C" fn(*mut c_void, Fmi2Status)>,
    component_environment: *mut c_void,
}

#[cfg(test)]
const OK: Fmi2Status = 0;
const ERROR: Fmi2Status = 3;
const FATAL: Fmi2Status = 4;

/// The FMI wrapper around an instance: the host's logger and the string buffers.
struct Component {
    inst: Instance,
    logger: Option<Logger>,
    env: usize,
    name_c: CString,
    strings: Vec<CString>,
    string_ptrs: Vec<*const c_char>,
}

/// Addresses of live components.
static LIVE: Mutex<Vec<usize>> = Mutex::new(Vec::new());

fn live() -> std::sync::MutexGuard<'static, Vec<usize>> {
    LIVE.lock().unwrap_or_else(|e| e.into_inner())
}

fn is_live(c: Fmi2Component) -> bool {
    !c.is_null() && live().contains(&(c as usize))
}

impl Component {
    fn log(&self, status: Status, msg: &str) {
        if let Some(logger) = self.logger {
            let category: &CStr = if status >= Status::Error {
                c"logStatusError"
            } else {
                c"logAll"
            };
            let msg = CString::new(msg.replace('\0', " ")).unwrap_or_default();
            // The message goes through "%s" so that '%' in it is never a format directive.
            unsafe {
                logger(
                    self.env as *mut c_void,
                    self.name_c.as_ptr(),
                    status as c_int,
                    category.as_ptr(),
                    c"%s".as_ptr(),
                    msg.as_ptr(),
                )
            };
        }
    }
}

/// Run `f` on the live component `c` under `catch_unwind`.
fn with(c: Fmi2Component, f: impl FnOnce(&mut Component) -> Res<Status>) -> Fmi2Status {
    if !is_live(c) {
        return ERROR;
    }
    let comp = c as *mut Component;
    match catch_unwind(AssertUnwindSafe(|| f(unsafe { &mut *comp }))) {
        Ok(Ok(s)) => s as c_int,
        Ok(Err((s, msg))) => {
            let comp = unsafe { &mut *comp };
            comp.log(s, &msg);
            if s == Status::Fatal {
                comp.inst.fail();
            }
            s as c_int
        }
        Err(_) => {
            let comp = unsafe { &mut *comp };
            comp.inst.fail();
            comp.log(
                Status::Fatal,
                "internal error (panic caught); the instance is unusable",
            );
            FATAL
        }
    }
}

fn ok(r: Res) -> Res<Status> {
    r.map(|_| Status::Ok)
}

/// Slices from host arrays; NULL with n > 0 is an error.
unsafe fn slice<'a, T>(p: *const T, n: usize) -> Res<&'a [T]> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err((Status::Error, "NULL array".into()));
    }
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Res<&'a mut [T]> {
    if n == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err((Status::Error, "NULL array".into()));
    }
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

#[no_mangle]
pub extern "C" fn fmi2GetTypesPlatform() -> Fmi2String {
    c"default".as_ptr()
}

#[no_mangle]
pub extern "C" fn fmi2GetVersion() -> Fmi2String {
    c"2.0".as_ptr()
}

#[no_mangle]
pub extern "C" fn fmi2SetDebugLogging(
    c: Fmi2Component,
    _on: Fmi2Boolean,
    n: usize,
    cats: *const Fmi2String,
) -> Fmi2Status {
    with(c, |_| {
        unsafe { slice(cats, n) }?;
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub extern "C" fn fmi2Instantiate(
    name: Fmi2String,
    fmu_type: c_int,
    guid: Fmi2String,
    _resources: Fmi2String,
    functions: *const CallbackFunctions,
    _visible: Fmi2Boolean,
    _logging_on: Fmi2Boolean,
) -> Fmi2Component {
    let r = catch_unwind(|| {
        if name.is_null() || guid.is_null() || fmu_type != 1 {
            return std::ptr::null_mut();
        }
        let name = unsafe { CStr::from_ptr(name) }
            .to_string_lossy()
            .into_owned();
        let guid = unsafe { CStr::from_ptr(guid) }
            .to_string_lossy()
            .into_owned();
        if guid != crate::GUID {
            return std::ptr::null_mut();
        }
        let (logger, env) = if functions.is_null() {
            (None, 0)
        } else {
            unsafe {
                (
                    (*functions).logger,
                    (*functions).component_environment as usize,
                )
            }
        };
        let comp = Box::new(Component {
            name_c: CString::new(name.replace('\0', " ")).unwrap_or_default(),
            inst: Instance::new(&name),
            logger,
            env,
            strings: Vec::new(),
            string_ptrs: Vec::new(),
        });
        let p = Box::into_raw(comp);
        live().push(p as usize);
        p as Fmi2Component
    });
    r.unwrap_or(std::ptr::null_mut())
}

#[no_mangle]
pub extern "C" fn fmi2FreeInstance(c: Fmi2Component) {
    let _ = catch_unwind(|| {
        let mut l = live();
        if let Some(i) = l.iter().position(|&p| p == c as usize) {
            l.swap_remove(i);
            drop(l);
            drop(unsafe { Box::from_raw(c as *mut Component) });
        }
    });
}

#[no_mangle]
pub extern "C" fn fmi2SetupExperiment(
    c: Fmi2Component,
    _tol_defined: Fmi2Boolean,
    _tol: f64,
    start: f64,
    _stop_defined: Fmi2Boolean,
    _stop: f64,
) -> Fmi2Status {
    with(c, |k| ok(k.inst.setup_experiment(start)))
}

#[no_mangle]
pub extern "C" fn fmi2EnterInitializationMode(c: Fmi2Component) -> Fmi2Status {
    with(c, |k| ok(k.inst.enter_initialization()))
}

#[no_mangle]
pub extern "C" fn fmi2ExitInitializationMode(c: Fmi2Component) -> Fmi2Status {
    with(c, |k| ok(k.inst.exit_initialization()))
}

#[no_mangle]
pub extern "C" fn fmi2Terminate(c: Fmi2Component) -> Fmi2Status {
    with(c, |k| ok(k.inst.terminate()))
}

#[no_mangle]
pub extern "C" fn fmi2Reset(c: Fmi2Component) -> Fmi2Status {
    with(c, |k| ok(k.inst.reset()))
}

#[no_mangle]
pub extern "C" fn fmi2GetReal(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *mut f64,
) -> Fmi2Status {
    with(c, |k| {
        let (vr, value) = unsafe { (slice(vr, n)?, slice_mut(value, n)?) };
        for (v, out) in vr.iter().zip(value.iter_mut()) {
            *out = k.inst.get_real(*v)?;
        }
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub extern "C" fn fmi2GetInteger(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    _value: *mut c_int,
) -> Fmi2Status {
    with(c, |_| {
        let vr = unsafe { slice(vr, n)? };
        match vr.first() {
            None => Ok(Status::Ok),
            Some(v) => Err((
                Status::Error,
                format!("no Integer variable with value reference {v}"),
            )),
        }
    })
}

#[no_mangle]
pub extern "C" fn fmi2GetBoolean(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *mut Fmi2Boolean,
) -> Fmi2Status {
    with(c, |k| {
        let (vr, value) = unsafe { (slice(vr, n)?, slice_mut(value, n)?) };
        for (v, out) in vr.iter().zip(value.iter_mut()) {
            *out = k.inst.get_boolean(*v)? as c_int;
        }
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub extern "C" fn fmi2GetString(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *mut Fmi2String,
) -> Fmi2Status {
    with(c, |k| {
        let (vr, value) = unsafe { (slice(vr, n)?, slice_mut(value, n)?) };
        // Owned by the component until its next call: never dangling.
        k.strings.clear();
        for v in vr {
            let s = k.inst.get_string(*v)?;
            k.strings.push(CString::new(s).unwrap_or_default());
        }
        k.string_ptrs.clear();
        k.string_ptrs.extend(k.strings.iter().map(|s| s.as_ptr()));
        value.copy_from_slice(&k.string_ptrs);
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub extern "C" fn fmi2SetReal(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *const f64,
) -> Fmi2Status {
    with(c, |k| {
        let (vr, value) = unsafe { (slice(vr, n)?, slice(value, n)?) };
        for (v, x) in vr.iter().zip(value) {
            if *v == TEST_PANIC_VR && std::env::var_os("PCSIM_FMU_TEST_PANIC").is_some() {
                panic!("test hook: deliberate panic");
            }
            k.inst.set_real(*v, *x)?;
        }
        Ok(Status::Ok)
    })
}

/// A value reference that panics inside `fmi2SetReal` when the environment variable
/// `PCSIM_FMU_TEST_PANIC` is set: the misuse suite's way to check that a panic gives Fatal and
/// the host survives. Not in the model description.
pub const TEST_PANIC_VR: u32 = 0xFFFF_FFF0;

#[no_mangle]
pub extern "C" fn fmi2SetInteger(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    _value: *const c_int,
) -> Fmi2Status {
    with(c, |_| {
        let vr = unsafe { slice(vr, n)? };
        match vr.first() {
            None => Ok(Status::Ok),
            Some(v) => Err((
                Status::Error,
                format!("no Integer variable with value reference {v}"),
            )),
        }
    })
}

#[no_mangle]
pub extern "C" fn fmi2SetBoolean(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *const Fmi2Boolean,
) -> Fmi2Status {
    with(c, |k| {
        let (vr, value) = unsafe { (slice(vr, n)?, slice(value, n)?) };
        for (v, x) in vr.iter().zip(value) {
            k.inst.set_boolean(*v, *x != 0)?;
        }
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub extern "C" fn fmi2SetString(
    c: Fmi2Component,
    vr: *const Fmi2ValueReference,
    n: usize,
    value: *const Fmi2String,
) -> Fmi2Status {
    with(c, |k| {
        let (vr, value) = unsafe { (slice(vr, n)?, slice(value, n)?) };
        for (v, x) in vr.iter().zip(value) {
            if x.is_null() {
                return Err((Status::Error, "NULL string".into()));
            }
            let s = unsafe { CStr::from_ptr(*x) }.to_string_lossy().into_owned();
            k.inst.set_string(*v, &s)?;
        }
        Ok(Status::Ok)
    })
}

fn unsupported(c: Fmi2Component, what: &str) -> Fmi2Status {
    with(c, |_| {
        Err((
            Status::Error,
            format!(
                "{what} is not supported by this FMU (see modelDescription.xml capability flags)"
            ),
        ))
    })
}

#[no_mangle]
pub extern "C" fn fmi2GetFMUstate(c: Fmi2Component, _s: *mut *mut c_void) -> Fmi2Status {
    unsupported(c, "fmi2GetFMUstate")
}

#[no_mangle]
pub extern "C" fn fmi2SetFMUstate(c: Fmi2Component, _s: *mut c_void) -> Fmi2Status {
    unsupported(c, "fmi2SetFMUstate")
}

#[no_mangle]
pub extern "C" fn fmi2FreeFMUstate(c: Fmi2Component, _s: *mut *mut c_void) -> Fmi2Status {
    unsupported(c, "fmi2FreeFMUstate")
}

#[no_mangle]
pub extern "C" fn fmi2SerializedFMUstateSize(
    c: Fmi2Component,
    _s: *mut c_void,
    _size: *mut usize,
) -> Fmi2Status {
    unsupported(c, "fmi2SerializedFMUstateSize")
}

#[no_mangle]
pub extern "C" fn fmi2SerializeFMUstate(
    c: Fmi2Component,
    _s: *mut c_void,
    _b: *mut u8,
    _n: usize,
) -> Fmi2Status {
    unsupported(c, "fmi2SerializeFMUstate")
}

#[no_mangle]
pub extern "C" fn fmi2DeSerializeFMUstate(
    c: Fmi2Component,
    _b: *const u8,
    _n: usize,
    _s: *mut *mut c_void,
) -> Fmi2Status {
    unsupported(c, "fmi2DeSerializeFMUstate")
}

#[no_mangle]
pub extern "C" fn fmi2GetDirectionalDerivative(
    c: Fmi2Component,
    _vu: *const Fmi2ValueReference,
    _nu: usize,
    _vk: *const Fmi2ValueReference,
    _nk: usize,
    _dk: *const f64,
    _du: *mut f64,
) -> Fmi2Status {
    unsupported(c, "fmi2GetDirectionalDerivative")
}

#[no_mangle]
pub extern "C" fn fmi2SetRealInputDerivatives(
    c: Fmi2Component,
    _vr: *const Fmi2ValueReference,
    _n: usize,
    _o: *const c_int,
    _v: *const f64,
) -> Fmi2Status {
    unsupported(c, "fmi2SetRealInputDerivatives")
}

#[no_mangle]
pub extern "C" fn fmi2GetRealOutputDerivatives(
    c: Fmi2Component,
    _vr: *const Fmi2ValueReference,
    _n: usize,
    _o: *const c_int,
    _v: *mut f64,
) -> Fmi2Status {
    unsupported(c, "fmi2GetRealOutputDerivatives")
}

#[no_mangle]
pub extern "C" fn fmi2DoStep(
    c: Fmi2Component,
    t: f64,
    h: f64,
    _no_prior: Fmi2Boolean,
) -> Fmi2Status {
    with(c, |k| k.inst.do_step(t, h))
}

#[no_mangle]
pub extern "C" fn fmi2CancelStep(c: Fmi2Component) -> Fmi2Status {
    unsupported(c, "fmi2CancelStep (steps are synchronous)")
}

#[no_mangle]
pub extern "C" fn fmi2GetStatus(c: Fmi2Component, _kind: c_int, _v: *mut Fmi2Status) -> Fmi2Status {
    unsupported(c, "fmi2GetStatus (steps are synchronous)")
}

#[no_mangle]
pub extern "C" fn fmi2GetRealStatus(c: Fmi2Component, kind: c_int, v: *mut f64) -> Fmi2Status {
    with(c, |k| {
        // fmi2LastSuccessfulTime = 2
        if kind != 2 || v.is_null() {
            return Err((
                Status::Error,
                format!("fmi2GetRealStatus: status kind {kind} not available"),
            ));
        }
        if k.inst.phase() == Phase::Instantiated {
            return Err((Status::Error, "no step yet".into()));
        }
        unsafe { *v = k.inst.time() };
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub extern "C" fn fmi2GetIntegerStatus(
    c: Fmi2Component,
    _kind: c_int,
    _v: *mut c_int,
) -> Fmi2Status {
    unsupported(c, "fmi2GetIntegerStatus")
}

#[no_mangle]
pub extern "C" fn fmi2GetBooleanStatus(
    c: Fmi2Component,
    kind: c_int,
    v: *mut Fmi2Boolean,
) -> Fmi2Status {
    with(c, |k| {
        // fmi2Terminated = 3
        if kind != 3 || v.is_null() {
            return Err((
                Status::Error,
                format!("fmi2GetBooleanStatus: status kind {kind} not available"),
            ));
        }
        unsafe { *v = (k.inst.phase() == Phase::Terminated) as c_int };
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub extern "C" fn fmi2GetStringStatus(
    c: Fmi2Component,
    _kind: c_int,
    _v: *mut Fmi2String,
) -> Fmi2Status {
    unsupported(c, "fmi2GetStringStatus")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn registry_refuses_null_foreign_and_freed_pointers() {
        let name = CString::new("t").unwrap();
        let guid = CString::new(crate::GUID).unwrap();
        let c = fmi2Instantiate(
            name.as_ptr(),
            1,
            guid.as_ptr(),
            std::ptr::null(),
            std::ptr::null(),
            0,
            0,
        );
        assert!(!c.is_null());
        assert_eq!(fmi2EnterInitializationMode(std::ptr::null_mut()), ERROR);
        let mut foreign = 0u64;
        assert_eq!(
            fmi2EnterInitializationMode(&mut foreign as *mut u64 as *mut c_void),
            ERROR
        );
        assert_eq!(fmi2EnterInitializationMode(c), OK);
        fmi2FreeInstance(c);
        fmi2FreeInstance(c); // no-op
        assert_eq!(fmi2ExitInitializationMode(c), ERROR);
        let bad = CString::new("{not-our-guid}").unwrap();
        assert!(fmi2Instantiate(
            name.as_ptr(),
            1,
            bad.as_ptr(),
            std::ptr::null(),
            std::ptr::null(),
            0,
            0
        )
        .is_null());
        assert!(fmi2Instantiate(
            name.as_ptr(),
            0,
            guid.as_ptr(),
            std::ptr::null(),
            std::ptr::null(),
            0,
            0
        )
        .is_null());
    }
}
