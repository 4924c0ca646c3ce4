"""The tornado server against a fake backend: real HTTP and websocket, no ROS."""
import json
import logging
import os

import tornado.httpclient
import tornado.tcpclient
import tornado.websocket
from tornado.testing import AsyncHTTPTestCase, gen_test

from mybot_web import hosts
from mybot_web.protocol import Drive, Goal
from mybot_web.server import LOG_FIRST, MAX_AUTH_FAILURES, WebServer

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
    allowed_hosts = hosts.LOOPBACK_NAMES

    def get_app(self):
        self.backend = FakeBackend()
        self.web = WebServer(self.backend, WWW, token=self.token, view_rate=0,
                             log=logging.getLogger("test"), allowed_hosts=self.allowed_hosts)
        return self.web.app

    async def connect(self, origin=None, host=None):
        url = "ws://127.0.0.1:%d/ws" % self.get_http_port()
        headers = {"Origin": origin} if origin else {}
        if host is not None:
            headers["Host"] = host
        ws = await tornado.websocket.websocket_connect(
            tornado.httpclient.HTTPRequest(url, headers=headers))
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
    async def test_deeply_nested_json_is_answered_and_the_socket_stays(self):
        # 2000 levels in 4000 bytes: json's recursive decoder used to raise RecursionError,
        # and tornado then dropped the connection.
        ws, hello = await self.connect()
        ws.write_message("[" * 2000 + "]" * 2000)
        err = json.loads(await ws.read_message())
        assert err["type"] == "error" and "nested deeper" in err["message"]
        ws.write_message(json.dumps({"type": "drive", "vx": 0.5, "vy": 0, "wz": 0}))
        await self.until(lambda: any(c[0] == "drive" for c in self.backend.calls))
        assert self.backend.calls[-1] == ("drive", hello["client"], Drive(0.5, 0.0, 0.0))

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

    @gen_test
    async def test_lone_surrogate_token_is_answered_and_the_socket_stays(self):
        # JSON may spell half a UTF-16 pair; it used to raise UnicodeEncodeError in the token
        # comparison, and tornado then dropped the connection.
        ws, _ = await self.connect()
        ws.write_message('{"type":"auth","token":"\\ud800"}')
        err = json.loads(await ws.read_message())
        assert err["type"] == "error" and "auth.token is not valid Unicode" in err["message"]
        ws.write_message(json.dumps({"type": "auth", "token": "correct-horse"}))
        assert json.loads(await ws.read_message()) == {"type": "auth", "authed": True}


def refused(response, words):
    body = response.body.decode()
    return (response.code == 403 and response.headers["Content-Type"].startswith("text/plain")
            and all(w in body for w in words))


class TestHostCheck(ServerCase):
    """DNS rebinding: a page whose own name resolves to this machine must not be answered."""

    def get(self, path, host):
        return self.fetch(path, headers={"Host": host})

    def test_loopback_names_and_addresses_are_served(self):
        port = self.get_http_port()
        for host in ("localhost:%d" % port, "LocalHost", "127.0.0.1", "127.0.0.1:%d" % port,
                     "[::1]:8080", "[::1]", "localhost.", "192.168.1.7:8080", "[fe80::1]:80"):
            assert self.get("/", host).code == 200, host
        assert self.get("/static/app.js", "localhost:%d" % port).code == 200

    def test_other_names_get_403_naming_the_host_and_the_parameter(self):
        for path in ("/", "/static/app.js", "/ws", "/no-such-page"):
            r = self.get(path, "evil.example:%d" % self.get_http_port())
            assert refused(r, ["evil.example", "~allowed_hosts"]), (path, r.code, r.body)
        for host in ("Evil.Example", "localhost.evil.example", "127.0.0.1.evil.example"):
            assert refused(self.get("/", host), [host.lower()]), host
        assert self.backend.calls == []

    def test_empty_and_malformed_hosts_get_403(self):
        for host in ("", "localhost:80:80", "[::1", "[::1]x", "localhost:http", "local host"):
            assert refused(self.get("/", host), ["Host", "malformed"]), host

    @gen_test
    async def test_missing_host_gets_403(self):
        # HTTP/1.0 allows it; tornado itself would take the request as 127.0.0.1.
        stream = await tornado.tcpclient.TCPClient().connect("127.0.0.1", self.get_http_port())
        await stream.write(b"GET / HTTP/1.0\r\n\r\n")
        reply = await stream.read_until_close()
        assert reply.startswith(b"HTTP/1.1 403") and b"Host (none) is missing" in reply

    def test_refusals_are_logged_throttled(self):
        with self.assertLogs("test", "WARNING") as logs:
            for _ in range(LOG_FIRST + 3):
                self.get("/", "evil.example")
        assert len(logs.records) == LOG_FIRST
        assert "Host 'evil.example'" in logs.output[0] and "[1 refused]" in logs.output[0]

    @gen_test
    async def test_websocket_from_the_page_or_without_origin_is_accepted(self):
        port = self.get_http_port()
        await self.connect(origin="http://127.0.0.1:%d" % port)
        await self.connect(origin="http://localhost:%d" % port, host="localhost:%d" % port)
        ws, _ = await self.connect()  # no Origin: not a browser
        ws.write_message(json.dumps({"type": "stop"}))
        await self.until(lambda: self.backend.calls)

    @gen_test
    async def test_websocket_from_another_origin_gets_403(self):
        port = self.get_http_port()
        for origin, host, words in [
            ("http://evil.example:%d" % port, None, ["Origin", "evil.example", "~allowed_hosts"]),
            ("null", None, ["Origin 'null' is missing or malformed"]),
            ("http://[::1", None, ["malformed"]),
            # The rebinding itself: the page and the socket both under the attacker's name.
            ("http://evil.example:%d" % port, "evil.example:%d" % port, ["Host", "evil.example"]),
            (None, "evil.example:%d" % port, ["Host", "evil.example"]),
        ]:
            try:
                await self.connect(origin=origin, host=host)
            except tornado.httpclient.HTTPClientError as e:
                assert refused(e.response, words), (origin, host, e.response.body)
            else:
                raise AssertionError("websocket accepted: Origin %s, Host %s" % (origin, host))
        assert self.web.clients == set()


class TestConfiguredNames(ServerCase):
    allowed_hosts = hosts.allowed_names("robot.lan", ["Cam.Example"])

    def test_bind_name_and_allowed_hosts_are_served(self):
        for host in ("robot.lan:8080", "ROBOT.LAN", "cam.example.", "localhost:8080"):
            assert self.fetch("/", headers={"Host": host}).code == 200, host
        assert self.fetch("/", headers={"Host": "other.lan"}).code == 403

    @gen_test
    async def test_websocket_under_a_configured_name(self):
        origin = "http://cam.example:%d" % self.get_http_port()
        ws, hello = await self.connect(origin=origin, host=origin[len("http://"):])
        assert hello["authed"]
