//! What the FMI 2.0 and 3.0 C ABIs share: the component around an instance (the host's logger,
//! the string buffers, the FMU states handed out), the registry of live components, and the
//! `catch_unwind` wrapper every entry point runs under.

use std::ffi::{c_char, c_int, c_void, CStr, CString};
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::sync::Mutex;

use crate::instance::{FmuState, Instance, Res, Status};

/// The FMI 2.0 logger (variadic).
pub(crate) type Logger2 =
    unsafe extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char, ...);
/// The FMI 3.0 log-message callback.
pub(crate) type Logger3 = unsafe extern "C" fn(*mut c_void, c_int, *const c_char, *const c_char);

/// The host's logger, by FMI version.
pub(crate) enum Logger {
    None,
    V2(Logger2),
    V3(Logger3),
}

pub(crate) const ERROR: c_int = 3;
pub(crate) const FATAL: c_int = 4;

/// The FMI wrapper around an instance: the host's logger, the string buffers and the FMU states
/// handed out.
pub(crate) struct Component {
    pub inst: Instance,
    pub logger: Logger,
    pub env: usize,
    pub name_c: CString,
    pub strings: Vec<CString>,
    pub string_ptrs: Vec<*const c_char>,
    /// FMU states handed out and not yet freed (their addresses).
    pub states: Vec<usize>,
}

impl Drop for Component {
    fn drop(&mut self) {
        for p in self.states.drain(..) {
            // SAFETY: every address in `states` came from `Box::into_raw` in `hand_out` and is
            // removed when freed, so each is a live box, dropped once here.
            drop(unsafe { Box::from_raw(p as *mut FmuState) });
        }
    }
}

/// Addresses of live components.
static LIVE: Mutex<Vec<usize>> = Mutex::new(Vec::new());

pub(crate) fn live() -> std::sync::MutexGuard<'static, Vec<usize>> {
    LIVE.lock().unwrap_or_else(|e| e.into_inner())
}

fn is_live(c: *mut c_void) -> bool {
    !c.is_null() && live().contains(&(c as usize))
}

impl Component {
    pub fn new(inst: Instance, name: &str, logger: Logger, env: usize) -> Self {
        Component {
            name_c: CString::new(name.replace('\0', " ")).unwrap_or_default(),
            inst,
            logger,
            env,
            strings: Vec::new(),
            string_ptrs: Vec::new(),
            states: Vec::new(),
        }
    }

    fn log(&self, status: Status, msg: &str) {
        let category: &CStr = if status >= Status::Error {
            c"logStatusError"
        } else {
            c"logAll"
        };
        let msg = CString::new(msg.replace('\0', " ")).unwrap_or_default();
        match self.logger {
            Logger::None => {}
            // The message goes through "%s" so that '%' in it is never a format directive.
            // SAFETY: the host gave this logger at instantiation (FMI 2.0 §2.1.5) for the
            // instance's life; every string passed is a NUL-terminated CString alive meanwhile.
            Logger::V2(logger) => unsafe {
                logger(
                    self.env as *mut c_void,
                    self.name_c.as_ptr(),
                    status as c_int,
                    category.as_ptr(),
                    c"%s".as_ptr(),
                    msg.as_ptr(),
                )
            },
            // SAFETY: as for FMI 2.0: the host's logger, with live NUL-terminated strings.
            Logger::V3(cb) => unsafe {
                cb(
                    self.env as *mut c_void,
                    status as c_int,
                    category.as_ptr(),
                    msg.as_ptr(),
                )
            },
        }
    }

    /// Set Real (FMI 2.0) / Float64 (FMI 3.0) variables, one value per reference (both ABIs).
    pub fn set_reals(&mut self, vr: &[u32], values: &[f64]) -> Res {
        for (v, x) in vr.iter().zip(values) {
            if *v == TEST_PANIC_VR && std::env::var_os("PCSIM_FMU_TEST_PANIC").is_some() {
                panic!("test hook: deliberate panic");
            }
            self.inst.set_real(*v, *x)?;
        }
        Ok(())
    }

    /// Get String variables into the host's array (both ABIs); the strings stay valid until
    /// the component's next call.
    pub fn get_strings(&mut self, vr: &[u32], out: &mut [*const c_char]) -> Res {
        let strings = vr
            .iter()
            .map(|v| self.inst.get_string(*v).map(str::to_string))
            .collect::<Result<Vec<_>, _>>()?;
        out.copy_from_slice(self.hold_strings(strings));
        Ok(())
    }

    /// Set String variables from the host's C strings (both ABIs).
    ///
    /// # Safety
    /// Each value is NULL or a NUL-terminated string valid for the call.
    pub unsafe fn set_strings(&mut self, vr: &[u32], values: &[*const c_char]) -> Res {
        for (v, x) in vr.iter().zip(values) {
            // SAFETY: NULL or NUL-terminated and valid (this function's contract).
            self.inst.set_string(*v, &unsafe { host_str(*x) }?)?;
        }
        Ok(())
    }

