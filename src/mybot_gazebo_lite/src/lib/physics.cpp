#include "mybot_gazebo_lite/physics.h"
#include "mybot_common/checks.h"

#include <BulletCollision/CollisionShapes/btBvhTriangleMeshShape.h>
#include <BulletCollision/CollisionShapes/btTriangleMesh.h>
#include <BulletDynamics/Featherstone/btMultiBody.h>
#include <BulletDynamics/Featherstone/btMultiBodyConstraintSolver.h>
#include <BulletDynamics/Featherstone/btMultiBodySphericalJointMotor.h>
#include <BulletDynamics/Featherstone/btMultiBodyDynamicsWorld.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointLimitConstraint.h>
#include <BulletDynamics/Featherstone/btMultiBodyJointMotor.h>
#include <BulletDynamics/Featherstone/btMultiBodyLinkCollider.h>
#include <Eigen/Dense>
#include <btBulletDynamicsCommon.h>

#include <algorithm>
#include <limits>
#include <cmath>
#include <functional>

namespace mybot_gazebo_lite
{

namespace
{
// A joint motor whose impulse over the last step can be read. Bullet sizes a constraint's record of
// impulses when its solver first sees the constraint, and getAppliedImpulse before then reads past
// an empty array.
class JointMotor : public btMultiBodyJointMotor
{
public:
  using btMultiBodyJointMotor::btMultiBodyJointMotor;
  double lastImpulse() { return m_data.size() > 0 ? getAppliedImpulse(0) : 0.0; }
};

// Viscous joint damping d, integrated implicitly: a soft solver row on the joint's velocity, whose
// impulse is -d dt v_new, v_new being the velocity at the end of the step. Bullet's solver drives a
// row to (rhs - cfm impulse) / jacDiagABInv = J dv; with the row's J M^-1 J^T = a (the joint's
// inverse effective inertia, the whole multibody's) and the compliance c = 1 / (d dt), the fixed
// point is impulse = -(v + a impulse) / c: implicit Euler, solved together with the contacts and the
// other joints' rows (a ball joint's three rows, coupled by the bob's inertia, keep its swing in its
// plane). An isolated joint's velocity becomes v / (1 + a d dt): stable for any d, and an
// over-damped joint creeps at the rate where damping balances its load. The explicit torque -d v it
// replaces made the joint's velocity change sign and grow once d dt exceeded twice its inertia: a
// 10 g link with damping 0.1 went to NaN.
void dampRow(btMultiBodySolverConstraint& row, double velocity, double damping, double dt)
{
  const double a = 1 / row.m_jacDiagABInv;  // inf for a row without inertia: then no impulse
  const double c = 1 / (damping * dt);      // inf for no damping, or one so small (1e-310) that d dt is 0
  row.m_rhsPenetration = 0;
  if (!std::isfinite(a) || !std::isfinite(c) || !(c > 0))
  {
    row.m_jacDiagABInv = row.m_rhs = row.m_cfm = row.m_lowerLimit = row.m_upperLimit = 0;
    return;
  }
  row.m_jacDiagABInv = 1 / (a + c);
  row.m_cfm = c * row.m_jacDiagABInv;
  row.m_rhs = -velocity * row.m_jacDiagABInv;
  row.m_lowerLimit = -BT_LARGE_FLOAT;
  row.m_upperLimit = BT_LARGE_FLOAT;
}

// A revolute or prismatic joint's damper: Bullet's motor row, its impulse set by dampRow.
class DamperRow : public btMultiBodyJointMotor
{
public:
  // Any nonzero impulse: Bullet's motor makes no row with 0 (it is how a motor is switched off).
  DamperRow(btMultiBody* mb, int link) : btMultiBodyJointMotor(mb, link, 0, 1) {}
  double damping = 0;

  void createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                            const btContactSolverInfo& info) override
  {
    const int first = rows.size();
    btMultiBodyJointMotor::createConstraintRows(rows, data, info);
    if (rows.size() == first + 1)
      dampRow(rows[first], m_bodyA->getJointVel(m_linkA), damping, info.m_timeStep);
  }
};

// A ball joint's damper: one row about each axis of the child link, which are the joint's three
// velocity coordinates.
class BallDamperRows : public btMultiBodySphericalJointMotor
{
public:
  BallDamperRows(btMultiBody* mb, int link, double damping)
      : btMultiBodySphericalJointMotor(mb, link, 1), damping_(damping)
  {
  }

  void createConstraintRows(btMultiBodyConstraintArray& rows, btMultiBodyJacobianData& data,
                            const btContactSolverInfo& info) override
  {
    const int first = rows.size();
    btMultiBodySphericalJointMotor::createConstraintRows(rows, data, info);
    if (rows.size() != first + 3)
      return;
    const btScalar* w = m_bodyA->getJointVelMultiDof(m_linkA);
    for (int i = 0; i < 3; ++i)
      dampRow(rows[first + i], w[i], damping_, info.m_timeStep);
  }

private:
  double damping_;
};

constexpr int kStaticGroup = btBroadphaseProxy::StaticFilter;
constexpr int kDynamicGroup = btBroadphaseProxy::DefaultFilter;

// Per-child friction: colliders carry a pointer to one mu per compound child,
// so a frictionless caster lumped into the chassis stays frictionless.
Surface childSurface(const btCollisionObjectWrapper* w, int index)
{
  const btCollisionObject* o = w->getCollisionObject();
  auto* s = static_cast<const std::vector<Surface>*>(o->getUserPointer());
  if (s && index >= 0 && index < static_cast<int>(s->size()))
    return (*s)[index];
  if (s && s->size() == 1)
    return (*s)[0];
  return Surface{o->getFriction()};
}

bool contactAdded(btManifoldPoint& cp, const btCollisionObjectWrapper* w0, int, int i0,
                  const btCollisionObjectWrapper* w1, int, int i1)
{
  cp.m_combinedFriction = std::min(childSurface(w0, i0).mu, childSurface(w1, i1).mu);  // ODE-style, as in Gazebo
  cp.m_combinedRestitution = 0;
  return true;
}

struct MassProps
{
  double mass = 0;
  btTransform inertial = btTransform::getIdentity();  // in body root frame
  btVector3 diag{0, 0, 0};
};

MassProps composite(const std::vector<std::pair<const LinkSpec*, btTransform>>& members)
{
  MassProps mp;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  struct Part
  {
    double m;
    Eigen::Vector3d c;
    Eigen::Matrix3d I;
  };
  std::vector<Part> parts;
  for (const auto& [link, tf] : members)
  {
    if (!link->has_inertial || link->inertial.mass <= 0)
      continue;
    const Inertial& in = link->inertial;
    btTransform t = tf * in.origin;
    Eigen::Matrix3d R;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c)
        R(r, c) = t.getBasis()[r][c];
    Eigen::Matrix3d I;
    I << in.ixx, in.ixy, in.ixz, in.ixy, in.iyy, in.iyz, in.ixz, in.iyz, in.izz;
    Eigen::Vector3d c(t.getOrigin().x(), t.getOrigin().y(), t.getOrigin().z());
    parts.push_back({in.mass, c, R * I * R.transpose()});
    mp.mass += in.mass;
    com += in.mass * c;
  }
  if (mp.mass <= 0)
    return mp;
  com /= mp.mass;
  Eigen::Matrix3d I = Eigen::Matrix3d::Zero();
  for (const auto& p : parts)
  {
    Eigen::Vector3d d = p.c - com;
    I += p.I + p.m * (d.squaredNorm() * Eigen::Matrix3d::Identity() - d * d.transpose());
  }
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> es(I);
  Eigen::Matrix3d V = es.eigenvectors();
  if (V.determinant() < 0)
    V.col(2) = -V.col(2);
  btMatrix3x3 basis(V(0, 0), V(0, 1), V(0, 2), V(1, 0), V(1, 1), V(1, 2), V(2, 0), V(2, 1), V(2, 2));
  mp.inertial = btTransform(basis, btVector3(com.x(), com.y(), com.z()));
  Eigen::Vector3d ev = es.eigenvalues();
  double floor = 1e-9;
  mp.diag = btVector3(std::max(ev(0), floor), std::max(ev(1), floor), std::max(ev(2), floor));
  return mp;
}
}  // namespace

// ---------------------------------------------------------------- Robot

std::vector<std::string> Robot::movableJoints() const
{
  std::vector<std::string> out;
  for (const auto& j : joints_)
    out.push_back(j.spec->name);
  return out;
}

btTransform Robot::bodyWorld(const LinkRef& ref) const
{
  return ref.body < 0 ? mb_->getBaseWorldTransform() : mb_->getLink(ref.body).m_cachedWorldTransform;
}

btTransform Robot::linkPose(const std::string& link) const
{
  const LinkRef& ref = links_.at(link);
  return bodyWorld(ref) * ref.in_body_inertial;
}

void Robot::addWrench(const std::string& link, const btVector3& force, const btVector3& torque)
{
  const int body = links_.at(link).body;
  if (body < 0)
  {
    mb_->addBaseForce(force);
    mb_->addBaseTorque(torque);
  }
  else
  {
    mb_->addLinkForce(body, force);
    mb_->addLinkTorque(body, torque);
  }
  mb_->wakeUp();
  auto& sum = pending_wrench_[static_cast<size_t>(body + 1)];
  sum.first += force;
  sum.second += torque;
}

std::pair<btVector3, btVector3> Robot::externalWrench(const std::string& link) const
{
  return last_wrench_[static_cast<size_t>(links_.at(link).body + 1)];
}

bool Robot::hasKeptFixedJoint(const std::string& n) const
{
  return kept_fixed_.count(n) != 0;
}

void Robot::watchJointWrench(const std::string& joint)
{
  for (const auto& w : watched_wrench_)
    if (w.spec->name == joint)
      return;
  WatchedJoint w;
  if (hasJoint(joint))
  {
    w.spec = this->joint(joint).spec;
    w.link = this->joint(joint).link;
  }
  else
  {
    w.link = kept_fixed_.at(joint);
    for (const JointSpec& js : spec_->joints)
      if (js.name == joint)
        w.spec = &js;
  }
  watched_wrench_.push_back(w);
}

std::pair<btVector3, btVector3> Robot::jointWrench(const std::string& joint) const
{
  for (const auto& w : watched_wrench_)
    if (w.spec->name == joint)
      return w.wrench;
  throw std::logic_error("jointWrench: joint " + joint + " is not watched");
}

