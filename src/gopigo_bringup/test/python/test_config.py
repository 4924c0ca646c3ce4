import pytest

from fakes import make_fake_gopigo, make_fake_gopigo3
from gopigo_bringup.backends import GoPiGo3Backend, GoPiGoBackend, SimBackend
from gopigo_bringup.config import ConfigError, HardwareError, create_backend, read_config


def cfg_from(d):
    return read_config(lambda name, default: d.get(name, default))


def importer_for(modules):
    def imp(name):
        if name not in modules:
            raise ImportError("No module named '%s'" % name)
        return modules[name]
    return imp


class Log:
    def __init__(self):
        self.lines = []

    def __call__(self, level, msg):
        self.lines.append((level, msg))


def test_defaults_are_valid():
    cfg = cfg_from({})
    assert cfg.cmd_timeout == 0.5 and cfg.left_joint == "left_wheel_hinge"
    assert cfg.motor_map.command(5.32) == 255


@pytest.mark.parametrize("d, word", [
    ({"rate": 0}, "~rate"),
    ({"cmd_timeout": -1.0}, "~cmd_timeout"),
    ({"backend": "gopigo4"}, "~backend"),
    ({"gopigo_on": "yes"}, "~gopigo_on"),
    ({"right_joint": "left_wheel_hinge"}, "~left_joint"),
    ({"motor_cmd_min": 300}, "motor_cmd_max"),
    ({"sim_encoder_ppr": 0}, "~sim_encoder_ppr"),
])
def test_bad_values_name_the_parameter(d, word):
    with pytest.raises(ConfigError, match=word):
        cfg_from(d)


def test_gopigo_off_is_simulated_with_log_line():
    log = Log()
    b = create_backend(cfg_from({"gopigo_on": False}), log, importer_for({}))
    assert isinstance(b, SimBackend)
    assert any("SIMULATED" in m for _, m in log.lines)


def test_missing_library_falls_back_with_warning():
    log = Log()
    b = create_backend(cfg_from({"gopigo_on": True, "backend": "gopigo3"}), log, importer_for({}))
    assert isinstance(b, SimBackend)
    assert any(level == "warn" and "gopigo3" in m and "SIMULATED" in m for level, m in log.lines)


def test_missing_library_with_require_hardware_is_an_error():
    with pytest.raises(ConfigError, match="require_hardware"):
        create_backend(cfg_from({"gopigo_on": True, "require_hardware": True}), Log(), importer_for({}))


def test_hardware_backends_selected():
    b3 = create_backend(cfg_from({"gopigo_on": True, "backend": "gopigo3"}), Log(),
                        importer_for({"gopigo3": make_fake_gopigo3()}))
    assert isinstance(b3, GoPiGo3Backend)
    b2 = create_backend(cfg_from({"gopigo_on": True, "backend": "gopigo"}), Log(),
                        importer_for({"gopigo": make_fake_gopigo()}))
    assert isinstance(b2, GoPiGoBackend)


def test_board_not_answering_is_a_hardware_error():
    mod = make_fake_gopigo3(board_error=IOError("No SPI response"))
    with pytest.raises(HardwareError, match="No SPI response"):
        create_backend(cfg_from({"gopigo_on": True}), Log(), importer_for({"gopigo3": mod}))
