//! One run with its evidence (`pcsim run`, Python's `pcsim.run`): the one orchestration of a
//! run (issue 52: it was written in the core, in the CLI and in Python). The case is set up and
//! run (with its droppers followed when asked), its summary made, then its evidence: the run
//! refined and with a stiffer contact (`--verify`), and its ranged values varied
//! (`--sensitivity`). Its files are `summary.json`, `timeseries.csv` and the droppers' CSVs;
//! its answer each pantograph's statistics, the evidence, and the events that refuse it.

use std::fmt::Write as _;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::analysis::events::{run_errors, AllowedErrors};
use crate::analysis::record::{simulate_with, DropperOptions, DropperRun, RunOutput};
use crate::analysis::report::{timeseries_columns, RunSummary};
use crate::analysis::sensitivity::{sensitivity, SensitivitySpec};
use crate::compile::{Budget, Setup};
use crate::error::{CaseError, SimError};
use crate::input::case::{Case, RangedValue};
use crate::study::{Answer, Study, StudyFile, StudyKind};

/// The most numbers `dropper_forces.csv` may hold (droppers × steps: about 100 MB of text);
/// beyond it only `droppers.csv` is written, and the run says so.
pub const DROPPER_HISTORY_LIMIT: usize = 10_000_000;

/// What a run is asked for beyond itself (`Default`: the run alone, one thread).
#[derive(Debug, Clone, PartialEq)]
pub struct RunSpec {
    /// The run again refined (twice the modes, half the step) and with a stiffer contact.
    pub verify: bool,
    /// The case's ranged values varied (none: not asked).
    pub sensitivity: Option<SensitivitySpec>,
    /// The error-level events accepted (a run's otherwise refuses it).
    pub allowed: AllowedErrors,
    /// Follow every dropper's tension (none: not asked).
    pub droppers: Option<DropperOptions>,
    /// Threads of the one run (`solve::team`; the same bytes on any count).
    pub threads: usize,
}

impl Default for RunSpec {
    fn default() -> Self {
        RunSpec {
            verify: false,
            sensitivity: None,
            allowed: AllowedErrors::default(),
            droppers: None,
            threads: 1,
        }
    }
}

/// A run of a case with its evidence.
#[derive(Debug, Clone)]
pub struct RunStudy {
    /// The case.
    pub case: Case,
    /// The ranges its text gives its values (what `--sensitivity` varies).
    pub ranges: Vec<RangedValue>,
    /// The paths a flag set (their ranges are not varied).
    pub fixed: Vec<String>,
    /// The flags that overrode the case's values, as given (in the summary).
    pub overrides: Vec<String>,
    /// What is asked beyond the run.
    pub spec: RunSpec,
    /// Each run's limits.
    pub budget: Budget,
    /// Worker threads of the evidence's runs (`None`: every core).
    pub jobs: Option<usize>,
}

/// A run's output: its summary (`summary.json`, written and read back through this type), and,
/// when it was just run, the run itself (its time series and droppers; not read back).
#[derive(Debug, Clone, Serialize, Deserialize)]
pub struct RunStudyOutput {
    /// The summary.
    #[serde(flatten)]
    pub summary: RunSummary,
    /// The run (none when read back).
    #[serde(skip)]
    pub run: Option<RunOutput>,
    /// The error-level events the user accepted (not read back: a report shows every event).
    #[serde(skip)]
    pub allowed: AllowedErrors,
}

impl RunStudy {
    /// The set-up of the case within the budget, on the spec's threads.
    pub fn setup(&self) -> Result<Setup, CaseError> {
        let mut s = Setup::from_case_with(&self.case, &self.budget)?;
        s.options.threads = self.spec.threads;
        Ok(s)
    }

