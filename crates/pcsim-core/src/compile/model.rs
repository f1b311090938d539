//! A case becomes a model ([`model_from_case`]): the one place where a case's catenary, wires,
//! elements, pantographs, wind and irregularity become the model's data. This is where every
//! element kind is registered (hand-made models for analytic checks and the zoo come from
//! `model::ModelBuilder`).

use crate::error::{CaseError, Warning};
use crate::input::case::{
    Case, CatenaryCase, Dof, IceCase, IrregularityCase, PantographCase, Spectrum,
    TensionLengthCase, WindProfile, WireCase,
};
use crate::model::basis::SineBasis;
use crate::model::dof::Direction;
use crate::model::elements::contact::{Contact, ContactLaw, Contacts};
use crate::model::elements::dropper::{Dropper, Droppers};
use crate::model::elements::registration::{Registration, Registrations};
use crate::model::elements::section_insulator::{
    curvature_stiffness_n_per_m, runner_height_m, SectionInsulator, SectionInsulators,
};
use crate::model::elements::steady_arm::{SteadyArm, SteadyArms};
use crate::model::elements::stitch::{Stitch, Stitches};
use crate::model::elements::support::{Support, Supports};
use crate::model::elements::{Attach, PointElement};
use crate::model::irregularity::{IrregularityProfile, IrregularitySource};
use crate::model::lateral::{LateralGeometry, StaggerLine};
use crate::model::line::{
    LineStatics, SpanLayout, StitchWire, TensionLengthDesign, TensionLengthStatics,
};
use crate::model::pantograph::{Lumped, Pantograph, PantographKind, Strip, UpliftTable};
use crate::model::statics::{
    presag_values, StaticDesign, StaticSolution, StitchDesign, StitchStatic, G,
};
use crate::model::wind::{mean_at_height, Profile, WindLoad, WindReport, WireWind};
use crate::model::wind_field::{FieldSpec, SpectrumModel, WindField};
use crate::model::wire::{Section, Wire, WireRole};
use crate::model::{HardSpot, HardSpotKind, Model, Node, StaticShape};

/// What the static shape needs of a case's catenary.
pub fn static_design(c: &CatenaryCase) -> StaticDesign {
    StaticDesign {
        span_m: c.span_m,
        spans: c.spans,
        encumbrance_m: c.encumbrance_m,
        dropper_x_m: c.droppers.positions_m.clone(),
        presag: c.presag.clone(),
        arm_holds_contact: c.steady_arm.static_support,
        contact_mass_per_m_kg: c.contact_wire.mass_per_m_kg,
        contact_tension_n: c.contact_wire.tension_n,
        messenger_mass_per_m_kg: c.messenger.mass_per_m_kg,
        messenger_tension_n: c.messenger.tension_n,
        dropper_mass_per_m_kg: c.droppers.mass_per_m_kg,
        clamp_mass_contact_kg: c.droppers.clamp_mass_contact_kg,
        clamp_mass_messenger_kg: c.droppers.clamp_mass_messenger_kg,
        stitch: c.stitch_wire.as_ref().map(|s| StitchDesign {
            droppers: s.droppers.clone(),
            tension_n: s.tension_n,
            length_m: s.length_m,
            clamp_mass_kg: s.clamp_mass_kg,
            mass_per_m_kg: s.mass_per_m_kg,
        }),
    }
}

/// A case's irregularity sources as the model's.
pub fn irregularity_sources(v: &[IrregularityCase]) -> Vec<IrregularitySource> {
    v.iter()
        .map(|s| match s {
            IrregularityCase::Table {
                position_m,
                deviation_m,
                source_file,
            } => IrregularitySource::Table {
                position_m: position_m.clone(),
                deviation_m: deviation_m.clone(),
                source_file: source_file.clone(),
            },
            IrregularityCase::Psd {
                rms_m,
                min_wavelength_m,
                max_wavelength_m,
                exponent,
                table,
                seed,
            } => IrregularitySource::Psd {
                rms_m: *rms_m,
                min_wavelength_m: *min_wavelength_m,
                max_wavelength_m: *max_wavelength_m,
                exponent: *exponent,
                table: table.clone(),
                seed: *seed,
            },
            IrregularityCase::Droppers { rms_m, seed } => IrregularitySource::Droppers {
                rms_m: *rms_m,
                seed: *seed,
            },
        })
        .collect()
}

/// Index of the messenger and of the contact wire in a catenary model built from a case.
pub const MESSENGER: usize = 0;
/// Index of the contact wire in the model's wires.
pub const CONTACT: usize = 1;

/// The quasi-steady torsional aerodynamic damping per metre of a wire of diameter `d` in a
/// normal wind `u`, N·m·s/m: `½ρ d² R u C_M'(0)` with the characteristic radius `R = d/2`
/// (`model::wind`; Blevins' quasi-steady torsional galloping, the radius a guess).
pub fn torsional_aero_damping(rho: f64, d: f64, u: f64, dcm_per_rad: f64) -> f64 {
    0.5 * rho * d * d * (0.5 * d) * u * dcm_per_rad
}

/// Mass per metre of radial ice of thickness `t` on a wire of diameter `d` (the annulus), kg/m,
/// and its polar mass moment per metre, kg·m.
pub fn ice_mass(density_kg_m3: f64, d: f64, t: f64) -> (f64, f64) {
    let (r, ro) = (0.5 * d, 0.5 * d + t);
    let pi = std::f64::consts::PI;
    (
        density_kg_m3 * pi * (ro * ro - r * r),
        density_kg_m3 * 0.5 * pi * (ro.powi(4) - r.powi(4)),
    )
}

/// The section of a wire for the dynamics: the dynamic mass per metre (clamps and ice smeared
/// in), the vertical data, and the lateral and torsional data of `section` when given (lateral
/// bending stiffness defaults to the vertical one; torsion data are zero when not modelled).
fn section(mass_per_m_kg: f64, w: &WireCase, ice_polar_kg_m: f64) -> Section {
    let mut s = Section::vertical(mass_per_m_kg, w.tension_n, w.ei_nm2);
    if let Some(sc) = &w.section {
        s.ei_lateral_nm2 = sc.ei_lateral_nm2.unwrap_or(w.ei_nm2);
        s.gj_nm2 = sc.gj_nm2.unwrap_or(0.0);
        s.polar_inertia_kg_m = sc.polar_inertia_kg_m.unwrap_or(0.0) + ice_polar_kg_m;
    }
    s
}

/// The directions of a case.
fn directions(case: &Case) -> Vec<Direction> {
    Direction::ALL
        .into_iter()
        .filter(|d| {
            case.run.dofs.contains(&match d {
                Direction::Vertical => Dof::Vertical,
                Direction::Lateral => Dof::Lateral,
                Direction::Torsional => Dof::Torsional,
            })
        })
        .collect()
}

/// Duration of a case's run, s (the rearmost pantograph from its start to `end_m`).
fn run_duration_s(case: &Case) -> f64 {
    let max_off = case
        .pantographs
        .iter()
        .map(|p| p.offset_m())
        .fold(0.0, f64::max);
    (case.run.end_m - (case.run.start_m - max_off)) / case.speed_m_s().max(1e-9)
}

