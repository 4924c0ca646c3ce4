"""Which Host names the server answers to: the DNS-rebinding defence (no ROS, no tornado).

A page from another site cannot read this server's responses or open its websocket (the
browser's same-origin policy, tornado's origin check) - unless its name is made to resolve to
this machine ("DNS rebinding": evil.example first points to the attacker, then to 127.0.0.1).
The page and this server are then the same origin to the browser, and bound to loopback no
token is needed to drive. The browser still sends the attacker's name as Host (and as Origin),
so the server answers only names it knows to be its own.

An IP address as Host is always accepted: rebinding needs a name the attacker controls, and a
browser sends an address only when the address itself is in the URL. This keeps
http://<robot's LAN address>:8080/ working without a list of the machine's addresses.
"""
import ipaddress
import re

# Always accepted; ::1 also as Host "[::1]", which host_name() unwraps.
LOOPBACK_NAMES = ("localhost", "127.0.0.1", "::1")

_NAME = re.compile(r"[a-z0-9_]([a-z0-9_-]*[a-z0-9_])?(\.[a-z0-9_]([a-z0-9_-]*[a-z0-9_])?)*")
_PORT = re.compile(r"[0-9]*")


def _address(text):
    try:
        return ipaddress.ip_address(text)
    except ValueError:
        return None


def normal_name(text):
    """A bare host name or address ("Robot.LAN.", "[::1]", "::1"), lowercase, without brackets
    or the trailing dot of an absolute name; None when it is neither."""
    text = text.strip().lower()
    if text.startswith("[") and text.endswith("]"):
        address = _address(text[1:-1])
        return str(address) if address is not None and address.version == 6 else None
    if text.endswith("."):
        text = text[:-1]
    address = _address(text)
    if address is not None:
        return str(address)  # canonical: "0:0::1" is "::1"
    return text if _NAME.fullmatch(text) else None


def host_name(header):
    """The host of a Host header or of an Origin's authority ("localhost:8080", "[::1]:8080"),
    normalised as normal_name(); None when missing or malformed."""
    if not header:
        return None
    text = header.strip()
    if text.startswith("["):
        end = text.find("]")
        if end < 0:
            return None
        host, rest = text[:end + 1], text[end + 1:]
        if rest and not (rest[0] == ":" and _PORT.fullmatch(rest[1:])):
            return None
    elif text.count(":") == 1:
        host, port = text.split(":")
        if not _PORT.fullmatch(port):
            return None
    else:
        # No port, or an IPv6 address without brackets (not valid in a Host header, but
        # unambiguous).
        host = text
    return normal_name(host)


def is_wildcard(bind_host):
    address = _address(bind_host)
    return address is not None and address.is_unspecified


def allowed_names(bind_host, extra=(), machine_names=()):
    """The host names accepted besides addresses: the loopback names, the names in extra
    (~allowed_hosts) and the bind address ~host or, bound to all interfaces (0.0.0.0 or ::),
    the machine's own names (hostname, fqdn) that a page on the network would be opened with."""
    names = list(LOOPBACK_NAMES) + list(extra)
    names += machine_names if is_wildcard(bind_host) else [bind_host]
    return frozenset(n for n in map(normal_name, names) if n)


def is_allowed(name, allowed):
    """name: from host_name() (None = missing or malformed, never allowed)."""
    return name is not None and (name in allowed or _address(name) is not None)
