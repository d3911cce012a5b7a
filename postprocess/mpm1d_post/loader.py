"""Loader for the HDF5 files written by mpm1d: one single run, or one sweep (a table of cases).

Every figure and report of the post-processing reads its input through this module, so that the
file layout (documented in docs/output.md) is known in one place only.

Strings are written by mpm1d as variable-length strings (older files: fixed-length, space-padded);
they are returned here as stripped Python ``str`` (or numpy arrays of ``str``). Scalars come back as
Python numbers and 1-D datasets as numpy arrays. Every dataset of ``/summary`` and every column of
``/cases`` is returned, those the loader requires (listed below) and any other (a scene's own
reports, ``trip_step`` and ``trip_time``: the step and time at which a guard stopped the run, as
numbers, 0 where it completed).

What the input parameters are is not listed here: mpm1d writes its parameter registry into every
file (``/config`` attribute ``parameters``, the text ``mpm1d --list-parameters`` prints), and the
loader takes from it which ``/config`` attributes a file must hold and which ``/cases`` columns
are swept variables. Files written before the registry existed are read as they come.

A result that does not exist is NaN ("no value"), and the status says why: the ``max_error`` and
``relative_error`` of a run a guard stopped (the error reached up to the stop is in
``error_before_stop`` and ``relative_error_before_stop``), every result of a sweep case not run
(status ``not_run``, an interrupted sweep), the ``run_time`` of a case not timed (``repeats`` 0).
Files written before these columns existed are read the same way (a stopped case's ``max_error``
moved to ``error_before_stop``, the ``run_time`` 0 of a case not timed made NaN).

``load_sweep`` returns the completed cases by default, the ones an analysis may use (so that
``np.argmin(sweep.cases['max_error'])`` picks a result, never a stopped case's error), and warns
how many it left out; ``load_sweep(path, cases='all')`` returns every case, for figures that show
the stopped ones apart (``sweep.stopped``, ``sweep.not_run``).

    >>> run = load_run('usf.h5')             # doctest: +SKIP
    >>> run.scheme, run.elements, run.summary['max_error']
    >>> sweep = load_sweep('sweep_usf.h5')   # doctest: +SKIP
    >>> sweep.cases['max_error'][np.argmin(sweep.cases['max_error'])]
    >>> every = load_sweep('sweep_usf.h5', cases='all')   # doctest: +SKIP
    >>> every.cases['trip_step'][every.stopped]
"""

from __future__ import annotations

import dataclasses
import os
import warnings
from pathlib import Path
from dataclasses import dataclass, field
from typing import Any, Dict, List, Optional, Sequence

import numpy as np

try:
    import h5py
except ImportError as exc:  # pragma: no cover - depends on the installation
    raise ImportError("mpm1d post-processing needs h5py (Debian: apt install python3-h5py; "
                      "use the project's .venv/bin/python, which studies/setup.sh makes with Debian's packages)") from exc

__all__ = ['Mpm1dFileError', 'Parameter', 'Run', 'Snapshot', 'Sweep', 'load_run', 'load_sweep',
           'merge_sweeps', 'concatenate_sweeps', 'parse_parameters', 'LeftOutCases', 'STATUS_OK', 'STATUS_NOT_RUN']

#: Status of a run that completed (``/summary/status``, ``/cases/status``).
STATUS_OK = 0
#: Status of a sweep case that has not run (the sweep was interrupted before it; ``--resume`` runs it).
STATUS_NOT_RUN = -1


class LeftOutCases(UserWarning):
    """``load_sweep`` left cases out of the table it returns (those that did not complete)."""

HISTORY_DATASETS = ('time', 'ucm', 'ucm_exact', 'kinetic_energy', 'strain_energy')
SNAPSHOT_DATASETS = ('x', 'velocity', 'stress', 'volume_ratio', 'grid_x', 'grid_velocity')
SUMMARY_DATASETS = ('max_error', 'relative_error', 'ucm_amplitude', 'steps', 'steps_done',
                    'particles', 'dt', 'run_time', 'status', 'status_name', 'message',
                    'initial_energy', 'final_energy', 'max_energy_ratio', 'min_volume_ratio',
                    'max_cell_move', 'min_node_mass_ratio')
