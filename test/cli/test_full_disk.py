"""Every write path of mpm1d on a full disk: a single run, a sweep (with histories), a shard, a
resumed sweep and a merge, each made to fail at several points of its file; a sweep whose output
fails keeps its finished cases in its journal, and --resume writes the file without running them again;
the Python figure commands (mpm1d-plot-sweep, mpm1d-linear-stability, mpm1d-plot-run, mpm1d-animate)
fail the same way. Two ways to fill the disk:
  * a small tmpfs (ENOSPC, "no space left on device"), filled but for a few kilobytes: needs root and
    a kernel that lets it mount one; skipped, saying why, where it cannot;
  * a file-size limit (RLIMIT_FSIZE, `ulimit -f`: EFBIG, "file too large"), anywhere.
Each failure must end with exit code 3 (the output error of mpm1d --help), a message in mpm1d's words
naming the file and the cause, nothing under the final name but the older file of that name (intact),
and no temporary file left; with enough room every path writes its file. A run that crashed in its
exit handlers (HDF5's clean-up of a file whose close failed: SIGSEGV) or in HDF5's copy fails here.

Usage: $PYTHON test/cli/test_full_disk.py [--exe PATH]
"""
import argparse
import os
import re
import resource
import shutil
import signal
import subprocess
import sys
from pathlib import Path

from cli_checks import ROOT, Tally, find_exe

SCRATCH = ROOT / 'build' / 'test_scratch' / 'full_disk'
OLDER = b'an older file of this name\n'
CRASH_WORDS = re.compile(r'Fortran runtime|Backtrace|Program received signal|Segmentation fault|HDF5-DIAG|'
                         r'Error termination|At line \d+')
RUN = """&discretisation elements=200 /
&output file='{out}', snapshot_times=0.001, 0.002, 0.003 /
"""
SWEEP = """&output file='{out}' /
&sweep elements=3, 4, 5, 6, 7, 8, dt_fraction=0.1, 0.2, 0.3, 0.4, min_time=0, histories=.true., threads=1 /
"""

TALLY = Tally()
check = TALLY.check


def run(args, cwd, limit_kb=None, env=None):
    """Run a command in `cwd`; with `limit_kb` under a file-size limit of that many KiB."""
    def limited():
        if limit_kb is not None:
            resource.setrlimit(resource.RLIMIT_FSIZE, (limit_kb * 1024, resource.RLIM_INFINITY))
    full_env = dict(os.environ, OMP_NUM_THREADS='1', LC_ALL='C')
    full_env.update(env or {})
    return subprocess.run(args, cwd=cwd, capture_output=True, text=True, preexec_fn=limited, env=full_env,
                          timeout=600)


def leftovers(folder):
    return sorted(p.name for p in Path(folder).iterdir() if '.part' in p.name)


def expect_failure(label, p, folder, final, cause):
    """A write that failed: exit 3, the message, the older file intact, no temporary file."""
    text = p.stdout + p.stderr
    check(f'{label}: exit 3', p.returncode == 3, f'exit {p.returncode}; {p.stderr.strip()[:300]}')
    check(f'{label}: no crash text', not CRASH_WORDS.search(text), text[:300])
    check(f'{label}: message names the file and the cause',
          p.stderr.startswith('mpm1d:') and Path(final).name in p.stderr and cause in p.stderr, p.stderr[:300])
    check(f'{label}: the older file intact', Path(final).read_bytes() == OLDER)
    check(f'{label}: no temporary file left', not leftovers(folder), leftovers(folder))


