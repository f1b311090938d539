//! Measured contact force against position, as a recording car gives it (issue 22, item 4): a
//! CSV file `position_m,force_n` (metres and newtons, a header line first), at a uniform spacing.
//! Read from text; the front end reads the file.

use super::bounds::inv;
use crate::error::CaseError;

/// A measured contact force record.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasuredForce {
    /// Position along the track, m, increasing at a uniform spacing.
    pub position_m: Vec<f64>,
    /// Contact force, N.
    pub force_n: Vec<f64>,
    /// The spacing, m.
    pub spacing_m: f64,
}

/// The fewest samples a measured record may have.
pub const MIN_SAMPLES: usize = 64;
/// The largest contact force a record may hold, N: a thousand times any pantograph's (so that
/// the statistics' sums of squares stay finite numbers).
pub const MAX_FORCE_N: f64 = 1e6;
/// The largest position a record may hold, m (ten thousand kilometres).
pub const MAX_POSITION_M: f64 = 1e7;
/// How far the spacing may vary along the record (relative).
pub const SPACING_TOLERANCE: f64 = 0.01;

impl MeasuredForce {
    /// Read `position_m,force_n` rows (after that header line). `source` names the file in the
    /// errors, which name the line, the column or the spacing at fault.
    pub fn from_csv(text: &str, source: &str) -> Result<Self, CaseError> {
        let text = crate::input::without_bom(text);
        let mut lines = text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty());
        let Some((_, header)) = lines.next() else {
            return Err(inv(
                source,
                "an empty file",
                "a measured record needs the header `position_m,force_n` and its rows",
            ));
        };
        check_header(header, source)?;
        // The file's line of each row (1-based), for the errors.
        let (mut x, mut f, mut at) = (Vec::new(), Vec::new(), Vec::new());
        for (i, line) in lines {
            let v: Vec<&str> = line.split(',').map(str::trim).collect();
            let num = |k: usize| {
                v.get(k)
                    .and_then(|s| s.parse::<f64>().ok())
                    .filter(|y| y.is_finite())
            };
            match (v.len(), num(0), num(1)) {
                (2, Some(a), Some(b)) if a.abs() <= MAX_POSITION_M && b.abs() <= MAX_FORCE_N => {
                    x.push(a);
                    f.push(b);
                    at.push(i + 1);
                }
                (2, Some(a), Some(b)) => {
                    return Err(inv(
                        source,
                        format!("line {}: `{}`", i + 1, line.trim()),
                        &format!(
                            "{} is beyond what a measured record holds (positions within ± {MAX_POSITION_M:e} m, forces within ± {MAX_FORCE_N:e} N)",
                            if a.abs() > MAX_POSITION_M { format!("position {a} m") } else { format!("force {b} N") }
                        ),
                    ))
                }
                _ => {
                    return Err(inv(
                        source,
                        format!("line {}: `{}`", i + 1, line.trim()),
                        "each row must be `position_m,force_n`: two finite numbers (m, N)",
                    ))
                }
            }
        }
        if x.len() < MIN_SAMPLES {
            return Err(inv(
                source,
                format!("{} rows", x.len()),
                &format!("a measured record needs at least {MIN_SAMPLES} rows"),
            ));
        }
        let spacing = (x[x.len() - 1] - x[0]) / (x.len() - 1) as f64;
        for (k, w) in x.windows(2).enumerate() {
            let d = w[1] - w[0];
            if d <= 0.0 || (d - spacing).abs() > SPACING_TOLERANCE * spacing.abs() {
                return Err(inv(
                    source,
                    format!(
                        "lines {} and {}: positions {} and {} m",
                        at[k],
                        at[k + 1],
                        w[0],
                        w[1]
                    ),
                    &format!(
                        "positions must increase at a uniform spacing (the record's mean is {spacing} m, within {} %): resample the record first",
                        100.0 * SPACING_TOLERANCE
                    ),
                ));
            }
        }
        Ok(MeasuredForce {
            position_m: x,
            force_n: f,
            spacing_m: spacing,
        })
    }
}

/// Refuse a header other than `position_m,force_n`, saying which column's unit is wrong.
fn check_header(header: &str, source: &str) -> Result<(), CaseError> {
    let cols: Vec<String> = header
        .split(',')
        .map(|c| c.trim().trim_matches('"').to_ascii_lowercase())
        .collect();
    if cols != ["position_m", "force_n"] {
        let why = if cols.iter().any(|c| c.parse::<f64>().is_ok()) {
            "the first line must be the header `position_m,force_n`".to_string()
        } else if let Some(c) = cols
            .iter()
            .find(|c| c.starts_with("position") && c.as_str() != "position_m")
        {
            format!(
                "column `{c}`: positions are read in metres, as `position_m` (convert km × 1000)"
            )
        } else if let Some(c) = cols
            .iter()
            .find(|c| c.starts_with("force") && c.as_str() != "force_n")
        {
            format!("column `{c}`: forces are read in newtons, as `force_n` (convert kN × 1000)")
        } else {
            "the header must be `position_m,force_n` (metres, newtons; two columns)".to_string()
        };
        return Err(inv(source, format!("header `{}`", header.trim()), &why));
    }
    Ok(())
}
