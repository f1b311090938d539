//! Sweep output directories (`eva`, `window`): one CSV row per case, per-case files in `cases/`,
//! a manifest with the sweep's fingerprint, and a merge of shards that refuses shards of
//! different sweeps, never writes into a shard and leaves nothing behind when it fails.

use anyhow::{bail, Context, Result};
use pcsim_core::analysis::sweep::merge_rows;
use std::path::{Path, PathBuf};

use crate::common::shown;
use crate::output::write_manifest;

/// What a kind of sweep directory holds.
pub struct SweepKind {
    /// The manifest's kind.
    pub kind: pcsim_core::study::StudyKind,
    /// The per-case CSV and its header.
    pub csv: &'static str,
    pub header: &'static str,
    /// What the columns mean (written into the manifest).
    pub columns: &'static str,
    /// Work on a merged directory before it is moved into place (summaries over all cases).
    pub finish: fn(&Path) -> Result<()>,
}

/// A shard directory, read for the merge.
struct ShardDir {
    dir: PathBuf,
    fingerprint: String,
    cases: usize,
    shard: (usize, usize),
    rows: Vec<(usize, String)>,
}

/// The largest per-case CSV of a shard that a merge reads, bytes.
const MAX_SHARD_CSV_BYTES: u64 = 256 << 20;

/// Read a shard for the merge, its manifest parsed into checked types: complete, of this kind
/// and this version, `shard = [I, N]` with `1 ≤ N` and `I < N`, `cases` at most the grid a
/// shard can describe, the per-case rows of this version, and its `cases/` folder present
/// when it holds cases. A corrupt manifest is an error naming the field, never a panic.
fn read_shard(k: &SweepKind, d: &Path) -> Result<ShardDir> {
    let m = crate::output::read_complete_manifest(d).with_context(|| {
        format!(
            "{} cannot be merged as a shard of a {} sweep",
            d.display(),
            k.kind
        )
    })?;
    if m.kind != k.kind {
        bail!(
            "{} is not a {} sweep (pcsim.json kind `{}`)",
            d.display(),
            k.kind,
            m.kind
        );
    }
    if m.version != env!("CARGO_PKG_VERSION") {
        bail!(
            "{} was made by pcsim {} and cannot be merged by pcsim {}: rerun the shard with this version",
            d.display(),
            if m.version.is_empty() { "(unknown)" } else { m.version.as_str() },
            env!("CARGO_PKG_VERSION")
        );
    }
    let v = &m.record.study;
    let [si, sn] = v
        .shard
        .with_context(|| format!("{}: pcsim.json has no `shard` [I, N]", d.display()))?;
    if sn == 0 || si >= sn {
        bail!(
            "{}: pcsim.json `shard` is [{si}, {sn}]: need 0 ≤ I < N",
            d.display()
        );
    }
    let cases = v
        .cases
        .with_context(|| format!("{}: pcsim.json has no count of `cases`", d.display()))?;
    if sn > MAX_SHARDS || cases > MAX_CASES {
        bail!(
            "{}: pcsim.json says {cases} cases in {sn} shards: more than a sweep can hold ({MAX_CASES} cases, {MAX_SHARDS} shards)",
            d.display()
        );
    }
    let fingerprint = (v.fingerprint.clone())
        .filter(|f| !f.is_empty())
        .with_context(|| format!("{}: pcsim.json has no `fingerprint`", d.display()))?;
    if !m.lists(k.csv) {
        bail!("{}: pcsim.json does not list {}", d.display(), k.csv);
    }
    let p = d.join(k.csv);
    let text = crate::common::read_text_limited(&p, MAX_SHARD_CSV_BYTES, "a shard's table")?;
    let mut lines = text.lines();
    if lines.next() != Some(k.header) {
        bail!(
            "{} is not a {} of this version of pcsim (header differs)",
            p.display(),
            k.csv
        );
    }
    let mut rows = Vec::new();
    for l in lines.filter(|l| !l.is_empty()) {
        let idx: usize = l
            .split(',')
            .next()
            .and_then(|s| s.parse().ok())
            .with_context(|| format!("{}: bad row `{l}`", p.display()))?;
        if idx >= cases {
            bail!(
                "{}: row of case {idx}, but the sweep has {cases} cases",
                p.display()
            );
        }
        rows.push((idx, l.to_string()));
    }
    if !rows.is_empty() && !m.files.iter().any(|f| f.starts_with("cases/")) {
        bail!(
            "{}: its cases/ folder is missing (the per-case files of its {} rows)",
            d.display(),
            rows.len()
        );
    }
    Ok(ShardDir {
        dir: d.to_path_buf(),
        fingerprint,
        cases,
        shard: (si, sn),
        rows,
    })
}

/// The most shards and cases a merge accepts (a manifest claiming more is corrupt).
pub const MAX_SHARDS: usize = 100_000;
/// See [`MAX_SHARDS`].
pub const MAX_CASES: usize = 10_000_000;

