//! A line of spans that need not repeat (issue 21): one tension length's supports, its spans
//! (each with its own length, dropper layout and pre-sag), the contact-wire height and the system
//! height at each support, and its static shape (paper §2.1: "the static shape of the catenary is
//! obtained based on its design parameters").
//!
//! The laws are those of the span-periodic solution ([`crate::model::statics`]), shared with it:
//! between nodes a tensioned wire under its weight is a parabola, the force at a node is the kink
//! ([`kink_force`]), each messenger span hangs between its two supports under its weight and the
//! loads at its droppers ([`simply_supported_moments`], plus the chord between supports of
//! different heights), stitch elements sag by `F/k` ([`stitch_stiffness`]). What differs from the
//! periodic solution: the spans, droppers and heights are the line's, one by one, and the wires
//! end at anchors — the contact wire is held at its design height at both end supports whatever
//! the steady arms do (its end is the anchor's), and the messenger too.

use crate::model::statics::{
    between_nodes, kink_force, simply_supported_moments, stitch_stiffness, StitchStatic, G,
};
use crate::model::wire::WireRole;

/// One span of a tension length.
#[derive(Debug, Clone, PartialEq)]
pub struct SpanLayout {
    /// Span length, m.
    pub length_m: f64,
    /// Dropper positions from the span's first support, m, increasing, inside `(0, length_m)`.
    pub dropper_x_m: Vec<f64>,
    /// Design pre-sag of the contact wire at each dropper (downward), m: below the straight line
    /// between the two supports' contact-wire heights.
    pub presag_m: Vec<f64>,
    /// Whether each dropper hangs from the stitch wire of its nearer support.
    pub on_stitch: Vec<bool>,
}

/// A stitch wire at every support of a tension length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StitchWire {
    /// Tension, N.
    pub tension_n: f64,
    /// Length, centred on the support, m.
    pub length_m: f64,
    /// Mass of each stitch-dropper clamp, kg.
    pub clamp_mass_kg: f64,
    /// Mass per length, kg/m.
    pub mass_per_m_kg: f64,
}

/// What the static shape of one tension length needs of its design.
#[derive(Debug, Clone, PartialEq)]
pub struct TensionLengthDesign {
    /// Track position of the first support (the first anchor), m.
    pub start_m: f64,
    /// The spans, in track order.
    pub spans: Vec<SpanLayout>,
    /// Contact-wire design height at each support (`spans.len() + 1` values), m, relative to the
    /// line's nominal contact-wire height.
    pub contact_height_m: Vec<f64>,
    /// System height (messenger above contact wire) at each support, m.
    pub encumbrance_m: Vec<f64>,
    /// Whether the steady arms hold the contact wire at its design height at the interior
    /// supports (simple catenaries); the end supports hold it always (the anchors).
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
    /// The stitch wires, if any.
    pub stitch: Option<StitchWire>,
}

impl TensionLengthDesign {
    /// Track positions of the supports, m (`start_m` plus the running sum of the span lengths).
    pub fn supports_m(&self) -> Vec<f64> {
        let mut x = vec![self.start_m];
        for s in &self.spans {
            let last = x[x.len() - 1];
            x.push(last + s.length_m);
        }
        x
    }
}

/// A piecewise-parabolic wire profile over a whole wire: heights at its nodes (track positions,
/// increasing) and between nodes the parabola of a tensioned wire under its weight.
#[derive(Debug, Clone, PartialEq)]
pub struct LineProfile {
    /// Node positions, increasing, m.
    pub xs: Vec<f64>,
    /// Heights at the nodes, m.
    pub hs: Vec<f64>,
    /// Weight per metre, N/m.
    pub w: f64,
    /// Tension, N.
    pub t: f64,
}

impl LineProfile {
    /// Height at track position `x`; beyond the end nodes the end height (the anchors).
    pub fn height(&self, x: f64) -> f64 {
        let n = self.xs.len();
        if x <= self.xs[0] {
            return self.hs[0];
        }
        if x >= self.xs[n - 1] {
            return self.hs[n - 1];
        }
        let j = self.xs.partition_point(|&xn| xn <= x) - 1;
        let (x0, h0, x1, h1) = (self.xs[j], self.hs[j], self.xs[j + 1], self.hs[j + 1]);
        between_nodes(self.w, self.t, (x0, h0), (x1, h1), x)
    }

