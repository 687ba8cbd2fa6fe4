#!/usr/bin/env python3
"""rigid_body_sim.testing on the fixture's paused lockstep node (test/kit_scene.yaml: 2 kg, 1 m/s along x,
zero g, max_force 100 N). Each wait of the kit is checked by a closed form that a late or lost input, or a
sample taken at the wrong step, would miss by at least one step's worth (F dt / M = 1e-3 m/s here)."""
import math
import unittest

import rospy
import rostest
from geometry_msgs.msg import Pose

from rigid_body_sim.testing import Simulator, SimulatorError, assert_pose_near

MASS, DT, SPEED = 2.0, 0.001, 1.0


class TestingKit(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.sim = Simulator(timeout=20.0)
        cls.sim.wait_for_node()

    def setUp(self):
        self.sim.reset()  # the initial state, wrenches cleared
        self.start = self.sim.state()

    def test_step_and_collect_returns_one_sample_per_chunk_on_the_step_grid(self):
        samples = self.sim.step_and_collect(100, every=10)
        self.assertEqual(len(samples), 10)
        t0 = self.start.stamp.to_nsec()
        for k, odom in enumerate(samples, start=1):
            self.assertEqual(odom.header.stamp.to_nsec() - t0, k * 10 * 1000000)  # exactly 10 k steps of 1 ms
            # Free motion: x = x0 + v t, exact for rk4 but for rounding.
            self.assertAlmostEqual(odom.pose.pose.position.x - self.start.pose.position.x, SPEED * k * 0.01, delta=1e-12)
        self.assertEqual(self.sim.state().total_steps, self.start.total_steps + 100)

    def test_a_pushed_wrench_acts_from_the_next_step(self):
        force = 2.0
        self.sim.push_wrench((force, 0.0, 0.0), frame="world")
        self.sim.step(1000)
        v = self.sim.state().twist_world.linear.x
        # From the first of the 1 000 steps: v = v0 + F t / M. One step late would be short by F dt / M.
        self.assertAlmostEqual(v, SPEED + force * 1.0 / MASS, delta=1e-9)
        # The latest message wins: a push of zero stops the acceleration from the next step.
        self.sim.push_wrench((0.0, 0.0, 0.0))
        self.sim.step(500)
        self.assertAlmostEqual(self.sim.state().twist_world.linear.x, SPEED + force / MASS, delta=1e-9)

    def test_a_body_frame_push_turns_with_the_body(self):
        # Turned 90 deg about z, body x is world y: a body-frame push along x accelerates along world y.
        half = math.sqrt(0.5)
        self.sim.set_state((0.0, 0.0, 0.0), (0.0, 0.0, half, half))
        self.sim.push_wrench((4.0, 0.0, 0.0), frame="kit_link")
        self.sim.step(100)
        twist = self.sim.state().twist_world.linear
        self.assertAlmostEqual(twist.y, 4.0 * 0.1 / MASS, delta=1e-9)
        self.assertAlmostEqual(twist.x, 0.0, delta=1e-9)

    def test_refused_wrenches_raise_and_leave_the_acting_one(self):
        self.sim.push_wrench((1.0, 0.0, 0.0))
        with self.assertRaisesRegex(SimulatorError, "refused"):
            self.sim.push_wrench((float("nan"), 0.0, 0.0))
        with self.assertRaisesRegex(SimulatorError, "refused"):
            self.sim.push_wrench((101.0, 0.0, 0.0))  # above max_force
        with self.assertRaisesRegex(SimulatorError, "refused"):
            self.sim.push_wrench((1.0, 0.0, 0.0), frame="no_such_frame")
        self.sim.step(100)
        self.assertAlmostEqual(self.sim.state().twist_world.linear.x, SPEED + 1.0 * 0.1 / MASS, delta=1e-9)

    def test_a_timed_wrench_acts_for_its_duration(self):
        self.sim.apply_wrench((0.0, 0.0, 3.0), duration=0.25)
        self.sim.step(1000)
        self.assertAlmostEqual(self.sim.state().twist_world.linear.z, 3.0 * 0.25 / MASS, delta=1e-9)

    def test_bad_requests_raise_with_the_nodes_message(self):
        with self.assertRaisesRegex(SimulatorError, "step 0"):
            self.sim.step(0)
        with self.assertRaisesRegex(SimulatorError, "unit quaternion"):
            self.sim.set_state((0.0, 0.0, 0.0), (0.0, 0.0, 0.0, 2.0))
        with self.assertRaisesRegex(ValueError, "whole number"):
            self.sim.step_and_collect(15, every=10)
        self.assertEqual(self.sim.state().total_steps, self.start.total_steps)  # nothing moved

    def test_assert_pose_near_fails_outside_its_tolerances(self):
        pose = Pose()
        pose.position.x, pose.orientation.w = 1.0, 1.0
        assert_pose_near(pose, (1.0005, 0.0, 0.0), position_tolerance=1e-3)
        with self.assertRaisesRegex(AssertionError, "from"):
            assert_pose_near(pose, (1.002, 0.0, 0.0), position_tolerance=1e-3)
        with self.assertRaises(AssertionError):
            assert_pose_near(pose, (float("nan"), 0.0, 0.0))
        # q and -q are one rotation; 0.01 rad about z is outside 1e-3 rad.
        assert_pose_near(pose, (1.0, 0.0, 0.0), orientation=(0.0, 0.0, 0.0, -1.0))
        turned = (0.0, 0.0, math.sin(0.005), math.cos(0.005))
        with self.assertRaisesRegex(AssertionError, "rad from"):
            assert_pose_near(pose, (1.0, 0.0, 0.0), orientation=turned, angle_tolerance=1e-3)
        assert_pose_near(pose, (1.0, 0.0, 0.0), orientation=turned, angle_tolerance=0.011)
        # The node's own state: where free motion puts it.
        self.sim.step(250)
        x0 = self.start.pose.position
        assert_pose_near(self.sim.state(), (x0.x + 0.25 * SPEED, x0.y, x0.z), position_tolerance=1e-9)


if __name__ == "__main__":
    rospy.init_node("testing_kit_test")
    rostest.rosrun("rigid_body_sim", "testing_kit", TestingKit)
