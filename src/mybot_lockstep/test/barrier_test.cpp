#include "mybot_lockstep/barrier.h"

#include <gtest/gtest.h>

using namespace mybot_lockstep;

namespace
{
Link link(const std::string& topic, const std::string& src, const std::string& dst, std::uint64_t n)
{
  Link l;
  l.topic = topic;
  l.source = src;
  l.destination = dst;
  l.count = n;
  return l;
}
}  // namespace

TEST(Roster, APeriodCompletesOnlyWhenEveryParticipantAcked)
{
  Roster r(5.0);
  r.begin(1, 0.0);
  EXPECT_TRUE(r.ack("/a", 1, false, {}));  // joins
  EXPECT_TRUE(r.ack("/b", 1, false, {}));
  r.begin(2, 0.1);
  EXPECT_FALSE(r.complete(0.2, nullptr));
  EXPECT_FALSE(r.ack("/a", 2, false, {}));  // not a join
  EXPECT_FALSE(r.complete(0.2, nullptr));
  EXPECT_EQ(r.waiting(), std::vector<std::string>{"/b"});
  r.ack("/b", 2, false, {});
  EXPECT_TRUE(r.complete(0.3, nullptr));
}

TEST(Roster, AJoinerDoesNotHoldThePeriodUnderWay)
{
  Roster r(5.0);
  r.begin(7, 0.0);
  r.ack("/late", 3, false, {});  // an old tick's Ack: it owes Acks from period 8 on
  EXPECT_TRUE(r.complete(0.1, nullptr));
  r.begin(8, 0.2);
  EXPECT_FALSE(r.complete(0.2, nullptr));
}

TEST(Roster, ASilentParticipantIsDroppedAfterTheTimeoutAndNamed)
{
  Roster r(1.0);
  r.begin(1, 0.0);
  r.ack("/fast", 1, false, {});
  r.ack("/stuck", 1, false, {});
  r.begin(2, 10.0);
  r.ack("/fast", 2, false, {});
  std::vector<std::string> dropped;
  EXPECT_FALSE(r.complete(10.9, &dropped));
  EXPECT_TRUE(dropped.empty());
  EXPECT_TRUE(r.complete(11.1, &dropped));
  EXPECT_EQ(dropped, std::vector<std::string>{"/stuck"});
  EXPECT_FALSE(r.has("/stuck"));
}

TEST(Roster, LeavingRemovesAtOnce)
{
  Roster r(5.0);
  r.begin(1, 0.0);
  r.ack("/a", 1, false, {});
  r.begin(2, 0.0);
  r.ack("/a", 1, true, {});
  EXPECT_EQ(r.size(), 0u);
  EXPECT_TRUE(r.complete(0.0, nullptr));
}

TEST(Roster, ExpectationsKeepOnlyLinksIntoParticipants)
{
  Roster r(5.0);
  r.begin(1, 0.0);
  r.ack("/ctrl", 1, false,
        {link("/cmd", "/ctrl", "/gazebo", 4), link("/cmd", "/ctrl", "/rviz", 4), link("/odom", "/ctrl", "/test", 9)});
  r.ack("/test", 1, false, {});
  const auto e = r.expectations({link("/joint_states", "/gazebo", "/ctrl", 12), link("/scan", "/gazebo", "/rviz", 3)});
  ASSERT_EQ(e.size(), 2u);
  EXPECT_EQ(e[0].topic, "/joint_states");
  EXPECT_EQ(e[1].topic, "/odom");
  const auto owed = r.owedTo("/gazebo");
  ASSERT_EQ(owed.size(), 1u);
  EXPECT_EQ(owed[0].count, 4u);
}

TEST(Ledger, WaitsForEveryCountedMessageAddressedToIt)
{
  Ledger l("/ctrl");
  l.count("/joint_states");
  const std::vector<Link> e = {link("/joint_states", "/gazebo", "/ctrl", 2), link("/tf", "/gazebo", "/ctrl", 50),
                               link("/joint_states", "/gazebo", "/other", 9)};
  ASSERT_NE(l.firstUnmet(e), nullptr);  // /tf is not counted, /other is not us
  EXPECT_EQ(l.firstUnmet(e)->topic, "/joint_states");
  l.received("/joint_states", "/gazebo");
  EXPECT_NE(l.firstUnmet(e), nullptr);
  l.received("/joint_states", "/gazebo");
  EXPECT_EQ(l.firstUnmet(e), nullptr);
}

