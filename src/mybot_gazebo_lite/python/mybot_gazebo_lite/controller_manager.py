"""Client side of gazebo_lite's controller_manager: what `spawner` and `controller_manager`
(the scripts, with controller_manager's command lines) do with its services."""

import threading
import time

import rosgraph
import rospy
from rosgraph_msgs.msg import Log

from controller_manager_msgs.srv import (ListControllers, ListControllerTypes, LoadController,
                                         ReloadControllerLibraries, SwitchController, UnloadController)
from mybot_lockstep import publisher_has_link

STRICT = 2
BEST_EFFORT = 1
# How long a failed call waits for the manager's log line saying why (wall seconds): it comes
# through rosout within milliseconds; past this the error says where to look instead.
REASON_TIMEOUT = 5.0


class ControllerManagerError(RuntimeError):
    """A call that failed; the message says which controller and why."""


class ControllerManager:
    """The services under <namespace>/controller_manager/."""

    def __init__(self, namespace=None):
        ns = rospy.get_namespace() if namespace is None else namespace
        if not ns.endswith("/"):
            ns += "/"
        if not ns.startswith("/"):
            ns = rospy.get_namespace() + ns
        self.prefix = ns + "controller_manager/"
        self._proxies = {}
        # controller_manager_msgs' replies say only ok or not; the manager logs why (as upstream's
        # does, with ROS_ERROR), after the service's name. Read from the manager's own /rosout
        # publication: rostest, unlike roslaunch, runs no rosout node to aggregate it.
        self._reasons = []
        self._reason_seen = threading.Condition()
        self._log = None
        self._manager = None

    def wait(self, timeout):
        """Waits for the manager (wall seconds; None = forever). False when it did not appear."""
        try:
            rospy.wait_for_service(self.prefix + "load_controller", timeout=timeout)
            return True
        except rospy.ROSException:
            return False

    def _call(self, service, srv, **fields):
        if service not in self._proxies:
            self._proxies[service] = rospy.ServiceProxy(self.prefix + service, srv)
        try:
            return self._proxies[service](**fields)
        except rospy.ServiceException as e:
            raise ControllerManagerError("%s%s: %s" % (self.prefix, service, e))

    def _on_log(self, m):
        if m.level >= Log.WARN and m.msg.startswith(self.prefix) and m.name == self._manager:
            with self._reason_seen:
                self._reasons.append(m.msg)
                self._reason_seen.notify_all()

    def _reason(self, service, first):
        """The manager's log line for a failed call to `service`, or None. `first`: how many
        lines were seen before the call."""
        head = self.prefix + service + ": "
        deadline = time.monotonic() + REASON_TIMEOUT
        with self._reason_seen:
            while True:
                found = [r for r in self._reasons[first:] if r.startswith(head)]
                left = deadline - time.monotonic()
                if found or left <= 0 or rospy.is_shutdown():
                    return found[-1] if found else None
                self._reason_seen.wait(min(left, 0.1))

    def _listen_to_manager(self, service):
        """Subscribes to /rosout and waits until connected to the manager node's publication: a
        line it logs before that is not seen."""
        master = rosgraph.Master(rospy.get_name())
        try:
            _, _, services = master.getSystemState()
            self._manager = next(nodes[0] for name, nodes in services if name == self.prefix + service)
            uri = master.lookupNode(self._manager)
        except (StopIteration, rosgraph.MasterException, OSError):
            return
        self._log = rospy.Subscriber("/rosout", Log, self._on_log, queue_size=100)
        # Once the manager counts the link (its getBusInfo), every line it logs reaches us.
        _wait_until(lambda: publisher_has_link(uri, "/rosout", rospy.get_name()), REASON_TIMEOUT)

    def _checked(self, service, srv, **fields):
        if self._log is None:
            self._listen_to_manager(service)
        with self._reason_seen:
            first = len(self._reasons)
        res = self._call(service, srv, **fields)
        if not res.ok:
            why = self._reason(service, first)
            raise ControllerManagerError(why or "%s%s failed (the controller manager's log says why)"
                                         % (self.prefix, service))
        return res

    def load(self, controller):
        self._checked("load_controller", LoadController, name=controller)

    def unload(self, controller):
        self._checked("unload_controller", UnloadController, name=controller)

    def switch(self, start=(), stop=(), strictness=STRICT):
        self._checked("switch_controller", SwitchController, start_controllers=list(start),
                      stop_controllers=list(stop), strictness=strictness, start_asap=False, timeout=0.0)

    def list(self):
        return self._call("list_controllers", ListControllers).controller

    def list_types(self):
        res = self._call("list_controller_types", ListControllerTypes)
        return list(zip(res.types, res.base_classes))

    def reload_libraries(self, force_kill=False):
        self._checked("reload_controller_libraries", ReloadControllerLibraries, force_kill=force_kill)


def _wait_until(predicate, timeout):
    """Polls `predicate` for up to `timeout` wall seconds (a connection being made, not time
    passing in the simulation)."""
    deadline = time.monotonic() + timeout
    while not predicate() and time.monotonic() < deadline and not rospy.is_shutdown():
        time.sleep(0.01)
