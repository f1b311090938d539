//! Validation against published acceptance ranges (`data/validation-targets.toml`, embedded):
//! which preset, which targets, the runs they need, and the table of value against range.

use serde::Serialize;

use crate::analysis::record::{run_case, RunOutput};
use crate::analysis::stats::ContactStats;
use crate::analysis::sweep::parallel_map;
use crate::error::{CaseError, SimError};
use crate::input::case::Case;
use crate::input::presets;
pub use crate::input::targets::{
    target_cases, targets_file, TargetCase, TargetsFile, QUANTITIES, TARGETS_TOML,
};

/// One row of a validation table.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Row {
    /// The quantity's name, as in the targets.
    pub quantity: String,
    /// pcsim's value.
    pub value: f64,
    /// Unit of the value and the range: N, mm or %.
    pub unit: &'static str,
    /// The target range [low, high].
    pub range: [f64; 2],
    /// Whether the value lies in the range.
    pub pass: bool,
    /// The seed paper's own value, where the targets give one.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub paper_value: Option<f64>,
    /// Whether the paper's value lies in the range.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub paper_pass: Option<bool>,
    /// With `--verify`: the row under the refined run and the stiffer contact.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub verification: Option<RowVerification>,
}

/// A validation row under its run's verification (`pcsim validate --verify`, issue 42).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RowVerification {
    /// The refined run's value (twice the modes, half the step).
    pub refined: f64,
    /// Whether it lies in the range.
    pub refined_pass: bool,
    /// The value with the contact twice as stiff (the model check).
    pub stiff_contact: f64,
    /// Whether it lies in the range.
    pub stiff_contact_pass: bool,
    /// Whether the statistic is converged to its tolerance (none: a quantity the verification
    /// has no tolerance for: the contact-point range, the loss of contact).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub converged: Option<bool>,
    /// Whether the verdict stands: the refined run gives the same one and the value is not
    /// found unconverged (the model check is reported beside, never folded in).
    pub established: bool,
}

/// A speed case of a validation.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CaseRows {
    /// Train speed, km/h.
    pub speed_kmh: f64,
    /// "leading" or "trailing" where the targets distinguish pantographs.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub pantograph: Option<String>,
    /// One row per quantity.
    pub rows: Vec<Row>,
    /// Quantities the targets name without a range, with pcsim's value: not compared (a range
    /// is never invented).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub missing: Vec<Unchecked>,
}

/// A quantity the targets name without a range: pcsim's value, unchecked.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Unchecked {
    /// The quantity's name.
    pub quantity: String,
    /// pcsim's value.
    pub value: f64,
    /// Its unit: N, mm or %.
    pub unit: &'static str,
}

/// The value of quantity `q` (one of [`QUANTITIES`]) in `s`.
pub fn stat_value(s: &ContactStats, q: &str) -> Option<f64> {
    Some(match q {
        "mean" => s.mean_n,
        "std" => s.std_n,
        "std_0_5hz" => s.std_0_5hz_n,
        "std_5_20hz" => s.std_5_20hz_n,
        "stat_max" => s.stat_max_n,
        "stat_min" => s.stat_min_n,
        "actual_max" => s.actual_max_n,
        "actual_min" => s.actual_min_n,
        "contact_point_range_mm" => s.contact_point_range_mm,
        "max_uplift_at_support_mm" => s.max_uplift_at_support_mm,
        "loss_of_contact_percent" => s.loss_of_contact_percent,
        _ => return None,
    })
}

/// The unit of quantity `q`.
pub fn unit_of(q: &str) -> &'static str {
    if q.ends_with("_mm") {
        "mm"
    } else if q.ends_with("_percent") {
        "%"
    } else {
        "N"
    }
}

