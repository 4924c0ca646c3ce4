#include <gtest/gtest.h>

#include <random>

#include "mybot_slam/pose_graph.h"

using namespace mybot_navigation;

TEST(PoseGraph, LoopEdgeRemovesAccumulatedDrift)
{
  // A 4 x 4 m square driven in 40 steps with biased odometry, then one loop closure back to start.
  std::vector<Pose2D> truth;
  Pose2D p;
  for (int side = 0; side < 4; ++side)
  {
    for (int i = 0; i < 10; ++i)
    {
      truth.push_back(p);
      p = compose(p, {0.4, 0.0, i == 9 ? M_PI / 2 : 0.0});
    }
  }
  PoseGraph g;
  Pose2D est = truth[0];
  g.addNode(est);
  std::mt19937 rng(3);
  std::normal_distribution<double> n(0.0, 0.01);
  for (size_t i = 1; i < truth.size(); ++i)
  {
    Pose2D z = between(truth[i - 1], truth[i]);
    z.theta += 0.01 + n(rng);  // heading bias
    z.x += n(rng);
    est = compose(est, z);
    g.addNode(est);
    g.addEdge({static_cast<int>(i - 1), static_cast<int>(i), z, 0.02, 0.02, false});
  }
  auto err = [&]()
  {
    double e = 0;
    for (size_t i = 0; i < truth.size(); ++i)
      e = std::max(e, std::hypot(g.node(i).x - truth[i].x, g.node(i).y - truth[i].y));
    return e;
  };
  const double before = err();
  g.addEdge({static_cast<int>(truth.size()) - 1, 0, between(truth.back(), truth[0]), 0.01, 0.005, true});
  const OptimizationSummary s = g.optimize();
  EXPECT_LT(s.final_cost, s.initial_cost);
  EXPECT_GT(before, 0.3);
  EXPECT_LT(err(), 0.1);
  EXPECT_DOUBLE_EQ(g.node(0).x, 0.0);  // gauge fixed
}

TEST(PoseGraph, RejectsBadIndices)
{
  PoseGraph g;
  g.addNode({});
  EXPECT_THROW(g.addEdge({0, 1, {}, 0.1, 0.1, false}), std::out_of_range);
}

TEST(PoseGraph, ResidualTellsAConsistentClosureFromAWrongOne)
{
  // A straight 5 m chain measured well, then a closure back to the start: the true one leaves no
  // residual after optimisation, one placed a metre off (a neighbouring aisle) cannot be honoured.
  auto chain = []()
  {
    PoseGraph g;
    g.addNode({});
    for (int i = 1; i <= 10; ++i)
    {
      g.addNode({0.5 * i, 0.0, 0.0});
      g.addEdge({i - 1, i, {0.5, 0.0, 0.0}, 0.02, 0.01, false});
    }
    return g;
  };
  PoseGraph good = chain();
  const PoseGraphEdge truth{0, 10, {5.0, 0.0, 0.0}, 0.05, 0.02, true};
  good.addEdge(truth);
  good.optimize();
  EXPECT_LT(translationNorm(good.residual(truth)), 1e-6);

  PoseGraph bad = chain();
  const PoseGraphEdge wrong{0, 10, {5.0, 1.0, 0.0}, 0.05, 0.02, true};
  bad.addEdge(wrong);
  EXPECT_NEAR(translationNorm(bad.residual(wrong)), 1.0, 1e-9);
  bad.optimize();
  EXPECT_GT(translationNorm(bad.residual(wrong)), 3 * 0.05);
  bad.popEdge();
  EXPECT_EQ(bad.edges().size(), 10u);
}

TEST(PoseGraph, ARedescendingEdgeKeepsAWholeJumpWhereAHuberEdgeBendsTheChain)
{
  // A straight chain of 10 steps of 0.5 m; step 3 is unconfirmed odometry that jumped 2 m which
  // never happened, and an exact closure from the start to the end says so. The optimiser starts
  // with the jump undone at its own step (as Slam::spreadCorrection starts it).
  auto run = [](bool redescending)
  {
    PoseGraph g;
    g.addNode({});
    for (int i = 1; i <= 10; ++i)
    {
      PoseGraphEdge e{i - 1, i, {i == 3 ? 2.5 : 0.5, 0.0, 0.0}, 0.02, 0.01, false};
      if (i == 3)
      {
        e.sigma_xy = 0.1;
        e.sigma_theta = 0.05;
        e.robust = !redescending;
        e.redescending = redescending;
      }
      g.addNode({0.5 * i, 0.0, 0.0});
      g.addEdge(e);
    }
    g.addEdge({0, 10, {5.0, 0.0, 0.0}, 0.01, 0.01, true});
    g.optimize(100);
    double bent = 0.0;  // the largest change of a confirmed step
    for (int i = 1; i <= 10; ++i)
      if (i != 3)
        bent = std::max(bent, std::abs(g.node(i).x - g.node(i - 1).x - 0.5));
    return bent;
  };
  const double cauchy = run(true), huber = run(false);
  std::printf("largest change of a confirmed step: Cauchy %.4f m, Huber %.4f m\n", cauchy, huber);
  // The Cauchy loss hardly pulls at 20 sigma; the Huber loss pulls as hard as at 1 sigma.
  EXPECT_LT(cauchy, 0.005);
  EXPECT_GT(huber, 2 * cauchy);
}
