//! The FMI 3.0 co-simulation C ABI over the same [`crate::instance::Instance`] as FMI 2.0: every
//! entry point of `fmi3Functions.h` is exported (a host binds them all by name); those of Model
//! Exchange, Scheduled Execution, clocks, event mode, the integer and binary types and
//! derivatives give `fmi3Error` with the reason logged. Float64, Boolean and String variables,
//! fixed communication steps as whole numbers of internal steps, and FMU states (get, set, free,
//! serialise) are supported. The same registry, `catch_unwind` wrapper and logger as FMI 2.0
//! (`host.rs`).

#![allow(
    non_snake_case,
    clippy::not_unsafe_ptr_arg_deref,
    clippy::too_many_arguments
)]

use std::ffi::{c_char, c_int, c_void};
use std::panic::catch_unwind;

use crate::host::{
    host_str, ok, register, slice, slice_mut, unregister, unsupported, with, Component, Logger,
    Logger3,
};
use crate::instance::{Instance, Res, Status};

type Fmi3Instance = *mut c_void;
type Fmi3Status = c_int;
type Fmi3Vr = u32;
type Fmi3String = *const c_char;
type Fmi3State = *mut c_void;
type IntermediateUpdate = *mut c_void;

/// FMI 3.0 passes the number of value references and of values separately; they must agree
/// (one value per scalar variable here).
fn same_count(nvr: usize, nvalues: usize) -> Res<()> {
    if nvr != nvalues {
        return Err((
            Status::Error,
            format!("{nvr} value references, {nvalues} values"),
        ));
    }
    Ok(())
}

/// A getter's body over the host's arrays: the same count of references and values, neither
/// NULL, then `f` on the instance, the references and the values to fill.
fn getter<T>(
    c: Fmi3Instance,
    (vr, nvr): (*const Fmi3Vr, usize),
    (values, nvalues): (*mut T, usize),
    f: impl FnOnce(&mut Component, &[Fmi3Vr], &mut [T]) -> Res,
) -> Fmi3Status {
    with(c, |k| {
        same_count(nvr, nvalues)?;
        // SAFETY: the host passes `n` values per array, valid for the call (FMI); NULL is refused.
        let (vr, values) = unsafe { (slice(vr, nvr)?, slice_mut(values, nvalues)?) };
        ok(f(k, vr, values))
    })
}

/// A setter's body over the host's arrays: as [`getter`], the values read.
fn setter<T>(
    c: Fmi3Instance,
    (vr, nvr): (*const Fmi3Vr, usize),
    (values, nvalues): (*const T, usize),
    f: impl FnOnce(&mut Component, &[Fmi3Vr], &[T]) -> Res,
) -> Fmi3Status {
    with(c, |k| {
        same_count(nvr, nvalues)?;
        // SAFETY: the host passes `n` values per array, valid for the call (FMI); NULL is refused.
        let (vr, values) = unsafe { (slice(vr, nvr)?, slice(values, nvalues)?) };
        ok(f(k, vr, values))
    })
}

#[no_mangle]
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    c"3.0".as_ptr()
}

#[no_mangle]
pub extern "C" fn fmi3SetDebugLogging(
    c: Fmi3Instance,
    _on: bool,
    _n: usize,
    _categories: *const Fmi3String,
) -> Fmi3Status {
    with(c, |_| Ok(Status::Ok))
}

#[no_mangle]
pub extern "C" fn fmi3InstantiateModelExchange(
    _name: Fmi3String,
    _token: Fmi3String,
    _resources: Fmi3String,
    _visible: bool,
    _logging_on: bool,
    _env: *mut c_void,
    _log: Option<Logger3>,
) -> Fmi3Instance {
    std::ptr::null_mut()
}

