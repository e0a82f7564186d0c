"""The bundled Hinsdale 2023 trials (src/uvms/data/hinsdale_2023) against their index and, when a copy of the source
repository is at hand (``UVMS_HINSDALE_SOURCE`` or the default mirror path), against the original rows."""

from __future__ import annotations

import io
import os
import subprocess
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
import yaml

ROOT = Path(__file__).resolve().parents[2]
BUNDLE = ROOT / "src" / "uvms" / "data" / "hinsdale_2023"
COMMIT = "18d9b2f5e9b687c535b6d69f70860fe6a9fff270"
MIRROR = Path(os.environ.get("UVMS_HINSDALE_SOURCE", "/work/.mirror/hkolano+UVMS-SysID-with-EAs/repo"))


@pytest.fixture(scope="module")
def index() -> dict:
    return yaml.safe_load((BUNDLE / "trials.yaml").read_text(encoding="utf-8"))


def _csv(rel: str) -> pd.DataFrame:
    return pd.read_csv(BUNDLE / rel)


def test_the_index_lists_every_trial_once_with_its_role(index):
    roles = [t["role"] for t in index["trials"]]
    assert (roles.count("fit"), roles.count("held_out"), roles.count("baseline")) == (44, 13, 3)
    names = [t["name"] for t in index["trials"]]
    assert len(set(names)) == len(names)
    assert {n for n, r in zip(names, roles) if r == "held_out"} == {
        f"traj_alt_{c}" for c in "001-0 001-1 001-2 002-0 002-1 008-0 008-1 008-2 009-0 009-1 011-0 011-1 011-2".split()}
    assert all(n.startswith("traj0") for n, r in zip(names, roles) if r == "fit")
    assert sum(t["role"] == "held_out" and "authors_sim" in t for t in index["trials"]) == 13


def test_the_files_match_the_index_rows_spans_and_are_time_ordered(index):
    for trial in index["trials"]:
        streams = dict(trial["streams"])
        if "authors_sim" in trial:
            streams["sim"] = trial["authors_sim"]
        for kind, info in streams.items():
            df = _csv(info["file"])
            t = df["time_secs"].to_numpy()
            assert len(df) == info["rows"], (trial["name"], kind)
            assert t[0] == pytest.approx(info["t0"], abs=1e-9) and t[-1] == pytest.approx(info["t1"], abs=1e-9)
            assert np.all(np.diff(t) > 0), (trial["name"], kind)
            assert not df.isna().any().any(), (trial["name"], kind)


def test_the_replay_window_lies_inside_every_stream(index):
    for trial in index["trials"]:
        start, end = trial["start"], trial["start"] + trial["duration"]
        assert trial["duration"] > 5
        for info in trial["streams"].values():
            assert info["t0"] <= start and end <= info["t1"] + 1e-9, trial["name"]


def test_quaternions_are_unit(index):
    for trial in index["trials"]:
        for kind in ("mocap", "imu"):
            q = _csv(trial["streams"][kind]["file"])[["x_ori", "y_ori", "z_ori", "w_ori"]].to_numpy()
            assert np.abs(np.linalg.norm(q, axis=1) - 1).max() < 5e-5, (trial["name"], kind)


def test_each_log_description_names_its_files_columns_and_window(index):
    for trial in index["trials"]:
        name = trial["name"]
        log = yaml.safe_load((BUNDLE / name / f"{name}.yaml").read_text(encoding="utf-8"))
        assert (log["start"], log["duration"], log["frame"]) == (trial["start"], trial["duration"], "enu")
        assert log["joints"]["columns"] == {"base": "axis_e_pos", "shoulder": "axis_d_pos",
                                            "elbow": "axis_c_pos", "wrist": "axis_b_pos"}
        assert log["joints"]["offset"] == {"base": -3.07, "wrist": -2.879}
        for key in ("pose", "joints", "imu"):
            df = pd.read_csv(BUNDLE / name / log[key]["file"], nrows=1)
            named = [log[key]["time"]]
            for field in ("position", "quaternion_xyzw", "angular_velocity", "linear_acceleration"):
                named += log[key].get(field, [])
            named += list(log[key].get("columns", {}).values())
            assert set(named) <= set(df.columns), (name, key)


def test_the_licence_is_the_sources_mit_notice():
    text = (BUNDLE / "LICENSE").read_text(encoding="utf-8")
    assert text.startswith("MIT License") and "Copyright (c) 2023 Hannah Kolano" in text
    assert "The above copyright notice and this permission notice shall be included in all" in text
    assert (BUNDLE / "SOURCE.md").is_file()


def test_the_bundle_stays_small():
    total = sum(p.stat().st_size for p in BUNDLE.rglob("*") if p.is_file())
    assert total < 6.5e6


# -- against the source repository (skipped without it) -------------------------------------------------------

def _source():
    if not MIRROR.exists():
        pytest.skip(f"no copy of hkolano/UVMS-SysID-with-EAs at {MIRROR}")
    if (MIRROR / "data").is_dir():
        return lambda rel: (MIRROR / rel).read_bytes()
    return lambda rel: subprocess.run(["git", "-C", str(MIRROR), "show", f"{COMMIT}:{rel}"],
                                      capture_output=True, check=True).stdout


def _decimals(series: pd.Series) -> int:
    return max((len(s.split(".")[1]) if "." in s else 0) for s in series.astype(str))


def test_the_kept_rows_are_the_original_rows_rounded(index):
    read = _source()
    assert (BUNDLE / "LICENSE").read_bytes() == read("LICENSE")
    for trial in index["trials"]:
        pairs = [(info["file"], f"data/hinsdale-data-2023/{info['source']['file']}") for info in trial["streams"].values()]
        if "authors_sim" in trial:
            pairs.append((trial["authors_sim"]["file"], f"data/sim_trajs/{trial['authors_sim']['source']['file']}"))
        for rel, original in pairs:
            kept = _csv(rel)
            raw = read(original)
            orig = pd.read_csv(io.BytesIO(raw))
            info = next(i for i in [*trial["streams"].values(), trial.get("authors_sim", {})] if i.get("file") == rel)
            assert (len(raw), len(orig)) == (info["source"]["bytes"], info["source"]["rows"]), rel
            orig = orig.dropna(subset=list(kept.columns))
            t = orig["time_secs"].to_numpy()
            at = np.clip(np.searchsorted(t, kept["time_secs"].to_numpy()), 1, len(t) - 1)
            at = np.where(np.abs(t[at - 1] - kept["time_secs"]) < np.abs(t[at] - kept["time_secs"]), at - 1, at)
            for col in kept.columns:
                tol = 0.5 * 10.0 ** -_decimals(kept[col]) + 1e-12
                err = np.abs(orig[col].to_numpy()[at] - kept[col].to_numpy())
                assert err.max() <= tol, (rel, col, err.max())
