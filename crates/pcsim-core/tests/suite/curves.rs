//! Issue 41, item 2: curved track. The wires run straight between registrations, so relative to
//! the curved track they bow toward the centre; each registration holds the tension's change of
//! direction (the pull-off force); a canted track moves the pantograph's head toward the centre.
//! Checked against an independent construction in plane Cartesian coordinates (the arc, its
//! registration points, the chords between them), and a very large radius against the straight
//! track.

use crate::common;

use pcsim_core::compile::Setup;
use pcsim_core::input::case::Case;
use pcsim_core::model::dof::Direction;
use pcsim_core::model::WireRole;
use pcsim_core::{run_case, CaseError};

fn curved(radius_m: Option<f64>, cant_m: f64) -> Case {
    let mut c = common::short_preset("stitched-2018-like-3d", 10, 250.0);
    let l = c.catenary.lateral.as_mut().unwrap();
    l.track_radius_m = radius_m;
    l.cant_m = cant_m;
    c
}

/// The track at arc length `x` on a curve of radius `r` (centre at `(0, r)`) and the unit normal
/// toward the centre there.
fn track(r: f64, x: f64) -> ([f64; 2], [f64; 2]) {
    let th = x / r;
    ([r * th.sin(), r - r * th.cos()], [-th.sin(), th.cos()])
}

/// The offset toward the centre, measured along the track's normal at `x`, of the straight
/// chord from `p` to `q`.
fn chord_offset(r: f64, x: f64, p: [f64; 2], q: [f64; 2]) -> f64 {
    let (t, n) = track(r, x);
    // t + y n = p + λ (q − p): two equations in (y, λ).
    let d = [q[0] - p[0], q[1] - p[1]];
    let det = n[0] * (-d[1]) - n[1] * (-d[0]);
    let rhs = [p[0] - t[0], p[1] - t[1]];
    (rhs[0] * (-d[1]) - rhs[1] * (-d[0])) / det
}

/// The static lateral profile of both wires in a 1 000 m curve is the polygon between the
/// registrations, measured from the curved track, within 1 mm (the issue's check; the model's
/// bow is second order in span/radius) at every metre of every span.
#[test]
fn issue_41_the_static_lateral_profile_in_a_curve_is_the_polygon_between_registrations() {
    for r in [1000.0, -1000.0, 4000.0] {
        let case = curved(Some(r), 0.0);
        let setup = Setup::from_case(&case).unwrap();
        let m = &setup.model;
        let geo = m.lateral.as_ref().unwrap();
        let s = geo.uniform_span_m.unwrap();
        let mut worst: f64 = 0.0;
        for role in [WireRole::Contact, WireRole::Messenger] {
            let w = m.wire_index(role).unwrap();
            for i in 0..geo.lines[0].stagger_m.len() - 1 {
                // Arc length along the curve; offsets positive toward positive stagger, which is
                // toward the centre when r > 0.
                let sign = r.signum();
                let (ra, xa, xb) = (r.abs(), i as f64 * s, (i + 1) as f64 * s);
                let reg = |x: f64, y: f64| {
                    let (t, n) = track(ra, x);
                    [t[0] + sign * y * n[0], t[1] + sign * y * n[1]]
                };
                let (p, q) = (
                    reg(xa, geo.lines[0].stagger_m[i]),
                    reg(xb, geo.lines[0].stagger_m[i + 1]),
                );
                for k in 1..s as usize {
                    let x = xa + k as f64;
                    let exact = sign * chord_offset(ra, x, p, q);
                    let model = m.static_height(w, Direction::Lateral, x, 0.0);
                    worst = worst.max((model - exact).abs());
                }
            }
        }
        assert!(worst < 1e-3, "radius {r} m: {worst} m from the polygon");
        // And the bow is there: mid-span of a span between equal staggers is s²/(8R) inside.
        let bow = s * s / (8.0 * r);
        let mid = m.static_height(
            m.wire_index(WireRole::Contact).unwrap(),
            Direction::Lateral,
            0.5 * s,
            0.0,
        );
        let chord = 0.5 * (geo.lines[0].stagger_m[0] + geo.lines[0].stagger_m[1]);
        assert!(
            (mid - chord - bow).abs() < 1e-12,
            "radius {r}: bow {} against {bow}",
            mid - chord
        );
    }
}

