"""The HTTP + websocket server (tornado), independent of ROS: it talks to a backend object.

Backend interface (the ROS node implements it; tests use a fake):
    info() -> dict            static facts for the page (holonomic, scales, timeouts, mode)
    drive(client, Drive)      -> None, or a reason the command was refused
    release(client)           the client let go / disconnected / sent bad input: stop if it drove
    set_mode(mode)            "manual" | "autonomous"
    send_goal(Goal)           -> None, or a reason the goal was refused
    cancel_goal()
    map_message() -> (version, dict) or None
    state() -> dict           live view snapshot (pose, trail, scan, path, modules, battery, ...)
All backend methods are called on the tornado IOLoop thread.

Every request must name the server by one of its own names (Host, and Origin for the
websocket), else it gets a 403: the DNS-rebinding defence of hosts.py.
"""
import itertools
import json
import logging
import os
from urllib.parse import urlsplit

import tornado.ioloop
import tornado.netutil
import tornado.web
import tornado.websocket
from tornado.httpserver import HTTPServer

from . import hosts, protocol
from .auth import token_matches

MAX_AUTH_FAILURES = 3
# Log the first few rejections of a connection, then one in LOG_EVERY, so a broken client
# cannot flood the log.
LOG_FIRST, LOG_EVERY = 5, 100

_log = logging.getLogger("mybot_web")


class _HostCheck:
    """First base of every handler: the Host check runs before any handler method."""

    def prepare(self):
        self.check_host()

    def check_host(self):
        """True, or False after answering 403, when Host is not one of the server's names."""
        # The header itself: request.host is "127.0.0.1" when the header is missing.
        value = self.request.headers.get("Host")
        return self.application.settings["web"].admit(self, "Host", value,
                                                      hosts.host_name(value))


class _NotFound(_HostCheck, tornado.web.RequestHandler):
    def prepare(self):
        if self.check_host():
            raise tornado.web.HTTPError(404)


class _Page(_HostCheck, tornado.web.RequestHandler):
    def initialize(self, path):
        self.path = path

    def set_default_headers(self):
        _security_headers(self)

    def get(self):
        self.set_header("Content-Type", "text/html; charset=utf-8")
        self.set_header("Cache-Control", "no-store")
        with open(self.path, "rb") as f:
            self.write(f.read())


class _Static(_HostCheck, tornado.web.StaticFileHandler):
    def set_default_headers(self):
        _security_headers(self)


def _security_headers(handler):
    # Nothing is fetched from anywhere but this server; no inline script.
    handler.set_header("Content-Security-Policy",
                       "default-src 'self'; img-src 'self' data:; connect-src 'self'; "
                       "frame-ancestors 'none'")
    handler.set_header("X-Content-Type-Options", "nosniff")
    handler.set_header("Referrer-Policy", "no-referrer")


def _origin_host(origin):
    try:
        return hosts.host_name(urlsplit(origin).netloc)
    except ValueError:  # e.g. an unclosed "[" in the address
        return None