std::vector<Robot::BodyMotion> Robot::bodyMotions() const
{
  const int n = mb_->getNumLinks();
  btAlignedObjectArray<btVector3> omega, vel;
  omega.resize(n + 1);
  vel.resize(n + 1);
  mb_->compTreeLinkVelocities(&omega[0], &vel[0]);  // in each body's own (principal) axes
  std::vector<BodyMotion> out(static_cast<size_t>(n + 1));
  for (int b = -1; b < n; ++b)
  {
    BodyMotion& o = out[static_cast<size_t>(b + 1)];
    o.pose = b < 0 ? mb_->getBaseWorldTransform() : mb_->getLink(b).m_cachedWorldTransform;
    const double m = b < 0 ? mb_->getBaseMass() : mb_->getLinkMass(b);
    const btVector3 inertia = b < 0 ? mb_->getBaseInertia() : mb_->getLinkInertia(b);
    o.p = o.pose.getBasis() * (m * vel[b + 1]);
    o.L = o.pose.getBasis() * (inertia * omega[b + 1]);  // diag(I) w, then to the world's axes
  }
  return out;
}

Pose Robot::linkState(const std::string& link) const
{
  const LinkRef& ref = links_.at(link);
  Pose p;
  const btTransform body_world = bodyWorld(ref);
  btVector3 v, w;
  if (ref.body < 0)
  {
    v = mb_->getBaseVel();
    w = mb_->getBaseOmega();
  }
  else
  {
    // Link velocities in local frames; index 0 is the base.
    btAlignedObjectArray<btVector3> omega, vel;
    omega.resize(mb_->getNumLinks() + 1);
    vel.resize(mb_->getNumLinks() + 1);
    mb_->compTreeLinkVelocities(&omega[0], &vel[0]);
    w = body_world.getBasis() * omega[ref.body + 1];
    v = body_world.getBasis() * vel[ref.body + 1];
  }
  p.tf = body_world * ref.in_body_inertial;
  p.angular = w;
  p.linear = v + w.cross(p.tf.getOrigin() - body_world.getOrigin());
  return p;
}

double Robot::jointPosition(const std::string& j) const
{
  return mb_->getJointPos(joint(j).link);
}
double Robot::jointVelocity(const std::string& j) const
{
  return mb_->getJointVel(joint(j).link);
}

void Robot::commandVelocity(const std::string& n, double vel, double max_effort)
{
  Joint& j = joints_.at(joint_index_.at(n));
  if (j.mode != Mode::VELOCITY || j.target != vel || j.max_effort != max_effort)
    mb_->wakeUp();
  j.mode = Mode::VELOCITY;
  j.target = vel;
  j.max_effort = max_effort;
}

void Robot::commandPosition(const std::string& n, double pos, double max_effort, double velocity)
{
  Joint& j = joints_.at(joint_index_.at(n));
  if (j.mode != Mode::POSITION || j.target != pos || j.max_effort != max_effort)
    mb_->wakeUp();
  j.mode = Mode::POSITION;
  j.target = pos;
  j.target_velocity = velocity;
  j.max_effort = max_effort;
}

void Robot::commandNone(const std::string& n)
{
  joints_.at(joint_index_.at(n)).mode = Mode::NONE;
}

void Robot::commandEffort(const std::string& n, double effort)
{
  Joint& j = joints_.at(joint_index_.at(n));
  if (j.spec->effort > 0)
    effort = std::max(-j.spec->effort, std::min(j.spec->effort, effort));
  if (j.mode != Mode::EFFORT || j.target != effort)
    mb_->wakeUp();
  j.mode = Mode::EFFORT;
  j.target = effort;
}

double Robot::jointEffort(const std::string& n) const
{
  const Joint& j = joint(n);
  switch (j.mode)
  {
    case Mode::EFFORT:
      return j.target;
    case Mode::VELOCITY:
    case Mode::POSITION:
      return j.motor_effort;
    case Mode::NONE:
      break;
  }
  return 0.0;
}

void Robot::setContactFriction(double mu)
{
  for (auto& surfaces : child_mu_)
    for (auto& sf : *surfaces)
      sf.mu = mu;
}

// ---------------------------------------------------------------- World

PhysicsWorld::PhysicsWorld(const WorldSpec& world, const Options& opt) : opt_(opt), spec_(world)
{
  gContactAddedCallback = contactAdded;
  config_ = std::make_unique<btDefaultCollisionConfiguration>();
  dispatcher_ = std::make_unique<btCollisionDispatcher>(config_.get());
  broadphase_ = std::make_unique<btDbvtBroadphase>();
  solver_ = std::make_unique<btMultiBodyConstraintSolver>();
  world_ =
      std::make_unique<btMultiBodyDynamicsWorld>(dispatcher_.get(), broadphase_.get(), solver_.get(), config_.get());
  world_->setGravity(spec_.gravity);
  auto& si = world_->getSolverInfo();
  si.m_numIterations = opt_.solver_iterations;
  si.m_timeStep = opt_.step;
  si.m_splitImpulse = 1;
  if (spec_.ground_plane)
  {
    WorldModel g;
    g.name = "ground_plane";
    g.is_static = true;
    WorldLink l;
    l.name = "link";
    Shape s;
    s.type = Shape::PLANE;
    l.shapes.push_back(s);
    g.links.push_back(l);
    addWorldModel(g);
  }
  for (const auto& m : spec_.models)
    addWorldModel(m);
}

namespace
{
void deleteShape(btCollisionShape* shape)
{
  // A triangle mesh shape does not own its mesh (built by buildShape).
  if (auto* mesh = dynamic_cast<btBvhTriangleMeshShape*>(shape))
    delete mesh->getMeshInterface();
  delete shape;
}
}  // namespace

PhysicsWorld::~PhysicsWorld()
{
  while (!robots_.empty())
    removeRobot(robots_.back()->name());
  for (auto& wb : world_bodies_)
    removeWorldBody(wb);
}

void PhysicsWorld::removeWorldBody(WorldBody& wb)
{
  if (wb.body)
    world_->removeRigidBody(wb.body);
  else
    world_->removeCollisionObject(wb.obj);
  delete wb.obj;
  for (auto* shape : wb.shapes)
    deleteShape(shape);
  wb.obj = nullptr;
  wb.body = nullptr;
  wb.shapes.clear();
}

void PhysicsWorld::addModel(const WorldModel& m)
{
  if (robot(m.name) ||
      std::any_of(world_bodies_.begin(), world_bodies_.end(), [&](const WorldBody& wb) { return wb.model == m.name; }))
    throw LoadError("model name '" + m.name + "' already exists");
  if (std::none_of(m.links.begin(), m.links.end(), [](const WorldLink& l) { return !l.shapes.empty(); }))
    throw LoadError("model '" + m.name + "' has no link with a <collision>: there is nothing to simulate");
  spec_.models.push_back(m);
  addWorldModel(spec_.models.back());
}

bool PhysicsWorld::removeModel(std::string name, bool* was_static)
{
  bool found = false;
  for (auto it = world_bodies_.begin(); it != world_bodies_.end();)
  {
    if (it->model != name)
    {
      ++it;
      continue;
    }
    if (was_static)
      *was_static = it->body == nullptr;
    removeWorldBody(*it);
    it = world_bodies_.erase(it);
    found = true;
  }
  leaveModelOrder(name);
  // Its spec too: the static world's slices and the cameras' scene are built from it.
  spec_.models.erase(
      std::remove_if(spec_.models.begin(), spec_.models.end(), [&](const WorldModel& m) { return m.name == name; }),
      spec_.models.end());
  return found;
}

btCollisionShape* PhysicsWorld::buildShape(const Shape& s, bool dynamic_body, std::vector<btCollisionShape*>& owned,
                                           const std::string& where)
{
  btCollisionShape* shape = nullptr;
  switch (s.type)
  {
    case Shape::BOX:
    {
      shape = new btBoxShape(s.size * 0.5);
      // Bullet's default 4 cm margin would round small boxes away.
      shape->setMargin(std::min(0.004, 0.1 * std::min({s.size.x(), s.size.y(), s.size.z()})));
      break;
    }
    case Shape::CYLINDER:
    {
      shape = new btCylinderShapeZ(btVector3(s.radius, s.radius, s.length * 0.5));
      shape->setMargin(std::min(0.002, 0.1 * std::min(s.radius, s.length)));
      break;
    }
    case Shape::SPHERE:
      shape = new btSphereShape(s.radius);
      break;
    case Shape::PLANE:
      if (dynamic_body)
        throw LoadError(where + ": <plane> geometry only in static models");
      shape = new btStaticPlaneShape(s.normal, 0);
      break;
    case Shape::MESH:
    {
      if (dynamic_body)
      {
        auto* hull = new btConvexHullShape();
        for (const auto& t : *s.triangles)
        {
          hull->addPoint(t.a, false);
          hull->addPoint(t.b, false);
          hull->addPoint(t.c, false);
        }
        hull->recalcLocalAabb();
        hull->optimizeConvexHull();
        hull->setMargin(0.001);
        shape = hull;
      }
      else
      {
        auto* mesh = new btTriangleMesh();
        for (const auto& t : *s.triangles)
          mesh->addTriangle(t.a, t.b, t.c, true);
        shape = new btBvhTriangleMeshShape(mesh, true);
      }
      break;
    }
  }
  owned.push_back(shape);
  return shape;
}

void PhysicsWorld::enterModelOrder(const std::string& name)
{
  // model_order_ stays sorted by rank (the file's models in its order, then the others as they
  // came), so the place is found by bisection: a world of 1000 models loads in O(n^2 log n)
  // string comparisons at worst.
  const std::vector<std::string>& file = spec_.file_order;
  const auto rank = [&](const std::string& n) { return std::find(file.begin(), file.end(), n) - file.begin(); };
  const auto r = rank(name);  // file.size() when the file does not list it: after the file's own
  model_order_.insert(std::upper_bound(model_order_.begin(), model_order_.end(), r,
                                       [&](auto rank_of_new, const std::string& n) { return rank_of_new < rank(n); }),
                      name);
}

void PhysicsWorld::leaveModelOrder(const std::string& name)
{
  model_order_.erase(std::remove(model_order_.begin(), model_order_.end(), name), model_order_.end());
  // Spawned again, it comes after the file's models, as any spawned model.
  spec_.file_order.erase(std::remove(spec_.file_order.begin(), spec_.file_order.end(), name), spec_.file_order.end());
}

