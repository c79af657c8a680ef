#!/usr/bin/python3
"""thorvald_sim's actors: sim/actors lists the scenario's actors and they move; r1's lidar, looking at the rear wall
across crosser1's line, sees crosser1 where sim/actors says it is. Every wait is for a condition with a deadline."""
import math
import unittest

import rospy
import rostest
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import LaserScan
from thorvald_sim.msg import ActorArray
from thorvald_testing import Latest, wait_for

PERSON_RADIUS = 0.25


class ActorsPeopleTest(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        rospy.init_node("actors_people_test")
        cls.clock = Latest("/clock", Clock)
        cls.actors = Latest("/sim/actors", ActorArray)
        cls.scan = Latest("/r1/scan", LaserScan)
        wait_for(lambda: cls.actors.msg is not None and cls.scan.msg is not None, 60.0, "sim/actors and r1/scan")

    def actor(self, name):
        for a in self.actors.msg.actors:
            if a.name == name:
                return a
        self.fail("no actor %s in sim/actors" % name)

    def ahead(self):
        """Range straight ahead (the middle beam) [m]."""
        s = self.scan.msg
        return s.ranges[int(round((0.0 - s.angle_min) / s.angle_increment))]

    def test_0_actors_listed_and_moving(self):
        self.assertEqual(len(self.actors.msg.actors), rospy.get_param("~actors"))
        name = rospy.get_param("~watched")
        first = self.actor(name)
        t0 = self.actors.msg.header.stamp.to_sec()
        wait_for(lambda: self.actors.msg.header.stamp.to_sec() > t0 + 2.0, 30.0, "2 s of actor poses")
        moved = math.hypot(self.actor(name).x - first.x, self.actor(name).y - first.y)
        self.assertGreater(moved, 1.0, "%s moved %.2f m in 2 s" % (name, moved))
        self.assertNotEqual(self.actors.msg.header.frame_id, "")

    def test_1_lidar_sees_the_person(self):
        lx, ly = rospy.get_param("~lidar_x"), rospy.get_param("~lidar_y")
        wall = lx - rospy.get_param("~rear_wall_x")
        # Nobody in the beam: the rear wall straight ahead.
        wait_for(lambda: abs(self.ahead() - wall) < 0.05, 60.0, "the rear wall straight ahead (%.2f m)" % wall)
        # Someone crosses: the range drops, and the surface seen lies on a person sim/actors puts there.
        wait_for(lambda: self.ahead() < wall - 0.8, 60.0, "a return short of the wall")
        rng, hit_x = self.ahead(), lx - self.ahead()
        people = [a for a in self.actors.msg.actors if a.kind == "person"]
        nearest = min(people, key=lambda a: math.hypot(a.x - hit_x, a.y - ly))
        gap = math.hypot(nearest.x - hit_x, nearest.y - ly)
        rospy.loginfo("range ahead %.3f m (wall %.2f m): hit at x %.2f; %s at (%.2f, %.2f), %.3f m from the hit",
                      rng, wall, hit_x, nearest.name, nearest.x, nearest.y, gap)
        # Within the body radius, plus up to 0.12 m walked between the scan and the pose.
        self.assertLess(gap, PERSON_RADIUS + 0.15)


if __name__ == "__main__":
    rostest.rosrun("thorvald_sim", "actors_people", ActorsPeopleTest)
