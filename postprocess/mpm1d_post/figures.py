"""The figures of the mpm1d bar study (paper figures 3b-10, and an error-versus-time plot).

One function per figure. Each takes data loaded by `mpm1d_post.loader` and an output folder, writes PNG
file(s) and returns the written path(s) (and, where the figure rests on a computation such as a
fit or a Pareto front, the numbers too). Every figure names its quantities with units, the scheme
and the parameters, and carries a footer with the code version and input files (provenance).

Shared pieces: `save_figure` (footer and PNG), `case_grid` + `draw_colour_map` (the colour maps of
figures 4, 5, 7, 8), `shared_log_norm` (one colour scale across panels and schemes), the fits
`linear_fit` / `rational_fit`, `scene_text` (a scene's own parameters with units) and
`plain_ticks`.

The sweeps given to the figures hold every case (``load_sweep(path, cases='all')``): fits, fronts and
colour scales use the completed cases only; a case a guard stopped has no result and is drawn apart
(a red 'x' in the maps), a case not run is hatched.
"""

from __future__ import annotations

from pathlib import Path
import re
import textwrap
from dataclasses import dataclass
from typing import Dict, Iterable, List, Mapping, Optional, Sequence, Tuple, Union

import matplotlib
import matplotlib.ticker

matplotlib.use('Agg')
import matplotlib.pyplot as plt  # noqa: E402  (the backend must be chosen first)
from matplotlib.colors import LogNorm  # noqa: E402
from matplotlib.lines import Line2D  # noqa: E402
import numpy as np  # noqa: E402

from .loader import Run, Sweep  # noqa: E402
from .output_files import save_figure_file  # noqa: E402
from .pareto import pareto_front  # noqa: E402

DPI = 150
#: Paper figure numbers of the per-scheme figures: (error map, time map, time fits).
FIGURE_NUMBERS = {'usf': (4, 5, 6), 'usl': (7, 8, 9)}
SCHEME_MARKERS = {'usf': 'o', 'usl': 's', 'musl': '^'}
ERROR_LABEL = r'max $|u_{cm} - u_{cm}^{exact}|$ (m)'
TIME_LABEL = 'computation time per run (s)'
PPE_LABEL = 'particles per element'
#: The sweep's time-step setting is dt_fraction = dt·c/dx, a fraction of the time dx/c a wave takes to
#: cross an element: not the stability limit, which depends on the scheme (USL with linear shapes
#: and 1 particle per element: about 0.71), so the axes say what it is (once).
DT_LABEL = 'time step dt (% of dx/c)'
#: Median repeat spread (interquartile range over median of a case's timing repeats) above which
#: timings are too noisy to fit (the paper claims' rule, studies.paper_claims.MAX_TIMING_SPREAD).
NOISY_TIMING_SPREAD = 0.2

Source = Union[Run, Sweep]


class FigureSkipped(Exception):
    """The data needed for a figure is not in the inputs; the message says what is missing."""


# --------------------------------------------------------------------------------------------
# Shared helpers: provenance, saving, text
# --------------------------------------------------------------------------------------------

def provenance(sources: Iterable[Source]) -> str:
    """Footer text: code version(s) and input file name(s) of the data shown."""
    versions, files = [], []
    for source in sources:
        versions += source.code_versions if isinstance(source, Sweep) else [source.code_version]
        files += source.paths if isinstance(source, Sweep) else [source.path]
    versions = list(dict.fromkeys(versions))
    files = list(dict.fromkeys(Path(f).name for f in files))
    shown = ', '.join(files[:4]) + (f' (+{len(files) - 4} more)' if len(files) > 4 else '')
    return f"{' / '.join(versions)}  |  data: {shown}  |  mpm1d postprocess"


def save_figure(fig: plt.Figure, outdir: str, name: str, sources: Iterable[Source]) -> str:
    """Add the provenance footer, write `outdir/name` as PNG and close the figure."""
    fig.text(0.005, 0.004, provenance(sources), fontsize=6.5, color='0.35',
             ha='left', va='bottom')
    Path(outdir).mkdir(parents=True, exist_ok=True)
    path = str(Path(outdir) / name)
    save_figure_file(fig, path, dpi=DPI)
    plt.close(fig)
    return path


def output_folder_problem(outdir: Path, given: str) -> str:
    """Make the figures' folder `outdir` (`given` on the command line as -o): '' when it is there or was
    made, else what is wrong, for the command's message."""
    if outdir.exists() and not outdir.is_dir():
        return (f'-o {given}: is an existing file, not a folder; allowed: a folder (created when missing) for '
                'the figures')
    try:
        outdir.mkdir(parents=True, exist_ok=True)
    except OSError as exc:
        return f'-o {given}: cannot make the folder ({exc.strerror})'
    return ''


