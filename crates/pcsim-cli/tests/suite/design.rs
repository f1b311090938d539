//! `pcsim design` (issue 24): the answer's files, a killed search resumed from its journal to the
//! same bytes, the same bytes on 1 and 2 jobs, an infeasible spec, and refusals by name.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn pcsim() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pcsim"))
}

fn scratch(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("pcsim-design-test-{}-{name}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The shared test spec (`tests/design/swarm.toml`, 6 spans of en50318-2002), its base read from a
/// case file beside it (`base.file`), with `min_force` for its constraint.
fn spec(dir: &Path, min_force: f64) -> PathBuf {
    let text = include_str!("../../../../tests/design/swarm.toml");
    let (mut c, _) = pcsim_core::presets::load("en50318-2002").unwrap();
    c.catenary.spans = 6;
    c.run.start_m = 60.0;
    c.run.end_m = 300.0;
    c.run.analysis_m = [120.0, 240.0];
    std::fs::write(dir.join("short.toml"), c.to_toml_string()).unwrap();
    let (head, rest) = text.split_once("[base]").unwrap();
    let (_, rest) = rest.split_once("\n[[variable]]").unwrap();
    let text = format!("{head}[base]\nfile = \"short.toml\"\n\n[[variable]]{rest}")
        .replace("min = 20.0", &format!("min = {min_force:?}"));
    let p = dir.join("spec.toml");
    std::fs::write(&p, text).unwrap();
    p
}

fn design(spec: &Path, out: &Path, extra: &[&str]) -> Output {
    pcsim()
        .arg("design")
        .arg(spec)
        .arg("--out")
        .arg(out)
        .args(["--quiet", "--no-plot"])
        .args(extra)
        .output()
        .unwrap()
}

fn text(o: &Output) -> String {
    format!(
        "{}{}",
        String::from_utf8_lossy(&o.stdout),
        String::from_utf8_lossy(&o.stderr)
    )
}

#[test]
fn design_answers_and_a_killed_search_resumes_to_the_same_bytes() {
    let dir = scratch("resume");
    let spec = spec(&dir, 20.0);
    let out = dir.join("whole");
    let o = design(&spec, &out, &["--jobs", "2"]);
    assert!(o.status.success(), "{}", text(&o));
    let whole = std::fs::read(out.join("design.csv")).unwrap();
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("design.json")).unwrap()).unwrap();
    assert_eq!(json["feasible"], true);
    assert_eq!(json["confirmation"]["same_as_search"], true);
    assert_eq!(json["sensitivity"].as_array().unwrap().len(), 2);
    assert!(json["constraints"]
        .as_array()
        .unwrap()
        .iter()
        .any(|c| c["name"] == "acceptance:speed-ratio@250"));
    // The best design's case reads back, with the best values in it.
    let best = std::fs::read_to_string(out.join("best-case.toml")).unwrap();
    let (case, _) = pcsim_core::Case::from_toml_str(&best).unwrap();
    let x = json["best"]["x"].as_array().unwrap();
    assert_eq!(case.catenary.contact_wire.tension_n, x[1].as_f64().unwrap());
    assert!(std::fs::read_to_string(out.join("traces.csv"))
        .unwrap()
        .starts_with("design,speed_kmh,pantograph,position_m,force_n\nbase,250,"));
    // The report carries the answer, and the journal as parsed CSV (its violated lists quote
    // commas), not the force traces.
    let o = pcsim().arg("report").arg(&out).output().unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let html = std::fs::read_to_string(out.join("report.html")).unwrap();
    assert!(html.contains("The best design (evaluation") && html.contains("equal to the search"));
    assert!(html.contains("Sensitivity") && html.contains("acceptance:speed-ratio@250"));
    assert!(!html.contains("<h2>traces.csv</h2>"));
    // Killed in its second batch: the journal holds its header, the first rows, and a torn one.
    let journal = dir.join("whole-journal.csv");
    let full = std::fs::read_to_string(&journal).unwrap();
    let lines: Vec<&str> = full.lines().collect();
    assert!(lines.len() > 8);
    let torn = format!("{}\n{}", lines[..6].join("\n"), &lines[6][..20]);
    let cut = dir.join("cut-journal.csv");
    std::fs::write(&cut, torn).unwrap();
    let o = design(&spec, &dir.join("cut"), &["--jobs", "1"]);
    assert!(o.status.success(), "{}", text(&o));
    assert!(
        text(&o).contains("resuming from 5 evaluation(s)"),
        "{}",
        text(&o)
    );
    assert!(text(&o).contains("cut short"), "{}", text(&o));
    assert_eq!(std::fs::read(dir.join("cut/design.csv")).unwrap(), whole);
    assert_eq!(
        std::fs::read(dir.join("cut/design.json")).unwrap(),
        std::fs::read(out.join("design.json")).unwrap()
    );
    // Run again: every evaluation comes from the journal, the same bytes.
    let o = design(&spec, &out, &[]);
    assert!(text(&o).contains("0 run now"), "{}", text(&o));
    assert_eq!(std::fs::read(out.join("design.csv")).unwrap(), whole);
    // Another spec meets this journal: refused by its fingerprint, unless --fresh.
    let other = dir.join("other.toml");
    std::fs::write(
        &other,
        std::fs::read_to_string(&spec)
            .unwrap()
            .replace("seed = 7", "seed = 4"),
    )
    .unwrap();
    let o = design(&other, &out, &[]);
    assert!(!o.status.success());
    assert!(
        text(&o).contains("fingerprint") && text(&o).contains("--fresh"),
        "{}",
        text(&o)
    );
    let o = design(&other, &out, &["--fresh"]);
    assert!(o.status.success(), "{}", text(&o));
    assert_ne!(std::fs::read(out.join("design.csv")).unwrap(), whole);
}