#[no_mangle]
pub extern "C" fn fmi3InstantiateCoSimulation(
    name: Fmi3String,
    token: Fmi3String,
    resources: Fmi3String,
    _visible: bool,
    _logging_on: bool,
    event_mode_used: bool,
    _early_return_allowed: bool,
    _required: *const Fmi3Vr,
    _n_required: usize,
    env: *mut c_void,
    log: Option<Logger3>,
    _intermediate: IntermediateUpdate,
) -> Fmi3Instance {
    let r = catch_unwind(|| {
        if name.is_null() || token.is_null() || event_mode_used {
            return std::ptr::null_mut();
        }
        // SAFETY: checked non-NULL above; the FMI standard has the host pass NUL-terminated
        // strings valid for the call.
        let Ok(name) = (unsafe { host_str(name) }) else {
            return std::ptr::null_mut();
        };
        // SAFETY: checked non-NULL above; the FMI standard has the host pass NUL-terminated
        // strings valid for the call.
        let Ok(token) = (unsafe { host_str(token) }) else {
            return std::ptr::null_mut();
        };
        if token != crate::GUID {
            return std::ptr::null_mut();
        }
        let logger = match log {
            Some(l) => Logger::V3(l),
            None => Logger::None,
        };
        // SAFETY: NULL or a NUL-terminated string valid for the call (FMI 3.0: the resource
        // folder's path, or NULL).
        let resources = unsafe { host_str(resources) }
            .ok()
            .and_then(|r| crate::instance::resource_dir(&r));
        register(Component::new(
            Instance::new(&name).with_resources(resources),
            &name,
            logger,
            env as usize,
        ))
    });
    r.unwrap_or(std::ptr::null_mut())
}

#[no_mangle]
pub extern "C" fn fmi3InstantiateScheduledExecution(
    _name: Fmi3String,
    _token: Fmi3String,
    _resources: Fmi3String,
    _visible: bool,
    _logging_on: bool,
    _env: *mut c_void,
    _log: Option<Logger3>,
    _clock_update: *mut c_void,
    _lock: *mut c_void,
    _unlock: *mut c_void,
) -> Fmi3Instance {
    std::ptr::null_mut()
}

#[no_mangle]
pub extern "C" fn fmi3FreeInstance(c: Fmi3Instance) {
    let _ = catch_unwind(|| unregister(c));
}

#[no_mangle]
pub extern "C" fn fmi3EnterInitializationMode(
    c: Fmi3Instance,
    _tol_defined: bool,
    _tol: f64,
    start: f64,
    _stop_defined: bool,
    _stop: f64,
) -> Fmi3Status {
    with(c, |k| {
        k.inst.setup_experiment(start)?;
        ok(k.inst.enter_initialization())
    })
}

#[no_mangle]
pub extern "C" fn fmi3ExitInitializationMode(c: Fmi3Instance) -> Fmi3Status {
    with(c, |k| ok(k.inst.exit_initialization()))
}

#[no_mangle]
pub extern "C" fn fmi3EnterEventMode(c: Fmi3Instance) -> Fmi3Status {
    unsupported(c, "fmi3EnterEventMode (no event mode)")
}

#[no_mangle]
pub extern "C" fn fmi3Terminate(c: Fmi3Instance) -> Fmi3Status {
    with(c, |k| ok(k.inst.terminate()))
}

#[no_mangle]
pub extern "C" fn fmi3Reset(c: Fmi3Instance) -> Fmi3Status {
    with(c, |k| ok(k.inst.reset()))
}

#[no_mangle]
pub extern "C" fn fmi3GetFloat64(
    c: Fmi3Instance,
    vr: *const Fmi3Vr,
    nvr: usize,
    values: *mut f64,
    nvalues: usize,
) -> Fmi3Status {
    getter(c, (vr, nvr), (values, nvalues), |k, vr, values| {
        for (v, out) in vr.iter().zip(values.iter_mut()) {
            *out = if *v == crate::vars::VR_TIME {
                k.inst.time()
            } else {
                k.inst.get_real(*v)?
            };
        }
        Ok(())
    })
}

#[no_mangle]
pub extern "C" fn fmi3SetFloat64(
    c: Fmi3Instance,
    vr: *const Fmi3Vr,
    nvr: usize,
    values: *const f64,
    nvalues: usize,
) -> Fmi3Status {
    setter(c, (vr, nvr), (values, nvalues), |k, vr, values| {
        k.set_reals(vr, values)
    })
}

