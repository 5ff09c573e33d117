//! The serialised forms of the parameter types: a misspelt key is an error naming it (including
//! beside a field-less variant such as `{"kind": "zero"}`), the documented forms parse, and
//! serialising gives exactly those forms back.

#![allow(
    clippy::unwrap_used,
    reason = "tests may unwrap: a failure is the test failing"
)]

use std::fmt::Debug;

use dql::{
    BehaviourValues, BuiltinPolicy, DoubleQParams, EpisodeOptions, EpsilonGreedy, Initialisation,
    QLearningParams, Schedule, Softmax,
};
use serde::Serialize;
use serde::de::DeserializeOwned;

/// `json` is rejected with a message naming `key`.
fn assert_rejects_key<T: DeserializeOwned + Debug>(json: &str, key: &str) {
    let error = serde_json::from_str::<T>(json).unwrap_err().to_string();
    assert!(
        error.contains(&format!("unknown field `{key}`")),
        "{json}: {error}"
    );
}

/// `value` serialises to exactly `json`, and `json` parses back to `value`.
fn assert_form<T: Serialize + DeserializeOwned + PartialEq + Debug>(value: &T, json: &str) {
    assert_eq!(serde_json::to_string(value).unwrap(), json);
    assert_eq!(&serde_json::from_str::<T>(json).unwrap(), value);
}

#[test]
fn schedule_rejects_misspelt_keys_and_keeps_its_forms() {
    assert_form(&Schedule::Constant(0.1), r#"{"constant":0.1}"#);
    assert_form(
        &Schedule::Exponential {
            start: 0.95,
            factor: 0.5,
            floor: 0.0,
        },
        r#"{"exponential":{"start":0.95,"factor":0.5,"floor":0.0}}"#,
    );
    assert_rejects_key::<Schedule>(
        r#"{"exponential":{"start":0.95,"factr":0.5,"floor":0.0}}"#,
        "factr",
    );
    let error = serde_json::from_str::<Schedule>(r#"{"constnt":0.1}"#).unwrap_err();
    assert!(
        error.to_string().contains("unknown variant `constnt`"),
        "{error}"
    );
}

#[test]
fn initialisation_rejects_misspelt_keys_and_keeps_its_forms() {
    assert_form(&Initialisation::Zero, r#"{"kind":"zero"}"#);
    assert_form(
        &Initialisation::Constant { value: 1.5 },
        r#"{"kind":"constant","value":1.5}"#,
    );
    assert_form(
        &Initialisation::Uniform {
            low: -0.5,
            high: 0.5,
        },
        r#"{"kind":"uniform","low":-0.5,"high":0.5}"#,
    );
    // The field-less variant too: a plain unit variant would ignore `value` here.
    assert_rejects_key::<Initialisation>(r#"{"kind":"zero","value":1.0}"#, "value");
    assert_rejects_key::<Initialisation>(r#"{"kind":"constant","valeu":1.0}"#, "valeu");
    assert_rejects_key::<Initialisation>(r#"{"kind":"uniform","low":0.0,"hihg":1.0}"#, "hihg");
}

#[test]
fn double_q_params_reject_misspelt_keys_and_keep_their_form() {
    assert_form(
        &DoubleQParams::default(),
        r#"{"alpha":0.1,"gamma":0.95,"xi":0.5,"init":{"kind":"zero"},"behaviour":"mean"}"#,
    );
    assert_form(
        &DoubleQParams {
            xi: 0.9,
            init: Initialisation::Constant { value: 2.0 },
            behaviour: BehaviourValues::Sum,
            ..DoubleQParams::default()
        },
        r#"{"alpha":0.1,"gamma":0.95,"xi":0.9,"init":{"kind":"constant","value":2.0},"behaviour":"sum"}"#,
    );
    // Missing optional fields take their defaults.
    assert_eq!(
        serde_json::from_str::<DoubleQParams>(r#"{"alpha":0.1,"gamma":0.95}"#).unwrap(),
        DoubleQParams::default()
    );
    assert_rejects_key::<DoubleQParams>(r#"{"alpha":0.1,"gamma":0.95,"ksi":0.9}"#, "ksi");
    assert_rejects_key::<DoubleQParams>(
        r#"{"alpha":0.1,"gamma":0.95,"init":{"kind":"zero","low":0.0}}"#,
        "low",
    );
}

#[test]
fn q_learning_params_reject_misspelt_keys_and_keep_their_form() {
    assert_form(
        &QLearningParams::default(),
        r#"{"alpha":0.1,"gamma":0.95,"init":{"kind":"zero"}}"#,
    );
    assert_eq!(
        serde_json::from_str::<QLearningParams>(r#"{"alpha":0.1,"gamma":0.95}"#).unwrap(),
        QLearningParams::default()
    );
    assert_rejects_key::<QLearningParams>(r#"{"alpha":0.1,"gama":0.95}"#, "gama");
}

#[test]
fn episode_options_reject_misspelt_keys_and_keep_their_form() {
    assert_form(
        &EpisodeOptions::default(),
        r#"{"episode":0,"seed":null,"max_steps":null,"learn":true,"record_trajectory":false}"#,
    );
    assert_form(
        &EpisodeOptions::new(3).with_seed(7),
        r#"{"episode":3,"seed":7,"max_steps":null,"learn":true,"record_trajectory":false}"#,
    );
    assert_eq!(
        serde_json::from_str::<EpisodeOptions>("{}").unwrap(),
        EpisodeOptions::default()
    );
    assert_rejects_key::<EpisodeOptions>(r#"{"episodes":3}"#, "episodes");
}

#[test]
fn builtin_policy_rejects_misspelt_keys_and_keeps_its_forms() {
    assert_form(&BuiltinPolicy::Greedy, r#"{"kind":"greedy"}"#);
    assert_form(
        &BuiltinPolicy::EpsilonGreedy(EpsilonGreedy::new(Schedule::Constant(0.1)).unwrap()),
        r#"{"kind":"epsilon_greedy","epsilon":{"constant":0.1}}"#,
    );
    assert_form(
        &BuiltinPolicy::Softmax(Softmax::new(Schedule::Constant(0.5)).unwrap()),
        r#"{"kind":"softmax","temperature":{"constant":0.5}}"#,
    );
    // The field-less variant too: a plain unit variant would ignore `epsilon` here.
    assert_rejects_key::<BuiltinPolicy>(
        r#"{"kind":"greedy","epsilon":{"constant":0.1}}"#,
        "epsilon",
    );
    assert_rejects_key::<BuiltinPolicy>(
        r#"{"kind":"epsilon_greedy","epsilon":{"constant":0.1},"temperature":{"constant":1.0}}"#,
        "temperature",
    );
    assert_rejects_key::<BuiltinPolicy>(
        r#"{"kind":"softmax","temprature":{"constant":0.5}}"#,
        "temprature",
    );
}