#[test]
fn design_on_one_and_two_jobs_writes_the_same_bytes() {
    let dir = scratch("jobs");
    let spec = spec(&dir, 20.0);
    for jobs in ["1", "2"] {
        let o = design(&spec, &dir.join(format!("j{jobs}")), &["--jobs", jobs]);
        assert!(o.status.success(), "{}", text(&o));
    }
    for f in ["design.csv", "design.json", "traces.csv", "best-case.toml"] {
        assert_eq!(
            std::fs::read(dir.join("j1").join(f)).unwrap(),
            std::fs::read(dir.join("j2").join(f)).unwrap(),
            "{f}"
        );
    }
}

#[test]
fn an_infeasible_design_spec_exits_1_without_a_best_design() {
    let dir = scratch("infeasible");
    let spec = spec(&dir, 500.0);
    let out = dir.join("out");
    let o = design(&spec, &out, &[]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("INFEASIBLE"), "{}", text(&o));
    let json: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("design.json")).unwrap()).unwrap();
    assert_eq!(json["feasible"], false);
    assert!(json["best"].is_null());
    assert!(json["least_violating"]["violated"][0]
        .as_str()
        .unwrap()
        .starts_with("stat_min_n[worst]>=500"));
    assert!(!out.join("best-case.toml").exists());
}

#[test]
fn a_design_spec_naming_what_does_not_exist_is_refused_by_name() {
    let dir = scratch("refuse");
    let spec = spec(&dir, 20.0);
    let good = std::fs::read_to_string(&spec).unwrap();
    for (from, to, named) in [
        ("\"std_n\"", "\"sigma_n\"", "sigma_n"),
        (
            "pantographs[0].uplift_n",
            "pantographs[0].uplfit_n",
            "uplfit_n",
        ),
        (
            "pantographs[0].uplift_n",
            "pantographs[4].uplift_n",
            "pantographs[4]",
        ),
        ("system = \"ac\"", "system = \"ac-25\"", "ac-25"),
        (
            "file = \"short.toml\"",
            "file = \"absent.toml\"",
            "absent.toml",
        ),
    ] {
        std::fs::write(&spec, good.replace(from, to)).unwrap();
        let o = design(&spec, &dir.join("out"), &[]);
        assert!(!o.status.success(), "{to}");
        assert!(text(&o).contains(named), "{to}: {}", text(&o));
    }
}

