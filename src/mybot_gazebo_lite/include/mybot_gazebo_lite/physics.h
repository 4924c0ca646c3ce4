// Bullet (Featherstone) world holding static/dynamic world models and URDF
// robots as btMultiBody trees. No ROS types.
#pragma once

#include "mybot_gazebo_lite/model.h"

#include <LinearMath/btAlignedObjectArray.h>

#include <map>
#include <memory>
#include <string>
#include <vector>

class btMultiBody;
class btMultiBodyDynamicsWorld;
class btMultiBodyJointMotor;
class btMultiBodyJointLimitConstraint;
class btCollisionObject;
class btCollisionShape;
class btRigidBody;
class btCollisionConfiguration;
class btCollisionDispatcher;
class btBroadphaseInterface;
class btMultiBodyConstraintSolver;
class btMultiBodyConstraint;
class btPersistentManifold;

namespace mybot_gazebo_lite
{

// One collision's contact surface: its friction (the smaller of Gazebo's mu1, mu2). Contacts are
// rigid: see the README's Gazebo tags for kp, kd.
struct Surface
{
  double mu = 1.0;
};

struct Pose
{
  btTransform tf = btTransform::getIdentity();
  btVector3 linear{0, 0, 0};   // world-frame velocity of the frame origin
  btVector3 angular{0, 0, 0};  // world-frame angular velocity
};

// The wrench of gazebo_ros's apply_body_wrench in the world frame, about the centre of mass `com`
// of the body it acts on. Without a reference frame (`frame` null), force and torque are in the
// world's axes and `point` is a lever arm from the centre of mass (upstream's reading). With one,
// force, torque and point are in that frame, and the force acts at the point.
void worldWrench(const btVector3& force, const btVector3& torque, const btVector3& point, const btTransform* frame,
                 const btVector3& com, btVector3& force_out, btVector3& torque_out);

// `s` seen from `frame` (both world-frame states), as gazebo_ros's get_model_state and
// get_link_state give it: the pose relative to the frame, and the velocity differences turned
// into the frame's axes (Gazebo ignores the frame's rotation sweeping the point, and so does this).
Pose relativeTo(const Pose& s, const Pose& frame);

class Robot
{
public:
  enum class Mode
  {
    NONE,
    VELOCITY,
    POSITION,
    EFFORT
  };
  struct Joint
  {
    const JointSpec* spec = nullptr;
    int link = -1;  // btMultiBody link index
    btMultiBodyJointMotor* motor = nullptr;
    btMultiBodyJointMotor* friction = nullptr;  // Coulomb: at most friction dt of impulse a step
    // Viscous damping, as a solver row (DamperRow in physics.cpp); made when the joint has damping,
    // at load or when set_joint_properties gives it some.
    btMultiBodyJointMotor* damper = nullptr;
    Mode mode = Mode::NONE;
    double target = 0, max_effort = 0, target_velocity = 0;
    double motor_effort = 0;  // what the motor exerted over the last step (N m or N)
    // The spec's until set_joint_properties changes them.
    double damping = 0;
    bool limited = false;
    double lower = 0, upper = 0;
    btMultiBodyJointLimitConstraint* limit = nullptr;
  };
  // A URDF link lives in a body (-1 = multibody base, else link index).
  struct LinkRef
  {
    int body = -1;
    btTransform in_body_inertial;  // URDF link frame in the body's inertial frame
  };

  const std::string& name() const { return name_; }
  const std::string& robotNamespace() const { return ns_; }
  const RobotSpec& spec() const { return *spec_; }
  const btTransform& spawnPose() const { return spawn_; }
  bool hasLink(const std::string& n) const { return links_.count(n) != 0; }
  bool hasJoint(const std::string& n) const { return joint_index_.count(n) != 0; }
  // A fixed joint Gazebo keeps (JointSpec::keep_fixed): not movable, but its wrench can be watched.
  bool hasKeptFixedJoint(const std::string& n) const;
  std::vector<std::string> movableJoints() const;

  // World pose and velocity of a URDF link frame.
  Pose linkState(const std::string& link) const;
  // Its world pose alone (no velocities to compute).
  btTransform linkPose(const std::string& link) const;
  double jointPosition(const std::string& joint) const;
  double jointVelocity(const std::string& joint) const;
  const Joint& joint(const std::string& n) const { return joints_.at(joint_index_.at(n)); }