def write_paths(exe, folder, free_levels, fill, cause):
    """Each write path in `folder`, with `fill(level)` making the disk full at each level (returns the
    keyword arguments of run, the file-size limit)."""
    folder = Path(folder)
    side = SCRATCH / 'inputs'
    # the shards merged and the interrupted sweep resumed, made where there is room
    shutil.rmtree(side, ignore_errors=True)
    side.mkdir(parents=True)
    (side / 'sw.nml').write_text(SWEEP.format(out='sw.h5'))
    for shard in ('1/2', '2/2'):
        assert run([exe, 'sw.nml', '-q', '--shard', shard], side).returncode == 0
    merged = [str(side / 'sw_shard001of002.h5'), str(side / 'sw_shard002of002.h5')]
    paths = {
        'single run': ([exe, 'run.nml', '-q'], 'run.h5'),
        'sweep': ([exe, 'sw.nml', '-q'], 'sw.h5'),
        'shard': ([exe, 'sw.nml', '-q', '--shard', '2/2'], 'sw_shard002of002.h5'),
        'merge': ([exe, 'merge', 'merged.h5'] + merged, 'merged.h5'),
        'resumed sweep': ([exe, 'sw.nml', '-q', '--resume'], 'sw.h5'),
    }
    for level in free_levels:
        for name, (args, final) in paths.items():
            for p in folder.iterdir():
                p.unlink()
            (folder / 'run.nml').write_text(RUN.format(out='run.h5'))
            (folder / 'sw.nml').write_text(SWEEP.format(out='sw.h5'))
            if name == 'resumed sweep':
                # an interrupted sweep's file (4 of 24 cases) stands where the resumed one goes
                interrupted = interrupted_sweep(exe, side)
                shutil.copy(interrupted, folder / 'sw.h5')
                limits = fill(level)
                p = run(args, folder, **limits)
                check(f'{name}, {level}: exit 3', p.returncode == 3, f'exit {p.returncode}; {p.stderr[:300]}')
                check(f'{name}, {level}: the interrupted file intact',
                      (folder / 'sw.h5').read_bytes() == Path(interrupted).read_bytes())
                check(f'{name}, {level}: message names the file and the cause',
                      'sw.h5' in p.stderr and cause in p.stderr and not CRASH_WORDS.search(p.stderr), p.stderr[:300])
                check(f'{name}, {level}: no temporary file left', not leftovers(folder), leftovers(folder))
                continue
            (folder / final).write_bytes(OLDER)
            limits = fill(level)
            p = run(args, folder, **limits)
            expect_failure(f'{name}, {level}', p, folder, folder / final, cause)


def figure_commands(folder, sweep, single, fill, levels, cause):
    """The Python figure commands writing into a full `folder` (`fill(level)`: the limits), from the sweep
    file `sweep` and the run file `single`: exit 3, the file and the cause in the command's own words, the
    older file of that name intact, no temporary file."""
    bin_dir = Path(sys.executable).parent
    commands = {
        'mpm1d-plot-sweep': ([str(bin_dir / 'mpm1d-plot-sweep'), str(sweep), '-o', '.'], 'error_vs_elements.png'),
        'mpm1d-linear-stability': ([str(bin_dir / 'mpm1d-linear-stability'), '--schemes', 'usl', '--ppc', '1',
                                    '--elements', '10', '--out', '.'], 'predicted_critical.csv'),
        'mpm1d-plot-run': ([str(bin_dir / 'mpm1d-plot-run'), str(single), '-o', '.'], 'ucm.png'),
        'mpm1d-animate': ([str(bin_dir / 'mpm1d-animate'), str(single), '-o', 'run.gif'], 'run.gif'),
    }
    for level in levels:
        for name, (args, first) in commands.items():
            if level > 0 and name == 'mpm1d-linear-stability':
                continue  # (its files are small: full from the start only)
            for p in folder.iterdir():
                p.unlink()
            (folder / first).write_bytes(OLDER)
            p = run(args, folder, **fill(level))
            label = f'{name}, {level}'
            check(f'{label}: exit 3', p.returncode == 3, f'exit {p.returncode}; {p.stderr[-300:]}')
            check(f'{label}: the message names the file and the cause', re.search(
                rf"^{name}: cannot write '[^']+': {cause}$", p.stderr, re.M) is not None and 'Traceback' not in p.stderr,
                p.stderr[-300:])
            check(f'{label}: the older file intact', (folder / first).read_bytes() == OLDER)
            check(f'{label}: no temporary file left', not leftovers(folder), leftovers(folder))


