#!/usr/bin/python3
"""A lockstep participant that dies at 1 s of sim time without leaving (no last Ack)."""
import os

import rospy

from mybot_lockstep import participant

rospy.init_node('lockstep_quitter')
ls = participant()
ls.wait_for(lambda: rospy.get_time() >= 1.0, 120.0)
os._exit(0)
