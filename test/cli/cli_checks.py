"""What the command-line test scripts share: the checks' tally and the path of the release build."""
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


class Tally:
    """Checks counted; a failed one printed with its name and what was found."""

    def __init__(self):
        self.passed = self.failed = 0

    def check(self, name, ok, detail=''):
        if ok:
            self.passed += 1
        else:
            self.failed += 1
            print(f'FAIL {name}' + (f': {detail}' if detail else ''))


def find_exe():
    """The release build's mpm1d (built by fpm if it is not up to date)."""
    out = subprocess.run(['fpm', 'run', '--profile', 'release', '--target', 'mpm1d', '--runner', 'echo'],
                         cwd=ROOT, capture_output=True, text=True, check=True).stdout.strip().splitlines()
    return str(ROOT / out[-1])
