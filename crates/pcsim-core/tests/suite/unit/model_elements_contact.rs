//! The unit tests of `model::elements::contact` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

use pcsim_core::model::dof::Direction;
use pcsim_core::model::elements::contact::*;
use pcsim_core::model::elements::{Attach, Io, PointElement, Slot, WindowMap};

/// The contact force and its moment about the wire's axis at a rotation φ, for a contact
/// point at depth `e` (0: a round running face).
fn force_and_moment(e: f64, phi: f64) -> (f64, f64) {
    let c = Contacts(vec![Contact {
        pantograph: 0,
        head: 0,
        along_m: 0.0,
        wire: 0,
        dir: Direction::Vertical,
        law: ContactLaw::Penalty {
            stiffness_n_per_m: 50_000.0,
        },
        eccentricity_m: e,
        twist: e != 0.0,
    }]);
    // Slots: 0 the ground, 1 the wire's height, 2 the head, 3 the rotation.
    let slots = [
        Slot { u: 1, v: 0 },
        Slot { u: 2, v: 0 },
        Slot {
            u: if e != 0.0 { 3 } else { 0 },
            v: 0,
        },
    ];
    let u = [0.0, 0.0, 0.002, phi];
    let mut f = [0.0; 4];
    let mut io = Io {
        u: &u,
        v: &[0.0; 4],
        f: &mut f,
        loads: &[0.0],
        off_head: &[false; 4],
        absent: &[false; 4],
        slack: 0,
    };
    c.add_forces(&slots, &mut io);
    (f[1], f[3])
}

#[test]
fn a_round_running_face_has_no_moment_and_a_fixed_point_has_f_e_phi() {
    let phi = 0.05;
    // Round face: the force is the penalty on the 2 mm penetration, whatever φ; no moment.
    let (f, m) = force_and_moment(0.0, phi);
    assert_eq!(f, 100.0);
    assert_eq!(m, 0.0);
    // A point fixed 6.2 mm below the axis: lifted by e φ²/2, and the moment F e φ.
    let e = 0.0062;
    let (f, m) = force_and_moment(e, phi);
    let want_f = 50_000.0 * (0.002 - 0.5 * e * phi * phi);
    assert!((f - want_f).abs() < 1e-12, "{f} vs {want_f}");
    assert!((m - want_f * e * phi).abs() < 1e-15, "{m}");
}
