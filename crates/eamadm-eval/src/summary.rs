//! Statistics over seeds: Student's t quantile, summaries with 95% confidence intervals, the
//! per-episode mean band that figures draw, the moving average that smooths curves, and the
//! per-method summary of an experiment's runs ([`summarise`]).
//!
//! Every interval here is a 95% confidence interval for the *mean over seeds*:
//! `mean ± t_{0.975, n−1} · sd / √n`, with `sd` the sample standard deviation (divisor `n − 1`).
//! With a single seed there is no interval: summaries say so with `None`, bands collapse onto the
//! mean.

use serde::{Deserialize, Serialize};

use crate::record::RunRecord;

pub use crate::stats::StatsError;

/// `z_{0.975}`, the standard normal quantile that Student's t tends to.
const Z_975: f64 = 1.959_963_984_540_054;

/// `t_{0.975, df}` for `df = 1..=30` (computed by numerical inversion of the t CDF, 6 decimals).
const T_975_TABLE: [f64; 30] = [
    12.706_205, 4.302_653, 3.182_446, 2.776_445, 2.570_582, 2.446_912, 2.364_624, 2.306_004,
    2.262_157, 2.228_139, 2.200_985, 2.178_813, 2.160_369, 2.144_787, 2.131_450, 2.119_905,
    2.109_816, 2.100_922, 2.093_024, 2.085_963, 2.079_614, 2.073_873, 2.068_658, 2.063_899,
    2.059_539, 2.055_529, 2.051_831, 2.048_407, 2.045_230, 2.042_272,
];

/// The 0.975 quantile of Student's t distribution with `df` degrees of freedom, the factor of a
/// two-sided 95% confidence interval; `None` for `df = 0`.
///
/// Exact to 6 decimals for `df ≤ 30` (a table); above, the Cornish–Fisher expansion of
/// Abramowitz & Stegun 26.7.5 in powers of `1/df`, whose error is below `1e-6` there.
pub fn student_t_975(df: usize) -> Option<f64> {
    match df {
        0 => None,
        1..=30 => Some(T_975_TABLE[df - 1]),
        _ => {
            let v = df as f64;
            let z = Z_975;
            let z2 = z * z;
            let g1 = z * (z2 + 1.0) / 4.0;
            let g2 = z * ((5.0 * z2 + 16.0) * z2 + 3.0) / 96.0;
            let g3 = z * (((3.0 * z2 + 19.0) * z2 + 17.0) * z2 - 15.0) / 384.0;
            let g4 =
                z * ((((79.0 * z2 + 776.0) * z2 + 1482.0) * z2 - 1920.0) * z2 - 945.0) / 92_160.0;
            Some(z + g1 / v + g2 / (v * v) + g3 / (v * v * v) + g4 / (v * v * v * v))
        }
    }
}

/// Mean, spread and 95% confidence interval of one quantity over seeds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct SeedSummary {
    /// Number of seeds.
    pub n: usize,
    /// Mean over seeds.
    pub mean: f64,
    /// Sample standard deviation (divisor `n − 1`); `None` with a single seed.
    pub sd: Option<f64>,
    /// Half-width of the 95% confidence interval of the mean, `t_{0.975,n−1} · sd / √n`;
    /// `None` with a single seed.
    pub ci95_half_width: Option<f64>,
}

/// Summarises one value per seed (`values[seed]`); [`summarise`] summarises whole runs per method.
pub fn summarise_seeds(values: &[f64]) -> Result<SeedSummary, StatsError> {
    if values.is_empty() {
        return Err(StatsError::NoSeeds);
    }
    if let Some((seed, &value)) = values.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(StatsError::NonFiniteInCurve {
            seed,
            episode: 0,
            value,
        });
    }
    Ok(summarise_seeds_finite(values))
}

/// [`summarise_seeds`] for values already known to be finite and non-empty.
fn summarise_seeds_finite(values: &[f64]) -> SeedSummary {
    let n = values.len();
    let count = n as f64;
    // Divide before adding so that large finite values cannot overflow the sum.
    let mean: f64 = values.iter().map(|v| v / count).sum();
    let (sd, ci95_half_width) = match student_t_975(n - 1) {
        None => (None, None),
        Some(t) => {
            let variance = values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (count - 1.0);
            let sd = variance.sqrt();
            (Some(sd), Some(t * sd / count.sqrt()))
        }
    };
    SeedSummary {
        n,
        mean,
        sd,
        ci95_half_width,
    }
}

