//! `pcsim eva`: EVA sweeps over speed, tension and damping, in parallel, with shards and a merge
//! that refuses shards of different sweeps.

use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use pcsim_core::analysis::eva::{run_eva, EvaOutput, EvaRow, EvaSettings};
use pcsim_core::analysis::sweep::{merge_rows, parallel_map, parse_damping, Grid, Job, Shard};
use pcsim_core::input::units::{parse_quantity, Dimension};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use crate::common::{apply, load_case, shown, Ctx, Override};
use crate::output::{read_manifest, write_manifest};
use crate::progress::Progress;

#[derive(Args)]
#[command(args_conflicts_with_subcommands = true)]
pub struct EvaArgs {
    #[command(subcommand)]
    sub: Option<EvaSub>,
    /// Case file (TOML). Give this or --preset.
    case: Option<PathBuf>,
    /// Embedded preset name.
    #[arg(long)]
    preset: Option<String>,
    /// Speeds, comma-separated: km/h, or with a unit (250km/h). Default: the case's speed.
    #[arg(long, value_delimiter = ',', value_name = "KM/H")]
    speed: Vec<String>,
    /// Contact-wire tensions, comma-separated: kN, or with a unit (9.8kN, 9800N). Default: the
    /// case's tension.
    #[arg(long, value_delimiter = ',', value_name = "KN")]
    tension: Vec<String>,
    /// Dampings (comma-separated): `preset`, `rayleigh:ALPHA:BETA` or `modal:RATIO`.
    #[arg(long, value_delimiter = ',', default_value = "preset")]
    damping: Vec<String>,
    /// Output directory.
    #[arg(long, default_value = "out/eva")]
    out: PathBuf,
    /// Worker threads, at least 1 [default: all cores].
    #[arg(long)]
    jobs: Option<usize>,
    /// Run only the cases with index ≡ I (mod N), as `I/N`.
    #[arg(long)]
    shard: Option<String>,
    /// Step Δd between window lengths, m.
    #[arg(long, default_value_t = 1.0)]
    step: f64,
    /// Tolerance of the paper's criterion, J.
    #[arg(long, default_value_t = 0.01)]
    tol: f64,
    /// Energy fraction of the step-independent criterion.
    #[arg(long, default_value_t = 0.99)]
    fraction: f64,
    /// Largest window length, m (default: the model length).
    #[arg(long)]
    max_window: Option<f64>,
    /// Snapshot position of the leading pantograph, m (default: mid-model).
    #[arg(long)]
    snapshot_at: Option<f64>,
    /// No figures.
    #[arg(long)]
    no_plot: bool,
}

#[derive(Subcommand)]
enum EvaSub {
    /// Join the shards of one sweep (their eva.csv, case files and manifests) into one directory.
    Merge {
        /// Shard output directories: every shard of the sweep, once.
        #[arg(required = true)]
        dirs: Vec<PathBuf>,
        /// Merged output directory (not one of the shards).
        #[arg(long, default_value = "out/eva")]
        out: PathBuf,
        /// No figures.
        #[arg(long)]
        no_plot: bool,
    },
}

/// What the columns of `eva.csv` mean (written into the manifest).
const COLUMNS: &str = "lengths in m, energies in J; an EVA column is empty where its criterion was not reached within the largest window; *_max_m and *_mean_m are the EVA of the maximum over the passage and of the time average";

fn case_stem(job: &Job) -> String {
    format!(
        "case{:04}_v{}_t{}",
        job.index,
        job.speed_kmh,
        job.tension_n / 1e3
    )
}

fn write_case_files(dir: &Path, job: &Job, o: &EvaOutput) -> Result<()> {
    let cdir = dir.join("cases");
    std::fs::create_dir_all(&cdir)?;
    let mut s = String::from("xi_m,snapshot_j_per_m,max_j_per_m,mean_j_per_m\n");
    for i in 0..o.xi_m.len() {
        let _ = writeln!(
            s,
            "{:.4},{:.6e},{:.6e},{:.6e}",
            o.xi_m[i],
            o.snapshot.density_j_per_m[i],
            o.max.density_j_per_m[i],
            o.mean.density_j_per_m[i]
        );
    }
    std::fs::write(cdir.join(format!("{}_distribution.csv", case_stem(job))), s)?;
    let mut s = String::from("window_m,snapshot_j,max_j,mean_j\n");
    for i in 0..o.window_m.len() {
        let _ = writeln!(
            s,
            "{},{:.6},{:.6},{:.6}",
            o.window_m[i], o.snapshot.window_j[i], o.max.window_j[i], o.mean.window_j[i]
        );
    }
    std::fs::write(cdir.join(format!("{}_window.csv", case_stem(job))), s)?;
    Ok(())
}

