//! `pcsim presets`: list the embedded presets, or print one as an editable case.

use anyhow::{bail, Result};
use clap::Args;
use pcsim_core::presets;

#[derive(Args)]
pub struct PresetsArgs {
    /// `show NAME` prints a preset as an editable TOML case.
    action: Option<String>,
    name: Option<String>,
}

pub fn presets(a: PresetsArgs) -> Result<i32> {
    match (a.action.as_deref(), a.name.as_deref()) {
        (None, _) => {
            let w = presets::PRESETS
                .iter()
                .map(|p| p.name.chars().count())
                .max()
                .unwrap_or(0);
            for p in presets::PRESETS {
                println!("{:<w$}  {}", p.name, p.summary);
            }
        }
        (Some("show"), Some(name)) => print!("{}", presets::find(name)?.toml),
        (Some("show"), None) => bail!("usage: pcsim presets show NAME"),
        (Some(other), _) => {
            bail!("unknown action `{other}` (use `pcsim presets` or `pcsim presets show NAME`)")
        }
    }
    Ok(0)
}
