"""Regenerate ``src/uvms/data/hinsdale_2023/`` from the public Hinsdale 2023 pool trials.

Source: github.com/hkolano/UVMS-SysID-with-EAs (MIT, Copyright (c) 2023 Hannah Kolano), commit 18d9b2f5.
Reads either a bare git repository (``git show <commit>:<path>``) or a checkout (a work tree) of it::

    python tools/bundle_hinsdale.py --source /path/to/UVMS-SysID-with-EAs[.git] [--out DIR]

What it writes (see ``SOURCE.md`` in the bundle for the why):

* ``<trial>/<trial>_mocap.csv``: the motion-capture rows kept by sub-sampling to 25 Hz (the first original row
  at or after each 40 ms tick; values rounded, never interpolated), columns time, position, quaternion;
* ``<trial>/<trial>_joint_states.csv``: the same sub-sampling of the encoders, axes b..e (the jaw, axis a, left
  out), positions and rates;
* ``<trial>/<trial>_imu.csv``: the same sub-sampling of the IMU to 10 Hz (ticks of 0.1 s), rounded;
* ``<trial>/_alt_NNN-K.csv`` (held-out trials only): the authors' simulated trajectory, time and qs1..qs10;
* ``<trial>/<trial>.yaml``: the log description for :class:`uvms.Log`;
* ``trials.yaml``: the index; ``LICENSE``: the source's MIT notice, verbatim.

``SOURCE.md`` is written by hand and is left alone.
"""

from __future__ import annotations

import argparse
import io
import math
import subprocess
from pathlib import Path

import numpy as np
import pandas as pd
import yaml

COMMIT = "18d9b2f5e9b687c535b6d69f70860fe6a9fff270"
REPOSITORY = "https://github.com/hkolano/UVMS-SysID-with-EAs"
ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "src" / "uvms" / "data" / "hinsdale_2023"
DATA = "data/hinsdale-data-2023"

TICK = 0.04  # s: the 25 Hz grid the mocap and encoder streams are sub-sampled on
IMU_TICK = 0.1  # s: the IMU (20 Hz) is sub-sampled to 10 Hz the same way
FIT = ["003-0", "003-1", "004-0", "004-1", "005-0", "005-1", "005-2", "005-3", "006-0", "006-1", "006-2",
       "006-3", "006-4", "007-0", "007-1", "009-0", "009-1", "012-0", "012-1", "012-2", "012-3", "014-0",
       "014-1", "014-2", "015-0", "015-1", "016-0", "016-1", "019-0", "019-1", "019-2", "019-3", "020-0",
       "020-1", "024-0", "024-1", "024-2", "025-0", "025-1", "026-0", "026-1", "026-2", "030-0", "030-1"]
HELD_OUT = ["001-0", "001-1", "001-2", "002-0", "002-1", "008-0", "008-1", "008-2", "009-0", "009-1",
            "011-0", "011-1", "011-2"]
BASELINES = ["baseline1", "baseline2", "baseline3"]

# column -> decimals kept
MOCAP = {"time_secs": 4, "x_pose": 5, "y_pose": 5, "z_pose": 5,
         "x_ori": 5, "y_ori": 5, "z_ori": 5, "w_ori": 5}
JOINTS = {"time_secs": 4, **{f"axis_{a}_pos": 4 for a in "bcde"}, **{f"axis_{a}_vel": 3 for a in "bcde"}}
IMU = {"time_secs": 4, "x_ori": 5, "y_ori": 5, "z_ori": 5, "w_ori": 5,
       "x_angvel": 4, "y_angvel": 4, "z_angvel": 4, "x_linacc": 2, "y_linacc": 2, "z_linacc": 2}
SIM = {"time_secs": 2, **{f"qs{i}": 4 for i in range(1, 11)}}

# the uvms model's joint names -> encoder columns, and the offsets the authors add to the encoder reading
JOINT_COLUMNS = {"base": "axis_e_pos", "shoulder": "axis_d_pos", "elbow": "axis_c_pos", "wrist": "axis_b_pos"}
JOINT_OFFSET = {"base": -3.07, "wrist": -2.879}


