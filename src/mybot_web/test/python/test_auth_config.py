import pytest

from mybot_web import config
from mybot_web.auth import ConfigError, is_loopback, resolve_token, token_matches


@pytest.mark.parametrize("host, loop", [
    ("127.0.0.1", True), ("127.3.2.1", True), ("::1", True), ("localhost", True),
    ("0.0.0.0", False), ("::", False), ("192.168.1.7", False), ("robot.local", False),
])
def test_loopback(host, loop):
    assert is_loopback(host) == loop


def test_no_token_needed_on_loopback():
    assert resolve_token("127.0.0.1", "") == (None, False)


def test_token_generated_on_a_public_address():
    token, generated = resolve_token("0.0.0.0", "")
    assert generated and len(token) >= 16
    assert resolve_token("0.0.0.0", "")[0] != token  # random each start


def test_given_token_is_used_everywhere():
    assert resolve_token("127.0.0.1", "s3cret-token") == ("s3cret-token", False)
    assert resolve_token("0.0.0.0", "s3cret-token") == ("s3cret-token", False)


@pytest.mark.parametrize("bad", ["short", " padded-token ", "tab\tinside-token", 1234])
def test_bad_tokens_are_configuration_errors(bad):
    with pytest.raises(ConfigError) as e:
        resolve_token("0.0.0.0", bad)
    assert "~token" in str(e.value)


def test_token_matches():
    assert token_matches("abcdefgh", "abcdefgh")
    assert not token_matches("abcdefgh", "abcdefgX")
    assert not token_matches("abcdefgh", "")
    assert not token_matches("abcdefgh", "\ud800")  # a lone surrogate: no match, no error


def test_config_defaults():
    cfg = config.load(lambda name, default: default)
    assert cfg.host == "127.0.0.1" and cfg.port == 8080
    assert cfg.deadman_timeout == 0.3 and cfg.scale_linear == 0.5 and cfg.scale_angular == 1.0
    assert cfg.swerve_modules == [] and cfg.allowed_hosts == []


@pytest.mark.parametrize("name, value, words", [
    ("port", 70000, "~port must be in [0, 65535]"),
    ("port", "80", "~port must be an integer"),
    ("deadman_timeout", 0, "~deadman_timeout must be in (0, 5]"),
    ("scale_linear", -1.0, "~scale_linear"),
    ("holonomic", "yes", "~holonomic must be true or false"),
    ("initial_mode", "auto", "~initial_mode must be one of manual, autonomous"),
    ("swerve_modules", ["a", "a"], "~swerve_modules has duplicates"),
    ("swerve_angle_topic", "swerve/angle", "{module}"),
    ("host", "", "~host must be a non-empty string"),
    ("allowed_hosts", "robot.lan", "~allowed_hosts must be a list of host names"),
    ("allowed_hosts", ["robot.lan", 7], "~allowed_hosts must be a list of host names"),
    ("allowed_hosts", [None], "~allowed_hosts must be a list of host names"),
    ("allowed_hosts", ["http://robot.lan"], "~allowed_hosts has 'http://robot.lan', not a host"),
    ("allowed_hosts", ["robot.lan:8080"], "~allowed_hosts has 'robot.lan:8080'"),
    ("allowed_hosts", [""], "~allowed_hosts has ''"),
])
def test_config_errors_name_the_parameter(name, value, words):
    with pytest.raises(ConfigError) as e:
        config.load(lambda n, default: value if n == name else default)
    assert words in str(e.value)


def test_config_accepts_int_for_float():
    cfg = config.load(lambda n, default: 1 if n == "scale_linear" else default)
    assert cfg.scale_linear == 1.0 and isinstance(cfg.scale_linear, float)


def test_config_accepts_host_names_and_addresses():
    hosts = ["robot.lan", "Cam.Example.", "10.0.0.2", "[fe80::1]", "fe80::2"]
    assert config.load(lambda n, default: hosts if n == "allowed_hosts" else default
                       ).allowed_hosts == hosts
