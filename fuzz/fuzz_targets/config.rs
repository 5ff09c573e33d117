//! Fuzz target: experiment configs through parsing, validation and task loading
//! (`ExperimentConfig::from_toml_str`, `Experiment::new`). Any panic is a bug.
#![no_main]

use eamadm::{Experiment, ExperimentConfig};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    if let Ok(config) = ExperimentConfig::from_toml_str(text) {
        if let Ok(experiment) = Experiment::new(config) {
            let _ = experiment.jobs();
        }
    }
});
