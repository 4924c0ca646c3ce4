#!/usr/bin/env python3
"""Simulator-in-the-loop tests for gazebo_lite (run by rostest; ~suite selects the cases).

Everything is measured in sim time against the simulator's ground truth; waits are
conditions with timeouts, never fixed delays.
"""
import math
import os
import subprocess
import sys
import tempfile
import threading
import time
import unittest
import xml.etree.ElementTree as ET

import rospy
import rostest
import tf2_ros
from geometry_msgs.msg import Pose, Twist, Vector3, Wrench
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Log
from sensor_msgs.msg import JointState, LaserScan
from std_srvs.srv import Empty

from gazebo_msgs.msg import (LinkState, LinkStates, ModelState, ModelStates, ODEJointProperties, ODEPhysics,
                             PerformanceMetrics)
from gazebo_msgs.srv import GetJointPropertiesResponse
from gazebo_msgs.srv import (ApplyBodyWrench, ApplyJointEffort, BodyRequest, DeleteModel, GetJointProperties,
                              GetLinkProperties, GetLinkState, GetModelProperties, GetModelState, GetPhysicsProperties,
                              GetWorldProperties, SetJointProperties, SetLinkProperties, SetLinkState, SetModelState,
                              SetPhysicsProperties, SpawnModel)
from mybot_gazebo_lite.msg import ModelContacts
from mybot_common.geometry import wrap, yaw_of
from mybot_lockstep import participant

WALL_TIMEOUT = 60.0


def root_link(urdf):
    """The URDF's root link: the one no joint has as its child."""
    robot = ET.fromstring(urdf)
    children = {j.find('child').get('link') for j in robot.iter('joint')}
    return next(l.get('name') for l in robot.iter('link') if l.get('name') not in children)


class Robot:
    """Latest ground truth / odom of one (possibly namespaced) robot and a cmd_vel publisher.

    A robot that is commanded (commands=True) makes this node a lockstep participant
    (mybot_lockstep): the simulator waits for it every period, so a command sent for period k
    acts at period k whatever the load, and every ground-truth sample is seen. The main thread
    then holds the simulation between its sleeps, so it waits only through the helper's sleeps
    (wait, settle, drive) and calls release() before any other blocking call. It joins at its
    first sleep (defer_join), with every subscription below made: a suite whose launch names it
    in lockstep_wait_for then starts in the same period on every run."""

    def __init__(self, ns='', commands=True):
        p = ns.strip('/') + '/' if ns else ''
        self.lock = threading.Lock()
        self.gt = None
        self.odom = None
        self.scan = None
        self.joints = None
        self.history = None
        # Without commands (the rest test: 600 s of sim time, no input) the node stays out of
        # lockstep: the simulation need not hand it every period.
        self.ls = participant(defer_join=True) if commands else None
        sub = self.ls.Subscriber if self.ls else rospy.Subscriber
        self.cmd = (self.ls.Publisher if self.ls else rospy.Publisher)('/' + p + 'cmd_vel', Twist, queue_size=1)
        sub('/' + p + 'ground_truth/odom', Odometry, self._gt)
        sub('/' + p + 'odom', Odometry, self._odom)
        sub('/' + p + 'scan', LaserScan, self._scan)
        sub('/' + p + 'joint_states', JointState, self._js)

    def _gt(self, m):
        with self.lock:
            self.gt = m
            if self.history is not None:
                self.history.append(m)

    def _odom(self, m):
        with self.lock:
            self.odom = m

    def _scan(self, m):
        with self.lock:
            self.scan = m

    def _js(self, m):
        with self.lock:
            self.joints = m

    def wait(self, cond, what, timeout=WALL_TIMEOUT):
        """Until cond(), a period of sim time at a time; the bound is wall time (start-up)."""
        end = time.monotonic() + timeout
        while time.monotonic() < end and not rospy.is_shutdown():
            with self.lock:
                if cond():
                    return
            if self.ls and (self.ls.active or rospy.get_rostime() > rospy.Time(0)):
                self.ls.sleep(0.01)  # under lockstep the first one joins, before time starts
            else:
                time.sleep(0.002)
        raise AssertionError('timed out waiting for ' + what)

    def release(self):
        """Before a blocking call (a service, wait_for_message): stop holding the simulation."""
        if self.ls:
            self.ls.release()

    def ready(self):
        self.wait(lambda: self.gt is not None, 'ground truth')
        self.wait(lambda: self.cmd.get_num_connections() > 0, 'cmd_vel subscriber')

    def now(self):
        with self.lock:
            return self.gt.header.stamp.to_sec()

    def pose(self):
        with self.lock:
            p = self.gt.pose.pose
            return p.position.x, p.position.y, yaw_of(p.orientation)

    def drive(self, v, w, duration):
        """Publishes (v, w) every 20 ms of sim time for `duration` sim seconds, then stops."""
        self.publish_for(v, w, duration, 50)
        self.cmd.publish(Twist())

    def publish_for(self, v, w, duration, hz):
        t_end = self.now() + duration
        tw = Twist()
        tw.linear.x, tw.angular.z = v, w
        rate = self.ls.Rate(hz)
        while self.now() < t_end:
            self.cmd.publish(tw)
            rate.sleep()

    def record(self, v, w, duration):
        """Drives for `duration` plus a margin and returns the ground-truth samples.

        At real_time_factor 0 the sim runs ahead of this process, so windows are
        measured on the recorded trajectory from the motion onset, not from when
        the command was sent."""
        with self.lock:
            self.history = []
        self.drive(v, w, duration + 0.5)
        self.settle(0.3)
        with self.lock:
            h, self.history = self.history, None
        return h

    @staticmethod
    def window(history, duration, moving):
        onset = next(i for i, m in enumerate(history) if moving(m))
        t0 = history[max(onset - 1, 0)].header.stamp.to_sec()
        end = min(history, key=lambda m: abs(m.header.stamp.to_sec() - (t0 + duration)))
        return history[max(onset - 1, 0)], end, history[max(onset - 1, 0):history.index(end) + 1]

    def settle(self, seconds=0.5, wall_timeout=WALL_TIMEOUT):
        t = self.now() + seconds
        self.wait(lambda: self.gt.header.stamp.to_sec() >= t, 'sim time to pass', timeout=wall_timeout)


