"""Reference values for `eamadm::stats`, computed by independent implementations.

Not run by CI. The values it prints are pinned in `stats.rs` next to this file; rerun it to check
them after a change of inputs:

    python3 -m venv /tmp/statsref
    /tmp/statsref/bin/pip install scipy numpy statsmodels
    /tmp/statsref/bin/python crates/eamadm-eval/tests/it/stats_reference.py

Pinned with scipy 1.17.1, statsmodels 0.15.0, numpy 2.4.6 (Python 3.11).

Sources of truth, one per statistic:
  * trimmed mean, median, sample sd, quartiles: scipy.stats.trim_mean(x, 0.25), numpy.median,
    numpy.std(ddof=1), numpy.percentile (linear)
  * Holm: statsmodels.stats.multitest.multipletests(method="holm")
  * Wilson: statsmodels.stats.proportion.proportion_confint(method="wilson")
  * probability of improvement: scipy.stats.mannwhitneyu(x, y).statistic / (n m)
  * exact permutation p-value: scipy.stats.permutation_test(permutation_type="independent",
    n_resamples=inf, alternative="greater") of |T(x) - T(y)| (all splits enumerated)
  * normal quantile: scipy.stats.norm.ppf
  * retention slope (`scores::slope`): scipy.stats.linregress(range(n), y).slope
  * Student t factor and seed summary (`summary`): scipy.stats.t.ppf(0.975, df), numpy.mean,
    numpy.std(ddof=1)
  * bootstrap: the exact bootstrap distribution of the mean by enumerating all n^n resamples,
    and scipy.stats.bootstrap(method="percentile") for Monte-Carlo comparisons
"""

import itertools

import numpy as np
from scipy import stats
from statsmodels.stats.multitest import multipletests
from statsmodels.stats.proportion import proportion_confint

SAMPLES = {
    "EA_MADM_TASK2": [73, 73, 73, 73, 73, 75, 2000, 2000, 2000, 2000],
    "COMPETITOR_TASK2": [812, 2000, 1377, 2000, 954, 2000, 1640, 2000, 1105, 2000],
    "ONE": [4.25],
    "TWO": [3.0, -1.5],
    "THREE": [0.3, 0.1, 0.2],
    "FIVE": [2.5, -7.25, 3.125, 11.0, 0.0],
    "SEVEN": [0.1, 0.7, 0.2, 0.35, 0.9, 0.15, 0.6],
    "TWELVE": [5.5, 1.0, 9.25, -3.0, 4.0, 4.0, 12.5, 0.75, 6.0, 2.0, 8.0, -1.25],
    "THIRTEEN": [13, 1, 12, 2, 11, 3, 10, 4, 9, 5, 8, 6, 700],
}


def rust_array(values):
    return "[" + ", ".join(repr(float(v)) for v in values) + "]"


def iqm(x, axis=-1):
    return stats.trim_mean(x, 0.25, axis=axis)


