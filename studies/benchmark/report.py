"""The benchmark's summary.md and benchmark.png from the CSV files studies/benchmark/run.sh wrote: the
analysis is mpm1d_post.studies.benchmark.  Usage: python studies/benchmark/report.py OUTDIR"""
import sys

from mpm1d_post.studies.benchmark import main

if __name__ == '__main__':
    sys.exit(main())
