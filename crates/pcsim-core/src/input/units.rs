//! Quantities with units at the user boundary: `20kN`, `20000 N`, `250km/h`, `69.4m/s`, `215m`,
//! `1ms`. The core works in SI; a value typed without a unit is read in the unit that the flag
//! or field names.

/// What a quantity measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Dimension {
    /// Returned in km/h (the unit of train speeds in every source).
    Speed,
    /// Returned in N.
    Force,
    /// Returned in m.
    Length,
    /// Returned in s.
    Time,
}

impl Dimension {
    fn units(self) -> &'static [(&'static str, f64)] {
        match self {
            Dimension::Speed => &[("km/h", 1.0), ("kmh", 1.0), ("m/s", 3.6)],
            Dimension::Force => &[("kn", 1e3), ("n", 1.0)],
            Dimension::Length => &[("km", 1e3), ("mm", 1e-3), ("m", 1.0)],
            Dimension::Time => &[("ms", 1e-3), ("us", 1e-6), ("µs", 1e-6), ("s", 1.0)],
        }
    }

    /// The units accepted, for messages.
    pub fn accepted(self) -> &'static str {
        match self {
            Dimension::Speed => "km/h, m/s",
            Dimension::Force => "N, kN",
            Dimension::Length => "m, km, mm",
            Dimension::Time => "s, ms, us",
        }
    }
}

/// A parsed quantity: its value in the dimension's return unit, and whether the text gave a unit.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Quantity {
    /// The value in the dimension's return unit.
    pub value: f64,
    /// Whether the text gave a unit.
    pub explicit_unit: bool,
}

/// Parse `text` as a number with an optional unit. `default_scale` converts a bare number into
/// the dimension's return unit (e.g. 1000 for a `--tension` given in kN, returned in N).
pub fn parse_quantity(text: &str, dim: Dimension, default_scale: f64) -> Result<Quantity, String> {
    let t = text.trim();
    let split = t
        .find(|c: char| !(c.is_ascii_digit() || matches!(c, '.' | '-' | '+' | 'e' | 'E')))
        .unwrap_or(t.len());
    // `1e3kN`: an `e` followed by a letter belongs to the unit only if no digit follows it.
    let (num, unit) = t.split_at(split);
    let unit = unit.trim();
    let value: f64 = num
        .parse()
        .map_err(|_| format!("`{text}` is not a number with a unit ({})", dim.accepted()))?;
    if !value.is_finite() {
        return Err(format!("`{text}` is not finite"));
    }
    if unit.is_empty() {
        return Ok(Quantity {
            value: value * default_scale,
            explicit_unit: false,
        });
    }
    let lower = unit.to_lowercase();
    let scale = dim
        .units()
        .iter()
        .find(|(u, _)| *u == lower)
        .map(|(_, s)| *s)
        .ok_or_else(|| format!("`{text}`: unknown unit `{unit}` (use {})", dim.accepted()))?;
    Ok(Quantity {
        value: value * scale,
        explicit_unit: true,
    })
}
