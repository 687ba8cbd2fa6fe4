#!/usr/bin/env python3
"""The simulator as a nodelet (test/nodelet.test): with the example controller nodelet in its manager, the
closed loop runs exactly the sampled loop (every odometry message answered in process, every answer acting
from the next output period), and the outputs still reach other processes: /clock, tf and odometry agree
with the state at each step."""
import subprocess
import unittest

import rospy
import rostest
from nav_msgs.msg import Odometry
from rosgraph_msgs.msg import Clock
from tf2_msgs.msg import TFMessage

from rigid_body_sim.testing import Simulator, assert_pose_near

TARGET = (0.5, -0.2, 1.0)  # the controller's parameters in test/nodelet.test
KP, KD, T = 40.0, 10.0, 0.01  # its gains and the output period (rate 100 Hz) [s]
GRAVITY = (0.0, 0.0, -9.81)


def sampled_loop(x0, chunks):
    """Positions after each chunk under the PD law with the weight fed forward and one period of delay:
    a_0 = g, then a_k = kp (target - x_k) - kd v_k, held over chunk k (rk4 integrates it exactly)."""
    x, v, positions = list(x0), [0.0, 0.0, 0.0], []
    for k in range(chunks):
        a = list(GRAVITY) if k == 0 else [KP * (TARGET[i] - x[i]) - KD * v[i] for i in range(3)]
        x = [x[i] + v[i] * T + 0.5 * a[i] * T * T for i in range(3)]
        v = [v[i] + a[i] * T for i in range(3)]
        positions.append(x)
    return positions


class Latest:
    """The messages of a topic received from the simulator's process, by stamp."""

    def __init__(self, topic, message_class, stamp_of):
        self.by_stamp = {}
        self.stamp_of = stamp_of
        self.subscriber = rospy.Subscriber(topic, message_class, self.on_message, queue_size=1000)

    def on_message(self, message):
        for stamp, item in self.stamp_of(message):
            self.by_stamp[stamp] = item


class Nodelet(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.sim = Simulator(timeout=20.0)
        cls.sim.wait_for_node()

    def setUp(self):
        self.sim.reset()
        start = self.sim.state().pose.position
        self.x0 = (start.x, start.y, start.z)

    def test_the_controller_in_the_manager_holds_the_body_along_the_sampled_loop(self):
        states = self.sim.step_with_controller(2000, every=10)
        expected = sampled_loop(self.x0, len(states))
        for k, (state, x) in enumerate(zip(states, expected)):
            p = state.pose.position
            self.assertLess(max(abs(p.x - x[0]), abs(p.y - x[1]), abs(p.z - x[2])), 1e-9, "chunk %d" % k)
        assert_pose_near(states[-1], TARGET, orientation=(0.0, 0.0, 0.0, 1.0), position_tolerance=1e-3)

    def test_clock_tf_and_odometry_reach_another_process_at_every_output(self):
        clock = Latest("/clock", Clock, lambda m: [(m.clock, m)])
        tf = Latest("/tf", TFMessage,
                    lambda m: [(t.header.stamp, t) for t in m.transforms if t.child_frame_id == "base_link"])
        odom = Latest("odom", Odometry, lambda m: [(m.header.stamp, m)])
        for collector in (clock, tf, odom):
            self.sim._wait(lambda: collector.subscriber.get_num_connections() > 0, collector.subscriber.name)
        for _ in range(5):
            self.sim.step(10)
            state = self.sim.state()
            for collector in (clock, tf, odom):
                self.sim._wait(lambda: state.stamp in collector.by_stamp,
                               "%s stamped %s" % (collector.subscriber.name, state.stamp.to_sec()))
            p = state.pose.position
            t = tf.by_stamp[state.stamp].transform.translation
            o = odom.by_stamp[state.stamp].pose.pose.position
            self.assertEqual((t.x, t.y, t.z), (p.x, p.y, p.z))
            self.assertEqual((o.x, o.y, o.z), (p.x, p.y, p.z))

    def test_a_bad_parameter_fails_the_load_and_the_running_simulator_goes_on(self):
        before = self.sim.state().stamp
        load = subprocess.run(["rosrun", "nodelet", "nodelet", "load", "rigid_body_sim/RigidBodyNodelet",
                               "/rigid_body_manager", "__name:=bad_simulator", "_mass:=-1.0"],
                              stdout=subprocess.PIPE, stderr=subprocess.STDOUT, timeout=60)
        rospy.delete_param("/bad_simulator")
        self.assertNotEqual(load.returncode, 0, load.stdout)
        self.sim.step(10)
        self.assertAlmostEqual((self.sim.state().stamp - before).to_sec(), 0.01, places=9)


if __name__ == "__main__":
    rospy.init_node("nodelet_test")
    rostest.rosrun("rigid_body_sim", "nodelet_test", Nodelet)
