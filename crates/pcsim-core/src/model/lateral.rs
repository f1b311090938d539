//! The static lateral shape (issue 12; lines and curves, issue 41): stagger. Each contact wire
//! is registered at each of its supports at its stagger and runs straight between registration
//! points (a tensioned wire with no lateral load); its messenger follows the same stagger, as on
//! most high-speed lines, so that the droppers hang vertically in still air and carry no static
//! lateral force. The kinks at the supports are carried by the steady arms and the messenger
//! supports, whose static forces are not part of the deviation. On a line each tension length's
//! wires have their own stagger at their own supports; in an overlap the two contact wires run
//! side by side and cross in plan. A steady wind adds its static deflection to this shape; that
//! part is solved with the dynamic model's own operators (`solve::Integrator::initial_state`), so
//! that the run starts in equilibrium.

/// One stagger polyline: a wire's static lateral position at a run of consecutive supports.
#[derive(Debug, Clone, PartialEq)]
pub struct StaggerLine {
    /// Index of the polyline's first support in [`LateralGeometry::supports_m`].
    pub first_support: usize,
    /// Stagger at supports `first_support`, `first_support + 1`, … (the ends held beyond), m.
    pub stagger_m: Vec<f64>,
}

/// Where a track position lies among the supports.
enum At {
    Before,
    Span(usize, f64),
    After,
}

/// The stagger polylines of the model's wires and the lateral constants the run's outputs need.
#[derive(Debug, Clone, PartialEq)]
pub struct LateralGeometry {
    /// Track positions of the supports, increasing, m.
    pub supports_m: Vec<f64>,
    /// The span when every span is as long (a `[catenary]`): the uniform path of
    /// [`LateralGeometry::stagger_at`].
    pub uniform_span_m: Option<f64>,
    /// The stagger polylines (a `[catenary]` has one, shared by its two wires; a line one per
    /// tension length).
    pub lines: Vec<StaggerLine>,
    /// Per wire of the model: the index of its polyline in `lines` (`None`: no static stagger).
    pub wire_line: Vec<Option<usize>>,
    /// Per span (between supports `i` and `i + 1`): the track's curvature, 1/m, positive toward
    /// positive stagger (0: straight).
    pub curvature_per_m: Vec<f64>,
    /// Per span: the pantograph head's centre from the track's centre line (a canted curve), m.
    pub head_offset_m: Vec<f64>,
    /// Depth of the contact point below the contact wire's axis, m: the contact point's lateral
    /// position is `z − e_c φ`.
    pub contact_point_eccentricity_m: f64,
    /// `(wire, position)` (model coordinates: a window's own) where a contact wire's lateral
    /// deviation is monitored for the blow-out: droppers and mid-spans.
    pub probes_m: Vec<(usize, f64)>,
}

impl LateralGeometry {
    /// Where track position `x` lies among the supports: before the first, in span `i` at
    /// fraction `t ∈ (0, 1)`, or beyond the last.
    fn span_of(&self, x: f64) -> At {
        let s = &self.supports_m;
        let n = s.len();
        if n < 2 {
            return At::Before;
        }
        if let Some(span) = self.uniform_span_m {
            let r = (x - s[0]) / span;
            if r <= 0.0 {
                return At::Before;
            }
            let i = r.floor() as usize;
            if i + 1 >= n {
                return At::After;
            }
            return At::Span(i, r - i as f64);
        }
        if x <= s[0] {
            return At::Before;
        }
        let i = s.partition_point(|&p| p <= x);
        if i >= n {
            return At::After;
        }
        let i = i - 1;
        At::Span(i, (x - s[i]) / (s[i + 1] - s[i]))
    }

    /// Length of span `i`, m.
    fn span_len(&self, i: usize) -> f64 {
        self.uniform_span_m
            .unwrap_or_else(|| self.supports_m[i + 1] - self.supports_m[i])
    }

