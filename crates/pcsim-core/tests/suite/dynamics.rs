//! Dynamics of the full catenary: slack droppers, the energy balance, determinism.

use crate::common;

use common::{short_en50318, short_preset, with_moving_force};
use pcsim_core::analysis::energy::{dissipation_rate, system_energy};
use pcsim_core::compile::{Setup, Stepper};
use pcsim_core::input::case::Damping;
use pcsim_core::model::elements::dropper::Droppers;
use pcsim_core::model::elements::stitch::Stitches;
use pcsim_core::run_case;

#[test]
fn droppers_go_slack_when_pushed_past_their_preload() {
    // A large stationary upward force in mid-span lifts the contact wire more than the messenger:
    // droppers near it lose their whole preload and carry exactly zero (never compression).
    let mut case = with_moving_force(short_en50318(5, 100.0), 2000.0);
    case.catenary.damping = Damping::Modal { ratio: 0.3 };
    let mut setup = Setup::from_case(&case).unwrap();
    setup.plan.speed_m_s = 0.0;
    setup.plan.start_m = 150.0 + 17.0;
    let mut s = Stepper::new(&setup).unwrap();
    for _ in 0..20_000 {
        s.step();
    }
    let (droppers, slots) = s.integ.compiled().element::<Droppers>().unwrap();
    let nd = droppers.list().len();
    let mut t = vec![0.0; nd];
    let mut e = vec![0.0; nd];
    let u = s.integ.compiled().displacements(&s.ws);
    droppers.tensions(slots, u, &mut t);
    droppers.elongations(slots, u, &mut e);
    let mut slack = 0;
    for i in 0..nd {
        let d = &droppers.list()[i];
        let linear = d.preload_n + d.stiffness_n_per_m * e[i];
        if linear < 0.0 {
            slack += 1;
            assert_eq!(t[i], 0.0);
        } else {
            assert!((t[i] - linear).abs() < 1e-9);
        }
    }
    assert!(
        slack >= 2,
        "expected slack droppers near the load, found {slack}"
    );
    assert_eq!(slack, s.ws.slack_droppers());
    // Far from the load the droppers keep (nearly) their preload.
    assert!((t[0] - droppers.list()[0].preload_n).abs() < 0.2 * droppers.list()[0].preload_n);
}

#[test]
fn slack_droppers_are_common_at_speed() {
    // README §5: at least one dropper slack in most steps at 300 km/h.
    let case = short_en50318(8, 300.0);
    let out = run_case(&case, &mut |_| true).unwrap();
    assert!(
        out.steps_with_slack_percent > 50.0,
        "{} %",
        out.steps_with_slack_percent
    );
    assert!(out.max_slack_droppers >= 2);
}

/// Integrate the energy balance along a run: E(t) − E(0) + dissipated(t) − work(t).
fn energy_residual(setup: Setup, steps: usize, moving_force: Option<f64>) -> (f64, f64, usize) {
    let Stepper {
        integ,
        state: mut st,
        mut ws,
    } = Stepper::new(&setup).unwrap();
    let e0 = system_energy(integ.compiled(), &st, &mut ws).total();
    let mut d_prev = dissipation_rate(integ.compiled(), &st, &mut ws);
    let mut p_prev = 0.0;
    let (mut dissipated, mut work) = (0.0, 0.0);
    let dt = integ.dt_s();
    let mut worst: f64 = 0.0;
    let mut scale: f64 = 0.0;
    let mut max_slack = 0;
    for _ in 0..steps {
        integ.step(&mut st, &mut ws);
        max_slack = max_slack.max(ws.slack_droppers());
        let p_now = ws.samples()[0].wire_velocity_m_s;
        let d = dissipation_rate(integ.compiled(), &st, &mut ws);
        dissipated += 0.5 * dt * (d + d_prev);
        d_prev = d;
        if let Some(f) = moving_force {
            let p = f * p_now;
            work += 0.5 * dt * (p + p_prev);
            p_prev = p;
        }
        let e = system_energy(integ.compiled(), &st, &mut ws).total();
        worst = worst.max((e - e0 + dissipated - work).abs());
        scale = scale.max((e - e0).abs()).max(dissipated).max(work.abs());
    }
    eprintln!("energy residual {worst:.4e} J of {scale:.4e} J, max slack {max_slack}");
    (worst, scale, max_slack)
}