/// The spectrum of the wind's turbulence (`u_c`: the mean speed at the contact wire, m/s).
fn spectrum_model(wd: &crate::input::lateral::WindCase, u_c: f64) -> Option<SpectrumModel> {
    match wd.spectrum {
        Spectrum::Kaimal { integral_length_m } => Some(SpectrumModel::Kaimal {
            integral_length_m,
            mean_m_s: u_c,
        }),
        Spectrum::Davenport => Some(SpectrumModel::Davenport {
            reference_m_s: wd.mean_speed_m_s,
        }),
        Spectrum::None => None,
    }
}

/// The wind's turbulent field on the grid `xs` over `duration` s (a calm one without turbulence):
/// `sigma` its standard deviation, `u_c` the mean speed at the contact wire's height, m/s.
fn turbulent_field(
    wd: &crate::input::lateral::WindCase,
    xs: &[f64],
    spectrum: Option<SpectrumModel>,
    sigma: f64,
    u_c: f64,
    duration: f64,
) -> WindField {
    match spectrum {
        Some(sp) if sigma > 0.0 => WindField::generate(
            xs,
            &FieldSpec {
                spectrum: sp,
                sigma_m_s: sigma,
                mean_m_s: u_c.max(0.1),
                coherence_decay: wd.coherence_decay,
            },
            wd.dt_s,
            duration,
            wd.seed,
        ),
        _ => WindField::calm(xs, wd.dt_s),
    }
}

/// The crosswind of a case on the model's wires (each tension length's messenger and contact
/// wire: wire `2k + i`, on its own diameters and coefficients where a tension length overrides
/// its wires): the mean wind at each wire's height, the aerodynamic coefficients, the
/// linearised aerodynamic damping and the generated turbulence on one grid along the whole line
/// (an overlap's two tension lengths feel the same field). On a curved track the wind keeps its
/// direction while the track turns: its part normal to the track at each grid point is
/// `sin(ψ − θ(x))` ([`curve_normals`]), and each wire's damping is linearised about its mean
/// normal speed over the wire's extent.
fn wind_load(
    case: &Case,
    iced: &Iced,
    placed: &Placed,
    geometry: Option<&LateralGeometry>,
) -> Option<WindLoad> {
    let wd = case.wind.as_ref()?;
    let c = &case.catenary;
    let lat = c.lateral.as_ref()?;
    let length_m = case.length_m();
    let profile = match wd.profile {
        WindProfile::Log { roughness_m } => Profile::Log { roughness_m },
        WindProfile::Power { exponent } => Profile::Power { exponent },
    };
    // Signed: positive yaw blows toward positive stagger, negative toward negative stagger
    // (a mirror image of the case gives the mirror result).
    let normal = wd.yaw_deg.to_radians().sin();
    // The lift of a section symmetric about its vertical plane does not change sign with the
    // wind's side: on `½ρ V|V|` its coefficient carries the side of the normal wind at the first
    // support (`½ρ V²` wherever the normal wind keeps that side).
    let side = if normal < 0.0 { -1.0 } else { 1.0 };
    let rho = wd.air_density_kg_m3;
    let n_grid = (length_m / wd.grid_m).floor() as usize;
    let xs: Vec<f64> = (1..n_grid)
        .map(|g| g as f64 * wd.grid_m)
        .filter(|&x| x < length_m - 1e-9)
        .collect();
    let curve = geometry.filter(|g| g.curved());
    let normal_by_grid = curve.map_or_else(Vec::new, |g| curve_normals(g, wd.yaw_deg, &xs));
    let mut wires = Vec::new();
    for (k, tl) in placed.tls.iter().enumerate() {
        // The mean normal fraction over the tension length's extent (its end supports).
        let extent = (tl.supports_m.first(), tl.supports_m.last());
        let damped = match (curve, extent) {
            (Some(g), (Some(&a), Some(&b))) => mean_abs_normal(g, wd.yaw_deg, a, b),
            _ => normal,
        };
        // A `[catenary]`'s wires are `iced`'s; a line's tension length carries its own.
        let tl_iced;
        let (ck, diam) = if case.line.is_none() {
            (c, iced.diameters)
        } else {
            tl_iced = Iced::on(&tl.catenary, c.ice.as_ref());
            (&tl.catenary, tl_iced.diameters)
        };
        let heights = [
            lat.contact_wire_height_m + ck.encumbrance_m,
            lat.contact_wire_height_m,
        ];
        for (i, w) in [(MESSENGER, &ck.messenger), (CONTACT, &ck.contact_wire)] {
            let aero = w.section.as_ref().and_then(|s| s.aero.as_ref())?;
            let d = diam[i];
            let (cd, cl, cm) = aero.at(0.0);
            let (_, dcl, dcm) = aero.slopes_at_zero();
            let along = mean_at_height(
                wd.mean_speed_m_s,
                wd.reference_height_m,
                heights[i],
                &profile,
            );
            let u = normal * along;
            // The speed the wire's motion is linearised about (`|u|` on a straight track): the
            // aerodynamic damping does not depend on the wind's side.
            let ud = if curve.is_some() {
                damped * along
            } else {
                u.abs()
            };
            wires.push(WireWind {
                wire: 2 * k + i,
                height_m: heights[i],
                mean_normal_m_s: u,
                mean_along_m_s: along,
                lateral_m: d * cd,
                vertical_m: side * d * cl,
                torsional_m2: d * d * cm,
                damping_lateral: rho * d * cd * ud,
                damping_vertical: 0.5 * rho * d * ud * (dcl + cd),
                damping_torsional: torsional_aero_damping(rho, d, ud, dcm),
            });
        }
    }
    let sigma = wd.turbulence_intensity * wd.mean_speed_m_s;
    let u_c = mean_at_height(
        wd.mean_speed_m_s,
        wd.reference_height_m,
        lat.contact_wire_height_m,
        &profile,
    );
    let duration = run_duration_s(case) + 2.0 * wd.dt_s;
    let spectrum = spectrum_model(wd, u_c);
    let field = turbulent_field(wd, &xs, spectrum, sigma, u_c, duration);
    let achieved = field.std_over(duration) / wd.mean_speed_m_s.max(1e-12);
    Some(WindLoad {
        air_density_kg_m3: rho,
        normal_fraction: normal,
        wires,
        normal_by_grid,
        field,
        grid_m: wd.grid_m,
        report: WindReport {
            mean_speed_m_s: wd.mean_speed_m_s,
            reference_height_m: wd.reference_height_m,
            yaw_deg: wd.yaw_deg,
            spectrum: spectrum.map_or("none", |s| s.name()).into(),
            seed: wd.seed,
            turbulence_intensity_target: wd.turbulence_intensity,
            turbulence_intensity_achieved: achieved,
        },
    })
}