  // Commands take effect at the next step; the motor is limited to max_effort (N m or N).
  void commandVelocity(const std::string& joint, double vel, double max_effort);
  // `velocity`: the setpoint's own rate (a ramped target), fed forward so the servo does not lag.
  void commandPosition(const std::string& joint, double pos, double max_effort, double velocity = 0.0);
  void commandNone(const std::string& joint);
  // A force or torque (N or N m) applied at every step until the next command, clamped to the
  // URDF <limit effort> when it has one.
  void commandEffort(const std::string& joint, double effort);
  // The actuator's effort on the joint (N m or N), as a motor's current tells it on a real robot:
  // an effort-driven joint's command, or what its velocity or position servo exerted over the
  // last step (what holds an arm up). Not the limits', friction's, damping's or applied efforts'.
  // 0 for a joint nothing commands.
  double jointEffort(const std::string& joint) const;
  // A world-frame force at the centre of mass of `link`'s body and a world-frame torque, for the
  // next step only (gazebo_ros_force every step; apply_body_wrench's jobs come through here too).
  void addWrench(const std::string& link, const btVector3& force, const btVector3& torque);
  // The external wrench addWrench put on `link`'s body over the last step, summed (world frame,
  // about its centre of mass): what gazebo_ros_f3d reports. Contact and joint forces are not in it.
  std::pair<btVector3, btVector3> externalWrench(const std::string& link) const;
  // Contact friction of every collision of the robot (planar_move: the base slides as commanded).
  void setContactFriction(double mu);
  // The wrench the parent link exerts on `joint`'s child through the joint over the last step
  // (constraint, actuation and the joint's damping alike), in the child link's axes, its torque
  // about the joint's origin (a URDF joint's is the child link's): what Gazebo's GetForceTorque gives as
  // body2Force / body2Torque, and what a force-torque sensor between the two links measures.
  // Bullet's own joint feedback leaves out the motors' impulses, so it is computed by
  // Newton-Euler on the child's subtree instead (jointWrenches in physics.cpp). Zero until a step
  // has run with the joint watched; watching costs a pass over the robot's bodies per step.
  // `joint`: a movable joint, or a fixed one Gazebo keeps.
  void watchJointWrench(const std::string& joint);
  std::pair<btVector3, btVector3> jointWrench(const std::string& joint) const;

  btMultiBody* multibody() const { return mb_; }
  const std::vector<btCollisionObject*>& colliders() const { return colliders_; }