def sweep_keeps_its_cases(exe, folder, reference, full, room, cause):
    """A sweep whose output cannot be written keeps its finished cases in its journal (`full`: the
    limits of a disk with room for the journal, then of one with room for part of it), and `room()`
    freeing space, --resume writes the file without running them again: the uninterrupted table."""
    for label, limits, whole in (('the journal fits', full(True), True), ('the journal fills too', full(False), False)):
        for p in folder.iterdir():
            p.unlink()
        (folder / 'sw.nml').write_text(SWEEP.format(out='sw.h5'))
        limits = limits() if callable(limits) else limits
        p = run([exe, 'sw.nml', '-q'], folder, **limits)
        text = p.stderr
        check(f'sweep, {label}: exit 3', p.returncode == 3, f'exit {p.returncode}; {text[:300]}')
        check(f'sweep, {label}: the message names the output, the cause and the journal', cause in text and
              "journal 'sw.h5.journal'" in text and '--resume' in text and not CRASH_WORDS.search(text), text[:400])
        if not whole:
            check(f'sweep, {label}: the message says the journal failed too', 'before it too failed' in text, text[:400])
        check(f'sweep, {label}: the journal kept, no temporary file', (folder / 'sw.h5.journal').exists() and
              not leftovers(folder), sorted(p.name for p in folder.iterdir()))
        room()
        p = run([exe, 'sw.nml', '--resume'], folder)
        check(f'sweep, {label}: --resume writes the file', p.returncode == 0 and (folder / 'sw.h5').exists(),
              p.stderr[:300])
        if whole:
            check(f'sweep, {label}: --resume runs no case again', '24 of 24 cases ran before (kept); 0 to run'
                  in p.stdout, p.stdout[:300])
        else:
            check(f'sweep, {label}: --resume runs the cases after the journal failed',
                  re.search(r'resumed: ([1-9]|1\d|2[0-3]) of 24 cases ran before \(kept\)', p.stdout), p.stdout[:300])
        if (folder / 'sw.h5').exists():
            check(f'sweep, {label}: the table equals the uninterrupted one', same_cases(reference, folder / 'sw.h5'))
        check(f'sweep, {label}: the journal removed', not (folder / 'sw.h5.journal').exists())


def same_cases(a, b):
    """The /cases columns but the timings and the histories, bit for bit."""
    import h5py
    import numpy as np

    def same(x, y):
        x, y = np.asarray(x), np.asarray(y)
        return x.tolist() == y.tolist() if x.dtype.kind in 'OSU' else x.tobytes() == y.tobytes()
    with h5py.File(a, 'r') as f, h5py.File(b, 'r') as g:
        if set(f['cases']) != set(g['cases']) or set(f['histories']) != set(g['histories']):
            return False
        return all(same(f['cases'][k][()], g['cases'][k][()]) for k in f['cases'] if k != 'run_time') and \
            all(same(f['histories'][k][d][()], g['histories'][k][d][()]) for k in f['histories'] for d in f['histories'][k])


def interrupted_sweep(exe, side):
    """A sweep file with 4 of its 24 cases run (a SIGINT after the 4th; made once)."""
    path = side / 'interrupted' / 'sw.h5'
    if path.exists():
        return path
    path.parent.mkdir()
    (path.parent / 'sw.nml').write_text(SWEEP.format(out='sw.h5'))
    env = dict(os.environ, OMP_NUM_THREADS='1', MPM1D_PAUSE_AFTER_CASES='4')
    p = subprocess.Popen([exe, 'sw.nml', '-q'], cwd=path.parent, env=env, stdout=subprocess.DEVNULL,
                         stderr=subprocess.DEVNULL)
    while not (path.parent / 'mpm1d_paused').exists():
        assert p.poll() is None, 'the sweep ended before its pause'
    p.send_signal(signal.SIGINT)
    assert p.wait() == 130
    return path


