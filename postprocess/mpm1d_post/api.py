"""Run mpm1d from Python: a configuration in, its results as pandas tables out.

    >>> import mpm1d_post
    >>> run = mpm1d_post.run({'discretisation': {'elements': 40, 'scheme': 'usf'}})   # doctest: +SKIP
    >>> run.summary['relative_error'], run.history[['time', 'ucm', 'ucm_exact']]      # doctest: +SKIP
    >>> sweep = mpm1d_post.sweep({'sweep': {'scheme': ['usf', 'usl'], 'elements': [10, 20, 40],
    ...                                     'min_time': 0}})                          # doctest: +SKIP
    >>> sweep.to_dataframe().groupby('scheme')['relative_error'].min()                # doctest: +SKIP

A configuration is namelist text (what ``mpm1d input.nml`` reads) or a nested dict, one dict per
namelist group: ``{'scene': {'kind': 'plastic_wave'}, 'output': {'snapshot_every': 20}}``. Values
are Python numbers, strings, booleans or lists (a list for a list variable or a sweep list). mpm1d
itself checks the input: a variable it does not know, a value out of range, a missing folder are
refused with its own message and exit code, raised here as `Mpm1dError`. A run a guard stopped (exit
1) raises `Mpm1dError` too, with the partial result (the history up to the stop) attached as
``error.result``: a stopped run has no error value, and the exception keeps it from being read as one.

The executable: ``exe=`` if given, else ``$MPM1D_EXE``, else ``mpm1d`` on PATH (where the README's
``fpm install`` puts it), else the release build of the checkout this package was installed from
(``fpm run --profile release --runner echo`` names it). Each call runs in ``workdir`` (a new folder
under the system's temporary folder when not given: the input and output files stay there, named
in the result).
"""

from __future__ import annotations

import math
import os
import re
import shutil
import subprocess
import tempfile
import warnings
from dataclasses import dataclass, field
from numbers import Integral, Real
from pathlib import Path
from typing import Any, Dict, List, Mapping, Optional, Union

import numpy as np
import pandas as pd

from . import frames
from .loader import Mpm1dFileError, Run, Sweep, _chosen_cases, load_run, load_sweep
from .namelist_doc import find_mpm1d

__all__ = ['run', 'sweep', 'RunResult', 'Mpm1dError', 'Mpm1dWarning', 'find_executable', 'namelist_text']

Config = Union[str, Mapping[str, Mapping[str, Any]]]

#: Exit codes of mpm1d (``mpm1d --help``): a guard stopped the run; the input was refused.
EXIT_GUARD, EXIT_INPUT = 1, 2


class Mpm1dError(RuntimeError):
    """mpm1d exited with a non-zero code. ``message``: what it said (its ``mpm1d: ...`` lines on
    standard error); ``exit_code``: 1 a guard stopped the run, 2 the input was refused, 3 a file could
    not be written, 128 + N a signal N interrupted it; ``result``: what it wrote all the same (the
    `RunResult` of a stopped run, the `Sweep` of an interrupted sweep, with every case), else None."""

    def __init__(self, message: str, exit_code: int, command: List[str], workdir: Path,
                 stdout: str = '', stderr: str = '', result: Any = None):
        self.message = message
        self.exit_code = exit_code
        self.command = command
        self.workdir = workdir
        self.stdout = stdout
        self.stderr = stderr
        self.result = result
        super().__init__(f'mpm1d exited with code {exit_code}: {message}')


class Mpm1dWarning(UserWarning):
    """A warning mpm1d printed (``mpm1d: warning: ...``) about a run it carried out."""


@dataclass
class RunResult:
    """One run's results, read from the file mpm1d wrote (``path``, in ``workdir``).

    ``summary``: the ``/summary`` values (dict); ``history``: one row per step (time, ucm, ucm_exact,
    energies; empty without ``&output history``); ``snapshots``: one row per particle per snapshot
    (`frames.snapshot_frame`: positions, velocity, stress and the scene's exact fields); ``grid``: the
    snapshots' nodal velocities; ``config``: the ``/config`` attributes (the whole input as run);
    ``file``: the loader's `Run` of the file, which the figure commands take; ``output``: what
    mpm1d printed."""
    path: Path
    workdir: Path
    file: Run
    summary: Dict[str, Any]
    config: Dict[str, Any]
    history: pd.DataFrame
    snapshots: pd.DataFrame
    grid: pd.DataFrame
    output: str = ''
    warnings: List[str] = field(default_factory=list)

    @classmethod
    def load(cls, path: 'str | os.PathLike', output: str = '', messages: Optional[List[str]] = None) -> 'RunResult':
        """The result of a run from its file."""
        file = load_run(path)
        return cls(path=Path(file.path), workdir=Path(file.path).parent, file=file, summary=file.summary,
                   config=file.config, history=frames.history_frame(file.history),
                   snapshots=frames.snapshot_frame(file.snapshots), grid=frames.grid_frame(file.snapshots),
                   output=output, warnings=list(messages or []))

    @property
    def ok(self) -> bool:
        """Whether the run completed (a stopped run's error is NaN)."""
        return self.file.ok


