"""Floating-base dynamics of the vehicle-manipulator system, compiled with numba.

``aba`` (forward dynamics, the articulated-body algorithm with hydrodynamics), ``rnea`` (inverse dynamics)
and ``crba`` (mass matrix) share the outward velocity pass of :mod:`uvms.dynamics.passes`, which also
evaluates every body's hydrodynamic bias. :mod:`uvms.dynamics.api` holds the labelled Python entry points.
"""