    /// Static lateral position of wire `wire` at track position `x` from the track's centre
    /// line, m: the straight line between the staggers of the neighbouring supports, and in a
    /// curve of curvature `κ` that chord's bow toward the centre, `κ (x − x_i)(x_{i+1} − x) / 2`
    /// (the chord against the arc, to second order in the span over the radius). Beyond the
    /// wire's end supports its end staggers hold.
    pub fn stagger_at(&self, wire: usize, x: f64) -> f64 {
        let Some(line) = self.wire_line.get(wire).copied().flatten() else {
            return 0.0;
        };
        let l = &self.lines[line];
        let n = l.stagger_m.len();
        if n == 0 {
            return 0.0;
        }
        let last = l.first_support + n - 1;
        let (i, t) = match self.span_of(x) {
            At::Span(span, t) if span >= l.first_support && span < last => (span, t),
            At::Span(span, _) if span >= last => return l.stagger_m[n - 1],
            At::After => return l.stagger_m[n - 1],
            _ => return l.stagger_m[0],
        };
        let span = i;
        let i = i - l.first_support;
        let chord = l.stagger_m[i] + t * (l.stagger_m[i + 1] - l.stagger_m[i]);
        let kappa = self.curvature_per_m.get(span).copied().unwrap_or(0.0);
        if kappa == 0.0 {
            return chord;
        }
        let s = self.span_len(span);
        let bow = 0.5 * kappa * (t * s) * ((1.0 - t) * s);
        chord + bow
    }

    /// The pantograph head's centre from the track's centre line at track position `x`, m.
    pub fn head_offset_at(&self, x: f64) -> f64 {
        match self.head_offset_m.len() {
            0 => 0.0,
            1 => self.head_offset_m[0],
            n => match self.span_of(x) {
                At::Before => self.head_offset_m[0],
                At::Span(i, _) => self.head_offset_m[i.min(n - 1)],
                At::After => self.head_offset_m[n - 1],
            },
        }
    }

    /// The track's turn from its direction at the first support to its direction at track
    /// position `x`, rad: `θ(x) = ∫ κ ds` from the first support, each span on its own
    /// curvature (positive: toward positive stagger); before the first support and beyond the
    /// last, the end spans' curvatures continue.
    pub fn turn_rad(&self, x: f64) -> f64 {
        let n = self.curvature_per_m.len();
        if n == 0 || self.supports_m.is_empty() {
            return 0.0;
        }
        let s0 = self.supports_m[0];
        let mut theta = 0.0;
        let mut from = s0;
        for i in 0..n {
            let to = self.span_start(i) + self.span_len(i);
            let k = self.curvature_per_m[i];
            if x <= to || i + 1 == n {
                let lo = if i == 0 { x.min(from) } else { from };
                let hi = if i == 0 && x < from { from } else { x };
                let sign = if i == 0 && x < from { -1.0 } else { 1.0 };
                return theta + sign * k * (hi - lo);
            }
            theta += k * (to - from);
            from = to;
        }
        theta
    }

    /// Whether the track curves anywhere.
    pub fn curved(&self) -> bool {
        self.curvature_per_m.iter().any(|&k| k != 0.0)
    }

    /// The static lateral force each interior registration of polyline `line` applies to a
    /// wire of tension `tension_n` (positive toward positive stagger), N: the tension's change
    /// of direction there,
    /// `T [(y_{i+1} − y_i)/s_i − (y_i − y_{i−1})/s_{i−1} + (κ_{i−1} s_{i−1} + κ_i s_i)/2]`
    /// (the kink of the stagger, and in a curve the pull-off, `T s / R` on equal spans). The
    /// polyline's interior supports, in order.
    pub fn registration_forces_n(&self, line: usize, tension_n: f64) -> Vec<f64> {
        let l = &self.lines[line];
        let y = &l.stagger_m;
        (1..y.len().saturating_sub(1))
            .map(|i| {
                let g = l.first_support + i;
                let (s0, s1) = (self.span_len(g - 1), self.span_len(g));
                let k0 = self.curvature_per_m.get(g - 1).copied().unwrap_or(0.0);
                let k1 = self.curvature_per_m.get(g).copied().unwrap_or(0.0);
                if self.uniform_span_m.is_some() && k0 == k1 {
                    // Equal spans on one curve: the same sum in the uniform form.
                    return tension_n * ((y[i + 1] - 2.0 * y[i] + y[i - 1]) / s1 + k1 * s1);
                }
                tension_n
                    * ((y[i + 1] - y[i]) / s1 - (y[i] - y[i - 1]) / s0 + 0.5 * (k0 * s0 + k1 * s1))
            })
            .collect()
    }

