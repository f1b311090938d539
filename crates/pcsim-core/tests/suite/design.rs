//! The design search (issue 24, item 5): a synthetic objective with an analytic optimum, the
//! same search on 1 and 2 jobs, an interrupted search resumed from its journal, an infeasible
//! spec reported as such, and a spec that names what does not exist.

use pcsim_core::input::design::DesignSpec;
use pcsim_core::input::presets;
use pcsim_core::study::design::{search, Design, DesignResult, Evaluation, Local, StopReason};

/// en50318-2002 over its 20 spans, with the frame's spring to the roof taken out: the pantograph
/// is then held by its uplift force alone, so over a run the mean contact force equals the
/// uplift (the masses' mean acceleration is zero; aerodynamic force 0 in this preset). The
/// search looks for the uplift whose mean contact force is 100 N: the optimum is 100 N exactly,
/// up to what the masses' momentum changes over the analysis section (checked below).
const SYNTHETIC: &str = r#"
[base]
preset = "en50318-2002"
set = { "pantographs[0].stiffness_n_per_m" = [4200.0, 0.0] }

[[variable]]
path = "pantographs[0].uplift_n"
min = 60.0
max = 160.0
step = 2.0

[[speed]]
kmh = 250.0

[[objective]]
statistic = "mean_n"
pantograph = "leading"
target = 100.0

[budget]
evaluations = 14
method = "nelder-mead"
"#;

fn design(text: &str) -> Design {
    let spec = DesignSpec::from_toml_str(text).unwrap();
    let (base, _) = presets::load(spec.base.preset.as_deref().unwrap()).unwrap();
    Design::new(spec, base).unwrap()
}

fn run(d: &Design, journal: Vec<Evaluation>, jobs: usize) -> DesignResult {
    search(
        d,
        journal,
        &Local { jobs: Some(jobs) },
        Some(jobs),
        &mut |_| true,
    )
    .unwrap()
}

#[test]
fn the_search_finds_the_uplift_whose_mean_force_is_the_target() {
    let d = design(SYNTHETIC);
    // The analytic optimum holds in the model: the mean force at an uplift of 100 N.
    let (at100, _) = d.evaluate(&[100.0], Some(1));
    let fm = at100.values[0][0].unwrap();
    assert!((fm - 100.0).abs() < 0.2, "mean force at 100 N uplift: {fm}");
    let r = run(&d, Vec::new(), 2);
    let best = &r.evaluations[r.best.expect("a feasible design")];
    assert!(
        (best.x[0] - 100.0).abs() < 1.0,
        "uplift found {}",
        best.x[0]
    );
    let (c, same) = r.confirmation.as_ref().unwrap();
    assert!(
        *same,
        "the confirmation run gives the journal's numbers: {c:?}"
    );
    assert_eq!(r.sensitivity.len(), 1);
}

/// The shared test spec (`tests/design/swarm.toml`): two variables, a swarm of 4 over 3 batches,
/// two speeds, a constraint and the acceptance criteria, on 6 spans.
const SWARM: &str = include_str!("../../../../tests/design/swarm.toml");

/// Two searches gave the same evaluations, bit for bit.
fn same_search(a: &DesignResult, b: &DesignResult) {
    assert_eq!(a.evaluations.len(), b.evaluations.len());
    for (x, y) in a.evaluations.iter().zip(&b.evaluations) {
        assert_eq!(x, y, "evaluation {}", x.index);
    }
    assert_eq!(a.best, b.best);
    assert_eq!(a.stop, b.stop);
}