#[test]
fn design_evaluated_by_another_program_gives_the_local_bytes() {
    // What a cluster does (scripts/slurm/design_batch.sh submits the same tasks as a job
    // array): each design of a batch by `pcsim design SPEC --task DIR --task-index I`.
    let dir = scratch("evaluate-with");
    let spec = spec(&dir, 20.0);
    let script = dir.join("batch.sh");
    std::fs::write(
        &script,
        format!(
            "#!/bin/sh\nset -e\ni=0\nwhile [ $i -lt $3 ]; do\n  {} design \"$2\" --task \"$1\" --task-index $i --quiet\n  i=$((i + 1))\ndone\n",
            env!("CARGO_BIN_EXE_pcsim")
        ),
    )
    .unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&script, std::fs::Permissions::from_mode(0o755)).unwrap();
    let o = design(&spec, &dir.join("local"), &[]);
    assert!(o.status.success(), "{}", text(&o));
    let o = design(
        &spec,
        &dir.join("remote"),
        &["--evaluate-with", script.to_str().unwrap()],
    );
    assert!(o.status.success(), "{}", text(&o));
    assert!(dir.join("remote-batches/batch-0/row-0.csv").exists());
    for f in ["design.csv", "design.json"] {
        assert_eq!(
            std::fs::read(dir.join("local").join(f)).unwrap(),
            std::fs::read(dir.join("remote").join(f)).unwrap(),
            "{f}"
        );
    }
    // A program that fails stops the search with its error; the journal keeps what was run.
    std::fs::write(&script, "#!/bin/sh\nexit 3\n").unwrap();
    let o = design(
        &spec,
        &dir.join("failing"),
        &["--evaluate-with", script.to_str().unwrap()],
    );
    assert!(!o.status.success());
    assert!(text(&o).contains("failed"), "{}", text(&o));
}

/// Issue 51, item 1: `pcsim design` never recommends what it did not beat. The base (a short
/// en50318-2002) is run first; the spec's target is its own mean force, so the base costs
/// exactly 0 and no other uplift can do better: the answer says "NO IMPROVEMENT FOUND", exits
/// 1, writes no best-case.toml, and design.json's `best` is null beside `best_evaluated`.
#[test]
fn issue_51_a_design_from_a_base_that_cannot_be_beaten_recommends_nothing() {
    let dir = scratch("unbeaten");
    let (mut c, _) = pcsim_core::presets::load("en50318-2002").unwrap();
    c.catenary.spans = 6;
    c.run.start_m = 60.0;
    c.run.end_m = 300.0;
    c.run.analysis_m = [120.0, 240.0];
    std::fs::write(dir.join("short.toml"), c.to_toml_string()).unwrap();
    let o = pcsim()
        .arg("run")
        .arg(dir.join("short.toml"))
        .args(["--quiet", "--out"])
        .arg(dir.join("base"))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", text(&o));
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.join("base/summary.json")).unwrap()).unwrap();
    let fm = s["pantographs"][0]["stats"]["mean_n"].as_f64().unwrap();
    let spec = format!(
        "[base]\nfile = \"short.toml\"\n\n[[variable]]\npath = \"pantographs[0].uplift_n\"\nmin = 100.0\nmax = 140.0\n\n[[speed]]\nkmh = 250.0\n\n[[objective]]\nstatistic = \"mean_n\"\npantograph = \"leading\"\ntarget = {fm:?}\n\n[budget]\nevaluations = 4\nparticles = 4\nseed = 3\n"
    );
    let p = dir.join("spec.toml");
    std::fs::write(&p, spec).unwrap();
    let out = dir.join("out");
    let o = design(&p, &out, &[]);
    assert_eq!(o.status.code(), Some(1), "{}", text(&o));
    assert!(text(&o).contains("NO IMPROVEMENT FOUND"), "{}", text(&o));
    assert!(!out.join("best-case.toml").exists());
    let j: serde_json::Value =
        serde_json::from_slice(&std::fs::read(out.join("design.json")).unwrap()).unwrap();
    assert_eq!(j["answer"], "no improvement found");
    assert!(j["best"].is_null() && !j["best_evaluated"].is_null());
    assert_eq!(j["base"]["objective"], 0.0);
}