/// At every interior registration the static lateral force is the tension's change of
/// direction: against the exact one from the Cartesian chords (`T (u_next − u_prev) · n`) within
/// 0.1 % of the largest, for both wires, and on a straight track the stagger's kink alone.
#[test]
fn issue_41_the_pull_off_balances_the_tensions_change_of_direction() {
    for r in [1000.0, 4000.0] {
        let setup = Setup::from_case(&curved(Some(r), 0.0)).unwrap();
        let m = &setup.model;
        let geo = m.lateral.as_ref().unwrap();
        let s = geo.uniform_span_m.unwrap();
        for role in [WireRole::Contact, WireRole::Messenger] {
            let t = m.wires[m.wire_index(role).unwrap()].section.tension_n;
            let model = geo.registration_forces_n(0, t);
            let reg = |i: usize| {
                let (p, n) = track(r, i as f64 * s);
                [
                    p[0] + geo.lines[0].stagger_m[i] * n[0],
                    p[1] + geo.lines[0].stagger_m[i] * n[1],
                ]
            };
            let unit = |a: [f64; 2], b: [f64; 2]| {
                let d = [b[0] - a[0], b[1] - a[1]];
                let l = d[0].hypot(d[1]);
                [d[0] / l, d[1] / l]
            };
            let scale = model.iter().map(|f| f.abs()).fold(0.0, f64::max);
            for (k, f) in model.iter().enumerate() {
                let i = k + 1;
                let (u0, u1) = (unit(reg(i - 1), reg(i)), unit(reg(i), reg(i + 1)));
                let n = track(r, i as f64 * s).1;
                let exact = t * ((u1[0] - u0[0]) * n[0] + (u1[1] - u0[1]) * n[1]);
                assert!(
                    (f - exact).abs() < 1e-3 * scale,
                    "radius {r}, {role:?}, registration {i}: {f} N against {exact} N"
                );
            }
            // The ±stagger pattern's kinks alternate: two neighbours' mean is the pull-off
            // `T s / R` alone.
            for pair in model.windows(2) {
                let mean = 0.5 * (pair[0] + pair[1]);
                let want = t * s / r;
                assert!((mean - want).abs() < 1e-9 * want, "{mean} vs {want}");
            }
        }
    }
}

/// A curve of very large radius runs as the straight track: the vertical statistics to 1e-9,
/// the contact point's lateral positions within the chord's bow `s²/(8R)`.
#[test]
fn issue_41_a_curve_of_very_large_radius_runs_as_the_straight_track() {
    let r = 1.0e7;
    let a = run_case(&curved(None, 0.0), &mut |_| true).unwrap();
    let b = run_case(&curved(Some(r), 0.0), &mut |_| true).unwrap();
    common::same_statistics(&a, &b, 1e-9, "still air");
    let (worst, bow) = lateral_apart(&a, &b, r);
    assert!(
        worst <= bow + 1e-12 && worst > 0.0,
        "{worst} m, bow {bow} m"
    );
    assert!(a.curve.is_none() && b.curve.is_some());
}

/// The largest difference of two runs' lateral traces of the first pantograph, m, and the
/// chord's bow `s²/(8R)` on a curve of radius `r` (60 m spans), m.
fn lateral_apart(a: &pcsim_core::RunOutput, b: &pcsim_core::RunOutput, r: f64) -> (f64, f64) {
    let worst = (a.pantographs[0].lateral_m.iter())
        .zip(&b.pantographs[0].lateral_m)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    (worst, 60.0f64.powi(2) / (8.0 * r))
}

/// On a canted curve the head stands `h · cant / 1.5` toward the centre: the wire is where it
/// was (the same lateral trace), and the contact point's position on the head is that trace less
/// the offset (the statistics and the verdicts read it there).
#[test]
fn issue_41_a_canted_curve_moves_the_head_not_the_wire() {
    let (r, cant) = (1000.0, 0.06);
    let flat = run_case(&curved(Some(r), 0.0), &mut |_| true).unwrap();
    let canted = run_case(&curved(Some(r), cant), &mut |_| true).unwrap();
    let h = curved(None, 0.0)
        .catenary
        .lateral
        .unwrap()
        .contact_wire_height_m;
    let offset = h * cant / 1.5;
    let c = canted.curve.as_ref().unwrap();
    assert!((c.head_offset_m - offset).abs() < 1e-15);
    assert_eq!(
        flat.pantographs[0].lateral_m,
        canted.pantographs[0].lateral_m
    );
    let p = &canted.pantographs[0];
    let section = canted.analysis_m;
    let want = (p.lateral_m.iter().zip(&p.position_m))
        .filter(|(_, x)| **x >= section[0] && **x <= section[1])
        .map(|(z, _)| (z - offset).abs())
        .fold(0.0, f64::max);
    let got = p.lateral.as_ref().unwrap().max_lateral_offset_mm;
    assert!(
        (got - want * 1e3).abs() < 1e-9,
        "{got} mm on the head, want {} mm",
        want * 1e3
    );
}

