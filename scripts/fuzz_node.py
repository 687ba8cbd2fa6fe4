#!/usr/bin/env python3
"""Seeded fuzzing of a running rigid_body_node (started by scripts/fuzz_node.sh against a private master).

Sends wrenches with extreme and non-finite components in odd frames with odd stamps, on both wrench topics,
publishes odd transforms on /tf (non-finite values, zero quaternions, loops, a spoofed parent of the body
frame, frames below the body), and calls every service with extreme arguments, for a given time. Meanwhile it reads odom, state,
applied_wrench and /tf and reports: messages sent, service calls made (and how many timed out), non-finite
values published (must be 0), odometry stamps that did not increase, the odometry rate over the last
seconds, and whether the node still answers get_state. Exit code 1 if anything must-not-happen happened.

Usage: fuzz_node.py NAMESPACE SECONDS SEED RATE_HZ
"""
import math
import random
import sys
import threading
import time

import rospy
from geometry_msgs.msg import TransformStamped, Wrench, WrenchStamped
from nav_msgs.msg import Odometry
from rigid_body_sim.msg import RigidBodyState
from rigid_body_sim.srv import (ApplyWrench, ApplyWrenchRequest, GetState, ListBodies, Remove, SetState,
                                SetStateRequest, Spawn, Step)
from std_srvs.srv import Empty, Trigger
from tf2_msgs.msg import TFMessage

# Values from the everyday to the absurd; NaN and the infinities included.
EXTREMES = [0.0, 1.0, -1.0, 1e-300, -1e-300, 5e-324, 1e3, 1e100, 1e300, -1e300, 1.7976931348623157e308,
            -1.7976931348623157e308, float("nan"), float("inf"), float("-inf")]
FRAMES = ["", "world", "base_link", "/world", "//world", "/", "unknown", "/unknown", "base_link ", "a" * 300,
          "world/", "\u00e9t\u00e9", "map", "odom", "thruster", "loop_a", "loop_b"]
# Parent and child frames of the transforms sent on /tf: below the body, beside it, in a loop, over it.
TF_EDGES = [("base_link", "thruster"), ("world", "map"), ("map", "odom"), ("loop_a", "loop_b"), ("loop_b", "loop_a"),
            ("thruster", "base_link"), ("world", "base_link"), ("odom", "odom"), ("", "thruster"), ("map", "")]


def number(rng):
    if rng.random() < 0.5:
        return rng.choice(EXTREMES)
    return rng.gauss(0.0, 1.0) * 10.0 ** rng.randint(-5, 5)


def finite(*values):
    return all(math.isfinite(v) for v in values)


class Watch:
    """What the node publishes, checked as it arrives."""

    def __init__(self, ns):
        self.lock = threading.Lock()
        self.non_finite = 0
        self.stamp_anomalies = 0
        self.odom_stamps = []
        self.messages = 0
        rospy.Subscriber(ns + "/odom", Odometry, self.on_odom, queue_size=1000)
        rospy.Subscriber(ns + "/state", RigidBodyState, self.on_state, queue_size=1000)
        rospy.Subscriber(ns + "/applied_wrench", WrenchStamped, self.on_wrench, queue_size=1000)
        rospy.Subscriber("/tf", TFMessage, self.on_tf, queue_size=1000)
        self.own_name = rospy.get_name()

    def count(self, ok):
        with self.lock:
            self.messages += 1
            if not ok:
                self.non_finite += 1

    def on_odom(self, m):
        p, q, v, w = m.pose.pose.position, m.pose.pose.orientation, m.twist.twist.linear, m.twist.twist.angular
        self.count(finite(p.x, p.y, p.z, q.x, q.y, q.z, q.w, v.x, v.y, v.z, w.x, w.y, w.z))
        with self.lock:
            stamp = m.header.stamp.to_sec()
            if self.odom_stamps and stamp <= self.odom_stamps[-1][0]:
                self.stamp_anomalies += 1
            self.odom_stamps.append((stamp, time.monotonic()))

    def on_state(self, m):
        values = [m.pose.position.x, m.pose.position.y, m.pose.position.z, m.pose.orientation.w,
                  m.twist.linear.x, m.twist.linear.y, m.twist.linear.z, m.twist.angular.x, m.twist.angular.y,
                  m.twist.angular.z, m.linear_momentum.x, m.linear_momentum.y, m.linear_momentum.z,
                  m.angular_momentum.x, m.angular_momentum.y, m.angular_momentum.z, m.applied_wrench.force.x,
                  m.applied_wrench.force.y, m.applied_wrench.force.z, m.applied_wrench.torque.x,
                  m.applied_wrench.torque.y, m.applied_wrench.torque.z, m.kinetic_energy, m.potential_energy,
                  m.quaternion_norm_error]
        self.count(finite(*values))

    def on_wrench(self, m):
        f, t = m.wrench.force, m.wrench.torque
        self.count(finite(f.x, f.y, f.z, t.x, t.y, t.z))

    def on_tf(self, m):
        if m._connection_header.get("callerid") == self.own_name:
            return  # the fuzzer's own transforms
        for t in m.transforms:
            r, q = t.transform.translation, t.transform.rotation
            self.count(finite(r.x, r.y, r.z, q.x, q.y, q.z, q.w))


