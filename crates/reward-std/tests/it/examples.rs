//! Worked examples, degenerate cases and error cases as plain unit tests.

use reward_std::{
    MAX_ABS_REWARD, RewardStandardiser, RewardStdError, RunningStandardiser, Standardisation,
    cross_sectional,
};

fn assert_close(got: f64, want: f64, tol: f64) {
    assert!(
        (got - want).abs() <= tol,
        "got {got}, want {want} (tolerance {tol})"
    );
}

// ---------------------------------------------------------------- cross-sectional (Eq. 10-12)

#[test]
fn cross_sectional_uses_the_population_standard_deviation() {
    let mut z = [0.0; 4];
    let mean = cross_sectional(&[2.0, 4.0, 4.0, 6.0], &mut z).unwrap();
    // μ = 4, population σ = sqrt((4 + 0 + 0 + 4) / 4) = sqrt(2) (the sample σ would be 1.633).
    let s = 2.0_f64.sqrt();
    assert_eq!(z, [-2.0 / s, 0.0, 0.0, 2.0 / s]);
    assert_eq!(mean, 0.0);
}

#[test]
fn cross_sectional_with_equal_rewards_is_all_zeros() {
    let mut z = [9.0; 3];
    assert_eq!(cross_sectional(&[0.1, 0.1, 0.1], &mut z), Ok(0.0));
    assert_eq!(z, [0.0; 3]);
    let mut one = [9.0];
    assert_eq!(cross_sectional(&[-100.0], &mut one), Ok(0.0));
    assert_eq!(one, [0.0]);
}

#[test]
fn cross_sectional_handles_extreme_magnitudes() {
    let mut z = [0.0; 2];
    cross_sectional(&[f64::MAX, -f64::MAX], &mut z).unwrap();
    assert_eq!(z, [1.0, -1.0]);
    cross_sectional(&[5e-324, 0.0], &mut z).unwrap();
    assert_eq!(z, [1.0, -1.0]);
    let mut z3 = [0.0; 3];
    let mean = cross_sectional(&[1e300, 1e300, -1e300], &mut z3).unwrap();
    let s = 2.0_f64.sqrt();
    assert_close(z3[0], 1.0 / s, 1e-12);
    assert_close(z3[2], -s, 1e-12);
    assert!(mean.abs() < 1e-15);
}

#[test]
fn cross_sectional_rejects_bad_input_and_leaves_the_buffer_alone() {
    let mut z = [7.0; 2];
    assert_eq!(
        cross_sectional(&[], &mut []),
        Err(RewardStdError::Empty { what: "rewards" })
    );
    assert_eq!(
        cross_sectional(&[1.0, 2.0, 3.0], &mut z),
        Err(RewardStdError::LengthMismatch {
            what: "z_out",
            expected: 3,
            found: 2
        })
    );
    let err = cross_sectional(&[1.0, f64::NAN], &mut z).unwrap_err();
    assert!(
        matches!(err, RewardStdError::NonFinite { what: "rewards", index: 1, value } if value.is_nan())
    );
    assert_eq!(err.to_string(), "`rewards[1]` is NaN, not a finite number");
    assert!(matches!(
        cross_sectional(&[f64::INFINITY, 0.0], &mut z),
        Err(RewardStdError::NonFinite { index: 0, .. })
    ));
    assert_eq!(z, [7.0; 2]);
}

// ---------------------------------------------------------------- running (our repair)

#[test]
fn running_first_step_of_an_episode_is_zero() {
    let mut s = RunningStandardiser::new(3).unwrap();
    assert_eq!(s.push(&[1.0, -100.0, 2.0]), Ok(0.0));
    assert_eq!(s.z_scores(), [0.0; 3]);
    assert_eq!(s.count(), 1);
    assert_eq!(s.means(), [1.0, -100.0, 2.0]);
    assert_eq!(s.variances(), [0.0; 3]);
}

#[test]
fn running_standardises_each_subtask_against_its_own_history() {
    let mut s = RunningStandardiser::new(2).unwrap();
    s.push(&[0.0, 10.0]).unwrap();
    s.push(&[2.0, 10.0]).unwrap();
    // Sub-task 0: rewards (0, 2, 4): μ = 2, population σ² = 8/3; z = 2 / sqrt(8/3).
    // Sub-task 1: constant, σ = 0, z = 0.
    let signal = s.push(&[4.0, 10.0]).unwrap();
    let z0 = 2.0 / (8.0_f64 / 3.0).sqrt();
    assert_close(s.z_scores()[0], z0, 1e-12);
    assert_eq!(s.z_scores()[1], 0.0);
    assert_close(signal, z0 / 2.0, 1e-12);
    assert_close(s.means()[0], 2.0, 0.0);
    assert_close(s.variances()[0], 8.0 / 3.0, 1e-12);
}

#[test]
fn running_reset_starts_a_new_episode() {
    let mut s = RunningStandardiser::new(2).unwrap();
    for r in [[1.0, 2.0], [3.0, -4.0], [5.0, 0.5]] {
        s.push(&r).unwrap();
    }
    s.reset();
    assert_eq!(s.count(), 0);
    assert_eq!(s.means(), [0.0; 2]);
    assert_eq!(s.z_scores(), [0.0; 2]);
    assert_eq!(s.push(&[9.0, 9.0]), Ok(0.0));
    assert_eq!(s, {
        let mut fresh = RunningStandardiser::new(2).unwrap();
        fresh.push(&[9.0, 9.0]).unwrap();
        fresh
    });
}