  // Penetrating contacts with world models and other robots (never the ground plane), counted
  // by the physics engine at every step since spawn or the last world reset.
  struct Contacts
  {
    uint64_t steps = 0;            // steps with at least one contact
    double time = 0;               // and their time (s)
    double max_depth = 0;          // deepest penetration (m)
    double first_time = -1;        // sim time of the first contact (s), -1 = none yet
    std::string first_model;       // what it touched first
    std::vector<std::string> now;  // what it touches at the last step
    // Every contact point of the last step, with the ground too (bumpers).
    struct Point
    {
      std::vector<std::string> links;  // the URDF links of the body that touched
      std::string other;               // model name, "ground_plane" for the ground
      btVector3 position, normal;      // world frame; normal points from the other body into ours
      double depth = 0;                // penetration (m)
      double impulse = 0;              // normal impulse of the step (N s)
    };
    std::vector<Point> points;
  };
  const Contacts& contacts() const { return contacts_; }
  // Contacts::points are gathered only for robots that ask (a bumper): they cost a string per point.
  void recordContactPoints(bool on) { record_points_ = on; }

private:
  friend class PhysicsWorld;
  // The world pose of the body a link lives in (the base or a multibody link).
  btTransform bodyWorld(const LinkRef& ref) const;
  // A body's world pose (its centre of mass and principal axes) and momentum: linear, and angular
  // about its centre of mass.
  struct BodyMotion
  {
    btTransform pose;
    btVector3 p, L;
  };
  // Each body's (index body + 1).
  std::vector<BodyMotion> bodyMotions() const;
  std::string name_, ns_;
  std::shared_ptr<const RobotSpec> spec_;
  btTransform spawn_;
  btTransform base_root_in_inertial_;  // URDF root link frame in base inertial frame
  btMultiBody* mb_ = nullptr;
  std::map<std::string, LinkRef> links_;
  std::vector<Joint> joints_;
  std::map<std::string, size_t> joint_index_;
  std::vector<btCollisionObject*> colliders_;
  std::vector<btCollisionShape*> shapes_;
  Contacts contacts_;
  bool record_points_ = false;
  std::vector<btMultiBodyConstraint*> constraints_;
  std::vector<std::unique_ptr<std::vector<Surface>>> child_mu_;
  std::vector<char> gravity_off_;  // by body (index body + 1): set_link_properties' gravity_mode false
  // addWrench's sums by body (index body + 1): for the coming step, and over the last one.
  std::vector<std::pair<btVector3, btVector3>> pending_wrench_, last_wrench_;
  // watchJointWrench's joints and their wrench over the last step; the bodies' motion before the step.
  struct WatchedJoint
  {
    const JointSpec* spec = nullptr;
    int link = -1;  // the multibody link the joint heads
    std::pair<btVector3, btVector3> wrench{btVector3(0, 0, 0), btVector3(0, 0, 0)};
  };
  std::vector<WatchedJoint> watched_wrench_;
  std::vector<BodyMotion> motion_before_;
  std::map<std::string, int> kept_fixed_;  // kept fixed joints -> their multibody link
};

// A collision object that may intersect a sensor ray (robots and dynamic world bodies).
struct DynamicObstacle
{
  const btCollisionObject* object;
  btVector3 center;  // AABB centre
  double radius;     // bounding sphere radius
  double zmin, zmax;
};

// What gazebo_ros's get_model_properties tells of a model, as Gazebo builds it from a URDF: one
// link per moving body (a fixed joint's child is lumped into its parent), the movable joints, and
// the collisions named as Gazebo's URDF conversion names them ("<link>_collision", the body's
// n-th from the second on "_<n>", a lumped child's "<link>_fixed_joint_lump__<child>_collision").
// An SDF model's, as Gazebo keeps it: its own links and joints (fixed and ball ones too, in the
// file's order), the collisions by their own names, and its nested and included models as child
// models (their links and joints are theirs, not listed here).
struct ModelProperties
{
  std::string canonical_link;  // the root link (a "world" root: its first child body)
  std::vector<std::string> links, collisions, joints, child_models;
  bool is_static = false;
};

// gazebo_ros's get/set_link_properties of a link (a body: a link with the links fixed to it).
// As Gazebo reports them: the centre of mass in the link frame with no rotation, the inertia about
// it in the link frame's axes.
struct LinkProperties
{
  btVector3 com{0, 0, 0};
  bool gravity_mode = true;
  double mass = 0;
  btMatrix3x3 inertia{0, 0, 0, 0, 0, 0, 0, 0, 0};
};

// set_joint_properties: what it changes (a list of ODEJointProperties: empty = unchanged).
struct JointSettings
{
  std::vector<double> damping, lower, upper, fmax, vel;
};

// gazebo_ros's get_joint_properties of one movable joint.
struct JointProperties
{
  // An SDF model's fixed or ball joint is reported too (Gazebo keeps them), at position 0.
  JointSpec::Type type = JointSpec::REVOLUTE;
  double damping = 0, position = 0, rate = 0;
};

class PhysicsWorld
{
public:
  struct Options
  {
    double step = 0.001;
    int solver_iterations = 10;
  };
  PhysicsWorld(const WorldSpec& world, const Options& opt);
  ~PhysicsWorld();
  PhysicsWorld(const PhysicsWorld&) = delete;
  PhysicsWorld& operator=(const PhysicsWorld&) = delete;

  // Throws LoadError (naming the element) for a model Bullet cannot build.
  Robot& addRobot(std::shared_ptr<const RobotSpec> spec, const std::string& name, const std::string& ns,
                  const btTransform& pose);
  // By value: the name may be the robot's own, which the removal frees.
  bool removeRobot(std::string name);
  Robot* robot(const std::string& name);
  std::vector<Robot*> robots();