def call_with_timeout(call, timeout):
    """`call()` in a thread: True if it returned (or raised) within `timeout` seconds."""
    done = threading.Event()

    def run():
        try:
            call()
        except Exception:  # refusals come back as exceptions too; only a hang counts
            pass
        done.set()

    threading.Thread(target=run, daemon=True).start()
    return done.wait(timeout)


def random_wrench(rng):
    w = Wrench()
    w.force.x, w.force.y, w.force.z = number(rng), number(rng), number(rng)
    w.torque.x, w.torque.y, w.torque.z = number(rng), number(rng), number(rng)
    return w


def random_transforms(rng):
    m = TFMessage()
    for _ in range(rng.choice([1, 2, 5, 1000])):
        t = TransformStamped()
        t.header.frame_id, t.child_frame_id = rng.choice(TF_EDGES)
        t.header.stamp = random_stamp(rng) if rng.random() < 0.5 else rospy.Time.now()
        r, q = t.transform.translation, t.transform.rotation
        r.x, r.y, r.z = number(rng), number(rng), number(rng)
        q.x, q.y, q.z, q.w = rng.choice([(0, 0, 0, 1), (0, 0, 0, 0), (number(rng), number(rng), 0, 1),
                                          (0, 0, 0.70710678118654752, 0.70710678118654752)])
        m.transforms.append(t)
    return m


# Names a spawn and a remove draw from: a few real ones (so that removals hit spawned bodies), the flat
# body's frame (refused: it is the only body, or the fuzzer's target stays), and odd strings.
SPAWN_NAMES = ["s1", "s2", "s3", "s4", "world", "base_link", "", "1abc", "a b", "x" * 300, "ü"]
SPAWN_SHAPES = ["box", "sphere", "cylinder", "mesh", "capsule", "plane", "nothing"]


def random_spawn(rng):
    """YAML text of a body, valid or not: odd names, shapes, sizes, masses, positions, broken syntax."""
    def value():
        x = number(rng)
        return repr(x) if math.isfinite(x) else rng.choice([".nan", ".inf", "-.inf", "nan"])
    name = rng.choice(SPAWN_NAMES)
    parts = ["name: '%s'" % name, "shape: %s" % rng.choice(SPAWN_SHAPES), "mass: %s" % value(),
             "size: [%s]" % ", ".join(value() for _ in range(rng.randint(0, 4))),
             "initial: {position: [%s, %s, %s]}" % (value(), value(), value())]
    if rng.random() < 0.5:
        parts.append("collision: %s" % rng.choice(["true", "false", "{shape: capsule, size: [0.1, 0.2]}", "3"]))
    text = "{" + ", ".join(rng.sample(parts, rng.randint(1, len(parts)))) + "}"
    return text[:rng.randint(0, len(text))] if rng.random() < 0.1 else text


def random_stamp(rng):
    choice = rng.randint(0, 4)
    if choice == 0:
        return rospy.Time(0)
    if choice == 1:
        return rospy.Time.now()
    if choice == 2:
        return rospy.Time(4294967295, 999999999)  # the end of ROS time
    if choice == 3:
        return rospy.Time(rng.randint(0, 4294967295), rng.randint(0, 999999999))
    return rospy.Time.now() - rospy.Duration(rng.uniform(0, 1000))


