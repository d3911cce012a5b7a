"""The messages the user guide quotes are the ones mpm1d prints: each quoted text (as the page has it,
line breaks aside) must be in the page and in what mpm1d prints for the input beside it."""
from __future__ import annotations

import re
import subprocess

import pytest

from conftest import ROOT

GUIDE = ROOT / 'docs' / 'user-guide.md'

#: (what the user guide quotes, the input that makes mpm1d print it, further arguments)
QUOTED = [
    ("scene: 'gravity' is not used by kind = 'vibrating_bar'; it belongs to kind column",
     "&scene gravity=9.81 /", []),
    ("material: yield_stress = 100000000 is used only with law = 'elastoplastic', not with law = 'hencky'",
     "&material yield_stress=1e8 /", []),
    ("discretisation: 'scheme' is not used by integrator = 'implicit'; it belongs to integrator explicit",
     "&discretisation integrator='implicit', scheme='usf' /", []),
    ("scene: mode = 1073741823 with periods = 2 gives an end time 1.839e-11 s, shorter than one time step "
     "dt = 2.469e-05 s; allowed: mode <= 800 (or run: periods >= 2.685e+06)",
     "&scene mode=1073741823 /", []),
    ("snapshot_times(2) = 0.5 s is after the end of the run at 4.937e-03 s",
     "&run periods=0.25 /\n&output snapshot_times=0.0, 0.5 /", []),
    ("unknown namelist group &discretization; did you mean &discretisation? known groups: &scene, &material, "
     "&discretisation, &run, &output, &guards, &sweep", "&discretization elements=3 /", []),
    ("did you mean 'usf' or 'usl'?", "&discretisation scheme='usx' /", []),
    ("it belongs to &discretisation", "&run elements=40 /", []),
    ("'length' of &scene is not swept", "&sweep length=1,2 /", []),
    ("--shard -1/2 is out of range: I = -1 must be >= 1; allowed: I/N, whole numbers with 1 <= I <= N",
     "&run periods=0.1 /", ['--shard', '-1/2']),
    ("allowed: ... gap <= 38 m at elements = 20",
     "&scene kind='impact', lengths=1.0, 1.0, youngs_moduli=200e9, 200e9, densities=7800, 7800, velocities=1, -1, "
     "gap=1e300 /", []),
    ("mpm1d: warning: the bars do not meet before the end of the run: gap = 0.01 m closing at 2 m/s first touches "
     "at t = 5e-03 s, after the end time 8e-04 s;",
     "&scene kind='impact', lengths=1.0, 1.0, youngs_moduli=1e9, 1e9, densities=1000, 1000, velocities=1, -1, "
     "gap=0.01 /\n&run end_time=8e-4 /", []),
    ("stopped by a guard at step 9 of 27 (8 steps completed)",
     "&discretisation elements=27, dt_fraction=2.0 /\n&run periods=0.5 /", []),
    ("mpm1d: guard newton_not_converged tripped at step 1 of 2 (t = 0.5 s, dt = 0.5 s): Newton's method did not "
     "converge: relative residual 7.3899e-03 after 1 linear solves (newton_tolerance = 1e-10, "
     "max_newton_iterations = 1)",
     "&scene kind='column', length=1.0, youngs_modulus=1.0e10, density=1000.0, gravity=3.0e6 /\n"
     "&discretisation integrator='quasi_static', elements=10, particles_per_element=2, load_steps=2, "
     "max_newton_iterations=1 /\n&guards max_cell_move=100 /", []),
    ("the plastic wave cannot yield: drive_velocity = 1 m/s is at or below the yield velocity "
     "yield_stress/(density c) = 6.33 m/s",
     "&scene kind='plastic_wave', length=1.0, drive_velocity=1.0 /", []),
]


def one_line(text: str) -> str:
    return re.sub(r'\s+', ' ', text)


@pytest.mark.parametrize('quoted, namelist, arguments', QUOTED, ids=[q[0][:40] for q in QUOTED])
def test_the_guide_quotes_what_mpm1d_prints(mpm1d, tmp_path, quoted, namelist, arguments):
    guide = one_line(GUIDE.read_text())
    # the page may break the quote across lines and mark code with backticks around it
    assert one_line(quoted) in guide.replace('`', ''), f'docs/user-guide.md no longer quotes: {quoted}'
    (tmp_path / 'in.nml').write_text(namelist + '\n')
    done = subprocess.run([str(mpm1d), 'in.nml', 'output.file=out.h5', *arguments], cwd=tmp_path,
                          capture_output=True, text=True)
    printed = one_line(done.stdout + done.stderr)
    assert in_order(quoted, printed), f'mpm1d prints no longer: {quoted}\nit prints: {printed[-600:]}'


def in_order(quoted: str, printed: str) -> bool:
    """Whether `printed` holds the quote, whose '...' stands for text left out: its parts in order."""
    at = 0
    for part in (p.strip() for p in one_line(quoted).split('...')):
        if not part:
            continue
        at = printed.find(part, at)
        if at < 0:
            return False
        at += len(part)
    return True
