"""A sweep killed with SIGKILL at any moment resumes to the uninterrupted sweep's table.

  * 24 kills at moments drawn over the whole run (error pass, timing pass, the final write, after it),
    of a sweep with histories on 2 threads, alternately without and with a timing pass; each followed by
    `mpm1d SWEEP.nml --resume`, whose /cases table must equal the uninterrupted sweep's bit for bit in
    every column but the timings, and its histories too; the journal is gone afterwards. Each kill
    reports what it lost: the cases that had finished (the progress log, a line per case, is written
    after the case's journal record) but are not in the journal (must be none), and the cases the
    resume ran again (those in flight and those not started).
  * Kills at known points: while the complete output waits for its rename (test hook
    MPM1D_PAUSE_BEFORE_RENAME): the resume runs nothing and writes the file.
  * A torn journal: the last record cut at 16 places, a byte of its payload or of its checksum
    changed, a record in the middle changed: the torn record (and what follows it) is dropped, never
    read, and the resume gives the uninterrupted table; a journal cut inside its first record with no
    sweep file is refused ("nothing to resume"); a journal of another sweep is refused naming it.
The journal is read here by an implementation of its format of its own (src/io/mpm_journal_c.c).

Usage: $PYTHON test/cli/test_sweep_kill.py [--exe PATH] [--kills N]
"""
import argparse
import os
import random
import re
import shutil
import signal
import struct
import subprocess
import sys
import time
from pathlib import Path

import h5py
import numpy as np

from cli_checks import ROOT, Tally, find_exe

SCRATCH = ROOT / 'build' / 'test_scratch' / 'sweep_kill'
TIMING_COLUMNS = {'run_time', 'repeats', 'run_time_spread', 'timing_rounds'}
SWEEP = """&run periods=2 /
&output file='{out}' /
&sweep elements=10, 20, 40, 80, particles_per_element=1, 2, 4, dt_fraction=0.1, 0.2, 0.3, 2.5,
       min_time={min_time}, histories=.true., threads=2, progress=.true. /
"""
MAGIC = 0x4A4D504D

TALLY = Tally()
check = TALLY.check


