"""Thesis case comparisons: each case runs the DEM damage model (and, where the thesis did, the
conventional DEM and a continuum reference), and writes ``results/<case>/`` with a summary JSON,
CSV curves, PNG figures and a markdown report. Run ``python -m comparisons list``.
"""