/// Checks that there is at least one seed, no empty curve and no non-finite value.
fn validate_runs(runs: &[Vec<f64>]) -> Result<(), StatsError> {
    if runs.is_empty() {
        return Err(StatsError::NoSeeds);
    }
    runs.iter()
        .enumerate()
        .try_for_each(|(seed, curve)| validate_curve(seed, curve))
}

/// Checks that the curve of seed `seed` has an episode and only finite values.
fn validate_curve(seed: usize, curve: &[f64]) -> Result<(), StatsError> {
    if curve.is_empty() {
        return Err(StatsError::EmptyCurve { seed });
    }
    if let Some((episode, &value)) = curve.iter().enumerate().find(|(_, v)| !v.is_finite()) {
        return Err(StatsError::NonFiniteInCurve {
            seed,
            episode,
            value,
        });
    }
    Ok(())
}

/// Summarises the final window over seeds: each seed contributes the mean of its last `window`
/// episodes (all of them if its curve is shorter, e.g. in a `--quick` run), and these per-seed
/// means are summarised by [`summarise_seeds`]. `runs[seed][episode]`; curves may differ in length.
pub fn final_window_summary(runs: &[Vec<f64>], window: usize) -> Result<SeedSummary, StatsError> {
    if window == 0 {
        return Err(StatsError::ZeroWindow);
    }
    validate_runs(runs)?;
    let per_seed: Vec<f64> = runs
        .iter()
        .map(|curve| {
            let tail = &curve[curve.len().saturating_sub(window)..];
            let count = tail.len() as f64;
            tail.iter().map(|v| v / count).sum()
        })
        .collect();
    Ok(summarise_seeds_finite(&per_seed))
}

/// One episode of a mean curve with its 95% confidence band.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BandPoint {
    /// Number of seeds whose curve reaches this episode.
    pub n: usize,
    /// Mean over those seeds.
    pub mean: f64,
    /// Lower edge of the band, `mean − half-width` (`mean` when `n = 1`).
    pub lower: f64,
    /// Upper edge of the band, `mean + half-width` (`mean` when `n = 1`).
    pub upper: f64,
}

/// The mean over seeds and its 95% confidence band, episode by episode (`runs[seed][episode]`).
///
/// Ragged input is allowed: episode `i` is summarised over the seeds whose curve is longer than
/// `i`, so the result is as long as the longest curve. The curves go through a
/// [`BandAccumulator`] in order, so this and a figure that streams its seeds agree.
pub fn mean_band(runs: &[Vec<f64>]) -> Result<Vec<BandPoint>, StatsError> {
    if runs.is_empty() {
        return Err(StatsError::NoSeeds);
    }
    let mut band = BandAccumulator::new();
    for curve in runs {
        band.push(curve)?;
    }
    Ok(band.band())
}

/// One point of a success band ([`success_band`]): the share of (seed, episode) outcomes that
/// reached the target over a window of episodes, with its Wilson 95 % interval.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct ProportionPoint {
    /// The window's last episode (0-based).
    pub episode: usize,
    /// Outcomes that reached the target.
    pub successes: u64,
    /// Outcomes counted: every seed's episodes in the window.
    pub trials: u64,
    /// `successes / trials` with its Wilson 95 % interval.
    pub wilson: crate::stats::Interval,
}