/// Join the shards of one sweep: every shard exactly once, all with one fingerprint; the result
/// is built beside the output and moved into place only when complete, so a failed merge leaves
/// nothing behind and never writes into a shard.
pub fn merge(k: &SweepKind, dirs: &[PathBuf], out: &Path, no_plot: bool) -> Result<i32> {
    if dirs.is_empty() {
        bail!("give the shard directories to merge");
    }
    let shards: Vec<ShardDir> = dirs
        .iter()
        .map(|d| read_shard(k, d))
        .collect::<Result<_>>()?;
    let first = &shards[0];
    let n = check_shards(&shards)?;
    let rows = merge_rows(shards.iter().flat_map(|s| s.rows.clone()).collect())?;
    if rows.len() != first.cases {
        bail!(
            "the shards hold {} of the sweep's {} cases",
            rows.len(),
            first.cases
        );
    }
    // Never write into an input.
    refuse_writing_into_a_shard(&shards, out)?;
    let od = crate::output::OutDir::begin(out)?;
    let partial = od.path();
    std::fs::create_dir_all(partial.join("cases"))
        .with_context(|| format!("cannot create {}", partial.join("cases").display()))?;
    for s in &shards {
        let cdir = s.dir.join("cases");
        if cdir.is_dir() {
            for e in std::fs::read_dir(&cdir)
                .with_context(|| format!("cannot read {}", cdir.display()))?
            {
                let e = e?;
                let to = partial.join("cases").join(e.file_name());
                std::fs::copy(e.path(), &to).with_context(|| {
                    format!("cannot copy {} to {}", e.path().display(), to.display())
                })?;
            }
        }
    }
    // The case as given, with its sources (the shards share it: one fingerprint).
    let case = first.dir.join("case.toml");
    if case.is_file() {
        std::fs::copy(&case, partial.join("case.toml"))
            .with_context(|| format!("cannot copy {} into the merged sweep", case.display()))?;
    }
    let mut csv = String::from(k.header);
    csv.push('\n');
    for (_, r) in &rows {
        csv.push_str(r);
        csv.push('\n');
    }
    crate::output::write_file(&partial.join(k.csv), csv)?;
    write_manifest(
        partial,
        k.kind.name(),
        crate::output::StudyManifest {
            fingerprint: Some(first.fingerprint.clone()),
            cases: Some(first.cases),
            shard: Some([0, 1]),
            merged_from_shards: Some(n),
            cases_in_shard: Some(rows.iter().map(|r| r.0).collect()),
            columns: Some(k.columns.to_string()),
            ..Default::default()
        },
    )?;
    (k.finish)(partial).with_context(|| format!("merging into {}", out.display()))?;
    if !no_plot {
        crate::plot::redraw_kind(partial, k.kind)
            .with_context(|| format!("merging into {}", out.display()))?;
    }
    od.commit()?;
    println!(
        "merged {} cases from {} shards into {}",
        rows.len(),
        dirs.len(),
        shown(out, k.csv)
    );
    Ok(0)
}

/// The shards of one sweep, each once and none missing, split the same way: their count.
fn check_shards(shards: &[ShardDir]) -> Result<usize> {
    let first = &shards[0];
    for s in &shards[1..] {
        if s.shard.1 != first.shard.1 {
            bail!(
                "shard {}/{} ({}) cannot be merged with shard {}/{} ({}): they split the sweep differently",
                s.shard.0,
                s.shard.1,
                s.dir.display(),
                first.shard.0,
                first.shard.1,
                first.dir.display()
            );
        }
        if s.fingerprint != first.fingerprint {
            bail!(
                "{} and {} are shards of different sweeps (another case, grid, seeds or option)",
                first.dir.display(),
                s.dir.display()
            );
        }
    }
    let n = first.shard.1;
    let mut seen = vec![None; n];
    for s in shards {
        if let Some(prev) = seen[s.shard.0].replace(&s.dir) {
            bail!(
                "shard {}/{n} is given twice ({} and {})",
                s.shard.0,
                prev.display(),
                s.dir.display()
            );
        }
    }
    if let Some(k) = seen.iter().position(|s| s.is_none()) {
        bail!("shard {k}/{n} of the sweep is missing");
    }
    Ok(n)
}

/// Refuse an output directory inside a shard, or holding one.
fn refuse_writing_into_a_shard(shards: &[ShardDir], out: &Path) -> Result<()> {
    let canon = |p: &Path| std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf());
    let out_abs = if out.exists() {
        canon(out)
    } else {
        let parent = out.parent().filter(|p| !p.as_os_str().is_empty());
        let parent = parent.map(canon).unwrap_or_else(|| canon(Path::new(".")));
        parent.join(out.file_name().unwrap_or_default())
    };
    for s in shards {
        let d = canon(&s.dir);
        if out_abs.starts_with(&d) || d.starts_with(&out_abs) {
            bail!(
                "--out {} would write into the shard {}: choose another directory",
                out.display(),
                s.dir.display()
            );
        }
    }
    Ok(())
}

