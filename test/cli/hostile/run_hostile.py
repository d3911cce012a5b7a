"""Run the hostile-input suite: every case of cases.py against the mpm1d executable.

Usage (from anywhere): $PYTHON test/cli/hostile/run_hostile.py [--exe PATH] [--only REGEX] [--list] [-j N]

A case is data (see cases.py): input text (or bytes), arguments, environment, standard input, the
expected exit code, a pattern the output must contain, files that must / must not exist afterwards and,
for runs that must succeed, the expected relative error. Besides its own checks every case is held to
the suite's general rules (issue 18): no partial file is left, a refusal (exit 2) speaks in mpm1d's
words (starts 'mpm1d:', no compiler runtime text), and a run that exits 0 writes no non-finite result
(issue 24: NaN only where docs/output.md says a value does not exist, the status saying why; no Infinity).
Cases run in parallel in their own folders under build/test_scratch/hostile/.

No case depends on wall-clock time (the machine may be busy): a case's `cpu_seconds` is a budget of
CPU time (user + system of its processes, which hardly depends on the load; a large input must be
read in linear time), and every case gets HANG_SECONDS of wall time before it counts as hung.
"""
import argparse
import concurrent.futures as futures
import glob
import os
import importlib.util
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[2]
# the table lives next to this runner
_spec = importlib.util.spec_from_file_location('cases', HERE / 'cases.py')
case_table = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(case_table)

COMPILER_WORDS = re.compile(r'Fortran runtime|At line \d+|Error termination|Backtrace|ERROR STOP|SIGSEGV|'
                            r'Program received signal|Segmentation fault|HDF5-DIAG|floating-point exceptions are signalling')


def find_exe():
    out = subprocess.run(['fpm', 'run', '--profile', 'release', '--target', 'mpm1d', '--runner', 'echo'],
                         cwd=ROOT, capture_output=True, text=True, check=True).stdout.strip().splitlines()
    return str(ROOT / out[-1])


#: Where a file may hold NaN ("no value", docs/output.md): which rows of which datasets, by the row's
#: status (0 completed, > 0 stopped by a guard, -1 not run) and repeats (0: not timed). Infinity nowhere.
NO_VALUE_ALLOWED = {
    'max_error': lambda status, repeats: status != 0,
    'relative_error': lambda status, repeats: status != 0,
    'error_before_stop': lambda status, repeats: status <= 0,
    'relative_error_before_stop': lambda status, repeats: status <= 0,
    'run_time': lambda status, repeats: repeats == 0,
    'run_time_spread': lambda status, repeats: repeats == 0,
}


def non_finite_datasets(path):
    """The datasets (and /config attributes) of `path` holding a non-finite number that is not a
    documented "no value": the rule is no non-finite result (issue 24), not nothing non-finite."""
    bad = []

    def visit(name, obj):
        if not (isinstance(obj, h5py.Dataset) and obj.dtype.kind == 'f'):
            return
        values = np.atleast_1d(np.asarray(obj[()], dtype=float))
        if np.all(np.isfinite(values)):
            return
        group, _, leaf = name.rpartition('/')
        if group in ('cases', 'summary') and not np.isinf(values).any():
            status = np.atleast_1d(np.asarray(f[f'{group}/status'][()]))
            repeats = np.atleast_1d(np.asarray(f['cases/repeats'][()])) if group == 'cases' \
                else np.ones_like(status)
            allowed = NO_VALUE_ALLOWED.get(leaf, lambda status, repeats: status == -1)
            if np.all(np.isfinite(values) | allowed(status, repeats)):
                return
        bad.append(name)
    with h5py.File(path, 'r') as f:
        f.visititems(visit)
        for name, value in f.get('config', {}).attrs.items() if 'config' in f else []:
            a = np.asarray(value)
            if a.dtype.kind == 'f' and not np.all(np.isfinite(a)):
                bad.append('config@' + name)
    return bad


def relative_error(path):
    with h5py.File(path, 'r') as f:
        return float(f['summary/relative_error'][()])


#: system files no case may change (a broken build run as root could replace a device named as output)
GUARDED = ['/dev/null', '/dev/zero', '/dev/full']


