//! The integration tests of pcsim-capi, one binary (one build and one link for all): each
//! module is one former test file, named as before (`cargo test -p pcsim-capi --test suite NAME::`).

mod header;
mod matrix;
mod robustness;