def fnv1a(data, h):
    """FNV-1a over 64-bit little-endian words, then the bytes that do not fill one."""
    whole = len(data) // 8 * 8
    for (word,) in struct.iter_unpack('<Q', data[:whole]):
        h = ((h ^ word) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    for b in data[whole:]:
        h = ((h ^ b) * 1099511628211) & 0xFFFFFFFFFFFFFFFF
    return h


def checksum(kind, length, payload):
    """A record's checksum: the hash of its kind (4 bytes), then of its length (8), then of its payload."""
    h = fnv1a(struct.pack('<I', kind), 14695981039346656037)
    return fnv1a(payload, fnv1a(struct.pack('<Q', length), h))


def journal_records(path):
    """The whole records of a journal [(kind, payload, offset, end)] and the bytes after them."""
    data = Path(path).read_bytes() if Path(path).exists() else b''
    records, at = [], 0
    while len(data) - at >= 24:
        magic, kind, length = struct.unpack_from('<IIQ', data, at)
        if magic != MAGIC or length > len(data) - at - 24:
            break
        payload = data[at + 16:at + 16 + length]
        (stored,) = struct.unpack_from('<Q', data, at + 16 + length)
        if stored != checksum(kind, length, payload):
            break
        records.append((kind, payload, at, at + 24 + length))
        at += 24 + length
    return records, len(data) - at


def same(x, y):
    x, y = np.asarray(x), np.asarray(y)
    if x.dtype.kind in 'OSU':
        return x.tolist() == y.tolist()
    return x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes()


def differences(reference, path):
    """The /cases columns (but the timings) and histories of `path` that differ from `reference`'s."""
    bad = []
    with h5py.File(reference, 'r') as a, h5py.File(path, 'r') as b:
        if set(a['cases']) != set(b['cases']):
            bad.append('the /cases columns')
        bad += [k for k in a['cases'] if k not in TIMING_COLUMNS and k in b['cases'] and
                not same(a['cases'][k][()], b['cases'][k][()])]
        if set(a['histories']) != set(b['histories']):
            bad.append('the set of histories')
        else:
            bad += [f'history {k}' for k in a['histories'] if any(not same(a['histories'][k][d][()], b['histories'][k][d][()])
                                                                  for d in a['histories'][k])]
        if 'run_time' in a['cases']:
            # the timing columns: a timed case wherever the uninterrupted sweep timed one
            if not np.array_equal(a['cases']['repeats'][()] > 0, b['cases']['repeats'][()] > 0):
                bad.append('which cases are timed')
    return bad


def run(exe, args, cwd, **kw):
    env = dict(os.environ, OMP_NUM_THREADS='2', LC_ALL='C')
    env.update(kw.pop('env', {}))
    return subprocess.run([exe] + args, cwd=cwd, capture_output=True, text=True, env=env, timeout=600, **kw)


def finished_in_log(path):
    """Cases finished according to the progress log (the last 'error pass: N / M cases' line)."""
    text = Path(path).read_text(errors='replace') if Path(path).exists() else ''
    done = re.findall(r'error pass: (\d+) / \d+ cases', text)
    return int(done[-1]) if done else 0


def resume_equals(exe, folder, reference, label, expect_torn=None):
    """--resume in `folder`: exit 0, the table and histories of `reference`, no journal left."""
    p = run(exe, ['sw.nml', '--resume'], folder)
    check(f'{label}: --resume exits 0', p.returncode == 0, p.stderr[:400])
    if p.returncode != 0:
        return p
    bad = differences(reference, folder / 'sw.h5')
    check(f'{label}: the resumed table equals the uninterrupted one', not bad, bad)
    check(f'{label}: no journal left', not (folder / 'sw.h5.journal').exists())
    if expect_torn is not None:
        check(f'{label}: the torn record is reported', f'a torn last record of {expect_torn} bytes dropped'
              in p.stdout, p.stdout[-400:])
    return p


def kills(exe, references, durations, count, rng):
    completed = {}
    for timing, reference in references.items():
        with h5py.File(reference, 'r') as f:
            completed[timing] = int(np.sum(f['cases']['repeats'][()] > 0)) if timing else 0
    print('kill  at (s)  of run (s)  phase           journal: cases timings   finished (log)  lost  run again  '
          'timed again')
    for k in range(count):
        timing = k % 2 == 1
        reference, duration = references[timing], durations[timing]
        folder = SCRATCH / f'kill{k:02d}'
        shutil.rmtree(folder, ignore_errors=True)
        folder.mkdir(parents=True)
        (folder / 'sw.nml').write_text(SWEEP.format(out='sw.h5', min_time='0.0005' if timing else '0'))
        delay = rng.uniform(0.0, 1.1 * duration)
        env = dict(os.environ, OMP_NUM_THREADS='2', MPM1D_PROGRESS_LOG_SECONDS='0')
        with open(folder / 'log.txt', 'w') as log:
            p = subprocess.Popen([exe, 'sw.nml'], cwd=folder, env=env, stdout=log, stderr=log)
            start = time.monotonic()
            try:
                p.wait(timeout=delay)
            except subprocess.TimeoutExpired:
                p.send_signal(signal.SIGKILL)
                p.wait()
        ran = time.monotonic() - start
        if p.returncode == 0:
            phase = 'after the end'
        else:
            check(f'kill {k}: killed by SIGKILL', p.returncode == -signal.SIGKILL, f'exit {p.returncode}')
            phase = ''
        records, torn = journal_records(folder / 'sw.h5.journal')
        cases = sum(1 for kind, *_ in records if kind == 2)
        timings = sum(1 for kind, *_ in records if kind == 3)
        if p.returncode != 0:
            if list(folder.glob('sw.h5.*.part')):
                phase = 'writing'
            elif not (folder / 'sw.h5.journal').exists():
                # no journal: killed before it began, or after the finished sweep removed it (its file in
                # place, the process not yet gone)
                phase = 'after the end' if (folder / 'sw.h5').exists() else 'starting'
            elif not records and not (folder / 'sw.h5').exists():
                # killed while it wrote its journal's first record: nothing whole kept
                phase = 'starting'
            elif timing and cases == 48:
                phase = 'timing pass'
            else:
                phase = 'error pass'
        log_done = finished_in_log(folder / 'log.txt')
        lost = max(0, log_done - cases) if phase not in ('after the end', 'starting') else 0
        check(f'kill {k}: every case the log saw finish is in the journal', lost == 0, f'{log_done} > {cases}')
        if phase == 'after the end':
            check(f'kill {k}: a finished sweep leaves no journal', not (folder / 'sw.h5.journal').exists())
            with h5py.File(folder / 'sw.h5', 'r') as f:
                check(f'kill {k}: a finished sweep wrote its every case', f['cases']['index'].shape == (48,),
                      str(f['cases']['index'].shape))
            again = 0
        elif phase == 'starting':
            # killed before its journal held a whole record: nothing kept, and --resume says so
            p = run(exe, ['sw.nml', '--resume'], folder)
            check(f'kill {k} (starting): nothing to resume', p.returncode == 2 and 'nothing to resume' in p.stderr,
                  p.stderr[:300])
            again = 48
        else:
            p = resume_equals(exe, folder, reference, f'kill {k} ({phase})')
            m = re.search(r'(\d+) to run', p.stdout)
            again = int(m.group(1)) if m else -1
        timed_again = completed[timing] - timings if phase not in ('after the end',) else 0
        print(f'{k:4d}  {ran:6.3f}   {duration:6.3f}    {phase:<15} {cases:13d} {timings:7d}   {log_done:14d}  '
              f'{lost:4d}  {again:9d}  {timed_again:11d}')


def known_points(exe, reference):
    folder = SCRATCH / 'before_rename'
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    (folder / 'sw.nml').write_text(SWEEP.format(out='sw.h5', min_time='0'))
    env = dict(os.environ, OMP_NUM_THREADS='2', MPM1D_PAUSE_BEFORE_RENAME='600')
    p = subprocess.Popen([exe, 'sw.nml', '-q'], cwd=folder, env=env, stderr=subprocess.DEVNULL)
    while not list(folder.glob('sw.h5.*.part')):
        if p.poll() is not None:
            break
        time.sleep(0.02)
    p.send_signal(signal.SIGKILL)
    p.wait()
    records, _ = journal_records(folder / 'sw.h5.journal')
    check('killed before the rename: every case in the journal', sum(1 for r in records if r[0] == 2) == 48)
    q = resume_equals(exe, folder, reference, 'killed before the rename')
    check('killed before the rename: the resume runs nothing', 'resumed: 48 of 48 cases ran before (kept); 0 to run'
          in q.stdout, q.stdout[:300])


def torn_journals(exe, reference):
    """A journal of a sweep killed after some cases, then torn or changed in many ways."""
    source = SCRATCH / 'torn_source'
    shutil.rmtree(source, ignore_errors=True)
    source.mkdir(parents=True)
    (source / 'sw.nml').write_text(SWEEP.format(out='sw.h5', min_time='0'))
    env = dict(os.environ, OMP_NUM_THREADS='1', MPM1D_PAUSE_AFTER_CASES='6')
    p = subprocess.Popen([exe, 'sw.nml', '-q', '--threads', '1'], cwd=source, env=env, stderr=subprocess.DEVNULL)
    while not (source / 'mpm1d_paused').exists():
        if p.poll() is not None:
            break
        time.sleep(0.02)
    p.send_signal(signal.SIGKILL)
    p.wait()
    data = (source / 'sw.h5.journal').read_bytes()
    records, torn = journal_records(source / 'sw.h5.journal')
    check('torn: the paused sweep journaled its identity and 6 cases', [r[0] for r in records] == [1] + [2] * 6 and
          torn == 0, [r[0] for r in records])
    last_start, last_end = records[-1][2], records[-1][3]
    length = last_end - last_start
    cuts = sorted({1, 4, 8, 15, 16, 17, 23, 24, length // 3, length // 2, length - 9, length - 8, length - 7,
                   length - 2, length - 1, 2 * length // 3})
    variants = [(f'cut {c} bytes into the last record', data[:last_start + c], c) for c in cuts]
    flip = bytearray(data)
    flip[last_start + 16 + (length - 24) // 2] ^= 0x40
    variants.append(('a byte of the last payload changed', bytes(flip), length))
    flip = bytearray(data)
    flip[last_end - 3] ^= 0x01
    variants.append(('a byte of the last checksum changed', bytes(flip), length))
    middle = records[3]
    flip = bytearray(data)
    flip[middle[2] + 20] ^= 0x10
    variants.append(('a record in the middle changed', bytes(flip), len(data) - middle[2]))
    for label, content, dropped in variants:
        folder = SCRATCH / 'torn'
        shutil.rmtree(folder, ignore_errors=True)
        folder.mkdir(parents=True)
        shutil.copy(source / 'sw.nml', folder)
        (folder / 'sw.h5.journal').write_bytes(content)
        resume_equals(exe, folder, reference, f'torn journal, {label}', expect_torn=dropped)
    # cut inside its first record, no sweep file: nothing to resume
    folder = SCRATCH / 'torn_identity'
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    shutil.copy(source / 'sw.nml', folder)
    (folder / 'sw.h5.journal').write_bytes(data[:records[0][3] - 5])
    p = run(exe, ['sw.nml', '--resume'], folder)
    check('a journal torn in its first record, no sweep file: refused', p.returncode == 2 and
          'holds no whole record' in p.stderr and not (folder / 'sw.h5').exists(), p.stderr[:300])
    # another sweep's journal: refused, naming what differs, left as it was
    folder = SCRATCH / 'other'
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    shutil.copy(source / 'sw.nml', folder)
    (folder / 'sw.h5.journal').write_bytes(data)
    p = run(exe, ['sw.nml', 'sweep.elements=10,20', '--resume'], folder)
    check("another sweep's journal: refused naming it", p.returncode == 2 and
          "the journal 'sw.h5.journal' holds another sweep: its &sweep group differs" in p.stderr, p.stderr[:300])
    check("another sweep's journal: left as it was", (folder / 'sw.h5.journal').read_bytes() == data)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--exe')
    parser.add_argument('--kills', type=int, default=24)
    args = parser.parse_args()
    exe = args.exe or find_exe()
    shutil.rmtree(SCRATCH, ignore_errors=True)
    SCRATCH.mkdir(parents=True)
    references, durations = {}, {}
    for timing in (False, True):
        folder = SCRATCH / f'reference_{int(timing)}'
        folder.mkdir()
        (folder / 'sw.nml').write_text(SWEEP.format(out='sw.h5', min_time='0.0005' if timing else '0'))
        start = time.monotonic()
        p = run(exe, ['sw.nml', '-q'], folder)
        durations[timing] = time.monotonic() - start
        check(f'the uninterrupted sweep runs ({"with" if timing else "without"} a timing pass)', p.returncode == 0,
              p.stderr[:300])
        check('the uninterrupted sweep leaves no journal', not (folder / 'sw.h5.journal').exists())
        references[timing] = folder / 'sw.h5'
    kills(exe, references, durations, args.kills, random.Random(38))
    known_points(exe, references[False])
    torn_journals(exe, references[False])
    print(f'test_sweep_kill: {TALLY.passed} passed, {TALLY.failed} failed')
    sys.exit(1 if TALLY.failed else 0)


if __name__ == '__main__':
    main()
