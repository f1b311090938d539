//! The acceptance criteria (issue 22, item 3): each quoted criterion's formula reproduced at two
//! speeds from its source, and the verdicts' rules (a limit only where one is held).

use pcsim_core::analysis::assess::{assess, AssessInput, AssessSource, PantographInput, Verdict};
use pcsim_core::analysis::stats::ContactStats;
use pcsim_core::input::criteria::{self, Criterion, Status, System};
use pcsim_core::input::targets::target_cases;

fn builtin(id: &str) -> Criterion {
    criteria::builtin()
        .into_iter()
        .find(|c| c.id == id)
        .unwrap_or_else(|| panic!("no built-in criterion {id}"))
}

fn stats(mean: f64, std: f64) -> ContactStats {
    ContactStats {
        mean_n: mean,
        std_n: std,
        std_0_5hz_n: 0.0,
        std_5_20hz_n: 0.0,
        stat_max_n: mean + 3.0 * std,
        stat_min_n: mean - 3.0 * std,
        actual_max_n: mean + 2.0 * std,
        actual_min_n: mean - 2.0 * std,
        contact_point_range_mm: 20.0,
        max_uplift_at_support_mm: 60.0,
        loss_of_contact_percent: 0.0,
        max_lateral_offset_mm: None,
        min_head_margin_mm: None,
        max_contact_wire_blowout_mm: None,
    }
}

fn input(speed_kmh: f64, ratio: Option<f64>, pans: &[(f64, f64)]) -> AssessInput {
    AssessInput {
        speed_kmh,
        speed_ratio: ratio,
        pantographs: pans
            .iter()
            .enumerate()
            .map(|(i, &(m, s))| PantographInput {
                name: format!("p{i}"),
                stats: Some(stats(m, s)),
                head_half_width_m: None,
                arcing_percent: None,
                speed_kmh: None,
            })
            .collect(),
        run_errors: Vec::new(),
        verification: None,
        source: AssessSource::Run,
    }
}

#[test]
fn the_en50367_target_mean_force_at_275_and_320_kmh_is_the_en50318_references_mean() {
    // The source's check (reference notes §2, item 1): 0.00097 v² + 70 N gives 143.4 N at
    // 275 km/h and 169.3 N at 320 km/h, the mean forces of the EN 50318:2018 reference as the
    // seed paper's Table 1 quotes them (143–144 N; 169 N, printed without decimals).
    let c = builtin("mean-force-target-ac");
    assert_eq!(c.status, Status::Quoted);
    assert_eq!(c.systems, vec![System::Ac]);
    let none = |_| None;
    for (v, quoted, key) in [
        (275.0, 143.4, "v275_leading"),
        (320.0, 169.3, "v320_leading"),
    ] {
        let fm = c.limit_at(v, &none).unwrap();
        assert!((fm - quoted).abs() < 0.05, "{v} km/h: {fm} N");
        let t = target_cases("seed_table1")
            .unwrap()
            .into_iter()
            .find(|t| t.key == key)
            .unwrap();
        assert_eq!(t.speed_kmh, v);
        let [lo, hi] = t.ranges.iter().find(|(q, _)| q == "mean").unwrap().1;
        assert!(
            fm >= lo - 0.5 && fm <= hi + 0.5,
            "{v} km/h: {fm} N outside [{lo}, {hi}]"
        );
    }
    // A target without a public tolerance gives the deviation, never a verdict.
    let a = assess(
        &input(320.0, None, &[(175.0, 20.0)]),
        &[c],
        Some(System::Ac),
    );
    assert_eq!(a.rows[0].verdict, Verdict::Deviation);
    let d = a.rows[0].deviation_percent.unwrap();
    assert!(
        (d - 100.0 * (175.0 - 169.328) / 169.328).abs() < 1e-9,
        "{d}"
    );
    assert_eq!((a.met, a.not_met, a.without_verdict), (0, 0, 1));
}

