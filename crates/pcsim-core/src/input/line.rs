//! A line in the case file (issue 21): `[line]` with its tension lengths, each with spans given
//! one by one or as runs of equal spans, an optional dropper layout per span, the contact-wire
//! height and system height at each support, and its own wires where they differ; and the
//! overlaps between consecutive tension lengths. The `[catenary]` table supplies everything a
//! tension length does not override: the wires, the droppers' data and their reference layout
//! (positions on a span of `catenary.span_m`, scaled to each span), the supports, the arms, the
//! stitch wires and the damping. Without `[line]`, `[catenary]` is a line of one tension length
//! of `catenary.spans` equal spans (every preset).
//!
//! An overlap of `n` spans: the last `n` spans of a tension length are the first `n` of the
//! next (the same supports, their lengths equal); the wire that leaves the track rises by
//! `rise_m` at its last support (its anchor), the one that arrives comes down from `rise_m` at its
//! first. Each tension length's wires end at its first and last supports.
//!
//! ```toml
//! [[line.tension_lengths]]
//! span_runs = [{ count = 4, length_m = 60.0 }, { count = 1, length_m = 45.0 }]
//! contact_height_m = [0.0, 0.0, 0.0, -0.15, -0.3, -0.3]   # one per support, m
//! [[line.tension_lengths]]
//! spans_m = [60.0, 45.0, 60.0, 60.0]
//! [[line.overlaps]]
//! spans = 2
//! rise_m = 0.5
//! ```

use crate::input::case::{ArmCase, CatenaryCase, DropperCase, SupportCase, WireCase};
use serde::{Deserialize, Serialize};

/// The line: its tension lengths in track order, and the overlaps between them.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LineCase {
    /// The tension lengths, in track order.
    pub tension_lengths: Vec<TensionLengthCase>,
    /// The overlap between tension lengths `k` and `k + 1`, for each `k`.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub overlaps: Vec<OverlapCase>,
}

/// An overlap between two consecutive tension lengths.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OverlapCase {
    /// Number of spans the two tension lengths share.
    pub spans: usize,
    /// Rise of the out-of-running contact wire at its anchor support, m (above its working
    /// height; added to that support's `contact_height_m`).
    #[serde(default)]
    pub rise_m: f64,
    /// Lateral separation of the two contact wires in the overlap, m (reported with the
    /// clearance; the vertical model does not use it).
    #[serde(default)]
    pub separation_m: f64,
}

/// A run of equal spans.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SpanRun {
    /// Number of spans in the run.
    pub count: usize,
    /// Their length, m.
    pub length_m: f64,
    /// The track's radius along the run, m, signed as `catenary.lateral.track_radius_m` (issue
    /// 41: a curve per run of spans); by default `catenary.lateral`'s (straight without it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub track_radius_m: Option<f64>,
    /// The cant along the run, m (with `track_radius_m`); by default `catenary.lateral.cant_m`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cant_m: Option<f64>,
}

/// One tension length.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
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
    /// The contact wire's stagger at each support, m (one per support; with lateral motion). By
    /// default `catenary.lateral`'s pattern, counted along the line's supports, and through an
    /// overlap the two wires side by side ([`LineCase::staggers_m`]).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub stagger_m: Vec<f64>,
    /// This tension length's contact wire, where it differs from `catenary.contact_wire`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub contact_wire: Option<WireCase>,
    /// Its messenger, where it differs from `catenary.messenger`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub messenger: Option<WireCase>,
    /// Its droppers, where they differ from `catenary.droppers`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub droppers: Option<DropperCase>,
    /// Its messenger supports, where they differ from `catenary.messenger_support`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub messenger_support: Option<SupportCase>,
    /// Its steady arms, where they differ from `catenary.steady_arm`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub steady_arm: Option<ArmCase>,
}

/// The keys of `[catenary]` a tension length may override.
pub const OVERRIDES: [&str; 5] = [
    "contact_wire",
    "messenger",
    "droppers",
    "messenger_support",
    "steady_arm",
];