class Source:
    """The files of the source repository at ``COMMIT``, from a bare repository or a work tree."""

    def __init__(self, path: Path, commit: str = COMMIT):
        self.path, self.commit = Path(path), commit
        self.bare = not (self.path / "data").is_dir()
        if self.bare:
            head = subprocess.run(["git", "-C", str(self.path), "rev-parse", commit], capture_output=True,
                                  text=True, check=True).stdout.strip()
            if head != COMMIT:
                raise SystemExit(f"{path}: commit {head}, expected {COMMIT}")

    def read(self, rel: str) -> bytes:
        if self.bare:
            return subprocess.run(["git", "-C", str(self.path), "show", f"{self.commit}:{rel}"],
                                  capture_output=True, check=True).stdout
        return (self.path / rel).read_bytes()

    def exists(self, rel: str) -> bool:
        if self.bare:
            return subprocess.run(["git", "-C", str(self.path), "cat-file", "-e", f"{self.commit}:{rel}"],
                                  capture_output=True).returncode == 0
        return (self.path / rel).is_file()


def subsample(df: pd.DataFrame, tick: float = TICK) -> pd.DataFrame:
    """The first row at or after each multiple of ``tick`` (rows kept as they are; a gap stays a gap)."""
    t = df["time_secs"].to_numpy()
    grid = np.arange(math.floor(t[0] / tick), math.floor(t[-1] / tick) + 1) * tick
    rows = np.unique(np.searchsorted(t, grid - 1e-9))
    return df.iloc[rows[rows < len(df)]]


def write_csv(df: pd.DataFrame, decimals: dict[str, int], path: Path) -> pd.DataFrame:
    out = df[list(decimals)].round(decimals)
    out.to_csv(path, index=False, float_format=None, lineterminator="\n")
    return out


def stream_info(df: pd.DataFrame, rel: str, size: int, rows: int) -> dict:
    return {"file": rel, "rows": int(len(df)), "t0": round(float(df.time_secs.iloc[0]), 4),
            "t1": round(float(df.time_secs.iloc[-1]), 4),
            "source": {"file": rel.split("/")[-1], "bytes": size, "rows": rows}}


def trial_names(code: str, role: str) -> tuple[str, str, str]:
    """(trial name, metadata file, trajectory yaml) for a code of the authors' lists (009-0 is in both)."""
    if role == "baseline":
        return code, "", ""
    if role == "held_out":
        return (f"traj_alt_{code}", f"{DATA}/metadata__alt_{code}.yml",
                f"data/combo_traj_yaml_files_otherhome/traj{code[:3]}/traj{code}.yaml")
    return (f"traj{code}", f"{DATA}/metadata_{code}.yml",
            f"data/combo_traj_yaml_files_fullrange2/traj{code[:3]}/traj{code}.yaml")


def log_yaml(name: str, role: str, start: float, duration: float, has_imu: bool) -> str:
    cols = ", ".join(f"{k}: {v}" for k, v in JOINT_COLUMNS.items())
    off = ", ".join(f"{k}: {v}" for k, v in JOINT_OFFSET.items())
    text = (f"# {name}: Hinsdale 2023 pool trial ({role}); BlueROV2 + Reach Alpha 5, thrusters off, arm moving.\n"
            f"# Data: hkolano/UVMS-SysID-with-EAs @ {COMMIT[:7]} (MIT, see ../LICENSE), sub-sampled: ../SOURCE.md\n"
            f"start: {start}\n"
            f"duration: {duration}\n"
            "frame: enu               # world z up (motion capture), body forward-left-up\n"
            f"pose:   {{file: {name}_mocap.csv, time: time_secs, position: [x_pose, y_pose, z_pose],\n"
            "         quaternion_xyzw: [x_ori, y_ori, z_ori, w_ori]}\n"
            f"joints: {{file: {name}_joint_states.csv, time: time_secs,\n"
            f"         columns: {{{cols}}},\n"
            f"         offset: {{{off}}}}}\n")
    if has_imu:
        text += (f"imu:    {{file: {name}_imu.csv, time: time_secs, quaternion_xyzw: [x_ori, y_ori, z_ori, w_ori],\n"
                 "         angular_velocity: [x_angvel, y_angvel, z_angvel],\n"
                 "         linear_acceleration: [x_linacc, y_linacc, z_linacc]}\n")
    return text


