//! Presets: TOML cases embedded in the binary, every field with its source or a `guess` mark.

use crate::error::CaseError;
use crate::input::case::{Case, PantographCase, Provenance};

/// A named embedded case.
#[derive(Debug, Clone, Copy)]
pub struct Preset {
    /// Name (`--preset NAME`).
    pub name: &'static str,
    /// One line on what it is.
    pub summary: &'static str,
    /// The case file's text, every field with its source.
    pub toml: &'static str,
}

/// All presets.
pub const PRESETS: &[Preset] = &[
    Preset {
        name: "en50318-2002",
        summary: "simple catenary, 60 m spans, EN 50318:2002 reference pantograph (public candidate data, README §3.1)",
        toml: include_str!("../../../../presets/en50318-2002.toml"),
    },
    Preset {
        name: "benchmark-55m",
        summary: "simple catenary, 55 m spans, 3-mass pantograph (probably the 2015 benchmark, README §3.2)",
        toml: include_str!("../../../../presets/benchmark-55m.toml"),
    },
    Preset {
        name: "benchmark-55m-two-strips",
        summary: "benchmark-55m with the head as two collector strips 0.5 m apart and a height-dependent static force (guesses on the published head)",
        toml: include_str!("../../../../presets/benchmark-55m-two-strips.toml"),
    },
    Preset {
        name: "stitched-2018-like",
        summary: "stitched catenary, 30 x 60 m, two pantographs 200 m apart (the paper's Table 1 set-up from public data; not EN 50318:2018)",
        toml: include_str!("../../../../presets/stitched-2018-like.toml"),
    },
    Preset {
        name: "neutral-section-2018-like",
        summary: "stitched-2018-like with a short neutral section: two section insulators 6 m apart at 915-921 m (issue 55; the insulators' data guesses)",
        toml: include_str!("../../../../presets/neutral-section-2018-like.toml"),
    },
    Preset {
        name: "syt-7.0-9.8",
        summary: "Swedish stitched SYT 7.0/9.8 (reconstructed; the paper's EVA case), DSA380-type pantograph, 222 km/h",
        toml: include_str!("../../../../presets/syt-7.0-9.8.toml"),
    },
    Preset {
        name: "stitched-2018-like-3d",
        summary: "stitched-2018-like with lateral and torsional motion, ±0.3 m stagger, lateral registration, 1600 mm heads (issue 12)",
        toml: include_str!("../../../../presets/stitched-2018-like-3d.toml"),
    },
    Preset {
        name: "stitched-2018-like-3d-crosswind",
        summary: "stitched-2018-like-3d in a 25 m/s crosswind at 10 % turbulence (Kaimal, Davenport coherence, seeded)",
        toml: include_str!("../../../../presets/stitched-2018-like-3d-crosswind.toml"),
    },
    Preset {
        name: "stitched-2018-like-3d-curve",
        summary: "stitched-2018-like-3d on a 4000 m curve with 150 mm cant: the wires' bow, the pull-off forces, the head moved by the cant (issue 41; the curve's data guesses from public design rules)",
        toml: include_str!("../../../../presets/stitched-2018-like-3d-curve.toml"),
    },
    Preset {
        name: "line-structure-2002",
        summary: "a [line]: en50318-2002's catenary over 15 spans of 40-60 m, the contact wire 0.2 m lower under a structure (issue 21)",
        toml: include_str!("../../../../presets/line-structure-2002.toml"),
    },
    Preset {
        name: "en50318-2018-like-simple",
        summary: "the EN 50318:2018 structure, simple: three tension lengths, two 3-span overlaps, 31 x 60 m, two pantographs (public data, not the standard's; issue 21)",
        toml: include_str!("../../../../presets/en50318-2018-like-simple.toml"),
    },
    Preset {
        name: "en50318-2018-like-stitched",
        summary: "the EN 50318:2018 structure, stitched: three tension lengths, two 3-span overlaps, 31 x 60 m, two pantographs (public data, not the standard's; issue 21)",
        toml: include_str!("../../../../presets/en50318-2018-like-stitched.toml"),
    },
    Preset {
        name: "en50318-2018-like-stitched-3d",
        summary: "en50318-2018-like-stitched in 3D: lateral and torsional motion, ±0.3 m stagger along the line, the overlaps' wires side by side and crossing in plan, 1600 mm heads (issue 41)",
        toml: include_str!("../../../../presets/en50318-2018-like-stitched-3d.toml"),
    },
    Preset {
        name: "line-10km-2002",
        summary: "a 10.4 km line for scale: 10 tension lengths of 20 x 60 m, 3-span overlaps, en50318-2002's catenary and pantograph (issue 21)",
        toml: include_str!("../../../../presets/line-10km-2002.toml"),
    },
];

/// Find a preset by name.
pub fn find(name: &str) -> Result<&'static Preset, CaseError> {
    PRESETS
        .iter()
        .find(|p| p.name == name)
        .ok_or_else(|| CaseError::UnknownPreset(name.to_string()))
}

/// Parse a preset into a case.
pub fn load(name: &str) -> Result<(Case, Provenance), CaseError> {
    Case::from_toml_str(find(name)?.toml)
}

/// The benchmark case (`pcsim bench --preset en50318-2002`, `examples/length_cost.rs`): the
/// `en50318-2002` catenary over `spans` spans of 60 m with `modes` modes per wire, a second
/// pantograph 200 m behind the first, at `speed_kmh`, from 260 m to 240 m before the end.
pub fn benchmark_case(speed_kmh: f64, modes: usize, spans: usize) -> Result<Case, CaseError> {
    let mut c = load("en50318-2002")?.0;
    c.catenary.spans = spans;
    let l = spans as f64 * c.catenary.span_m;
    c.run.modes = Some(modes);
    c.run.modes_per_m = None;
    c.run.speed_kmh = speed_kmh;
    let mut trailing = c.pantographs[0].clone();
    if let PantographCase::Lumped { name, offset_m, .. } = &mut trailing {
        *name = "trailing".into();
        *offset_m = 200.0;
    }
    c.pantographs.push(trailing);
    c.run.start_m = 260.0;
    c.run.end_m = l - 240.0;
    c.run.analysis_m = [480.0, l - 300.0];
    Ok(c)
}