/// Compare statistics with a target case. Values are compared after rounding to the ranges'
/// own precision (0.1 N/mm/%); a single-value range such as `[169, 169]` gets ±0.5.
pub fn compare(stats: &ContactStats, target: &TargetCase) -> CaseRows {
    let rows = target
        .ranges
        .iter()
        .filter_map(|(q, r)| {
            let v = stat_value(stats, q)?;
            let inside = |v: f64| {
                let (lo, hi) = if r[0] == r[1] && r[0] != 0.0 {
                    (r[0] - 0.5, r[1] + 0.5)
                } else {
                    (r[0].min(r[1]), r[0].max(r[1]))
                };
                let vr = (v * 10.0).round() / 10.0;
                vr >= lo && vr <= hi
            };
            let paper_value = target.paper.iter().find(|(k, _)| k == q).map(|(_, v)| *v);
            Some(Row {
                quantity: q.clone(),
                value: v,
                unit: unit_of(q),
                range: *r,
                pass: inside(v),
                paper_value,
                paper_pass: paper_value.map(inside),
                verification: None,
            })
        })
        .collect();
    CaseRows {
        speed_kmh: target.speed_kmh,
        pantograph: target.pantograph.clone(),
        rows,
        missing: target
            .missing
            .iter()
            .filter_map(|q| {
                Some(Unchecked {
                    quantity: q.clone(),
                    value: stat_value(stats, q)?,
                    unit: unit_of(q),
                })
            })
            .collect(),
    }
}

/// A validation pcsim knows: its preset and its table of targets.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Validation {
    /// Name on the command line.
    pub name: &'static str,
    /// The preset it runs.
    pub preset: &'static str,
    /// The table of targets it reads.
    pub table: &'static str,
    /// Title printed above the table.
    pub title: &'static str,
}

/// Every validation, by name.
pub const VALIDATIONS: &[Validation] = &[
    Validation {
        name: "en50318-2002",
        preset: "en50318-2002",
        table: "en50318_2002",
        title: "EN 50318:2002 validation",
    },
    Validation {
        name: "seed-table1",
        preset: "stitched-2018-like",
        table: "seed_table1",
        title: "The seed paper's Table 1 (ranges quoted there from EN 50318:2018; our model is built from public data, not the standard's)",
    },
];

/// The runs a validation needs and how its targets map onto them.
#[derive(Debug, Clone)]
pub struct ValidationPlan {
    /// Title printed above the table.
    pub title: String,
    /// What it runs, as printed: the preset's name (`preset \`…\``) or the user's case
    /// ([`ValidationPlan::on_case`]).
    pub runs_on: String,
    /// Where the ranges come from, as printed.
    pub ranges_from: String,
    /// Its targets, one per speed (and pantograph).
    pub targets: Vec<TargetCase>,
    /// One case per distinct target speed (targets within 1e-9 km/h share a run).
    pub cases: Vec<Case>,
    /// For each target, the index of its run in `cases`.
    pub run_of_target: Vec<usize>,
}

/// The result: the JSON of `pcsim validate --json`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ValidationReport {
    /// Whether every row passes.
    pub all_pass: bool,
    /// The rows of every speed case.
    pub cases: Vec<CaseRows>,
    /// With `--verify`: each run's verification (twice the modes and half the step; the
    /// contact twice as stiff), one per run of the plan.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub verification: Vec<crate::analysis::verify::Verification>,
    /// With `--verify`: the rows whose verdict the verification does not establish.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub not_established: Vec<String>,
}

impl ValidationPlan {
    /// The plan of validation `name`.
    pub fn new(name: &str) -> Result<Self, CaseError> {
        let validation =
            *VALIDATIONS
                .iter()
                .find(|v| v.name == name)
                .ok_or_else(|| CaseError::Invalid {
                    field: "validation".into(),
                    value: name.into(),
                    reason: format!(
                        "unknown validation (available: {})",
                        VALIDATIONS
                            .iter()
                            .map(|v| v.name)
                            .collect::<Vec<_>>()
                            .join(", ")
                    ),
                })?;
        let targets = target_cases(validation.table)?;
        Self::of(
            validation.title.into(),
            presets::load(validation.preset)?.0,
            format!("preset `{}`", validation.preset),
            "data/validation-targets.toml".into(),
            targets,
        )
    }