class _Socket(_HostCheck, tornado.websocket.WebSocketHandler):
    def initialize(self, web):
        self.web = web

    def prepare(self):
        if not self.check_host():
            return
        headers = self.request.headers
        # The header names of tornado's own origin check (the older protocol's in the fallback).
        origin = headers.get("Origin", headers.get("Sec-Websocket-Origin"))
        # No Origin: not a browser, so no page that could have been rebound.
        if origin is not None:
            self.web.admit(self, "Origin", origin, _origin_host(origin))

    # tornado's default check_origin then refuses cross-site pages (a page elsewhere cannot
    # drive the robot through a visitor's browser), addresses included; keep it.

    def open(self):
        self.client = next(self.web.ids)
        self.authed = self.web.token is None
        self.auth_failures = 0
        self.rejected = 0
        self.map_version = None
        self.pending = None
        self.web.clients.add(self)
        info = dict(self.web.backend.info())
        info.update(type="hello", client=self.client, auth_required=self.web.token is not None,
                    authed=self.authed)
        self.send(info)
        self.web.push_map(self)
        self.web.log.info("web client %d connected from %s", self.client, self.request.remote_ip)

    def on_message(self, raw):
        try:
            msg = protocol.parse_message(raw)
        except protocol.ProtocolError as e:
            self.reject("rejected message: %s" % e)
            # The robot never keeps moving on bad input from the client that drives it.
            self.web.backend.release(self.client)
            return
        if isinstance(msg, protocol.Auth):
            self.authenticate(msg.token)
            return
        if not self.authed:
            self.reject("rejected %s: not authenticated (send the control token first)"
                        % type(msg).__name__.lower())
            return
        backend = self.web.backend
        error = None
        if isinstance(msg, protocol.Drive):
            error = backend.drive(self.client, msg)
        elif isinstance(msg, protocol.Stop):
            backend.release(self.client)
        elif isinstance(msg, protocol.Mode):
            backend.set_mode(msg.mode)
            self.web.log.info("web client %d: mode %s", self.client, msg.mode)
        elif isinstance(msg, protocol.Goal):
            error = backend.send_goal(msg)
            if error is None:
                self.web.log.info("web client %d: goal x=%.2f y=%.2f yaw=%.2f",
                                  self.client, msg.x, msg.y, msg.yaw)
        elif isinstance(msg, protocol.Cancel):
            backend.cancel_goal()
            self.web.log.info("web client %d: goal cancelled", self.client)
        if error:
            self.reject(error)

    def authenticate(self, token):
        if self.web.token is None or token_matches(self.web.token, token):
            self.authed = True
            self.send({"type": "auth", "authed": True})
            return
        self.auth_failures += 1
        self.reject("rejected auth: wrong control token")
        if self.auth_failures >= MAX_AUTH_FAILURES:
            self.close(code=4001, reason="too many wrong tokens")

    def reject(self, reason):
        self.rejected += 1
        if self.rejected <= LOG_FIRST or self.rejected % LOG_EVERY == 0:
            self.web.log.warning("web client %d (%s): %s [%d rejected]", self.client,
                                 self.request.remote_ip, reason, self.rejected)
        self.send({"type": "error", "message": reason})

    def on_close(self):
        self.web.clients.discard(self)
        self.web.backend.release(self.client)
        self.web.log.info("web client %d disconnected", self.client)

    def send(self, obj, droppable=False):
        """Queue one JSON message; a droppable one (a live view frame) is skipped while the
        previous one is still being written, so a slow client never builds a backlog."""
        if droppable and self.pending is not None and not self.pending.done():
            return
        try:
            self.pending = self.write_message(json.dumps(obj, separators=(",", ":")))
        except tornado.websocket.WebSocketClosedError:
            pass


class WebServer:
    """allowed_hosts: the server's names besides addresses, as from hosts.allowed_names()."""

    def __init__(self, backend, www_dir, token=None, view_rate=10.0, log=_log,
                 allowed_hosts=hosts.LOOPBACK_NAMES):
        self.backend = backend
        self.token = token
        self.view_rate = view_rate
        self.log = log
        self.allowed_hosts = frozenset(allowed_hosts)
        self.refused = 0
        self.clients = set()
        self.ids = itertools.count(1)
        self.app = tornado.web.Application([
            (r"/", _Page, {"path": os.path.join(www_dir, "index.html")}),
            (r"/ws", _Socket, {"web": self}),
            (r"/static/(.*)", _Static, {"path": www_dir}),
        ], default_handler_class=_NotFound, web=self,
            websocket_max_message_size=protocol.MAX_MESSAGE_BYTES,
            websocket_ping_interval=2.0, websocket_ping_timeout=4.0)
        self._http = None
        self._ticker = None

    def admit(self, handler, header, value, name):
        """True when name (from the header's value) is one of this server's; else answers 403
        saying what to set, logs (throttled as reject()) and returns False."""
        if hosts.is_allowed(name, self.allowed_hosts):
            return True
        shown = ascii(value[:100]) if value is not None else "(none)"
        if name is None:
            reason = "%s %s is missing or malformed" % (header, shown)
        else:
            reason = ("%s %s is not a name of this server; if it is one, add %s to the "
                      "web_controller parameter ~allowed_hosts" % (header, shown, name))
        self.refused += 1
        if self.refused <= LOG_FIRST or self.refused % LOG_EVERY == 0:
            self.log.warning("web: refused %s from %s: %s [%d refused]",
                             handler.request.path[:100], handler.request.remote_ip, reason,
                             self.refused)
        handler.set_status(403)
        handler.set_header("Content-Type", "text/plain; charset=utf-8")
        handler.finish(reason + "\n")
        return False

    def listen(self, host, port):
        """Bind (port 0 = any free port) and return the bound port. Raises OSError."""
        sockets = tornado.netutil.bind_sockets(port, address=host)
        self._http = HTTPServer(self.app)
        self._http.add_sockets(sockets)
        if self.view_rate > 0:
            self._ticker = tornado.ioloop.PeriodicCallback(self.broadcast, 1000.0 / self.view_rate)
            self._ticker.start()
        return sockets[0].getsockname()[1]

    def stop(self):
        if self._ticker:
            self._ticker.stop()
        if self._http:
            self._http.stop()
        for c in list(self.clients):
            c.close()

    def push_map(self, client):
        current = self.backend.map_message()
        if current is None or current[0] == client.map_version:
            return
        client.map_version = current[0]
        client.send(current[1])

    def broadcast(self):
        if not self.clients:
            return
        state = self.backend.state()
        state["type"] = "state"
        for c in list(self.clients):
            self.push_map(c)
            c.send(state, droppable=True)
