//! `pcsim fmu build`: bundle the FMI 2.0 and FMI 3.0 FMUs (one library exports both ABIs);
//! `pcsim fmu xml`: print a model description.

use anyhow::{bail, Context, Result};
use clap::{Args, Subcommand};
use std::path::PathBuf;

#[derive(Args)]
pub struct FmuArgs {
    #[command(subcommand)]
    sub: FmuSub,
}

#[derive(Subcommand)]
enum FmuSub {
    /// Bundle `pcsim_fmu.fmu` (FMI 2.0: modelDescription.xml + binaries/linux64/pcsim_fmu.so)
    /// and `pcsim_fmu_fmi3.fmu` (FMI 3.0: binaries/x86_64-linux/pcsim_fmu.so).
    Build {
        /// Output directory.
        #[arg(long, default_value = "out/fmu")]
        out: PathBuf,
        /// The shared library (default: libpcsim_fmu.so built beside this executable).
        #[arg(long)]
        lib: Option<PathBuf>,
        /// Which FMI version: 2, 3 or both.
        #[arg(long, default_value = "both")]
        fmi_version: String,
        /// A case file to bundle (resources/case.toml, the `case` parameter's start value):
        /// the FMU runs it instead of the default preset. Checked here: it must load and
        /// build a real-time window of the default length.
        #[arg(long, value_name = "CASE.toml")]
        case: Option<PathBuf>,
    },
    /// Print the generated modelDescription.xml.
    Xml {
        /// Which FMI version: 2 or 3.
        #[arg(long, default_value = "2")]
        fmi_version: String,
    },
}

/// A case file's text for the FMU's resources, once it has loaded and built a real-time window
/// of the FMU's default length (as the FMU will at initialisation).
fn bundle_case(path: &PathBuf) -> Result<String> {
    let (case, text) = crate::common::load_case_with_text(Some(path), None)?;
    pcsim_core::session::RealtimeSession::new(
        &case,
        pcsim_fmu::vars::DEFAULT_WINDOW_M,
        pcsim_core::session::Coupling::Hil,
    )
    .with_context(|| {
        format!(
            "--case {}: the FMU's real-time window ({} m) cannot run it",
            path.display(),
            pcsim_fmu::vars::DEFAULT_WINDOW_M
        )
    })?;
    Ok(text)
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

/// The FMI 2.0 entry points a co-simulation FMU's library must export (a sample that a foreign
/// file would not have).
const REQUIRED_SYMBOLS: &[&str] = &[
    "fmi2GetVersion",
    "fmi2Instantiate",
    "fmi2FreeInstance",
    "fmi2SetupExperiment",
    "fmi2DoStep",
    "fmi2GetReal",
    "fmi2SetReal",
    "fmi3InstantiateCoSimulation",
    "fmi3DoStep",
    "fmi3GetFloat64",
    "fmi3SerializeFMUState",
];

/// Check that `bytes` are a Linux shared library (ELF, type ET_DYN) naming the FMI 2.0 entry
/// points in its symbol tables.
pub fn check_library(path: &std::path::Path, bytes: &[u8]) -> Result<()> {
    if bytes.len() < 64 || &bytes[..4] != b"\x7fELF" {
        bail!(
            "--lib {}: not an ELF shared library (the FMU needs the pcsim-fmu library, libpcsim_fmu.so)",
            path.display()
        );
    }
    let e_type = match bytes[5] {
        1 => u16::from_le_bytes([bytes[16], bytes[17]]),
        _ => u16::from_be_bytes([bytes[16], bytes[17]]),
    };
    if e_type != 3 {
        bail!(
            "--lib {}: an ELF file but not a shared library (e_type {e_type})",
            path.display()
        );
    }
    let missing: Vec<&str> = REQUIRED_SYMBOLS
        .iter()
        .copied()
        .filter(|sym| {
            let mut pat = sym.as_bytes().to_vec();
            pat.push(0);
            !bytes.windows(pat.len()).any(|w| w == pat.as_slice())
        })
        .collect();
    if !missing.is_empty() {
        bail!(
            "--lib {}: a shared library that does not export the FMI 2.0 and 3.0 entry points ({} missing)",
            path.display(),
            missing.join(", ")
        );
    }
    Ok(())
}

pub fn fmu(a: FmuArgs) -> Result<i32> {
    match a.sub {
        FmuSub::Xml { fmi_version } => {
            match fmi_version.as_str() {
                "2" => print!("{}", pcsim_fmu::vars::model_description()),
                "3" => print!("{}", pcsim_fmu::vars::model_description_v3()),
                other => bail!("--fmi-version {other}: use 2 or 3"),
            }
            Ok(0)
        }
        FmuSub::Build {
            out,
            lib,
            fmi_version,
            case,
        } => {
            let bundled = case.as_ref().map(bundle_case).transpose()?;
            let versions: &[u8] = match fmi_version.as_str() {
                "2" => &[2],
                "3" => &[3],
                "both" => &[2, 3],
                other => bail!("--fmi-version {other}: use 2, 3 or both"),
            };
            let lib = match lib {
                Some(l) => l,
                None => find_lib()?,
            };
            let so =
                std::fs::read(&lib).with_context(|| format!("cannot read {}", lib.display()))?;
            check_library(&lib, &so)?;
            std::fs::create_dir_all(&out)
                .with_context(|| format!("cannot create {}", out.display()))?;
            let id = pcsim_fmu::MODEL_IDENTIFIER;
            let start = match bundled {
                Some(_) => pcsim_fmu::vars::BUNDLED_CASE,
                None => pcsim_fmu::vars::DEFAULT_CASE,
            };
            for &v in versions {
                let (xml, platform, file, label) = match v {
                    2 => (
                        pcsim_fmu::vars::model_description_for(start),
                        "linux64",
                        format!("{id}.fmu"),
                        "FMI 2.0 co-simulation, linux64",
                    ),
                    _ => (
                        pcsim_fmu::vars::model_description_v3_for(start),
                        "x86_64-linux",
                        format!("{id}_fmi3.fmu"),
                        "FMI 3.0 co-simulation, x86_64-linux",
                    ),
                };
                let binary = format!("binaries/{platform}/{id}.so");
                let resource = format!("resources/{}", pcsim_fmu::vars::BUNDLED_CASE);
                let mut entries = vec![
                    ("modelDescription.xml", xml.into_bytes()),
                    (binary.as_str(), so.clone()),
                ];
                if let Some(text) = &bundled {
                    entries.push((resource.as_str(), text.clone().into_bytes()));
                }
                let zip = zip_stored(&entries);
                let path = out.join(file);
                std::fs::write(&path, zip)
                    .with_context(|| format!("cannot write {}", path.display()))?;
                let with = case
                    .as_ref()
                    .map(|c| format!(", case {}", c.display()))
                    .unwrap_or_default();
                println!(
                    "wrote {} ({label}, from {}{with})",
                    path.display(),
                    lib.display()
                );
            }
            Ok(0)
        }
    }
}