#[test]
fn the_en50119_speed_ratio_at_two_speeds() {
    // EN 50119:2009 §5.2.4 (Bane NOR TRV:00599): the speed stays below 0.7 of the wave speed.
    // A contact wire of 27 kN and 1.08 kg/m: c = √(T/ρA) = 158.1 m/s = 569.2 km/h, so 0.7 c is
    // 398.4 km/h: 320 km/h meets it, 420 km/h does not.
    let c = builtin("speed-ratio");
    assert_eq!(c.limit_at(0.0, &|_| None), Some(0.7));
    let wave_kmh = (27_000.0_f64 / 1.08).sqrt() * 3.6;
    for (v, met) in [(320.0, true), (420.0, false)] {
        let a = assess(
            &input(v, Some(v / wave_kmh), &[(150.0, 20.0)]),
            std::slice::from_ref(&c),
            None,
        );
        assert_eq!(
            a.rows.len(),
            1,
            "one row for the run, not one per pantograph"
        );
        assert_eq!(a.rows[0].pantograph, None);
        let want = if met { Verdict::Met } else { Verdict::NotMet };
        assert_eq!(a.rows[0].verdict, want, "{v} km/h");
    }
    // Without a recorded ratio there is no value, and no verdict.
    let a = assess(&input(320.0, None, &[(150.0, 20.0)]), &[c], None);
    assert_eq!(a.rows[0].verdict, Verdict::NoValue);
}

#[test]
fn the_lateral_criteria_follow_the_head_width() {
    // 0.40 m for a 1 600 mm head, 0.55 m for a 1 950 mm head (reference notes §3, quoted).
    let all = criteria::builtin();
    let mut inp = input(250.0, None, &[(120.0, 20.0), (120.0, 20.0)]);
    for (p, (half, offset)) in inp
        .pantographs
        .iter_mut()
        .zip([(0.8, 420.0), (0.975, 420.0)])
    {
        p.head_half_width_m = Some(half);
        p.stats.as_mut().unwrap().max_lateral_offset_mm = Some(offset);
    }
    let a = assess(&inp, &all, None);
    let lat: Vec<_> = a
        .rows
        .iter()
        .filter(|r| r.id.starts_with("lateral"))
        .map(|r| (r.id.as_str(), r.pantograph.as_deref(), r.limit, r.verdict))
        .collect();
    assert_eq!(
        lat,
        vec![
            ("lateral-1600", Some("p0"), Some(400.0), Verdict::NotMet),
            ("lateral-1950", Some("p1"), Some(550.0), Verdict::Met),
        ]
    );
    // Without lateral motion neither applies, and both say why.
    let a = assess(&input(250.0, None, &[(120.0, 20.0)]), &all, None);
    assert!(a.rows.iter().all(|r| !r.id.starts_with("lateral")));
    assert_eq!(a.skipped.iter().filter(|s| s.contains("head")).count(), 2);
}

#[test]
fn criteria_without_a_limit_pcsim_can_cite_give_the_value_and_no_verdict() {
    let all = criteria::builtin();
    let a = assess(
        &input(300.0, Some(0.5), &[(160.0, 30.0)]),
        &all,
        Some(System::Dc3kV),
    );
    for r in &a.rows {
        assert!(r.value.is_some(), "{}", r.id);
        match r.status.as_str() {
            "quoted" => assert!(r.limit.is_some(), "{}", r.id),
            _ => {
                assert_eq!(r.limit, None, "{}", r.id);
                assert_eq!(r.verdict, Verdict::NoLimit, "{}", r.id);
            }
        }
    }
    // The AC target does not apply on a DC line, and without a system it is skipped by name.
    assert!(a.rows.iter().all(|r| r.id != "mean-force-target-ac"));
    let a = assess(&input(300.0, Some(0.5), &[(160.0, 30.0)]), &all, None);
    assert!(a
        .skipped
        .iter()
        .any(|s| s.starts_with("mean-force-target-ac") && s.contains("--system")));
    assert!(
        a.conclusion().contains("not an acceptance"),
        "{}",
        a.conclusion()
    );
}

