"""Thin rospy wrappers: read and validate parameters, convert messages, call the pure modules."""
