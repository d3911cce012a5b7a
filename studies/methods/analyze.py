"""The methods study's summary.md and figures from the files studies/methods/run.sh wrote: the analysis is
mpm1d_post.studies.methods.  Usage: python studies/methods/analyze.py OUTPUT_FOLDER [--elapsed S] [--load L]"""
import sys

from mpm1d_post.studies.methods import main

if __name__ == '__main__':
    sys.exit(main())
