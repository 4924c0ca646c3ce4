"""Keyboard teleoperation logic, matching teleop_twist_keyboard (pure: no ROS).

Key map, speed steps, printed help and status lines are those of
ros-teleop/teleop_twist_keyboard so users' muscle memory carries over.
"""

MSG = """
Reading from the keyboard  and Publishing to Twist!
---------------------------
Moving around:
   u    i    o
   j    k    l
   m    ,    .

For Holonomic mode (strafing), hold down the shift key:
---------------------------
   U    I    O
   J    K    L
   M    <    >

t : up (+z)
b : down (-z)

anything else : stop

q/z : increase/decrease max speeds by 10%
w/x : increase/decrease only linear speed by 10%
e/c : increase/decrease only angular speed by 10%

CTRL-C to quit
"""

# key -> (x, y, z, th) unit directions
MOVE_BINDINGS = {
    'i': (1, 0, 0, 0),
    'o': (1, 0, 0, -1),
    'j': (0, 0, 0, 1),
    'l': (0, 0, 0, -1),
    'u': (1, 0, 0, 1),
    ',': (-1, 0, 0, 0),
    '.': (-1, 0, 0, 1),
    'm': (-1, 0, 0, -1),
    'O': (1, -1, 0, 0),
    'I': (1, 0, 0, 0),
    'J': (0, 1, 0, 0),
    'L': (0, -1, 0, 0),
    'U': (1, 1, 0, 0),
    '<': (-1, 0, 0, 0),
    '>': (-1, -1, 0, 0),
    'M': (-1, 1, 0, 0),
    't': (0, 0, 1, 0),
    'b': (0, 0, -1, 0),
}

# key -> (linear factor, angular factor)
SPEED_BINDINGS = {
    'q': (1.1, 1.1),
    'z': (.9, .9),
    'w': (1.1, 1),
    'x': (.9, 1),
    'e': (1, 1.1),
    'c': (1, .9),
}

CTRL_C = '\x03'
TIMEOUT = ''  # what a key read returns when key_timeout expires


def vels(speed, turn):
    return "currently:\tspeed %s\tturn %s " % (speed, turn)


class KeyboardTeleop:
    """State machine of teleop_twist_keyboard's main loop.

    handle_key() returns (publish, lines): whether the twist changed and must be
    sent, and the lines to print. `done` turns true on Ctrl-C.
    """

    def __init__(self, speed=0.5, turn=1.0, speed_limit=1000.0, turn_limit=1000.0):
        self.speed = speed
        self.turn = turn
        self.speed_limit = speed_limit
        self.turn_limit = turn_limit
        self.x = self.y = self.z = self.th = 0
        self.status = 0
        self.done = False

    def moving(self):
        return any((self.x, self.y, self.z, self.th))

    def handle_key(self, key):
        lines = []
        if key in MOVE_BINDINGS:
            self.x, self.y, self.z, self.th = MOVE_BINDINGS[key]
        elif key in SPEED_BINDINGS:
            fs, ft = SPEED_BINDINGS[key]
            self.speed = min(self.speed_limit, self.speed * fs)
            self.turn = min(self.turn_limit, self.turn * ft)
            if self.speed == self.speed_limit:
                lines.append("Linear speed limit reached!")
            if self.turn == self.turn_limit:
                lines.append("Angular speed limit reached!")
            lines.append(vels(self.speed, self.turn))
            if self.status == 14:
                lines.append(MSG)
            self.status = (self.status + 1) % 15
        else:
            # A timeout while already stopped changes nothing (upstream skips it).
            if key == TIMEOUT and not self.moving():
                return False, lines
            self.x = self.y = self.z = self.th = 0
            if key == CTRL_C:
                self.done = True
        return True, lines

    def twist(self):
        """(linear x, y, z, angular z) of the current command."""
        return (self.x * self.speed, self.y * self.speed, self.z * self.speed, self.th * self.turn)