def duration_text(config: Mapping) -> str:
    """'t_end = 0.01 s', '1 period', '2.5 periods': how long the run is."""
    if 'end_time' in config:
        return f"t_end = {config['end_time']:g} s"
    periods = float(config.get('periods', float('nan')))
    return f"{periods:g} period{'' if periods == 1 else 's'}"


def problem_text(config: Mapping) -> str:
    """One line with the physical parameters of the bar problem."""
    return (f"E = {config.get('youngs_modulus', float('nan')) / 1e9:g} GPa, "
            f"ρ = {config.get('density', float('nan')):g} kg/m³, L = {config['length']:g} m, "
            f"v0 = {config['velocity_amplitude']:g} m/s, mode {config['mode']}, {duration_text(config)}")


def _namelist_group(namelist: str, group: str) -> List[str]:
    """The variable names given in `group` of namelist text (the /config 'namelist' attribute, which
    holds the variables the run's scene uses and leaves out those of other scenes)."""
    text = re.sub(r"'[^']*'|\"[^\"]*\"", "''", namelist)  # no '/' or '=' inside quoted text
    found = re.search(r'&' + group + r'\b(.*?)/', text, re.S | re.I)
    return [name.lower() for name in re.findall(r'([A-Za-z_]\w*)\s*=', found.group(1))] if found else []


def _with_unit(name: str, value, unit: str) -> str:
    if isinstance(value, np.ndarray) and value.ndim > 0:
        text = ', '.join(f'{v:g}' for v in value.ravel())
    elif isinstance(value, (int, float, np.integer, np.floating)):
        text = f'{value:g}'
    else:
        text = str(value)
    unit = unit.strip()
    return f'{name} = {text}' + (f' {unit}' if unit and unit != '-' else '')


def scene_text(source: Source, swept: Sequence[str] = ()) -> str:
    """The scene's kind and its own parameters with units (those its namelist's &scene group gives,
    not another scene's), the swept ones left out, and the run's duration: 'manufactured: length =
    1 m, youngs_modulus = 1e+07 Pa, density = 1000 kg/m^3, amplitude = 0.001 m, 1 period'."""
    config = source.config
    kind = str(config.get('scene_kind', 'vibrating_bar'))
    units = {p.attribute: p.unit for p in source.parameters if p.group == 'scene'}
    names = _namelist_group(str(config.get('namelist', '')), 'scene')
    if not names:  # files without the namelist text: the bar's parameters
        names = ['length', 'youngs_modulus', 'density', 'velocity_amplitude', 'mode']
    shown = [_with_unit(n, config[n], units.get(n, '')) for n in names
             if n not in ('kind', 'scene_kind') and n not in swept and n in config]
    return f"{kind.replace('_', ' ')}: " + ', '.join(shown + [duration_text(config)])


def plain_ticks(ax: plt.Axes, values: Iterable[float], axis: str = 'x') -> None:
    """Ticks at `values` written as plain numbers (element counts: 10, 20, 40, not 10^1 and a
    bare 2×10^1) on a logarithmic axis."""
    values = sorted(set(float(v) for v in values))
    target = ax.xaxis if axis == 'x' else ax.yaxis
    target.set_major_locator(matplotlib.ticker.FixedLocator(values))
    target.set_major_formatter(matplotlib.ticker.FixedFormatter([f'{v:g}' for v in values]))
    target.set_minor_locator(matplotlib.ticker.NullLocator())


def signed(value: float, unit: str = '') -> str:
    """' + 1.2e-3 s' or ' − 1.2e-3 s': a coefficient written after another term."""
    return f"{' −' if value < 0 else ' +'} {abs(value):.3g}{' ' + unit if unit else ''}"


def figure_title(scheme: str, which: int, text: str) -> str:
    """'Fig. N — SCHEME — text' with the paper's number for USF/USL (the scheme early, so that it
    is never the part a narrow figure loses)."""
    numbers = FIGURE_NUMBERS.get(scheme)
    prefix = f'Fig. {numbers[which]} — ' if numbers else ''
    return f'{prefix}{scheme.upper()} — {text}'


def wrap_phrases(line: str, characters: int) -> List[str]:
    """`line` cut into lines of at most `characters`, between phrases (at ' — ', ', ', '; ') where it
    can, within a phrase only when the phrase alone is longer than a line."""
    phrases, rest = [], line
    while rest:
        cuts = [(rest.find(sep), sep) for sep in (' — ', ', ', '; ') if rest.find(sep) >= 0]
        if not cuts:
            phrases.append(rest)
            break
        at, sep = min(cuts)
        phrases.append(rest[:at + len(sep.rstrip())])
        rest = rest[at + len(sep):]
    lines, current = [], ''
    for phrase in phrases:
        candidate = f'{current} {phrase}' if current else phrase
        if len(candidate) <= characters or not current:
            current = candidate
        else:
            lines.append(current)
            current = phrase
        if len(current) > characters:  # a phrase longer than a line: at word boundaries
            parts = textwrap.wrap(current, characters, break_on_hyphens=False)
            lines += parts[:-1]
            current = parts[-1]
    return lines + [current] if current else lines or ['']


