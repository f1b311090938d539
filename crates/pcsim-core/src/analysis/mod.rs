//! What the runs mean: filters, the EN 50318 statistics, the energy density and the EVA,
//! validation against published ranges, sweeps, and studies.
//!
//! | file | what it holds |
//! |---|---|
//! | `filter.rs` | zero-phase Butterworth filters (SciPy-compatible) |
//! | `compare.rs` | a run beside a measured force record: filtered, aligned, side by side |
//! | `stats.rs` | the EN 50318 contact-force statistics |
//! | `record.rs` | the EN 50318 recorder (an observer) and `simulate` |
//! | `energy.rs` | the energy density (Eq. 20), system energy and dissipation |
//! | `eva.rs` | window energy (Eq. 21), the EVA criteria, the energy sampler (an observer) |
//! | `fatigue.rs` | dropper tensions through a run, rainflow cycles, Miner's damage |
//! | `validation.rs` | which cases, which targets, the validation table |
//! | `sweep.rs` | grids of cases, shards, parallel execution, merge |
//! | `studies.rs` | the real-time window against the full model |
//! | `window_length.rs` | the accuracy-based window length and the energy criteria's fit |
//! | `montecarlo.rs` | realisations over seeds and their spread |
//! | `design.rs` | the design search: an optimiser over case fields, the journal, the answer |
//! | `verify.rs` | `--verify`: the run refined, and with a stiffer contact |
//! | `sensitivity.rs` | `--sensitivity`: the case's ranged values, one at a time and sampled |
//! | `frf.rs` | a pantograph's frequency response at the head, and a chain fitted to a measured one |
//! | `report.rs` | what a run reports: the summary and the time-series columns |

pub mod assess;
pub mod compare;
pub mod design;
pub mod energy;
pub mod eva;
pub mod fatigue;
pub mod filter;
pub mod frf;
pub mod montecarlo;
pub mod record;
pub mod report;
pub mod sensitivity;
pub mod specs;
pub mod stats;
pub mod studies;
pub mod sweep;
pub mod sweeps;
pub mod validation;
pub mod verify;
pub mod window_length;
