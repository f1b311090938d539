//! The FMI 2.0 co-simulation C ABI: 34 entry points over [`crate::instance::Instance`], FMU
//! states (get, set, free, serialise) included.
//!
//! Every entry point runs under `catch_unwind` (a panic gives `fmi2Fatal` and marks the instance
//! failed; the host survives). Component pointers are checked against a registry of live
//! instances, so NULL, foreign, freed and doubly freed pointers give `fmi2Error` (a repeated free
//! is a no-op). Strings returned to the host stay valid until the next call on that instance.

#![allow(non_snake_case, clippy::not_unsafe_ptr_arg_deref)]

use std::ffi::{c_char, c_int, c_uint, c_void};
use std::panic::catch_unwind;

use crate::host::{
    host_str, ok, register, slice, slice_mut, unregister, unsupported, with, Component, Logger,
};
use crate::instance::{Instance, Phase, Status};

type Fmi2Status = c_int;
type Fmi2Component = *mut c_void;
type Fmi2ValueReference = c_uint;
type Fmi2String = *const c_char;
type Fmi2Boolean = c_int;
type Logger2 = crate::host::Logger2;

/// `fmi2CallbackFunctions`.
#[repr(C)]
pub struct CallbackFunctions {
    logger: Option<Logger2>,
    allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    step_finished: Option<unsafe extern "C" fn(*mut c_void, Fmi2Status)>,
    component_environment: *mut c_void,
}

#[cfg(test)]
const OK: Fmi2Status = 0;
#[cfg(test)]
const ERROR: Fmi2Status = crate::host::ERROR;

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
        // SAFETY: the host passes `n` values per array, valid for the call (FMI); NULL is refused.
        unsafe { slice(cats, n) }?;
        Ok(Status::Ok)
    })
}

#[no_mangle]
pub extern "C" fn fmi2Instantiate(
    name: Fmi2String,
    fmu_type: c_int,
    guid: Fmi2String,
    resources: Fmi2String,
    functions: *const CallbackFunctions,
    _visible: Fmi2Boolean,
    _logging_on: Fmi2Boolean,
) -> Fmi2Component {
    let r = catch_unwind(|| {
        if name.is_null() || guid.is_null() || fmu_type != 1 {
            return std::ptr::null_mut();
        }
        // SAFETY: checked non-NULL above; the FMI standard has the host pass NUL-terminated
        // strings valid for the call.
        let Ok(name) = (unsafe { host_str(name) }) else {
            return std::ptr::null_mut();
        };
        // SAFETY: checked non-NULL above; the FMI standard has the host pass NUL-terminated
        // strings valid for the call.
        let Ok(guid) = (unsafe { host_str(guid) }) else {
            return std::ptr::null_mut();
        };
        if guid != crate::GUID {
            return std::ptr::null_mut();
        }
        let (logger, env) = if functions.is_null() {
            (None, 0)
        } else {
            // SAFETY: `functions` is non-NULL (checked) and points to the host's callback struct, valid for the call (FMI 2.0 §2.1.5); two fields are copied out.
            unsafe {
                (
                    (*functions).logger,
                    (*functions).component_environment as usize,
                )
            }
        };
        let logger = match logger {
            Some(l) => Logger::V2(l),
            None => Logger::None,
        };
        // SAFETY: NULL or a NUL-terminated string valid for the call (FMI 2.0 §2.1.5).
        let resources = unsafe { host_str(resources) }
            .ok()
            .and_then(|r| crate::instance::resource_dir(&r));
        let inst = Instance::new(&name).with_resources(resources);
        register(Component::new(inst, &name, logger, env))
    });
    r.unwrap_or(std::ptr::null_mut())
}