def main():
    ns, seconds, seed, rate = sys.argv[1], float(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
    rng = random.Random(seed)
    rospy.init_node("fuzz_node", anonymous=True)
    watch = Watch(ns)
    stamped = rospy.Publisher(ns + "/wrench", WrenchStamped, queue_size=100)
    unstamped = rospy.Publisher(ns + "/wrench_unstamped", Wrench, queue_size=100)
    transforms = rospy.Publisher("/tf", TFMessage, queue_size=100)
    types = {"apply_wrench": ApplyWrench, "set_state": SetState, "get_state": GetState, "step": Step,
             "pause": Empty, "unpause": Empty, "reset": Empty, "reset_time": Trigger, "clear_wrenches": Empty,
             "spawn": Spawn, "remove": Remove, "list_bodies": ListBodies}
    services = {name: rospy.ServiceProxy(ns + "/" + name, kind) for name, kind in types.items()}
    rospy.wait_for_service(ns + "/get_state", timeout=30)
    time.sleep(1.0)
    sent = sent_tf = calls = hung = 0
    end = time.monotonic() + seconds
    while time.monotonic() < end and not rospy.is_shutdown():
        kind = rng.random()
        if kind < 0.6:
            m = WrenchStamped()
            m.header.frame_id = rng.choice(FRAMES)
            m.header.stamp = random_stamp(rng)
            m.wrench = random_wrench(rng)
            stamped.publish(m)
            sent += 1
        elif kind < 0.7:
            unstamped.publish(random_wrench(rng))
            sent += 1
        elif kind < 0.8:
            transforms.publish(random_transforms(rng))
            sent_tf += 1
        else:
            name = rng.choice(sorted(services))
            proxy = services[name]
            if name == "apply_wrench":
                request = ApplyWrenchRequest()
                request.frame_id = rng.choice(FRAMES)
                request.wrench = random_wrench(rng)
                request.use_point = rng.random() < 0.5
                request.point.x, request.point.y, request.point.z = number(rng), number(rng), number(rng)
                request.start_time = random_stamp(rng)
                request.duration = rospy.Duration(rng.choice([0, -1, 1, 2147483647, -2147483648]),
                                                  rng.randint(0, 999999999))
            elif name == "set_state":
                request = SetStateRequest()
                p, o = request.pose.position, request.pose.orientation
                p.x, p.y, p.z = number(rng), number(rng), number(rng)
                o.x, o.y, o.z, o.w = rng.choice([(0, 0, 0, 1), (number(rng), 0, 0, 1), (0, 0, 0, 0)])
                request.twist.linear.x, request.twist.angular.z = number(rng), number(rng)
                request.twist_frame = rng.choice(["", "body", "world", "map"])
            elif name == "spawn":
                request = random_spawn(rng)
            elif name == "remove":
                request = rng.choice([n for n in SPAWN_NAMES if n != "base_link"])
            elif name == "step":
                request = rng.choice([-(2 ** 63), -1, 0, 1, 10, 1000, 10 ** 6, 10 ** 9, 2 ** 63 - 1])
            else:
                request = None
            calls += 1
            call = (lambda: proxy()) if request is None else (lambda: proxy(request))
            if not call_with_timeout(call, timeout=5.0):
                hung += 1
        time.sleep(1.0 / rate)
    # Unpause and let it run, then measure the odometry rate over the last two seconds of its own stamps.
    call_with_timeout(lambda: services["unpause"](), timeout=5.0)
    time.sleep(3.0)
    with watch.lock:
        recent = [s for s in watch.odom_stamps if s[1] > time.monotonic() - 2.0]
    odom_hz = (len(recent) - 1) / (recent[-1][0] - recent[0][0]) if len(recent) > 2 else 0.0
    alive = call_with_timeout(lambda: services["get_state"](), timeout=5.0)
    print(f"fuzz: seed {seed}, {seconds:g} s: {sent} wrench messages and {sent_tf} /tf messages sent, {calls} "
          f"service calls ({hung} not "
          f"answered within 5 s); {watch.messages} messages received, {watch.non_finite} with a non-finite value, "
          f"{watch.stamp_anomalies} odometry stamps not increasing; odometry {odom_hz:.1f} Hz over the last 2 s; "
          f"node {'answers' if alive else 'DOES NOT ANSWER'}")
    bad = watch.non_finite > 0 or watch.stamp_anomalies > 0 or hung > 0 or not alive
    sys.exit(1 if bad else 0)


if __name__ == "__main__":
    main()
