"""studies/batch/run.sh, run small (2 schemes x 2 meshes): every run succeeds through command-line
overrides and results.csv has one row per run with max_error and run_time."""
import csv
import os
import subprocess
import sys
import tempfile

root = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
with tempfile.TemporaryDirectory() as out:
    env = dict(os.environ, SCHEMES='usl musl', ELEMENTS='5 10', PYTHON=sys.executable)
    run = subprocess.run(['bash', os.path.join(root, 'studies', 'batch', 'run.sh'), out], env=env,
                         capture_output=True, text=True)
    failed = 0

    def check(name, ok, detail=''):
        global failed
        print(('ok   ' if ok else 'FAIL ') + name + ('' if ok else ': ' + detail))
        failed += not ok

    check('test_batch_script_exits_0', run.returncode == 0, run.stdout[-2000:] + run.stderr[-2000:])
    rows = list(csv.DictReader(open(os.path.join(out, 'results.csv')))) if run.returncode == 0 else []
    check('test_one_row_per_run', sorted((r['scheme'], r['elements']) for r in rows) ==
          [('musl', '10'), ('musl', '5'), ('usl', '10'), ('usl', '5')], str(rows))
    check('test_errors_and_times_are_numbers', all(float(r['max_error']) > 0 and float(r['run_time']) > 0
                                                    for r in rows), str(rows))
    check('test_finer_mesh_smaller_error', all(
        float(next(r for r in rows if r['scheme'] == s and r['elements'] == '10')['max_error']) <
        float(next(r for r in rows if r['scheme'] == s and r['elements'] == '5')['max_error'])
        for s in ('usl', 'musl')) if rows else False, str(rows))
    check('test_quiet_runs_print_nothing', 'max |u_cm' not in run.stdout, run.stdout[-500:])
print(f'test_batch: {"all passed" if failed == 0 else f"{failed} failed"}')
sys.exit(1 if failed else 0)
