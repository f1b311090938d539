//! Static shape of the catenary from its design geometry (paper §2.1: "the static shape of the
//! catenary is obtained based on its design parameters"; README §5).
//!
//! The design fixes the contact-wire height at the supports (0) and at every dropper (minus the
//! pre-sag). Between those nodes a tensioned wire under its own weight `w = ρA g` is a parabola
//! (`T y'' = w`), and the kink at a node gives the point force that holds it:
//!
//! ```text
//! F_node = T (s_left − s_right) + w (h_left + h_right)/2 (+ clamp weight),
//! ```
//!
//! with `s` the chord slopes and `h` the segment lengths. That yields the dropper tensions at the
//! contact wire and the steady-arm force. The messenger hangs from its supports (at the
//! encumbrance) under its weight, the dropper tensions, the dropper weights and its clamps; its
//! shape follows from the simply supported moment diagram, `y_m = E − M(x)/T_m`. Dropper lengths
//! are the differences of the two heights. Bending stiffness is neglected in this step: with
//! `√(EI/T) ≈ 0.1 m` it only rounds the kinks (the modal check in the tests includes EI and stays
//! within 1 mm of the design).
//!
//! The dynamic model works with deviations from this shape. The height the pantograph sees is this
//! analytic profile plus the modal deviation, never a truncated sine series of the static shape
//! (README §5).

use crate::basis::SineBasis;
use crate::case::{CatenaryCase, Presag, PresagZero, G};

/// The static equilibrium of one (repeating) span.
#[derive(Debug, Clone, PartialEq)]
pub struct StaticSolution {
    pub span_m: f64,
    pub n_spans: usize,
    /// Node positions within a span: 0, droppers…, span.
    pub nodes_x: Vec<f64>,
    /// Contact-wire design height at the nodes (0 at the supports), m.
    pub contact_heights_m: Vec<f64>,
    /// Messenger height at the nodes (encumbrance at the supports), m.
    pub messenger_heights_m: Vec<f64>,
    /// Dropper tension at the contact-wire clamp, N.
    pub dropper_force_contact_n: Vec<f64>,
    /// Dropper tension at the messenger clamp (adds the dropper's own weight), N.
    pub dropper_force_messenger_n: Vec<f64>,
    pub dropper_length_m: Vec<f64>,
    /// Upward force of a steady arm on the contact wire (interior supports), N.
    pub arm_force_n: f64,
    /// Upward force of a messenger support (interior supports), N.
    pub support_force_n: f64,
    w_contact: f64,
    w_messenger: f64,
    t_contact: f64,
    t_messenger: f64,
}

