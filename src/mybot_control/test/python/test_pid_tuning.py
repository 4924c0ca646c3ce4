import math

import numpy as np
import pytest
import yaml

from mybot_control import pid_tuning as pt
from mybot_control.nodes import pid_tuner
from mybot_common.params import ParamError

PLANT = pt.Plant()
COST = pt.Cost()


def test_vectorised_simulation_matches_scalar_reference():
    gains = [(1.0, 0.5, 0.05), (8.0, 0.0, 0.4), (30.0, 20.0, 1.0)]
    m = pt.simulate(PLANT, tuple(np.array(g) for g in zip(*gains)), np.array([2.0, 6.0, 10.0]), record=True)
    for k, (g, goal) in enumerate(zip(gains, [2.0, 6.0, 10.0])):
        assert m.trajectory[k] == pytest.approx(pt.simulate_scalar(PLANT, *g, goal), abs=1e-12)


def test_metrics_on_hand_made_response():
    # P-only on the integrating plant: no steady-state error, so it converges.
    m = pt.simulate(PLANT, (1.0, 0.0, 0.0), 4.0, record=True)
    v = m.trajectory[0]
    band = 0.02 * 4.0
    outside = np.nonzero(np.abs(v - 4.0) > band)[0]
    k = outside[-1]
    assert k * PLANT.dt <= m.convergence[0] <= (k + 1) * PLANT.dt
    assert m.overshoot[0] == pytest.approx(max(0.0, (v - 4.0).max()))
    assert m.error[0] == pytest.approx(np.abs(4.0 - v).sum() * PLANT.dt)
    # turning points outside the band, counted independently
    d = np.sign(np.diff(v))
    turns = [j + 1 for j in range(len(d) - 1) if d[j] != 0 and d[j + 1] != 0 and d[j] != d[j + 1]]
    assert m.oscillations[0] == sum(1 for j in turns if abs(v[j] - 4.0) > band)


def test_unstable_gains_do_not_converge():
    m = pt.simulate(PLANT, (40.0, 0.0, 0.0), 2.0)
    assert math.isinf(m.convergence[0]) and m.oscillations[0] > 10


def test_ultimate_gain_matches_analytic_stability_limit():
    # P loop: z^2 + (K dt c - 1 - d) z + d = 0, c = (1-d)/I; a root reaches z = -1 at K dt c = 2 + 2d.
    c = (1 - PLANT.acceleration_damping) / PLANT.inertia
    k_analytic = (2 + 2 * PLANT.acceleration_damping) / (PLANT.dt * c)
    ku, tu = pt.ultimate_gain_sweep(PLANT, step=0.1)
    assert ku == pytest.approx(k_analytic, rel=0.02)
    assert tu == pytest.approx(2 * PLANT.dt, rel=0.05)  # the z = -1 oscillation: two samples


def test_relay_and_zn_rule():
    ku, tu = pt.relay_test(PLANT)
    assert ku > 0 and tu > 0
    g = pt.ziegler_nichols(10.0, 2.0)
    assert (g.p, g.i, g.d) == pytest.approx((6.0, 6.0, 1.5))


def test_brute_force_finds_the_grid_minimum():
    g, f, n = pt.brute_force(PLANT, COST, [4.0], 0.5, 10.0, 6)
    assert n == 216
    axis = np.linspace(0.5, 10.0, 6)
    best = min(float(pt.mean_cost(PLANT, COST, ([p], [i], [d]), [4.0])[0])
               for p in axis for i in axis for d in axis)
    assert f == pytest.approx(best)
    assert g.p in axis and g.i in axis and g.d in axis


def test_gradient_descent_beats_the_thesis_grid():
    _, f_grid, _ = pt.brute_force(PLANT, COST, [4.0])
    g, f_gd, _ = pt.gradient_descent(PLANT, COST, [4.0])
    assert f_gd < f_grid
    m = pt.simulate(PLANT, g.as_tuple(), 4.0)
    assert np.isfinite(m.convergence[0]) and m.overshoot[0] < 0.1


def test_schedule_lookup_and_simulation():
    s = pt.Schedule([1.0, 2.0, 3.0], [pt.Gains(1, 0, 0), pt.Gains(2, 0, 0), pt.Gains(3, 0, 0)])
    assert s.lookup(0.2).p == 1 and s.lookup(1.6).p == 2 and s.lookup(9).p == 3
    # a one-key schedule is the plain PID
    one = pt.Schedule([1.0], [pt.Gains(1.2, 0.1, 0.05)])
    a = pt.simulate(PLANT, None, 3.0, record=True, schedule=one).trajectory
    b = pt.simulate(PLANT, (1.2, 0.1, 0.05), 3.0, record=True).trajectory
    assert a == pytest.approx(b)


