//! `pcsim schema NAME`: the JSON Schema of a case file or of an output, printed (issue 52).

use anyhow::{bail, Result};
use clap::Args;
use pcsim_core::study::schema::{schema, SCHEMAS};

#[derive(Args)]
pub struct SchemaArgs {
    /// Which schema: `case`, `summary`, `montecarlo`, `assessment`, `design`, `fit`, `compare`,
    /// `realtime` or `manifest` (none: list them).
    name: Option<String>,
}

pub fn schema_cmd(a: SchemaArgs) -> Result<i32> {
    let Some(name) = a.name else {
        for (n, what) in SCHEMAS {
            println!("{n:<11} {what}");
        }
        return Ok(0);
    };
    let Some(s) = schema(&name) else {
        let names: Vec<&str> = SCHEMAS.iter().map(|(n, _)| *n).collect();
        bail!("unknown schema `{name}` (one of: {})", names.join(", "));
    };
    println!("{}", serde_json::to_string_pretty(&s)?);
    Ok(0)
}