    /// The same geometry for a window starting at track position `origin_m`, whose wire `j` is
    /// the full model's wire `i` where `wire_map[i] == Some(j)`: the stagger stays in track
    /// coordinates, the probes inside `(origin, origin + length)` move to the window's.
    pub fn window(&self, origin_m: f64, length_m: f64, wire_map: &[Option<usize>]) -> Self {
        let mut wire_line = Vec::new();
        for (i, w) in wire_map.iter().enumerate() {
            if let Some(j) = *w {
                if wire_line.len() <= j {
                    wire_line.resize(j + 1, None);
                }
                wire_line[j] = self.wire_line.get(i).copied().flatten();
            }
        }
        Self {
            probes_m: self
                .probes_m
                .iter()
                .filter(|&&(_, x)| x > origin_m + 1e-9 && x < origin_m + length_m - 1e-9)
                .filter_map(|&(w, x)| Some((wire_map.get(w).copied().flatten()?, x - origin_m)))
                .collect(),
            wire_line,
            ..self.clone()
        }
    }
}

/// A curved track's report (`summary.json`, `curve`): the radius and cant, where the head
/// stands, the chord's largest bow, and the static lateral force of the registrations on each
/// wire (the pull-off: the tension's change of direction at each, closed form).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct CurveReport {
    /// Radius, m, signed as the case gives it (positive: the centre on the side of positive
    /// stagger); on a line of several curves, the tightest.
    pub track_radius_m: f64,
    /// The pantograph head's centre from the track's centre line (a canted curve), m; on a line,
    /// the largest in magnitude.
    pub head_offset_m: f64,
    /// The chord's largest bow toward the curve's centre within a span, `s²/(8R)`, mm.
    pub max_bow_mm: f64,
    /// The contact wires' registrations: smallest and largest static lateral force, N
    /// (positive toward positive stagger).
    pub contact_wire_registration_n: [f64; 2],
    /// The messengers' supports: smallest and largest static lateral force, N.
    pub messenger_support_n: [f64; 2],
    /// Each run of spans on one radius and cant, with each pantograph's contact point on its
    /// head there.
    pub sections: Vec<CurveSection>,
}

impl LateralGeometry {
    /// The curve's report for the model's contact wires and messengers, each `(polyline,
    /// tension)` (none on straight track).
    pub fn curve_report(
        &self,
        contact: &[(usize, f64)],
        messenger: &[(usize, f64)],
    ) -> Option<CurveReport> {
        if !self.curved() {
            return None;
        }
        let tightest = (self.curvature_per_m.iter().copied()).fold(0.0f64, |a, k| {
            if k.abs() > a.abs() {
                k
            } else {
                a
            }
        });
        let bow = (0..self.curvature_per_m.len())
            .map(|i| self.span_len(i).powi(2) * self.curvature_per_m[i].abs() / 8.0)
            .fold(0.0, f64::max);
        let head = (self.head_offset_m.iter().copied()).fold(0.0f64, |a, h| {
            if h.abs() > a.abs() {
                h
            } else {
                a
            }
        });
        let range = |wires: &[(usize, f64)]| {
            let f: Vec<f64> = (wires.iter())
                .flat_map(|&(l, t)| self.registration_forces_n(l, t))
                .collect();
            if f.is_empty() {
                return [0.0, 0.0];
            }
            [
                f.iter().copied().fold(f64::INFINITY, f64::min),
                f.iter().copied().fold(f64::NEG_INFINITY, f64::max),
            ]
        };
        Some(CurveReport {
            track_radius_m: 1.0 / tightest,
            head_offset_m: head,
            max_bow_mm: bow * 1e3,
            contact_wire_registration_n: range(contact),
            messenger_support_n: range(messenger),
            sections: self.curve_sections(contact, messenger),
        })
    }

    /// Where span `i` starts, m.
    fn span_start(&self, i: usize) -> f64 {
        match self.uniform_span_m {
            Some(s) => self.supports_m[0] + i as f64 * s,
            None => self.supports_m[i],
        }
    }

