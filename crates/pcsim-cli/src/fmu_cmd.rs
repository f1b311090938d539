//! `pcsim fmu build`: bundle the FMI 2.0 FMU; `pcsim hil`: replay an input file through the
//! real-time catenary (the Rust reference the FMU is tested against).

use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use pcsim_core::realtime::{Coupling, RealtimeCatenary};
use std::fmt::Write as _;
use std::path::{Path, PathBuf};

#[derive(Args)]
pub struct FmuArgs {
    #[command(subcommand)]
    sub: FmuSub,
}

#[derive(Subcommand)]
enum FmuSub {
    /// Bundle `pcsim_fmu.fmu` (modelDescription.xml + binaries/linux64/pcsim_fmu.so).
    Build {
        /// Output directory.
        #[arg(long, default_value = "out/fmu")]
        out: PathBuf,
        /// The shared library (default: libpcsim_fmu.so built beside this executable).
        #[arg(long)]
        lib: Option<PathBuf>,
    },
    /// Print the generated modelDescription.xml.
    Xml,
}

#[derive(Args)]
pub struct HilArgs {
    /// Case file (TOML). Give this or --preset.
    case: Option<PathBuf>,
    /// Embedded preset name.
    #[arg(long)]
    preset: Option<String>,
    /// Window length, m.
    #[arg(long, default_value_t = 215.0)]
    window: f64,
    /// Input CSV: time_s, contact_force_n, pantograph_position_m (relative to the case's start),
    /// one row per internal step; each row is held over its step.
    #[arg(long)]
    input: PathBuf,
    /// Output CSV: time_s, wire_height_m, wire_velocity_m_s, contact_force_n after each step.
    #[arg(long)]
    out: PathBuf,
}

/// CRC-32 (IEEE) for the zip container.
fn crc32(data: &[u8]) -> u32 {
    let mut table = [0u32; 256];
    for (i, t) in table.iter_mut().enumerate() {
        let mut c = i as u32;
        for _ in 0..8 {
            c = if c & 1 != 0 {
                0xEDB8_8320 ^ (c >> 1)
            } else {
                c >> 1
            };
        }
        *t = c;
    }
    let mut c = 0xFFFF_FFFFu32;
    for &b in data {
        c = table[((c ^ b as u32) & 0xFF) as usize] ^ (c >> 8);
    }
    c ^ 0xFFFF_FFFF
}

/// A zip archive with stored (uncompressed) entries. Written by hand (≈40 lines) rather than
/// pulling a compression crate into the tree for two files.
fn zip_stored(entries: &[(&str, Vec<u8>)]) -> Vec<u8> {
    let mut out = Vec::new();
    let mut central = Vec::new();
    for (name, data) in entries {
        let offset = out.len() as u32;
        let crc = crc32(data);
        let (n, len) = (name.len() as u16, data.len() as u32);
        let mut h = Vec::new();
        h.extend_from_slice(&0x0403_4b50u32.to_le_bytes());
        h.extend_from_slice(&[20, 0, 0, 0, 0, 0, 0, 0, 0x21, 0]); // version, flags, method 0 (stored), time, date 1980-01-01
        h.extend_from_slice(&crc.to_le_bytes());
        h.extend_from_slice(&len.to_le_bytes());
        h.extend_from_slice(&len.to_le_bytes());
        h.extend_from_slice(&n.to_le_bytes());
        h.extend_from_slice(&0u16.to_le_bytes());
        out.extend_from_slice(&h);
        out.extend_from_slice(name.as_bytes());
        out.extend_from_slice(data);
        central.extend_from_slice(&0x0201_4b50u32.to_le_bytes());
        central.extend_from_slice(&[20, 3, 20, 0, 0, 0, 0, 0, 0x21, 0, 0x21, 0]);
        central.extend_from_slice(&crc.to_le_bytes());
        central.extend_from_slice(&len.to_le_bytes());
        central.extend_from_slice(&len.to_le_bytes());
        central.extend_from_slice(&n.to_le_bytes());
        central.extend_from_slice(&[0, 0, 0, 0, 0, 0, 0, 0]); // extra, comment, disk, internal attrs
        central.extend_from_slice(&(0o100644u32 << 16).to_le_bytes()); // external attrs: rw-r--r--
        central.extend_from_slice(&offset.to_le_bytes());
        central.extend_from_slice(name.as_bytes());
    }
    let cd_offset = out.len() as u32;
    out.extend_from_slice(&central);
    out.extend_from_slice(&0x0605_4b50u32.to_le_bytes());
    out.extend_from_slice(&[0, 0, 0, 0]);
    out.extend_from_slice(&(entries.len() as u16).to_le_bytes());
    out.extend_from_slice(&(entries.len() as u16).to_le_bytes());
    out.extend_from_slice(&(central.len() as u32).to_le_bytes());
    out.extend_from_slice(&cd_offset.to_le_bytes());
    out.extend_from_slice(&0u16.to_le_bytes());
    out
}

