"""gopigo_driver: the thin ROS node around DriverCore.

Subscribes lwheel_angular_vel_motor / rwheel_angular_vel_motor (std_msgs/Float32,
rad/s), publishes joint_states (sensor_msgs/JointState) and battery_voltage
(std_msgs/Float32). Safety stops: stale commands (ROS time), shutdown, any
exception in the loop, an unreachable master, and a wall-clock net for a stalled clock.

In a lockstep simulation (gopigo.launch lockstep:=true, simulated motors) the driver takes part
(mybot_lockstep): the motors are integrated period by period in simulated time, so a drive gives
the same wheel angles on an idle and on a busy machine. The wall-clock net is off there: the
clock stands whenever a participant is slow, and simulated motors do not turn while it stands.
"""
import sys
import threading
import time
import xmlrpc.client

import rosgraph
import rospy
from sensor_msgs.msg import JointState
from std_msgs.msg import Float32

from mybot_lockstep import lockstep_requested, participant

from .config import ConfigError, HardwareError, create_backend, read_config
from .driver import LEFT, RIGHT, DriverCore


def _rospy_log(level, msg):
    {"debug": rospy.logdebug, "info": rospy.loginfo, "warn": rospy.logwarn,
     "error": rospy.logerr}.get(level, rospy.loginfo)(msg)


class _TimeoutTransport(xmlrpc.client.Transport):
    """XML-RPC without the default infinite timeout: a cut link must not hang the check."""

    def __init__(self, timeout):
        super().__init__()
        self._timeout = timeout

    def make_connection(self, host):
        conn = super().make_connection(host)
        conn.timeout = self._timeout
        return conn


