//! The line's hard spots in the case file (issue 55): section insulators and neutral sections.
//!
//! ```toml
//! [[section_insulator]]
//! position_m = 612.0   # its centre along the track, m
//! length_m = 2.0       # m
//! mass_kg = 12.0
//! ei_nm2 = 2.0e4       # its bending stiffness (at least the contact wire's), N·m²
//! ramp_m = 0.3         # the runners' lead-on at each end, m
//! prelift_m = 0.02     # the runners above the wire's design height, m
//!
//! [[neutral_section]]  # a dead length between two insulators
//! start_m = 611.0
//! end_m = 653.0
//! ```
//!
//! An insulator lies on one contact wire (a catenary's, or the tension length's that holds it),
//! away from an overlap; a neutral section's ends lie on insulators. The law is the model's
//! (`model::elements::section_insulator`).

use serde::{Deserialize, Serialize};

/// A section insulator inserted in the contact wire.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SectionInsulatorCase {
    /// Its centre along the track, m.
    pub position_m: f64,
    /// Its length along the wire (the runners' length), m.
    pub length_m: f64,
    /// Its mass, kg (what it adds to the wire's: the insulator with its runners and clamps,
    /// less the wire it replaces).
    pub mass_kg: f64,
    /// Its bending stiffness over its length, N·m² (at least the contact wire's: the model adds
    /// the difference).
    pub ei_nm2: f64,
    /// The length of the runners' lead-on at each end, m (the running surface rises linearly
    /// from the wire to `prelift_m` over it; at most half the length).
    #[serde(default)]
    pub ramp_m: f64,
    /// Height of the runners' running surface above the wire's design height over the
    /// insulator, m (its pre-lift; upward positive).
    #[serde(default)]
    pub prelift_m: f64,
}

impl SectionInsulatorCase {
    /// Its extent along the track, `[start, end]`, m.
    pub fn extent_m(&self) -> [f64; 2] {
        [
            self.position_m - 0.5 * self.length_m,
            self.position_m + 0.5 * self.length_m,
        ]
    }
}

/// A neutral section: a dead length of contact wire between two section insulators (the
/// current stops over it).
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NeutralSectionCase {
    /// Where the dead length starts (on a section insulator), m.
    pub start_m: f64,
    /// Where it ends (on a section insulator), m.
    pub end_m: f64,
}

/// The tension length whose contact wire holds the section `[a, b]` of track (the catenary's
/// own, 0, without `[line]`), or why none does: outside the line, or inside an overlap where two
/// contact wires run side by side.
pub fn tension_length_under(case: &crate::input::Case, [a, b]: [f64; 2]) -> Result<usize, String> {
    let length = case.length_m();
    if a <= 0.0 || b >= length {
        return Err(format!(
            "it must lie inside the contact wire, between 0 and {length} m (its extent is {a}–{b} m)"
        ));
    }
    let Some(line) = &case.line else {
        return Ok(0);
    };
    if let Some(o) = (line.overlap_sections_m().iter()).find(|o| b > o[0] && a < o[1]) {
        return Err(format!(
            "it reaches into the overlap at {}–{} m, where two contact wires run side by side: an insulator sits on one tension length's wire, outside the overlaps",
            o[0], o[1]
        ));
    }
    (0..line.tension_lengths.len())
        .find(|&k| {
            let s = line.tension_length_supports_m(k);
            a > s[0] && b < s[s.len() - 1]
        })
        .ok_or_else(|| "no tension length's contact wire holds all of it".to_string())
}