    /// Upward force of the end support on the wire at its first node (`first`) or its last:
    /// the vertical component of the tension along the end segment's parabola, `−T s + w h/2`
    /// with `s` the chord slope into the wire and `h` the segment's length.
    pub fn end_force(&self, first: bool) -> f64 {
        let n = self.xs.len();
        let (a, b) = if first { (0, 1) } else { (n - 1, n - 2) };
        let h = (self.xs[b] - self.xs[a]).abs();
        -self.t * (self.hs[b] - self.hs[a]) / h + self.w * h / 2.0
    }

    /// Upward force the wire needs at interior node `j` to hold this shape ([`kink_force`]).
    pub fn node_force(&self, j: usize) -> f64 {
        kink_force(
            self.t,
            self.w,
            (self.xs[j - 1], self.hs[j - 1]),
            (self.xs[j], self.hs[j]),
            (self.xs[j + 1], self.hs[j + 1]),
        )
    }
}

/// The static data of one dropper of a line.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DropperStatic {
    /// Track position, m.
    pub x_m: f64,
    /// The span it hangs in.
    pub span: usize,
    /// Design height of the contact wire at it, m.
    pub contact_height_m: f64,
    /// Tension at the contact-wire clamp, N.
    pub force_contact_n: f64,
    /// Tension at the upper clamp (adds the dropper's own weight), N.
    pub force_messenger_n: f64,
    /// Static length, m.
    pub length_m: f64,
    /// The stitch element it hangs from, if any.
    pub stitch: Option<StitchStatic>,
}

/// The static equilibrium of one tension length.
#[derive(Debug, Clone, PartialEq)]
pub struct TensionLengthStatics {
    /// Track positions of the supports, m.
    pub supports_m: Vec<f64>,
    /// Contact wire: nodes at the end supports, the droppers and (when the arms hold it) the
    /// interior supports.
    pub contact: LineProfile,
    /// Messenger: nodes at every support and dropper.
    pub messenger: LineProfile,
    /// The droppers, in track order.
    pub droppers: Vec<DropperStatic>,
    /// Upward force of the steady arm on the contact wire at each support, N (0 at the ends and
    /// where the arms do not hold it).
    pub arm_force_n: Vec<f64>,
    /// Upward force of the messenger support at each support, N (0 at the ends: the anchors).
    pub support_force_n: Vec<f64>,
}

/// The contact wire's design heights at its nodes (the supports it is held at, every dropper):
/// its profile, each dropper's (span, index, node) and each support's node.
#[allow(clippy::type_complexity)]
fn contact_profile(
    c: &TensionLengthDesign,
    sup: &[f64],
) -> (LineProfile, Vec<(usize, usize, usize)>, Vec<Option<usize>>) {
    let ns = c.spans.len();
    let hold = c.arm_holds_contact;
    let mut xs = Vec::new();
    let mut hs = Vec::new();
    let mut dropper_node = Vec::new();
    let mut support_node = vec![None; ns + 1];
    for (j, span) in c.spans.iter().enumerate() {
        if j == 0 || hold {
            support_node[j] = Some(xs.len());
            xs.push(sup[j]);
            hs.push(c.contact_height_m[j]);
        }
        let (ha, hb) = (c.contact_height_m[j], c.contact_height_m[j + 1]);
        for (i, &d) in span.dropper_x_m.iter().enumerate() {
            dropper_node.push((j, i, xs.len()));
            xs.push(sup[j] + d);
            hs.push(ha + (hb - ha) * d / span.length_m - span.presag_m[i]);
        }
    }
    support_node[ns] = Some(xs.len());
    xs.push(sup[ns]);
    hs.push(c.contact_height_m[ns]);
    let contact = LineProfile {
        xs,
        hs,
        w: c.contact_mass_per_m_kg * G,
        t: c.contact_tension_n,
    };
    (contact, dropper_node, support_node)
}

/// Stitch elements: each dropper that hangs from the stitch wire of its nearer support, the
/// wire's stiffness there and its clamp's mass.
fn stitches(
    c: &TensionLengthDesign,
    dropper_node: &[(usize, usize, usize)],
) -> Vec<Option<(f64, f64)>> {
    dropper_node
        .iter()
        .map(|&(j, i, _)| {
            let span = &c.spans[j];
            c.stitch.filter(|_| span.on_stitch[i]).map(|st| {
                let d = span.dropper_x_m[i];
                let dist = d.min(span.length_m - d);
                (
                    stitch_stiffness(st.tension_n, st.length_m, dist),
                    st.clamp_mass_kg + 0.5 * st.mass_per_m_kg * st.length_m,
                )
            })
        })
        .collect()
}

