//! Static shape of the catenary from its design geometry (paper §2.1: "the static shape of the
//! catenary is obtained based on its design parameters"; README §5).
//!
//! The design fixes the contact-wire height at every dropper (minus the pre-sag) and, where the
//! steady arm holds it (simple catenaries), at the supports (0). Between those nodes a tensioned wire under its own weight `w = ρA g` is a parabola
//! (`T y'' = w`), and the kink at a node gives the point force that holds it:
//!
//! ```text
//! F_node = T (s_left − s_right) + w (h_left + h_right)/2 (+ clamp weight),
//! ```
//!
//! with `s` the chord slopes and `h` the segment lengths. That yields the dropper tensions at the
//! contact wire and the steady-arm force. In a stitched catenary the stitch droppers hang from
//! stitch elements (see [`stitch_stiffness`]) that sag under their load by `F/k`. The messenger hangs from its supports (at the
//! encumbrance) under its weight, the dropper tensions, the dropper weights and its clamps; its
//! shape follows from the simply supported moment diagram, `y_m = E − M(x)/T_m`. Dropper lengths
//! are the differences of the two heights. Bending stiffness is neglected in this step: with
//! `√(EI/T) ≈ 0.1 m` it only rounds the kinks (the modal check in the tests includes EI and stays
//! within 1 mm of the design).
//!
//! The dynamic model works with deviations from this shape. The height the pantograph sees is this
//! analytic profile plus the modal deviation, never a truncated sine series of the static shape
//! (README §5).

use crate::model::basis::SineBasis;
use serde::{Deserialize, Serialize};

/// Gravitational acceleration, m/s².
pub const G: f64 = 9.81;

/// Where the pre-sag parabola is zero.
#[derive(Debug, Clone, Copy, Serialize, Deserialize, PartialEq, Eq, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum PresagZero {
    /// `presag(ξ) = 4 s ξ (1 − ξ)` over the whole span.
    Supports,
    /// The parabola spans the first to the last dropper; the contact wire is level from the
    /// support to the first dropper.
    EndDroppers,
}

/// Design pre-sag of the contact wire (downward, m), at each dropper.
#[derive(Debug, Clone, Serialize, Deserialize, PartialEq, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum Presag {
    /// A parabola over the span with its mid-span sag.
    Parabolic {
        /// Pre-sag at mid-span, m (downward).
        mid_span_m: f64,
        /// Where the parabola is zero.
        zero_at: PresagZero,
    },
    /// Pre-sag at each dropper, in dropper order.
    Table {
        /// Pre-sag at each dropper, in dropper order, m (downward).
        values_m: Vec<f64>,
    },
}

/// A span-periodic piecewise-parabolic wire profile: nodal heights, and between nodes the
/// parabola of a tensioned wire under its weight (`T y'' = w`).
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    /// Node positions within a span, sorted, in `[0, span)`.
    pub xs: Vec<f64>,
    /// Heights at the nodes, m.
    pub hs: Vec<f64>,
    /// Span length, m.
    pub span_m: f64,
    /// Number of spans.
    pub n_spans: usize,
    /// Weight per metre, N/m, and tension, N.
    pub w: f64,
    /// Tension, N.
    pub t: f64,
}

impl Profile {
    /// The segment `(x_left, h_left, x_right, h_right)` containing local coordinate `xi`.
    fn segment(&self, xi: f64) -> (f64, f64, f64, f64) {
        let n = self.xs.len();
        match self.xs.iter().rposition(|&x| x <= xi) {
            None => (
                self.xs[n - 1] - self.span_m,
                self.hs[n - 1],
                self.xs[0],
                self.hs[0],
            ),
            Some(j) if j + 1 < n => (self.xs[j], self.hs[j], self.xs[j + 1], self.hs[j + 1]),
            Some(j) => (self.xs[j], self.hs[j], self.xs[0] + self.span_m, self.hs[0]),
        }
    }

    /// Height at track position `x`.
    pub fn height(&self, x: f64) -> f64 {
        let s = self.span_m;
        let k = (x / s).floor().clamp(0.0, self.n_spans as f64);
        let xi = x - k * s;
        let (x0, h0, x1, h1) = self.segment(xi);
        between_nodes(self.w, self.t, (x0, h0), (x1, h1), xi)
    }

    /// Upward point force the wire needs at each node to hold this shape:
    /// `T (s_left − s_right) + w (h_left + h_right)/2` (the kink).
    pub fn node_forces(&self) -> Vec<f64> {
        let n = self.xs.len();
        (0..n)
            .map(|j| {
                let (xl, hl) = if j == 0 {
                    (self.xs[n - 1] - self.span_m, self.hs[n - 1])
                } else {
                    (self.xs[j - 1], self.hs[j - 1])
                };
                let (xr, hr) = if j + 1 == n {
                    (self.xs[0] + self.span_m, self.hs[0])
                } else {
                    (self.xs[j + 1], self.hs[j + 1])
                };
                kink_force(self.t, self.w, (xl, hl), (self.xs[j], self.hs[j]), (xr, hr))
            })
            .collect()
    }
}

