"""``uvms plot``'s panels follow the run's frame convention: a z-down run's X-Y path is a map (east right, north
up), a z-up run's path x right and y up, and the position labels say which way z points."""

import numpy as np
import pandas as pd
from matplotlib.figure import Figure

from uvms.plots import plot_end_effector_path, plot_vehicle_position


def _table(frame):
    t = np.linspace(0.0, 1.0, 5)
    table = pd.DataFrame({"t_s": t, "x_m": 2.0 * t, "y_m": 0.0 * t, "z_m": t, "ee_x_m": 2.0 * t, "ee_y_m": t})
    table.attrs["frame"] = frame
    return table


def test_a_z_up_path_is_drawn_x_right_and_a_z_down_one_north_up():
    for frame, along in (("ned", "vertical"), ("enu", "horizontal")):
        ax = Figure().subplots()
        plot_end_effector_path(ax, _table(frame))
        vehicle = next(line for line in ax.get_lines() if line.get_label() == "vehicle centre")
        x, y = vehicle.get_data()
        moved = {"horizontal": np.ptp(x), "vertical": np.ptp(y)}          # the vehicle moves along world x only
        assert moved[along] > 1.0 and moved[{"vertical": "horizontal", "horizontal": "vertical"}[along]] == 0.0
    ax = Figure().subplots()
    plot_vehicle_position(ax, _table("enu"))
    assert [line.get_label() for line in ax.get_lines()] == ["x", "y", "z (up)"]
