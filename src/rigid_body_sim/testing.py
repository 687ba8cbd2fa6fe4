"""Drive a lockstep rigid_body_node from a rostest, without sleeps or races (docs/tests.md).

The node of launch/test_fixture.launch owns simulated time and starts paused: nothing moves until the test
steps it. Every wait here is on an event the node reports, never on a clock:

* a step request returns once the steps are integrated, and the outputs of its last step are published
  before the reply (matched by their stamp, the state's stamp);
* a wrench message counts in the body's ``get_state`` (``wrench_messages``) once the node holds it, so it
  acts from the next step (callbacks run in arrival order on the node's one thread);
* a controller in another process is waited for the same way: step, its reply to the published odometry is
  counted, step again, so each reply acts from the step after the output it answers.

Timeouts are wall time and only guard against a node that never answers; a test never depends on them.
"""
import collections
import math
import time
import xmlrpc.client

import rosgraph
import rospy
from geometry_msgs.msg import Point, Pose, Quaternion, Twist, Vector3, Wrench, WrenchStamped
from nav_msgs.msg import Odometry
from std_srvs.srv import Empty

import yaml

from rigid_body_sim.srv import (ApplyWrench, ApplyWrenchRequest, GetProperties, GetState, ListBodies, Remove,
                                SetState, Spawn, Step)


class SimulatorError(AssertionError):
    """The simulator refused a request or did not answer within the timeout (an AssertionError, so that
    unittest reports a failure with the message, not an error)."""


def _join(*parts):
    """ROS name from parts, empty ones left out: _join('robot', '', 'odom') == 'robot/odom'."""
    kept = [part.strip("/") for part in parts if part and part.strip("/")]
    name = "/".join(kept)
    return "/" + name if parts and parts[0].startswith("/") else name


def _vector(values, kind=Vector3):
    x, y, z = (float(value) for value in values)
    return kind(x, y, z)


class _Collector:
    """Keeps the messages of one topic with their stamps, so a wait can look for one stamp."""

    def __init__(self, topic, message_class):
        self.messages = collections.deque(maxlen=1000)  # the newest; a wait looks for the latest stamp
        self.subscriber = rospy.Subscriber(topic, message_class, self.messages.append, queue_size=1000)

    def stamped(self, stamp):
        for message in reversed(self.messages):
            if message.header.stamp == stamp:
                return message
        return None