void PhysicsWorld::addWorldModel(const WorldModel& m)
{
  enterModelOrder(m.name);
  for (const auto& l : m.links)
  {
    if (l.shapes.empty())
      continue;
    std::string where = spec_.source + ": model '" + m.name + "' link '" + l.name + "'";
    auto* compound = new btCompoundShape(true, static_cast<int>(l.shapes.size()));
    std::vector<btCollisionShape*> owned{compound};
    auto mus = std::make_shared<std::vector<Surface>>();
    bool has_plane = false;
    for (const auto& s : l.shapes)
    {
      btCollisionShape* cs = buildShape(s, !m.is_static, owned, where);
      has_plane |= s.type == Shape::PLANE;
      compound->addChildShape(s.pose, cs);
      mus->push_back(Surface{std::min(s.mu1, s.mu2)});
    }
    btTransform tf = m.pose * l.pose;
    btCollisionObject* obj = nullptr;
    btRigidBody* body = nullptr;
    btCollisionShape* shape = compound;
    btTransform link_in_body = btTransform::getIdentity();
    if (has_plane && l.shapes.size() == 1)
    {
      // Planes cannot live in compounds sensibly; use the plane directly.
      shape = compound->getChildShape(0);
      tf = tf * l.shapes[0].pose;
      link_in_body = l.shapes[0].pose.inverse();
    }
    if (m.is_static)
    {
      obj = new btCollisionObject();
      obj->setCollisionShape(shape);
      obj->setWorldTransform(tf);
      obj->setFriction(1.0);
      world_->addCollisionObject(obj, kStaticGroup, btBroadphaseProxy::AllFilter ^ kStaticGroup);
    }
    else
    {
      btVector3 inertia(0, 0, 0);
      shape->calculateLocalInertia(l.mass, inertia);
      btRigidBody::btRigidBodyConstructionInfo ci(l.mass, nullptr, shape, inertia);
      ci.m_startWorldTransform = tf;
      ci.m_friction = 1.0;
      body = new btRigidBody(ci);
      obj = body;
      world_->addRigidBody(body, kDynamicGroup, btBroadphaseProxy::AllFilter);
    }
    if (shape == compound)
      obj->setUserPointer(mus.get());
    world_bodies_.push_back({m.name, obj, body, body ? std::make_shared<const WorldLink>(l) : nullptr, tf, has_plane,
                             l.name, l.pose, link_in_body, owned, mus});
  }
}

// A moving body of the multibody: a link with every link fixed to it, in breadth-first order so
// parents precede children.
struct PhysicsWorld::LumpedBody
{
  std::string root;
  int parent = -2;
  const JointSpec* joint = nullptr;
  btTransform joint_in_parent_root;
  std::vector<std::pair<const LinkSpec*, btTransform>> members;
  MassProps mp;
};

Robot& PhysicsWorld::addRobot(std::shared_ptr<const RobotSpec> spec, const std::string& name, const std::string& ns,
                              const btTransform& pose)
{
  if (robot(name))
    throw LoadError("model name '" + name + "' already exists");
  for (const auto& wb : world_bodies_)
    if (wb.model == name)
      throw LoadError("model name '" + name + "' already exists");
  auto r = std::make_unique<Robot>();
  r->name_ = name;
  r->ns_ = ns;
  r->spec_ = spec;
  r->spawn_ = pose;
  LinkPlaces where;
  const std::vector<LumpedBody> bodies = lumpFixedJoints(*spec, where);
  buildMultiBody(bodies, *r);
  for (const auto& [lname, bw] : where)
    r->links_[lname] = Robot::LinkRef{bw.first - 1, bodies[bw.first].mp.inertial.inverse() * bw.second};
  addColliders(bodies, *r);
  addJointConstraints(bodies, *r);
  setRobotPose(*r, pose, btVector3(0, 0, 0), btVector3(0, 0, 0));
  enterModelOrder(r->name_);
  robots_.push_back(std::move(r));
  return *robots_.back();
}

// A URDF whose root link is named "world" is fixed where it is spawned, its fixed children (the
// robot's base) with it, as Gazebo's URDF conversion joins such a robot to the world (UR's and
// most arms' descriptions: `world` -> `world_joint` (fixed) -> `base_link`). Featherstone's
// multibody then has a fixed base.
static bool anchoredToWorld(const RobotSpec& rs)
{
  return rs.root == "world";
}

// Fixed joints are lumped: Featherstone's multibody has one link per moving joint, and a fixed
// child's mass, inertia and colliders join its parent's (as Gazebo's URDF conversion does).
std::vector<PhysicsWorld::LumpedBody> PhysicsWorld::lumpFixedJoints(const RobotSpec& rs, LinkPlaces& where)
{
  std::vector<LumpedBody> bodies;
  bodies.push_back(LumpedBody{
      rs.root, -1, nullptr, btTransform::getIdentity(), {{rs.link(rs.root), btTransform::getIdentity()}}, {}});
  where[rs.root] = {0, btTransform::getIdentity()};
  std::vector<std::string> queue{rs.root};
  for (size_t qi = 0; qi < queue.size(); ++qi)
  {
    const std::string cur = queue[qi];
    for (const auto& j : rs.joints)
    {
      if (j.parent != cur)
        continue;
      auto [pb, ptf] = where[cur];
      if (j.type == JointSpec::FIXED && !j.keep_fixed)
      {
        btTransform t = ptf * j.origin;
        where[j.child] = {pb, t};
        bodies[pb].members.push_back({rs.link(j.child), t});
      }
      else
      {
        LumpedBody b;
        b.root = j.child;
        b.parent = pb;
        b.joint = &j;
        b.joint_in_parent_root = ptf * j.origin;
        b.members.push_back({rs.link(j.child), btTransform::getIdentity()});
        where[j.child] = {static_cast<int>(bodies.size()), btTransform::getIdentity()};
        bodies.push_back(b);
      }
      queue.push_back(j.child);
    }
  }
  for (auto& b : bodies)
  {
    b.mp = composite(b.members);
    if (b.mp.mass <= 0)
    {
      if (b.parent == -1 && !anchoredToWorld(rs))
        throw LoadError(rs.source + ": link '" + b.root + "': the root body (with its fixed children) has no mass");
      // Massless moving links are kept with a token mass (Gazebo would drop them).
      b.mp.mass = 1e-3;
      b.mp.diag = btVector3(1e-7, 1e-7, 1e-7);
    }
  }
  return bodies;
}

// One multibody link per moving body, each in its inertial frame, joined by its joint.
void PhysicsWorld::buildMultiBody(const std::vector<LumpedBody>& bodies, Robot& r)
{
  const int nlinks = static_cast<int>(bodies.size()) - 1;
  btMultiBody* mb = new btMultiBody(nlinks, bodies[0].mp.mass, bodies[0].mp.diag, anchoredToWorld(*r.spec_), true);
  mb->setLinearDamping(0);
  mb->setAngularDamping(0);
  mb->setHasSelfCollision(false);
  mb->setUseGyroTerm(true);
  mb->setMaxCoordinateVelocity(1000);
  r.base_root_in_inertial_ = bodies[0].mp.inertial.inverse();
  for (int i = 1; i <= nlinks; ++i)
  {
    const LumpedBody& b = bodies[i];
    const btTransform& Pi = bodies[b.parent].mp.inertial;
    const btTransform& Ci = b.mp.inertial;
    // The joint frame (at zero position) seen from the parent's and from the child's centre of mass.
    btTransform offA = Pi.inverse() * b.joint_in_parent_root * b.joint->pivot;
    btTransform offB = Ci.inverse() * b.joint->pivot;
    btQuaternion rotParentToThis = offB.getRotation() * offA.getRotation().inverse();
    btVector3 axis = quatRotate(offB.getRotation(), b.joint->axis);
    int parent_link = b.parent - 1;
    if (b.joint->type == JointSpec::FIXED)  // a fixed joint Gazebo keeps (keep_fixed)
      mb->setupFixed(i - 1, b.mp.mass, b.mp.diag, parent_link, rotParentToThis, offA.getOrigin(), -offB.getOrigin(),
                     true);
    else if (b.joint->type == JointSpec::BALL)
      mb->setupSpherical(i - 1, b.mp.mass, b.mp.diag, parent_link, rotParentToThis, offA.getOrigin(), -offB.getOrigin(),
                         true);
    else if (b.joint->type == JointSpec::PRISMATIC)
      mb->setupPrismatic(i - 1, b.mp.mass, b.mp.diag, parent_link, rotParentToThis, axis, offA.getOrigin(),
                         -offB.getOrigin(), true);
    else
      mb->setupRevolute(i - 1, b.mp.mass, b.mp.diag, parent_link, rotParentToThis, axis, offA.getOrigin(),
                        -offB.getOrigin(), true);
  }
  mb->finalizeMultiDof();
  world_->addMultiBody(mb);
  r.mb_ = mb;
  r.gravity_off_.assign(bodies.size(), 0);
  r.pending_wrench_.assign(bodies.size(), {btVector3(0, 0, 0), btVector3(0, 0, 0)});
  r.last_wrench_ = r.pending_wrench_;
}

// Colliders: one compound per body in its inertial frame, each child shape with its own friction.
void PhysicsWorld::addColliders(const std::vector<LumpedBody>& bodies, Robot& r)
{
  const RobotSpec& rs = *r.spec_;
  btMultiBody* mb = r.mb_;
  for (int i = 0; i < static_cast<int>(bodies.size()); ++i)
  {
    const LumpedBody& b = bodies[i];
    auto* compound = new btCompoundShape(true);
    auto mus = std::make_unique<std::vector<Surface>>();
    btTransform inv = b.mp.inertial.inverse();
    for (const auto& [link, tf] : b.members)
      for (const auto& s : link->collisions)
      {
        btCollisionShape* cs = buildShape(s, true, r.shapes_, rs.source + ": link '" + link->name + "'");
        compound->addChildShape(inv * tf * s.pose, cs);
        mus->push_back(Surface{std::min(s.mu1, s.mu2)});
      }
    r.shapes_.push_back(compound);
    if (compound->getNumChildShapes() == 0)
      continue;
    auto* col = new btMultiBodyLinkCollider(mb, i - 1);
    col->setCollisionShape(compound);
    col->setFriction(1.0);
    col->setRestitution(0);
    col->setUserPointer(mus.get());
    col->setCollisionFlags(col->getCollisionFlags() | btCollisionObject::CF_CUSTOM_MATERIAL_CALLBACK);
    world_->addCollisionObject(col, kDynamicGroup, btBroadphaseProxy::AllFilter);
    if (i == 0)
      mb->setBaseCollider(col);
    else
      mb->getLink(i - 1).m_collider = col;
    r.colliders_.push_back(col);
    r.child_mu_.push_back(std::move(mus));
  }
}

void PhysicsWorld::setDamping(Robot& r, Robot::Joint& j, double damping)
{
  j.damping = damping;
  if (damping > 0 && !j.damper)
  {
    j.damper = new DamperRow(r.mb_, j.link);
    world_->addMultiBodyConstraint(j.damper);
    r.constraints_.push_back(j.damper);
  }
  if (j.damper)
    static_cast<DamperRow*>(j.damper)->damping = damping;
}

