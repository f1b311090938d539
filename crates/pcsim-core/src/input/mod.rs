//! What a user gives: case files (TOML with provenance), the embedded presets, and the
//! validation targets. The bottom layer: it imports nothing else from the crate.

pub mod bounds;
pub mod case;
pub mod criteria;
pub mod design;
pub mod hard_spots;
pub mod irregularity;
pub mod lateral;
pub mod line;
pub mod measured;
pub mod overrides;
pub mod presets;
pub mod targets;
pub mod units;
mod validate;

pub use case::{Case, Provenance, RangedValue, Warning, G};

/// The one case loader of every front end (CLI, C API, Python, FMU), with one error wording. The
/// core does no I/O: the front end reads the file and hands over what the read gave.
pub fn case_from_file(
    path: &str,
    read: std::io::Result<String>,
) -> Result<Case, crate::error::CaseError> {
    case_and_ranges_from_file(path, read).map(|(c, _)| c)
}

/// [`case_from_file`], with the ranges the case gives its values (for `--sensitivity`).
pub fn case_and_ranges_from_file(
    path: &str,
    read: std::io::Result<String>,
) -> Result<(Case, Vec<RangedValue>), crate::error::CaseError> {
    let text = read.map_err(|e| crate::error::CaseError::Read {
        path: path.to_string(),
        reason: e.to_string(),
    })?;
    Case::from_toml_str_with_ranges(&text)
        .map(|(c, _, r)| (c, r))
        .map_err(|e| crate::error::CaseError::InFile {
            path: path.to_string(),
            error: Box::new(e),
        })
}

/// The largest input a front end reads by default, bytes: a case file, a profile, a HIL input
/// or a saved state (the largest real inputs are HIL recordings of a few tens of MB). The CLI
/// raises it with `--max-input-mb`.
pub const MAX_INPUT_BYTES: u64 = 256 << 20;

/// Read all of `reader` as UTF-8 text, refusing more than `limit_bytes` (the one bounded read of
/// every front end: the core opens no file, the front end hands over the reader). The error says
/// the limit; the front end names the file and how to raise it. A leading byte-order mark (a
/// spreadsheet's CSV) is dropped.
pub fn read_text_limited(reader: impl std::io::Read, limit_bytes: u64) -> std::io::Result<String> {
    use std::io::Read;
    let mut buf = Vec::new();
    reader
        .take(limit_bytes.saturating_add(1))
        .read_to_end(&mut buf)?;
    if buf.len() as u64 > limit_bytes {
        return Err(std::io::Error::new(
            std::io::ErrorKind::InvalidData,
            format!("larger than the limit of {limit_bytes} bytes"),
        ));
    }
    String::from_utf8(buf)
        .map(|t| match t.strip_prefix(BOM) {
            Some(rest) => rest.to_string(),
            None => t,
        })
        .map_err(|e| {
            std::io::Error::new(
                std::io::ErrorKind::InvalidData,
                format!("not UTF-8 text (byte {})", e.utf8_error().valid_up_to()),
            )
        })
}

/// The UTF-8 byte-order mark a spreadsheet writes at the start of a CSV file.
const BOM: char = '\u{feff}';

/// `text` without a leading byte-order mark (a spreadsheet's CSV: its header must read as the
/// header it looks like). Every reader of a user's text takes it through here or
/// [`read_text_limited`].
pub fn without_bom(text: &str) -> &str {
    text.strip_prefix(BOM).unwrap_or(text)
}

/// An embedded preset by name (the same wording for an unknown name everywhere).
pub fn case_from_preset(name: &str) -> Result<Case, crate::error::CaseError> {
    Ok(presets::load(name)?.0)
}
