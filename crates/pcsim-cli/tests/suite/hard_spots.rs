//! Issue 55: a neutral section on a 2018-like line (the preset `neutral-section-2018-like`) at
//! its line speed through `run`, `report`, `assess`, `eva` and the real-time window; its hard
//! spots reported per pantograph, in the report's table and on its figures; a bad insulator
//! refused by its field; the wear study draws no current over the dead length.

use crate::common::{ok, pcsim, scratch, stderr};

fn json(path: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

#[test]
fn a_neutral_section_runs_through_run_report_assess_eva_and_the_window() {
    let d = scratch("hard-spots", "preset");
    let run = d.join("run");
    let preset = ["--preset", "neutral-section-2018-like"];
    ok(&pcsim()
        .arg("run")
        .args(preset)
        .args(["--report", "--quiet", "--out"])
        .arg(&run)
        .output()
        .unwrap());
    let s = json(&run.join("summary.json"));
    for p in s["pantographs"].as_array().unwrap() {
        let kinds: Vec<&str> = (p["hard_spots"].as_array().unwrap().iter())
            .map(|h| h["kind"].as_str().unwrap())
            .collect();
        assert_eq!(
            kinds,
            ["section_insulator", "section_insulator", "neutral_section"]
        );
    }
    let report = std::fs::read_to_string(run.join("report.html")).unwrap();
    assert!(report.contains("Passages over the hard spots"));
    assert!(
        report.contains("section insulators and neutral sections"),
        "the figures' legend"
    );
    ok(&pcsim()
        .args(["assess", "--quiet"])
        .arg(&run)
        .output()
        .unwrap());
    assert!(run.join("assessment.json").is_file());
    let eva = d.join("eva");
    ok(&pcsim()
        .arg("eva")
        .args(preset)
        .args(["--no-plot", "--quiet", "--out"])
        .arg(&eva)
        .output()
        .unwrap());
    assert!(eva.join("eva.csv").is_file());
    let rt = d.join("realtime");
    let o = pcsim()
        .arg("realtime")
        .args(preset)
        .args(["--window", "240", "--no-plot", "--quiet", "--out"])
        .arg(&rt)
        .output()
        .unwrap();
    ok(&o);
    assert!(rt.join("realtime.json").is_file(), "{}", stderr(&o));
}

#[test]
fn an_insulator_softer_than_its_wire_is_refused_by_its_field() {
    let d = scratch("hard-spots", "soft");
    let case = d.join("case.toml");
    let text = pcsim()
        .args(["presets", "show", "neutral-section-2018-like"])
        .output()
        .unwrap()
        .stdout;
    let text = String::from_utf8(text).unwrap().replacen(
        "ei_nm2 = { value = 2.0e4",
        "ei_nm2 = { value = 50.0",
        1,
    );
    std::fs::write(&case, text).unwrap();
    let o = pcsim()
        .args(["run", "--quiet", "--out"])
        .arg(d.join("out"))
        .arg(&case)
        .output()
        .unwrap();
    assert!(!o.status.success());
    let e = stderr(&o);
    assert!(e.contains("section_insulator[0].ei_nm2"), "{e}");
    assert!(e.contains("softer than the contact wire"), "{e}");
}
