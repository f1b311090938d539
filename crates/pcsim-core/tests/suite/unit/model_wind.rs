//! The unit tests of `model::wind` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use pcsim_core::model::wind_field::{SpectrumModel, WindField};
/// The pressure's quadratic over an interval is the law at every fraction (to rounding),
/// for both signs of the normal wind and from or to zero, and there is none when the
/// normal wind changes sign inside the interval.
#[test]
fn the_pressures_quadratic_is_the_law_inside_an_interval() {
    let mut wl = pcsim_core::model::wind::WindLoad::uniform_lateral(0, 1.0);
    wl.air_density_kg_m3 = 1.225;
    wl.normal_fraction = 0.8;
    for (mean, u0, u1) in [
        (20.0, 3.0, -5.0),
        (-20.0, 3.0, -5.0),
        (0.0, 0.0, 4.0),
        (0.0, -4.0, 0.0),
        (4.0, -5.0, -5.0),
        (0.0, 0.0, 0.0),
    ] {
        wl.wires[0].mean_normal_m_s = mean;
        let c = wl.pressure_quadratic(0, u0, u1).unwrap();
        for k in 0..=10 {
            let tau = k as f64 / 10.0;
            let want = wl.pressure(0, u0 + tau * (u1 - u0));
            let got = c[0] + tau * (c[1] + tau * c[2]);
            assert!(
                (got - want).abs() <= 1e-12 * want.abs().max(1.0),
                "{mean} {u0} {u1} at {tau}: {got} vs {want}"
            );
        }
    }
    wl.wires[0].mean_normal_m_s = 1.0;
    assert_eq!(wl.pressure_quadratic(0, -5.0, 5.0), None);
    assert_eq!(wl.pressure_quadratic(0, 5.0, -5.0), None);
}
