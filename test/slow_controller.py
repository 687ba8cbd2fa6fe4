#!/usr/bin/env python3
"""A controller that is slow to answer: for every odometry message it waits ~latency seconds of wall time,
then publishes a constant world-frame force ~force [N] along x. A test stepping it must wait for each reply
(test/testing_kit_loop.test)."""
import time

import rospy
from geometry_msgs.msg import WrenchStamped
from nav_msgs.msg import Odometry


def main():
    rospy.init_node("slow_controller")
    latency = rospy.get_param("~latency", 0.05)
    force = rospy.get_param("~force", 1.0)
    publisher = rospy.Publisher("wrench", WrenchStamped, queue_size=100)

    def answer(odom):
        time.sleep(latency)
        reply = WrenchStamped()
        reply.header.stamp = odom.header.stamp
        reply.header.frame_id = "world"
        reply.wrench.force.x = force
        publisher.publish(reply)

    rospy.Subscriber("odom", Odometry, answer, queue_size=100)
    rospy.spin()


if __name__ == "__main__":
    main()
