"""An animation of one mpm1d run: a particle field moving through the run, the exact profile beside it.

    mpm1d-animate RUN.h5 -o FILE.gif|FILE.mp4 [--field stress|velocity|displacement] [--fps N]

One frame per snapshot of the file (a run keeps evenly spaced ones with ``&output snapshot_every =
N``: a snapshot every N steps): every particle's value of the field at its position x, coloured by
body where the scene has several (the impact's bars), the scene's exact profile in black where the file
has it (``exact_<field>``, docs/output.md), and the time and step in the frame. The axes are the same in
every frame (the grid domain; the field's range over the run). The title names the scene, scheme, shape,
transfer, law and mesh from ``/config``. A run a guard stopped is drawn in grey and says so.

GIF through Pillow (matplotlib's PillowWriter); MP4 through ffmpeg where it is installed (else the
command says so and exits 2). Exit status 0 written, 2 bad input (a file with fewer than two snapshots,
another suffix, ffmpeg missing for .mp4), 3 the file could not be written (it is written under a
temporary name and renamed when complete: a full disk leaves an older file of that name as it was).
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path
from typing import Optional, Sequence, Tuple

import numpy as np

from . import figures
import matplotlib.animation as animation  # (after figures, which selects the Agg backend)
import matplotlib.pyplot as plt
from .loader import Mpm1dFileError, Run, load_run
from .output_files import replacing_path, with_output_errors
from .plot_run import FIELDS, draw_field, field_values, moment_text, result_text, run_title, time_label

PROGRAM = 'mpm1d-animate'
SUFFIXES = ('.gif', '.mp4')


class AnimationError(ValueError):
    """The file cannot be animated as asked; the message says why and what to do."""


def field_range(run: Run, field: str) -> Tuple[float, float]:
    """The smallest and largest value of `field` over every snapshot, particles and exact profile,
    widened by 5 % (and to a unit range about a field that is zero throughout)."""
    low, high = np.inf, -np.inf
    for snapshot in run.snapshots:
        _, values, exact = field_values(snapshot, field)
        parts = [values] + ([exact[1]] if exact is not None else [])
        for part in parts:
            finite = part[np.isfinite(part)]
            if finite.size:
                low, high = min(low, finite.min()), max(high, finite.max())
    if not np.isfinite(low):
        return -1.0, 1.0
    if high == low:
        pad = abs(high) if high != 0 else 1.0
        return low - pad, high + pad
    pad = 0.05 * (high - low)
    return low - pad, high + pad


def animate(run: Run, output: 'str | Path', field: str = 'stress', fps: float = 10.0) -> int:
    """Write the animation of `run`'s `field` to `output` (.gif or .mp4); returns the frames written."""
    output = Path(output)
    if field not in FIELDS:
        raise AnimationError(f"--field {field}; allowed: {', '.join(FIELDS)}")
    if output.suffix.lower() not in SUFFIXES:
        raise AnimationError(f"-o {output}: allowed: a file name ending in {' or '.join(SUFFIXES)}")
    if len(run.snapshots) < 2:
        raise AnimationError(f'{run.path} has {len(run.snapshots)} snapshot{"s" if len(run.snapshots) != 1 else ""}; '
                             'an animation needs at least 2 (one frame per snapshot): run it with &output '
                             'snapshot_every=N (a snapshot every N steps)')
    if fps <= 0:
        raise AnimationError(f'--fps {fps:g}; allowed: > 0')
    if output.suffix.lower() == '.mp4':
        if not animation.writers.is_available('ffmpeg'):
            raise AnimationError(f'-o {output}: writing MP4 needs ffmpeg, which is not installed here; '
                                 'write a .gif (Pillow) instead')
        writer = animation.FFMpegWriter(fps=fps)
    else:
        writer = animation.PillowWriter(fps=fps)
    grid = np.concatenate([s.grid_x for s in run.snapshots])
    fig, ax = plt.subplots(figsize=(8, 4.8))
    figures.fitted_title(fig, f"{FIELDS[field][0].split(' (')[0]} over the run ({len(run.snapshots)} snapshots)\n"
                              f'{run_title(run)}\n{result_text(run)}', fontsize=8)
    fig.text(0.005, 0.004, figures.provenance([run]), fontsize=6.5, color='0.35', ha='left', va='bottom')
    # the artists once (the first snapshot's), then each frame only sets their data
    draw_field(ax, run, run.snapshots[0], field, legend=True)
    particles = [line for line in ax.lines if line.get_label() != 'exact']
    exact = next((line for line in ax.lines if line.get_label() == 'exact'), None)
    ax.set_xlim(float(grid.min()), float(grid.max()))
    ax.set_ylim(*field_range(run, field))
    ax.set_xlabel('particle position x (m)')
    ax.set_ylabel(FIELDS[field][0])
    ax.grid(True, alpha=0.3)
    moment = ax.set_title(moment_text(run, run.snapshots[0]), fontsize=9, loc='left')
    fig.tight_layout(rect=(0, 0.03, 1, 1))
    body = run.snapshots[0].extra.get('body')
    bodies = np.unique(body) if body is not None and np.unique(body).size > 1 else None
    output.parent.mkdir(parents=True, exist_ok=True)
    with replacing_path(output) as temporary, writer.saving(fig, str(temporary), dpi=100):
        for snapshot in run.snapshots:
            x, values, profile = field_values(snapshot, field)
            if bodies is None:
                particles[0].set_data(x, values)
            else:
                for line, b in zip(particles, bodies):
                    mine = np.asarray(snapshot.extra['body']) == b
                    line.set_data(x[mine], values[mine])
            if exact is not None and profile is not None:
                exact.set_data(*profile)
            moment.set_text(moment_text(run, snapshot))
            writer.grab_frame()
    plt.close(fig)
    return len(run.snapshots)


def build_parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog=PROGRAM, description=__doc__.split('\n\n')[0])
    p.add_argument('run', help='the HDF5 file of one run with snapshots (mpm1d RUN.nml)')
    p.add_argument('-o', '--output', required=True, help='the animation to write: FILE.gif or FILE.mp4')
    p.add_argument('--field', default='stress', choices=list(FIELDS), help='the particle field shown (default stress)')
    p.add_argument('--fps', type=float, default=10.0, help='frames per second (default 10)')
    return p


def _main(argv: Optional[Sequence[str]] = None) -> int:
    args = build_parser().parse_args(argv)
    try:
        run = load_run(args.run)
        frames = animate(run, args.output, args.field, args.fps)
    except (Mpm1dFileError, AnimationError) as exc:
        print(f'{PROGRAM}: {exc}', file=sys.stderr)
        return 2
    size = Path(args.output).stat().st_size
    print(f'{PROGRAM}: wrote {args.output}: {frames} frames ({args.field}), {size / 1024:.0f} KiB; '
          f'{time_label(run).split(" (")[0]} from {run.snapshots[0].time:.4g} to {run.snapshots[-1].time:.4g}')
    return 0



def main(argv: Optional[Sequence[str]] = None) -> int:
    """Command-line entry point; returns the exit status (3: the file could not be written)."""
    return with_output_errors(PROGRAM, _main, argv)


if __name__ == '__main__':
    sys.exit(main())
