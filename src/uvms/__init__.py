"""uvms: simulation and station-keeping control of underwater vehicle-manipulator systems.

Public API (stable names)::

    load_model(name_or_path) -> Model          State.from_euler(model, position=, euler=, nu=, q=, qd=)
    forward_dynamics(model, state, ...)        inverse_dynamics(model, state, nu_dot=, qdd=)
    mass_matrix(model, state)                  end_effector_position(model, state)
"""

from uvms.dynamics.api import Accelerations, bias_forces, forward_dynamics, inverse_dynamics, mass_matrix
from uvms.kinematics import end_effector_position, forward_kinematics
from uvms.model.model import Model
from uvms.state import State

__version__ = "0.1.0"


def load_model(name_or_path) -> Model:
    """Load a bundled model by name (``"paper"``) or a model YAML file by path."""
    from uvms.model.load import load_model as _load

    return _load(name_or_path)


__all__ = [
    "Accelerations", "Model", "State", "bias_forces", "end_effector_position", "forward_dynamics",
    "forward_kinematics", "inverse_dynamics", "load_model", "mass_matrix", "__version__",
]
