//! Tiny cases of every geometry family (issue 41's matrix, widened in issue 51): the catenary
//! and the line, each vertical, in 3D, in a crosswind, on a curve, under ice, with
//! irregularity, with two pantographs and with a head of collector strips. Every capability and
//! every front end is checked on each (`docs/matrix.md`); a cell runs or is refused by name.
//! Shared by the core's tests, the front ends' tests and the Python package's, so each front
//! end meets the same cases.

use crate::input::case::{
    Case, IrregularityCase, LineCase, OverlapCase, SpanRun, TensionLengthCase,
};
use crate::input::hard_spots::{NeutralSectionCase, SectionInsulatorCase};
use crate::input::lateral::IceCase;
use crate::input::presets;

/// The `en50318-2002` preset cut to `spans` spans with the pantograph run over the middle.
pub fn short_en50318(spans: usize, speed_kmh: f64) -> Case {
    let (mut c, _) = presets::load("en50318-2002").expect("embedded");
    c.catenary.spans = spans;
    let l = c.length_m();
    c.run.speed_kmh = speed_kmh;
    c.run.start_m = c.catenary.span_m;
    c.run.end_m = l - c.catenary.span_m;
    c.run.analysis_m = [2.0 * c.catenary.span_m, l - 2.0 * c.catenary.span_m];
    c
}

/// A preset cut to `spans` spans, leading pantograph only, run over the middle, one mode per
/// metre.
pub fn short_preset(name: &str, spans: usize, speed_kmh: f64) -> Case {
    let (mut c, _) = presets::load(name).expect("embedded");
    c.catenary.spans = spans;
    c.pantographs.truncate(1);
    let l = c.length_m();
    c.run.speed_kmh = speed_kmh;
    c.run.start_m = c.catenary.span_m;
    c.run.end_m = l - c.catenary.span_m;
    c.run.analysis_m = [2.0 * c.catenary.span_m, l - 2.0 * c.catenary.span_m];
    c.run.modes = None;
    c.run.modes_per_m = Some(1.0);
    c
}

/// Two tension lengths of six 60 m spans with a 3-span overlap (180–360 m), the 2002 catenary,
/// 250 km/h over 60–480 m.
pub fn overlap_line() -> Case {
    let mut case = short_en50318(9, 250.0);
    let t = TensionLengthCase {
        span_runs: vec![SpanRun {
            count: 6,
            length_m: 60.0,
            track_radius_m: None,
            cant_m: None,
        }],
        spans_m: Vec::new(),
        droppers_m: Vec::new(),
        contact_height_m: Vec::new(),
        encumbrance_m: Vec::new(),
        stagger_m: Vec::new(),
        contact_wire: None,
        messenger: None,
        droppers: None,
        messenger_support: None,
        steady_arm: None,
    };
    case.line = Some(LineCase {
        tension_lengths: vec![t.clone(), t],
        overlaps: vec![OverlapCase {
            spans: 3,
            rise_m: 0.3,
            separation_m: 0.2,
        }],
    });
    case.catenary.spans = 9;
    case.run.start_m = 60.0;
    case.run.end_m = 480.0;
    case.run.analysis_m = [120.0, 420.0];
    case
}

/// The 3D preset's wire sections, lateral registration and directions on `c`.
fn sections_and_lateral(mut c: Case) -> Case {
    let d = presets::load("stitched-2018-like-3d").expect("embedded").0;
    c.catenary.messenger.section = d.catenary.messenger.section.clone();
    c.catenary.contact_wire.section = d.catenary.contact_wire.section.clone();
    c.catenary.lateral = d.catenary.lateral.clone();
    c.run.dofs = d.run.dofs.clone();
    c
}

/// The 3D preset's wire sections (the ice's annulus needs a diameter).
fn sections(mut c: Case) -> Case {
    let d = presets::load("stitched-2018-like-3d").expect("embedded").0;
    c.catenary.messenger.section = d.catenary.messenger.section;
    c.catenary.contact_wire.section = d.catenary.contact_wire.section;
    c
}