/// FNV-1a 64-bit hash, for sweep fingerprints.
pub fn fnv1a64(data: &[u8]) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in data {
        h ^= b as u64;
        h = h.wrapping_mul(0x0100_0000_01b3);
    }
    format!("{h:016x}")
}

pub fn eva(a: EvaArgs, ctx: &Ctx) -> Result<i32> {
    if let Some(EvaSub::Merge { dirs, out, no_plot }) = a.sub {
        return merge(&dirs, &out, no_plot);
    }
    let base = load_case(a.case.as_ref(), a.preset.as_deref())?;
    let dampings = a
        .damping
        .iter()
        .map(|d| parse_damping(d, &base.catenary.damping))
        .collect::<Result<Vec<_>, _>>()?;
    for (name, v) in [
        ("--step", a.step),
        ("--tol", a.tol),
        ("--max-window", a.max_window.unwrap_or(1.0)),
    ] {
        if !(v.is_finite() && v > 0.0) {
            bail!("{name} = {v}: must be a finite number > 0");
        }
    }
    if !(a.fraction > 0.0 && a.fraction < 1.0) {
        bail!("--fraction = {}: must lie in (0, 1)", a.fraction);
    }
    if a.jobs == Some(0) {
        bail!("--jobs 0: give at least 1 worker (leave it out to use every core)");
    }
    let shard = match &a.shard {
        None => Shard::ALL,
        Some(s) => Shard::parse(s)?,
    };
    let speeds: Vec<f64> = a
        .speed
        .iter()
        .map(|s| {
            Ok(parse_quantity(s, Dimension::Speed, 1.0)
                .map_err(|e| anyhow::anyhow!("--speed {e}"))?
                .value)
        })
        .collect::<Result<_>>()?;
    let tensions: Vec<f64> = a
        .tension
        .iter()
        .map(|s| {
            Ok(parse_quantity(s, Dimension::Force, 1e3)
                .map_err(|e| anyhow::anyhow!("--tension {e}"))?
                .value)
        })
        .collect::<Result<_>>()?;
    // Every grid point is checked up front, with the flags named on error.
    let base = apply(&base, &[])?;
    let grid = Grid::new(base.clone(), speeds, tensions, dampings);
    let jobs = grid.jobs().with_context(|| {
        let mut o: Vec<Override> = Vec::new();
        if !a.speed.is_empty() {
            o.push(Override {
                flag: format!("--speed {}", a.speed.join(",")),
                reading: "km/h unless a unit is given".into(),
                path: String::new(),
                value: 0.0,
            });
        }
        if !a.tension.is_empty() {
            o.push(Override {
                flag: format!("--tension {}", a.tension.join(",")),
                reading: "kN unless a unit is given; write 9800N for newtons".into(),
                path: String::new(),
                value: 0.0,
            });
        }
        format!("in the sweep (with {})", crate::common::override_note(&o))
    })?;
    let settings = EvaSettings {
        step_m: a.step,
        max_window_m: a.max_window,
        tolerance_j: a.tol,
        fraction: a.fraction,
        snapshot_at_m: a.snapshot_at,
        budget: ctx.budget,
        ..EvaSettings::default()
    };
    // The sweep's fingerprint: its case, grid and options, and the number of shards.
    let mut desc = base.to_toml_string();
    let _ = write!(
        desc,
        "\n[sweep]\nspeeds = {:?}\ntensions = {:?}\ndampings = {:?}\nstep = {}\ntol = {}\nfraction = {}\nmax_window = {:?}\nsnapshot_at = {:?}\npoints_per_mode = {}\nsample_every = {}\nshards = {}\nversion = {}\n",
        grid.speeds_kmh,
        grid.tensions_n,
        grid.dampings.iter().map(pcsim_core::analysis::sweep::damping_label).collect::<Vec<_>>(),
        settings.step_m,
        settings.tolerance_j,
        settings.fraction,
        settings.max_window_m,
        settings.snapshot_at_m,
        settings.points_per_mode,
        settings.sample_every_s,
        shard.count,
        env!("CARGO_PKG_VERSION")
    );
    let fingerprint = fnv1a64(desc.as_bytes());
    let mine: Vec<&Job> = jobs.iter().filter(|j| shard.contains(j.index)).collect();
    std::fs::create_dir_all(&a.out)
        .with_context(|| format!("cannot create {}", a.out.display()))?;
    let pb = Progress::new(
        "eva",
        mine.len() as u64,
        ctx.progress,
        "eva [{bar:40}] {pos}/{len} cases {elapsed_precise} eta {eta}",
    );
    let results = parallel_map(&mine, a.jobs, |job| {
        let setup = pcsim_core::Setup::from_case_with(&job.case, &ctx.budget)?;
        let out = run_eva(&setup, &settings, &mut |_| true)
            .map_err(|e| anyhow::anyhow!("case {}: {e}", job.index))?;
        write_case_files(&a.out, job, &out)?;
        pb.inc();
        Ok::<_, anyhow::Error>(out)
    });
    pb.finish();
    let done: Vec<EvaOutput> = results.into_iter().collect::<Result<_>>()?;
    let rows: Vec<EvaRow> = mine
        .iter()
        .zip(&done)
        .map(|(j, o)| EvaRow::new(j.index, j.speed_kmh, j.tension_n / 1e3, &j.damping, o))
        .collect();
    let mut csv = String::from(EvaRow::HEADER);
    csv.push('\n');
    for r in &rows {
        csv.push_str(&r.to_csv());
        csv.push('\n');
    }
    std::fs::write(a.out.join("eva.csv"), &csv)?;
    write_manifest(
        &a.out,
        "eva",
        serde_json::json!({
            "fingerprint": fingerprint,
            "cases": jobs.len(),
            "shard": [shard.index, shard.count],
            "cases_in_shard": mine.iter().map(|j| j.index).collect::<Vec<_>>(),
            "columns": COLUMNS,
        }),
    )?;
    if mine.is_empty() {
        println!(
            "shard {}/{} holds none of the {} cases: wrote {} (header only) and {}, which `eva merge` needs",
            shard.index,
            shard.count,
            jobs.len(),
            shown(&a.out, "eva.csv"),
            shown(&a.out, "pcsim.json")
        );
        return Ok(0);
    }
    println!(
        "EVA (Δd = {} m, tolerance {} J, fraction {}), snapshot at {} m; window energies in J",
        a.step,
        a.tol,
        a.fraction,
        done.first().map(|d| d.snapshot_at_m).unwrap_or(0.0)
    );
    println!(
        "{:>6} {:>8} {:<22} {:>12} {:>12} {:>14} {:>12}",
        "km/h", "kN", "damping", "EVA step [m]", "EVA 99% [m]", "converged [J]", "total [J]"
    );
    for r in &rows {
        let f = |v: Option<f64>| {
            v.map(|x| format!("{x:.1}"))
                .unwrap_or_else(|| "not reached".into())
        };
        println!(
            "{:>6} {:>8} {:<22} {:>12} {:>12} {:>14} {:>12.3}",
            r.speed_kmh,
            r.tension_kn,
            r.damping,
            f(r.eva_step_m),
            f(r.eva_fraction_m),
            f(r.converged_energy_j),
            r.total_energy_j
        );
    }
    println!(
        "wrote {} and {}",
        shown(&a.out, "eva.csv"),
        shown(&a.out, "cases")
    );
    if !a.no_plot && shard == Shard::ALL {
        let files = crate::plot::redraw(&a.out)?;
        crate::plot::report(&files);
    }
    Ok(0)
}