#[no_mangle]
pub extern "C" fn fmi2FreeInstance(c: Fmi2Component) {
    let _ = catch_unwind(|| unregister(c));
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

/// The typed get/set shells of FMI 2.0, written once: each takes the component, `n` value
/// references and `n` values, refuses NULL arrays, and hands the slices to its body (`get`: the
/// values writable, `set`: read-only); `none` answers Error for a type this FMU has no variables
/// of, naming the first value reference.
macro_rules! typed_shell {
    (get $name:ident, $t:ty, |$k:ident, $vr:ident, $value:ident| $body:expr) => {
        #[no_mangle]
        pub extern "C" fn $name(
            c: Fmi2Component,
            vr: *const Fmi2ValueReference,
            n: usize,
            value: *mut $t,
        ) -> Fmi2Status {
            with(c, |$k| {
                // SAFETY: the host passes `n` values per array, valid for the call (FMI); NULL is
                // refused.
                let ($vr, $value) = unsafe { (slice(vr, n)?, slice_mut(value, n)?) };
                $body
            })
        }
    };
    (set $name:ident, $t:ty, |$k:ident, $vr:ident, $value:ident| $body:expr) => {
        #[no_mangle]
        pub extern "C" fn $name(
            c: Fmi2Component,
            vr: *const Fmi2ValueReference,
            n: usize,
            value: *const $t,
        ) -> Fmi2Status {
            with(c, |$k| {
                // SAFETY: the host passes `n` values per array, valid for the call (FMI); NULL is
                // refused.
                let ($vr, $value) = unsafe { (slice(vr, n)?, slice(value, n)?) };
                $body
            })
        }
    };
    (none $get:ident, $set:ident, $t:ty, $type_name:literal) => {
        typed_shell!(@none $get, *mut $t, $type_name);
        typed_shell!(@none $set, *const $t, $type_name);
    };
    (@none $name:ident, $ptr:ty, $type_name:literal) => {
        #[no_mangle]
        pub extern "C" fn $name(
            c: Fmi2Component,
            vr: *const Fmi2ValueReference,
            n: usize,
            _value: $ptr,
        ) -> Fmi2Status {
            with(c, |_| {
                // SAFETY: the host passes `n` value references, valid for the call (FMI); NULL is
                // refused.
                let vr = unsafe { slice(vr, n)? };
                match vr.first() {
                    None => Ok(Status::Ok),
                    Some(v) => Err((
                        Status::Error,
                        format!(concat!("no ", $type_name, " variable with value reference {}"), v),
                    )),
                }
            })
        }
    };
}

typed_shell!(get fmi2GetReal, f64, |k, vr, value| {
    for (v, out) in vr.iter().zip(value.iter_mut()) {
        *out = k.inst.get_real(*v)?;
    }
    Ok(Status::Ok)
});
typed_shell!(get fmi2GetBoolean, Fmi2Boolean, |k, vr, value| {
    for (v, out) in vr.iter().zip(value.iter_mut()) {
        *out = k.inst.get_boolean(*v)? as c_int;
    }
    Ok(Status::Ok)
});
typed_shell!(get fmi2GetString, Fmi2String, |k, vr, value| ok(
    k.get_strings(vr, value)
));
typed_shell!(set fmi2SetReal, f64, |k, vr, value| ok(k.set_reals(vr, value)));
typed_shell!(set fmi2SetBoolean, Fmi2Boolean, |k, vr, value| {
    for (v, x) in vr.iter().zip(value) {
        k.inst.set_boolean(*v, *x != 0)?;
    }
    Ok(Status::Ok)
});
typed_shell!(set fmi2SetString, Fmi2String, |k, vr, value| {
    // SAFETY: the host passes each value as a NUL-terminated string valid for the call (FMI
    // 2.0 §2.1.7); NULL is refused by `host_str`.
    ok(unsafe { k.set_strings(vr, value) })
});
typed_shell!(none fmi2GetInteger, fmi2SetInteger, c_int, "Integer");

#[no_mangle]
pub extern "C" fn fmi2GetFMUstate(c: Fmi2Component, s: *mut *mut c_void) -> Fmi2Status {
    with(c, |k| ok(k.get_state(s)))
}

#[no_mangle]
pub extern "C" fn fmi2SetFMUstate(c: Fmi2Component, s: *mut c_void) -> Fmi2Status {
    with(c, |k| ok(k.set_state_from(s)))
}

#[no_mangle]
pub extern "C" fn fmi2FreeFMUstate(c: Fmi2Component, s: *mut *mut c_void) -> Fmi2Status {
    with(c, |k| ok(k.free_state_at(s)))
}

#[no_mangle]
pub extern "C" fn fmi2SerializedFMUstateSize(
    c: Fmi2Component,
    s: *mut c_void,
    size: *mut usize,
) -> Fmi2Status {
    with(c, |k| ok(k.serialized_size_into(s, size)))
}

#[no_mangle]
pub extern "C" fn fmi2SerializeFMUstate(
    c: Fmi2Component,
    s: *mut c_void,
    b: *mut u8,
    n: usize,
) -> Fmi2Status {
    with(c, |k| ok(k.serialize_into(s, b, n)))
}

#[no_mangle]
pub extern "C" fn fmi2DeSerializeFMUstate(
    c: Fmi2Component,
    b: *const u8,
    n: usize,
    s: *mut *mut c_void,
) -> Fmi2Status {
    with(c, |k| ok(k.deserialize_from(b, n, s)))
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
        // SAFETY: `v` is non-NULL (checked above) and points to the host's variable for the result, writable for the call.
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
        // SAFETY: `v` is non-NULL (checked above) and points to the host's variable for the result, writable for the call.
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
    use std::ffi::CString;

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
