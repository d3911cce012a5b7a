"""Numbers drawn from the sweeps: error statistics and checks of the paper's claims.

Every statistic uses the completed cases only (a case a guard stopped has no result: NaN max_error);
the sweeps may hold every case (``load_sweep(path, cases='all')``), the masks select.

Each claim check returns a `Claim` holding the verdict computed from the data (never assumed),
the numbers it rests on, and the rule applied, so that the report can show all three.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Dict, List, Mapping, Optional, Sequence

import numpy as np

from ..figures import linear_fit, timing_too_small
from ..loader import Sweep
from ..orders import log_slope

#: Element counts below this are left out of the convergence-rate fit of claim (d): one element
#: cannot represent the vibration mode at all (paper, Fig. 10), which says nothing about a rate.
CONVERGENCE_MIN_ELEMENTS = 3
#: Claim (b) concerns meshes at least this fine, claim (c) the meshes listed.
FINE_MESH_ELEMENTS = 10
COARSE_MESH_ELEMENTS = (1, 3)


@dataclass
class Claim:
    """One claim of the paper and whether mpm1d's numbers support it."""
    key: str
    statement: str
    rule: str
    holds: Optional[bool]            # None: the data needed is not there, or do not decide
    details: List[str] = field(default_factory=list)
    #: Why the data there do not support a verdict either way ('' = they do, or data missing).
    unsupported: str = ''

    @property
    def verdict(self) -> str:
        if self.holds is None:
            if self.unsupported:
                return f'no verdict: the data do not support one ({self.unsupported})'
            return 'not checked (data missing)'
        return 'holds' if self.holds else 'does not hold'


def median_by(sweep: Sweep, mask: np.ndarray, key: str, quantity: str = 'max_error'
              ) -> Dict[float, float]:
    """Median of `quantity` over the completed cases in `mask`, per distinct value of `key`."""
    mask = mask & sweep.ok
    values = sweep.cases[key][mask]
    result = {}
    for value in np.unique(values):
        result[value.item()] = float(np.median(sweep.cases[quantity][mask][values == value]))
    return result


def error_extremes(sweep: Sweep, scheme: str) -> Dict[str, object]:
    """Smallest and largest error of the completed cases of `scheme`, with their cases, and the
    count of failed cases per status name."""
    mask = sweep.where(scheme=scheme)
    ok = mask & sweep.ok
    result: Dict[str, object] = {'cases': int(mask.sum()), 'completed': int(ok.sum()),
                                 'failed': {}}
    for name in np.unique(sweep.cases['status_name'][mask & sweep.failed]):
        result['failed'][str(name)] = int(np.sum(
            (sweep.cases['status_name'] == name) & mask & sweep.failed))
    if ok.any():
        errors = np.where(ok, sweep.cases['max_error'], np.nan)
        for label, index in (('min', int(np.nanargmin(errors))), ('max', int(np.nanargmax(errors)))):
            result[label] = {c: sweep.cases[c][index].item() for c in
                             ('max_error', 'relative_error', 'elements', 'particles_per_element',
                              'dt_fraction')}
    return result


def verification_case(sweep: Sweep, scheme: str, elements: int = 20,
                      particles_per_element: int = 1, dt_fraction: float = 0.1
                      ) -> Optional[Dict[str, object]]:
    """The sweep's case matching the verification discretisation, or None."""
    mask = sweep.where(scheme=scheme, elements=elements,
                       particles_per_element=particles_per_element, dt_fraction=dt_fraction)
    if not mask.any():
        return None
    i = int(np.flatnonzero(mask)[0])
    return {c: sweep.cases[c][i].item() for c in ('max_error', 'relative_error', 'status_name',
                                                  'run_time')}


