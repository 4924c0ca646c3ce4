"""Host and Pi in two network namespaces joined by a veth pair (see test/netns/scenario.py)."""
import os
import shutil
import subprocess
import sys

import pytest

HERE = os.path.dirname(os.path.abspath(__file__))
SCENARIO = os.path.join(HERE, "..", "netns", "scenario.py")


def _run(*cmd):
    return subprocess.run(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)


@pytest.fixture
def netns_pair():
    if os.geteuid() != 0:
        pytest.skip("network namespaces need root (ip netns add); not root here")
    if shutil.which("ip") is None:
        pytest.skip("the 'ip' tool (iproute2) is not installed")
    if _run("rospack", "find", "gopigo_bringup").returncode != 0:
        pytest.skip("workspace environment not sourced (rospack cannot find gopigo_bringup)")
    tag = str(os.getpid() % 100000)
    host, pi = "ggh" + tag, "ggp" + tag
    hveth, pveth = "ggvh" + tag, "ggvp" + tag
    subnet = 10 + os.getpid() % 200
    host_ip, pi_ip = "10.213.%d.1" % subnet, "10.213.%d.2" % subnet
    created = []
    try:
        r = _run("ip", "netns", "add", host)
        if r.returncode != 0:
            pytest.skip("cannot create a network namespace here: " + r.stdout.strip())
        created.append(host)
        steps = [
            ("ip", "netns", "add", pi),
            ("ip", "link", "add", hveth, "type", "veth", "peer", "name", pveth),
            ("ip", "link", "set", hveth, "netns", host),
            ("ip", "link", "set", pveth, "netns", pi),
            ("ip", "-n", host, "addr", "add", host_ip + "/24", "dev", hveth),
            ("ip", "-n", pi, "addr", "add", pi_ip + "/24", "dev", pveth),
            ("ip", "-n", host, "link", "set", "lo", "up"),
            ("ip", "-n", pi, "link", "set", "lo", "up"),
            ("ip", "-n", host, "link", "set", hveth, "up"),
            ("ip", "-n", pi, "link", "set", pveth, "up"),
        ]
        for step in steps:
            r = _run(*step)
            if step[:3] == ("ip", "netns", "add") and r.returncode == 0:
                created.append(pi)
            assert r.returncode == 0, "%s: %s" % (" ".join(step), r.stdout)
        yield host, pi, hveth, host_ip, pi_ip
    finally:
        for ns in created:  # deleting a namespace removes its veth end (and the pair)
            _run("ip", "netns", "del", ns)


def test_host_and_pi_over_veth(netns_pair):
    host, pi, hveth, host_ip, pi_ip = netns_pair
    r = subprocess.run(["ip", "netns", "exec", host, sys.executable, SCENARIO, host, pi, hveth, host_ip, pi_ip],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, timeout=150)
    print(r.stdout)
    assert r.returncode == 0, r.stdout[-6000:]
