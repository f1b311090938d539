//! A window of a model: the real-time catenary's own model (paper §4.2, after Facchinetti &
//! Bruni 2012).

use crate::model::basis::SineBasis;
use crate::model::elements::contact::{ContactLaw, Contacts};
use crate::model::elements::{PointElement, WindowMap};
use crate::model::pantograph::{Pantograph, PantographKind};
use crate::model::{Model, Node, StaticShape};

impl Model {
    /// A window `[origin, origin + length]` of this (full) model, with its own sine basis of
    /// `n_modes` modes and the point elements and nodes that fall strictly inside it, in window
    /// coordinates (x − origin). Every wire keeps its section, damping law and directions. For a
    /// span-periodic catenary `origin` should be a whole number of spans, so that the static
    /// shape reads the same in window coordinates.
    ///
    /// On a line (tension lengths that end, `StaticShape::Line`) each wire's part inside the
    /// window is a wire of its own, on a sine basis over that part with the window's mode
    /// density (rounded down, so no mode is faster than the full model's fastest); a wire of
    /// which less than one mode's length lies inside is left out, with its elements and
    /// contacts. The static shape is the line's, read at the window's origin.
    ///
    /// With `external`, the pantographs become [`PantographKind::External`] (hardware in the
    /// loop); otherwise they are kept (software in the loop).
    pub fn window(&self, origin_m: f64, length_m: f64, n_modes: usize, external: bool) -> Model {
        let basis = SineBasis::new(length_m, n_modes);
        let end_m = origin_m + length_m;
        let mut wires = Vec::new();
        let mut wire_map = Vec::with_capacity(self.wires.len());
        let mut full_wire = Vec::new();
        for (i, wire) in self.wires.iter().enumerate() {
            let StaticShape::Line(_) = self.statics else {
                wire_map.push(Some(wires.len()));
                wires.push(wire.rebased(0.0, basis.clone()));
                continue;
            };
            let a = wire.origin_m.max(origin_m);
            let b = (wire.origin_m + wire.basis.length_m()).min(end_m);
            let n = (n_modes as f64 * (b - a) / length_m + 1e-9).floor();
            if n < 1.0 {
                wire_map.push(None);
                continue;
            }
            wire_map.push(Some(wires.len()));
            full_wire.push(i);
            wires.push(wire.rebased(a - origin_m, SineBasis::new(b - a, n as usize)));
        }
        let mut w = WindowMap {
            origin_m,
            length_m,
            node_map: Vec::with_capacity(self.nodes.len()),
            wire_map,
        };
        let mut nodes = Vec::new();
        for n in &self.nodes {
            if w.inside(n.x_m) {
                w.node_map.push(Some(nodes.len()));
                nodes.push(Node {
                    x_m: n.x_m - origin_m,
                    ..n.clone()
                });
            } else {
                w.node_map.push(None);
            }
        }
        let elements: Vec<Box<dyn PointElement>> =
            self.elements.iter().map(|e| e.restrict(&w)).collect();
        let statics = match &self.statics {
            StaticShape::Line(l) => StaticShape::Line(Box::new(l.window(origin_m, full_wire))),
            other => other.clone(),
        };
        let mut m = Model::new(
            wires,
            nodes,
            elements,
            self.pantographs.clone(),
            statics,
            // The point sampler uses the periodic path only when the window is whole spans.
            self.span_m,
        );
        let inside = |x: f64| x >= origin_m - 1e-9 && x <= end_m + 1e-9;
        m.supports_m = (self.supports_m.iter().copied())
            .filter(|&x| inside(x))
            .map(|x| x - origin_m)
            .collect();
        m.overlaps_m = (self.overlaps_m.iter())
            .filter(|o| inside(o[0]) || inside(o[1]))
            .map(|o| [o[0] - origin_m, o[1] - origin_m])
            .collect();
        // Stagger and irregularity stay in track coordinates (`Model::static_height` adds the
        // state's origin); the lateral probes move to the window's coordinates.
        m.track_origin_m = self.track_origin_m + origin_m;
        m.lateral = (self.lateral.as_ref()).map(|l| l.window(origin_m, length_m, &w.wire_map));
        m.wind = self.wind.as_ref().map(|w| w.window(origin_m, length_m));
        m.irregularity = self.irregularity.clone();
        if external {
            m.with_external_pantographs()
        } else {
            m
        }
    }

    /// The same model with every pantograph replaced by an external load (position and force
    /// given at every step: hardware in the loop). The rig is the pantograph: its force is the
    /// head's total at its position, so a head of collector strips keeps one contact per wire
    /// (its first strip's, moved to the pantograph's position).
    pub fn with_external_pantographs(mut self) -> Model {
        for p in &mut self.pantographs {
            *p = Pantograph {
                name: p.name.clone(),
                offset_m: 0.0,
                kind: PantographKind::External,
                head_half_width_m: p.head_half_width_m,
                working_half_width_m: p.working_half_width_m,
            };
        }
        let np = self.pantographs.len();
        for e in &mut self.elements {
            if let Some(c) = e.as_any().downcast_ref::<Contacts>() {
                let mut c = c.clone();
                c.0.retain(|k| k.head == 0);
                for k in &mut c.0 {
                    k.law = ContactLaw::prescribed(k.dir, k.pantograph, np);
                    k.along_m = 0.0;
                }
                *e = Box::new(c);
            }
        }
        self
    }
}