/// Height at `x` of a tensioned wire (tension `t_n`, weight `w_n_per_m`) between the nodes
/// `(x0, h0)` and `(x1, h1)`: the chord plus the parabola of `T y'' = w`. The one place of this
/// law, for the span-periodic profile and a line's.
#[inline]
pub fn between_nodes(
    w_n_per_m: f64,
    t_n: f64,
    (x0, h0): (f64, f64),
    (x1, h1): (f64, f64),
    x: f64,
) -> f64 {
    h0 + (h1 - h0) / (x1 - x0) * (x - x0) + w_n_per_m / (2.0 * t_n) * (x - x0) * (x - x1)
}

/// Upward point force a tensioned wire (tension `t_n`, weight `w_n_per_m`) needs at a node
/// `(x, h)` between its neighbours `(xl, hl)` and `(xr, hr)` to hold the piecewise-parabolic shape
/// (`T y'' = w` between nodes): the kink of the chord slopes plus the weight of half of each
/// segment, `T (s_left − s_right) + w (h_left + h_right)/2`. The one place of this law, for the
/// span-periodic profile and a line's.
#[inline]
pub fn kink_force(
    t_n: f64,
    w_n_per_m: f64,
    (xl, hl): (f64, f64),
    (x, h): (f64, f64),
    (xr, hr): (f64, f64),
) -> f64 {
    t_n * ((h - hl) / (x - xl) - (hr - h) / (xr - x)) + w_n_per_m * 0.5 * (xr - xl)
}

/// Bending moment of a simply supported span of length `span_m` under its weight `w_n_per_m`
/// and point loads `loads_n` (downward) at `xs_m` (sorted, from the left support), at each of
/// the same points: `M(x) = R_A x − w x²/2 − Σ_{x_i < x} P_i (x − x_i)` with
/// `R_A = Σ P_i (S − x_i)/S + w S/2`. The messenger's shape follows as `y = chord − M/T`.
pub fn simply_supported_moments(
    span_m: f64,
    w_n_per_m: f64,
    xs_m: &[f64],
    loads_n: &[f64],
) -> Vec<f64> {
    let s = span_m;
    let ra = loads_n
        .iter()
        .zip(xs_m)
        .map(|(p, x)| p * (s - x) / s)
        .sum::<f64>()
        + w_n_per_m * s / 2.0;
    xs_m.iter()
        .map(|&x| {
            let mut m = ra * x - w_n_per_m * x * x / 2.0;
            for (i, &xi) in xs_m.iter().enumerate() {
                if xi < x {
                    m -= loads_n[i] * (x - xi);
                }
            }
            m
        })
        .collect()
}

/// Transverse stiffness of a stitch wire (tension `T`, length `L`) at a point `a` from its nearer
/// end: `k = T L / (a (L − a))`, the point flexibility of a taut string. This is how pcsim derives
/// the stiffness of the paper's stitch spring elements (§2.1) from the stitch-wire data.
pub fn stitch_stiffness(tension_n: f64, length_m: f64, dist_to_support_m: f64) -> f64 {
    let a = 0.5 * length_m - dist_to_support_m;
    tension_n * length_m / (a * (length_m - a))
}

/// The static equilibrium of one (repeating) span.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticSolution {
    /// Span length, m.
    pub span_m: f64,
    /// Number of spans.
    pub n_spans: usize,
    /// Contact wire: nodes at the droppers (and at the support when the steady arm holds it).
    pub contact: Profile,
    /// Messenger: nodes at the support and the droppers.
    pub messenger: Profile,
    /// Dropper positions within a span.
    pub dropper_x_m: Vec<f64>,
    /// Dropper tension at the contact-wire clamp, N.
    pub dropper_force_contact_n: Vec<f64>,
    /// Dropper tension at the upper clamp (adds the dropper's own weight), N.
    pub dropper_force_messenger_n: Vec<f64>,
    /// Static dropper lengths, m.
    pub dropper_length_m: Vec<f64>,
    /// Per dropper: the stitch element it hangs from (stiffness N/m, node mass kg, static force
    /// in the element N), or `None` for droppers on the messenger.
    pub stitch: Vec<Option<StitchStatic>>,
    /// Upward force of a steady arm on the contact wire (interior supports), N.
    pub arm_force_n: f64,
    /// Upward force of a messenger support (interior supports), N.
    pub support_force_n: f64,
}

