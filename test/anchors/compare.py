"""Compare two folders of regression-anchor outputs (test/anchors/run.sh) dataset by dataset.

Every dataset of every HDF5 file in OLD is compared with the same dataset in NEW: bit for bit
(NaN equal to NaN), else the largest absolute and relative difference is printed. Timing datasets
(run times, repeats, timing rounds) and the /config group are skipped: they change from run to run
or with the parameter registry. A dataset present on one side only is listed, not counted as a
difference (new columns appear as features land). Exit status 0 when every common dataset is
bit-identical, 1 otherwise; with --tolerance R, differences up to R relative also pass.

    .venv/bin/python test/anchors/compare.py OLD_DIR NEW_DIR [--tolerance 1e-12]
"""
from __future__ import annotations

import argparse
import pathlib
import sys

import h5py
import numpy as np

SKIPPED = {"run_time", "run_time_spread", "repeats", "timing_rounds", "timed"}


def datasets(path: pathlib.Path) -> dict[str, np.ndarray]:
    found: dict[str, np.ndarray] = {}
    with h5py.File(path, "r") as f:
        def visit(name, obj):
            if not isinstance(obj, h5py.Dataset) or name.startswith("config"):
                return
            if name.rsplit("/", 1)[-1] in SKIPPED:
                return
            data = obj[()]
            if obj.dtype.kind in "OSU":
                data = np.asarray(obj.asstr()[()], dtype=object)
            found[name] = np.asarray(data)
        f.visititems(visit)
    return found


def stopped_rows(sets: dict[str, np.ndarray], group: str) -> np.ndarray | None:
    status = sets.get(f"{group}/status_name")
    if status is None:
        return None
    return np.array([str(s) != "ok" for s in np.atleast_1d(status)])


def compare(a: np.ndarray, b: np.ndarray) -> tuple[bool, str]:
    if a.shape != b.shape:
        return False, f"shape {a.shape} -> {b.shape}"
    if a.dtype.kind == "O" or b.dtype.kind == "O":
        same = np.array_equal(a.astype(str), b.astype(str))
        return same, "" if same else "strings differ"
    if a.dtype.kind in "iub" and b.dtype.kind in "iub":
        same = np.array_equal(a, b)
        return same, "" if same else f"{int(np.sum(a != b))} integers differ"
    fa, fb = a.astype(np.float64), b.astype(np.float64)
    same_bits = np.array_equal(fa.view(np.uint64), fb.view(np.uint64)) or np.array_equal(fa, fb, equal_nan=True)
    if same_bits:
        return True, ""
    both = np.isfinite(fa) & np.isfinite(fb)
    nan_moved = int(np.sum(np.isnan(fa) != np.isnan(fb)))
    diff = np.abs(fa[both] - fb[both])
    scale = np.maximum(np.abs(fa[both]), np.abs(fb[both]))
    rel = np.where(scale > 0, diff / np.where(scale > 0, scale, 1), 0)
    return False, (f"{int(np.sum(fa[both] != fb[both]))} of {fa.size} differ, max abs {diff.max(initial=0):.3e}, "
                   f"max rel {rel.max(initial=0):.3e}" + (f", NaN in {nan_moved} places on one side only" if nan_moved else ""))


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("old", type=pathlib.Path)
    parser.add_argument("new", type=pathlib.Path)
    parser.add_argument("--tolerance", type=float, default=0.0, help="relative difference accepted")
    parser.add_argument("--quiet", action="store_true", help="print differences only")
    args = parser.parse_args(argv)
    files = sorted(p.name for p in args.old.glob("*.h5"))
    if not files:
        print(f"no .h5 files in {args.old}")
        return 2
    failures = identical = within = 0
    for name in files:
        other = args.new / name
        if not other.exists():
            print(f"{name}: missing in {args.new}")
            failures += 1
            continue
        a, b = datasets(args.old / name), datasets(other)
        # A stopped case's error moved to its own column (error_before_stop; max_error is NaN).
        for group in ("cases", "summary"):
            rows = stopped_rows(b, group)
            if (rows is not None and f"{group}/error_before_stop" in b and f"{group}/max_error" in a
                    and f"{group}/error_before_stop" not in a):  # (old from before that column)
                for col, moved in (("max_error", "error_before_stop"), ("relative_error", "relative_error_before_stop")):
                    if f"{group}/{moved}" not in b or f"{group}/{col}" not in a:
                        continue
                    old = np.atleast_1d(a[f"{group}/{col}"]).astype(float).copy()
                    new = np.atleast_1d(b[f"{group}/{moved}"]).astype(float)
                    if old.shape == new.shape == rows.shape:  # stopped rows from old, the others as new has them
                        a[f"{group}/{moved}"] = np.where(rows, old, new).reshape(np.shape(b[f"{group}/{moved}"]))
                    old[rows] = np.nan
                    a[f"{group}/{col}"] = old.reshape(np.shape(a[f"{group}/{col}"]))
        for key in sorted(set(a) | set(b)):
            if key not in b:
                print(f"{name}:{key}: only in old")
                continue
            if key not in a:
                if not args.quiet:
                    print(f"{name}:{key}: only in new")
                continue
            same, how = compare(a[key], b[key])
            if same:
                identical += 1
                continue
            ok = False
            if args.tolerance > 0 and "max rel" in how and "NaN" not in how:
                ok = float(how.rsplit("max rel ", 1)[1]) <= args.tolerance
            within += ok
            failures += not ok
            print(f"{name}:{key}: {'within tolerance' if ok else 'DIFFERS'}: {how}")
    print(f"{len(files)} files: {identical} datasets bit-identical, {within} within tolerance, {failures} differ")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
