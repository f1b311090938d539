//! The plausibility bounds of every quantity a case holds, in one table and one style (SI units
//! as the names say): outside the hard bounds a value is physically meaningless (an error),
//! outside the soft bounds merely unusual (a warning naming the field and the typical range).
//! Also the helpers every validator uses to say so ([`check_bound`], [`inv`], [`num`]).

use crate::error::{CaseError, Warning};

/// Plausibility bounds of a quantity: outside `hard` it is an error (physically meaningless),
/// outside `soft` a warning (legal but unusual). A hard lower bound of 0 excludes 0 when
/// `soft.0 > 0`.
#[derive(Debug, Clone, Copy)]
pub struct Bound {
    /// Outside: an error (physically meaningless).
    pub hard: (f64, f64),
    /// Outside: a warning (legal but unusual).
    pub soft: (f64, f64),
    /// Unit of the bounds, as written in messages.
    pub unit: &'static str,
    /// The typical values, as written in warnings.
    pub typical: &'static str,
}

const fn b(hard: (f64, f64), soft: (f64, f64), unit: &'static str, typical: &'static str) -> Bound {
    Bound {
        hard,
        soft,
        unit,
        typical,
    }
}

/// Span length, m.
pub const SPAN: Bound = b((1.0, 1000.0), (20.0, 100.0), "m", "27–70 m");
/// The contact-wire height at a support relative to the line's nominal height (a lowering
/// under a structure, a raising toward an anchor), m. Bounds are a guess: the hard bound is
/// where the model's small-slope wires stop meaning anything, the soft one beyond the height
/// changes of ordinary lines.
pub const CONTACT_HEIGHT_CHANGE: Bound = b((-3.0, 3.0), (-1.0, 1.0), "m", "0 to ±0.5 m");
/// Gradient of the working contact wire between two consecutive supports of a line (the height
/// change over the span; a ratio). Hard bound: 1:40 (guess: about the steepest gradient that
/// design rules allow at all, and only at walking speed; steeper, the runs of this model blow up:
/// docs/validation.md, "A line judged per tension length"); soft bound: 1:200 (guess: running
/// lines are designed at a few per mille).
pub const CONTACT_GRADIENT: Bound = b(
    (0.0, 0.025),
    (0.0, 0.005),
    "",
    "at most a few per mille on a running line",
);
/// Rise of an overlap's out-of-running contact wire at its anchor support, m. A guess: public
/// designs raise it by a few decimetres; the hard bound is where the small-slope wire stops
/// meaning anything.
pub const OVERLAP_RISE: Bound = b((0.0, 3.0), (0.0, 1.0), "m", "0.2–0.5 m");
/// Lateral separation of an overlap's two contact wires, m (a guess: public designs keep them
/// 0.1–0.5 m apart).
pub const OVERLAP_SEPARATION: Bound = b((0.0, 3.0), (0.0, 0.8), "m", "0.1–0.5 m");
/// Encumbrance (system height at the supports), m.
pub const ENCUMBRANCE: Bound = b((0.05, 20.0), (0.3, 3.5), "m", "0.3–2 m");
/// A wire's mass per length, kg/m.
pub const WIRE_MASS: Bound = b((0.01, 100.0), (0.1, 5.0), "kg/m", "0.3–2 kg/m");
/// A wire's tension, N.
pub const TENSION: Bound = b((100.0, 1.0e6), (1000.0, 60_000.0), "N", "5–40 kN");
/// A wire's bending stiffness EI, N·m².
pub const EI: Bound = b((0.0, 1.0e6), (0.0, 5000.0), "N·m²", "10–300 N·m²");
/// A dropper's stiffness in tension, N/m.
pub const DROPPER_STIFFNESS: Bound = b((0.0, 1.0e10), (1.0e3, 1.0e7), "N/m", "1e4–1e6 N/m");
/// A dropper's axial stiffness EA, N.
pub const DROPPER_EA: Bound = b((0.0, 1.0e11), (1.0e3, 1.0e8), "N", "1e5–1e7 N");
/// A dropper clamp's mass, kg.
pub const CLAMP_MASS: Bound = b((0.0, 100.0), (0.0, 5.0), "kg", "0.1–0.5 kg");
/// A dropper's mass per length, kg/m.
pub const DROPPER_MASS: Bound = b((0.0, 20.0), (0.0, 2.0), "kg/m", "0.05–0.5 kg/m");
/// Rayleigh damping's mass factor α, 1/s.
pub const RAYLEIGH_ALPHA: Bound = b((0.0, 1.0e4), (0.0, 10.0), "1/s", "0–1 1/s");
/// Rayleigh damping's stiffness factor β, s.
pub const RAYLEIGH_BETA: Bound = b((0.0, 10.0), (0.0, 0.1), "s", "0–0.02 s");
/// A modal damping ratio.
pub const MODAL_RATIO: Bound = b((0.0, 0.999_999), (0.0, 0.2), "", "0–0.05");
/// A messenger support's stiffness, N/m.
pub const SUPPORT_STIFFNESS: Bound = b((0.0, 1.0e11), (0.0, 1.0e8), "N/m", "1e2–1e6 N/m");
/// A messenger support's damping, N·s/m.
pub const SUPPORT_DAMPING: Bound = b((0.0, 1.0e8), (0.0, 1.0e5), "N·s/m", "0–2000 N·s/m");
/// A steady arm's mass, kg.
pub const ARM_MASS: Bound = b((0.0, 1000.0), (0.0, 10.0), "kg", "0.5–3 kg");
/// A stitch wire's length, m.
pub const STITCH_LENGTH: Bound = b((0.1, 1000.0), (5.0, 30.0), "m", "12–25 m");
/// A stitch wire's tension, N.
pub const STITCH_TENSION: Bound = b((10.0, 1.0e6), (300.0, 10_000.0), "N", "1–5 kN");
/// The contact's penalty stiffness (Eq. 19), N/m.
pub const CONTACT_STIFFNESS: Bound = b((100.0, 1.0e9), (1.0e4, 5.0e5), "N/m", "5e4 N/m");
/// A dropper wire's cross-section, mm².
pub const DROPPER_AREA: Bound = b(
    (0.1, 1000.0),
    (2.0, 100.0),
    "mm²",
    "about 10 mm² for a dropper wire",
);
/// An S–N curve's slope m.
pub const SN_SLOPE: Bound = b((1.0, 50.0), (2.0, 20.0), "", "3–10");
/// An S–N curve's reference stress range, MPa.
pub const SN_STRESS_RANGE: Bound = b((1e-3, 1e4), (1.0, 1000.0), "MPa", "10–300 MPa");
/// Cycles to failure at an S–N curve's reference stress range.
pub const SN_CYCLES: Bound = b((1.0, 1e13), (1e3, 1e10), "cycles", "1e5–1e8");
/// Train speed, km/h.
pub const SPEED: Bound = b((0.0, 1000.0), (10.0, 400.0), "km/h", "50–350 km/h");
/// A pantograph's distance behind the leading one, m.
pub const OFFSET: Bound = b((0.0, 1.0e5), (0.0, 500.0), "m", "0–400 m");
/// A pantograph mass, kg.
pub const PANTOGRAPH_MASS: Bound = b((0.01, 1.0e4), (0.5, 100.0), "kg", "3–20 kg");
/// A pantograph spring, N/m.
pub const PANTOGRAPH_STIFFNESS: Bound = b((0.0, 1.0e9), (0.0, 1.0e6), "N/m", "0–2e4 N/m");
/// A pantograph damper, N·s/m.
pub const PANTOGRAPH_DAMPING: Bound = b((0.0, 1.0e7), (0.0, 1.0e4), "N·s/m", "0–200 N·s/m");
/// A collector strip's place on the head along the track, m.
pub const STRIP_ALONG: Bound = b(
    (-2.0, 2.0),
    (-0.5, 0.5),
    "m",
    "±0.2–0.3 m (two strips 0.4–0.6 m apart)",
);
/// A collector strip's running face above the others', m.
pub const STRIP_HEIGHT_OFFSET: Bound = b((-0.5, 0.5), (-0.02, 0.02), "m", "0 (strips worn alike)");
/// A pantograph's static uplift, N.
pub const UPLIFT: Bound = b((-1.0e4, 1.0e4), (20.0, 500.0), "N", "50–150 N");
/// A pantograph's aerodynamic force at the run's speed, N.
pub const AERO: Bound = b((-1.0e4, 1.0e4), (-50.0, 300.0), "N", "0–100 N");
/// A constant moving force, N.
pub const MOVING_FORCE: Bound = b((-1.0e5, 1.0e5), (-1000.0, 1000.0), "N", "50–300 N");
/// The lateral force of a constant moving force (a probe), N.
pub const MOVING_LATERAL_FORCE: Bound = b((-1.0e5, 1.0e5), (-1000.0, 1000.0), "N", "0–100 N");
/// The time step, s.
pub const DT: Bound = b((0.0, 0.01), (1.0e-5, 2.0e-3), "s", "0.2–1 ms");