/// Contact-wire pre-sag at each dropper (positive downward), m.
pub fn presag_at_droppers(c: &CatenaryCase) -> Vec<f64> {
    let d = &c.droppers.positions_m;
    match &c.presag {
        Presag::Table { values_m } => values_m.clone(),
        Presag::Parabolic {
            mid_span_m,
            zero_at,
        } => d
            .iter()
            .map(|&x| match zero_at {
                PresagZero::Supports => {
                    let xi = x / c.span_m;
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

impl StaticSolution {
    /// Solve the static shape of the catenary of `c`.
    pub fn solve(c: &CatenaryCase) -> Self {
        let s = c.span_m;
        let mut nodes_x = vec![0.0];
        nodes_x.extend_from_slice(&c.droppers.positions_m);
        nodes_x.push(s);
        let presag = presag_at_droppers(c);
        let mut hc = vec![0.0];
        hc.extend(presag.iter().map(|p| -p));
        hc.push(0.0);
        let wc = c.contact_wire.mass_per_m_kg * G;
        let wm = c.messenger.mass_per_m_kg * G;
        let (tc, tm) = (c.contact_wire.tension_n, c.messenger.tension_n);
        let nn = nodes_x.len();
        let seg_len: Vec<f64> = (0..nn - 1).map(|j| nodes_x[j + 1] - nodes_x[j]).collect();
        let slope: Vec<f64> = (0..nn - 1)
            .map(|j| (hc[j + 1] - hc[j]) / seg_len[j])
            .collect();
        let nd = nn - 2;
        let fc: Vec<f64> = (1..=nd)
            .map(|i| {
                tc * (slope[i - 1] - slope[i])
                    + wc * 0.5 * (seg_len[i - 1] + seg_len[i])
                    + c.droppers.clamp_mass_contact_kg * G
            })
            .collect();
        let arm = tc * (slope[nn - 2] - slope[0]) + wc * 0.5 * (seg_len[nn - 2] + seg_len[0]);

        // Messenger: iterate on dropper lengths (their weight loads the messenger).
        let mut len = vec![c.encumbrance_m; nd];
        let mut hm = vec![c.encumbrance_m; nn];
        let mut fm = fc.clone();
        for _ in 0..6 {
            fm = (0..nd)
                .map(|i| {
                    fc[i]
                        + c.droppers.mass_per_m_kg * G * len[i]
                        + c.droppers.clamp_mass_messenger_kg * G
                })
                .collect();
            let ra = fm
                .iter()
                .zip(&nodes_x[1..=nd])
                .map(|(p, x)| p * (s - x) / s)
                .sum::<f64>()
                + wm * s / 2.0;
            for (j, &x) in nodes_x.iter().enumerate() {
                let mut m = ra * x - wm * x * x / 2.0;
                for i in 0..nd {
                    if nodes_x[i + 1] < x {
                        m -= fm[i] * (x - nodes_x[i + 1]);
                    }
                }
                hm[j] = c.encumbrance_m - m / tm;
            }
            hm[0] = c.encumbrance_m;
            hm[nn - 1] = c.encumbrance_m;
            for i in 0..nd {
                len[i] = hm[i + 1] - hc[i + 1];
            }
        }
        let support = fm.iter().sum::<f64>() + wm * s;
        Self {
            span_m: s,
            n_spans: c.spans,
            nodes_x,
            contact_heights_m: hc,
            messenger_heights_m: hm,
            dropper_force_contact_n: fc,
            dropper_force_messenger_n: fm,
            dropper_length_m: len,
            arm_force_n: arm,
            support_force_n: support,
            w_contact: wc,
            w_messenger: wm,
            t_contact: tc,
            t_messenger: tm,
        }
    }

    fn eval(&self, x: f64, h: &[f64], w: f64, t: f64) -> f64 {
        let s = self.span_m;
        let k = (x / s).floor().clamp(0.0, (self.n_spans - 1) as f64);
        let xi = (x - k * s).clamp(0.0, s);
        let j = match self.nodes_x.iter().position(|&n| n > xi) {
            Some(0) => 0,
            Some(p) => p - 1,
            None => self.nodes_x.len() - 2,
        };
        let (x0, x1) = (self.nodes_x[j], self.nodes_x[j + 1]);
        let sl = (h[j + 1] - h[j]) / (x1 - x0);
        h[j] + sl * (xi - x0) + w / (2.0 * t) * (xi - x0) * (xi - x1)
    }

    /// Static contact-wire height at track position `x` (0 at the supports), m.
    pub fn contact_height(&self, x: f64) -> f64 {
        self.eval(x, &self.contact_heights_m, self.w_contact, self.t_contact)
    }

    /// Static messenger height at `x`, m.
    pub fn messenger_height(&self, x: f64) -> f64 {
        self.eval(
            x,
            &self.messenger_heights_m,
            self.w_messenger,
            self.t_messenger,
        )
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
        crate::basis::axpy(f, &row, &mut q);
    }
    for (i, qi) in q.iter_mut().enumerate() {
        let k = basis.wavenumber(i);
        *qi /= 0.5 * l * (tension_n * k * k + ei_nm2 * k.powi(4));
    }
    q
}