class DriveTests(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.r = Robot()
        cls.r.ready()

    def setUp(self):
        # From the period this node holds: the simulator serves the call between two periods.
        rospy.wait_for_service('/gazebo/reset_world', 30)
        rospy.ServiceProxy('/gazebo/reset_world', Empty)()
        self.r.settle(0.5)

    def test_straight_line_two_metres(self):
        h = self.r.record(0.5, 0.0, 4.0)
        a, b, _ = Robot.window(h, 4.0, lambda m: abs(m.twist.twist.linear.x) > 1e-3)
        pa, pb = a.pose.pose.position, b.pose.pose.position
        d = math.hypot(pb.x - pa.x, pb.y - pa.y)
        self.assertAlmostEqual(d, 2.0, delta=0.04, msg='moved %.4f m' % d)

    def test_turn_in_place_returns_to_heading(self):
        h = self.r.record(0.0, 0.5, 2 * math.pi / 0.5)
        a, b, seg = Robot.window(h, 2 * math.pi / 0.5, lambda m: abs(m.twist.twist.angular.z) > 1e-3)
        turned = 0.0
        for m0, m1 in zip(seg, seg[1:]):
            turned += wrap(yaw_of(m1.pose.pose.orientation) - yaw_of(m0.pose.pose.orientation))
        self.assertLess(abs(math.degrees(turned - 2 * math.pi)), 2.0, 'turned %.2f deg' % math.degrees(turned))
        pa, pb = a.pose.pose.position, b.pose.pose.position
        self.assertLess(math.hypot(pb.x - pa.x, pb.y - pa.y), 0.05)

    def test_odom_agrees_with_ground_truth_on_square(self):
        travelled = 0.0
        for _ in range(4):
            x0, y0, _ = self.r.pose()
            self.r.drive(0.4, 0.0, 5.0)
            x1, y1, _ = self.r.pose()
            travelled += math.hypot(x1 - x0, y1 - y0)
            self.r.drive(0.0, 0.5, (math.pi / 2) / 0.5)
        self.r.settle(0.2)
        with self.r.lock:
            o = self.r.odom.pose.pose.position
            g = self.r.gt.pose.pose.position
        err = math.hypot(o.x - g.x, o.y - g.y)
        self.assertGreater(travelled, 7.0)
        self.assertLess(err, 0.01 * travelled, 'odom error %.4f m after %.2f m' % (err, travelled))

    def test_nan_commands_are_ignored(self):
        x0, y0, _ = self.r.pose()
        self.r.publish_for(float('nan'), float('inf'), 1.0, 200)
        x1, y1, th1 = self.r.pose()
        self.assertLess(math.hypot(x1 - x0, y1 - y0), 0.001)
        self.assertTrue(all(math.isfinite(v) for v in (x1, y1, th1)))

    def test_command_timeout_stops_robot(self):
        tw = Twist()
        tw.linear.x = 0.5
        self.r.cmd.publish(tw)  # one command, then silence
        self.r.settle(2.0)
        with self.r.lock:
            v = self.r.gt.twist.twist.linear
        self.assertLess(math.hypot(v.x, v.y), 0.01)

    def test_body_wrenches_lift_the_robot_while_they_last(self):
        apply = rospy.ServiceProxy('/gazebo/apply_body_wrench', ApplyBodyWrench)
        clear = rospy.ServiceProxy('/gazebo/clear_body_wrenches', BodyRequest)
        urdf = rospy.get_param('/robot_description')
        root = 'mybot::' + root_link(urdf)
        weight = 9.8 * sum(float(m.get('value')) for m in ET.fromstring(urdf).iter('mass'))

        def z():
            with self.r.lock:
                return self.r.gt.pose.pose.position.z

        z0 = z()
        # Three times its weight upwards for 0.2 s: up with 2 g, then it falls back and rests.
        up = Wrench()
        up.force.z = 3 * weight
        res = apply(body_name=root, wrench=up, duration=rospy.Duration(0.2))
        self.assertTrue(res.success, res.status_message)
        self.r.settle(0.2)
        self.assertGreater(z() - z0, 0.5 * 2 * 9.8 * 0.2 ** 2 * 0.8)
        self.r.settle(1.0)
        self.assertLess(abs(z() - z0), 0.01)
        # Until cleared: it rises while the wrench lasts, and comes back down once it is cleared.
        self.assertTrue(apply(body_name=root, wrench=up, duration=rospy.Duration(-1)).success)
        self.r.settle(0.2)
        self.assertGreater(z() - z0, 0.1)
        clear(body_name=root)
        self.r.settle(1.0)
        self.assertLess(abs(z() - z0), 0.01)
        # Refused, saying why, and nothing pushes.
        nan = Wrench()
        nan.force.x = float('nan')
        for res, text in ((apply(body_name=root, wrench=nan, duration=rospy.Duration(1)), 'wrench.force.x is nan'),
                          (apply(body_name='mybot::no_link', wrench=up, duration=rospy.Duration(1)), "'mybot::no_link'"),
                          (apply(body_name='ground_plane::link', wrench=up, duration=rospy.Duration(1)), 'dynamic'),
                          (apply(body_name=root, reference_frame='nowhere', wrench=up, duration=rospy.Duration(1)),
                           "'nowhere'")):
            self.assertFalse(res.success)
            self.assertIn(text, res.status_message)
        self.r.settle(0.2)
        self.assertLess(abs(z() - z0), 0.01)

    def test_joint_efforts_turn_a_wheel_while_they_last(self):
        apply = rospy.ServiceProxy('/gazebo/apply_joint_effort', ApplyJointEffort)
        urdf = rospy.get_param('/robot_description')
        left = next(e.text.strip() for e in ET.fromstring(urdf).iter('leftJoint'))
        x0, y0, th0 = self.r.pose()
        # 20 N m on the left wheel, four times what its drive motor holds it with: the robot turns.
        res = apply(joint_name=left, effort=20.0, duration=rospy.Duration(0.5))
        self.assertTrue(res.success, res.status_message)
        self.r.settle(0.6)  # past its end
        _, _, th1 = self.r.pose()
        self.assertGreater(abs(wrap(th1 - th0)), 0.05)
        # Over: the wheel is no longer driven faster (it rolls on, slowing).
        speed = lambda: abs(self.r.joints.velocity[self.r.joints.name.index(left)])  # noqa: E731
        with self.r.lock:
            v_end = speed()
        self.r.settle(0.5)
        with self.r.lock:
            self.assertLessEqual(speed(), v_end + 1e-6)
        self.assertGreater(v_end, 1.0)
        # The model's name prefix works too; an unknown joint or a NaN is refused, naming it.
        self.assertTrue(apply(joint_name='mybot::' + left, effort=1.0, duration=rospy.Duration(0)).success)
        for res, text in ((apply(joint_name='no_joint', effort=1.0, duration=rospy.Duration(1)), "'no_joint'"),
                          (apply(joint_name=left, effort=float('nan'), duration=rospy.Duration(1)), 'effort is nan')):
            self.assertFalse(res.success)
            self.assertIn(text, res.status_message)

    def test_reset_world_restores_spawn_pose(self):
        self.r.drive(0.5, 0.3, 2.0)
        x, y, _ = self.r.pose()
        self.assertGreater(math.hypot(x, y), 0.5)
        rospy.ServiceProxy('/gazebo/reset_world', Empty)()
        self.r.settle(0.2)
        x, y, th = self.r.pose()
        self.assertLess(math.hypot(x, y), 0.005)
        self.assertLess(abs(th), 0.01)
        st = rospy.ServiceProxy('/gazebo/get_model_state', GetModelState)(model_name='mybot')
        self.assertTrue(st.success)
        self.assertAlmostEqual(st.pose.position.x, x, delta=0.01)


class StatesTests(unittest.TestCase):
    """gazebo_ros's /gazebo/model_states, /gazebo/link_states and the /gazebo/set_model_state
    topic. A suite of its own: a lockstep participant subscribed to the states handles two
    messages a physics step, which slowed the drive suite from 25 s to over 200 s."""

    @classmethod
    def setUpClass(cls):
        cls.r = Robot()
        # How many states messages arrived, and the last one.
        cls.states = {'model': [0, None], 'link': [0, None]}
        cls.r.ls.Subscriber('/gazebo/model_states', ModelStates, cls._on_states, callback_args='model')
        cls.r.ls.Subscriber('/gazebo/link_states', LinkStates, cls._on_states, callback_args='link')
        cls.set_state_topic = cls.r.ls.Publisher('/gazebo/set_model_state', ModelState)
        cls.r.ready()
        cls.r.wait(lambda: cls.set_state_topic.get_num_connections() > 0, 'the simulator on set_model_state')

    @classmethod
    def _on_states(cls, m, kind):
        with cls.r.lock:
            cls.states[kind][0] += 1
            cls.states[kind][1] = m

    def setUp(self):
        rospy.ServiceProxy('/gazebo/reset_world', Empty)()
        self.r.settle(0.2)

    def test_model_and_link_states_after_every_step_as_gazebo(self):
        get_state = rospy.ServiceProxy('/gazebo/get_model_state', GetModelState)
        with self.r.lock:
            t0, models0, links0 = rospy.get_time(), self.states['model'][0], self.states['link'][0]
        self.r.drive(0.3, 0.2, 0.5)
        with self.r.lock:  # held: the period's messages are all in
            t1, models, links = rospy.get_time(), self.states['model'][0] - models0, self.states['link'][0] - links0
            last_models, last_links = self.states['model'][1], self.states['link'][1]
        # One message after every physics step (the empty world's 1 ms), none lost under lockstep.
        steps = round((t1 - t0) / 0.001)
        self.assertGreater(steps, 400)
        self.assertEqual((models, links), (steps, steps))
        # World models first, then the robots; the pose is where get_model_state puts it, now.
        self.assertEqual(last_models.name, ['ground_plane', 'mybot'])
        st = get_state(model_name='mybot')
        p = last_models.pose[1].position
        self.assertEqual((p.x, p.y, p.z), (st.pose.position.x, st.pose.position.y, st.pose.position.z))
        self.assertGreater(math.hypot(p.x, p.y), 0.1)  # it moved: not the spawn pose
        self.assertAlmostEqual(last_models.twist[1].linear.x, st.twist.linear.x, delta=1e-12)
        # Every URDF link, "model::link"; the root link's pose is the model's.
        root = root_link(rospy.get_param('/robot_description'))
        self.assertEqual(last_links.name[0], 'ground_plane::link')
        self.assertTrue(all(n.startswith('mybot::') for n in last_links.name[1:]), last_links.name)
        self.assertEqual(last_links.pose[last_links.name.index('mybot::' + root)], last_models.pose[1])

    def test_set_model_state_topic_teleports_and_refuses_bad_states(self):
        get_state = rospy.ServiceProxy('/gazebo/get_model_state', GetModelState)
        z = get_state(model_name='mybot').pose.position.z

        def send(x, y, frame='', yaw=0.5):
            m = ModelState(model_name='mybot', reference_frame=frame)
            m.pose.position.x, m.pose.position.y, m.pose.position.z = x, y, z
            m.pose.orientation.z, m.pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
            self.set_state_topic.publish(m)
            self.r.settle(0.1)
            return get_state(model_name='mybot').pose.position

        p = send(1.0, -0.5)
        self.assertAlmostEqual(p.x, 1.0, delta=0.005)
        self.assertAlmostEqual(p.y, -0.5, delta=0.005)
        self.assertAlmostEqual(yaw_of(get_state(model_name='mybot').pose.orientation), 0.5, delta=0.01)
        # A NaN, or a frame gazebo_lite does not place relative to, moves nothing.
        for x, y, frame in ((float('nan'), 0.0, ''), (3.0, 3.0, 'mybot::chassis')):
            q = send(x, y, frame)
            self.assertLess(math.hypot(q.x - p.x, q.y - p.y), 0.001, (x, y, frame))


    def test_world_properties_and_link_states_relative_to_entities(self):
        get_model = rospy.ServiceProxy('/gazebo/get_model_state', GetModelState)
        get_link = rospy.ServiceProxy('/gazebo/get_link_state', GetLinkState)
        world = rospy.ServiceProxy('/gazebo/get_world_properties', GetWorldProperties)()
        self.assertTrue(world.success)
        self.assertEqual(world.model_names, ['ground_plane', 'mybot'])
        self.assertAlmostEqual(world.sim_time, rospy.get_time(), delta=0.011)
        self.r.drive(0.3, 0.5, 0.5)  # somewhere turned, and moving
        root = 'mybot::' + root_link(rospy.get_param('/robot_description'))
        model = get_model(model_name='mybot')
        link = get_link(link_name=root)
        self.assertTrue(link.success, link.status_message)
        self.assertEqual(link.link_state.pose, model.pose)  # the root link is the model's frame
        # Relative to itself, to its root link, or to the ground plane (the world's origin).
        for frame in ('mybot', root):
            rel = get_model(model_name='mybot', relative_entity_name=frame)
            self.assertTrue(rel.success, rel.status_message)
            self.assertLess(math.hypot(rel.pose.position.x, rel.pose.position.y), 1e-9, frame)
            self.assertAlmostEqual(rel.pose.orientation.w, 1.0, delta=1e-9)
        rel = get_link(link_name=root, reference_frame='ground_plane::link')
        self.assertAlmostEqual(rel.link_state.pose.position.x, model.pose.position.x, delta=1e-9)
        # Names that are not there: said, not answered with a pose.
        for res, text in ((get_link(link_name='mybot::no_link'), "no link named 'mybot::no_link'"),
                          (get_link(link_name='mybot'), 'model::link'),
                          (get_model(model_name='mybot', relative_entity_name='nobody'), "'nobody'")):
            self.assertFalse(res.success)
            self.assertIn(text, res.status_message)

    def test_sdf_models_spawned_and_deleted_while_running(self):
        """spawn_model -sdf (a static block ahead of the robot: the laser's static world is rebuilt),
        spawn_sdf_model (a dynamic crate that falls), delete_model; as gazebo_ros."""
        def centre_range():
            self.r.settle(0.1)
            with self.r.lock:
                ranges = self.r.scan.ranges
            return ranges[len(ranges) // 2]

        self.assertGreater(centre_range(), 5.0)  # nothing ahead in the empty world
        block = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'fixtures', 'wall_block.sdf')
        self.r.release()  # the tool takes seconds to start
        p = subprocess.run(['rosrun', 'gazebo_ros', 'spawn_model', '-sdf', '-file', block, '-model', 'block',
                            '-x', '2'], capture_output=True, text=True, timeout=60)
        self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
        ahead = centre_range()
        self.assertLess(ahead, 1.9)  # the block's face is 1.9 m from the robot's origin
        self.assertGreater(ahead, 1.5)
        # Moved, static as it is (set_model_state), the laser sees it 1 m farther.
        m = ModelState(model_name='block')
        m.pose.position.x, m.pose.position.z, m.pose.orientation.w = 3.0, 0.5, 1.0
        res = rospy.ServiceProxy('/gazebo/set_model_state', SetModelState)(model_state=m)
        self.assertTrue(res.success, res.status_message)
        self.assertAlmostEqual(centre_range() - ahead, 1.0, delta=0.05)
        crate = ('<sdf version="1.6"><model name="crate"><link name="l"><inertial><mass>1</mass></inertial>'
                 '<collision name="c"><geometry><box><size>0.2 0.2 0.2</size></box></geometry></collision>'
                 '</link></model></sdf>')
        pose = Pose()
        pose.position.x, pose.position.y, pose.position.z = 0.0, 2.0, 1.0
        pose.orientation.w = 1.0
        spawn = rospy.ServiceProxy('/gazebo/spawn_sdf_model', SpawnModel)
        res = spawn(model_name='crate', model_xml=crate, initial_pose=pose)
        self.assertTrue(res.success, res.status_message)
        self.assertFalse(spawn(model_name='crate', model_xml=crate, initial_pose=pose).success)  # the name is taken
        self.r.settle(1.5)
        with self.r.lock:
            names = self.states['model'][1].name
            z = self.states['model'][1].pose[names.index('crate')].position.z
        self.assertEqual(names, ['ground_plane', 'mybot', 'block', 'crate'])  # Gazebo's: the order they came in
        self.assertAlmostEqual(z, 0.1, delta=0.01)  # fell onto the ground
        delete = rospy.ServiceProxy('/gazebo/delete_model', DeleteModel)
        for name in ('block', 'crate'):
            self.assertTrue(delete(model_name=name).success, name)
        self.assertGreater(centre_range(), 5.0)  # the block is gone from the laser's world too
        with self.r.lock:
            self.assertEqual(self.states['model'][1].name, ['ground_plane', 'mybot'])

    def test_model_and_joint_properties_as_gazebo_gives_them(self):
        urdf = rospy.get_param('/robot_description')
        root = root_link(urdf)
        props = rospy.ServiceProxy('/gazebo/get_model_properties', GetModelProperties)(model_name='mybot')
        self.assertTrue(props.success, props.status_message)
        # Gazebo's links: the root body (every fixed link lumped in it) and the wheels.
        self.assertEqual(props.body_names, [root, 'left_wheel', 'right_wheel'])
        self.assertEqual(props.canonical_body_name, root)
        self.assertEqual(props.joint_names, ['left_wheel_hinge', 'right_wheel_hinge'])
        self.assertIn(root + '_fixed_joint_lump__chassis_collision', props.geom_names)
        self.assertFalse(props.is_static)
        self.assertTrue(rospy.ServiceProxy('/gazebo/get_model_properties', GetModelProperties)(
            model_name='ground_plane').is_static)
        self.assertFalse(rospy.ServiceProxy('/gazebo/get_model_properties', GetModelProperties)(
            model_name='nobody').success)
        get_joint = rospy.ServiceProxy('/gazebo/get_joint_properties', GetJointProperties)
        self.r.publish_for(0.3, 0.0, 0.5, 50)
        j = get_joint(joint_name='mybot::left_wheel_hinge')  # while it rolls at 0.3 m/s
        self.assertTrue(j.success, j.status_message)
        self.assertEqual(j.type, j.CONTINUOUS)
        self.assertGreater(j.rate[0], 1.0)
        self.r.drive(0.0, 0.0, 0.0)
        self.r.settle(0.5)  # stopped: joint_states and the service see the same wheel
        j = get_joint(joint_name='left_wheel_hinge')  # one model has it
        with self.r.lock:
            js = self.r.joints
        self.assertAlmostEqual(j.position[0], js.position[js.name.index('left_wheel_hinge')], delta=1e-3)
        self.assertLess(abs(j.rate[0]), 0.01)
        self.assertFalse(get_joint(joint_name='mybot::chassis_joint').success)  # fixed: lumped, as in Gazebo

    def test_set_link_state_moves_a_robot_by_its_root_body_and_refuses_wheels(self):
        get_state = rospy.ServiceProxy('/gazebo/get_model_state', GetModelState)
        set_link = rospy.ServiceProxy('/gazebo/set_link_state', SetLinkState)
        root = root_link(rospy.get_param('/robot_description'))
        z = get_state(model_name='mybot').pose.position.z
        state = LinkState(link_name='mybot::' + root)
        state.pose.position.x, state.pose.position.y, state.pose.position.z = -1.0, 0.5, z
        state.pose.orientation.w = 1.0
        res = set_link(link_state=state)
        self.assertTrue(res.success, res.status_message)
        p = get_state(model_name='mybot').pose.position
        self.assertAlmostEqual(p.x, -1.0, delta=1e-9)
        self.assertAlmostEqual(p.y, 0.5, delta=1e-9)
        # The topic, counted under lockstep: set in the period it was sent in.
        topic = self.r.ls.Publisher('/gazebo/set_link_state', LinkState)
        self.r.wait(lambda: topic.get_num_connections() > 0, 'the simulator on set_link_state')
        state.pose.position.x = 1.5
        topic.publish(state)
        self.r.settle(0.01)
        self.assertAlmostEqual(get_state(model_name='mybot').pose.position.x, 1.5, delta=0.002)
        for name, text in (('mybot::left_wheel', 'placed by its joints'), ('mybot::nothing', 'no link')):
            res = set_link(link_state=LinkState(link_name=name, pose=state.pose))
            self.assertFalse(res.success, name)
            self.assertIn(text, res.status_message)
        self.assertAlmostEqual(get_state(model_name='mybot').pose.position.x, 1.5, delta=0.002)

    def test_physics_properties_change_step_gravity_and_rate(self):
        get = rospy.ServiceProxy('/gazebo/get_physics_properties', GetPhysicsProperties)
        set_ = rospy.ServiceProxy('/gazebo/set_physics_properties', SetPhysicsProperties)
        before = get()
        self.assertTrue(before.success)
        self.assertEqual((before.time_step, before.max_update_rate, before.pause), (0.001, 0.0, False))
        self.assertEqual((before.gravity.x, before.gravity.y, before.gravity.z), (0.0, 0.0, -9.8))
        self.assertGreaterEqual(before.ode_config.sor_pgs_iters, 1)
        crate = ('<sdf version="1.6"><model name="floater"><link name="l"><inertial><mass>1</mass></inertial>'
                 '<collision name="c"><geometry><box><size>0.2 0.2 0.2</size></box></geometry></collision>'
                 '</link></model></sdf>')
        pose = Pose()
        pose.position.x, pose.position.y, pose.position.z, pose.orientation.w = 0.0, -2.0, 1.0, 1.0
        earth, weightless = Vector3(0.0, 0.0, -9.8), Vector3(0.0, 0.0, 0.0)

        def iters(n):
            return ODEPhysics(sor_pgs_iters=n)
        try:
            # Weightless, a crate stays where it is put; two-millisecond steps count half the states.
            res = set_(time_step=0.002, max_update_rate=0.0, gravity=weightless, ode_config=before.ode_config)
            self.assertTrue(res.success, res.status_message)
            self.assertTrue(rospy.ServiceProxy('/gazebo/spawn_sdf_model', SpawnModel)(
                model_name='floater', model_xml=crate, initial_pose=pose).success)
            with self.r.lock:
                t0, n0 = rospy.get_time(), self.states['model'][0]
            self.r.settle(0.5)
            with self.r.lock:
                t1, n1 = rospy.get_time(), self.states['model'][0]
            self.assertEqual(n1 - n0, round((t1 - t0) / 0.002))
            z = rospy.ServiceProxy('/gazebo/get_model_state', GetModelState)(model_name='floater').pose.position.z
            self.assertAlmostEqual(z, 1.0, delta=1e-6)
            now = get()
            self.assertEqual((now.time_step, now.gravity.z), (0.002, 0.0))
            # Refused, naming the field, and nothing changed: a step that does not divide the lockstep
            # period (10 ms), a NaN, no solver iterations.
            for kwargs, text in (({'time_step': 0.003}, 'lockstep period'),
                                 ({'time_step': float('nan')}, 'time_step'),
                                 ({'max_update_rate': -1.0}, 'max_update_rate')):
                args = dict(time_step=0.002, max_update_rate=0.0, gravity=earth, ode_config=before.ode_config)
                args.update(kwargs)
                res = set_(**args)
                self.assertFalse(res.success, kwargs)
                self.assertIn(text, res.status_message)
            res = set_(time_step=0.002, max_update_rate=0.0, gravity=earth, ode_config=iters(0))
            self.assertIn('sor_pgs_iters', res.status_message)
            self.assertEqual(get().gravity.z, 0.0)
        finally:  # the world as the other tests know it
            set_(time_step=0.001, max_update_rate=0.0, gravity=earth, ode_config=iters(before.ode_config.sor_pgs_iters))
            rospy.ServiceProxy('/gazebo/delete_model', DeleteModel)(model_name='floater')

    def test_an_sdf_model_with_joints_and_plugins_is_simulated_as_gazebo_does(self):
        """spawn_sdf_model of a flap hinged to a post anchored to the world, with gazebo_ros's joint
        state publisher: its joint moves, its plugin publishes, as in Gazebo (until 2026-12-01 its
        links were one rigid body and its plugin was not run)."""
        flap = ('<sdf version="1.6"><model name="flap">'
                '<link name="post"><pose>0 0 0.5 0 0 0</pose><collision name="c"><geometry><box>'
                '<size>0.05 0.05 1</size></box></geometry></collision></link>'
                '<link name="leaf"><pose>0.3 0 0.5 0 0 0</pose><inertial><mass>2</mass><inertia><ixx>0.1</ixx>'
                '<iyy>0.1</iyy><izz>0.1</izz></inertia></inertial><collision name="c"><geometry><box>'
                '<size>0.5 0.02 0.5</size></box></geometry></collision></link>'
                '<joint name="anchor" type="fixed"><parent>world</parent><child>post</child></joint>'
                '<joint name="hinge" type="revolute"><pose>-0.25 0 0 0 0 0</pose><parent>post</parent>'
                '<child>leaf</child><axis><xyz>0 0 1</xyz><dynamics><damping>0.5</damping></dynamics></axis></joint>'
                '<plugin name="js" filename="libgazebo_ros_joint_state_publisher.so"><jointName>hinge</jointName>'
                '<updateRate>50</updateRate></plugin></model></sdf>')
        pose = Pose()
        pose.position.x, pose.position.y, pose.orientation.w = -2.0, -2.0, 1.0
        res = rospy.ServiceProxy('/gazebo/spawn_sdf_model', SpawnModel)(
            model_name='flap', model_xml=flap, robot_namespace='flap', initial_pose=pose)
        self.assertTrue(res.success, res.status_message)
        try:
            props = rospy.ServiceProxy('/gazebo/get_model_properties', GetModelProperties)(model_name='flap')
            # Gazebo keeps an SDF model's fixed joint (a URDF's it lumps away).
            self.assertEqual((props.body_names, props.joint_names), (['post', 'leaf'], ['anchor', 'hinge']))
            self.assertEqual(props.geom_names, ['c', 'c'])  # the SDF's own collision names
            res = rospy.ServiceProxy('/gazebo/apply_joint_effort', ApplyJointEffort)(
                joint_name='flap::hinge', effort=2.0, start_time=rospy.Time(0), duration=rospy.Duration(0.5))
            self.assertTrue(res.success, res.status_message)
            self.r.settle(1.0)
            angle = rospy.ServiceProxy('/gazebo/get_joint_properties', GetJointProperties)(
                joint_name='flap::hinge').position[0]
            self.assertGreater(angle, 0.2)
            # The leaf turned about its hinge (-1.95, -2): its centre is still 0.25 m from it.
            leaf = rospy.ServiceProxy('/gazebo/get_link_state', GetLinkState)(link_name='flap::leaf')
            p = leaf.link_state.pose.position
            self.assertAlmostEqual(math.hypot(p.x + 1.95, p.y + 2.0), 0.25, delta=1e-6)
            post = rospy.ServiceProxy('/gazebo/get_link_state', GetLinkState)(link_name='flap::post')
            self.assertAlmostEqual(post.link_state.pose.position.x, -2.0, delta=1e-6)  # anchored
            self.r.release()  # a blocking wait: time moves meanwhile
            js = rospy.wait_for_message('/flap/joint_states', JointState, timeout=30)
            self.assertEqual(list(js.name), ['hinge'])
            self.assertGreater(js.position[0], 0.2)
        finally:
            rospy.ServiceProxy('/gazebo/delete_model', DeleteModel)(model_name='flap')

    def test_spawn_model_sets_initial_joint_positions(self):
        """spawn_model -J (set_model_configuration after the spawn, as gazebo_ros)."""
        turntable = os.path.join(os.path.dirname(os.path.abspath(__file__)), 'fixtures', 'turntable.urdf')
        self.r.release()  # the tool takes seconds to start
        try:
            p = subprocess.run(['rosrun', 'gazebo_ros', 'spawn_model', '-urdf', '-file', turntable, '-model', 'table',
                                '-y', '3', '-J', 'turn', '1.2'], capture_output=True, text=True, timeout=60)
            self.assertEqual(p.returncode, 0, p.stdout + p.stderr)
            j = rospy.ServiceProxy('/gazebo/get_joint_properties', GetJointProperties)(joint_name='table::turn')
            self.assertTrue(j.success, j.status_message)
            self.assertAlmostEqual(j.position[0], 1.2, delta=1e-6)  # nothing turns it about the vertical
            self.assertEqual(list(j.damping), [0.1])
            p = subprocess.run(['rosrun', 'gazebo_ros', 'spawn_model', '-urdf', '-file', turntable, '-model', 'table2',
                                '-y', '-3', '-J', 'turn', '4'], capture_output=True, text=True, timeout=60)
            self.assertEqual(p.returncode, 1)
            self.assertIn("beyond the limits [-3, 3] of joint 'turn'", p.stdout + p.stderr)
        finally:
            for name in ('table', 'table2'):
                rospy.ServiceProxy('/gazebo/delete_model', DeleteModel)(model_name=name)


    def test_performance_metrics_report_the_laser_at_its_rate(self):
        """/gazebo/performance_metrics: the real-time factor and each sensor, named as Gazebo names it
        (world::model::link::sensor, the link its body's), at its update rate in simulated time."""
        root = rospy.ServiceProxy('/gazebo/get_model_properties', GetModelProperties)(
            model_name='mybot').canonical_body_name
        reports = []
        sub = rospy.Subscriber('/gazebo/performance_metrics', PerformanceMetrics, reports.append)
        # Reports come at most 5 a wall second: time moves until four of them span a simulated second.
        def span():
            return reports[-1].header.stamp.to_sec() - reports[0].header.stamp.to_sec() if reports else 0.0
        end = time.monotonic() + WALL_TIMEOUT
        try:
            while (len(reports) < 4 or span() < 1.0) and time.monotonic() < end:
                self.r.settle(0.2)
        finally:
            sub.unregister()
        self.assertGreaterEqual(len(reports), 4, 'no four reports in %.0f s of wall time' % WALL_TIMEOUT)
        laser = 'default::mybot::%s::head_hokuyo_sensor' % root
        for m in reports:
            self.assertGreater(m.real_time_factor, 0.0)
            self.assertIn(laser, [s.name for s in m.sensors])
        # The laser's updates over the reports' span (each report counts since the one before).
        updates = 0.0
        for prev, m in zip(reports, reports[1:]):
            s = next(s for s in m.sensors if s.name == laser)
            updates += s.sim_update_rate * (m.header.stamp.to_sec() - prev.header.stamp.to_sec())
            self.assertEqual(s.fps, -1.0)  # not a camera
            # The same updates over the report's wall time: its sim rate times its real-time
            # factor. (Not > 0: on a loaded machine a report's window can hold less simulated time
            # than the laser's 25 ms period, and then no update; the gate at f640eca saw one.)
            self.assertAlmostEqual(s.real_update_rate, s.sim_update_rate * m.real_time_factor,
                                   delta=1e-9 * max(1.0, s.real_update_rate))
        self.assertGreaterEqual(span(), 1.0)
        self.assertAlmostEqual(updates / span(), 40.0, delta=1.0 / span())  # 40 Hz, within one update

    def test_link_and_joint_properties_as_gazebo_sets_them(self):
        """get/set_link_properties and set_joint_properties on a turntable: its plate's mass, the
        joint's motor (ODE's vel and fmax) and stops."""
        with open(os.path.join(os.path.dirname(os.path.abspath(__file__)), 'fixtures', 'turntable.urdf')) as f:
            urdf = f.read()
        pose = Pose()
        pose.position.y, pose.orientation.w = 3.0, 1.0
        res = rospy.ServiceProxy('/gazebo/spawn_urdf_model', SpawnModel)(model_name='table', model_xml=urdf,
                                                                          initial_pose=pose)
        self.assertTrue(res.success, res.status_message)
        get_link = rospy.ServiceProxy('/gazebo/get_link_properties', GetLinkProperties)
        set_link = rospy.ServiceProxy('/gazebo/set_link_properties', SetLinkProperties)
        set_joint = rospy.ServiceProxy('/gazebo/set_joint_properties', SetJointProperties)
        get_joint = rospy.ServiceProxy('/gazebo/get_joint_properties', GetJointProperties)
        try:
            plate = get_link(link_name='table::plate')
            self.assertTrue(plate.success, plate.status_message)
            self.assertEqual(plate.status_message, 'GetLinkProperties: got properties')
            self.assertAlmostEqual(plate.com.position.x, 0.1, delta=1e-6)
            self.assertEqual(plate.com.orientation.w, 1.0)
            self.assertAlmostEqual(plate.mass, 0.5, delta=1e-6)
            self.assertAlmostEqual(plate.izz, 0.004, delta=1e-6)
            self.assertTrue(plate.gravity_mode)

            # The joint's motor: 1 rad/s at up to 5 N m (ODE's erp is not applied: no error either).
            res = set_joint(joint_name='table::turn',
                            ode_joint_config=ODEJointProperties(fmax=[5.0], vel=[1.0], erp=[0.2]))
            self.assertTrue(res.success, res.status_message)
            self.r.settle(0.5)
            self.assertAlmostEqual(get_joint(joint_name='table::turn').rate[0], 1.0, delta=0.02)
            # A stop at 0.8 rad holds it there.
            res = set_joint(joint_name='table::turn', ode_joint_config=ODEJointProperties(hiStop=[0.8]))
            self.assertTrue(res.success, res.status_message)
            self.r.settle(1.0)
            self.assertAlmostEqual(get_joint(joint_name='table::turn').position[0], 0.8, delta=0.02)
            res = set_joint(joint_name='table::turn', ode_joint_config=ODEJointProperties(loStop=[1.0]))
            self.assertFalse(res.success)
            self.assertIn('is above hiStop[0]', res.status_message)

            # Twice the plate: the same motor still turns it; a NaN or a moved centre of mass is refused.
            res = set_link(link_name='table::plate', com=plate.com, gravity_mode=True, mass=1.0, ixx=2 * plate.ixx,
                           ixy=0.0, ixz=0.0, iyy=2 * plate.iyy, iyz=0.0, izz=2 * plate.izz)
            self.assertTrue(res.success, res.status_message)
            self.assertAlmostEqual(get_link(link_name='table::plate').mass, 1.0, delta=1e-6)
            res = set_link(link_name='table::plate', com=plate.com, gravity_mode=True, mass=float('nan'),
                           ixx=plate.ixx, iyy=plate.iyy, izz=plate.izz)
            self.assertFalse(res.success)
            self.assertIn('mass', res.status_message)
            moved = Pose()
            moved.position.x, moved.orientation.w = 0.3, 1.0
            res = set_link(link_name='table::plate', com=moved, gravity_mode=True, mass=1.0, ixx=plate.ixx,
                           iyy=plate.iyy, izz=plate.izz)
            self.assertFalse(res.success)
            self.assertIn("centre of mass", res.status_message)
            self.assertAlmostEqual(get_link(link_name='table::plate').mass, 1.0, delta=1e-6)
            self.assertFalse(get_link(link_name='table::nothing').success)
        finally:
            rospy.ServiceProxy('/gazebo/delete_model', DeleteModel)(model_name='table')


class RestTests(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.r = Robot(commands=False)
        cls.r.ready()

    def test_rest_ten_minutes(self):
        self.r.settle(2.0)
        x0, y0, _ = self.r.pose()
        # 600 s of sim time took 10 s of wall time idle; the deadline (within rest.test's 240 s
        # time-limit) is only there to fail a hung simulator, not to ask for a speed.
        self.r.settle(600.0, wall_timeout=200.0)
        x1, y1, _ = self.r.pose()
        self.assertLess(math.hypot(x1 - x0, y1 - y0), 0.001)


class WallTests(unittest.TestCase):
    """Spawned at the origin of mybot.world facing +x; the east wall's face is at x = 5.0."""

    @classmethod
    def setUpClass(cls):
        cls.r = Robot()
        cls.contacts = []  # counted, as the robot's topics: each message in its period
        cls.r.ls.Subscriber('/gazebo/model_contacts', ModelContacts, cls.contacts.append, queue_size=50)
        cls.tf = tf2_ros.Buffer()
        cls.listener = tf2_ros.TransformListener(cls.tf)
        cls.r.ready()

    def contacts_since(self, t):
        """The first /gazebo/model_contacts stamped at or after sim time t."""
        self.r.wait(lambda: any(c.header.stamp.to_sec() >= t for c in self.contacts), '/gazebo/model_contacts')
        return next(c for c in self.contacts if c.header.stamp.to_sec() >= t)

    def test_laser_range_to_wall(self):
        self.r.settle(0.5)
        contacts = self.contacts_since(self.r.now())
        self.assertEqual(contacts.model_name, 'mybot')
        self.assertEqual((contacts.contact_steps, contacts.first_time), (0, -1.0), 'resting on the ground is no contact')
        self.r.wait(lambda: self.r.scan is not None, 'scan')
        with self.r.lock:
            scan = self.r.scan
        x, y, th = self.r.pose()
        # Waited for period by period: a lookup's own timeout runs in sim time, which stands
        # while this node holds the period.
        self.r.wait(lambda: self.tf.can_transform('base_footprint', 'hokuyo', rospy.Time(0)), 'tf base_footprint -> hokuyo')
        tf = self.tf.lookup_transform('base_footprint', 'hokuyo', rospy.Time(0))
        hokuyo_x = tf.transform.translation.x
        stddev = 0.01
        mid = len(scan.ranges) // 2
        angle = scan.angle_min + mid * scan.angle_increment
        truth = (5.0 - (x + hokuyo_x)) / math.cos(th + angle)
        errs = [scan.ranges[i] - truth for i in (mid,)]
        self.assertLess(abs(errs[0]), 3 * stddev + 0.005, 'range %.4f vs %.4f' % (scan.ranges[mid], truth))
        self.assertEqual(len(scan.ranges), 720)
        self.assertAlmostEqual(scan.angle_increment, math.pi / 719, places=5)
        # Inside the closed room every beam hits something within range.
        self.assertTrue(all(scan.range_min <= r <= scan.range_max for r in scan.ranges))

    def test_zz_drive_into_wall_stops_at_wall(self):
        self.r.drive(100.0, 0.0, 6.0)  # absurd: limited by wheelTorque, stopped by the wall
        self.r.settle(1.0)
        x, y, th = self.r.pose()
        with self.r.lock:
            z = self.r.gt.pose.pose.position.z
            v = self.r.gt.twist.twist.linear
        self.assertTrue(all(math.isfinite(a) for a in (x, y, th, z)))
        # Chassis front is 0.2 m ahead of base_footprint; the wall face at 5.0.
        self.assertLess(x, 5.0 - 0.15)
        self.assertGreater(x, 4.0)
        self.assertLess(abs(z), 0.1)
        self.assertLess(math.hypot(v.x, v.y), 0.05)
        contacts = self.contacts_since(self.r.now())
        # Pushing for seconds: in contact for most of them (at rest afterwards it may just touch).
        self.assertEqual(contacts.first_model, 'wall_east', str(contacts))
        self.assertGreater(contacts.contact_time, 0.5, str(contacts))
        self.assertGreater(contacts.max_depth, 0.0)


class MultiRobotTests(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.r1 = Robot('robot1')
        cls.r2 = Robot('robot2')
        cls.r1.ready()
        cls.r2.ready()

    def test_no_crosstalk(self):
        # Both robots stand from time 0 (multi_robot.launch starts the world once robot2 is in);
        # they settle onto their wheels first: robot2 moves 0.77 mm in the 2 s from its spawn.
        self.r1.settle(2.0)
        a0 = self.r1.pose()
        b0 = self.r2.pose()
        self.assertAlmostEqual(a0[0], -1.0, delta=0.01)
        self.assertAlmostEqual(b0[0], 1.0, delta=0.01)
        h = self.r1.record(-0.5, 0.0, 2.0)  # robot1 backs away from robot2
        a, b, _ = Robot.window(h, 2.0, lambda m: abs(m.twist.twist.linear.x) > 1e-3)
        b1 = self.r2.pose()
        self.assertAlmostEqual(b.pose.pose.position.x - a.pose.pose.position.x, -1.0, delta=0.05)
        self.assertLess(math.hypot(b1[0] - b0[0], b1[1] - b0[1]), 1e-4)  # at rest: it moved 0 m
        with self.r1.lock:
            self.assertEqual(self.r1.odom.child_frame_id, 'robot1/base_footprint')
        self.r2.wait(lambda: self.r2.scan is not None, 'robot2 scan')
        with self.r2.lock:
            self.assertEqual(self.r2.scan.header.frame_id, 'robot2/hokuyo')
            # robot2 faces robot1 (yaw pi): its centre beam sees robot1, not the far wall.
            mid = self.r2.scan.ranges[len(self.r2.scan.ranges) // 2]
        self.assertLess(mid, 3.5)

    def test_zz_a_robots_noise_does_not_depend_on_the_others(self):
        """Each sensor draws from its own noise stream (~seed, the model, the plugin): a robot's
        first scan from a pose is the same whether or not another robot was spawned before it."""
        scans = []
        self.r1.ls.Subscriber('/probe/scan', LaserScan, scans.append)
        xml = rospy.get_param('/robot1/robot_description')
        spawn = rospy.ServiceProxy('/gazebo/spawn_urdf_model', SpawnModel)
        delete = rospy.ServiceProxy('/gazebo/delete_model', DeleteModel)

        def first_scan(others):
            names = others + ['probe']
            for k, name in enumerate(names):
                pose = Pose()
                pose.position.y = 1.5 if name == 'probe' else -1.5 - k
                pose.orientation.w = 1.0
                del scans[:]
                res = spawn(model_name=name, model_xml=xml, robot_namespace=name, initial_pose=pose)
                self.assertTrue(res.success, res.status_message)
            self.r1.wait(lambda: scans, 'the probe\'s first scan')
            ranges = scans[0].ranges
            for name in names:
                self.assertTrue(delete(model_name=name).success)
            return ranges

        alone = first_scan([])
        after_another = first_scan(['other'])
        diffs = sorted(abs(a - b) for a, b in zip(alone, after_another) if math.isfinite(a) and math.isfinite(b))
        self.assertGreater(len(diffs), len(alone) // 2)
        # A beam may see the other robot; the laser's noise (0.01 m) would move most of them.
        self.assertLess(diffs[len(diffs) // 2], 1e-4, 'median change %.4f m' % diffs[len(diffs) // 2])


class MalformedInputTests(unittest.TestCase):
    """Bad files make the tools exit non-zero naming the file and the element."""

    @classmethod
    def setUpClass(cls):
        cls.tmp = tempfile.mkdtemp()

    def write(self, name, text):
        p = os.path.join(self.tmp, name)
        with open(p, 'w') as f:
            f.write(text)
        return p

    def run_tool(self, args):
        p = subprocess.run(['rosrun', 'mybot_gazebo_lite'] + args, stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, timeout=60, universal_newlines=True)
        return p.returncode, p.stdout

    def test_bad_sdf_world(self):
        path = self.write('bad.world', '<sdf version="1.6"><world name="w"><model name="m"><static>true</static>'
                          '<link name="l"><collision name="c"><geometry><box><size>1 x 1</size></box>'
                          '</geometry></collision></link></model></world></sdf>')
        rc, out = self.run_tool(['gazebo_lite', '__name:=bad_world_sim', '_world:=' + path])
        self.assertNotEqual(rc, 0)
        self.assertIn(path, out)
        self.assertIn("<model name='m'>", out)
        self.assertIn('<size>', out)

    def test_bad_yaml_world(self):
        path = self.write('bad.yaml', 'image: nothing.pgm\nresolution: -1\norigin: [0, 0, 0]\n')
        rc, out = self.run_tool(['gazebo_lite', '__name:=bad_yaml_sim', '_world:=' + path])
        self.assertNotEqual(rc, 0)
        self.assertIn(path, out)
        self.assertIn("'resolution'", out)

    def test_bad_urdf(self):
        path = self.write('bad.urdf', '<robot name="r"><link name="a"><inertial><mass value="abc"/>'
                          '<inertia ixx="1" iyy="1" izz="1"/></inertial></link></robot>')
        rc, out = self.run_tool(['spawn_model', '-urdf', '-file', path, '-model', 'bad', '-timeout', '30'])
        self.assertNotEqual(rc, 0)
        self.assertIn(path, out)
        self.assertIn("link 'a'", out)
        self.assertIn('mass', out)

    def test_parameter_of_the_wrong_type_is_named(self):
        for param, value in (('max_step_size', 'abc'), ('real_time_factor', 'fast'), ('solver_iterations', '2.5')):
            # One node name per case: a private parameter outlives its node on the master.
            name = 'bad_%s_sim' % param
            rc, out = self.run_tool(['gazebo_lite', '__name:=' + name, '_%s:=%s' % (param, value)])
            self.assertNotEqual(rc, 0, param)
            self.assertIn('parameter /%s/%s' % (name, param), out)

    def test_misspelled_unsimulated_or_unknown_parameters_are_warned_naming_them(self):
        logs = []
        sub = rospy.Subscriber('/rosout', Log, lambda m: logs.append(m.msg))
        path = self.write('typo.urdf', '<robot name="r"><link name="base"><inertial><mass value="1"/>'
                          '<inertia ixx="0.1" iyy="0.1" izz="0.1"/></inertial></link>'
                          '<link name="l"><inertial><mass value="0.1"/><inertia ixx="0.001" iyy="0.001" izz="0.001"/>'
                          '</inertial></link><link name="r"><inertial><mass value="0.1"/>'
                          '<inertia ixx="0.001" iyy="0.001" izz="0.001"/></inertial></link>'
                          '<joint name="lj" type="continuous"><parent link="base"/><child link="l"/></joint>'
                          '<joint name="rj" type="continuous"><parent link="base"/><child link="r"/></joint>'
                          '<gazebo><plugin name="dd" filename="libgazebo_ros_diff_drive.so"><leftJoint>lj</leftJoint>'
                          '<rightJoint>rj</rightJoint><wheelSeperation>0.3</wheelSeperation></plugin></gazebo>'
                          # A Gazebo parameter gazebo_lite knows and does not simulate, and a <gazebo> tag it
                          # does not know: each warned once, naming it.
                          '<gazebo><plugin name="imu" filename="libgazebo_ros_imu.so"><bodyName>base</bodyName>'
                          '<serviceName>imu_service</serviceName><rpyOffset>0 0 0.1</rpyOffset></plugin></gazebo>'
                          '<gazebo reference="base"><fooBar>1</fooBar></gazebo>'
                          # Jackal's and Husky's descriptions give hector's IMU a heading error it
                          # does not read (its tags are yaw*): warned, as Gazebo would ignore it.
                          '<gazebo><plugin name="himu" filename="libhector_gazebo_ros_imu.so">'
                          '<headingDrift>0.005</headingDrift></plugin></gazebo></robot>')
        rc, out = self.run_tool(['spawn_model', '-urdf', '-file', path, '-model', 'typo', '-timeout', '30'])
        self.assertEqual(rc, 0, out)
        wants = [("plugin 'dd'", 'unknown parameter <wheelSeperation> ignored (did you mean <wheelSeparation>?)'),
                 ("plugin 'imu'", 'parameter <serviceName> is not simulated by gazebo_lite; ignored'),
                 ("plugin 'imu' on link 'base'", '<rpyOffset> 0 0 0.1 is not simulated by gazebo_lite; ignored'),
                 ("model 'typo'", "<gazebo reference='base'> <fooBar>: unknown tag ignored"),
                 ("plugin 'himu'", 'unknown parameter <headingDrift> ignored')]
        warned = lambda: all(any(a in m and b in m for m in logs) for a, b in wants)  # noqa: E731
        deadline = time.monotonic() + WALL_TIMEOUT
        while not warned() and time.monotonic() < deadline:
            time.sleep(0.05)
        sub.unregister()
        for a, b in wants:
            self.assertTrue(any(a in m and b in m for m in logs), (a, b, logs))

    # A robot of one link (and `child`, a second one on joint `j` of `joint_type`) with `plugin`.
    LINK = '<link name="%s"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1"/></inertial></link>'

    def assert_spawn_refused(self, model, plugin, says, joint_type=None):
        """Spawning the robot with `plugin` (its <plugin> element) fails, naming each of `says`."""
        body = self.LINK % 'a'
        if joint_type:
            body += self.LINK % 'b' + ('<joint name="j" type="%s"><parent link="a"/><child link="b"/></joint>'
                                       % joint_type)
        path = self.write(model + '.urdf', '<robot name="r">%s<gazebo>%s</gazebo></robot>' % (body, plugin))
        rc, out = self.run_tool(['spawn_model', '-urdf', '-file', path, '-model', model, '-timeout', '30'])
        self.assertNotEqual(rc, 0, model)
        for phrase in says:
            self.assertIn(phrase, out)

    def test_bad_plugin_parameter(self):
        self.assert_spawn_refused('badp', '<plugin name="gt" filename="libgazebo_ros_p3d.so"><topicName>gt</topicName>'
                                  '<updateRate>fast</updateRate><bodyName>a</bodyName></plugin>',
                                  ('<updateRate>', 'libgazebo_ros_p3d.so'))

    def test_a_negative_gaussian_noise_is_named(self):
        """A deviation below 0 is a mistake (gazebo_ros would square it away): refused, naming it."""
        for lib in ('libgazebo_ros_p3d.so', 'libgazebo_ros_imu.so', 'libgazebo_ros_ft_sensor.so'):
            self.assert_spawn_refused('noise_' + lib.split('_')[-1][:-3],
                                      '<plugin name="n" filename="%s"><topicName>n</topicName><bodyName>b</bodyName>'
                                      '<jointName>j</jointName><gaussianNoise>-0.1</gaussianNoise></plugin>' % lib,
                                      ('<gaussianNoise>', 'must be >= 0', lib), 'continuous')

    def test_bad_hector_error_model_is_named(self):
        """hector's per-axis errors are three numbers: two are refused naming the tag; a negative
        spread too."""
        for tag, value, message in (('accelDrift', '0.1 0.1', 'expected 3 numbers'),
                                    ('rateGaussianNoise', '0 0 -0.1', 'must be >= 0')):
            self.assert_spawn_refused('bad_' + tag, '<plugin name="imu" filename="libhector_gazebo_ros_imu.so">'
                                      '<%s>%s</%s></plugin>' % (tag, value, tag),
                                      ('<%s>' % tag, message, 'libhector_gazebo_ros_imu.so'))

    def test_a_plugin_on_a_fixed_joint_is_told_it_is_lumped(self):
        """A force-torque sensor on a fixed joint its <gazebo reference> does not keep: Gazebo
        lumps the joint away, and so does gazebo_lite; the error says so, and how to keep it."""
        self.assert_spawn_refused('ft_fixed', '<plugin name="ft" filename="libgazebo_ros_ft_sensor.so">'
                                  '<jointName>j</jointName><topicName>ft</topicName></plugin>',
                                  ('<jointName>', "joint 'j' is fixed", '<preserveFixedJoint>',
                                   'libgazebo_ros_ft_sensor.so'), 'fixed')

    def assert_service_refuses(self, model, body, says):
        """/gazebo/spawn_urdf_model refuses a robot of link 'a' and `body`, naming each of `says` (the
        service, not spawn_model: a tool's start costs 2-5 s a case in the gate)."""
        rospy.wait_for_service('/gazebo/spawn_urdf_model', timeout=WALL_TIMEOUT)
        res = rospy.ServiceProxy('/gazebo/spawn_urdf_model', SpawnModel)(
            model_name=model, model_xml='<robot name="r">%s%s</robot>' % (self.LINK % 'a', body),
            reference_frame='world')
        self.assertFalse(res.success, model)
        for phrase in says:
            self.assertIn(phrase, res.status_message, model)

    def test_a_laser_with_absurd_samples_or_angles_is_named(self):
        """An absurd ray count (it was turned into an int: undefined, then a terabyte of beams) and an
        angle span that is not finite are refused, naming the tag (found by scripts/fuzz --only plugin)."""
        laser = ('<gazebo reference="a"><sensor type="ray" name="l"><ray><scan><horizontal><samples>%s</samples>'
                 '<min_angle>-%s</min_angle><max_angle>%s</max_angle></horizontal></scan><range><min>0.1</min>'
                 '<max>5</max></range></ray><plugin name="l" filename="libgazebo_ros_laser.so"><topicName>scan'
                 '</topicName></plugin></sensor></gazebo>')
        for model, samples, angle, says in (('samples_1e308', '1e308', '1', 'whole numbers of samples'),
                                            ('samples_half', '2.5', '1', 'whole numbers of samples'),
                                            ('span_inf', '10', '1e308', 'max_angle - min_angle must be finite')):
            self.assert_service_refuses(model, laser % (samples, angle, angle), ("plugin 'l'", '<ray/scan', says))

    def test_two_message_types_on_one_topic_or_a_bad_topic_name_are_named(self):
        """roscpp refuses a second message type on a topic (an Odometry and an Imu both on 'gt'), and
        the plugin would publish nothing: the spawn is refused naming the plugin and the tag. A name
        roscpp cannot take is named the same way."""
        p3d = ('<gazebo><plugin name="gt" filename="libgazebo_ros_p3d.so"><topicName>gt</topicName><bodyName>a'
               '</bodyName>%s</plugin></gazebo>')
        imu = ('<gazebo><plugin name="imu" filename="libgazebo_ros_imu.so"><topicName>%s</topicName><bodyName>a'
               '</bodyName></plugin></gazebo>')
        self.assert_service_refuses('two_types', p3d % '' + imu % 'gt',
                                    ("plugin 'imu'", '<topicName>', "topic '/gt' is already published with another "
                                     'message type than sensor_msgs/Imu'))
        self.assert_service_refuses('bad_name', imu % 'a b', ("plugin 'imu'", '<topicName>', "'a b' is not a ROS name"))
        self.assert_service_refuses('bad_ns', p3d % '<robotNamespace>a b</robotNamespace>',
                                    ("plugin 'gt'", "<robotNamespace> 'a b' is not a ROS name"))

    def test_a_joint_mimicking_itself_is_named(self):
        self.assert_spawn_refused('mimic_self', '<plugin name="m" filename="libroboticsgroup_gazebo_mimic_joint_plugin.so">'
                                  '<joint>j</joint><mimicJoint>j</mimicJoint></plugin>',
                                  ('<mimicJoint>', 'a joint cannot mimic itself',
                                   'libroboticsgroup_gazebo_mimic_joint_plugin.so'), 'continuous')


class BadPoseTests(unittest.TestCase):
    """Non-finite or absurd poses never enter running state: refused naming the field, and the
    model's ground truth stays what it was."""

    BOX = ('<robot name="box"><link name="a"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1"/>'
           '</inertial><collision><geometry><box size="0.2 0.2 0.2"/></geometry></collision></link></robot>')

    @classmethod
    def setUpClass(cls):
        for s in ('/gazebo/spawn_urdf_model', '/gazebo/set_model_state', '/gazebo/get_model_state'):
            rospy.wait_for_service(s, timeout=WALL_TIMEOUT)
        cls.spawn = rospy.ServiceProxy('/gazebo/spawn_urdf_model', SpawnModel)
        cls.set_state = rospy.ServiceProxy('/gazebo/set_model_state', SetModelState)
        cls.get_state = rospy.ServiceProxy('/gazebo/get_model_state', GetModelState)
        pose = Pose()
        pose.position.x, pose.position.y, pose.position.z = 1.0, 2.0, 0.1
        pose.orientation.w = 1.0
        res = cls.spawn(model_name='good_box', model_xml=cls.BOX, initial_pose=pose)
        assert res.success, res.status_message

    def spawn_with(self, name, field, value):
        pose = Pose()
        pose.orientation.w = 1.0
        obj, attr = field.split('.')
        setattr(getattr(pose, obj), attr, value)
        return self.spawn(model_name=name, model_xml=self.BOX, initial_pose=pose)

    def test_spawn_nan_position_refused(self):
        res = self.spawn_with('nan_box', 'position.x', float('nan'))
        self.assertFalse(res.success)
        self.assertIn('initial_pose.position.x is nan', res.status_message)
        self.assertFalse(self.get_state(model_name='nan_box').success)  # no such model

    def test_spawn_inf_orientation_refused(self):
        res = self.spawn_with('inf_box', 'orientation.z', float('inf'))
        self.assertFalse(res.success)
        self.assertIn('initial_pose.orientation.z is inf', res.status_message)

    def test_spawn_absurd_position_refused(self):
        res = self.spawn_with('far_box', 'position.y', 1e30)
        self.assertFalse(res.success)
        self.assertIn('initial_pose.position.y is 1e+30', res.status_message)

    def check_set_refused(self, field, value, message):
        before = self.get_state(model_name='good_box').pose.position
        m = ModelState(model_name='good_box')
        m.pose.position.x, m.pose.position.y, m.pose.position.z = 5.0, 5.0, 0.1
        m.pose.orientation.w = 1.0
        part, sub, attr = field.split('.')
        setattr(getattr(getattr(m, part), sub), attr, value)
        res = self.set_state(model_state=m)
        self.assertFalse(res.success)
        self.assertIn(message, res.status_message)
        after = self.get_state(model_name='good_box').pose.position
        for a in ('x', 'y', 'z'):
            self.assertTrue(math.isfinite(getattr(after, a)))
        self.assertAlmostEqual(after.x, before.x, delta=0.05)  # not moved to (5, 5)
        self.assertAlmostEqual(after.y, before.y, delta=0.05)

    def test_set_model_state_nan_position_refused(self):
        self.check_set_refused('pose.position.y', float('nan'), 'model_state.pose.position.y is nan')

    def test_set_model_state_absurd_position_refused(self):
        self.check_set_refused('pose.position.x', -1e30, 'model_state.pose.position.x is -1e+30')

    def test_set_model_state_nan_twist_refused(self):
        self.check_set_refused('twist.angular.z', float('nan'), 'model_state.twist.angular.z is nan')


class WorldRobotTests(unittest.TestCase):
    """fixtures/flap.world: a flap hinged to a post anchored to the world, with gazebo_ros's joint
    state publisher, in the world file itself."""

    def test_a_world_files_model_with_joints_is_a_robot(self):
        rospy.wait_for_service('/gazebo/get_model_properties', timeout=WALL_TIMEOUT)
        props = rospy.ServiceProxy('/gazebo/get_model_properties', GetModelProperties)(model_name='flap')
        self.assertTrue(props.success, props.status_message)
        self.assertEqual((props.body_names, props.joint_names), (['post', 'leaf'], ['anchor', 'hinge']))
        anchor = rospy.ServiceProxy('/gazebo/get_joint_properties', GetJointProperties)(joint_name='flap::anchor')
        self.assertTrue(anchor.success, anchor.status_message)
        self.assertEqual((anchor.type, list(anchor.position)), (GetJointPropertiesResponse.FIXED, [0.0]))
        js = rospy.wait_for_message('/flap/joint_states', JointState, timeout=WALL_TIMEOUT)
        self.assertEqual(list(js.name), ['hinge'])
        res = rospy.ServiceProxy('/gazebo/apply_joint_effort', ApplyJointEffort)(
            joint_name='flap::hinge', effort=2.0, start_time=rospy.Time(0), duration=rospy.Duration(0.5))
        self.assertTrue(res.success, res.status_message)
        t0 = rospy.get_time()
        end = time.monotonic() + WALL_TIMEOUT
        while rospy.get_time() < t0 + 1.0 and time.monotonic() < end:
            time.sleep(0.01)  # the world runs on its own: nothing here takes part in lockstep
        angle = rospy.ServiceProxy('/gazebo/get_joint_properties', GetJointProperties)(joint_name='hinge').position[0]
        self.assertGreater(angle, 0.2)
        post = rospy.ServiceProxy('/gazebo/get_link_state', GetLinkState)(link_name='flap::post')
        self.assertAlmostEqual(post.link_state.pose.position.x, -2.0, delta=1e-6)  # anchored where the file put it

    def test_a_nested_models_plugin_names_its_own_joints(self):
        """my_robot's nested mast has its own joint_state_publisher naming its joint 'pan', as Gazebo
        resolves names in the plugin's model; the robot's joint is 'mast::pan'."""
        js = rospy.wait_for_message('/my_robot/joint_states', JointState, timeout=WALL_TIMEOUT)
        self.assertEqual(list(js.name), ['pan'])
        res = rospy.ServiceProxy('/gazebo/apply_joint_effort', ApplyJointEffort)(
            joint_name='my_robot::mast::pan', effort=0.01, start_time=rospy.Time(0), duration=rospy.Duration(0.2))
        self.assertTrue(res.success, res.status_message)
        end = time.monotonic() + WALL_TIMEOUT
        while time.monotonic() < end:  # the world runs on its own: nothing here takes part in lockstep
            js = rospy.wait_for_message('/my_robot/joint_states', JointState, timeout=WALL_TIMEOUT)
            if js.position[0] > 0.1:
                break
        self.assertGreater(js.position[0], 0.1)

    def test_model_states_list_the_world_files_models_in_its_order(self):
        """As Gazebo lists them: the file's order, robots and rigid models alike (until 2026-12-01 its
        robots came after its rigid models)."""
        states = rospy.wait_for_message('/gazebo/model_states', ModelStates, timeout=WALL_TIMEOUT)
        self.assertEqual(list(states.name), ['ground_plane', 'flap', 'my_robot', 'wall'])

    def test_a_laser_model_included_in_a_robot_rides_it_and_scans(self):
        """my_robot includes model://tutorial_laser (test/fixtures/models) 0.2 m ahead of and above its
        frame, fixed to its chassis by a joint to 'tutorial_laser::link', as Gazebo's tutorial robot
        attaches its hokuyo; the laser's own plugin publishes what it sees of the wall 2 m ahead."""
        scan = rospy.wait_for_message('/tutorial/scan', LaserScan, timeout=WALL_TIMEOUT)
        self.assertEqual((scan.header.frame_id, len(scan.ranges)), ('laser_link', 90))
        # The middle beams, 0.0176 rad either side of straight ahead, from the sensor 0.21 m ahead of
        # the robot's frame to the wall's face at 1.9 m.
        for r in scan.ranges[44:46]:
            self.assertAlmostEqual(r, 1.69 / math.cos(1.57 / 89), delta=0.005)
        laser = rospy.ServiceProxy('/gazebo/get_link_state', GetLinkState)(link_name='my_robot::tutorial_laser::link')
        self.assertTrue(laser.success, laser.status_message)
        p = laser.link_state.pose.position
        self.assertAlmostEqual(p.x, 0.2, delta=1e-3)
        self.assertAlmostEqual(p.z, 0.2, delta=2e-3)
        # As Gazebo lists an SDF model: its own links and joints (the fixed ones too), its included
        # and nested models as child models; a link fixed to another is still its own.
        props = rospy.ServiceProxy('/gazebo/get_model_properties', GetModelProperties)(model_name='my_robot')
        self.assertEqual((props.body_names, props.joint_names, props.child_model_names),
                         (['chassis'], ['laser_joint', 'mast_joint'], ['tutorial_laser', 'mast']))
        link = rospy.ServiceProxy('/gazebo/get_link_properties', GetLinkProperties)(
            link_name='my_robot::tutorial_laser::link')
        self.assertTrue(link.success, link.status_message)
        self.assertAlmostEqual(link.mass, 0.1, places=9)
        self.assertAlmostEqual(link.ixx, 0.0001, places=12)


SUITES = {'bad_pose': BadPoseTests, 'drive': DriveTests, 'states': StatesTests, 'rest': RestTests, 'wall': WallTests, 'multi': MultiRobotTests, 'malformed': MalformedInputTests,
          'world_robots': WorldRobotTests}

if __name__ == '__main__':
    rospy.init_node('sim_test', anonymous=True)
    suite = rospy.get_param('~suite')
    rostest.rosrun('mybot_gazebo_lite', 'sim_' + suite, SUITES[suite], sys.argv)
