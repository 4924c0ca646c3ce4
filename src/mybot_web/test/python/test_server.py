"""The tornado server against a fake backend: real HTTP and websocket, no ROS."""
import json
import logging
import os

import tornado.httpclient
import tornado.websocket
from tornado.testing import AsyncHTTPTestCase, gen_test

from mybot_web.protocol import Drive, Goal
from mybot_web.server import MAX_AUTH_FAILURES, WebServer

WWW = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "www")


class FakeBackend:
    def __init__(self):
        self.calls = []
        self.map = None

    def info(self):
        return {"holonomic": False, "send_period": 0.05, "mode": "autonomous", "modules": [],
                "trail": [], "trail_frame": None}

    def drive(self, client, msg):
        self.calls.append(("drive", client, msg))

    def release(self, client):
        self.calls.append(("release", client))

    def set_mode(self, mode):
        self.calls.append(("mode", mode))

    def send_goal(self, goal):
        self.calls.append(("goal", goal))

    def cancel_goal(self):
        self.calls.append(("cancel",))

    def map_message(self):
        return self.map

    def state(self):
        return {"pose": [1.0, 2.0, 0.5]}


class ServerCase(AsyncHTTPTestCase):
    token = None

    def get_app(self):
        self.backend = FakeBackend()
        self.web = WebServer(self.backend, WWW, token=self.token, view_rate=0,
                             log=logging.getLogger("test"))
        return self.web.app

    async def connect(self, origin=None):
        url = "ws://127.0.0.1:%d/ws" % self.get_http_port()
        req = tornado.httpclient.HTTPRequest(url, headers={"Origin": origin} if origin else {})
        ws = await tornado.websocket.websocket_connect(req)
        hello = json.loads(await ws.read_message())
        assert hello["type"] == "hello"
        return ws, hello

    async def until(self, predicate):
        # The server handles a frame on the same loop; yield until it has.
        for _ in range(200):
            if predicate():
                return
            await tornado.gen.sleep(0.005)
        raise AssertionError("condition not reached; calls: %r" % self.backend.calls)


class TestOpenServer(ServerCase):
    def test_page_and_assets_are_served_with_a_strict_policy(self):
        r = self.fetch("/")
        assert r.code == 200 and b'<canvas id="map"' in r.body
        assert "default-src 'self'" in r.headers["Content-Security-Policy"]
        assert self.fetch("/static/app.js").code == 200
        assert self.fetch("/static/../../setup.py").code in (403, 404)

    @gen_test
    async def test_drive_stop_and_close(self):
        ws, hello = await self.connect()
        assert hello["authed"] and not hello["auth_required"]
        ws.write_message(json.dumps({"type": "drive", "vx": 0.5, "vy": 0, "wz": 0.25}))
        ws.write_message(json.dumps({"type": "stop"}))
        await self.until(lambda: len(self.backend.calls) >= 2)
        client = hello["client"]
        assert self.backend.calls[:2] == [("drive", client, Drive(0.5, 0.0, 0.25)), ("release", client)]
        ws.close()
        await self.until(lambda: len(self.backend.calls) >= 3)
        assert self.backend.calls[2] == ("release", client)  # closing the page stops the robot

    @gen_test
    async def test_bad_input_is_rejected_and_stops(self):
        ws, hello = await self.connect()
        ws.write_message(json.dumps({"type": "drive", "vx": 3, "vy": 0, "wz": 0}))
        err = json.loads(await ws.read_message())
        assert err["type"] == "error" and "drive.vx" in err["message"]
        assert self.backend.calls == [("release", hello["client"])]
        assert not any(c[0] == "drive" for c in self.backend.calls)

    @gen_test
    async def test_mode_goal_cancel_reach_the_backend(self):
        ws, _ = await self.connect()
        for m in ({"type": "mode", "mode": "manual"}, {"type": "goal", "x": 1, "y": 2, "yaw": 0},
                  {"type": "cancel"}):
            ws.write_message(json.dumps(m))
        await self.until(lambda: len(self.backend.calls) >= 3)
        assert self.backend.calls == [("mode", "manual"), ("goal", Goal(1.0, 2.0, 0.0)), ("cancel",)]

    @gen_test
    async def test_map_on_connect_and_state_broadcast(self):
        self.backend.map = (1, {"type": "map", "width": 1})
        ws, _ = await self.connect()
        assert json.loads(await ws.read_message())["type"] == "map"
        self.web.broadcast()
        state = json.loads(await ws.read_message())
        assert state == {"type": "state", "pose": [1.0, 2.0, 0.5]}
        self.backend.map = (2, {"type": "map", "width": 2})
        self.web.broadcast()
        assert json.loads(await ws.read_message())["width"] == 2  # new map version pushed

    @gen_test
    async def test_cross_origin_pages_cannot_connect(self):
        try:
            await self.connect(origin="http://evil.example")
        except tornado.httpclient.HTTPClientError as e:
            assert e.code == 403
        else:
            raise AssertionError("cross-origin websocket accepted")


class TestTokenServer(ServerCase):
    token = "correct-horse"

    @gen_test
    async def test_control_needs_the_token(self):
        ws, hello = await self.connect()
        assert hello["auth_required"] and not hello["authed"]
        ws.write_message(json.dumps({"type": "drive", "vx": 1, "vy": 0, "wz": 0}))
        err = json.loads(await ws.read_message())
        assert "not authenticated" in err["message"]
        ws.write_message(json.dumps({"type": "auth", "token": "wrong-horse"}))
        assert "wrong control token" in json.loads(await ws.read_message())["message"]
        assert self.backend.calls == []  # nothing reached the robot
        ws.write_message(json.dumps({"type": "auth", "token": "correct-horse"}))
        assert json.loads(await ws.read_message()) == {"type": "auth", "authed": True}
        ws.write_message(json.dumps({"type": "drive", "vx": 1, "vy": 0, "wz": 0}))
        await self.until(lambda: self.backend.calls)
        assert self.backend.calls[0][0] == "drive"

    @gen_test
    async def test_guessing_closes_the_connection(self):
        ws, _ = await self.connect()
        for _ in range(MAX_AUTH_FAILURES):
            ws.write_message(json.dumps({"type": "auth", "token": "guess-guess"}))
        messages = []
        while True:
            m = await ws.read_message()
            if m is None:
                break
            messages.append(json.loads(m))
        assert len(messages) == MAX_AUTH_FAILURES
        assert ws.close_code == 4001
