#!/usr/bin/env python3
"""The controller holds the body at its target (test/hold_position.test). The simulator steps one output
period (10 steps of 1 ms) at a time and waits for the controller's answer to that output before the next, so
the closed loop is exactly the sampled one: the force of output k acts over chunk k + 1. Then the trajectory
has a closed form, the recursion below, which a lost or late controller message would leave by far more
than the rounding the assertion allows."""
import unittest

import rospy
import rostest

from rigid_body_sim.testing import Simulator, assert_pose_near

TARGET = (0.5, -0.2, 1.0)
KP, KD, T = 40.0, 10.0, 0.01  # the controller's gains (hold_position.test) and the output period [s]
GRAVITY = (0.0, 0.0, -9.81)


def sampled_loop(x0, chunks):
    """Positions after each chunk: constant acceleration a_k over chunk k, x += v T + a T^2 / 2, v += a T,
    with a_0 = g (no answer yet) and a_k = kp (target - x_k) - kd v_k after (the weight fed forward)."""
    x, v, positions = list(x0), [0.0, 0.0, 0.0], []
    for k in range(chunks):
        a = list(GRAVITY) if k == 0 else [KP * (TARGET[i] - x[i]) - KD * v[i] for i in range(3)]
        x = [x[i] + v[i] * T + 0.5 * a[i] * T * T for i in range(3)]
        v = [v[i] + a[i] * T for i in range(3)]
        positions.append(x)
    return positions


class HoldPosition(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.sim = Simulator(timeout=20.0)
        cls.sim.wait_for_node()

    def setUp(self):
        self.sim.reset()
        start = self.sim.state().pose.position
        self.x0 = (start.x, start.y, start.z)

    def test_reaches_the_target_along_the_sampled_closed_loop(self):
        states = self.sim.step_with_controller(3000, every=10)  # 3 s
        expected = sampled_loop(self.x0, len(states))
        for k, (state, x) in enumerate(zip(states, expected)):
            p = state.pose.position
            # rk4 integrates a constant force exactly: the two differ by rounding only.
            self.assertLess(max(abs(p.x - x[0]), abs(p.y - x[1]), abs(p.z - x[2])), 1e-9, "chunk %d" % k)
        assert_pose_near(states[-1], TARGET, orientation=(0.0, 0.0, 0.0, 1.0), position_tolerance=1e-3)

    def test_recovers_from_a_push(self):
        self.sim.step_with_controller(3000, every=10)
        # 5 N for 0.1 s: an impulse of 0.5 N s on 1 kg, some centimetres off before the controller wins.
        self.sim.apply_wrench((0.0, 5.0, 0.0), duration=0.1)
        states = self.sim.step_with_controller(3000, every=10)
        offset = max(abs(s.pose.position.y - TARGET[1]) for s in states)
        self.assertGreater(offset, 0.01)
        assert_pose_near(states[-1], TARGET, position_tolerance=1e-3)


if __name__ == "__main__":
    rospy.init_node("test_hold_position")
    rostest.rosrun("hold_position_example", "hold_position_test", HoldPosition)
