"""Current: a uniform flow of velocity ``v_c(t)`` and acceleration ``a_f(t)`` (world frame), paper Eqs. 2, 7.

The fluid's spatial velocity in body axes is ``[0; R^T v_c]`` (a uniform, irrotational flow), so the body's
velocity relative to the fluid is ``nu_r = nu - [0; R^T v_c]``. Every drag and added-mass term uses
``nu_r``. The fluid acceleration seen in body axes is the rate of change of ``R^T v_c``:
``d/dt (R^T v_c) = R^T a_f - omega x R^T v_c``. With these two, the motion relative to a uniformly moving
fluid is the same as in still water (Galilean invariance; tested in ``tests/hydro``).
"""

from __future__ import annotations

from uvms.jit import block


@block
def relative_velocity(nu, v_current_body, out):
    """``out = nu - [0; v_c]``: body velocity relative to the fluid, body axes, ``[angular; linear]``."""
    for k in range(3):
        out[k] = nu[k]
        out[3 + k] = nu[3 + k] - v_current_body[k]


@block
def fluid_acceleration_in_body(omega, v_current_body, a_fluid_body, out):
    """``out = [0; R^T a_f - omega x R^T v_c]``: the fluid's acceleration as seen in body axes."""
    out[0] = 0.0
    out[1] = 0.0
    out[2] = 0.0
    out[3] = a_fluid_body[0] - (omega[1] * v_current_body[2] - omega[2] * v_current_body[1])
    out[4] = a_fluid_body[1] - (omega[2] * v_current_body[0] - omega[0] * v_current_body[2])
    out[5] = a_fluid_body[2] - (omega[0] * v_current_body[1] - omega[1] * v_current_body[0])
