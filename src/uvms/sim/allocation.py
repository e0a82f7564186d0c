"""Turning a controller's wrench into held actuator commands (interim: the Python allocator of the event loop)."""

from __future__ import annotations

import numpy as np


class Commands:
    """Turns a controller's wrench into held actuator commands (allocation, thrust -> voltage).

    Fast path every update: the layout's pseudo-inverse (minimum-norm least squares); only when that violates a
    thrust limit does the saturation-aware :func:`~uvms.thrusters.allocation.allocate` run. Healey thrusters get
    the compiled steady-state inverse (thrust -> inflow -> speed -> voltage, clipped to the supply); table
    thrusters the table's inverse (:func:`~uvms.thrusters.table.table_command`, the dead band's centre at zero).
    """

    LABELS = ("K", "M", "N", "X", "Y", "Z")

    def __init__(self, thrusters: tuple):
        self.thrusters = thrusters
        self.m = len(thrusters)
        if self.m:
            from uvms.thrusters.healey import healey_voltage_for_thrust, steady_coefficients
            from uvms.thrusters.layouts import layout_matrix, thrust_limits
            from uvms.thrusters.table import table_command

            self.Lambda = layout_matrix(thrusters)
            self.pinv = np.linalg.pinv(self.Lambda)
            self.lower, self.upper = thrust_limits(thrusters)
            self.healey = [(t.parameters.as_array(), steady_coefficients(t.parameters)) if t.model == "healey"
                           else None for t in thrusters]
            self.voltage = healey_voltage_for_thrust
            self.table = [t.parameters.as_array() if t.model == "table" else None for t in thrusters]
            self.table_command = table_command
            self.names = [f"thrust_cmd_{t.name}" for t in thrusters] + [f"unachieved_{a}" for a in self.LABELS]

    def __call__(self, wrench: np.ndarray) -> tuple[np.ndarray, dict[str, float]]:
        if self.m == 0:
            return np.array(wrench, dtype=float), {}
        thrust = self.pinv @ wrench
        if np.any(thrust < self.lower) or np.any(thrust > self.upper):
            from uvms.thrusters.allocation import allocate

            thrust = allocate(self.Lambda, wrench, self.lower, self.upper).thrust
        residual = wrench - self.Lambda @ thrust
        command = np.zeros(max(self.m, 6))
        thrusts = thrust.tolist()
        for j, T in enumerate(thrusts):
            h = self.healey[j]
            if h is not None:
                command[j] = self.voltage(h[0], h[1], T)
            elif self.table[j] is not None:
                command[j] = self.table_command(self.table[j], T)
            else:
                command[j] = T
        return command, dict(zip(self.names, thrusts + residual.tolist()))
