"""Cross-check mpm1d against the independent NumPy implementation in reference_mpm.py.

Runs the mpm1d executable on cases of the paper's study (both schemes, and MUSL) and compares the
max centre-of-mass error, the step count and the whole u_cm history to the reference. Agreement
must be at round-off level: the two codes sum in different orders, nothing more.
Usage: python3 test/reference/check_reference.py [path/to/mpm1d]
"""
import os
import subprocess
import sys
import tempfile

import h5py
import numpy as np

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import reference_mpm  # noqa: E402

CASES = [  # scheme, elements, particles per element, dt fraction
    ('usf', 20, 1, 0.10), ('usl', 20, 1, 0.10), ('usf', 1, 1, 0.05), ('usl', 1, 10, 0.50),
    ('usf', 3, 4, 0.15), ('usl', 7, 3, 0.35), ('usf', 10, 10, 0.05), ('usl', 10, 7, 0.45),
    ('usf', 50, 2, 0.25), ('usl', 50, 5, 0.20), ('musl', 10, 3, 0.30), ('musl', 20, 1, 0.10),
]


def find_executable():
    if len(sys.argv) > 1:
        return os.path.abspath(sys.argv[1])
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    out = subprocess.run(['fpm', 'run', '--profile', 'release', '--target', 'mpm1d', '--runner', 'echo'], cwd=root,
                         capture_output=True, text=True, check=True).stdout.split()
    return os.path.join(root, out[-1])


def main():
    exe = find_executable()
    passed = failed = 0
    with tempfile.TemporaryDirectory() as tmp:
        for scheme, ne, ppc, k in CASES:
            nml = os.path.join(tmp, 'case.nml')
            out = os.path.join(tmp, 'case.h5')
            with open(nml, 'w') as f:
                f.write(f"&discretisation scheme='{scheme}', elements={ne}, particles_per_element={ppc}, "
                        f"dt_fraction={k} /\n&output file='{out}' /\n")
            subprocess.run([exe, nml], check=True, capture_output=True)
            with h5py.File(out, 'r') as h:
                err = float(h['summary/max_error'][()])
                steps = int(h['summary/steps'][()])
                ucm = h['history/ucm'][:]
            ref = reference_mpm.run(scheme, ne, ppc, k)
            amp = ref['max_error'] / ref['relative_error']
            checks = {
                'steps': steps == ref['steps'],
                'max_error': abs(err - ref['max_error']) <= 1e-9 * ref['max_error'] + 1e-12 * amp,
                'history': np.max(np.abs(ucm - ref['ucm'])) <= 1e-11 * amp,
            }
            ok = all(checks.values())
            passed += ok
            failed += not ok
            print(f"{'ok  ' if ok else 'FAIL'} {scheme:4s} {ne:3d} el {ppc:2d} ppc {k:.2f}: "
                  f"mpm1d {err:.12e}  reference {ref['max_error']:.12e}  "
                  f"rel. diff {abs(err - ref['max_error']) / ref['max_error']:.1e}"
                  + ('' if ok else f"  failed: {[n for n, v in checks.items() if not v]}"))
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
