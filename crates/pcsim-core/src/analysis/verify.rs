//! A run's numerical and modelling evidence (issue 42, item 1: `pcsim run --verify`): the case
//! run again refined (twice the modes, half the time step) and once with the contact twice as
//! stiff (a model check: the penalty stiffness of Eq. 19 is a modelling choice, not a measured
//! value), each EN 50318 statistic beside its refined value, the change, and whether the change
//! is within the statistic's tolerance.
//!
//! A statistic is *converged* when refining the discretisation moves it by no more than its
//! tolerance ([`tolerance_percent`]). The change is relative to the statistic's scale
//! ([`scale`]): its own magnitude, but for a minimum the mean contact force (a statistical
//! minimum near zero would otherwise turn a fraction of a newton into hundreds of per cent),
//! and for the uplift no less than 1 mm. The contact-stiffness check is reported beside, never folded
//! into the verdict: it says how much a choice of model moves the number, not whether the
//! numbers of that model are converged.

use serde::{Deserialize, Serialize};

use crate::analysis::record::{simulate, RunOutput};
use crate::analysis::stats::ContactStats;
use crate::compile::budget::Budget;
use crate::compile::Setup;
use crate::error::{CaseError, SimError};
use crate::input::case::Case;

/// The refinement's factors: modes × 2, Δt × ½; the model check's contact stiffness × 2.
pub const MODES_FACTOR: f64 = 2.0;
/// The refined time step over the case's.
pub const DT_FACTOR: f64 = 0.5;
/// The model check's contact stiffness over the case's.
pub const CONTACT_FACTOR: f64 = 2.0;

/// The statistics verified, with their units (the names of `summary.json`'s `stats`): the
/// EN 50318 statistics and the uplift, the first nine of [`VERDICT_STATISTICS`].
pub const STATISTICS: &[(&str, &str)] = VERDICT_STATISTICS.split_at(9).0;

/// The tolerance a statistic must be converged to, % of its scale: the mean 0.5 % and σ 2 %
/// (the convergence the time step and the mode count were chosen for, docs/validation.md
/// "Convergence"); Fm ± 3σ 2 % (they follow the two); the bands, the extremes and the uplift
/// 5 % (a guess, stated: single samples and band-limited parts converge more slowly, and EN
/// 50318's ranges for them are wider).
pub fn tolerance_percent(statistic: &str) -> f64 {
    match statistic {
        "mean_n" => 0.5,
        "std_n" | "stat_max_n" | "stat_min_n" => 2.0,
        _ => 5.0,
    }
}

/// The verified statistic of a validation quantity (`input/targets.rs` `QUANTITIES`: `mean`,
/// `std`, …), none for the quantities the verification has no tolerance for.
pub fn statistic_of_quantity(quantity: &str) -> Option<&'static str> {
    Some(match quantity {
        "mean" => "mean_n",
        "std" => "std_n",
        "std_0_5hz" => "std_0_5hz_n",
        "std_5_20hz" => "std_5_20hz_n",
        "stat_max" => "stat_max_n",
        "stat_min" => "stat_min_n",
        "actual_max" => "actual_max_n",
        "actual_min" => "actual_min_n",
        "max_uplift_at_support_mm" => "max_uplift_at_support_mm",
        _ => return None,
    })
}

/// Every statistic that decides a verdict, as the studies that vary a case report them
/// (`--sensitivity`, Monte Carlo): [`STATISTICS`], the share of contact lost and, where the
/// lateral motion is modelled, the contact point's largest offset, the head's smallest margin
/// and the contact wire's largest blow-out (a study leaves out those a run has no value of).
pub const VERDICT_STATISTICS: [(&str, &str); 13] = [
    ("mean_n", "N"),
    ("std_n", "N"),
    ("std_0_5hz_n", "N"),
    ("std_5_20hz_n", "N"),
    ("stat_max_n", "N"),
    ("stat_min_n", "N"),
    ("actual_max_n", "N"),
    ("actual_min_n", "N"),
    ("max_uplift_at_support_mm", "mm"),
    ("loss_of_contact_percent", "%"),
    ("max_lateral_offset_mm", "mm"),
    ("min_head_margin_mm", "mm"),
    ("max_contact_wire_blowout_mm", "mm"),
];