#[test]
fn the_same_seed_gives_the_same_search_on_one_and_two_jobs() {
    let d = design(SWARM);
    let one = run(&d, Vec::new(), 1);
    let two = run(&d, Vec::new(), 2);
    same_search(&one, &two);
    assert_eq!(one.stop, StopReason::Evaluations);
    assert_eq!(one.asked, 12);
    // A feasible best, confirmed, with each variable's sensitivity and the constraint's status
    // at both speeds.
    let best = &one.evaluations[one.best.unwrap()];
    assert!(best.feasible());
    assert!(one.confirmation.as_ref().unwrap().1);
    assert_eq!(one.sensitivity.len(), 2);
    // Fm − 3σ ≥ 20 N and the EN 50119 speed ratio (the one criterion with a limit here) at
    // both speeds.
    let names: Vec<&str> = one.constraints.iter().map(|c| c.name.as_str()).collect();
    assert_eq!(
        names,
        [
            "stat_min_n[worst]>=20@250",
            "acceptance:speed-ratio@250",
            "stat_min_n[worst]>=20@200",
            "acceptance:speed-ratio@200"
        ]
    );
    // Another seed searches elsewhere.
    let other = run(
        &design(&SWARM.replace("seed = 7", "seed = 8")),
        Vec::new(),
        1,
    );
    assert_ne!(other.evaluations[0].x, one.evaluations[0].x);
}

#[test]
fn an_interrupted_search_resumed_from_its_journal_gives_the_uninterrupted_result() {
    let d = design(SWARM);
    let whole = run(&d, Vec::new(), 2);
    // Interrupted after its second batch: the journal holds what was run, as design.csv does.
    let mut batches = 0;
    let mut rows: Vec<Vec<String>> = Vec::new();
    let cut = search(
        &d,
        Vec::new(),
        &Local { jobs: Some(2) },
        Some(2),
        &mut |fresh| {
            rows.extend(fresh.iter().map(|e| d.journal_row(e)));
            batches += 1;
            batches < 2
        },
    )
    .unwrap();
    assert_eq!(cut.stop, StopReason::Interrupted);
    assert!(cut.base.is_none() && cut.confirmation.is_none());
    // Two batches of 4 particles; a point asked twice (two particles clamped to the same
    // corner) is run once.
    assert!((5..=8).contains(&rows.len()), "{}", rows.len());
    // Read back as text, and resumed.
    let header = d.journal_header();
    let journal: Vec<Evaluation> = rows
        .iter()
        .map(|r| d.journal_read(&header, r).unwrap())
        .collect();
    let mut ran = 0;
    let resumed = search(
        &d,
        journal,
        &Local { jobs: Some(1) },
        Some(1),
        &mut |fresh| {
            ran += fresh.len();
            true
        },
    )
    .unwrap();
    same_search(&whole, &resumed);
    assert_eq!(resumed.run_now, ran);
    assert_eq!(
        whole.run_now - resumed.run_now,
        rows.len(),
        "the journal's evaluations were not run again"
    );
    // A journal of another search is refused, naming the fingerprint.
    let other = design(&SWARM.replace("seed = 7", "seed = 9"));
    let e = other
        .journal_read(&header, &rows[0])
        .unwrap_err()
        .to_string();
    assert!(e.contains("fingerprint"), "{e}");
}

#[test]
fn an_infeasible_spec_is_reported_as_infeasible() {
    let d = design(&SWARM.replace("min = 20.0", "min = 150.0"));
    let r = run(&d, Vec::new(), 2);
    assert_eq!(r.best, None);
    assert!(r.confirmation.is_none() && r.sensitivity.is_empty());
    let least = &r.evaluations[r.least_violating.expect("runs that gave statistics")];
    assert!(!least.feasible() && least.violation > 0.0);
    assert!(
        least
            .violated
            .iter()
            .any(|v| v.starts_with("stat_min_n[worst]>=150")),
        "{:?}",
        least.violated
    );
    assert!(r.evaluations.iter().all(|e| e.cost >= 1e20));
}