def bundle_trial(src: Source, code: str, role: str, out: Path) -> dict:
    name, meta_file, traj_file = trial_names(code, role)
    d = out / name
    d.mkdir(parents=True, exist_ok=True)
    entry: dict = {"name": name, "role": role}
    streams = {}
    for kind, cols, tick in (("mocap", MOCAP, TICK), ("joint_states", JOINTS, TICK), ("imu", IMU, IMU_TICK)):
        rel = f"{DATA}/{name}_{kind}.csv"
        raw = src.read(rel)
        df = pd.read_csv(io.BytesIO(raw))
        n = len(df)
        df = df.dropna(subset=list(cols))
        kept = write_csv(subsample(df, tick), cols, d / f"{name}_{kind}.csv")
        streams[kind] = stream_info(kept, f"{name}/{name}_{kind}.csv", len(raw), n)
    t_first = max(s["t0"] for s in streams.values())
    t_last = min(s["t1"] for s in streams.values())
    if meta_file:
        start_time = float(yaml.safe_load(src.read(meta_file))["start_time"])
        entry["start_time"] = start_time
        entry["start_source"] = f"{meta_file.split('/')[-1]} start_time"
        start = start_time
        if start < t_first:  # traj006-4: start_time -0.2, before any stream has begun
            start = math.ceil(t_first * 100) / 100
            entry["start_source"] += " (before the streams begin: moved to the first time all three have begun)"
        arm = yaml.safe_load(src.read(traj_file))
        entry["arm_motion_duration"] = round(float(arm["duration"]), 4)
        entry["arm_motion_file"] = traj_file
    else:  # baselines: no metadata, the arm is still; start where every stream has begun
        start = math.ceil(t_first * 100) / 100
        entry["start_source"] = "first time all three streams have begun (no metadata file)"
    entry["start"] = start
    entry["duration"] = math.floor((t_last - start) * 100) / 100
    entry["streams"] = streams
    if role == "held_out":
        rel = f"data/sim_trajs/_alt_{code}.csv"
        raw = src.read(rel)
        df = pd.read_csv(io.BytesIO(raw))
        kept = write_csv(df, SIM, d / f"_alt_{code}.csv")
        info = stream_info(kept, f"{name}/_alt_{code}.csv", len(raw), len(df))
        info["time_offset"] = 0.0
        info["columns"] = {"qs1": "roll [rad]", "qs2": "pitch [rad]", "qs3": "yaw [rad]",
                           "qs4": "x [m]", "qs5": "y [m]", "qs6": "z [m]",
                           "qs7": "base [rad]", "qs8": "shoulder [rad]", "qs9": "elbow [rad]", "qs10": "wrist [rad]"}
        info["note"] = ("time_secs is log time (the sim started 10 s earlier from the log's state at t = 0, "
                        "with the arm held; its arm motion starts at start); roll/pitch/yaw are ZYX Euler angles")
        entry["authors_sim"] = info
    (d / f"{name}.yaml").write_text(log_yaml(name, role, start, entry["duration"], True), encoding="utf-8")
    return entry


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--source", type=Path, default=Path("/work/.mirror/hkolano+UVMS-SysID-with-EAs/repo"),
                    help="bare git repository or work tree of hkolano/UVMS-SysID-with-EAs")
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args()
    src = Source(args.source)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "LICENSE").write_bytes(src.read("LICENSE"))
    trials = [bundle_trial(src, c, "fit", args.out) for c in FIT]
    trials += [bundle_trial(src, c, "held_out", args.out) for c in HELD_OUT]
    trials += [bundle_trial(src, c, "baseline", args.out) for c in BASELINES]
    index = {
        "dataset": "hinsdale_2023",
        "source": {"repository": REPOSITORY, "commit": COMMIT, "licence": "MIT (LICENSE)",
                   "paper": "Kolano, Palmer, Davidson, The Coupling Effect: Experimental Validation of the Fusion "
                            "of Fossen and Featherstone to Simulate UVMS Dynamics in Julia, arXiv:2209.13577"},
        "model": "hinsdale_bluerov2_alpha5",
        "frame": "enu",
        "joints": {"columns": JOINT_COLUMNS, "offset": JOINT_OFFSET},
        "subsampling": {"mocap": "first original row at or after each 0.04 s tick (25 Hz), rounded",
                        "joint_states": "first original row at or after each 0.04 s tick (25 Hz), rounded",
                        "imu": "first original row at or after each 0.1 s tick (10 Hz), rounded"},
        "duration_rule": "from start to the end of the shortest of the three streams, floored to 0.01 s",
        "trials": trials,
    }
    text = ("# Index of the bundled Hinsdale 2023 trials; written by tools/bundle_hinsdale.py, see SOURCE.md.\n"
            + yaml.safe_dump(index, sort_keys=False, width=120))
    (args.out / "trials.yaml").write_text(text, encoding="utf-8")
    total = sum(p.stat().st_size for p in args.out.rglob("*") if p.is_file())
    print(f"{len(trials)} trials, {total / 1e6:.2f} MB in {args.out}")


if __name__ == "__main__":
    main()
