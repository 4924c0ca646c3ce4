"""The Python twin of time_jump_test.cpp: the same cases, the same answers."""

import importlib.util
import os

# Loaded by its path: the package's __init__ needs rospy and the generated messages; this module
# needs neither.
_spec = importlib.util.spec_from_file_location(
    "time_jump", os.path.join(os.path.dirname(__file__), "..", "..", "src", "mybot_lockstep", "time_jump.py"))
_module = importlib.util.module_from_spec(_spec)
_spec.loader.exec_module(_module)
TimeJump = _module.TimeJump


def test_time_going_forward_is_no_jump_and_nothing_is_stale():
    j = TimeJump()
    assert not j.went_back(0.0)
    assert not j.went_back(5.0)
    assert not j.went_back(5.0)
    assert not j.stale(100.0, 5.0)


def test_a_simulation_reset_is_one_jump():
    j = TimeJump()
    j.went_back(19.96)
    assert j.went_back(0.02)
    assert not j.went_back(0.02)
    assert not j.went_back(0.04)
    assert abs(j.guard_until - 9.99) < 1e-12


def test_transforms_stamped_before_the_reset_are_stale_and_the_new_ones_not():
    j = TimeJump()
    j.went_back(19.96)
    j.went_back(0.02)
    assert j.stale(19.96 + 0.1, 0.02)
    assert j.stale(19.5, 0.04)
    assert not j.stale(0.02 + 0.5, 0.02)
    assert not j.stale(0.0, 0.02)


def test_a_future_dated_transform_near_the_midpoint_is_not():
    j = TimeJump()
    j.went_back(12.04)
    j.went_back(0.02)
    assert not j.stale(6.051, 5.86)
    assert j.stale(12.225, 0.02)


def test_once_the_clock_passes_the_midpoint_nothing_is_stale():
    j = TimeJump()
    j.went_back(19.96)
    j.went_back(0.02)
    assert not j.stale(19.96, 9.99)


def test_a_second_jump_moves_the_midpoint():
    j = TimeJump()
    for t in (20.0, 0.0, 4.0):
        j.went_back(t)
    assert j.went_back(2.0)
    assert j.guard_until == 3.0
    assert j.stale(3.9, 2.0)
    assert not j.stale(2.1, 2.0)
