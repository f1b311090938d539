//! Stitch elements (paper §2.1: the stitch wire "simplified as two spring-damping elements
//! attached to the messenger wire"): a spring-damper between the messenger and a stitch node (the
//! stitch clamp and half the stitch wire, `Model::nodes`), from which a stitch dropper hangs.
//! Stiffness from `model::statics::stitch_stiffness`.

use super::{Attach, Io, PointElement, Slot, WindowMap};

/// One stitch element.
#[derive(Debug, Clone, PartialEq)]
pub struct Stitch {
    /// The messenger at the stitch dropper.
    pub wire: Attach,
    /// The stitch node.
    pub node: Attach,
    /// Stiffness of the stitch element, N/m.
    pub stiffness_n_per_m: f64,
    /// Damping of the stitch element, N·s/m.
    pub damping_ns_per_m: f64,
}

/// All stitch elements of a model.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct Stitches(pub Vec<Stitch>);

impl PointElement for Stitches {
    fn kind(&self) -> &'static str {
        "stitch"
    }
    fn len(&self) -> usize {
        self.0.len()
    }
    fn arity(&self) -> usize {
        2
    }
    fn attachment(&self, i: usize, a: usize) -> Attach {
        if a == 0 {
            self.0[i].wire
        } else {
            self.0[i].node
        }
    }
    fn needs_velocity(&self, i: usize, _a: usize) -> bool {
        self.0[i].damping_ns_per_m != 0.0
    }
    fn stiffness(&self, i: usize) -> f64 {
        self.0[i].stiffness_n_per_m
    }
    fn add_forces(&self, slots: &[Slot], io: &mut Io) {
        for (i, s) in self.0.iter().enumerate() {
            let (w, n) = (slots[2 * i], slots[2 * i + 1]);
            // Force on the node; the messenger takes the reaction.
            let f = -s.stiffness_n_per_m * (io.u[n.u as usize] - io.u[w.u as usize])
                - s.damping_ns_per_m * (io.v[n.v as usize] - io.v[w.v as usize]);
            io.f[n.u as usize] += f;
            io.f[w.u as usize] -= f;
        }
    }
    fn energy(&self, slots: &[Slot], io: &Io) -> f64 {
        let mut e = 0.0;
        for (i, s) in self.0.iter().enumerate() {
            let (w, n) = (slots[2 * i], slots[2 * i + 1]);
            e += 0.5 * s.stiffness_n_per_m * (io.u[n.u as usize] - io.u[w.u as usize]).powi(2);
        }
        e
    }
    fn dissipation(&self, slots: &[Slot], io: &Io) -> f64 {
        let mut d = 0.0;
        for (i, s) in self.0.iter().enumerate() {
            let (w, n) = (slots[2 * i], slots[2 * i + 1]);
            d += s.damping_ns_per_m * (io.v[n.v as usize] - io.v[w.v as usize]).powi(2);
        }
        d
    }
    fn restrict(&self, w: &WindowMap) -> Box<dyn PointElement> {
        Box::new(Stitches(
            self.0
                .iter()
                .filter_map(|s| {
                    Some(Stitch {
                        wire: w.map(s.wire)?,
                        node: w.map(s.node)?,
                        ..s.clone()
                    })
                })
                .collect(),
        ))
    }
    fn clone_box(&self) -> Box<dyn PointElement> {
        Box::new(self.clone())
    }
    fn as_any(&self) -> &dyn std::any::Any {
        self
    }
}
