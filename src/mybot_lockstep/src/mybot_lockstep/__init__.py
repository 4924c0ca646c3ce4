"""Makes a rospy node a lockstep participant (the Python twin of participant.h).

    ls = mybot_lockstep.Participant()
    ls.Subscriber('ground_truth/odom', Odometry, cb)      # counted input
    pub = ls.Publisher('cmd_vel', Twist)                    # synchronous under lockstep
    rate = ls.Rate(50)
    while not rospy.is_shutdown():
        pub.publish(...)
        rate.sleep()                                        # the period is done: time may advance

The simulator does not start period k+1 until this node has handled every message sent to it
on its counted subscriptions, run its timers (ls.Timer), and, if its main thread was woken for
period k, until that thread sleeps again through ls.sleep / ls.Rate / ls.wait_for (as Webots'
robot_step). A main thread that has not slept through the helper yet, or has called release(),
does not hold the simulation.

Lockstep is on when /use_sim_time and /lockstep are both true; otherwise every call is the
plain rospy one, so the same code runs against a real robot.
"""
import threading
import time
import warnings
from xmlrpc.client import ServerProxy

import rospy
from rospy.impl.registration import get_topic_manager

from tf2_msgs.msg import TFMessage

from mybot_lockstep.msg import Ack, LinkCount, Tick
from mybot_lockstep.time_jump import TimeJump

__all__ = ['Participant', 'participant', 'lockstep_requested', 'TransformListener', 'wait_connected',
           'publisher_has_link']


def lockstep_requested():
    return bool(rospy.get_param('/use_sim_time', False)) and bool(rospy.get_param('/lockstep', False))


def publisher_has_link(publisher_uri, topic, subscriber):
    """Whether the node at `publisher_uri` (its XML-RPC URI) has a live connection carrying `topic`
    to the node named `subscriber`, by its own account (getBusInfo). A rospy subscriber counts its
    connection once it has read the publisher's header, and a rospy publisher adds the connection
    to its topic only after writing that header: a message published in between is lost to that
    subscriber (a Joy of test_teleop_joy, 5 ms apart, 2026-11-30). Once the publisher has added
    it, what it publishes waits in the socket until the subscriber reads it."""
    try:
        code, _, info = ServerProxy(publisher_uri).getBusInfo(rospy.get_name())
    except Exception:  # not serving yet, or gone
        return False
    return code == 1 and any(c[1] == subscriber and c[2] == 'o' and c[4] == topic and c[5] for c in info)


def _connected(link):
    """A Publisher: a subscriber is connected. A Subscriber: a publisher has added the link too."""
    if not isinstance(link, rospy.Subscriber):
        return link.get_num_connections() > 0
    impl = link.impl
    me = rospy.get_name()
    return impl is not None and any(
        publisher_has_link(c.endpoint_id, link.resolved_name, me) for c in list(impl.connections))


def wait_connected(links, timeout=60.0):
    """Waits, in wall time (a connection is made in wall time, whatever the sim time), until every
    rospy Publisher or Subscriber of `links` has a connection, a Subscriber's as its publisher
    counts it (publisher_has_link): a message sent before its connection is open is lost. Raises
    RuntimeError naming the unconnected topics after `timeout` s."""
    deadline = time.monotonic() + timeout
    while not rospy.is_shutdown():
        missing = [link.resolved_name for link in links if not _connected(link)]
        if not missing:
            return
        if time.monotonic() > deadline:
            raise RuntimeError('no connection within %.0f s on %s' % (timeout, missing))
        time.sleep(0.05)


def _sent_links(me):
    """Per outgoing connection of this process: messages written (or queued) so far."""
    out = []
    tm = get_topic_manager()
    for topic, impl in list(tm.pubs.items()):
        for c in list(impl.connections):
            n = c.stat_num_msg + len(getattr(c, '_queue', ()))
            out.append(LinkCount(topic=topic, source=me, destination=c.endpoint_id, count=n))
    return out


class _Rate:
    def __init__(self, ls, hz):
        self._ls = ls
        self._period = rospy.Duration(1.0 / hz)
        self._last = None

    def sleep(self):
        now = rospy.get_rostime()
        if self._last is None or now < self._last or now - self._last > self._period * 2:
            self._last = now
        self._last = self._last + self._period
        self._ls.sleep_until(self._last)