#[no_mangle]
pub extern "C" fn fmi3GetBoolean(
    c: Fmi3Instance,
    vr: *const Fmi3Vr,
    nvr: usize,
    values: *mut bool,
    nvalues: usize,
) -> Fmi3Status {
    getter(c, (vr, nvr), (values, nvalues), |k, vr, values| {
        for (v, out) in vr.iter().zip(values.iter_mut()) {
            *out = k.inst.get_boolean(*v)?;
        }
        Ok(())
    })
}

#[no_mangle]
pub extern "C" fn fmi3SetBoolean(
    c: Fmi3Instance,
    vr: *const Fmi3Vr,
    nvr: usize,
    values: *const bool,
    nvalues: usize,
) -> Fmi3Status {
    setter(c, (vr, nvr), (values, nvalues), |k, vr, values| {
        for (v, x) in vr.iter().zip(values) {
            k.inst.set_boolean(*v, *x)?;
        }
        Ok(())
    })
}

#[no_mangle]
pub extern "C" fn fmi3GetString(
    c: Fmi3Instance,
    vr: *const Fmi3Vr,
    nvr: usize,
    values: *mut Fmi3String,
    nvalues: usize,
) -> Fmi3Status {
    getter(c, (vr, nvr), (values, nvalues), |k, vr, values| {
        k.get_strings(vr, values)
    })
}

#[no_mangle]
pub extern "C" fn fmi3SetString(
    c: Fmi3Instance,
    vr: *const Fmi3Vr,
    nvr: usize,
    values: *const Fmi3String,
    nvalues: usize,
) -> Fmi3Status {
    setter(c, (vr, nvr), (values, nvalues), |k, vr, values| {
        // SAFETY: each value is a NUL-terminated string valid for the call (FMI 3.0); NULL is
        // refused by `host_str`.
        unsafe { k.set_strings(vr, values) }
    })
}

/// Getters and setters of types this FMU has no variables of: Error, naming the type.
macro_rules! no_type {
    ($get:ident, $set:ident, $t:ty, $name:literal) => {
        #[no_mangle]
        pub extern "C" fn $get(
            c: Fmi3Instance,
            _vr: *const Fmi3Vr,
            _nvr: usize,
            _values: *mut $t,
            _nvalues: usize,
        ) -> Fmi3Status {
            unsupported(c, concat!("variables of type ", $name))
        }
        #[no_mangle]
        pub extern "C" fn $set(
            c: Fmi3Instance,
            _vr: *const Fmi3Vr,
            _nvr: usize,
            _values: *const $t,
            _nvalues: usize,
        ) -> Fmi3Status {
            unsupported(c, concat!("variables of type ", $name))
        }
    };
}

no_type!(fmi3GetFloat32, fmi3SetFloat32, f32, "Float32");
no_type!(fmi3GetInt8, fmi3SetInt8, i8, "Int8");
no_type!(fmi3GetUInt8, fmi3SetUInt8, u8, "UInt8");
no_type!(fmi3GetInt16, fmi3SetInt16, i16, "Int16");
no_type!(fmi3GetUInt16, fmi3SetUInt16, u16, "UInt16");
no_type!(fmi3GetInt32, fmi3SetInt32, i32, "Int32");
no_type!(fmi3GetUInt32, fmi3SetUInt32, u32, "UInt32");
no_type!(fmi3GetInt64, fmi3SetInt64, i64, "Int64");
no_type!(fmi3GetUInt64, fmi3SetUInt64, u64, "UInt64");

#[no_mangle]
pub extern "C" fn fmi3GetBinary(
    c: Fmi3Instance,
    _vr: *const Fmi3Vr,
    _nvr: usize,
    _sizes: *mut usize,
    _values: *mut *const u8,
    _nvalues: usize,
) -> Fmi3Status {
    unsupported(c, "variables of type Binary")
}

#[no_mangle]
pub extern "C" fn fmi3SetBinary(
    c: Fmi3Instance,
    _vr: *const Fmi3Vr,
    _nvr: usize,
    _sizes: *const usize,
    _values: *const *const u8,
    _nvalues: usize,
) -> Fmi3Status {
    unsupported(c, "variables of type Binary")
}

#[no_mangle]
pub extern "C" fn fmi3GetClock(
    c: Fmi3Instance,
    _vr: *const Fmi3Vr,
    _nvr: usize,
    _values: *mut bool,
) -> Fmi3Status {
    unsupported(c, "clocks")
}