/// How the contact wire hangs from the messenger: each dropper's messenger height, force at the
/// messenger, length and stitch force.
struct Hanging {
    hm: Vec<f64>,
    fm: Vec<f64>,
    len: Vec<f64>,
    st_force: Vec<f64>,
}

impl Hanging {
    /// The messenger, each span between its supports, iterated on the dropper lengths (their
    /// weight loads the messenger).
    fn solve(
        c: &TensionLengthDesign,
        contact: &LineProfile,
        dropper_node: &[(usize, usize, usize)],
        fc: &[f64],
        stitch: &[Option<(f64, f64)>],
    ) -> Hanging {
        let ns = c.spans.len();
        let wm = c.messenger_mass_per_m_kg * G;
        let tm = c.messenger_tension_n;
        let top: Vec<f64> = (0..=ns)
            .map(|j| c.contact_height_m[j] + c.encumbrance_m[j])
            .collect();
        let nd = dropper_node.len();
        let mut len: Vec<f64> = dropper_node
            .iter()
            .map(|&(j, _, _)| c.encumbrance_m[j])
            .collect();
        let mut hm = vec![0.0; nd];
        let mut fm = fc.to_vec();
        let mut load = vec![0.0; nd];
        let mut st_force = vec![0.0; nd];
        for _ in 0..8 {
            for k in 0..nd {
                fm[k] = fc[k] + c.dropper_mass_per_m_kg * G * len[k];
                load[k] = match stitch[k] {
                    Some((_, m)) => {
                        st_force[k] = fm[k] + m * G;
                        st_force[k]
                    }
                    None => fm[k] + c.clamp_mass_messenger_kg * G,
                };
            }
            let mut k0 = 0;
            for (j, span) in c.spans.iter().enumerate() {
                let k1 = k0 + span.dropper_x_m.len();
                let m =
                    simply_supported_moments(span.length_m, wm, &span.dropper_x_m, &load[k0..k1]);
                for (i, &d) in span.dropper_x_m.iter().enumerate() {
                    hm[k0 + i] = top[j] + (top[j + 1] - top[j]) * d / span.length_m - m[i] / tm;
                }
                k0 = k1;
            }
            for k in 0..nd {
                let upper = match stitch[k] {
                    Some((kst, _)) => hm[k] - st_force[k] / kst,
                    None => hm[k],
                };
                len[k] = upper - contact.hs[dropper_node[k].2];
            }
        }
        Hanging {
            hm,
            fm,
            len,
            st_force,
        }
    }
}

/// The messenger's profile through its supports and the droppers' tops `hm`, and each
/// support's node.
fn messenger_profile(
    c: &TensionLengthDesign,
    sup: &[f64],
    contact: &LineProfile,
    dropper_node: &[(usize, usize, usize)],
    hm: &[f64],
) -> (LineProfile, Vec<usize>) {
    let ns = c.spans.len();
    let top: Vec<f64> = (0..=ns)
        .map(|j| c.contact_height_m[j] + c.encumbrance_m[j])
        .collect();
    let nd = dropper_node.len();
    let mut mxs = Vec::with_capacity(nd + ns + 1);
    let mut mhs = Vec::with_capacity(nd + ns + 1);
    let mut msup = Vec::with_capacity(ns + 1);
    let mut k = 0;
    for (j, span) in c.spans.iter().enumerate() {
        msup.push(mxs.len());
        mxs.push(sup[j]);
        mhs.push(top[j]);
        for _ in &span.dropper_x_m {
            mxs.push(contact.xs[dropper_node[k].2]);
            mhs.push(hm[k]);
            k += 1;
        }
    }
    msup.push(mxs.len());
    mxs.push(sup[ns]);
    mhs.push(top[ns]);
    let messenger = LineProfile {
        xs: mxs,
        hs: mhs,
        w: c.messenger_mass_per_m_kg * G,
        t: c.messenger_tension_n,
    };
    (messenger, msup)
}