    /// Copies of `strings` owned by the component until its next call: never dangling.
    pub fn hold_strings(&mut self, strings: Vec<String>) -> &[*const c_char] {
        self.strings = strings
            .into_iter()
            .map(|s| CString::new(s).unwrap_or_default())
            .collect();
        self.string_ptrs.clear();
        self.string_ptrs
            .extend(self.strings.iter().map(|s| s.as_ptr()));
        &self.string_ptrs
    }

    /// A state pointer of this component (handed out and not freed), or an error.
    pub fn own_state(&self, s: *mut c_void) -> Res<*mut FmuState> {
        if s.is_null() || !self.states.contains(&(s as usize)) {
            return Err((
                Status::Error,
                "not an FMU state of this instance (NULL, foreign or freed)".into(),
            ));
        }
        Ok(s as *mut FmuState)
    }

    /// Set the instance to state `s`, one handed out and not freed (both ABIs).
    pub fn set_state_from(&mut self, s: *mut c_void) -> Res {
        let p = self.own_state(s)?;
        // SAFETY: `own_state` returned `p` only because it is a state this component handed out
        // and has not freed: a live `Box<FmuState>`.
        self.inst.set_state(unsafe { &*p })
    }

    /// Free the state in the host's state variable `s` and set the variable to NULL (both ABIs:
    /// `fmi2FreeFMUstate`, `fmi3FreeFMUState`).
    pub fn free_state_at(&mut self, s: *mut *mut c_void) -> Res {
        if s.is_null() {
            return Err((Status::Error, "NULL state pointer".into()));
        }
        // SAFETY: `s` is non-NULL (checked) and points to the host's state variable (the
        // standard's `fmi*FMUState*`), readable and writable for the call.
        self.free_state(unsafe { *s })?;
        // SAFETY: as above: `s` is the host's non-NULL state variable.
        unsafe { *s = std::ptr::null_mut() };
        Ok(())
    }

    /// De-serialise the host's `n` bytes at `b` into its state variable `s` (both ABIs).
    pub fn deserialize_from(&mut self, b: *const u8, n: usize, s: *mut *mut c_void) -> Res {
        // SAFETY: the host passes `n` bytes, valid for the call (FMI); NULL is refused.
        let bytes = unsafe { slice(b, n)? };
        self.deserialize_state(bytes, s)
    }

    /// Hand a new state to the host.
    pub fn hand_out(&mut self, st: FmuState) -> *mut c_void {
        let p = Box::into_raw(Box::new(st));
        self.states.push(p as usize);
        p as *mut c_void
    }

    /// Free a state handed out (a NULL state is a no-op).
    pub fn free_state(&mut self, s: *mut c_void) -> Res {
        if s.is_null() {
            return Ok(());
        }
        let p = self.own_state(s)?;
        self.states.retain(|&q| q != p as usize);
        // SAFETY: `own_state` found `p` among the states handed out (live boxes); it was just
        // removed from the list, so it is dropped exactly once.
        drop(unsafe { Box::from_raw(p) });
        Ok(())
    }

    /// Get the state into the host's existing one (in place) or a new one.
    pub fn get_state(&mut self, s: *mut *mut c_void) -> Res {
        if s.is_null() {
            return Err((Status::Error, "NULL state pointer".into()));
        }
        // SAFETY: `s` is non-NULL (checked) and is the host's state variable, readable and
        // writable for the call (FMI 2.0 `fmi2GetFMUstate`, FMI 3.0 `fmi3GetFMUState`).
        let cur = unsafe { *s };
        if !cur.is_null() && self.states.contains(&(cur as usize)) {
            // SAFETY: `cur` is a state this component handed out and has not freed (a live
            // box), and the host does not use it during the call.
            let st = unsafe { &mut *(cur as *mut FmuState) };
            self.inst.get_state_into(st)
        } else {
            let st = self.inst.get_state()?;
            // SAFETY: `s` is the host's writable state variable (above).
            unsafe { *s = self.hand_out(st) };
            Ok(())
        }
    }

    /// De-serialise into the host's existing state (in place) or a new one.
    pub fn deserialize_state(&mut self, bytes: &[u8], s: *mut *mut c_void) -> Res {
        if s.is_null() {
            return Err((Status::Error, "NULL state pointer".into()));
        }
        let st = self.inst.deserialize_state(bytes)?;
        // SAFETY: `s` is non-NULL (checked) and is the host's state variable, readable and
        // writable for the call.
        let cur = unsafe { *s };
        if !cur.is_null() && self.states.contains(&(cur as usize)) {
            // SAFETY: `cur` is a live state handed out by this component (a box).
            unsafe { *(cur as *mut FmuState) = st };
        } else {
            // SAFETY: `s` is the host's writable state variable (above).
            unsafe { *s = self.hand_out(st) };
        }
        Ok(())
    }

    /// The serialised bytes of a state handed out.
    pub fn serialize_state(&self, s: *mut c_void) -> Res<Vec<u8>> {
        let p = self.own_state(s)?;
        // SAFETY: `own_state` returned `p` only for a live state handed out by this component.
        Ok(Instance::serialize_state(unsafe { &*p }))
    }