    /// Run it, `progress(fraction)` through the main run (returning `false` cancels it).
    pub fn run_with(
        &self,
        progress: &mut dyn FnMut(f64) -> bool,
    ) -> Result<RunStudyOutput, SimError> {
        let setup = self.setup()?;
        let warnings: Vec<String> = setup.warnings.iter().map(|w| w.to_string()).collect();
        let t0 = Instant::now();
        let out = simulate_with(&setup, self.spec.droppers, progress)?;
        let wall = t0.elapsed().as_secs_f64();
        let mut summary = RunSummary::new(&self.case, &out, wall, self.overrides.clone(), warnings);
        if self.spec.verify {
            summary.verification = Some(crate::analysis::verify::verify(
                &self.case,
                &out,
                &self.budget,
                self.jobs,
            )?);
        }
        if let Some(spec) = &self.spec.sensitivity {
            summary.sensitivity = Some(sensitivity(
                &self.case,
                &out,
                &self.ranges,
                &self.fixed,
                spec,
                self.spec.allowed,
                &self.budget,
                self.jobs,
                &|_, _| {},
            )?);
        }
        Ok(RunStudyOutput {
            summary,
            run: Some(out),
            allowed: self.spec.allowed,
        })
    }
}

impl Study for RunStudy {
    const KIND: StudyKind = StudyKind::Run;
    type Output = RunStudyOutput;

    fn check(&self) -> Result<(), CaseError> {
        if let Some(s) = &self.spec.sensitivity {
            s.check()?;
            if self.ranges.is_empty() {
                return Err(crate::input::bounds::inv(
                    "sensitivity",
                    "no ranged value",
                    "the case gives no value a range (mark one as `{ value = …, source = \"…\", range = [low, high], range_source = \"why\" }`)",
                ));
            }
        }
        // The case's own checks and its bound on the work; the model is built by the run.
        self.case.validate()?;
        self.budget.check(&self.case).map(drop)
    }

    fn work(&self) -> usize {
        1000
    }

    fn run(&self, done: &(dyn Fn() + Sync)) -> Result<RunStudyOutput, SimError> {
        let mut shown = 0usize;
        self.run_with(&mut |f| {
            while shown < (f * 1000.0) as usize {
                shown += 1;
                done();
            }
            true
        })
    }

    fn files(&self, o: &RunStudyOutput) -> Vec<StudyFile> {
        let mut files = vec![StudyFile::text(
            "summary.json",
            serde_json::to_string_pretty(&o.summary).unwrap_or_default() + "\n",
        )];
        if let Some(out) = &o.run {
            files.push(StudyFile {
                name: "timeseries.csv".into(),
                bytes: timeseries_csv(out),
            });
            if let Some(d) = &out.droppers {
                files.push(StudyFile::text("droppers.csv", droppers_csv(d)));
                if let Some(h) = &d.history {
                    files.push(StudyFile::text(
                        "dropper_forces.csv",
                        dropper_forces_csv(out, d, h),
                    ));
                }
            }
        }
        files
    }

    fn answer(o: &RunStudyOutput) -> Answer {
        let s = &o.summary;
        let mut a = Answer {
            headline: format!(
                "{} at {} km/h: {} s simulated in {:.2} s wall ({:.1}x real time), {} modes/wire",
                s.case_name,
                s.speed_kmh,
                s.simulated_time_s,
                s.wall_time_s,
                s.simulated_time_s / s.wall_time_s.max(1e-9),
                s.modes_per_wire
            ),
            // The set-up's warnings and the run's verdicts (summary.json's `warnings`).
            warnings: s.warnings.clone(),
            ..Answer::default()
        };
        crate::study::run_answer::statistics(s, &mut a.rows);
        if let Some(v) = &s.verification {
            crate::study::run_answer::verification(v, &mut a.rows);
        }
        if let Some(t) = &s.sensitivity {
            crate::study::run_answer::sensitivity(t, &mut a.rows);
            if let Err(e) = t.check() {
                a.failures.push(format!("{e} (the outputs are written)"));
            }
        }
        if let Some(out) = &o.run {
            if let Some(d) = &out.droppers {
                crate::study::run_answer::droppers(d, out, &mut a.rows, &mut a.warnings);
            }
            // Error-level events: each kind a warning when accepted, else the first refused
            // one refuses the run (its outputs written).
            let errors = run_errors(out);
            for e in errors.iter().filter(|e| o.allowed.allows(e.kind)) {
                a.warnings
                    .push(format!("{} (allowed by {})", e.message, e.kind.flag()));
            }
            if let Some(e) = o.allowed.first_refused(&errors) {
                a.failures.insert(
                    0,
                    format!(
                        "{} (the outputs are written; give {} to accept the run)",
                        e.message,
                        e.kind.flag()
                    ),
                );
            }
        }
        a
    }
}

