//! A short-run fuzz of `pcsim run` on shortened cases (no nightly toolchain needed): mutate the
//! case text at random (a seeded generator, so a failure is reproducible), run the binary, and
//! accept only exit status 0 or 2, no panic, no hang, and no NaN or infinity in any output.
//!
//! CI runs 200 mutations; the documented longer run is
//! `PCSIM_FUZZ_CASES=1000 cargo test --release -p pcsim-cli --test suite fuzz_run:: -- --nocapture`.

use pcsim_core::zoo::number_spans as numbers;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A small seeded generator (SplitMix64).
struct Rng(u64);

impl Rng {
    fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        z ^ (z >> 31)
    }
    fn below(&mut self, n: usize) -> usize {
        (self.next() % n.max(1) as u64) as usize
    }
}

const REPLACEMENTS: &[&str] = &[
    "-1.0", "0", "0.0", "1e-300", "1e300", "nan", "inf", "-inf", "1e-12", "1e12", "2", "-3", "0.5",
    "100", "1e6", "7.5",
];

/// Shortened cases of every preset (a few spans, one mode per metre, a short run).
fn bases() -> Vec<String> {
    pcsim_core::presets::PRESETS
        .iter()
        .map(|p| {
            let (mut c, _) = pcsim_core::presets::load(p.name).unwrap();
            if c.line.is_none() {
                c.catenary.spans = 6;
            }
            let l = c.length_m();
            c.pantographs.truncate(1);
            c.run.modes = None;
            c.run.modes_per_m = Some(0.5);
            let s = c.catenary.span_m;
            c.run.start_m = s;
            c.run.end_m = l - s;
            c.run.analysis_m = [2.0 * s, l - 2.0 * s];
            if let Some(line) = &c.line {
                // A line: six spans of it, through its first overlap if it has one.
                let from = line
                    .overlap_sections_m()
                    .first()
                    .map_or(s, |o| (o[0] - 2.0 * s).max(s));
                c.run.start_m = from;
                c.run.end_m = (from + 6.0 * s).min(l - s);
                c.run.analysis_m = [from + s, c.run.end_m - 0.5 * s];
            }
            c.to_toml_string()
        })
        .collect()
}

fn mutate(text: &str, rng: &mut Rng) -> String {
    let mut t = text.to_string();
    for _ in 0..1 + rng.below(3) {
        match rng.below(10) {
            0..=6 => {
                let n = numbers(&t);
                if let Some(&(s, e)) = n.get(rng.below(n.len())) {
                    let r = REPLACEMENTS[rng.below(REPLACEMENTS.len())];
                    t = format!("{}{r}{}", &t[..s], &t[e..]);
                }
            }
            7 | 8 => {
                let lines: Vec<&str> = t.lines().collect();
                let k = rng.below(lines.len());
                t = lines
                    .iter()
                    .enumerate()
                    .filter(|(j, _)| *j != k)
                    .map(|(_, l)| *l)
                    .collect::<Vec<_>>()
                    .join("\n");
            }
            _ => {
                let mut k = rng.below(t.len());
                while !t.is_char_boundary(k) {
                    k -= 1;
                }
                t.truncate(k);
            }
        }
    }
    t
}

fn check_one(dir: &Path, k: usize, text: &str) -> Result<&'static str, String> {
    let case = dir.join(format!("case{k}.toml"));
    std::fs::write(&case, text).unwrap();
    let out = dir.join(format!("out{k}"));
    let mut child = Command::new(env!("CARGO_BIN_EXE_pcsim"))
        .arg("run")
        .arg(&case)
        .args(["--quiet", "--max-steps", "100000", "--out"])
        .arg(&out)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let t0 = Instant::now();
    while child.try_wait().unwrap().is_none() {
        if t0.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            return Err(format!("case {k} hangs:\n{text}"));
        }
        std::thread::sleep(Duration::from_millis(5));
    }
    let o = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&o.stderr);
    match o.status.code() {
        Some(0) => {
            // Every cell of the time series a finite number; every statistic a number (JSON has
            // no NaN: serde writes it as null).
            let ts = std::fs::read_to_string(out.join("timeseries.csv")).unwrap();
            for line in ts.lines().skip(1) {
                if !line
                    .split(',')
                    .all(|c| c.parse::<f64>().is_ok_and(|v| v.is_finite()))
                {
                    return Err(format!("case {k}: a non-finite cell `{line}`:\n{text}"));
                }
            }
            let js: serde_json::Value =
                serde_json::from_str(&std::fs::read_to_string(out.join("summary.json")).unwrap())
                    .unwrap();
            for p in js["pantographs"].as_array().unwrap() {
                if let Some(st) = p["stats"].as_object() {
                    if let Some((key, _)) = st.iter().find(|(_, v)| !v.is_number()) {
                        return Err(format!(
                            "case {k}: statistic {key} is not a number:\n{text}"
                        ));
                    }
                }
            }
            let _ = std::fs::remove_dir_all(&out);
            Ok("ran")
        }
        Some(2) if !err.contains("panicked") && err.contains("error: ") => Ok("refused"),
        code => Err(format!(
            "case {k}: exit {code:?}, stderr:\n{err}\ncase:\n{text}"
        )),
    }
}

#[test]
fn mutated_short_cases_exit_0_or_2_without_nan() {
    let n: usize = std::env::var("PCSIM_FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(200);
    let seed: u64 = std::env::var("PCSIM_FUZZ_SEED")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(20261125);
    let dir = std::env::temp_dir().join(format!("pcsim-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let bases = bases();
    let mut rng = Rng(seed);
    let texts: Vec<String> = (0..n)
        .map(|_| {
            let b = &bases[rng.below(bases.len())];
            mutate(b, &mut rng)
        })
        .collect();
    let results: Vec<Result<&str, String>> = std::thread::scope(|s| {
        let chunks: Vec<_> = texts
            .chunks(n.div_ceil(2).max(1))
            .enumerate()
            .map(|(c, chunk)| {
                let dir = &dir;
                s.spawn(move || {
                    chunk
                        .iter()
                        .enumerate()
                        .map(|(i, t)| check_one(dir, c * n.div_ceil(2) + i, t))
                        .collect::<Vec<_>>()
                })
            })
            .collect();
        chunks.into_iter().flat_map(|h| h.join().unwrap()).collect()
    });
    let ran = results.iter().filter(|r| matches!(r, Ok("ran"))).count();
    let refused = results
        .iter()
        .filter(|r| matches!(r, Ok("refused")))
        .count();
    eprintln!("fuzz (seed {seed}): {n} mutated cases, {ran} ran, {refused} refused");
    let failures: Vec<&String> = results.iter().filter_map(|r| r.as_ref().err()).collect();
    assert!(failures.is_empty(), "{}", failures[0]);
    assert!(
        ran > n / 20,
        "too few mutations ran ({ran}): the fuzz would test nothing"
    );
    let _ = std::fs::remove_dir_all(&dir);
}
