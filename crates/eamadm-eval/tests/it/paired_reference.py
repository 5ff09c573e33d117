"""Reference values for `eamadm_eval::stats::paired`, computed by independent implementations.

Not run by CI. The values it prints are pinned in `paired.rs` next to this file; rerun it to
check them after a change of inputs:

    python3 -m venv /tmp/statsref
    /tmp/statsref/bin/pip install scipy numpy statsmodels
    /tmp/statsref/bin/python crates/eamadm-eval/tests/it/paired_reference.py

Pinned with scipy 1.17.1, statsmodels 0.15.0, numpy 2.4.6.

Sources of truth:
  * sign-flip test: scipy.stats.permutation_test((d,), statistic, permutation_type="samples",
    n_resamples=inf) (all 2^n sign vectors enumerated), statistic = mean or
    scipy.stats.trim_mean(., 0.25) (the IQM)
  * TOST: max of the "greater" test on d + margin and the "less" test on d - margin, each as above
  * sign test / McNemar exact: scipy.stats.binomtest(k, n, 0.5).pvalue and
    statsmodels.stats.contingency_tables.mcnemar(table, exact=True).pvalue, and the exact
    rational 2 sum_{i <= k} C(n, i) / 2^n with fractions.Fraction
"""

from fractions import Fraction
from math import comb

import numpy as np
from scipy import stats
from statsmodels.stats.contingency_tables import mcnemar

# Final steps of two methods on the same ten seeds (made up, shaped like Task I: most seeds at
# the optimum 58, one detour, one collapse to the 2000-step cap).
X = [58, 58, 60, 58, 2000, 58, 64, 58, 58, 60]
Y = [58, 60, 58, 58, 58, 58, 60, 58, 62, 58]
# Twelve paired differences without ties at 0.
D12 = [1.5, -0.5, 2.0, 0.25, -1.0, 3.0, 0.75, -0.25, 1.25, 0.5, -2.0, 1.0]


def mean(d, axis=-1):
    return np.mean(d, axis=axis)


def iqm(d, axis=-1):
    return stats.trim_mean(d, 0.25, axis=axis)


def flip(d, statistic, alternative):
    return stats.permutation_test(
        (np.asarray(d, dtype=float),),
        statistic,
        permutation_type="samples",
        n_resamples=np.inf,
        alternative=alternative,
        vectorized=True,
    ).pvalue


d10 = list(np.subtract(X, Y).astype(float))
print("d10 =", d10)
for name, d in [("d10", d10), ("D12", D12)]:
    for sname, s in [("mean", mean), ("iqm", iqm)]:
        for alt in ["two-sided", "greater", "less"]:
            print(f"{name} {sname} {alt}: {flip(d, s, alt)!r}")
for name, d, margin in [("d10", d10, 2.0), ("D12", D12, 2.0), ("D12", D12, 1.0)]:
    for sname, s in [("mean", mean), ("iqm", iqm)]:
        lower = flip(np.add(d, margin), s, "greater")
        upper = flip(np.subtract(d, margin), s, "less")
        print(f"TOST {name} {sname} margin {margin}: {max(lower, upper)!r}")
for wins, losses in [(2, 0), (0, 5), (3, 0), (5, 0), (1, 1), (2, 1), (1, 7), (0, 9), (3, 14),
                     (10, 10), (1, 19), (0, 0), (10, 115), (60, 65), (63, 63), (10, 116),
                     (5, 121), (80, 120), (60, 70), (0, 130)]:
    n = wins + losses
    p = stats.binomtest(wins, n, 0.5).pvalue if n else 1.0
    m = mcnemar([[5, wins], [losses, 5]], exact=True).pvalue if n else 1.0
    # The exact rational's nearest float: scipy is a few ulps off it at large n (60 vs 65).
    k = min(wins, losses)
    rational = min(Fraction(1), 2 * Fraction(sum(comb(n, i) for i in range(k + 1)), 2**n))
    print(f"sign {wins} {losses}: {float(p)!r} (mcnemar {float(m)!r}, exact {float(rational)!r})")
