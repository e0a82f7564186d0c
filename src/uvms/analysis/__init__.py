"""Analyses of a model at rest: its trim and levelling ballast (:mod:`uvms.analysis.trim`, ``uvms trim``) and the
report of ``uvms validate`` (:mod:`uvms.analysis.report`).

A floor of its own, above the dynamics and the controllers it evaluates and below the simulation that uses it
(a trimmed initial state): the model floor imports neither.
"""