// Joints: a motor for commands, one for Coulomb friction, a damper, limits.
void PhysicsWorld::addJointConstraints(const std::vector<LumpedBody>& bodies, Robot& r)
{
  btMultiBody* mb = r.mb_;
  for (int i = 1; i < static_cast<int>(bodies.size()); ++i)
  {
    const JointSpec* js = bodies[i].joint;
    if (js->type == JointSpec::FIXED)
    {
      r.kept_fixed_[js->name] = i - 1;
      continue;
    }
    if (js->type == JointSpec::BALL)
    {
      if (js->damping > 0)
      {
        auto* damper = new BallDamperRows(mb, i - 1, js->damping);
        world_->addMultiBodyConstraint(damper);
        r.constraints_.push_back(damper);
      }
      continue;
    }
    Robot::Joint j;
    j.spec = js;
    j.link = i - 1;
    j.limited = js->has_limits && js->type != JointSpec::CONTINUOUS;
    j.lower = js->lower;
    j.upper = js->upper;
    j.motor = new JointMotor(mb, i - 1, 0, 0);
    j.motor->setMaxAppliedImpulse(0);
    world_->addMultiBodyConstraint(j.motor);
    r.constraints_.push_back(j.motor);
    if (js->friction > 0)
    {
      j.friction = new btMultiBodyJointMotor(mb, i - 1, 0, js->friction * opt_.step);
      world_->addMultiBodyConstraint(j.friction);
      r.constraints_.push_back(j.friction);
    }
    setDamping(r, j, js->damping);
    if (j.limited)
    {
      j.limit = new btMultiBodyJointLimitConstraint(mb, i - 1, j.lower, j.upper);
      world_->addMultiBodyConstraint(j.limit);
      r.constraints_.push_back(j.limit);
    }
    r.joint_index_[js->name] = r.joints_.size();
    r.joints_.push_back(j);
  }
}

void PhysicsWorld::setRobotPose(Robot& r, const btTransform& root_pose, const btVector3& lin, const btVector3& ang)
{
  btMultiBody* mb = r.mb_;
  btTransform base = root_pose * r.base_root_in_inertial_.inverse();
  mb->setBaseWorldTransform(base);
  mb->setBaseVel(lin + ang.cross(base.getOrigin() - root_pose.getOrigin()));
  mb->setBaseOmega(ang);
  mb->clearForcesAndTorques();
  mb->wakeUp();
  syncRobotTransforms(r);
}

void PhysicsWorld::syncRobotTransforms(Robot& r)
{
  r.mb_->forwardKinematics(scratch_q_, scratch_m_);
  r.mb_->updateCollisionObjectWorldTransforms(scratch_q_, scratch_m_);
  for (auto* c : r.colliders_)
    world_->updateSingleAabb(c);
}

bool PhysicsWorld::removeRobot(std::string name)
{
  for (auto it = robots_.begin(); it != robots_.end(); ++it)
  {
    Robot& r = **it;
    if (r.name_ != name)
      continue;
    for (auto* c : r.constraints_)
    {
      world_->removeMultiBodyConstraint(c);
      delete c;
    }
    for (auto* c : r.colliders_)
    {
      world_->removeCollisionObject(c);
      delete c;
    }
    world_->removeMultiBody(r.mb_);
    delete r.mb_;
    for (auto* s : r.shapes_)
      deleteShape(s);
    robots_.erase(it);
    leaveModelOrder(name);
    return true;
  }
  return false;
}

Robot* PhysicsWorld::robot(const std::string& name)
{
  for (auto& r : robots_)
    if (r->name_ == name)
      return r.get();
  return nullptr;
}

std::vector<Robot*> PhysicsWorld::robots()
{
  std::vector<Robot*> out;
  for (auto& r : robots_)
    out.push_back(r.get());
  return out;
}

void PhysicsWorld::step()
{
  const double dt = opt_.step;
  for (auto& rp : robots_)
  {
    Robot& r = *rp;
    btMultiBody* mb = r.mb_;
    for (auto& j : r.joints_)
    {
      switch (j.mode)
      {
        case Robot::Mode::NONE:
          j.motor->setMaxAppliedImpulse(0);
          break;
        case Robot::Mode::VELOCITY:
        {
          // A motor cannot exceed the URDF <limit velocity> (when given).
          double vmax = j.spec->velocity > 0 ? j.spec->velocity : 1e9;
          j.motor->setVelocityTarget(std::max(-vmax, std::min(vmax, j.target)), 1.0);
          j.motor->setPositionTarget(0, 0);
          j.motor->setMaxAppliedImpulse(j.max_effort * dt);
          break;
        }
        case Robot::Mode::EFFORT:
          j.motor->setMaxAppliedImpulse(0);
          mb->addJointTorque(j.link, j.target);
          break;
        case Robot::Mode::POSITION:
          // Critically damped-ish servo: converge over ~10 steps, effort-limited.
          j.motor->setPositionTarget(j.target, 0.1);
          j.motor->setVelocityTarget(j.target_velocity, 1.0);
          j.motor->setMaxAppliedImpulse(j.max_effort * dt);
          break;
      }
    }
  }
  applyWrenches();
  applyEfforts();
  cancelGravity();
  for (auto& rp : robots_)
    if (!rp->watched_wrench_.empty())
      rp->motion_before_ = rp->bodyMotions();
  world_->stepSimulation(dt, 0, dt);
  for (auto& rp : robots_)
  {
    for (auto& j : rp->joints_)  // every joint's motor is one (addJointConstraints)
      j.motor_effort = static_cast<JointMotor*>(j.motor)->lastImpulse() / dt;
    std::swap(rp->last_wrench_, rp->pending_wrench_);
    for (auto& w : rp->pending_wrench_)
      w = {btVector3(0, 0, 0), btVector3(0, 0, 0)};
  }
  // The links' world transforms at the new joint positions: Bullet leaves the cached ones where
  // the step began (a link on a turning joint was reported a step behind its joint's position).
  for (auto& rp : robots_)
    rp->mb_->forwardKinematics(scratch_q_, scratch_m_);
  ++steps_;
  time_ = time_base_ + (steps_ - steps_base_) * dt;
  updateContacts();
  for (auto& rp : robots_)
    if (!rp->watched_wrench_.empty())
      jointWrenches(*rp);
}

// A joint's wrench by Newton-Euler on the subtree S its child heads. The joint is the only link
// between S and the rest of the robot, so what it transmits is what S's motion needs beyond the
// other external wrenches: f = dp/dt - sum(m g + F_applied + F_contact), and about a point P,
// tau_P = sum[dL_k/dt + (c_k - P) x (dp_k/dt - m_k g - F_k)] - sum(tau_k) - sum((x_i - P) x F_i)
// over S's bodies k (centre of mass c_k) and its contact points x_i. The rates are the step's:
// Bullet's semi-implicit step makes m (v' - v) / dt exactly the mean force of the step, contact
// and joint impulses included, and the forces between S's own bodies cancel in the sum. Those
// forces act where the step began (positions move last, with the new velocities), so the moment
// arms and the child's axes are taken there too.
void PhysicsWorld::jointWrenches(Robot& r)
{
  btMultiBody* mb = r.mb_;
  const int n = mb->getNumLinks();
  const double dt = opt_.step;
  const std::vector<Robot::BodyMotion>& before = r.motion_before_;
  const std::vector<Robot::BodyMotion> after = r.bodyMotions();
  if (before.size() != after.size())
    return;
  // Per body: the external force, and its torque about the body's centre of mass, over the step.
  std::vector<std::pair<btVector3, btVector3>> external(after.size(), {btVector3(0, 0, 0), btVector3(0, 0, 0)});
  for (int b = -1; b < n; ++b)
  {
    const size_t k = static_cast<size_t>(b + 1);
    const double m = b < 0 ? mb->getBaseMass() : mb->getLinkMass(b);
    if (k >= r.gravity_off_.size() || !r.gravity_off_[k])
      external[k].first += spec_.gravity * m;
    external[k].first += r.last_wrench_[k].first;
    external[k].second += r.last_wrench_[k].second;
  }
  for (int i = 0; i < dispatcher_->getNumManifolds(); ++i)
  {
    const btPersistentManifold* m = dispatcher_->getManifoldByIndexInternal(i);
    for (int side = 0; side < 2; ++side)
    {
      const auto* col = btMultiBodyLinkCollider::upcast(side == 0 ? m->getBody0() : m->getBody1());
      if (!col || col->m_multiBody != mb)
        continue;
      const auto* other = btMultiBodyLinkCollider::upcast(side == 0 ? m->getBody1() : m->getBody0());
      if (other && other->m_multiBody == mb)
        continue;  // a self-collision: the two bodies' impulses are equal and opposite
      const size_t k = static_cast<size_t>(col->m_link + 1);
      const btVector3 c = before[k].pose.getOrigin();
      for (int p = 0; p < m->getNumContacts(); ++p)
      {
        const btManifoldPoint& pt = m->getContactPoint(p);
        // Bullet's normal points from body 1 into body 0; friction acts along the lateral
        // directions on body 0, and the opposite on body 1.
        btVector3 impulse = pt.m_normalWorldOnB * pt.m_appliedImpulse +
                            pt.m_lateralFrictionDir1 * pt.m_appliedImpulseLateral1 +
                            pt.m_lateralFrictionDir2 * pt.m_appliedImpulseLateral2;
        if (side == 1)
          impulse = -impulse;
        const btVector3 f = impulse / dt;
        const btVector3 x = side == 0 ? pt.getPositionWorldOnA() : pt.getPositionWorldOnB();
        external[k].first += f;
        external[k].second += (x - c).cross(f);
      }
    }
  }
  for (auto& w : r.watched_wrench_)
  {
    const int head = w.link;
    // In the child link's axes, about the joint's origin (the child's own for a URDF joint).
    const btTransform child = before[static_cast<size_t>(head + 1)].pose * r.links_.at(w.spec->child).in_body_inertial;
    const btVector3 P = child * w.spec->pivot.getOrigin();
    btVector3 f(0, 0, 0), tau(0, 0, 0);
    for (int b = head; b < n; ++b)
    {
      int a = b;
      while (a > head)
        a = mb->getParent(a);
      if (a != head)
        continue;  // not in the subtree (links are numbered parents first)
      const size_t k = static_cast<size_t>(b + 1);
      const btVector3 net = (after[k].p - before[k].p) / dt - external[k].first;
      f += net;
      tau += (after[k].L - before[k].L) / dt - external[k].second + (before[k].pose.getOrigin() - P).cross(net);
    }
    const btMatrix3x3 to_child = child.getBasis().transpose();
    w.wrench = {to_child * f, to_child * tau};
  }
}

