//! A line in the case file (issue 21): `[line]` with its tension lengths, each with spans given
//! one by one or as runs of equal spans, an optional dropper layout per span, and the contact-wire
//! height and system height at each support. The `[catenary]` table supplies everything a tension
//! length does not override: the wires, the droppers' data and their reference layout (positions
//! on a span of `catenary.span_m`, scaled to each span), the supports, the arms, the stitch wires
//! and the damping. Without `[line]`, `[catenary]` is a line of one tension length of
//! `catenary.spans` equal spans (every preset).
//!
//! ```toml
//! [[line.tension_lengths]]
//! span_runs = [{ count = 4, length_m = 60.0 }, { count = 1, length_m = 45.0 }]
//! contact_height_m = [0.0, 0.0, 0.0, -0.15, -0.3, -0.3]   # one per support, m
//! ```

use serde::{Deserialize, Serialize};

/// The line: its tension lengths in track order.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct LineCase {
    /// The tension lengths, in track order.
    pub tension_lengths: Vec<TensionLengthCase>,
}

/// A run of equal spans.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct SpanRun {
    /// Number of spans in the run.
    pub count: usize,
    /// Their length, m.
    pub length_m: f64,
}

/// One tension length.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq)]
#[serde(deny_unknown_fields)]
pub struct TensionLengthCase {
    /// Span lengths one by one, m (or `span_runs`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub spans_m: Vec<f64>,
    /// Runs of equal spans (or `spans_m`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub span_runs: Vec<SpanRun>,
    /// Dropper positions per span, from the span's first support, m; by default
    /// `catenary.droppers.positions_m` scaled by each span's length over `catenary.span_m`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub droppers_m: Vec<Vec<f64>>,
    /// Contact-wire design height at each support relative to the nominal height, m (one per
    /// support; by default 0 everywhere).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub contact_height_m: Vec<f64>,
    /// System height (messenger above contact wire) at each support, m (one per support; by
    /// default `catenary.encumbrance_m`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub encumbrance_m: Vec<f64>,
}

impl TensionLengthCase {
    /// The span lengths, m, runs expanded.
    pub fn span_lengths_m(&self) -> Vec<f64> {
        let mut s = self.spans_m.clone();
        for r in &self.span_runs {
            s.extend(std::iter::repeat_n(r.length_m, r.count));
        }
        s
    }

    /// The number of spans (runs counted without expanding them).
    pub fn n_spans(&self) -> usize {
        self.span_runs
            .iter()
            .fold(self.spans_m.len(), |a, r| a.saturating_add(r.count))
    }

    /// The dropper positions of span `j` of length `length_m`: its own, or the reference
    /// layout `reference_m` on a span of `reference_span_m` scaled to it.
    pub fn droppers_of_span(
        &self,
        j: usize,
        length_m: f64,
        reference_m: &[f64],
        reference_span_m: f64,
    ) -> Vec<f64> {
        match self.droppers_m.get(j) {
            Some(d) => d.clone(),
            None if length_m == reference_span_m => reference_m.to_vec(),
            None => reference_m
                .iter()
                .map(|x| x * (length_m / reference_span_m))
                .collect(),
        }
    }
}

impl LineCase {
    /// The number of spans of the whole line (no overlap counted twice: one tension length).
    pub fn n_spans(&self) -> usize {
        self.tension_lengths
            .iter()
            .fold(0, |a, t| a.saturating_add(t.n_spans()))
    }

    /// Track positions of the line's supports (the first at 0), m.
    pub fn supports_m(&self) -> Vec<f64> {
        let mut x = vec![0.0];
        for s in self.tension_lengths.iter().flat_map(|t| t.span_lengths_m()) {
            let last = x[x.len() - 1];
            x.push(last + s);
        }
        x
    }

    /// The line's length, m.
    pub fn length_m(&self) -> f64 {
        self.tension_lengths
            .iter()
            .flat_map(|t| t.span_lengths_m())
            .sum()
    }
}