/// A statistic's value by its name (none: not a statistic, or one the run has no value of, a
/// lateral one of a vertical run).
pub fn statistic(s: &ContactStats, name: &str) -> Option<f64> {
    Some(match name {
        "loss_of_contact_percent" => s.loss_of_contact_percent,
        "contact_point_range_mm" => s.contact_point_range_mm,
        "max_lateral_offset_mm" => return s.max_lateral_offset_mm,
        "min_head_margin_mm" => return s.min_head_margin_mm,
        "max_contact_wire_blowout_mm" => return s.max_contact_wire_blowout_mm,
        "mean_n" => s.mean_n,
        "std_n" => s.std_n,
        "std_0_5hz_n" => s.std_0_5hz_n,
        "std_5_20hz_n" => s.std_5_20hz_n,
        "stat_max_n" => s.stat_max_n,
        "stat_min_n" => s.stat_min_n,
        "actual_max_n" => s.actual_max_n,
        "actual_min_n" => s.actual_min_n,
        "max_uplift_at_support_mm" => s.max_uplift_at_support_mm,
        _ => return None,
    })
}

/// The scale a change of statistic `name` (value `x`, mean force `fm`) is measured against:
/// a minimum's is the mean force (a minimum near zero is no scale), a force's its magnitude but
/// no less than a tenth of the mean force, the uplift's its magnitude but no less than 1 mm.
pub fn scale(name: &str, x: f64, fm: f64) -> f64 {
    if name.ends_with("_mm") {
        x.abs().max(1.0)
    } else if name.ends_with("min_n") {
        fm.abs().max(x.abs()).max(1e-9)
    } else {
        x.abs().max(0.1 * fm.abs()).max(1e-9)
    }
}

/// One statistic of one pantograph, checked.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct StatisticCheck {
    /// Its name (as in `summary.json`'s `stats`).
    pub statistic: String,
    /// Its unit.
    pub unit: String,
    /// The run's value.
    pub value: f64,
    /// The refined run's value.
    pub refined: f64,
    /// `(refined − value) / scale`, %.
    pub change_percent: f64,
    /// The tolerance, %.
    pub tolerance_percent: f64,
    /// Whether `|change| ≤ tolerance`.
    pub converged: bool,
    /// The value with the contact twice as stiff (the model check).
    pub stiff_contact: f64,
    /// `(stiff_contact − value) / scale`, %.
    pub stiff_contact_change_percent: f64,
}

/// One pantograph's checks.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct PantographCheck {
    /// Its name.
    pub name: String,
    /// Its statistics, in [`STATISTICS`]' order.
    pub statistics: Vec<StatisticCheck>,
}

/// What each run was.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Discretisation {
    /// Modes per wire.
    pub modes_per_wire: usize,
    /// Time step, s.
    pub dt_s: f64,
    /// Contact stiffness, N/m.
    pub contact_stiffness_n_per_m: f64,
}

/// The verification of a run (`summary.json`'s `verification`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Verification {
    /// The run's own discretisation.
    pub run: Discretisation,
    /// The refined run's (twice the modes, half the step).
    pub refined: Discretisation,
    /// The model check's (the contact twice as stiff; its time step halved again when the
    /// stiffer contact needs it, said here).
    pub stiff_contact: Discretisation,
    /// Per pantograph that crossed the analysis section.
    pub pantographs: Vec<PantographCheck>,
    /// The statistics not converged to their tolerance, as sentences (empty: all are).
    pub not_converged: Vec<String>,
}

impl Verification {
    /// The check of pantograph `name`'s statistic `statistic`, if verified.
    pub fn check(&self, pantograph: &str, statistic: &str) -> Option<&StatisticCheck> {
        self.pantographs
            .iter()
            .find(|p| p.name == pantograph)?
            .statistics
            .iter()
            .find(|s| s.statistic == statistic)
    }
}

/// The refined case: twice the modes (`run.modes` or `run.modes_per_m`), half the time step.
pub fn refined_case(case: &Case) -> Case {
    let mut c = case.clone();
    match (c.run.modes, c.run.modes_per_m) {
        (Some(n), _) => c.run.modes = Some((n as f64 * MODES_FACTOR).round() as usize),
        (None, Some(d)) => c.run.modes_per_m = Some(d * MODES_FACTOR),
        (None, None) => {}
    }
    c.run.dt_s *= DT_FACTOR;
    c
}

/// The model check's case: the contact twice as stiff (a collector strip's own contact
/// stiffness too, where it gives one).
pub fn stiff_contact_case(case: &Case) -> Case {
    let mut c = case.clone();
    c.contact.stiffness_n_per_m *= CONTACT_FACTOR;
    for p in &mut c.pantographs {
        if let crate::input::case::PantographCase::Lumped { strips, .. } = p {
            for k in strips
                .iter_mut()
                .filter_map(|s| s.contact_stiffness_n_per_m.as_mut())
            {
                *k *= CONTACT_FACTOR;
            }
        }
    }
    c
}