/// A shard directory, read for the merge.
struct ShardDir {
    dir: PathBuf,
    fingerprint: String,
    cases: usize,
    shard: (usize, usize),
    rows: Vec<(usize, String)>,
}

fn read_shard(d: &Path) -> Result<ShardDir> {
    let m = read_manifest(d)?.with_context(|| {
        format!(
            "{} is not a shard of an EVA sweep (no pcsim.json; made by an older pcsim?)",
            d.display()
        )
    })?;
    if m["kind"] != "eva" {
        bail!(
            "{} is not an EVA sweep (pcsim.json kind {})",
            d.display(),
            m["kind"]
        );
    }
    let p = d.join("eva.csv");
    let text =
        std::fs::read_to_string(&p).with_context(|| format!("cannot read {}", p.display()))?;
    let mut lines = text.lines();
    if lines.next() != Some(EvaRow::HEADER) {
        bail!(
            "{} is not an eva.csv of this version of pcsim (header differs)",
            p.display()
        );
    }
    let mut rows = Vec::new();
    for l in lines.filter(|l| !l.is_empty()) {
        let idx: usize = l
            .split(',')
            .next()
            .and_then(|s| s.parse().ok())
            .with_context(|| format!("{}: bad row `{l}`", p.display()))?;
        rows.push((idx, l.to_string()));
    }
    let num = |v: &serde_json::Value, what: &str| -> Result<usize> {
        v.as_u64()
            .map(|x| x as usize)
            .with_context(|| format!("{}: pcsim.json lacks `{what}`", d.display()))
    };
    Ok(ShardDir {
        dir: d.to_path_buf(),
        fingerprint: m["fingerprint"].as_str().unwrap_or_default().to_string(),
        cases: num(&m["cases"], "cases")?,
        shard: (num(&m["shard"][0], "shard")?, num(&m["shard"][1], "shard")?),
        rows,
    })
}

