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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quantities_with_and_without_units() {
        let f = |t: &str| parse_quantity(t, Dimension::Force, 1e3).unwrap().value;
        assert_eq!(f("20kN"), 20_000.0);
        assert_eq!(f("20000N"), 20_000.0);
        assert_eq!(f("20000 n"), 20_000.0);
        assert_eq!(f("9.8"), 9_800.0); // bare: the flag's unit, kN
        assert_eq!(f("1.5e1kN"), 15_000.0);
        let v = |t: &str| parse_quantity(t, Dimension::Speed, 1.0).unwrap().value;
        assert_eq!(v("250"), 250.0);
        assert_eq!(v("250km/h"), 250.0);
        assert!((v("50m/s") - 180.0).abs() < 1e-12);
        assert!(parse_quantity("20kg", Dimension::Force, 1.0)
            .unwrap_err()
            .contains("unknown unit"));
        assert!(parse_quantity("abc", Dimension::Force, 1.0)
            .unwrap_err()
            .contains("not a number"));
        assert!(parse_quantity("nan", Dimension::Force, 1.0).is_err());
        assert_eq!(
            parse_quantity("215", Dimension::Length, 1.0).unwrap().value,
            215.0
        );
        assert_eq!(
            parse_quantity("1ms", Dimension::Time, 1.0).unwrap().value,
            1e-3
        );
    }
}
