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
}

impl LateralGeometry {
    /// Static lateral position of the wires at track position `x`, m: the straight line between
    /// the staggers of the neighbouring supports.
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
        self.stagger_m[i] + t * (self.stagger_m[i + 1] - self.stagger_m[i])
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
