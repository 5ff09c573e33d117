//! Small, readable outputs pinned as insta snapshots (floats rounded to 6 decimals).

use std::fmt::Write as _;

use madm_owa::{MadmDecider, OwaWeights, Support, Weighting, natural_visibility_graph};

fn r6(x: f64) -> String {
    // `+ 0.0` turns a rounded -0.000000 into 0.000000.
    format!("{:.6}", (x * 1e6).round() / 1e6 + 0.0)
}

fn weighting_name(w: &Weighting) -> &'static str {
    match w {
        Weighting::Visibility {
            support: Support::Paper { .. },
        } => "visibility/paper",
        Weighting::Visibility {
            support: Support::Distance,
        } => "visibility/distance",
        Weighting::Uniform => "uniform",
        Weighting::MaximumEntropy { .. } => "max-entropy(0.7)",
        _ => "other",
    }
}

#[test]
fn worked_example_weights_and_aggregate() {
    let row = [0.3, 0.9, 0.6, 0.7];
    let mut text = String::new();
    for support in [Support::default(), Support::Distance] {
        let mut decider = MadmDecider::new(Weighting::Visibility { support }).unwrap();
        let mut weights = [0.0; 4];
        let eq = decider.row_weights(&row, &mut weights).unwrap();
        writeln!(text, "support: {support:?}").unwrap();
        writeln!(
            text,
            "  edges: {:?}",
            natural_visibility_graph(&[0.9, 0.7, 0.6, 0.3]).unwrap()
        )
        .unwrap();
        for (position, (value, w)) in [0.9, 0.7, 0.6, 0.3].iter().zip(weights).enumerate() {
            writeln!(
                text,
                "  position {position}: value {value:.1}  weight {}",
                r6(w)
            )
            .unwrap();
        }
        writeln!(
            text,
            "  orness {}",
            r6(OwaWeights::new(weights.to_vec()).unwrap().orness())
        )
        .unwrap();
        writeln!(text, "  Eq = {}", r6(eq)).unwrap();
    }
    insta::assert_snapshot!(text);
}

#[test]
fn visibility_edge_lists() {
    let series: [&[f64]; 7] = [
        &[3.0, 1.0, 2.0, 4.0],
        &[4.0, 3.0, 2.0, 1.0],
        &[1.0, 1.0, 1.0],
        &[0.9, 0.7, 0.6, 0.3],
        &[5.0, 1.0, 1.0, 5.0],
        &[2.0, 0.0, 3.0, 0.0, 1.0, 4.0],
        &[10.0, 2.0, 1.0, -100.0],
    ];
    let mut text = String::new();
    for s in series {
        writeln!(text, "{s:?} -> {:?}", natural_visibility_graph(s).unwrap()).unwrap();
    }
    insta::assert_snapshot!(text);
}

#[test]
fn decision_table_for_each_weighting() {
    // 5 actions x 4 attributes, the robot task's shape.
    let matrix = [
        12.5, -3.0, 0.8, 4.1, //
        10.2, 1.5, 0.8, 3.9, //
        -95.0, 2.0, 1.1, -7.5, //
        11.0, 0.3, 0.8, 4.4, //
        9.7, 2.2, 2.2, 5.0, //
    ];
    let weightings = [
        Weighting::default(),
        Weighting::Visibility {
            support: Support::Distance,
        },
        Weighting::Uniform,
        Weighting::MaximumEntropy { orness: 0.7 },
    ];
    let mut text = String::from(
        "weighting            | Eq(a0)     Eq(a1)     Eq(a2)     Eq(a3)     Eq(a4)     | best\n",
    );
    for w in weightings {
        let name = weighting_name(&w);
        let mut decider = MadmDecider::new(w).unwrap();
        let mut out = [0.0; 5];
        decider.evaluate(&matrix, 5, 4, &mut out).unwrap();
        let best = (0..5).fold(0, |b, i| if out[i] > out[b] { i } else { b });
        let cells: Vec<String> = out.iter().map(|&v| format!("{:>10}", r6(v))).collect();
        writeln!(text, "{name:<20} | {} | a{best}", cells.join(" ")).unwrap();
    }
    insta::assert_snapshot!(text);
}