/// Static data of one stitch element.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StitchStatic {
    /// Stiffness of the stitch element, N/m.
    pub stiffness_n_per_m: f64,
    /// Mass of its node, kg.
    pub node_mass_kg: f64,
    /// Force carried by the stitch element (dropper tension at the top + node weight), N.
    pub force_n: f64,
}

/// What the static shape needs of a catenary's design (one span, repeated): the compile step
/// fills it from a case (`compile::model::static_design`).
#[derive(Debug, Clone, PartialEq)]
pub struct StaticDesign {
    /// Span length, m.
    pub span_m: f64,
    /// Number of spans.
    pub spans: usize,
    /// System height at the supports, m.
    pub encumbrance_m: f64,
    /// Dropper positions within a span, m.
    pub dropper_x_m: Vec<f64>,
    /// Design pre-sag of the contact wire.
    pub presag: Presag,
    /// Whether the steady arm holds the contact wire at its design height at the support.
    pub arm_holds_contact: bool,
    /// Contact wire's mass per length, kg/m.
    pub contact_mass_per_m_kg: f64,
    /// Contact wire's tension, N.
    pub contact_tension_n: f64,
    /// Messenger's mass per length, kg/m.
    pub messenger_mass_per_m_kg: f64,
    /// Messenger's tension, N.
    pub messenger_tension_n: f64,
    /// Droppers' mass per length, kg/m.
    pub dropper_mass_per_m_kg: f64,
    /// Mass of a dropper clamp on the contact wire, kg.
    pub clamp_mass_contact_kg: f64,
    /// Mass of a dropper clamp on the messenger, kg.
    pub clamp_mass_messenger_kg: f64,
    /// The stitch wire, if any.
    pub stitch: Option<StitchDesign>,
}

/// A stitch wire's design: the droppers it carries and its own data.
#[derive(Debug, Clone, PartialEq)]
pub struct StitchDesign {
    /// Indices of the droppers that hang from it.
    pub droppers: Vec<usize>,
    /// Tension, N.
    pub tension_n: f64,
    /// Length, centred on the support, m.
    pub length_m: f64,
    /// Mass of each stitch-dropper clamp, kg.
    pub clamp_mass_kg: f64,
    /// Mass per length, kg/m.
    pub mass_per_m_kg: f64,
}

/// Contact-wire pre-sag at each dropper (positive downward), m.
pub fn presag_at_droppers(c: &StaticDesign) -> Vec<f64> {
    presag_values(&c.presag, c.span_m, &c.dropper_x_m)
}

/// Contact-wire pre-sag (positive downward, m) of `presag` at droppers `d` (from the span's
/// start) of a span of `span_m`.
pub fn presag_values(presag: &Presag, span_m: f64, d: &[f64]) -> Vec<f64> {
    match presag {
        Presag::Table { values_m } => values_m.clone(),
        Presag::Parabolic {
            mid_span_m,
            zero_at,
        } => d
            .iter()
            .map(|&x| match zero_at {
                PresagZero::Supports => {
                    let xi = x / span_m;
                    4.0 * mid_span_m * xi * (1.0 - xi)
                }
                PresagZero::EndDroppers => {
                    let (a, b) = (d[0], d[d.len() - 1]);
                    if b <= a {
                        0.0
                    } else {
                        let eta = (x - a) / (b - a);
                        4.0 * mid_span_m * eta * (1.0 - eta)
                    }
                }
            })
            .collect(),
    }
}

/// Each dropper's stitch wire, if it has one: its stiffness (N/m) and the mass of its node at
/// the messenger (kg: the clamp and half the wire).
fn stitch_at_droppers(c: &StaticDesign) -> Vec<Option<(f64, f64)>> {
    let d = &c.dropper_x_m;
    (0..c.dropper_x_m.len())
        .map(|i| {
            c.stitch
                .as_ref()
                .filter(|st| st.droppers.contains(&i))
                .map(|st| {
                    let dist = d[i].min(c.span_m - d[i]);
                    let k = stitch_stiffness(st.tension_n, st.length_m, dist);
                    (k, st.clamp_mass_kg + 0.5 * st.mass_per_m_kg * st.length_m)
                })
        })
        .collect()
}

