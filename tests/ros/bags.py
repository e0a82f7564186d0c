"""What the bag tests share: the half turn written out by hand and a bag read back with ``rosbags`` (an
independent decoder, with the message definitions stored in the file)."""

from __future__ import annotations

from pathlib import Path

import numpy as np

H = np.diag([1.0, -1.0, -1.0])                 # ned -> enu: the half turn about x, world and body alike


def read_bag(path: Path) -> dict[str, list]:
    """``{topic: [(log time [ns], message), ...], "types": {topic: message type}}`` of the bag at ``path``."""
    from rosbags.highlevel import AnyReader
    from rosbags.typesys import Stores, get_typestore

    out: dict[str, list] = {}
    with AnyReader([path], default_typestore=get_typestore(Stores.ROS2_HUMBLE)) as reader:
        types = {c.topic: c.msgtype for c in reader.connections}
        for connection, log_time, raw in reader.messages():
            out.setdefault(connection.topic, []).append((log_time, reader.deserialize(raw, connection.msgtype)))
    out["types"] = types
    return out