class Participant:
    def __init__(self, forgive_after=2.0, defer_join=False):
        self.active = lockstep_requested()
        # Whether the next tick may make this node a participant (see participant()).
        self._joinable = not defer_join
        self._me = rospy.get_name()
        self._cond = threading.Condition()
        self._handled = {}  # (topic, source) -> messages received
        self._inbox = {}  # (topic, source) -> [(callback, msg)] waiting for their period
        self._taken = {}  # (topic, source) -> messages handed to their callback
        self._forgiven = {}  # (topic, source) -> messages given up as lost
        self._counted = {}  # topic -> subscriptions to it
        self._timers = []  # [period_ns, next_ns, callback]
        self._wake = None  # rospy.Time the main thread sleeps until
        self._held = None  # the tick the main thread was woken for and has not finished
        self._holding_next = False  # the main thread sleeps in hold_next_period()
        self._last_ack = None
        self._last_stamp = None  # the last tick's stamp
        self._forgive_after = forgive_after
        if not self.active:
            return
        # Synchronous (no queue): written to the simulator's connection in the acknowledging
        # thread, not handed to a writer thread of rospy's, a thread switch less per period.
        with warnings.catch_warnings():
            warnings.simplefilter('ignore')
            self._ack_pub = rospy.Publisher('/lockstep/ack', Ack, queue_size=None, tcp_nodelay=True)
        rospy.Subscriber('/lockstep/tick', Tick, self._on_tick, queue_size=100, tcp_nodelay=True)
        rospy.loginfo('lockstep: %s takes part (simulated time waits for it)', self._me)

    # --- inputs and outputs -----------------------------------------------------------------
    def Subscriber(self, topic, data_class, callback, queue_size=None, **kw):
        """rospy.Subscriber through lockstep: under lockstep the message is handed to `callback`
        when its period is processed (in the tick's thread, ordered by topic, then publisher,
        then arrival), once everything owed to this node for the period is in."""
        if not self.active:
            return rospy.Subscriber(topic, data_class, callback, queue_size=queue_size, **kw)
        if 'callback_args' in kw:  # rospy's: handed to the callback after the message
            args = kw.pop('callback_args')
            callback = (lambda msg, cb=callback: cb(msg, args))
        resolved = rospy.resolve_name(topic)
        with self._cond:  # two subscriptions to a topic each receive every message
            self._counted[resolved] = self._counted.get(resolved, 0) + 1

        def arrived(msg):
            source = msg._connection_header.get('callerid', '') if hasattr(msg, '_connection_header') else ''
            with self._cond:
                key = (resolved, source)
                self._inbox.setdefault(key, []).append((callback, msg))
                self._handled[key] = self._handled.get(key, 0) + 1
                self._cond.notify_all()

        return rospy.Subscriber(topic, data_class, arrived, queue_size=queue_size, **kw)

    def Publisher(self, topic, data_class, queue_size=10, **kw):
        """rospy.Publisher; synchronous under lockstep, so its counts are exact at each Ack."""
        if not self.active:
            return rospy.Publisher(topic, data_class, queue_size=queue_size, **kw)
        with warnings.catch_warnings():
            warnings.simplefilter('ignore')
            return rospy.Publisher(topic, data_class, queue_size=None, **kw)

    def Timer(self, period, callback):
        """A periodic callback at the whole multiples of `period` (rospy.Duration or seconds)."""
        if not self.active:
            return rospy.Timer(period if isinstance(period, rospy.Duration) else rospy.Duration(period), callback)
        p = (period if isinstance(period, rospy.Duration) else rospy.Duration(period)).to_nsec()
        now = rospy.get_rostime().to_nsec()
        with self._cond:
            self._timers.append([p, (now // p + 1) * p, callback])

    # --- the main thread --------------------------------------------------------------------
    def Rate(self, hz):
        return _Rate(self, hz) if self.active else rospy.Rate(hz)

    def sleep(self, duration):
        if not self.active:
            rospy.sleep(duration)
            return
        d = duration if isinstance(duration, rospy.Duration) else rospy.Duration(duration)
        self.sleep_until(rospy.get_rostime() + d)

    def sleep_until(self, t, then=None):
        """Finishes the current period (if the main thread held one) and waits for sim time t.
        Returns at once when the clock jumps back (a reset), where rospy.sleep would raise.
        `then`, if given, is called once the wake-up is registered, before waiting: a call that
        lets time move on (unpause_physics) made there cannot let the period pass unseen."""
        if not self.active:
            if then is not None:
                then()
            rospy.sleep(max(0.0, (t - rospy.get_rostime()).to_sec()))
            return
        with self._cond:
            self._joinable = True
            self._wake = t
            self._finish_held()
        if then is not None:
            try:
                then()
            except BaseException:
                with self._cond:  # not sleeping after all: wake for nothing, hold no period
                    self._wake = None
                    self._finish_held()
                raise
        with self._cond:
            while self._wake is not None and not rospy.is_shutdown():
                self._cond.wait(0.1)
        if rospy.is_shutdown():
            raise rospy.ROSInterruptException('shutdown')

    def hold_next_period(self, then=None):
        """Waits for the next period's start and holds it: what the main thread does next (a
        profile's first command, its start time) belongs to a period, as everything after its
        later sleeps does; time read between periods lies anywhere inside one. A node that does
        not take part yet joins, and holds the period after the one it joined in: by then the
        simulator has opened its connections (it holds time on a join until they are), and which
        period that is does not depend on whether the node's /clock or its first tick came
        first. `then` as in sleep_until. Off lockstep: calls `then` and returns."""
        if not self.active:
            if then is not None:
                then()
            return
        with self._cond:
            self._holding_next = True
        try:
            self.sleep_until(rospy.get_rostime() + rospy.Duration(0, 1), then=then)
        finally:
            with self._cond:
                self._holding_next = False

    def wait_for(self, predicate, timeout, period=0.02):
        """Sleeps in steps of `period` of sim time until predicate() or `timeout` s of sim time."""
        end = rospy.get_rostime() + rospy.Duration(timeout)
        while not predicate():
            if rospy.get_rostime() > end:
                return False
            self.sleep(period)
        return True

    def release(self):
        """The main thread stops holding the simulation (before a blocking call of its own)."""
        if not self.active:
            return
        with self._cond:
            self._joinable = True
            self._finish_held()

    def _finish_held(self):
        """Acknowledges the period the main thread held, if any (called with self._cond held)."""
        if self._held is not None:
            held, self._held = self._held, None
            self._ack(held)

    # --- the tick thread --------------------------------------------------------------------
    def _unmet(self, expected):
        for l in expected:
            if self._handled.get((l.topic, l.source), 0) < l.count:
                return l
        return None

    def _on_tick(self, tick):
        with self._cond:
            if self._last_ack is None and not self._joinable:
                return  # set-up not done yet: not a participant
            joining = self._last_ack is None and self._held is None
            last = self._last_ack.seq if self._last_ack is not None else 0
            if (self._held is not None and tick.seq <= self._held.seq) or tick.seq < last:
                return
            if tick.seq == last:  # republished while the simulator waits: a fresh Ack
                self._last_ack.sent = _sent_links(self._me)
                self._ack_pub.publish(self._last_ack)
                return
            expected = [LinkCount(topic=l.topic, source=l.source, destination=l.destination,
                                  count=l.count * self._counted[l.topic])
                        for l in tick.expected if l.destination == self._me and l.topic in self._counted]
            deadline = time.monotonic() + self._forgive_after
            while self._unmet(expected) is not None and time.monotonic() < deadline and not rospy.is_shutdown():
                self._cond.wait(0.05)
            missing = self._unmet(expected)
            if missing is not None:
                rospy.logwarn('lockstep: %s gives up waiting for %s from %s (%d of %d handled)', self._me,
                              missing.topic, missing.source,
                              self._handled.get((missing.topic, missing.source), 0), missing.count)
                for l in expected:  # forgive: later periods expect only what comes after
                    key = (l.topic, l.source)
                    missing_n = l.count - self._handled.get(key, 0)
                    if missing_n > 0:
                        self._handled[key] = l.count
                        self._forgiven[key] = self._forgiven.get(key, 0) + missing_n
        # /clock is handled in rospy's own thread; what runs now must see the period's time (after
        # a reset exactly: participant.cpp says why).
        went_back = self._last_stamp is not None and tick.stamp < self._last_stamp
        deadline = time.monotonic() + self._forgive_after
        while (not rospy.rostime.is_wallclock() and not rospy.is_shutdown() and time.monotonic() < deadline
               and (rospy.get_rostime() < tick.stamp or (went_back and rospy.get_rostime() > tick.stamp))):
            time.sleep(0.0002)
        # The period's messages first, in a fixed order. One from a participant is handed over
        # in the period its publisher's Ack announced it, never earlier (it may arrive early).
        participants = set(tick.participants)
        due = {}
        for l in expected:
            key = (l.topic, l.source)
            due[key] = max(due.get(key, 0), l.count)
        batch = []
        with self._cond:
            for key in sorted(self._inbox):
                queue = self._inbox[key]
                if key[1] in participants:
                    n = max(0, due.get(key, 0) - self._forgiven.get(key, 0) - self._taken.get(key, 0))
                else:
                    n = len(queue)
                n = min(n, len(queue))
                if n:
                    batch.extend(queue[:n])
                    del queue[:n]
                    self._taken[key] = self._taken.get(key, 0) + n
        for callback, msg in batch:
            callback(msg)
        now = tick.stamp.to_nsec()
        with self._cond:
            timers = list(self._timers)
        for t in sorted(timers, key=lambda e: e[1]):
            if now < t[1] - t[0]:  # time went backwards: start over from now
                t[1] = (now // t[0] + 1) * t[0]
            if t[1] <= now:
                due = t[1]
                t[1] = due + t[0] if due + t[0] > now else (now // t[0] + 1) * t[0]
                ev = rospy.timer.TimerEvent(None, None, rospy.Time(due // 10**9, due % 10**9), tick.stamp, None)
                t[2](ev)
        with self._cond:
            # A main thread sleeping until a time the clock has jumped back from (a simulation
            # reset) wakes at once, as rospy.sleep raises then: it must notice the jump itself.
            self._last_stamp = tick.stamp
            if (self._wake is not None and (tick.stamp >= self._wake or went_back)
                    and not (joining and self._holding_next)):
                self._wake = None
                self._held = tick  # the main thread runs this period; it acks when it sleeps again
                self._cond.notify_all()
                return
            self._ack(tick)

    def _ack(self, tick):
        ack = Ack(node=self._me, seq=tick.seq, leaving=False, sent=_sent_links(self._me))
        try:
            self._ack_pub.publish(ack)
        except rospy.ROSException:
            # A tick that arrives while the node shuts down (rospy closes its topics in a
            # pre-shutdown hook, before is_shutdown() turns true): the simulator drops us on the
            # closed connection, so there is nobody to answer.
            if not rospy.core.is_shutdown_requested():
                raise
            return
        self._last_ack = ack


class TransformListener:
    """Fills a tf2_ros.Buffer from /tf and /tf_static received through the participant (the twin
    of transform_listener.h): under lockstep a transform published for period k is in the buffer
    when this node handles period k+1, never earlier or later, so a lookup at rospy.Time(0) gives
    the same answer on an idle and on a loaded machine. tf2_ros's own listener fills the buffer
    from rospy's threads whenever messages arrive. Never wait for a transform with a timeout while
    the main thread holds a period (time cannot move): look up without one and sleep through the
    helper. As tf2_ros's listener, it clears the buffer when ROS time goes back; unlike it, it
    then drops the transforms stamped before the jump that arrive late (time_jump.py)."""

    def __init__(self, buffer, ls=None):
        self.buffer = buffer
        self._last_now = None
        self._jump = TimeJump()
        ls = ls or participant()
        # 1000 messages, as transform_listener.h: every message a period owes is waited for.
        ls.Subscriber('/tf', TFMessage, lambda m: self._received(m, 'tf', False), queue_size=1000,
                      tcp_nodelay=True)
        ls.Subscriber('/tf_static', TFMessage, lambda m: self._received(m, 'tf_static', True),
                      queue_size=1000, tcp_nodelay=True)

    def _received(self, msg, authority, is_static):
        now = rospy.get_rostime()
        if self._jump.went_back(now.to_sec()):
            rospy.logwarn('tf: time went backwards (%.3f -> %.3f s); clearing the transform buffer',
                          self._last_now.to_sec(), now.to_sec())
            self.buffer.clear()
        self._last_now = now
        dropped = []
        for t in msg.transforms:
            if is_static:
                self.buffer.set_transform_static(t, authority)
            elif self._jump.stale(t.header.stamp.to_sec(), now.to_sec()):
                # Sent before time went back, received after the clear (time_jump.py).
                dropped.append('%s -> %s at %.6f' % (t.header.frame_id, t.child_frame_id, t.header.stamp.to_sec()))
            else:
                self.buffer.set_transform(t, authority)
        if dropped:
            rospy.logwarn('tf: dropped what was sent before time went back: %s', ', '.join(dropped))


_instance = None
_instance_lock = threading.Lock()


def participant(defer_join=False):
    """The process's Participant (one per process, as in C++), made on first use after init_node.

    defer_join (first call only): the node takes part from its main thread's first sleep through
    the helper (or release()), not from the first tick. Everything it set up before (an action
    client's five topics, its subscriptions) is then registered with the master when it joins,
    and the simulator, which holds time on a join until every connection between participants is
    open, starts the next period with all of them connected. Without it a node that sets up
    after its first tick may connect a period sooner or later with load."""
    global _instance
    with _instance_lock:
        if _instance is None:
            _instance = Participant(defer_join=defer_join)
        return _instance
