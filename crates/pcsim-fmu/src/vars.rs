//! The FMU's variables and the generated `modelDescription.xml`.

use std::fmt::Write as _;

/// Variable types.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kind {
    Real,
    Boolean,
    String,
}

/// FMI causality.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Causality {
    Input,
    Output,
    Parameter,
}

/// One scalar variable.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Var {
    pub name: &'static str,
    pub vr: u32,
    pub kind: Kind,
    pub causality: Causality,
    pub unit: Option<&'static str>,
    /// Start value as written to the XML (inputs and parameters).
    pub start: Option<&'static str>,
    pub description: &'static str,
}

/// The independent variable of the FMI 3.0 description (time, s).
pub const VR_TIME: u32 = 0;
pub const VR_CONTACT_FORCE: u32 = 1;
pub const VR_PANTOGRAPH_POSITION: u32 = 2;
pub const VR_WIRE_HEIGHT: u32 = 3;
pub const VR_WIRE_VELOCITY: u32 = 4;
pub const VR_PANTOGRAPH_CONTACT_FORCE: u32 = 5;
pub const VR_WINDOW_LENGTH: u32 = 6;
pub const VR_STEP_SIZE: u32 = 7;
pub const VR_SIL: u32 = 8;
pub const VR_CASE: u32 = 9;
pub const VR_CONTACT_LATERAL: u32 = 10;
pub const VR_IRREGULARITY_FILE: u32 = 11;

/// Default start values.
pub const DEFAULT_CASE: &str = "syt-7.0-9.8";
/// The name of the case file `pcsim fmu build --case` puts in the FMU's `resources/` folder, and
/// then the `case` parameter's start value.
pub const BUNDLED_CASE: &str = "case.toml";
pub const DEFAULT_WINDOW_M: f64 = 215.0;
pub const DEFAULT_STEP_S: f64 = 0.001;
/// Largest number of internal steps one `fmi2DoStep` may take.
pub const MAX_INTERNAL_STEPS: u64 = 100_000;

/// The table of variables.
pub const VARS: &[Var] = &[
    Var {
        name: "contact_force",
        vr: VR_CONTACT_FORCE,
        kind: Kind::Real,
        causality: Causality::Input,
        unit: Some("N"),
        start: Some("0"),
        description: "HIL: measured contact force pushing the contact wire up (held over a communication step)",
    },
    Var {
        name: "position_from_start",
        vr: VR_PANTOGRAPH_POSITION,
        kind: Kind::Real,
        causality: Causality::Input,
        unit: Some("m"),
        start: Some("0"),
        description: "HIL: pantograph position along the track (0 = the case's start position)",
    },
    Var {
        name: "wire_height",
        vr: VR_WIRE_HEIGHT,
        kind: Kind::Real,
        causality: Causality::Output,
        unit: Some("m"),
        start: None,
        description: "contact-wire height at the contact point (static shape + deviation)",
    },
    Var {
        name: "wire_velocity",
        vr: VR_WIRE_VELOCITY,
        kind: Kind::Real,
        causality: Causality::Output,
        unit: Some("m/s"),
        start: None,
        description: "contact-wire vertical velocity at the contact point",
    },
    Var {
        name: "pantograph_contact_force",
        vr: VR_PANTOGRAPH_CONTACT_FORCE,
        kind: Kind::Real,
        causality: Causality::Output,
        unit: Some("N"),
        start: None,
        description: "contact force: computed by pcsim's pantograph (SIL) or the input echoed (HIL)",
    },
    Var {
        name: "contact_lateral",
        vr: VR_CONTACT_LATERAL,
        kind: Kind::Real,
        causality: Causality::Output,
        unit: Some("m"),
        start: None,
        description: "lateral position of the contact point from the track centre line (stagger + lateral deviation; 0 for a vertical-only case)",
    },
    Var {
        name: "window_length",
        vr: VR_WINDOW_LENGTH,
        kind: Kind::Real,
        causality: Causality::Parameter,
        unit: Some("m"),
        start: Some("215"),
        description: "length of the moving catenary window",
    },
    Var {
        name: "step_size",
        vr: VR_STEP_SIZE,
        kind: Kind::Real,
        causality: Causality::Parameter,
        unit: Some("s"),
        start: Some("0.001"),
        description: "internal fixed time step; communication steps must be whole multiples",
    },
    Var {
        name: "sil",
        vr: VR_SIL,
        kind: Kind::Boolean,
        causality: Causality::Parameter,
        unit: None,
        start: Some("false"),
        description: "true: pcsim's own pantograph in the loop (SIL), inputs ignored; false: HIL",
    },
    Var {
        name: "case",
        vr: VR_CASE,
        kind: Kind::String,
        causality: Causality::Parameter,
        unit: None,
        start: Some(DEFAULT_CASE),
        description: "pcsim preset name (see `pcsim presets`), or a case file (.toml): looked up in the FMU's resources first (`pcsim fmu build --case` bundles one as case.toml, then the start value), then as a path",
    },
    Var {
        name: "irregularity_file",
        vr: VR_IRREGULARITY_FILE,
        kind: Kind::String,
        causality: Causality::Parameter,
        unit: None,
        start: Some(""),
        description: "contact-wire irregularity profile: a CSV file of position_m,deviation_m rows after a header (empty: none)",
    },
];