/// The part of the wind normal to a curved track at each of the points `xs`, `sin(ψ − θ(x))`:
/// the wind keeps the direction it has at the first support (yaw `ψ` there: positive blows
/// toward positive stagger, negative toward negative stagger) while the track turns by `θ(x)`
/// ([`LateralGeometry::turn_rad`], signed with the curve's hand). The mirror image of a case
/// (radius, stagger and yaw negated) negates every normal part.
fn curve_normals(g: &LateralGeometry, yaw_deg: f64, xs: &[f64]) -> Vec<f64> {
    let psi = yaw_deg.to_radians();
    xs.iter().map(|&x| (psi - g.turn_rad(x)).sin()).collect()
}

/// The mean of `|sin(ψ − θ(x))|` over `[a, b]` (midpoints of 1 m or finer cells): the normal
/// speed a wire's aerodynamic damping is linearised about on a curve.
fn mean_abs_normal(g: &LateralGeometry, yaw_deg: f64, a: f64, b: f64) -> f64 {
    let psi = yaw_deg.to_radians();
    let cells = ((b - a).abs().ceil() as usize).clamp(1, 100_000);
    let h = (b - a) / cells as f64;
    (0..cells)
        .map(|i| (psi - g.turn_rad(a + (i as f64 + 0.5) * h)).sin().abs())
        .sum::<f64>()
        / cells as f64
}

pub(crate) fn default_name(name: &str, i: usize) -> String {
    if !name.is_empty() {
        name.to_string()
    } else if i == 0 {
        "leading".to_string()
    } else {
        format!("pantograph-{}", i + 1)
    }
}

/// The pantographs of a case, and one contact per pantograph and contact wire.
/// The chain of a lumped pantograph of the case (none for a moving force), its static forces
/// (the uplift and its table against height) times `uplift_factor`.
pub(crate) fn lumped_chain(
    p: &PantographCase,
    uplift_factor: f64,
    contact_stiffness_n_per_m: f64,
) -> Option<Lumped> {
    let PantographCase::Lumped {
        masses_kg,
        stiffness_n_per_m,
        damping_ns_per_m,
        uplift_n,
        uplift_by_height,
        aero_coeffs_kmh,
        strips,
        ..
    } = p
    else {
        return None;
    };
    Some(Lumped {
        masses_kg: masses_kg.clone(),
        stiffness_n_per_m: stiffness_n_per_m.clone(),
        damping_ns_per_m: damping_ns_per_m.clone(),
        uplift_n: *uplift_n * uplift_factor,
        uplift_by_height: uplift_by_height.as_ref().map(|t| UpliftTable {
            height_m: t.height_m.clone(),
            uplift_n: t.uplift_n.iter().map(|f| f * uplift_factor).collect(),
        }),
        aero_coeffs_kmh: aero_coeffs_kmh.clone(),
        strips: (strips.iter())
            .map(|s| Strip {
                mass_kg: s.mass_kg,
                stiffness_n_per_m: s.stiffness_n_per_m,
                damping_ns_per_m: s.damping_ns_per_m,
                along_m: s.along_m,
                height_offset_m: s.height_offset_m,
                contact_stiffness_n_per_m: s
                    .contact_stiffness_n_per_m
                    .unwrap_or(contact_stiffness_n_per_m),
            })
            .collect(),
    })
}

fn pantographs(
    case: &Case,
    contact_wires: &[usize],
    eccentricity_m: f64,
    twist: bool,
    lateral: bool,
) -> (Vec<Pantograph>, Contacts) {
    let mut contacts = Vec::new();
    let n_pans = case.pantographs.len();
    let pans = case
        .pantographs
        .iter()
        .enumerate()
        .map(|(i, p)| {
            let (mut head, mut working) = (None, None);
            let (name, offset_m, kind, law) = match p {
                PantographCase::Lumped {
                    name,
                    offset_m,
                    head_half_width_m,
                    working_half_width_m,
                    ..
                } => (
                    {
                        head = *head_half_width_m;
                        working = *working_half_width_m;
                        name
                    },
                    offset_m,
                    PantographKind::Lumped(
                        lumped_chain(p, case.run.uplift_factor(), case.contact.stiffness_n_per_m)
                            .expect("a lumped pantograph"),
                    ),
                    ContactLaw::Penalty {
                        stiffness_n_per_m: case.contact.stiffness_n_per_m,
                    },
                ),
                PantographCase::MovingForce {
                    name,
                    offset_m,
                    force_n,
                    lateral_force_n,
                } => (
                    name,
                    offset_m,
                    PantographKind::MovingForce {
                        force_n: *force_n,
                        lateral_force_n: *lateral_force_n,
                    },
                    ContactLaw::prescribed(Direction::Vertical, i, n_pans),
                ),
            };
            // One contact per contact head (the head, or each collector strip at its place on
            // the head, on its own penalty spring) and contact wire (a line's tension lengths;
            // in an overlap the head meets one wire, both, then the other).
            let heads: Vec<(f64, ContactLaw)> = match &kind {
                PantographKind::Lumped(l) if !l.strips.is_empty() => (l.strips.iter())
                    .map(|s| {
                        let k = s.contact_stiffness_n_per_m;
                        (
                            s.along_m,
                            ContactLaw::Penalty {
                                stiffness_n_per_m: k,
                            },
                        )
                    })
                    .collect(),
                _ => vec![(0.0, law)],
            };
            for (head, &(along_m, law)) in heads.iter().enumerate() {
                for &wire in contact_wires {
                    contacts.push(Contact {
                        pantograph: i,
                        head,
                        along_m,
                        wire,
                        dir: Direction::Vertical,
                        law,
                        eccentricity_m,
                        twist,
                    });
                }
            }
            if lateral && matches!(p, PantographCase::MovingForce { .. }) {
                // The lateral probe, after the vertical contact (the pantograph's first moving
                // point is its vertical one): a prescribed force on the lateral series at the
                // point under the pantograph, its load after the vertical ones.
                contacts.push(Contact {
                    pantograph: i,
                    head: 0,
                    along_m: 0.0,
                    wire: contact_wires[0],
                    dir: Direction::Lateral,
                    law: ContactLaw::prescribed(Direction::Lateral, i, n_pans),
                    eccentricity_m: 0.0,
                    twist: false,
                });
            }
            Pantograph {
                name: default_name(name, i),
                offset_m: *offset_m,
                kind,
                head_half_width_m: head,
                working_half_width_m: working,
            }
        })
        .collect();
    (pans, Contacts(contacts))
}

/// Build the model of a case (validated first).
///
/// Deviation from the paper: dropper clamp masses (and half of each dropper's own mass) are
/// smeared into the wires' mass per metre instead of being point masses, as the reference
/// README §5 allows (σ changes by ≤ 1 N); point masses treated explicitly would be unstable.
/// Steady-arm masses stay point masses, solved exactly in the mass matrix.
pub fn model_from_case(case: &Case) -> Result<(Model, Vec<Warning>), CaseError> {
    let warnings = case.validate()?;
    model_from_validated(case, warnings)
}