#[test]
fn a_users_criteria_give_verdicts_by_their_rules() {
    // A test file (not a claim about any standard): σ at most 0.25 Fm, Fm − 3σ at least 10 N,
    // Fm within 5 % of 100 N + 0.001 v², above 200 km/h only.
    let user = criteria::user_file(
        r#"
[[criterion]]
id = "t-std"
quantity = "std_n"
kind = "max"
factor_of = { quantity = "mean_force_n", factor = 0.25 }
clause = "test"
source = "test fixture"
status = "user"

[[criterion]]
id = "t-min"
quantity = "stat_min_n"
kind = "min"
limit = 10.0
clause = "test"
source = "test fixture"
status = "user"

[[criterion]]
id = "t-mean"
quantity = "mean_force_n"
kind = "target"
formula_kmh = [100.0, 0.0, 0.001]
tolerance_percent = 5.0
speed_kmh = [200.0, 400.0]
clause = "test"
source = "test fixture"
status = "user"
"#,
    )
    .unwrap();
    // 250 km/h: target 162.5 N. Pantograph 0: Fm 160, σ 30 (≤ 40; min 70 ≥ 10; −1.5 %): all
    // met. Pantograph 1: Fm 180 (+10.8 %), σ 50 (> 45), min 30: two not met.
    let a = assess(
        &input(250.0, None, &[(160.0, 30.0), (180.0, 50.0)]),
        &user,
        None,
    );
    let v: Vec<_> = a
        .rows
        .iter()
        .map(|r| (r.id.as_str(), r.pantograph.clone().unwrap(), r.verdict))
        .collect();
    use Verdict::*;
    assert_eq!(
        v,
        vec![
            ("t-std", "p0".into(), Met),
            ("t-std", "p1".into(), NotMet),
            ("t-min", "p0".into(), Met),
            ("t-min", "p1".into(), Met),
            ("t-mean", "p0".into(), Met),
            ("t-mean", "p1".into(), NotMet),
        ]
    );
    assert_eq!((a.met, a.not_met, a.without_verdict), (4, 2, 0));
    // At the boundaries (exact in binary): σ exactly 0.25 Fm is met, Fm − 3σ exactly 10 N too;
    // 200 km/h is outside (200, 400].
    let a = assess(&input(200.0, None, &[(40.0, 10.0)]), &user, None);
    assert_eq!((a.rows[0].verdict, a.rows[1].verdict), (Met, Met));
    assert!(a.rows.iter().all(|r| r.id != "t-mean"));
    assert!(a.skipped.iter().any(|s| s.starts_with("t-mean")));
    // A target that is zero at the run's speed gives no deviation (never a NaN or an infinity).
    let zero = criteria::user_file(
        "[[criterion]]\nid = \"z\"\nquantity = \"mean_force_n\"\nkind = \"target\"\nformula_kmh = [0.0, 0.0, 0.0]\nclause = \"test\"\nsource = \"test fixture\"\nstatus = \"user\"\n",
    )
    .unwrap();
    let a = assess(&input(250.0, None, &[(160.0, 30.0)]), &zero, None);
    assert_eq!(
        (a.rows[0].verdict, a.rows[0].deviation_percent),
        (NoLimit, None)
    );
    // A pantograph that did not cross the section has no value, and no verdict.
    let mut inp = input(250.0, None, &[(160.0, 30.0)]);
    inp.pantographs[0].stats = None;
    let a = assess(&inp, &user, None);
    assert!(a.rows.iter().all(|r| r.verdict == NoValue));
}

