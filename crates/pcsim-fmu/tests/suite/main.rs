//! The integration tests of pcsim-fmu, one binary (`cargo test -p pcsim-fmu --test suite NAME::`).

mod matrix;
