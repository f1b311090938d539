//! The static lateral shape (issue 12): stagger. The contact wire is registered at each support
//! at its stagger and runs straight between registration points (a tensioned wire with no
//! lateral load); the messenger follows the same stagger, as on most high-speed lines, so that
//! the droppers hang vertically in still air and carry no static lateral force. The kinks at the
//! supports are carried by the steady arms and the messenger supports, whose static forces are
//! not part of the deviation. A steady wind adds its static deflection to this shape; that part is
//! solved with the dynamic model's own operators (`solve::Integrator::initial_state`), so that the
//! run starts in equilibrium.

/// The stagger polyline and the lateral constants the run's outputs need.
#[derive(Debug, Clone, PartialEq)]
pub struct LateralGeometry {
    /// Track position of support 0, m.
    pub first_support_m: f64,
    /// Span length, m.
    pub span_m: f64,
    /// Stagger at supports 0, 1, 2, … (the last repeats beyond), m.
    pub stagger_m: Vec<f64>,
    /// Depth of the contact point below the contact wire's axis, m: the contact point's lateral
    /// position is `z − e_c φ`.
    pub contact_point_eccentricity_m: f64,
    /// Positions (model coordinates: a window's own) where the contact wire's lateral deviation
    /// is monitored for the blow-out: droppers and mid-spans.
    pub probes_m: Vec<f64>,
    /// Curvature of the track, 1/m, positive toward positive stagger (0: straight).
    pub curvature_per_m: f64,
    /// The pantograph head's centre from the track's centre line on a canted curve, m.
    pub head_offset_m: f64,
}

impl LateralGeometry {
    /// Static lateral position of the wires at track position `x` from the track's centre line,
    /// m: the straight line between the staggers of the neighbouring supports, and in a curve of
    /// curvature `κ` that chord's bow toward the centre, `κ (x − x_i)(x_{i+1} − x) / 2` (the
    /// chord against the arc, to second order in the span over the radius).
    pub fn stagger_at(&self, x: f64) -> f64 {
        let n = self.stagger_m.len();
        if n == 0 {
            return 0.0;
        }
        let s = (x - self.first_support_m) / self.span_m;
        if s <= 0.0 {
            return self.stagger_m[0];
        }
        let i = s.floor() as usize;
        if i + 1 >= n {
            return self.stagger_m[n - 1];
        }
        let t = s - i as f64;
        let chord = self.stagger_m[i] + t * (self.stagger_m[i + 1] - self.stagger_m[i]);
        if self.curvature_per_m == 0.0 {
            return chord;
        }
        let bow = 0.5 * self.curvature_per_m * (t * self.span_m) * ((1.0 - t) * self.span_m);
        chord + bow
    }

    /// The static lateral force each interior registration applies to a wire of tension
    /// `tension_n` (positive toward positive stagger), N: the tension's change of direction
    /// there, `T [(y_{i+1} − 2y_i + y_{i−1})/s + κ s]` (the kink of the stagger, and in a curve
    /// the pull-off `T s / R`). Registrations 1 … n−2 (the interior supports), in order.
    pub fn registration_forces_n(&self, tension_n: f64) -> Vec<f64> {
        let (y, s) = (&self.stagger_m, self.span_m);
        (1..y.len().saturating_sub(1))
            .map(|i| {
                tension_n * ((y[i + 1] - 2.0 * y[i] + y[i - 1]) / s + self.curvature_per_m * s)
            })
            .collect()
    }

    /// The same geometry for a window starting at track position `origin_m`: the stagger stays in
    /// track coordinates, the probes inside `(origin, origin + length)` move to the window's.
    pub fn window(&self, origin_m: f64, length_m: f64) -> Self {
        Self {
            probes_m: self
                .probes_m
                .iter()
                .filter(|&&x| x > origin_m + 1e-9 && x < origin_m + length_m - 1e-9)
                .map(|x| x - origin_m)
                .collect(),
            ..self.clone()
        }
    }
}

/// A curved track's report (`summary.json`, `curve`): the radius and cant, where the head
/// stands, the chord's largest bow, and the static lateral force of the registrations on each
/// wire (the pull-off: the tension's change of direction at each, closed form).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct CurveReport {
    /// Radius, m, signed as the case gives it (positive: the centre on the side of positive
    /// stagger).
    pub track_radius_m: f64,
    /// The pantograph head's centre from the track's centre line (a canted curve), m.
    pub head_offset_m: f64,
    /// The chord's largest bow toward the curve's centre within a span, `s²/(8R)`, mm.
    pub max_bow_mm: f64,
    /// The contact wire's registrations: smallest and largest static lateral force, N
    /// (positive toward positive stagger).
    pub contact_wire_registration_n: [f64; 2],
    /// The messenger's supports: smallest and largest static lateral force, N.
    pub messenger_support_n: [f64; 2],
}

impl LateralGeometry {
    /// The curve's report for wires of tension `contact_n` and `messenger_n` (none on straight
    /// track).
    pub fn curve_report(&self, contact_n: f64, messenger_n: f64) -> Option<CurveReport> {
        if self.curvature_per_m == 0.0 {
            return None;
        }
        let r = 1.0 / self.curvature_per_m;
        let range = |t: f64| {
            let f = self.registration_forces_n(t);
            let lo = f.iter().copied().fold(f64::INFINITY, f64::min);
            let hi = f.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            if f.is_empty() {
                [0.0, 0.0]
            } else {
                [lo, hi]
            }
        };
        Some(CurveReport {
            track_radius_m: r,
            head_offset_m: self.head_offset_m,
            max_bow_mm: self.span_m * self.span_m / (8.0 * r.abs()) * 1e3,
            contact_wire_registration_n: range(contact_n),
            messenger_support_n: range(messenger_n),
        })
    }
}