#: Result columns of ``/cases`` (the swept parameters' columns come from the file's registry).
RESULT_DATASETS = ('steps', 'dt', 'max_error', 'relative_error', 'run_time', 'repeats', 'status',
                   'status_name', 'max_energy_ratio', 'final_energy_ratio', 'particles')
#: The error reached up to a guard's stop, where a stopped run's (NaN) max_error / relative_error went.
BEFORE_STOP = {'max_error': 'error_before_stop', 'relative_error': 'relative_error_before_stop'}


def _no_values(table: Dict[str, Any], status: Any, repeats: Any = None) -> None:
    """Files written before stopped runs had no result: a stopped run's max_error / relative_error
    move to their *_before_stop columns (NaN left behind), a run time not measured (repeats 0)
    becomes NaN. Files that have the columns are left as they are."""
    stopped = np.asarray(status) != STATUS_OK
    for name, moved in BEFORE_STOP.items():
        if moved in table or name not in table:
            continue
        values = np.asarray(table[name], dtype=float)
        table[moved] = np.where(stopped, values, np.nan)
        table[name] = np.where(stopped, np.nan, values)
        if np.ndim(values) == 0:
            table[moved], table[name] = float(table[moved]), float(table[name])
    if repeats is not None and 'run_time' in table:
        untimed = (np.asarray(repeats) == 0) & (np.asarray(table['run_time'], dtype=float) == 0)
        if untimed.any():
            for name in ('run_time', 'run_time_spread'):
                if name in table:
                    table[name] = np.where(untimed, np.nan, np.asarray(table[name], dtype=float))


@dataclass(frozen=True)
class Parameter:
    """One entry of mpm1d's parameter registry (a line of ``mpm1d --list-parameters``).

    ``value`` is the value in the file's run (the default in ``--list-parameters``); an empty
    ``value`` of a real is an optional variable left unset (e.g. ``end_time`` when ``periods`` is
    given), which has no ``/config`` attribute."""
    group: str
    name: str
    attribute: str
    type: str
    unit: str
    value: str
    allowed: str
    sweep_list: str
    help: str
    #: The sweep list's former name, still accepted ('' = none; absent in older files).
    sweep_alias: str = ''
    #: The scene kinds that use it, comma separated ('' = every kind; absent in older files).
    kinds: str = ''

    @property
    def written(self) -> bool:
        """Whether the run's ``/config`` holds this variable."""
        return not (self.type == 'real' and self.value == '')


def parse_parameters(text: str) -> List[Parameter]:
    """The registry from its tab-separated text (header line first)."""
    lines = [line for line in text.splitlines() if line.strip()]
    if not lines:
        return []
    header = lines[0].split('\t')
    fields = list(Parameter.__dataclass_fields__)
    required = [name for name, f in Parameter.__dataclass_fields__.items()
                if f.default is dataclasses.MISSING]
    if len(set(header)) != len(header) or not set(required) <= set(header) or not set(header) <= set(fields):
        raise ValueError(f'unexpected parameter table header: {lines[0]!r}')
    rows = []
    for line in lines[1:]:
        cells = line.split('\t')
        if len(cells) != len(header):
            raise ValueError(f'malformed parameter table line: {line!r}')
        rows.append(Parameter(**dict(zip(header, cells))))
    return rows


class Mpm1dFileError(Exception):
    """An input file is missing, unreadable, or not the kind of mpm1d file that was expected.

    The message always names the file and says what is wrong with it.
    """

    def __init__(self, path: str, problem: str):
        self.path = str(path)
        self.problem = problem
        super().__init__(f"{self.path}: {problem}")


# --------------------------------------------------------------------------------------------
# Decoding of what h5py returns
# --------------------------------------------------------------------------------------------

