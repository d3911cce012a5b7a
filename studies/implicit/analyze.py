"""The implicit study's summary.md and figures from the runs studies/implicit/run.sh wrote: the analysis is
mpm1d_post.studies.implicit.  Usage: python studies/implicit/analyze.py OUTPUT_FOLDER [--elapsed S]
[--load L] [--quick 0|1]"""
import sys

from mpm1d_post.studies.implicit import main

if __name__ == '__main__':
    sys.exit(main())
