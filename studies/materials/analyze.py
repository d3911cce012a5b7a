"""The materials study's summary.md and figures from the files studies/materials/run.sh wrote: the
analysis is mpm1d_post.studies.materials.  Usage: python studies/materials/analyze.py OUT_FOLDER"""
import sys

from mpm1d_post.studies.materials import main

if __name__ == '__main__':
    sys.exit(main())
