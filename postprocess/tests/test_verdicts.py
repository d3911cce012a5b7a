"""Verdicts in summaries are stated only when the data support them: claim (e), "computation time
is linear in the particle count", on synthetic timings. Clean data: it holds. A straight line with
one disturbed timing (the USL fit that gave R² = 0.37 in one run and 0.99 in the next): no verdict,
the point named. Noisy repeats: no verdict. A real curve measured cleanly: it does not hold."""
from __future__ import annotations

import numpy as np

from mpm1d_post.studies import paper_claims as analysis

PARTICLES = np.arange(1, 11, dtype=float)


def _fits(times, spread):
    r2 = float(np.corrcoef(PARTICLES, times)[0, 1] ** 2)     # R² of the least-squares line
    return {'usl': {'particles': {'x': PARTICLES.tolist(), 'time': list(times), 'spread': list(spread),
                                  'r2': r2}}}


def _line(noise=0.01, seed=3):
    rng = np.random.default_rng(seed)
    return (2e-4 + 5e-5 * PARTICLES) * (1 + noise * rng.standard_normal(PARTICLES.size))


def test_clean_line_holds():
    claim = analysis.claim_linear_time(_fits(_line(), np.full(10, 0.02)))
    assert claim.holds is True and claim.verdict == 'holds', claim.details


def test_one_disturbed_timing_gives_no_verdict():
    times = _line()
    times[6] *= 4.0                       # one case timed while a neighbour ran
    judged = analysis.judge_linear(PARTICLES, times, np.full(10, 0.02))
    assert judged.r2 < 0.97 < judged.r2_range[1]       # R² alone would say "does not hold"
    claim = analysis.claim_linear_time(_fits(times, np.full(10, 0.02)))
    assert claim.holds is None and claim.verdict.startswith('no verdict'), claim.verdict
    assert 'x = 7' in claim.details[0] and 're-time' in claim.details[0]


def test_noisy_repeats_give_no_verdict():
    claim = analysis.claim_linear_time(_fits(_line(), np.full(10, 0.5)))
    assert claim.holds is None and 'too noisy' in claim.details[0], claim.details


def test_too_few_points_give_no_verdict():
    judged = analysis.judge_linear(PARTICLES[:3], _line()[:3])
    assert judged.verdict is None and '3 points' in judged.reason


def test_a_real_curve_does_not_hold():
    times = 1e-5 * PARTICLES ** 3 * (1 + 0.01 * np.random.default_rng(5).standard_normal(10))
    claim = analysis.claim_linear_time(_fits(times, np.full(10, 0.02)))
    assert claim.holds is False and claim.verdict == 'does not hold', claim.details


def test_without_stored_spreads_the_outlier_rule_still_applies():
    times = _line()
    times[2] *= 5.0
    fits = {'usf': {'particles': {'x': PARTICLES.tolist(), 'time': times.tolist(), 'spread': None}}}
    assert analysis.claim_linear_time(fits).holds is None


def test_a_change_within_the_spread_gives_no_verdict():
    """Timings of 3 elements (USL, 2.4e-4 s a run) that do not grow with the particles: R² near 0,
    yet the line changes over n = 1..10 by less than the repeats' spread of the median time, so
    the data cannot tell flat from linear."""
    times = 2.4e-4 * (1 + 0.01 * np.random.default_rng(7).standard_normal(10))
    judged = analysis.judge_linear(PARTICLES, times, np.full(10, 0.065))
    assert judged.r2 < 0.5 and judged.verdict is None, judged
    assert 'too small to judge' in judged.reason, judged.reason
    claim = analysis.claim_linear_time(_fits(times, np.full(10, 0.065)))
    assert claim.holds is None and claim.verdict.startswith('no verdict'), claim.verdict


def test_scatter_between_cases_gives_no_verdict():
    """Each case's repeats agree (spread 0.02) but the cases, timed at different moments of a shared
    machine, scatter by 30 % about the line: R² is low, yet no curve fits either, so this is not
    evidence against linearity."""
    times = (2e-4 + 1e-5 * PARTICLES) * (1 + 0.3 * np.random.default_rng(11).standard_normal(10))
    judged = analysis.judge_linear(PARTICLES, times, np.full(10, 0.02))
    assert judged.r2 < 0.97 and judged.verdict is None, judged
    assert 'scatter about any smooth curve' in judged.reason, judged.reason
