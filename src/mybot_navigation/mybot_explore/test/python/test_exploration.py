"""Frontier exploration on synthetic grids."""
import numpy as np
import pytest

from mybot_explore.exploration import GridInfo, find_frontiers, frontier_mask, frontier_near, path_lengths


def room(rows=60, cols=80, known_cols=40):
    """A walled room; the left part is known free, the right part unknown."""
    g = np.full((rows, cols), -1, dtype=np.int8)
    g[:, :known_cols] = 0
    g[0, :known_cols] = g[-1, :known_cols] = 100
    g[:, 0] = 100
    return g


INFO = GridInfo(resolution=0.05, origin_x=0.0, origin_y=0.0)


def test_frontier_cells_are_free_cells_next_to_unknown():
    g = room()
    m = frontier_mask(g)
    cols = np.unique(np.argwhere(m)[:, 1])
    assert list(cols) == [39]
    assert not m[0, 39] and not m[-1, 39]   # walls are never frontier


def test_path_lengths_go_around_walls():
    free = np.ones((20, 20), dtype=bool)
    free[:15, 10] = False                     # a wall with a gap at the bottom
    d = path_lengths(free, (0, 0))
    assert d[0, 0] == 0
    assert d[0, 5] == pytest.approx(5)
    assert d[0, 19] > 28                      # must go down through the gap and back up
    free2 = free.copy()
    free2[15:, 10] = False
    assert np.isinf(path_lengths(free2, (0, 0))[0, 19])


def test_nearest_reachable_frontier_first_and_blacklist():
    g = room()
    g[:, 60:] = 0                             # a second known area, unreachable (unknown between)
    fr = find_frontiers(g, INFO, robot_xy=(0.5, 1.5), robot_radius=0.2)
    assert fr, "a frontier is expected"
    x, y = fr[0].goal
    assert 1.2 < x < 2.0                      # near the boundary at x = 2.0 m, on the known side
    assert all(np.isfinite(f.path_length) for f in fr)
    assert all(f.goal[0] < 2.0 for f in fr)   # the disconnected area's frontiers are unreachable
    fr2 = find_frontiers(g, INFO, robot_xy=(0.5, 1.5), blacklist=[fr[0].goal], blacklist_radius=5.0)
    assert fr2 == []


def test_fully_known_map_has_no_frontier():
    g = np.zeros((40, 40), dtype=np.int8)
    g[0, :] = g[-1, :] = g[:, 0] = g[:, -1] = 100
    assert find_frontiers(g, INFO, robot_xy=(1.0, 1.0)) == []


def test_small_frontiers_are_ignored():
    g = np.zeros((40, 40), dtype=np.int8)
    g[0, :] = g[-1, :] = g[:, 0] = g[:, -1] = 100
    g[20, 20] = -1                            # a single unknown cell: 4 frontier cells < 5
    assert find_frontiers(g, INFO, robot_xy=(0.5, 0.5), min_frontier_size=5) == []


def test_boundary_keeps_exploration_inside():
    g = room()
    fr = find_frontiers(g, INFO, robot_xy=(0.5, 1.5), robot_radius=0.2)
    assert fr
    # The frontier runs along x = 1.95 m: a boundary ending at x = 1.5 m excludes it,
    # one ending at 3 m keeps it.
    assert find_frontiers(g, INFO, robot_xy=(0.5, 1.5), robot_radius=0.2, boundary=(0, 0, 1.5, 3.0)) == []
    kept = find_frontiers(g, INFO, robot_xy=(0.5, 1.5), robot_radius=0.2, boundary=(0, 0, 3.0, 3.0))
    assert [f.goal for f in kept] == [f.goal for f in fr]


def test_frontier_near_looks_only_around_the_point():
    g = room()                                # frontier along x = 1.95 m
    assert frontier_near(g, INFO, (1.5, 1.5), radius=1.0)
    assert not frontier_near(g, INFO, (0.5, 1.5), radius=1.0)
    assert not frontier_near(g, INFO, (-5.0, -5.0), radius=1.0)   # off the map
    assert not frontier_near(g, INFO, (1.5, 1.5), radius=1.0, min_cells=100)  # 2 m of it in reach: 40 cells
    g[:, :] = 0
    assert not frontier_near(g, INFO, (1.5, 1.5), radius=1.0)