/// 5 mm of radial ice on both wires.
fn iced(mut c: Case) -> Case {
    c.catenary.ice = Some(IceCase {
        density_kg_m3: 900.0,
        contact_wire_m: 0.005,
        messenger_m: 0.005,
    });
    c
}

/// 2 mm RMS of contact-wire irregularity (a power-law spectrum, seeded).
fn rough(mut c: Case) -> Case {
    c.irregularity = vec![IrregularityCase::Psd {
        rms_m: 0.002,
        min_wavelength_m: 2.0,
        max_wavelength_m: 60.0,
        exponent: 2.0,
        table: None,
        seed: 7,
    }];
    c
}

/// A section insulator as the zoo and the example case take it (issue 55; every value a guess
/// from makers' data sheets of high-speed section insulators, docs/hard-spots.md): 2 m long,
/// 12 kg, 2·10⁴ N·m², runners with a 0.3 m lead-on and 10 mm of pre-lift.
pub fn section_insulator(position_m: f64) -> SectionInsulatorCase {
    SectionInsulatorCase {
        position_m,
        length_m: 2.0,
        mass_kg: 12.0,
        ei_nm2: 2.0e4,
        ramp_m: 0.3,
        prelift_m: 0.01,
    }
}

/// A neutral section of `dead_m` starting at `start_m`: a section insulator at each end of the
/// dead length.
pub fn neutral_section(mut c: Case, start_m: f64, dead_m: f64) -> Case {
    c.section_insulator = vec![
        section_insulator(start_m),
        section_insulator(start_m + dead_m),
    ];
    c.neutral_section = vec![NeutralSectionCase {
        start_m,
        end_m: start_m + dead_m,
    }];
    c
}

/// The crosswind preset's wind, with its wires' coefficients (sections with `aero`).
fn windy(mut c: Case) -> Case {
    let w = presets::load("stitched-2018-like-3d-crosswind")
        .expect("embedded")
        .0;
    c.wind = w.wind;
    c.catenary.messenger.section = w.catenary.messenger.section;
    c.catenary.contact_wire.section = w.catenary.contact_wire.section;
    c
}

/// A 2 000 m curve under every span of the line.
fn curved_line(mut c: Case) -> Case {
    for t in &mut c.line.as_mut().expect("a line").tension_lengths {
        for r in &mut t.span_runs {
            r.track_radius_m = Some(2000.0);
        }
    }
    c
}

/// A second pantograph 60 m behind the first (the case's own pantograph again), the run started
/// a span later and ended a span sooner so that both stay on the model and cross the analysis
/// section.
fn two_pantographs(mut c: Case) -> Case {
    let mut trailing = c.pantographs[0].clone();
    if let crate::input::case::PantographCase::Lumped { name, offset_m, .. } = &mut trailing {
        *name = "trailing".into();
        *offset_m = 60.0;
    }
    c.pantographs.truncate(1);
    c.pantographs.push(trailing);
    c.run.start_m += 60.0;
    c.run.end_m -= 60.0;
    c.run.analysis_m = [c.run.analysis_m[0] + 60.0, c.run.end_m];
    c
}

/// The leading pantograph replaced by benchmark-55m-two-strips' head of two collector strips.
fn strips(mut c: Case) -> Case {
    let p = presets::load("benchmark-55m-two-strips")
        .expect("embedded")
        .0
        .pantographs
        .remove(0);
    c.pantographs[0] = p;
    c
}