/// A binary metric over episodes as what it is, a proportion (issue 34 item 7: never the IQM
/// of 0/1 outcomes, which reads 1 when more than three quarters of the seeds succeed): per
/// episode `e`, the outcomes of every seed (`runs[seed][episode]`, ragged allowed) over the
/// trailing `window` episodes `e − window + 1 … e` pooled, with the Wilson 95 % interval
/// ([`wilson`](crate::stats::wilson)). With `window = 1` the trials are the seeds, which are
/// independent; a wider window pools episodes of one seed, which are not, so its interval is
/// narrower than the truth (say so beside a figure that draws it).
///
/// ```
/// use eamadm_eval::summary::success_band;
///
/// // Four seeds, two episodes: 3 of 4 reach in the first, all in the second.
/// let runs = vec![vec![true, true], vec![true, true], vec![false, true], vec![true, true]];
/// let band = success_band(&runs, 1)?;
/// assert_eq!((band[0].successes, band[0].trials), (3, 4));
/// assert_eq!(band[0].wilson.estimate, 0.75); // the IQM of the 0/1 outcomes would be 1
/// assert_eq!((band[1].successes, band[1].trials), (4, 4));
/// // Pooled over both episodes: 7 of 8.
/// assert_eq!(success_band(&runs, 2)?[1].successes, 7);
/// # Ok::<(), eamadm_eval::summary::StatsError>(())
/// ```
///
/// # Errors
/// [`StatsError::NoSeeds`] for no curve, [`StatsError::ZeroWindow`] for a window of 0.
pub fn success_band(runs: &[Vec<bool>], window: usize) -> Result<Vec<ProportionPoint>, StatsError> {
    if runs.is_empty() {
        return Err(StatsError::NoSeeds);
    }
    if window == 0 {
        return Err(StatsError::ZeroWindow);
    }
    let episodes = runs.iter().map(Vec::len).max().unwrap_or(0);
    let mut points = Vec::with_capacity(episodes);
    for episode in 0..episodes {
        let first = (episode + 1).saturating_sub(window);
        let (mut successes, mut trials) = (0_u64, 0_u64);
        for curve in runs {
            for &reached in curve.iter().take(episode + 1).skip(first) {
                successes += u64::from(reached);
                trials += 1;
            }
        }
        points.push(ProportionPoint {
            episode,
            successes,
            trials,
            wilson: crate::stats::wilson(successes, trials, 0.95)?,
        });
    }
    Ok(points)
}

/// The per-episode mean band of [`mean_band`], accumulated one seed's curve at a time, so a
/// caller that reads runs one by one holds three numbers and a count per episode, never the
/// curves: memory grows with the longest curve, not with the number of seeds.
///
/// Per episode it keeps Welford's running mean and sum of squared deviations (`M2`), which are
/// exact in exact arithmetic and stable in floating point; compared with a two-pass computation
/// (mean first, then squared deviations) the results differ by rounding only, and so does a
/// different order of the seeds.
///
/// ```
/// use eamadm_eval::summary::{BandAccumulator, mean_band};
///
/// let runs = vec![vec![3.0, 2.0, 1.0], vec![5.0, 4.0]];
/// let mut band = BandAccumulator::new();
/// for curve in &runs {
///     band.push(curve)?;
/// }
/// assert_eq!(band.seeds(), 2);
/// assert_eq!(band.band(), mean_band(&runs)?);
/// assert_eq!(band.band()[2].n, 1);
/// # Ok::<(), eamadm_eval::summary::StatsError>(())
/// ```
#[derive(Debug, Clone, Default, PartialEq)]
pub struct BandAccumulator {
    /// Curves pushed so far.
    seeds: usize,
    /// Per episode: seeds whose curve reached it, their running mean and `M2`.
    episodes: Vec<Welford>,
}

/// Welford's running count, mean and sum of squared deviations from the mean.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Welford {
    n: usize,
    mean: f64,
    m2: f64,
}

impl BandAccumulator {
    /// An accumulator without seeds.
    #[must_use]
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds the curve of the next seed (`curve[episode]`; any length of at least one episode).
    ///
    /// # Errors
    /// [`StatsError::EmptyCurve`] or [`StatsError::NonFiniteInCurve`], with `seed` the number of
    /// curves pushed before this one (its index in [`mean_band`]'s input); the accumulator is
    /// then unchanged.
    pub fn push(&mut self, curve: &[f64]) -> Result<(), StatsError> {
        validate_curve(self.seeds, curve)?;
        if self.episodes.len() < curve.len() {
            self.episodes.resize(curve.len(), Welford::default());
        }
        for (state, &value) in self.episodes.iter_mut().zip(curve) {
            state.n += 1;
            let delta = value - state.mean;
            state.mean += delta / state.n as f64;
            state.m2 += delta * (value - state.mean);
        }
        self.seeds += 1;
        Ok(())
    }

    /// Curves pushed so far.
    #[must_use]
    pub fn seeds(&self) -> usize {
        self.seeds
    }

    /// Episodes of the longest curve pushed so far (the length of [`band`](Self::band)).
    #[must_use]
    pub fn episodes(&self) -> usize {
        self.episodes.len()
    }

