//! What a run means, run by run: filters, the EN 50318 statistics, the energy density and the
//! EVA, dropper fatigue, a run beside a measurement, a run against the acceptance criteria, and
//! a run's own evidence (refined, stiffer, over its ranged values). The studies over many runs
//! are `study/`, one file each.
//!
//! | file | what it holds |
//! |---|---|
//! | `filter.rs` | zero-phase Butterworth filters (SciPy-compatible) |
//! | `stats.rs` | the EN 50318 contact-force statistics |
//! | `record.rs` | the EN 50318 recorder (an observer) and `simulate` |
//! | `energy.rs` | the energy density (Eq. 20), system energy and dissipation |
//! | `eva.rs` | window energy (Eq. 21), the EVA criteria, the energy sampler (an observer) |
//! | `fatigue.rs` | dropper tensions through a run, rainflow cycles, Miner's damage |
//! | `compare.rs` | a run beside a measured force record: filtered, aligned, side by side |
//! | `assess.rs` | a run against the acceptance criteria: value, limit, verdict, clause, source |
//! | `events.rs` | a run's error-level events and which a user accepted |
//! | `verify.rs` | `--verify`: the run refined, and with a stiffer contact |
//! | `sensitivity.rs` | `--sensitivity`: the case's ranged values, one at a time and sampled |
//! | `sweep.rs` | grids of cases, shards, parallel execution, merge |
//! | `report.rs` | what a run reports: the summary and the time-series columns |

pub mod assess;
pub mod compare;
pub mod energy;
pub mod eva;
pub mod events;
pub mod fatigue;
pub mod filter;
pub mod record;
pub mod report;
pub mod sensitivity;
pub mod stats;
pub mod sweep;
pub mod verify;
