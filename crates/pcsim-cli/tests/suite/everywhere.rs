//! Issue 41, item 5: a case file wherever a preset is accepted (`pcsim validate CASE.toml
//! [--targets FILE]`).

use crate::common::{ok, pcsim, refused, scratch, stdout};
use std::path::PathBuf;

fn write(dir: &std::path::Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn preset_text(name: &str) -> String {
    let o = pcsim().args(["presets", "show", name]).output().unwrap();
    ok(&o);
    stdout(&o)
}

fn json(o: &std::process::Output) -> serde_json::Value {
    ok(o);
    serde_json::from_slice(&o.stdout).unwrap()
}

/// The validation's preset written as a case file gives the preset's report, byte for byte;
/// the same file with another static force gives that force's mean (the case is what runs).
#[test]
fn issue_41_5_validate_runs_a_case_file_against_a_validations_targets() {
    let d = scratch("everywhere", "validate");
    let text = preset_text("en50318-2002");
    let same = write(&d, "same.toml", &text);
    let preset = pcsim()
        .args(["validate", "--json", "--quiet"])
        .output()
        .unwrap();
    let case = pcsim()
        .args(["validate", "--json", "--quiet"])
        .arg(&same)
        .output()
        .unwrap();
    ok(&preset);
    assert_eq!(
        case.stdout, preset.stdout,
        "the preset as a file is the preset"
    );
    let o = pcsim()
        .args(["validate", "--quiet"])
        .arg(&same)
        .output()
        .unwrap();
    ok(&o);
    assert!(stdout(&o).contains("on case `"), "{}", stdout(&o));

    let heavier = text.replace("uplift_n = { value = 117.0", "uplift_n = { value = 150.0");
    assert_ne!(heavier, text, "the preset's static force line moved");
    let heavier = write(&d, "heavier.toml", &heavier);
    let js = json(
        &pcsim()
            .args(["validate", "--json", "--quiet"])
            .arg(&heavier)
            .output()
            .unwrap(),
    );
    for c in js["cases"].as_array().unwrap() {
        let mean = c["rows"]
            .as_array()
            .unwrap()
            .iter()
            .find(|r| r["quantity"] == "mean")
            .unwrap()["value"]
            .as_f64()
            .unwrap();
        // The mean contact force is the static force plus the (small) aerodynamic and
        // dynamic share: 150 N in, not the preset's 117 N.
        assert!((mean - 150.0).abs() < 5.0, "mean {mean} N");
    }
}

/// A case file with a user's targets: the targets' speeds run on the case (not on the preset
/// the targets name); a validation's name with --targets is refused, naming both ways.
#[test]
fn issue_41_5_validate_runs_a_case_file_against_a_targets_file() {
    let d = scratch("everywhere", "targets");
    let targets = write(
        &d,
        "targets.toml",
        "[mine]\nsource = \"typed in\"\npreset = \"en50318-2018-like-simple\"\n\n\
         [mine.v250]\nspeed_kmh = 250\nmean = [140.0, 160.0]\n",
    );
    let heavier = preset_text("en50318-2002")
        .replace("uplift_n = { value = 117.0", "uplift_n = { value = 150.0");
    let case = write(&d, "heavier.toml", &heavier);
    let o = pcsim()
        .args(["validate", "--quiet", "--strict", "--targets"])
        .arg(&targets)
        .arg(&case)
        .output()
        .unwrap();
    let out = stdout(&o);
    assert_eq!(o.status.code(), Some(0), "{out}");
    assert!(
        out.contains("1 of 1 rows pass") && out.contains("heavier.toml"),
        "{out}"
    );
    // The same targets on their own preset: its mean is not in [140, 160].
    let o = pcsim()
        .args(["validate", "--quiet", "--strict", "--targets"])
        .arg(&targets)
        .output()
        .unwrap();
    assert_eq!(o.status.code(), Some(1), "{}", stdout(&o));

    let o = pcsim()
        .args(["validate", "seed-table1", "--targets"])
        .arg(&targets)
        .output()
        .unwrap();
    refused(&o, &["seed-table1", "--targets"]);
    let o = pcsim().args(["validate", "nosuch"]).output().unwrap();
    refused(&o, &["nosuch", "case file"]);
    let o = pcsim()
        .args(["validate"])
        .arg(d.join("missing.toml"))
        .output()
        .unwrap();
    refused(&o, &["missing.toml"]);
}