Robot* PhysicsWorld::robotOf(const btCollisionObject* o) const
{
  const auto* c = btMultiBodyLinkCollider::upcast(o);
  if (!c)
    return nullptr;
  for (const auto& r : robots_)
    if (r->mb_ == c->m_multiBody)
      return r.get();
  return nullptr;
}

std::string PhysicsWorld::modelOf(const btCollisionObject* o) const
{
  if (Robot* r = robotOf(o))
    return r->name_;
  for (const auto& wb : world_bodies_)
    if (wb.obj == o)
      return wb.ground ? std::string() : wb.model;
  return "?";
}

void PhysicsWorld::recordPoints(const btPersistentManifold* m)
{
  for (int side = 0; side < 2; ++side)
  {
    const btCollisionObject* self = side == 0 ? m->getBody0() : m->getBody1();
    Robot* r = robotOf(self);
    if (!r || !r->record_points_)
      continue;
    const auto* col = btMultiBodyLinkCollider::upcast(self);
    std::vector<std::string> links;
    for (const auto& [name, ref] : r->links_)
      if (ref.body == col->m_link)
        links.push_back(name);
    std::string other = modelOf(side == 0 ? m->getBody1() : m->getBody0());
    if (other.empty())
      other = "ground_plane";
    for (int k = 0; k < m->getNumContacts(); ++k)
    {
      const btManifoldPoint& p = m->getContactPoint(k);
      // A body resting on another is held a hair apart as often as a hair into it (+1e-7 m for a
      // wheel on the ground, as the bodies around it had it): a point that pushed counts too.
      if (p.getDistance() > 0 && p.getAppliedImpulse() <= 0)
        continue;
      Robot::Contacts::Point pt;
      pt.links = links;
      pt.other = other;
      // Bullet's normal points from body 1 to body 0.
      pt.position = side == 0 ? p.getPositionWorldOnA() : p.getPositionWorldOnB();
      pt.normal = side == 0 ? p.m_normalWorldOnB : -p.m_normalWorldOnB;
      pt.depth = -p.getDistance();
      pt.impulse = p.getAppliedImpulse();
      r->contacts_.points.push_back(std::move(pt));
    }
  }
}

void PhysicsWorld::updateContacts()
{
  for (auto& r : robots_)
  {
    r->contacts_.now.clear();
    r->contacts_.points.clear();
  }
  const int n = dispatcher_->getNumManifolds();
  for (int i = 0; i < n; ++i)
  {
    const btPersistentManifold* m = dispatcher_->getManifoldByIndexInternal(i);
    recordPoints(m);
    // Points within the contact margin are kept before bodies touch: only penetration counts.
    double depth = 0;
    for (int k = 0; k < m->getNumContacts(); ++k)
      depth = std::max(depth, -double(m->getContactPoint(k).getDistance()));
    if (depth <= 0)
      continue;
    Robot* ra = robotOf(m->getBody0());
    Robot* rb = robotOf(m->getBody1());
    if ((!ra && !rb) || ra == rb)
      continue;  // world-world, or a robot's own links
    for (auto [r, other] : {std::make_pair(ra, m->getBody1()), std::make_pair(rb, m->getBody0())})
    {
      if (!r)
        continue;
      std::string what = modelOf(other);
      if (what.empty())
        continue;
      auto& c = r->contacts_;
      if (std::find(c.now.begin(), c.now.end(), what) == c.now.end())
        c.now.push_back(what);
      c.max_depth = std::max(c.max_depth, depth);
      if (c.first_time < 0)
      {
        c.first_time = time_;
        c.first_model = what;
      }
    }
  }
  for (auto& r : robots_)
    if (!r->contacts_.now.empty())
    {
      ++r->contacts_.steps;
      r->contacts_.time += opt_.step;
    }
}

bool PhysicsWorld::resetWorld()
{
  bool static_changed = false;
  for (auto& wb : world_bodies_)
    if (!wb.body && !(wb.obj->getWorldTransform() == wb.initial))
    {
      placeStatic(wb, wb.initial);
      static_changed = true;
    }
  for (auto& rp : robots_)
  {
    Robot& r = *rp;
    r.contacts_ = Robot::Contacts();
    for (int i = 0; i < r.mb_->getNumLinks(); ++i)
      if (r.mb_->getLink(i).m_jointType == btMultibodyLink::eFixed)
        continue;  // a kept fixed joint: nothing to reset (and no velocity of its own to write)
      else if (r.mb_->getLink(i).m_jointType == btMultibodyLink::eSpherical)
      {
        const btScalar identity[4] = {0, 0, 0, 1}, rest[3] = {0, 0, 0};  // the quaternion x y z w
        r.mb_->setJointPosMultiDof(i, identity);
        r.mb_->setJointVelMultiDof(i, rest);
      }
      else
      {
        r.mb_->setJointPos(i, 0);
        r.mb_->setJointVel(i, 0);
      }
    for (auto& j : r.joints_)
    {
      if (j.mode == Robot::Mode::VELOCITY)
        j.target = 0;
      j.motor_effort = 0;  // at rest: nothing exerted until the next step
    }
    setRobotPose(r, r.spawn_, btVector3(0, 0, 0), btVector3(0, 0, 0));
  }
  for (auto& wb : world_bodies_)
  {
    if (!wb.body)
      continue;
    wb.body->setWorldTransform(wb.initial);
    wb.body->setLinearVelocity(btVector3(0, 0, 0));
    wb.body->setAngularVelocity(btVector3(0, 0, 0));
    wb.body->activate(true);
  }
  world_->getBroadphase()->resetPool(dispatcher_.get());
  world_->getConstraintSolver()->reset();
  return static_changed;
}

void PhysicsWorld::placeStatic(WorldBody& wb, const btTransform& body_tf)
{
  wb.obj->setWorldTransform(body_tf);
  world_->updateSingleAabb(wb.obj);  // Bullet does not refresh a static object's bounds itself
  for (auto& m : spec_.models)
    if (m.name == wb.model)
      for (const auto& l : m.links)
        if (l.name == wb.link_name)
          m.pose = body_tf * wb.link_in_body * wb.link_in_model.inverse();
}

void PhysicsWorld::setRobotVelocity(Robot& r, const btVector3& lin, const btVector3& ang)
{
  const Pose root = r.linkState(r.spec().root);
  const btVector3 base = r.mb_->getBaseWorldTransform().getOrigin();
  r.mb_->setBaseVel(lin + ang.cross(base - root.tf.getOrigin()));
  r.mb_->setBaseOmega(ang);
  r.mb_->wakeUp();
}

bool PhysicsWorld::setModelState(const std::string& name, const btTransform& pose, const btVector3& lin,
                                 const btVector3& ang, bool* moved_static)
{
  if (Robot* r = robot(name))
  {
    setRobotPose(*r, pose, lin, ang);
    return true;
  }
  bool found = false;
  for (auto& wb : world_bodies_)
  {
    if (wb.model != name)
      continue;
    // `pose` is the model's frame: each link body where the model puts it.
    const btTransform body_tf = pose * wb.link_in_model * wb.link_in_body.inverse();
    found = true;
    if (!wb.body)
    {
      placeStatic(wb, body_tf);
      if (moved_static)
        *moved_static = true;
      continue;
    }
    wb.body->setWorldTransform(body_tf);
    wb.body->setLinearVelocity(lin + ang.cross(body_tf.getOrigin() - pose.getOrigin()));
    wb.body->setAngularVelocity(ang);
    wb.body->activate(true);
  }
  return found;
}

bool PhysicsWorld::getModelState(const std::string& name, Pose& out) const
{
  for (const auto& r : robots_)
    if (r->name_ == name)
    {
      out = r->linkState(r->spec_->root);
      return true;
    }
  for (const auto& wb : world_bodies_)
    if (wb.model == name)
    {
      out = modelFrameState(wb);
      return true;
    }
  return false;
}

Pose PhysicsWorld::linkFrameState(const WorldBody& wb)
{
  Pose p;
  p.tf = wb.obj->getWorldTransform() * wb.link_in_body;
  if (wb.body)
  {
    // A rigid body turns about its origin: the link frame's velocity adds w x r.
    p.angular = wb.body->getAngularVelocity();
    p.linear =
        wb.body->getLinearVelocity() + p.angular.cross(p.tf.getOrigin() - wb.obj->getWorldTransform().getOrigin());
  }
  return p;
}

Pose PhysicsWorld::modelFrameState(const WorldBody& wb)
{
  Pose p = linkFrameState(wb);
  const btVector3 link_origin = p.tf.getOrigin();
  p.tf = p.tf * wb.link_in_model.inverse();
  p.linear += p.angular.cross(p.tf.getOrigin() - link_origin);
  return p;
}

std::vector<std::pair<std::string, Pose>> PhysicsWorld::modelStates() const
{
  std::vector<std::pair<std::string, Pose>> out;
  for (const std::string& name : model_order_)
  {
    if (const Robot* r = robotNamed(name))
      out.emplace_back(name, r->linkState(r->spec_->root));
    else
      for (const auto& wb : world_bodies_)
        if (wb.model == name)
        {
          out.emplace_back(name, modelFrameState(wb));  // its first link stands for it
          break;
        }
  }
  return out;
}

std::vector<std::pair<std::string, Pose>> PhysicsWorld::linkStates() const
{
  std::vector<std::pair<std::string, Pose>> out;
  for (const std::string& name : model_order_)
  {
    if (const Robot* r = robotNamed(name))
    {
      for (const auto& l : r->spec_->links)
        if (r->hasLink(l.name))
          out.emplace_back(name + "::" + l.name, r->linkState(l.name));
      continue;
    }
    for (const auto& wb : world_bodies_)
      if (wb.model == name)
        out.emplace_back(name + "::" + wb.link_name, linkFrameState(wb));
  }
  return out;
}

std::vector<std::pair<std::string, Pose>> PhysicsWorld::movingLinksNear(const btVector3& centre, double radius,
                                                                        const std::string& except_model) const
{
  std::vector<std::pair<std::string, Pose>> out;
  for (const std::string& name : model_order_)
  {
    if (name == except_model)
      continue;
    if (const Robot* r = robotNamed(name))
    {
      // Where a frame is costs one transform; its velocity, a pass over the tree: only for those near.
      for (const auto& l : r->spec_->links)
        if (r->hasLink(l.name) && (r->linkPose(l.name).getOrigin() - centre).length() < radius)
          out.emplace_back(name + "::" + l.name, r->linkState(l.name));
      continue;
    }
    for (const auto& wb : world_bodies_)
      if (wb.model == name && wb.body &&
          ((wb.obj->getWorldTransform() * wb.link_in_body).getOrigin() - centre).length() < radius)
        out.emplace_back(name + "::" + wb.link_name, linkFrameState(wb));
  }
  return out;
}