fn find_lib() -> Result<PathBuf> {
    let exe = std::env::current_exe().context("cannot locate the pcsim executable")?;
    let dir = exe.parent().context("executable has no directory")?;
    for p in [
        dir.join("libpcsim_fmu.so"),
        dir.join("deps").join("libpcsim_fmu.so"),
    ] {
        if p.exists() {
            return Ok(p);
        }
    }
    bail!("libpcsim_fmu.so not found beside {}; build it with `cargo build --release` (or pass --lib PATH)", exe.display())
}

pub fn fmu(a: FmuArgs) -> Result<i32> {
    match a.sub {
        FmuSub::Xml => {
            print!("{}", pcsim_fmu::vars::model_description());
            Ok(0)
        }
        FmuSub::Build { out, lib } => {
            let lib = match lib {
                Some(l) => l,
                None => find_lib()?,
            };
            let so =
                std::fs::read(&lib).with_context(|| format!("cannot read {}", lib.display()))?;
            let xml = pcsim_fmu::vars::model_description().into_bytes();
            let id = pcsim_fmu::MODEL_IDENTIFIER;
            let zip = zip_stored(&[
                ("modelDescription.xml", xml),
                (&format!("binaries/linux64/{id}.so"), so),
            ]);
            std::fs::create_dir_all(&out)
                .with_context(|| format!("cannot create {}", out.display()))?;
            let path = out.join(format!("{id}.fmu"));
            std::fs::write(&path, zip)
                .with_context(|| format!("cannot write {}", path.display()))?;
            println!(
                "wrote {} (FMI 2.0 co-simulation, linux64, from {})",
                path.display(),
                lib.display()
            );
            Ok(0)
        }
    }
}

fn read_input(p: &Path) -> Result<Vec<[f64; 3]>> {
    let text =
        std::fs::read_to_string(p).with_context(|| format!("cannot read {}", p.display()))?;
    let mut rows = Vec::new();
    for (i, line) in text.lines().enumerate().skip(1) {
        if line.trim().is_empty() {
            continue;
        }
        let v: Vec<f64> = line
            .split(',')
            .map(|s| s.trim().parse::<f64>())
            .collect::<Result<_, _>>()
            .with_context(|| format!("{} line {}: not three numbers", p.display(), i + 1))?;
        if v.len() != 3 || v.iter().any(|x| !x.is_finite()) {
            bail!("{} line {}: need three finite numbers (time_s, contact_force_n, pantograph_position_m)", p.display(), i + 1);
        }
        rows.push([v[0], v[1], v[2]]);
    }
    Ok(rows)
}

pub fn hil(a: HilArgs) -> Result<i32> {
    let mut case = crate::commands::load_case(a.case.as_ref(), a.preset.as_deref())?;
    case.pantographs.truncate(1);
    let rows = read_input(&a.input)?;
    let mut rt = RealtimeCatenary::new(&case, a.window, Coupling::Hil)?;
    let x0 = case.run.start_m;
    let mut s = String::from("time_s,wire_height_m,wire_velocity_m_s,contact_force_n\n");
    for r in &rows {
        rt.set_input(r[1], x0 + r[2]);
        let o = rt.step();
        let _ = writeln!(
            s,
            "{:.9},{:.12e},{:.12e},{:.12e}",
            r[0] + rt.dt_s(),
            o.wire_height_m,
            o.wire_velocity_m_s,
            o.contact_force_n
        );
    }
    std::fs::write(&a.out, s).with_context(|| format!("cannot write {}", a.out.display()))?;
    println!(
        "replayed {} steps through a {} m window; wrote {}",
        rows.len(),
        a.window,
        a.out.display()
    );
    Ok(0)
}
