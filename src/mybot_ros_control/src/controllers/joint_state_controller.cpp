// joint_state_controller/JointStateController: every joint of the hardware on <ns>/joint_states
// at publish_rate (required, as upstream), plus extra_joints with their given values.
#include "controllers.h"

#include <sensor_msgs/JointState.h>

namespace mybot_ros_control
{

namespace
{
class JointStateController : public Controller
{
public:
  explicit JointStateController(const ControllerContext& c) : hw_(c.hw)
  {
    if (!c.nh.hasParam("publish_rate"))
      c.fail("publish_rate", "required parameter missing");
    period_ = 1.0 / c.positive("publish_rate", 0.0);
    XmlRpc::XmlRpcValue extra;
    if (c.nh.getParam("extra_joints", extra))
    {
      if (extra.getType() != XmlRpc::XmlRpcValue::TypeArray)
        c.fail("extra_joints", "expected a list");
      for (int k = 0; k < extra.size(); ++k)
      {
        const std::string field = "extra_joints[" + std::to_string(k) + "]";
        if (extra[k].getType() != XmlRpc::XmlRpcValue::TypeStruct || !extra[k].hasMember("name"))
          c.fail(field, "expected {name: ..., position: ..., velocity: ..., effort: ...}");
        Extra e;
        e.name = static_cast<std::string>(extra[k]["name"]);
        for (auto [key, out] : {std::pair<const char*, double*>{"position", &e.position},
                                {"velocity", &e.velocity},
                                {"effort", &e.effort}})
          if (extra[k].hasMember(key))
          {
            XmlRpc::XmlRpcValue& v = extra[k][key];
            if (v.getType() == XmlRpc::XmlRpcValue::TypeDouble)
              *out = static_cast<double>(v);
            else if (v.getType() == XmlRpc::XmlRpcValue::TypeInt)
              *out = static_cast<int>(v);
            else
              c.fail(field + "." + key, "expected a number");
          }
        extras_.push_back(e);
      }
    }
    pub_ = ros::NodeHandle(c.root_nh).advertise<sensor_msgs::JointState>("joint_states", 10);
  }
  void starting(double t) override { next_ = t; }
  void update(double t, double) override
  {
    if (t + 1e-9 < next_)
      return;
    next_ = (next_ + period_ < t) ? t + period_ : next_ + period_;
    sensor_msgs::JointState m;
    m.header.stamp = ros::Time(t);
    for (const auto& j : hw_->joints())
    {
      m.name.push_back(j.name);
      m.position.push_back(j.position);
      m.velocity.push_back(j.velocity);
      m.effort.push_back(j.effort);
    }
    for (const auto& e : extras_)
    {
      m.name.push_back(e.name);
      m.position.push_back(e.position);
      m.velocity.push_back(e.velocity);
      m.effort.push_back(e.effort);
    }
    pub_.publish(m);
  }

private:
  struct Extra
  {
    std::string name;
    double position = 0, velocity = 0, effort = 0;
  };
  RobotHWSim* hw_;
  double period_ = 0, next_ = 0;
  std::vector<Extra> extras_;
  ros::Publisher pub_;
};
}  // namespace

std::unique_ptr<Controller> makeJointStateController(const ControllerContext& c)
{
  return std::make_unique<JointStateController>(c);
}

}  // namespace mybot_ros_control