/// Look a variable up by value reference and kind.
pub fn find(vr: u32, kind: Kind) -> Option<&'static Var> {
    VARS.iter().find(|v| v.vr == vr && v.kind == kind)
}

fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

/// `modelDescription.xml`, generated from [`VARS`].
pub fn model_description() -> String {
    model_description_for(DEFAULT_CASE)
}

/// A variable's start value, with `case` as the `case` parameter's.
fn start_of<'a>(v: &'a Var, case: &'a str) -> Option<&'a str> {
    if v.vr == VR_CASE && v.kind == Kind::String {
        Some(case)
    } else {
        v.start
    }
}

/// [`model_description`] with `case` as the `case` parameter's start value (an FMU built with
/// a bundled case: [`BUNDLED_CASE`]).
pub fn model_description_for(case: &str) -> String {
    let mut x = String::new();
    let _ = writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        x,
        r#"<fmiModelDescription fmiVersion="2.0" modelName="pcsim real-time catenary" guid="{}" description="Moving-window pantograph-catenary model (pcsim)" generationTool="pcsim {}" variableNamingConvention="flat" numberOfEventIndicators="0">"#,
        crate::GUID,
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(
        x,
        r#"  <CoSimulation modelIdentifier="{}" canHandleVariableCommunicationStepSize="true" canInterpolateInputs="false" canRunAsynchronuously="false" canBeInstantiatedOnlyOncePerProcess="false" canNotUseMemoryManagementFunctions="true" canGetAndSetFMUstate="true" canSerializeFMUstate="true" providesDirectionalDerivative="false"/>"#,
        crate::MODEL_IDENTIFIER
    );
    x.push_str("  <UnitDefinitions>\n");
    x.push_str("    <Unit name=\"N\"><BaseUnit kg=\"1\" m=\"1\" s=\"-2\"/></Unit>\n");
    x.push_str("    <Unit name=\"m\"><BaseUnit m=\"1\"/></Unit>\n");
    x.push_str("    <Unit name=\"m/s\"><BaseUnit m=\"1\" s=\"-1\"/></Unit>\n");
    x.push_str("    <Unit name=\"s\"><BaseUnit s=\"1\"/></Unit>\n");
    x.push_str("  </UnitDefinitions>\n");
    let _ = writeln!(
        x,
        r#"  <DefaultExperiment startTime="0" stopTime="10" stepSize="{DEFAULT_STEP_S}"/>"#
    );
    x.push_str("  <ModelVariables>\n");
    for v in VARS {
        let (causality, variability, initial) = match v.causality {
            Causality::Input => ("input", "continuous", None),
            Causality::Output => ("output", "continuous", Some("calculated")),
            Causality::Parameter => ("parameter", "fixed", Some("exact")),
        };
        let _ = write!(
            x,
            r#"    <ScalarVariable name="{}" valueReference="{}" description="{}" causality="{causality}" variability="{variability}""#,
            v.name,
            v.vr,
            esc(v.description)
        );
        if let Some(i) = initial {
            let _ = write!(x, r#" initial="{i}""#);
        }
        x.push('>');
        let tag = match v.kind {
            Kind::Real => "Real",
            Kind::Boolean => "Boolean",
            Kind::String => "String",
        };
        let _ = write!(x, "<{tag}");
        if let Some(u) = v.unit {
            let _ = write!(x, r#" unit="{u}""#);
        }
        if let Some(s) = start_of(v, case) {
            let _ = write!(x, r#" start="{}""#, esc(s));
        }
        x.push_str("/></ScalarVariable>\n");
    }
    x.push_str("  </ModelVariables>\n  <ModelStructure>\n    <Outputs>\n");
    // Indices are 1-based positions in ModelVariables.
    for (i, v) in VARS.iter().enumerate() {
        if v.causality == Causality::Output {
            let _ = writeln!(x, r#"      <Unknown index="{}" dependencies=""/>"#, i + 1);
        }
    }
    x.push_str("    </Outputs>\n    <InitialUnknowns>\n");
    for (i, v) in VARS.iter().enumerate() {
        if v.causality == Causality::Output {
            let _ = writeln!(x, r#"      <Unknown index="{}" dependencies=""/>"#, i + 1);
        }
    }
    x.push_str("    </InitialUnknowns>\n  </ModelStructure>\n</fmiModelDescription>\n");
    x
}

/// The FMI 3.0 `modelDescription.xml`, generated from the same [`VARS`].
pub fn model_description_v3() -> String {
    model_description_v3_for(DEFAULT_CASE)
}

/// [`model_description_v3`] with `case` as the `case` parameter's start value.
pub fn model_description_v3_for(case: &str) -> String {
    let mut x = String::new();
    let _ = writeln!(x, r#"<?xml version="1.0" encoding="UTF-8"?>"#);
    let _ = writeln!(
        x,
        r#"<fmiModelDescription fmiVersion="3.0" modelName="pcsim real-time catenary" instantiationToken="{}" description="Moving-window pantograph-catenary model (pcsim)" generationTool="pcsim {}" variableNamingConvention="flat">"#,
        crate::GUID,
        env!("CARGO_PKG_VERSION")
    );
    let _ = writeln!(
        x,
        r#"  <CoSimulation modelIdentifier="{}" canHandleVariableCommunicationStepSize="true" canGetAndSetFMUState="true" canSerializeFMUState="true" canBeInstantiatedOnlyOncePerProcess="false" providesDirectionalDerivatives="false" providesAdjointDerivatives="false" hasEventMode="false" canReturnEarlyAfterIntermediateUpdate="false" providesIntermediateUpdate="false"/>"#,
        crate::MODEL_IDENTIFIER
    );
    x.push_str("  <UnitDefinitions>\n");
    x.push_str("    <Unit name=\"N\"><BaseUnit kg=\"1\" m=\"1\" s=\"-2\"/></Unit>\n");
    x.push_str("    <Unit name=\"m\"><BaseUnit m=\"1\"/></Unit>\n");
    x.push_str("    <Unit name=\"m/s\"><BaseUnit m=\"1\" s=\"-1\"/></Unit>\n");
    x.push_str("    <Unit name=\"s\"><BaseUnit s=\"1\"/></Unit>\n");
    x.push_str("  </UnitDefinitions>\n");
    let _ = writeln!(
        x,
        r#"  <DefaultExperiment startTime="0" stopTime="10" stepSize="{DEFAULT_STEP_S}"/>"#
    );
    x.push_str("  <ModelVariables>\n");
    let _ = writeln!(
        x,
        r#"    <Float64 name="time" valueReference="{VR_TIME}" description="simulation time" causality="independent" variability="continuous" unit="s"/>"#
    );
    for v in VARS {
        let (causality, variability, initial) = match v.causality {
            Causality::Input => ("input", "continuous", None),
            Causality::Output => ("output", "continuous", Some("calculated")),
            Causality::Parameter => ("parameter", "fixed", Some("exact")),
        };
        let (tag, variability) = match v.kind {
            Kind::Real => ("Float64", variability),
            Kind::Boolean => ("Boolean", "fixed"),
            Kind::String => ("String", "fixed"),
        };
        let _ = write!(
            x,
            r#"    <{tag} name="{}" valueReference="{}" description="{}" causality="{causality}" variability="{variability}""#,
            v.name,
            v.vr,
            esc(v.description)
        );
        if let Some(i) = initial {
            let _ = write!(x, r#" initial="{i}""#);
        }
        if let Some(u) = v.unit {
            let _ = write!(x, r#" unit="{u}""#);
        }
        match (v.kind, start_of(v, case)) {
            (Kind::String, Some(s)) => {
                let _ = writeln!(x, r#"><Start value="{}"/></String>"#, esc(s));
            }
            (_, Some(s)) => {
                let _ = writeln!(x, r#" start="{}"/>"#, esc(s));
            }
            (_, None) => x.push_str("/>\n"),
        }
    }
    x.push_str("  </ModelVariables>\n  <ModelStructure>\n");
    for v in VARS.iter().filter(|v| v.causality == Causality::Output) {
        let _ = writeln!(x, r#"    <Output valueReference="{}"/>"#, v.vr);
    }
    for v in VARS.iter().filter(|v| v.causality == Causality::Output) {
        let _ = writeln!(x, r#"    <InitialUnknown valueReference="{}"/>"#, v.vr);
    }
    x.push_str("  </ModelStructure>\n</fmiModelDescription>\n");
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn value_references_are_unique_and_the_xml_lists_every_variable() {
        let xml = model_description();
        for (i, v) in VARS.iter().enumerate() {
            assert!(
                VARS.iter()
                    .skip(i + 1)
                    .all(|w| w.vr != v.vr || w.kind != v.kind),
                "duplicate vr {}",
                v.vr
            );
            assert!(
                xml.contains(&format!(r#"name="{}" valueReference="{}""#, v.name, v.vr)),
                "{}",
                v.name
            );
        }
        assert_eq!(xml.matches("<ScalarVariable ").count(), VARS.len());
        assert!(xml.contains(crate::GUID) && xml.contains(r#"modelIdentifier="pcsim_fmu""#));
        let x3 = model_description_v3();
        for v in VARS {
            assert!(
                x3.contains(&format!(r#"name="{}" valueReference="{}""#, v.name, v.vr)),
                "FMI 3.0: {}",
                v.name
            );
        }
        // Value references are unique across all variables in FMI 3.0.
        for (i, v) in VARS.iter().enumerate() {
            assert!(VARS.iter().skip(i + 1).all(|w| w.vr != v.vr), "vr {}", v.vr);
        }
        assert!(
            x3.contains(r#"instantiationToken=""#) && x3.contains("canSerializeFMUState=\"true\"")
        );
    }
}
