//! The unit tests of `study::compare`'s support positions (moved out of the CLI: issue 52,
//! one derivation for every front end).

use pcsim_core::study::compare::support_positions;

#[test]
fn a_lines_own_supports_else_multiples_of_its_span_past_the_last_position() {
    // A line's supports are its own, whatever its span says.
    assert_eq!(
        support_positions(&[0.0, 55.0, 117.0], Some(60.0), 500.0),
        vec![0.0, 55.0, 117.0]
    );
    // A repeating span: 0, 55, … up to a span past the last position (130 m → 0…220 m).
    assert_eq!(
        support_positions(&[], Some(55.0), 130.0),
        vec![0.0, 55.0, 110.0, 165.0, 220.0]
    );
    // Neither: none; a span that is not a length: none.
    assert!(support_positions(&[], None, 130.0).is_empty());
    assert!(support_positions(&[], Some(0.0), 130.0).is_empty());
    assert!(support_positions(&[], Some(55.0), f64::NAN).is_empty());
}