  void step();
  double time() const { return time_; }
  double stepSize() const { return opt_.step; }
  uint64_t steps() const { return steps_; }
  // set_physics_properties: from the next step on. Time goes on from where it is.
  void setStepSize(double step);
  int solverIterations() const { return opt_.solver_iterations; }
  void setSolverIterations(int iterations);
  const btVector3& gravity() const { return spec_.gravity; }
  void setGravity(const btVector3& g);

  // Robots back to their spawn poses at rest, dynamic world models to their initial poses.
  // Returns whether the static world changed (a static model moved by setModelState went back).
  bool resetWorld();
  void resetTime()
  {
    time_ = time_base_ = 0;
    steps_ = steps_base_ = 0;
  }

  // Sets the velocity of a robot's root link frame (world frame), for the next step.
  void setRobotVelocity(Robot& r, const btVector3& lin, const btVector3& ang);
  // Teleport a robot (base frame = URDF root link) or a world model; velocities in world frame.
  // A static model is moved too (its velocities ignored): then *moved_static is set, and the
  // static world's caches must be rebuilt.
  bool setModelState(const std::string& name, const btTransform& pose, const btVector3& lin, const btVector3& ang,
                     bool* moved_static = nullptr);
  bool getModelState(const std::string& name, Pose& out) const;
  // A world model added while the world runs (gazebo_ros's spawn_sdf_model), at m.pose; throws
  // LoadError naming it when its name is taken or it has nothing to collide with.
  void addModel(const WorldModel& m);
  // Removes a world model added at load or since (delete_model); false when there is none of
  // that name. `was_static`: whether it was static (the static world's caches must be rebuilt).
  bool removeModel(std::string name, bool* was_static = nullptr);  // by value, as removeRobot
  // Every model's name and state, as Gazebo's /gazebo/model_states lists them: in the order they
  // came into the world (the world file's, then spawned robots and models).
  std::vector<std::pair<std::string, Pose>> modelStates() const;
  // Every link's state, named "model::link" as in Gazebo's /gazebo/link_states, in the same order.
  std::vector<std::pair<std::string, Pose>> linkStates() const;
  // The links of the models that move (robots and dynamic world models, but `except_model`) whose
  // frame is within `radius` of `centre`, named and ordered as linkStates() names them, with their
  // states. Only those links' velocities are computed: a vacuum gripper asks at every step.
  std::vector<std::pair<std::string, Pose>> movingLinksNear(const btVector3& centre, double radius,
                                                            const std::string& except_model) const;
  // A model's state, or a link's ("model::link"); false when there is no such entity.
  bool entityState(const std::string& name, Pose& out) const;

  // get_model_properties; false when there is no such model.
  bool modelProperties(const std::string& model, ModelProperties& out) const;
  // The link Gazebo names the body a robot's `link` is in (a fixed joint's child is lumped into its
  // parent); `link` itself when there is no such robot or link.
  std::string bodyLinkOf(const std::string& model, const std::string& link) const;
  // get_joint_properties of "model::joint", or of a joint name one robot alone has; "" or why not.
  std::string jointProperties(const std::string& joint, JointProperties& out) const;
  // get_link_properties of "model::link", or of a link name one model alone has; "" or why not.
  // A static model's link: its mass, no inertia (it is not simulated).
  std::string linkProperties(const std::string& link, LinkProperties& out) const;
  // set_link_properties: mass, inertia and gravity of a link of a robot or of a dynamic world
  // model, from the next step on. Bullet's bodies are built about their centre of mass and along
  // the inertia's principal axes: a request that moves the centre of mass or turns the axes is
  // refused, as are a mass or inertia that is not physical. "" or why nothing was set.
  std::string setLinkProperties(const std::string& link, const LinkProperties& p);
  // set_joint_properties of a movable joint (named as apply_joint_effort's): damping, limits,
  // and the joint motor ODE's fmax and vel drive (fmax 0: off). "" or why nothing was set.
  std::string setJointProperties(const std::string& joint, const JointSettings& s);
  // set_model_configuration: the named joints of a robot at these positions, at rest, at once; the
  // root link stays where it is, and so do the joints not named. "" or why nothing was set (an
  // unknown joint or a position beyond the joint's limits, named).
  std::string setJointPositions(const std::string& model, const std::vector<std::string>& joints,
                                const std::vector<double>& positions);
  // set_link_state of "model::link" (world frame): a world model's link, or the link a robot's
  // root body carries (which moves the robot). A link placed by joints is refused: its pose is
  // its joints'. "" or why; *moved_static as setModelState.
  std::string setLinkState(const std::string& link, const btTransform& pose, const btVector3& lin, const btVector3& ang,
                           bool* moved_static = nullptr);

