"""The three robot descriptions: expansion, validity, physics, plugin geometry."""
import math
import os
import shutil
import subprocess
import xml.etree.ElementTree as ET

import numpy as np
import pytest

PKG = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
WS = os.path.dirname(os.path.dirname(PKG))
ROBOTS = ["mybot", "swerve", "gopigo"]
VARIANTS = [("mybot", ""), ("mybot", "drive:=joints"), ("mybot", "laser:=false camera:=false imu:=false"),
            ("swerve", ""), ("gopigo", ""), ("gopigo", "drive:=joints distance_sensor:=true laser:=true imu:=true")]


def xacro_cmd():
    venv = os.path.join(WS, ".venv", "bin", "xacro")
    return shutil.which("xacro") or venv


def expand(robot, args=""):
    path = os.path.join(PKG, "urdf", robot + ".xacro")
    res = subprocess.run([xacro_cmd(), path] + args.split(), capture_output=True, text=True)
    return res


_cache = {}


def urdf(robot, args=""):
    if (robot, args) not in _cache:
        res = expand(robot, args)
        assert res.returncode == 0, res.stderr
        _cache[(robot, args)] = res.stdout
    return _cache[(robot, args)]


def floats(text):
    return [float(v) for v in text.split()]


def rpy_matrix(r, p, y):
    cr, sr, cp, sp, cy, sy = math.cos(r), math.sin(r), math.cos(p), math.sin(p), math.cos(y), math.sin(y)
    return np.array([[cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
                     [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
                     [-sp, cp * sr, cp * cr]])


def origin_transform(elem):
    t = np.eye(4)
    o = elem.find("origin") if elem is not None else None
    if o is not None:
        t[:3, :3] = rpy_matrix(*floats(o.get("rpy", "0 0 0")))
        t[:3, 3] = floats(o.get("xyz", "0 0 0"))
    return t


class Model:
    def __init__(self, text):
        self.root = ET.fromstring(text)
        self.links = {l.get("name"): l for l in self.root.findall("link")}
        self.joints = {j.get("name"): j for j in self.root.findall("joint")}
        self.parent_joint = {j.find("child").get("link"): j for j in self.joints.values()}

    def root_link(self):
        roots = [l for l in self.links if l not in self.parent_joint]
        assert len(roots) == 1, roots
        return roots[0]

    def link_pose(self, link):
        """Pose of a link in the root frame with every joint at zero."""
        t = np.eye(4)
        while link in self.parent_joint:
            j = self.parent_joint[link]
            t = origin_transform(j) @ t
            link = j.find("parent").get("link")
        return t

    def plugins(self, filename):
        return [p for p in self.root.iter("plugin") if p.get("filename") == filename]


def model(robot, args=""):
    return Model(urdf(robot, args))


@pytest.mark.parametrize("robot,args", VARIANTS)
def test_expands_and_passes_check_urdf(robot, args, tmp_path):
    f = tmp_path / (robot + ".urdf")
    f.write_text(urdf(robot, args))
    res = subprocess.run(["check_urdf", str(f)], capture_output=True, text=True)
    assert res.returncode == 0, res.stdout + res.stderr
    assert "Successfully Parsed XML" in res.stdout


@pytest.mark.parametrize("robot", ROBOTS)
def test_root_on_ground_and_base_link_above(robot):
    m = model(robot)
    assert m.root_link() == "base_footprint"
    j = m.parent_joint["base_link"]
    assert j.find("parent").get("link") == "base_footprint"
    assert m.link_pose("base_link")[2, 3] > 0.0
    # The lowest collision point of the robot (the wheels) touches z = 0.
    lowest = min(lowest_point(m, name) for name in m.links if m.links[name].find("collision") is not None)
    assert abs(lowest) < 1e-3, lowest


def lowest_point(m, link):
    """Lowest z of a link's cylinder/sphere/box collisions in the root frame."""
    best = math.inf
    for c in m.links[link].findall("collision"):
        t = m.link_pose(link) @ origin_transform(c)
        g = c.find("geometry")[0]
        if g.tag == "sphere":
            best = min(best, t[2, 3] - float(g.get("radius")))
        elif g.tag == "cylinder":
            r, h = float(g.get("radius")), float(g.get("length"))
            axis = t[:3, 2]
            # Lowest point of a cylinder: the rim reaches r*sqrt(1-az^2) below, the caps h/2*|az|.
            best = min(best, t[2, 3] - r * math.sqrt(max(0.0, 1 - axis[2] ** 2)) - h / 2 * abs(axis[2]))
        elif g.tag == "box":
            half = np.array(floats(g.get("size"))) / 2
            best = min(best, t[2, 3] - float(np.abs(t[2, :3]) @ half))
    return best


@pytest.mark.parametrize("robot,args", VARIANTS)
def test_inertias_physically_valid(robot, args):
    m = model(robot, args)
    massive = 0
    for name, link in m.links.items():
        inertial = link.find("inertial")
        if inertial is None:
            continue
        massive += 1
        mass = float(inertial.find("mass").get("value"))
        assert mass > 0.005, "%s: mass %g kg is not physical" % (name, mass)
        i = inertial.find("inertia")
        g = {k: float(i.get(k)) for k in ("ixx", "ixy", "ixz", "iyy", "iyz", "izz")}
        tensor = np.array([[g["ixx"], g["ixy"], g["ixz"]], [g["ixy"], g["iyy"], g["iyz"]], [g["ixz"], g["iyz"], g["izz"]]])
        eig = np.linalg.eigvalsh(tensor)
        assert eig.min() > 0, "%s: inertia not positive definite %s" % (name, eig)
        a, b, c = sorted(eig)
        assert a + b >= c * (1 - 1e-9), "%s: principal moments %s break the triangle inequality" % (name, eig)
    assert massive >= 3


def wheel_radius(m, joint):
    link = m.joints[joint].find("child").get("link")
    cyl = m.links[link].find("collision/geometry/cylinder")
    return float(cyl.get("radius"))


@pytest.mark.parametrize("robot", ["mybot", "gopigo"])
def test_diff_drive_plugin_matches_geometry(robot):
    m = model(robot)
    (p,) = m.plugins("libgazebo_ros_diff_drive.so")
    left, right = p.findtext("leftJoint"), p.findtext("rightJoint")
    assert (left, right) == ("left_wheel_hinge", "right_wheel_hinge")
    dist = np.linalg.norm(m.link_pose(m.joints[left].find("child").get("link"))[:3, 3]
                          - m.link_pose(m.joints[right].find("child").get("link"))[:3, 3])
    assert abs(float(p.findtext("wheelSeparation")) - dist) < 1e-3
    for j in (left, right):
        assert abs(float(p.findtext("wheelDiameter")) - 2 * wheel_radius(m, j)) < 1e-9
        assert m.joints[j].get("type") == "continuous"
    for tag in ("commandTopic", "odometryTopic", "odometryFrame", "robotBaseFrame", "wheelTorque", "updateRate"):
        assert p.findtext(tag), tag
    assert p.findtext("robotBaseFrame") == "base_footprint"


def test_mybot_dimensions():
    m = model("mybot")
    box = m.links["chassis"].find("collision/geometry/box")
    assert floats(box.get("size")) == [0.4, 0.2, 0.1]
    for j in ("left_wheel_hinge", "right_wheel_hinge"):
        assert wheel_radius(m, j) == pytest.approx(0.1)
        link = m.joints[j].find("child").get("link")
        assert float(m.links[link].find("collision/geometry/cylinder").get("length")) == pytest.approx(0.05)
    for link in ("camera", "hokuyo", "caster_front", "caster_back", "imu_link"):
        assert link in m.links
    # Casters are frictionless, wheels are not.
    refs = {g.get("reference"): g for g in m.root.findall("gazebo") if g.get("reference")}
    for c in ("caster_front", "caster_back"):
        assert float(refs[c].findtext("mu1")) == 0.0 and float(refs[c].findtext("mu2")) == 0.0
    assert float(refs["left_wheel"].findtext("mu1")) > 0.5
    # Camera on the front face, laser on top.
    assert m.link_pose("camera")[0, 3] == pytest.approx(0.2 + 0.025)
    assert m.link_pose("hokuyo")[2, 3] > m.link_pose("chassis")[2, 3] + 0.05


def test_mybot_sensors_match_tutorial():
    m = model("mybot")
    (laser,) = m.plugins("libgazebo_ros_laser.so")
    sensor = [s for s in m.root.iter("sensor") if s.find("plugin") is laser or laser in list(s)][0]
    assert sensor.get("type") == "ray"
    h = sensor.find("ray/scan/horizontal")
    assert int(h.findtext("samples")) == 720
    assert float(h.findtext("min_angle")) == pytest.approx(-math.pi / 2)
    assert float(h.findtext("max_angle")) == pytest.approx(math.pi / 2)
    assert float(sensor.findtext("ray/range/min")) == pytest.approx(0.10)
    assert float(sensor.findtext("ray/range/max")) == pytest.approx(30.0)
    assert float(sensor.findtext("ray/noise/stddev")) == pytest.approx(0.01)
    assert float(sensor.findtext("update_rate")) == pytest.approx(40)
    assert laser.findtext("topicName") == "scan" and laser.findtext("frameName") == "hokuyo"

    (cam,) = m.plugins("libgazebo_ros_camera.so")
    csensor = [s for s in m.root.iter("sensor") if cam in list(s)][0]
    assert csensor.get("name") == "camera1"
    assert float(csensor.findtext("update_rate")) == pytest.approx(30)
    assert math.degrees(float(csensor.findtext("camera/horizontal_fov"))) == pytest.approx(80, abs=1e-4)
    assert (csensor.findtext("camera/image/width"), csensor.findtext("camera/image/height")) == ("800", "800")
    assert cam.findtext("cameraName") + "/" + cam.findtext("imageTopicName") == "mybot/camera1/image_raw"
    assert cam.findtext("cameraInfoTopicName") == "camera_info"

    assert len(m.plugins("libgazebo_ros_imu_sensor.so")) == 1
    (p3d,) = m.plugins("libgazebo_ros_p3d.so")
    assert p3d.findtext("topicName") == "ground_truth/odom"


def test_mybot_sensor_switches_and_joint_drive():
    m = model("mybot", "drive:=joints laser:=false camera:=false imu:=false ground_truth:=false")
    assert not m.plugins("libgazebo_ros_diff_drive.so")
    assert not m.plugins("libgazebo_ros_laser.so") and not m.plugins("libgazebo_ros_camera.so")
    assert not m.plugins("libgazebo_ros_p3d.so")
    (cmd,) = m.plugins("libmybot_joint_command.so")
    names = sorted(j.findtext("name") for j in cmd.findall("joint"))
    assert names == ["left_wheel_hinge", "right_wheel_hinge"]
    for j in cmd.findall("joint"):
        assert j.findtext("type") == "velocity" and float(j.findtext("effortLimit")) > 0
    (js,) = m.plugins("libgazebo_ros_joint_state_publisher.so")
    assert [s.strip() for s in js.findtext("jointName").split(",")] == ["left_wheel_hinge", "right_wheel_hinge"]


@pytest.mark.parametrize("robot", ["mybot", "gopigo"])
def test_bad_drive_argument_fails_naming_it(robot):
    res = expand(robot, "drive:=tracks")
    assert res.returncode != 0
    assert "drive_must_be_plugin_or_joints" in res.stderr


def test_swerve_modules():
    m = model("swerve")
    offsets = []
    for mod in "abcd":
        pivot, wheel = m.joints["swerve_%s_pivot_joint" % mod], m.joints["swerve_%s_wheel_joint" % mod]
        assert pivot.get("type") == "continuous" and floats(pivot.find("axis").get("xyz")) == [0, 0, 1]
        assert wheel.get("type") == "continuous" and floats(wheel.find("axis").get("xyz")) == [0, 1, 0]
        assert wheel.find("parent").get("link") == pivot.find("child").get("link")
        offsets.append(tuple(np.round(m.link_pose(pivot.find("child").get("link"))[:2, 3], 6)))
    assert len(set(offsets)) == 4
    assert sorted(np.sign(o[0]) * 2 + np.sign(o[1]) for o in offsets) == [-3, -1, 1, 3]
    (cmd,) = m.plugins("libmybot_joint_command.so")
    commanded = {j.findtext("name") for j in cmd.findall("joint")}
    for mod in "abcd":
        assert {"swerve_%s_pivot_joint" % mod, "swerve_%s_wheel_joint" % mod} <= commanded
    assert "camera_pivot_joint" in m.joints and "imu_link" in m.links and "hokuyo" in m.links
    assert m.plugins("libgazebo_ros_p3d.so") and m.plugins("libgazebo_ros_imu_sensor.so")
    assert m.plugins("libgazebo_ros_laser.so")


def test_gopigo_dimensions():
    m = model("gopigo")
    for j in ("left_wheel_hinge", "right_wheel_hinge"):
        assert 2 * wheel_radius(m, j) == pytest.approx(0.0665)
    sep = abs(m.link_pose("left_wheel")[1, 3] - m.link_pose("right_wheel")[1, 3])
    assert sep == pytest.approx(0.117)
    assert "caster" in m.links
    assert "distance_sensor" not in m.links
    assert "distance_sensor" in model("gopigo", "distance_sensor:=true").links


def test_display_launch_rejects_unknown_model():
    launch = os.path.join(PKG, "launch", "display.launch")
    res = subprocess.run(["roslaunch", "--nodes", launch, "model:=tank"], capture_output=True, text=True)
    assert res.returncode != 0
    out = res.stdout + res.stderr
    assert "unknown_model_use_mybot_swerve_or_gopigo" in out and "double underscore" not in out
    ok = subprocess.run(["roslaunch", "--nodes", launch, "model:=swerve", "rviz:=false"], capture_output=True, text=True)
    assert ok.returncode == 0, ok.stderr