/// Every geometry family, by name, with its tiny case (8 spans of a catenary, or two tension
/// lengths of six spans with a 3-span overlap; 250 km/h).
pub fn geometries() -> Vec<(&'static str, Case)> {
    let cat = || short_en50318(8, 250.0);
    let cat3d = || short_preset("stitched-2018-like-3d", 8, 250.0);
    let line = overlap_line;
    let line3d = || sections_and_lateral(line());
    vec![
        ("catenary", cat()),
        ("catenary, two pantographs", two_pantographs(cat())),
        ("catenary, collector strips", strips(cat())),
        ("catenary, 3D", cat3d()),
        (
            "catenary, 3D, crosswind",
            short_preset("stitched-2018-like-3d-crosswind", 8, 250.0),
        ),
        (
            "catenary, 3D, curve",
            short_preset("stitched-2018-like-3d-curve", 8, 250.0),
        ),
        ("catenary, ice", iced(sections(cat()))),
        ("catenary, irregularity", rough(cat())),
        (
            "catenary, neutral section",
            neutral_section(cat(), 190.0, 25.0),
        ),
        ("line", line()),
        ("line, two pantographs", two_pantographs(line())),
        ("line, collector strips", strips(line())),
        ("line, 3D", line3d()),
        ("line, 3D, crosswind", windy(line3d())),
        ("line, 3D, curve", curved_line(line3d())),
        ("line, ice", iced(sections(line()))),
        ("line, irregularity", rough(line())),
        (
            "line, 3D, neutral section",
            neutral_section(line3d(), 395.0, 30.0),
        ),
        (
            "line, 3D, crosswind, ice, irregularity",
            rough(iced(windy(line3d()))),
        ),
        (
            "line, 3D, curve, ice, irregularity",
            rough(iced(curved_line(line3d()))),
        ),
        (
            "line, 3D, crosswind, curve, ice, irregularity",
            rough(iced(curved_line(windy(line3d())))),
        ),
    ]
}

/// The block `name` of a matrix document (between `<!-- matrix: NAME -->` and
/// `<!-- end: NAME -->`), each front end's table written by its own test.
pub fn matrix_block<'a>(doc: &'a str, name: &str) -> Option<&'a str> {
    let open = format!("<!-- matrix: {name} -->\n");
    let close = format!("<!-- end: {name} -->");
    let a = doc.find(&open)? + open.len();
    let b = a + doc[a..].find(&close)?;
    Some(&doc[a..b])
}

/// `doc` with block `name` set to `text` (appended with its markers when absent).
pub fn with_matrix_block(doc: &str, name: &str, text: &str) -> String {
    let open = format!("<!-- matrix: {name} -->\n");
    let close = format!("<!-- end: {name} -->");
    match (doc.find(&open), doc.find(&close)) {
        (Some(a), Some(b)) if b > a => {
            format!("{}{open}{text}{}", &doc[..a], &doc[b..])
        }
        _ => format!("{doc}\n{open}{text}{close}\n"),
    }
}

/// The field a refusal's message names (`invalid value for \`FIELD\` = …`), for a front end's
/// cell that sees the message only.
pub fn refused_field(message: &str) -> Option<String> {
    let rest = &message[message.find("invalid value for `")? + "invalid value for `".len()..];
    Some(rest[..rest.find('`')?].to_string())
}

/// One front end's table of the matrix: per geometry, each column's cell (`Ok(())` runs,
/// `Err(field)` refused naming it), as Markdown.
pub fn render_front_end(
    title: &str,
    columns: &[&str],
    rows: &[(&str, Vec<Result<(), String>>)],
) -> String {
    let mut s = format!("### {title}\n\n| geometry |");
    for c in columns {
        s.push_str(&format!(" {c} |"));
    }
    s.push_str("\n|---|");
    for _ in columns {
        s.push_str("---|");
    }
    s.push('\n');
    for (g, cells) in rows {
        s.push_str(&format!("| {g} |"));
        for c in cells {
            match c {
                Ok(()) => s.push_str(" runs |"),
                Err(f) => s.push_str(&format!(" refused: `{f}` |")),
            }
        }
        s.push('\n');
    }
    s
}