class Simulator:
    """One rigid_body_node, seen from a test.

    ``namespace`` is the node's namespace (``ns`` of test_fixture.launch), ``body`` the body's name in a scene
    of several (its topics and services are ``NAME/...``; empty for a one-body scene), ``timeout`` the longest
    any single wait may take [s, wall time]."""

    def __init__(self, namespace="", body="", timeout=30.0):
        self.namespace = namespace
        self.body = body
        self.timeout = timeout
        self._collectors = {}
        self._wrench_publishers = {}
        self._proxies = {}  # by resolved name: waited for once, then reused (a loop calls them per chunk)

    # Names ---------------------------------------------------------------------------------------------
    def name(self, name, body=None):
        """The resolved name of the node's topic or service `name` (a body's own when `body` or self.body)."""
        return rospy.resolve_name(_join(self.namespace, self.body if body is None else body, name))

    def _service(self, name, service_class, body=None):
        resolved = self.name(name, body)
        proxy = self._proxies.get(resolved)
        if proxy is None:
            try:
                rospy.wait_for_service(resolved, timeout=self.timeout)
            except rospy.ROSException:
                raise SimulatorError("no service %s after %g s: is the simulator running (test_fixture.launch), "
                                     "and does the body exist with publish/body_services on?" % (resolved, self.timeout))
            proxy = self._proxies[resolved] = rospy.ServiceProxy(resolved, service_class)
        return proxy

    def _wait(self, poll, what):
        """The first true value `poll()` returns, looked at every millisecond up to the timeout."""
        deadline = time.monotonic() + self.timeout
        while True:
            value = poll()
            if value:
                return value
            if time.monotonic() > deadline or rospy.is_shutdown():
                raise SimulatorError("%s: not within %g s" % (what, self.timeout))
            time.sleep(0.001)

    # The node ------------------------------------------------------------------------------------------
    def wait_for_node(self):
        """Returns once the node answers (its step and the body's get_state services exist)."""
        self._service("step", Step, body="")
        return self.state()

    def step(self, steps=1):
        """Advances the paused simulation by exactly `steps` steps of dt; returns the Step reply. Raises
        SimulatorError with the node's message if it refused (not paused-lockstep, too many, a divergence)."""
        reply = self._service("step", Step, body="")(steps)
        if not reply.success:
            raise SimulatorError("step %d: %s" % (steps, reply.message))
        return reply

    def state(self, body=None):
        """The body's GetState reply: stamp, pose, twist in body and world axes, steps, wrench counts."""
        return self._service("get_state", GetState, body)()

    def properties(self, body=None):
        """The body's GetProperties reply: mass, inertia, shape, material, integrator."""
        return self._service("get_properties", GetProperties, body)()

    def reset(self):
        """Back to the initial state, wrenches cleared (time goes on)."""
        self._service("reset", Empty, body="")()

    def set_state(self, position, orientation=(0.0, 0.0, 0.0, 1.0), linear=(0.0, 0.0, 0.0),
                  angular=(0.0, 0.0, 0.0), twist_frame="world", body=None):
        """Replaces the body's state; orientation [x, y, z, w], velocities in `twist_frame` axes."""
        pose = Pose(_vector(position, Point), Quaternion(*(float(value) for value in orientation)))
        reply = self._service("set_state", SetState, body)(pose, Twist(_vector(linear), _vector(angular)), twist_frame)
        if not reply.success:
            raise SimulatorError("set_state: %s" % reply.message)

    # Scene edits ---------------------------------------------------------------------------------------
    def spawn(self, body):
        """Adds a body at once: `body` is a dict (or YAML text) with the keys of one item of ~bodies, at least
        its name. Raises SimulatorError with the node's reason if it refused (a bad key, a name taken, an
        overlap)."""
        text = body if isinstance(body, str) else yaml.safe_dump(body, default_flow_style=True)
        reply = self._service("spawn", Spawn, body="")(text)
        if not reply.success:
            raise SimulatorError(reply.message)
        return reply

    def remove(self, name):
        """Removes the body called `name` at once; SimulatorError with the node's reason if refused."""
        reply = self._service("remove", Remove, body="")(name)
        if not reply.success:
            raise SimulatorError(reply.message)
        return reply

    def list_bodies(self):
        """The ListBodies reply: names, body_frames, shapes, masses, colliding, in the scene's order."""
        return self._service("list_bodies", ListBodies, body="")()

    # Inputs --------------------------------------------------------------------------------------------
    def apply_wrench(self, force, torque=(0.0, 0.0, 0.0), frame="world", duration=0.0, body=None):
        """A timed wrench (apply_wrench): from the next step for `duration` s (0: one step, negative: until
        clear_wrenches), summed with the topic's wrench. The service answers once it is queued."""
        request = ApplyWrenchRequest()
        request.frame_id = frame
        request.wrench = Wrench(_vector(force), _vector(torque))
        request.duration = rospy.Duration.from_sec(duration)
        reply = self._service("apply_wrench", ApplyWrench, body)(request)
        if not reply.success:
            raise SimulatorError("apply_wrench: %s" % reply.message)

    def clear_wrenches(self):
        self._service("clear_wrenches", Empty, body="")()

    def push_wrench(self, force, torque=(0.0, 0.0, 0.0), frame="world", body=None):
        """Publishes a wrench on the body's `wrench` topic, as a controller would, and returns once the node
        holds it: it acts from the next step on, until the next message (or wrench_timeout). Raises
        SimulatorError if the node refused it (non-finite, above max_force or max_torque, unknown frame)."""
        topic = self.name("wrench", body)
        publisher = self._wrench_publishers.get(topic)
        if publisher is None:
            publisher = rospy.Publisher(topic, WrenchStamped, queue_size=10)
            self._wrench_publishers[topic] = publisher
        self._wait(lambda: publisher.get_num_connections() > 0, "the simulator subscribing to %s" % topic)
        before = self.state(body)
        message = WrenchStamped()
        message.header.frame_id = frame
        message.wrench = Wrench(_vector(force), _vector(torque))
        publisher.publish(message)
        after = self.wait_for_wrenches(1, since=before, body=body)
        if after.wrench_messages_refused > before.wrench_messages_refused:
            raise SimulatorError("the simulator refused the wrench %s in frame '%s' (its log says why)"
                                 % (message.wrench, frame))

    def wait_for_wrenches(self, count=1, since=None, body=None):
        """Returns the body's state once the node has received `count` wrench messages more than it had in
        the state `since` (default: now)."""
        start = (since or self.state(body)).wrench_messages

        def arrived():
            state = self.state(body)
            return state if state.wrench_messages >= start + count else None

        return self._wait(arrived, "%d wrench message(s) on %s" % (count, self.name("wrench", body)))

    # Outputs -------------------------------------------------------------------------------------------
    def _collector(self, topic, message_class, body=None):
        resolved = rospy.resolve_name(topic) if topic.startswith("/") else self.name(topic, body)
        collector = self._collectors.get(resolved)
        if collector is None:
            collector = _Collector(resolved, message_class)
            self._collectors[resolved] = collector
        self._wait(lambda: collector.subscriber.get_num_connections() > 0, "a publisher of %s" % resolved)
        return collector

    def step_and_collect(self, steps, every=1, topic="odom", message_class=Odometry, body=None):
        """Steps `steps` steps in chunks of `every` and returns the message of `topic` published at the end
        of each chunk (len = steps // every): a trajectory with one sample per chunk, stamped on the step
        grid. A topic thinned by its own rate (publish/odom_rate) has no message after some chunks: step to
        its grid then."""
        chunks = _chunks(steps, every)
        collector = self._collector(topic, message_class, body)
        samples = []
        for _ in range(chunks):
            self.step(every)
            stamp = self.state(body).stamp
            samples.append(self._wait(lambda: collector.stamped(stamp),
                                      "a message on %s stamped %s" % (collector.subscriber.name, stamp.to_sec())))
        return samples

    # A controller in another process -------------------------------------------------------------------
    def wait_for_controller(self, body=None):
        """Returns once another node subscribes to the body's odometry and publishes its wrench, both
        connected to the simulator (its bus, not just the master's lists): after this no output is lost."""
        odom, wrench = self.name("odom", body), self.name("wrench", body)
        me = (rospy.get_name(), rospy.get_node_uri())  # outbound links name their peer, inbound its URI

        def connected():
            links = _bus_links(_publisher_of(odom))
            return any(topic == odom and direction == "o" and peer not in me for topic, direction, peer in links) and \
                any(topic == wrench and direction == "i" and peer not in me for topic, direction, peer in links)

        self._wait(connected, "a controller connected to %s and %s" % (odom, wrench))

    def step_with_controller(self, steps, every, body=None):
        """Steps `steps` steps in chunks of `every` (the output period: rate · dt = 1/every), and after each
        chunk waits until the controller's reply to the odometry of that chunk is held by the node, so that it
        acts from the next chunk: a closed loop with one output period of delay, the same on every run.
        Returns the body's state after each chunk."""
        chunks = _chunks(steps, every)
        self.wait_for_controller(body)
        states = []
        before = self.state(body)
        for _ in range(chunks):
            self.step(every)
            before = self.wait_for_wrenches(1, since=before, body=body)
            states.append(before)
        return states