/// Monte Carlo summary of a sweep with seeds: `montecarlo.csv` with, per grid point (the
/// `group` columns), the number of realisations and the mean, standard deviation and 95 %
/// confidence interval of each `values` column (empty cells are realisations where the value was
/// not reached; they are counted in `n_missing_<column>`). Does nothing for a single realisation.
pub fn write_montecarlo(dir: &Path, csv: &str, group: &[&str], values: &[&str]) -> Result<()> {
    use pcsim_core::study::montecarlo::Spread;
    let p = dir.join(csv);
    let text =
        std::fs::read_to_string(&p).with_context(|| format!("cannot read {}", p.display()))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or("").split(',').collect();
    let col = |name: &str| {
        header
            .iter()
            .position(|h| *h == name)
            .with_context(|| format!("{} has no column {name}", p.display()))
    };
    let seed_col = col("seed_offset")?;
    let gcols: Vec<usize> = group.iter().map(|g| col(g)).collect::<Result<_>>()?;
    let vcols: Vec<usize> = values.iter().map(|v| col(v)).collect::<Result<_>>()?;
    let rows: Vec<Vec<&str>> = lines
        .filter(|l| !l.is_empty())
        .map(|l| l.split(',').collect())
        .collect();
    if rows.iter().all(|r| r.get(seed_col) == Some(&"0")) {
        return Ok(());
    }
    let mut keys: Vec<Vec<String>> = Vec::new();
    for r in &rows {
        let k: Vec<String> = gcols.iter().map(|&c| r[c].to_string()).collect();
        if !keys.contains(&k) {
            keys.push(k);
        }
    }
    let mut out = group.join(",") + ",n";
    for v in values {
        out += &format!(",{v}_mean,{v}_std,{v}_ci95_low,{v}_ci95_high,n_missing_{v}");
    }
    out.push('\n');
    for k in &keys {
        let members: Vec<&Vec<&str>> = rows
            .iter()
            .filter(|r| gcols.iter().zip(k).all(|(&c, v)| r[c] == v))
            .collect();
        out += &format!("{},{}", k.join(","), members.len());
        for &c in &vcols {
            let vals: Vec<f64> = members.iter().filter_map(|r| r[c].parse().ok()).collect();
            let missing = members.len() - vals.len();
            match Spread::of(&vals) {
                Some(s) => {
                    // An undefined spread (one realisation) is an empty cell, never 0.
                    let o = |v: Option<f64>| v.map_or(String::new(), |x| format!("{x:.4}"));
                    out += &format!(
                        ",{:.4},{},{},{},{missing}",
                        s.mean,
                        o(s.std),
                        o(s.ci95_low),
                        o(s.ci95_high)
                    )
                }
                None => out += &format!(",,,,,{missing}"),
            }
        }
        out.push('\n');
    }
    crate::output::write_file(&dir.join("montecarlo.csv"), out)
}

/// A sweep's output directory begun (locked, staged) with the case as given (every value with
/// its source, for the report), and its progress over `cases` cases: the start every sweep
/// command shares (`eva`, `window`).
pub fn begin(
    out: &Path,
    case_text: &str,
    kind: &str,
    cases: usize,
    ctx: &crate::common::Ctx,
) -> Result<(crate::output::OutDir, crate::progress::Progress)> {
    let od = crate::output::OutDir::begin(out)?;
    crate::output::write_file(&od.path().join("case.toml"), case_text)?;
    let pb = crate::progress::Progress::new(
        kind,
        cases as u64,
        ctx.progress,
        &format!("{kind} [{{bar:40}}] {{pos}}/{{len}} cases {{elapsed_precise}} eta {{eta}}"),
    );
    Ok((od, pb))
}

/// A sweep's rows as CSV text: the header, then a line per row.
pub fn rows_csv(header: &str, rows: impl IntoIterator<Item = String>) -> String {
    let mut csv = String::from(header);
    csv.push('\n');
    for r in rows {
        csv.push_str(&r);
        csv.push('\n');
    }
    csv
}

/// A sweep shard's manifest entries: its fingerprint, the cases of the whole sweep, its shard
/// `[I, N]` and its cases, and what its columns mean (a study adds its own to it).
pub fn shard_manifest(
    fingerprint: &str,
    cases: usize,
    shard: pcsim_core::analysis::sweep::Shard,
    cases_in_shard: Vec<usize>,
    columns: &str,
) -> crate::output::StudyManifest {
    crate::output::StudyManifest {
        fingerprint: Some(fingerprint.to_string()),
        cases: Some(cases),
        shard: Some([shard.index, shard.count]),
        cases_in_shard: Some(cases_in_shard),
        columns: Some(columns.to_string()),
        ..Default::default()
    }
}