/// Join the shards of one sweep: every shard exactly once, all with one fingerprint; the result
/// is built beside the output and moved into place only when complete, so a failed merge leaves
/// nothing behind and never writes into a shard.
fn merge(dirs: &[PathBuf], out: &Path, no_plot: bool) -> Result<i32> {
    let shards: Vec<ShardDir> = dirs.iter().map(|d| read_shard(d)).collect::<Result<_>>()?;
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
                "{} and {} are shards of different sweeps (another case, grid, --step, --tol, --fraction or other option)",
                first.dir.display(),
                s.dir.display()
            );
        }
    }
    let n = first.shard.1;
    let mut seen = vec![None; n];
    for s in &shards {
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
    let rows = merge_rows(shards.iter().flat_map(|s| s.rows.clone()).collect())?;
    if rows.len() != first.cases {
        bail!(
            "the shards hold {} of the sweep's {} cases",
            rows.len(),
            first.cases
        );
    }
    // Never write into an input.
    let canon = |p: &Path| std::fs::canonicalize(p).unwrap_or_else(|_| p.to_path_buf());
    let out_abs = if out.exists() {
        canon(out)
    } else {
        let parent = out.parent().filter(|p| !p.as_os_str().is_empty());
        let parent = parent.map(canon).unwrap_or_else(|| canon(Path::new(".")));
        parent.join(out.file_name().unwrap_or_default())
    };
    for s in &shards {
        let d = canon(&s.dir);
        if out_abs.starts_with(&d) || d.starts_with(&out_abs) {
            bail!(
                "--out {} would write into the shard {}: choose another directory",
                out.display(),
                s.dir.display()
            );
        }
    }
    if out.exists()
        && read_manifest(out).ok().flatten().is_none()
        && out.read_dir()?.next().is_some()
    {
        bail!(
            "--out {} exists and is not an output of pcsim: choose another directory",
            out.display()
        );
    }
    let partial = out_abs.with_file_name(format!(
        "{}.partial-{}",
        out_abs.file_name().unwrap_or_default().to_string_lossy(),
        std::process::id()
    ));
    let result = (|| -> Result<()> {
        std::fs::create_dir_all(partial.join("cases"))?;
        for s in &shards {
            let cdir = s.dir.join("cases");
            if cdir.is_dir() {
                for e in std::fs::read_dir(&cdir)? {
                    let e = e?;
                    std::fs::copy(e.path(), partial.join("cases").join(e.file_name()))?;
                }
            }
        }
        let mut csv = String::from(EvaRow::HEADER);
        csv.push('\n');
        for (_, r) in &rows {
            csv.push_str(r);
            csv.push('\n');
        }
        std::fs::write(partial.join("eva.csv"), csv)?;
        write_manifest(
            &partial,
            "eva",
            serde_json::json!({
                "fingerprint": first.fingerprint,
                "cases": first.cases,
                "shard": [0, 1],
                "merged_from_shards": n,
                "cases_in_shard": rows.iter().map(|r| r.0).collect::<Vec<_>>(),
                "columns": COLUMNS,
            }),
        )?;
        if !no_plot {
            crate::plot::redraw(&partial)?;
        }
        if out.exists() {
            std::fs::remove_dir_all(out)?;
        }
        std::fs::rename(&partial, out)?;
        Ok(())
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_dir_all(&partial);
        return Err(e.context(format!("merging into {}", out.display())));
    }
    println!(
        "merged {} cases from {} shards into {}",
        rows.len(),
        dirs.len(),
        shown(out, "eva.csv")
    );
    Ok(0)
}
