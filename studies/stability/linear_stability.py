#!/usr/bin/env python3
"""Predicted critical time-step fractions of mpm1d from the linearised one-step map.

The analysis lives in the post-processing package (``mpm1d_post.linear_stability``, also the
console script ``mpm1d-linear-stability``); this file runs it from here, as STABILITY_THEORY.md and
studies/shapes/run.sh call it. ``--help`` lists the options.
"""
import sys

from mpm1d_post.linear_stability import main

if __name__ == '__main__':
    sys.exit(main())
