import json
import math

import pytest

from mybot_web import protocol
from mybot_web.protocol import Drive, Goal, Mode, ProtocolError, parse_message


def msg(**fields):
    return json.dumps(fields)


def test_valid_messages_parse():
    assert parse_message(msg(type="drive", vx=0.5, vy=0, wz=-1)) == Drive(0.5, 0.0, -1.0)
    assert parse_message(msg(type="stop")) == protocol.Stop()
    assert parse_message(msg(type="mode", mode="manual")) == Mode("manual")
    assert parse_message(msg(type="goal", x=1.5, y=-2, yaw=3.0)) == Goal(1.5, -2.0, 3.0)
    assert parse_message(msg(type="cancel")) == protocol.Cancel()
    assert parse_message(msg(type="auth", token="abc")).token == "abc"


@pytest.mark.parametrize("raw, field", [
    (msg(type="drive", vx=1.01, vy=0, wz=0), "drive.vx"),           # out of range: rejected
    (msg(type="drive", vx=0, vy=-7, wz=0), "drive.vy"),
    ('{"type": "drive", "vx": 0, "vy": 0, "wz": 1e400}', "drive.wz must be finite"),
    ('{"type": "drive", "vx": NaN, "vy": 0, "wz": 0}', "NaN"),      # non-standard JSON
    ('{"type": "drive", "vx": Infinity, "vy": 0, "wz": 0}', "Infinity"),
    (msg(type="drive", vx=True, vy=0, wz=0), "drive.vx must be a number"),
    (msg(type="drive", vx="0.5", vy=0, wz=0), "drive.vx must be a number"),
    (msg(type="drive", vx=0.1, vy=0), "drive.wz is missing"),
    (msg(type="drive", vx=0, vy=0, wz=0, boost=1), "unknown field"),
    (msg(type="mode", mode="turbo"), "mode.mode"),
    (msg(type="goal", x=0, y=1e9, yaw=0), "goal.y"),
    (msg(type="goal", x=0, y=0, yaw=7), "goal.yaw"),
    (msg(type="auth", token=5), "auth.token must be a string"),
    (msg(type="auth", token="x" * 300), "auth.token is longer"),
    (msg(type="fly"), "type must be one of"),
    (msg(kind="drive"), "type must be one of"),
    ("[1, 2]", "JSON object"),
    ("{not json", "not valid JSON"),
    (b'{"type": "stop"}', "binary"),
    ('{"type": "stop", "pad": "' + "x" * 5000 + '"}', "longer than"),
    ("[" * 2000 + "]" * 2000, "nested deeper than"),             # RecursionError in json
    ('{"type": "stop", "pad": ' + "{\"a\": " * 9 + "1" + "}" * 9 + "}", "nested deeper than"),
    ('{"type": "auth", "token": "\\ud800"}', "auth.token is not valid Unicode"),
    ('{"type": "auth", "token": "ab\\udfffcd"}', "auth.token is not valid Unicode"),
])
def test_bad_messages_are_rejected_naming_the_problem(raw, field):
    with pytest.raises(ProtocolError) as e:
        parse_message(raw)
    assert field in str(e.value)


def test_range_edges_are_accepted():
    assert parse_message(msg(type="drive", vx=-1, vy=1, wz=1.0)) == Drive(-1.0, 1.0, 1.0)
    g = parse_message(msg(type="goal", x=0, y=0, yaw=-2 * math.pi))
    assert g.yaw == -2 * math.pi


def test_brackets_and_escapes_inside_strings_are_not_nesting():
    token = '[[[[[[\\"{{{{{{'
    assert parse_message('{"type": "auth", "token": "%s"}' % token).token == '[[[[[["{{{{{{'
    # A surrogate pair is one real character.
    assert parse_message('{"type": "auth", "token": "\\ud83d\\ude00"}').token == "\U0001f600"


def test_unknown_field_names_are_escaped_in_the_error():
    with pytest.raises(ProtocolError) as e:
        parse_message('{"type": "stop", "x\\ud800\\n": 1}')
    assert "'x\\ud800\\n'" in str(e.value)
    str(e.value).encode("utf-8")  # safe to log
