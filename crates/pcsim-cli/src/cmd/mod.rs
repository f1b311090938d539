//! One file per command.

pub mod assess;
pub mod bench;
pub mod compare;
pub mod design;
pub mod eva;
pub mod fmu;
pub mod hil;
pub mod pantograph;
pub mod plot;
pub mod presets;
pub mod realtime;
pub mod report;
pub mod run;
pub mod schema;
pub mod study;
pub mod validate;
pub mod window;
