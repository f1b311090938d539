//! Issue 42, item 1: `--verify`. The verification's refined and stiff-contact values are those of
//! runs made by hand (the case with twice the modes and half the step; with the contact twice as
//! stiff), each change is the stated formula, a statistic is converged exactly when its change is
//! within its tolerance, and `assess` says which rows the verification does not establish.

use crate::common;

use pcsim_core::analysis::assess::{assess, AssessInput, Verdict};
use pcsim_core::analysis::report::RunSummary;
use pcsim_core::analysis::verify::{scale, statistic, tolerance_percent, verify, STATISTICS};
use pcsim_core::compile::Budget;
use pcsim_core::input::criteria;
use pcsim_core::run_case;

#[test]
fn issue_42_1_the_verification_is_the_runs_made_by_hand() {
    let case = common::short_en50318(10, 250.0);
    let out = run_case(&case, &mut |_| true).unwrap();
    let v = verify(&case, &out, &Budget::default(), Some(2)).unwrap();
    // By hand: twice the modes, half the step; and the contact twice as stiff.
    let mut fine = case.clone();
    fine.run.modes = Some(2 * case.n_modes());
    fine.run.modes_per_m = None;
    fine.run.dt_s = 0.5 * case.run.dt_s;
    let mut stiff = case.clone();
    stiff.contact.stiffness_n_per_m *= 2.0;
    let (f, k) = (
        run_case(&fine, &mut |_| true).unwrap(),
        run_case(&stiff, &mut |_| true).unwrap(),
    );
    let (s, sf, sk) = (
        out.pantographs[0].stats.unwrap(),
        f.pantographs[0].stats.unwrap(),
        k.pantographs[0].stats.unwrap(),
    );
    assert_eq!(v.refined.modes_per_wire, 2 * out.n_modes);
    assert_eq!(v.refined.dt_s, 0.5 * out.dt_s);
    assert_eq!(
        v.stiff_contact.contact_stiffness_n_per_m,
        2.0 * case.contact.stiffness_n_per_m
    );
    let p = &v.pantographs[0];
    assert_eq!(p.statistics.len(), STATISTICS.len());
    let mut not = 0;
    for c in &p.statistics {
        let name = c.statistic.as_str();
        let (x, xf, xk) = (
            statistic(&s, name).unwrap(),
            statistic(&sf, name).unwrap(),
            statistic(&sk, name).unwrap(),
        );
        assert_eq!((c.value, c.refined, c.stiff_contact), (x, xf, xk), "{name}");
        let sc = scale(name, x, s.mean_n);
        assert_eq!(c.change_percent, 100.0 * (xf - x) / sc, "{name}");
        assert_eq!(
            c.stiff_contact_change_percent,
            100.0 * (xk - x) / sc,
            "{name}"
        );
        assert_eq!(c.tolerance_percent, tolerance_percent(name));
        assert_eq!(
            c.converged,
            c.change_percent.abs() <= c.tolerance_percent,
            "{name}"
        );
        not += usize::from(!c.converged);
    }
    assert_eq!(v.not_converged.len(), not);
    // A minimum is measured against the mean force, a force against itself.
    assert_eq!(scale("stat_min_n", 10.0, 120.0), 120.0);
    assert_eq!(scale("std_n", 30.0, 120.0), 30.0);
    assert_eq!(scale("max_uplift_at_support_mm", 0.2, 120.0), 1.0);

    // Through summary.json into the assessment: each row with a statistic carries its refined
    // value and verdict; a verdict that the refinement would change is not established.
    let mut summary = RunSummary::new(&case, &out, 0.0, Vec::new(), Vec::new());
    summary.verification = Some(v.clone());
    let text = serde_json::to_string(&summary).unwrap();
    let input = AssessInput::from_summary_json(&text).unwrap();
    // (JSON's decimal text reads back within rounding.)
    let back = input
        .verification
        .as_ref()
        .expect("summary.json's verification is read");
    assert_eq!(back.not_converged, v.not_converged);
    assert!((back.pantographs[0].statistics[1].refined - sf.std_n).abs() < 1e-12 * sf.std_n);
    let a = assess(&input, &criteria::builtin(), Some(criteria::System::Ac));
    let target = a
        .rows
        .iter()
        .find(|r| r.id == "mean-force-target-ac")
        .unwrap();
    let k = target
        .verification
        .as_ref()
        .expect("the mean force is verified");
    assert!((k.refined - sf.mean_n).abs() < 1e-12 * sf.mean_n);
    let mut forged = input.clone();
    // A verification in which the refined σ exceeds a limit the run meets: the row is met, but
    // not established.
    let mut crit = criteria::builtin();
    let std_max = crit.iter_mut().find(|c| c.id == "std-max").unwrap();
    std_max.kind = criteria::Kind::Max;
    std_max.limit = criteria::Limit::Constant(s.std_n + 0.5 * (sf.std_n - s.std_n).abs().max(1e-6));
    let fv = forged.verification.as_mut().unwrap();
    let std_check = fv.pantographs[0]
        .statistics
        .iter_mut()
        .find(|c| c.statistic == "std_n")
        .unwrap();
    std_check.refined = s.std_n + (sf.std_n - s.std_n).abs().max(1e-6);
    let a = assess(&forged, &crit, Some(criteria::System::Ac));
    let row = a.rows.iter().find(|r| r.id == "std-max").unwrap();
    assert_eq!(row.verdict, Verdict::Met);
    assert_eq!(
        row.verification.as_ref().unwrap().refined_verdict,
        Verdict::NotMet
    );
    assert!(
        a.not_established.iter().any(|n| n.starts_with("std-max")),
        "{:?}",
        a.not_established
    );
    assert!(
        a.conclusion().contains("not established"),
        "{}",
        a.conclusion()
    );
}