/// The set-up of the model check: the stiffer contact at the case's time step, or, where the
/// stability check refuses that step, at half of it (then a quarter).
fn stiff_setup(case: &Case, budget: &Budget) -> Result<Setup, CaseError> {
    let mut c = stiff_contact_case(case);
    let mut last = None;
    for _ in 0..3 {
        match Setup::from_case_with(&c, budget) {
            Ok(s) => return Ok(s),
            Err(CaseError::Invalid { ref field, .. }) if field == "run.dt_s" => {
                last = Some(Setup::from_case_with(&c, budget).unwrap_err());
                c.run.dt_s *= 0.5;
            }
            Err(e) => return Err(e),
        }
    }
    Err(last.expect("three refusals"))
}

fn discretisation(setup: &Setup, case_stiffness: f64) -> Discretisation {
    Discretisation {
        modes_per_wire: setup.model.n_modes(),
        dt_s: setup.options.dt_s,
        contact_stiffness_n_per_m: case_stiffness,
    }
}

/// The two runs of a verification of `case` (side by side on `jobs` threads): the refined run
/// and the model check, with the three discretisations (the case's, the refined, the model
/// check's).
pub fn verification_runs(
    case: &Case,
    budget: &Budget,
    jobs: Option<usize>,
) -> Result<(RunOutput, RunOutput, [Discretisation; 3]), SimError> {
    let base = Setup::from_case_with(case, budget)?;
    let refined_case = refined_case(case);
    let refined = Setup::from_case_with(&refined_case, budget)?;
    let stiff = stiff_setup(case, budget)?;
    let runs = crate::analysis::sweep::parallel_map(&[&refined, &stiff], jobs, |s| {
        simulate(s, &mut |_| true)
    });
    let mut runs = runs.into_iter();
    let r = runs.next().expect("two runs")?;
    let k = runs.next().expect("two runs")?;
    Ok((
        r,
        k,
        [
            discretisation(&base, case.contact.stiffness_n_per_m),
            discretisation(&refined, case.contact.stiffness_n_per_m),
            discretisation(&stiff, case.contact.stiffness_n_per_m * CONTACT_FACTOR),
        ],
    ))
}

/// Verify `case`, whose run gave `out`: the refined run and the model check (run side by side
/// on `jobs` threads), and each statistic beside its refined and stiff-contact values.
pub fn verify(
    case: &Case,
    out: &RunOutput,
    budget: &Budget,
    jobs: Option<usize>,
) -> Result<Verification, SimError> {
    let (r, k, d) = verification_runs(case, budget, jobs)?;
    Ok(compare_runs(out, &r, &k, d))
}

/// The checks of run `out` against its refined run `refined` and its model check `stiff`.
pub fn compare_runs(
    out: &RunOutput,
    refined: &RunOutput,
    stiff: &RunOutput,
    [run, refined_d, stiff_d]: [Discretisation; 3],
) -> Verification {
    let mut pantographs = Vec::new();
    let mut not_converged = Vec::new();
    for (p, (r, k)) in out
        .pantographs
        .iter()
        .zip(refined.pantographs.iter().zip(&stiff.pantographs))
    {
        let (Some(s), Some(sr), Some(sk)) = (&p.stats, &r.stats, &k.stats) else {
            continue;
        };
        let mut statistics = Vec::new();
        for (name, unit) in STATISTICS {
            let (x, xr, xk) = (
                statistic(s, name).expect("listed"),
                statistic(sr, name).expect("listed"),
                statistic(sk, name).expect("listed"),
            );
            let sc = scale(name, x, s.mean_n);
            let change = 100.0 * (xr - x) / sc;
            let tol = tolerance_percent(name);
            let converged = change.abs() <= tol;
            if !converged {
                not_converged.push(format!(
                    "pantograph {}: {name} {x:.4} {unit} moves to {xr:.4} {unit} refined ({change:+.2} %, tolerance {tol} %)",
                    p.name
                ));
            }
            statistics.push(StatisticCheck {
                statistic: (*name).into(),
                unit: (*unit).into(),
                value: x,
                refined: xr,
                change_percent: change,
                tolerance_percent: tol,
                converged,
                stiff_contact: xk,
                stiff_contact_change_percent: 100.0 * (xk - x) / sc,
            });
        }
        pantographs.push(PantographCheck {
            name: p.name.clone(),
            statistics,
        });
    }
    Verification {
        run,
        refined: refined_d,
        stiff_contact: stiff_d,
        pantographs,
        not_converged,
    }
}
