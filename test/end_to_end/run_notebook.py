"""Execute a notebook as a reader would, every cell in order, on the python3 kernel of this Python (the
project's .venv: nbclient and ipykernel from studies/setup.sh), and fail on the first cell that raises.

    .venv/bin/python test/end_to_end/run_notebook.py docs/tutorial.ipynb [--timeout SECONDS] [--keep EXECUTED.ipynb]

The cells run in a scratch folder (build/test_scratch/notebook/), with MPM1D_EXE naming the checkout's
release build when it is not set (fpm build --profile release first). The notebook file itself is left
as it is (no outputs are written into it); --keep writes the executed copy. Prints each cell's wall time
and the total; exit status 0 when every cell ran, 1 when one raised (its error printed), 2 bad input.
"""
from __future__ import annotations

import argparse
import os
import subprocess
import sys
import time
from pathlib import Path

import nbformat
from nbclient import NotebookClient
from nbclient.exceptions import CellExecutionError

ROOT = Path(__file__).resolve().parents[2]


def release_build() -> str:
    """The checkout's mpm1d of fpm's release profile ('' when fpm cannot name it)."""
    out = subprocess.run(['fpm', 'run', '--profile', 'release', '--target', 'mpm1d', '--runner', 'echo'],
                         cwd=ROOT, capture_output=True, text=True)
    words = out.stdout.split()
    return str(ROOT / words[-1]) if out.returncode == 0 and words and (ROOT / words[-1]).is_file() else ''


def main(argv=None) -> int:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument('notebook')
    p.add_argument('--timeout', type=float, default=600, help='seconds one cell may take (default 600)')
    p.add_argument('--keep', help='write the executed notebook here')
    args = p.parse_args(argv)
    try:
        nb = nbformat.read(args.notebook, as_version=4)
    except (OSError, nbformat.reader.NotJSONError) as exc:
        print(f'run_notebook: {args.notebook}: {exc}', file=sys.stderr)
        return 2
    if not os.environ.get('MPM1D_EXE'):
        exe = release_build()
        if not exe:
            print('run_notebook: no mpm1d: build it (fpm build --profile release) or set MPM1D_EXE', file=sys.stderr)
            return 2
        os.environ['MPM1D_EXE'] = exe
    scratch = ROOT / 'build' / 'test_scratch' / 'notebook'
    scratch.mkdir(parents=True, exist_ok=True)
    client = NotebookClient(nb, timeout=args.timeout, kernel_name='python3',
                            resources={'metadata': {'path': str(scratch)}})
    start = time.perf_counter()
    status = 0
    with client.setup_kernel():
        for index, cell in enumerate(nb.cells):
            if cell.cell_type != 'code':
                continue
            began = time.perf_counter()
            try:
                client.execute_cell(cell, index)
            except CellExecutionError as exc:
                print(f'run_notebook: {args.notebook}: cell {index} raised:\n{exc}', file=sys.stderr)
                status = 1
                break
            first = cell.source.strip().splitlines()[0] if cell.source.strip() else ''
            print(f'cell {index:2d}: {time.perf_counter() - began:6.1f} s  {first[:70]}')
    print(f'{args.notebook}: {"every cell ran" if status == 0 else "stopped at an error"} in '
          f'{time.perf_counter() - start:.1f} s (mpm1d: {os.environ["MPM1D_EXE"]})')
    if args.keep:
        nbformat.write(nb, args.keep)
    return status


if __name__ == '__main__':
    sys.exit(main())