impl TensionLengthCase {
    /// The catenary of this tension length: `base` with this tension length's overrides.
    pub fn catenary(&self, base: &CatenaryCase) -> CatenaryCase {
        let mut c = base.clone();
        if let Some(w) = &self.contact_wire {
            c.contact_wire = w.clone();
        }
        if let Some(w) = &self.messenger {
            c.messenger = w.clone();
        }
        if let Some(d) = &self.droppers {
            c.droppers = d.clone();
        }
        if let Some(s) = &self.messenger_support {
            c.messenger_support = s.clone();
        }
        if let Some(a) = &self.steady_arm {
            c.steady_arm = a.clone();
        }
        c
    }

    /// Whether this tension length overrides `[catenary]`'s `key` (one of [`OVERRIDES`]).
    pub fn overrides(&self, key: &str) -> bool {
        match key {
            "contact_wire" => self.contact_wire.is_some(),
            "messenger" => self.messenger.is_some(),
            "droppers" => self.droppers.is_some(),
            "messenger_support" => self.messenger_support.is_some(),
            "steady_arm" => self.steady_arm.is_some(),
            _ => false,
        }
    }

    /// The span lengths, m, runs expanded.
    pub fn span_lengths_m(&self) -> Vec<f64> {
        let mut s = self.spans_m.clone();
        for r in &self.span_runs {
            s.extend(std::iter::repeat_n(r.length_m, r.count));
        }
        s
    }

    /// Each span's curve, `(radius, cant)`: a run's own, else `default` (`catenary.lateral`'s).
    pub fn span_curves(&self, default: (Option<f64>, f64)) -> Vec<(Option<f64>, f64)> {
        let mut c = vec![default; self.spans_m.len()];
        for r in &self.span_runs {
            let own = match r.track_radius_m {
                Some(radius) => (Some(radius), r.cant_m.unwrap_or(default.1)),
                None => (default.0, r.cant_m.unwrap_or(default.1)),
            };
            c.extend(std::iter::repeat_n(own, r.count));
        }
        c
    }

