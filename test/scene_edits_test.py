#!/usr/bin/env python3
"""spawn, remove and list_bodies on the paused lockstep node of test/edits_scene.yaml (a box on a floor, a
free body in free fall). Each test spawns bodies of its own names, so the order they run in does not matter.
A body that got another's index after an edit (its topic, its service, its contact) would move by the wrong
closed form; a refused edit must leave the list as it was."""
import unittest

import time

import rosgraph
import rospy
import rostest
import tf2_ros

from sensor_msgs.msg import Imu
from visualization_msgs.msg import Marker, MarkerArray

from rigid_body_sim.msg import BodyStates
from rigid_body_sim.testing import Simulator, SimulatorError, assert_pose_near

DT, G = 0.001, 9.81
DRIFTER_START, DRIFTER_VELOCITY = (5.0, 0.0, 100.0), (1.0, 0.0, 5.0)


def box(name, position, collision=True, mass=1.0):
    return {"name": name, "shape": "box", "size": [0.2, 0.2, 0.2], "mass": mass, "collision": collision,
            "initial": {"position": list(position)}}


class SceneEdits(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.sim = Simulator(body="drifter", timeout=20.0)  # a scene of several: a body's services by name
        cls.sim.wait_for_node()
        cls.tf = tf2_ros.Buffer()
        cls.tf_listener = tf2_ros.TransformListener(cls.tf)
        cls.markers = []
        cls.marker_subscriber = rospy.Subscriber("/markers", MarkerArray, cls.markers.append, queue_size=100)
        cls.drifter_steps_at_start = 0  # the drifter's step count when it was last at its initial state

    def spawn(self, body):
        """Spawns `body`, removed again when the test ends however it ends."""
        self.sim.spawn(body)
        self.addCleanup(lambda: body["name"] in self.names() and self.sim.remove(body["name"]))

    def wait_for_markers(self, wanted):
        """The first marker message from now on that has a marker for which wanted(marker) holds (the node
        publishes markers with a step request's outputs while someone listens, at marker_rate)."""
        del self.markers[:]
        deadline = time.monotonic() + 10.0
        while time.monotonic() < deadline:
            self.sim.step(100)  # 0.1 s: at least one marker period of 1/20 s
            for message in list(self.markers):
                if any(wanted(marker) for marker in message.markers):
                    return message
        self.fail("no marker message with the wanted marker")

    def names(self):
        return list(self.sim.list_bodies().names)

    def assert_drifter_on_its_parabola(self):
        # rk4 is exact for a quadratic: p = p0 + v0 t + g t²/2 to rounding, whatever happened elsewhere.
        state = self.sim.state(body="drifter")
        t = (state.total_steps - self.drifter_steps_at_start) * DT
        expected = [p + v * t for p, v in zip(DRIFTER_START, DRIFTER_VELOCITY)]
        expected[2] -= 0.5 * G * t * t
        assert_pose_near(state, expected, position_tolerance=1e-9)

    def test_a_spawned_box_gets_its_topics_and_lands_on_the_box_below(self):
        self.spawn(box("lander", (0.0, 0.0, 0.6)))
        listed = self.sim.list_bodies()
        index = list(listed.names).index("lander")
        self.assertTrue(listed.colliding[index])
        self.assertEqual(listed.shapes[index], "box")
        self.assertAlmostEqual(self.sim.properties(body="lander").mass, 1.0)
        # Its odometry is there at once; 1.5 s after a 0.3 m drop it rests on the base (top face at 0.2 m, its
        # centre 0.1 m above), not in it nor through it on the floor.
        first = self.sim.step_and_collect(10, every=10, body="lander")[0]
        self.assertEqual(first.child_frame_id, "lander")
        # Its tf frame too, at the odometry's stamp and pose.
        transform = self.tf.lookup_transform("world", "lander", first.header.stamp, rospy.Duration(5.0))
        self.assertAlmostEqual(transform.transform.translation.z, first.pose.pose.position.z, places=12)
        self.sim.step(1500)
        assert_pose_near(self.sim.state(body="lander"), (0.0, 0.0, 0.3), position_tolerance=2e-3)
        assert_pose_near(self.sim.state(body="base"), (0.0, 0.0, 0.1), position_tolerance=2e-3)
        self.assert_drifter_on_its_parabola()
        # Its marker: its box in its own frame.
        self.wait_for_markers(lambda m: m.ns == "bodies" and m.header.frame_id == "lander" and
                              m.type == Marker.CUBE and abs(m.scale.z - 0.2) < 1e-12)

    def test_after_a_removal_each_topic_and_service_reaches_its_own_body(self):
        # Three free bodies far from everything; the middle one goes, the last one moves down an index.
        for i, name in enumerate(("first", "middle", "last")):
            self.spawn(box(name, (20.0 + 2 * i, 0.0, 50.0), collision=False, mass=1.0 + i))
        self.sim.step(10)
        last_id = len(self.names()) - 1
        self.sim.remove("middle")
        self.assertNotIn("middle", self.names())
        # The freed marker id (the old last index) is deleted; "last" is drawn under the id before it.
        message = self.wait_for_markers(lambda m: m.ns == "bodies" and m.action == Marker.DELETE)
        deleted = [m.id for m in message.markers if m.ns == "bodies" and m.action == Marker.DELETE]
        self.assertEqual(deleted, [last_id])
        drawn = {m.header.frame_id: m.id for m in message.markers if m.ns == "bodies" and m.action == Marker.ADD}
        self.assertEqual(drawn["last"], last_id - 1)
        self.assertNotIn("middle", drawn)
        master = rosgraph.Master("/scene_edits_test")
        topics = [name for name, _ in master.getPublishedTopics("/")]
        self.assertNotIn("/middle/odom", topics)
        self.assertIn("/last/odom", topics)
        # 3 N on the 3 kg "last" along +y for its topic wrench: +1 m/s² there, nothing on "first".
        self.sim.push_wrench((0.0, 3.0, 0.0), body="last")
        before = {name: self.sim.state(body=name) for name in ("first", "last")}
        self.sim.step(500)
        for name, gain in (("first", 0.0), ("last", 0.5)):
            after = self.sim.state(body=name)
            self.assertAlmostEqual(after.twist_world.linear.y - before[name].twist_world.linear.y, gain, places=9,
                                   msg=name)
            self.assertAlmostEqual(after.pose.position.x, before[name].pose.position.x, places=12, msg=name)
        states = self.sim.step_and_collect(10, every=10, topic="/bodies/states", message_class=BodyStates)[0]
        self.assertEqual(list(states.name)[-2:], ["first", "last"])
        self.assert_drifter_on_its_parabola()

    def test_a_body_spawned_into_a_freed_marker_id_is_drawn_not_deleted(self):
        # Removed and spawned again before any marker message: the id is the new body's, so no DELETE of it.
        self.spawn(box("flash", (-8.0, 0.0, 40.0), collision=False))
        freed = len(self.names()) - 1
        self.sim.remove("flash")
        self.spawn(box("again", (-8.0, 3.0, 40.0), collision=False))
        message = self.wait_for_markers(lambda m: m.header.frame_id == "again")
        ids = [(m.id, m.action) for m in message.markers if m.ns == "bodies" and m.id == freed]
        self.assertEqual(ids, [(freed, Marker.ADD)])

    def test_a_spawned_imu_reads_its_own_body_after_a_body_before_it_goes(self):
        # A falling decoy first, then a box resting on the floor with an IMU; the decoy goes, so the sensor's
        # body moves down an index. At rest the IMU reads the specific force +g up (REP 145); a sensor left
        # on the old index would read the free fall of another body (0) or nothing.
        self.spawn(box("decoy", (-3.0, -3.0, 60.0), collision=False))
        sensed = box("sensed", (3.0, -3.0, 0.1))
        sensed["imu"] = {"rate": 100.0}
        self.spawn(sensed)
        self.sim.step(300)
        self.sim.remove("decoy")
        reading = self.sim.step_and_collect(100, every=100, topic="imu", message_class=Imu, body="sensed")[0]
        self.assertEqual(reading.header.frame_id, "sensed_imu")
        self.assertAlmostEqual(reading.linear_acceleration.z, G, delta=0.01 * G)
        self.assertAlmostEqual(reading.linear_acceleration.x, 0.0, delta=0.01 * G)

    def test_refused_edits_say_why_and_change_nothing(self):
        before = self.names()
        cases = [
            (box("inside", (0.05, 0.0, 0.15)), "base"),          # overlaps the base box
            (box("sunk", (3.0, 0.0, 0.05)), "floor"),            # half in the floor
            (box("base", (9.0, 0.0, 5.0)), "name"),              # a name taken
            ({"name": "typo", "mas": 1.0}, "mas"),               # not a key
            ({"name": "heavy", "mass": -1.0}, "mass"),           # a value out of range
            ("{name: [", "YAML"),                                 # not YAML
        ]
        for body, reason in cases:
            with self.assertRaises(SimulatorError) as refused:
                self.sim.spawn(body)
            self.assertIn(reason, str(refused.exception))
        with self.assertRaises(SimulatorError) as unknown:
            self.sim.remove("nobody")
        self.assertIn("nobody", str(unknown.exception))
        self.assertEqual(self.names(), before)
        self.sim.step(10)
        self.assert_drifter_on_its_parabola()

    def test_a_reset_keeps_a_spawned_body_and_takes_it_back_to_its_spawn_state(self):
        self.spawn(box("keeper", (-5.0, 0.0, 30.0), collision=False))
        self.sim.step(300)
        self.assertLess(self.sim.state(body="keeper").pose.position.z, 30.0 - 0.4)
        self.sim.reset()
        SceneEdits.drifter_steps_at_start = self.sim.state(body="drifter").total_steps
        assert_pose_near(self.sim.state(body="keeper"), (-5.0, 0.0, 30.0), position_tolerance=1e-12)
        self.assertIn("keeper", self.names())


if __name__ == "__main__":
    rospy.init_node("scene_edits_test")
    rostest.rosrun("rigid_body_sim", "scene_edits", SceneEdits)
