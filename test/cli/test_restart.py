"""A single run killed after a checkpoint restarts to the uninterrupted run's file, bit for bit.

For each case of a set that covers every scene, shape, transfer, formulation, law and integrator (and
the fused kernels beside the generic path): the run uninterrupted (its checkpoint removed at the end);
the same run killed (SIGKILL) just after its second checkpoint (test hook MPM1D_PAUSE_AFTER_CHECKPOINT);
`mpm1d RUN.nml --restart`, which must say the step it restarts from and write the uninterrupted run's
file, bit for bit in every dataset and attribute of /history, /snapshots, /summary and /config but the
run time; no checkpoint left after it.
Then, on one case: SIGTERM stops a run with checkpoints, which writes its checkpoint at the step it
reached and says how to go on, and --restart completes it alike; --restart without a checkpoint, with
another input (a changed variable, named), and with a damaged checkpoint (torn, a byte changed) is
refused with exit 2 and the checkpoint left as it was. And SIGTERM stops a long run without checkpoints
after the step it is in, naming it, with exit 143 and no file.

Usage: $PYTHON test/cli/test_restart.py [--exe PATH] [--only REGEX]
"""
import argparse
import os
import re
import shutil
import signal
import subprocess
import sys
import time

import h5py
import numpy as np

from cli_checks import ROOT, Tally, find_exe

SCRATCH = ROOT / 'build' / 'test_scratch' / 'restart'
TALLY = Tally()
check = TALLY.check

#: name: (namelist groups, checkpoint_steps); each run keeps its history and 4 snapshots
IMPACT = ("&scene kind='impact', lengths=1.0, 1.0, youngs_moduli=200.0e9, 200.0e9, densities=7800.0, 7800.0, "
          "velocities=1.0, -1.0, gap=0.0, contact='{contact}' /\n")
CASES = {
    'bar_usl_linear_flip_fused': ("&discretisation elements=40 /\n&run periods=1 /", 37),
    'bar_usf_generic': ("&discretisation elements=40, kernels='generic', scheme='usf' /\n&run periods=1 /", 41),
    'bar_musl_bspline3_apic': ("&discretisation elements=40, shape='bspline3', transfer='apic', scheme='musl' /\n"
                               "&run periods=1 /", 53),
    'bar_ugimp_blend': ("&discretisation elements=30, shape='ugimp', transfer='blend', flip_fraction=0.9 /\n"
                        "&run periods=1 /", 29),
    'bar_cpgimp_pic_linear_law': ("&discretisation elements=30, shape='cpgimp', transfer='pic' /\n"
                                  "&material law='linear' /\n&run periods=1 /", 31),
    'bar_bspline2_xpic': ("&discretisation elements=30, shape='bspline2', transfer='xpic' /\n&run periods=1 /", 33),
    'bar_fmpm': ("&discretisation elements=30, transfer='fmpm' /\n&run periods=1 /", 27),
    'bar_asflip': ("&discretisation elements=30, transfer='asflip' /\n&run periods=1 /", 27),
    'bar_cpdi': ("&discretisation elements=30, shape='cpdi' /\n&run periods=1 /", 27),
    'bar_total_lagrangian': ("&discretisation elements=30, formulation='total' /\n&run periods=1 /", 27),
    'bar_elastoplastic': ("&discretisation elements=30 /\n&material law='elastoplastic', yield_stress=1.0e6 /\n"
                          "&run periods=1 /", 27),
    'bar_implicit_consistent': ("&discretisation elements=30, integrator='implicit', mass='consistent', "
                                "particles_per_element=2, dt_fraction=2 /\n&run periods=1 /", 7),
    'column': ("&scene kind='column' /\n&discretisation elements=30 /", 23),
    'column_quasi_static': ("&scene kind='column' /\n&discretisation elements=20, integrator='quasi_static', "
                            "load_steps=10 /", 3),
    'manufactured_ugimp': ("&scene kind='manufactured' /\n&discretisation elements=30, shape='ugimp' /", 19),
    'composite_bar': ("&scene kind='composite_bar', lengths=1.0, 1.0, youngs_moduli=16.0e6, 1.0e6, "
                      "densities=1000.0, 1000.0, drive_velocity=0.01 /\n"
                      "&discretisation elements=40, particles_per_element=2, dt_fraction=0.2 /\n&run end_time=0.01 /",
                      31),
    'impact_frictionless_fused': (IMPACT.format(contact='frictionless') +
                                  "&discretisation elements=40, particles_per_element=2, dt_fraction=0.2 /", 29),
    'impact_frictionless_generic_gimp': (IMPACT.format(contact='frictionless') +
                                         "&discretisation elements=40, particles_per_element=2, dt_fraction=0.2, "
                                         "shape='ugimp', kernels='generic' /", 29),
    'impact_none': (IMPACT.format(contact='none') +
                    "&discretisation elements=40, particles_per_element=2, dt_fraction=0.2, kernels='generic' /", 29),
    'plastic_wave': ("&scene kind='plastic_wave' /\n&discretisation elements=40 /", 37),
    'plastic_wave_implicit': ("&scene kind='plastic_wave' /\n&discretisation elements=40, integrator='implicit' /", 11),
}