def _step_trend(sweep: Sweep, scheme: str, elements: int) -> Dict[str, float]:
    """How the median error (over particles per element) changes with the time step for one
    element count: log-log slope (> 0: error falls with smaller steps) and the ratio of the
    error at the largest step to that at the smallest."""
    by_dt = median_by(sweep, sweep.where(scheme=scheme, elements=elements), 'dt_fraction')
    steps = sorted(by_dt)
    if len(steps) < 2:
        return {'slope': float('nan'), 'ratio': float('nan'), 'smallest': float('nan'),
                'largest': float('nan')}
    return {'slope': log_slope(steps, [by_dt[k] for k in steps]),
            'ratio': by_dt[steps[-1]] / by_dt[steps[0]],
            'smallest': 100 * steps[0], 'largest': 100 * steps[-1]}


def _elements_of(sweep: Sweep, scheme: str) -> List[int]:
    return sorted(set(sweep.cases['elements'][sweep.where(scheme=scheme) & sweep.ok].tolist()))


def claim_elements(sweeps: Mapping[str, Sweep]) -> Claim:
    """(a) The error falls with more elements."""
    claim = Claim('a', 'The error falls as the number of elements grows.',
                  'median max error over all completed cases of each element count decreases '
                  'strictly from each element count to the next, for every scheme', None)
    verdicts = []
    for scheme, sweep in sweeps.items():
        medians = median_by(sweep, sweep.where(scheme=scheme), 'elements')
        if len(medians) < 2:
            continue
        counts = sorted(medians)
        values = [medians[c] for c in counts]
        falls = bool(np.all(np.diff(values) < 0))
        verdicts.append(falls)
        rises = [f'{a}→{b}' for a, b, u, v in zip(counts, counts[1:], values, values[1:])
                 if v >= u]
        claim.details.append(f'{scheme.upper()}: ' + ', '.join(
            f'{c} el. {v:.3g} m' for c, v in zip(counts, values))
            + ('' if falls else f' (no decrease at {", ".join(rises)})'))
    claim.holds = all(verdicts) if verdicts else None
    return claim


#: Error ratio (largest / smallest step) within which the error counts as flat, not falling.
FLAT_RATIO = 1.1


def _claim_steps(sweeps: Mapping[str, Sweep], key: str, statement: str, select, expect_fall: bool
                 ) -> Claim:
    """Claims (b) and (c): the trend of the error with the time step on chosen meshes."""
    direction = 'falls' if expect_fall else 'does not fall'
    claim = Claim(key, statement,
                  'the median error (over particles per element) at the largest step is '
                  f'{"more than" if expect_fall else "at most"} {FLAT_RATIO:g} times that at the '
                  f'smallest step (the error {direction} with smaller steps) for every such mesh and '
                  f'scheme; a ratio of at most {FLAT_RATIO:g} counts as not falling', None)
    verdicts = []
    for scheme, sweep in sweeps.items():
        for elements in [e for e in _elements_of(sweep, scheme) if select(e)]:
            trend = _step_trend(sweep, scheme, elements)
            if not np.isfinite(trend['slope']):
                continue
            falls = trend['ratio'] > FLAT_RATIO
            verdicts.append(falls == expect_fall)
            claim.details.append(
                f"{scheme.upper()}, {elements} el.: slope {trend['slope']:+.3g}, median error at "
                f"{trend['largest']:g} % / at {trend['smallest']:g} % = {trend['ratio']:.3g} "
                f"→ error {'falls' if falls else 'does not fall'} with smaller steps")
    claim.holds = all(verdicts) if verdicts else None
    return claim


def claim_fine_meshes(sweeps: Mapping[str, Sweep]) -> Claim:
    """(b) On fine meshes (>= 10 elements) the error falls with smaller time steps."""
    return _claim_steps(sweeps, 'b', f'On fine meshes (>= {FINE_MESH_ELEMENTS} elements) the '
                        'error falls with smaller time steps.',
                        lambda e: e >= FINE_MESH_ELEMENTS, expect_fall=True)


def claim_coarse_meshes(sweeps: Mapping[str, Sweep]) -> Claim:
    """(c) With 1 and 3 elements the error does not fall with smaller time steps."""
    return _claim_steps(sweeps, 'c', 'With ' + ' and '.join(map(str, COARSE_MESH_ELEMENTS))
                        + ' elements the error does not fall with smaller time steps.',
                        lambda e: e in COARSE_MESH_ELEMENTS, expect_fall=False)