#[test]
fn a_spec_naming_what_does_not_exist_is_refused_by_name() {
    let bad = |text: String| {
        let spec = DesignSpec::from_toml_str(&text);
        match spec {
            Err(e) => e.to_string(),
            Ok(spec) => {
                let (base, _) = presets::load("en50318-2002").unwrap();
                Design::new(spec, base).unwrap_err().to_string()
            }
        }
    };
    let e = bad(SWARM.replace(
        "catenary.contact_wire.tension_n",
        "catenary.contact_wire.tensoin_n",
    ));
    assert!(e.contains("tensoin_n"), "{e}");
    let e = bad(SWARM.replace("\"std_n\"", "\"sigma\""));
    assert!(
        e.contains("objective[0].statistic") && e.contains("sigma"),
        "{e}"
    );
    let e = bad(SWARM.replace(
        "statistic = \"std_n\"",
        "statistic = \"std_n\"\npantograph = 3",
    ));
    assert!(
        e.contains("objective[0].pantograph") && e.contains('3'),
        "{e}"
    );
    let e = bad(SWARM.replace("min = 12000.0", "min = -5.0"));
    assert!(e.contains("variable[1]") && e.contains("tension_n"), "{e}");
}

#[test]
fn a_search_stopped_by_its_wall_time_answers_from_its_first_batch() {
    let d = design(&SWARM.replace("seed = 7", "seed = 7\nwall_s = 1e-9"));
    let r = run(&d, Vec::new(), 2);
    assert_eq!(r.stop, StopReason::WallTime);
    assert_eq!(r.asked, 4, "the first batch of 4 particles, no more");
    let whole = run(&design(SWARM), Vec::new(), 2);
    assert_eq!(r.evaluations[..4], whole.evaluations[..4]);
}

#[test]
fn a_journal_row_reads_back_to_the_same_evaluation() {
    let d = design(SWARM);
    let e = Evaluation {
        index: 3,
        phase: "search".into(),
        batch: 1,
        x: vec![0.1 + 0.2, 1.0 / 3.0 * 30000.0],
        values: vec![vec![Some(1e-300), None], vec![Some(-0.0), Some(f64::MAX)]],
        objective: None,
        violation: 0.3,
        violated: vec!["a; b, \"c\"".into(), "run error@250: x\ny".into()],
        error: Some("at 250 km/h: one, two; three".into()),
        cost: 1e30,
    };
    let back = d
        .journal_read(&d.journal_header(), &d.journal_row(&e))
        .unwrap();
    assert_eq!(back, e);
    assert_eq!(back.values[1][0].unwrap().to_bits(), (-0.0f64).to_bits());
}

/// Issue 39, item 6: a journal row edited by hand (or damaged on disk) no longer matches its
/// checksum and is refused, not trusted; the checksum is of every column before it.
#[test]
fn issue_39_6_an_edited_journal_row_is_refused_by_its_checksum() {
    let d = design(SWARM);
    let e = Evaluation {
        index: 2,
        phase: "search".into(),
        batch: 0,
        x: vec![100.0, 20000.0],
        values: vec![vec![Some(30.0), Some(80.0)], vec![Some(25.0), Some(90.0)]],
        objective: Some(30.0),
        violation: 0.0,
        violated: vec![],
        error: None,
        cost: 30.0,
    };
    let header = d.journal_header();
    assert_eq!(header.last().map(String::as_str), Some("row_checksum"));
    let row = d.journal_row(&e);
    assert_eq!(d.journal_read(&header, &row).unwrap(), e);
    let col = |name: &str| header.iter().position(|h| h == name).unwrap();
    for (name, value) in [("objective", "3.0"), ("cost", "3.0"), ("feasible", "false")] {
        let mut edited = row.clone();
        edited[col(name)] = value.into();
        let err = d.journal_read(&header, &edited).unwrap_err().to_string();
        assert!(err.contains("checksum"), "{name}: {err}");
    }
    // A damaged checksum is refused too.
    let mut edited = row.clone();
    let last = edited.len() - 1;
    edited[last] = "0000000000000000".into();
    assert!(d.journal_read(&header, &edited).is_err());
}

