"""The numberings of the compiled controllers: one place for the ints their kernels switch on.

Vehicle controllers (:attr:`uvms.control.kernels.ControllerData.kind`, dispatched by
:func:`uvms.control.kernels.controller_update`)::

    NONE     no controller (never updated: :func:`uvms.control.kernels.no_controller`)
    SLIDING  the sliding-mode law (smc-ab, smc-vehicle, smc-ne; :mod:`uvms.control.smc`)
    PID      the PID baseline (:mod:`uvms.control.pid`)

Models of the vehicle's acceleration of the sliding-mode law (``ControllerData.predictor``, dispatched by
``uvms.control.kernels._predict``)::

    AB       smc-ab       articulated-body algorithm of the whole system (Eqs. 13-25)
    VEHICLE  smc-vehicle  the vehicle body alone
    NE       smc-ne       the vehicle alone plus the arm's Newton-Euler reaction at an IMU-measured acceleration

Joint-torque sources (:attr:`uvms.control.arm.ArmData.kind`, dispatched by :func:`uvms.control.arm.arm_torques`)::

    CONSTANT         constant torques (:func:`uvms.control.arm.constant_arm`)
    SCHEDULE         piecewise-constant torques (:func:`uvms.control.arm.schedule_arm`)
    COMPUTED_TORQUE  the computed-torque tracker (:class:`uvms.control.arm.ComputedTorqueArm`)
    PD               the PD tracker (:class:`uvms.control.arm.PdArm`)

The compiled kernels (:mod:`uvms.jit`) freeze these numbers into their machine code, so this file keys the
kernel cache (:mod:`uvms._cache`).
"""

from __future__ import annotations

NONE, SLIDING, PID = 0, 1, 2
"""Vehicle controller kinds."""
AB, VEHICLE, NE = 0, 1, 2
"""Sliding-mode predictors (how ``f_hat`` is computed)."""
CONSTANT, SCHEDULE, COMPUTED_TORQUE, PD = 0, 1, 2, 3
"""Joint-torque source kinds."""
