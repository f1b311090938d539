//! Issue 54: the current-collection study through `pcsim study`, the one command of the
//! spec-file studies: its embedded default runs, writes its typed output, its answer and its
//! figures, and its report opens with the answer; on a 2D case with contact loss the arcs are
//! counted (NQ within the loss of contact) and the strips and the sweep refused with their
//! physical reason; a bad spec is refused by its field; its schemas are printed.

use crate::common::{ok, pcsim, refused, scratch, stderr, stdout};

#[test]
fn the_default_wear_study_answers_first_and_writes_its_typed_output() {
    let d = scratch("wear", "default");
    let out = d.join("out");
    let o = pcsim()
        .args(["study", "wear", "--report", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    ok(&o);
    let text = stdout(&o);
    assert!(
        text.starts_with("en50318-2018-like-stitched-3d: the contact wire reaches its wear limit"),
        "{text}"
    );
    for f in [
        "wear.csv",
        "arcing.csv",
        "strips.csv",
        "sweep.csv",
        "wear.json",
        "answer.json",
        "figures.json",
        "wear_profile.svg",
        "strip_wear.svg",
        "sweep_speed.svg",
        "report.html",
        "case.toml",
        "study.toml",
    ] {
        assert!(out.join(f).is_file(), "{f}");
    }
    let w: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("wear.json")).unwrap()).unwrap();
    let trains = w["trains"].as_array().unwrap();
    assert_eq!(trains.len(), 3);
    // The sweep: ±0.3 m over 60 m spans is 2sv/L = 0.76 m/s at 275 km/h away from the
    // overlaps, 0.28 m/s at 100 km/h: the freight train sweeps every span too slowly.
    let share = |t: &serde_json::Value| t["sweep"]["share_below_limit_percent"].as_f64().unwrap();
    assert_eq!(share(&trains[0]), 0.0);
    assert_eq!(share(&trains[2]), 100.0);
    let median = |t: &serde_json::Value| {
        let mut v: Vec<f64> = t["sweep"]["spans"]
            .as_array()
            .unwrap()
            .iter()
            .map(|s| s["speed_m_s"].as_f64().unwrap())
            .collect();
        v.sort_by(f64::total_cmp);
        v[v.len() / 2]
    };
    let exact = 2.0 * 0.3 * (275.0 / 3.6) / 60.0;
    assert!(
        (median(&trains[0]) - exact).abs() / exact < 0.02,
        "{}",
        median(&trains[0])
    );
    // No contact lost, no arc; every strip has a finite life.
    for t in trains {
        for p in t["pantographs"].as_array().unwrap() {
            if p["loss_percent"].as_f64().unwrap() == 0.0 {
                assert_eq!(p["nq_percent"].as_f64().unwrap(), 0.0);
                assert!(p["arc_events"].as_array().unwrap().is_empty());
            }
            assert!(p["strip"]["life_km"].as_f64().unwrap() > 0.0);
        }
    }
    let years = w["wire"]["years_to_limit"].as_f64().unwrap();
    assert!(years.is_finite() && years > 0.0);
    // The report opens with the answer (answer.json's headline), before any other section.
    let report = std::fs::read_to_string(out.join("report.html")).unwrap();
    let a: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("answer.json")).unwrap()).unwrap();
    let headline = a["headline"].as_str().unwrap();
    let first = report
        .find("the contact wire reaches its wear limit")
        .expect("the answer in the report");
    assert!(
        report[..first].matches("<h2").count() <= 1,
        "the answer is not first"
    );
    assert!(text.contains(headline));
    // The spec as given travels with its outputs.
    assert_eq!(
        std::fs::read_to_string(out.join("study.toml")).unwrap(),
        pcsim_core::study::wear::DEFAULT_SPEC
    );
    let m: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("pcsim.json")).unwrap()).unwrap();
    assert_eq!(m["kind"], "wear");
    // `pcsim assess` takes the study's arcing: NQ per train and pantograph with its clause and
    // no limit held (none is cited); the report, made again, carries the assessment.
    let o = pcsim()
        .args(["assess", "--quiet"])
        .arg(&out)
        .output()
        .unwrap();
    ok(&o);
    let a: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("assessment.json")).unwrap())
            .unwrap();
    let rows = a["rows"].as_array().unwrap();
    assert_eq!(rows.len(), 6, "three trains of two pantographs");
    for (r, t) in rows.iter().zip(
        trains
            .iter()
            .flat_map(|t| t["pantographs"].as_array().unwrap().iter()),
    ) {
        assert_eq!(r["id"], "arcing-nq");
        assert_eq!(r["verdict"], "no-limit");
        assert_eq!(r["value"], t["nq_percent"]);
    }
    let report = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(report.contains("Acceptance criteria") && report.contains("arcing-nq"));
}