    /// The plan of a user's targets file (`pcsim validate --targets FILE`, [`targets_file`]),
    /// read from `text`; `path` names it in the report.
    pub fn from_targets(text: &str, path: &str) -> Result<Self, CaseError> {
        Self::from_targets_on(text, path, None)
    }

    /// A user's targets file run on the preset it names, or on a user's case `on = (case,
    /// label)` (`pcsim validate CASE.toml --targets FILE`): then the file need name no preset;
    /// one it names is said not to be run (the report's "runs on" names both), never ignored
    /// silently. Without a case, a file that names no preset is refused, saying how to give one.
    pub fn from_targets_on(
        text: &str,
        path: &str,
        on: Option<(Case, &str)>,
    ) -> Result<Self, CaseError> {
        let f = targets_file(text)?;
        let title = if f.source.is_empty() {
            format!("Targets `{}`", f.table)
        } else {
            format!("Targets `{}` ({})", f.table, f.source)
        };
        let (base, runs_on) = match (on, &f.preset) {
            (Some((case, label)), None) => (case, format!("case `{label}`")),
            (Some((case, label)), Some(p)) => (
                case,
                format!("case `{label}` (the targets name preset `{p}`: it is not run, the case is)"),
            ),
            (None, Some(p)) => (presets::load(p)?.0, format!("preset `{p}`")),
            (None, None) => {
                return Err(CaseError::Invalid {
                    field: format!("{}.preset", f.table),
                    value: "missing".into(),
                    reason: "name the preset the targets are for (preset = \"…\"), or run them on your case: pcsim validate CASE.toml --targets FILE".into(),
                })
            }
        };
        Self::of(title, base, runs_on, path.into(), f.cases)
    }

    /// The same targets run on a user's case instead of the preset they name (`pcsim validate
    /// CASE.toml`): the case at each target's speed, everything else as the case gives it.
    /// `label` names the case in the report (its path). The ranges stay those of the targets:
    /// the caller says what they were written for.
    pub fn on_case(self, base: Case, label: &str) -> Result<Self, CaseError> {
        Self::of(
            self.title,
            base,
            format!("case `{label}`"),
            self.ranges_from,
            self.targets,
        )
    }

    fn of(
        title: String,
        base: Case,
        runs_on: String,
        ranges_from: String,
        mut targets: Vec<TargetCase>,
    ) -> Result<Self, CaseError> {
        targets.sort_by(|a, b| {
            a.speed_kmh
                .total_cmp(&b.speed_kmh)
                .then(a.pantograph.cmp(&b.pantograph))
        });
        let mut speeds: Vec<f64> = Vec::new();
        let mut run_of_target = Vec::with_capacity(targets.len());
        for t in &targets {
            let k = match speeds.iter().position(|&v| (v - t.speed_kmh).abs() < 1e-9) {
                Some(k) => k,
                None => {
                    speeds.push(t.speed_kmh);
                    speeds.len() - 1
                }
            };
            run_of_target.push(k);
        }
        let cases = speeds
            .iter()
            .map(|&v| {
                let mut c = base.clone();
                c.run.speed_kmh = v;
                c
            })
            .collect();
        Ok(Self {
            title,
            runs_on,
            ranges_from,
            targets,
            cases,
            run_of_target,
        })
    }

    /// Compare the runs (one per entry of `cases`, in order) with the targets.
    pub fn assemble(&self, runs: &[RunOutput]) -> Result<ValidationReport, CaseError> {
        let mut cases = Vec::with_capacity(self.targets.len());
        for (t, &k) in self.targets.iter().zip(&self.run_of_target) {
            let out = &runs[k];
            let p = match &t.pantograph {
                Some(name) => out
                    .pantographs
                    .iter()
                    .find(|p| &p.name == name)
                    .ok_or_else(|| CaseError::Invalid {
                        field: "pantographs".into(),
                        value: name.clone(),
                        reason: format!("{} has no pantograph of that name", self.runs_on),
                    })?,
                None => &out.pantographs[0],
            };
            let stats = p.stats.ok_or_else(|| CaseError::Invalid {
                field: "run.analysis_m".into(),
                value: format!("{:?}", out.analysis_m),
                reason: format!(
                    "the {} pantograph did not cross the analysis section",
                    p.name
                ),
            })?;
            cases.push(compare(&stats, t));
        }
        Ok(ValidationReport {
            // A missing range is not a pass: nothing was checked.
            all_pass: cases
                .iter()
                .all(|c| c.missing.is_empty() && c.rows.iter().all(|r| r.pass)),
            cases,
            verification: Vec::new(),
            not_established: Vec::new(),
        })
    }