#[no_mangle]
pub extern "C" fn fmi3SetClock(
    c: Fmi3Instance,
    _vr: *const Fmi3Vr,
    _nvr: usize,
    _values: *const bool,
) -> Fmi3Status {
    unsupported(c, "clocks")
}

#[no_mangle]
pub extern "C" fn fmi3GetNumberOfVariableDependencies(
    c: Fmi3Instance,
    _vr: Fmi3Vr,
    _n: *mut usize,
) -> Fmi3Status {
    unsupported(c, "fmi3GetNumberOfVariableDependencies")
}

#[no_mangle]
pub extern "C" fn fmi3GetVariableDependencies(
    c: Fmi3Instance,
    _dependent: Fmi3Vr,
    _element_dep: *mut usize,
    _independents: *mut Fmi3Vr,
    _element_ind: *mut usize,
    _kinds: *mut c_int,
    _n: usize,
) -> Fmi3Status {
    unsupported(c, "fmi3GetVariableDependencies")
}

#[no_mangle]
pub extern "C" fn fmi3GetFMUState(c: Fmi3Instance, s: *mut Fmi3State) -> Fmi3Status {
    with(c, |k| ok(k.get_state(s)))
}

#[no_mangle]
pub extern "C" fn fmi3SetFMUState(c: Fmi3Instance, s: Fmi3State) -> Fmi3Status {
    with(c, |k| ok(k.set_state_from(s)))
}

#[no_mangle]
pub extern "C" fn fmi3FreeFMUState(c: Fmi3Instance, s: *mut Fmi3State) -> Fmi3Status {
    with(c, |k| ok(k.free_state_at(s)))
}

#[no_mangle]
pub extern "C" fn fmi3SerializedFMUStateSize(
    c: Fmi3Instance,
    s: Fmi3State,
    size: *mut usize,
) -> Fmi3Status {
    with(c, |k| ok(k.serialized_size_into(s, size)))
}

#[no_mangle]
pub extern "C" fn fmi3SerializeFMUState(
    c: Fmi3Instance,
    s: Fmi3State,
    b: *mut u8,
    n: usize,
) -> Fmi3Status {
    with(c, |k| ok(k.serialize_into(s, b, n)))
}

#[no_mangle]
pub extern "C" fn fmi3DeserializeFMUState(
    c: Fmi3Instance,
    b: *const u8,
    n: usize,
    s: *mut Fmi3State,
) -> Fmi3Status {
    with(c, |k| ok(k.deserialize_from(b, n, s)))
}

#[no_mangle]
pub extern "C" fn fmi3GetDirectionalDerivative(
    c: Fmi3Instance,
    _unknowns: *const Fmi3Vr,
    _nu: usize,
    _knowns: *const Fmi3Vr,
    _nk: usize,
    _seed: *const f64,
    _ns: usize,
    _sens: *mut f64,
    _nsens: usize,
) -> Fmi3Status {
    unsupported(c, "fmi3GetDirectionalDerivative")
}

#[no_mangle]
pub extern "C" fn fmi3GetAdjointDerivative(
    c: Fmi3Instance,
    _unknowns: *const Fmi3Vr,
    _nu: usize,
    _knowns: *const Fmi3Vr,
    _nk: usize,
    _seed: *const f64,
    _ns: usize,
    _sens: *mut f64,
    _nsens: usize,
) -> Fmi3Status {
    unsupported(c, "fmi3GetAdjointDerivative")
}

#[no_mangle]
pub extern "C" fn fmi3EnterConfigurationMode(c: Fmi3Instance) -> Fmi3Status {
    unsupported(c, "fmi3EnterConfigurationMode (no structural parameters)")
}

#[no_mangle]
pub extern "C" fn fmi3ExitConfigurationMode(c: Fmi3Instance) -> Fmi3Status {
    unsupported(c, "fmi3ExitConfigurationMode (no structural parameters)")
}

#[no_mangle]
pub extern "C" fn fmi3GetIntervalDecimal(
    c: Fmi3Instance,
    _vr: *const Fmi3Vr,
    _n: usize,
    _intervals: *mut f64,
    _qualifiers: *mut c_int,
) -> Fmi3Status {
    unsupported(c, "clocks")
}

