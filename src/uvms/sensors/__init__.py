"""Simulated sensors (``docs/sensors.md``): measurement models of true quantities, each at its own rate, with
seeded noise and a mount on the vehicle, and the Allan deviation to check an inertial record against a
datasheet. The models take the truth (:class:`~uvms.sensors.base.Truth`) as arguments, so they sit on the
physics floor; :mod:`uvms.sim.sensing` samples a run for them."""

from uvms.sensors.allan import FLICKER_FLOOR, allan_deviation
from uvms.sensors.base import Mount, Reading, SensorRecord, Truth
from uvms.sensors.dvl import Dvl
from uvms.sensors.encoders import Encoders
from uvms.sensors.imu import Imu
from uvms.sensors.noise import NoiseDensity
from uvms.sensors.pressure import PressureSensor

KINDS = {"imu": Imu, "pressure": PressureSensor, "dvl": Dvl, "encoders": Encoders}
"""The sensor kinds of a ``sensors:`` section, by name."""

__all__ = ["FLICKER_FLOOR", "KINDS", "Dvl", "Encoders", "Imu", "Mount", "NoiseDensity", "PressureSensor",
           "Reading", "SensorRecord", "Truth", "allan_deviation"]
