//! Issue 51: the CLI's table of docs/matrix.md. Every geometry family of the core's zoo
//! (`pcsim_core::zoo::geometries`), written as a case file: `pcsim run CASE` and `pcsim hil CASE`
//! (a 180 m window fed a constant 100 N at the case's speed for a second), `pcsim study SPEC`
//! (the current-collection study of a spec naming the case file). Each cell runs (exit
//! 0, a summary with statistics; every `hil` row finite and `ok`) or is refused by name (exit 2, the
//! message names the field). Nothing is injected. `PCSIM_BLESS=1` rewrites the block; the test
//! fails while it differs.

use crate::common::pcsim;
use pcsim_core::zoo::geometries::{
    geometries, matrix_block, refused_field, render_front_end, with_matrix_block,
};

fn outcome(g: &str, what: &str, o: &std::process::Output) -> Result<(), String> {
    let e = String::from_utf8_lossy(&o.stderr);
    match o.status.code() {
        Some(0) => Ok(()),
        Some(2) => Err(refused_field(&e).unwrap_or_else(|| {
            panic!("{what} on {g}: neither a result nor a refusal by name: {e}")
        })),
        c => panic!("{what} on {g}: exit {c:?}: {e}"),
    }
}

fn cells(dir: &std::path::Path, g: &str, case: &pcsim_core::Case) -> Vec<Result<(), String>> {
    let stem = g.replace([',', ' '], "_");
    let path = dir.join(format!("{stem}.toml"));
    std::fs::write(&path, case.to_toml_string()).unwrap();
    let out = dir.join(format!("{stem}-run"));
    let o = pcsim()
        .arg("run")
        .arg(&path)
        .args(["--quiet", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let run = outcome(g, "run", &o);
    if run.is_ok() {
        let s: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                .unwrap();
        let fm = s["pantographs"][0]["stats"]["mean_n"].as_f64().unwrap();
        assert!(fm > 20.0 && fm < 500.0, "run on {g}: mean {fm} N");
    }
    let v = case.run.speed_kmh / 3.6;
    let mut input = String::from("time_s,contact_force_n,position_from_start_m\n");
    for k in 0..=1000 {
        let t = k as f64 * 1e-3;
        input.push_str(&format!("{t:.3},100.0,{:.6}\n", v * t));
    }
    let inp = dir.join(format!("{stem}-input.csv"));
    std::fs::write(&inp, input).unwrap();
    let hout = dir.join(format!("{stem}-hil.csv"));
    let o = pcsim()
        .arg("hil")
        .arg(&path)
        .args(["--window", "180", "--input"])
        .arg(&inp)
        .arg("--out")
        .arg(&hout)
        .output()
        .unwrap();
    let hil = outcome(g, "hil", &o);
    if hil.is_ok() {
        let text = std::fs::read_to_string(&hout).unwrap();
        assert!(text.lines().count() > 1000, "hil on {g}");
        for l in text.lines().skip(1) {
            let (nums, status) = l.rsplit_once(',').unwrap();
            assert!(
                status == "ok"
                    && nums
                        .split(',')
                        .all(|x| x.parse::<f64>().is_ok_and(f64::is_finite)),
                "hil on {g}: {l}"
            );
        }
    }
    vec![run, hil, study(dir, g, &stem, case)]
}

/// Issue 54: `pcsim study SPEC` of the current-collection study, its spec naming the case file
/// beside it (the default spec's first train at the case's speed): exit 0 with wear.json's wire
/// worn, or a refusal by name.
fn study(
    dir: &std::path::Path,
    g: &str,
    stem: &str,
    case: &pcsim_core::Case,
) -> Result<(), String> {
    let text = pcsim_core::study::wear::DEFAULT_SPEC.replace(
        "case = \"en50318-2018-like-stitched-3d\"",
        &format!("case = \"{stem}.toml\""),
    );
    let second = text.match_indices("[[trains]]").nth(1).unwrap().0;
    let law = text.find("[law]").unwrap();
    let text = format!("{}{}", &text[..second], &text[law..]).replace(
        "speed_kmh = { value = 275.0,",
        &format!("speed_kmh = {{ value = {},", case.run.speed_kmh),
    );
    let spec = dir.join(format!("{stem}-wear.toml"));
    std::fs::write(&spec, text).unwrap();
    let out = dir.join(format!("{stem}-wear"));
    let o = pcsim()
        .arg("study")
        .arg(&spec)
        .args(["--quiet", "--no-plot", "--out"])
        .arg(&out)
        .output()
        .unwrap();
    let r = outcome(g, "study", &o);
    if r.is_ok() {
        let w: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("wear.json")).unwrap()).unwrap();
        let mech = w["trains"][0]["pantographs"][0]["wire_terms_mm3"][0]
            .as_f64()
            .unwrap();
        assert!(mech > 0.0, "study on {g}: {w}");
    }
    r
}

#[test]
fn issue_51_every_geometry_through_the_cli_runs_or_is_refused_by_name() {
    let dir = crate::common::scratch("matrix", "all");
    let rows: Vec<(&str, Vec<Result<(), String>>)> = geometries()
        .iter()
        .map(|(g, case)| (*g, cells(&dir, g, case)))
        .collect();
    for (g, c) in &rows {
        assert!(c[0].is_ok(), "run on {g}: {:?}", c[0]);
        assert!(c[2].is_ok(), "study on {g}: {:?}", c[2]);
        match &c[1] {
            Err(f) => assert!(g.contains("crosswind") && f == "wind", "{g}: {f}"),
            Ok(()) => assert!(!g.contains("crosswind"), "{g}"),
        }
    }
    let text = render_front_end(
        "CLI (`pcsim run CASE`, `pcsim hil CASE`, `pcsim study SPEC` of a wear spec naming CASE)",
        &["run", "real-time window (HIL)", "current collection"],
        &rows,
    );
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../docs/matrix.md");
    let doc = std::fs::read_to_string(path).unwrap_or_default();
    if std::env::var_os("PCSIM_BLESS").is_some() {
        std::fs::write(path, with_matrix_block(&doc, "cli", &text)).unwrap();
    }
    let doc = std::fs::read_to_string(path).unwrap_or_default();
    assert!(
        matrix_block(&doc, "cli") == Some(text.as_str()),
        "docs/matrix.md's CLI table differs (PCSIM_BLESS=1 rewrites it):\n{text}"
    );
}
