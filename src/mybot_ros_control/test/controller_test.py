"""What the ros_control rostests share: a lockstep participant watching /joint_states, the
controller manager's services, the world unpaused once the spawner runs the controllers, and
action goals run to their result."""
import threading
import unittest

import rospy
from nav_msgs.msg import Odometry
from sensor_msgs.msg import JointState

from controller_manager_msgs.srv import ListControllers, LoadController, SwitchController
from gazebo_msgs.srv import GetModelState
from mybot_common.geometry import yaw_of
from mybot_gazebo_lite.controller_manager import ControllerManager, ControllerManagerError
from mybot_lockstep import participant
from mybot_lockstep.start_paused import unpause_when

CM = "/controller_manager/"


def refusal(call):
    """Why the controller manager refused `call(client)`, made through gazebo_lite's client (the
    spawner's): controller_manager_msgs' replies say only `ok`, the manager logs why."""
    try:
        call(ControllerManager("/"))
    except ControllerManagerError as e:
        return str(e)
    raise AssertionError("the controller manager did not refuse the call")


class ControllerTest(unittest.TestCase):
    @classmethod
    def join(cls, node):
        """Starts this test's node as a lockstep participant (it joins at its first sleep), with
        `history` of the joint states: (sim time, {joint: position})."""
        rospy.init_node(node)
        cls.ls = participant(defer_join=True)
        cls.lock = threading.Lock()
        cls.joints = None
        cls.history = []
        cls.ls.Subscriber("/joint_states", JointState, cls._on_joints)
        rospy.wait_for_service(CM + "list_controllers", timeout=60)
        cls.list = rospy.ServiceProxy(CM + "list_controllers", ListControllers)
        cls.load = rospy.ServiceProxy(CM + "load_controller", LoadController)
        cls.switch = rospy.ServiceProxy(CM + "switch_controller", SwitchController)

    @classmethod
    def unpause_when_running(cls, count, clients):
        """Unpauses the world once the spawner runs `count` controllers; then waits for the
        action servers of `clients`."""
        unpause_when(cls.ls, lambda: sum(c.state == "running" for c in cls.list().controller) == count,
                     "the spawner did not start the %d controllers" % count)
        for c in clients:
            assert c.wait_for_server(rospy.Duration(30)), "no action server for " + str(getattr(c.action_client, "ns", "?"))

    @classmethod
    def _on_joints(cls, m):
        with cls.lock:
            cls.joints = m
            cls.history.append((m.header.stamp.to_sec(), dict(zip(m.name, m.position))))

    def assert_advertises(self, types):
        """The master lists each topic of {topic: type} with that type, as `rostopic type` shows it."""
        listed = dict(rospy.get_published_topics())
        for topic, t in types.items():
            self.assertEqual(listed.get(topic), t, topic)

    def position(self, name):
        with self.lock:
            js = self.joints
        return None if js is None else js.position[js.name.index(name)]

    def velocity(self, name):
        with self.lock:
            js = self.joints
        return js.velocity[js.name.index(name)]

    def comes_to_rest(self, name, at, within, timeout=3.0):
        """Whether the joint comes to rest (under 1 mm/s) within `within` of `at` in `timeout` s of sim time."""
        return self.ls.wait_for(lambda: abs(self.position(name) - at) < within and abs(self.velocity(name)) < 1e-3,
                                timeout)

    def run_goal(self, client, goal, timeout=30.0, feedback=None):
        """Sends `goal` and waits for its result: (state, result)."""
        client.send_goal(goal, feedback_cb=feedback)
        self.assertTrue(client.wait_for_result(rospy.Duration(timeout)), "no result")
        return client.get_state(), client.get_result()


class DriveTest(ControllerTest):
    """A mobile base's test: the model's ground truth from the simulator and the drive
    controller's odometry, each as (x, y, yaw)."""

    @classmethod
    def watch(cls, model, odom_topic):
        """Reads `odom_topic` and asks the simulator for `model`'s pose (after join)."""
        cls.model_name = model
        cls.odom = None
        cls.ls.Subscriber(odom_topic, Odometry, cls._on_odom)
        rospy.wait_for_service("/gazebo/get_model_state", timeout=60)
        cls.model = rospy.ServiceProxy("/gazebo/get_model_state", GetModelState)

    @classmethod
    def _on_odom(cls, m):
        with cls.lock:
            cls.odom = m

    def truth(self):
        """(x, y, yaw) of the robot's base_link, from the simulator."""
        p = self.model(model_name=self.model_name, relative_entity_name="world").pose
        return p.position.x, p.position.y, yaw_of(p.orientation)

    def odometry(self):
        with self.lock:
            p = self.odom.pose.pose
        return p.position.x, p.position.y, yaw_of(p.orientation)
