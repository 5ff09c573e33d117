"""Reference values for `eamadm_eval::stats::paired_mean` (issue 34), by independent means.

Not run by CI. The values it prints are pinned in `paired_mean.rs` next to this file; rerun it
to check them after a change of inputs:

    python3 -m venv /tmp/statsvenv
    /tmp/statsvenv/bin/pip install scipy numpy statsmodels
    /tmp/statsvenv/bin/python crates/eamadm-eval/tests/it/paired_mean_reference.py

Pinned with scipy 1.17.1, numpy 2.4.6, Python 3.11.

Sources of truth:
  * one-sided sign-flip p-values of the mean of d - c:
    scipy.stats.permutation_test((d - c,), mean, permutation_type="samples",
    n_resamples=inf, alternative="greater" / "less") -- all 2^n sign vectors enumerated;
  * the interval: every non-empty subset's mean computed with numpy (the subsets as the
    rows of a 0/1 matrix), sorted, and the one at rank floor(0.025 * 2^n) taken from each end
    (Hartigan's subsample means; the inversion of the sign-flip test);
  * beyond = min(1, 2 min(p_less(-m), p_greater(m))), within = min(1, 2 max(p_greater(-m),
    p_less(m))) from those scipy p-values.
The samples' values are multiples of 1/20 or 1/4 whose sums are exact in binary where they
tie, so ties are exact ties for both implementations.
"""

import numpy as np
from scipy import stats

# Task-II-like paired differences of final steps (EA-MADM - a competitor): 6 seeds where
# EA-MADM collapsed to the 2000-step cap, 14 where it reached in 73-77 steps.
TASK2 = [-1235.65, 567.2, 507.4, 449.45, -1400.0, 496.95, -1417.55, -1502.75, -1406.9,
         -1528.7, -1333.6, 551.7, -1408.2, -1485.3, -1470.2, -1357.4, -1428.75, 637.05,
         -1385.65, -1353.75]
# Task-I-like: most seeds tie at 0, two collapses, a few detours of 2 steps.
TASK1 = [0.0, 0.0, 0.0, -2.0, 0.0, 0.0, 0.0, -2.0, 0.0, 0.0, 0.0, 0.0, 0.25, 0.0, 1942.0,
         0.0, 1940.0, 0.0, -4.0, 0.0]
# Twelve without ties; seven; five (too few for a 95 % interval).
D12 = [1.5, -0.5, 2.0, 0.25, -1.0, 3.0, 0.75, -0.25, 1.25, 0.5, -2.0, 1.0]
D7 = [3.0, 1.0, 4.0, 1.5, 5.0, 9.0, 2.5]
D5 = [3.0, 1.0, 4.0, 1.5, 5.0]


def mean(d, axis=-1):
    return np.mean(d, axis=axis)


def p(d, c, alternative):
    return stats.permutation_test(
        (np.asarray(d, dtype=float) - c,), mean, permutation_type="samples",
        n_resamples=np.inf, alternative=alternative, vectorized=True, batch=1 << 16,
    ).pvalue


def interval(d, confidence=0.95):
    d = np.asarray(d, dtype=float)
    n = len(d)
    masks = np.arange(1, 1 << n, dtype=np.int64)
    bits = ((masks[:, None] >> np.arange(n)) & 1).astype(float)
    means = np.sort(bits @ d / bits.sum(axis=1))
    k = int(np.floor((1 - confidence) / 2 * 2 ** n))
    if k == 0:
        return None, None
    return means[k - 1], means[len(means) - k]


for name, d, margin in [("TASK2", TASK2, 2.0), ("TASK1", TASK1, 2.0), ("D12", D12, 0.5),
                        ("D7", D7, 1.0), ("D5", D5, 1.0)]:
    g0, l0 = p(d, 0.0, "greater"), p(d, 0.0, "less")
    gm, lm = p(d, -margin, "greater"), p(d, -margin, "less")
    gp, lp = p(d, margin, "greater"), p(d, margin, "less")
    low, high = interval(d)
    print(f"{name}: n={len(d)} mean={np.mean(d)!r}")
    print(f"  p_greater(0)={g0!r} p_less(0)={l0!r} two_sided={min(1, 2 * min(g0, l0))!r}")
    print(f"  margin={margin} beyond={min(1.0, 2 * min(lm, gp))!r} within={min(1.0, 2 * max(gm, lp))!r}")
    print(f"  p_greater(-m)={gm!r} p_less(m)={lp!r} p_less(-m)={lm!r} p_greater(m)={gp!r}")
    print(f"  interval95=({low!r}, {high!r})")
    if name == "D12":
        for conf in (0.5, 0.9, 0.99):
            print(f"  interval{conf}={interval(d, conf)!r}")