/// Issue 39, item 1: a run's error-level events (summary.json's `errors`) reach the assessment:
/// listed, said in the conclusion, and the run is not accepted even where every row with a
/// verdict is met (`pcsim assess --strict` fails on it).
#[test]
fn issue_39_1_a_runs_error_events_are_assessed_and_not_accepted() {
    let list = criteria::builtin();
    let mut inp = input(250.0, Some(0.5), &[(160.0, 30.0)]);
    let clean = assess(&inp, &list, Some(System::Ac));
    assert!(clean.run_errors.is_empty());
    inp.run_errors = vec!["pantograph p0: dewirement: the contact wire left the head".into()];
    let a = assess(&inp, &list, Some(System::Ac));
    assert_eq!(a.met, clean.met);
    assert_eq!(a.not_met, clean.not_met);
    assert_eq!(a.run_errors, inp.run_errors);
    assert!(!a.passes());
    assert!(
        a.conclusion().contains("1 error-level event(s)"),
        "{}",
        a.conclusion()
    );
    // Read from a summary.json that has them (and from one that has none).
    let json = r#"{"speed_kmh": 250.0, "speed_ratio": 0.5, "pantographs": [], "errors": ["pantograph x: dewirement"]}"#;
    assert_eq!(
        AssessInput::from_summary_json(json).unwrap().run_errors,
        vec!["pantograph x: dewirement".to_string()]
    );
    let json = r#"{"speed_kmh": 250.0, "speed_ratio": 0.5, "pantographs": []}"#;
    assert!(AssessInput::from_summary_json(json)
        .unwrap()
        .run_errors
        .is_empty());
}

#[test]
fn issue_54_the_arcing_of_the_current_collection_study_is_assessed_without_a_limit() {
    // wear.json as the study writes it, cut to what the assessment reads.
    let wear = r#"{"trains": [
        {"name": "fast", "speed_kmh": 300.0, "pantographs": [{"name": "leading", "nq_percent": 0.25}]},
        {"name": "slow", "speed_kmh": 100.0, "pantographs": [{"name": "leading", "nq_percent": 0.0}]}
    ]}"#;
    let input = AssessInput::from_wear_json(wear).unwrap();
    let a = assess(&input, &criteria::builtin(), Some(System::Ac));
    // One row per train and pantograph: NQ, its clause, no limit held (none is cited).
    let arcing: Vec<_> = a.rows.iter().filter(|r| r.id == "arcing-nq").collect();
    assert_eq!(arcing.len(), 2);
    assert_eq!(
        arcing[0].pantograph.as_deref(),
        Some("fast at 300 km/h, leading")
    );
    assert_eq!(arcing[0].value, Some(0.25));
    assert!(arcing
        .iter()
        .all(|r| r.verdict == Verdict::NoLimit && r.limit.is_none()));
    // Nothing else is judged on a study that gives the arcing only: each criterion says why.
    assert_eq!(a.rows.len(), 2);
    assert!(a
        .skipped
        .iter()
        .any(|s| s.starts_with("std-max: the current-collection study gives the arcing only")));
    // A run has no arcing: the criterion says where it is.
    let run = assess(&input_for_run(), &criteria::builtin(), Some(System::Ac));
    assert!(run.rows.iter().all(|r| r.id != "arcing-nq"));
    assert!(run
        .skipped
        .iter()
        .any(|s| s.starts_with("arcing-nq: arcing is the current-collection study's")));
    // A user's limit above a speed (a test file, not a claim about any standard) judges each
    // train at its own speed: the fast one against it, the slow one not, saying so.
    let user = criteria::user_file(
        r#"
[[criterion]]
id = "t-nq"
quantity = "arcing_percent"
kind = "max"
limit = 0.2
speed_kmh = [250.0, 400.0]
clause = "test"
source = "test fixture"
status = "user"
"#,
    )
    .unwrap();
    let a = assess(&input, &user, None);
    assert_eq!(a.rows.len(), 1);
    assert_eq!(
        a.rows[0].pantograph.as_deref(),
        Some("fast at 300 km/h, leading")
    );
    assert_eq!(a.rows[0].verdict, Verdict::NotMet);
    assert!(
        a.skipped
            .iter()
            .any(|s| s.starts_with("t-nq: applies above 250")
                && s.ends_with("(slow at 100 km/h, leading)")),
        "{:?}",
        a.skipped
    );
    // A file that is not one is refused, saying what it expected.
    let e = AssessInput::from_wear_json("{}").unwrap_err().to_string();
    assert!(e.contains("wear.json"), "{e}");
}

fn input_for_run() -> AssessInput {
    input(275.0, Some(0.6), &[(120.0, 25.0)])
}
