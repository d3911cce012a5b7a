"""The harness of the studies' pipeline tests (studies/*/test_*_study.py): run a study's ``run.sh``
in its quick mode (``MPM1D_QUICK=1``) into a fresh temporary folder, and tally named checks that
print ``ok``/``FAIL`` lines; each test ends with ``N passed, M failed``."""
from __future__ import annotations

import os
import subprocess
import tempfile
from pathlib import Path
from typing import List, Tuple


class Checks:
    """Named checks, printed as they are made; ``results`` holds one bool per check."""

    def __init__(self) -> None:
        self.results: List[bool] = []

    def __call__(self, name: str, ok: object, detail: str = '') -> None:
        self.results.append(bool(ok))
        print(f"{'ok  ' if ok else 'FAIL'} {name}" + (f': {detail}' if detail and not ok else ''))


def run_quick(study: 'str | os.PathLike', prefix: str,
              timeout: float = 900) -> Tuple[str, subprocess.CompletedProcess]:
    """Run ``<study>/run.sh <out>`` with MPM1D_QUICK=1 from the repository's root (two folders up);
    returns the output folder and the finished process (stdout and stderr captured as text)."""
    study = Path(study).resolve()
    out = tempfile.mkdtemp(prefix=prefix)
    proc = subprocess.run(['bash', str(study / 'run.sh'), out], cwd=study.parent.parent,
                          env=dict(os.environ, MPM1D_QUICK='1'), capture_output=True, text=True, timeout=timeout)
    return out, proc