/// A span longer than a fifth of the radius and a cant without a curve are refused, each naming
/// its field.
#[test]
fn issue_41_curves_refuse_what_they_cannot_model_by_name() {
    let field = |c: &Case| match c.validate() {
        Err(CaseError::Invalid { field, .. }) => field,
        other => panic!("{other:?}"),
    };
    assert_eq!(
        field(&curved(Some(250.0), 0.0)),
        "catenary.lateral.track_radius_m"
    );
    assert_eq!(field(&curved(None, 0.05)), "catenary.lateral.cant_m");
}

/// The crosswind preset (25 m/s, Kaimal turbulence, 90° to the track at its start) on the curve
/// of [`curved`].
fn windy_curve(radius_m: Option<f64>, yaw_deg: f64) -> Case {
    let mut c = curved(radius_m, 0.0);
    let w = pcsim_core::presets::load("stitched-2018-like-3d-crosswind")
        .unwrap()
        .0;
    c.wind = w.wind;
    c.wind.as_mut().unwrap().yaw_deg = yaw_deg;
    c.catenary.messenger.section = w.catenary.messenger.section;
    c.catenary.contact_wire.section = w.catenary.contact_wire.section;
    c
}

/// On a curve the wind keeps its direction while the track turns: the part normal to the track
/// at every grid point is `sin(ψ − θ)`, `θ = (x − x₀)/R` the arc's turn since the first support
/// (closed form), for both signs of the radius and a wind at 60° to the track; on a straight
/// track there is no per-point normal (the yaw's `sin ψ` everywhere).
#[test]
fn issue_41_a_crosswinds_normal_part_turns_with_the_track() {
    for (r, yaw) in [
        (1000.0, 90.0),
        (-1000.0, 90.0),
        (2000.0, 60.0),
        (2000.0, -60.0),
    ] {
        let (m, _) = pcsim_core::compile::model_from_case(&windy_curve(Some(r), yaw)).unwrap();
        let wl = m.wind.as_ref().unwrap();
        let x0 = m.lateral.as_ref().unwrap().supports_m[0];
        assert_eq!(wl.normal_by_grid.len(), wl.field.x_m.len());
        let psi = yaw.to_radians();
        for (&x, &s) in wl.field.x_m.iter().zip(&wl.normal_by_grid) {
            let want = (psi - (x - x0) / r).sin();
            assert!(
                (s - want).abs() < 1e-12,
                "R {r} yaw {yaw} at {x} m: {s} vs {want}"
            );
        }
        // The pressure there is the law at the point's normal wind.
        let g = wl.normal_by_grid.len() - 1;
        let v = wl.normal_by_grid[g] * wl.wires[0].mean_along_m_s;
        let want = 0.5 * wl.air_density_kg_m3 * v * v.abs();
        assert!((wl.mean_pressure_at(0, g) - want).abs() <= 1e-12 * want.abs());
    }
    let (m, _) = pcsim_core::compile::model_from_case(&windy_curve(None, 90.0)).unwrap();
    assert!(m.wind.as_ref().unwrap().normal_by_grid.is_empty());
}

/// A crosswind on a curve of very large radius runs as on the straight track: the vertical
/// statistics within 1e-7 (the wind's normal part differs by `θ²/2`, 1e-9, and the wire by the
/// bow `s²/(8R)`), the contact point's lateral trace within the bow and a micrometre.
#[test]
fn issue_41_a_crosswind_on_a_curve_of_very_large_radius_runs_as_on_the_straight_track() {
    let r = 1.0e7;
    let a = run_case(&windy_curve(None, 90.0), &mut |_| true).unwrap();
    let b = run_case(&windy_curve(Some(r), 90.0), &mut |_| true).unwrap();
    common::same_statistics(&a, &b, 1e-7, "in wind");
    let (worst, bow) = lateral_apart(&a, &b, r);
    assert!(worst <= bow + 1e-6, "{worst} m, bow {bow} m");
}