def fitted_title(fig: plt.Figure, text: str, fontsize: float = 10) -> plt.Text:
    """`fig.suptitle(text)`, each line wrapped to the figure's width between phrases (never in the
    middle of 'median over repeats'), so that no part of a title is cut off however narrow the
    figure (one-panel maps are 5 inches wide)."""
    width_points = fig.get_figwidth() * 72.0 * 0.94
    characters = max(20, int(width_points / (0.56 * fontsize)))  # an average glyph is ~0.5 em wide
    lines = [wrapped for line in text.split('\n') for wrapped in wrap_phrases(line, characters)]
    return fig.suptitle('\n'.join(lines), fontsize=fontsize)


def wavenumber(config: Mapping) -> float:
    """β_n = (2n − 1)π / (2L) of the bar's vibration mode."""
    return (2 * int(config['mode']) - 1) * np.pi / (2 * float(config['length']))


# --------------------------------------------------------------------------------------------
# Shared helpers: numbers
# --------------------------------------------------------------------------------------------

def r_squared(y: Sequence[float], y_fit: Sequence[float]) -> float:
    """Coefficient of determination 1 − SS_res/SS_tot (1 for a perfect fit)."""
    y, y_fit = np.asarray(y, float), np.asarray(y_fit, float)
    ss_res = float(np.sum((y - y_fit) ** 2))
    ss_tot = float(np.sum((y - y.mean()) ** 2))
    if ss_tot == 0.0:
        return 1.0 if ss_res == 0.0 else float('nan')
    return 1.0 - ss_res / ss_tot


