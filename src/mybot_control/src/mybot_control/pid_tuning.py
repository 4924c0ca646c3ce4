"""PID tuning study of the thesis, vectorised (pure: numpy only, no ROS).

Plant (the thesis's wheel model, Euler-integrated with step dt over a horizon):
    tau_k  = clamp(u_k, -max_torque, max_torque)
    a_k    = damping * a_{k-1} + (1 - damping) * tau_k / inertia
    v_k+1  = v_k + a_k * dt
"acceleration damping" is the fraction of the previous acceleration kept each
step: the drive cannot change its acceleration instantly (a first-order lag),
which makes the loop oscillate under high gain like a real wheel does.

PID: the same law as the wheel/swerve controllers' C++ Pid (mybot_control/pid.hpp), so
tuned gains transfer: e = goal - v; u = p*e + i_term - d*dv/dt (derivative on the
measurement: no kick on a setpoint step); i_term += i*e*dt clamped to the i_clamp
range, with conditional integration (the integral does not grow while it would push
a saturated output further); u is clamped to +/- max_torque (output_min/max).
A MultiPID schedule picks, at every step, the gains whose key is nearest to
|goal - v| (keys are step sizes; one tuning per integer step).

Metrics (the thesis's, made precise):
  convergence  time after which |v - goal| stays within tolerance*|goal| for the
               rest of the horizon (linearly interpolated between samples);
               inf if still outside at the end
  overshoot    largest excursion past the goal, in the goal's units (>= 0)
  oscillations number of turning points (peaks and troughs) of v that lie
               outside the tolerance band
  error        accumulated absolute error, sum |goal - v| * dt
"""
import math
import time
from dataclasses import dataclass, field, asdict

import numpy as np

from mybot_common.params import ParamError, number


@dataclass
class Plant:
    inertia: float = 0.4
    max_torque: float = 3.75
    acceleration_damping: float = 0.5
    dt: float = 0.1
    horizon: float = 10.0

    def validate(self):
        number("inertia", self.inertia, low=0, low_open=True)
        number("max_torque", self.max_torque, low=0, low_open=True)
        number("acceleration_damping", self.acceleration_damping, low=0, high=1, high_open=True)
        number("dt", self.dt, low=0, low_open=True)
        number("horizon", self.horizon, low=0, low_open=True)
        if self.horizon < 2 * self.dt:
            raise ParamError("horizon", "must be at least two steps (2*dt = %g s), got %g" % (2 * self.dt, self.horizon))
        return self

    @property
    def steps(self):
        return int(round(self.horizon / self.dt))


@dataclass
class Cost:
    """Weighted cost the grid and gradient methods minimise."""
    tolerance: float = 0.02         # band, fraction of |goal|
    w_convergence: float = 1.0      # per second
    w_overshoot: float = 10.0       # per unit of overshoot / |goal|
    w_oscillation: float = 0.5      # per turning point outside the band
    w_error: float = 0.1            # per unit of accumulated error / |goal|
    not_converged_penalty: float = 2.0  # convergence counted as this x horizon when never converged

    def validate(self):
        number("tolerance", self.tolerance, low=0, low_open=True, high=1, high_open=True)
        for name in ("w_convergence", "w_overshoot", "w_oscillation", "w_error", "not_converged_penalty"):
            number(name, getattr(self, name), low=0)
        return self


@dataclass
class Gains:
    p: float
    i: float
    d: float

    def as_tuple(self):
        return (self.p, self.i, self.d)


@dataclass
class Schedule:
    """MultiPID: gains per key of |goal - current|, nearest key wins."""
    keys: list
    gains: list  # of Gains, same order as keys

    def lookup(self, abs_error):
        k = int(np.argmin(np.abs(np.asarray(self.keys, dtype=float) - abs_error)))
        return self.gains[k]


@dataclass
class Metrics:
    convergence: np.ndarray
    overshoot: np.ndarray
    oscillations: np.ndarray
    error: np.ndarray
    trajectory: np.ndarray = field(default=None, repr=False)


