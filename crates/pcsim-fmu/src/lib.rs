//! # pcsim-fmu
//!
//! FMI 2.0 and 3.0 co-simulation FMUs of pcsim's real-time catenary: they only translate the
//! core's real-time session ([`pcsim_core::session::RealtimeSession`], which owns the step
//! contract and the state format). Standard library only: the Rust FMI crates in the registry
//! return dangling pointers from string getters, enforce none of the standard's rules and do not
//! catch panics (issue 6), so the entry points are written by hand.
//!
//! # Safety
//! The entry points of both ABIs (`fmi2*`, `fmi3*`) are `extern "C"` functions that take the
//! host's raw pointers. Their contract is the FMI standard's: a component pointer is NULL or one
//! this library returned (checked against a registry, so NULL, foreign and freed pointers are
//! refused); arrays hold the stated number of values and strings are NUL-terminated, valid for
//! the call; one instance is called from one thread at a time. Every dereference names the rule
//! it relies on in a `SAFETY:` comment (`clippy::undocumented_unsafe_blocks` is denied).
//!
//! Layers, so that an FMI 3.0 wrapper can sit over the same code:
//! - [`vars`]: the table of variables (value references, causality, units), from which
//!   `modelDescription.xml` is generated;
//! - [`instance`]: the FMI-independent instance: phases, setters and getters with the standard's
//!   rules, `do_step` with its contract and the roll-back on a non-finite state;
//! - `fmi2` (the C ABI): null/foreign/freed-pointer checks through a registry of live instances,
//!   `catch_unwind` around every entry point (a panic gives `fmi2Fatal`), status codes.

#![deny(clippy::undocumented_unsafe_blocks, clippy::missing_safety_doc)]
// No production function over 100 lines (clippy.toml's threshold; issue 52): a long function
// is split into named parts. Tests are exempt (a scenario reads best whole).
#![cfg_attr(not(test), deny(clippy::too_many_lines))]

pub mod instance;
pub mod vars;

mod fmi2;
mod fmi3;
mod host;

/// The model identifier (the shared library's base name inside the FMU).
pub const MODEL_IDENTIFIER: &str = "pcsim_fmu";
/// The GUID written to modelDescription.xml and checked by `fmi2Instantiate` (changed when the
/// interface changed: the input `pantograph_position` became `position_from_start`).
pub const GUID: &str = "{6b1e4f0a-2c3d-4e5f-8a9b-0c1d2e3f4a5c}";