/// [`model_from_case`] for a case already validated, whose validation gave `warnings`: a short
/// driver over the named builders, each one part of the model (the elements' list and their
/// order visible here, in one place).
pub fn model_from_validated(
    case: &Case,
    mut warnings: Vec<Warning>,
) -> Result<(Model, Vec<Warning>), CaseError> {
    let dirs = Dirs::of(case);
    // Ice: its mass joins the wires' (statics and dynamics); the design geometry is kept.
    let iced = Iced::of(case);
    // The design's static shape, dropper lengths and preloads are those of the ice-free line:
    // the ice's weight is a steady load on that geometry (it lowers the wires, solved in the
    // start state, `solve::equilibrium`).
    let placed = place(case)?;
    let (registrations, geometry) = build_registrations(case, &iced.catenary, &placed, &dirs);
    let wind = wind_load(case, &iced, &placed, geometry.as_ref());
    let wires = build_wires(case, &iced, &placed, wind.as_ref(), &dirs);
    warnings.extend(wind_warnings(wind.as_ref(), &wires, &dirs));
    let points = build_point_elements(&placed, &iced.catenary, &dirs);
    let (pans, contacts) = build_pantographs(case, &placed, &iced.catenary, &dirs);
    // The registration of every element kind, in the order their forces are evaluated.
    let mut elements: Vec<Box<dyn PointElement>> = vec![
        Box::new(Droppers::new(points.droppers)),
        Box::new(Supports(points.supports)),
        Box::new(SteadyArms(points.arms)),
        Box::new(Stitches(points.stitches)),
    ];
    if !registrations.is_empty() {
        elements.push(Box::new(Registrations(registrations)));
    }
    if !case.section_insulator.is_empty() {
        elements.push(Box::new(build_section_insulators(case, &dirs)?));
    }
    elements.push(Box::new(contacts));
    let mut model = Model::new(
        wires,
        points.nodes,
        elements,
        pans,
        placed.shape,
        placed.span_m,
    );
    model.supports_m = placed.supports_m;
    model.overlaps_m = case
        .line
        .as_ref()
        .map_or(Vec::new(), |l| l.overlap_sections_m());
    model.hard_spots = hard_spots(case);
    model.lateral = geometry;
    model.wind = wind;
    model.irregularity = build_irregularity(case, &iced.catenary);
    Ok((model, warnings))
}

/// The directions a case models.
struct Dirs {
    all: Vec<Direction>,
    lateral: bool,
    torsional: bool,
}

impl Dirs {
    fn of(case: &Case) -> Dirs {
        let all = directions(case);
        Dirs {
            lateral: all.contains(&Direction::Lateral),
            torsional: all.contains(&Direction::Torsional),
            all,
        }
    }
}

/// The catenary with its ice: the ice's mass added to each wire's, the iced diameters (for the
/// wind) and the ice's polar inertia and weight per metre, by wire (`MESSENGER`, `CONTACT`).
struct Iced {
    catenary: CatenaryCase,
    diameters: [f64; 2],
    polar_kg_m: [f64; 2],
    mass_kg_m: [f64; 2],
}

impl Iced {
    fn of(case: &Case) -> Iced {
        Iced::on(&case.catenary, case.catenary.ice.as_ref())
    }

    /// Catenary `c` (the case's, or a line's tension length with its own wires) under `ice`.
    fn on(c: &CatenaryCase, ice: Option<&IceCase>) -> Iced {
        let mut c = c.clone();
        let diam = |w: &WireCase| w.section.as_ref().map_or(0.0, |s| s.diameter_m);
        let mut diameters = [diam(&c.messenger), diam(&c.contact_wire)];
        let mut polar_kg_m = [0.0; 2];
        let mut mass_kg_m = [0.0; 2];
        if let Some(ice) = ice {
            for (i, t) in [(MESSENGER, ice.messenger_m), (CONTACT, ice.contact_wire_m)] {
                let (m, j) = ice_mass(ice.density_kg_m3, diameters[i], t);
                mass_kg_m[i] = m;
                let w = if i == MESSENGER {
                    &mut c.messenger
                } else {
                    &mut c.contact_wire
                };
                w.mass_per_m_kg += m;
                polar_kg_m[i] = j;
                diameters[i] += 2.0 * t;
            }
        }
        Iced {
            catenary: c,
            diameters,
            polar_kg_m,
            mass_kg_m,
        }
    }
}

/// The wires: two per tension length, the messenger then the contact wire (wire 2k is tension
/// length k's messenger, 2k + 1 its contact wire; `MESSENGER`, `CONTACT` for the first), each on
/// its basis, with the wind's aerodynamic damping and the ice's weight.
fn build_wires(
    case: &Case,
    iced: &Iced,
    placed: &Placed,
    wind: Option<&WindLoad>,
    dirs: &Dirs,
) -> Vec<Wire> {
    let c = &iced.catenary;
    let l = case.length_m();
    // The linearised aerodynamic damping of the wind joins each wire's modal damping.
    let aero = |wire: usize, dir: Direction| {
        wind.and_then(|wl| wl.wires.iter().find(|ww| ww.wire == wire))
            .map_or(0.0, |ww| match dir {
                Direction::Lateral => ww.damping_lateral,
                Direction::Vertical => ww.damping_vertical,
                Direction::Torsional => ww.damping_torsional,
            })
    };
    let one = placed.tls.len() == 1;
    let mut wires: Vec<Wire> = Vec::with_capacity(2 * placed.tls.len());
    for (k, tl) in placed.tls.iter().enumerate() {
        // A `[catenary]` carries the ice in `iced`; each tension length of a `[line]` carries
        // it on its own wires (their own diameters, where the tension length overrides them).
        let tl_iced;
        let (ck, ice_k) = if case.line.is_none() {
            (c, iced)
        } else {
            tl_iced = Iced::on(&tl.catenary, case.catenary.ice.as_ref());
            (&tl_iced.catenary, &tl_iced)
        };
        let periodic = matches!(placed.shape, StaticShape::Catenary(_)).then_some(c.span_m);
        let (rho_c, rho_m) = smeared_masses(ck, tl, periodic);
        let basis = if case.line.is_none() || one {
            SineBasis::new(l, case.n_modes())
        } else {
            let n = (case.n_modes() as f64 * tl.length_m / l).round().max(1.0) as usize;
            SineBasis::new(tl.length_m, n)
        };
        let suffix = if one {
            String::new()
        } else {
            format!("-{}", k + 1)
        };
        for (name, role, rho, wc, i) in [
            (
                "messenger",
                WireRole::Messenger,
                rho_m,
                &ck.messenger,
                MESSENGER,
            ),
            (
                "contact_wire",
                WireRole::Contact,
                rho_c,
                &ck.contact_wire,
                CONTACT,
            ),
        ] {
            let w = 2 * k + i;
            // The messenger's torsion is modelled only where something drives it: no clamp
            // holds it eccentrically (the droppers' and steady arms' eccentric clamps grip the
            // contact wire; the cantilever's registration holds the messenger laterally only),
            // so only a wind moment (`d² C_M ≠ 0`) does. Undriven, it would stay exactly zero
            // at the cost of a sixth of a 3D step (issue 23, item 2).
            let driven = |w: usize| {
                wind.is_some_and(|wl| {
                    wl.wires
                        .iter()
                        .any(|ww| ww.wire == w && ww.torsional_m2 != 0.0)
                })
            };
            let wire_dirs: Vec<Direction> = dirs
                .all
                .iter()
                .copied()
                .filter(|&d| d != Direction::Torsional || i != MESSENGER || driven(w))
                .collect();
            wires.push(
                Wire::new(
                    &format!("{name}{suffix}"),
                    role,
                    tl.start_m,
                    basis.clone(),
                    section(rho, wc, ice_k.polar_kg_m[i]),
                    c.damping.clone(),
                    &wire_dirs,
                )
                .with_added_damping(Direction::Lateral, aero(w, Direction::Lateral))
                .with_added_damping(Direction::Vertical, aero(w, Direction::Vertical))
                .with_added_damping(Direction::Torsional, aero(w, Direction::Torsional))
                .with_static_load(Direction::Vertical, -ice_k.mass_kg_m[i] * G),
            );
        }
    }
    wires
}

