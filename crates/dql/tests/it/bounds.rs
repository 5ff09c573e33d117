//! Initial action values are bounded (issue 14, item 1): a finite but huge initial value let a
//! validated config overflow the values a decision rule combines.

use dql::{DoubleQParams, DqlError, Initialisation, MAX_ABS_INITIAL_VALUE};

fn field_of(error: &DqlError) -> &str {
    match error {
        DqlError::InvalidParameter { name, .. } => name,
        other => panic!("expected an invalid parameter, got {other}"),
    }
}

#[test]
fn huge_finite_initial_values_are_refused_naming_the_field() {
    for value in [1e308, -1e308, 5e307, 1.000_001e9, -2e9] {
        let error = Initialisation::Constant { value }.validate().unwrap_err();
        assert_eq!(field_of(&error), "init.value", "{value}");
        let params = DoubleQParams {
            init: Initialisation::Constant { value },
            ..DoubleQParams::default()
        };
        assert_eq!(field_of(&params.validate().unwrap_err()), "init.value");
    }
    let error = Initialisation::Uniform {
        low: -1e308,
        high: 0.0,
    }
    .validate()
    .unwrap_err();
    assert_eq!(field_of(&error), "init.low");
    let error = Initialisation::Uniform {
        low: 0.0,
        high: 1e300,
    }
    .validate()
    .unwrap_err();
    assert_eq!(field_of(&error), "init.high");
}

#[test]
fn initial_values_up_to_the_bound_are_accepted() {
    assert_eq!(MAX_ABS_INITIAL_VALUE, 1e9);
    for value in [0.0, 1.0, -10.0, 1e9, -1e9] {
        assert!(
            Initialisation::Constant { value }.validate().is_ok(),
            "{value}"
        );
    }
    let uniform = Initialisation::Uniform {
        low: -1e9,
        high: 1e9,
    };
    assert!(uniform.validate().is_ok());
}