    /// The run of spans (index in `span_runs`) that span `j` belongs to; `None` for a span
    /// listed in `spans_m` (they come first) or beyond the last.
    pub fn run_of_span(&self, j: usize) -> Option<usize> {
        let mut first = self.spans_m.len();
        for (i, r) in self.span_runs.iter().enumerate() {
            if j >= first && j < first + r.count {
                return Some(i);
            }
            first += r.count;
        }
        None
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
    /// The number of spans of the whole line (an overlap's spans counted once).
    pub fn n_spans(&self) -> usize {
        let all = self
            .tension_lengths
            .iter()
            .fold(0usize, |a, t| a.saturating_add(t.n_spans()));
        let shared = self
            .overlaps
            .iter()
            .fold(0usize, |a, o| a.saturating_add(o.spans));
        all.saturating_sub(shared)
    }

    /// The track position of each tension length's first support (the first at 0), m: the
    /// next one starts `overlaps[k].spans` spans before the end of tension length `k`.
    pub fn starts_m(&self) -> Vec<f64> {
        let mut starts = Vec::with_capacity(self.tension_lengths.len());
        let mut x0 = 0.0;
        for (k, t) in self.tension_lengths.iter().enumerate() {
            starts.push(x0);
            let lengths = t.span_lengths_m();
            let shared = self
                .overlaps
                .get(k)
                .map_or(0, |o| o.spans)
                .min(lengths.len());
            x0 += lengths[..lengths.len() - shared].iter().sum::<f64>();
        }
        starts
    }

    /// The index of tension length `k`'s first support among the line's supports
    /// ([`LineCase::supports_m`]).
    pub fn first_support(&self, k: usize) -> usize {
        (0..k).fold(0, |a, j| {
            let n = self.tension_lengths[j].n_spans();
            a + n - self.overlaps.get(j).map_or(0, |o| o.spans).min(n)
        })
    }

    /// Each span of the line's curve `(radius, cant)`: the tension length's that first covers
    /// it (an overlap's spans are checked to agree, `input::validate`).
    pub fn span_curves(&self, default: (Option<f64>, f64)) -> Vec<(Option<f64>, f64)> {
        let mut out: Vec<(Option<f64>, f64)> = Vec::new();
        for (k, t) in self.tension_lengths.iter().enumerate() {
            let first = self.first_support(k);
            for (j, c) in t.span_curves(default).into_iter().enumerate() {
                if first + j >= out.len() {
                    out.push(c);
                }
            }
        }
        out
    }

    /// The contact wire's stagger at each support of each tension length, m: the tension
    /// length's own `stagger_m`, or the pattern `pattern(i)` at the line's support `i`; through
    /// an overlap of `n` spans the two wires lie about the pattern `±σ_j e/2` apart (`e` the
    /// overlap's `separation_m`), `σ_j` running from −1 at the overlap's first shared support to
    /// +1 at its last (the wire that leaves on `+`, the one that arrives on `−`): side by side
    /// at the ends, crossing in plan midway, where the heights cross too. The default layout is
    /// a guess: the public design rules (EN 50119 §5.2.5 asks only for the changeover's
    /// clearances) leave the overlap's plan to each system.
    pub fn staggers_m(&self, pattern: &dyn Fn(usize) -> f64) -> Vec<Vec<f64>> {
        let ntl = self.tension_lengths.len();
        (0..ntl)
            .map(|k| {
                let t = &self.tension_lengths[k];
                let n = t.n_spans();
                if !t.stagger_m.is_empty() {
                    return t.stagger_m.clone();
                }
                let first = self.first_support(k);
                (0..=n)
                    .map(|j| {
                        let mut y = pattern(first + j);
                        // Leaving into overlap k (its first shared support at local n − o).
                        if let Some(o) = self.overlaps.get(k).filter(|o| o.spans > 0) {
                            if j + o.spans >= n {
                                let sigma = -1.0 + 2.0 * (j + o.spans - n) as f64 / o.spans as f64;
                                y += sigma * 0.5 * o.separation_m;
                            }
                        }
                        // Arriving from overlap k − 1 (shared supports local 0 … o).
                        if let Some(o) = (k.checked_sub(1))
                            .and_then(|i| self.overlaps.get(i))
                            .filter(|o| o.spans > 0)
                        {
                            if j <= o.spans {
                                let sigma = -1.0 + 2.0 * j as f64 / o.spans as f64;
                                y -= sigma * 0.5 * o.separation_m;
                            }
                        }
                        y
                    })
                    .collect()
            })
            .collect()
    }

    /// Track positions of the supports of tension length `k`, m.
    pub fn tension_length_supports_m(&self, k: usize) -> Vec<f64> {
        let mut x = vec![self.starts_m()[k]];
        for s in self.tension_lengths[k].span_lengths_m() {
            let last = x[x.len() - 1];
            x.push(last + s);
        }
        x
    }

    /// Track positions of every support of the line (an overlap's shared supports once), m.
    pub fn supports_m(&self) -> Vec<f64> {
        let mut x: Vec<f64> = (0..self.tension_lengths.len())
            .flat_map(|k| self.tension_length_supports_m(k))
            .collect();
        x.sort_by(f64::total_cmp);
        x.dedup_by(|a, b| (*a - *b).abs() < 1e-3);
        x
    }

    /// The line's length (to the last tension length's last support), m.
    pub fn length_m(&self) -> f64 {
        let k = self.tension_lengths.len();
        if k == 0 {
            return 0.0;
        }
        let last: f64 = self.tension_lengths[k - 1].span_lengths_m().iter().sum();
        self.starts_m()[k - 1] + last
    }

    /// The overlaps as track sections `[first shared support, last shared support]`, m.
    pub fn overlap_sections_m(&self) -> Vec<[f64; 2]> {
        (0..self
            .overlaps
            .len()
            .min(self.tension_lengths.len().saturating_sub(1)))
            .map(|k| {
                let next = self.tension_length_supports_m(k + 1);
                let n = self.overlaps[k].spans.min(next.len() - 1);
                [next[0], next[n]]
            })
            .collect()
    }
}
