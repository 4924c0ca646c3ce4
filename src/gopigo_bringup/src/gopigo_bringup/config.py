"""Driver parameters: names, defaults, validation and backend creation (no ROS types).

``read_config(get)`` takes a getter ``get(name, default)`` (rospy.get_param on
the private namespace in the node, a dict in tests) and returns a validated
Config or raises ConfigError naming the parameter.
"""
import importlib
import math

from .backends import GoPiGo3Backend, GoPiGoBackend, SimBackend
from .motor_map import MotorMap, MotorMapError


class ConfigError(ValueError):
    """Bad configuration; the message names the parameter."""


class HardwareError(RuntimeError):
    """The hardware library is there but the board does not answer."""


def _finite(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


_pos = (lambda v: _finite(v) and v > 0, "a number > 0")
_nonneg = (lambda v: _finite(v) and v >= 0, "a number >= 0")
_posint = (lambda v: isinstance(v, int) and not isinstance(v, bool) and v > 0, "an integer > 0")
_int = (lambda v: isinstance(v, int) and not isinstance(v, bool), "an integer")
_bool = (lambda v: isinstance(v, bool), "true or false")
_name = (lambda v: isinstance(v, str) and v.strip() != "", "a non-empty string")
_number = (lambda v: _finite(v), "a finite number")

BACKENDS = ("gopigo3", "gopigo")

# name: (default, (check, description), doc)
PARAMS = {
    "gopigo_on": (False, _bool, "drive real hardware; false = simulated motors"),
    "backend": ("gopigo3", (lambda v: v in BACKENDS, "one of %s" % ", ".join(BACKENDS)),
                "hardware library when gopigo_on: gopigo3 (GoPiGo3) or gopigo (GoPiGo v1/v2)"),
    "require_hardware": (False, _bool, "exit instead of simulating when gopigo_on and the library is missing"),
    "rate": (20.0, _pos, "main loop: commands out, encoders in, joint_states (Hz)"),
    "cmd_timeout": (0.5, _pos, "stop the motors when a wheel command is older than this (s, ROS time)"),
    "wall_timeout": (1.0, _pos, "independent wall-clock stop if no command arrives (s); catches a stalled clock"),
    "master_check_period": (1.0, _nonneg, "how often to check the ROS master is reachable (s, 0 = never)"),
    "battery_rate": (1.0, _nonneg, "battery_voltage publish rate (Hz, 0 = never)"),
    "velocity_window": (0.2, _nonneg, "encoder speed: least-squares slope over this time (s)"),
    "left_joint": ("left_wheel_hinge", _name, "joint name of the left wheel"),
    "right_joint": ("right_wheel_hinge", _name, "joint name of the right wheel"),
    "publish_enc": (False, _bool, "also publish lwheel/rwheel_angular_vel_enc (Float32, rad/s)"),
    # tutorial motor map
    "motor_min_angular_vel": (1.28, _pos, "wheel speed at motor_cmd_min (rad/s)"),
    "motor_max_angular_vel": (5.32, _pos, "wheel speed at motor_cmd_max (rad/s)"),
    "motor_cmd_min": (110, _nonneg, "smallest command that turns the wheel"),
    "motor_cmd_max": (255, _pos, "largest motor command"),
    # GoPiGo v1/v2
    "encoder_ppr": (18, _posint, "GoPiGo v1/v2 encoder pulses per wheel revolution"),
    "board_timeout": (1.0, _nonneg, "GoPiGo v1/v2 on-board communication timeout (s, 0 = off)"),
    # GoPiGo3
    "gopigo3_max_dps": (1000.0, _pos, "GoPiGo3 speed clamp (wheel degrees/s)"),
    # simulated backend
    "sim_time_constant": (0.1, _nonneg, "simulated motor first-order time constant (s)"),
    "sim_left_gain": (1.0, _nonneg, "left motor strength (1 = as calibrated, 0.8 = 20% weaker)"),
    "sim_right_gain": (1.0, _nonneg, "right motor strength"),
    "sim_deadband": (-1.0, _number, "command below which the motor does not turn; < 0 = from the motor map"),
    "sim_rad_per_cmd": (-1.0, _number, "rad/s per command unit above the dead band; <= 0 = from the motor map"),
    "sim_encoder_ppr": (360, _posint, "simulated encoder counts per wheel revolution"),
    "sim_noise_std": (0.0, _nonneg, "simulated wheel speed noise (rad/s, 1 sigma)"),
    "sim_seed": (0, _int, "noise seed"),
    "sim_battery_voltage": (9.6, _pos, "battery_voltage reported by the simulated backend (V)"),
}


class Config(dict):
    __getattr__ = dict.__getitem__


def read_config(get):
    cfg = Config()
    for name, (default, (check, what), _doc) in PARAMS.items():
        value = get(name, default)
        if isinstance(default, float) and isinstance(value, int) and not isinstance(value, bool):
            value = float(value)
        if not check(value):
            raise ConfigError("parameter ~%s must be %s, got %r" % (name, what, value))
        cfg[name] = value
    if cfg.left_joint == cfg.right_joint:
        raise ConfigError("parameters ~left_joint and ~right_joint must differ (both %r)" % cfg.left_joint)
    try:
        cfg["motor_map"] = MotorMap(cfg.motor_min_angular_vel, cfg.motor_max_angular_vel,
                                    cfg.motor_cmd_min, cfg.motor_cmd_max)
    except MotorMapError as e:
        raise ConfigError("parameter ~%s" % e)
    return cfg


def make_sim_backend(cfg):
    return SimBackend.from_params(
        cfg.motor_map, time_constant=cfg.sim_time_constant, left_gain=cfg.sim_left_gain,
        right_gain=cfg.sim_right_gain, counts_per_rev=cfg.sim_encoder_ppr,
        noise_std=cfg.sim_noise_std, seed=cfg.sim_seed,
        deadband=None if cfg.sim_deadband < 0 else cfg.sim_deadband,
        rad_per_cmd=None if cfg.sim_rad_per_cmd <= 0 else cfg.sim_rad_per_cmd,
        battery_voltage=cfg.sim_battery_voltage)


def create_backend(cfg, log, importer=importlib.import_module):
    """The backend the configuration asks for. log(level, message)."""
    if not cfg.gopigo_on:
        log("info", "gopigo_on is false: using the SIMULATED motor backend (no hardware is driven)")
        return make_sim_backend(cfg)
    library = cfg.backend
    try:
        module = importer(library)
    except ImportError as e:
        if cfg.require_hardware:
            raise ConfigError("~gopigo_on and ~require_hardware are true but the '%s' library cannot be "
                              "imported (%s)" % (library, e))
        log("warn", "gopigo_on is true but the '%s' library cannot be imported (%s): using the SIMULATED "
                    "motor backend instead; NO HARDWARE IS DRIVEN" % (library, e))
        return make_sim_backend(cfg)
    if library == "gopigo3":
        try:
            board = module.GoPiGo3()
        except Exception as e:  # IOError, FirmwareVersionError, spidev errors
            raise HardwareError("GoPiGo3 board not usable: %s" % e)
        log("info", "GoPiGo3 backend (set_motor_dps / get_motor_encoder)")
        return GoPiGo3Backend(board, cfg.gopigo3_max_dps)
    log("info", "GoPiGo v1/v2 backend (motor1/motor2, enc_read, %d pulses/rev)" % cfg.encoder_ppr)
    return GoPiGoBackend(module, cfg.motor_map, cfg.encoder_ppr, cfg.board_timeout)