    /// The serialised size of state `s`, written to the host's `size` (both ABIs).
    pub fn serialized_size_into(&self, s: *mut c_void, size: *mut usize) -> Res {
        let n = self.serialize_state(s)?.len();
        // SAFETY: the host passes a writable `size_t` (NULL is refused by `slice_mut`).
        let size = unsafe { slice_mut(size, 1)? };
        size[0] = n;
        Ok(())
    }

    /// Serialise state `s` into the host's buffer of exactly its serialised size (both ABIs).
    pub fn serialize_into(&self, s: *mut c_void, b: *mut u8, n: usize) -> Res {
        let bytes = self.serialize_state(s)?;
        if bytes.len() != n {
            return Err((
                Status::Error,
                format!("buffer of {n} bytes for a state of {} bytes", bytes.len()),
            ));
        }
        // SAFETY: the host passes a buffer of `n` writable bytes (NULL is refused).
        let out = unsafe { slice_mut(b, n)? };
        out.copy_from_slice(&bytes);
        Ok(())
    }
}

/// A value reference that panics inside `fmi2SetReal` / `fmi3SetFloat64` when the environment
/// variable `PCSIM_FMU_TEST_PANIC` is set: the misuse suites' way to check that a panic gives
/// Fatal and the host survives. Not in the model description.
pub const TEST_PANIC_VR: u32 = 0xFFFF_FFF0;

/// Register a new component and return its address.
pub(crate) fn register(comp: Component) -> *mut c_void {
    let p = Box::into_raw(Box::new(comp));
    live().push(p as usize);
    p as *mut c_void
}

/// Unregister and drop a component (freeing a freed or foreign pointer is a no-op).
pub(crate) fn unregister(c: *mut c_void) {
    let mut l = live();
    if let Some(i) = l.iter().position(|&p| p == c as usize) {
        l.swap_remove(i);
        drop(l);
        // SAFETY: `c` was in the registry, so it came from `Box::into_raw` in `register` and
        // was not freed; it has just been removed, so it is dropped exactly once.
        drop(unsafe { Box::from_raw(c as *mut Component) });
    }
}

/// Run `f` on the live component `c` under `catch_unwind`.
pub(crate) fn with(c: *mut c_void, f: impl FnOnce(&mut Component) -> Res<Status>) -> c_int {
    if !is_live(c) {
        return ERROR;
    }
    let comp = c as *mut Component;
    // SAFETY: `c` is in the registry of live components (checked), and the FMI standard lets a
    // host call one instance from one thread at a time, so this is the only reference.
    match catch_unwind(AssertUnwindSafe(|| f(unsafe { &mut *comp }))) {
        Ok(Ok(s)) => s as c_int,
        Ok(Err((s, msg))) => {
            // SAFETY: the same live component; the closure's borrow has ended.
            let comp = unsafe { &mut *comp };
            comp.log(s, &msg);
            if s == Status::Fatal {
                comp.inst.fail();
            }
            s as c_int
        }
        Err(_) => {
            // SAFETY: the same live component; the panicking closure's borrow has ended.
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

pub(crate) fn ok(r: Res) -> Res<Status> {
    r.map(|_| Status::Ok)
}

/// Slices from host arrays; NULL with n > 0 is an error.
///
/// # Safety
/// `p` is NULL or points to `n` initialised values that stay valid and unchanged for `'a`.
pub(crate) unsafe fn slice<'a, T>(p: *const T, n: usize) -> Res<&'a [T]> {
    if n == 0 {
        return Ok(&[]);
    }
    if p.is_null() {
        return Err((Status::Error, "NULL array".into()));
    }
    // SAFETY: non-NULL, and `n` valid values for `'a` (the caller's contract).
    Ok(unsafe { std::slice::from_raw_parts(p, n) })
}

/// A mutable slice of a host array; NULL with n > 0 is an error.
///
/// # Safety
/// `p` is NULL or points to `n` writable values that nothing else uses for `'a`.
pub(crate) unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Res<&'a mut [T]> {
    if n == 0 {
        return Ok(&mut []);
    }
    if p.is_null() {
        return Err((Status::Error, "NULL array".into()));
    }
    // SAFETY: non-NULL, and `n` writable values used by nothing else for `'a` (the caller's
    // contract).
    Ok(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// A call the FMU does not support: Error with the reason logged.
pub(crate) fn unsupported(c: *mut c_void, what: &str) -> c_int {
    with(c, |_| {
        Err((
            Status::Error,
            format!(
                "{what} is not supported by this FMU (see modelDescription.xml capability flags)"
            ),
        ))
    })
}

/// A string from the host, copied (NULL is an error).
///
/// # Safety
/// `p` is NULL or a NUL-terminated string valid for the call (the FMI standard has the host
/// pass such strings).
pub(crate) unsafe fn host_str(p: *const c_char) -> Res<String> {
    if p.is_null() {
        return Err((Status::Error, "NULL string".into()));
    }
    // SAFETY: non-NULL (checked) and NUL-terminated, valid for the call (this function's
    // contract); only copied here.
    Ok(unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned())
}