def decode(value: Any) -> Any:
    """Turn an HDF5 value into plain Python/numpy: stripped ``str`` for (arrays of) byte strings,
    Python scalars for 0-d and 1-element values, numpy arrays otherwise."""
    if isinstance(value, (bytes, np.bytes_)):
        return value.decode('utf-8', errors='replace').strip(' \x00')
    if isinstance(value, str):
        return value.strip(' \x00')
    if isinstance(value, np.ndarray):
        if value.dtype.kind in ('S', 'O', 'U'):
            texts = [decode(item) for item in value.ravel()]
            if value.ndim == 0:
                return texts[0]
            return np.array(texts, dtype=str).reshape(value.shape)
        if value.ndim == 0:
            return value.item()
        return value
    if isinstance(value, np.generic):
        return value.item()
    return value


def _attributes(node: 'h5py.HLObject') -> Dict[str, Any]:
    """All attributes of an HDF5 group or dataset, decoded; 1-element arrays become scalars
    (some writers store a scalar attribute with dimension [1])."""
    result = {}
    for name, value in node.attrs.items():
        value = decode(value)
        if isinstance(value, np.ndarray) and value.shape == (1,):
            value = decode(value.reshape(()))
        result[name] = value
    return result


def _read(path: str, h5: 'h5py.File', name: str) -> Any:
    """Dataset `name` of the open file, decoded; a clear error if it is absent."""
    if name not in h5:
        raise Mpm1dFileError(path, f"missing dataset '{name}'")
    node = h5[name]
    if not isinstance(node, h5py.Dataset):
        raise Mpm1dFileError(path, f"'{name}' is a group, expected a dataset")
    return decode(node[()])


def _open(path: 'str | os.PathLike', content: str) -> 'h5py.File':
    """Open `path` for reading and check that it is an mpm1d file whose root attribute
    ``content`` equals `content`."""
    if not Path(path).exists():
        raise Mpm1dFileError(path, 'no such file')
    if Path(path).is_dir():
        raise Mpm1dFileError(path, 'is a directory, expected an HDF5 file')
    path = os.fspath(path)
    if not h5py.is_hdf5(path):
        raise Mpm1dFileError(path, 'not an HDF5 file')
    try:
        h5 = h5py.File(path, 'r')
    except OSError as exc:
        raise Mpm1dFileError(path, f'cannot open as HDF5 ({exc})') from exc
    root = _attributes(h5)
    if 'code_version' not in root or 'content' not in root:
        h5.close()
        raise Mpm1dFileError(path, "not an mpm1d file (no 'code_version'/'content' attributes "
                                   "on the root group)")
    if root['content'] != content:
        h5.close()
        raise Mpm1dFileError(path, f"holds a '{root['content']}' file, expected '{content}'")
    return h5


def _config(path: str, h5: 'h5py.File') -> Dict[str, Any]:
    """The ``/config`` attributes, checked against the registry the file carries."""
    if '/config' not in h5:
        raise Mpm1dFileError(path, "missing group '/config'")
    config = _attributes(h5['/config'])
    missing = [p.attribute for p in _parameters(path, config) if p.written and p.attribute not in config]
    if missing:
        raise Mpm1dFileError(path, "missing attribute(s) of '/config': " + ', '.join(missing))
    return config


def _parameters(path: str, config: Dict[str, Any]) -> List[Parameter]:
    """The registry stored in the file (empty for files written before it existed)."""
    try:
        return parse_parameters(str(config.get('parameters', '')))
    except ValueError as exc:
        raise Mpm1dFileError(path, f"unreadable '/config/parameters': {exc}") from exc


def _history(path: str, group: 'h5py.Group', where: str) -> Dict[str, np.ndarray]:
    """The 1-D time series of a history group as a dict of float arrays: the required ones and any other
    (``plastic_work`` where a body is elastoplastic)."""
    names = list(HISTORY_DATASETS) + sorted(set(group.file[where]) - set(HISTORY_DATASETS))
    return {name: np.asarray(_read(path, group.file, f'{where}/{name}'), dtype=float) for name in names}


# --------------------------------------------------------------------------------------------
# Single run
# --------------------------------------------------------------------------------------------

