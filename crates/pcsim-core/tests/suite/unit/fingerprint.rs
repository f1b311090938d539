//! The unit tests of `fingerprint` (moved out of the library so that the core compiles once
//! for `cargo run --release` and `cargo test --release`: issue 53, item 3).

#![allow(unused_imports)]

#[test]
fn known_values() {
    // The published FNV-1a 64 test vectors.
    assert_eq!(pcsim_core::fingerprint::fnv1a64(b""), 0xcbf2_9ce4_8422_2325);
    assert_eq!(
        pcsim_core::fingerprint::fnv1a64(b"a"),
        0xaf63_dc4c_8601_ec8c
    );
    assert_eq!(
        pcsim_core::fingerprint::fnv1a64_hex(b"foobar"),
        "85944171f73967e8"
    );
}