#[no_mangle]
pub extern "C" fn fmi3GetIntervalFraction(
    c: Fmi3Instance,
    _vr: *const Fmi3Vr,
    _n: usize,
    _counters: *mut u64,
    _resolutions: *mut u64,
    _qualifiers: *mut c_int,
) -> Fmi3Status {
    unsupported(c, "clocks")
}

#[no_mangle]
pub extern "C" fn fmi3GetShiftDecimal(
    c: Fmi3Instance,
    _vr: *const Fmi3Vr,
    _n: usize,
    _shifts: *mut f64,
) -> Fmi3Status {
    unsupported(c, "clocks")
}

#[no_mangle]
pub extern "C" fn fmi3GetShiftFraction(
    c: Fmi3Instance,
    _vr: *const Fmi3Vr,
    _n: usize,
    _counters: *mut u64,
    _resolutions: *mut u64,
) -> Fmi3Status {
    unsupported(c, "clocks")
}

#[no_mangle]
pub extern "C" fn fmi3SetIntervalDecimal(
    c: Fmi3Instance,
    _vr: *const Fmi3Vr,
    _n: usize,
    _intervals: *const f64,
) -> Fmi3Status {
    unsupported(c, "clocks")
}

#[no_mangle]
pub extern "C" fn fmi3SetIntervalFraction(
    c: Fmi3Instance,
    _vr: *const Fmi3Vr,
    _n: usize,
    _counters: *const u64,
    _resolutions: *const u64,
) -> Fmi3Status {
    unsupported(c, "clocks")
}

#[no_mangle]
pub extern "C" fn fmi3SetShiftDecimal(
    c: Fmi3Instance,
    _vr: *const Fmi3Vr,
    _n: usize,
    _shifts: *const f64,
) -> Fmi3Status {
    unsupported(c, "clocks")
}

#[no_mangle]
pub extern "C" fn fmi3SetShiftFraction(
    c: Fmi3Instance,
    _vr: *const Fmi3Vr,
    _n: usize,
    _counters: *const u64,
    _resolutions: *const u64,
) -> Fmi3Status {
    unsupported(c, "clocks")
}

#[no_mangle]
pub extern "C" fn fmi3EvaluateDiscreteStates(c: Fmi3Instance) -> Fmi3Status {
    unsupported(c, "fmi3EvaluateDiscreteStates (no event mode)")
}

#[no_mangle]
pub extern "C" fn fmi3UpdateDiscreteStates(
    c: Fmi3Instance,
    _need_update: *mut bool,
    _terminate: *mut bool,
    _nominals_changed: *mut bool,
    _values_changed: *mut bool,
    _next_defined: *mut bool,
    _next_time: *mut f64,
) -> Fmi3Status {
    unsupported(c, "fmi3UpdateDiscreteStates (no event mode)")
}

#[no_mangle]
pub extern "C" fn fmi3EnterContinuousTimeMode(c: Fmi3Instance) -> Fmi3Status {
    unsupported(c, "Model Exchange")
}

#[no_mangle]
pub extern "C" fn fmi3CompletedIntegratorStep(
    c: Fmi3Instance,
    _no_set_prior: bool,
    _enter_event: *mut bool,
    _terminate: *mut bool,
) -> Fmi3Status {
    unsupported(c, "Model Exchange")
}

#[no_mangle]
pub extern "C" fn fmi3SetTime(c: Fmi3Instance, _t: f64) -> Fmi3Status {
    unsupported(c, "Model Exchange")
}

#[no_mangle]
pub extern "C" fn fmi3SetContinuousStates(
    c: Fmi3Instance,
    _x: *const f64,
    _n: usize,
) -> Fmi3Status {
    unsupported(c, "Model Exchange")
}

#[no_mangle]
pub extern "C" fn fmi3GetContinuousStateDerivatives(
    c: Fmi3Instance,
    _dx: *mut f64,
    _n: usize,
) -> Fmi3Status {
    unsupported(c, "Model Exchange")
}

#[no_mangle]
pub extern "C" fn fmi3GetEventIndicators(c: Fmi3Instance, _z: *mut f64, _n: usize) -> Fmi3Status {
    unsupported(c, "Model Exchange")
}

