"""``smc-ne``'s simulated IMU, which lives in the sensors room: :mod:`uvms.sensors.body_acceleration` (this
module re-exports it for the code that imported it from here)."""

from uvms.sensors.body_acceleration import (ACCELERATION, FINITE_DIFFERENCE, ImuData, ImuParameters, SimulatedImu,
                                            imu_data, imu_measure)

__all__ = ["ACCELERATION", "FINITE_DIFFERENCE", "ImuData", "ImuParameters", "SimulatedImu", "imu_data", "imu_measure"]