@dataclass
class Snapshot:
    """Particle and grid state of one run at one time (``/snapshots/NNNN``)."""
    time: float
    step: int
    x: np.ndarray
    velocity: np.ndarray
    stress: np.ndarray
    volume_ratio: np.ndarray
    grid_x: np.ndarray
    grid_velocity: np.ndarray
    #: Every other dataset of the snapshot, by name: what a scene writes besides the fields above
    #: (``reference_x``, ``body``, ``youngs_modulus``, ...), as numpy arrays.
    extra: Dict[str, np.ndarray] = field(default_factory=dict)


@dataclass
class Run:
    """One mpm1d run (file written by ``mpm1d run.nml``)."""
    path: str
    code_version: str
    config: Dict[str, Any]
    summary: Dict[str, Any]
    history: Optional[Dict[str, np.ndarray]] = None
    snapshots: List[Snapshot] = field(default_factory=list)
    #: The parameter registry stored in the file (empty for older files).
    parameters: List[Parameter] = field(default_factory=list)

    @property
    def scheme(self) -> str:
        """Update scheme: 'usf', 'usl' or 'musl'."""
        return str(self.config['scheme']).lower()

    @property
    def elements(self) -> int:
        return int(self.config['elements'])

    @property
    def particles_per_element(self) -> int:
        return int(self.config['particles_per_element'])

    @property
    def dt_fraction(self) -> float:
        """Time step as a fraction of dx/c (the time a wave takes to cross an element; not the
        stability limit, which depends on the scheme and shape)."""
        return float(self.config['dt_fraction'])

    @property
    def ok(self) -> bool:
        """Whether the run completed (status 0): only then are max_error and relative_error results."""
        return int(self.summary['status']) == STATUS_OK

    def snapshot_at(self, step: int = 0) -> Optional[Snapshot]:
        """The snapshot taken at `step` (the initial state by default), or None."""
        for snapshot in self.snapshots:
            if snapshot.step == step:
                return snapshot
        return None

    def label(self) -> str:
        """Short description: scheme and discretisation."""
        return (f"{self.scheme.upper()}, {self.elements} el., {self.particles_per_element} ppe, "
                f"dt = {self.dt_fraction:g} dx/c")


def load_run(path: str) -> Run:
    """Read a single-run file. Raises `Mpm1dFileError` naming the file and the problem."""
    h5 = _open(path, 'single run')
    path = os.fspath(path)
    with h5:
        code_version = decode(h5.attrs['code_version'])
        config = _config(path, h5)
        summary = {name: _read(path, h5, f'/summary/{name}') for name in SUMMARY_DATASETS}
        summary.update({name: _read(path, h5, f'/summary/{name}') for name in h5['/summary']
                        if name not in summary})
        _no_values(summary, summary['status'])
        history = _history(path, h5, '/history') if '/history' in h5 else None
        snapshots = []
        if '/snapshots' in h5:
            for name in sorted(h5['/snapshots'], key=lambda n: int(n) if n.isdigit() else n):
                where = f'/snapshots/{name}'
                attrs = _attributes(h5[where])
                if 'time' not in attrs or 'step' not in attrs:
                    raise Mpm1dFileError(path, f"'{where}' lacks its 'time'/'step' attributes")
                arrays = {key: np.asarray(_read(path, h5, f'{where}/{key}'), dtype=float)
                          for key in SNAPSHOT_DATASETS}
                extra = {key: np.asarray(_read(path, h5, f'{where}/{key}')) for key in h5[where]
                         if key not in SNAPSHOT_DATASETS}
                snapshots.append(Snapshot(time=float(attrs['time']), step=int(attrs['step']),
                                          extra=extra, **arrays))
    return Run(path=path, code_version=code_version, config=config, summary=summary,
               history=history, snapshots=snapshots, parameters=_parameters(path, config))


# --------------------------------------------------------------------------------------------
# Sweep
# --------------------------------------------------------------------------------------------

