//! The core's unit tests, one module per source file they test (`src/` holds no tests: the
//! library is compiled once for the binary and the tests).

mod analysis_fatigue;
mod analysis_sensitivity;
mod compile;
mod fingerprint;
mod input_criteria;
mod input_design;
mod input_measured;
mod input_overrides;
mod input_units;
mod linalg;
mod model_basis;
mod model_elements_contact;
mod model_wind;
mod solve_kernels;
mod solve_nufft;
mod solve_realtime_line;
mod solve_sampler;
mod solve_state;
mod study_compare;
mod study_run;
mod study_schema;