/// Issue 51, item 1: a search never recommends what it did not beat. The synthetic spec's
/// target is set to the base design's own mean force (uplift 100 N): the base costs exactly 0
/// and every other uplift moves the mean force (it equals the uplift, tested above), so no
/// evaluation can beat it. The answer is "no improvement found", with no design recommended;
/// the same spec with a target the base misses by 20 N is improved upon.
#[test]
fn a_search_from_a_base_that_cannot_be_beaten_recommends_nothing() {
    let with_base = SYNTHETIC.replace(
        "set = { \"pantographs[0].stiffness_n_per_m\" = [4200.0, 0.0] }",
        "set = { \"pantographs[0].stiffness_n_per_m\" = [4200.0, 0.0], \"pantographs[0].uplift_n\" = 100.0 }",
    );
    let probe = design(&with_base);
    let (base, _) = probe.evaluate(&probe.base_x(), Some(1));
    let fm0 = base.values[0][0].unwrap();
    let spec = with_base
        .replace("target = 100.0", &format!("target = {fm0:?}"))
        .replace("evaluations = 14", "evaluations = 6");
    let d = design(&spec);
    let r = run(&d, Vec::new(), 2);
    let b = r.base.as_ref().expect("the base evaluated");
    assert_eq!(
        b.objective,
        Some(0.0),
        "the base meets its own target exactly"
    );
    let best = &r.evaluations[r.best.expect("the search's best")];
    // Nelder–Mead starts from the base: its best is the base itself, a tie, which is no
    // improvement either.
    assert!(best.cost >= b.cost, "nothing costs less than 0");
    assert_eq!(r.recommended, None, "nothing beat the base");
    assert_eq!(r.answer(), "no improvement found");
    let v = r.to_json(&d);
    assert!(
        v["best"].is_null(),
        "design.json recommends nothing: {}",
        v["best"]
    );
    assert_eq!(v["best_evaluated"]["index"], best.index);
    // The base 20 N off its target: the search beats it and recommends its best.
    let off = design(&spec.replace(
        &format!("target = {fm0:?}"),
        &format!("target = {:?}", fm0 + 20.0),
    ));
    let r = run(&off, Vec::new(), 2);
    assert_eq!(r.answer(), "improved");
    let rec = &r.evaluations[r.recommended.expect("a recommendation")];
    assert!(rec.cost < r.base.as_ref().unwrap().cost);
}

/// Issue 53, item 6: `method = "corners"` runs every corner of the box, once each, in bit
/// order, and nothing else in its search: on the synthetic problem (the mean force equals the
/// uplift) the corners' envelope of the mean force is the uplift's range, the exact bounds of
/// a response monotone in its variable; the best corner is the one nearer the target. Too small
/// a budget is refused by its field before any run.
#[test]
fn a_corner_plan_runs_every_corner_once_and_bounds_a_monotone_response() {
    let spec = SYNTHETIC.replace(
        "evaluations = 14\nmethod = \"nelder-mead\"",
        "evaluations = 2\nmethod = \"corners\"",
    );
    let d = design(&spec);
    let r = run(&d, Vec::new(), 2);
    let search: Vec<&Evaluation> = r
        .evaluations
        .iter()
        .filter(|e| e.phase == "search")
        .collect();
    let xs: Vec<f64> = search.iter().map(|e| e.x[0]).collect();
    assert_eq!(xs, [60.0, 160.0]);
    for e in &search {
        let fm = e.values[0][0].unwrap();
        assert!(
            (fm - e.x[0]).abs() < 0.2,
            "mean {fm} N at uplift {}",
            e.x[0]
        );
    }
    assert_eq!(r.evaluations[r.best.unwrap()].x, [60.0]);
    assert_eq!(r.stop, StopReason::Converged);
    let small = SYNTHETIC.replace(
        "evaluations = 14\nmethod = \"nelder-mead\"",
        "evaluations = 1\nmethod = \"corners\"",
    );
    let e = DesignSpec::from_toml_str(&small).unwrap_err().to_string();
    assert!(
        e.contains("budget.evaluations") && e.contains("need 2 evaluations"),
        "{e}"
    );
}