#[test]
fn energy_balance_with_moving_force_slack_droppers_and_damping() {
    let mut case = with_moving_force(short_en50318(5, 150.0), 400.0);
    case.catenary.messenger_support.damping_ns_per_m = 200.0;
    case.catenary.damping = Damping::Rayleigh {
        alpha: 0.05,
        beta: 2e-4,
    };
    case.run.dt_s = 2.5e-4;
    let setup = Setup::from_case(&case).unwrap();
    let (worst, scale, slack) = energy_residual(setup, 20_000, Some(400.0));
    assert!(slack > 0, "the load should slacken droppers");
    assert!(scale > 1.0, "scale {scale} J");
    assert!(
        worst < 2e-3 * scale,
        "energy residual {worst} J against {scale} J"
    );
}

#[test]
fn energy_balance_with_pantograph_contact_and_damping() {
    // Stationary pantograph started off equilibrium: contact, pantograph dampers, wire damping.
    let mut case = short_en50318(5, 100.0);
    case.catenary.messenger_support.damping_ns_per_m = 200.0;
    case.run.dt_s = 2.5e-4;
    let mut setup = Setup::from_case(&case).unwrap();
    setup.plan.speed_m_s = 0.0;
    setup.plan.start_m = 150.0 + 30.0;
    // Kick the pantograph head upward by 5 cm relative to equilibrium.
    let (worst, scale) = {
        let Stepper {
            integ,
            state: mut st,
            mut ws,
        } = Stepper::new(&setup).unwrap();
        st.pantographs.u[0] += 0.05;
        let e0 = system_energy(integ.compiled(), &st, &mut ws).total();
        let dt = integ.dt_s();
        let mut d_prev = dissipation_rate(integ.compiled(), &st, &mut ws);
        let mut dissipated = 0.0;
        let (mut worst, mut scale): (f64, f64) = (0.0, 0.0);
        for _ in 0..20_000 {
            integ.step(&mut st, &mut ws);
            let d = dissipation_rate(integ.compiled(), &st, &mut ws);
            dissipated += 0.5 * dt * (d + d_prev);
            d_prev = d;
            let e = system_energy(integ.compiled(), &st, &mut ws).total();
            worst = worst.max((e - e0 + dissipated).abs());
            scale = scale.max((e - e0).abs()).max(dissipated);
        }
        eprintln!("energy residual {worst:.4e} J of {scale:.4e} J");
        (worst, scale)
    };
    assert!(scale > 1.0, "scale {scale} J");
    assert!(
        worst < 2e-3 * scale,
        "energy residual {worst} J against {scale} J"
    );
}

#[test]
fn runs_are_bitwise_deterministic() {
    let case = short_en50318(6, 250.0);
    let a = run_case(&case, &mut |_| true).unwrap();
    let b = run_case(&case, &mut |_| true).unwrap();
    assert_eq!(a, b);
    let bits = |v: &[f64]| v.iter().map(|x| x.to_bits()).collect::<Vec<_>>();
    assert_eq!(
        bits(&a.pantographs[0].force_n),
        bits(&b.pantographs[0].force_n)
    );
}

#[test]
fn energy_balance_with_stitch_nodes() {
    // Stitched catenary: stitch nodes (mass, spring, damper) and stitch droppers that slacken.
    let mut case = with_moving_force(short_preset("stitched-2018-like", 5, 150.0), 400.0);
    case.run.dt_s = 2.5e-4;
    let setup = Setup::from_case(&case).unwrap();
    assert_eq!(setup.model.element::<Stitches>().unwrap().0.len(), 2 * 5);
    let (worst, scale, slack) = energy_residual(setup, 20_000, Some(400.0));
    assert!(slack > 0);
    assert!(scale > 1.0, "scale {scale} J");
    assert!(
        worst < 2e-3 * scale,
        "energy residual {worst} J against {scale} J"
    );
}

/// Issue 54's contact gap (`PantographTrace::gap_m`, recorded every step).
#[test]
fn a_runs_contact_gap_is_the_penalty_laws_other_side() {
    // en50318-2002 at 300 km/h loses contact over 1.3 % of its section: the force is the
    // penalty's k·max(0, −gap) at every step (Eq. 19), the gap positive exactly where the force
    // is zero.
    let mut case = pcsim_core::input::case_from_preset("en50318-2002").unwrap();
    case.run.speed_kmh = 300.0;
    let k = case.contact.stiffness_n_per_m;
    let out = pcsim_core::run_case(&case, &mut |_| true).unwrap();
    let p = &out.pantographs[0];
    assert_eq!(p.gap_m.len(), p.force_n.len());
    let (mut open, mut closed) = (0, 0);
    for (&f, &g) in p.force_n.iter().zip(&p.gap_m) {
        assert!(
            (f - k * (-g).max(0.0)).abs() <= 1e-9 * k.max(1.0) * g.abs().max(1e-3),
            "{f} vs gap {g}"
        );
        if g > 0.0 {
            open += 1;
        } else {
            closed += 1;
        }
    }
    assert!(open > 0 && closed > open, "{open} open, {closed} closed");
}
