"""Frontier exploration on an occupancy grid (no ROS types).

A frontier cell is a known-free cell with an unknown 4-neighbour. Frontier
cells are grouped into 8-connected clusters; each cluster offers one goal: its
reachable cell with enough clearance closest to the cluster's centroid. The
explorer picks the cluster with the shortest path from the robot (a breadth-
first search over free cells with clearance), never a blacklisted one.
"""
from dataclasses import dataclass

import numpy as np
from scipy import ndimage
from scipy.sparse import csr_matrix
from scipy.sparse.csgraph import dijkstra

UNKNOWN = -1


@dataclass
class GridInfo:
    resolution: float
    origin_x: float
    origin_y: float

    def to_cell(self, x, y):
        return int(np.floor((y - self.origin_y) / self.resolution)), int(np.floor((x - self.origin_x) / self.resolution))

    def to_world(self, row, col):
        return (self.origin_x + (col + 0.5) * self.resolution, self.origin_y + (row + 0.5) * self.resolution)


@dataclass
class Frontier:
    goal: tuple          # (x, y) in the map frame
    size: int            # frontier cells in the cluster
    path_length: float   # metres along free space from the robot
    cells: np.ndarray    # (N, 2) rows/cols of the cluster


def free_mask(grid, free_thresh=25):
    return (grid >= 0) & (grid <= free_thresh)


def frontier_mask(grid, free_thresh=25):
    """Free cells with at least one unknown 4-neighbour."""
    unknown = grid == UNKNOWN
    near_unknown = np.zeros_like(unknown)
    near_unknown[1:, :] |= unknown[:-1, :]
    near_unknown[:-1, :] |= unknown[1:, :]
    near_unknown[:, 1:] |= unknown[:, :-1]
    near_unknown[:, :-1] |= unknown[:, 1:]
    return free_mask(grid, free_thresh) & near_unknown


def path_lengths(passable, start):
    """8-connected shortest path lengths in cells from start over passable
    cells (Dijkstra on a sparse graph); inf where unreachable."""
    rows, cols = passable.shape
    dist = np.full(passable.shape, np.inf)
    r0, c0 = start
    if not (0 <= r0 < rows and 0 <= c0 < cols) or not passable[r0, c0]:
        return dist
    index = np.full(passable.shape, -1, dtype=np.int64)
    index[passable] = np.arange(int(passable.sum()))
    src, dst, w = [], [], []
    for dr, dc in ((0, 1), (1, 0), (1, 1), (1, -1)):
        a = index[max(0, -dr):rows - max(0, dr), max(0, -dc):cols - max(0, dc)]
        b = index[max(0, dr):rows - max(0, -dr), max(0, dc):cols - max(0, -dc)]
        both = (a >= 0) & (b >= 0)
        src.append(a[both]); dst.append(b[both]); w.append(np.full(int(both.sum()), np.hypot(dr, dc)))
    n = int(passable.sum())
    graph = csr_matrix((np.concatenate(w), (np.concatenate(src), np.concatenate(dst))), shape=(n, n))
    d = dijkstra(graph, directed=False, indices=int(index[r0, c0]))
    dist[passable] = d
    return dist


def enclosed_unknown(grid, max_area_cells):
    """Unknown cells in 4-connected pockets of at most max_area_cells that do
    not touch the grid's edge: the inside of a box or pillar, which no laser
    can see however often the robot drives around it."""
    unknown = np.asarray(grid) == UNKNOWN
    labels, n = ndimage.label(unknown)
    if n == 0:
        return np.zeros_like(unknown)
    sizes = np.bincount(labels.ravel(), minlength=n + 1)
    edge = np.unique(np.concatenate([labels[0, :], labels[-1, :], labels[:, 0], labels[:, -1]]))
    small = sizes <= max_area_cells
    small[0] = False
    small[edge] = False
    return small[labels]


def start_cell(free, passable, info, robot_xy, robot_radius, grid=None):
    """The passable cell the search starts from: the robot's own, or, when it
    stands closer to an obstacle than its radius (a narrow gap, a wall it
    brushed), the nearest passable cell it can get to through free space
    within 2 m. None when there is none: the robot's position says nothing
    about the frontiers then, so that is not "explored"."""
    r, c = info.to_cell(*robot_xy)
    if not (0 <= r < free.shape[0] and 0 <= c < free.shape[1]):
        return None
    if passable[r, c]:
        return r, c
    if not free[r, c]:
        # The SLAM grid may mark the robot's own cell: take the nearest free cell next to it. A
        # sensor that does not see around the robot (a depth camera's narrow field of view and
        # minimum range) leaves the robot's own cell unknown: look as far as 1 m for free space.
        unknown_here = grid is not None and grid[r, c] < 0
        k = int(np.ceil(max(robot_radius, 1.0 if unknown_here else 0.0) / info.resolution))
        win = np.argwhere(free[max(r - k, 0):r + k + 1, max(c - k, 0):c + k + 1])
        if len(win) == 0:
            return None
        win = win + [max(r - k, 0), max(c - k, 0)]
        r, c = win[np.argmin(np.hypot(win[:, 0] - r, win[:, 1] - c))]
    seed = np.zeros_like(free)
    seed[r, c] = True
    around = ndimage.binary_dilation(seed, iterations=int(np.ceil(2.0 / info.resolution)), mask=free)
    cand = np.argwhere(around & passable)
    if len(cand) == 0:
        return None
    near = cand[np.argmin(np.hypot(cand[:, 0] - r, cand[:, 1] - c))]
    return int(near[0]), int(near[1])