    /// The mean over seeds and its 95% confidence band per episode, as long as the longest
    /// curve pushed (empty before the first push).
    #[must_use]
    pub fn band(&self) -> Vec<BandPoint> {
        self.episodes
            .iter()
            .map(|state| {
                let half_width = student_t_975(state.n - 1).map_or(0.0, |t| {
                    let count = state.n as f64;
                    let sd = (state.m2 / (count - 1.0)).sqrt();
                    t * sd / count.sqrt()
                });
                BandPoint {
                    n: state.n,
                    mean: state.mean,
                    lower: state.mean - half_width,
                    upper: state.mean + half_width,
                }
            })
            .collect()
    }
}

/// Trailing moving average: point `i` is the mean of `curve[i + 1 − window ..= i]`, over fewer
/// points at the start where the window does not fit yet. Causal (never looks ahead), so a
/// smoothed curve does not show an improvement before it happens. `window = 1` is the identity.
pub fn moving_average(curve: &[f64], window: usize) -> Result<Vec<f64>, StatsError> {
    if window == 0 {
        return Err(StatsError::ZeroWindow);
    }
    Ok((0..curve.len())
        .map(|i| {
            let slice = &curve[(i + 1).saturating_sub(window)..=i];
            let count = slice.len() as f64;
            slice.iter().map(|v| v / count).sum()
        })
        .collect())
}

/// The final window of the paper-style summaries: the last 20 episodes of each run.
pub const DEFAULT_FINAL_WINDOW: usize = 20;

/// One method of one experiment, summarised over its seeds.
///
/// "Final" quantities are per seed the mean over the last `window` training episodes, then
/// summarised over seeds ([`final_window_summary`]): mean, standard deviation and 95%
/// confidence interval of the mean.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct MethodSummary {
    /// The experiment's name.
    pub experiment: String,
    /// The method's label.
    pub method: String,
    /// Number of runs (seeds) summarised.
    pub seeds: usize,
    /// Episodes in the final window.
    pub window: usize,
    /// Steps per episode in the final window.
    pub final_steps: SeedSummary,
    /// Task return per episode in the final window.
    pub final_return: SeedSummary,
    /// Fraction of final-window episodes that reached the target.
    pub final_reached: SeedSummary,
    /// Collisions per episode in the final window.
    pub final_collisions: SeedSummary,
    /// The task's optimal route length (BFS for mazes), when known.
    pub optimum_steps: Option<u64>,
    /// Final-window steps divided by the optimum (1 is optimal), when the optimum is known.
    pub final_steps_to_optimum: Option<SeedSummary>,
    /// Steps of the greedy evaluation episode.
    pub evaluation_steps: SeedSummary,
    /// Fraction of seeds whose greedy evaluation reached the target.
    pub evaluation_reached: f64,
    /// Environment steps spent on sub-task pre-training.
    pub pretrain_env_steps: SeedSummary,
    /// Environment steps of the whole run, pre-training included.
    pub total_env_steps: SeedSummary,
    /// The robot metrics of the final window (robot task only).
    pub robot: Option<RobotSummary>,
}

/// The robot task's metrics (Sec. VI.B) in the final window, summarised over seeds.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct RobotSummary {
    /// Average reward (return per second) per episode.
    pub average_reward: SeedSummary,
    /// Retention time per episode, in seconds.
    pub retention_time: SeedSummary,
    /// Time to reach the target, over the final-window episodes that reached it (seeds with
    /// none are left out); `None` when no seed reached it in its final window.
    pub time_to_reach: Option<SeedSummary>,
}

/// Summarises `records` per (experiment, method), in the order each pair first appears, over
/// the last `window` training episodes of each run (all of them when a run is shorter).
///
/// # Errors
/// [`StatsError::ZeroWindow`]; [`StatsError::EmptyCurve`] for a run without episodes;
/// [`StatsError::NonFiniteInCurve`] for a non-finite return.
pub fn summarise(records: &[RunRecord], window: usize) -> Result<Vec<MethodSummary>, StatsError> {
    if window == 0 {
        return Err(StatsError::ZeroWindow);
    }
    let mut groups: Vec<(&str, &str, Vec<&RunRecord>)> = Vec::new();
    for record in records {
        match groups.iter_mut().find(|(experiment, method, _)| {
            *experiment == record.experiment && *method == record.method
        }) {
            Some((_, _, runs)) => runs.push(record),
            None => groups.push((&record.experiment, &record.method, vec![record])),
        }
    }
    groups
        .into_iter()
        .map(|(experiment, method, runs)| summarise_method(experiment, method, &runs, window))
        .collect()
}