def namelist(groups, out, every):
    """The run's input: its groups and &output (the file, a snapshot every `every` - 3 steps, a
    checkpoint every `every` steps)."""
    return f"{groups}\n&output file='{out}', snapshot_every={max(every - 3, 1)}, checkpoint_steps={every} /\n"


def run(exe, args, cwd, env=None, **kw):
    full = dict(os.environ, OMP_NUM_THREADS='1', LC_ALL='C')
    full.update(env or {})
    return subprocess.run([exe] + args, cwd=cwd, capture_output=True, text=True, env=full, timeout=600, **kw)


def same(x, y):
    x, y = np.asarray(x), np.asarray(y)
    if x.dtype.kind in 'OSU':
        return x.tolist() == y.tolist()
    return x.dtype == y.dtype and x.shape == y.shape and x.tobytes() == y.tobytes()


def differences(reference, path):
    """What differs between two run files: every dataset and attribute but /summary's run time."""
    bad = []
    with h5py.File(reference, 'r') as a, h5py.File(path, 'r') as b:
        names_a, names_b = [], []
        a.visit(names_a.append)
        b.visit(names_b.append)
        if sorted(names_a) != sorted(names_b):
            return [f'the objects: {sorted(set(names_a) ^ set(names_b))[:6]}']
        for name in names_a:
            for key in a[name].attrs:
                if 'run_time' in key or key == 'wall_time':
                    continue
                if key not in b[name].attrs or not same(a[name].attrs[key], b[name].attrs[key]):
                    bad.append(f'{name}@{key}')
            if isinstance(a[name], h5py.Dataset) and 'run_time' not in name:
                if not same(a[name][()], b[name][()]):
                    bad.append(name)
    return bad


def paused_run(exe, folder, args, env):
    """Start `mpm1d args` in `folder` and return it once it pauses after its checkpoint (None if it ended)."""
    marker = folder / 'mpm1d_paused'
    marker.unlink(missing_ok=True)
    full = dict(os.environ, OMP_NUM_THREADS='1', LC_ALL='C', **env)
    p = subprocess.Popen([exe] + args, cwd=folder, env=full, stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                         text=True)
    while not marker.exists():
        if p.poll() is not None:
            return p, False
        time.sleep(0.01)
    return p, True


def restart_cases(exe, only):
    print('case                          steps  checkpoint at  restart: exit  equal')
    for name, (groups, every) in CASES.items():
        if only and not re.search(only, name):
            continue
        whole, folder = SCRATCH / name / 'whole', SCRATCH / name / 'killed'
        shutil.rmtree(SCRATCH / name, ignore_errors=True)
        for f in (whole, folder):
            f.mkdir(parents=True)
            (f / 'run.nml').write_text(namelist(groups, 'run.h5', every))
        p = run(exe, ['run.nml', '-q'], whole)
        check(f'{name}: the uninterrupted run', p.returncode == 0, p.stderr[-400:])
        check(f'{name}: the uninterrupted run leaves no checkpoint', not (whole / 'run.h5.checkpoint').exists())
        if p.returncode != 0:
            continue
        p, paused = paused_run(exe, folder, ['run.nml', '-q'], {'MPM1D_PAUSE_AFTER_CHECKPOINT': '2'})
        check(f'{name}: the run pauses after its second checkpoint', paused, p.stderr.read()[-300:] if not paused else '')
        if not paused:
            continue
        p.send_signal(signal.SIGKILL)
        p.wait()
        check(f'{name}: the checkpoint is there, no output', (folder / 'run.h5.checkpoint').exists() and
              not (folder / 'run.h5').exists())
        q = run(exe, ['run.nml', '--restart'], folder)
        m = re.search(r'restarted from step (\d+)', q.stdout)
        check(f'{name}: --restart exits 0 and says where it started', q.returncode == 0 and m is not None and
              int(m.group(1)) == 2 * every, (q.stdout + q.stderr)[-400:])
        bad = differences(whole / 'run.h5', folder / 'run.h5') if q.returncode == 0 else ['no file']
        check(f'{name}: the restarted file equals the uninterrupted one', not bad, bad[:8])
        check(f'{name}: no checkpoint left', not (folder / 'run.h5.checkpoint').exists())
        with h5py.File(whole / 'run.h5', 'r') as f:
            steps = len(f['history']['time']) - 1 if 'history' in f and 'time' in f['history'] else -1
        print(f'{name:<29} {steps:5d}  {2 * every:13d}  {q.returncode:13d}  {"yes" if not bad else "NO"}')


