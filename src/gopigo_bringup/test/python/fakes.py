"""Fakes of the GoPiGo hardware libraries, with the real libraries' API and number formats."""
import types


def make_fake_gopigo():
    """A stand-in for the v1/v2 ``gopigo`` module: records calls, 16-bit unsigned counters."""
    m = types.ModuleType("gopigo")
    m.calls = []
    m.raw = [0, 0]          # enc_read(0), enc_read(1)
    m.voltage = 9.1
    m.fail_reads = False

    def motor1(direction, speed):
        assert direction in (0, 1) and 0 <= speed <= 255 and isinstance(speed, int)
        m.calls.append(("motor1", direction, speed))
        return 1

    def motor2(direction, speed):
        assert direction in (0, 1) and 0 <= speed <= 255 and isinstance(speed, int)
        m.calls.append(("motor2", direction, speed))
        return 1

    def enc_read(motor):
        assert motor in (0, 1)
        return -1 if m.fail_reads else m.raw[motor] % 65536

    def volt():
        return m.voltage

    def stop():
        m.calls.append(("stop",))

    def enable_com_timeout(ms):
        m.calls.append(("enable_com_timeout", ms))

    m.motor1, m.motor2, m.enc_read, m.volt, m.stop = motor1, motor2, enc_read, volt, stop
    m.enable_com_timeout = enable_com_timeout
    return m


class FakeGoPiGo3:
    """Mirrors gopigo3.GoPiGo3: ports are bit masks, encoders are signed 32-bit tick counters."""
    MOTOR_LEFT = 0x01
    MOTOR_RIGHT = 0x02
    MOTOR_FLOAT = -128
    MOTOR_TICKS_PER_DEGREE = (120.0 * 16.0) / 360.0

    def __init__(self):
        self.dps = {self.MOTOR_LEFT: 0, self.MOTOR_RIGHT: 0}
        self.power = {}
        self.ticks = {self.MOTOR_LEFT: 0, self.MOTOR_RIGHT: 0}
        self.calls = []

    def set_motor_dps(self, port, dps):
        self.calls.append(("set_motor_dps", port, dps))
        for p in (self.MOTOR_LEFT, self.MOTOR_RIGHT):
            if port & p:
                self.dps[p] = int(dps)

    def set_motor_power(self, port, power):
        self.calls.append(("set_motor_power", port, power))
        for p in (self.MOTOR_LEFT, self.MOTOR_RIGHT):
            if port & p:
                self.power[p] = power

    def set_ticks(self, port, ticks):
        # store as the board does: 32-bit two's complement
        self.ticks[port] = ((ticks + 2 ** 31) % 2 ** 32) - 2 ** 31

    def get_motor_encoder(self, port):
        if port not in (self.MOTOR_LEFT, self.MOTOR_RIGHT):
            raise IOError("Port(s) unsupported. Must be one at a time.")
        return int(self.ticks[port] / self.MOTOR_TICKS_PER_DEGREE)

    def get_voltage_battery(self):
        return 11.1


def make_fake_gopigo3(board_error=None):
    m = types.ModuleType("gopigo3")

    def factory():
        if board_error is not None:
            raise board_error
        m.board = FakeGoPiGo3()
        return m.board

    m.GoPiGo3 = factory
    return m
