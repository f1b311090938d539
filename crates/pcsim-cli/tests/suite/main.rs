//! The integration tests of pcsim-cli, one binary (one build and one link for all): each
//! module is one former test file, named as before (`cargo test -p pcsim-cli --test suite NAME::`).

mod byte_golden;
mod cli;
mod common;
mod design;
mod everywhere;
mod evidence;
mod fuzz_run;
mod hardening;
mod loud;
mod matrix;
mod preset_golden;
mod realtime_golden;
mod trust;
mod trust3;
mod window_checks;