class DriverNode:
    def __init__(self, cfg, core):
        self.cfg = cfg
        self.core = core
        self._last_cmd_wall = None
        self._last_ros_time = 0.0
        self._exit = threading.Event()
        self.ls = participant()
        pub = self.ls.Publisher
        self.js_pub = pub("joint_states", JointState, queue_size=10)
        self.batt_pub = rospy.Publisher("battery_voltage", Float32, queue_size=1)
        self.enc_pubs = None
        if cfg.publish_enc:
            self.enc_pubs = (pub("lwheel_angular_vel_enc", Float32, queue_size=10),
                             pub("rwheel_angular_vel_enc", Float32, queue_size=10))
        # Simulated backend only: the model's true wheel angles/speeds (unquantised),
        # the ground truth tests and benchmarks compare against; effort = motor command.
        self.truth_pub = None
        if hasattr(core.backend, "true_state"):
            self.truth_pub = pub("~sim_truth", JointState, queue_size=10)
        self.joint_state = JointState()
        self.joint_state.name = [cfg.left_joint, cfg.right_joint]
        # A queue of a few: under lockstep every command of a period is waited for and handled.
        self.ls.Subscriber("lwheel_angular_vel_motor", Float32, lambda m: self._on_cmd(m, LEFT), queue_size=5)
        self.ls.Subscriber("rwheel_angular_vel_motor", Float32, lambda m: self._on_cmd(m, RIGHT), queue_size=5)
        self._next_battery = 0.0

    def _on_cmd(self, msg, wheel):
        self._last_cmd_wall = time.monotonic()
        t = rospy.get_rostime().to_sec()
        written = self.core.stops_written
        if self.core.command(wheel, msg.data, t) and self.core.stops_written != written:
            self._publish_truth(rospy.Time.from_sec(t))  # a stop written on receipt

    # ---- watchdog thread (wall clock: it watches the network and the clock itself)
    def _watchdog(self):
        period = 0.1
        master = None
        if self.cfg.master_check_period > 0:
            master = xmlrpc.client.ServerProxy(rosgraph.get_master_uri(),
                                               transport=_TimeoutTransport(min(1.0, self.cfg.master_check_period)))
        next_master_check = time.monotonic()
        while not self._exit.wait(period):
            now = time.monotonic()
            try:
                if (not self.ls.active and self._last_cmd_wall is not None and not self.core.stopped
                        and now - self._last_cmd_wall > self.cfg.wall_timeout):
                    self.core.emergency_stop("no command for %.1f s of wall-clock time" % self.cfg.wall_timeout,
                                             self._last_ros_time)
                if master is not None and now >= next_master_check:
                    next_master_check = now + self.cfg.master_check_period
                    try:
                        master.getPid(rospy.get_name())
                        self.core.release()
                    except Exception as e:  # socket.timeout, ConnectionRefusedError, OSError
                        self.core.inhibit("ROS master %s unreachable (%s)" % (rosgraph.get_master_uri(), e),
                                          self._last_ros_time)
            except Exception as e:  # never let the watchdog die silently
                rospy.logerr("watchdog: %s" % e)

    # ---- main loop --------------------------------------------------------
    def _publish(self, state):
        js = self.joint_state
        js.header.stamp = rospy.Time.from_sec(state.stamp)
        js.position = list(state.positions)
        js.velocity = list(state.velocities)
        self.js_pub.publish(js)
        self._publish_truth(js.header.stamp)
        if self.enc_pubs is not None:
            self.enc_pubs[0].publish(Float32(state.velocities[0]))
            self.enc_pubs[1].publish(Float32(state.velocities[1]))

    def _publish_truth(self, stamp):
        if self.truth_pub is None:
            return
        truth = JointState()
        truth.header.stamp = stamp
        truth.name = self.joint_state.name
        with self.core.lock:  # the loop and the command callbacks both publish it
            truth.position, truth.velocity = (list(x) for x in self.core.backend.true_state())
            truth.effort = [float(c) for c in self.core.backend.last_commands]  # motor commands applied
        self.truth_pub.publish(truth)

    def _battery(self, t):
        if self.cfg.battery_rate <= 0 or t < self._next_battery:
            return
        self._next_battery = t + 1.0 / self.cfg.battery_rate
        v = self.core.battery_voltage()
        if v is not None:
            self.batt_pub.publish(Float32(v))

    def _cycle(self, t):
        self._last_ros_time = t
        try:
            state = self.core.step(t)
            if state is not None:
                self._publish(state)
            self._battery(t)
        except Exception as e:  # a hardware glitch must stop the wheels, not the node
            rospy.logerr_throttle(1.0, "gopigo_driver loop error, motors stopped: %r" % e)
            try:
                self.core.emergency_stop("exception: %r" % e, t)
            except Exception as e2:
                rospy.logerr_throttle(1.0, "gopigo_driver: stopping the motors failed too: %r" % e2)

    def _time_went_back(self):
        self.core.emergency_stop("ROS time moved backwards", None)
        self._next_battery = 0.0

    def spin(self):
        watchdog = threading.Thread(target=self._watchdog, name="gopigo_watchdog", daemon=True)
        watchdog.start()
        period = 1.0 / self.cfg.rate
        next_tick = None
        last_t = None
        try:
            while not rospy.is_shutdown():
                t = rospy.get_rostime().to_sec()
                if last_t is not None and t < last_t:
                    # Under lockstep the sleep below returns instead of raising.
                    self._time_went_back()
                    next_tick = None
                last_t = t
                if next_tick is None or t >= next_tick:
                    self._cycle(t)
                    next_tick = t + period if next_tick is None or t - next_tick > period else next_tick + period
                else:
                    self.core.check_timeout(t)
                # Wake for the next cycle, or exactly when the commands go stale,
                # so a stop is never late by up to a loop period.
                wake = next_tick
                deadline = self.core.deadline()
                if deadline is not None and deadline < wake:
                    wake = deadline + 1e-3
                try:
                    self.ls.sleep(max(0.0, wake - rospy.get_rostime().to_sec()))
                except rospy.ROSTimeMovedBackwardsException:
                    self._time_went_back()
                    next_tick = None
                    last_t = None
        except rospy.ROSInterruptException:
            pass
        finally:
            self._exit.set()


def main(argv=None):
    rospy.init_node("gopigo_driver")
    try:
        cfg = read_config(lambda name, default: rospy.get_param("~" + name, default))
        if cfg.gopigo_on and lockstep_requested():
            raise ConfigError("~gopigo_on is true (real motors) but /lockstep is on: a simulation's clock "
                              "must not pace real motors; lockstep is for the simulated backend only")
        backend = create_backend(cfg, _rospy_log)
    except (ConfigError, HardwareError) as e:
        rospy.logfatal("gopigo_driver: %s" % e)
        return 2
    core = DriverCore(backend, cfg.cmd_timeout, cfg.velocity_window, _rospy_log)
    # Belt and braces: whichever way the process ends, the motors get a stop.
    rospy.on_shutdown(core.shutdown)
    try:
        DriverNode(cfg, core).spin()
    except Exception as e:
        rospy.logfatal("gopigo_driver: unexpected error, motors stopped: %s" % e)
        core.shutdown()
        raise
    core.shutdown()
    return 0


if __name__ == "__main__":
    sys.exit(main())
