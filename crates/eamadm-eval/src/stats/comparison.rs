//! Comparing several methods: Holm's step-down adjustment and the probability of improvement.

use super::{StatsError, check_sample};

/// Holm–Bonferroni step-down adjusted p-values, in the input order, monotone, capped at 1.
pub fn holm(p_values: &[f64]) -> Result<Vec<f64>, StatsError> {
    if p_values.is_empty() {
        return Err(StatsError::Empty { what: "p_values" });
    }
    if let Some((index, &value)) = p_values
        .iter()
        .enumerate()
        .find(|(_, p)| !(0.0..=1.0).contains(*p))
    {
        return Err(StatsError::NotAProbability {
            what: "p_values",
            index,
            value,
        });
    }
    let m = p_values.len();
    let mut order: Vec<usize> = (0..m).collect();
    order.sort_by(|&a, &b| p_values[a].total_cmp(&p_values[b]).then(a.cmp(&b)));
    let mut adjusted = vec![0.0; m];
    let mut running = 0.0_f64;
    for (rank, &i) in order.iter().enumerate() {
        running = running.max(((m - rank) as f64 * p_values[i]).min(1.0));
        adjusted[i] = running;
    }
    Ok(adjusted)
}

/// P(X > Y) + ½ P(X = Y) over all pairs (Mann–Whitney U / (n m)).
pub fn probability_of_improvement(x: &[f64], y: &[f64]) -> Result<f64, StatsError> {
    check_sample(x, "x")?;
    check_sample(y, "y")?;
    // Twice the U statistic, in integers: 2 per win, 1 per tie.
    let mut doubled_u = 0_u128;
    for a in x {
        for b in y {
            doubled_u += match a.partial_cmp(b) {
                Some(std::cmp::Ordering::Greater) => 2,
                Some(std::cmp::Ordering::Equal) => 1,
                _ => 0,
            };
        }
    }
    let pairs = x.len() as u128 * y.len() as u128;
    Ok(doubled_u as f64 / (2 * pairs) as f64)
}
