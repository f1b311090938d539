//! Bounded resources: before a model is built or a run starts, estimate its steps and its memory
//! from the case alone, and refuse what exceeds a stated limit with an error that names the cause
//! and the estimate. A user who really wants such a run raises the limit (`--max-steps`,
//! `--max-memory-gb` on the command line).

use crate::error::CaseError;
use crate::input::bounds::num;
use crate::input::case::Case;

/// Limits of a run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Budget {
    /// Most time steps of one run (20 million: 5.5 hours of simulated time at Δt = 1 ms).
    pub max_steps: u64,
    /// Most memory one run may need, bytes (4 GiB).
    pub max_memory_bytes: u64,
}

impl Default for Budget {
    fn default() -> Self {
        Budget {
            max_steps: 20_000_000,
            max_memory_bytes: 4 << 30,
        }
    }
}

/// What a run of a case would take.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// Time steps.
    pub steps: u64,
    /// Simulated time, s.
    pub simulated_s: f64,
    /// Distance the rearmost pantograph travels, m.
    pub distance_m: f64,
    /// Memory of the model, its operators and scratch, bytes.
    pub model_bytes: f64,
    /// Memory of the recorded time histories and their statistics, bytes.
    pub record_bytes: f64,
}

impl Estimate {
    /// Everything, bytes.
    pub fn bytes(&self) -> f64 {
        self.model_bytes + self.record_bytes
    }
}

fn gib(b: f64) -> String {
    format!("{:.2} GiB", b / (1u64 << 30) as f64)
}

/// Estimate a run of a validated case without building anything. The model's memory follows
/// the implementation: modal arrays (a few dozen per mode), the point sampler's tables (each point
/// keeps `P + 2` numbers, `P = 2 × spans`), the implicit point terms (a capacitance matrix per
/// wire, rows of the sines while it is built).
pub fn estimate(case: &Case) -> Estimate {
    let c = &case.catenary;
    let spans = c.spans as f64;
    let n = case.n_modes() as f64;
    let per_span = c.droppers.positions_m.len() as f64 + 1.0;
    let points = per_span * spans;
    let period = 2.0 * spans;
    let stitch = c
        .stitch_wire
        .as_ref()
        .map_or(0.0, |s| s.droppers.len() as f64);
    let velocity_points = spans * (1.0 + stitch);
    let implicit = spans;
    // Directions modelled: each adds a block per wire (the modal arrays and the gathered points
    // grow with it; the sampler's tables are shared).
    let dirs = case.run.dofs.len().max(1) as f64;
    let doubles = 60.0 * n * dirs
        + points * (period + 2.0) * dirs
        + velocity_points * (period + 2.0)
        + 2.0 * implicit * (n + period + 2.0) * dirs
        + 2.0 * implicit * implicit * dirs
        + 40.0 * points * dirs;
    let max_off = case
        .pantographs
        .iter()
        .map(|p| p.offset_m())
        .fold(0.0, f64::max);
    let distance = case.run.end_m - (case.run.start_m - max_off);
    let v = case.speed_m_s();
    let simulated = distance / v;
    let steps = (simulated / case.run.dt_s).ceil();
    let np = case.pantographs.len() as f64;
    // The generated wind: the fluctuation at every grid point over the run (a power of two of
    // samples), and its spectra while it is made (complex, twice over).
    let wind = case.wind.as_ref().map_or(0.0, |w| {
        let grid = (spans * c.span_m / w.grid_m.max(1e-9)).floor().max(0.0);
        let samples = ((simulated / w.dt_s.max(1e-12)).ceil() + 2.0)
            .max(16.0)
            .log2()
            .ceil()
            .exp2();
        grid * samples * 3.0
    });
    Estimate {
        steps: if steps.is_finite() && steps < u64::MAX as f64 {
            steps as u64
        } else {
            u64::MAX
        },
        simulated_s: simulated,
        distance_m: distance,
        model_bytes: 8.0 * (doubles + wind),
        record_bytes: 8.0 * steps * (1.0 + (9.0 + if dirs > 1.0 { 2.0 } else { 0.0 }) * np),
    }
}

impl Budget {
    /// Refuse a case whose run exceeds the limits; the error names the cause and the estimate.
    pub fn check(&self, case: &Case) -> Result<Estimate, CaseError> {
        let e = estimate(case);
        if e.steps > self.max_steps {
            let r = &case.run;
            // The cause: the speed if even at Δt = 1 ms the run were too long, else the step.
            let at_1ms = e.simulated_s / 1e-3;
            let (field, value) = if at_1ms > self.max_steps as f64 || r.dt_s >= 1e-3 {
                ("run.speed_kmh", num(r.speed_kmh))
            } else {
                ("run.dt_s", num(r.dt_s))
            };
            return Err(CaseError::Invalid {
                field: field.into(),
                value,
                reason: format!(
                    "the run would take {:.3e} steps ({:.0} m at {} km/h is {:.3e} s of simulated time, at run.dt_s = {} s), above the limit of {:.1e} steps (raise it with --max-steps)",
                    e.steps as f64, e.distance_m, num(r.speed_kmh), e.simulated_s, num(r.dt_s), self.max_steps as f64
                ),
            });
        }
        if e.bytes() > self.max_memory_bytes as f64 {
            let (field, value, cause) = if e.model_bytes >= e.record_bytes {
                (
                    "catenary.spans",
                    case.catenary.spans.to_string(),
                    format!(
                        "the model with {} modes per wire over {} spans needs about {} (its point tables grow with the square of the spans)",
                        case.n_modes(),
                        case.catenary.spans,
                        gib(e.model_bytes)
                    ),
                )
            } else {
                (
                    "run.dt_s",
                    num(case.run.dt_s),
                    format!(
                        "recording {:.3e} steps needs about {}",
                        e.steps as f64,
                        gib(e.record_bytes)
                    ),
                )
            };
            return Err(CaseError::Invalid {
                field: field.into(),
                value,
                reason: format!(
                    "{cause}, above the limit of {} (raise it with --max-memory-gb)",
                    gib(self.max_memory_bytes as f64)
                ),
            });
        }
        Ok(e)
    }
}

/// Refuse an array of `len` numbers that would exceed the memory limit; `field` and `value`
/// name the setting that makes it (an EVA step, a count of steps).
pub fn check_len(
    budget: &Budget,
    field: &str,
    value: impl std::fmt::Display,
    len: f64,
) -> Result<(), CaseError> {
    let bytes = 8.0 * len;
    if bytes.is_nan() || bytes > budget.max_memory_bytes as f64 {
        return Err(CaseError::Invalid {
            field: field.into(),
            value: value.to_string(),
            reason: format!(
                "would need {len:.3e} values (about {}), above the limit of {} (raise it with --max-memory-gb)",
                gib(bytes),
                gib(budget.max_memory_bytes as f64)
            ),
        });
    }
    Ok(())
}