/// A curve tight enough that the wind crosses the track's direction: a wind at 20° to the track
/// at its start on a 500 m radius curving toward it (the track turns 1.2 rad over the model, so
/// the normal part changes sign along it) runs to the end with finite forces and positions.
#[test]
fn issue_41_a_crosswind_that_crosses_the_track_on_a_tight_curve_runs() {
    let mut c = windy_curve(Some(500.0), 20.0);
    c.catenary.span_m = 60.0;
    // The 60 m spans bow 0.9 m toward the centre on 500 m: the stagger is laid 0.45 m outside
    // at every registration (design practice on tight curves), so the wire stays on the head.
    let l = c.catenary.lateral.as_mut().unwrap();
    l.stagger_m = None;
    l.stagger_list_m = Some(vec![-0.45, -0.45]);
    let (m, _) = pcsim_core::compile::model_from_case(&c).unwrap();
    let wl = m.wind.as_ref().unwrap();
    let (lo, hi) = wl
        .normal_by_grid
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &s| {
            (a.min(s), b.max(s))
        });
    assert!(lo < -0.3 && hi > 0.3, "normal part from {lo} to {hi}");
    let out = run_case(&c, &mut |_| true).unwrap();
    let s = out.pantographs[0].stats.unwrap();
    assert!(s.mean_n.is_finite() && s.std_n.is_finite() && s.std_n > 0.0);
    assert!(out.pantographs[0].lateral_m.iter().all(|y| y.is_finite()));
}

/// On a canted curve the stagger's usual range is about the head's centre: the curve preset's
/// staggers (0.53 ± 0.2 m from the track's centre line) give no warning; the straight track's
/// ±0.3 m there lies up to 0.83 m from the head's centre and is warned about, naming the field.
#[test]
fn issue_41_on_a_canted_curve_the_stagger_is_judged_from_the_heads_centre() {
    let (preset, _) = pcsim_core::presets::load("stitched-2018-like-3d-curve").unwrap();
    let stagger_warnings = |c: &Case| {
        c.validate()
            .unwrap()
            .into_iter()
            .filter(|w| w.0.contains("stagger"))
            .count()
    };
    assert_eq!(stagger_warnings(&preset), 0);
    let mut c = preset.clone();
    let l = c.catenary.lateral.as_mut().unwrap();
    l.stagger_list_m = None;
    l.stagger_m = Some(0.3);
    let w = c.validate().unwrap();
    assert!(
        w.iter()
            .any(|w| w.0.contains("catenary.lateral.stagger_m") && w.0.contains("head's centre")),
        "{w:?}"
    );
}

