"""Python tooling of mybot_control: teleop, timed moves, PID tuning, measurement."""
