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

# The methods of reference_methods.py against mpm1d: the bar at v0 = 50 m/s (0.01 c: particles cross cells,
# strains of 1e-2 switch ASFLIP's separation test) and at 0.1 m/s (the linear-law bar of the total-Lagrangian
# convergence), the manufactured solution at A/L = 0.05 (F from 0.69 to 1.31).
CROSSING = dict(elements=12, ppc=3, dt_fraction=0.2, periods=0.5, v0=50.0, law='hencky')
SMALL = dict(elements=20, ppc=2, dt_fraction=0.1, periods=0.5, v0=0.1, law='linear')
LARGE = dict(kind='manufactured', elements=16, ppc=2, dt_fraction=0.1, periods=0.5, length=1.0, youngs_modulus=1e7,
             density=1000.0, amplitude=0.05, law='hencky')
METHOD_CASES = (
    [dict(formulation='total', scheme=s, **SMALL) for s in ('usf', 'usl', 'musl')]
    + [dict(formulation='total', scheme='usl', transfer='pic', **CROSSING),
       dict(formulation='total', scheme='musl', **LARGE),
       dict(formulation='total', scheme='usl', transfer='xpic', xpic_order=3, **CROSSING)]
    + [dict(shape='cpdi', scheme=s, **CROSSING) for s in ('usf', 'usl', 'musl')]
    + [dict(shape='cpdi', scheme='usl', transfer='pic', **CROSSING), dict(shape='cpdi', scheme='usf', **LARGE),
       dict(shape='cpdi', scheme='usl', transfer='fmpm', fmpm_order=3, **LARGE),
       dict(shape='cpdi', formulation='total', scheme='usl', **SMALL)]
    + [dict(transfer='xpic', xpic_order=m, scheme=s, **CROSSING) for s, m in (('usf', 2), ('usl', 3), ('musl', 5))]
    + [dict(transfer='xpic', xpic_order=8, scheme='usl', **LARGE)]
    + [dict(transfer='fmpm', fmpm_order=k, scheme=s, **CROSSING) for s, k in (('usf', 2), ('usl', 4), ('musl', 3))]
    + [dict(transfer='asflip', asflip_alpha=a, scheme=s, **CROSSING) for s, a in (('usf', 0.99), ('usl', 0.5),
                                                                                   ('musl', 0.99))]
    + [dict(transfer='asflip', asflip_alpha=0.99, scheme='usl', **LARGE)])


def method_namelist(case, out):
    """The mpm1d input of a case of METHOD_CASES."""
    if case.get('kind') == 'manufactured':
        scene = (f"kind='manufactured', length={case['length']!r}, youngs_modulus={case['youngs_modulus']!r}, "
                 f"density={case['density']!r}, amplitude={case['amplitude']!r}")
    else:
        scene = f"velocity_amplitude={case['v0']!r}"
    extra = ''.join(f", {name}={case[name]!r}" for name in ('xpic_order', 'fmpm_order', 'asflip_alpha') if name in case)
    return (f"&scene {scene} /\n&material law='{case['law']}' /\n&run periods={case['periods']!r} /\n"
            f"&discretisation scheme='{case['scheme']}', elements={case['elements']}, "
            f"particles_per_element={case['ppc']}, dt_fraction={case['dt_fraction']}, "
            f"shape='{case.get('shape', 'linear')}', transfer='{case.get('transfer', 'flip')}', "
            f"formulation='{case.get('formulation', 'updated')}'{extra} /\n&output file='{out}' /\n")


def method_label(case):
    words = [case.get('formulation', 'updated'), case.get('shape', 'linear'), case.get('transfer', 'flip')]
    for name in ('xpic_order', 'fmpm_order', 'asflip_alpha'):
        if name in case:
            words[-1] += f"({case[name]:g})"
    return ' '.join(words + [case['scheme'], case.get('kind', 'bar'), case['law']])


def find_executable():
    if len(sys.argv) > 1:
        return os.path.abspath(sys.argv[1])
    root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    out = subprocess.run(['fpm', 'run', '--profile', 'release', '--target', 'mpm1d', '--runner', 'echo'], cwd=root,
                         capture_output=True, text=True, check=True).stdout.split()
    return os.path.join(root, out[-1])


def run_case(exe, nml, out):
    """mpm1d on input `nml` writing `out`: its max error, steps, u_cm history, status and lightest node."""
    subprocess.run([exe, nml], check=True, capture_output=True)
    with h5py.File(out, 'r') as h:
        return (float(h['summary/max_error'][()]), int(h['summary/steps'][()]), h['history/ucm'][:],
                h['summary/status'][()], h['summary/min_node_mass_ratio'][()])


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
            err, steps, ucm, status, lightest = run_case(exe, nml, out)
            crossed = lightest < 0.1
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
        largest = {}
        for case in METHOD_CASES:
            nml = os.path.join(tmp, 'case.nml')
            out = os.path.join(tmp, 'case.h5')
            with open(nml, 'w') as f:
                f.write(method_namelist(case, out))
            err, steps, ucm, status, _ = run_case(exe, nml, out)
            options = {name: value for name, value in case.items() if name not in ('ppc',)}
            ref = reference_methods.run(ppc=case['ppc'], **options)
            amp = ref['max_error'] / ref['relative_error']
            difference = abs(err - ref['max_error']) / ref['max_error']
            checks = {
                'steps': steps == ref['steps'],
                'status ok': status == 0,
                'max_error': difference <= 1e-9,
                'history': np.max(np.abs(ucm - ref['ucm'])) <= 1e-11 * amp,
            }
            ok = all(checks.values())
            passed += ok
            failed += not ok
            for method, used in (('total-Lagrangian', case.get('formulation') == 'total'),
                                 ('CPDI', case.get('shape') == 'cpdi'), ('XPIC', case.get('transfer') == 'xpic'),
                                 ('FMPM', case.get('transfer') == 'fmpm'), ('ASFLIP', case.get('transfer') == 'asflip')):
                if used:
                    largest[method] = max(largest.get(method, 0.0), difference)
            print(f"{'ok  ' if ok else 'FAIL'} {method_label(case)}: mpm1d {err:.12e}  reference "
                  f"{ref['max_error']:.12e}  rel. diff {difference:.1e}"
                  + ('' if ok else f"  failed: {[n for n, v in checks.items() if not v]}"))
        for method, difference in largest.items():
            print(f"     {method}: largest relative difference of max_error {difference:.1e}")
    print(f"{passed} passed, {failed} failed")
    return 1 if failed else 0


if __name__ == '__main__':
    sys.exit(main())
