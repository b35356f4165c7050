//! The unit tests of [`super`]: the refusal messages and the step counts.

use super::*;

#[test]
fn messages_name_the_value_the_bound_and_the_reason() {
    let m = THICKNESS.check("[[floe]] #0: thickness", 9e15).unwrap_err();
    assert!(
        m.starts_with("[[floe]] #0: thickness = 9e15 m is above the limit of 1000 m: new ice"),
        "{m}"
    );
    let m = THICKNESS.check("thickness", -1.0).unwrap_err();
    assert_eq!(m, "thickness = -1 m must be finite and >= 0.001 m");
    let m = THICKNESS.check("thickness", 1e-300).unwrap_err();
    assert_eq!(m, "thickness = 1e-300 m must be finite and >= 0.001 m");
    let m = FRICTION.check("friction", f64::NAN).unwrap_err();
    assert_eq!(m, "friction = NaN must be finite and >= 0");
    let m = CORIOLIS.check("coriolis", -3.0).unwrap_err();
    assert!(
        m.starts_with("coriolis = -3 s^-1 is below the limit of -1 s^-1"),
        "{m}"
    );
    let m = FLOES.check_integer("count", i64::MAX as i128).unwrap_err();
    assert!(
        m.starts_with("count = 9223372036854775807 is above the limit of 100000 floes"),
        "{m}"
    );
    let m = FLOES.check_integer("count", 0).unwrap_err();
    assert_eq!(m, "count = 0 must be >= 1");
    let m = DURATION.check("duration", f64::INFINITY).unwrap_err();
    assert_eq!(m, "duration = inf s must be finite and > 0");
    let m = SPEED.check_vector("velocity", [3e8, 0.0]).unwrap_err();
    assert!(
        m.starts_with(
            "velocity = [3e8, 0] m/s has a length of 3e8 m/s, above the limit of 100 m/s"
        ),
        "{m}"
    );
    assert!(CONCENTRATION.check("c", 0.0).is_err() && CONCENTRATION.check("c", 0.9).is_ok());
    assert_eq!(show(5e-324), "5e-324");
    assert_eq!(show(1e300), "1e300");
    assert_eq!(show(0.5), "0.5");
}

#[test]
fn step_counts_are_bounded_through_the_duration() {
    assert!(check_count(&STEPS, "step", 1.0, 1e8).is_ok());
    let m = check_count(&STEPS, "step", 1e-6, 1e8).unwrap_err();
    assert!(m.contains("gives 1e14 steps"), "{m}");
    assert!(check_count(&OUTPUTS, "output_interval", 5e-324, 10.0).is_err());
}