#[no_mangle]
pub extern "C" fn fmi3GetContinuousStates(c: Fmi3Instance, _x: *mut f64, _n: usize) -> Fmi3Status {
    unsupported(c, "Model Exchange")
}

#[no_mangle]
pub extern "C" fn fmi3GetNominalsOfContinuousStates(
    c: Fmi3Instance,
    _x: *mut f64,
    _n: usize,
) -> Fmi3Status {
    unsupported(c, "Model Exchange")
}

#[no_mangle]
pub extern "C" fn fmi3GetNumberOfEventIndicators(c: Fmi3Instance, _n: *mut usize) -> Fmi3Status {
    unsupported(c, "Model Exchange")
}

#[no_mangle]
pub extern "C" fn fmi3GetNumberOfContinuousStates(c: Fmi3Instance, _n: *mut usize) -> Fmi3Status {
    unsupported(c, "Model Exchange")
}

#[no_mangle]
pub extern "C" fn fmi3EnterStepMode(c: Fmi3Instance) -> Fmi3Status {
    // Without event mode the FMU is in step mode after initialisation: nothing to do there.
    with(c, |k| match k.inst.phase() {
        crate::instance::Phase::Stepping => Ok(Status::Ok),
        _ => Err((
            Status::Error,
            "fmi3EnterStepMode: allowed only after initialisation".into(),
        )),
    })
}

#[no_mangle]
pub extern "C" fn fmi3GetOutputDerivatives(
    c: Fmi3Instance,
    _vr: *const Fmi3Vr,
    _n: usize,
    _orders: *const i32,
    _values: *mut f64,
    _nv: usize,
) -> Fmi3Status {
    unsupported(c, "fmi3GetOutputDerivatives")
}

#[no_mangle]
pub extern "C" fn fmi3DoStep(
    c: Fmi3Instance,
    t: f64,
    h: f64,
    _no_set_prior: bool,
    event_handling_needed: *mut bool,
    terminate: *mut bool,
    early_return: *mut bool,
    last_successful: *mut f64,
) -> Fmi3Status {
    with(c, |k| {
        let r = k.inst.do_step(t, h);
        // SAFETY: each output pointer is NULL (skipped) or points to the host's variable, writable for the call (FMI 3.0 `fmi3DoStep`).
        unsafe {
            for p in [event_handling_needed, terminate, early_return] {
                if !p.is_null() {
                    *p = false;
                }
            }
            if !last_successful.is_null() {
                *last_successful = k.inst.time();
            }
        }
        r
    })
}

#[no_mangle]
pub extern "C" fn fmi3ActivateModelPartition(
    c: Fmi3Instance,
    _clock: Fmi3Vr,
    _t: f64,
) -> Fmi3Status {
    unsupported(c, "Scheduled Execution")
}

#[cfg(test)]
mod tests {
    use super::*;

    fn instantiate() -> Fmi3Instance {
        let name = std::ffi::CString::new("t3").unwrap();
        let token = std::ffi::CString::new(crate::GUID).unwrap();
        fmi3InstantiateCoSimulation(
            name.as_ptr(),
            token.as_ptr(),
            std::ptr::null(),
            false,
            false,
            false,
            false,
            std::ptr::null(),
            0,
            std::ptr::null_mut(),
            None,
            std::ptr::null_mut(),
        )
    }