  // gazebo_ros's apply_body_wrench: a world-frame force at the centre of mass of `link`'s body and
  // a world-frame torque, applied at every step from sim time `start` for `duration` s (< 0:
  // until cleared; shorter than a step: one step). `link` is "model::link" of a robot or of a
  // dynamic world model; false when there is none.
  bool applyBodyWrench(const std::string& link, const btVector3& force, const btVector3& torque, double start,
                       double duration);
  // clear_body_wrenches: that link's wrenches ("": all of them, as reset_simulation does).
  void clearBodyWrenches(const std::string& link = "");
  // The world-frame centre of mass of the body `link` belongs to; false when there is none.
  bool centreOfMass(const std::string& link, btVector3& out) const;
  // gazebo_ros's apply_joint_effort: `effort` (N m or N) added on a robot's movable joint at every
  // step from `start` for `duration` s, as apply_body_wrench. `joint` is "model::joint", or a
  // joint name that one robot alone has. "" or why it was refused.
  std::string applyJointEffort(const std::string& joint, double effort, double start, double duration);
  // clear_joint_forces: that joint's efforts ("": all of them).
  void clearJointForces(const std::string& joint = "");

  const WorldSpec& worldSpec() const { return spec_; }
  std::vector<DynamicObstacle> dynamicObstacles(const Robot* exclude) const;
  // Every collision shape of the robots (but `exclude`) and of the dynamic world bodies, where it
  // is now: what a camera draws besides the static world.
  std::vector<PlacedShape> movingShapes(const Robot* exclude) const;
  // Distance along the ray to the object (or -1 when missed).
  double rayTestObject(const btCollisionObject* obj, const btVector3& from, const btVector3& to) const;
  // Closest hit of a ray against all collision objects except those of `exclude`; -1 when missed.
  double rayTest(const btVector3& from, const btVector3& to, const Robot* exclude) const;

private:
  // The stages of addRobot, in order.
  struct LumpedBody;
  using LinkPlaces = std::map<std::string, std::pair<int, btTransform>>;  // link -> (body, frame in body root)
  static std::vector<LumpedBody> lumpFixedJoints(const RobotSpec& rs, LinkPlaces& where);
  void buildMultiBody(const std::vector<LumpedBody>& bodies, Robot& r);
  void addColliders(const std::vector<LumpedBody>& bodies, Robot& r);
  void addJointConstraints(const std::vector<LumpedBody>& bodies, Robot& r);
  // The joint's damping; its damper row is made the first time it has some (at load or by
  // set_joint_properties), not looked for at every step.
  void setDamping(Robot& r, Robot::Joint& j, double damping);
  void addWorldModel(const WorldModel& m);
  void updateContacts();
  // The watched joints' wrenches (Robot::watchJointWrench) from the step just taken.
  void jointWrenches(Robot& r);
  void recordPoints(const btPersistentManifold* m);
  Robot* robotOf(const btCollisionObject* o) const;
  std::string modelOf(const btCollisionObject* o) const;  // "" for the ground plane
  void syncRobotTransforms(Robot& r);
  void setRobotPose(Robot& r, const btTransform& root_pose, const btVector3& lin, const btVector3& ang);
  btCollisionShape* buildShape(const Shape& s, bool dynamic_body, std::vector<btCollisionShape*>& owned,
                               const std::string& where);

