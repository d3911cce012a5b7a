"""The scenes study's summary.md and figures from the files studies/scenes/run.sh wrote: the analysis is
mpm1d_post.studies.scenes (``--help`` lists the arguments)."""
import sys

from mpm1d_post.studies.scenes import main

if __name__ == '__main__':
    sys.exit(main())