def main():
    print("# location and spread: (name, mean, median, iqm, sd)")
    for name, x in SAMPLES.items():
        x = np.asarray(x, dtype=float)
        sd = float(np.std(x, ddof=1)) if len(x) > 1 else 0.0
        print(f"({name}, {float(np.mean(x))!r}, {float(np.median(x))!r}, {float(iqm(x))!r}, {sd!r}),")

    print("# quartiles (numpy's linear percentile): (name, q1, q3)")
    for name, x in SAMPLES.items():
        q1, q3 = np.percentile(np.asarray(x, dtype=float), [25, 75])
        print(f"({name}, {float(q1)!r}, {float(q3)!r}),")

    print("# holm: input -> adjusted")
    for p in [
        [0.01, 0.04, 0.03, 0.005],
        [0.2, 0.2, 0.01, 0.6, 0.04],
        [0.5],
        [0.3, 0.4, 0.9],
        [0.0, 1.0, 0.011, 0.012],
        [0.02, 0.02, 0.02, 0.5],
        [0.04, 0.03],
        [0.0625, 0.25, 1.0],
    ]:
        adjusted = multipletests(p, method="holm")[1]
        print(f"({rust_array(p)}, {rust_array(adjusted)}),")

    print("# wilson: (successes, trials, confidence, low, high)")
    for s, n, confidence in [
        (0, 10, 0.95),
        (10, 10, 0.95),
        (7, 10, 0.95),
        (62, 100, 0.95),
        (1, 3, 0.9),
        (13, 20, 0.99),
        (500, 1000, 0.5),
    ]:
        low, high = proportion_confint(s, n, alpha=1 - confidence, method="wilson")
        print(f"({s}, {n}, {confidence!r}, {low!r}, {high!r}),")

    print("# probability of improvement: (x, y, U/(n m))")
    for x, y in [
        ("EA_MADM_TASK2", "COMPETITOR_TASK2"),
        ("FIVE", "SEVEN"),
        ("TWELVE", "THIRTEEN"),
        ("TWO", "THREE"),
    ]:
        a, b = SAMPLES[x], SAMPLES[y]
        u = float(stats.mannwhitneyu(a, b).statistic) / (len(a) * len(b))
        print(f"({x}, {y}, {u!r}),")

    print("# exact permutation p of |T(x) - T(y)|: (statistic, x, y, p)")
    small_x = [73, 73, 75, 2000, 2000]
    small_y = [812, 2000, 1377, 954, 1105, 2000]
    tiny_x = [1, 5, 2]
    tiny_y = [9, 7, 8, 6]
    for label, statistic in [("Mean", np.mean), ("Median", np.median), ("Iqm", iqm)]:
        for x, y in [(small_x, small_y), (tiny_x, tiny_y), (small_y, tiny_x)]:
            result = stats.permutation_test(
                (np.asarray(x, float), np.asarray(y, float)),
                lambda a, b, axis: np.abs(statistic(a, axis=axis) - statistic(b, axis=axis)),
                permutation_type="independent",
                vectorized=True,
                n_resamples=np.inf,
                alternative="greater",
            )
            print(f"({label}, {rust_array(x)}, {rust_array(y)}, {float(result.pvalue)!r}),")

    print("# normal quantile: (p, norm.ppf(p))")
    for p in [1e-300, 1e-20, 1e-10, 1e-5, 0.001, 0.025, 0.07, 0.3, 0.5, 0.6, 0.8, 0.975, 0.999, 1 - 1e-10]:
        print(f"({p!r}, {float(stats.norm.ppf(p))!r}),")

    print("# exact bootstrap distribution of the mean: (x, 2.5 %, 97.5 %) over all n^n resamples")
    x = [1.0, 2.0, 4.0, 8.0, 16.0, 32.0]
    means = np.array([np.mean(r) for r in itertools.product(x, repeat=len(x))])
    print(f"({rust_array(x)}, {float(np.percentile(means, 2.5))!r}, {float(np.percentile(means, 97.5))!r}),")

    print("# scipy percentile bootstrap, 200 000 resamples: (what, statistic, low, high)")
    rng = np.random.default_rng(12345)
    a = np.asarray(SAMPLES["EA_MADM_TASK2"], float)
    b = np.asarray(SAMPLES["COMPETITOR_TASK2"], float)
    for label, statistic in [("Mean", np.mean), ("Iqm", iqm)]:
        one = stats.bootstrap(
            (a,), lambda s, axis: statistic(s, axis=axis), method="percentile",
            n_resamples=200_000, random_state=rng,
        ).confidence_interval
        print(f"(\"interval EA_MADM_TASK2\", {label}, {float(one.low)!r}, {float(one.high)!r}),")
        two = stats.bootstrap(
            (a, b), lambda s, t, axis: statistic(s, axis=axis) - statistic(t, axis=axis),
            method="percentile", n_resamples=200_000, random_state=rng,
        ).confidence_interval
        print(f"(\"difference EA_MADM_TASK2 - COMPETITOR_TASK2\", {label}, {float(two.low)!r}, {float(two.high)!r}),")

    print("# IQM conventions (docs/paper-notes.md §10.1a): (name, trim_mean 0.25, mean of the "
          "empirical quantile function over [0.25, 0.75])")
    for name, x in SAMPLES.items():
        x = np.sort(np.asarray(x, dtype=float))
        n = len(x)
        low, high = 0.25 * n, 0.75 * n
        weights = [max(0.0, min(i + 1, high) - max(i, low)) for i in range(n)]
        fractional = float(np.dot(weights, x) / (high - low))
        print(f"({name}, {float(iqm(x))!r}, {fractional!r}),")

    print("# least-squares slope against the index: (y, linregress slope)")
    for y in [[5.0, 3.0, 1.0], [1.0, 1.6, 1.9, 2.5], [2.0, 2.0],
              [0.8, 0.75, 0.9, 0.6, 0.55, 0.7, 0.4, 0.45, 0.5, 0.3, 0.35, 0.2]]:
        slope = stats.linregress(np.arange(len(y)), y).slope
        print(f"({rust_array(y)}, {float(slope)!r}),")

    print("# Student t 0.975 quantile: (df, t.ppf(0.975, df))")
    for df in [1, 2, 5, 19, 30, 31, 50, 100, 1000]:
        print(f"({df}, {float(stats.t.ppf(0.975, df))!r}),")

    print("# seed summary: (x, mean, sd ddof=1, t.ppf(0.975, n - 1) sd / sqrt(n))")
    x = np.asarray([3.0, 9.5, 4.25, 7.0, 1.0, 12.0, 6.5, 8.0, 2.0, 5.0])
    sd = np.std(x, ddof=1)
    half = stats.t.ppf(0.975, len(x) - 1) * sd / np.sqrt(len(x))
    print(f"({rust_array(x)}, {float(np.mean(x))!r}, {float(sd)!r}, {float(half)!r}),")


if __name__ == "__main__":
    main()