    #[test]
    fn state_round_trip_is_bit_identical_and_foreign_states_are_refused() {
        let c = instantiate();
        assert!(!c.is_null());
        assert_eq!(
            fmi3EnterInitializationMode(c, false, 0.0, 0.0, false, 0.0),
            0
        );
        assert_eq!(fmi3ExitInitializationMode(c), 0);
        let vr_force = [crate::vars::VR_CONTACT_FORCE];
        assert_eq!(
            fmi3SetFloat64(c, vr_force.as_ptr(), 1, [90.0].as_ptr(), 1),
            0
        );
        let step = |c: Fmi3Instance, t0: f64, n: usize| -> f64 {
            let mut t = t0;
            let vr = [crate::vars::VR_WIRE_HEIGHT];
            let mut h = [0.0];
            for k in 0..n {
                let pos = [crate::vars::VR_PANTOGRAPH_POSITION];
                let x = [(t + 0.001) * 222.0 / 3.6];
                assert_eq!(fmi3SetFloat64(c, pos.as_ptr(), 1, x.as_ptr(), 1), 0);
                let (mut a, mut b, mut e, mut l) = (true, true, true, 0.0);
                assert_eq!(
                    fmi3DoStep(c, t, 0.001, false, &mut a, &mut b, &mut e, &mut l),
                    0,
                    "step {k}"
                );
                t += 0.001;
            }
            assert_eq!(fmi3GetFloat64(c, vr.as_ptr(), 1, h.as_mut_ptr(), 1), 0);
            h[0]
        };
        let t1 = 0.0;
        let _ = step(c, t1, 300);
        let mut s: Fmi3State = std::ptr::null_mut();
        assert_eq!(fmi3GetFMUState(c, &mut s), 0);
        let a = step(c, 0.3, 300);
        assert_eq!(fmi3SetFMUState(c, s), 0);
        let b = step(c, 0.3, 300);
        assert_eq!(a.to_bits(), b.to_bits());
        // Serialise, a new instance, de-serialise, step: the same again.
        let mut size = 0usize;
        assert_eq!(fmi3SerializedFMUStateSize(c, s, &mut size), 0);
        let mut buf = vec![0u8; size];
        assert_eq!(fmi3SerializeFMUState(c, s, buf.as_mut_ptr(), size), 0);
        assert_eq!(fmi3FreeFMUState(c, &mut s), 0);
        assert!(s.is_null());
        fmi3FreeInstance(c);
        let c2 = instantiate();
        assert_eq!(
            fmi3EnterInitializationMode(c2, false, 0.0, 0.0, false, 0.0),
            0
        );
        assert_eq!(fmi3ExitInitializationMode(c2), 0);
        let mut s2: Fmi3State = std::ptr::null_mut();
        assert_eq!(fmi3DeserializeFMUState(c2, buf.as_ptr(), size, &mut s2), 0);
        assert_eq!(fmi3SetFMUState(c2, s2), 0);
        let b2 = step(c2, 0.3, 300);
        assert_eq!(a.to_bits(), b2.to_bits());
        // A damaged state and a state of another window are refused.
        let mut bad = buf.clone();
        bad[0] = b'X';
        let mut s3: Fmi3State = std::ptr::null_mut();
        assert_eq!(fmi3DeserializeFMUState(c2, bad.as_ptr(), size, &mut s3), 3);
        assert_eq!(
            fmi3DeserializeFMUState(c2, buf.as_ptr(), size - 1, &mut s3),
            3
        );
        fmi3FreeInstance(c2);
        let c3 = instantiate();
        let wl = [crate::vars::VR_WINDOW_LENGTH];
        assert_eq!(fmi3SetFloat64(c3, wl.as_ptr(), 1, [240.0].as_ptr(), 1), 0);
        assert_eq!(
            fmi3EnterInitializationMode(c3, false, 0.0, 0.0, false, 0.0),
            0
        );
        assert_eq!(fmi3ExitInitializationMode(c3), 0);
        assert_eq!(fmi3DeserializeFMUState(c3, buf.as_ptr(), size, &mut s3), 3);
        fmi3FreeInstance(c3);
    }

    #[test]
    fn calls_in_the_wrong_state_are_errors() {
        let c = instantiate();
        let (mut a, mut b, mut e, mut l) = (false, false, false, 0.0);
        assert_eq!(
            fmi3DoStep(c, 0.0, 0.001, false, &mut a, &mut b, &mut e, &mut l),
            3
        );
        assert_eq!(fmi3ExitInitializationMode(c), 3);
        assert_eq!(fmi3EnterEventMode(c), 3);
        let mut s: Fmi3State = std::ptr::null_mut();
        assert_eq!(fmi3GetFMUState(c, &mut s), 3);
        assert_eq!(fmi3EnterStepMode(c), 3);
        fmi3FreeInstance(c);
        assert_eq!(fmi3Terminate(c), 3);
        assert_eq!(fmi3Terminate(std::ptr::null_mut()), 3);
    }
}