def find_executable(exe: 'str | os.PathLike | None' = None) -> str:
    """The mpm1d to run (see the module's text for the order); FileNotFoundError when there is none."""
    if exe is not None:
        found = shutil.which(os.fspath(exe))
        if found is None:
            raise FileNotFoundError(f"mpm1d executable '{exe}' not found or not executable")
        return found
    if os.environ.get('MPM1D_EXE'):
        return find_executable(os.environ['MPM1D_EXE'])
    if shutil.which('mpm1d'):
        return shutil.which('mpm1d')
    checkout = Path(__file__).resolve().parents[2]
    built = find_mpm1d(checkout)
    if os.sep in built and Path(built).is_file():
        return built
    raise FileNotFoundError("no mpm1d executable: install it as the README says (fpm install --profile release "
                            "--prefix ~/.local, with ~/.local/bin on PATH), build this checkout (fpm build "
                            "--profile release), or name it: MPM1D_EXE=/path/to/mpm1d or exe=")


def _value(value: Any) -> str:
    """A Python value as namelist text."""
    if isinstance(value, (bool, np.bool_)):
        return '.true.' if value else '.false.'
    if isinstance(value, str):
        return "'" + value.replace("'", "''") + "'"
    if isinstance(value, Integral):
        return str(int(value))
    if isinstance(value, Real):
        number = float(value)
        return repr(number) if math.isfinite(number) else ('NaN' if math.isnan(number) else
                                                          ('Infinity' if number > 0 else '-Infinity'))
    if isinstance(value, (list, tuple, np.ndarray)):
        if len(value) == 0:
            raise ValueError('an empty list has no namelist text')
        return ', '.join(_value(item) for item in value)
    raise TypeError(f'{value!r} ({type(value).__name__}) has no namelist text: give numbers, strings, '
                    'booleans or lists of them')


def namelist_text(config: Mapping[str, Mapping[str, Any]]) -> str:
    """Namelist text of a nested dict, one group per key: {'scene': {'length': 1.0}} -> "&scene length=1.0 /"."""
    lines = []
    for group, variables in config.items():
        if not isinstance(variables, Mapping):
            raise TypeError(f"config['{group}'] is a {type(variables).__name__}; expected a dict of the group's "
                            "variables, e.g. {'discretisation': {'elements': 40}}")
        items = ', '.join(f'{name}={_value(value)}' for name, value in variables.items())
        lines.append(f'&{group} {items} /')
    return '\n'.join(lines) + '\n'


def _groups(text: str) -> Dict[str, str]:
    """The namelist groups of `text` (lower-case name -> body), quoted text and comments aside."""
    plain = re.sub(r"'(?:[^']|'')*'|\"(?:[^\"]|\"\")*\"", lambda m: 'Q' * len(m.group(0)), text)
    plain = re.sub(r'!.*', '', plain)
    return {m.group(1).lower(): text[m.start(2):m.end(2)]
            for m in re.finditer(r'&(\w+)\b(.*?)/', plain, re.S)}


def _output_file(text: str) -> Optional[str]:
    """The &output group's file (None when the text does not give one)."""
    body = _groups(text).get('output', '')
    found = re.search(r"\bfile\s*=\s*(?:'((?:[^']|'')*)'|\"((?:[^\"]|\"\")*)\")", body, re.I)
    if not found:
        return None
    return found.group(1).replace("''", "'") if found.group(1) is not None else found.group(2).replace('""', '"')


def _prepare(config: Config, kind: str) -> tuple:
    """The namelist text of `config`, the command-line overrides it needs (an output file where the
    configuration names none) and the output file's name."""
    if isinstance(config, Mapping):
        config = {str(group).lower(): dict(variables) if isinstance(variables, Mapping) else variables
                  for group, variables in config.items()}
        text = namelist_text(config)
    elif isinstance(config, str):
        text = config
    else:
        raise TypeError(f'config is a {type(config).__name__}; expected namelist text or a dict of groups')
    has_sweep = 'sweep' in _groups(text)
    if kind == 'run' and has_sweep:
        raise ValueError('the configuration has a &sweep group: run it with mpm1d_post.sweep()')
    if kind == 'sweep' and not has_sweep:
        raise ValueError("the configuration has no &sweep group: give one (e.g. {'sweep': {'elements': [10, 20]}}), "
                         'or run a single case with mpm1d_post.run()')
    output = _output_file(text)
    overrides = []
    if output is None:
        output = f'{kind}.h5'
        overrides.append(f'output.file={output}')
    return text, overrides, output