@dataclass
class Sweep:
    """A table of cases (file written by ``mpm1d sweep.nml``), or several shards merged.

    ``cases`` maps each ``/cases`` dataset name to a 1-D array (one entry per case; strings as
    arrays of ``str``, integers as ``int``): the results and one column per swept variable of the
    scene. ``histories`` maps a 0-based case index to its history, where stored.
    ``sweep`` holds the ``/sweep`` attributes of each source file (one dict per file).
    ``left_out`` counts the cases of the files not in ``cases`` (``load_sweep``'s default keeps the
    completed ones), per status name.
    """
    paths: List[str]
    code_versions: List[str]
    config: Dict[str, Any]
    sweep: List[Dict[str, Any]]
    cases: Dict[str, np.ndarray]
    histories: Dict[int, Dict[str, np.ndarray]] = field(default_factory=dict)
    #: The parameter registry stored in the file (empty for older files).
    parameters: List[Parameter] = field(default_factory=list)
    #: Cases of the source files left out of ``cases``, per status name (empty: none).
    left_out: Dict[str, int] = field(default_factory=dict)

    @property
    def parameter_columns(self) -> List[str]:
        """The ``/cases`` columns of the swept variables (those of the scene's variables the file has)."""
        return [p.attribute for p in self.parameters if p.sweep_list and p.attribute in self.cases]

    @property
    def path(self) -> str:
        """The source file(s), comma separated."""
        return ', '.join(self.paths)

    @property
    def code_version(self) -> str:
        """Code version(s) that wrote the source files."""
        return ', '.join(sorted(set(self.code_versions)))

    def __len__(self) -> int:
        return len(self.cases['status'])

    @property
    def ok(self) -> np.ndarray:
        """Mask of the cases that completed (status 0)."""
        return self.cases['status'] == STATUS_OK

    @property
    def failed(self) -> np.ndarray:
        """Mask of the cases that ran and were stopped by a guard (status > 0); same as ``stopped``."""
        return self.cases['status'] > STATUS_OK

    @property
    def stopped(self) -> np.ndarray:
        """Mask of the cases a guard stopped (status > 0): no max_error (NaN); the error reached
        up to the stop is in ``error_before_stop``."""
        return self.cases['status'] > STATUS_OK

    @property
    def not_run(self) -> np.ndarray:
        """Mask of the cases not run (status -1: the sweep was interrupted before them)."""
        return self.cases['status'] == STATUS_NOT_RUN

    def completed(self) -> 'Sweep':
        """The completed cases alone (what ``load_sweep`` returns by default)."""
        kept = self.select(self.ok)
        left_out = dict(self.left_out)
        for name in self.cases['status_name'][~self.ok].tolist():
            left_out[str(name)] = left_out.get(str(name), 0) + 1
        kept.left_out = left_out
        return kept

    @property
    def schemes(self) -> List[str]:
        """Schemes present, in order of first appearance."""
        return list(dict.fromkeys(self.cases['scheme'].tolist()))

    def select(self, mask: np.ndarray) -> 'Sweep':
        """A new Sweep holding only the cases where `mask` is true (histories follow)."""
        mask = np.asarray(mask, dtype=bool)
        index = np.flatnonzero(mask)
        renumber = {int(old): new for new, old in enumerate(index)}
        return Sweep(paths=self.paths, code_versions=self.code_versions, config=self.config,
                     sweep=self.sweep, cases={k: v[mask] for k, v in self.cases.items()},
                     histories={renumber[k]: h for k, h in self.histories.items()
                                if k in renumber}, parameters=self.parameters, left_out=dict(self.left_out))

    def to_dataframe(self) -> 'pandas.DataFrame':
        """The cases as a pandas DataFrame: one row per case this Sweep holds, one column per
        ``/cases`` dataset, the file's values as they are (NaN and statuses included)."""
        from .frames import cases_frame  # pandas only when a table is asked for
        return cases_frame(self)

    def where(self, **criteria: Any) -> np.ndarray:
        """Mask of the cases matching every ``column=value`` (floats compared with a relative
        tolerance of 1e-9); a list, tuple or set of values matches any of them.

        >>> sweep.where(scheme='usf', elements=20, particles_per_element=1, dt_fraction=0.1)
        >>> sweep.where(scheme=('usl', 'musl'), shape='linear') & sweep.ok
        """
        mask = np.ones(len(self), dtype=bool)
        for column, value in criteria.items():
            if column not in self.cases:
                raise KeyError(f"where: no column '{column}' (columns: {', '.join(sorted(self.cases))})")
            values = self.cases[column]
            wanted = list(value) if isinstance(value, (list, tuple, set, frozenset)) else [value]
            match = np.zeros(len(self), dtype=bool)
            for one in wanted:
                if values.dtype.kind == 'f':
                    match |= np.isclose(values, one, rtol=1e-9, atol=0.0)
                else:
                    match |= values == one
            mask &= match
        return mask

    def rows(self, order_by: Optional[str] = None, descending: bool = False, **criteria: Any) -> np.ndarray:
        """Indices of the cases matching `criteria` (as `where`), in the order of column `order_by`
        (ascending, or descending; ties keep the file's order), else in the file's order.

        >>> i = sweep.rows('elements', scheme='usl', shape='linear')   # one mesh series, coarse to fine
        >>> sweep.cases['elements'][i], sweep.cases['relative_error'][i]
        """
        index = np.flatnonzero(self.where(**criteria))
        if order_by is not None:
            key = self.cases[order_by][index]
            index = index[np.argsort(-key if descending else key, kind='stable')]
        return index


