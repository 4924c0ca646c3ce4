import pytest

from mybot_web.hosts import allowed_names, host_name, is_allowed, normal_name


@pytest.mark.parametrize("header, name", [
    ("localhost:8080", "localhost"), ("LocalHost", "localhost"), ("127.0.0.1", "127.0.0.1"),
    ("[::1]:8080", "::1"), ("[::1]", "::1"), ("::1", "::1"), ("[0:0::1]", "::1"),
    ("robot.lan.:80", "robot.lan"), ("localhost:", "localhost"), (" evil.example ", "evil.example"),
    (None, None), ("", None), ("[::1", None), ("[::1]x", None), ("[::1]:x", None),
    ("[127.0.0.1]", None), ("a:b:c", None), ("localhost:80:80", None), ("local host", None),
    ("évil.example", None), ("http://robot.lan", None),
])
def test_host_header_parsing(header, name):
    assert host_name(header) == name


def test_loopback_bind_accepts_only_loopback_names_and_its_own():
    allowed = allowed_names("127.0.0.1", [], ["robot", "robot.lan"])
    assert allowed == {"localhost", "127.0.0.1", "::1"}  # machine names: not on loopback
    assert allowed_names("robot.lan", ["Cam.Example."]) >= {"robot.lan", "cam.example"}


@pytest.mark.parametrize("bind", ["0.0.0.0", "::"])
def test_wildcard_bind_adds_the_machine_names(bind):
    allowed = allowed_names(bind, [], ["Robot", "robot.lan"])
    assert {"robot", "robot.lan", "localhost"} <= allowed


def test_addresses_are_always_allowed_names_only_when_listed():
    allowed = allowed_names("127.0.0.1")
    for header in ("10.1.2.3:8080", "[fe80::1]", "localhost:1"):
        assert is_allowed(host_name(header), allowed), header
    for header in ("evil.example", "robot.lan", "", "localhost.evil.example", None):
        assert not is_allowed(host_name(header), allowed), header


@pytest.mark.parametrize("entry", ["", "robot:8080", "http://robot", "robot/x", "two names"])
def test_entries_that_are_not_names(entry):
    assert normal_name(entry) is None
