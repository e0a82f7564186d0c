"""ROS 2 without ROS: a run written as an MCAP file of ROS 2 messages (:func:`write_mcap`), and bags read as logs
(:mod:`uvms.logs.bag`). Needs the optional extra ``uvms[ros]`` (``mcap``, ``mcap-ros2-support``, ``rosbags``);
``docs/ros.md`` documents the topics, the frames and the conversions.
"""

from uvms.ros.export import SENSOR_PREFIX, SENSOR_TOPICS, TOPICS, sensor_topics, write_mcap

__all__ = ["SENSOR_PREFIX", "SENSOR_TOPICS", "TOPICS", "sensor_topics", "write_mcap"]