def test_yaml_round_trip(tmp_path):
    sched = pt.Schedule([1.0, 2.0], [pt.Gains(1.0, 0.4, 0.0), pt.Gains(1.4, 0.6, 0.0)])
    data = pt.gains_yaml("pid", pt.Gains(1.2, 0.5, 0.01), sched, output_limit=10.0, i_clamp=(-1.0, 1.0))
    path = tmp_path / "g.yaml"
    path.write_text(yaml.safe_dump(data))
    loaded = yaml.safe_load(path.read_text())
    assert loaded["pid"]["schedule"][1] == {"error": 2.0, "p": 1.4, "i": 0.6, "d": 0.0}
    g, s, extras = pt.load_gains(loaded)
    assert g == pt.Gains(1.2, 0.5, 0.01)
    assert s.keys == [1.0, 2.0] and s.gains[1] == pt.Gains(1.4, 0.6, 0.0)
    assert extras == {"i_clamp_min": -1.0, "i_clamp_max": 1.0, "output_min": -10.0, "output_max": 10.0}


@pytest.mark.parametrize("data, name", [
    ({}, "pid"),
    ({"pid": {"p": 1, "i": 0}}, "pid/d"),
    ({"pid": {"p": "x", "i": 0, "d": 0}}, "pid/p"),
    ({"pid": {"p": 1, "i": 0, "d": 0, "output_min": 2, "output_max": 1}}, "pid/output_min"),
    ({"pid": {"p": 1, "i": 0, "d": 0, "schedule": [{"error": 1, "p": 1, "i": 0}]}}, "pid/schedule[0]/d"),
])
def test_bad_gains_yaml_names_field(data, name):
    with pytest.raises(ParamError) as e:
        pt.load_gains(data)
    assert e.value.name == name


@pytest.mark.parametrize("field, value", [
    ("inertia", 0.0), ("max_torque", -1.0), ("acceleration_damping", 1.0), ("dt", 0.0), ("horizon", 0.1)])
def test_impossible_plant_is_rejected(field, value):
    kw = {field: value}
    with pytest.raises(ParamError) as e:
        pt.Plant(**kw).validate()
    assert e.value.name == field


def test_tuner_cli_end_to_end(tmp_path, capsys):
    out = tmp_path / "run"
    code = pid_tuner.main(["--goals", "2,4", "--methods", "zn,gd,schedule", "--schedule-range", "2",
                           "--grid-n", "8", "--out-dir", str(out)])
    assert code == 0
    text = capsys.readouterr().out
    assert "| zn | 2 |" in text and "| schedule | 4 |" in text
    for f in ("table.md", "step_all.png", "step_gd.png", "pid_gains.yaml"):
        assert (out / f).stat().st_size > 0
    g, s, extras = pt.load_gains(yaml.safe_load((out / "pid_gains.yaml").read_text()))
    assert s.keys == [1.0, 2.0] and extras["output_max"] == PLANT.max_torque and g.p > 0


@pytest.mark.parametrize("argv, name", [
    (["--inertia", "0"], "inertia"),
    (["--grid-min", "5", "--grid-max", "1", "--methods", "grid", "--yaml-method", "grid"], "grid_max"),
    (["--methods", "zn,foo"], "methods"),
    (["--goals", "0"], "goals"),
    (["--schedule-range", "0", "--methods", "gd,schedule"], "schedule_range"),
])
def test_tuner_cli_bad_input(tmp_path, capsys, argv, name):
    assert pid_tuner.main(argv + ["--out-dir", str(tmp_path), "--no-plots"]) == 2
    err = capsys.readouterr().err
    assert "parameter '%s'" % name in err


def test_committed_gains_files_load():
    import glob
    import os
    files = glob.glob(os.path.join(os.path.dirname(__file__), "..", "..", "config", "pid_gains*.yaml"))
    assert files
    for f in files:
        with open(f) as fh:
            g, s, extras = pt.load_gains(yaml.safe_load(fh))
        assert g.p > 0 and extras["output_min"] < extras["output_max"]
        assert s is None or s.keys == sorted(s.keys)