def linear_fit(x: Sequence[float], y: Sequence[float]) -> Dict[str, float]:
    """Least-squares line y = slope·x + intercept, with its R²."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    if x.size < 2:
        raise FigureSkipped('a fit needs at least two points')
    slope, intercept = np.polyfit(x, y, 1)
    return {'slope': float(slope), 'intercept': float(intercept),
            'r2': r_squared(y, slope * x + intercept)}


def rational_fit(k: Sequence[float], y: Sequence[float]) -> Dict[str, float]:
    """Least-squares y = a/k + b (linear in 1/k), with its R² on y."""
    k, y = np.asarray(k, float), np.asarray(y, float)
    line = linear_fit(1.0 / k, y)
    return {'a': line['slope'], 'b': line['intercept'],
            'r2': r_squared(y, line['slope'] / k + line['intercept'])}


def shared_log_norm(arrays: Iterable[np.ndarray]) -> LogNorm:
    """A logarithmic colour scale covering the finite positive values of all `arrays`."""
    values = np.concatenate([np.ravel(a) for a in arrays] or [np.array([])])
    values = values[np.isfinite(values) & (values > 0)]
    if values.size == 0:
        raise FigureSkipped('no finite positive values to colour')
    low, high = values.min(), values.max()
    if high <= low:
        low, high = low / 2, high * 2
    return LogNorm(vmin=low, vmax=high)


# --------------------------------------------------------------------------------------------
# Shared helpers: colour maps over particles per element x time-step fraction
# --------------------------------------------------------------------------------------------

@dataclass
class CaseGrid:
    """Values of one quantity over particles per element (columns) × time-step fraction (rows)."""
    particles_per_element: np.ndarray
    dt_percent: np.ndarray
    values: np.ndarray      # shape (rows, columns), NaN where no completed case
    failed: np.ndarray      # shape (rows, columns), True where a guard stopped the case (no result)
    missing: np.ndarray     # shape (rows, columns), True where no case ran (none, or not run)


def case_grid(sweep: Sweep, mask: np.ndarray, quantity: str) -> CaseGrid:
    """Arrange `quantity` of the cases selected by `mask` as a particles × time-step grid."""
    cases = sweep.cases
    ppe = np.unique(cases['particles_per_element'][mask])
    dtp = np.unique(np.round(100 * cases['dt_fraction'][mask], 9))
    values = np.full((dtp.size, ppe.size), np.nan)
    failed = np.zeros(values.shape, bool)
    missing = np.ones(values.shape, bool)
    for i in np.flatnonzero(mask):
        row = np.searchsorted(dtp, np.round(100 * cases['dt_fraction'][i], 9))
        col = np.searchsorted(ppe, cases['particles_per_element'][i])
        if cases['status'][i] == 0:
            values[row, col] = cases[quantity][i]
            missing[row, col] = False
        elif cases['status'][i] > 0:
            failed[row, col] = True
            missing[row, col] = False
    return CaseGrid(ppe, dtp, values, failed, missing)


def draw_colour_map(ax: plt.Axes, grid: CaseGrid, norm: LogNorm, cmap: str = 'viridis',
                    annotate: Optional[str] = None):
    """Draw `grid` as cells on `ax` with the colour scale `norm`; cases a guard stopped (no result)
    get a red 'x' on grey, cases without data are hatched. `annotate` is a format for the value written in each cell.
    Returns the mappable (for a colourbar)."""
    rows, cols = grid.values.shape
    colours = plt.get_cmap(cmap).copy()
    colours.set_bad('0.85')
    mesh = ax.pcolormesh(np.arange(cols + 1) - 0.5, np.arange(rows + 1) - 0.5,
                         np.ma.masked_invalid(grid.values), norm=norm, cmap=colours,
                         shading='flat')
    fail_r, fail_c = np.nonzero(grid.failed)
    ax.plot(fail_c, fail_r, 'x', color='red', markersize=7, markeredgewidth=1.8, linestyle='none')
    for r, c in zip(*np.nonzero(grid.missing)):
        ax.add_patch(plt.Rectangle((c - 0.5, r - 0.5), 1, 1, fill=False, hatch='//',
                                   edgecolor='0.6', linewidth=0))
    if annotate:
        for r, c in zip(*np.nonzero(np.isfinite(grid.values))):
            value = grid.values[r, c]
            dark = norm(value) < 0.55
            ax.text(c, r, format(value, annotate), ha='center', va='center', fontsize=5.5,
                    color='white' if dark else 'black')
    step_c, step_r = max(1, cols // 10), max(1, rows // 10)
    ax.set_xticks(np.arange(0, cols, step_c), [f'{v:g}' for v in grid.particles_per_element[::step_c]])
    ax.set_yticks(np.arange(0, rows, step_r), [f'{v:g}' for v in grid.dt_percent[::step_r]])
    ax.set_xlim(-0.5, cols - 0.5)
    ax.set_ylim(-0.5, rows - 0.5)
    return mesh


def _status_legend(fig: plt.Figure, grids: Sequence[CaseGrid]) -> None:
    """A figure legend explaining the 'x' and hatch marks, when any are shown."""
    handles = []
    if any(g.failed.any() for g in grids):
        handles.append(Line2D([], [], marker='x', color='red', linestyle='none',
                              markeredgewidth=1.8, label='stopped by a guard: no result'))
    if any(g.missing.any() for g in grids):
        handles.append(plt.Rectangle((0, 0), 1, 1, fill=False, hatch='//', edgecolor='0.6',
                                     label='no data (not run)'))
    if handles:
        fig.legend(handles=handles, loc='upper right', fontsize=8, frameon=False)


def _panel_layout(count: int) -> Tuple[int, int]:
    """(rows, columns) for `count` panels: at most three per row."""
    columns = min(count, 3)
    return int(np.ceil(count / columns)), columns


def _figure_number(scheme: str, which: int) -> str:
    """File-name prefix: paper figure number for USF/USL, the scheme name otherwise."""
    numbers = FIGURE_NUMBERS.get(scheme)
    return f'fig{numbers[which]}_' if numbers else ''


# --------------------------------------------------------------------------------------------
# Figure 3b: verification, u_cm(t) against the exact solution
# --------------------------------------------------------------------------------------------

def fig3b(runs: Sequence[Run], outdir: str) -> str:
    """Centre-of-mass displacement against time, numerical and exact, one column per run
    (USF and USL, 20 elements, 1 particle per element, dt = 0.1 dx/c in the paper),
    with the error below."""
    runs = [r for r in runs if r.history is not None]
    if not runs:
        raise FigureSkipped('fig3b needs single-run files with a history')
    fig, axes = plt.subplots(2, len(runs), figsize=(5.2 * len(runs), 6.2), sharex='col',
                             squeeze=False, gridspec_kw={'height_ratios': [2.2, 1]})
    for column, run in enumerate(runs):
        h = run.history
        top, bottom = axes[0, column], axes[1, column]
        top.plot(h['time'], 1e3 * h['ucm_exact'], color='black', linewidth=2.4, alpha=0.35,
                 label='exact, Eq. (14)')
        top.plot(h['time'], 1e3 * h['ucm'], color='C0', linewidth=1.1, label='MPM')
        top.set_ylabel(r'centre-of-mass displacement $u_{cm}$ (mm)')
        top.set_title(run.label(), fontsize=10)
        top.legend(fontsize=8, loc='upper right')
        bottom.plot(h['time'], 1e6 * (h['ucm'] - h['ucm_exact']), color='C3', linewidth=1.0)
        bottom.axhline(0.0, color='0.5', linewidth=0.6)
        bottom.set_ylabel(r'$u_{cm} - u_{cm}^{exact}$ (µm)')
        bottom.set_xlabel('time t (s)')
        if run.ok:
            bottom.set_title(f"max error = {run.summary['max_error']:.3g} m "
                             f"({100 * run.summary['relative_error']:.3g} % of the amplitude), "
                             f"status {run.summary['status_name']}", fontsize=8)
        else:
            bottom.set_title(f"no result: stopped by a guard ({run.summary['status_name']}); error before "
                             f"the stop {run.summary.get('error_before_stop', float('nan')):.3g} m", fontsize=8)
        for ax in (top, bottom):
            ax.grid(alpha=0.3)
    fig.suptitle('Fig. 3b — vibrating bar, centre-of-mass displacement: MPM against exact\n'
                 + problem_text(runs[0].config), fontsize=10)
    fig.tight_layout(rect=(0, 0.02, 1, 1))
    return save_figure(fig, outdir, 'fig3b_ucm_verification.png', runs)


# --------------------------------------------------------------------------------------------
# Figures 4/7 and 5/8: colour maps
# --------------------------------------------------------------------------------------------

def _colour_map_figure(sweep: Sweep, scheme: str, panels: Sequence[int], quantity: str,
                       norms: Mapping[int, LogNorm], which: int, title: str, colour_label: str, outdir: str,
                       name: str, annotate: Optional[str] = None) -> str:
    """One figure of colour maps of `quantity` for `scheme`, one panel per element count in
    `panels`, each on its colour scale `norms[elements]`: one colourbar per panel, or one for the
    figure when every panel has the same scale."""
    rows, columns = _panel_layout(len(panels))
    one_scale = len({(norms[e].vmin, norms[e].vmax) for e in panels}) == 1
    width = max(4.0 * columns + (1.2 if one_scale else 0.9 * columns), 7.0)
    fig, axes = plt.subplots(rows, columns, figsize=(width, 3.5 * rows + 1.1),
                             squeeze=False, constrained_layout=True)
    grids, mesh = [], None
    for ax, elements in zip(axes.flat, panels):
        grid = case_grid(sweep, sweep.where(scheme=scheme, elements=elements), quantity)
        grids.append(grid)
        mesh = draw_colour_map(ax, grid, norms[elements], annotate=annotate)
        ax.set_title(f'{elements} element{"s" if elements != 1 else ""}', fontsize=10)
        ax.set_xlabel(PPE_LABEL)
        ax.set_ylabel(DT_LABEL)
        if not one_scale:
            fig.colorbar(mesh, ax=ax, label=colour_label, shrink=0.9)
    for ax in list(axes.flat)[len(panels):]:
        ax.set_visible(False)
    if one_scale:
        fig.colorbar(mesh, ax=axes, label=colour_label, shrink=0.9)
    _status_legend(fig, grids)
    fitted_title(fig, f'{figure_title(scheme, which, title)}\n{problem_text(sweep.config)}')
    fig.get_layout_engine().set(rect=(0, 0.025, 1, 0.975))
    return save_figure(fig, outdir, name, [sweep])


def error_maps(sweeps: Mapping[str, Sweep], outdir: str,
               elements: Optional[Sequence[int]] = None) -> Dict[str, str]:
    """Figures 4 (USF) and 7 (USL): maximum u_cm error over particles per element × time step,
    one panel per element count, each on a logarithmic colour scale of its own (the error spans
    orders of magnitude from 1 to 50 elements: on one scale each panel would be nearly one colour and
    the trends within a mesh would not show), shared by the schemes given, so that USF and USL compare
    panel by panel. Returns {scheme: path}."""
    panels = {scheme: sorted(set(s.cases['elements'][s.where(scheme=scheme)].tolist()))
              for scheme, s in sweeps.items()}
    if elements is not None:
        panels = {k: [e for e in v if e in elements] for k, v in panels.items()}
    norms = {count: shared_log_norm(s.cases['max_error'][s.where(scheme=k, elements=count) & s.ok]
                                    for k, s in sweeps.items())
             for count in sorted({c for v in panels.values() for c in v})}
    shared = ', one colour scale per mesh, shared by ' + ' and '.join(k.upper() for k in sweeps) \
        if len(sweeps) > 1 else ', one colour scale per mesh'
    return {scheme: _colour_map_figure(
        sweep, scheme, panels[scheme], 'max_error', norms, 0,
        'Maximum centre-of-mass displacement error' + shared, 'max |u_cm − u_cm,exact| (m)', outdir,
        f'{_figure_number(scheme, 0)}error_map_{scheme}.png')
        for scheme, sweep in sweeps.items() if panels[scheme]}


def time_maps(sweeps: Mapping[str, Sweep], outdir: str, elements: int = 3) -> Dict[str, str]:
    """Figures 5 (USF) and 8 (USL): computation time per run over particles per element × time
    step for one element count (3 in the paper), on a shared logarithmic scale, values written
    in the cells. Returns {scheme: path}; schemes without timings are left out."""
    timed = {}
    for scheme, sweep in sweeps.items():
        mask = sweep.where(scheme=scheme, elements=elements) & sweep.ok
        if mask.any() and np.any(sweep.cases['run_time'][mask] > 0):
            timed[scheme] = sweep
    if not timed:
        raise FigureSkipped(f'no timed cases with {elements} elements (run_time is 0 when the '
                            'sweep ran without timing)')
    norm = shared_log_norm(s.cases['run_time'][s.where(scheme=k, elements=elements) & s.ok]
                           for k, s in timed.items())
    return {scheme: _colour_map_figure(
        sweep, scheme, [elements], 'run_time', {elements: norm}, 1,
        'Computation time per run (median over repeats)', TIME_LABEL,
        outdir, f'{_figure_number(scheme, 1)}time_map_{scheme}.png', annotate='.2g')
        for scheme, sweep in timed.items()}


# --------------------------------------------------------------------------------------------
# Figures 6/9: computation time against particles and against time step, with fits
# --------------------------------------------------------------------------------------------

def timing_noise(spreads: Optional[Sequence[float]]) -> str:
    """Why timings with these repeat spreads are too noisy to judge a fit by ('' when they are
    steady enough: median spread at most NOISY_TIMING_SPREAD, or no spreads recorded)."""
    if not spreads:
        return ''
    median = float(np.nanmedian(np.asarray(spreads, float)))
    if not median > NOISY_TIMING_SPREAD:
        return ''
    return (f'timings too noisy to judge a fit (median spread of the repeats {median:.2g} > '
            f'{NOISY_TIMING_SPREAD:g})')


def timing_too_small(fitted: Sequence[float], times: Sequence[float],
                     spreads: Optional[Sequence[float]]) -> str:
    """Why a fit's timings are too small to judge it by ('' when they are not, or no spreads are
    recorded): the fitted time changes over the measured range (largest minus smallest of `fitted`,
    the fit at the measured points) by no more than the repeats' spread (median relative spread
    times the median time), so that a slope, flat or steep, is not told apart from timing noise."""
    if spreads is None or len(spreads) == 0:
        return ''
    change = float(np.ptp(np.asarray(fitted, float)))
    noise = float(np.nanmedian(np.asarray(spreads, float)) * np.nanmedian(np.asarray(times, float)))
    if change > noise:
        return ''
    return (f'timings too small to judge a fit (the fit changes by {change:.2g} s over the range, '
            f'the repeats spread by {noise:.2g} s)')


def time_fits(sweep: Sweep, scheme: str, outdir: str, elements: int = 3,
              dt_fraction: Optional[float] = None,
              particles_per_element: Optional[int] = None) -> Tuple[str, Dict[str, Dict]]:
    """Figures 6 (USF) and 9 (USL). (a) time against particles per element at one time step
    (5 % in the paper; the smallest present by default) with a least-squares line; (b) time
    against the time-step fraction k at one particle count (10 in the paper; the largest present
    by default) with a least-squares a/k + b. Returns (path, fits), fits = {'particles': {...},
    'time_step': {...}} with the coefficients, R² and the data used."""
    base = sweep.where(scheme=scheme, elements=elements) & sweep.ok \
        & (sweep.cases['run_time'] > 0)
    if not base.any():
        raise FigureSkipped(f'no timed {scheme.upper()} cases with {elements} elements')
    cases = sweep.cases
    if dt_fraction is None:
        dt_fraction = float(cases['dt_fraction'][base].min())
    if particles_per_element is None:
        particles_per_element = int(cases['particles_per_element'][base].max())
    row = base & sweep.where(dt_fraction=dt_fraction)
    column = base & sweep.where(particles_per_element=particles_per_element)
    n = cases['particles_per_element'][row].astype(float)
    t_n = cases['run_time'][row]
    k = 100 * cases['dt_fraction'][column]
    t_k = cases['run_time'][column]
    order_n, order_k = np.argsort(n), np.argsort(k)
    n, t_n, k, t_k = n[order_n], t_n[order_n], k[order_k], t_k[order_k]
    line = linear_fit(n, t_n)
    curve = rational_fit(k, t_k)
    has_spread = 'run_time_spread' in cases
    spread = cases['run_time_spread'][row][order_n].tolist() if has_spread else None
    spread_k = cases['run_time_spread'][column][order_k].tolist() if has_spread else None
    fits = {'particles': dict(line, elements=elements, dt_fraction=dt_fraction,
                              x=n.tolist(), time=t_n.tolist(), spread=spread),
            'time_step': dict(curve, elements=elements,
                              particles_per_element=particles_per_element,
                              x=k.tolist(), time=t_k.tolist(), spread=spread_k)}

    fig, (ax_a, ax_b) = plt.subplots(1, 2, figsize=(10.5, 4.5))
    n_fine = np.linspace(n.min(), n.max(), 100)
    k_fine = np.linspace(k.min(), k.max(), 200)
    for ax, x, t, spreads, fit_x, fit_t, formula, r2 in (
            (ax_a, n, t_n, spread, n_fine, line['slope'] * n_fine + line['intercept'],
             f"t = {line['slope']:.3g} s·n{signed(line['intercept'], 's')}", line['r2']),
            (ax_b, k, t_k, spread_k, k_fine, curve['a'] / k_fine + curve['b'],
             f"t = {curve['a']:.3g} s·%/k{signed(curve['b'], 's')}", curve['r2'])):
        # each point's spread of repeats (interquartile range over median) as a bar of its width
        bars = 0.5 * np.asarray(spreads, float) * t if spreads else None
        ax.errorbar(x, t, yerr=bars, fmt='o', color='C0', capsize=2,
                    label='measured (bar: interquartile range of the repeats)' if spreads else 'measured')
        at_points = line['slope'] * x + line['intercept'] if ax is ax_a else curve['a'] / x + curve['b']
        noisy = timing_noise(spreads) or timing_too_small(at_points, t, spreads)
        ax.plot(fit_x, fit_t, color='0.6' if noisy else 'C1', ls='--' if noisy else '-',
                label=f'{formula}\nR² = {r2:.4f}' + (f'\n{textwrap.fill(noisy, 48)}' if noisy else ''))
    ax_a.set_xlabel(f'{PPE_LABEL} n ({elements} elements)')
    ax_a.set_title(f'(a) time step dt = {100 * dt_fraction:g} % of dx/c', fontsize=10)
    ax_b.set_xlabel('time step k (% of dx/c)')
    ax_b.set_title(f'(b) {particles_per_element} particles per element', fontsize=10)
    for ax in (ax_a, ax_b):
        ax.set_ylabel(TIME_LABEL)
        ax.grid(alpha=0.3)
        ax.legend(fontsize=7)
    fitted_title(fig, figure_title(scheme, 2, f'Computation time, {elements} elements') + '\n'
                 + problem_text(sweep.config))
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    path = save_figure(fig, outdir, f'{_figure_number(scheme, 2)}time_fits_{scheme}.png',
                       [sweep])
    return path, fits


# --------------------------------------------------------------------------------------------
# Figure 10: the initial velocity field as the grid represents it
# --------------------------------------------------------------------------------------------

def fig10(runs: Sequence[Run], outdir: str,
          elements: Optional[Sequence[int]] = None) -> Tuple[str, Dict[int, float]]:
    """Initial velocity field as the method represents it, one panel per element count: the
    nodal velocity of the first particle-to-grid mapping interpolated linearly (the shape
    functions) to a fine set of points and to the particle positions, against the prescribed
    v0·sin(βx). Uses the first run per element count with a snapshot at step 0.
    Returns (path, {elements: max |v_grid − v_exact| / v0 over the bar})."""
    chosen: Dict[int, Run] = {}
    for run in runs:
        if run.snapshot_at(0) is not None and run.elements not in chosen:
            if elements is None or run.elements in elements:
                chosen[run.elements] = run
    if not chosen:
        raise FigureSkipped('fig10 needs single-run files with a snapshot at t = 0')
    counts = sorted(chosen)
    rows, columns = _panel_layout(len(counts)) if len(counts) > 4 else (1, len(counts))
    fig, axes = plt.subplots(rows, columns, figsize=(3.6 * columns + 0.6, 3.4 * rows + 1.0),
                             squeeze=False, sharey=True)
    deviation = {}
    for ax, count in zip(axes.flat, counts):
        run = chosen[count]
        snap = run.snapshot_at(0)
        v0, length, beta = run.config['velocity_amplitude'], run.config['length'], \
            wavenumber(run.config)
        x_fine = np.linspace(0.0, length, 400)
        v_fine = np.interp(x_fine, snap.grid_x, snap.grid_velocity)
        deviation[count] = float(np.max(np.abs(v_fine - v0 * np.sin(beta * x_fine))) / abs(v0))
        ax.plot(x_fine, v0 * np.sin(beta * x_fine), color='black', linewidth=2.2, alpha=0.4,
                label=r'prescribed $v_0 \sin(\beta x)$')
        ax.plot(x_fine, v_fine, color='C0', linewidth=1.2, label='grid (linear shape functions)')
        ax.plot(snap.grid_x, snap.grid_velocity, 's', color='C0', markersize=4, label='nodes')
        ax.plot(snap.x, np.interp(snap.x, snap.grid_x, snap.grid_velocity), 'o', color='C1',
                markersize=4, label='grid velocity at particles')
        ax.set_title(f'{count} element{"s" if count != 1 else ""}, '
                     f'{run.particles_per_element} ppe ({run.scheme.upper()})\n'
                     f'max |v_grid − v_exact| = {100 * deviation[count]:.1f} % of v0',
                     fontsize=9)
        ax.set_xlabel('position x (m)')
        ax.set_xlim(0.0, length)  # the bar (the grid's empty margin cells beyond it show nothing)
        ax.grid(alpha=0.3)
    for ax in axes[:, 0]:
        ax.set_ylabel('initial velocity v (m/s)')
    for ax in list(axes.flat)[len(counts):]:
        ax.set_visible(False)
    handles, labels = axes.flat[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc='lower center', ncol=4, fontsize=8, frameon=False,
               bbox_to_anchor=(0.5, 0.03))
    fig.suptitle('Fig. 10 — initial velocity field as represented by the grid (step 0)\n'
                 + problem_text(chosen[counts[0]].config), fontsize=10)
    fig.tight_layout(rect=(0, 0.1, 1, 1))
    path = save_figure(fig, outdir, 'fig10_initial_velocity.png', [chosen[c] for c in counts])
    return path, deviation


# --------------------------------------------------------------------------------------------
# Error against computation time, with the Pareto front
# --------------------------------------------------------------------------------------------

def error_vs_time(sweeps: Mapping[str, Sweep], outdir: str) -> Tuple[str, List[Dict]]:
    """Every completed, timed case of every scheme as a point (time per run, max error) on
    log-log axes, coloured by element count, one marker per scheme, with the Pareto front (no
    other case both faster and more accurate) as a step line. Returns (path, Pareto-optimal
    cases fastest first, each a dict with scheme, elements, particles_per_element, dt_fraction,
    run_time, max_error)."""
    columns = ('scheme', 'elements', 'particles_per_element', 'dt_fraction', 'run_time',
               'max_error')
    table = {c: [] for c in columns}
    sources = []
    stopped = 0
    for scheme, sweep in sweeps.items():
        mask = sweep.where(scheme=scheme) & sweep.ok & (sweep.cases['run_time'] > 0) \
            & (sweep.cases['max_error'] > 0)
        stopped += int((sweep.where(scheme=scheme) & ~sweep.ok).sum())
        if mask.any():
            sources.append(sweep)
        for c in columns:
            table[c].append(sweep.cases[c][mask])
    table = {c: np.concatenate(v) for c, v in table.items()}
    if table['run_time'].size == 0:
        raise FigureSkipped('no completed, timed cases (run_time is 0 without timing)')
    front = pareto_front(table['run_time'], table['max_error'])

    fig, ax = plt.subplots(figsize=(8.0, 5.6))
    element_counts = np.unique(table['elements'])
    colours = {e: plt.get_cmap('tab10')(i % 10) for i, e in enumerate(element_counts)}
    for scheme in dict.fromkeys(table['scheme'].tolist()):
        for count in element_counts:
            sel = (table['scheme'] == scheme) & (table['elements'] == count)
            if sel.any():
                ax.scatter(table['run_time'][sel], table['max_error'][sel], s=16, alpha=0.75,
                           color=colours[count], marker=SCHEME_MARKERS.get(scheme, 'D'),
                           edgecolors='none')
    ax.step(table['run_time'][front], table['max_error'][front], where='post', color='black',
            linewidth=1.3, zorder=3)
    ax.plot(table['run_time'][front], table['max_error'][front], 'o', markersize=8,
            markerfacecolor='none', markeredgecolor='black', zorder=3)
    ax.set_xscale('log')
    ax.set_yscale('log')
    ax.set_xlabel(TIME_LABEL)
    ax.set_ylabel(ERROR_LABEL)
    ax.grid(alpha=0.3, which='both')
    handles = [Line2D([], [], marker='o', linestyle='none', color=colours[e],
                      label=f'{e} element{"s" if e != 1 else ""}') for e in element_counts]
    handles += [Line2D([], [], marker=SCHEME_MARKERS.get(s, 'D'), linestyle='none', color='0.3',
                       label=s.upper()) for s in dict.fromkeys(table['scheme'].tolist())]
    handles.append(Line2D([], [], color='black', marker='o', markerfacecolor='none',
                          label=f'Pareto front ({front.size} cases)'))
    if stopped:
        handles.append(Line2D([], [], marker='x', color='0.55', linestyle='none',
                              label=f"{stopped} case{'s' if stopped != 1 else ''} stopped by a guard or not run: "
                                    "no result, not shown"))
    ax.legend(handles=handles, fontsize=8, loc='best')
    ax.set_title('Accuracy against cost, every case of the sweep(s)\n'
                 + problem_text(sources[0].config), fontsize=10)
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    path = save_figure(fig, outdir, 'error_vs_time.png', sources)
    pareto = [{c: table[c][i].item() for c in columns} for i in front]
    return path, pareto
