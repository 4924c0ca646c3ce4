"""Small helpers every mybot package shares, one home each. No rospy."""
