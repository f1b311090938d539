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

/// Issue 41, item 4: `--pantograph` picks the pantograph the window follows, as the case's
/// `run.window_pantograph` does: on the three-tension-length 2018 line, `pcsim hil --pantograph
/// trailing` writes the same bytes as the case file with `window_pantograph = "trailing"`, other
/// bytes than the leading pantograph's window (it starts 200 m further back); `pcsim realtime`
/// takes it too; a pantograph the case does not have is refused, naming the field and the names.
#[test]
fn issue_41_4_the_window_follows_the_pantograph_named_by_flag_or_case() {
    let d = scratch("everywhere", "trailing");
    let text = preset_text("en50318-2018-like-simple");
    let trailing = write(
        &d,
        "trailing.toml",
        &text.replacen("[run]\n", "[run]\nwindow_pantograph = \"trailing\"\n", 1),
    );
    let mut input = String::from("time_s,contact_force_n,position_from_start_m\n");
    for k in 0..2000 {
        let t = k as f64 * 1e-3;
        input.push_str(&format!("{t:?},150.0,{:?}\n", (t + 1e-3) * 275.0 / 3.6));
    }
    let inp = write(&d, "in.csv", &input);
    let hil = |args: &[&str], out: &str| {
        let o = pcsim()
            .arg("hil")
            .args(args)
            .arg("--input")
            .arg(&inp)
            .arg("--out")
            .arg(d.join(out))
            .output()
            .unwrap();
        ok(&o);
        std::fs::read(d.join(out)).unwrap()
    };
    let by_flag = hil(
        &[
            "--preset",
            "en50318-2018-like-simple",
            "--pantograph",
            "trailing",
        ],
        "flag.csv",
    );
    let by_case = hil(&[trailing.to_str().unwrap()], "case.csv");
    let leading = hil(&["--preset", "en50318-2018-like-simple"], "lead.csv");
    assert_eq!(by_flag, by_case);
    assert_ne!(by_flag, leading);
    let o = pcsim()
        .args([
            "hil",
            "--preset",
            "en50318-2018-like-simple",
            "--pantograph",
            "middle",
        ])
        .arg("--input")
        .arg(&inp)
        .arg("--out")
        .arg(d.join("x.csv"))
        .output()
        .unwrap();
    refused(
        &o,
        &["run.window_pantograph", "middle", "leading, trailing"],
    );
    let o = pcsim()
        .args([
            "realtime",
            "--preset",
            "en50318-2018-like-simple",
            "--pantograph",
            "nobody",
        ])
        .args(["--window", "240", "--no-plot", "--out"])
        .arg(d.join("rt"))
        .output()
        .unwrap();
    refused(&o, &["run.window_pantograph", "nobody"]);
}

/// Issue 41's done-when: a line with 3D, a crosswind, ice, irregularity and a curve
/// (examples/cases/line-3d-everything.toml) runs through `run` and `eva` with every physics in
/// its summary and finite statistics; the real-time window refuses it naming `wind` (the field
/// ahead of a moving window is not known to a rig: docs/matrix.md).
#[test]
fn issue_41_a_line_with_every_physics_and_a_curve_runs() {
    let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../..");
    let case = root.join("examples/cases/line-3d-everything.toml");
    let d = scratch("everywhere", "everything");
    let o = pcsim()
        .arg("run")
        .arg(&case)
        .arg("--out")
        .arg(d.join("run"))
        .output()
        .unwrap();
    ok(&o);
    let s: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("run/summary.json")).unwrap()).unwrap();
    for key in ["curve", "wind", "irregularity"] {
        assert!(
            s.get(key).is_some_and(|v| !v.is_null()),
            "summary.json lacks `{key}`"
        );
    }
    // The ice is in the model (its sag's mode-density warning names it).
    assert!(
        s["warnings"].to_string().contains("catenary.ice"),
        "{}",
        s["warnings"]
    );
    let st = &s["pantographs"][0]["stats"];
    for k in ["mean_n", "std_n", "actual_max_n"] {
        let v = st[k].as_f64().unwrap();
        assert!(v.is_finite() && v > 0.0, "{k} = {v}");
    }
    assert!(s["curve"]["sections"]
        .as_array()
        .is_some_and(|a| !a.is_empty()));
    let o = pcsim()
        .arg("eva")
        .arg(&case)
        .arg("--out")
        .arg(d.join("eva"))
        .output()
        .unwrap();
    ok(&o);
    let eva = std::fs::read_to_string(d.join("eva/eva.csv")).unwrap();
    assert!(eva.lines().count() >= 2 && !eva.contains("NaN"), "{eva}");
    let o = pcsim()
        .args(["realtime", "--window", "120"])
        .arg(&case)
        .output()
        .unwrap();
    refused(&o, &["`wind`", "rig"]);
}
