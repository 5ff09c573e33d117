//! Small, readable outputs pinned as insta snapshots (floats rounded to 6 decimals).

use std::fmt::Write as _;

use reward_std::{RunningStandardiser, cross_sectional};

fn r6(x: f64) -> String {
    // `+ 0.0` turns a rounded -0.000000 into 0.000000.
    format!("{:>10.6}", (x * 1e6).round() / 1e6 + 0.0)
}

/// Sub-task rewards of a short episode in the robot task's style: "reach faster" (+/- small),
/// "do not hit" (negative, -100 on a near hit), "keep the target in view" (+2 / -10).
const EPISODE: [[f64; 3]; 6] = [
    [1.0, -0.2, 2.0],
    [1.0, -0.5, 2.0],
    [-1.0, -3.0, 2.0],
    [1.0, -100.0, -10.0],
    [1.0, -0.1, 2.0],
    [1.0, -0.1, 2.0],
];

#[test]
fn standardisation_table() {
    let mut text = String::from(
        "step | rewards (r1, r2, r3)   | cross-sectional z (r1, r2, r3)   Eq.12  | running z (r1, r2, r3)           mean\n",
    );
    let mut running = RunningStandardiser::new(3).unwrap();
    for (t, step) in EPISODE.iter().enumerate() {
        let mut z = [0.0; 3];
        let literal = cross_sectional(step, &mut z).unwrap();
        let signal = running.push(step).unwrap();
        let rewards: Vec<String> = step.iter().map(|r| format!("{r:>6.1}")).collect();
        let zc: Vec<String> = z.iter().map(|&v| r6(v)).collect();
        let zr: Vec<String> = running.z_scores().iter().map(|&v| r6(v)).collect();
        writeln!(
            text,
            "{t:>4} | {} | {} {} | {} {}",
            rewards.join(" "),
            zc.join(" "),
            r6(literal),
            zr.join(" "),
            r6(signal)
        )
        .unwrap();
    }
    insta::assert_snapshot!(text);
}
