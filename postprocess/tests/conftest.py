"""Fixtures shared by the post-processing tests."""
from __future__ import annotations

import subprocess
from pathlib import Path

import pytest

#: The repository's root (this file is postprocess/tests/conftest.py).
ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope='session')
def mpm1d() -> Path:
    """The mpm1d executable of fpm's release build (the tests that run mpm1d are skipped, with the
    reason, where fpm cannot give it)."""
    try:
        out = subprocess.run(['fpm', 'run', '--profile', 'release', '--target', 'mpm1d', '--runner', 'echo'],
                             cwd=ROOT, capture_output=True, text=True, check=True).stdout.split()
    except (OSError, subprocess.CalledProcessError) as exc:
        pytest.skip(f'mpm1d not built ({exc})')
    exe = ROOT / out[-1] if out else None
    if exe is None or not exe.is_file():
        pytest.skip('mpm1d not built (fpm build --profile release)')
    return exe
