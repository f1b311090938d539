//! The integration tests of pcsim-cli, one binary (one build and one link for all): each
//! module is one topic, named by what it tests (`cargo test -p pcsim-cli --test suite NAME::`).

mod byte_golden;
mod case_files;
mod cli;
mod common;
mod current_collection;
mod design;
mod errors_downstream;
mod evidence;
mod fuzz_run;
mod hard_spots;
mod matrix;
mod output_transactions;
mod physics_errors;
mod preset_golden;
mod realtime_golden;
mod refusals;
mod window_checks;
