#!/usr/bin/env python3
"""Holds a body at a point: a PD controller on its odometry, with the weight fed forward,
F = M (kp (target - x) - kd v - g), published in the world frame for every odometry message it gets
(stamped with that message's stamp). Parameters: ~target [m], ~kp [1/s^2], ~kd [1/s], ~mass [kg],
~gravity [m/s^2]."""
import sys

import rospy
from geometry_msgs.msg import WrenchStamped
from nav_msgs.msg import Odometry


def rotate(q, v):
    """v turned by the unit quaternion q = (x, y, z, w): v + 2 w (u x v) + 2 u x (u x v), u = (x, y, z)."""
    u, w = (q.x, q.y, q.z), q.w

    def cross(a, b):
        return (a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0])

    uv = cross(u, v)
    uuv = cross(u, uv)
    return tuple(v[i] + 2.0 * (w * uv[i] + uuv[i]) for i in range(3))


class HoldPosition:
    def __init__(self):
        self.target = self.vector("~target", [0.0, 0.0, 1.0])
        self.gravity = self.vector("~gravity", [0.0, 0.0, -9.81])
        self.kp = self.positive("~kp", 40.0)
        self.kd = self.positive("~kd", 10.0)
        self.mass = self.positive("~mass", 1.0)
        self.publisher = rospy.Publisher("wrench", WrenchStamped, queue_size=10)
        self.subscriber = rospy.Subscriber("odom", Odometry, self.on_odometry, queue_size=10)

    @staticmethod
    def vector(name, default):
        value = rospy.get_param(name, default)
        if not (isinstance(value, list) and len(value) == 3 and all(isinstance(x, (int, float)) for x in value)):
            rospy.logfatal("hold_position: %s must be a list of 3 numbers, got %r", rospy.resolve_name(name), value)
            sys.exit(2)
        return [float(x) for x in value]

    @staticmethod
    def positive(name, default):
        value = rospy.get_param(name, default)
        if not (isinstance(value, (int, float)) and 0.0 < value < float("inf")):
            rospy.logfatal("hold_position: %s must be a finite number > 0, got %r", rospy.resolve_name(name), value)
            sys.exit(2)
        return float(value)

    def on_odometry(self, odom):
        x = odom.pose.pose.position
        v_body = odom.twist.twist.linear  # nav_msgs/Odometry: twist in the body frame
        v = rotate(odom.pose.pose.orientation, (v_body.x, v_body.y, v_body.z))
        error = (self.target[0] - x.x, self.target[1] - x.y, self.target[2] - x.z)
        wrench = WrenchStamped()
        wrench.header.stamp = odom.header.stamp
        wrench.header.frame_id = odom.header.frame_id  # the world frame
        force = [self.mass * (self.kp * error[i] - self.kd * v[i] - self.gravity[i]) for i in range(3)]
        wrench.wrench.force.x, wrench.wrench.force.y, wrench.wrench.force.z = force
        self.publisher.publish(wrench)


if __name__ == "__main__":
    rospy.init_node("hold_position")
    HoldPosition()
    rospy.spin()