def claim_usl_faster(sweeps: Mapping[str, Sweep]) -> Claim:
    """(d) USL converges faster than USF."""
    claim = Claim('d', 'USL converges to the exact solution faster than USF.',
                  'at the finest mesh both schemes ran, the median error of USL is below that of '
                  'USF, AND the log-log slope of median error against element count '
                  f'(meshes >= {CONVERGENCE_MIN_ELEMENTS} elements) is steeper (more negative) '
                  'for USL', None)
    if 'usf' not in sweeps or 'usl' not in sweeps:
        claim.details.append('needs both a USF and a USL sweep')
        return claim
    medians = {s: median_by(sweeps[s], sweeps[s].where(scheme=s), 'elements')
               for s in ('usf', 'usl')}
    common = sorted(set(medians['usf']) & set(medians['usl']))
    if not common:
        claim.details.append('the two sweeps share no element count')
        return claim
    finest = common[-1]
    lower = medians['usl'][finest] < medians['usf'][finest]
    claim.details.append(f'finest common mesh {finest} el.: median error USF '
                         f"{medians['usf'][finest]:.3g} m, USL {medians['usl'][finest]:.3g} m")
    slopes = {}
    for s in ('usf', 'usl'):
        counts = [c for c in common if c >= CONVERGENCE_MIN_ELEMENTS]
        slopes[s] = log_slope(counts, [medians[s][c] for c in counts])
    steeper = bool(slopes['usl'] < slopes['usf'])
    claim.details.append(f"convergence slope d log(error)/d log(elements): USF "
                         f"{slopes['usf']:.3g}, USL {slopes['usl']:.3g}")
    if not all(np.isfinite(list(slopes.values()))):
        claim.holds = None
        claim.details.append(f'fewer than two element counts >= {CONVERGENCE_MIN_ELEMENTS}')
        return claim
    claim.holds = bool(lower and steeper)
    if lower != steeper:
        claim.details.append('the two criteria disagree: ' + (
            'USL is more accurate at the finest mesh but its slope is not steeper' if lower else
            'USL has the steeper slope but is not more accurate at the finest mesh'))
    return claim


#: A verdict on a timing fit needs steady timings: the median over the fit's cases of the relative
#: spread of their repeats (interquartile range / median, /cases/run_time_spread) at most this.
MAX_TIMING_SPREAD = 0.2
#: ... and at least this many points (a line through 3 points says little about linearity).
MIN_FIT_POINTS = 4


@dataclass
class LineJudgement:
    """Whether measured points lie on a line, judged so that timing noise cannot flip it."""
    verdict: Optional[bool]     # True: linear, False: not linear, None: the data do not decide
    r2: float                   # R² of the least-squares line through every point
    r2_range: tuple             # (min, max) of R² with any one point left out
    spread: float               # median relative spread of the points' repeats (NaN: not stored)
    reason: str                 # why, in words, with the numbers


def _r2_line(x: np.ndarray, y: np.ndarray) -> float:
    """R² of the least-squares line through the points."""
    return linear_fit(x, y)['r2']