// counts far below 2^52
fn summarise_method(
    experiment: &str,
    method: &str,
    runs: &[&RunRecord],
    window: usize,
) -> Result<MethodSummary, StatsError> {
    let curve = |value: &dyn Fn(&crate::record::EpisodeRecord) -> f64| -> Vec<Vec<f64>> {
        runs.iter()
            .map(|run| run.episodes.iter().map(value).collect())
            .collect()
    };
    let per_run = |value: &dyn Fn(&RunRecord) -> f64| -> Vec<f64> {
        runs.iter().map(|run| value(run)).collect()
    };
    let steps = curve(&|e| e.steps as f64);
    let final_steps = final_window_summary(&steps, window)?;
    let optimum_steps = runs.first().and_then(|run| run.optimum_steps);
    let final_steps_to_optimum = match optimum_steps {
        Some(optimum) if optimum > 0 => {
            let ratios: Vec<Vec<f64>> = steps
                .iter()
                .map(|curve| curve.iter().map(|s| s / optimum as f64).collect())
                .collect();
            Some(final_window_summary(&ratios, window)?)
        }
        _ => None,
    };
    let robot = if runs
        .iter()
        .any(|run| run.episodes.iter().any(|e| e.robot.is_some()))
    {
        let metric = |value: &dyn Fn(&crate::record::RobotEpisodeMetrics) -> f64| {
            curve(&|e| e.robot.as_ref().map_or(0.0, value))
        };
        let reach_times: Vec<f64> = runs
            .iter()
            .filter_map(|run| {
                let tail = &run.episodes[run.episodes.len().saturating_sub(window)..];
                let times: Vec<f64> = tail
                    .iter()
                    .filter_map(|e| e.robot.and_then(|r| r.time_to_reach))
                    .collect();
                (!times.is_empty()).then(|| times.iter().sum::<f64>() / times.len() as f64)
            })
            .collect();
        Some(RobotSummary {
            average_reward: final_window_summary(&metric(&|r| r.average_reward), window)?,
            retention_time: final_window_summary(&metric(&|r| r.retention_time), window)?,
            time_to_reach: if reach_times.is_empty() {
                None
            } else {
                Some(summarise_seeds(&reach_times)?)
            },
        })
    } else {
        None
    };
    Ok(MethodSummary {
        experiment: experiment.to_owned(),
        method: method.to_owned(),
        seeds: runs.len(),
        window,
        final_steps,
        final_return: final_window_summary(&curve(&|e| e.task_return), window)?,
        final_reached: final_window_summary(&curve(&|e| f64::from(u8::from(e.reached))), window)?,
        final_collisions: final_window_summary(&curve(&|e| e.collisions as f64), window)?,
        optimum_steps,
        final_steps_to_optimum,
        evaluation_steps: summarise_seeds(&per_run(&|run| run.evaluation.steps as f64))?,
        evaluation_reached: runs.iter().filter(|run| run.evaluation.reached).count() as f64
            / runs.len() as f64,
        pretrain_env_steps: summarise_seeds(&per_run(&|run| run.pretrain_env_steps as f64))?,
        total_env_steps: summarise_seeds(&per_run(&|run| run.total_env_steps as f64))?,
        robot,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tolerance: f64) -> bool {
        (a - b).abs() <= tolerance
    }

    #[test]
    fn t_quantile_matches_known_values() {
        assert_eq!(student_t_975(0), None);
        let known = [
            (1, 12.706),
            (2, 4.303),
            (4, 2.776),
            (9, 2.262),
            (19, 2.093),
            (29, 2.045),
            (30, 2.042),
        ];
        for (df, expected) in known {
            let t = student_t_975(df).unwrap();
            assert!(close(t, expected, 5e-4), "df {df}: {t} vs {expected}");
        }
    }

    #[test]
    fn t_quantile_expansion_is_accurate_beyond_the_table() {
        // Reference values from numerical inversion of the t CDF.
        let known = [
            (31, 2.039_513),
            (40, 2.021_075),
            (60, 2.000_298),
            (120, 1.979_930),
            (1000, 1.962_339),
        ];
        for (df, expected) in known {
            let t = student_t_975(df).unwrap();
            assert!(close(t, expected, 2e-6), "df {df}: {t} vs {expected}");
        }
        assert!(close(student_t_975(1_000_000).unwrap(), Z_975, 1e-5));
    }

    #[test]
    fn t_quantile_decreases_with_df() {
        let values: Vec<f64> = (1..200).map(|df| student_t_975(df).unwrap()).collect();
        assert!(values.windows(2).all(|w| w[0] > w[1]), "{values:?}");
    }

    #[test]
    fn summary_of_ten_seeds() {
        // 1..=10: mean 5.5, sd = sqrt(55/6) ≈ 3.027650, half-width 2.262157 · sd / √10.
        let values: Vec<f64> = (1..=10).map(f64::from).collect();
        let s = summarise_seeds(&values).unwrap();
        assert_eq!(s.n, 10);
        assert!(close(s.mean, 5.5, 1e-12));
        let sd = (55.0_f64 / 6.0).sqrt();
        assert!(close(s.sd.unwrap(), sd, 1e-12));
        assert!(close(
            s.ci95_half_width.unwrap(),
            2.262_157 * sd / 10.0_f64.sqrt(),
            1e-9
        ));
        assert!(close(s.ci95_half_width.unwrap(), 2.165_850, 1e-6));
    }

    #[test]
    fn summary_of_one_seed_has_no_interval() {
        let s = summarise_seeds(&[42.0]).unwrap();
        assert_eq!(
            s,
            SeedSummary {
                n: 1,
                mean: 42.0,
                sd: None,
                ci95_half_width: None
            }
        );
    }

    #[test]
    fn identical_seeds_have_zero_width() {
        let s = summarise_seeds(&[3.0, 3.0, 3.0]).unwrap();
        assert_eq!(s.sd, Some(0.0));
        assert_eq!(s.ci95_half_width, Some(0.0));
    }

    #[test]
    fn bad_values_are_named() {
        assert_eq!(summarise_seeds(&[]), Err(StatsError::NoSeeds));
        assert!(matches!(
            summarise_seeds(&[1.0, f64::NAN]),
            Err(StatsError::NonFiniteInCurve { seed: 1, .. })
        ));
        let runs = vec![vec![1.0, 2.0], vec![3.0, f64::INFINITY]];
        assert_eq!(
            mean_band(&runs),
            Err(StatsError::NonFiniteInCurve {
                seed: 1,
                episode: 1,
                value: f64::INFINITY
            })
        );
        assert_eq!(
            final_window_summary(&[vec![1.0], vec![]], 5),
            Err(StatsError::EmptyCurve { seed: 1 })
        );
        assert_eq!(
            final_window_summary(&[vec![1.0]], 0),
            Err(StatsError::ZeroWindow)
        );
        assert_eq!(moving_average(&[1.0], 0), Err(StatsError::ZeroWindow));
    }

    #[test]
    fn final_window_uses_the_last_episodes_of_each_seed() {
        let runs = vec![vec![100.0, 100.0, 10.0, 20.0], vec![0.0, 30.0]];
        let s = final_window_summary(&runs, 2).unwrap();
        // Seed means: 15 and 15.
        assert_eq!(s.n, 2);
        assert!(close(s.mean, 15.0, 1e-12));
        assert_eq!(s.ci95_half_width, Some(0.0));
        // A window longer than a curve takes the whole curve.
        let s = final_window_summary(&[vec![2.0, 4.0]], 10).unwrap();
        assert!(close(s.mean, 3.0, 1e-12));
    }

    #[test]
    fn band_handles_ragged_curves() {
        let runs = vec![vec![1.0, 2.0, 3.0], vec![3.0, 4.0]];
        let band = mean_band(&runs).unwrap();
        assert_eq!(band.len(), 3);
        assert_eq!(band[0].n, 2);
        assert!(close(band[0].mean, 2.0, 1e-12));
        // sd = √2, half-width = 12.706205 · √2 / √2.
        assert!(close(band[0].upper - band[0].mean, 12.706_205, 1e-9));
        assert!(close(band[0].mean - band[0].lower, 12.706_205, 1e-9));
        assert_eq!(
            band[2],
            BandPoint {
                n: 1,
                mean: 3.0,
                lower: 3.0,
                upper: 3.0
            }
        );
    }

    #[test]
    fn moving_average_is_trailing() {
        let smoothed = moving_average(&[0.0, 2.0, 4.0, 6.0], 2).unwrap();
        assert_eq!(smoothed, vec![0.0, 1.0, 3.0, 5.0]);
        let same = moving_average(&[1.5, -2.0], 1).unwrap();
        assert_eq!(same, vec![1.5, -2.0]);
        assert!(moving_average(&[], 3).unwrap().is_empty());
    }
}
