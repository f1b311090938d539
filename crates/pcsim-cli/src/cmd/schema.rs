//! `pcsim schema NAME`: the JSON Schema of a case file or of an output, printed (issue 52).

use anyhow::{bail, Result};
use clap::Args;
use pcsim_core::study::schema::{names, schema};

#[derive(Args)]
pub struct SchemaArgs {
    /// Which schema: `case`, `summary`, `montecarlo`, `assessment`, `design`, `fit`, `compare`,
    /// `realtime`, `manifest`, `answer`, `figures`, or a spec-file study's output and spec
    /// (`wear`, `wear-spec`) (none: list them).
    name: Option<String>,
}

pub fn schema_cmd(a: SchemaArgs) -> Result<i32> {
    let Some(name) = a.name else {
        for (n, what) in names() {
            println!("{n:<11} {what}");
        }
        return Ok(0);
    };
    let Some(s) = schema(&name) else {
        let names: Vec<String> = names().into_iter().map(|(n, _)| n).collect();
        bail!("unknown schema `{name}` (one of: {})", names.join(", "));
    };
    println!("{}", serde_json::to_string_pretty(&s)?);
    Ok(0)
}