/// The wind's warnings: negative aerodynamic damping (galloping possible), by wire.
fn wind_warnings(wind: Option<&WindLoad>, wires: &[Wire], dirs: &Dirs) -> Vec<Warning> {
    let mut warnings = Vec::new();
    for ww in wind.iter().flat_map(|wl| &wl.wires) {
        if ww.damping_vertical < 0.0 {
            warnings.push(Warning(format!(
                "wind: the {} has negative vertical aerodynamic damping ({:.3} N·s/m², C_L' + C_D < 0): Den Hartog galloping is possible",
                wires[ww.wire].name, ww.damping_vertical
            )));
        }
        if ww.damping_torsional < 0.0 && dirs.torsional {
            warnings.push(Warning(format!(
                "wind: the {} has negative torsional aerodynamic damping ({:.3e} N·m·s/m, C_M' < 0): torsional galloping is possible",
                wires[ww.wire].name, ww.damping_torsional
            )));
        }
    }
    warnings
}

/// Where a point of wire `wire` attaches in direction `dir`: the wire there when the direction
/// is modelled, else the ground.
fn on_dir(wire: usize, dir: Direction, x_m: f64, modelled: bool) -> Attach {
    if modelled {
        Attach::Wire { wire, dir, x_m }
    } else {
        Attach::Ground
    }
}

/// A vertical attachment to wire `wire` at `x_m`.
fn on(wire: usize, x_m: f64) -> Attach {
    Attach::Wire {
        wire,
        dir: Direction::Vertical,
        x_m,
    }
}

/// The point elements hung on the placed tension lengths, and the stitch clamps' nodes.
struct PointElements {
    droppers: Vec<Dropper>,
    stitches: Vec<Stitch>,
    nodes: Vec<Node>,
    supports: Vec<Support>,
    arms: Vec<SteadyArm>,
}

/// The droppers (with their stitch wires and clamp nodes), the messenger supports and the steady
/// arms of every tension length.
fn build_point_elements(placed: &Placed, c: &CatenaryCase, dirs: &Dirs) -> PointElements {
    let (lateral, torsional) = (dirs.lateral, dirs.torsional);
    let dropper_ecc = c
        .lateral
        .as_ref()
        .map_or(0.0, |l| l.dropper_clamp_eccentricity_m);
    let mut p = PointElements {
        droppers: Vec::new(),
        stitches: Vec::new(),
        nodes: Vec::new(),
        supports: Vec::new(),
        arms: Vec::new(),
    };
    for (k, tl) in placed.tls.iter().enumerate() {
        let (mw, cw) = (2 * k + MESSENGER, 2 * k + CONTACT);
        let ck = &tl.catenary;
        let sup = &ck.messenger_support;
        for h in &tl.hangers {
            let x = h.x_m;
            let top = match h.stitch {
                Some(st) => {
                    let damping = match ck.stitch_wire.as_ref().and_then(|w| w.damping_ns_per_m) {
                        Some(cs) => cs,
                        None if sup.stiffness_n_per_m > 0.0 => {
                            sup.damping_ns_per_m / sup.stiffness_n_per_m * st.stiffness_n_per_m
                        }
                        None => 0.0,
                    };
                    p.nodes.push(Node {
                        x_m: x,
                        mass_kg: st.node_mass_kg,
                        dir: Direction::Vertical,
                    });
                    let node = Attach::Node(p.nodes.len() - 1);
                    p.stitches.push(Stitch {
                        wire: on(mw, x),
                        node,
                        stiffness_n_per_m: st.stiffness_n_per_m,
                        damping_ns_per_m: damping,
                    });
                    node
                }
                None => on(mw, x),
            };
            p.droppers.push(Dropper {
                x_m: x,
                stiffness_n_per_m: h.stiffness_n_per_m,
                preload_n: h.preload_n,
                top,
                bottom: on(cw, x),
                length_m: h.length_m,
                top_lateral: on_dir(mw, Direction::Lateral, x, lateral),
                bottom_lateral: on_dir(cw, Direction::Lateral, x, lateral),
                bottom_twist: on_dir(cw, Direction::Torsional, x, torsional && dropper_ecc != 0.0),
                eccentricity_m: if torsional { dropper_ecc } else { 0.0 },
            });
        }
        for &x in &tl.interior_supports_m {
            p.supports.push(Support {
                at: on(mw, x),
                stiffness_n_per_m: sup.stiffness_n_per_m,
                damping_ns_per_m: sup.damping_ns_per_m,
            });
            p.arms.push(SteadyArm {
                at: on(cw, x),
                mass_kg: ck.steady_arm.mass_kg,
                stiffness_n_per_m: ck.steady_arm.stiffness_n_per_m,
            });
        }
    }
    p
}

/// Lateral registration at the inner supports of every tension length (each wire's ends are
/// pinned by its sine series): the contact wire's steady arm, eccentric by e_s, and the
/// messenger's support; and the lateral geometry (each tension length's stagger, the curve per
/// span, the probes). None without lateral motion.
fn build_registrations(
    case: &Case,
    c: &CatenaryCase,
    placed: &Placed,
    dirs: &Dirs,
) -> (Vec<Registration>, Option<LateralGeometry>) {
    let torsional = dirs.torsional;
    let mut registrations = Vec::new();
    let (true, Some(lc)) = (dirs.lateral, &c.lateral) else {
        return (registrations, None);
    };
    let e_s = if torsional {
        lc.steady_arm_clamp_eccentricity_m
    } else {
        0.0
    };
    let k_phi = lc.steady_arm_torsional_stiffness_nm_per_rad;
    for (k, tl) in placed.tls.iter().enumerate() {
        let (mw, cw) = (2 * k + MESSENGER, 2 * k + CONTACT);
        for (i, &x) in tl.interior_supports_m.iter().enumerate() {
            registrations.push(Registration {
                at: on_dir(cw, Direction::Lateral, x, true),
                twist: on_dir(
                    cw,
                    Direction::Torsional,
                    x,
                    torsional && (e_s != 0.0 || k_phi != 0.0),
                ),
                torsional_stiffness_nm_per_rad: if torsional { k_phi } else { 0.0 },
                eccentricity_m: e_s,
                stiffness_n_per_m: lc.steady_arm_stiffness_n_per_m,
                mass_kg: lc.steady_arm_mass_kg,
                vertical_force_n: if tl.catenary.steady_arm.static_support {
                    tl.arm_force_n[i]
                } else {
                    0.0
                },
            });
            registrations.push(Registration {
                at: on_dir(mw, Direction::Lateral, x, true),
                twist: Attach::Ground,
                eccentricity_m: 0.0,
                stiffness_n_per_m: lc.messenger_support_stiffness_n_per_m,
                mass_kg: 0.0,
                vertical_force_n: 0.0,
                torsional_stiffness_nm_per_rad: 0.0,
            });
        }
    }
    (
        registrations,
        Some(lateral_geometry(case, lc, placed, torsional)),
    )
}