def load_sweep(path: 'str | os.PathLike', cases: str = 'completed') -> Sweep:
    """Read a sweep file. Raises `Mpm1dFileError` naming the file and the problem.

    ``cases='completed'`` (the default): the completed cases only (status 0), the ones whose errors
    and times are results; the others are counted in ``left_out`` and a `LeftOutCases` warning says
    how many were left out and how to get them. ``cases='all'``: every case (stopped ones have NaN
    ``max_error``; draw them apart, never as data points of a fit)."""
    if cases not in ('completed', 'all'):
        raise ValueError(f"load_sweep: cases={cases!r}; allowed: 'completed' or 'all'")
    return _chosen_cases(_load_sweep_file(path), cases, "load_sweep(path, cases='all')", stacklevel=3)


def _chosen_cases(every: Sweep, cases: str, every_call: str, stacklevel: int) -> Sweep:
    """`every` ('all') or its completed cases, a `LeftOutCases` warning counting the others and naming
    `every_call`, the call that returns them all, said at the caller's line `stacklevel`."""
    if cases == 'all':
        return every
    kept = every.completed()
    if kept.left_out:
        counts = ', '.join(f'{name} {n}' for name, n in sorted(kept.left_out.items()))
        warnings.warn(f"{every.path}: left out {sum(kept.left_out.values())} of {len(every)} cases that did not "
                      f"complete ({counts}): analyses use completed cases; {every_call} returns every case",
                      LeftOutCases, stacklevel=stacklevel)
    return kept


def _load_sweep_file(path: 'str | os.PathLike') -> Sweep:
    """Every case of a sweep file."""
    h5 = _open(path, 'sweep')
    path = os.fspath(path)
    with h5:
        code_version = decode(h5.attrs['code_version'])
        config = _config(path, h5)
        if '/sweep' not in h5:
            raise Mpm1dFileError(path, "missing group '/sweep'")
        sweep = _attributes(h5['/sweep'])
        if '/cases' not in h5:
            raise Mpm1dFileError(path, "missing group '/cases'")
        parameters = _parameters(path, config)
        # the columns of the swept variables the file has (a scene's own), then the results
        names = [p.attribute for p in parameters if p.sweep_list and p.attribute in h5['/cases']]
        names += list(RESULT_DATASETS)
        names += [name for name in h5['/cases'] if name not in names]
        cases = {}
        for name in names:
            values = _read(path, h5, f'/cases/{name}')
            cases[name] = np.atleast_1d(np.asarray(values))
        sizes = {name: len(values) for name, values in cases.items()}
        if len(set(sizes.values())) != 1:
            raise Mpm1dFileError(path, 'the /cases datasets differ in length: ' +
                                 ', '.join(f'{k}={v}' for k, v in sizes.items()))
        for name, values in cases.items():
            if values.dtype.kind in ('S', 'O', 'U'):
                cases[name] = values.astype(str)
            elif values.dtype.kind in ('i', 'u'):
                cases[name] = values.astype(int)
        if 'scheme' in cases:
            cases['scheme'] = np.char.lower(cases['scheme'])
        _no_values(cases, cases['status'], cases['repeats'])
        histories = {}
        if '/histories' in h5:
            for name in h5['/histories']:
                if not name.isdigit():
                    raise Mpm1dFileError(path, f"'/histories/{name}' is not a case number")
                histories[int(name) - 1] = _history(path, h5, f'/histories/{name}')
    return Sweep(paths=[path], code_versions=[code_version], config=config, sweep=[sweep],
                 cases=cases, histories=histories, parameters=parameters)


