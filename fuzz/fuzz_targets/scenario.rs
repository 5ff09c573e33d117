//! Fuzz target: robot scenarios through the parser, the planner (small budget) and a few
//! environment steps. Any panic is a bug.
#![no_main]

use eamadm::dql::Environment as _;
use eamadm::wmr_model::{PlannerParams, Scenario, WmrEnv, shortest_plan};
use libfuzzer_sys::fuzz_target;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(scenario) = Scenario::from_toml_str(text) else {
        return;
    };
    let params = PlannerParams {
        max_expansions: 5_000,
        ..PlannerParams::default()
    };
    let _ = shortest_plan(&scenario, &params);
    let Ok(mut env) = WmrEnv::new(scenario) else {
        return;
    };
    env.reset(Some(3));
    for step in 0..5 {
        if env.step(step % env.n_actions()).done() {
            break;
        }
    }
});