/// The lateral geometry of a case: the supports, each tension length's stagger polyline (its
/// two wires share it), the curve and the head's offset per span, and the blow-out probes
/// (each contact wire's droppers and mid-spans).
fn lateral_geometry(
    case: &Case,
    lc: &crate::input::lateral::LateralCase,
    placed: &Placed,
    torsional: bool,
) -> LateralGeometry {
    use crate::input::lateral::head_offset_m;
    let default = (lc.track_radius_m, lc.cant_m);
    let (staggers, curves, uniform) = match &case.line {
        None => {
            let c = &case.catenary;
            (
                vec![(0..=c.spans).map(|i| lc.stagger_at(i)).collect::<Vec<_>>()],
                vec![default; c.spans],
                Some(c.span_m),
            )
        }
        Some(line) => (
            line.staggers_m(&|i| lc.stagger_at(i)),
            line.span_curves(default),
            None,
        ),
    };
    let mut probes: Vec<(usize, f64)> = Vec::new();
    for (k, tl) in placed.tls.iter().enumerate() {
        let cw = 2 * k + CONTACT;
        let mut xs: Vec<f64> = tl.hangers.iter().map(|h| h.x_m).collect();
        let sup = &tl.supports_m;
        xs.extend(sup.windows(2).map(|w| match uniform {
            Some(span) => w[0] + 0.5 * span,
            None => w[0] + 0.5 * (w[1] - w[0]),
        }));
        xs.sort_by(f64::total_cmp);
        xs.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
        probes.extend(xs.into_iter().map(|x| (cw, x)));
    }
    LateralGeometry {
        supports_m: placed.supports_m.clone(),
        uniform_span_m: uniform,
        lines: (placed.tls.iter().zip(staggers))
            .map(|(tl, stagger_m)| StaggerLine {
                first_support: tl.first_support,
                stagger_m,
            })
            .collect(),
        wire_line: (0..2 * placed.tls.len()).map(|w| Some(w / 2)).collect(),
        curvature_per_m: curves
            .iter()
            .map(|(r, _)| r.map_or(0.0, |r| 1.0 / r))
            .collect(),
        head_offset_m: curves
            .iter()
            .map(|&(r, cant)| head_offset_m(r, cant, lc.contact_wire_height_m))
            .collect(),
        contact_point_eccentricity_m: if torsional {
            lc.contact_point_eccentricity_m
        } else {
            0.0
        },
        probes_m: probes,
    }
}

/// The pantographs and their contacts with every contact wire (the contact point below the axis
/// by e_c where torsion is modelled).
fn build_pantographs(
    case: &Case,
    placed: &Placed,
    c: &CatenaryCase,
    dirs: &Dirs,
) -> (Vec<Pantograph>, Contacts) {
    let e_c = match (&c.lateral, dirs.torsional) {
        (Some(lc), true) => lc.contact_point_eccentricity_m,
        _ => 0.0,
    };
    let contact_wires: Vec<usize> = (0..placed.tls.len()).map(|k| 2 * k + CONTACT).collect();
    pantographs(
        case,
        &contact_wires,
        e_c,
        dirs.torsional && e_c != 0.0,
        dirs.lateral,
    )
}

/// The contact wire's irregularity (the case's sources on the line), if any, with the section
/// insulators' runners ([`runner_height_m`]: the running surface's deviation from the wire's
/// design height over each insulator, a given geometry as an irregularity is).
fn build_irregularity(case: &Case, c: &CatenaryCase) -> Option<IrregularityProfile> {
    let runners: Vec<_> = (case.section_insulator.iter())
        .filter(|s| s.prelift_m != 0.0)
        .collect();
    if case.irregularity.is_empty() && runners.is_empty() {
        return None;
    }
    let mut profile = IrregularityProfile::build(
        &irregularity_sources(&case.irregularity),
        case.length_m(),
        c.span_m,
        &c.droppers.positions_m,
    );
    for s in runners {
        profile.add(|x| runner_height_m(x, s.position_m, s.length_m, s.ramp_m, s.prelift_m));
    }
    Some(profile)
}

/// The hard spots a run reports its passage over: each section insulator (its extent) and each
/// neutral section (its dead length), on the contact wire that holds it (a validated case).
fn hard_spots(case: &Case) -> Vec<HardSpot> {
    let wire = |section_m| {
        2 * crate::input::hard_spots::tension_length_under(case, section_m).unwrap_or(0) + CONTACT
    };
    let insulators = case.section_insulator.iter().map(|s| HardSpot {
        kind: HardSpotKind::SectionInsulator,
        section_m: s.extent_m(),
        wire: wire(s.extent_m()),
    });
    let neutral = case.neutral_section.iter().map(|n| {
        // On the contact wire of the insulator it starts on.
        let on = (case.section_insulator.iter())
            .find(|s| (s.extent_m()[0]..=s.extent_m()[1]).contains(&n.start_m))
            .map_or([n.start_m, n.start_m], |s| s.extent_m());
        HardSpot {
            kind: HardSpotKind::NeutralSection,
            section_m: [n.start_m, n.end_m],
            wire: wire(on),
        }
    });
    insulators.chain(neutral).collect()
}

/// The section insulators of a case (issue 55): each on the contact wire of the tension length
/// that holds it, in every modelled translation (vertical, lateral), adding its mass and its
/// bending stiffness over the wire's (`model::elements::section_insulator`).
fn build_section_insulators(case: &Case, dirs: &Dirs) -> Result<SectionInsulators, CaseError> {
    let mut out = Vec::new();
    for (i, s) in case.section_insulator.iter().enumerate() {
        let k = crate::input::hard_spots::tension_length_under(case, s.extent_m()).map_err(
            |reason| {
                crate::input::bounds::inv(
                    &format!("section_insulator[{i}].position_m"),
                    s.position_m,
                    &reason,
                )
            },
        )?;
        let catenary = case.line.as_ref().map_or_else(
            || case.catenary.clone(),
            |l| l.tension_lengths[k].catenary(&case.catenary),
        );
        let wire = 2 * k + CONTACT;
        let c = curvature_stiffness_n_per_m(s.ei_nm2 - catenary.contact_wire.ei_nm2, s.length_m);
        for &dir in dirs.all.iter().filter(|&&d| d != Direction::Torsional) {
            let at = |x_m| Attach::Wire { wire, dir, x_m };
            let [a, b] = s.extent_m();
            out.push(SectionInsulator {
                at: [at(a), at(s.position_m), at(b)],
                mass_kg: s.mass_kg,
                curvature_n_per_m: c,
            });
        }
    }
    Ok(SectionInsulators(out))
}