bool PhysicsWorld::entityState(const std::string& name, Pose& out) const
{
  const size_t sep = name.find("::");
  if (sep == std::string::npos)
    return getModelState(name, out);
  const std::string model = name.substr(0, sep), link = name.substr(sep + 2);
  if (const Robot* r = robotNamed(model))
  {
    if (!r->hasLink(link))
      return false;
    out = r->linkState(link);
    return true;
  }
  for (const auto& wb : world_bodies_)
    if (wb.model == model && wb.link_name == link)
    {
      out = linkFrameState(wb);
      return true;
    }
  return false;
}

void worldWrench(const btVector3& force, const btVector3& torque, const btVector3& point, const btTransform* frame,
                 const btVector3& com, btVector3& force_out, btVector3& torque_out)
{
  if (!frame)
  {
    force_out = force;
    torque_out = torque + point.cross(force);
    return;
  }
  force_out = frame->getBasis() * force;
  torque_out = frame->getBasis() * torque + ((*frame) * point - com).cross(force_out);
}

bool PhysicsWorld::applyBodyWrench(const std::string& link, const btVector3& force, const btVector3& torque,
                                   double start, double duration)
{
  btVector3 com;
  if (!centreOfMass(link, com))
    return false;
  const size_t sep = link.find("::");  // centreOfMass found it, so it has one
  wrenches_.push_back(
      {link, link.substr(0, sep), link.substr(sep + 2), force, torque, JobTime(start, duration, opt_.step)});
  return true;
}

PhysicsWorld::JobTime::JobTime(double start_, double duration, double step)
    : start(start_), end(duration < 0 ? std::numeric_limits<double>::infinity() : start_ + std::max(duration, step))
{
}

void PhysicsWorld::clearBodyWrenches(const std::string& link)
{
  wrenches_.erase(std::remove_if(wrenches_.begin(), wrenches_.end(),
                                 [&](const WrenchJob& j) { return link.empty() || j.asked == link; }),
                  wrenches_.end());
}

bool PhysicsWorld::centreOfMass(const std::string& link, btVector3& out) const
{
  const size_t sep = link.find("::");
  if (sep == std::string::npos)
    return false;
  const std::string model = link.substr(0, sep), name = link.substr(sep + 2);
  if (const Robot* r = robotNamed(model))
  {
    if (!r->hasLink(name))
      return false;
    out = r->bodyWorld(r->links_.at(name)).getOrigin();  // a Featherstone body's frame is its centre of mass
    return true;
  }
  for (const auto& wb : world_bodies_)
    if (wb.model == model && wb.link_name == name && wb.body)
    {
      out = wb.body->getCenterOfMassPosition();
      return true;
    }
  return false;
}

// The wrenches due at this step, on the bodies they act on (Bullet clears them after each step).
// A job whose link has gone (its model deleted) is dropped.
void PhysicsWorld::applyWrenches()
{
  for (auto it = wrenches_.begin(); it != wrenches_.end();)
  {
    const WrenchJob& j = *it;
    bool exists = false;
    if (Robot* r = robot(j.model); r && r->hasLink(j.link))
    {
      exists = true;
      if (j.time.due(time_))
      {
        r->addWrench(j.link, j.force, j.torque);
      }
    }
    for (auto& wb : world_bodies_)
      if (wb.model == j.model && wb.link_name == j.link && wb.body)
      {
        exists = true;
        if (j.time.due(time_))
        {
          wb.body->applyCentralForce(j.force);
          wb.body->applyTorque(j.torque);
          wb.body->activate(true);
        }
      }
    if (!exists || j.time.over(time_, opt_.step))
      it = wrenches_.erase(it);
    else
      ++it;
  }
}

// A name several models have: which, and how to name one of them.
static std::string inSeveralModels(const std::string& kind, const std::string& name,
                                   const std::vector<std::string>& models)
{
  return kind + " '" + name + "' is in " + std::to_string(models.size()) + " models (" + models[0] + ", " + models[1] +
         (models.size() > 2 ? ", ..." : "") + "): name it model::" + kind;
}

std::string PhysicsWorld::findJoint(const std::string& joint, JointRef& out, const std::string& kind) const
{
  out = JointRef();
  const size_t sep = joint.find("::");
  const std::string model = sep == std::string::npos ? "" : joint.substr(0, sep);
  const std::string name = sep == std::string::npos ? joint : joint.substr(sep + 2);
  std::vector<JointRef> found;
  std::string gone;  // why a joint the model's file has is not one here
  for (const auto& r : robots_)
  {
    const JointSpec* js = (model.empty() || r->name_ == model) ? r->spec_->joint(name) : nullptr;
    if (!js)
      continue;
    const bool movable = r->hasJoint(name);
    const bool kept = r->hasKeptFixedJoint(name) ||
                      (r->spec_->from_sdf && (js->type == JointSpec::FIXED || js->type == JointSpec::BALL));
    if (movable || kept)
      found.push_back({r.get(), js, movable});
    else if (js->type == JointSpec::FIXED)
      gone = "joint '" + joint +
             "' is fixed, and Gazebo lumps it away as gazebo_lite does (its <gazebo reference> keeps it with "
             "<preserveFixedJoint>)";
    else
      gone = "joint '" + joint + "' is not simulated (its type is not one gazebo_lite moves)";
  }
  if (found.size() > 1)
  {
    std::vector<std::string> models;
    for (const auto& f : found)
      models.push_back(f.robot->name_);
    return inSeveralModels("joint", joint, models);
  }
  if (found.empty())
    return !gone.empty() ? gone : "no " + kind + " named '" + joint + "'";
  out = found.front();
  return "";
}

std::string PhysicsWorld::resolveJoint(const std::string& joint, const Robot*& robot, std::string& name) const
{
  JointRef ref;
  const std::string why = findJoint(joint, ref, "movable joint");
  robot = ref.robot;
  name = ref.spec ? ref.spec->name : joint;
  if (!why.empty() || ref.movable)
    return why;
  return "joint '" + joint + "' is " +
         (ref.spec->type == JointSpec::BALL ? "a ball joint, free about its pivot: it has no axis to move on"
                                            : "fixed: it does not move");
}

std::string PhysicsWorld::applyJointEffort(const std::string& joint, double effort, double start, double duration)
{
  const Robot* r = nullptr;
  std::string name;
  const std::string why = resolveJoint(joint, r, name);
  if (!why.empty())
    return why;
  efforts_.push_back({joint, r->name_, name, effort, JobTime(start, duration, opt_.step)});
  return "";
}

std::string PhysicsWorld::jointProperties(const std::string& joint, JointProperties& out) const
{
  JointRef ref;
  const std::string why = findJoint(joint, ref);
  if (!why.empty())
    return why;
  out = JointProperties();
  out.type = ref.spec->type;
  if (!ref.movable)  // fixed or ball: at 0, as Gazebo reports them
  {
    out.damping = ref.spec->damping;
    return "";
  }
  const Robot::Joint& j = ref.robot->joint(ref.spec->name);
  out.damping = j.damping;
  out.position = ref.robot->jointPosition(ref.spec->name);
  out.rate = ref.robot->jointVelocity(ref.spec->name);
  return "";
}

std::string PhysicsWorld::resolveBody(const std::string& link, BodyRef& out) const
{
  out = BodyRef();
  const size_t sep = link.find("::");
  const std::string name = sep == std::string::npos ? link : link.substr(sep + 2);
  const std::string model = sep == std::string::npos ? "" : link.substr(0, sep);
  const auto in_model = [&](const std::string& m) { return sep == std::string::npos || m == model; };
  std::vector<BodyRef> found;
  std::string lumped;  // why a link that is lumped into another is not one
  for (const auto& r : robots_)
  {
    if (!in_model(r->name_) || !r->hasLink(name))
      continue;
    const int body = r->links_.at(name).body;
    const auto bodies = bodyLinks(*r);
    const auto b = bodies.find(body);
    if (b == bodies.end())
      continue;  // a "world" root: the world, no link
    if (b->second != name)
    {
      lumped = "link '" + link + "' is lumped into '" + r->name_ + "::" + b->second +
               "' by a fixed joint, as in Gazebo: ask for that link";
      continue;
    }
    BodyRef ref;
    ref.robot = r.get();
    ref.body = body;
    ref.model = r->name_;
    ref.link = name;
    found.push_back(ref);
  }
  for (const auto& wb : world_bodies_)
    if (wb.link_name == name && in_model(wb.model))
    {
      BodyRef ref;
      ref.world = &wb;
      ref.model = wb.model;
      ref.link = name;
      found.push_back(ref);
    }
  if (found.size() > 1)
  {
    std::vector<std::string> models;
    for (const auto& f : found)
      models.push_back(f.model);
    return inSeveralModels("link", link, models);
  }
  if (found.empty())
    return !lumped.empty() ? lumped
                           : "no link named '" + link +
                                 "' (links are named model::link; a link without a <collision> is not simulated)";
  out = found.front();
  return "";
}

btTransform PhysicsWorld::bodyInLink(const BodyRef& b)
{
  // A multibody's body frame is its inertial frame; a world body's is its link frame (a plane's
  // shape pose aside).
  return b.robot ? b.robot->links_.at(b.link).in_body_inertial.inverse() : b.world->link_in_body.inverse();
}

static btMatrix3x3 diagonal(const btVector3& d)
{
  return btMatrix3x3(d.x(), 0, 0, 0, d.y(), 0, 0, 0, d.z());
}

std::string PhysicsWorld::linkProperties(const std::string& link, LinkProperties& out) const
{
  BodyRef b;
  const std::string why = resolveBody(link, b);
  if (!why.empty())
    return why;
  out = LinkProperties();
  const btTransform frame = bodyInLink(b);
  btVector3 moments(0, 0, 0);
  if (b.robot)
  {
    const btMultiBody* mb = b.robot->mb_;
    out.mass = b.body < 0 ? mb->getBaseMass() : mb->getLinkMass(b.body);
    moments = b.body < 0 ? mb->getBaseInertia() : mb->getLinkInertia(b.body);
    out.gravity_mode = !b.robot->gravity_off_[b.body + 1];
  }
  else if (b.world->body)
  {
    const btRigidBody* rb = b.world->body;
    const auto inverse = [](btScalar x) { return x > 0 ? 1 / x : 0; };
    out.mass = inverse(rb->getInvMass());
    const btVector3 inv = rb->getInvInertiaDiagLocal();
    moments = btVector3(inverse(inv.x()), inverse(inv.y()), inverse(inv.z()));
    out.gravity_mode = !(rb->getFlags() & BT_DISABLE_WORLD_GRAVITY);
  }
  else
  {
    // A static model's link does not move: its mass is the SDF's, and it has no inertia here.
    for (const auto& m : spec_.models)
      for (const auto& l : m.links)
        if (m.name == b.model && l.name == b.link)
          out.mass = l.mass;
  }
  out.com = frame.getOrigin();
  // The principal moments turned into the link frame's axes: R diag(I) R^T.
  out.inertia = frame.getBasis() * diagonal(moments) * frame.getBasis().transpose();
  return "";
}