// Lateral and torsional motion, wind, ice, pantograph heads.
/// A wire's diameter, m.
pub const DIAMETER: Bound = b((0.0, 0.2), (0.004, 0.04), "m", "0.008–0.02 m");
/// A wire's torsional stiffness GJ, N·m².
pub const GJ: Bound = b((0.0, 1.0e6), (1.0, 5000.0), "N·m²", "20–400 N·m²");
/// A wire's polar mass moment per length, kg·m.
pub const POLAR: Bound = b((0.0, 1.0), (1.0e-7, 1.0e-3), "kg·m", "1e-5–1e-4 kg·m");
/// An aerodynamic coefficient (drag, lift or moment).
pub const COEFF: Bound = b(
    (-10.0, 10.0),
    (-3.0, 3.0),
    "",
    "C_D 0.8–1.3, C_L and C_M within ±0.5",
);
/// A contact wire's stagger at a support, m.
pub const STAGGER: Bound = b((-2.0, 2.0), (-0.45, 0.45), "m", "±0.2–0.4 m");
/// A track curve's radius (its magnitude), m. Hard: the chord's bow is taken to second order in
/// the span over the radius, so a span may be at most a fifth of the radius (checked beside);
/// 20 m is below any railway's. Soft: main lines rarely go below 300 m (guess: EN 13803's
/// ranges for the speeds this tool is for are far above it).
pub const TRACK_RADIUS: Bound = b((20.0, 1.0e7), (300.0, 1.0e5), "m", "300 m and more");
/// A track's cant, m over 1.5 m. Hard: 0.25 m (guess: beyond any line's); soft 0.18 m (guess:
/// about the largest cant of European main lines, EN 13803).
pub const CANT: Bound = b((0.0, 0.25), (0.0, 0.18), "m", "0–0.16 m");
/// A lateral registration or support stiffness, N/m.
pub const LAT_STIFF: Bound = b((0.0, 1.0e11), (0.0, 1.0e8), "N/m", "1e4–1e6 N/m");
/// A torsional stiffness of a clamp or registration, N·m/rad.
pub const TORS_STIFF: Bound = b((0.0, 1.0e6), (0.0, 500.0), "N·m/rad", "0–100 N·m/rad");
/// A clamp's or the contact point's eccentricity, m.
pub const ECC: Bound = b((-0.5, 0.5), (-0.05, 0.05), "m", "0–0.02 m");
/// Contact-wire height above the rail, m.
pub const WIRE_HEIGHT: Bound = b((0.5, 100.0), (3.0, 10.0), "m", "4.9–6.5 m");
/// Density of ice, kg/m³.
pub const ICE_DENSITY: Bound = b(
    (0.0, 1000.0),
    (100.0, 917.0),
    "kg/m³",
    "300 (rime) – 900 (glaze) kg/m³",
);
/// Radial ice thickness, m.
pub const ICE: Bound = b((0.0, 0.5), (0.0, 0.05), "m", "0–0.03 m radial");
/// Mean wind speed, m/s.
pub const WIND: Bound = b((0.0, 120.0), (0.0, 45.0), "m/s", "0–40 m/s");
/// Reference height of the wind profile, m.
pub const REF_HEIGHT: Bound = b((0.1, 1000.0), (2.0, 100.0), "m", "10 m");
/// Terrain roughness length, m.
pub const ROUGH: Bound = b((0.0, 10.0), (1.0e-4, 2.0), "m", "0.003–1 m");
/// Exponent of a power-law wind profile.
pub const EXPONENT: Bound = b((0.0, 1.0), (0.05, 0.5), "", "0.1–0.3");
/// Wind direction to the track, °.
pub const YAW: Bound = b(
    (-360.0, 360.0),
    (-180.0, 180.0),
    "°",
    "90° (square to the track)",
);
/// Turbulence intensity.
pub const TI: Bound = b((0.0, 1.0), (0.0, 0.4), "", "0.05–0.25");
/// Turbulence integral length scale, m.
pub const LENGTH_SCALE: Bound = b((0.0, 10_000.0), (5.0, 500.0), "m", "30–300 m");
/// Davenport coherence decay constant.
pub const DECAY: Bound = b((0.0, 1000.0), (2.0, 30.0), "", "7–16");
/// Air density, kg/m³.
pub const AIR: Bound = b((0.0, 10.0), (0.9, 1.5), "kg/m³", "1.225 kg/m³");
/// Spacing of the wind grid, m.
pub const GRID: Bound = b((0.0, 1000.0), (0.5, 20.0), "m", "2–10 m");
/// Time step of the wind field, s.
pub const WIND_DT: Bound = b((0.0, 1.0), (0.002, 0.1), "s", "0.01–0.05 s");
/// A pantograph head's half-width, m.
pub const HALF_WIDTH: Bound = b(
    (0.0, 2.0),
    (0.3, 1.2),
    "m",
    "0.8 m (1600 mm head), 0.975 m (1950 mm)",
);