def simulate(plant, gains, goal, tolerance=0.02, i_clamp=(None, None), record=False, schedule=None):
    """Closed-loop step responses from rest, vectorised over a batch.

    gains: (p, i, d) arrays broadcastable to one batch shape (N,) -- ignored when
    `schedule` is given; goal: scalar or (N,). Metrics are accumulated while
    stepping so a 27,000-run batch never stores trajectories (unless record).
    """
    dt = plant.dt
    p, i, d = (np.atleast_1d(np.asarray(g, dtype=float)) for g in gains) if schedule is None else (0.0, 0.0, 0.0)
    goal = np.atleast_1d(np.asarray(goal, dtype=float))
    shape = np.broadcast_shapes(np.shape(p), np.shape(i), np.shape(d), goal.shape)
    goal = np.broadcast_to(goal, shape)
    if schedule is not None:
        keys = np.asarray(schedule.keys, dtype=float)
        sched = np.array([g.as_tuple() for g in schedule.gains], dtype=float)
    v = np.zeros(shape)
    acc = np.zeros(shape)
    i_term = np.zeros(shape)
    band = tolerance * np.where(goal == 0, 1.0, np.abs(goal))
    nsgn = np.where(goal < 0, 1.0, -1.0)  # -sign(goal): overshoot = max(-sign * e)
    keep, gain_in = plant.acceleration_damping, (1.0 - plant.acceleration_damping) / plant.inertia
    lo, hi = -plant.max_torque, plant.max_torque
    i_lo = -np.inf if i_clamp[0] is None else i_clamp[0]
    i_hi = np.inf if i_clamp[1] is None else i_clamp[1]
    # streaming metrics (plain ufunc calls with out=: small batches are overhead-bound)
    overshoot = np.zeros(shape)
    error = np.zeros(shape)
    oscill = np.zeros(shape, dtype=np.int64)
    last_out = np.full(shape, -1, dtype=np.int64)   # last sample index outside the band
    out_mag = np.zeros(shape)                        # |e| - band at that sample (>0)
    in_mag = np.zeros(shape)                         # band - |e| at the sample after it
    slope_sign = np.zeros(shape)                     # sign of the last non-zero slope
    e, ae, tmp, u, slope, cand, d_term = (np.empty(shape) for _ in range(7))
    outside, just_in, turn, nz = (np.empty(shape, dtype=bool) for _ in range(4))
    traj = [v.copy()] if record else None
    n = plant.steps
    for k in range(n + 1):
        np.subtract(goal, v, out=e)
        np.abs(e, out=ae)
        error += ae
        np.multiply(nsgn, e, out=tmp)
        np.maximum(overshoot, tmp, out=overshoot)
        np.greater(ae, band, out=outside)
        np.equal(last_out, k - 1, out=just_in)
        just_in &= ~outside
        np.subtract(band, ae, out=tmp)
        np.copyto(in_mag, tmp, where=just_in)
        np.copyto(last_out, k, where=outside)
        np.negative(tmp, out=tmp)
        np.copyto(out_mag, tmp, where=outside)
        if k == n:
            break
        if schedule is not None:
            idx = np.abs(ae[..., None] - keys).argmin(axis=-1)
            p, i, d = sched[idx, 0], sched[idx, 1], sched[idx, 2]
        # derivative on measurement; acc is the last step's dv/dt (0 before the first step)
        np.multiply(acc, d, out=d_term)
        np.negative(d_term, out=d_term)
        # conditional integration, as in the C++ Pid
        np.multiply(e, i * dt, out=cand)
        cand += i_term
        np.minimum(cand, i_hi, out=cand)
        np.maximum(cand, i_lo, out=cand)
        np.multiply(p, e, out=u)
        u += d_term
        np.add(u, cand, out=tmp)
        push = ((tmp > hi) & (cand > i_term)) | ((tmp < lo) & (cand < i_term))
        np.copyto(i_term, cand, where=~push)
        u += i_term
        np.minimum(u, hi, out=u)
        np.maximum(u, lo, out=u)
        acc *= keep
        u *= gain_in
        acc += u
        # turning point at the current sample: the slope changes sign here
        np.sign(acc, out=slope)  # v_next - v = acc*dt
        np.not_equal(slope, 0, out=nz)
        np.not_equal(slope, slope_sign, out=turn)
        turn &= nz
        np.not_equal(slope_sign, 0, out=just_in)  # just_in is free again here
        turn &= just_in
        turn &= outside
        oscill += turn
        np.copyto(slope_sign, slope, where=nz)
        v = v + acc * dt
        if record:
            traj.append(v)
    error *= dt
    frac = np.where(last_out >= 0, out_mag / np.maximum(out_mag + in_mag, 1e-300), 0.0)
    conv = np.where(last_out == n, np.inf, np.where(last_out < 0, 0.0, (last_out + frac) * dt))
    return Metrics(conv, overshoot, oscill, error,
                   np.stack(traj, axis=-1) if record else None)


