"""rosrun mybot_control teleop_joy: sensor_msgs/Joy -> cmd_vel with teleop_twist_joy's parameters."""
import rospy
from geometry_msgs.msg import Twist, TwistStamped
from sensor_msgs.msg import Joy

from mybot_common import params
from mybot_control import joy
from mybot_control.nodes import common


class Node:
    def __init__(self):
        kw = {}
        for name in ("axis_linear", "scale_linear", "scale_linear_turbo",
                     "axis_angular", "scale_angular", "scale_angular_turbo"):
            if rospy.has_param("~" + name):
                kw[name] = rospy.get_param("~" + name)
        try:
            self.mapping = joy.TwistJoy(
                enable_button=common.get("enable_button", 0, params.number, integer=True, low=0),
                enable_turbo_button=common.get("enable_turbo_button", -1, params.number, integer=True, low=-1),
                require_enable_button=common.get("require_enable_button", True, params.boolean),
                inverted_reverse=common.get("inverted_reverse", False, params.boolean),
                **kw)
        except ValueError as e:
            if isinstance(e, params.ParamError):
                raise
            raise params.ParamError("~" + str(e).split(":")[0].split(".")[0], str(e))
        self.stamped = common.get("publish_stamped_twist", False, params.boolean)
        self.frame = common.get("frame", "teleop_twist_joy", params.string)
        self.pub = rospy.Publisher("cmd_vel", TwistStamped if self.stamped else Twist, queue_size=1)
        for kind, amap in (("Linear", self.mapping.axis_linear), ("Angular", self.mapping.axis_angular)):
            for field, axis in sorted(amap.items()):
                rospy.loginfo("teleop_joy: %s axis %s on %d at scale %g", kind, field, axis,
                              self.mapping.scale[kind.lower(), "normal"][field])
        self.sub = rospy.Subscriber("joy", Joy, self.on_joy, queue_size=1)

    def on_joy(self, msg):
        twist = self.mapping.process(msg.axes, msg.buttons)
        if twist is None:
            return
        out = TwistStamped() if self.stamped else Twist()
        t = out.twist if self.stamped else out
        if self.stamped:
            out.header.stamp = rospy.Time.now()
            out.header.frame_id = self.frame
        (t.linear.x, t.linear.y, t.linear.z, t.angular.x, t.angular.y, t.angular.z) = twist
        self.pub.publish(out)

    def spin(self):
        rospy.spin()
        return 0


def main():
    common.run("teleop_joy", lambda: Node().spin())