std::string PhysicsWorld::setLinkProperties(const std::string& link, const LinkProperties& p)
{
  BodyRef b;
  const std::string why = resolveBody(link, b);
  if (!why.empty())
    return why;
  if (b.world && !b.world->body)
    return "model '" + b.model + "' is static: its links do not move";
  if (!(p.mass > 0))
    return "mass " + mybot_common::formatNumber(p.mass) + " kg: it must be > 0";
  const btTransform frame = bodyInLink(b);
  const btVector3 com = frame.getOrigin();
  if ((p.com - com).length() > 1e-6)
    return "com (" + mybot_common::formatNumber(p.com.x()) + ", " + mybot_common::formatNumber(p.com.y()) + ", " +
           mybot_common::formatNumber(p.com.z()) + ") is not where the link's centre of mass is (" +
           mybot_common::formatNumber(com.x()) + ", " + mybot_common::formatNumber(com.y()) + ", " +
           mybot_common::formatNumber(com.z()) + "): gazebo_lite builds a body about it and cannot move it";
  // The inertia in the body's axes must be diagonal: the same principal axes.
  const btMatrix3x3 in_body = frame.getBasis().transpose() * p.inertia * frame.getBasis();
  const btVector3 moments(in_body[0][0], in_body[1][1], in_body[2][2]);
  const double off = std::max({std::fabs(in_body[0][1]), std::fabs(in_body[0][2]), std::fabs(in_body[1][2])});
  if (off > 1e-6 * std::max({std::fabs(moments.x()), std::fabs(moments.y()), std::fabs(moments.z())}))
    return "ixy, ixz, iyz turn the inertia's principal axes: gazebo_lite builds a body along them and cannot turn "
           "them (scale the tensor, or keep its products)";
  const double eps = 1e-9 * (moments.x() + moments.y() + moments.z());
  if (!(moments.x() > 0 && moments.y() > 0 && moments.z() > 0) || moments.x() > moments.y() + moments.z() + eps ||
      moments.y() > moments.x() + moments.z() + eps || moments.z() > moments.x() + moments.y() + eps)
    return "inertia: principal moments (" + mybot_common::formatNumber(moments.x()) + ", " +
           mybot_common::formatNumber(moments.y()) + ", " + mybot_common::formatNumber(moments.z()) +
           ") are not a body's (each > 0 and at most the sum of the other two)";
  if (b.robot)
  {
    Robot& r = *robot(b.model);
    if (b.body < 0)
    {
      r.mb_->setBaseMass(p.mass);
      r.mb_->setBaseInertia(moments);
    }
    else
    {
      // Read afresh at every step by Bullet's articulated-body algorithm: nothing else to update.
      r.mb_->getLink(b.body).m_mass = p.mass;
      r.mb_->getLink(b.body).m_inertiaLocal = moments;
    }
    r.gravity_off_[b.body + 1] = !p.gravity_mode;
    r.mb_->wakeUp();
    return "";
  }
  btRigidBody* rb = b.world->body;
  rb->setMassProps(p.mass, moments);
  rb->updateInertiaTensor();
  if (p.gravity_mode)
  {
    rb->setFlags(rb->getFlags() & ~BT_DISABLE_WORLD_GRAVITY);
    rb->setGravity(world_->getGravity());
  }
  else
  {
    rb->setFlags(rb->getFlags() | BT_DISABLE_WORLD_GRAVITY);
    rb->setGravity(btVector3(0, 0, 0));
  }
  rb->activate(true);
  return "";
}

// Bullet pulls every multibody link down with its weight: the bodies set_link_properties took
// gravity from get their weight back, upwards.
void PhysicsWorld::cancelGravity()
{
  const btVector3& g = spec_.gravity;
  for (auto& r : robots_)
    for (size_t i = 0; i < r->gravity_off_.size(); ++i)
    {
      if (!r->gravity_off_[i])
        continue;
      const int body = static_cast<int>(i) - 1;
      if (body < 0)
        r->mb_->addBaseForce(-g * r->mb_->getBaseMass());
      else
        r->mb_->addLinkForce(body, -g * r->mb_->getLinkMass(body));
    }
}

std::string PhysicsWorld::setJointProperties(const std::string& joint, const JointSettings& s)
{
  const Robot* found = nullptr;
  std::string name;
  const std::string why = resolveJoint(joint, found, name);
  if (!why.empty())
    return why;
  const std::pair<const char*, const std::vector<double>*> lists[] = {
      {"damping", &s.damping}, {"hiStop", &s.upper}, {"loStop", &s.lower}, {"fmax", &s.fmax}, {"vel", &s.vel}};
  for (const auto& [field, values] : lists)
  {
    if (values->size() > 1)
      return "joint '" + joint + "' has one axis: " + field + " has " + std::to_string(values->size()) + " values";
    if (!values->empty() && std::isnan((*values)[0]))
      return std::string(field) + "[0] is not a number";
  }
  const auto first = [](const std::vector<double>& v, double otherwise) { return v.empty() ? otherwise : v[0]; };
  Robot& r = *robot(found->name_);
  Robot::Joint& j = r.joints_[r.joint_index_.at(name)];
  const double damping = first(s.damping, j.damping);
  const double lower = first(s.lower, j.limited ? j.lower : -INFINITY);
  const double upper = first(s.upper, j.limited ? j.upper : INFINITY);
  const double fmax = first(s.fmax, j.mode == Robot::Mode::VELOCITY ? j.max_effort : 0);
  const double vel = first(s.vel, j.mode == Robot::Mode::VELOCITY ? j.target : 0);
  if (!(damping >= 0 && std::isfinite(damping)))
    return "damping[0] = " + mybot_common::formatNumber(damping) + ": it must be >= 0";
  if (!(lower <= upper))
    return "loStop[0] = " + mybot_common::formatNumber(lower) +
           " is above hiStop[0] = " + mybot_common::formatNumber(upper) + " of joint '" + joint + "'";
  if (!(fmax >= 0 && std::isfinite(fmax)) || !std::isfinite(vel))
    return "fmax[0] must be >= 0 and vel[0] finite";
  if (!s.vel.empty() && s.fmax.empty() && fmax == 0)
    return "vel without fmax: joint '" + joint + "' has no motor running (give fmax, its maximum effort)";
  setDamping(r, j, damping);
  if (!s.lower.empty() || !s.upper.empty())
  {
    j.limited = std::isfinite(lower) || std::isfinite(upper);
    // No stop on a side: Gazebo's 1e16, a bound Bullet's limit rows can hold.
    j.lower = std::max(lower, -1e16);
    j.upper = std::min(upper, 1e16);
    if (j.limit)
    {
      j.limit->setLowerBound(j.lower);
      j.limit->setUpperBound(j.upper);
    }
    else if (j.limited)
    {
      j.limit = new btMultiBodyJointLimitConstraint(r.mb_, j.link, j.lower, j.upper);
      world_->addMultiBodyConstraint(j.limit);
      r.constraints_.push_back(j.limit);
    }
  }
  if (!s.fmax.empty() || !s.vel.empty())
  {
    // ODE's joint motor: vel at up to fmax (0: off).
    if (fmax > 0)
      r.commandVelocity(name, vel, fmax);
    else
      r.commandNone(name);
  }
  r.mb_->wakeUp();
  return "";
}

void PhysicsWorld::clearJointForces(const std::string& joint)
{
  efforts_.erase(std::remove_if(efforts_.begin(), efforts_.end(),
                                [&](const EffortJob& j) { return joint.empty() || j.asked == joint; }),
                 efforts_.end());
}

void PhysicsWorld::applyEfforts()
{
  for (auto it = efforts_.begin(); it != efforts_.end();)
  {
    Robot* r = robot(it->model);
    const bool exists = r && r->hasJoint(it->joint);
    if (exists && it->time.due(time_))
    {
      r->mb_->addJointTorque(r->joint(it->joint).link, it->effort);
      r->mb_->wakeUp();
    }
    if (!exists || it->time.over(time_, opt_.step))
      it = efforts_.erase(it);
    else
      ++it;
  }
}

Pose relativeTo(const Pose& s, const Pose& frame)
{
  Pose out;
  out.tf = frame.tf.inverse() * s.tf;
  const btMatrix3x3 to_frame = frame.tf.getBasis().transpose();
  out.linear = to_frame * (s.linear - frame.linear);
  out.angular = to_frame * (s.angular - frame.angular);
  return out;
}

// The links that begin a body, in the URDF's order: the root and every movable joint's child. A
// "world" root is no link of Gazebo's: the world itself.
std::map<int, std::string> PhysicsWorld::bodyLinks(const Robot& r)
{
  const RobotSpec& rs = *r.spec_;
  std::map<int, std::string> body_link;
  for (const auto& l : rs.links)
  {
    const auto ref = r.links_.find(l.name);
    if (ref == r.links_.end() || (l.name == rs.root && anchoredToWorld(rs)))
      continue;
    const bool starts_body = l.name == rs.root || std::any_of(rs.joints.begin(), rs.joints.end(),
                                                              [&](const JointSpec& j) {
                                                                return j.child == l.name && j.type != JointSpec::FIXED;
                                                              });
    if (starts_body || !body_link.count(ref->second.body))
      body_link[ref->second.body] = l.name;
  }
  return body_link;
}

std::string PhysicsWorld::bodyLinkOf(const std::string& model, const std::string& link) const
{
  const Robot* r = robotNamed(model);
  if (!r || !r->hasLink(link))
    return link;
  const auto bodies = bodyLinks(*r);
  const auto b = bodies.find(r->links_.at(link).body);
  return b == bodies.end() ? link : b->second;
}