TEST(Ledger, ForgivenMessagesAreNotAwaitedAgain)
{
  Ledger l("/sim");
  l.count("/cmd");
  l.received("/cmd", "/a");
  l.forgive({link("/cmd", "/a", "/sim", 3)});  // two lost for good
  EXPECT_EQ(l.firstUnmet({link("/cmd", "/a", "/sim", 3)}), nullptr);
  EXPECT_NE(l.firstUnmet({link("/cmd", "/a", "/sim", 4)}), nullptr);
  l.received("/cmd", "/a");
  EXPECT_EQ(l.firstUnmet({link("/cmd", "/a", "/sim", 4)}), nullptr);
}

TEST(Ledger, TwoSubscriptionsToOneTopicEachHandleEveryMessage)
{
  Ledger l("/chain");
  l.count("/joint_states");
  l.count("/joint_states");
  const std::vector<Link> e = {link("/joint_states", "/gazebo", "/chain", 2)};
  for (int i = 0; i < 3; ++i)
    l.received("/joint_states", "/gazebo");
  EXPECT_NE(l.firstUnmet(e), nullptr);
  EXPECT_EQ(l.releasable("/joint_states", "/gazebo", 0, e, true), 3u);
  l.received("/joint_states", "/gazebo");
  EXPECT_EQ(l.firstUnmet(e), nullptr);
}

TEST(Ledger, AMessageThatComesEarlyWaitsForItsPeriod)
{
  Ledger l("/test");
  l.count("/odom");
  for (int i = 0; i < 3; ++i)
    l.received("/odom", "/odom_node");
  const std::vector<Link> e = {link("/odom", "/odom_node", "/test", 2)};
  EXPECT_EQ(l.releasable("/odom", "/odom_node", 0, e, true), 2u);  // the third is next period's
  EXPECT_EQ(l.releasable("/odom", "/odom_node", 2, e, true), 0u);
  EXPECT_EQ(l.releasable("/odom", "/odom_node", 2, {}, true), 0u);  // not announced at all yet
  EXPECT_EQ(l.releasable("/odom", "/rostopic", 0, {}, false), 0u);  // nothing from it received
  l.received("/odom", "/rostopic");
  EXPECT_EQ(l.releasable("/odom", "/rostopic", 0, {}, false), 1u);  // not a participant: at once
}

TEST(TickTimers, FireAtMultiplesOfTheirPeriodWhateverTheStartTime)
{
  TickTimers t;
  std::vector<std::int64_t> fired;
  t.add(20, 13, [&](std::int64_t due, std::int64_t) { fired.push_back(due); });  // started at 13
  for (std::int64_t now = 10; now <= 100; now += 10)
    t.run(now);
  EXPECT_EQ(fired, (std::vector<std::int64_t>{20, 40, 60, 80, 100}));
}

TEST(TickTimers, EarliestDueFirstAndNoCatchUpBurst)
{
  TickTimers t;
  std::vector<int> order;
  t.add(30, 0, [&](std::int64_t, std::int64_t) { order.push_back(30); });
  t.add(20, 0, [&](std::int64_t, std::int64_t) { order.push_back(20); });
  t.run(30);  // 20 due at 20, 30 due at 30
  EXPECT_EQ(order, (std::vector<int>{20, 30}));
  order.clear();
  t.run(200);  // far behind: each fires once
  EXPECT_EQ(order, (std::vector<int>{20, 30}));
}

TEST(TickTimers, TimeGoingBackwardsRealigns)
{
  TickTimers t;
  std::vector<std::int64_t> fired;
  t.add(10, 0, [&](std::int64_t due, std::int64_t) { fired.push_back(due); });
  t.run(1000);
  fired.clear();
  t.run(5);  // reset to near zero: next due is 10, not 1010
  t.run(10);
  EXPECT_EQ(fired, (std::vector<std::int64_t>{10}));
}

TEST(TickTimers, ACallbackMayRemoveItsOwnTimer)
{
  TickTimers t;
  int id = -1, calls = 0;
  id = t.add(10, 0,
             [&](std::int64_t, std::int64_t)
             {
               ++calls;
               t.remove(id);
             });
  t.run(10);
  t.run(20);
  EXPECT_EQ(calls, 1);
}

int main(int argc, char** argv)
{
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