def refusals(exe):
    """SIGTERM, then the refusals, on the bar."""
    groups, every = CASES['bar_usf_generic']
    whole, folder = SCRATCH / 'sigterm' / 'whole', SCRATCH / 'sigterm' / 'stopped'
    shutil.rmtree(SCRATCH / 'sigterm', ignore_errors=True)
    for f in (whole, folder):
        f.mkdir(parents=True)
        (f / 'run.nml').write_text(namelist(groups, 'run.h5', every))
    run(exe, ['run.nml', '-q'], whole)
    p, paused = paused_run(exe, folder, ['run.nml'], {'MPM1D_PAUSE_AFTER_CHECKPOINT': '1'})
    check('SIGTERM: the run paused', paused)
    if not paused:
        return
    p.send_signal(signal.SIGTERM)
    out, err = p.communicate()
    check('SIGTERM: exit 143, the checkpoint named, how to go on', p.returncode == 143 and
          "checkpoint 'run.h5.checkpoint'" in err and '--restart' in err and not (folder / 'run.h5').exists(),
          f'exit {p.returncode}: {err[-400:]}')
    saved = (folder / 'run.h5.checkpoint').read_bytes()
    # another input: refused naming the variable, the checkpoint left as it was
    q = run(exe, ['run.nml', 'discretisation.elements=41', '--restart'], folder)
    check('another input: refused naming the variable', q.returncode == 2 and 'discretisation.elements' in q.stderr and
          'another input' in q.stderr, q.stderr[-400:])
    check('another input: the checkpoint left as it was', (folder / 'run.h5.checkpoint').read_bytes() == saved)
    # damaged: torn, a byte changed
    for label, content in (('torn', saved[:len(saved) * 2 // 3]), ('a byte changed', saved[:200] + bytes([saved[200] ^ 1])
                                                                    + saved[201:])):
        (folder / 'run.h5.checkpoint').write_bytes(content)
        q = run(exe, ['run.nml', '--restart'], folder)
        check(f'a damaged checkpoint ({label}): refused', q.returncode == 2 and 'is damaged' in q.stderr and
              not (folder / 'run.h5').exists(), q.stderr[-400:])
        check(f'a damaged checkpoint ({label}): left as it was', (folder / 'run.h5.checkpoint').read_bytes() == content)
    (folder / 'run.h5.checkpoint').write_bytes(saved)
    q = run(exe, ['run.nml', '--restart'], folder)
    bad = differences(whole / 'run.h5', folder / 'run.h5') if q.returncode == 0 else ['no file']
    check('SIGTERM: --restart completes the run, bit for bit', q.returncode == 0 and not bad, (q.stderr[-300:], bad))
    check('SIGTERM: no checkpoint left', not (folder / 'run.h5.checkpoint').exists())
    q = run(exe, ['run.nml', '--restart'], folder)
    check('--restart without a checkpoint: refused, saying so', q.returncode == 2 and
          "there is no checkpoint 'run.h5.checkpoint'" in q.stderr, q.stderr[-300:])


def stopped_without_checkpoints(exe):
    """SIGTERM stops a long run that keeps no checkpoints after the step it is in: exit 143, that step and
    the run's steps named, the way to keep a run's state said, no file written."""
    folder = SCRATCH / 'sigterm_plain'
    shutil.rmtree(folder, ignore_errors=True)
    folder.mkdir(parents=True)
    (folder / 'run.nml').write_text("&discretisation elements=2000 /\n&run periods=20 /\n&output file='run.h5' /\n")
    p = subprocess.Popen([str(exe), 'run.nml'], cwd=folder, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    began = False
    for line in p.stdout:  # the header, flushed before the time loop: the run has begun
        if line.startswith('# usl,'):
            began = True
            break
    p.send_signal(signal.SIGTERM)
    _, err = p.communicate()
    check('SIGTERM without checkpoints: the run began', began)
    stopped = re.search(r'SIGTERM stopped the run after step (\d+) of (\d+); nothing was written '
                        r'\(&output checkpoint_steps = N', err)
    check('SIGTERM without checkpoints: exit 143, the step it reached named, checkpoint_steps said',
          p.returncode == 143 and stopped is not None and int(stopped.group(1)) < int(stopped.group(2)),
          f'exit {p.returncode}: {err[-400:]}')
    check('SIGTERM without checkpoints: no file written', sorted(q.name for q in folder.iterdir()) == ['run.nml'],
          sorted(q.name for q in folder.iterdir()))


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument('--exe')
    parser.add_argument('--only')
    args = parser.parse_args()
    exe = args.exe or find_exe()
    shutil.rmtree(SCRATCH, ignore_errors=True)
    SCRATCH.mkdir(parents=True)
    restart_cases(exe, args.only)
    if not args.only:
        refusals(exe)
        stopped_without_checkpoints(exe)
    print(f'test_restart: {TALLY.passed} passed, {TALLY.failed} failed')
    sys.exit(1 if TALLY.failed else 0)


if __name__ == '__main__':
    main()