impl StaticSolution {
    /// Solve the static shape of the catenary of `c`.
    pub fn solve(c: &StaticDesign) -> Self {
        let s = c.span_m;
        let d = &c.dropper_x_m;
        let nd = d.len();
        let presag = presag_at_droppers(c);
        let hold = c.arm_holds_contact;
        let mut xs = Vec::new();
        let mut hs = Vec::new();
        if hold {
            xs.push(0.0);
            hs.push(0.0);
        }
        xs.extend_from_slice(d);
        hs.extend(presag.iter().map(|p| -p));
        let contact = Profile {
            xs,
            hs,
            span_m: s,
            n_spans: c.spans,
            w: c.contact_mass_per_m_kg * G,
            t: c.contact_tension_n,
        };
        let nf = contact.node_forces();
        let off = hold as usize;
        let fc: Vec<f64> = (0..nd)
            .map(|i| nf[i + off] + c.clamp_mass_contact_kg * G)
            .collect();
        let arm = if hold { nf[0] } else { 0.0 };

        let stitch = stitch_at_droppers(c);

        // Messenger: iterate on dropper lengths (their weight loads the messenger).
        let wm = c.messenger_mass_per_m_kg * G;
        let tm = c.messenger_tension_n;
        let mut len = vec![c.encumbrance_m; nd];
        let mut hm = vec![c.encumbrance_m; nd];
        let mut fm = fc.clone();
        let mut st_force = vec![0.0; nd];
        for _ in 0..8 {
            fm = (0..nd)
                .map(|i| fc[i] + c.dropper_mass_per_m_kg * G * len[i])
                .collect();
            let loads: Vec<f64> = (0..nd)
                .map(|i| match stitch[i] {
                    Some((_, m)) => {
                        st_force[i] = fm[i] + m * G;
                        st_force[i]
                    }
                    None => fm[i] + c.clamp_mass_messenger_kg * G,
                })
                .collect();
            let moments = simply_supported_moments(s, wm, d, &loads);
            for (j, m) in moments.iter().enumerate() {
                hm[j] = c.encumbrance_m - m / tm;
            }
            for i in 0..nd {
                let top = match stitch[i] {
                    Some((k, _)) => hm[i] - st_force[i] / k,
                    None => hm[i],
                };
                len[i] = top - contact.height(d[i]);
            }
        }
        let loads_total: f64 = (0..nd)
            .map(|i| match stitch[i] {
                Some(_) => st_force[i],
                None => fm[i] + c.clamp_mass_messenger_kg * G,
            })
            .sum();
        let mut mxs = vec![0.0];
        mxs.extend_from_slice(d);
        let mut mhs = vec![c.encumbrance_m];
        mhs.extend_from_slice(&hm);
        let messenger = Profile {
            xs: mxs,
            hs: mhs,
            span_m: s,
            n_spans: c.spans,
            w: wm,
            t: tm,
        };
        Self {
            span_m: s,
            n_spans: c.spans,
            contact,
            messenger,
            dropper_x_m: d.clone(),
            dropper_force_contact_n: fc,
            dropper_force_messenger_n: fm,
            dropper_length_m: len,
            stitch: (0..nd)
                .map(|i| {
                    stitch[i].map(|(k, m)| StitchStatic {
                        stiffness_n_per_m: k,
                        node_mass_kg: m,
                        force_n: st_force[i],
                    })
                })
                .collect(),
            arm_force_n: arm,
            support_force_n: loads_total + wm * s,
        }
    }

    /// Static contact-wire height at track position `x` (0 at the supports' design height), m.
    pub fn contact_height(&self, x: f64) -> f64 {
        self.contact.height(x)
    }

    /// Static messenger height at `x`, m.
    pub fn messenger_height(&self, x: f64) -> f64 {
        self.messenger.height(x)
    }

    /// Messenger height at dropper `i` (within a span).
    pub fn messenger_height_at_dropper(&self, i: usize) -> f64 {
        self.messenger.hs[i + 1]
    }
}

/// Static deflection of a tensioned beam over `basis` (pinned at both ends) under a uniform load
/// `q_per_m` (N/m, upward positive) and point loads `(x, F)`, in modal coordinates:
/// `q_k = Q_k / K_k` with the diagonal stiffness of Eq. 12 (`K_k = L/2 (T κ² + EI κ⁴)`).
pub fn modal_static_deflection(
    basis: &SineBasis,
    tension_n: f64,
    ei_nm2: f64,
    q_per_m: f64,
    points: &[(f64, f64)],
) -> Vec<f64> {
    let l = basis.length_m();
    let n = basis.n_modes();
    let mut row = vec![0.0; n];
    let mut q = vec![0.0; n];
    for i in 0..n {
        let k = basis.wavenumber(i);
        // ∫_0^L sin(κx) dx = (1 − cos kπ)/κ
        let parity = if i % 2 == 0 { 2.0 } else { 0.0 };
        q[i] = q_per_m * parity / k;
    }
    for &(x, f) in points {
        basis.fill_sines(x, &mut row);
        crate::linalg::axpy(f, &row, &mut q);
    }
    for (i, qi) in q.iter_mut().enumerate() {
        let k = basis.wavenumber(i);
        *qi /= 0.5 * l * (tension_n * k * k + ei_nm2 * k.powi(4));
    }
    q
}