/// One dropper of the model, where it hangs, with its static data.
#[derive(Debug, Clone, Copy)]
struct Hanger {
    x_m: f64,
    length_m: f64,
    preload_n: f64,
    stiffness_n_per_m: f64,
    stitch: Option<StitchStatic>,
}

/// One tension length placed on the line: its catenary (with its own overrides), where its
/// wires begin and how long they are, its droppers and its interior supports.
struct PlacedTl {
    catenary: CatenaryCase,
    start_m: f64,
    length_m: f64,
    hangers: Vec<Hanger>,
    /// The interior supports (where the messenger supports and steady arms are), m.
    interior_supports_m: Vec<f64>,
    /// Every support of it, ends included, m.
    supports_m: Vec<f64>,
    /// The index of its first support among the line's.
    first_support: usize,
    /// The steady arm's static force at each interior support, N.
    arm_force_n: Vec<f64>,
}

/// Where a case's droppers and supports are and what the static shape gives them: the one
/// hand-over from either static solution (the span-periodic `[catenary]`, or a `[line]`'s
/// tension lengths) to the wires and elements.
struct Placed {
    tls: Vec<PlacedTl>,
    /// Every support of the line, ends included, model coordinates, m.
    supports_m: Vec<f64>,
    shape: StaticShape,
    /// The span when the layout repeats every span (the fast sampler's periodic path).
    span_m: Option<f64>,
}

/// A dropper shorter than 5 cm (or not finite): the static messenger sags onto the contact wire.
fn too_short(field: String, value: String, i: usize, len: f64) -> CaseError {
    CaseError::Invalid {
        field,
        value,
        reason: format!(
            "the static messenger sags onto the contact wire: dropper {} would be {:.3} m long",
            i + 1,
            len
        ),
    }
}

/// [`place`] on a `[line]`: each tension length's statics, droppers and supports.
fn place_line(c: &CatenaryCase, line: &crate::input::case::LineCase) -> Result<Placed, CaseError> {
    let starts = line.starts_m();
    let mut tls = Vec::new();
    let mut statics = Vec::new();
    // The sampler's periodic path needs the points to repeat every span: every span of
    // every tension length of one length with one dropper layout (heights do not matter:
    // they move no point).
    let mut repeats = true;
    let mut first_span: Option<SpanLayout> = None;
    for (k, t) in line.tension_lengths.iter().enumerate() {
        let ck = t.catenary(c);
        let mut d = tension_length_design(&ck, t);
        d.start_m = starts[k];
        let ns = d.spans.len();
        // The overlaps' out-of-running wires rise toward their anchors.
        if let Some(o) = k.checked_sub(1).and_then(|j| line.overlaps.get(j)) {
            d.contact_height_m[0] += o.rise_m;
        }
        if let Some(o) = line.overlaps.get(k) {
            d.contact_height_m[ns] += o.rise_m;
        }
        let st = TensionLengthStatics::solve(&d);
        for (i, h) in st.droppers.iter().enumerate() {
            if !h.length_m.is_finite() || h.length_m <= 0.05 {
                return Err(too_short(
                    format!("line.tension_lengths[{k}].encumbrance_m[{}]", h.span),
                    d.encumbrance_m[h.span].to_string(),
                    i,
                    h.length_m,
                ));
            }
        }
        let first = &d.spans[0];
        let reference = first_span.get_or_insert_with(|| first.clone());
        repeats = repeats
            && d.spans.iter().all(|s| {
                s.length_m == reference.length_m && s.dropper_x_m == reference.dropper_x_m
            });
        let stiffness = |len: f64| dropper_stiffness(&ck, len);
        tls.push(PlacedTl {
            start_m: starts[k],
            length_m: st.supports_m[ns] - st.supports_m[0],
            hangers: st
                .droppers
                .iter()
                .map(|h| Hanger {
                    x_m: h.x_m,
                    length_m: h.length_m,
                    preload_n: h.force_contact_n,
                    stiffness_n_per_m: stiffness(h.length_m),
                    stitch: h.stitch,
                })
                .collect(),
            interior_supports_m: st.supports_m[1..ns].to_vec(),
            supports_m: st.supports_m.clone(),
            first_support: line.first_support(k),
            arm_force_n: st.arm_force_n[1..ns].to_vec(),
            catenary: ck,
        });
        statics.push(st);
    }
    Ok(Placed {
        tls,
        supports_m: line.supports_m(),
        shape: StaticShape::Line(Box::new(LineStatics::new(statics))),
        span_m: first_span.filter(|_| repeats).map(|s| s.length_m),
    })
}

/// The droppers and supports of `case` from its static shape; an error when the messenger would
/// sag onto the contact wire.
fn place(case: &Case) -> Result<Placed, CaseError> {
    let c = &case.catenary;
    if let Some(line) = &case.line {
        return place_line(c, line);
    }
    let stat = StaticSolution::solve(&static_design(c));
    for (i, len) in stat.dropper_length_m.iter().enumerate() {
        if !len.is_finite() || *len <= 0.05 {
            return Err(too_short(
                "catenary.encumbrance_m".into(),
                c.encumbrance_m.to_string(),
                i,
                *len,
            ));
        }
    }
    let mut hangers = Vec::with_capacity(c.spans * c.droppers.positions_m.len());
    for s in 0..c.spans {
        for (i, &d) in c.droppers.positions_m.iter().enumerate() {
            hangers.push(Hanger {
                x_m: s as f64 * c.span_m + d,
                length_m: stat.dropper_length_m[i],
                preload_n: stat.dropper_force_contact_n[i],
                stiffness_n_per_m: dropper_stiffness(c, stat.dropper_length_m[i]),
                stitch: stat.stitch[i],
            });
        }
    }
    Ok(Placed {
        tls: vec![PlacedTl {
            catenary: c.clone(),
            start_m: 0.0,
            length_m: case.length_m(),
            hangers,
            interior_supports_m: (1..c.spans).map(|s| s as f64 * c.span_m).collect(),
            supports_m: (0..=c.spans).map(|s| s as f64 * c.span_m).collect(),
            first_support: 0,
            arm_force_n: vec![stat.arm_force_n; c.spans.saturating_sub(1)],
        }],
        supports_m: (0..=c.spans).map(|s| s as f64 * c.span_m).collect(),
        shape: StaticShape::Catenary(Box::new(stat)),
        span_m: Some(c.span_m),
    })
}

/// A dropper's stiffness in tension (Eq. 15): the catenary's, or `EA / length` with its static
/// length, N/m.
fn dropper_stiffness(c: &CatenaryCase, length_m: f64) -> f64 {
    match (c.droppers.stiffness_n_per_m, c.droppers.ea_n) {
        (Some(k), _) => k,
        (None, Some(ea)) => ea / length_m,
        (None, None) => unreachable!("validated"),
    }
}

