//! The unit tests of `compile` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use pcsim_core::compile::Setup;
use pcsim_core::error::{CaseError, Warning};
use pcsim_core::input::case::Case;
use pcsim_core::input::presets;
use pcsim_core::model::build::BuilderRun;
use pcsim_core::model::Model;
use pcsim_core::solve::integrator::Integrator;
use pcsim_core::solve::kernels;
use pcsim_core::solve::realtime::{Coupling, RealtimeCatenary};
use pcsim_core::solve::stability;
use pcsim_core::solve::{ContactSample, Options, Plan, State, Workspace};

/// (Here, above `solve/` and `input/`: the engine's own files name no case.) The crosswind's
/// generalised forces inside a field interval, as the quadratic of its three
/// scatters, against one scatter of the step's own pressures (the law at the field's value
/// at `t`), on both kernel paths; and the per-step scatter where the normal wind changes
/// sign inside an interval.
#[test]
fn the_winds_interval_quadratic_is_the_steps_own_scatter() {
    let (mut case, _) = presets::load("stitched-2018-like-3d-crosswind").unwrap();
    case.catenary.spans = 4;
    case.pantographs.truncate(1);
    case.run.modes = None;
    case.run.modes_per_m = Some(1.0);
    case.run.start_m = 40.0;
    case.run.end_m = 200.0;
    case.run.analysis_m = [60.0, 180.0];
    case.run.allow_start_transient = true;
    let setup = Setup::from_case(&case).unwrap();
    for isa in [kernels::Isa::best_available(), kernels::Isa::Portable] {
        // The whole model on that path: its samplers' scatters as well as the quadratic.
        let mut setup = setup.clone();
        setup.options.isa = isa;
        let integ = setup.integrator().unwrap();
        let cm = integ.compiled();
        assert_eq!(cm.isa, isa);
        let mut wl = setup.model.wind.clone().unwrap();
        let w = cm.wind.as_ref().unwrap();
        assert_eq!(w.parts.len(), 1, "a catenary's wires share one basis");
        let mut ws = integ.workspace();
        let check = |wl: &pcsim_core::model::wind::WindLoad,
                     ws: &mut pcsim_core::solve::Workspace| {
            let (mut quadratic, mut per_step) = (0, 0);
            for part in &w.parts {
                let kn = part.k * part.n;
                let mut p = vec![0.0; part.k * part.ng];
                let mut c = vec![0.0; 3 * kn];
                for step in 0..200 {
                    let t = 0.137 + step as f64 * 1e-3;
                    let (interval, tau) = wl.field.interval(t);
                    // The step's own scatter.
                    let mut direct = vec![0.0; kn];
                    part.step_forces(wl, t, &mut p, &mut direct, &mut ws.scr);
                    if part.interval_forces(wl, interval, &mut p, &mut c, &mut ws.scr) {
                        quadratic += 1;
                        let (c0, rest) = c.split_at(kn);
                        let (c1, c2) = rest.split_at(kn);
                        let mut q = vec![0.0; kn];
                        kernels::quadratic(isa, &mut q, c0, c1, c2, tau);
                        let scale = direct.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                        let err = q
                            .iter()
                            .zip(&direct)
                            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
                        assert!(err <= 1e-12 * scale, "t {t}: {err} of {scale}");
                    } else {
                        per_step += 1;
                        // A sign change inside the interval: at one of its grid points the
                        // normal wind has both signs at the interval's ends.
                        let changes = part.slots.iter().any(|&slot| {
                            part.grid.iter().any(|&g| {
                                let (u0, u1) = wl.field.ends(g, interval);
                                wl.pressure_quadratic(slot, u0, u1).is_none()
                            })
                        });
                        assert!(changes, "t {t}");
                    }
                }
            }
            (quadratic, per_step)
        };
        // The preset's wind: its normal wind keeps its sign.
        let (q, s) = check(&wl, &mut ws);
        assert_eq!((q, s), (200, 0));
        // A weak mean: the fluctuation reverses the normal wind at some grid points.
        for ww in &mut wl.wires {
            ww.mean_normal_m_s = 0.3;
        }
        let (q, s) = check(&wl, &mut ws);
        assert!(s > 0, "{q} quadratic, {s} per step");
    }
}

/// On a curve the mean crosswind's generalised force is the projection of the mean
/// pressure `½ρ U² sin²(ψ − θ(x))` on each mode, against its closed form (the product of a
/// sine and a cosine integrated exactly): within 1e-4 of the uniform load's first-mode
/// value over the first 20 modes (the part that varies along the curve is taken on the
/// wind's 5 m grid).
#[test]
fn a_curves_mean_wind_projects_as_its_closed_form() {
    let mut case = pcsim_core::presets::load("stitched-2018-like-3d-crosswind")
        .unwrap()
        .0;
    let r = 2000.0;
    case.catenary.lateral.as_mut().unwrap().track_radius_m = Some(r);
    let mut setup = Setup::from_case(&case).unwrap();
    setup.options.isa = kernels::Isa::Portable;
    let integ = setup.integrator().unwrap();
    let ws = integ.compiled().wind.as_ref().unwrap();
    let model = &setup.model;
    let wl = model.wind.as_ref().unwrap();
    let x0 = model.lateral.as_ref().unwrap().supports_m[0];
    let lay = &model.layout;
    let part = &ws.parts[0];
    let b = lay
        .find(
            wl.wires[part.slots[0]].wire,
            pcsim_core::model::dof::Direction::Vertical,
        )
        .unwrap();
    let (basis, origin) = (lay.basis(b), lay.groups[lay.blocks[b].group].origin_m);
    let l = basis.length_m();
    for (s, &slot) in part.slots.iter().enumerate() {
        let a = wl.wires[slot].mean_along_m_s;
        let c = 0.5 * wl.air_density_kg_m3 * a * a;
        // sin²(b' − ξ/R) = (1 − cos(B − Cξ))/2 in the basis' coordinate ξ.
        let bp = std::f64::consts::FRAC_PI_2 - (origin - x0) / r;
        let (bb, cc) = (2.0 * bp, 2.0 / r);
        let scale = c * 2.0 / basis.wavenumber(0);
        for j in 0..20 {
            let k = basis.wavenumber(j);
            let i1 = (bb.cos() - ((k - cc) * l + bb).cos()) / (k - cc);
            let i2 = (bb.cos() - ((k + cc) * l - bb).cos()) / (k + cc);
            let want = 0.5 * c * ((1.0 - (k * l).cos()) / k - 0.5 * (i1 + i2));
            let got = part.mean[s * part.n + j];
            assert!(
                (got - want).abs() < 1e-4 * scale,
                "wire {slot} mode {}: {got} vs {want} (scale {scale})",
                j + 1
            );
        }
    }
}