def mounted_tmpfs(folder, size_kb):
    """Mount a tmpfs of size_kb at `folder`; the reason it cannot, or None."""
    if os.geteuid() != 0:
        return 'not root (mounting a tmpfs needs root)'
    folder.mkdir(parents=True, exist_ok=True)
    p = subprocess.run(['mount', '-t', 'tmpfs', '-o', f'size={size_kb}k', 'tmpfs', str(folder)],
                       capture_output=True, text=True)
    return None if p.returncode == 0 else f'mount -t tmpfs failed: {p.stderr.strip()}'


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--exe')
    args = parser.parse_args()
    exe = args.exe or find_exe()
    shutil.rmtree(SCRATCH, ignore_errors=True)
    SCRATCH.mkdir(parents=True)

    # a file-size limit anywhere: the files fail at 1 KiB, then at points through their whole size
    limited = SCRATCH / 'limited'
    limited.mkdir()
    write_paths(exe, limited, [1, 16, 48, 96, 136], lambda kb: {'limit_kb': kb}, 'file too large')
    # the sweep's journal takes 223 KiB, its output 320 KiB (a limit is per file)
    (SCRATCH / 'reference').mkdir()
    (SCRATCH / 'reference' / 'sw.nml').write_text(SWEEP.format(out='sw.h5'))
    assert run([exe, 'sw.nml', '-q'], SCRATCH / 'reference').returncode == 0
    reference = SCRATCH / 'reference' / 'sw.h5'
    (SCRATCH / 'reference' / 'run.nml').write_text(RUN.format(out='run.h5'))
    assert run([exe, 'run.nml', '-q'], SCRATCH / 'reference').returncode == 0
    single = SCRATCH / 'reference' / 'run.h5'
    sweep_keeps_its_cases(exe, limited, reference, lambda whole: {'limit_kb': 256 if whole else 64},
                          lambda: None, 'file too large')
    figure_commands(limited, reference, single, lambda kb: {'limit_kb': kb}, [0, 4], 'file too large')

    # a full tmpfs: filled by a filler file but for `free` KiB
    disk = SCRATCH / 'tmpfs'
    size_kb = 1024
    why = mounted_tmpfs(disk, size_kb)
    skipped = None
    if why is None:
        try:
            def fill(free_kb):
                with open(disk / 'filler', 'wb', buffering=0) as f:
                    for _ in range(size_kb - free_kb):
                        try:
                            f.write(b'\0' * 1024)
                        except OSError:
                            break
                return {}
            write_paths(exe, disk, [0, 8, 32, 64, 128], fill, 'no space left on device')
            # room for the journal (223 KiB) but not the output (320 KiB more), then for part of the journal
            sweep_keeps_its_cases(exe, disk, reference, lambda whole: (lambda: fill(448 if whole else 96)),
                                  lambda: (disk / 'filler').unlink(), 'no space left on device')
            figure_commands(disk, reference, single, lambda free: (fill(free) or {}), [0, 4], 'no space left on device')
            # with room again, every path writes its file
            for p in disk.iterdir():
                p.unlink()
            (disk / 'run.nml').write_text(RUN.format(out='run.h5'))
            p = run([exe, 'run.nml', '-q'], disk)
            check('tmpfs with room: the run writes its file', p.returncode == 0 and (disk / 'run.h5').exists(),
                  p.stderr[:300])
        finally:
            subprocess.run(['umount', str(disk)], check=False)
    else:
        skipped = why
    print(f'test_full_disk: {TALLY.passed} passed, {TALLY.failed} failed')
    if skipped:
        print(f'test_full_disk: the tmpfs part skipped: {skipped} (the file-size limit part ran)')
    sys.exit(1 if TALLY.failed else 0)


if __name__ == '__main__':
    main()