def simulate_scalar(plant, p, i, d, goal):
    """One step response, loop by loop in plain Python: a readable transcription of the
    plant and of the C++ Pid::compute, used to cross-check `simulate` and as the
    un-vectorised baseline of the benchmark (how the thesis ran its study)."""
    v = acc = i_term = 0.0
    v_prev = None
    vs = [v]
    for _ in range(plant.steps):
        e = goal - v
        rate = 0.0 if v_prev is None else (v - v_prev) / plant.dt
        v_prev = v
        d_term = -d * rate
        cand = i_term + i * e * plant.dt
        unsat_with = p * e + cand + d_term
        if not ((unsat_with > plant.max_torque and cand > i_term)
                or (unsat_with < -plant.max_torque and cand < i_term)):
            i_term = cand
        u = max(-plant.max_torque, min(plant.max_torque, p * e + i_term + d_term))
        acc = plant.acceleration_damping * acc + (1 - plant.acceleration_damping) * u / plant.inertia
        v += acc * plant.dt
        vs.append(v)
    return np.array(vs)


def cost(m, goal, plant, c):
    g = np.where(np.asarray(goal) == 0, 1.0, np.abs(goal))
    conv = np.where(np.isinf(m.convergence), c.not_converged_penalty * plant.horizon, m.convergence)
    return (c.w_convergence * conv + c.w_overshoot * m.overshoot / g
            + c.w_oscillation * m.oscillations + c.w_error * m.error / g)


def mean_cost(plant, c, gains, goals):
    """Cost of each gain set averaged over several goals; gains arrays shaped (N,)."""
    goals = np.asarray(goals, dtype=float)
    p, i, d = (np.asarray(x, dtype=float)[:, None] for x in gains)
    m = simulate(plant, (p, i, d), goals[None, :], c.tolerance)
    return cost(m, goals[None, :], plant, c).mean(axis=1)


# ---------------------------------------------------------------- methods ---