/// `timeseries.csv`: the columns of [`timeseries_columns`], each value with its decimals.
pub fn timeseries_csv(out: &RunOutput) -> Vec<u8> {
    let cols = timeseries_columns(out);
    // The names are validated (no comma, quote or line break): a plain header line.
    let header: Vec<&str> = cols.iter().map(|c| c.name.as_str()).collect();
    let mut text = header.join(",").into_bytes();
    text.push(b'\n');
    for k in 0..out.time_s.len() {
        for (j, c) in cols.iter().enumerate() {
            if j > 0 {
                text.push(b',');
            }
            push_fixed(&mut text, c.values[k], c.decimals);
        }
        text.push(b'\n');
    }
    text
}

/// `droppers.csv`: each dropper's position, wire, static tension, extremes, slack steps,
/// rainflow cycles, largest range and Miner's damage (when the case gives an S–N curve).
fn droppers_csv(d: &DropperRun) -> String {
    let mut s = String::from(
        "dropper,x_m,wire,preload_n,min_n,max_n,slack_steps,cycles,max_range_n,damage\n",
    );
    for (i, f) in d.droppers.iter().enumerate() {
        let _ = writeln!(
            s,
            "{i},{:.3},{},{:.3},{:.3},{:.3},{},{},{:.3},{}",
            f.x_m,
            csv_field(&f.wire),
            f.preload_n,
            f.min_n,
            f.max_n,
            f.slack_steps,
            f.cycles,
            f.max_range_n,
            f.damage.map_or(String::new(), |v| format!("{v:e}"))
        );
    }
    s
}

/// A CSV field, quoted when it holds a comma, a quote or a line break (the csv crate's rule).
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// `dropper_forces.csv`: the time and every dropper's tension at every step, N.
fn dropper_forces_csv(out: &RunOutput, d: &DropperRun, h: &[f64]) -> String {
    let n = d.droppers.len();
    let mut s = String::from("time_s");
    for (i, f) in d.droppers.iter().enumerate() {
        let _ = write!(s, ",d{i}_at_{:.2}m_n", f.x_m);
    }
    s.push('\n');
    for (k, t) in out.time_s.iter().enumerate() {
        let _ = write!(s, "{t:.6}");
        for v in &h[k * n..(k + 1) * n] {
            let _ = write!(s, ",{v:.3}");
        }
        s.push('\n');
    }
    s
}

/// `x` with `decimals` digits after the point, the bytes of `format!("{x:.decimals$}")` (the
/// correctly rounded decimal of the binary value; `-` kept on a negative value that rounds to
/// zero), at a fraction of its cost: `timeseries.csv` holds a few numbers per step of every run.
/// The fast path scales by 10^decimals once (one rounding, at most half an ulp of the product
/// `v`) and takes the nearest integer, which is the correctly rounded one whenever `v` lies
/// further than 4 ulps from a half-integer; near a half-integer, for large or non-finite values
/// and beyond 9 decimals it formats as `format!` does (tested against it).
pub fn push_fixed(out: &mut Vec<u8>, x: f64, decimals: usize) {
    const POW10: [f64; 10] = [1.0, 1e1, 1e2, 1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9];
    const IPOW10: [u64; 10] = [
        1,
        10,
        100,
        1_000,
        10_000,
        100_000,
        1_000_000,
        10_000_000,
        100_000_000,
        1_000_000_000,
    ];
    if decimals < POW10.len() && x.is_finite() {
        let v = x.abs() * POW10[decimals];
        let half_gap = (v - v.floor() - 0.5).abs();
        if v < 4.5e15 && half_gap > 4.0 * f64::EPSILON * v.max(1.0) {
            let n = v.round() as u64;
            if x.is_sign_negative() {
                out.push(b'-');
            }
            let mut buf = itoa::Buffer::new();
            out.extend_from_slice(buf.format(n / IPOW10[decimals]).as_bytes());
            if decimals > 0 {
                out.push(b'.');
                let frac = buf.format(n % IPOW10[decimals]).as_bytes();
                out.extend(std::iter::repeat_n(b'0', decimals - frac.len()));
                out.extend_from_slice(frac);
            }
            return;
        }
    }
    use std::io::Write as _;
    let _ = write!(out, "{x:.decimals$}");
}