def find_frontiers(grid, info, robot_xy, robot_radius=0.2, min_frontier_size=5,
                   blacklist=(), blacklist_radius=0.5, free_thresh=25, boundary=None, min_unknown_area=2.0):
    """Frontier clusters reachable from the robot, nearest (by path) first;
    None when the robot cannot be placed on the grid's passable space.
    boundary (xmin, ymin, xmax, ymax), in the map frame, keeps exploration
    inside an area: laser rays leaving through an open door do not send the
    robot out to map the car park. Unknown pockets enclosed by known cells and
    smaller than min_unknown_area (m^2) are not worth a frontier: they are the
    insides of obstacles."""
    grid = np.asarray(grid)
    if min_unknown_area > 0:
        pockets = enclosed_unknown(grid, int(min_unknown_area / info.resolution ** 2))
        if pockets.any():
            grid = grid.copy()
            grid[pockets] = 100  # treated as solid: no frontier borders them
    free = free_mask(grid, free_thresh)
    blocked = ~free  # unknown counts as blocked for clearance: goals stay inside known space
    clearance = ndimage.distance_transform_edt(~blocked) * info.resolution
    passable = free & (clearance >= robot_radius)

    start = start_cell(free, passable, info, robot_xy, robot_radius, grid)
    if start is None:
        return None
    dist = path_lengths(passable, start)

    front = frontier_mask(grid, free_thresh)
    if boundary is not None:
        xmin, ymin, xmax, ymax = boundary
        rows, cols = np.indices(grid.shape)
        x = info.origin_x + (cols + 0.5) * info.resolution
        y = info.origin_y + (rows + 0.5) * info.resolution
        front &= (x >= xmin) & (x <= xmax) & (y >= ymin) & (y <= ymax)
    labels, n = ndimage.label(front, structure=np.ones((3, 3)))
    frontiers = []
    for k in range(1, n + 1):
        cells = np.argwhere(labels == k)
        if len(cells) < min_frontier_size:
            continue
        # Frontier cells border unknown space, so they rarely have clearance:
        # the goal is the reachable cell nearest the cluster within a short reach.
        centroid = cells.mean(axis=0)
        window = int(np.ceil((robot_radius * 2 + 0.5) / info.resolution))
        r0, c0 = np.maximum(cells.min(axis=0) - window, 0)
        r1, c1 = np.minimum(cells.max(axis=0) + window + 1, grid.shape)
        sub = dist[r0:r1, c0:c1]
        reach = np.argwhere(np.isfinite(sub))
        if len(reach) == 0:
            continue
        reach = reach + [r0, c0]
        # Distance from each reachable candidate to the nearest frontier cell of the cluster.
        d_front = np.min(np.hypot(reach[:, None, 0] - cells[None, ::max(1, len(cells) // 50), 0],
                                  reach[:, None, 1] - cells[None, ::max(1, len(cells) // 50), 1]), axis=1)
        ok = reach[d_front * info.resolution <= robot_radius * 2 + 0.5]
        # ...and sees it: the frontier must lie within that reach through free space, not behind a
        # wall (rays through a door map free cells outside, right behind the wall from inside).
        seen = np.zeros((r1 - r0, c1 - c0), dtype=bool)
        seen[cells[:, 0] - r0, cells[:, 1] - c0] = True
        seen = ndimage.binary_dilation(seen, iterations=int(np.ceil((robot_radius * 2 + 0.5) / info.resolution)),
                                       mask=free[r0:r1, c0:c1])
        ok = ok[seen[ok[:, 0] - r0, ok[:, 1] - c0]]
        # Goals already tried are excluded candidate by candidate, not cluster by cluster: a
        # long frontier seen from one end can still be reached from elsewhere.
        for bx, by in blacklist:
            br, bc = (by - info.origin_y) / info.resolution - 0.5, (bx - info.origin_x) / info.resolution - 0.5
            ok = ok[np.hypot(ok[:, 0] - br, ok[:, 1] - bc) * info.resolution >= blacklist_radius]
        if len(ok) == 0:
            continue
        best = ok[np.argmin(np.hypot(ok[:, 0] - centroid[0], ok[:, 1] - centroid[1]))]
        goal = info.to_world(*best)
        frontiers.append(Frontier(goal=goal, size=len(cells), path_length=float(dist[tuple(best)]) * info.resolution,
                                  cells=cells))
    frontiers.sort(key=lambda f: f.path_length)
    return frontiers


def frontier_near(grid, info, xy, radius, min_cells=1, free_thresh=25):
    """Whether at least min_cells frontier cells lie within radius of xy: the
    cheap check, on a window of the grid, that a frontier being driven to
    still exists."""
    grid = np.asarray(grid)
    r, c = info.to_cell(*xy)
    k = int(np.ceil(radius / info.resolution)) + 1
    r0, c0 = max(r - k, 0), max(c - k, 0)
    r1, c1 = min(r + k + 1, grid.shape[0]), min(c + k + 1, grid.shape[1])
    if r0 >= r1 or c0 >= c1:
        return False
    window = grid[max(r0 - 1, 0):min(r1 + 1, grid.shape[0]), max(c0 - 1, 0):min(c1 + 1, grid.shape[1])]
    front = frontier_mask(window, free_thresh)
    cells = np.argwhere(front) + [max(r0 - 1, 0), max(c0 - 1, 0)]
    d = np.hypot(cells[:, 0] - r, cells[:, 1] - c) * info.resolution
    return int(np.count_nonzero(d <= radius)) >= min_cells