// Contact-wire irregularity.
/// RMS of a contact-wire irregularity, m.
pub const IRREGULARITY_RMS: Bound = b((0.0, 0.5), (0.0, 0.03), "m", "0–20 mm");
/// A wavelength of an irregularity PSD, m.
pub const IRREGULARITY_WAVELENGTH: Bound = b((0.0, 1.0e5), (0.1, 1000.0), "m", "1–200 m");
/// A tabulated deviation of the contact wire, m.
pub const IRREGULARITY_DEVIATION: Bound = b((-1.0, 1.0), (-0.1, 0.1), "m", "within ±30 mm");
/// A section insulator's length, m (a guess from makers' data sheets: 1–3 m for high-speed
/// designs; the hard bound where a point element stops meaning anything).
pub const INSULATOR_LENGTH: Bound = b((0.1, 20.0), (0.5, 5.0), "m", "1–3 m");
/// A section insulator's mass, kg (a guess: makers' sheets give 5–25 kg).
pub const INSULATOR_MASS: Bound = b((0.0, 500.0), (0.0, 50.0), "kg", "5–25 kg");
/// A section insulator's bending stiffness, N·m² (a guess: a wire's is 10²–10³, a glass-fibre
/// rod with its runners a few 10⁴).
pub const INSULATOR_EI: Bound = b((0.0, 1.0e8), (0.0, 1.0e6), "N·m²", "10³–10⁵ N·m²");
/// A section insulator's pre-lift (its runners above the wire's design height), m (a guess:
/// installation rules ask for a few centimetres at most).
pub const INSULATOR_PRELIFT: Bound = b((-0.2, 0.2), (-0.01, 0.05), "m", "0–30 mm");
/// A neutral section's dead length, m (a guess: short neutral sections are a few metres,
/// phase breaks up to about 400 m).
pub const NEUTRAL_SECTION_LENGTH: Bound = b((0.1, 5000.0), (1.0, 500.0), "m", "a few m to 400 m");

