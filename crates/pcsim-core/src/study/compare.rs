//! A run beside a recording car's measured contact force (`pcsim compare`; issue 22, item 4) as a
//! study (issue 52): the run's force record and the measurement in, the comparison of
//! [`crate::analysis::compare`] out (filtered alike, aligned, side by side), written as its
//! tables and `compare.json`, and the answer the terminal and the report open with. The front
//! end reads the run's directory and the measured file, and fills [`CompareStudy`].

use std::fmt::Write as _;

use serde::{Deserialize, Serialize};

use crate::analysis::compare::{check_inputs, compare, Comparison};
use crate::error::{CaseError, SimError};
use crate::input::measured::MeasuredForce;
use crate::study::contract::{Answer, Study, StudyFile, StudyKind};

/// The comparison's inputs: one pantograph's force record of a run, and a measurement.
#[derive(Debug, Clone, PartialEq)]
pub struct CompareStudy {
    /// The run's pantograph compared.
    pub pantograph: String,
    /// The run's case.
    pub case_name: String,
    /// The run's contact-point positions, m.
    pub position_m: Vec<f64>,
    /// The run's contact force at them, N.
    pub force_n: Vec<f64>,
    /// The run's speed, km/h.
    pub speed_kmh: f64,
    /// The run's analysis section, m.
    pub analysis_m: [f64; 2],
    /// The run's support positions (the span profile's origins), m.
    pub supports_m: Vec<f64>,
    /// The measurement.
    pub measured: MeasuredForce,
    /// Where the measurement came from (its file).
    pub measured_name: String,
    /// The alignment is searched within ± this length, m.
    pub search_m: f64,
}

/// A run's supports, the span profile's origins, m: a line's own (`supports_m`, as summary.json
/// gives them), else the multiples of its repeating span from 0 to a span past the last position
/// `last_m`, else none (the one derivation, for every front end).
pub fn support_positions(supports_m: &[f64], span_m: Option<f64>, last_m: f64) -> Vec<f64> {
    if !supports_m.is_empty() {
        return supports_m.to_vec();
    }
    match span_m {
        Some(s) if s > 0.0 && last_m.is_finite() => (0..=((last_m.max(0.0) / s).ceil() as usize
            + 1))
            .map(|k| k as f64 * s)
            .collect(),
        _ => Vec::new(),
    }
}

/// What a comparison gives (`compare.json`, written and read back through this type; `pcsim
/// schema compare`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct CompareOutput {
    /// The run's pantograph compared.
    pub pantograph: String,
    /// The run's case.
    pub case_name: String,
    /// Where the measurement came from.
    pub measured: String,
    /// The measurement's spacing, m.
    pub spacing_m: f64,
    /// The comparison.
    pub comparison: Comparison,
}

impl Study for CompareStudy {
    const KIND: StudyKind = StudyKind::Compare;
    type Output = CompareOutput;

    fn check(&self) -> Result<(), CaseError> {
        check_inputs(
            (&self.position_m, &self.force_n),
            &self.measured,
            self.speed_kmh / 3.6,
            self.search_m,
        )
    }

    fn work(&self) -> usize {
        1
    }

    fn run(&self, done: &(dyn Fn() + Sync)) -> Result<CompareOutput, SimError> {
        let comparison = compare(
            (&self.position_m, &self.force_n),
            &self.measured,
            self.speed_kmh / 3.6,
            self.analysis_m,
            self.search_m,
            &self.supports_m,
        )?;
        done();
        Ok(CompareOutput {
            pantograph: self.pantograph.clone(),
            case_name: self.case_name.clone(),
            measured: self.measured_name.clone(),
            spacing_m: self.measured.spacing_m,
            comparison,
        })
    }

    fn files(&self, o: &CompareOutput) -> Vec<StudyFile> {
        let c = &o.comparison;
        let mut stats = String::from("quantity,run,measured,difference\n");
        let _ = writeln!(stats, "shift_m,,{},", c.shift_m);
        let _ = writeln!(stats, "correlation,,{},", c.correlation);
        for w in &c.warnings {
            // A doubtful alignment travels with the numbers it qualifies.
            let _ = writeln!(stats, "warning,,\"{}\",", w.replace('"', "'"));
        }
        for ((name, s), (_, m)) in c.simulated.rows().iter().zip(c.measured.rows()) {
            let _ = writeln!(stats, "{name},{s},{m},{}", m - s);
        }
        let mut force = String::from("position_m,run_force_filtered_n,measured_force_filtered_n\n");
        for ((x, s), m) in c.position_m.iter().zip(&c.simulated_n).zip(&c.measured_n) {
            let _ = writeln!(force, "{x:.4},{s:.4},{m:.4}");
        }
        let table = |head: &str, rows: &[[f64; 3]]| {
            let mut t = String::from(head);
            for r in rows {
                let _ = writeln!(t, "{},{},{}", r[0], r[1], r[2]);
            }
            t
        };
        vec![
            StudyFile::text("compare_stats.csv", stats),
            StudyFile::text("compare.csv", force),
            StudyFile::text(
                "compare_spectrum.csv",
                table(
                    "frequency_per_m,run_psd_n2_m,measured_psd_n2_m\n",
                    &c.spectrum,
                ),
            ),
            StudyFile::text(
                "compare_profile.csv",
                table(
                    "span_fraction,run_mean_force_n,measured_mean_force_n\n",
                    &c.profile,
                ),
            ),
            StudyFile::text(
                "compare.json",
                serde_json::to_string_pretty(o).unwrap_or_default() + "\n",
            ),
        ]
    }

    fn answer(o: &CompareOutput) -> Answer {
        let c = &o.comparison;
        let mut rows = vec![(
            "0–20 Hz contact force over".to_string(),
            format!(
                "{:?} m ({} samples): run, measured, difference",
                c.section_m, c.simulated.samples
            ),
        )];
        for ((name, s), (_, m)) in c.simulated.rows().iter().zip(c.measured.rows()) {
            rows.push((
                format!("{name:<14}"),
                format!(
                    "{s:>10.2} {m:>10.2} {:>+10.2} N {:>+8.1} %",
                    m - s,
                    100.0 * (m - s) / s.abs().max(1e-9)
                ),
            ));
        }
        Answer {
            headline: format!(
                "the {} pantograph of {} beside the measurement {}: shift {:+.2} m ({} samples of {} m; searched ± {} m), correlation {:.3}",
                o.pantograph,
                o.case_name,
                o.measured,
                c.shift_m,
                c.shift_samples,
                o.spacing_m,
                c.search_m,
                c.correlation
            ),
            rows,
            warnings: c.warnings.clone(),
            failures: Vec::new(),
        }
    }
}