impl TensionLengthStatics {
    /// Solve the static shape of the tension length `c`.
    pub fn solve(c: &TensionLengthDesign) -> Self {
        let sup = c.supports_m();
        let ns = c.spans.len();
        let (contact, dropper_node, support_node) = contact_profile(c, &sup);
        let fc: Vec<f64> = dropper_node
            .iter()
            .map(|&(_, _, n)| contact.node_force(n) + c.clamp_mass_contact_kg * G)
            .collect();
        let arm_force_n: Vec<f64> = (0..=ns)
            .map(|j| match support_node[j] {
                Some(n) if j > 0 && j < ns => contact.node_force(n),
                _ => 0.0,
            })
            .collect();
        let stitch = stitches(c, &dropper_node);
        let hang = Hanging::solve(c, &contact, &dropper_node, &fc, &stitch);
        let (messenger, msup) = messenger_profile(c, &sup, &contact, &dropper_node, &hang.hm);
        let support_force_n = (0..=ns)
            .map(|j| {
                if j > 0 && j < ns {
                    messenger.node_force(msup[j])
                } else {
                    0.0
                }
            })
            .collect();
        let droppers = dropper_node
            .iter()
            .enumerate()
            .map(|(k, &(j, _, n))| DropperStatic {
                x_m: contact.xs[n],
                span: j,
                contact_height_m: contact.hs[n],
                force_contact_n: fc[k],
                force_messenger_n: hang.fm[k],
                length_m: hang.len[k],
                stitch: stitch[k].map(|(kst, m)| StitchStatic {
                    stiffness_n_per_m: kst,
                    node_mass_kg: m,
                    force_n: hang.st_force[k],
                }),
            })
            .collect();
        TensionLengthStatics {
            supports_m: sup,
            contact,
            messenger,
            droppers,
            arm_force_n,
            support_force_n,
        }
    }

    /// Static contact-wire height at track position `x`, m.
    pub fn contact_height(&self, x: f64) -> f64 {
        self.contact.height(x)
    }

    /// Static messenger height at track position `x`, m.
    pub fn messenger_height(&self, x: f64) -> f64 {
        self.messenger.height(x)
    }
}

/// The static shape of a whole line: each tension length's. Its wires are numbered as the
/// full model's: wire `2k` is tension length `k`'s messenger, `2k + 1` its contact wire. A
/// window of the line (the real-time catenary, `Model::window`) reads it at its own origin and
/// with its own wire numbers.
#[derive(Debug, Clone, PartialEq)]
pub struct LineStatics {
    /// The tension lengths, in track order.
    pub tension_lengths: Vec<TensionLengthStatics>,
    /// Line position of the model's x = 0, m (0 for the full model; a window's origin).
    pub origin_m: f64,
    /// For each wire of the model: its number in the full model (empty: the same numbers).
    pub full_wire: Vec<usize>,
}

impl LineStatics {
    /// The line of these tension lengths.
    pub fn new(tension_lengths: Vec<TensionLengthStatics>) -> Self {
        LineStatics {
            tension_lengths,
            origin_m: 0.0,
            full_wire: Vec::new(),
        }
    }

    /// The same shape read by a window that starts at line position `origin_m` and whose wire
    /// `i` is the full model's `full_wire[i]`.
    pub fn window(&self, origin_m: f64, full_wire: Vec<usize>) -> Self {
        LineStatics {
            tension_lengths: self.tension_lengths.clone(),
            origin_m: self.origin_m + origin_m,
            full_wire: if self.full_wire.is_empty() {
                full_wire
            } else {
                full_wire.iter().map(|&i| self.full_wire[i]).collect()
            },
        }
    }

    /// Static height of wire `wire` (role `role`) at model coordinate `x`, m.
    pub fn height(&self, wire: usize, role: WireRole, x: f64) -> f64 {
        let wire = self.full_wire.get(wire).copied().unwrap_or(wire);
        let t = &self.tension_lengths[(wire / 2).min(self.tension_lengths.len() - 1)];
        let x = x + self.origin_m;
        match role {
            WireRole::Contact => t.contact_height(x),
            _ => t.messenger_height(x),
        }
    }

    /// The system height (messenger above contact wire) at model coordinate `x`, the largest of
    /// the tension lengths whose wires reach there, m.
    pub fn system_height(&self, x: f64) -> f64 {
        let x = x + self.origin_m;
        self.tension_lengths
            .iter()
            .filter(|t| x >= t.supports_m[0] && x <= t.supports_m[t.supports_m.len() - 1])
            .map(|t| t.messenger_height(x) - t.contact_height(x))
            .fold(f64::NEG_INFINITY, f64::max)
    }
}