def device_state():
    return {p: (os.stat(p).st_mode, os.stat(p).st_rdev) for p in GUARDED if os.path.exists(p)}


#: wall seconds after which a case counts as hung (a guard only: the budgets are CPU time)
HANG_SECONDS = 300

#: runs a command (argv[2:]) and writes the CPU seconds (user + system) of it and the descendants it
#: waited for into argv[1]; exits as the command did (by its signal if one ended it)
CPU_WRAPPER = r"""
import os, signal, sys
pid = os.fork()
if pid == 0:
    for s in (signal.SIGPIPE, signal.SIGXFSZ, signal.SIGINT):
        signal.signal(s, signal.SIG_DFL)
    os.execvp(sys.argv[2], sys.argv[2:])
signal.signal(signal.SIGINT, signal.SIG_IGN)
_, status, usage = os.wait4(pid, 0)
with open(sys.argv[1], 'w') as f:
    f.write(repr(usage.ru_utime + usage.ru_stime))
if os.WIFSIGNALED(status):
    signal.signal(os.WTERMSIG(status), signal.SIG_DFL)
    os.kill(os.getpid(), os.WTERMSIG(status))
sys.exit(os.WEXITSTATUS(status))
"""


def run_case(case, exe, scratch, refs):
    folder = scratch / case['name']
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    problems = []
    if case.get('input') is not None:
        data = case['input']
        (folder / 'in.nml').write_bytes(data if isinstance(data, bytes) else data.encode())
    for name, data in case.get('files', {}).items():
        (folder / name).write_bytes(data if isinstance(data, bytes) else data.encode())
    env = dict(os.environ)
    env.update({'MPM1D': exe, 'OMP_NUM_THREADS': '1', 'LC_ALL': 'C', 'PYTHON': sys.executable})
    env.update(case.get('env', {}))
    if case.get('setup'):
        subprocess.run(['bash', '-c', case['setup']], cwd=folder, env=env, check=True)
    if case.get('shell'):
        command = ['bash', '-c', case['shell']]
    else:
        command = [exe] + [a.replace('{exe}', exe) for a in case.get('args', ['in.nml'])]
    cpu_file = scratch / (case['name'] + '.cpu_seconds')
    if 'cpu_seconds' in case:
        command = [sys.executable, '-c', CPU_WRAPPER, str(cpu_file)] + command
    stdin = case.get('stdin')
    start = time.time()
    try:
        p = subprocess.run(command, cwd=folder, env=env, capture_output=True, timeout=HANG_SECONDS,
                           input=(stdin.encode() if isinstance(stdin, str) else stdin) if stdin is not None else None,
                           stdin=None if stdin is not None else subprocess.DEVNULL)
        code, out, err = p.returncode, p.stdout.decode(errors='replace'), p.stderr.decode(errors='replace')
    except subprocess.TimeoutExpired:
        return case, [f'still running after {HANG_SECONDS} s (hangs)'], None, time.time() - start
    text = out + err
    if 'cpu_seconds' in case:
        cpu = float(cpu_file.read_text()) if cpu_file.exists() else float('nan')
        if not cpu <= case['cpu_seconds']:
            problems.append(f"{cpu:.2f} s of CPU time, allowed {case['cpu_seconds']} s")
        if os.environ.get('HOSTILE_SHOW_CPU'):
            print(f"cpu {case['name']}: {cpu:.3f} s (budget {case['cpu_seconds']} s)")
    allowed = case['exit'] if isinstance(case['exit'], list) else [case['exit']]
    if code not in allowed:
        problems.append(f"exit {code}, expected {case['exit']}")
    pattern = case.get('pattern')
    if pattern and not re.search(pattern, text, re.S):
        problems.append(f'message lacks /{pattern}/')
    anti = case.get('not_pattern')
    if anti and re.search(anti, text, re.S):
        problems.append(f'message has /{anti}/')
    if COMPILER_WORDS.search(text):
        problems.append('compiler or library runtime text in the output')
    # (env_warning: a library reading the environment at start-up may warn first)
    if code == 2 and not case.get('shell') and not err.startswith('mpm1d:') and \
            not (case.get('env_warning') and '\nmpm1d:' in err):
        problems.append("refusal not in mpm1d's words (standard error does not start 'mpm1d:')")
    for g in case.get('exists', []):
        if not glob.glob(str(folder / g)):
            problems.append(f'{g} missing')
    for g in case.get('absent', []) + ([] if case.get('allow_part') else ['*.part', '.*.part']):
        if glob.glob(str(folder / g)):
            problems.append(f'{g} exists')
    measured = None
    if code == 0:
        for h5 in glob.glob(str(folder / '*.h5')):
            try:
                bad = non_finite_datasets(h5)
            except OSError:
                continue
            if bad:
                problems.append(f'exit 0 but non-finite results in {os.path.basename(h5)}: {bad[:4]}')
    if ('rel_error' in case or case.get('ref')) and code == 0:
        try:
            measured = relative_error(folder / case.get('output', 'o.h5'))
        except (OSError, KeyError) as e:
            problems.append(f'no relative error to read: {e}')
    if 'rel_error' in case and measured is None and code != 0 and 0 in allowed and code in allowed:
        pass  # an accepted refusal: no relative error to compare
    elif 'rel_error' in case and measured is not None:
        expected = case['rel_error']
        if isinstance(expected, str):
            expected = refs.get(expected[1:])
        tol = case.get('rel_tol', 1e-6)
        if expected is None or not abs(measured - expected) <= tol*abs(expected):
            problems.append(f'relative error {measured!r}, expected {expected!r} (tolerance {tol:g} relative)')
    if not problems and not case.get('keep'):
        shutil.rmtree(folder, ignore_errors=True)
    elif problems:
        problems.append('stderr: ' + err.strip()[:400].replace('\n', ' | '))
    return case, problems, measured, time.time() - start


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--exe')
    parser.add_argument('--only', help='run the cases whose name matches this regular expression')
    parser.add_argument('--list', action='store_true')
    parser.add_argument('-j', type=int, default=2)
    args = parser.parse_args()
    table = case_table.CASES
    names = [c['name'] for c in table]
    duplicates = {n for n in names if names.count(n) > 1}
    if duplicates:
        sys.exit(f'duplicate case names: {sorted(duplicates)}')
    if args.only:
        wanted = [c for c in table if re.search(args.only, c['name'])]
        needed = {c['rel_error'][1:] for c in wanted if isinstance(c.get('rel_error'), str)}
        table = [c for c in table if c in wanted or c['name'] in needed]
    if args.list:
        for c in table:
            print(c['cls'], c['name'])
        return
    exe = args.exe or find_exe()
    devices = device_state()
    scratch = ROOT / 'build' / 'test_scratch' / 'hostile'
    shutil.rmtree(scratch, ignore_errors=True)
    scratch.mkdir(parents=True)
    refs, failures, counts, start = {}, [], {}, time.time()
    # references first (runs whose relative error others must reproduce), then everything else
    for phase in (True, False):
        batch = [c for c in table if bool(c.get('ref')) == phase]
        with futures.ThreadPoolExecutor(max_workers=args.j) as pool:
            for case, problems, measured, seconds in pool.map(lambda c: run_case(c, exe, scratch, refs), batch):
                counts.setdefault(case['cls'], [0, 0])[0 if not problems else 1] += 1
                if case.get('ref') and measured is not None:
                    refs[case['name']] = measured
                if problems:
                    failures.append((case, problems))
    if device_state() != devices:
        failures.append(({'cls': 'suite', 'name': 'devices untouched'}, ['a system device was replaced: restore it']))
    for case, problems in failures:
        print(f"FAIL [{case['cls']}] {case['name']}: " + '; '.join(problems))
    print('hostile-input suite: cases per class (passed/failed):')
    for cls in sorted(counts):
        print(f'  {cls:<28} {counts[cls][0]:4d} passed {counts[cls][1]:4d} failed')
    total = sum(sum(v) for v in counts.values())
    print(f'{total} cases, {len(failures)} failed, {time.time() - start:.1f} s')
    sys.exit(1 if failures else 0)


if __name__ == '__main__':
    main()