    /// The curve's sections: each run of consecutive spans on one radius with one head offset,
    /// with its extent, the chord's largest bow and the registrations' static lateral forces at
    /// its supports (its ends included). The pantographs' ranges on the head are the
    /// recorder's to fill.
    fn curve_sections(
        &self,
        contact: &[(usize, f64)],
        messenger: &[(usize, f64)],
    ) -> Vec<CurveSection> {
        let n = self.curvature_per_m.len();
        let head = |i: usize| match self.head_offset_m.len() {
            0 => 0.0,
            h => self.head_offset_m[i.min(h - 1)],
        };
        let mut sections: Vec<CurveSection> = Vec::new();
        let mut i = 0;
        while i < n {
            let (k, h) = (self.curvature_per_m[i], head(i));
            let mut j = i + 1;
            while j < n && self.curvature_per_m[j] == k && head(j) == h {
                j += 1;
            }
            if k != 0.0 {
                let (from, to) = (
                    self.span_start(i),
                    self.span_start(i) + (i..j).map(|g| self.span_len(g)).sum::<f64>(),
                );
                let range = |wires: &[(usize, f64)]| {
                    let mut r = [f64::INFINITY, f64::NEG_INFINITY];
                    for &(l, t) in wires {
                        let first = self.lines[l].first_support;
                        for (m, f) in self.registration_forces_n(l, t).into_iter().enumerate() {
                            let g = first + m + 1;
                            if g >= i && g <= j {
                                r = [r[0].min(f), r[1].max(f)];
                            }
                        }
                    }
                    if r[0] > r[1] {
                        [0.0, 0.0]
                    } else {
                        r
                    }
                };
                sections.push(CurveSection {
                    from_m: from,
                    to_m: to,
                    track_radius_m: 1.0 / k,
                    head_offset_m: h,
                    max_bow_mm: (i..j)
                        .map(|g| self.span_len(g).powi(2) * k.abs() / 8.0)
                        .fold(0.0, f64::max)
                        * 1e3,
                    contact_wire_registration_n: range(contact),
                    messenger_support_n: range(messenger),
                    on_head: Vec::new(),
                });
            }
            i = j;
        }
        sections
    }
}

/// One section of a curve: a run of spans on one radius, with one cant (issue 41: the contact
/// point's lateral range on the head reported per curve).
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct CurveSection {
    /// Where it starts and ends along the track, m (supports).
    pub from_m: f64,
    /// Where it ends, m.
    pub to_m: f64,
    /// Radius, m, signed as the case gives it.
    pub track_radius_m: f64,
    /// The pantograph head's centre from the track's centre line (a canted curve), m.
    pub head_offset_m: f64,
    /// The chord's largest bow toward the curve's centre within a span, `s²/(8R)`, mm.
    pub max_bow_mm: f64,
    /// The contact wires' registrations at its supports: smallest and largest static lateral
    /// force, N (positive toward positive stagger).
    pub contact_wire_registration_n: [f64; 2],
    /// The messengers' supports at its supports: smallest and largest static lateral force, N.
    pub messenger_support_n: [f64; 2],
    /// Each pantograph's contact point on its head while it runs through the section.
    pub on_head: Vec<OnHead>,
}

/// Where a pantograph's contact point ran on its head through a curve's section.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize, schemars::JsonSchema)]
pub struct OnHead {
    /// The pantograph's name.
    pub pantograph: String,
    /// The contact point's lateral position from the head's centre, smallest and largest, m
    /// (positive toward positive stagger).
    pub lateral_m: [f64; 2],
    /// The head's half-width less the largest distance from its centre, m (negative: off the
    /// head).
    pub min_head_margin_m: Option<f64>,
}

impl CurveReport {
    /// The head's centre from the track's centre line at track position `x`, m: the section's
    /// that holds `x` (0 on straight track).
    pub fn head_offset_at(&self, x: f64) -> f64 {
        self.sections
            .iter()
            .find(|c| x >= c.from_m && x <= c.to_m)
            .map_or(0.0, |c| c.head_offset_m)
    }
}