def _chunks(steps, every):
    """How many chunks of `every` steps make `steps`; ValueError unless a whole number of them."""
    if every < 1 or steps % every:
        raise ValueError("steps (%d) must be a whole number of chunks of every (%d) >= 1" % (steps, every))
    return steps // every


def _publisher_of(topic):
    """The XML-RPC URI of the node that publishes `topic` (the simulator)."""
    master = rosgraph.Master(rospy.get_name())
    for name, nodes in master.getSystemState()[0]:
        if name == topic and nodes:
            return master.lookupNode(nodes[0])
    return None


def _bus_links(uri):
    """(topic, 'i' or 'o', peer) of each live connection of the node at `uri` (roscpp's getBusInfo)."""
    if uri is None:
        return []
    code, _, info = xmlrpc.client.ServerProxy(uri).getBusInfo(rospy.get_name())
    if code != 1:
        return []
    return [(link[4], link[2], link[1]) for link in info if len(link) > 5 and link[5]]


def pose_of(thing):
    """The geometry_msgs/Pose in a GetState reply, an Odometry, a PoseStamped or a Pose."""
    for path in (("pose", "pose"), ("pose",), ()):
        value = thing
        try:
            for attribute in path:
                value = getattr(value, attribute)
        except AttributeError:
            continue
        if isinstance(value, Pose):
            return value
    raise TypeError("no pose in a %s" % type(thing).__name__)


def assert_pose_near(actual, position, orientation=None, position_tolerance=1e-3, angle_tolerance=1e-3):
    """Fails (AssertionError naming the distance) unless the pose of `actual` (see pose_of) is within
    `position_tolerance` [m] of `position` and, if given, within `angle_tolerance` [rad] of the rotation
    `orientation` [x, y, z, w] (the angle of the rotation between the two, q and -q alike)."""
    pose = pose_of(actual)
    p = (pose.position.x, pose.position.y, pose.position.z)
    distance = math.sqrt(sum((a - b) ** 2 for a, b in zip(p, position)))
    if not distance <= position_tolerance:  # NaN fails too
        raise AssertionError("position (%.6g, %.6g, %.6g) is %.3g m from (%.6g, %.6g, %.6g); tolerance %.3g m"
                             % (p + (distance,) + tuple(position) + (position_tolerance,)))
    if orientation is None:
        return
    q = (pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w)
    norm = math.sqrt(sum(a * a for a in q)) * math.sqrt(sum(b * b for b in orientation))
    dot = abs(sum(a * b for a, b in zip(q, orientation))) / norm if norm > 0 else float("nan")
    angle = 2.0 * math.acos(min(1.0, dot)) if dot == dot else float("nan")
    if not angle <= angle_tolerance:
        raise AssertionError("orientation %s is %.3g rad from %s; tolerance %.3g rad"
                             % (list(q), angle, list(orientation), angle_tolerance))