def _execute(config: Config, kind: str, workdir, threads, exe) -> tuple:
    """Write the input into `workdir`, run mpm1d there; the completed process, its command, the folder
    and the output file's path."""
    text, overrides, output = _prepare(config, kind)
    program = find_executable(exe)
    folder = Path(tempfile.mkdtemp(prefix=f'mpm1d-{kind}-')) if workdir is None else Path(workdir)
    folder.mkdir(parents=True, exist_ok=True)
    folder = folder.resolve()
    (folder / f'{kind}.nml').write_text(text)
    command = [program, f'{kind}.nml', *overrides]
    env = dict(os.environ)
    if threads is not None:
        if int(threads) < 1:
            raise ValueError(f'threads = {threads}; allowed: at least 1')
        if kind == 'sweep':
            command += ['--threads', str(int(threads))]
        else:
            env['OMP_NUM_THREADS'] = str(int(threads))
    done = subprocess.run(command, cwd=folder, capture_output=True, text=True, env=env)
    path = Path(output) if os.path.isabs(output) else folder / output
    return done, command, folder, path


def _said(stderr: str) -> tuple:
    """mpm1d's messages on standard error (its 'mpm1d: ' lines with their continuations), apart from
    its warnings."""
    messages, warned = [], []
    for line in stderr.splitlines():
        if line.startswith('mpm1d: warning: '):
            warned.append(line[len('mpm1d: warning: '):])
        elif line.strip():
            messages.append(line)
    return '\n'.join(messages).strip(), warned


def _check(done: subprocess.CompletedProcess, command: List[str], folder: Path, path: Path, partial) -> List[str]:
    """mpm1d's warnings as Python warnings (said at the caller's caller: the user's line); on a non-zero
    exit, Mpm1dError with its message, its exit code and `partial()`, the file it wrote all the same
    (None when there is none). Returns the warnings."""
    message, warned = _said(done.stderr)
    for text in warned:
        warnings.warn(text, Mpm1dWarning, stacklevel=3)
    if done.returncode == 0:
        return warned
    result = None
    if path.is_file():
        try:
            result = partial()
        except Mpm1dFileError:
            result = None
    raise Mpm1dError(message or f'no message (standard output: {done.stdout.strip()[-500:]})', done.returncode,
                     command, folder, done.stdout, done.stderr, result)


def run(config: Config, workdir: 'str | os.PathLike | None' = None, threads: Optional[int] = None,
        exe: 'str | os.PathLike | None' = None) -> RunResult:
    """Run one case of mpm1d (`config`: namelist text or a dict of groups; no &sweep group) and return
    its `RunResult`. ``threads``: OpenMP threads of the run (a large run splits over them; the default
    is OpenMP's). Raises `Mpm1dError` with mpm1d's message and exit code when it refuses the input or
    stops the run (a guard's stop: ``error.result`` is the run up to the stop)."""
    done, command, folder, path = _execute(config, 'run', workdir, threads, exe)
    warned = _check(done, command, folder, path, lambda: RunResult.load(path, done.stdout, _said(done.stderr)[1]))
    return RunResult.load(path, done.stdout, warned)


def sweep(config: Config, workdir: 'str | os.PathLike | None' = None, threads: Optional[int] = None,
          exe: 'str | os.PathLike | None' = None, cases: str = 'completed') -> Sweep:
    """Run a sweep (`config` with a &sweep group) and return its `Sweep` (``Sweep.to_dataframe()``
    for the table). ``threads``: the error pass's threads (``mpm1d --threads``); ``cases``: as
    `load_sweep`'s, 'completed' (the default: the cases with a result, a `LeftOutCases` warning
    counting the others) or 'all'. Cases a guard stopped are data, not an error: their status says
    why. Raises `Mpm1dError` when mpm1d refuses the input, or when a signal interrupts the sweep
    (``error.result``: every case of the file it wrote, those not run with status 'not_run')."""
    if cases not in ('completed', 'all'):
        raise ValueError(f"sweep: cases={cases!r}; allowed: 'completed' or 'all'")
    done, command, folder, path = _execute(config, 'sweep', workdir, threads, exe)
    _check(done, command, folder, path, lambda: load_sweep(path, cases='all'))
    # (said at the caller's line, naming this call's way to every case)
    return _chosen_cases(load_sweep(path, cases='all'), cases, "sweep(..., cases='all')", stacklevel=3)
