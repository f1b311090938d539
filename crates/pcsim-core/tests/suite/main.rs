//! The integration tests of pcsim-core, one binary (one build and one link for all): each
//! module is one former test file, named as before (`cargo test -p pcsim-core --test suite NAME::`).

mod analytic;
mod assess;
mod cases;
mod common;
mod compare;
mod convergence;
mod curves;
mod design;
mod dynamics;
mod en50318_2002;
mod energy;
mod fatigue;
mod filter_golden;
mod frf;
mod irregularity;
mod isa;
mod lateral;
mod layers;
mod line;
mod line_physics;
mod matrix;
mod mutations;
mod realtime;
mod realtime_alloc;
mod realtime_session;
mod sensitivity;
mod stability;
mod statics;
mod steady_loads;
mod stitched;
mod strips;
mod threads;
mod uplift_height;
mod verify;
mod zoo;