/// Dropper clamp masses and half of each dropper's mass smeared into the wires' mass per metre
/// (see [`model_from_case`]): `(contact wire, messenger)` of tension length `tl` with the wire
/// data of `c`, kg/m. Stitch droppers' upper clamps are the stitch nodes (own degrees of
/// freedom). The span-periodic catenary sums one span's droppers (`periodic_span_m`).
fn smeared_masses(c: &CatenaryCase, tl: &PlacedTl, periodic_span_m: Option<f64>) -> (f64, f64) {
    match periodic_span_m {
        Some(span) => {
            let nd = c.droppers.positions_m.len() as f64;
            let mean_len = tl.hangers[..c.droppers.positions_m.len()]
                .iter()
                .map(|h| h.length_m)
                .sum::<f64>()
                / nd;
            let half_dropper = 0.5 * c.droppers.mass_per_m_kg * mean_len;
            let rho_c = c.contact_wire.mass_per_m_kg
                + nd * (c.droppers.clamp_mass_contact_kg + half_dropper) / span;
            let n_on_messenger =
                nd - c.stitch_wire.as_ref().map_or(0, |st| st.droppers.len()) as f64;
            let rho_m = c.messenger.mass_per_m_kg
                + (n_on_messenger * c.droppers.clamp_mass_messenger_kg + nd * half_dropper) / span;
            (rho_c, rho_m)
        }
        None => {
            let (mut on_c, mut on_m) = (0.0, 0.0);
            for h in &tl.hangers {
                let half = 0.5 * c.droppers.mass_per_m_kg * h.length_m;
                on_c += c.droppers.clamp_mass_contact_kg + half;
                on_m += half
                    + if h.stitch.is_some() {
                        0.0
                    } else {
                        c.droppers.clamp_mass_messenger_kg
                    };
            }
            (
                c.contact_wire.mass_per_m_kg + on_c / tl.length_m,
                c.messenger.mass_per_m_kg + on_m / tl.length_m,
            )
        }
    }
}

/// The static design of a `[line]`'s tension length `t`, with what it does not override from
/// the catenary `c`.
pub fn tension_length_design(c: &CatenaryCase, t: &TensionLengthCase) -> TensionLengthDesign {
    let lengths = t.span_lengths_m();
    let n = lengths.len();
    let stitched: Vec<usize> = c
        .stitch_wire
        .as_ref()
        .map_or(Vec::new(), |s| s.droppers.clone());
    let spans = lengths
        .iter()
        .enumerate()
        .map(|(j, &len)| {
            let d = t.droppers_of_span(j, len, &c.droppers.positions_m, c.span_m);
            SpanLayout {
                length_m: len,
                presag_m: presag_values(&c.presag, len, &d),
                on_stitch: (0..d.len()).map(|i| stitched.contains(&i)).collect(),
                dropper_x_m: d,
            }
        })
        .collect();
    let per_support = |v: &[f64], default: f64| {
        if v.is_empty() {
            vec![default; n + 1]
        } else {
            v.to_vec()
        }
    };
    TensionLengthDesign {
        start_m: 0.0,
        spans,
        contact_height_m: per_support(&t.contact_height_m, 0.0),
        encumbrance_m: per_support(&t.encumbrance_m, c.encumbrance_m),
        arm_holds_contact: c.steady_arm.static_support,
        contact_mass_per_m_kg: c.contact_wire.mass_per_m_kg,
        contact_tension_n: c.contact_wire.tension_n,
        messenger_mass_per_m_kg: c.messenger.mass_per_m_kg,
        messenger_tension_n: c.messenger.tension_n,
        dropper_mass_per_m_kg: c.droppers.mass_per_m_kg,
        clamp_mass_contact_kg: c.droppers.clamp_mass_contact_kg,
        clamp_mass_messenger_kg: c.droppers.clamp_mass_messenger_kg,
        stitch: c.stitch_wire.as_ref().map(|s| StitchWire {
            tension_n: s.tension_n,
            length_m: s.length_m,
            clamp_mass_kg: s.clamp_mass_kg,
            mass_per_m_kg: s.mass_per_m_kg,
        }),
    }
}

/// Total static weight and support forces of a catenary model, for the balance check (N).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StaticBalance {
    /// Wire, clamp and dropper weights.
    pub weight_n: f64,
    /// Messenger supports plus steady arms (all supports, including both ends).
    pub support_n: f64,
}

/// Vertical static balance of the whole modelled catenary of `case`: every support (messenger
/// support, steady arm; the end supports carry half a span) against every weight.
pub fn static_balance(case: &Case) -> StaticBalance {
    let c = &case.catenary;
    if case.line.is_some() {
        // Tension lengths: their anchors carry the wires' end segments.
        let Ok(placed) = place(case) else {
            return StaticBalance {
                weight_n: f64::NAN,
                support_n: f64::NAN,
            };
        };
        let StaticShape::Line(ls) = &placed.shape else {
            unreachable!("a line's shape")
        };
        let (mut weight, mut support) = (0.0, 0.0);
        for (tl, s) in placed.tls.iter().zip(&ls.tension_lengths) {
            let c = &tl.catenary;
            weight += (c.contact_wire.mass_per_m_kg + c.messenger.mass_per_m_kg) * G * tl.length_m;
            for h in &s.droppers {
                let upper = match h.stitch {
                    Some(st) => st.node_mass_kg,
                    None => c.droppers.clamp_mass_messenger_kg,
                };
                weight += (c.droppers.clamp_mass_contact_kg
                    + upper
                    + c.droppers.mass_per_m_kg * h.length_m)
                    * G;
            }
            support += s.arm_force_n.iter().sum::<f64>()
                + s.support_force_n.iter().sum::<f64>()
                + [&s.contact, &s.messenger]
                    .iter()
                    .map(|p| p.end_force(true) + p.end_force(false))
                    .sum::<f64>();
        }
        return StaticBalance {
            weight_n: weight,
            support_n: support,
        };
    }
    let s = StaticSolution::solve(&static_design(c));
    let l = case.length_m();
    let n = c.spans as f64;
    let dropper_w: f64 = s
        .dropper_length_m
        .iter()
        .map(|len| len * c.droppers.mass_per_m_kg * G)
        .sum();
    // Upper clamps: on the messenger, or the stitch clamp plus half a stitch wire per stitch dropper.
    let clamps: f64 = (0..c.droppers.positions_m.len())
        .map(|i| {
            let upper = match c.stitch_wire.as_ref().filter(|st| st.droppers.contains(&i)) {
                Some(st) => st.clamp_mass_kg + 0.5 * st.mass_per_m_kg * st.length_m,
                None => c.droppers.clamp_mass_messenger_kg,
            };
            (c.droppers.clamp_mass_contact_kg + upper) * G
        })
        .sum();
    let weight = (c.contact_wire.mass_per_m_kg + c.messenger.mass_per_m_kg) * G * l
        + n * (dropper_w + clamps);
    // Support forces from the kinks of the solved shapes at a support (not from load sums): the
    // messenger's kink is the messenger-support force; the steady arm carries the contact wire's
    // kink when it holds the design height (zero in a stitched catenary). Interior supports carry
    // one span's load and the two end supports half each: n spans in all.
    let sup = s.messenger.node_forces()[0];
    let support = n * (s.arm_force_n + sup);
    StaticBalance {
        weight_n: weight,
        support_n: support,
    }
}
