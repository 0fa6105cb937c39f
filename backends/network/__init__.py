"""Across machines: `issv serve` publishes a backend's frames, the `network` backend subscribes
(ZeroMQ by default, ROS 1 topics with transport = "ros")."""