#[test]
fn arcs_on_a_2d_line_with_contact_loss_and_the_strips_refused_with_their_reason() {
    let d = scratch("wear", "arcs");
    let spec = pcsim_core::study::wear::DEFAULT_SPEC.replace(
        "case = \"en50318-2018-like-stitched-3d\"",
        "case = \"en50318-2002\"",
    );
    // One train at 300 km/h, where en50318-2002 loses contact over 1.3 % of its section.
    let first_train = spec.find("[[trains]]").unwrap();
    let law = spec.find("[law]").unwrap();
    let spec = format!(
        "{}[[trains]]\nname = \"fast\"\nspeed_kmh = {{ value = 300.0, source = \"test\" }}\ncurrent_a = {{ value = 300.0, source = \"test\" }}\npassages_per_day = {{ value = 50.0, source = \"test\" }}\n\n{}",
        &spec[..first_train],
        &spec[law..]
    );
    std::fs::write(d.join("spec.toml"), &spec).unwrap();
    let out = d.join("out");
    let o = pcsim()
        .args(["study"])
        .arg(d.join("spec.toml"))
        .args(["--no-plot", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    ok(&o);
    assert!(
        stderr(&o).contains("the case models no lateral motion"),
        "{}",
        stderr(&o)
    );
    let w: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("wear.json")).unwrap()).unwrap();
    let p = &w["trains"][0]["pantographs"][0];
    let (nq, loss) = (
        p["nq_percent"].as_f64().unwrap(),
        p["loss_percent"].as_f64().unwrap(),
    );
    assert!(
        loss > 1.0 && nq > 0.0 && nq <= loss,
        "NQ {nq} %, loss {loss} %"
    );
    assert!(p["strip"].is_null() && w["trains"][0]["sweep"].is_null());
    let arcs = std::fs::read_to_string(out.join("arcing.csv")).unwrap();
    assert_eq!(
        arcs.lines().count() - 1,
        p["arc_events"].as_array().unwrap().len()
    );
    assert!(arcs.lines().count() > 1);
    assert_eq!(
        std::fs::read_to_string(out.join("strips.csv"))
            .unwrap()
            .lines()
            .count(),
        1
    );
}

#[test]
fn a_bad_spec_is_refused_by_its_field_and_the_schemas_are_printed() {
    let d = scratch("wear", "bad");
    let cases = [
        ("bin_m =", "bin_mmm =", "bin_mmm"),
        (
            "case = \"en50318-2018-like-stitched-3d\"",
            "case = \"no-such-line\"",
            "case",
        ),
        ("kind = \"wear\"", "kind = \"tear\"", "kind"),
        (
            "passages_per_day = { value = 60.0",
            "passages_per_day = { value = -60.0",
            "trains[0].passages_per_day",
        ),
    ];
    for (i, (from, to, field)) in cases.iter().enumerate() {
        let p = d.join(format!("spec{i}.toml"));
        std::fs::write(&p, pcsim_core::study::wear::DEFAULT_SPEC.replace(from, to)).unwrap();
        let o = pcsim()
            .args(["study"])
            .arg(&p)
            .args(["--no-plot", "--out"])
            .arg(d.join("out"))
            .output()
            .unwrap();
        refused(&o, &[field]);
        assert!(
            !d.join("out").exists(),
            "{field}: a refused spec wrote its directory"
        );
    }
    let o = pcsim().args(["study", "nothing-here"]).output().unwrap();
    refused(&o, &["wear"]);
    for name in ["wear", "wear-spec", "answer", "figures"] {
        let o = pcsim().args(["schema", name]).output().unwrap();
        ok(&o);
        let s: serde_json::Value = serde_json::from_str(&stdout(&o)).unwrap();
        assert!(
            s.get("properties").is_some() || s.get("items").is_some(),
            "{name}"
        );
    }
    let o = pcsim().args(["study", "wear", "--show"]).output().unwrap();
    assert_eq!(stdout(&o), pcsim_core::study::wear::DEFAULT_SPEC);
}