#[test]
fn running_rejects_bad_input_without_changing_state() {
    assert_eq!(
        RunningStandardiser::new(0),
        Err(RewardStdError::Empty { what: "subtasks" })
    );
    let mut s = RunningStandardiser::new(2).unwrap();
    s.push(&[1.0, 2.0]).unwrap();
    let before = s.clone();
    assert_eq!(s.push(&[]), Err(RewardStdError::Empty { what: "rewards" }));
    assert_eq!(
        s.push(&[1.0, 2.0, 3.0]),
        Err(RewardStdError::LengthMismatch {
            what: "rewards",
            expected: 2,
            found: 3
        })
    );
    assert!(matches!(
        s.push(&[1.0, f64::NAN]),
        Err(RewardStdError::NonFinite { index: 1, .. })
    ));
    assert_eq!(
        s.push(&[0.0, -1e200]),
        Err(RewardStdError::OutOfRange {
            index: 1,
            value: -1e200,
            limit: MAX_ABS_REWARD
        })
    );
    assert_eq!(s, before);
}

#[test]
fn running_survives_the_largest_accepted_rewards() {
    let mut s = RunningStandardiser::new(1).unwrap();
    for i in 0..10_000 {
        let r = if i % 2 == 0 {
            MAX_ABS_REWARD
        } else {
            -MAX_ABS_REWARD
        };
        let v = s.push(&[r]).unwrap();
        assert!(v.is_finite());
    }
    assert_close(s.variances()[0] / 1e300, 1.0, 1e-9);
}

/// Two-pass mean and population variance, with a correction pass for the mean.
fn two_pass(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let rough = xs.iter().sum::<f64>() / n;
    let mean = rough + xs.iter().map(|x| x - rough).sum::<f64>() / n;
    let var = xs.iter().map(|x| (x - mean) * (x - mean)).sum::<f64>() / n;
    (mean, var)
}

#[test]
fn running_statistics_stay_accurate_over_a_long_episode_with_a_large_offset() {
    // A million steps of unit-scale rewards on top of an offset of 1e9: the naive
    // E[r²] - E[r]² would lose every significant digit of the variance here.
    let mut s = RunningStandardiser::new(2).unwrap();
    let mut history = Vec::with_capacity(1_000_000);
    let mut last = 0.0;
    for i in 0..1_000_000_u32 {
        let noise = (f64::from(i) * 0.618_033_988_749_894_9).fract() - 0.5;
        let r = 1e9 + noise;
        history.push(r);
        last = s.push(&[r, -noise]).unwrap();
    }
    let (mean, var) = two_pass(&history);
    assert_close(s.means()[0] / mean, 1.0, 1e-14);
    assert_close(s.variances()[0] / var, 1.0, 1e-6);
    let z_two_pass = (history[history.len() - 1] - mean) / var.sqrt();
    assert_close(s.z_scores()[0], z_two_pass, 1e-5);
    assert!(last.is_finite());
}

// ---------------------------------------------------------------- the switchable standardiser

#[test]
fn standardiser_dispatches_on_its_mode() {
    let steps = [[1.0, -1.0, 100.0], [1.0, -100.0, 2.0], [-1.0, 1.0, 2.0]];
    let mut literal = RewardStandardiser::new(Standardisation::CrossSectional, 3).unwrap();
    let mut running = RewardStandardiser::new(Standardisation::default(), 3).unwrap();
    let mut reference = RunningStandardiser::new(3).unwrap();
    for step in steps {
        let mut z = [0.0; 3];
        assert_eq!(literal.push(&step), cross_sectional(&step, &mut z));
        assert_eq!(literal.z_scores(), z);
        assert_eq!(running.push(&step), reference.push(&step));
        assert_eq!(running.z_scores(), reference.z_scores());
    }
    assert_eq!(running.mode(), Standardisation::Running);
    assert_eq!(literal.subtasks(), 3);
    assert_eq!(
        literal.push(&[1.0, 2.0]),
        Err(RewardStdError::LengthMismatch {
            what: "rewards",
            expected: 3,
            found: 2
        })
    );
    running.reset();
    assert_eq!(running.push(&steps[0]), Ok(0.0));
}

#[test]
fn standardisation_reads_from_config_strings() {
    #[derive(serde::Deserialize)]
    struct Config {
        standardisation: Standardisation,
    }
    let parse = |t: &str| toml::from_str::<Config>(t).map(|c| c.standardisation);
    assert_eq!(
        parse(r#"standardisation = "running""#).unwrap(),
        Standardisation::Running
    );
    assert_eq!(
        parse(r#"standardisation = "cross_sectional""#).unwrap(),
        Standardisation::CrossSectional
    );
    assert!(parse(r#"standardisation = "sample""#).is_err());
    assert_eq!(
        serde_json::to_string(&Standardisation::CrossSectional).unwrap(),
        r#""cross_sectional""#
    );
}
