"""Client side of gazebo_lite's controller_manager: what `spawner` and `controller_manager`
(the scripts, with controller_manager's command lines) do with its services."""

import rospy

from mybot_gazebo_lite.srv import (ListControllers, ListControllerTypes, LoadController, ReloadControllerLibraries,
                                   SwitchController, UnloadController)

STRICT = 2
BEST_EFFORT = 1


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

    def _checked(self, service, srv, **fields):
        res = self._call(service, srv, **fields)
        if not res.ok:
            raise ControllerManagerError(res.message or "%s failed" % service)
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
