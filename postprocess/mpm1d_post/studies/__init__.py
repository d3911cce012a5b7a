"""The analyses of the studies under ``studies/``: one module per study, each with ``main(argv=None) ->
int`` making the study's ``summary.md`` and figures from the files its ``run.sh`` wrote (the script in
the study's folder only calls it). The computations they share are the package's: ``orders``,
``pareto``, ``limits``, ``tables`` and the selection of a sweep's cases (``Sweep.where``, ``Sweep.rows``).
"""
