"""rosrun mybot_control pid_tuner: the thesis's PID tuning study, offline (no ROS master needed).

Tunes the wheel model with Ziegler-Nichols, the thesis's brute-force grid,
gradient descent and a MultiPID schedule; prints the thesis-style table, writes
step-response PNGs and the gains YAML the wheel/swerve-module PIDs load.
"""
import argparse
import datetime
import os
import sys

import numpy as np
import yaml

from mybot_common.atomic_file import write_file_atomically
from mybot_control import pid_tuning as pt
from mybot_common.params import ParamError

METHODS = ("zn", "grid", "gd", "schedule")


def parse_args(argv):
    a = argparse.ArgumentParser(prog="pid_tuner", description=__doc__,
                                formatter_class=argparse.RawDescriptionHelpFormatter)
    d = pt.Plant()
    a.add_argument("--inertia", type=float, default=d.inertia, help="kg m^2 (default %(default)s)")
    a.add_argument("--max-torque", type=float, default=d.max_torque, help="N m (default %(default)s)")
    a.add_argument("--acceleration-damping", type=float, default=d.acceleration_damping,
                   help="fraction of the previous acceleration kept per step, [0, 1) (default %(default)s)")
    a.add_argument("--dt", type=float, default=d.dt, help="s (default %(default)s)")
    a.add_argument("--horizon", type=float, default=d.horizon, help="s (default %(default)s)")
    c = pt.Cost()
    a.add_argument("--tolerance", type=float, default=c.tolerance,
                   help="convergence band and oscillation threshold, fraction of |goal| (default %(default)s)")
    for w in ("w_convergence", "w_overshoot", "w_oscillation", "w_error"):
        a.add_argument("--" + w.replace("_", "-"), type=float, default=getattr(c, w),
                       help="cost weight (default %(default)s)")
    a.add_argument("--goals", default="2,4,6,8,10", help="goals of the table, comma separated (default %(default)s)")
    a.add_argument("--methods", default=",".join(METHODS), help="subset of %s (default all)" % ",".join(METHODS))
    a.add_argument("--zn", choices=("sweep", "relay"), default="sweep",
                   help="how Ziegler-Nichols finds Ku, Tu (default %(default)s)")
    a.add_argument("--grid-min", type=float, default=0.01)
    a.add_argument("--grid-max", type=float, default=200.0)
    a.add_argument("--grid-n", type=int, default=30, help="points per gain: n^3 runs (default %(default)s)")
    a.add_argument("--schedule-range", type=int, default=10,
                   help="MultiPID keys 1..N of |goal - current| (default %(default)s)")
    a.add_argument("--yaml-method", default="gd", choices=("zn", "grid", "gd"),
                   help="tuning written as the block's p/i/d (default %(default)s)")
    a.add_argument("--block", default="pid", help="name of the YAML block (default %(default)s)")
    a.add_argument("--no-output-limit", action="store_true",
                   help="do not write output_min/max (= -/+ max torque the gains were tuned with)")
    a.add_argument("--out-dir", default="pid_tuning", help="directory for table, plots, YAML (default %(default)s)")
    a.add_argument("--yaml", default=None, help="gains file (default OUT_DIR/pid_gains.yaml)")
    a.add_argument("--no-plots", action="store_true")
    return a.parse_args(argv)


def parse_list(name, text, kind=float):
    try:
        vals = [kind(x) for x in text.split(",") if x.strip()]
    except ValueError:
        raise ParamError(name, "must be a comma separated list, got %r" % text)
    if not vals:
        raise ParamError(name, "must not be empty")
    return vals


