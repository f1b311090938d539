//! Validation of a case, in one place (issue 18): [`Case::validate`] runs the sections below in a
//! fixed order (the first error found is the one reported, as the hardening tests pin), each
//! against the one table of bounds (`input::bounds`). The case's types know nothing of it, so
//! validation imports them and nothing imports validation: no circle.

use crate::error::{CaseError, Warning};
use crate::input::bounds::{self, check_bound, inv, Bound};
use crate::input::case::*;
use crate::input::irregularity::IrregularityCase;
use crate::input::lateral::*;
use crate::input::line::{LineCase, TensionLengthCase, OVERRIDES};

mod catenary;
mod hard_spots;
mod irregularity;
mod lateral;
mod line;
mod pantographs;
mod run;

use catenary::*;
use hard_spots::*;
use irregularity::*;
use lateral::*;
use line::*;
use pantographs::*;
use run::*;

/// A positive finite number, or an error naming the field.
fn pos(field: &str, v: f64) -> Result<(), CaseError> {
    if v > 0.0 && v.is_finite() {
        Ok(())
    } else {
        Err(inv(field, v, "must be a finite number > 0"))
    }
}

impl Case {
    /// Check every value; return warnings, or an error naming the field and its value.
    ///
    /// Every number has plausibility bounds: outside the hard bounds it is physically
    /// meaningless (an error), outside the soft bounds merely unusual (a warning naming the
    /// field and the typical range). See [`bounds`].
    pub fn validate(&self) -> Result<Vec<Warning>, CaseError> {
        let mut w = Vec::new();
        finite_all(self)?;
        line(self, &mut w)?;
        geometry_and_wires(self, &mut w)?;
        droppers(self, &mut w)?;
        presag(self, &mut w)?;
        damping(self, &mut w)?;
        supports_and_arms(self, &mut w)?;
        stitch_wire(self, &mut w)?;
        contact_and_pantographs(self, &mut w)?;
        dropper_fatigue(self, &mut w)?;
        run(self, &mut w)?;
        lateral_dofs(self, &mut w)?;
        lateral_sections(self, &mut w)?;
        lateral_geometry(self, &mut w)?;
        ice(self, &mut w)?;
        wind(self, &mut w)?;
        pantograph_heads(self, &mut w)?;
        irregularity(self, &mut w)?;
        hard_spots(self, &mut w)?;
        Ok(w)
    }
}

/// Reject NaN and infinities anywhere in the case, naming the field.
fn finite_all(case: &Case) -> Result<(), CaseError> {
    let v = toml::Value::try_from(case).map_err(|e| CaseError::Parse(e.to_string()))?;
    fn walk(v: &toml::Value, path: &str) -> Result<(), CaseError> {
        match v {
            toml::Value::Float(f) if !f.is_finite() => Err(inv(path, f, "must be finite")),
            toml::Value::Table(t) => {
                for (k, x) in t {
                    let p = if path.is_empty() {
                        k.clone()
                    } else {
                        format!("{path}.{k}")
                    };
                    walk(x, &p)?;
                }
                Ok(())
            }
            toml::Value::Array(a) => {
                for (i, x) in a.iter().enumerate() {
                    walk(x, &format!("{path}[{i}]"))?;
                }
                Ok(())
            }
            _ => Ok(()),
        }
    }
    walk(&v, "")
}