def judge_linear(x: Sequence[float], y: Sequence[float], spread: Optional[Sequence[float]] = None,
                 threshold: float = 0.97) -> LineJudgement:
    """Is y linear in x (R² of the least-squares line above `threshold`)? A verdict is stated only
    when the data support it: the timings are steady (median spread of their repeats at most
    MAX_TIMING_SPREAD), the line's change over the measured range is larger than their spread
    (figures.timing_too_small), there are at least MIN_FIT_POINTS points, no single point decides it
    (R² with any one point left out stays on the same side of the threshold; a point that decides
    is an outlier to re-time, not evidence), and points off the line lie on a curve (a parabola's R²
    above `threshold`; else they scatter). Otherwise the verdict is None, with the reason."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    n = x.size
    r2 = _r2_line(x, y) if n >= 2 else float('nan')
    spreads = np.asarray(spread, float) if spread is not None else np.array([])
    median_spread = float(np.median(spreads)) if spreads.size else float('nan')
    if n < MIN_FIT_POINTS:
        return LineJudgement(None, r2, (r2, r2), median_spread,
                             f'{n} points; at least {MIN_FIT_POINTS} needed')
    left_out = [_r2_line(np.delete(x, i), np.delete(y, i)) for i in range(n)]
    low, high = float(np.nanmin(left_out)), float(np.nanmax(left_out))
    numbers = (f'R² = {r2:.4f}, {low:.4f} to {high:.4f} with any one of the {n} points left out'
               + (f', median spread of the repeats {median_spread:.2g}' if spreads.size else ''))
    if spreads.size and median_spread > MAX_TIMING_SPREAD:
        return LineJudgement(None, r2, (low, high), median_spread,
                             f'timings too noisy (median spread of the repeats {median_spread:.2g} > '
                             f'{MAX_TIMING_SPREAD:g}): {numbers}')
    if spreads.size:
        fit = linear_fit(x, y)
        too_small = timing_too_small(fit['slope'] * x + fit['intercept'], y, spreads)
        if too_small:
            return LineJudgement(None, r2, (low, high), median_spread, f'{too_small}: {numbers}')
    if low > threshold and r2 > threshold:
        return LineJudgement(True, r2, (low, high), median_spread, numbers)
    if high <= threshold and r2 <= threshold:
        # off a line: a curve says so only if the points lie on one (a parabola fits them); points
        # that scatter about every smooth curve are timing noise between the cases
        curve = np.polyval(np.polyfit(x, y, 2), x)
        r2_curve = 1.0 - float(np.sum((y - curve) ** 2) / np.sum((y - np.mean(y)) ** 2))
        if r2_curve <= threshold:
            return LineJudgement(None, r2, (low, high), median_spread,
                                 f'the points scatter about any smooth curve (R² of a parabola {r2_curve:.2f}): '
                                 f'timing noise between the cases, not a shape: {numbers}')
        return LineJudgement(False, r2, (low, high), median_spread, numbers)
    worst = int(np.nanargmax(left_out)) if r2 <= threshold else int(np.nanargmin(left_out))
    return LineJudgement(None, r2, (low, high), median_spread,
                         f'one point decides (x = {x[worst]:g}; re-time it): {numbers}')


def claim_linear_time(fits: Mapping[str, Mapping], threshold: float = 0.97) -> Claim:
    """(e) Computation time is linear in the number of particles (R² > 0.97 in the paper); stated
    only where the timings support a verdict (judge_linear)."""
    claim = Claim('e', f'Computation time grows linearly with the particle count '
                  f'(R² > {threshold:g} in the paper).',
                  f'R² of the least-squares line of time against particles per element > '
                  f'{threshold:g} for every scheme, with any one point left out too; no verdict when '
                  f'a single point decides it, with fewer than {MIN_FIT_POINTS} points, when the '
                  f'repeats of a case spread by more than {MAX_TIMING_SPREAD:g} of their median '
                  f'(median over the cases), or when the line changes over the measured range by no '
                  f'more than that spread of the median time (too small to judge); "does not hold" '
                  f'only when the points lie on a curve (R² of a parabola > {threshold:g})', None)
    verdicts = []
    for scheme, fit in fits.items():
        line = fit['particles']
        judged = judge_linear(line['x'], line['time'], line.get('spread'), threshold)
        verdicts.append(judged.verdict)
        word = {True: 'linear', False: 'not linear', None: 'undecided'}[judged.verdict]
        claim.details.append(f'{scheme.upper()}: {word}; {judged.reason}')
    if not verdicts:
        return claim
    if any(v is None for v in verdicts):
        claim.unsupported = 'see the schemes marked undecided'
        return claim
    claim.holds = all(verdicts)
    return claim


def check_claims(sweeps: Mapping[str, Sweep], fits: Mapping[str, Mapping]) -> List[Claim]:
    """All claim checks, in the order of the report."""
    return [claim_elements(sweeps), claim_fine_meshes(sweeps), claim_coarse_meshes(sweeps),
            claim_usl_faster(sweeps), claim_linear_time(fits)]
