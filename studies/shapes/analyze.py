"""The shapes study's summary.md and figures from the files studies/shapes/run.sh wrote: the analysis is
mpm1d_post.studies.shapes.  Usage: python studies/shapes/analyze.py OUTPUT_FOLDER"""
import sys

from mpm1d_post.studies.shapes import main

if __name__ == '__main__':
    sys.exit(main())