/// `pcsim validate --verify`: each row's refined and stiff-contact values are those of the
/// validation's cases run by hand refined and with the contact twice as stiff, judged by the
/// same ranges; a row is established exactly when the refinement keeps its verdict and does not
/// find its value unconverged.
#[test]
fn issue_42_1_a_validations_verification_is_the_runs_made_by_hand() {
    use pcsim_core::analysis::verify::{refined_case, statistic_of_quantity, stiff_contact_case};
    use pcsim_core::study::validate::{compare, validate};
    let (plan, mut report, runs) = validate("en50318-2002", Some(2)).unwrap();
    plan.verify(&runs, &mut report, &Budget::default(), Some(2))
        .unwrap();
    assert_eq!(report.verification.len(), plan.cases.len());
    let mut not = 0;
    for (k, c) in report.cases.iter().enumerate() {
        let case = &plan.cases[plan.run_of_target[k]];
        let fine = run_case(&refined_case(case), &mut |_| true).unwrap();
        let stiff = run_case(&stiff_contact_case(case), &mut |_| true).unwrap();
        let rf = compare(&fine.pantographs[0].stats.unwrap(), &plan.targets[k]);
        let rs = compare(&stiff.pantographs[0].stats.unwrap(), &plan.targets[k]);
        for ((row, f), s) in c.rows.iter().zip(&rf.rows).zip(&rs.rows) {
            let v = row.verification.as_ref().unwrap();
            assert_eq!(
                (v.refined, v.refined_pass),
                (f.value, f.pass),
                "{}",
                row.quantity
            );
            assert_eq!((v.stiff_contact, v.stiff_contact_pass), (s.value, s.pass));
            let converged = statistic_of_quantity(&row.quantity).map(|q| {
                report.verification[plan.run_of_target[k]]
                    .check("leading", q)
                    .unwrap()
                    .converged
            });
            assert_eq!(v.converged, converged, "{}", row.quantity);
            assert_eq!(
                v.established,
                f.pass == row.pass && converged != Some(false)
            );
            not += usize::from(!v.established);
        }
    }
    assert_eq!(report.not_established.len(), not);
    // The run's verdicts themselves are unchanged by the verification.
    let (_, plain, _) = validate("en50318-2002", Some(2)).unwrap();
    for (a, b) in plain.cases.iter().zip(&report.cases) {
        for (x, y) in a.rows.iter().zip(&b.rows) {
            assert_eq!((x.value, x.pass), (y.value, y.pass));
        }
    }
}