#: Parts of the &sweep text that do not change results (merge compares shards without them).
_RUN_SETTINGS = ('shard', 'shards', 'min_time', 'threads', 'timing_threads', 'progress')


def _sweep_identity(sweep: Sweep, index: int = 0) -> tuple:
    """What shards of one sweep share: the base configuration's namelist, the &sweep lists and
    settings that change results, the case count and the shard count (as mpm1d merge compares)."""
    text = str(sweep.sweep[index].get('namelist', ''))
    kept = [item.strip() for item in text.replace('/', ',').split(',')
            if item.strip() and item.strip().split('=')[0].strip() not in _RUN_SETTINGS]
    return (str(sweep.config.get('namelist', '')), tuple(kept), sweep.sweep[index].get('cases'),
            sweep.sweep[index].get('shards'))


def merge_sweeps(sweeps: Sequence[Sweep]) -> Sweep:
    """Concatenate the shards of one sweep into one table (as ``mpm1d merge`` does, in any order).

    Raises ValueError when the sweeps are not shards of the same sweep (another namelist, other
    lists, another shard count: their cases must not be mixed, e.g. in one fit), or when a shard or
    a case is given twice. `concatenate_sweeps` joins tables of different sweeps on purpose."""
    if not sweeps:
        raise ValueError('merge_sweeps needs at least one sweep')
    if len(sweeps) == 1:
        return sweeps[0]
    first = _sweep_identity(sweeps[0])
    shards_seen: Dict[Any, str] = {}
    for s in sweeps:
        for i, path in enumerate(s.paths):
            if _sweep_identity(s, i) != first:
                raise ValueError(f"'{path}' is not a shard of the same sweep as '{sweeps[0].paths[0]}' "
                                 "(another configuration, other &sweep lists or another shard count)")
            shard = s.sweep[i].get('shard')
            if shard in shards_seen and s.sweep[i].get('shards', 1) != 1:
                raise ValueError(f"shard {shard} is given twice ('{shards_seen[shard]}' and '{path}')")
            shards_seen[shard] = path
    merged = concatenate_sweeps(sweeps)
    if 'index' in merged.cases and np.unique(merged.cases['index']).size != merged.cases['index'].size:
        raise ValueError('the sweeps hold the same case twice (a shard given twice?)')
    return merged


def concatenate_sweeps(sweeps: Sequence[Sweep]) -> Sweep:
    """One table of the cases of several sweeps, which may be different sweeps (a study that puts
    runs of several namelists side by side); the columns are those of the first. The configuration
    is the first sweep's: use its columns, not ``config``, for what differs."""
    if not sweeps:
        raise ValueError('concatenate_sweeps needs at least one sweep')
    if len(sweeps) == 1:
        return sweeps[0]
    columns = sweeps[0].cases.keys()
    missing = [(s.path, c) for s in sweeps for c in columns if c not in s.cases]
    if missing:
        raise ValueError(f"'{missing[0][0]}' has no column '{missing[0][1]}' (another scene's sweep?)")
    cases = {name: np.concatenate([s.cases[name] for s in sweeps]) for name in columns}
    histories, offset = {}, 0
    for s in sweeps:
        histories.update({offset + k: h for k, h in s.histories.items()})
        offset += len(s)
    left_out: Dict[str, int] = {}
    for s in sweeps:
        for name, n in s.left_out.items():
            left_out[name] = left_out.get(name, 0) + n
    return Sweep(paths=[p for s in sweeps for p in s.paths],
                 code_versions=[v for s in sweeps for v in s.code_versions],
                 config=sweeps[0].config, sweep=[a for s in sweeps for a in s.sweep],
                 cases=cases, histories=histories, parameters=sweeps[0].parameters, left_out=left_out)