/// Check `v` of `field` against `b`: an error outside the hard bounds, a warning outside the
/// soft ones.
pub fn check_bound(w: &mut Vec<Warning>, field: &str, v: f64, b: &Bound) -> Result<(), CaseError> {
    check(w, field, v, b)
}

fn check(w: &mut Vec<Warning>, field: &str, v: f64, b: &Bound) -> Result<(), CaseError> {
    let (lo, hi) = b.hard;
    let unit = if b.unit.is_empty() {
        String::new()
    } else {
        format!(" {}", b.unit)
    };
    // A hard lower bound of 0 with a positive soft one excludes 0 itself.
    let strict_zero = lo == 0.0 && b.soft.0 > 0.0;
    let low_ok = if strict_zero { v > 0.0 } else { v >= lo };
    if !v.is_finite() || !low_ok {
        let rel = if strict_zero {
            "> 0".to_string()
        } else if lo == 0.0 {
            "≥ 0".to_string()
        } else {
            format!("≥ {}{unit}", num(lo))
        };
        return Err(inv(
            field,
            num(v),
            &format!("must be a finite number {rel}"),
        ));
    }
    if v > hi {
        return Err(inv(
            field,
            num(v),
            &format!(
                "physically meaningless above {}{unit} (typical: {})",
                num(hi),
                b.typical
            ),
        ));
    }
    if v < b.soft.0 || v > b.soft.1 {
        w.push(Warning(format!(
            "{field} = {}{unit} is unusual (typical: {}); check the value and its unit",
            num(v),
            b.typical
        )));
    }
    Ok(())
}

/// A number for a message: plain where that is short, in exponent form where it is tiny or huge.
pub fn num(v: f64) -> String {
    if v != 0.0 && v.is_finite() && !(1e-4..1e7).contains(&v.abs()) {
        format!("{v:e}")
    } else {
        format!("{v}")
    }
}

/// An invalid value of `field`: the error every validator returns.
pub fn inv(field: &str, value: impl std::fmt::Display, reason: &str) -> CaseError {
    // A number such as 1e-300 is shown as such, not with its 300 decimals.
    let text = value.to_string();
    let value = match text.parse::<f64>() {
        Ok(v) if text.len() > 24 => num(v),
        _ => text,
    };
    CaseError::Invalid {
        field: field.to_string(),
        value,
        reason: reason.to_string(),
    }
}

/// Modes per metre from which the contact wire's static lateral blow-off under a steady
/// crosswind lies within 1 % of its converged value (0.7 %; the mode-density study of
/// docs/validation.md, `examples/mode_density_study.rs`: 0.67 per metre is 1.6 % low).
pub const LATERAL_MODES_PER_M_FOR_1_PCT: f64 = 1.25;

/// Modes per metre from which the ice's static sag (`Σ T sag` over half a span against its closed
/// form) lies within 1 % (−0.88 % at 2 per metre with the presets' bending stiffness, −1.46 % at
/// 1 per metre: the sine series falls short by `8/(π² ρ S)` at the kinks of the support
/// reactions; docs/validation.md, `tests/suite/steady_loads.rs`).
pub const ICE_MODES_PER_M_FOR_1_PCT: f64 = 2.0;