bool PhysicsWorld::modelProperties(const std::string& model, ModelProperties& out) const
{
  out = ModelProperties();
  if (const Robot* r = robotNamed(model); r && r->spec_->from_sdf)
  {
    // A nested or included model's links and joints are scoped ("mast::pan"): its own.
    for (const auto& l : r->spec_->links)
    {
      if (!r->hasLink(l.name) || l.name == "world")
        continue;
      const size_t sep = l.name.find("::");
      if (sep != std::string::npos)
      {
        const std::string child = l.name.substr(0, sep);
        if (std::find(out.child_models.begin(), out.child_models.end(), child) == out.child_models.end())
          out.child_models.push_back(child);
        continue;
      }
      out.links.push_back(l.name);
      for (const auto& c : l.collisions)
        out.collisions.push_back(c.name);
    }
    for (const auto& j : r->spec_->joints)
      if (j.name.find("::") == std::string::npos)
        out.joints.push_back(j.name);
    if (!out.links.empty())
      out.canonical_link = out.links.front();
    return true;
  }
  if (const Robot* r = robotNamed(model))
  {
    const RobotSpec& rs = *r->spec_;
    const std::map<int, std::string> body_link = bodyLinks(*r);
    for (const auto& l : rs.links)
    {
      const auto ref = r->links_.find(l.name);
      if (ref == r->links_.end() || !body_link.count(ref->second.body) || body_link.at(ref->second.body) != l.name)
        continue;
      out.links.push_back(l.name);
      // The body's collisions: its own link's first, then its lumped children's, counted across the body.
      size_t n = 0;
      for (const auto& m : rs.links)
      {
        const auto mref = r->links_.find(m.name);
        if (mref == r->links_.end() || mref->second.body != ref->second.body)
          continue;
        const std::string base = m.name == l.name ? l.name : l.name + "_fixed_joint_lump__" + m.name;
        for (size_t k = 0; k < m.collisions.size(); ++k, ++n)
          out.collisions.push_back(!m.collisions[k].name.empty()  // an SDF model's own name
                                       ? m.collisions[k].name
                                       : base + "_collision" + (n > 0 ? "_" + std::to_string(n) : ""));
      }
    }
    if (!out.links.empty())
      out.canonical_link = out.links.front();
    // The movable joints and the fixed ones Gazebo keeps, in the order of the bodies they head.
    std::map<int, std::string> by_link;
    for (const auto& j : r->joints_)
      by_link[j.link] = j.spec->name;
    for (const auto& [name, link] : r->kept_fixed_)
      by_link[link] = name;
    for (const auto& [link, name] : by_link)
      out.joints.push_back(name);
    return true;
  }
  const auto m =
      std::find_if(spec_.models.begin(), spec_.models.end(), [&](const WorldModel& w) { return w.name == model; });
  if (m == spec_.models.end())
  {
    if (model != "ground_plane" || !spec_.ground_plane)
      return false;
    out.links = {"link"};
    out.collisions = {"collision"};
    out.canonical_link = "link";
    out.is_static = true;
    return true;
  }
  for (const auto& l : m->links)
  {
    out.links.push_back(l.name);
    for (const auto& s : l.shapes)
      out.collisions.push_back(s.name);
  }
  if (!out.links.empty())
    out.canonical_link = out.links.front();
  out.is_static = m->is_static;
  return true;
}

std::string PhysicsWorld::setJointPositions(const std::string& model, const std::vector<std::string>& joints,
                                            const std::vector<double>& positions)
{
  if (joints.size() != positions.size())
    return "joint_names and joint_positions have different lengths (" + std::to_string(joints.size()) + " and " +
           std::to_string(positions.size()) + ")";
  Robot* r = robot(model);
  const bool exists =
      r || std::any_of(spec_.models.begin(), spec_.models.end(), [&](const WorldModel& w) { return w.name == model; });
  if (!exists)
    return "no model named '" + model + "'";
  for (size_t i = 0; i < joints.size(); ++i)
  {
    const Robot* owner = nullptr;
    std::string name;
    if (const std::string why = resolveJoint(model + "::" + joints[i], owner, name); !why.empty())
      return why;
    const Robot::Joint& j = r->joint(joints[i]);
    if (!std::isfinite(positions[i]))
      return "joint_positions[" + std::to_string(i) + "] (" + joints[i] + ") is not a number";
    if (j.limited && (positions[i] < j.lower - 1e-9 || positions[i] > j.upper + 1e-9))
      return "joint_positions[" + std::to_string(i) + "] = " + mybot_common::formatNumber(positions[i]) +
             " is beyond the limits [" + mybot_common::formatNumber(j.lower) + ", " +
             mybot_common::formatNumber(j.upper) + "] of joint '" + joints[i] + "'";
  }
  if (!r)
    return "";
  for (size_t i = 0; i < joints.size(); ++i)
  {
    const int link = r->joint(joints[i]).link;
    r->mb_->setJointPos(link, positions[i]);
    r->mb_->setJointVel(link, 0);
  }
  r->mb_->wakeUp();
  syncRobotTransforms(*r);
  return "";
}

std::string PhysicsWorld::setLinkState(const std::string& link, const btTransform& pose, const btVector3& lin,
                                       const btVector3& ang, bool* moved_static)
{
  const size_t sep = link.find("::");
  const std::string model = sep == std::string::npos ? "" : link.substr(0, sep);
  const std::string name = sep == std::string::npos ? "" : link.substr(sep + 2);
  if (Robot* r = robot(model); r && r->hasLink(name))
  {
    const Robot::LinkRef& ref = r->links_.at(name);
    if (ref.body >= 0)
      return "link '" + link +
             "' is placed by its joints: move the model (set_model_state) or its joints "
             "(set_model_configuration)";
    // The root link rides on the same body: where the root goes when this link is at `pose`.
    const std::string& root = r->spec_->root;
    const btTransform link_in_root = r->linkPose(root).inverse() * r->linkPose(name);
    const btTransform root_pose = pose * link_in_root.inverse();
    setRobotPose(*r, root_pose, lin + ang.cross(root_pose.getOrigin() - pose.getOrigin()), ang);
    return "";
  }
  for (auto& wb : world_bodies_)
  {
    if (wb.model != model || wb.link_name != name)
      continue;
    const btTransform body_tf = pose * wb.link_in_body.inverse();
    if (!wb.body)
    {
      placeStatic(wb, body_tf);
      if (moved_static)
        *moved_static = true;
      return "";
    }
    wb.body->setWorldTransform(body_tf);
    wb.body->setLinearVelocity(lin + ang.cross(body_tf.getOrigin() - pose.getOrigin()));
    wb.body->setAngularVelocity(ang);
    wb.body->activate(true);
    return "";
  }
  return "no link named '" + link + "' (links are named model::link; a link without a <collision> is not simulated)";
}

void PhysicsWorld::setStepSize(double step)
{
  time_base_ = time_;
  steps_base_ = steps_;
  opt_.step = step;
  world_->getSolverInfo().m_timeStep = step;
  // Joint friction is an impulse per step.
  for (auto& r : robots_)
    for (auto& j : r->joints_)
      if (j.friction)
        j.friction->setMaxAppliedImpulse(j.spec->friction * step);
}

void PhysicsWorld::setSolverIterations(int iterations)
{
  opt_.solver_iterations = iterations;
  world_->getSolverInfo().m_numIterations = iterations;
}

void PhysicsWorld::setGravity(const btVector3& g)
{
  spec_.gravity = g;      // what the IMUs read
  world_->setGravity(g);  // and every rigid body's own copy
  for (const auto& wb : world_bodies_)
    if (wb.body)
      wb.body->activate(true);  // a sleeping body would not feel it
  for (auto& r : robots_)
    r->mb_->wakeUp();
}

const Robot* PhysicsWorld::robotNamed(const std::string& name) const
{
  for (const auto& r : robots_)
    if (r->name_ == name)
      return r.get();
  return nullptr;
}

std::vector<DynamicObstacle> PhysicsWorld::dynamicObstacles(const Robot* exclude) const
{
  std::vector<DynamicObstacle> out;
  auto add = [&](const btCollisionObject* o)
  {
    btVector3 mn, mx;
    o->getCollisionShape()->getAabb(o->getWorldTransform(), mn, mx);
    out.push_back({o, (mn + mx) * 0.5, (mx - mn).length() * 0.5, mn.z(), mx.z()});
  };
  for (const auto& r : robots_)
  {
    if (r.get() == exclude)
      continue;
    for (auto* c : r->colliders_)
      add(c);
  }
  for (const auto& wb : world_bodies_)
    if (wb.body)
      add(wb.obj);
  return out;
}

std::vector<PlacedShape> PhysicsWorld::movingShapes(const Robot* exclude) const
{
  std::vector<PlacedShape> out;
  auto add = [&](const Shape& s, const btTransform& tf, const float color[3])
  {
    if (s.type == Shape::PLANE)
      return;
    PlacedShape p;
    p.shape = &s;
    p.tf = tf;
    std::copy(color, color + 3, p.color);
    out.push_back(p);
  };
  for (const auto& r : robots_)
  {
    if (r.get() == exclude)
      continue;
    for (const LinkSpec& l : r->spec_->links)
      if (!l.collisions.empty() && r->hasLink(l.name))
      {
        const btTransform link = r->linkPose(l.name);
        for (const Shape& s : l.collisions)
          add(s, link * s.pose, l.color);
      }
  }
  for (const auto& wb : world_bodies_)
    if (wb.body && wb.link)
      for (const Shape& s : wb.link->shapes)
        add(s, wb.obj->getWorldTransform() * s.pose, wb.link->color);
  return out;
}

double PhysicsWorld::rayTestObject(const btCollisionObject* obj, const btVector3& from, const btVector3& to) const
{
  btCollisionWorld::ClosestRayResultCallback cb(from, to);
  btTransform tf_from(btQuaternion::getIdentity(), from), tf_to(btQuaternion::getIdentity(), to);
  btCollisionWorld::rayTestSingle(tf_from, tf_to, const_cast<btCollisionObject*>(obj), obj->getCollisionShape(),
                                  obj->getWorldTransform(), cb);
  if (!cb.hasHit())
    return -1;
  return cb.m_closestHitFraction * (to - from).length();
}

double PhysicsWorld::rayTest(const btVector3& from, const btVector3& to, const Robot* exclude) const
{
  struct Cb : btCollisionWorld::ClosestRayResultCallback
  {
    const Robot* ex;
    Cb(const btVector3& a, const btVector3& b, const Robot* e) : ClosestRayResultCallback(a, b), ex(e) {}
    bool needsCollision(btBroadphaseProxy* proxy) const override
    {
      auto* o = static_cast<const btCollisionObject*>(proxy->m_clientObject);
      if (ex)
        for (auto* c : ex->colliders())
          if (c == o)
            return false;
      return ClosestRayResultCallback::needsCollision(proxy);
    }
  } cb(from, to, exclude);
  world_->rayTest(from, to, cb);
  if (!cb.hasHit())
    return -1;
  return cb.m_closestHitFraction * (to - from).length();
}

}  // namespace mybot_gazebo_lite
