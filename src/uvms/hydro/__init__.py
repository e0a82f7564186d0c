"""Hydrodynamic effects (paper Section 2.1), one module each: added mass, drag, buoyancy, current."""
