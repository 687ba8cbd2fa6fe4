#!/usr/bin/env python3
"""step_with_controller against a controller 50 ms slow to answer (test/testing_kit_loop.test: 2 kg at
1 m/s, the controller pushing 1 N along x for every output). Each reply must act from the chunk after the
output it answers: after n chunks of T = 10 ms, v = v0 + (n - 1) F T / M. A loop that stepped on without
waiting would integrate chunks before the replies came and fall behind by F T / M = 5e-3 m/s per chunk."""
import unittest

import rospy
import rostest

from rigid_body_sim.testing import Simulator

MASS, SPEED, FORCE, T = 2.0, 1.0, 1.0, 0.01


class ClosedLoop(unittest.TestCase):
    def test_each_reply_acts_from_the_next_chunk(self):
        sim = Simulator(timeout=20.0)
        sim.wait_for_node()
        states = sim.step_with_controller(200, every=10)
        self.assertEqual(len(states), 20)
        for n, state in enumerate(states, start=1):
            self.assertAlmostEqual(state.twist_world.linear.x, SPEED + (n - 1) * FORCE * T / MASS, delta=1e-9,
                                   msg="chunk %d" % n)
            self.assertEqual(state.wrench_messages, n)


if __name__ == "__main__":
    rospy.init_node("testing_kit_loop_test")
    rostest.rosrun("rigid_body_sim", "testing_kit_loop", ClosedLoop)