  Options opt_;
  WorldSpec spec_;
  double time_ = 0;
  uint64_t steps_ = 0;
  // Time is counted in whole steps from the last change of step size (no sum of rounded steps).
  double time_base_ = 0;
  uint64_t steps_base_ = 0;
  std::unique_ptr<btCollisionConfiguration> config_;
  std::unique_ptr<btCollisionDispatcher> dispatcher_;
  std::unique_ptr<btBroadphaseInterface> broadphase_;
  std::unique_ptr<btMultiBodyConstraintSolver> solver_;
  std::unique_ptr<btMultiBodyDynamicsWorld> world_;
  std::vector<std::unique_ptr<Robot>> robots_;
  struct WorldBody
  {
    std::string model;
    btCollisionObject* obj;
    btRigidBody* body;                      // null for static
    std::shared_ptr<const WorldLink> link;  // its spec (a copy), for dynamic bodies (null for static)
    btTransform initial;
    bool ground;  // a plane: wheels touch it all the time
    std::string link_name;
    btTransform link_in_model;  // the SDF link's pose in its model
    btTransform link_in_body;   // the link frame in the collision object's (a plane's shape pose is folded in)
    std::vector<btCollisionShape*> shapes;     // owned: deleted with the body
    std::shared_ptr<std::vector<Surface>> mu;  // the shapes' friction, by child index (the user pointer)
  };
  void removeWorldBody(WorldBody& wb);
  // A static body placed anew: the broadphase and the spec the static world's caches read follow.
  void placeStatic(WorldBody& wb, const btTransform& body_tf);
  const Robot* robotNamed(const std::string& name) const;
  // The one lookup of a joint by the name a service is given: "model::joint", or a joint name one
  // model alone has. It finds the joints Gazebo has: a robot's movable ones, the fixed ones a
  // <gazebo reference> keeps, and an SDF model's fixed and ball joints. Gazebo lumps a URDF's other
  // fixed joints away, and the message says so. "" or why not.
  struct JointRef
  {
    const Robot* robot = nullptr;
    const JointSpec* spec = nullptr;
    bool movable = false;  // one degree of freedom here: efforts, settings and positions apply
  };
  std::string findJoint(const std::string& joint, JointRef& out, const std::string& kind = "joint") const;
  // findJoint's, for a service that moves the joint: a fixed or ball joint is refused, saying so.
  std::string resolveJoint(const std::string& joint, const Robot*& robot, std::string& name) const;
  // The one lookup of a link by the name a service is given: "model::link", or a link name one
  // model alone has, to the robot body or the world body it is. A URDF link lumped into another
  // by a fixed joint is not one in Gazebo: the message names the other.
  struct BodyRef
  {
    const Robot* robot = nullptr;
    int body = -1;
    const WorldBody* world = nullptr;
    std::string model, link;
  };
  std::string resolveBody(const std::string& link, BodyRef& out) const;
  // The body's frame (its centre of mass and principal axes) in its link's frame.
  static btTransform bodyInLink(const BodyRef& b);
  // Each body of a robot and the link Gazebo names it by (the first link of the body in the URDF
  // that begins it: the root or a movable joint's child).
  static std::map<int, std::string> bodyLinks(const Robot& r);
  void cancelGravity();  // on the bodies set_link_properties took it from
  // The state of a world body's link frame, or of its model's frame.
  static Pose linkFrameState(const WorldBody& wb);
  static Pose modelFrameState(const WorldBody& wb);
  std::vector<WorldBody> world_bodies_;
  // Every model's name in /gazebo/model_states' order: a world file's as the file lists them
  // (enterModelOrder: its robots are added after its rigid models), then in the order they came in.
  std::vector<std::string> model_order_;
  void enterModelOrder(const std::string& name);
  void leaveModelOrder(const std::string& name);
  // When a wrench or an effort acts, as gazebo_ros times them: at every step from `start`; for
  // `duration` s (< 0: until cleared; shorter than a step: one step).
  struct JobTime
  {
    double start, end;  // sim time; end infinite: until cleared
    JobTime(double start, double duration, double step);
    bool due(double t) const { return start <= t + 1e-12; }
    bool over(double t, double step) const { return t + step > end - 1e-12; }  // after the step from t
  };
  struct WrenchJob
  {
    std::string asked, model, link;  // as asked for (clear_body_wrenches matches it), and split
    btVector3 force, torque;
    JobTime time;
  };
  std::vector<WrenchJob> wrenches_;
  void applyWrenches();
  struct EffortJob
  {
    std::string asked, model, joint;  // as asked for (clear_joint_forces matches it), and resolved
    double effort;
    JobTime time;
  };
  std::vector<EffortJob> efforts_;
  void applyEfforts();
  btAlignedObjectArray<btQuaternion> scratch_q_;
  btAlignedObjectArray<btVector3> scratch_m_;
};

}  // namespace mybot_gazebo_lite