def plot(path, title, goals, metrics_by_name, plant):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    t = np.arange(plant.steps + 1) * plant.dt
    names = list(metrics_by_name)
    fig, axes = plt.subplots(len(names), 1, figsize=(8, 2.6 * len(names)), sharex=True, squeeze=False)
    for ax, name in zip(axes[:, 0], names):
        m = metrics_by_name[name]
        for j, g in enumerate(goals):
            line, = ax.plot(t, m.trajectory[j], label="goal %g" % g)
            ax.axhline(g, color=line.get_color(), lw=0.6, ls=":")
        ax.set_title(name)
        ax.set_ylabel("speed [m/s]")
        ax.grid(alpha=0.3)
    axes[0, 0].legend(loc="lower right", fontsize="small", ncol=len(goals))
    axes[-1, 0].set_xlabel("time [s]")
    fig.suptitle(title)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def run(args):
    plant = pt.Plant(args.inertia, args.max_torque, args.acceleration_damping, args.dt, args.horizon).validate()
    cost = pt.Cost(args.tolerance, args.w_convergence, args.w_overshoot, args.w_oscillation,
                   args.w_error).validate()
    goals = parse_list("goals", args.goals)
    for g in goals:
        if g == 0:
            raise ParamError("goals", "a step to 0 from rest is not a step")
    methods = parse_list("methods", args.methods, str)
    for m in methods:
        if m not in METHODS:
            raise ParamError("methods", "unknown method %r (choose from %s)" % (m, ", ".join(METHODS)))
    if args.yaml_method not in methods:
        raise ParamError("yaml-method", "%r is not among --methods" % args.yaml_method)
    grid = (args.grid_min, args.grid_max, args.grid_n)
    tuned, timings, notes = {}, {}, []
    if "zn" in methods:
        (ku, tu), dt_ = pt.timed(pt.ultimate_gain_sweep if args.zn == "sweep" else pt.relay_test, plant)
        tuned["zn"] = pt.ziegler_nichols(ku, tu)
        timings["zn"] = dt_
        notes.append("Ziegler-Nichols (%s): Ku = %.4g, Tu = %.4g s" % (args.zn, ku, tu))
    if "grid" in methods:
        (g, f, n), timings["grid"] = pt.timed(pt.brute_force, plant, cost, goals, *grid)
        tuned["grid"] = g
        notes.append("brute force: %d combinations, cost %.4g" % (n, f))
    if "gd" in methods:
        (g, f, n), timings["gd"] = pt.timed(pt.gradient_descent, plant, cost, goals)
        tuned["gd"] = g
        notes.append("gradient descent: %d runs, cost %.4g" % (n, f))
    schedule = None
    if "schedule" in methods:
        schedule, timings["schedule"] = pt.timed(pt.tune_schedule, plant, cost, args.schedule_range, grid)
    rows, metrics = [], {}
    for name, g in tuned.items():
        m = pt.evaluate(plant, cost, goals, gains=g)
        metrics[name] = m
        rows.append((name, m, lambda _goal, g=g: g))
    if schedule is not None:
        m = pt.evaluate(plant, cost, goals, schedule=schedule)
        metrics["schedule"] = m
        rows.append(("schedule", m, lambda goal: schedule.lookup(abs(goal))))
    text = pt.table(rows, goals)
    os.makedirs(args.out_dir, exist_ok=True)
    summary = ["# PID tuning (%s)" % datetime.datetime.now().isoformat(timespec="seconds"), "",
               "Plant: inertia %g, max torque %g, acceleration damping %g, dt %g s, horizon %g s; "
               "tolerance %g of |goal|." % (plant.inertia, plant.max_torque, plant.acceleration_damping,
                                            plant.dt, plant.horizon, cost.tolerance), ""]
    summary += ["- " + n for n in notes]
    summary += ["- %s: %.3f s" % (k, v) for k, v in timings.items()]
    summary += ["", text, ""]
    print("\n".join(summary))
    write_file_atomically(os.path.join(args.out_dir, "table.md"), "\n".join(summary))
    if not args.no_plots:
        for name, m in metrics.items():
            plot(os.path.join(args.out_dir, "step_%s.png" % name), "step responses: %s" % name, goals, {name: m},
                 plant)
        plot(os.path.join(args.out_dir, "step_all.png"), "step responses", goals, metrics, plant)
    data = pt.gains_yaml(args.block, tuned[args.yaml_method], schedule,
                         None if args.no_output_limit else plant.max_torque)
    path = args.yaml or os.path.join(args.out_dir, "pid_gains.yaml")
    # Replaced whole or not at all: a tuning run killed mid-write keeps the gains a robot runs on.
    write_file_atomically(path, "# written by pid_tuner (%s gains; plant inertia %g, max torque %g, damping %g, dt %g)\n"
                          % (args.yaml_method, plant.inertia, plant.max_torque, plant.acceleration_damping, plant.dt)
                          + yaml.safe_dump(data, default_flow_style=None, sort_keys=False))
    print("wrote %s%s" % (path, "" if args.no_plots else " and plots in %s" % args.out_dir))
    return 0


def main(argv=None):
    args = parse_args(sys.argv[1:] if argv is None else argv)
    try:
        return run(args)
    except ParamError as e:
        sys.stderr.write("pid_tuner: %s\n" % e)
        return 2


if __name__ == "__main__":
    sys.exit(main())