/// The `[line]` of one tension length that spells out `case`'s `[catenary]` as runs of spans
/// `runs` (count, length, radius, cant).
fn line_of(mut case: Case, runs: &[(usize, f64, Option<f64>, Option<f64>)]) -> Case {
    use pcsim_core::input::case::{LineCase, SpanRun, TensionLengthCase};
    let t = TensionLengthCase {
        spans_m: Vec::new(),
        span_runs: runs
            .iter()
            .map(|&(count, length_m, track_radius_m, cant_m)| SpanRun {
                count,
                length_m,
                track_radius_m,
                cant_m,
            })
            .collect(),
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
    case.catenary.spans = t.n_spans();
    case.line = Some(LineCase {
        tension_lengths: vec![t],
        overlaps: Vec::new(),
    });
    case
}

/// `en50318-2002` (a simple catenary) over 10 spans in 3D with `stitched-2018-like-3d`'s
/// sections and lateral data, on a curve. A simple catenary: its periodic static shape is the
/// line's in every span; a stitched `[catenary]`'s periodic shape differs from a line's in the
/// first and last span, where the line's contact wire ends at its anchored support instead of
/// hanging from a stitch on either side (0.8 mm in the messenger's mid-span height).
fn curved_simple(radius_m: Option<f64>, cant_m: f64) -> Case {
    let d = curved(radius_m, cant_m);
    let mut c = common::short_en50318(10, 250.0);
    c.catenary.messenger.section = d.catenary.messenger.section.clone();
    c.catenary.contact_wire.section = d.catenary.contact_wire.section.clone();
    c.catenary.lateral = d.catenary.lateral.clone();
    c.run.dofs = d.run.dofs.clone();
    c
}

/// A curve on a line of one tension length, given per run of spans or by `catenary.lateral`,
/// runs as the curved `[catenary]` (the issue's exact check, a curve included): the vertical
/// statistics within 1e-9 relative; the contact point's lateral trace, the largest offset on the
/// head and the head margin within 1e-9 m; the counts equal.
#[test]
fn issue_41_a_curve_on_a_line_of_one_tension_length_runs_as_on_its_catenary() {
    let (r, cant) = (1000.0, 0.06);
    // In still air and in the crosswind preset's turbulent wind (its normal part turning along
    // the curve).
    let in_wind = |mut c: Case| {
        let w = pcsim_core::presets::load("stitched-2018-like-3d-crosswind")
            .unwrap()
            .0;
        c.wind = w.wind;
        c.catenary.messenger.section = w.catenary.messenger.section;
        c.catenary.contact_wire.section = w.catenary.contact_wire.section;
        c
    };
    for windy in [false, true] {
        let air = |c: Case| if windy { in_wind(c) } else { c };
        let cat = air(curved_simple(Some(r), cant));
        let a = run_case(&cat, &mut |_| true).unwrap();
        let straight = air(curved_simple(None, 0.0));
        let per_run = line_of(straight.clone(), &[(10, 60.0, Some(r), Some(cant))]);
        let by_default = line_of(cat.clone(), &[(10, 60.0, None, None)]);
        a_line_runs_as_its_catenary(
            &a,
            windy,
            [("per run", per_run), ("by default", by_default)],
        );
    }
}

fn a_line_runs_as_its_catenary(a: &pcsim_core::RunOutput, windy: bool, lines: [(&str, Case); 2]) {
    for (which, line) in lines {
        let which = format!("{which}{}", if windy { ", in wind" } else { "" });
        let b = run_case(&line, &mut |_| true).unwrap();

        common::same_statistics(a, &b, 1e-9, &which);
        let (la, lb) = (
            a.pantographs[0].lateral.as_ref().unwrap(),
            b.pantographs[0].lateral.as_ref().unwrap(),
        );
        assert!(
            (la.max_lateral_offset_mm - lb.max_lateral_offset_mm).abs() < 1e-9,
            "{la:?} vs {lb:?}"
        );
        match (la.min_head_margin_mm, lb.min_head_margin_mm) {
            (Some(x), Some(y)) => assert!((x - y).abs() < 1e-9, "head margin {x} vs {y} mm"),
            (x, y) => assert_eq!(x, y),
        }
        assert_eq!(la.samples_off_head, lb.samples_off_head);
        let worst = (a.pantographs[0].lateral_m.iter())
            .zip(&b.pantographs[0].lateral_m)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(worst < 1e-9, "{which}: lateral trace {worst} m apart");
        assert!(b.curve.is_some());
    }
}

/// On unequal spans (a line: 45, 60, 50, 60, 40, 55 m …) in a 1 000 m curve, every interior
/// registration's static lateral force is the tension's change of direction from the
/// Cartesian chords, `T (u₊ − u₋)·n`, within 0.1 % of the largest: the closed form
/// `T [(y₊ − y)/s₊ − (y − y₋)/s₋ + (κ₋ s₋ + κ₊ s₊)/2]` on unequal spans.
#[test]
fn issue_41_the_pull_off_on_unequal_spans_balances_the_tensions_change_of_direction() {
    let r = 1000.0;
    let spans = [45.0, 60.0, 50.0, 60.0, 40.0, 55.0, 60.0, 45.0, 60.0, 50.0];
    let runs: Vec<(usize, f64, Option<f64>, Option<f64>)> =
        spans.iter().map(|&s| (1, s, Some(r), None)).collect();
    let mut case = line_of(curved(None, 0.0), &runs);
    case.run.end_m = 465.0;
    case.run.analysis_m = [120.0, 420.0];
    let setup = Setup::from_case(&case).unwrap();
    let m = &setup.model;
    let geo = m.lateral.as_ref().unwrap();
    assert!(geo.uniform_span_m.is_none());
    let x: Vec<f64> = std::iter::once(0.0)
        .chain(spans.iter().scan(0.0, |a, s| {
            *a += s;
            Some(*a)
        }))
        .collect();
    let y = &geo.lines[0].stagger_m;
    assert_eq!(y.len(), x.len());
    let reg = |i: usize| {
        let (p, n) = track(r, x[i]);
        [p[0] + y[i] * n[0], p[1] + y[i] * n[1]]
    };
    let unit = |a: [f64; 2], b: [f64; 2]| {
        let d = [b[0] - a[0], b[1] - a[1]];
        let l = d[0].hypot(d[1]);
        [d[0] / l, d[1] / l]
    };
    for role in [WireRole::Contact, WireRole::Messenger] {
        let t = m.wires[m.wire_index(role).unwrap()].section.tension_n;
        let model = geo.registration_forces_n(0, t);
        assert_eq!(model.len(), spans.len() - 1);
        let scale = model.iter().map(|f| f.abs()).fold(0.0, f64::max);
        for (k, f) in model.iter().enumerate() {
            let i = k + 1;
            let (u0, u1) = (unit(reg(i - 1), reg(i)), unit(reg(i), reg(i + 1)));
            let n = track(r, x[i]).1;
            let exact = t * ((u1[0] - u0[0]) * n[0] + (u1[1] - u0[1]) * n[1]);
            assert!(
                (f - exact).abs() < 1e-3 * scale,
                "{role:?}, registration {i}: {f} N against {exact} N"
            );
        }
    }
    // And the static lateral profile is the polygon between those registrations within 1 mm.
    let w = m.wire_index(WireRole::Contact).unwrap();
    let mut worst: f64 = 0.0;
    for i in 0..spans.len() {
        for k in 1..spans[i] as usize {
            let xt = x[i] + k as f64;
            let exact = chord_offset(r, xt, reg(i), reg(i + 1));
            worst = worst.max((m.static_height(w, Direction::Lateral, xt, 0.0) - exact).abs());
        }
    }
    assert!(worst < 1e-3, "{worst} m from the polygon");
}

/// What a line's lateral layout cannot be is refused, naming its field: a span longer than a
/// fifth of its run's radius (or of catenary.lateral's), a cant without a curve, a stagger per
/// tension length of the wrong length, a curve or a stagger without the lateral model, and an
/// overlap's shared spans on two different curves.
#[test]
fn issue_41_a_lines_curves_and_staggers_refuse_by_name() {
    let field = |c: &Case| match c.validate() {
        Err(CaseError::Invalid { field, .. }) => field,
        other => panic!("{other:?}"),
    };
    let straight = curved(None, 0.0);
    let l = line_of(
        straight.clone(),
        &[(4, 60.0, None, None), (6, 60.0, Some(250.0), None)],
    );
    assert_eq!(
        field(&l),
        "line.tension_lengths[0].span_runs[1].track_radius_m"
    );
    let l = line_of(
        curved(Some(1000.0), 0.0),
        &[(4, 60.0, None, None), (6, 250.0, None, None)],
    );
    assert_eq!(field(&l), "catenary.lateral.track_radius_m");
    let l = line_of(straight.clone(), &[(10, 60.0, None, Some(0.05))]);
    assert_eq!(field(&l), "line.tension_lengths[0].span_runs[0].cant_m");
    let l = line_of(straight.clone(), &[(10, 60.0, Some(f64::NAN), None)]);
    assert_eq!(
        field(&l),
        "line.tension_lengths[0].span_runs[0].track_radius_m"
    );
    let mut l = line_of(straight.clone(), &[(10, 60.0, None, None)]);
    l.line.as_mut().unwrap().tension_lengths[0].stagger_m = vec![0.2; 10];
    assert_eq!(field(&l), "line.tension_lengths[0].stagger_m");
    l.line.as_mut().unwrap().tension_lengths[0].stagger_m = vec![0.2; 11];
    l.line.as_mut().unwrap().tension_lengths[0].stagger_m[3] = 5.0;
    assert_eq!(field(&l), "line.tension_lengths[0].stagger_m[3]");
    let mut vertical = line_of(straight.clone(), &[(10, 60.0, Some(1000.0), None)]);
    vertical.run.dofs = vec![pcsim_core::input::case::Dof::Vertical];
    assert_eq!(
        field(&vertical),
        "line.tension_lengths[0].span_runs[0].track_radius_m"
    );
    // Two tension lengths whose 3-span overlap the second puts on a curve the first does not.
    let (mut two, _) = pcsim_core::presets::load("en50318-2018-like-stitched-3d").unwrap();
    two.line.as_mut().unwrap().tension_lengths[1].span_runs[0].track_radius_m = Some(2000.0);
    assert_eq!(field(&two), "line.tension_lengths[1].span_runs");
}

/// A stagger given per tension length is laid as given (each support of that tension length,
/// both its wires), the other tension lengths keep the pattern.
#[test]
fn issue_41_a_stagger_per_tension_length_is_laid_as_given() {
    let (mut case, _) = pcsim_core::presets::load("en50318-2018-like-stitched-3d").unwrap();
    let given: Vec<f64> = (0..14)
        .map(|j| if j % 2 == 0 { -0.25 } else { 0.25 })
        .collect();
    case.line.as_mut().unwrap().tension_lengths[0].stagger_m = given.clone();
    let (base, _) = pcsim_core::presets::load("en50318-2018-like-stitched-3d").unwrap();
    let (m, m0) = (
        Setup::from_case(&case).unwrap().model,
        Setup::from_case(&base).unwrap().model,
    );
    let wires = |m: &pcsim_core::model::Model, role| -> Vec<usize> {
        (0..m.wires.len())
            .filter(|&w| m.wires[w].role == role)
            .collect()
    };
    for role in [WireRole::Contact, WireRole::Messenger] {
        let (w, w0) = (wires(&m, role), wires(&m0, role));
        for (j, &y) in given.iter().enumerate() {
            let x = 60.0 * j as f64;
            assert!((m.static_height(w[0], Direction::Lateral, x, 0.0) - y).abs() < 1e-12);
        }
        for x in [800.0, 1000.0, 1500.0, 1800.0] {
            assert_eq!(
                m.static_height(w[2], Direction::Lateral, x, 0.0),
                m0.static_height(w0[2], Direction::Lateral, x, 0.0)
            );
        }
    }
}

/// The contact point's lateral range on the head per curve (issue 41, item 2): a line of one
/// tension length, 4 spans on 1 000 m with 60 mm cant, 4 straight, 4 on −2 000 m without cant,
/// gives two sections (their extents, radii and head offsets as laid out); each section's range
/// on the head is the samples' inside it, from that section's head centre, and inside the
/// pantograph's overall range; and `timeseries.csv`'s head margin, from each sample's own head
/// centre, has the recorder's smallest margin (they disagreed while the column took the line's
/// largest cant everywhere).
#[test]
fn issue_41_the_contact_points_range_on_the_head_is_reported_per_curve() {
    use pcsim_core::analysis::report::{timeseries_columns, RunSummary};
    let c = line_of(
        curved_simple(None, 0.0),
        &[
            (4, 60.0, Some(1000.0), Some(0.06)),
            (4, 60.0, None, None),
            (4, 60.0, Some(-2000.0), None),
        ],
    );
    let mut c = c;
    // The 3D preset's pantograph: its head's width gives the margin.
    c.pantographs = curved(None, 0.0).pantographs[..1].to_vec();
    c.run.start_m = 60.0;
    c.run.end_m = 660.0;
    c.run.analysis_m = [120.0, 600.0];
    let out = run_case(&c, &mut |_| true).unwrap();
    let curve = out.curve.as_ref().expect("a curved line reports its curve");
    let s = &curve.sections;
    assert_eq!(s.len(), 2, "{s:?}");
    assert_eq!(
        (s[0].from_m, s[0].to_m, s[1].from_m, s[1].to_m),
        (0.0, 240.0, 480.0, 720.0)
    );
    assert!(
        (s[0].track_radius_m - 1000.0).abs() < 1e-9 && (s[1].track_radius_m + 2000.0).abs() < 1e-9
    );
    let h = pcsim_core::input::lateral::head_offset_m(
        Some(1000.0),
        0.06,
        c.catenary.lateral.as_ref().unwrap().contact_wire_height_m,
    );
    assert!(
        h.abs() > 0.1 && (s[0].head_offset_m - h).abs() < 1e-12,
        "{h}"
    );
    assert_eq!(s[1].head_offset_m, 0.0);
    let p = &out.pantographs[0];
    for sec in s {
        let on = &sec.on_head[0];
        assert_eq!(on.pantograph, p.name);
        let inside: Vec<f64> = (p.lateral_m.iter().zip(&p.position_m))
            .filter(|(_, &x)| x >= sec.from_m && x < sec.to_m)
            .map(|(z, _)| z - sec.head_offset_m)
            .collect();
        assert!(inside.len() > 100);
        let lo = inside.iter().copied().fold(f64::INFINITY, f64::min);
        let hi = inside.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        assert_eq!(on.lateral_m, [lo, hi]);
        assert!(hi - lo > 0.1, "the stagger is felt: {lo}..{hi}");
    }
    // The time series' head margin against the recorder's smallest (both over the analysis
    // section), from each sample's own head centre.
    let cols = timeseries_columns(&out);
    let margin = cols
        .iter()
        .find(|c| c.name.ends_with("_head_margin_m"))
        .expect("a head margin column");
    let least = (margin.values.iter().zip(&p.position_m))
        .filter(|(_, &x)| x >= c.run.analysis_m[0] && x <= c.run.analysis_m[1])
        .map(|(m, _)| *m)
        .fold(f64::INFINITY, f64::min);
    let recorded = p.lateral.as_ref().unwrap().min_head_margin_mm.unwrap();
    assert!(
        (least * 1e3 - recorded).abs() < 1e-3,
        "column {} mm, recorder {recorded} mm",
        least * 1e3,
    );
    let _ = RunSummary::new(&c, &out, 0.0, Vec::new(), Vec::new());
}

/// Issue 51, item 2: a wind's side, a curve's hand and a stagger's sign are physical. The mirror
/// image of a right-hand case in wind (radius, stagger and yaw negated: the same line seen in a
/// mirror along the track) gives the mirror result: the same vertical statistics (within 1e-9
/// relative), the contact point's lateral trace negated (within 1e-9 m), the same largest
/// offset. And a wind from the other side of the same curve is another case: yaw −60° on the
/// right-hand curve does not give yaw +60°'s lateral trace.
#[test]
fn issue_51_the_mirror_image_of_a_curve_in_wind_gives_the_mirror_result() {
    let right = windy_curve(Some(2000.0), 60.0);
    let mut mirror = windy_curve(Some(-2000.0), -60.0);
    let l = mirror.catenary.lateral.as_mut().unwrap();
    l.stagger_m = l.stagger_m.map(|s| -s);
    l.stagger_list_m = l
        .stagger_list_m
        .take()
        .map(|v| v.iter().map(|s| -s).collect());
    let a = run_case(&right, &mut |_| true).unwrap();
    let b = run_case(&mirror, &mut |_| true).unwrap();
    common::same_statistics(&a, &b, 1e-9, "mirror");
    let (pa, pb) = (&a.pantographs[0], &b.pantographs[0]);
    assert_eq!(pa.lateral_m.len(), pb.lateral_m.len());
    let worst = (pa.lateral_m.iter().zip(&pb.lateral_m))
        .map(|(x, y)| (x + y).abs())
        .fold(0.0, f64::max);
    assert!(worst < 1e-9, "the lateral trace is not mirrored: {worst} m");
    let (sa, sb) = (pa.stats.unwrap(), pb.stats.unwrap());
    let (oa, ob) = (
        sa.max_lateral_offset_mm.unwrap(),
        sb.max_lateral_offset_mm.unwrap(),
    );
    assert!((oa - ob).abs() < 1e-6, "largest offset {oa} mm vs {ob} mm");
    // The other side of the same curve: the wind pushes the wire the other way.
    let other = run_case(&windy_curve(Some(2000.0), -60.0), &mut |_| true).unwrap();
    let po = &other.pantographs[0];
    let apart = (pa.lateral_m.iter().zip(&po.lateral_m))
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max);
    assert!(
        apart > 0.01,
        "yaw +60 and -60 on one curve: {apart} m apart"
    );
}

/// Issue 51, item 2: a case a user writes runs or is refused for its physical reason before any
/// run starts. On a 300 m curve the 60 m spans bow the wire 1.5 m toward the centre: beyond the
/// 0.8 m half-width of the head. Refused when the run is planned, naming `catenary.lateral`, the
/// place and the head (it was a "numerical blow-up, try a smaller Δt" with the stagger, a
/// dewirement without); on the 4 000 m curve the same stagger runs.
#[test]
fn issue_51_a_curve_that_puts_the_wire_off_the_head_is_refused_before_the_run() {
    let mut c = curved(Some(300.0), 0.0);
    let l = c.catenary.lateral.as_mut().unwrap();
    l.stagger_m = Some(0.0);
    l.stagger_list_m = None;
    match Setup::from_case(&c) {
        Err(CaseError::Invalid {
            field,
            value,
            reason,
        }) => {
            assert!(field.starts_with("catenary.lateral"), "{field}");
            assert!(value.contains("from the head's centre"), "{value}");
            assert!(
                reason.contains("0.8 m") && reason.contains("leading"),
                "{reason}"
            );
        }
        other => panic!("{other:?}"),
    }
    assert!(Setup::from_case(&curved(Some(4000.0), 0.0)).is_ok());
}
