"""Result columns name the joints by the model's joint names (``q_<joint>_rad``, ``qd_<joint>_rad_s``,
``tau_<joint>_Nm``; metres for a prismatic joint), from one owner (:mod:`uvms.sim.columns`); older files with
numbered columns (``q1_rad``) still load."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest

import uvms
from uvms.sim.columns import joint_columns, joint_tokens, legacy_joint_columns, table_joints
from uvms.sim.metrics import Series
from uvms.sim.result import Result

VEHICLE = ["t_s", "x_m", "y_m", "z_m", "roll_rad", "pitch_rad", "yaw_rad", "p_rad_s", "q_rad_s", "r_rad_s",
           "u_m_s", "v_m_s", "w_m_s"]


def _result(names, types=None, K=5) -> Result:
    n = len(names)
    states = np.zeros((K, 13 + 2 * n))
    states[:, 3] = 1.0
    states[:, 13:13 + n] = np.arange(1, n + 1) * 0.1                  # q_j = 0.1 j
    states[:, 13 + n:] = np.arange(1, n + 1) * -0.01                  # qd_j = -0.01 j
    meta = {"joint_names": list(names), **({"joint_types": list(types)} if types else {})}
    return Result(time=np.linspace(0, 0.4, K), states=states, n_joints=n, end_effector=np.zeros((K, 3)),
                  joint_torques=np.tile(np.arange(1, n + 1) * 2.0, (K, 1)), metadata=meta)


def test_bundled_models_joint_names_make_the_columns():
    model = uvms.load_model("bluerov2_heavy_alpha5")
    cols = joint_columns(model.joint_names, model.joint_type)
    assert cols.q == ("q_axis_e_rad", "q_axis_d_rad", "q_axis_c_rad", "q_axis_b_rad")
    assert cols.qd[1] == "qd_axis_d_rad_s" and cols.tau[3] == "tau_axis_b_Nm"
    assert joint_columns(uvms.load_model("paper").joint_names).q == ("q_joint1_rad", "q_joint2_rad", "q_joint3_rad")


def test_prismatic_units_odd_names_and_repeats():
    cols = joint_columns(["slide", "wrist roll", "wrist,roll", "a"], ["prismatic", "revolute", "revolute", "revolute"])
    assert cols.q == ("q_slide_m", "q_wrist_roll_2_rad", "q_wrist_roll_3_rad", "q_a_rad")
    assert cols.qd[0] == "qd_slide_m_s" and cols.tau[0] == "tau_slide_N"
    assert len(set(cols.all())) == 12 and all("," not in c and " " not in c for c in cols.all())
    assert joint_tokens(["x", "x_2", "x"]) == ("x_1", "x_2", "x_3")
    assert joint_tokens(["x", "x", "x_2"]) == ("x_1", "x_2_2", "x_2")      # a made-up name never takes a real one


def test_result_columns_use_the_runs_joint_names_and_do_not_clash_with_the_pitch_rate():
    r = _result(["axis_e", "q"])                        # a joint named like the pitch rate's letter
    columns = list(r.columns())
    assert columns[:13] == VEHICLE
    assert columns[13:19] == ["q_axis_e_rad", "q_q_rad", "qd_axis_e_rad_s", "qd_q_rad_s", "tau_axis_e_Nm", "tau_q_Nm"]
    assert len(set(columns)) == len(columns)
    assert r.columns()["q_q_rad"][0] == pytest.approx(0.2) and r.columns()["q_rad_s"][0] == 0.0
    series = Series(r)
    assert series.get("q_q_rad")[0] == pytest.approx(0.2) and series.get("tau_axis_e_Nm")[0] == 2.0
    assert series.get("q2_rad")[0] == pytest.approx(0.2)                 # an older name: the second joint
    with pytest.raises(KeyError):
        series.get("q3_rad")


def test_save_and_load_round_trip_keeps_names_and_values(tmp_path):
    r = _result(["slide", "elbow"], ["prismatic", "revolute"])
    r.save(tmp_path)
    header = (tmp_path / "result.csv").read_text().splitlines()[0].split(",")
    assert "q_slide_m" in header and "qd_slide_m_s" in header and "tau_slide_N" in header and "q_elbow_rad" in header
    back = Result.load(tmp_path)
    assert back.n_joints == 2 and back.joint_names == ("slide", "elbow")
    np.testing.assert_allclose(back.q, r.q)
    np.testing.assert_allclose(back.qd, r.qd)
    np.testing.assert_allclose(back.joint_torques, r.joint_torques)
    assert back.signals == {} and list(back.columns()) == list(r.columns())


def test_an_older_file_with_numbered_columns_still_loads(tmp_path):
    r = _result(["a", "b", "c"])
    r.save(tmp_path)
    table = pd.read_csv(tmp_path / "result.csv")
    old = legacy_joint_columns(3)
    table = table.rename(columns=dict(zip(r.joint_columns().all(), old.all())))
    table.to_csv(tmp_path / "result.csv", index=False)
    (tmp_path / "result.json").write_text('{"complete": true, "message": "", "metadata": {}}')
    assert table_joints(table.columns)[1] == old
    back = Result.load(tmp_path)
    assert back.n_joints == 3 and back.joint_names == ("joint1", "joint2", "joint3") and back.signals == {}
    np.testing.assert_allclose(back.q, r.q)
    np.testing.assert_allclose(back.joint_torques, r.joint_torques)


def test_a_run_names_its_columns_by_the_models_joints():
    model = uvms.load_model("bluerov2_heavy_alpha5")
    result = uvms.simulate(model, duration=0.004, step=1e-3)
    assert result.joint_names == model.joint_names
    columns = list(result.to_dataframe().columns)
    assert columns[:13] == VEHICLE                                  # q_rad_s among them: the pitch rate
    assert columns[13:25] == [
        *(f"q_{j}_rad" for j in model.joint_names), *(f"qd_{j}_rad_s" for j in model.joint_names),
        *(f"tau_{j}_Nm" for j in model.joint_names)]
    assert "q1_rad" not in columns and "q_rad_s" in columns