def brute_force(plant, c, goals, low=0.01, high=200.0, n=30, chunk=None):
    """The thesis's grid: linspace(low, high, n) for each gain; n**3 runs."""
    number("grid_min", low, low=0)
    number("grid_max", high, low=low, low_open=True)
    number("grid_n", n, low=1, integer=True)
    axis = np.linspace(low, high, int(n))
    P, I, D = (a.ravel() for a in np.meshgrid(axis, axis, axis, indexing="ij"))
    goals = np.atleast_1d(goals)
    chunk = chunk or max(1, 200000 // len(goals))
    costs = np.concatenate([mean_cost(plant, c, (P[s:s + chunk], I[s:s + chunk], D[s:s + chunk]), goals)
                            for s in range(0, P.size, chunk)])
    best = int(np.argmin(costs))
    return Gains(float(P[best]), float(I[best]), float(D[best])), float(costs[best]), costs.size


def gradient_descent(plant, c, goals, start=None, iterations=40, step=0.25, h=0.05, min_step=1e-3,
                     floor=1e-3, rtol=1e-3):
    """Descent on the weighted cost in log-gain space.

    The gradient comes from central differences (6 runs in one batch), the step
    from a batched backtracking search (8 step sizes in one batch), so each
    iteration is two vectorised simulations. Log space keeps gains positive and
    makes one step size fit gains that differ by orders of magnitude.
    """
    evals = 0
    if start is None:  # coarse log grid (5^3 runs) as the starting point
        start, _, evals = coarse_start(plant, c, goals)
    x = np.log(np.maximum(np.asarray(start.as_tuple(), dtype=float), floor))
    fx = float(mean_cost(plant, c, tuple(np.exp(x)[:, None]), goals)[0])
    evals += 1
    eye = np.eye(3)
    # step sizes from 8x to 1/32x the nominal: long strides along valleys, fine ones near a minimum
    alphas = step * 2.0 ** np.arange(3, -6, -1)
    history = [fx]
    for _ in range(iterations):
        if len(history) > 4 and history[-5] - fx <= rtol * max(abs(fx), 1e-12):
            break
        history.append(fx)
        probes = np.concatenate([x + h * eye, x - h * eye])
        f = mean_cost(plant, c, tuple(np.exp(probes).T), goals)
        grad = (f[:3] - f[3:]) / (2 * h)
        evals += 6
        norm = np.linalg.norm(grad)
        if not np.isfinite(norm) or norm == 0:
            # flat or broken neighbourhood: the best probe is still a descent step
            k = int(np.argmin(f))
            if f[k] < fx:
                x, fx = probes[k], float(f[k])
                continue
            h *= 0.5
            if h < min_step:
                break
            continue
        direction = -grad / norm
        cands = x + alphas[:, None] * direction
        fc = mean_cost(plant, c, tuple(np.exp(cands).T), goals)
        evals += len(alphas)
        k = int(np.argmin(fc))
        if fc[k] < fx:
            x, fx = cands[k], float(fc[k])
        else:
            k = int(np.argmin(f))  # the probes themselves may be better
            if f[k] < fx:
                x, fx = probes[k], float(f[k])
            else:
                h *= 0.5
                alphas *= 0.25
                if alphas[0] < min_step:
                    break
    g = np.exp(x)
    return Gains(float(g[0]), float(g[1]), float(g[2])), fx, evals


def coarse_start(plant, c, goals, low=0.01, high=200.0, n=5):
    axis = np.geomspace(low, high, n)
    P, I, D = (a.ravel() for a in np.meshgrid(axis, axis, axis, indexing="ij"))
    f = mean_cost(plant, c, (P, I, D), goals)
    k = int(np.argmin(f))
    return Gains(float(P[k]), float(I[k]), float(D[k])), float(f[k]), P.size


def ultimate_gain_sweep(plant, step=1.0, k_min=0.01, k_max=1000.0, n=400):
    """Ziegler-Nichols ultimate gain Ku and period Tu from a P-only gain sweep.

    Ku is the smallest gain whose step response keeps oscillating (turning-point
    amplitude no longer decays), refined by a second, finer sweep.
    """
    number("zn_step", step, low=0, low_open=True)

    def sustained(kp):
        m = simulate(plant, (kp, 0.0, 0.0), step, record=True)
        return _oscillation(m.trajectory, plant.dt, step)

    ks = np.geomspace(k_min, k_max, n)
    ok, period = sustained(ks)
    if not ok.any():
        raise ParamError("zn_k_max", "no sustained oscillation up to Kp=%g; raise the sweep's upper bound" % k_max)
    j = int(np.argmax(ok))
    lo = ks[j - 1] if j > 0 else ks[0] / 2
    fine = np.linspace(lo, ks[j], n)
    ok2, period2 = sustained(fine)
    j2 = int(np.argmax(ok2))
    return float(fine[j2]), float(period2[j2])


def _oscillation(traj, dt, step):
    """For each response: (sustained?, period) from its turning points after the first half."""
    n = traj.shape[-1]
    e = traj - step
    de = np.diff(e, axis=-1)
    s = np.sign(de)
    turning = (s[..., 1:] * s[..., :-1]) < 0   # turning point at sample k+1
    ok = np.zeros(traj.shape[0], dtype=bool)
    period = np.full(traj.shape[0], np.nan)
    for r in range(traj.shape[0]):
        idx = np.nonzero(turning[r])[0] + 1
        if idx.size < 6:
            continue
        amp = np.abs(e[r, idx])
        half = idx >= n // 2
        late, early = amp[half], amp[~half]
        if late.size < 2 or early.size < 2 or late.max() < 1e-9 * step:
            continue
        # amplitude at the end at least that of the middle: not decaying
        ok[r] = late[-2:].mean() >= 0.98 * amp[max(0, len(amp) // 2 - 1):len(amp) // 2 + 1].mean()
        period[r] = 2.0 * np.mean(np.diff(idx[half])) * dt if half.sum() >= 2 else np.nan
    return ok, period


def relay_test(plant, step=1.0, amplitude=None):
    """Astrom-Hagglund relay feedback: u = +/-h; Ku = 4h/(pi a), Tu = limit-cycle period."""
    h = plant.max_torque if amplitude is None else number("relay_amplitude", amplitude, low=0, low_open=True)
    n = plant.steps
    v = acc = 0.0
    vs = []
    keep, gain_in = plant.acceleration_damping, (1.0 - plant.acceleration_damping) / plant.inertia
    for _ in range(n):
        u = h if step - v > 0 else -h
        acc = keep * acc + gain_in * min(max(u, -plant.max_torque), plant.max_torque)
        v += acc * plant.dt
        vs.append(v)
    vs = np.asarray(vs)
    tail = vs[n // 2:]
    a = 0.5 * (tail.max() - tail.min())
    s = np.sign(np.diff(tail))
    idx = np.nonzero(s[1:] * s[:-1] < 0)[0]
    if a <= 0 or idx.size < 3:
        raise ParamError("relay_amplitude", "relay test produced no limit cycle")
    tu = 2.0 * np.mean(np.diff(idx)) * plant.dt
    return 4.0 * h / (math.pi * a), float(tu)


def ziegler_nichols(ku, tu):
    """Classic PID rule: Kp = 0.6 Ku, Ti = Tu/2, Td = Tu/8."""
    kp = 0.6 * ku
    return Gains(kp, kp / (tu / 2.0), kp * tu / 8.0)


def tune_schedule(plant, c, key_range=10, grid=(0.01, 200.0, 30), refine=True):
    """MultiPID: one tuning per integer step size 1..key_range (grid, then gradient refinement)."""
    number("schedule_range", key_range, low=1, integer=True)
    keys, gains = [], []
    for k in range(1, int(key_range) + 1):
        g, f, _ = brute_force(plant, c, [float(k)], *grid)
        if refine:
            # descend from the grid's best and from a coarse log grid; keep the better valley
            cands = [gradient_descent(plant, c, [float(k)], g), gradient_descent(plant, c, [float(k)])]
            g, f, _ = min(cands, key=lambda r: r[1])
        keys.append(float(k))
        gains.append(g)
    return Schedule(keys, gains)


# ----------------------------------------------------------------- output ---

def evaluate(plant, c, goals, gains=None, schedule=None):
    goals = np.asarray(goals, dtype=float)
    if schedule is not None:
        return simulate(plant, None, goals, c.tolerance, record=True, schedule=schedule)
    return simulate(plant, tuple(np.full(goals.shape, g) for g in gains.as_tuple()), goals,
                    c.tolerance, record=True)


def fmt_time(t):
    return "n/c" if not np.isfinite(t) else "%.2f s" % t


def table(rows, goals):
    """Markdown table: one row per (method, goal). rows: list of (name, metrics, gains_for_goal)."""
    out = ["| method | goal | convergence | overshoot | oscillations | error | p | i | d |",
           "|---|---:|---:|---:|---:|---:|---:|---:|---:|"]
    for name, m, gains_of in rows:
        for j, g in enumerate(goals):
            gp = gains_of(g)
            out.append("| %s | %g | %s | %.3f | %d | %.3f | %.3g | %.3g | %.3g |" % (
                name, g, fmt_time(m.convergence[j]), m.overshoot[j], m.oscillations[j], m.error[j],
                gp.p, gp.i, gp.d))
    return "\n".join(out)


def gains_yaml(block, gains, schedule=None, output_limit=None, i_clamp=None):
    """The PID gains YAML (control_toolbox names) the wheel and swerve-module PIDs load."""
    entry = {"p": float(gains.p), "i": float(gains.i), "d": float(gains.d)}
    if i_clamp is not None:
        entry["i_clamp_min"], entry["i_clamp_max"] = float(i_clamp[0]), float(i_clamp[1])
    if output_limit is not None:
        entry["output_min"], entry["output_max"] = -float(output_limit), float(output_limit)
    if schedule is not None:
        entry["schedule"] = [{"error": float(k), "p": float(g.p), "i": float(g.i), "d": float(g.d)}
                             for k, g in zip(schedule.keys, schedule.gains)]
    return {block: entry}


def load_gains(data, block="pid"):
    """Parse and validate a gains block (as the C++ loader does); returns (Gains, Schedule|None, extras)."""
    if not isinstance(data, dict) or block not in data:
        raise ParamError(block, "missing block")
    b = data[block]
    if not isinstance(b, dict):
        raise ParamError(block, "must be a map with p, i, d")
    for k in ("p", "i", "d"):
        if k not in b:
            raise ParamError("%s/%s" % (block, k), "missing")
        number("%s/%s" % (block, k), b[k])
    extras = {}
    for k in ("i_clamp_min", "i_clamp_max", "output_min", "output_max"):
        if k in b:
            extras[k] = number("%s/%s" % (block, k), b[k])
    for lo, hi in (("i_clamp_min", "i_clamp_max"), ("output_min", "output_max")):
        if lo in extras and hi in extras and extras[lo] > extras[hi]:
            raise ParamError("%s/%s" % (block, lo), "must be <= %s" % hi)
    sched = None
    if "schedule" in b:
        if not isinstance(b["schedule"], list) or not b["schedule"]:
            raise ParamError("%s/schedule" % block, "must be a non-empty list")
        keys, gl = [], []
        for j, e in enumerate(b["schedule"]):
            name = "%s/schedule[%d]" % (block, j)
            if not isinstance(e, dict):
                raise ParamError(name, "must be a map {error, p, i, d}")
            for k in ("error", "p", "i", "d"):
                if k not in e:
                    raise ParamError("%s/%s" % (name, k), "missing")
            keys.append(number(name + "/error", e["error"], low=0))
            gl.append(Gains(*(number("%s/%s" % (name, k), e[k]) for k in ("p", "i", "d"))))
        sched = Schedule(keys, gl)
    return Gains(float(b["p"]), float(b["i"]), float(b["d"])), sched, extras


def timed(fn, *args, **kwargs):
    t = time.perf_counter()
    out = fn(*args, **kwargs)
    return out, time.perf_counter() - t


__all__ = ["Plant", "Cost", "Gains", "Schedule", "simulate", "cost", "brute_force", "gradient_descent",
           "ultimate_gain_sweep", "relay_test", "ziegler_nichols", "tune_schedule", "evaluate", "table",
           "gains_yaml", "load_gains", "asdict"]
