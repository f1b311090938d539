//! # pcsim-fmu
//!
//! An FMI 2.0 co-simulation FMU of pcsim's real-time catenary
//! ([`pcsim_core::solve::realtime::RealtimeCatenary`]). Standard library only: the Rust FMI crates in the
//! registry return dangling pointers from string getters, enforce none of the standard's rules and
//! do not catch panics (issue 6), so the 34 entry points are written by hand.
//!
//! Layers, so that an FMI 3.0 wrapper can sit over the same code:
//! - [`vars`]: the table of variables (value references, causality, units), from which
//!   `modelDescription.xml` is generated;
//! - [`instance`]: the FMI-independent instance: phases, setters and getters with the standard's
//!   rules, `do_step` with its contract and the roll-back on a non-finite state;
//! - `fmi2` (the C ABI): null/foreign/freed-pointer checks through a registry of live instances,
//!   `catch_unwind` around every entry point (a panic gives `fmi2Fatal`), status codes.

pub mod instance;
pub mod vars;

mod fmi2;
mod fmi3;
mod host;

/// The model identifier (the shared library's base name inside the FMU).
pub const MODEL_IDENTIFIER: &str = "pcsim_fmu";
/// The GUID written to modelDescription.xml and checked by `fmi2Instantiate`.
pub const GUID: &str = "{6b1e4f0a-2c3d-4e5f-8a9b-0c1d2e3f4a5b}";