def test_blacklisted_goal_moves_the_goal_not_the_whole_frontier():
    g = room()                                # one long frontier along x = 1.95 m, y 0.05..2.95
    first = find_frontiers(g, INFO, robot_xy=(0.5, 1.5), robot_radius=0.2)[0]
    again = find_frontiers(g, INFO, robot_xy=(0.5, 1.5), robot_radius=0.2,
                           blacklist=[first.goal], blacklist_radius=0.5)
    assert len(again) == 1 and again[0].size == first.size
    assert np.hypot(again[0].goal[0] - first.goal[0], again[0].goal[1] - first.goal[1]) >= 0.5


def test_inside_of_a_box_is_not_a_frontier():
    # A fully explored room with a 1 x 1 m box whose inside the laser never saw: driving around
    # it forever would not reveal it.
    g = np.zeros((80, 80), dtype=np.int8)
    g[0, :] = g[-1, :] = g[:, 0] = g[:, -1] = 100
    g[30:50, 30:50] = -1
    g[30, 30:50] = g[49, 30:50] = g[30:50, 30] = g[30:50, 49] = 100
    g[30, 36:44] = 0                         # a gap in the box's outline: its inside borders free space
    assert frontier_mask(g)[30, 40]
    assert find_frontiers(g, INFO, robot_xy=(0.5, 0.5), min_unknown_area=0) != []
    assert find_frontiers(g, INFO, robot_xy=(0.5, 0.5)) == []
    # A large unknown area is still explored, and so is unknown space reaching the map's edge.
    g2 = room()
    assert find_frontiers(g2, INFO, robot_xy=(0.5, 1.5)) != []
    g3 = np.zeros((120, 120), dtype=np.int8)
    g3[0, :] = g3[-1, :] = g3[:, 0] = g3[:, -1] = 100
    g3[20:100, 20:100] = -1                  # 16 m^2 unseen inside the walls
    assert find_frontiers(g3, INFO, robot_xy=(0.5, 0.5)) != []


def test_free_space_seen_through_a_door_is_not_a_frontier_from_behind_the_wall():
    # A room (x < 2 m) whose right wall has a door at its far end; rays through the door mapped a
    # strip of free space outside, right behind the wall, with unknown space beyond it.
    g = np.zeros((60, 80), dtype=np.int8)
    g[0, :] = g[-1, :] = g[:, 0] = 100
    g[:, 40] = 100
    g[50:56, 40] = 0                         # the door
    g[:, 44:] = -1                           # outside: a 3-cell strip mapped, then unknown
    fr = find_frontiers(g, INFO, robot_xy=(1.0, 0.5), robot_radius=0.2, min_unknown_area=0)
    assert fr
    # Every goal offered lies within reach of its frontier through the door (rows 50-55, reach 0.9 m
    # = 18 cells), none further along the wall.
    for f in fr:
        assert f.goal[1] / INFO.resolution >= 50 - 18, f.goal
    g[50:56, 40] = 100                       # door closed: the strip is unreachable and out of sight
    assert find_frontiers(g, INFO, robot_xy=(1.0, 0.5), robot_radius=0.2, min_unknown_area=0) == []


def test_robot_in_a_narrow_gap_still_finds_frontiers():
    # The robot stands in a 0.5 m gap between two shelves, narrower than its clearance radius.
    g = room(rows=80, cols=80, known_cols=60)
    g[30:50, 5:30] = 100
    g[30:50, 40:55] = 100                    # gap between cols 30 and 40: 0.5 m
    fr = find_frontiers(g, INFO, robot_xy=(1.75, 2.0), robot_radius=0.3)
    assert fr and fr[0].path_length > 0
    # Off the grid or walled in, the explorer learns nothing about the map: None, not "no frontier".
    assert find_frontiers(g, INFO, robot_xy=(-5.0, 1.0)) is None
    boxed = g.copy()
    boxed[38:43, 33:38] = 0
    boxed[37, 32:39] = boxed[43, 32:39] = boxed[37:44, 32] = boxed[37:44, 38] = 100
    assert find_frontiers(boxed, INFO, robot_xy=(1.75, 2.0), robot_radius=0.3) is None


def test_robot_on_unknown_cells_with_free_space_ahead_finds_frontiers():
    # A depth camera (87 degrees, 0.3 m minimum range, behind the robot's centre) leaves the
    # robot's own cells unknown: the free cone it saw ahead is where the search starts.
    g = np.full((80, 80), -1, dtype=np.int8)
    for r in range(80):
        for c in range(46, 70):
            if abs(r - 40) <= (c - 44) * 0.9:  # the cone, from 0.3 m ahead of the robot at column 40
                g[r, c] = 0
    fr = find_frontiers(g, INFO, robot_xy=(2.0, 2.0), robot_radius=0.3)
    assert fr, "no frontier from a robot standing on unknown cells behind its sensor's cone"
