"""Cross-check mpm1d against the independent NumPy implementations in reference_mpm.py (the paper's bar)
and reference_methods.py (total-Lagrangian MPM, CPDI, XPIC, FMPM, ASFLIP).

First checks each method of reference_methods.py on its own (its self_checks: facts it must satisfy).
Then runs the mpm1d executable on cases of the paper's study (both schemes, and MUSL) and compares the
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

import reference_methods  # noqa: E402  (found next to this script: Python puts the script's folder first)
import reference_mpm  # noqa: E402

CASES = [  # scheme, elements, particles per element, dt fraction
    ('usf', 20, 1, 0.10), ('usl', 20, 1, 0.10), ('usf', 1, 1, 0.05), ('usl', 1, 10, 0.50),
    ('usf', 3, 4, 0.15), ('usl', 7, 3, 0.35), ('usf', 10, 10, 0.05), ('usl', 10, 7, 0.45),
    ('usf', 50, 2, 0.25), ('usl', 50, 5, 0.20), ('musl', 10, 3, 0.30), ('musl', 20, 1, 0.10),
]
# Large motion on the grid domain with its margin: the free end moves v0/omega = 0.25 dx (the
# geometry of the paper's bar on 20000 elements x 4 particles), so the last particle crosses x = L
# into the empty margin cell and back; 0.3 periods.
MOVING_END = [('usf', 200, 4, 0.5), ('musl', 200, 4, 0.5)]
MOVING_END_V0, MOVING_END_PERIODS = 10.0, 0.3


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
    for name, ok, detail in reference_methods.self_checks():
        passed += ok
        failed += not ok
        print(f"{'ok  ' if ok else 'FAIL'} reference: {name}: {detail}")
    with tempfile.TemporaryDirectory() as tmp:
        cases = [(c, 0.1, 2.0) for c in CASES] + [(c, MOVING_END_V0, MOVING_END_PERIODS) for c in MOVING_END]
        for (scheme, ne, ppc, k), v0, periods in cases:
            nml = os.path.join(tmp, 'case.nml')
            out = os.path.join(tmp, 'case.h5')
            with open(nml, 'w') as f:
                f.write(f"&scene velocity_amplitude={v0!r} /\n&run periods={periods!r} /\n"
                        f"&discretisation scheme='{scheme}', elements={ne}, particles_per_element={ppc}, "
                        f"dt_fraction={k} /\n&output file='{out}' /\n")
            subprocess.run([exe, nml], check=True, capture_output=True)
            with h5py.File(out, 'r') as h:
                err = float(h['summary/max_error'][()])
                steps = int(h['summary/steps'][()])
                ucm = h['history/ucm'][:]
                status = h['summary/status'][()]
                crossed = h['summary/min_node_mass_ratio'][()] < 0.1
            ref = reference_mpm.run(scheme, ne, ppc, k, periods=periods, v0=v0)
            amp = ref['max_error'] / ref['relative_error']
            checks = {
                'steps': steps == ref['steps'],
                'status ok': status == 0,
                'a particle entered the margin (a node lighter than 0.1 particle)': crossed or v0 == 0.1,
                'max_error': abs(err - ref['max_error']) <= 1e-9 * ref['max_error'] + 1e-12 * amp,
                'history': np.max(np.abs(ucm - ref['ucm'])) <= 1e-11 * amp,
            }
            ok = all(checks.values())
            passed += ok
            failed += not ok
            print(f"{'ok  ' if ok else 'FAIL'} {scheme:4s} {ne:3d} el {ppc:2d} ppc {k:.2f} v0 {v0:g}: "
                  f"mpm1d {err:.12e}  reference {ref['max_error']:.12e}  "
                  f"rel. diff {abs(err - ref['max_error']) / ref['max_error']:.1e}"
                  + ('' if ok else f"  failed: {[n for n, v in checks.items() if not v]}"))
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
