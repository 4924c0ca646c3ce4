"""The page's JavaScript in headless chromium against the real server and a fake backend (no
ROS): token flow, keyboard driving of a holonomic robot, release, the swerve module panel."""
import asyncio
import os
import sys
import threading
import time

import pytest
import tornado.ioloop
from selenium.webdriver.common.action_chains import ActionChains
from selenium.webdriver.common.by import By

from mybot_web.protocol import Drive
from mybot_web.server import WebServer

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
from chromium import Chromium  # noqa: E402

WWW = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "www")
TOKEN = "correct-horse"


class Backend:
    """Records what the page asked for; reports four swerve modules at 90 degrees."""

    def __init__(self):
        self.lock = threading.Lock()
        self.calls = []

    def info(self):
        return {"holonomic": True, "scale_linear": 0.5, "scale_angular": 1.0, "send_period": 0.05,
                "deadman_timeout": 0.3, "mode": "manual", "modules": ["a", "b", "c", "d"],
                "trail": [], "trail_frame": None}

    def _record(self, *call):
        with self.lock:
            self.calls.append(call)

    def drive(self, client, msg):
        self._record("drive", msg)

    def release(self, client):
        self._record("release")

    def set_mode(self, mode):
        self._record("mode", mode)

    def send_goal(self, goal):
        self._record("goal", goal)

    def cancel_goal(self):
        self._record("cancel")

    def map_message(self):
        return None

    def state(self):
        return {"time": 12.5, "frame": "odom", "pose": [0.5, 0.25, 0.0], "scan": [], "path": [],
                "goal": None, "mode": "manual", "driver": None, "battery": 11.9, "cpu": 42.0,
                "cpu_source": "robot",
                "modules": [{"name": m, "angle": 1.5708, "speed": 0.25} for m in "abcd"]}

    def taken(self):
        with self.lock:
            calls, self.calls = self.calls, []
        return calls


class ServerThread:
    def __init__(self, backend):
        self.backend = backend
        self.ready = threading.Event()
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()
        assert self.ready.wait(10.0), "server did not start"

    def _run(self):
        asyncio.set_event_loop(asyncio.new_event_loop())
        self.loop = tornado.ioloop.IOLoop.current()
        self.web = WebServer(self.backend, WWW, token=TOKEN, view_rate=20.0)
        self.port = self.web.listen("127.0.0.1", 0)
        self.ready.set()
        self.loop.start()

    def sync(self):
        """Returns once the server's loop has run what it had queued before this call."""
        done = threading.Event()
        self.loop.add_callback(done.set)
        assert done.wait(10.0), "the server's loop did not run"

    def stop(self):
        self.loop.add_callback(self.web.stop)
        self.loop.add_callback(self.loop.stop)
        self.thread.join(10.0)


def wait_for(predicate, what, timeout=30.0):
    # Wall clock is right here: there is no ROS time, only a browser and a server.
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(0.02)
    raise AssertionError("timed out waiting for " + what)


@pytest.fixture(scope="module")
def env():
    backend = Backend()
    server = ServerThread(backend)
    chromium = Chromium(size="1000,700")
    yield backend, server, chromium.driver
    chromium.quit()
    server.stop()


def status(driver):
    return driver.find_element(By.ID, "status").text


def test_token_gates_control_and_keys_drive_a_holonomic_robot(env):
    backend, server, d = env
    d.get("http://127.0.0.1:%d/" % server.port)
    wait_for(lambda: "view only" in status(d), "the page to connect in view-only mode")
    assert d.find_element(By.ID, "auth").is_displayed()
    assert d.find_element(By.ID, "rotate").is_displayed()  # holonomic: a rotation strip
    body = d.find_element(By.TAG_NAME, "body")
    ActionChains(d).key_down("w").pause(0.3).key_up("w").perform()
    assert not [c for c in backend.taken() if c[0] == "drive"]  # nothing sent without the token

    token = d.find_element(By.ID, "token")
    token.send_keys("wrong-horse\n")
    wait_for(lambda: "wrong control token" in d.find_element(By.ID, "message").text,
             "the page to show the refusal")
    token.clear()
    token.send_keys(TOKEN + "\n")
    wait_for(lambda: not d.find_element(By.ID, "auth").is_displayed(), "the token form to go")
    assert status(d) == "connected"
    backend.taken()

    # Hold A (strafe left) then Q (turn left) at the default 50 % speed. Each step waits for what
    # the page sent, not for a span of wall time: a loaded machine may delay the page's timers.
    body.click()
    calls = []

    def drives():
        return [c[1] for c in calls if c[0] == "drive"]

    def take_until(predicate, what):
        def check():
            calls.extend(backend.taken())
            return predicate()
        wait_for(check, what)

    ActionChains(d).key_down("a").perform()
    take_until(lambda: Drive(0.0, 0.5, 0.0) in drives(), "a strafe while A is held")
    ActionChains(d).key_down("q").perform()
    # streamed while held (every send_period), not only sent when a key changes
    take_until(lambda: drives().count(Drive(0.0, 0.5, 0.5)) >= 5, "the strafe and turn repeated while A+Q are held")
    ActionChains(d).key_up("q").key_up("a").perform()
    take_until(lambda: ("release",) in calls, "a release after the keys go up")
    assert calls[-1] == ("release",)
    assert ("release",) not in calls[:-1]  # held keys never released the robot early

    # The live panel: four swerve modules, battery, CPU.
    captions = wait_for(lambda: [e.text for e in d.find_elements(By.CSS_SELECTOR, "#modules figcaption")
                                 if "90°" in e.text], "the module captions")
    assert len(captions) == 4 and "0.25 m/s" in captions[0]
    assert d.find_element(By.ID, "battery").text == "11.90 V"
    assert d.find_element(By.ID, "cpu").text == "42 % (robot)"


def test_token_from_the_url_and_mode_buttons(env):
    backend, server, d = env
    d.get("http://127.0.0.1:%d/?token=%s" % (server.port, TOKEN))
    wait_for(lambda: status(d) == "connected", "the page to authenticate from its URL")
    # The page before this one closes its socket as the browser leaves it, and the server records
    # a release when it handles the close: drained only once that has happened (one client left).
    wait_for(lambda: len(server.web.clients) == 1, "the previous page's socket to close")
    server.sync()  # on_close has returned (it leaves the set before it records the release)
    backend.taken()
    d.find_element(By.ID, "mode-autonomous").click()
    d.find_element(By.ID, "cancel").click()
    wait_for(lambda: (lambda c: c if ("cancel",) in c else None)(backend.calls[:]), "the cancel")
    assert backend.taken() == [("mode", "autonomous"), ("cancel",)]