    /// Verify `report` (assembled from `runs`): each run of the plan again refined and with the
    /// contact twice as stiff (`analysis/verify.rs`), each row with its value and verdict under
    /// both, and the rows whose verdict the verification does not establish. The runs share
    /// `jobs` threads.
    pub fn verify(
        &self,
        runs: &[RunOutput],
        report: &mut ValidationReport,
        budget: &crate::compile::Budget,
        jobs: Option<usize>,
    ) -> Result<(), SimError> {
        use crate::analysis::verify::{compare_runs, verification_runs};
        let checks: Vec<_> =
            parallel_map(&self.cases, jobs, |c| verification_runs(c, budget, None))
                .into_iter()
                .collect::<Result<_, _>>()?;
        report.verification = runs
            .iter()
            .zip(&checks)
            .map(|(out, (r, k, d))| compare_runs(out, r, k, *d))
            .collect();
        let (refined, stiff): (Vec<RunOutput>, Vec<RunOutput>) =
            checks.into_iter().map(|(r, k, _)| (r, k)).unzip();
        let (refined, stiff) = (self.assemble(&refined)?, self.assemble(&stiff)?);
        report.not_established.clear();
        for (k, c) in report.cases.iter_mut().enumerate() {
            let v = &report.verification[self.run_of_target[k]];
            let who = c.pantograph.clone();
            for (i, row) in c.rows.iter_mut().enumerate() {
                let (r, s) = (&refined.cases[k].rows[i], &stiff.cases[k].rows[i]);
                let name = who
                    .as_deref()
                    .unwrap_or_else(|| v.pantographs.first().map_or("", |p| p.name.as_str()));
                let converged = crate::analysis::verify::statistic_of_quantity(&row.quantity)
                    .and_then(|q| v.check(name, q))
                    .map(|c| c.converged);
                let established = r.pass == row.pass && converged != Some(false);
                if !established {
                    report.not_established.push(format!(
                        "{} km/h{}: {} {:.4} {} ({}) is {:.4} refined ({}){}",
                        c.speed_kmh,
                        who.as_deref().map(|p| format!(", {p}")).unwrap_or_default(),
                        row.quantity,
                        row.value,
                        row.unit,
                        if row.pass { "pass" } else { "FAIL" },
                        r.value,
                        if r.pass { "pass" } else { "FAIL" },
                        if converged == Some(false) {
                            ", not converged to its tolerance"
                        } else {
                            ""
                        }
                    ));
                }
                row.verification = Some(RowVerification {
                    refined: r.value,
                    refined_pass: r.pass,
                    stiff_contact: s.value,
                    stiff_contact_pass: s.pass,
                    converged,
                    established,
                });
            }
        }
        Ok(())
    }
}

/// Run validation `name` (its runs side by side on up to `jobs` threads; each run is
/// single-threaded and deterministic) and compare with the targets.
pub fn validate(
    name: &str,
    jobs: Option<usize>,
) -> Result<(ValidationPlan, ValidationReport, Vec<RunOutput>), SimError> {
    let plan = ValidationPlan::new(name)?;
    let runs: Vec<RunOutput> = parallel_map(&plan.cases, jobs, |c| run_case(c, &mut |_| true))
        .into_iter()
        .collect::<Result<_, _>>()?;
    let report = plan.assemble(&runs)?;
    Ok((plan, report, runs))
}
