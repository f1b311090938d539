//! The plan of a run (speed, start, duration, analysis section) and the method's options (the
//! time step). Both are separate from the model, which is the problem only.

use crate::error::CaseError;
use crate::error::Warning;
use crate::model::Model;
use crate::solve::kernels::Isa;

/// Where and how fast the pantographs run, and where the statistics are taken.
#[derive(Debug, Clone, PartialEq)]
pub struct Plan {
    /// Train speed, km/h (the unit of the aerodynamic law).
    pub speed_kmh: f64,
    /// Train speed, m/s.
    pub speed_m_s: f64,
    /// Position of the leading pantograph at t = 0 (model coordinates), m.
    pub start_m: f64,
    /// Simulated duration, s.
    pub duration_s: f64,
    /// Statistics are taken while a pantograph is inside this section (track coordinates), m.
    pub analysis_m: [f64; 2],
}

/// Options of the integrator.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Options {
    /// Fixed time step, s.
    pub dt_s: f64,
    /// Instruction set of the hot loops (default: the best of this CPU, unless
    /// `PCSIM_PORTABLE=1`; see `solve::kernels`).
    pub isa: Isa,
    /// Threads one run may use (`solve::team`): the step's per-group work is split into at
    /// most this many parts, cut between basis groups; a model of one group runs on one.
    /// The output bytes do not depend on it. Default 1.
    pub threads: usize,
}

impl Options {
    /// Options with time step `dt_s` and the default instruction set.
    pub fn new(dt_s: f64) -> Self {
        Options {
            dt_s,
            isa: Isa::default(),
            threads: 1,
        }
    }
}

impl Plan {
    /// Every pantograph with a head's width must find a contact wire on its head where it runs:
    /// the wires' static lateral positions (the stagger, a curve's bow) at every metre of its
    /// path, from the head's centre (which a canted curve moves), within its half-width for at
    /// least one contact wire present there. A design that puts the wire beyond the head (a
    /// tight curve's bow with the stagger on its outside) is refused before any run, naming
    /// the place, the distance and the head: the run could only dewire or blow up.
    fn check_wire_on_heads(&self, model: &Model) -> Result<(), CaseError> {
        use crate::model::dof::Direction;
        use crate::model::elements::contact::Contacts;
        let (Some(lat), Some(contacts)) = (&model.lateral, model.element::<Contacts>()) else {
            return Ok(());
        };
        let travel = self.speed_m_s * self.duration_s;
        for (p, pan) in model.pantographs.iter().enumerate() {
            let Some(hw) = pan.head_half_width_m else {
                continue;
            };
            let wires: Vec<usize> = (contacts.0.iter())
                .filter(|c| c.pantograph == p && c.dir == Direction::Vertical)
                .map(|c| c.wire)
                .collect();
            let from = self.start_m - pan.offset_m;
            let steps = (travel.max(0.0).ceil() as usize).min(1_000_000);
            for k in 0..=steps {
                let x = from + k as f64;
                let mut nearest: Option<f64> = None;
                for &w in &wires {
                    let wire = &model.wires[w];
                    let (a, b) = (wire.origin_m, wire.origin_m + wire.basis.length_m());
                    if x <= a || x >= b {
                        continue;
                    }
                    let on_head =
                        model.static_height(w, Direction::Lateral, x, 0.0) - lat.head_offset_at(x);
                    if nearest.is_none_or(|n| on_head.abs() < n.abs()) {
                        nearest = Some(on_head);
                    }
                }
                if let Some(z) = nearest.filter(|z| z.abs() > hw) {
                    return Err(CaseError::Model {
                        what: crate::error::ModelQuantity::StaticLateralPosition,
                        value: format!("{z:.3} m from the head's centre at x = {x:.1} m"),
                        reason: format!(
                            "pantograph {}'s head reaches {hw} m either side: there the contact wire, at rest, is off its head (the stagger and the curve's bow put it there), so the run could only dewire; lay the stagger inside the head, or a larger radius",
                            pan.name
                        ),
                    });
                }
            }
        }
        Ok(())
    }

    /// Number of fixed steps of length `dt` that cover the duration.
    pub fn n_steps(&self, dt: f64) -> usize {
        (self.duration_s / dt).ceil() as usize
    }

    /// Check the speed against every contact wire's wave speed
    /// ([`crate::model::Wire::wave_speed`], the one definition; on a line, each tension
    /// length's): an error at or above the slowest, a warning above 0.7 of it. Both name the
    /// wire that decides.
    pub fn check(&self, model: &Model) -> Result<Vec<Warning>, CaseError> {
        self.check_wire_on_heads(model)?;
        let mut w = Vec::new();
        let Some((cw, wave)) = model.slowest_contact_wire() else {
            return Ok(w);
        };
        let which = if model.contact_wave_speeds().len() > 1 {
            format!(
                " of {} (the slowest of the line's {} contact wires)",
                model.wires[cw].name,
                model.contact_wave_speeds().len()
            )
        } else {
            String::new()
        };
        let v = self.speed_m_s;
        if v >= wave {
            return Err(CaseError::Model {
                what: crate::error::ModelQuantity::Speed,
                value: self.speed_kmh.to_string(),
                reason: format!(
                    "at or above the contact-wire wave speed √(T/ρA) = {:.1} km/h{which}",
                    wave * 3.6
                ),
            });
        }
        if v / wave > 0.7 {
            w.push(Warning(format!(
                "speed ratio v/c = {:.3} is above 0.7 (c = {:.1} km/h{which}, clamps and droppers included in ρA): expect strong wave effects",
                v / wave,
                wave * 3.6
            )));
        }
        Ok(w)
    }
}
