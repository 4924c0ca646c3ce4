#include "mybot_lockstep/ros/coordinator.h"

#include <ros/publication.h>
#include <ros/topic_manager.h>

#include <map>
#include <set>
#include <tuple>

#include <ros/master.h>
#include <ros/network.h>
#include <ros/xmlrpc_manager.h>
#include <xmlrpcpp/XmlRpcClient.h>

#include "mybot_lockstep/ros/participant.h"
#include "ros_links.h"

namespace mybot_lockstep
{

Coordinator::Coordinator(double timeout, ros::CallbackQueue* queue)
    : roster_(timeout), timeout_(timeout), queue_(queue), self_(ros::this_node::getName())
{
  ledger_.setSelf(self_);
  ros::NodeHandle nh;
  tick_pub_ = nh.advertise<Tick>("/lockstep/tick", 10);
  ros::SubscribeOptions ops;
  ops.init<Ack>("/lockstep/ack", 1000, [this](const Ack::ConstPtr& a) { onAck(a); });
  ops.transport_hints = ros::TransportHints().tcpNoDelay();
  ack_sub_ = nh.subscribe(ops);
}

void Coordinator::onAck(const Ack::ConstPtr& ack)
{
  std::vector<Link> sent;
  sent.reserve(ack->sent.size());
  for (const LinkCount& l : ack->sent)
    sent.push_back(fromMsg(l));
  const bool joined = roster_.ack(ack->node, ack->seq, ack->leaving, sent);
  if (joined)
  {
    ROS_INFO("lockstep: %s joins (%zu participants)", ack->node.c_str(), roster_.size());
    settle_ = true;
    // The current period, republished while time stands, names it from now on: whoever starts
    // a node while time is paused can see that the simulator counts it before letting time move
    // (participants answer a republished tick without reading it). A copy: the published message
    // may still be in use.
    if (tick_)
    {
      auto tick = boost::make_shared<Tick>(*tick_);
      tick->participants = roster_.names();
      tick->participants.push_back(self_);
      tick_ = tick;
    }
  }
  else if (ack->leaving)
    ROS_INFO("lockstep: %s leaves (%zu participants)", ack->node.c_str(), roster_.size());
}

// A participant whose tick connection closed has exited (or crashed): drop it at once
// rather than wait out the timeout.
void Coordinator::dropDisconnected()
{
  const ros::PublicationPtr pub = ros::TopicManager::instance()->lookupPublication(tick_pub_.getTopic());
  if (!pub)
    return;
  XmlRpc::XmlRpcValue info;
  info.setSize(0);
  pub->getInfo(info);
  std::set<std::string> connected;
  for (int i = 0; i < info.size(); ++i)
    connected.insert(static_cast<std::string>(info[i][1]));
  for (const std::string& name : roster_.names())
    if (!connected.count(name) && roster_.remove(name))
      ROS_WARN("lockstep: participant %s left (its connection closed); %zu remain", name.c_str(), roster_.size());
}

namespace
{
// The subscribers `node` has an open outgoing connection to on `topic`, by its own account
// (the slave API's getBusInfo, as rosnode info asks it). Empty when the node cannot be asked.
std::set<std::string> connectedSubscribers(const std::string& self, const std::string& node, const std::string& topic)
{
  std::set<std::string> out;
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = self;
  args[1] = node;
  std::string host;
  uint32_t port = 0;
  if (!ros::master::execute("lookupNode", args, result, payload, false) ||
      !ros::network::splitURI(static_cast<std::string>(payload), host, port))
    return out;
  // Blocking, as ros::master::execute is (a node's XML-RPC server answers from a thread of its
  // own); asked only while time stands after a join, a spawn or an unpause.
  XmlRpc::XmlRpcClient* client = ros::XMLRPCManager::instance()->getXMLRPCClient(host, static_cast<int>(port), "/");
  XmlRpc::XmlRpcValue params, info;
  params[0] = self;
  const bool done = client->execute("getBusInfo", params, info) && !client->isFault();
  ros::XMLRPCManager::instance()->releaseXMLRPCClient(client);
  if (!done || info.getType() != XmlRpc::XmlRpcValue::TypeArray || info.size() < 3 ||
      info[2].getType() != XmlRpc::XmlRpcValue::TypeArray)
    return out;
  // [connection id, destination, direction, transport, topic, connected, ...]
  for (int i = 0; i < info[2].size(); ++i)
  {
    XmlRpc::XmlRpcValue& c = info[2][i];
    if (c.getType() == XmlRpc::XmlRpcValue::TypeArray && c.size() >= 5 && static_cast<std::string>(c[2]) == "o" &&
        static_cast<std::string>(c[4]) == topic)
      out.insert(static_cast<std::string>(c[1]));
  }
  return out;
}
}  // namespace

std::string Coordinator::missingConnection()
{
  XmlRpc::XmlRpcValue args, result, payload;
  args[0] = self_;
  if (!ros::master::execute("getSystemState", args, result, payload, false) || payload.size() < 2)
    return "the master's getSystemState";
  const std::vector<std::string> names = roster_.names();
  std::set<std::string> members(names.begin(), names.end());
  members.insert(self_);
  // Open connections: the participants' last Acks and the simulator's own publications.
  std::set<std::tuple<std::string, std::string, std::string>> open;
  for (const Link& l : collectSent())
    open.insert({l.topic, l.source, l.destination});
  for (const Link& l : roster_.sentLinks())
    open.insert({l.topic, l.source, l.destination});
  std::map<std::string, std::vector<std::string>> subscribers;
  for (int i = 0; i < payload[1].size(); ++i)
  {
    std::vector<std::string>& s = subscribers[static_cast<std::string>(payload[1][i][0])];
    for (int j = 0; j < payload[1][i][1].size(); ++j)
      s.push_back(static_cast<std::string>(payload[1][i][1][j]));
  }
  for (int i = 0; i < payload[0].size(); ++i)
  {
    const std::string topic = payload[0][i][0];
    if (topic.rfind("/lockstep/", 0) == 0 || topic == "/rosout" || topic == "/clock")
      continue;
    for (int j = 0; j < payload[0][i][1].size(); ++j)
    {
      const std::string pub = payload[0][i][1][j];
      if (!members.count(pub))
      {
        // The static transforms from a node that does not take part (robot_state_publisher,
        // static_transform_publisher): latched, sent once as a participant connects, and needed
        // before its first scan can be used. Time waits until they are on their way to every
        // participant, or AMCL starts localizing a load-dependent number of periods late.
        if (topic != "/tf_static")
          continue;
        std::vector<std::string> waiting;
        for (const std::string& sub : subscribers[topic])
          if (members.count(sub))
            waiting.push_back(sub);
        if (waiting.empty())
          continue;
        const std::set<std::string> connected = connectedSubscribers(self_, pub, topic);
        for (const std::string& sub : waiting)
          if (!connected.count(sub))
            return topic + ": " + pub + " -> " + sub;
        continue;
      }
      for (const std::string& sub : subscribers[topic])
        if (members.count(sub) && !open.count({topic, pub, sub}))
          return topic + ": " + pub + " -> " + sub;
    }
  }
  return "";
}

bool Coordinator::waitForParticipants()
{
  const ros::WallTime start = ros::WallTime::now();
  ros::WallTime next_check = start, next_settle = start;
  bool first = true;
  while (ros::ok())
  {
    // The first look does not wait: with nobody to wait for, a period costs no idle time.
    queue_->callAvailable(first ? ros::WallDuration() : ros::WallDuration(0.001));
    first = false;
    const ros::WallTime now = ros::WallTime::now();
    if (now >= next_check)
    {
      dropDisconnected();
      next_check = now + ros::WallDuration(0.05);
    }
    std::vector<std::string> dropped;
    const bool acked = roster_.complete(now.toSec(), &dropped);
    for (const std::string& d : dropped)
      ROS_WARN("lockstep: dropped participant %s: no Ack for period %llu within %.1f s of wall time", d.c_str(),
               static_cast<unsigned long long>(seq_), timeout_);
    if (!acked)
      continue;
    const std::vector<Link> owed = roster_.owedTo(self_);
    if (const Link* l = ledger_.firstUnmet(owed))
    {
      if ((now - start).toSec() < timeout_)
        continue;
      ROS_WARN("lockstep: gave up waiting for %s from %s (%llu of %llu handled after %.1f s)", l->topic.c_str(),
               l->source.c_str(), static_cast<unsigned long long>(ledger_.handled(l->topic, l->source)),
               static_cast<unsigned long long>(l->count), timeout_);
      ledger_.forgive(owed);
    }
    if (settle_)
    {
      if (now < next_settle)
        continue;
      const std::string missing = missingConnection();
      if (!missing.empty() && (now - start).toSec() < timeout_)
      {
        // Ask again: the participants answer a repeated tick with fresh connection counts.
        republish();
        next_settle = now + ros::WallDuration(0.02);
        continue;
      }
      if (!missing.empty())
        ROS_WARN("lockstep: starting without the connection %s (not open after %.1f s)", missing.c_str(), timeout_);
      settle_ = false;
    }
    return true;
  }
  return false;
}

void Coordinator::beginPeriod(const ros::Time& t)
{
  ++seq_;
  roster_.begin(seq_, ros::WallTime::now().toSec());
  tick_ = boost::make_shared<Tick>();
  tick_->seq = seq_;
  tick_->stamp = t;
  tick_->participants = roster_.names();
  tick_->participants.push_back(self_);
  // Counting what was sent costs two wake-ups of roscpp's poll thread: only when someone
  // is owed anything.
  if (roster_.size() > 0)
    for (const Link& l : roster_.expectations(collectSent()))
      tick_->expected.push_back(toMsg(l));
  tick_pub_.publish(tick_);
}

void Coordinator::republish()
{
  if (tick_)
    tick_pub_.publish(tick_);
}

}  // namespace mybot_lockstep
